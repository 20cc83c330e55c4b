//! Running the build and the grader with deadlines, and sweeping what a
//! submission leaves behind. Every command runs in its own process group
//! with its output in files (a child holding a pipe cannot stall us); the
//! group is killed at the deadline and when the command ends. After each
//! submission [`sweep`] ends every process it left: this process is a
//! child subreaper ([`become_subreaper`]), so an orphan that left its
//! group (a new session, a cleared parent-death signal) is still our
//! descendant; and, when the build and the student's code ran as another
//! user (`nobody`, as root), every process of that user.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Runs `cmd` in its own process group, its output in `stdout` and
/// `stderr`, killing the group at `limit` and when it ends. Returns the
/// exit code (`-1` for a signal), `None` when stopped at the limit.
pub fn run_limited(
    mut cmd: Command,
    stdout: &Path,
    stderr: &Path,
    limit: Duration,
) -> Result<Option<i32>, String> {
    let file = |p: &Path| std::fs::File::create(p).map_err(|e| format!("{}: {e}", p.display()));
    cmd.stdin(Stdio::null())
        .stdout(file(stdout)?)
        .stderr(file(stderr)?);
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        cmd.process_group(0);
    }
    let mut child = cmd
        .spawn()
        .map_err(|e| format!("cannot run {:?}: {e}", cmd.get_program()))?;
    let start = Instant::now();
    let code = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break Some(status.code().unwrap_or(-1));
        }
        if start.elapsed() >= limit {
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    kill_group(child.id());
    let _ = child.kill();
    let _ = child.wait();
    Ok(code)
}

/// Kills the process group `pgid` (gone already is fine).
pub use grader::isolate::process::kill_group;

/// Makes this process the reaper of its orphaned descendants, so that
/// [`sweep`] finds them. Returns whether the kernel agreed.
pub fn become_subreaper() -> bool {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: sets a flag of this process.
        unsafe { libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) == 0 }
    }
    #[cfg(not(target_os = "linux"))]
    {
        false
    }
}

/// (pid, parent pid, real uid) of every process, read from `/proc`.
fn processes() -> Vec<(i32, i32, u32)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir("/proc").into_iter().flatten().flatten() {
        let Some(pid) = entry
            .file_name()
            .to_str()
            .and_then(|n| n.parse::<i32>().ok())
        else {
            continue;
        };
        let Ok(status) = std::fs::read_to_string(entry.path().join("status")) else {
            continue;
        };
        let field = |key: &str| {
            status
                .lines()
                .find_map(|l| l.strip_prefix(key))
                .and_then(|v| v.split_whitespace().next())
                .and_then(|v| v.parse::<i64>().ok())
        };
        if let (Some(ppid), Some(uid)) = (field("PPid:"), field("Uid:")) {
            out.push((pid, ppid as i32, uid as u32));
        }
    }
    out
}

