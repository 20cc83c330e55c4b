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

/// The user a root grader drops to.
const NOBODY: u32 = 65534;

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

/// Whether `nobody` could run `exe`, given open by descriptor: the file is
/// executable by others. (The folders above it do not matter: the launcher
/// opens it before dropping privileges.)
pub fn runnable_by_others(exe: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(exe).is_ok_and(|m| m.permissions().mode() & 0o001 != 0)
}

#[cfg(target_os = "linux")]
pub(crate) type Resource = libc::__rlimit_resource_t;
#[cfg(not(target_os = "linux"))]
pub(crate) type Resource = libc::c_int;

/// Sets both the soft and the hard limit of `resource` to `value`.
pub(crate) fn set_limit(resource: Resource, value: u64) -> Result<(), String> {
    let limit = libc::rlimit {
        rlim_cur: value as libc::rlim_t,
        rlim_max: value as libc::rlim_t,
    };
    // SAFETY: a plain system call on a struct we own.
    if unsafe { libc::setrlimit(resource, &limit) } != 0 {
        return Err(format!(
            "setrlimit({resource}): {}",
            std::io::Error::last_os_error()
        ));
    }
    Ok(())
}

/// Drops to `nobody`. Returns whether it did.
fn drop_privileges() -> Result<bool, String> {
    // SAFETY: plain system calls; the launcher has one thread.
    unsafe {
        if libc::geteuid() != 0 {
            return Ok(false);
        }
        // Group first: once the user is dropped, the group cannot be.
        if libc::setgroups(0, std::ptr::null()) != 0
            || libc::setgid(NOBODY) != 0
            || libc::setuid(NOBODY) != 0
        {
            return Err(format!(
                "cannot drop to user nobody: {}",
                std::io::Error::last_os_error()
            ));
        }
        if libc::getuid() != NOBODY || libc::geteuid() != NOBODY {
            return Err("still privileged after dropping to nobody".into());
        }
    }
    Ok(true)
}

/// Landlock is Linux's: elsewhere the other protections stand alone.
#[cfg(not(target_os = "linux"))]
fn landlock(_: &std::fs::File) -> Result<i32, String> {
    Ok(0)
}

/// A Landlock ruleset that handles every file and network access and
/// scopes signals and abstract sockets (best effort up to ABI 6): nothing
/// is allowed until a launcher adds its rules. Shared by the case's and
/// the build's launchers.
#[cfg(target_os = "linux")]
pub(crate) fn denying_everything() -> Result<landlock::RulesetCreated, String> {
    use landlock::{
        Access, AccessFs, AccessNet, CompatLevel, Compatible, Ruleset, RulesetAttr, Scope, ABI,
    };
    let abi = ABI::V6;
    let fail = |e: &dyn std::fmt::Display| format!("Landlock: {e}");
    Ruleset::default()
        .set_compatibility(CompatLevel::BestEffort)
        .handle_access(AccessFs::from_all(abi))
        .map_err(|e| fail(&e))?
        .handle_access(AccessNet::from_all(abi))
        .map_err(|e| fail(&e))?
        .scope(Scope::from_all(abi))
        .map_err(|e| fail(&e))?
        .create()
        .map_err(|e| fail(&e))
}

