//! The grading process and the processes a case leaves: the grader made a
//! child subreaper and non-dumpable before its first case, process groups
//! killed, every orphan of a case swept where no PID namespace holds it,
//! the private copies of a child program `nobody` may run, and the kernel's
//! CPU clock of a case's child (the one timing the student's code cannot
//! touch).

use std::path::PathBuf;
use std::time::Duration;

use crate::isolate::protections::Protections;
use crate::isolate::sandbox::Limits;

/// Becomes a child subreaper: orphans of our children are reparented to
/// us, so [`kill_descendants`] can find them. Idempotent.
pub fn become_subreaper() {
    // SAFETY: a plain prctl call. (Linux only: elsewhere the process group
    // kill is the only sweep.)
    #[cfg(target_os = "linux")]
    unsafe {
        libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0);
    }
}

/// Whether the grader made itself non-dumpable (see [`guard_grader`]).
static NOT_DUMPABLE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Protects the grading process before its first case, whichever program
/// grades: a subreaper (for the sweep), and not dumpable, so that no
/// process of its user opens its `/proc/PID/mem` (its heap holds every
/// expected answer) or attaches to it, with or without Landlock. Idempotent.
pub fn guard_grader() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        become_subreaper();
        // SAFETY: plain prctl calls.
        #[cfg(target_os = "linux")]
        unsafe {
            if libc::prctl(libc::PR_SET_DUMPABLE, 0, 0, 0, 0) == 0
                && libc::prctl(libc::PR_GET_DUMPABLE, 0, 0, 0, 0) == 0
            {
                NOT_DUMPABLE.store(true, std::sync::atomic::Ordering::Relaxed);
            }
        }
    });
}

/// Whether [`guard_grader`] made this process non-dumpable.
pub fn grader_not_dumpable() -> bool {
    NOT_DUMPABLE.load(std::sync::atomic::Ordering::Relaxed)
}

/// Private copies of child programs `nobody` may not run (see
/// [`runnable_program`]): (the program, its copy's folder, the copy).
static COPIES: std::sync::Mutex<Vec<(PathBuf, PathBuf, PathBuf)>> =
    std::sync::Mutex::new(Vec::new());

/// Removes the private copies when the grader exits.
extern "C" fn remove_copies() {
    let copies = COPIES.lock().unwrap_or_else(|e| e.into_inner());
    for (_, dir, _) in copies.iter() {
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// The program to start for a case: `exe` itself, unless the grader is
/// root and `nobody` may not execute it (a build made with umask 077):
/// then a copy that `nobody` may execute, in a folder only root can enter
/// (the launcher opens it as root and runs it by descriptor), made once
/// and removed when the grader exits. Student code never runs as root: if
/// no copy can be made, grading stops with why.
pub fn runnable_program(exe: &std::path::Path, limits: &Limits) -> Result<PathBuf, String> {
    // SAFETY: geteuid only reads.
    let root = unsafe { libc::geteuid() } == 0;
    if !root || !limits.drop_user || crate::isolate::sys::runnable_by_others(exe) {
        return Ok(exe.to_path_buf());
    }
    let mut copies = COPIES.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, _, copy)) = copies.iter().find(|(p, _, _)| p == exe) {
        return Ok(copy.clone());
    }
    let fail = |e: &dyn std::fmt::Display| {
        format!(
            "the child program {} may not be run by user nobody, and no copy that may \
             could be made in {} ({e}); student code never runs as root: make the \
             program executable by others (chmod o+x) or grade as another user",
            exe.display(),
            std::env::temp_dir().display()
        )
    };
    use std::os::unix::fs::{DirBuilderExt, PermissionsExt};
    let stamp = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let dir = std::env::temp_dir().join(format!("meshlab-child-{}-{stamp:x}", std::process::id()));
    std::fs::DirBuilder::new()
        .mode(0o700)
        .create(&dir)
        .map_err(|e| fail(&e))?;
    let name = exe.file_name().unwrap_or(std::ffi::OsStr::new("child"));
    let copy = dir.join(name);
    let made = std::fs::copy(exe, &copy)
        .and_then(|_| std::fs::set_permissions(&copy, std::fs::Permissions::from_mode(0o755)));
    if let Err(e) = made {
        let _ = std::fs::remove_dir_all(&dir);
        return Err(fail(&e));
    }
    if copies.is_empty() {
        // SAFETY: registers a plain function, once.
        unsafe { libc::atexit(remove_copies) };
    }
    copies.push((exe.to_path_buf(), dir, copy.clone()));
    Ok(copy)
}

