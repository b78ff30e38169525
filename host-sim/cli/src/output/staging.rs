//! An output directory that holds exactly one complete run, or nothing new.
//!
//! A run writes into a hidden sibling directory and renames it into place when every file is
//! written, so an interrupted or failed run leaves neither half-written files nor a mix of an
//! old run's files with a new run's. A directory that exists is replaced only when it is an
//! output of the same kind (it holds that kind's marker file) or empty: anything else,
//! including a maglev output of the other kind (a run's directory given to `sweep merge`, a
//! sweep's to `run`), is refused rather than overwritten.
//!
//! The rule is checked when the run starts and again on the directory itself once it has
//! been renamed aside at the end (a directory made or filled at `--out` during the run is
//! put back and the run refused, never deleted). What a process leaves when it is killed is
//! cleaned by the next run into the same `--out`: its staging directory
//! (`.OUT.partial-PID`, known by [`PARTIAL`] inside) and the previous output it had renamed
//! aside (`.OUT.old-PID`, put back when `--out` is missing, else removed if marked). A
//! signal removes the staging directory at once ([`interrupt`]).
//!
//! A staging directory is known to be abandoned by its [`PARTIAL`] file, which the writing
//! process holds locked (`flock`) for as long as it lives: the kernel drops the lock when the
//! process ends, however it ends, so a process id reused by an unrelated process does not
//! keep a dead run's directory (the PID in the name only keeps concurrent runs apart). Where
//! the file system has no locks, the PID decides: alive means kept.

pub mod interrupt;

use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The file that marks a directory as a maglev run's output.
pub const MARKER: &str = ".maglev-output";

/// The file that marks a directory as a sweep's (written by `studies/sweep/store.rs`; here so
/// the output layer can recognise a sweep without naming the study above it).
pub const SWEEP_MARKER: &str = ".maglev-sweep";

/// The file that marks a staging directory (a run being written) as maglev's.
pub const PARTIAL: &str = ".maglev-partial";

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
                SWEEP_MARKER,
                "a maglev sweep",
                "maglev sweep (merged): runs/ holds one record per finished run\n",
            ),
        }
    }

    /// `Ok` when `dir` is missing, empty or this kind's output; else the `--out` error.
    fn may_replace(self, dir: &Path, target: &Path) -> Result<()> {
        if !dir.exists() {
            return Ok(());
        }
        let (marker, what, _) = self.marker();
        if dir.join(marker).is_file() || is_empty(dir)? {
            return Ok(());
        }
        let is = Kind::ALL
            .iter()
            .map(|k| k.marker())
            .find(|(m, _, _)| dir.join(m).is_file())
            .map_or("not a maglev output".to_string(), |(m, w, _)| {
                format!("{w} ({m}), not {what}")
            });
        Err(Error::invalid(
            format!("--out {}", target.display()),
            format!(
                "the directory exists and is {is} (no {marker} file); refusing to overwrite it"
            ),
        ))
    }
}

fn is_empty(dir: &Path) -> Result<bool> {
    Ok(std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .next()
        .is_none())
}