/// Applies Landlock; returns the ABI in force (0 when the kernel has none).
#[cfg(target_os = "linux")]
fn landlock(program: &std::fs::File) -> Result<i32, String> {
    use landlock::{
        AccessFs, LandlockStatus, PathBeneath, PathFd, RulesetCreatedAttr, RulesetStatus,
    };
    let fail = |e: &dyn std::fmt::Display| format!("Landlock: {e}");
    let mut ruleset = denying_everything()?;
    // The program by its open descriptor: its folder may be closed to
    // `nobody`, which this process may be by now.
    ruleset = ruleset
        .add_rule(PathBeneath::new(
            program,
            AccessFs::ReadFile | AccessFs::Execute,
        ))
        .map_err(|e| fail(&e))?;
    // Its own /proc entries (the pid survives exec): the runtime reads
    // /proc/self/maps to find the main thread's stack guard, without which
    // a stack overflow is a bare SIGSEGV instead of a named one.
    if let Ok(fd) = PathFd::new("/proc/self") {
        ruleset = ruleset
            .add_rule(PathBeneath::new(fd, AccessFs::ReadFile))
            .map_err(|e| fail(&e))?;
    }
    // The dynamic loader and the shared libraries the child program needs.
    for dir in [
        "/lib",
        "/lib64",
        "/usr/lib",
        "/usr/lib64",
        "/etc/ld.so.cache",
    ] {
        if let Ok(fd) = PathFd::new(dir) {
            let rights = if Path::new(dir).is_dir() {
                AccessFs::ReadFile | AccessFs::Execute
            } else {
                AccessFs::ReadFile.into()
            };
            ruleset = ruleset
                .add_rule(PathBeneath::new(fd, rights))
                .map_err(|e| fail(&e))?;
        }
    }
    let status = ruleset.restrict_self().map_err(|e| fail(&e))?;
    Ok(match (status.ruleset, status.landlock) {
        (RulesetStatus::NotEnforced, _) => 0,
        (_, LandlockStatus::Available { effective_abi, .. }) => effective_abi as i32,
        _ => 0,
    })
}

/// The descriptor the child reads its request on. Its standard input is
/// `/dev/null`: never a terminal, whatever started the grader.
pub const REQUEST_FD: i32 = 3;

pub(crate) fn os_error(what: &str) -> String {
    format!("{what}: {}", std::io::Error::last_os_error())
}

/// Moves the request pipe (the launcher's stdin) to [`REQUEST_FD`] and puts
/// `/dev/null` on stdin. Whatever the grader inherited on `REQUEST_FD` is
/// closed by the move.
fn move_request() -> Result<(), String> {
    // SAFETY: plain system calls on our own descriptor table.
    unsafe {
        if libc::dup2(0, REQUEST_FD) < 0 {
            return Err(os_error("cannot move the request pipe"));
        }
        let null = libc::open(c"/dev/null".as_ptr(), libc::O_RDWR);
        if null < 0 || libc::dup2(null, 0) < 0 {
            return Err(os_error("cannot open /dev/null"));
        }
        if null != 0 {
            libc::close(null);
        }
    }
    Ok(())
}

/// Makes sure this process leads a session of its own (the runner starts
/// it so): with no controlling terminal, nothing it starts can open
/// `/dev/tty` or type into the terminal the grader runs in.
fn own_session() -> Result<(), String> {
    // SAFETY: plain system calls.
    unsafe {
        if libc::getsid(0) != libc::getpid() && libc::setsid() < 0 {
            return Err(os_error("cannot start a session of its own"));
        }
    }
    Ok(())
}

/// `PR_SET_PDEATHSIG`: this process is killed when its parent ends.
/// Returns whether the parent had already gone, as far as `getppid` can
/// tell (1: reparented to init).
fn die_with_parent() -> bool {
    // SAFETY: plain system calls.
    unsafe {
        #[cfg(target_os = "linux")]
        libc::prctl(
            libc::PR_SET_PDEATHSIG,
            libc::SIGKILL as libc::c_ulong,
            0,
            0,
            0,
        );
        libc::getppid() == 1
    }
}

#[cfg(target_os = "linux")]
/// Points 0, 1, 2 and [`REQUEST_FD`] at `/dev/null`: the launcher's own
/// processes that stay behind (the namespace's parent and init) hold none
/// of the case's pipes, so the grader sees them close with the child.
fn let_go_of_pipes() {
    // SAFETY: plain system calls on our own descriptor table.
    unsafe {
        let null = libc::open(c"/dev/null".as_ptr(), libc::O_RDWR);
        for fd in [0, 1, 2, REQUEST_FD] {
            libc::dup2(null, fd);
        }
        if null > REQUEST_FD {
            libc::close(null);
        }
    }
}

