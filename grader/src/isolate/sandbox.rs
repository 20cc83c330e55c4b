//! Locking a case's child process in before any student code runs.
//!
//! The student's code is linked into the child program, and Rust lets code
//! run before `main` (a static in `.init_array`), so the child cannot lock
//! itself in: by then it is too late. Instead the grader starts itself
//! again as a *launcher* (grader code only), which takes every privilege
//! away and then `exec`s the child program, born locked:
//!
//! - Its own session (the runner calls `setsid`; the launcher checks): no
//!   controlling terminal. Its stdin is `/dev/null`; the request comes on
//!   [`REQUEST_FD`].
//! - A PID namespace where one can be had (as root, or in an unprivileged
//!   user namespace that maps only the grader's user): the launcher stays
//!   outside and waits, the namespace's init (grader code) waits for the
//!   child, and when the case ends the kernel kills everything left in the
//!   namespace. Elsewhere the runner's sweep of orphans is the catch.
//! - With the PID namespace, a mount namespace whose root is a fresh,
//!   read-only tmpfs holding only the program (at `/child`), the library
//!   folders (bound read-only) and the case's own `/proc`: Landlock guards
//!   opening, not `stat`, so without it the child could tell which paths
//!   exist (`fixtures/hidden`, a hidden case's name). Where the kernel
//!   refuses a step, the machine's tree stays, and the status says so.
//! - Landlock (best ABI the kernel offers, up to 6): no file may be read,
//!   written or executed except the child program, the system's shared
//!   libraries (read and map) and its own `/proc/self` (read); no TCP; no signals to, and no abstract
//!   sockets of, processes outside the sandbox. It cannot be undone.
//! - `RLIMIT_AS` (the memory cap), `RLIMIT_FSIZE` 0 (no file can grow, even
//!   without Landlock, nor a `memfd`), `RLIMIT_CORE` 0, `RLIMIT_NOFILE` 64
//!   (pipes buffer kernel memory the cap does not count), `RLIMIT_RTPRIO`
//!   and `RLIMIT_NICE` 0 (no raised priority, whatever was inherited).
//! - As root, it always drops to user `nobody` (and a process cap, which
//!   only binds users other than root); a launcher that would still be
//!   root refuses to start the child. Every capability is dropped.
//! - A seccomp filter ([`crate::isolate::seccomp`]): no new processes, no sockets,
//!   no IPC, no reaching other processes, no `prctl` that undoes any of
//!   this, no terminal input, no file watches.
//! - `PR_SET_PDEATHSIG`: if the grader dies, so does the launcher, and so
//!   on down to the child (the filter keeps it from being cleared).
//! - Not dumpable (the launcher's processes): no process of the same user
//!   reads their memory.
//! - An empty environment and `/` as working folder: nothing names a
//!   fixture, a result file or the grader's options.
//!
//! The launcher writes what it put in place as the first frame on the
//! result pipe ([`crate::isolate::wire::Frame::Sandbox`]); the grader prints it as
//! the protections line.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use crate::isolate::landlock_rules::landlock;
use crate::isolate::namespace::{
    empty_root, enter_pid_namespace, split_for_namespace, ROOTED_PROGRAM,
};
use crate::isolate::sys::{
    die_with_parent, drop_capabilities, drop_to_nobody, move_request, nobody, os_error,
    own_session, set_limit,
};
use crate::isolate::wire::REQUEST_FD;

/// The first argument that turns a grader process into a launcher.
pub const LAUNCH_ARG: &str = "--meshlab-sandbox-launch";

/// The exit status of a launcher that could not set up the sandbox.
pub const LAUNCH_FAILED: i32 = 97;

/// The most descriptors the child may hold (`RLIMIT_NOFILE`): its own
/// five and the loader's, with room to spare, but too few pipes to buffer
/// much kernel memory (at most 1 MiB each).
const OPEN_FILES: u64 = 64;

/// The most processes and threads the child's user may have
/// (`RLIMIT_NPROC`, where it counts only the case's).
const PROCESSES: u64 = 512;

