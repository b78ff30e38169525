//! Files a command owns in a directory it shares with others (`validate --out docs`).
//!
//! Why not [`super::Staging`]: a run's directory is replaced whole, which `docs/` must never
//! be. The rule is the same one, per file: a command writes into a directory only when it is
//! new or empty, or its marker [`MANIFEST`] says that command wrote there before; and there
//! it replaces only the files the marker lists (or files that do not exist yet), adding the
//! names it wrote to the list. So `validate --out docs --report validation.md` regenerates
//! the committed docs/validation.md and its figures (docs/.maglev-validation lists them),
//! and `validate --out ~/thesis` or `--report README.md` is refused before anything runs.

use super::write_atomic;
use crate::{Error, Result};
use std::path::Path;

/// The marker of a directory `maglev validate` writes into: the names of its files there.
pub const MANIFEST: &str = ".maglev-validation";

/// The names the marker of `dir` lists (none when it has no marker).
fn listed(dir: &Path) -> Result<Vec<String>> {
    let p = dir.join(MANIFEST);
    if !p.is_file() {
        return Ok(Vec::new());
    }
    let text = std::fs::read_to_string(&p).map_err(|e| Error::io(&p, e))?;
    Ok(text.lines().map(str::to_string).collect())
}

/// `Ok` when `name` is a plain file name (one component, not `.` or `..`), so that it lands
/// inside the directory it is joined to; else the error naming `key` (`--report ../notes.md`
/// would replace a file beside `--out`, outside it).
pub fn plain_name(key: &str, name: &str) -> Result<()> {
    let mut parts = Path::new(name).components();
    match (parts.next(), parts.next()) {
        (Some(std::path::Component::Normal(n)), None) if n == name => Ok(()),
        _ => Err(Error::invalid(
            key,
            format!("must be a file name inside --out (no directory, `..` or `/`), got {name:?}"),
        )),
    }
}

/// `Ok` when `names` may be written into `dir` (module docs), else the `--out` error naming
/// the first file that is not ours (or not a plain file name, [`plain_name`]).
pub fn check(dir: &Path, names: &[&str]) -> Result<()> {
    for n in names {
        plain_name(&format!("--out {}: file", dir.display()), n)?;
    }
    let refuse = |why: String| {
        Err(Error::invalid(
            format!("--out {}", dir.display()),
            format!("{why}; refusing to overwrite it"),
        ))
    };
    if !dir.exists() {
        return Ok(());
    }
    let empty = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .next()
        .is_none();
    if empty {
        return Ok(());
    }
    if !dir.join(MANIFEST).is_file() {
        return refuse(format!(
            "the directory exists and is not a maglev validation output (no {MANIFEST} file)"
        ));
    }
    let ours = listed(dir)?;
    match names
        .iter()
        .find(|n| dir.join(n).exists() && !ours.iter().any(|o| o == *n))
    {
        Some(n) => refuse(format!("{n} exists there and is not listed in {MANIFEST}")),
        None => Ok(()),
    }
}

/// Checks `files` ([`check`]) and writes each beside its place and renamed into it, then the
/// marker with their names added.
pub fn write(dir: &Path, files: &[(String, String)]) -> Result<()> {
    let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    check(dir, &names)?;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let mut ours = listed(dir)?;
    for (name, text) in files {
        write_atomic(&dir.join(name), text.as_bytes())?;
        if !ours.contains(name) {
            ours.push(name.clone());
        }
    }
    ours.sort();
    write_atomic(&dir.join(MANIFEST), (ours.join("\n") + "\n").as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_its_own_files_are_replaced() {
        let d = std::env::temp_dir().join(format!("maglev-owned-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        let files = |r: &str| vec![(r.to_string(), "report".to_string())];
        write(&d, &files("report.md")).unwrap();
        write(&d, &files("report.md")).unwrap();
        std::fs::write(d.join("notes.md"), "mine").unwrap();
        let e = write(&d, &files("notes.md")).unwrap_err().to_string();
        assert!(e.contains("notes.md exists there and is not listed"), "{e}");
        assert_eq!(std::fs::read_to_string(d.join("notes.md")).unwrap(), "mine");
        // A directory without the marker is refused whole.
        std::fs::remove_file(d.join(MANIFEST)).unwrap();
        let e = write(&d, &files("report.md")).unwrap_err().to_string();
        assert!(e.contains("not a maglev validation output"), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    /// A name that leaves the directory is refused before anything is written, naming the
    /// key; the file beside the directory is untouched.
    #[test]
    fn a_name_outside_the_directory_is_refused() {
        let root = std::env::temp_dir().join(format!("maglev-owned-out-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let d = root.join("v");
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(root.join("notes.md"), "mine").unwrap();
        for name in ["../notes.md", "sub/report.md", "/tmp/report.md", "..", "."] {
            let e = plain_name("--report", name).unwrap_err().to_string();
            assert!(
                e.starts_with("--report: must be a file name"),
                "{name}: {e}"
            );
            let e = write(&d, &[(name.to_string(), "report".to_string())])
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("must be a file name inside --out"),
                "{name}: {e}"
            );
        }
        assert_eq!(
            std::fs::read_to_string(root.join("notes.md")).unwrap(),
            "mine"
        );
        plain_name("--report", "validation.md").unwrap();
        std::fs::remove_dir_all(&root).unwrap();
    }
}