/// Enters a new PID namespace for the processes this one starts: as root
/// directly, otherwise inside a user namespace of its own that maps only
/// this user (an unprivileged user namespace, where the kernel allows
/// them). `false` where neither can be had: the grader's sweep of
/// orphans is then the only catch.
#[cfg(target_os = "linux")]
fn enter_pid_namespace() -> Result<bool, String> {
    use std::ffi::CString;
    // SAFETY: plain system calls; the launcher has one thread.
    let (uid, gid) = unsafe {
        if libc::unshare(libc::CLONE_NEWPID) == 0 {
            return Ok(true);
        }
        (libc::getuid(), libc::getgid())
    };
    // Root that may not make a PID namespace (some containers) would map
    // only itself in a user namespace, where `nobody` does not exist: it
    // keeps the sweep instead.
    if uid == 0 {
        return Ok(false);
    }
    // Only this user and group, as themselves: never root inside.
    let maps: Vec<(CString, CString)> = [
        ("setgroups", "deny".to_string()),
        ("uid_map", format!("{uid} {uid} 1\n")),
        ("gid_map", format!("{gid} {gid} 1\n")),
    ]
    .into_iter()
    .map(|(file, text)| {
        let path = CString::new(format!("/proc/self/{file}")).unwrap_or_default();
        (path, CString::new(text).unwrap_or_default())
    })
    .collect();
    // System calls only: also run in a forked process.
    let write_maps = || {
        maps.iter().all(|(path, text)| {
            // SAFETY: plain system calls on C strings we own.
            unsafe {
                let fd = libc::open(path.as_ptr(), libc::O_WRONLY | libc::O_CLOEXEC);
                let len = text.as_bytes().len();
                let ok = fd >= 0 && libc::write(fd, text.as_ptr().cast(), len) == len as isize;
                if fd >= 0 {
                    libc::close(fd);
                }
                ok
            }
        })
    };
    let flags = libc::CLONE_NEWUSER | libc::CLONE_NEWPID;
    // Tried first in a throwaway process: where the kernel lets a user
    // namespace be made but not mapped (Ubuntu's AppArmor restriction), the
    // launcher itself must not be left in one.
    let probe = fork()?;
    if probe == 0 {
        // SAFETY: plain system calls; this process ends here.
        unsafe {
            let ok = libc::unshare(flags) == 0 && write_maps();
            libc::_exit(if ok { 0 } else { 1 });
        }
    }
    if wait_for(probe) != Some(0) {
        return Ok(false);
    }
    // SAFETY: a plain system call; the launcher has one thread.
    if unsafe { libc::unshare(flags) } != 0 || !write_maps() {
        return Err(os_error("cannot map its user in a user namespace"));
    }
    Ok(true)
}

#[cfg(not(target_os = "linux"))]
fn enter_pid_namespace() -> Result<bool, String> {
    Ok(false)
}

#[cfg(target_os = "linux")]
pub(crate) fn fork() -> Result<libc::pid_t, String> {
    // SAFETY: the launcher has one thread; both sides go on with plain
    // system calls and its own code.
    match unsafe { libc::fork() } {
        -1 => Err(os_error("fork")),
        pid => Ok(pid),
    }
}

#[cfg(target_os = "linux")]
/// Waits for `pid` (retrying on interruption) and returns its wait status.
pub(crate) fn wait_for(pid: libc::pid_t) -> Option<libc::c_int> {
    let mut status = 0;
    loop {
        // SAFETY: waits for our own child, into our own int.
        let r = unsafe { libc::waitpid(pid, &mut status, 0) };
        if r == pid {
            return Some(status);
        }
        if r < 0 && std::io::Error::last_os_error().raw_os_error() != Some(libc::EINTR) {
            return None;
        }
    }
}

#[cfg(target_os = "linux")]
/// Ends this process the way `status` says another ended: the same exit
/// code, or the same signal (no core file: the limit is 0).
pub(crate) fn end_like(status: libc::c_int) -> ! {
    // SAFETY: plain system calls; the process ends here.
    unsafe {
        if libc::WIFSIGNALED(status) {
            let sig = libc::WTERMSIG(status);
            let none = libc::rlimit {
                rlim_cur: 0,
                rlim_max: 0,
            };
            libc::setrlimit(libc::RLIMIT_CORE, &none);
            libc::signal(sig, libc::SIG_DFL);
            let mut set: libc::sigset_t = std::mem::zeroed();
            libc::sigemptyset(&mut set);
            libc::sigaddset(&mut set, sig);
            libc::sigprocmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
            libc::kill(libc::getpid(), sig);
            libc::_exit(128 + sig);
        }
        libc::_exit(libc::WEXITSTATUS(status))
    }
}