/// Kills every descendant of this process and, with `user`, every process
/// of that user (never this process), until none is left or 50 rounds
/// passed (a fork loop). Returns how many were killed. Call it between
/// submissions, when nothing of ours should be running.
pub fn sweep(user: Option<u32>) -> usize {
    let me = std::process::id() as i32;
    let mut killed = 0;
    for _ in 0..50 {
        let all = processes();
        let mut doomed: Vec<i32> = Vec::new();
        let mut frontier = vec![me];
        while let Some(parent) = frontier.pop() {
            for &(pid, ppid, _) in &all {
                if ppid == parent && pid != me && !doomed.contains(&pid) {
                    doomed.push(pid);
                    frontier.push(pid);
                }
            }
        }
        if let Some(uid) = user {
            for &(pid, _, owner) in &all {
                if owner == uid && pid != me && !doomed.contains(&pid) {
                    doomed.push(pid);
                }
            }
        }
        if doomed.is_empty() {
            break;
        }
        for pid in &doomed {
            // SAFETY: kill only sends a signal.
            if unsafe { libc::kill(*pid, libc::SIGKILL) } == 0 {
                killed += 1;
            }
        }
        // Reap the ones that were our children (orphans reparented to us
        // included), so that they leave the process table.
        loop {
            let mut status = 0;
            // SAFETY: waitpid on any child, without blocking.
            let pid = unsafe { libc::waitpid(-1, &mut status, libc::WNOHANG) };
            if pid <= 0 {
                break;
            }
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    killed
}

/// The first argument that makes a program calling [`reap_if_asked`] a
/// reaper: `PROGRAM --meshlab-reap SECONDS COMMAND ARGS...`.
pub const REAP_ARG: &str = "--meshlab-reap";
/// A reaper's exit code when it stopped its command at the deadline.
pub const REAPED_AT_DEADLINE: i32 = 125;

/// `command` run under the reaper program `reaper` (one whose `main`
/// calls [`reap_if_asked`]) with a deadline of `seconds`: the reaper is a
/// child subreaper, stops the command's group at the deadline, and when
/// the command ends kills everything it left (orphans in sessions of their
/// own included), before it exits itself. So what a submission leaves is
/// swept by a process of its own, not by ours (which may have other
/// children: tests run side by side).
pub fn reaped(reaper: &Path, seconds: f64, command: &Command) -> Command {
    let mut cmd = Command::new(reaper);
    cmd.arg(REAP_ARG)
        .arg(format!("{seconds}"))
        .arg(command.get_program())
        .args(command.get_args());
    if let Some(dir) = command.get_current_dir() {
        cmd.current_dir(dir);
    }
    // Only the command's own variables: every command run here is
    // started with a cleared environment.
    cmd.env_clear();
    for (key, value) in command.get_envs() {
        if let Some(value) = value {
            cmd.env(key, value);
        }
    }
    cmd
}

/// In a reaper (started with [`REAP_ARG`]), runs the command, sweeps, and
/// exits with its code ([`REAPED_AT_DEADLINE`] when stopped); never
/// returns. Elsewhere returns at once. Call it first thing in `main`.
pub fn reap_if_asked() {
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    if args.get(1).map(|a| a.as_os_str()) != Some(REAP_ARG.as_ref()) {
        return;
    }
    let seconds = args
        .get(2)
        .and_then(|s| s.to_str()?.parse::<f64>().ok())
        .filter(|s| *s > 0.0);
    let (Some(seconds), Some(program)) = (seconds, args.get(3)) else {
        eprintln!("usage: {REAP_ARG} SECONDS COMMAND ARGS...");
        std::process::exit(2);
    };
    become_subreaper();
    let mut cmd = Command::new(program);
    cmd.args(&args[4..]);
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        cmd.process_group(0);
    }
    let code = match cmd.spawn() {
        Err(e) => {
            eprintln!("cannot run {}: {e}", program.to_string_lossy());
            127
        }
        Ok(mut child) => {
            let start = Instant::now();
            let code = loop {
                match child.try_wait() {
                    Ok(Some(status)) => break status.code().unwrap_or(-1),
                    Ok(None) if start.elapsed().as_secs_f64() < seconds => {
                        std::thread::sleep(Duration::from_millis(20))
                    }
                    _ => break REAPED_AT_DEADLINE,
                }
            };
            kill_group(child.id());
            let _ = child.kill();
            let _ = child.wait();
            code
        }
    };
    sweep(None);
    std::process::exit(code);
}

/// The uid of user `nobody`, the one the build and the case child drop to
/// when run as root.
pub fn nobody_uid() -> Option<u32> {
    Some(grader::isolate::sys::nobody().0)
}

/// Whether this process runs as root.
pub fn is_root() -> bool {
    // SAFETY: geteuid only reads.
    unsafe { libc::geteuid() == 0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sweep kills every descendant of the test process: one test at a time.
    static TURN: std::sync::Mutex<()> = std::sync::Mutex::new(());

    #[test]
    fn an_orphan_that_left_its_group_and_session_is_swept() {
        let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
        assert!(become_subreaper());
        let dir = std::env::temp_dir().join(format!("autograde-sweep-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut cmd = Command::new("sh");
        // The orphan: a new session, its parent gone as soon as the orphan
        // has left the group (it writes its pid from inside the new
        // session). Exiting at once raced the child's setsid: under load
        // the group's kill came first and took the child with it.
        cmd.args([
            "-c",
            "setsid sh -c 'echo $$ > pid; exec sleep 300' & \
             while [ ! -s pid ]; do sleep 0.01; done",
        ])
        .current_dir(&dir);
        let code = run_limited(
            cmd,
            &dir.join("out"),
            &dir.join("err"),
            Duration::from_secs(10),
        )
        .unwrap();
        assert_eq!(code, Some(0));
        std::thread::sleep(Duration::from_millis(200));
        let pid: i32 = std::fs::read_to_string(dir.join("pid"))
            .unwrap()
            .trim()
            .parse()
            .unwrap();
        let alive = |pid: i32| {
            std::path::Path::new(&format!("/proc/{pid}")).exists()
                && !std::fs::read_to_string(format!("/proc/{pid}/stat"))
                    .unwrap_or_default()
                    .contains(") Z ")
        };
        assert!(alive(pid), "the orphan outlived its group");
        assert!(sweep(None) >= 1);
        assert!(!alive(pid), "swept");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_deadline_kills_the_whole_group() {
        let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
        let dir = std::env::temp_dir().join(format!("autograde-limit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut cmd = Command::new("sh");
        cmd.args(["-c", "sleep 300 & sleep 300"]);
        let start = Instant::now();
        let code = run_limited(
            cmd,
            &dir.join("out"),
            &dir.join("err"),
            Duration::from_millis(300),
        )
        .unwrap();
        assert_eq!(code, None);
        assert!(start.elapsed() < Duration::from_secs(5));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
