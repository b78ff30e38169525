//! An output directory that holds exactly one complete run, or nothing new.
//!
//! A run writes into a hidden sibling directory and renames it into place when every file is
//! written, so an interrupted or failed run leaves neither half-written files nor a mix of an
//! old run's files with a new run's. A directory that exists and is not a maglev output (it
//! lacks the [`MARKER`] file and is not empty) is refused rather than overwritten.

use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The file that marks a directory as a maglev run's output.
pub const MARKER: &str = ".maglev-output";

/// A run's output being written.
pub struct Staging {
    target: PathBuf,
    tmp: PathBuf,
}

impl Staging {
    /// Checks that `target` may be replaced and creates the staging directory beside it.
    pub fn new(target: &Path) -> Result<Self> {
        if target.exists() {
            let is_ours = target.join(MARKER).is_file();
            let empty = std::fs::read_dir(target)
                .map_err(|e| Error::io(target, e))?
                .next()
                .is_none();
            if !is_ours && !empty {
                return Err(Error::invalid(
                    format!("--out {}", target.display()),
                    format!("the directory exists and is not a maglev output (no {MARKER} file); refusing to overwrite it"),
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

    /// Moves the complete run into place, replacing the previous maglev output there.
    pub fn finish(self) -> Result<()> {
        self.put(
            MARKER,
            "maglev run output; the whole directory is replaced by the next run\n",
        )?;
        let old = self.tmp.with_extension("old");
        if self.target.exists() {
            std::fs::rename(&self.target, &old).map_err(|e| Error::io(&self.target, e))?;
        }
        std::fs::rename(&self.tmp, &self.target).map_err(|e| Error::io(&self.target, e))?;
        let _ = std::fs::remove_dir_all(&old);
        Ok(())
    }
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
}
