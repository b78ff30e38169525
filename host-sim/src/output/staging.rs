//! An output directory that holds exactly one complete run, or nothing new.
//!
//! A run writes into a hidden sibling directory and renames it into place when every file is
//! written, so an interrupted or failed run leaves neither half-written files nor a mix of an
//! old run's files with a new run's. A directory that exists is replaced only when it is an
//! output of the same kind (it holds that kind's marker file) or empty: anything else,
//! including a maglev output of the other kind (a run's directory given to `sweep merge`, a
//! sweep's to `run`), is refused rather than overwritten.

use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The file that marks a directory as a maglev run's output.
pub const MARKER: &str = ".maglev-output";

/// The kinds of output directory; each replaces only its own.
#[derive(Clone, Copy)]
enum Kind {
    /// `run`, `hil`, `report`.
    Run,
    /// `sweep merge` (a sweep's own directory is kept by sweep/store.rs).
    Sweep,
}

impl Kind {
    const ALL: [Kind; 2] = [Kind::Run, Kind::Sweep];

    /// The marker file, what the kind is called, and the marker's text.
    fn marker(self) -> (&'static str, &'static str, &'static str) {
        match self {
            Kind::Run => (
                MARKER,
                "a maglev run's output",
                "maglev run output; the whole directory is replaced by the next run\n",
            ),
            Kind::Sweep => (
                crate::sweep::store::MARKER,
                "a maglev sweep",
                "maglev sweep (merged): runs/ holds one record per finished run\n",
            ),
        }
    }
}

/// A run's output being written.
pub struct Staging {
    target: PathBuf,
    tmp: PathBuf,
    kind: Kind,
}

impl Staging {
    /// Checks that `target` may be replaced by a run's output and creates the staging
    /// directory beside it.
    pub fn new(target: &Path) -> Result<Self> {
        Self::of_kind(target, Kind::Run)
    }

    /// The same for a merged sweep (`sweep merge`): replaces a sweep directory, never a run's.
    pub fn sweep(target: &Path) -> Result<Self> {
        Self::of_kind(target, Kind::Sweep)
    }

    fn of_kind(target: &Path, kind: Kind) -> Result<Self> {
        if target.exists() {
            let (marker, what, _) = kind.marker();
            let is_ours = target.join(marker).is_file();
            let empty = std::fs::read_dir(target)
                .map_err(|e| Error::io(target, e))?
                .next()
                .is_none();
            if !is_ours && !empty {
                let is = Kind::ALL
                    .iter()
                    .map(|k| k.marker())
                    .find(|(m, _, _)| target.join(m).is_file())
                    .map_or("not a maglev output".to_string(), |(m, w, _)| {
                        format!("{w} ({m}), not {what}")
                    });
                return Err(Error::invalid(
                    format!("--out {}", target.display()),
                    format!("the directory exists and is {is} (no {marker} file); refusing to overwrite it"),
                ));
            }
        }
        let name = target
            .file_name()
            .ok_or_else(|| {
                Error::invalid(
                    format!("--out {}", target.display()),
                    "not a directory name",
                )
            })?
            .to_string_lossy()
            .into_owned();
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&parent).map_err(|e| Error::io(&parent, e))?;
        let tmp = parent.join(format!(".{name}.partial-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&tmp);
        std::fs::create_dir(&tmp).map_err(|e| Error::io(&tmp, e))?;
        Ok(Staging {
            target: target.to_path_buf(),
            tmp,
            kind,
        })
    }

    /// Where file `name` of the run is being written (for streamed files).
    pub fn path(&self, name: &str) -> PathBuf {
        self.tmp.join(name)
    }

    /// Writes (or replaces) one file of the run.
    pub fn put(&self, name: &str, text: &str) -> Result<()> {
        let p = self.tmp.join(name);
        std::fs::write(&p, text).map_err(|e| Error::io(p, e))
    }

    /// Moves the complete run into place, replacing the previous output of its kind there.
    pub fn finish(self) -> Result<()> {
        let (marker, _, text) = self.kind.marker();
        self.put(marker, text)?;
        let old = self.tmp.with_extension("old");
        if self.target.exists() {
            std::fs::rename(&self.target, &old).map_err(|e| Error::io(&self.target, e))?;
        }
        std::fs::rename(&self.tmp, &self.target).map_err(|e| Error::io(&self.target, e))?;
        let _ = std::fs::remove_dir_all(&old);
        Ok(())
    }
}

/// Writes `text` to `path` through a sibling temporary file and a rename.
pub fn write_atomic(path: &Path, text: &[u8]) -> Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(
        ".{name}.tmp-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::write(&tmp, text).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e))
}

impl Drop for Staging {
    /// A run that did not finish leaves nothing behind.
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.tmp);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("maglev-staging-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_run_replaces_the_previous_run_whole() {
        let root = scratch("replace");
        let out = root.join("out");
        let s = Staging::new(&out).unwrap();
        s.put("a.svg", "old").unwrap();
        s.put("b.csv", "old").unwrap();
        s.finish().unwrap();
        let s = Staging::new(&out).unwrap();
        s.put("b.csv", "new").unwrap();
        s.finish().unwrap();
        assert!(
            !out.join("a.svg").exists(),
            "a stale file of the old run survived"
        );
        assert_eq!(std::fs::read_to_string(out.join("b.csv")).unwrap(), "new");
        let left: Vec<_> = std::fs::read_dir(&root).unwrap().collect();
        assert_eq!(left.len(), 1, "staging directories left behind");
    }

    #[test]
    fn an_unfinished_run_leaves_nothing() {
        let root = scratch("unfinished");
        let out = root.join("out");
        {
            let s = Staging::new(&out).unwrap();
            s.put("a.csv", "half").unwrap();
        }
        assert!(!out.exists());
        assert_eq!(std::fs::read_dir(&root).unwrap().count(), 0);
    }

    #[test]
    fn a_foreign_directory_is_refused() {
        let root = scratch("foreign");
        std::fs::write(root.join("thesis.tex"), "precious").unwrap();
        let e = Staging::new(&root).err().unwrap().to_string();
        assert!(e.contains("not a maglev output"), "{e}");
        assert!(root.join("thesis.tex").exists());
        // An empty directory is fine.
        let empty = root.join("empty");
        std::fs::create_dir(&empty).unwrap();
        Staging::new(&empty).unwrap().finish().unwrap();
        assert!(empty.join(MARKER).exists());
    }

    #[test]
    fn each_kind_replaces_only_its_own() {
        let root = scratch("kinds");
        let (run, sweep) = (root.join("run"), root.join("sweep"));
        Staging::new(&run).unwrap().finish().unwrap();
        Staging::sweep(&sweep).unwrap().finish().unwrap();
        assert!(sweep.join(crate::sweep::store::MARKER).exists());
        assert!(
            !sweep.join(MARKER).exists(),
            "a merged sweep marked as a run"
        );
        let e = Staging::new(&sweep).err().unwrap().to_string();
        assert!(
            e.contains("is a maglev sweep (.maglev-sweep), not a maglev run's output"),
            "{e}"
        );
        let e = Staging::sweep(&run).err().unwrap().to_string();
        assert!(
            e.contains("is a maglev run's output (.maglev-output), not a maglev sweep"),
            "{e}"
        );
        // Each replaces its own kind.
        Staging::new(&run).unwrap().finish().unwrap();
        Staging::sweep(&sweep).unwrap().finish().unwrap();
    }
}
