//! The host crates' layers (docs/architecture.md): data flows one way, scenario → case →
//! simulate → records → outputs, so in each of maglev-sim, maglev-hil and maglev a module never
//! names a module of a higher layer, and no two modules name each other, directly or around a
//! circle (an import circle makes two modules one: neither can be read, tested or moved
//! alone). Test code is exempt. A source scan, because the compiler allows any import within a
//! crate; between crates Cargo's dependencies keep the order (sim ← hil ← cli).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A host crate: its source directory (under the workspace) and its layers, lowest first,
/// each with the first names of the module paths in it (`crate::NAME…`; for the binary's
/// crate also the library modules it names at its root).
struct Crate {
    src: &'static str,
    layers: &'static [(&'static str, &'static [&'static str])],
}

const CRATES: [Crate; 3] = [
    Crate {
        src: "host-sim/sim/src",
        layers: &[
            ("leaves", &["error", "bands", "Error", "Result"]),
            ("physics", &["physics"]),
            ("records", &["probes"]),
            ("simulation", &["simulation"]),
            ("ground", &["ground"]),
            ("input", &["input"]),
            ("passage", &["setup", "safety", "running_safety"]),
            ("studies", &["studies"]),
            ("facade", &["prelude"]),
        ],
    },
    Crate {
        src: "host-sim/hil/src",
        layers: &[
            ("devices", &["board", "link", "step_frame"]),
            ("timing", &["realtime"]),
            ("coupling", &["coupling", "compare"]),
        ],
    },
    Crate {
        src: "host-sim/cli/src",
        layers: &[
            (
                "libraries",
                &[
                    "bands",
                    "ground",
                    "hil",
                    "input",
                    "physics",
                    "probes",
                    "setup",
                    "simulation",
                    "Error",
                    "Result",
                ],
            ),
            ("plots", &["plot"]),
            ("outputs", &["output"]),
            ("studies", &["studies"]),
            ("commands", &["cli"]),
        ],
    },
];

/// The rank of a first name in `layers`.
fn rank(layers: &[(&str, &[&str])], first: &str) -> Option<usize> {
    layers.iter().position(|(_, names)| names.contains(&first))
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

/// The module path of a file under `src/` (`a/b.rs` and `a/b/mod.rs` are `a::b`; `lib.rs`
/// and `main.rs` the root).
fn module_of(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_str().unwrap().to_string())
        .collect();
    let last = parts.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    if !(stem == "mod" || (parts.is_empty() && (stem == "lib" || stem == "main"))) {
        parts.push(stem.to_string());
    }
    parts
}

/// The paths a line of code in module `own` names, as paths from the crate root:
/// `crate::a::b`, `super::x` (from `own`'s parent, `super::super::` from its grandparent) and
/// `self::x`, with `{…}` groups expanded one level (`crate::{a, b::c}` gives `a` and `b::c`).
fn named_paths(code: &str, own: &[String]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let bytes = code.as_bytes();
    for (kw, base) in [("crate::", 0usize), ("super::", 1), ("self::", 2)] {
        for (i, _) in code.match_indices(kw) {
            if i > 0
                && (bytes[i - 1].is_ascii_alphanumeric()
                    || bytes[i - 1] == b'_'
                    || bytes[i - 1] == b':')
            {
                continue; // part of a longer word or path (`xcrate::`, `super::super::`)
            }
            let mut start: Vec<String> = match base {
                0 => Vec::new(),
                1 => own[..own.len().saturating_sub(1)].to_vec(),
                _ => own.to_vec(),
            };
            let mut rest = &code[i + kw.len()..];
            while let Some(r) = rest.strip_prefix("super::") {
                start.pop();
                rest = r;
            }
            // The identifiers of a path, up to the first character that continues no path.
            let segments = |s: &str| -> Vec<String> {
                let mut out = Vec::new();
                let mut rest = s.trim_start();
                loop {
                    let name: String = rest
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    if name.is_empty() {
                        break;
                    }
                    rest = &rest[name.len()..];
                    out.push(name);
                    match rest.strip_prefix("::") {
                        Some(r) => rest = r,
                        None => break,
                    }
                }
                out
            };
            if let Some(group) = rest.strip_prefix('{') {
                let group = group.split('}').next().unwrap_or("");
                for item in group.split(',') {
                    let mut p = start.clone();
                    p.extend(segments(item));
                    out.push(p);
                }
            } else {
                let mut p = start.clone();
                p.extend(segments(rest));
                out.push(p);
            }
        }
    }
    out
}