/// The limits a case runs under.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Limits {
    /// The address-space cap in bytes.
    pub memory: u64,
    /// Whether to drop to `nobody` when running as root. Always on in
    /// grading: off, a root launcher refuses to start the child at all
    /// (student code never runs as root).
    pub drop_user: bool,
    /// Whether to apply Landlock (off only to test what a kernel without
    /// it leaves: the other protections must still hold).
    pub landlock: bool,
    /// Whether to try a PID namespace (off only to test the fallback a
    /// machine without them has: the sweep and the parent-death signals).
    pub pid_namespace: bool,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            memory: 2 << 30,
            drop_user: true,
            landlock: true,
            pid_namespace: true,
        }
    }
}

/// The launcher's command line: `LAUNCH_ARG memory drop|keep
/// landlock|nolandlock pidns|nopidns child args...`.
pub fn launcher_args(limits: &Limits, child: &Path, child_args: &[OsString]) -> Vec<OsString> {
    let mut args: Vec<OsString> = vec![
        LAUNCH_ARG.into(),
        limits.memory.to_string().into(),
        if limits.drop_user { "drop" } else { "keep" }.into(),
        if limits.landlock {
            "landlock"
        } else {
            "nolandlock"
        }
        .into(),
        if limits.pid_namespace {
            "pidns"
        } else {
            "nopidns"
        }
        .into(),
        child.as_os_str().to_owned(),
    ];
    args.extend(child_args.iter().cloned());
    args
}

/// In a launcher (started with [`LAUNCH_ARG`]), sets up the sandbox and
/// `exec`s the child: never returns. Elsewhere returns at once. Every
/// program that grades calls this first thing in `main`.
pub fn launch_if_asked() {
    let args: Vec<OsString> = std::env::args_os().collect();
    if args.get(1).map(|a| a.as_os_str()) != Some(LAUNCH_ARG.as_ref()) {
        return;
    }
    let err = match parse_launch(&args[2..]) {
        Ok((limits, child, child_args)) => launch(&limits, &child, &child_args),
        Err(e) => e,
    };
    eprintln!("grader sandbox: {err}");
    std::process::exit(LAUNCH_FAILED);
}

fn parse_launch(args: &[OsString]) -> Result<(Limits, PathBuf, Vec<OsString>), String> {
    let [memory, drop, landlock, pidns, child, rest @ ..] = args else {
        return Err(
            "the launcher needs: MEMORY drop|keep landlock|nolandlock pidns|nopidns CHILD [ARGS]"
                .into(),
        );
    };
    let memory = memory
        .to_str()
        .and_then(|m| m.parse().ok())
        .ok_or("the memory cap is not a number")?;
    Ok((
        Limits {
            memory,
            drop_user: drop == "drop",
            landlock: landlock == "landlock",
            pid_namespace: pidns == "pidns",
        },
        PathBuf::from(child),
        rest.to_vec(),
    ))
}

/// Reads the grader's nonce, the first [`wire::NONCE_LEN`] bytes on
/// standard input (before any request).
///
/// [`wire::NONCE_LEN`]: crate::isolate::wire::NONCE_LEN
fn read_nonce() -> Result<[u8; crate::isolate::wire::NONCE_LEN], String> {
    let mut nonce = [0u8; crate::isolate::wire::NONCE_LEN];
    let mut got = 0;
    while got < nonce.len() {
        // SAFETY: reads into the rest of our own array.
        let n = unsafe { libc::read(0, nonce[got..].as_mut_ptr().cast(), nonce.len() - got) };
        if n == 0 {
            return Err("the grader is gone".into());
        }
        if n < 0 {
            if std::io::Error::last_os_error().raw_os_error() == Some(libc::EINTR) {
                continue;
            }
            return Err(os_error("cannot read the grader's nonce"));
        }
        got += n as usize;
    }
    Ok(nonce)
}

