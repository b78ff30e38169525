//! Data flows one way: args → case → simulate → output, and the module tree shows the layers
//! (docs/architecture.md). A module never names a module of a higher layer (`crate::…`); test
//! code is exempt. A source scan, because the compiler allows any import.

use std::path::{Path, PathBuf};

/// The layers, lowest first: (rank, what it is, the source paths in it, as prefixes of the path
/// under `src/` and of the module path under `crate::`).
const LAYERS: [(u8, &str, &[&str]); 7] = [
    (0, "leaves", &["error", "bands", "Error", "Result"]),
    (1, "physics", &["physics"]),
    (2, "simulation", &["simulation", "probes"]),
    (3, "ground", &["ground"]),
    (4, "input", &["input"]),
    (5, "passage", &["setup", "safety"]),
    (6, "studies", &["studies"]),
];

/// The layer of a file under `src/` or of a `crate::` path's first name.
fn rank(first: &str) -> Option<u8> {
    let first = first.trim_end_matches(".rs");
    LAYERS
        .iter()
        .find(|(_, _, names)| names.contains(&first))
        .map(|(r, _, _)| *r)
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The first names after `crate::` on a line of code (`crate::{a, b::c}` gives a and b).
fn crate_names(code: &str) -> Vec<String> {
    let mut names = Vec::new();
    for (i, _) in code.match_indices("crate::") {
        if code[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
            continue; // `maglev_sim::crate…` cannot occur; `xcrate::` is another word
        }
        let rest = &code[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let group = group.split('}').next().unwrap_or("");
            for item in group.split(',') {
                let name = item.trim().split("::").next().unwrap_or("").trim();
                if !name.is_empty() {
                    names.push(name.to_string());
                }
            }
        } else {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            names.push(name);
        }
    }
    names
}

/// The lines of `text` that are not test code: a `#[cfg(test)] mod x { … }` ends the scan of a
/// file (test modules close it, by the project's convention); a `#[cfg(test)]` before a
/// one-line item skips that line; a file named `tests.rs` is all test code.
fn code_lines(text: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut skip_next = false;
    for (n, line) in text.lines().enumerate() {
        let code = line.split("//").next().unwrap_or("");
        if skip_next && !code.trim().is_empty() {
            skip_next = false;
            if code.trim_start().starts_with("mod ") && code.trim_end().ends_with('{') {
                break;
            }
            continue;
        }
        if code.trim() == "#[cfg(test)]" {
            skip_next = true;
            continue;
        }
        out.push((n + 1, code));
    }
    out
}

#[test]
fn no_module_names_a_higher_layer() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../host-sim/sim/src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    assert!(
        files.len() > 90,
        "the scan found only {} files",
        files.len()
    );
    let mut offenders = Vec::new();
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_str()
            .unwrap();
        if first == "lib.rs" || rel.file_name().unwrap() == "tests.rs" {
            continue;
        }
        let own = rank(first).unwrap_or_else(|| panic!("{}: in no layer", rel.display()));
        let text = std::fs::read_to_string(f).unwrap();
        for (n, code) in code_lines(&text) {
            for name in crate_names(code) {
                let theirs = rank(&name).unwrap_or_else(|| {
                    panic!("{}:{n}: crate::{name} is in no layer", rel.display())
                });
                if theirs > own {
                    offenders.push(format!("{}:{n}: {}", rel.display(), code.trim()));
                }
            }
        }
    }
    assert!(offenders.is_empty(), "{}", offenders.join("\n"));
}

#[test]
fn the_scan_sees_a_higher_layer_and_skips_test_code() {
    assert_eq!(
        crate_names("use crate::{physics::fe, input::case::Case};"),
        ["physics", "input"]
    );
    assert_eq!(
        crate_names("let x = crate::studies::sweep::f(crate::Error::x);"),
        ["studies", "Error"]
    );
    assert!(rank("studies").unwrap() > rank("physics").unwrap());
    let text = "use crate::physics::fe;\n#[cfg(test)]\nuse crate::studies::x;\nfn f() {}\n#[cfg(test)]\nmod tests {\n    use crate::studies::y;\n}\n";
    let kept: Vec<&str> = code_lines(text).into_iter().map(|(_, c)| c).collect();
    assert_eq!(kept, ["use crate::physics::fe;", "fn f() {}"]);
}
