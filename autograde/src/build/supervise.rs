//! The build launcher's outside: it forks the locked-in child that runs
//! cargo, passes cargo's output on, enforces the time limit, kills the
//! build's session and every orphan, and tells the memory cap from how a
//! compiler ended (the wrapper it installs around rustc).

use std::ffi::{CString, OsStr, OsString};
use std::io::Read;
use std::os::unix::ffi::OsStrExt;
use std::path::Path;
use std::time::{Duration, Instant};

use super::lockin::lock_in;
use super::{Build, Outcome, Report, BUILD_LAUNCH_FAILED};

/// Set when the launcher is asked to stop.
static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

extern "C" fn on_stop(_: libc::c_int) {
    STOP.store(true, std::sync::atomic::Ordering::Relaxed);
}

/// The compiler wrapper's name in the target folder (cargo's
/// `build.rustc-wrapper`).
pub(super) const WRAPPER: &str = "meshlab-rustc-wrapper";

/// Where the wrapper notes each compiler process a signal ended (its shell
/// status, 128 + the signal), one a line.
pub(super) const SIGNALS: &str = "meshlab-compiler-signals";

/// The wrapper: runs one compiler process and notes whether a signal ended
/// it. A compiler that reaches the memory cap aborts (`SIGABRT`: an
/// allocation failed under `RLIMIT_AS`; rustc's and LLVM's handlers both
/// abort), or the kernel's OOM killer ends it (`SIGKILL`). No student code
/// runs in the build (no build script or macro of its own), and what it
/// makes the compiler print cannot end the compiler by a signal: so unlike
/// the compiler's words ("memory allocation of N bytes failed", which
/// `compile_error!` prints as well), this cannot be forged. rustc itself
/// never exits with a status above 128.
pub(super) const WRAPPER_SCRIPT: &str = "#!/bin/sh
# Written by the grader's build launcher: runs one compiler process and
# notes, for the launcher, the status of one a signal ended.
\"$@\"
status=$?
if [ \"$status\" -gt 128 ]; then
    echo \"$status\" >> \"${0%/*}/meshlab-compiler-signals\"
fi
exit \"$status\"
";

/// Writes the wrapper into the target folder (executable by the build's
/// user, who may be `nobody`) and clears the notes of an earlier build.
pub(super) fn install_wrapper(target: &Path) -> Result<(), String> {
    use std::os::unix::fs::PermissionsExt;
    let path = target.join(WRAPPER);
    let fail = |e: std::io::Error| format!("{}: {e}", path.display());
    // Replaced, not rewritten in place: a build never sees half of it.
    let fresh = target.join(format!("{WRAPPER}.new"));
    std::fs::write(&fresh, WRAPPER_SCRIPT).map_err(fail)?;
    std::fs::set_permissions(&fresh, std::fs::Permissions::from_mode(0o755)).map_err(fail)?;
    std::fs::rename(&fresh, &path).map_err(fail)?;
    match std::fs::remove_file(target.join(SIGNALS)) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(fail(e)),
        _ => Ok(()),
    }
}

/// Whether the wrapper saw a compiler process end by `SIGABRT` or
/// `SIGKILL`: the memory cap.
pub(super) fn compiler_hit_memory_cap(target: &Path) -> bool {
    let notes = std::fs::read_to_string(target.join(SIGNALS)).unwrap_or_default();
    notes.lines().any(|l| {
        l.trim()
            .parse::<i32>()
            .is_ok_and(|s| s == 128 + libc::SIGABRT || s == 128 + libc::SIGKILL)
    })
}

pub(super) fn last_error() -> String {
    std::io::Error::last_os_error().to_string()
}

