//! Class grading's temporary folders (its scratch copy of the lab, the
//! fixtures graded against, each submission's fresh cases, the builds):
//! only this user may enter them or read what they hold (0700 folders,
//! 0600 files where they hold fixtures: the hidden cases, and their digest
//! list, which seeds the fresh cases), and none outlives its run for long.
//! A folder is removed when its run lets go of it; a run that was killed
//! cannot, so each run first sweeps the folders no live run holds. A live
//! run holds each of its folders by a lock (`flock`) on a file inside,
//! which the kernel drops with the process however it ends: a folder
//! whose lock can be taken is a dead run's, and any other is left alone
//! (another TA's run, a test beside this one).

use std::fs::File;
use std::os::unix::fs::{MetadataExt, OpenOptionsExt, PermissionsExt};
use std::os::unix::io::AsRawFd;
use std::path::{Path, PathBuf};

use tempfile::TempDir;

/// The names class grading's folders start with in the temporary folder.
pub const PREFIXES: [&str; 4] = [
    "meshlab-class-",
    "meshlab-fixtures-",
    "meshlab-fresh-",
    "meshlab-build-",
];

/// The lock file in each folder a run holds.
const LOCK: &str = ".meshlab-run.lock";

/// A private temporary folder this run holds (see the module's doc):
/// removed when dropped, then let go.
pub struct RunDir {
    // Dropped in this order: the folder is gone before its lock is.
    dir: TempDir,
    _lock: File,
}

impl RunDir {
    pub fn path(&self) -> &Path {
        self.dir.path()
    }
}

/// Takes the lock on `file` without waiting; whether it was taken.
fn try_lock(file: &File) -> bool {
    // SAFETY: flock on a descriptor this process owns.
    unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) == 0 }
}

/// A new private temporary folder named `prefix` and a random suffix (one
/// of [`PREFIXES`]), held by this run.
pub fn run_dir(prefix: &str) -> Result<RunDir, String> {
    let dir = autograde::private_temp_dir(prefix)?;
    // Locked under another name and then renamed: a sweep never sees the
    // lock file before it is locked.
    let new = dir.path().join(".meshlab-run.lock.new");
    let lock = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .open(&new)
        .map_err(|e| format!("{}: {e}", new.display()))?;
    if !try_lock(&lock) {
        return Err(format!("{}: cannot be locked", new.display()));
    }
    let path = dir.path().join(LOCK);
    std::fs::rename(&new, &path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(RunDir { dir, _lock: lock })
}

/// Makes everything under `dir` this user's alone: folders 0700, files
/// 0600 (links are left as they are, never followed).
pub fn make_private(dir: &Path) -> Result<(), String> {
    let io = |e: std::io::Error, p: &Path| format!("{}: {e}", p.display());
    let meta = std::fs::symlink_metadata(dir).map_err(|e| io(e, dir))?;
    if meta.is_dir() {
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o700))
            .map_err(|e| io(e, dir))?;
        for entry in std::fs::read_dir(dir).map_err(|e| io(e, dir))? {
            make_private(&entry.map_err(|e| io(e, dir))?.path())?;
        }
    } else if meta.is_file() {
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o600))
            .map_err(|e| io(e, dir))?;
    }
    Ok(())
}

/// Removes the folders of [`PREFIXES`] in `tmp` that are this user's and
/// held by no live run (their lock can be taken); returns them. A folder
/// without a lock file (made by an older version, or not a run's) is left.
pub fn sweep(tmp: &Path) -> Vec<PathBuf> {
    // SAFETY: geteuid only reads.
    let me = unsafe { libc::geteuid() };
    let mut swept = Vec::new();
    for entry in std::fs::read_dir(tmp).into_iter().flatten().flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if !PREFIXES.iter().any(|p| name.starts_with(p)) {
            continue;
        }
        let path = entry.path();
        let Ok(meta) = std::fs::symlink_metadata(&path) else {
            continue;
        };
        if !meta.is_dir() || meta.uid() != me {
            continue;
        }
        let Ok(lock) = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK)
            .open(path.join(LOCK))
        else {
            continue;
        };
        // Held while it is removed: no other sweep takes it meanwhile.
        if try_lock(&lock) && std::fs::remove_dir_all(&path).is_ok() {
            swept.push(path);
        }
    }
    swept
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_held_folder_is_kept_and_one_let_go_without_removal_is_swept() {
        let tmp = tempfile::tempdir().unwrap();
        let run = |prefix: &str| {
            let d = tempfile::Builder::new()
                .prefix(prefix)
                .tempdir_in(tmp.path())
                .unwrap();
            let new = d.path().join(".meshlab-run.lock.new");
            let lock = File::create(&new).unwrap();
            assert!(try_lock(&lock));
            std::fs::rename(&new, d.path().join(LOCK)).unwrap();
            (d, lock)
        };
        let (live, _live_lock) = run("meshlab-fixtures-");
        // A killed run: its folder stays (kept past the TempDir), its lock
        // goes with the process (here: the file closed).
        let (dead, dead_lock) = run("meshlab-fresh-");
        let dead = dead.keep();
        std::fs::write(dead.join("secret.json"), "{}").unwrap();
        drop(dead_lock);
        // Not a run's: no lock file; and another tool's name.
        let stray = tmp.path().join("meshlab-class-stray");
        std::fs::create_dir(&stray).unwrap();
        let other = tmp.path().join("something-else");
        std::fs::create_dir(&other).unwrap();
        assert_eq!(sweep(tmp.path()), std::slice::from_ref(&dead));
        assert!(!dead.exists());
        assert!(live.path().is_dir() && stray.is_dir() && other.is_dir());
        assert_eq!(sweep(tmp.path()), Vec::<PathBuf>::new());
    }

    #[test]
    fn a_run_dir_is_private_locked_and_gone_when_dropped() {
        let dir = run_dir("meshlab-fixtures-").unwrap();
        let path = dir.path().to_path_buf();
        let mode = std::fs::metadata(&path).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o700);
        let again = File::open(path.join(LOCK)).unwrap();
        assert!(!try_lock(&again), "held by this run");
        drop(again);
        std::fs::create_dir_all(path.join("hidden")).unwrap();
        std::fs::write(path.join("hidden/SHA256SUMS"), "x").unwrap();
        make_private(&path).unwrap();
        let mode_of = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode_of(&path.join("hidden")), 0o700);
        assert_eq!(mode_of(&path.join("hidden/SHA256SUMS")), 0o600);
        drop(dir);
        assert!(!path.exists());
    }
}