/// In a new PID namespace, splits the launcher in three: this process
/// (outside) waits and ends as the child ended; its child, the
/// namespace's init (grader code only), waits for the case's child and
/// passes its status back; when init ends, the kernel kills whatever is
/// left in the namespace. Returns only in the case's child, which goes on
/// to lock itself in. (The case's child is not init itself: a PID 1
/// ignores the signals it sends itself, so an `abort` would show as
/// something else.)
#[cfg(target_os = "linux")]
fn split_for_namespace() -> Result<(), String> {
    let pipe = || -> Result<[i32; 2], String> {
        let mut fds = [0; 2];
        // SAFETY: fills our own array.
        if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) } != 0 {
            return Err(os_error("pipe"));
        }
        Ok(fds)
    };
    // The child's status, init to launcher; and the launcher's liveness,
    // which init checks once its parent-death signal is set.
    let [status_r, status_w] = pipe()?;
    let [alive_r, alive_w] = pipe()?;
    let init = fork()?;
    if init > 0 {
        // SAFETY: plain system calls on our own descriptors.
        unsafe {
            libc::close(status_w);
            libc::close(alive_r);
        }
        let_go_of_pipes();
        let waited = wait_for(init);
        let mut status: libc::c_int = 0;
        // SAFETY: reads into our own int.
        let n = unsafe {
            libc::read(
                status_r,
                (&mut status as *mut libc::c_int).cast(),
                std::mem::size_of::<libc::c_int>(),
            )
        };
        if n == std::mem::size_of::<libc::c_int>() as isize {
            end_like(status);
        }
        // Init itself died (killed with the group): end the same way.
        end_like(waited.unwrap_or(libc::SIGKILL));
    }
    // Init (PID 1 of the namespace).
    // SAFETY: plain system calls on our own descriptors.
    unsafe {
        libc::close(status_r);
        libc::close(alive_w);
        die_with_parent();
        let mut poll = libc::pollfd {
            fd: alive_r,
            events: libc::POLLIN,
            revents: 0,
        };
        if libc::poll(&mut poll, 1, 0) != 0 {
            return Err("the grader is gone".into());
        }
        libc::prctl(libc::PR_SET_DUMPABLE, 0, 0, 0, 0);
    }
    let child = fork()?;
    if child == 0 {
        // SAFETY: closes our own descriptors.
        unsafe {
            libc::close(status_w);
            libc::close(alive_r);
        }
        return Ok(());
    }
    let_go_of_pipes();
    let status = wait_for(child).unwrap_or(libc::SIGKILL);
    // SAFETY: writes our own int; then the namespace ends with us.
    unsafe {
        libc::write(
            status_w,
            (&status as *const libc::c_int).cast(),
            std::mem::size_of::<libc::c_int>(),
        );
        libc::_exit(0);
    }
}

#[cfg(not(target_os = "linux"))]
fn split_for_namespace() -> Result<(), String> {
    Ok(())
}

/// Where the child program is in its empty root: a name that says nothing
/// of the lab's folder.
const ROOTED_PROGRAM: &str = "/child";

/// The folders (or links) the dynamic loader and the shared libraries live
/// in, and its cache: all the child needs of the system. They hold nothing
/// secret.
#[cfg(target_os = "linux")]
const SYSTEM_PATHS: [&str; 5] = [
    "/lib",
    "/lib64",
    "/usr/lib",
    "/usr/lib64",
    "/etc/ld.so.cache",
];

#[cfg(target_os = "linux")]
pub(crate) fn cpath(path: &Path) -> Result<std::ffi::CString, String> {
    use std::os::unix::ffi::OsStrExt;
    std::ffi::CString::new(path.as_os_str().as_bytes())
        .map_err(|_| format!("{} holds a NUL byte", path.display()))
}

