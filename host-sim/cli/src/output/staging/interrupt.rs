//! SIGINT, SIGTERM and SIGHUP remove the staging directories of the runs under way, then end
//! the process as the signal would have.
//!
//! Why: a staging directory is removed when its [`super::Staging`] is dropped, which an
//! error reaches but a signal does not: every interrupted run left its `.OUT.partial-PID/`
//! behind (and an atomic write its `.NAME.tmp-…` file). A thread waits for the signals (signal-hook: libc and its registry, smaller than
//! ctrlc's nix); the directories are listed here while they exist. [`hold`] keeps a signal
//! from removing a directory while it is being renamed into place.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The staging directories (and `write_atomic`'s temporary files) of this process that exist
/// now.
static ACTIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn active() -> MutexGuard<'static, Vec<PathBuf>> {
    ACTIVE.lock().unwrap_or_else(|p| p.into_inner())
}

/// Starts the thread that handles the signals (`main` calls it once; a library user that
/// does not keeps its own signal handling). Without it the directories are still removed
/// on every error, only not on a signal.
pub fn install() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            remove_all(&mut active());
            // Ends the process as the signal's default action does (status 128 + sig).
            let _ = signal_hook::low_level::emulate_default_handler(sig);
            std::process::exit(128 + sig);
        }
    });
}

/// Removes every listed directory or file (a few tries: the run may be creating a file in
/// a directory).
fn remove_all(paths: &mut Vec<PathBuf>) {
    for d in paths.drain(..) {
        for _ in 0..3 {
            let removed = if d.is_dir() {
                std::fs::remove_dir_all(&d)
            } else {
                std::fs::remove_file(&d)
            };
            if removed.is_ok() || !d.exists() {
                break;
            }
        }
    }
}

/// Creates staging directory `dir` with `create` and lists it, in one step a signal cannot
/// split.
pub fn register<T>(dir: &Path, create: impl FnOnce() -> T) -> T {
    let mut list = active();
    let made = create();
    list.push(dir.to_path_buf());
    made
}

/// Takes `dir` off the list (it was renamed into place or removed).
pub fn unregister(dir: &Path) {
    active().retain(|d| d != dir);
}

/// Holds signals off (their cleanup waits) while the guard lives.
pub fn hold() -> MutexGuard<'static, Vec<PathBuf>> {
    active()
}

#[cfg(test)]
mod tests {
    /// What a signal removes: staging directories and `write_atomic`'s temporary files (a
    /// file was left behind: `remove_dir_all` does not remove files).
    #[test]
    fn a_signal_removes_listed_files_and_directories() {
        let base = std::env::temp_dir().join(format!("maglev-interrupt-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&base);
        std::fs::create_dir_all(base.join("dir")).unwrap();
        std::fs::write(base.join("dir/x.csv"), "t\n").unwrap();
        std::fs::write(base.join(".f.tmp-1"), "t\n").unwrap();
        let mut listed = vec![base.join("dir"), base.join(".f.tmp-1")];
        super::remove_all(&mut listed);
        assert!(!base.join("dir").exists());
        assert!(!base.join(".f.tmp-1").exists());
        std::fs::remove_dir_all(&base).unwrap();
    }
}