/// A run's output being written.
pub struct Staging {
    target: PathBuf,
    tmp: PathBuf,
    /// Where the previous output is moved while the new one is renamed into place.
    old: PathBuf,
    kind: Kind,
    /// The [`PARTIAL`] file, held locked while the run lives (module docs); `None` where the
    /// file system has no locks.
    _alive: Option<std::fs::File>,
    /// The parent directories this run created for `--out`, deepest first: removed again
    /// (when still empty) by a run that does not finish.
    made: Vec<PathBuf>,
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
        clean_stale(&parent, &name, target, kind);
        kind.may_replace(target, target)?;
        let made = missing_ancestors(&parent);
        std::fs::create_dir_all(&parent).map_err(|e| Error::io(&parent, e))?;
        let pid = std::process::id();
        let tmp = parent.join(format!(".{name}.partial-{pid}"));
        let _ = std::fs::remove_dir_all(&tmp);
        let alive = interrupt::register(&tmp, || create_locked(&tmp))?;
        Ok(Staging {
            target: target.to_path_buf(),
            old: parent.join(format!(".{name}.old-{pid}")),
            tmp,
            kind,
            _alive: alive,
            made,
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
    /// What is at `--out` now is checked again (module docs): anything else stays, and the
    /// run is refused.
    pub fn finish(mut self) -> Result<()> {
        let made = std::mem::take(&mut self.made);
        let finished = self.move_into_place();
        if finished.is_err() {
            self.made = made;
        }
        finished
    }

    /// [`Self::finish`] but for the parents it keeps.
    fn move_into_place(&self) -> Result<()> {
        let (marker, _, text) = self.kind.marker();
        self.put(marker, text)?;
        let _ = std::fs::remove_file(self.tmp.join(PARTIAL));
        let mut active = interrupt::hold();
        let moved = self.target.exists();
        if moved {
            std::fs::rename(&self.target, &self.old).map_err(|e| Error::io(&self.target, e))?;
            if let Err(e) = self.kind.may_replace(&self.old, &self.target) {
                // Changed during the run: put it back as it is.
                return Err(match std::fs::rename(&self.old, &self.target) {
                    Ok(()) => e,
                    Err(_) => Error::invalid(
                        format!("--out {}", self.target.display()),
                        format!(
                            "changed during the run; it was moved aside to {} and kept",
                            self.old.display()
                        ),
                    ),
                });
            }
        }
        if let Err(e) = std::fs::rename(&self.tmp, &self.target) {
            if moved {
                let _ = std::fs::rename(&self.old, &self.target);
            }
            return Err(Error::io(&self.target, e));
        }
        active.retain(|d| d != &self.tmp);
        drop(active);
        if moved {
            remove_replaced(&self.old);
        }
        Ok(())
    }
}

/// The ancestors of `dir` that do not exist, `dir` first (what `create_dir_all` will make).
fn missing_ancestors(dir: &Path) -> Vec<PathBuf> {
    dir.ancestors()
        .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
        .map(Path::to_path_buf)
        .collect()
}

/// Creates staging directory `tmp` with its [`PARTIAL`] file locked (module docs). The file
/// is written and locked under another name and then renamed, so no other process ever sees
/// an unlocked [`PARTIAL`] of a live run. `None`: the file system has no locks.
fn create_locked(tmp: &Path) -> Result<Option<std::fs::File>> {
    let io = |e| Error::io(tmp, e);
    std::fs::create_dir(tmp).map_err(io)?;
    let unnamed = tmp.join(format!("{PARTIAL}.new"));
    let mut file = std::fs::File::create(&unnamed).map_err(io)?;
    let locked = file.try_lock().is_ok();
    std::io::Write::write_all(&mut file, b"a maglev run being written\n").map_err(io)?;
    std::fs::rename(&unnamed, tmp.join(PARTIAL)).map_err(io)?;
    Ok(locked.then_some(file))
}

/// Whether the staging directory `dir` (named with `pid`) was abandoned: its [`PARTIAL`]
/// file is there and no process holds its lock (module docs); by the PID where the file
/// system has no locks.
fn abandoned(dir: &Path, pid: u32) -> bool {
    let Ok(file) = std::fs::File::open(dir.join(PARTIAL)) else {
        return false;
    };
    match file.try_lock() {
        Ok(()) => true,
        Err(std::fs::TryLockError::WouldBlock) => false,
        Err(std::fs::TryLockError::Error(_)) => !is_alive(pid),
    }
}

/// Removes a previous output moved aside (checked to be replaceable): all of it when marked,
/// only an empty directory otherwise (`remove_dir` refuses one filled meanwhile).
fn remove_replaced(old: &Path) {
    let marked = Kind::ALL.iter().any(|k| old.join(k.marker().0).is_file());
    let _ = if marked {
        std::fs::remove_dir_all(old)
    } else {
        std::fs::remove_dir(old)
    };
}

/// Cleans what dead processes left beside `target` (module docs): staging directories of
/// `name` that hold [`PARTIAL`], and previous outputs moved aside.
fn clean_stale(parent: &Path, name: &str, target: &Path, kind: Kind) {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    let (partial, old) = (format!(".{name}.partial-"), format!(".{name}.old-"));
    for entry in entries.flatten() {
        // Most entries of a parent such as /tmp are not ours: only their name is read.
        let file = entry.file_name();
        let file = file.to_string_lossy();
        let pid = |prefix: &str| {
            file.strip_prefix(prefix)
                .and_then(|pid| pid.parse::<u32>().ok())
        };
        let (staged, aside) = (pid(&partial), pid(&old));
        if staged.is_none() && aside.is_none() {
            continue;
        }
        let path = entry.path();
        if staged.is_some_and(|pid| abandoned(&path, pid)) {
            let _ = std::fs::remove_dir_all(&path);
        } else if aside.is_some_and(|pid| !is_alive(pid)) {
            if !target.exists() {
                let _ = std::fs::rename(&path, target);
            } else if kind.may_replace(&path, target).is_ok() {
                remove_replaced(&path);
            }
        }
    }
}

/// Whether process `pid` exists (a signal 0 reaches it, or it is another user's).
#[cfg(unix)]
fn is_alive(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return true;
    };
    // SAFETY: kill with signal 0 sends nothing; it only checks that the process exists.
    let r = unsafe { libc::kill(pid, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

/// Elsewhere every process counts as alive: nothing is cleaned.
#[cfg(not(unix))]
fn is_alive(_pid: u32) -> bool {
    true
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
    // Listed while it exists, so a signal removes it as it does a staging directory.
    let written = interrupt::register(&tmp, || std::fs::write(&tmp, text));
    let mut active = interrupt::hold();
    let done = written
        .map_err(|e| Error::io(&tmp, e))
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e)));
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    active.retain(|d| d != &tmp);
    done
}

impl Drop for Staging {
    /// A run that did not finish leaves nothing behind.
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.tmp);
        interrupt::unregister(&self.tmp);
        // Deepest first; `remove_dir` keeps one that something else filled meanwhile.
        for d in &self.made {
            let _ = std::fs::remove_dir(d);
        }
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