/// `mount(2)` with Rust arguments; `None` for a null pointer.
#[cfg(target_os = "linux")]
pub(crate) fn mount(
    source: Option<&Path>,
    target: &Path,
    fstype: Option<&str>,
    flags: libc::c_ulong,
    data: Option<&str>,
) -> Result<(), String> {
    let source = source.map(cpath).transpose()?;
    let target_c = cpath(target)?;
    let fstype = fstype.map(|f| cpath(Path::new(f))).transpose()?;
    let data = data.map(|d| cpath(Path::new(d))).transpose()?;
    let ptr = |c: &Option<std::ffi::CString>| c.as_ref().map_or(std::ptr::null(), |c| c.as_ptr());
    // SAFETY: C strings (or null) that outlive the call.
    let r = unsafe {
        libc::mount(
            ptr(&source),
            target_c.as_ptr(),
            ptr(&fstype),
            flags,
            ptr(&data).cast(),
        )
    };
    if r != 0 {
        return Err(os_error(&format!("mount {}", target.display())));
    }
    Ok(())
}

/// Binds `source` (a folder or a file) at `target`, read-only, no set-uid,
/// no devices (see [`remount_read_only`]).
#[cfg(target_os = "linux")]
fn bind_read_only(source: &Path, target: &Path) -> Result<(), String> {
    mount(
        Some(source),
        target,
        None,
        libc::MS_BIND | libc::MS_REC,
        None,
    )?;
    remount_read_only(target)
}

/// Remounts the bind mount at `target` read-only, no set-uid, no devices.
/// Its own locked flags (`noexec`, the access times) are kept: in a user
/// namespace, a remount that drops them fails.
#[cfg(target_os = "linux")]
pub(crate) fn remount_read_only(target: &Path) -> Result<(), String> {
    let mut kept: libc::c_ulong = 0;
    // SAFETY: statvfs fills our own struct.
    unsafe {
        let mut st: libc::statvfs = std::mem::zeroed();
        if libc::statvfs(cpath(target)?.as_ptr(), &mut st) != 0 {
            return Err(os_error(&format!("statvfs {}", target.display())));
        }
        for (st_flag, ms_flag) in [
            (libc::ST_NOEXEC, libc::MS_NOEXEC),
            (libc::ST_NOATIME, libc::MS_NOATIME),
            (libc::ST_NODIRATIME, libc::MS_NODIRATIME),
            (libc::ST_RELATIME, libc::MS_RELATIME),
        ] {
            if st.f_flag & st_flag != 0 {
                kept |= ms_flag;
            }
        }
    }
    mount(
        None,
        target,
        None,
        libc::MS_BIND
            | libc::MS_REMOUNT
            | libc::MS_RDONLY
            | libc::MS_NOSUID
            | libc::MS_NODEV
            | kept,
        None,
    )
}

/// Makes `dir` and every missing folder between `root` and it, each of
/// mode 0755 whatever the umask (a root grader run with umask 077 would
/// otherwise make folders `nobody` cannot enter, and the child's loader
/// would be out of its reach).
#[cfg(target_os = "linux")]
pub(crate) fn open_folders(root: &Path, dir: &Path) -> Result<(), String> {
    use std::os::unix::fs::PermissionsExt;
    let rel = dir.strip_prefix(root).unwrap_or(dir);
    let mut at = root.to_path_buf();
    for part in rel.components() {
        at.push(part);
        match std::fs::create_dir(&at) {
            Ok(()) => std::fs::set_permissions(&at, std::fs::Permissions::from_mode(0o755))
                .map_err(|e| format!("chmod {}: {e}", at.display()))?,
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(format!("mkdir {}: {e}", at.display())),
        }
    }
    Ok(())
}