/// Forks the locked-in cargo, waits for it within the time limit, kills
/// its session and every orphan, writes the status file. Returns the exit
/// status for the launcher.
pub(super) fn supervise(build: &Build) -> i32 {
    let mut report = Report {
        outcome: Outcome::NotLockedIn,
        exit: None,
        landlock: 0,
        network: String::new(),
        user: String::new(),
        root: String::new(),
        memory: build.memory,
        seconds: build.seconds,
        peak_kib: 0,
        error: String::new(),
    };
    let fail = |mut report: Report, error: String| {
        eprintln!("grader build sandbox: {error}");
        report.error = error;
        let _ = report.write(&build.status);
        BUILD_LAUNCH_FAILED
    };
    for dir in ["home/cargo", "tmp"] {
        if let Err(e) = std::fs::create_dir_all(build.target.join(dir)) {
            return fail(report, format!("{}: {e}", build.target.join(dir).display()));
        }
    }
    if let Err(e) = install_wrapper(&build.target) {
        return fail(report, e);
    }
    // Everything prepared before the fork: the child allocates nothing it
    // can avoid between fork and exec.
    let cargo = build.sysroot.join("bin/cargo");
    let c = |s: &OsStr| CString::new(s.as_bytes()).unwrap_or_default();
    let argv: Vec<CString> = std::iter::once(cargo.clone().into_os_string())
        .chain(build.cargo_args())
        .map(|a| c(&a))
        .collect();
    let envp: Vec<CString> = build
        .env()
        .into_iter()
        .map(|(k, v)| {
            let mut kv = OsString::from(k);
            kv.push("=");
            kv.push(v);
            c(&kv)
        })
        .collect();
    let lab = c(build.lab.as_os_str());
    // The child tells how it locked itself in on `status` (close-on-exec:
    // end of file means cargo started); its standard error comes through
    // `errors`, passed on.
    let (status_r, status_w) = match pipe() {
        Ok(p) => p,
        Err(e) => return fail(report, e),
    };
    let (errors_r, errors_w) = match pipe() {
        Ok(p) => p,
        Err(e) => return fail(report, e),
    };
    // SAFETY: plain system calls; this process has one thread here.
    unsafe {
        // Orphans of the build become ours, to be killed at the end.
        #[cfg(target_os = "linux")]
        libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0);
    }
    let parent = std::process::id() as libc::pid_t;
    // SAFETY: fork in a single-threaded process.
    let pid = unsafe { libc::fork() };
    if pid < 0 {
        return fail(report, format!("fork: {}", last_error()));
    }
    if pid == 0 {
        // SAFETY: our own descriptors.
        unsafe {
            libc::close(status_r);
            libc::close(errors_r);
            libc::dup2(errors_w, 2);
            libc::close(errors_w);
        }
        let message = match lock_in(build, parent, status_w) {
            Ok(line) => line,
            Err(e) => format!("error={e}"),
        };
        write_all(status_w, message.as_bytes());
        if !message.starts_with("error=") {
            let ptrs = |v: &[CString]| -> Vec<*const libc::c_char> {
                v.iter()
                    .map(|s| s.as_ptr())
                    .chain(std::iter::once(std::ptr::null()))
                    .collect()
            };
            let (argv_p, envp_p) = (ptrs(&argv), ptrs(&envp));
            // SAFETY: null-terminated arrays of C strings that outlive the call.
            unsafe {
                libc::chdir(lab.as_ptr());
                libc::execve(argv_p[0], argv_p.as_ptr(), envp_p.as_ptr());
            }
            write_all(
                status_w,
                format!("\nerror=cannot run {}: {}", cargo.display(), last_error()).as_bytes(),
            );
        }
        // SAFETY: ends the child without running the parent's destructors.
        unsafe { libc::_exit(BUILD_LAUNCH_FAILED) };
    }
    // SAFETY: our own descriptors.
    unsafe {
        libc::close(status_w);
        libc::close(errors_w);
    }
    let start = Instant::now();
    let mut locked = String::new();
    // SAFETY: the read end is ours; File takes it over.
    let mut status_file =
        unsafe { <std::fs::File as std::os::fd::FromRawFd>::from_raw_fd(status_r) };
    let _ = status_file.read_to_string(&mut locked);
    // SAFETY: as above.
    let errors_file = unsafe { <std::fs::File as std::os::fd::FromRawFd>::from_raw_fd(errors_r) };
    let reader = std::thread::spawn(move || pass_on(errors_file));

    // Asked to stop (a TA's Ctrl-C, the caller's SIGTERM): the build's
    // session goes too, rather than running on without a supervisor.
    for signal in [libc::SIGTERM, libc::SIGINT, libc::SIGHUP] {
        // SAFETY: the handler only stores to an atomic.
        unsafe { libc::signal(signal, on_stop as *const () as libc::sighandler_t) };
    }
    let limit = Duration::from_secs_f64(build.seconds.max(0.0));
    let mut timed_out = false;
    let mut wait_status = 0;
    loop {
        // SAFETY: waiting for our own child.
        let done = unsafe { libc::waitpid(pid, &mut wait_status, libc::WNOHANG) };
        if done == pid {
            break;
        }
        let stopped = STOP.load(std::sync::atomic::Ordering::Relaxed);
        if stopped || start.elapsed() >= limit {
            timed_out = !stopped;
            // The child's session is its process group.
            grader::isolate::process::kill_group(pid as u32);
            // SAFETY: waits for our own child.
            unsafe {
                libc::waitpid(pid, &mut wait_status, 0);
            }
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    sweep(pid);
    let _ = reader.join();
    let saw_memory = compiler_hit_memory_cap(&build.target);
    // SAFETY: a plain query about our (reaped) children.
    let peak = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage);
        usage.ru_maxrss.max(0) as u64
    };
    report.peak_kib = peak;
    let field = |key: &str| {
        locked
            .lines()
            .find_map(|l| l.strip_prefix(key)?.strip_prefix('='))
            .map(str::to_string)
    };
    if let Some(error) = field("error") {
        return fail(report, error);
    }
    report.landlock = field("landlock").and_then(|v| v.parse().ok()).unwrap_or(0);
    report.network = field("network").unwrap_or_default();
    report.user = field("user").unwrap_or_default();
    report.root = field("root").unwrap_or_default();
    let exit = libc::WIFEXITED(wait_status).then(|| libc::WEXITSTATUS(wait_status));
    report.exit = if timed_out { None } else { exit };
    report.outcome = match (timed_out, exit) {
        (true, _) => Outcome::OutOfTime,
        (false, Some(0)) => Outcome::Built,
        (false, _) if saw_memory => Outcome::OutOfMemory,
        (false, _) => Outcome::Failed,
    };
    if let Some(why) = report.failure() {
        eprintln!("grader build sandbox: {why}");
    }
    if let Err(e) = report.write(&build.status) {
        eprintln!(
            "grader build sandbox: cannot write {}: {e}",
            build.status.display()
        );
        return BUILD_LAUNCH_FAILED;
    }
    match report.outcome {
        Outcome::Built => 0,
        _ => exit.filter(|c| *c != 0).unwrap_or(1),
    }
}