/// The ids of the processes whose parent is `parent`, from /proc (none
/// where there is no /proc).
pub fn children_of(parent: u32) -> Vec<u32> {
    let Ok(dir) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    dir.filter_map(|e| e.ok()?.file_name().to_str()?.parse::<u32>().ok())
        .filter(|&pid| {
            let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
                return false;
            };
            // "pid (comm) state ppid ...": comm may hold spaces and parens.
            let after = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
            after.split_whitespace().nth(1) == Some(&parent.to_string())
        })
        .collect()
}

/// The children of cases still running (cases may run side by side): the
/// sweep leaves them alone. Spawning holds the lock too, so a sweep never
/// sees a child before it is listed.
static ACTIVE: std::sync::Mutex<Vec<u32>> = std::sync::Mutex::new(Vec::new());

pub fn active() -> std::sync::MutexGuard<'static, Vec<u32>> {
    ACTIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Kills every process this process is the parent of (orphans reparented
/// to us by the subreaper flag) but the children of running cases, and
/// reaps them, until none is left.
pub fn kill_descendants() {
    let me = std::process::id();
    let running = active();
    for _ in 0..200 {
        let found: Vec<u32> = children_of(me)
            .into_iter()
            .filter(|p| !running.contains(p))
            .collect();
        if found.is_empty() {
            return;
        }
        for pid in found {
            // SAFETY: plain system calls on a pid that is our child.
            unsafe {
                libc::kill(pid as i32, libc::SIGKILL);
                libc::waitpid(pid as i32, std::ptr::null_mut(), 0);
            }
        }
    }
}

/// [`kill_descendants`], unless the launcher reported a PID namespace:
/// then every process of the case lives in it (an orphan there goes to its
/// init, never to the grader) and dies with it, and the sweep, a walk of
/// all `/proc`, would find nothing.
pub fn sweep_unless_contained(launched: &Option<Protections>) {
    let contained = launched.is_some_and(|p| p.pid_namespace);
    if !contained {
        kill_descendants();
    }
}

/// Kills process group `pgid` (SIGKILL): the one way the lab kills a
/// group. Ids 0 and 1 are refused, since `kill(0)` would signal our own
/// group and `kill(-1)` every process we may signal.
pub fn kill_group(pgid: u32) {
    if let Ok(pgid) = libc::pid_t::try_from(pgid) {
        if pgid > 1 {
            // SAFETY: kill only sends a signal; a negative pid names a group.
            unsafe { libc::kill(-pgid, libc::SIGKILL) };
        }
    }
}

/// The kernel's CPU-time clock of a case's child process
/// (`clock_getcpuclockid`: the CPU time of all its threads, ended ones
/// included), read by the grader: nothing in the child can change it.
#[derive(Clone, Copy, Debug)]
pub struct CpuClock {
    #[cfg(target_os = "linux")]
    id: libc::clockid_t,
}

impl CpuClock {
    /// The clock of the child the launcher `launcher` started, by the id
    /// its report names (`pid=`, read by the launcher before the child
    /// program ran), checked against the process tree: in a PID namespace
    /// the child is the launcher's grandchild (under the namespace's
    /// init), elsewhere the launcher itself, `exec`ed. `None` where it
    /// cannot be found (then nothing is timed).
    #[cfg(target_os = "linux")]
    pub fn of_child(launched: &Protections, launcher: u32) -> Option<CpuClock> {
        let pid = launched.pid;
        let found = if launched.pid_namespace {
            parent_of(pid).and_then(parent_of) == Some(launcher)
        } else {
            pid == launcher
        };
        if !found {
            return None;
        }
        let mut id: libc::clockid_t = 0;
        // SAFETY: writes the clock id into our own variable.
        if unsafe { libc::clock_getcpuclockid(pid as libc::pid_t, &mut id) } != 0 {
            return None;
        }
        Some(CpuClock { id })
    }

    #[cfg(not(target_os = "linux"))]
    pub fn of_child(_: &Protections, _: u32) -> Option<CpuClock> {
        None
    }

    /// The CPU time the process has used, `None` once it is gone.
    #[cfg(target_os = "linux")]
    pub fn now(self) -> Option<Duration> {
        let mut t = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime writes the timespec it is given.
        if unsafe { libc::clock_gettime(self.id, &mut t) } != 0 {
            return None;
        }
        Some(Duration::new(
            t.tv_sec.max(0) as u64,
            t.tv_nsec.clamp(0, 999_999_999) as u32,
        ))
    }

    #[cfg(not(target_os = "linux"))]
    pub fn now(self) -> Option<Duration> {
        None
    }
}

/// The parent of process `pid`, from `/proc/PID/stat`.
pub fn parent_of(pid: u32) -> Option<u32> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // "pid (comm) state ppid ...": comm may hold spaces and parens.
    stat.rsplit_once(')')?
        .1
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()
}