/// Fills the fresh root mounted at `new`: the system's library folders
/// (bound read-only, or the same links where the system has links), the
/// child program at [`ROOTED_PROGRAM`], and a `/proc` of the case's own
/// PID namespace (the runtime reads `/proc/self/maps`; no other process
/// of the machine is in it).
#[cfg(target_os = "linux")]
fn furnish_root(new: &Path, program_tree: &std::os::fd::OwnedFd) -> Result<(), String> {
    use std::os::fd::AsRawFd;
    let fail = |what: &str, e: std::io::Error| format!("{what}: {e}");
    for host in SYSTEM_PATHS.map(Path::new) {
        let Ok(meta) = std::fs::symlink_metadata(host) else {
            continue;
        };
        let inside = new.join(host.strip_prefix("/").unwrap_or(host));
        if let Some(parent) = inside.parent() {
            open_folders(new, parent)?;
        }
        if meta.file_type().is_symlink() {
            let to = std::fs::read_link(host).map_err(|e| fail("readlink", e))?;
            std::os::unix::fs::symlink(to, &inside).map_err(|e| fail("symlink", e))?;
        } else if meta.is_dir() {
            open_folders(new, &inside)?;
            bind_read_only(host, &inside)?;
        } else {
            std::fs::File::create(&inside).map_err(|e| fail("create", e))?;
            bind_read_only(host, &inside)?;
        }
    }
    // The program, from the detached copy of its mount taken before the
    // new root hid its folder.
    let at = new.join(ROOTED_PROGRAM.trim_start_matches('/'));
    std::fs::File::create(&at).map_err(|e| fail("create", e))?;
    const MOVE_MOUNT_F_EMPTY_PATH: libc::c_uint = 0x4;
    // SAFETY: a plain system call on our descriptor and a C string we own.
    if unsafe {
        libc::syscall(
            libc::SYS_move_mount,
            program_tree.as_raw_fd(),
            c"".as_ptr(),
            libc::AT_FDCWD,
            cpath(&at)?.as_ptr(),
            MOVE_MOUNT_F_EMPTY_PATH,
        )
    } != 0
    {
        return Err(os_error("move_mount"));
    }
    mount(
        None,
        &at,
        None,
        libc::MS_BIND | libc::MS_REMOUNT | libc::MS_RDONLY | libc::MS_NOSUID | libc::MS_NODEV,
        None,
    )?;
    let proc = new.join("proc");
    std::fs::create_dir(&proc).map_err(|e| fail("mkdir", e))?;
    mount(
        Some(Path::new("proc")),
        &proc,
        Some("proc"),
        libc::MS_NOSUID | libc::MS_NODEV | libc::MS_NOEXEC,
        None,
    )
}

/// A detached mount of `program`'s file alone (`open_tree`), taken by its
/// path in this mount namespace, after checking the path still names the
/// same file. `None` where the kernel has no `open_tree` (before 5.2).
#[cfg(target_os = "linux")]
fn program_mount(program: &std::fs::File) -> Option<std::os::fd::OwnedFd> {
    use std::os::fd::{AsRawFd, FromRawFd};
    use std::os::unix::fs::MetadataExt;
    let path = std::fs::read_link(format!("/proc/self/fd/{}", program.as_raw_fd())).ok()?;
    const OPEN_TREE_CLONE: libc::c_uint = 1;
    // SAFETY: a plain system call on a C string we own; the descriptor it
    // returns is ours.
    let tree = unsafe {
        let fd = libc::syscall(
            libc::SYS_open_tree,
            libc::AT_FDCWD,
            cpath(&path).ok()?.as_ptr(),
            OPEN_TREE_CLONE | libc::O_CLOEXEC as libc::c_uint,
        );
        if fd < 0 {
            return None;
        }
        std::os::fd::OwnedFd::from_raw_fd(fd as i32)
    };
    let same =
        |a: &std::fs::Metadata, b: &std::fs::Metadata| a.dev() == b.dev() && a.ino() == b.ino();
    let mounted = std::fs::File::from(tree.try_clone().ok()?)
        .metadata()
        .ok()?;
    same(&mounted, &program.metadata().ok()?).then_some(tree)
}