/// The lines of `text` that are not test code: a `#[cfg(test)] mod x { … }` ends the scan of a
/// file (test modules close it, by the project's convention); a `#[cfg(test)]` before a
/// one-line item skips that line; comments are cut.
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

/// One import of a scanned crate: where (file:line), from which module, to which module.
struct Import {
    at: String,
    from: Vec<String>,
    to: Vec<String>,
    /// The first name after `crate::`, if the path started there.
    first: Option<String>,
}

/// Every import outside test code of the crate under `src` (`tests.rs` files are test code).
fn imports(src: &Path) -> (Vec<Vec<String>>, Vec<Import>) {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    let modules: Vec<Vec<String>> = files
        .iter()
        .map(|f| module_of(f.strip_prefix(src).unwrap()))
        .collect();
    let mut out = Vec::new();
    for (f, own) in files.iter().zip(&modules) {
        let rel = f.strip_prefix(src).unwrap();
        if rel.file_name().unwrap() == "tests.rs" {
            continue;
        }
        let text = std::fs::read_to_string(f).unwrap();
        for (n, code) in code_lines(&text) {
            let firsts = code.match_indices("crate::").count();
            for path in named_paths(code, own) {
                // The longest prefix of the path that is a module of the crate.
                let to = (0..=path.len())
                    .rev()
                    .map(|k| path[..k].to_vec())
                    .find(|p| modules.contains(p))
                    .unwrap_or_default();
                out.push(Import {
                    at: format!("{}:{n}", rel.display()),
                    from: own.clone(),
                    to,
                    first: (firsts > 0).then(|| path.first().cloned()).flatten(),
                });
            }
        }
    }
    (modules, out)
}

/// The edge an import makes between two sibling modules: `a::b::c → a::d::e` is `a::b → a::d`
/// (what the circle check looks at); `None` within one module or between a module and its
/// ancestors (a child naming its parent, a parent its child: one unit).
fn sibling_edge(from: &[String], to: &[String]) -> Option<(Vec<String>, Vec<String>)> {
    let k = from.iter().zip(to).take_while(|(a, b)| a == b).count();
    (k < from.len() && k < to.len()).then(|| (from[..=k].to_vec(), to[..=k].to_vec()))
}