    /// A run that does not finish (an error, a panic) removes the parents it made for
    /// `--out`, and only those; one that finishes keeps them.
    #[test]
    fn an_unfinished_run_removes_the_parents_it_made() {
        let root = scratch("parents");
        let out = root.join("a/b/c/out");
        let s = Staging::new(&out).unwrap();
        s.put("response.csv", "t\n").unwrap();
        assert!(root.join("a/b/c").is_dir());
        let panicked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || {
            let _owned = s;
            panic!("the run panicked");
        }));
        assert!(panicked.is_err());
        assert!(
            !root.join("a").exists(),
            "left {:?}",
            std::fs::read_dir(&root).unwrap().collect::<Vec<_>>()
        );
        assert!(root.is_dir(), "a directory that existed stays");
        // Dropped on an error, with a file put in a parent meanwhile: that parent stays.
        let s = Staging::new(&out).unwrap();
        std::fs::write(root.join("a/note"), "mine").unwrap();
        drop(s);
        assert!(!root.join("a/b").exists());
        assert_eq!(
            std::fs::read_to_string(root.join("a/note")).unwrap(),
            "mine"
        );
        std::fs::remove_file(root.join("a/note")).unwrap();
        // Finished: kept.
        Staging::new(&out).unwrap().finish().unwrap();
        assert!(out.join(MARKER).is_file());
        std::fs::remove_dir_all(&root).unwrap();
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
        assert!(sweep.join(SWEEP_MARKER).exists());
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

    /// A process id that no process has (a child that has exited and been reaped).
    fn dead_pid() -> u32 {
        let mut c = std::process::Command::new("true").spawn().unwrap();
        let pid = c.id();
        c.wait().unwrap();
        assert!(!is_alive(pid));
        pid
    }

    #[test]
    fn a_directory_made_at_out_during_the_run_is_kept_and_the_run_refused() {
        let root = scratch("d1");
        let out = root.join("out");
        let s = Staging::new(&out).unwrap();
        s.put("response.csv", "new").unwrap();
        std::fs::create_dir(&out).unwrap();
        std::fs::write(out.join("notes.txt"), "notes").unwrap();
        let e = s.finish().unwrap_err().to_string();
        assert!(
            e.contains("not a maglev output") && e.contains("refusing"),
            "{e}"
        );
        assert_eq!(
            std::fs::read_to_string(out.join("notes.txt")).unwrap(),
            "notes"
        );
        let left: Vec<_> = std::fs::read_dir(&root).unwrap().collect();
        assert_eq!(
            left.len(),
            1,
            "the staging directory or the aside copy was left"
        );
        // Nor does a marked run's directory lose what was put at --out in its place.
        let s = Staging::new(&root.join("run")).unwrap();
        std::fs::create_dir(root.join("run")).unwrap();
        std::fs::write(root.join("run/thesis.tex"), "x").unwrap();
        assert!(s.finish().is_err());
        assert!(root.join("run/thesis.tex").exists());
    }

    #[test]
    fn what_a_killed_run_left_is_cleaned_by_the_next_run() {
        let root = scratch("d6");
        let out = root.join("out");
        Staging::new(&out).unwrap().finish().unwrap();
        let pid = dead_pid();
        // A killed run's staging directory; one whose PID now belongs to another live
        // process (1, init: alive, but the run's lock is gone); a live run's (its PARTIAL
        // locked, as another process holds it: flock locks of two opens are independent);
        // and a directory that only looks like a staging directory (no PARTIAL file).
        let stale = root.join(format!(".out.partial-{pid}"));
        std::fs::create_dir(&stale).unwrap();
        std::fs::write(stale.join(PARTIAL), "").unwrap();
        let reused = root.join(".out.partial-1");
        std::fs::create_dir(&reused).unwrap();
        std::fs::write(reused.join(PARTIAL), "").unwrap();
        let live = root.join(format!(".out.partial-{}", pid + 2_000_000));
        std::fs::create_dir(&live).unwrap();
        std::fs::write(live.join(PARTIAL), "").unwrap();
        let held = std::fs::File::open(live.join(PARTIAL)).unwrap();
        held.try_lock().unwrap();
        let lookalike = root.join(format!(".out.partial-{}", pid + 1_000_000));
        std::fs::create_dir(&lookalike).unwrap();
        std::fs::write(lookalike.join("data"), "").unwrap();
        let s = Staging::new(&out).unwrap();
        assert!(
            !stale.exists(),
            "a dead process's staging directory was kept"
        );
        assert!(
            !reused.exists(),
            "a staging directory whose PID was reused was kept"
        );
        assert!(live.exists() && lookalike.exists());
        // Our own staging directory is locked: a second run into the same --out keeps it.
        let ours = root.join(format!(".out.partial-{}", std::process::id()));
        assert!(ours.join(PARTIAL).is_file() && !abandoned(&ours, std::process::id()));
        drop(held);
        s.finish().unwrap();
        // A run killed between its two renames: the previous output is put back.
        std::fs::rename(&out, root.join(format!(".out.old-{pid}"))).unwrap();
        Staging::new(&out).unwrap();
        assert!(
            out.join(MARKER).is_file(),
            "the previous output was not put back"
        );
    }

    #[test]
    fn a_left_over_old_directory_does_not_stop_later_runs() {
        let root = scratch("d7");
        let out = root.join("out");
        // The name earlier versions moved the previous output to, left full by a crash.
        std::fs::create_dir(root.join(".out.old")).unwrap();
        std::fs::write(root.join(".out.old/x"), "").unwrap();
        for _ in 0..2 {
            let s = Staging::new(&out).unwrap();
            s.put("a", "b").unwrap();
            s.finish().unwrap();
        }
        assert!(root.join(".out.old/x").exists(), "not ours to delete");
    }
}