/// Gives this process (the case's child-to-be, in its PID namespace, still
/// privileged there) a mount namespace whose root is a fresh, empty tmpfs
/// holding only what [`furnish_root`] puts in it: `stat` on any other path
/// (the lab, `fixtures/hidden`, `/tmp`, the TA's home) finds nothing.
/// Returns the program opened at its new path, or `None` where the kernel
/// refuses a step before the switch (today's protections then stand, and
/// the protections line says the machine's files are visible). A failure
/// after the switch is an error: the root would be half made.
#[cfg(target_os = "linux")]
fn empty_root(program: &std::fs::File) -> Result<Option<std::fs::File>, String> {
    // SAFETY: a plain system call; this process has one thread.
    if unsafe { libc::unshare(libc::CLONE_NEWNS) } != 0 {
        return Ok(None);
    }
    // Private first: nothing mounted here reaches the grader's namespace.
    if mount(
        None,
        Path::new("/"),
        None,
        libc::MS_REC | libc::MS_PRIVATE,
        None,
    )
    .is_err()
    {
        return Ok(None);
    }
    // A mount of the program alone, detached, for the new root. (A mount
    // is bound from a path in this namespace, not from the descriptor,
    // whose mount is the grader's namespace's; the path must still lead to
    // the same file.)
    let Some(program_tree) = program_mount(program) else {
        return Ok(None);
    };
    // Every system has /tmp; mounting over it here hides it from no one
    // else.
    let new = Path::new("/tmp");
    let made = mount(
        Some(Path::new("tmpfs")),
        new,
        Some("tmpfs"),
        libc::MS_NOSUID | libc::MS_NODEV,
        Some("size=64k,mode=0755"),
    )
    .and_then(|()| furnish_root(new, &program_tree));
    if made.is_err() {
        return Ok(None);
    }
    let dot = c".";
    // SAFETY: plain system calls on C strings we own. `pivot_root(".",
    // ".")` stacks the old root on the new one; detaching it leaves only
    // the new.
    unsafe {
        if libc::chdir(cpath(new)?.as_ptr()) != 0
            || libc::syscall(libc::SYS_pivot_root, dot.as_ptr(), dot.as_ptr()) != 0
        {
            libc::chdir(c"/".as_ptr());
            return Ok(None);
        }
        if libc::umount2(dot.as_ptr(), libc::MNT_DETACH) != 0 || libc::chdir(c"/".as_ptr()) != 0 {
            return Err(os_error("cannot let go of the old root"));
        }
    }
    mount(
        None,
        Path::new("/"),
        None,
        libc::MS_BIND | libc::MS_REMOUNT | libc::MS_RDONLY | libc::MS_NOSUID | libc::MS_NODEV,
        None,
    )?;
    std::fs::File::open(ROOTED_PROGRAM)
        .map(Some)
        .map_err(|e| format!("cannot open {ROOTED_PROGRAM} in the new root: {e}"))
}

#[cfg(not(target_os = "linux"))]
fn empty_root(_: &std::fs::File) -> Result<Option<std::fs::File>, String> {
    Ok(None)
}

/// `struct __user_cap_header_struct` and `__user_cap_data_struct`.
#[cfg(target_os = "linux")]
#[repr(C)]
struct CapHeader {
    version: u32,
    pid: i32,
}

#[cfg(target_os = "linux")]
#[repr(C)]
#[derive(Clone, Copy, Default)]
struct CapData {
    effective: u32,
    permitted: u32,
    inheritable: u32,
}

/// Drops every capability this process holds (a root that became `nobody`
/// holds none already; a launcher in a user namespace holds them all
/// there) and checks none is left.
#[cfg(target_os = "linux")]
fn drop_capabilities() -> Result<(), String> {
    const VERSION_3: u32 = 0x2008_0522;
    let mut header = CapHeader {
        version: VERSION_3,
        pid: 0,
    };
    let mut data = [CapData::default(); 2];
    // SAFETY: the header and two data records the v3 interface expects.
    unsafe {
        if libc::syscall(libc::SYS_capset, &mut header, data.as_ptr()) != 0 {
            return Err(os_error("cannot drop capabilities"));
        }
        header.version = VERSION_3;
        if libc::syscall(libc::SYS_capget, &mut header, data.as_mut_ptr()) != 0 {
            return Err(os_error("cannot read capabilities"));
        }
    }
    if data
        .iter()
        .any(|d| d.effective | d.permitted | d.inheritable != 0)
    {
        return Err("still holds capabilities after dropping them all".into());
    }
    Ok(())
}

#[cfg(not(target_os = "linux"))]
fn drop_capabilities() -> Result<(), String> {
    Ok(())
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
        let dropped = limits.drop_user && drop_privileges()?;
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
    let user = if unsafe { libc::geteuid() } == NOBODY {
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