/// A circle in `edges`, as the list of its nodes (the first repeated at the end), if any.
fn circle<N: Ord + Clone>(edges: &BTreeMap<N, Vec<N>>) -> Option<Vec<N>> {
    // Depth-first search; a node met again while on the stack closes a circle.
    fn visit<N: Ord + Clone>(
        n: &N,
        edges: &BTreeMap<N, Vec<N>>,
        done: &mut Vec<N>,
        stack: &mut Vec<N>,
    ) -> Option<Vec<N>> {
        if let Some(i) = stack.iter().position(|s| s == n) {
            let mut c = stack[i..].to_vec();
            c.push(n.clone());
            return Some(c);
        }
        if done.contains(n) {
            return None;
        }
        stack.push(n.clone());
        for m in edges.get(n).into_iter().flatten() {
            if let Some(c) = visit(m, edges, done, stack) {
                return Some(c);
            }
        }
        stack.pop();
        done.push(n.clone());
        None
    }
    let mut done = Vec::new();
    for n in edges.keys() {
        if let Some(c) = visit(n, edges, &mut done, &mut Vec::new()) {
            return Some(c);
        }
    }
    None
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[test]
fn no_module_names_a_higher_layer() {
    for c in &CRATES {
        let (modules, imports) = imports(&workspace().join(c.src));
        assert!(
            modules.len() > 5,
            "{}: the scan found {} files",
            c.src,
            modules.len()
        );
        let mut offenders = Vec::new();
        for m in modules.iter().filter(|m| !m.is_empty()) {
            rank(c.layers, &m[0]).unwrap_or_else(|| panic!("{}: {} is in no layer", c.src, m[0]));
        }
        for i in &imports {
            let (Some(own), Some(first)) = (i.from.first(), &i.first) else {
                continue; // the crate root (lib.rs: the facade) or a relative path
            };
            let theirs = rank(c.layers, first)
                .unwrap_or_else(|| panic!("{}/{}: crate::{first} is in no layer", c.src, i.at));
            if theirs > rank(c.layers, own).unwrap() {
                offenders.push(format!("{}/{}: {own} names crate::{first}", c.src, i.at));
            }
        }
        assert!(offenders.is_empty(), "{}", offenders.join("\n"));
    }
}

#[test]
fn no_import_circle_between_modules() {
    for c in &CRATES {
        let (_, imports) = imports(&workspace().join(c.src));
        let mut edges: BTreeMap<Vec<String>, Vec<Vec<String>>> = BTreeMap::new();
        let mut example: BTreeMap<(Vec<String>, Vec<String>), String> = BTreeMap::new();
        for i in &imports {
            if let Some((a, b)) = sibling_edge(&i.from, &i.to) {
                example
                    .entry((a.clone(), b.clone()))
                    .or_insert_with(|| i.at.clone());
                let e = edges.entry(a).or_default();
                if !e.contains(&b) {
                    e.push(b);
                }
            }
        }
        if let Some(cycle) = circle(&edges) {
            let steps: Vec<String> = cycle
                .windows(2)
                .map(|w| {
                    format!(
                        "{} → {} ({})",
                        w[0].join("::"),
                        w[1].join("::"),
                        example[&(w[0].clone(), w[1].clone())]
                    )
                })
                .collect();
            panic!("{}: an import circle: {}", c.src, steps.join(", "));
        }
    }
}

#[test]
fn the_scan_resolves_paths_and_skips_test_code() {
    let own: Vec<String> = ["studies", "stability", "report"]
        .map(String::from)
        .to_vec();
    let names = |code: &str| -> Vec<String> {
        named_paths(code, &own)
            .iter()
            .map(|p| p.join("::"))
            .collect()
    };
    assert_eq!(
        names("use crate::{physics::fe, input::case::Case};"),
        ["physics::fe", "input::case::Case"]
    );
    assert_eq!(
        names("use super::coupled::f;"),
        ["studies::stability::coupled::f"]
    );
    assert_eq!(names("use super::super::design;"), ["studies::design"]);
    assert_eq!(
        names("let x = crate::Error::x(self::y);"),
        ["Error::x", "studies::stability::report::y"]
    );
    let layers = CRATES[0].layers;
    assert!(rank(layers, "studies").unwrap() > rank(layers, "physics").unwrap());
    let text = "use crate::physics::fe;\n#[cfg(test)]\nuse crate::studies::x;\nfn f() {}\n#[cfg(test)]\nmod tests {\n    use crate::studies::y;\n}\n";
    let kept: Vec<&str> = code_lines(text).into_iter().map(|(_, c)| c).collect();
    assert_eq!(kept, ["use crate::physics::fe;", "fn f() {}"]);
}

#[test]
fn the_circle_check_sees_a_circle_between_siblings_only() {
    let p = |s: &str| -> Vec<String> { s.split("::").map(String::from).collect() };
    // A child naming its parent, or the parent its child, is no edge; cousins meet at their
    // common parent's children.
    assert_eq!(sibling_edge(&p("a::b"), &p("a")), None);
    assert_eq!(sibling_edge(&p("a"), &p("a::b")), None);
    assert_eq!(
        sibling_edge(&p("a::b::c"), &p("a::d::e")),
        Some((p("a::b"), p("a::d")))
    );
    let mut edges = BTreeMap::new();
    edges.insert(1, vec![2]);
    edges.insert(2, vec![3]);
    edges.insert(3, vec![4]);
    assert_eq!(circle(&edges), None);
    edges.insert(4, vec![2]);
    assert_eq!(circle(&edges), Some(vec![2, 3, 4, 2]));
}