/// Copies the build's standard error to ours. (Nothing is decided from
/// it: the student's crate chooses what the compiler prints.)
pub(super) fn pass_on(mut from: std::fs::File) {
    let _ = std::io::copy(&mut from, &mut std::io::stderr());
}

/// Kills the build's session and every process left to us (orphans come to
/// this launcher, a subreaper), then reaps them all.
pub(super) fn sweep(session: libc::pid_t) {
    let me = std::process::id().to_string();
    for _ in 0..50 {
        grader::isolate::process::kill_group(session as u32);
        let mut any = false;
        for entry in std::fs::read_dir("/proc").into_iter().flatten().flatten() {
            let Ok(pid) = entry.file_name().to_string_lossy().parse::<libc::pid_t>() else {
                continue;
            };
            let Ok(stat) = std::fs::read_to_string(entry.path().join("stat")) else {
                continue;
            };
            // The fields after the command's closing parenthesis: state, ppid.
            let ppid = stat
                .rsplit_once(')')
                .and_then(|(_, rest)| rest.split_whitespace().nth(1).map(str::to_string));
            if ppid.as_deref() == Some(me.as_str()) {
                any = true;
                // SAFETY: our own child.
                unsafe { libc::kill(pid, libc::SIGKILL) };
            }
        }
        // SAFETY: reaping our own children.
        while unsafe { libc::waitpid(-1, std::ptr::null_mut(), libc::WNOHANG) } > 0 {}
        if !any {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

pub(super) fn pipe() -> Result<(i32, i32), String> {
    let mut fds = [0; 2];
    // SAFETY: a plain system call filling our array.
    if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) } != 0 {
        return Err(format!("pipe: {}", last_error()));
    }
    Ok((fds[0], fds[1]))
}

pub(super) fn write_all(fd: i32, mut bytes: &[u8]) {
    while !bytes.is_empty() {
        // SAFETY: writing our own buffer to our own descriptor.
        let n = unsafe { libc::write(fd, bytes.as_ptr().cast(), bytes.len()) };
        if n <= 0 {
            return;
        }
        bytes = &bytes[n as usize..];
    }
}