/// This process's id as the grader sees it: in a PID namespace of its
/// own, the first of `NSpid` in `/proc/self/status` (the machine's
/// `/proc`, before the empty root hides it, is of the grader's namespace);
/// elsewhere its own id. `None` when it cannot be read.
fn pid_seen_by_grader(namespace: bool) -> Option<u32> {
    if !namespace {
        return Some(std::process::id());
    }
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status
        .lines()
        .find_map(|l| l.strip_prefix("NSpid:"))?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// Locks this process in and `exec`s the child. Returns only on failure.
fn launch(limits: &Limits, child: &Path, child_args: &[OsString]) -> String {
    use std::io::Write;
    use std::os::fd::AsRawFd;
    // Who nobody is, read while /etc/passwd is still in sight.
    let _ = nobody();
    // What this launcher makes (the empty root's folders) gets the modes it
    // asks for, whatever umask the grader was started with.
    // SAFETY: a plain system call.
    unsafe { libc::umask(0o022) };
    let nonce = match read_nonce() {
        Ok(n) => n,
        Err(e) => return e,
    };
    let early = || -> Result<(std::fs::File, bool), String> {
        move_request()?;
        own_session()?;
        if die_with_parent() {
            return Err("the grader is gone".into());
        }
        // Opened while still privileged, and executed by descriptor: a
        // child program in a folder `nobody` cannot enter (a root's home)
        // still runs as `nobody`. Close-on-exec, so the child does not
        // hold it.
        let program = std::fs::File::open(child)
            .map_err(|e| format!("cannot open {}: {e}", child.display()))?;
        let namespace = limits.pid_namespace && enter_pid_namespace()?;
        // SAFETY: a plain prctl call. Grader code only here, but its memory
        // is nobody's business either. (After the user namespace's maps:
        // a process that is not dumpable cannot write its own.)
        #[cfg(target_os = "linux")]
        unsafe {
            libc::prctl(libc::PR_SET_DUMPABLE, 0, 0, 0, 0);
        }
        if namespace {
            split_for_namespace()?;
        }
        Ok((program, namespace))
    };
    // SAFETY: geteuid only reads.
    let was_root = unsafe { libc::geteuid() } == 0;
    let (program, namespace) = match early() {
        Ok(p) => p,
        Err(e) => return e,
    };
    // Not root, a PID namespace comes only with a user namespace.
    let user_namespace = namespace && !was_root;
    // Read before the empty root hides the machine's /proc: the grader
    // times the child by this id (its CPU time, from the kernel).
    // (0: not found; then nothing is timed.)
    let pid = pid_seen_by_grader(namespace).unwrap_or(0);
    // The empty root needs the PID namespace (its `/proc` shows only the
    // case's processes): without one, the machine's files stay visible.
    let (program, rooted) = match namespace.then(|| empty_root(&program)).transpose() {
        Ok(Some(Some(rooted))) => (rooted, true),
        Ok(_) => (program, false),
        Err(e) => return e,
    };
    let setup = || -> Result<crate::isolate::protections::Protections, String> {
        set_limit(libc::RLIMIT_AS, limits.memory)?;
        set_limit(libc::RLIMIT_FSIZE, 0)?;
        set_limit(libc::RLIMIT_CORE, 0)?;
        // What pipes buffer is kernel memory the address-space cap does not
        // count: few descriptors, few pipes (the child needs five).
        set_limit(libc::RLIMIT_NOFILE, OPEN_FILES)?;
        // Whatever the grader inherited (an audio group's real-time
        // limit), the child raises no priority: a real-time thread that
        // spins holds a core until the time limit.
        set_limit(libc::RLIMIT_RTPRIO, 0)?;
        set_limit(libc::RLIMIT_NICE, 0)?;
        let dropped = limits.drop_user && drop_to_nobody()?;
        // SAFETY: plain system calls.
        if unsafe { libc::geteuid() == 0 || libc::getuid() == 0 } {
            return Err(
                "student code never runs as root, and this launcher was not \
                        asked to drop to nobody"
                    .into(),
            );
        }
        // Caps a thread bomb. It binds only a user other than root, and
        // counts every process of the user: for `nobody` (dropped to) that
        // is the case's own; for a grader run by a TA, only inside the
        // user namespace, where the kernel counts the namespace's own
        // processes (Linux 5.14 on) and the TA's others not at all.
        // Elsewhere it would count the TA's whole session: not set.
        if dropped || user_namespace {
            set_limit(libc::RLIMIT_NPROC, PROCESSES)?;
        }
        drop_capabilities()?;
        // Set after dropping privileges, which clears the parent-death
        // signal. In a namespace the parent is its init (PID 1), whose end
        // ends the namespace anyway.
        if die_with_parent() && !namespace {
            return Err("the grader is gone".into());
        }
        let abi = if limits.landlock {
            landlock(&program)?
        } else {
            0
        };
        std::env::set_current_dir("/").map_err(|e| format!("chdir /: {e}"))?;
        let filtered = crate::isolate::seccomp::apply()?;
        Ok(crate::isolate::protections::Protections {
            landlock: u8::try_from(abi).unwrap_or(u8::MAX),
            memory: limits.memory,
            nobody: dropped,
            own_session: true,
            pid_namespace: namespace,
            empty_root: rooted,
            no_capabilities: true,
            seccomp: filtered,
            pid,
        })
    };
    let status = match setup() {
        Ok(s) => s,
        Err(e) => return e,
    };
    let frame = crate::isolate::wire::sandbox_frame(&status);
    if let Err(e) = std::io::stdout().write_all(&frame) {
        return format!("cannot write to the grader: {e}");
    }
    let _ = std::io::stdout().flush();
    // Descriptors the grader itself inherited without close-on-exec (from
    // whatever started it) must not reach the child: only 0, 1, 2 and the
    // request do. (Marked close-on-exec rather than closed: `program` is
    // needed to exec.)
    // SAFETY: a plain system call on our own descriptor table.
    #[cfg(target_os = "linux")]
    unsafe {
        const CLOSE_RANGE_CLOEXEC: u32 = 1 << 2;
        libc::syscall(
            libc::SYS_close_range,
            REQUEST_FD as u32 + 1,
            u32::MAX,
            CLOSE_RANGE_CLOEXEC,
        );
    }
    let cstr = |s: &std::ffi::OsStr| {
        use std::os::unix::ffi::OsStrExt;
        std::ffi::CString::new(s.as_bytes()).unwrap_or_default()
    };
    // In the empty root the program's own name: the lab's path is not
    // even a name to the child.
    let name = if rooted {
        std::ffi::OsStr::new(ROOTED_PROGRAM)
    } else {
        child.as_os_str()
    };
    let argv: Vec<std::ffi::CString> = std::iter::once(name)
        .chain(child_args.iter().map(|a| a.as_os_str()))
        .map(cstr)
        .collect();
    let mut envp = vec![cstr("RUST_BACKTRACE=0".as_ref())];
    if let Some(log) = std::env::var_os("RUST_LOG") {
        let mut kv = OsString::from("RUST_LOG=");
        kv.push(log);
        envp.push(cstr(&kv));
    }
    let ptrs = |v: &[std::ffi::CString]| -> Vec<*const libc::c_char> {
        v.iter()
            .map(|c| c.as_ptr())
            .chain(std::iter::once(std::ptr::null()))
            .collect()
    };
    let (argv_p, envp_p) = (ptrs(&argv), ptrs(&envp));
    // SAFETY: null-terminated arrays of C strings that outlive the call.
    unsafe {
        libc::fexecve(program.as_raw_fd(), argv_p.as_ptr(), envp_p.as_ptr());
    }
    let error = std::io::Error::last_os_error();
    // SAFETY: geteuid only reads.
    let user = if unsafe { libc::geteuid() } == nobody().0 {
        "nobody"
    } else {
        "the grader's"
    };
    let why = format!(
        "cannot start the child program {}: {error} (can user {} run it: may it read the \
         program and its dynamic loader and libraries, and is their file system mounted \
         without noexec?)",
        child.display(),
        user
    );
    // Said with the grader's nonce, which no student code can hold: this
    // failure is the machine's, never the student's, though it comes after
    // the report (student code that prints the same words is the student's).
    let frame = crate::isolate::wire::launch_failed_frame(&nonce, &why);
    let _ = std::io::stdout().write_all(&frame);
    let _ = std::io::stdout().flush();
    why
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn launcher_arguments_parse_back() {
        let limits = Limits {
            memory: 123,
            drop_user: false,
            landlock: false,
            pid_namespace: false,
        };
        let args = launcher_args(&limits, Path::new("/x/child"), &["a".into()]);
        let (l, c, rest) = parse_launch(&args[1..]).unwrap();
        assert_eq!(l, limits);
        assert_eq!(c, PathBuf::from("/x/child"));
        assert_eq!(rest, vec![OsString::from("a")]);
    }
}
