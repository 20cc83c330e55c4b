//! Locking a case's child process in before any student code runs.
//!
//! The student's code is linked into the child program, and Rust lets code
//! run before `main` (a static in `.init_array`), so the child cannot lock
//! itself in: by then it is too late. Instead the grader starts itself
//! again as a *launcher* (grader code only), which takes every privilege
//! away and then `exec`s the child program, born locked:
//!
//! - Landlock (best ABI the kernel offers, up to 6): no file may be read,
//!   written or executed except the child program, the system's shared
//!   libraries (read and map) and its own `/proc/self` (read); no TCP; no signals to, and no abstract
//!   sockets of, processes outside the sandbox. It cannot be undone.
//! - `RLIMIT_AS` (the memory cap), `RLIMIT_FSIZE` 0 (no file can grow, even
//!   without Landlock), `RLIMIT_CORE` 0.
//! - As root, it drops to user `nobody` (and a process cap, which only
//!   binds users other than root) when the child program is readable by
//!   everyone.
//! - A seccomp filter ([`crate::seccomp`]): no new processes, no sockets,
//!   no IPC, no reaching other processes' priority or limits.
//! - `PR_SET_PDEATHSIG`: if the grader dies, so does the child.
//! - An empty environment and `/` as working folder: nothing names a
//!   fixture, a result file or the grader's options.
//!
//! The launcher writes what it put in place as the first frame on the
//! result pipe ([`crate::wire::Frame::Sandbox`]); the grader prints it as
//! the protections line.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// The first argument that turns a grader process into a launcher.
pub const LAUNCH_ARG: &str = "--meshlab-sandbox-launch";

/// The exit status of a launcher that could not set up the sandbox.
pub const LAUNCH_FAILED: i32 = 97;

/// The user a root grader drops to.
const NOBODY: u32 = 65534;

/// The limits a case runs under.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Limits {
    /// The address-space cap in bytes.
    pub memory: u64,
    /// Whether to drop to `nobody` when running as root.
    pub drop_user: bool,
    /// Whether to apply Landlock (off only to test what a kernel without
    /// it leaves: the other protections must still hold).
    pub landlock: bool,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            memory: 2 << 30,
            drop_user: true,
            landlock: true,
        }
    }
}

/// `2 GiB`, `512 MiB`: how messages say a memory size.
pub fn format_bytes(bytes: u64) -> String {
    const GIB: u64 = 1 << 30;
    const MIB: u64 = 1 << 20;
    if bytes % GIB == 0 {
        format!("{} GiB", bytes / GIB)
    } else if bytes >= GIB {
        format!("{:.1} GiB", bytes as f64 / GIB as f64)
    } else {
        format!("{} MiB", bytes.div_ceil(MIB))
    }
}

/// The launcher's command line: `LAUNCH_ARG memory drop|keep
/// landlock|nolandlock child args...`.
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
    let [memory, drop, landlock, child, rest @ ..] = args else {
        return Err("the launcher needs: MEMORY drop|keep landlock|nolandlock CHILD [ARGS]".into());
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
type Resource = libc::__rlimit_resource_t;
#[cfg(not(target_os = "linux"))]
type Resource = libc::c_int;

fn set_limit(resource: Resource, value: u64) -> Result<(), String> {
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

/// Applies Landlock; returns the ABI in force (0 when the kernel has none).
#[cfg(target_os = "linux")]
fn landlock(program: &std::fs::File) -> Result<i32, String> {
    use landlock::{
        Access, AccessFs, AccessNet, CompatLevel, Compatible, LandlockStatus, PathBeneath, PathFd,
        Ruleset, RulesetAttr, RulesetCreatedAttr, RulesetStatus, Scope, ABI,
    };
    let abi = ABI::V6;
    let fail = |e: &dyn std::fmt::Display| format!("Landlock: {e}");
    let mut ruleset = Ruleset::default()
        .set_compatibility(CompatLevel::BestEffort)
        .handle_access(AccessFs::from_all(abi))
        .map_err(|e| fail(&e))?
        .handle_access(AccessNet::from_all(abi))
        .map_err(|e| fail(&e))?
        .scope(Scope::from_all(abi))
        .map_err(|e| fail(&e))?
        .create()
        .map_err(|e| fail(&e))?;
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

/// Locks this process in and `exec`s the child. Returns only on failure.
fn launch(limits: &Limits, child: &Path, child_args: &[OsString]) -> String {
    use std::io::Write;
    use std::os::fd::AsRawFd;
    // Opened while still privileged, and executed by descriptor: a child
    // program in a folder `nobody` cannot enter (a root's home) still runs
    // as `nobody`. Close-on-exec, so the child does not hold it.
    let program = match std::fs::File::open(child) {
        Ok(f) => f,
        Err(e) => return format!("cannot open {}: {e}", child.display()),
    };
    let setup = || -> Result<String, String> {
        set_limit(libc::RLIMIT_AS, limits.memory)?;
        set_limit(libc::RLIMIT_FSIZE, 0)?;
        set_limit(libc::RLIMIT_CORE, 0)?;
        let dropped = limits.drop_user && drop_privileges()?;
        if dropped {
            // Binds only a user other than root: caps a fork bomb.
            set_limit(libc::RLIMIT_NPROC, 512)?;
        }
        // SAFETY: plain prctl calls. Set after dropping privileges, which
        // clears the parent-death signal.
        #[cfg(target_os = "linux")]
        unsafe {
            libc::prctl(
                libc::PR_SET_PDEATHSIG,
                libc::SIGKILL as libc::c_ulong,
                0,
                0,
                0,
            );
            if libc::getppid() == 1 {
                return Err("the grader is gone".into());
            }
        }
        let abi = if limits.landlock {
            landlock(&program)?
        } else {
            0
        };
        let filtered = crate::seccomp::apply()?;
        std::env::set_current_dir("/").map_err(|e| format!("chdir /: {e}"))?;
        Ok(format!(
            "landlock={abi} memory={} user={} group=own seccomp={}",
            limits.memory,
            if dropped { "nobody" } else { "same" },
            u8::from(filtered)
        ))
    };
    let status = match setup() {
        Ok(s) => s,
        Err(e) => return e,
    };
    let frame = crate::wire::sandbox_frame(&status);
    if let Err(e) = std::io::stdout().write_all(&frame) {
        return format!("cannot write to the grader: {e}");
    }
    let _ = std::io::stdout().flush();
    // Descriptors the grader itself inherited without close-on-exec (from
    // whatever started it) must not reach the child: only 0, 1 and 2 do.
    // (Marked close-on-exec rather than closed: `program` is needed to exec.)
    // SAFETY: a plain system call on our own descriptor table.
    #[cfg(target_os = "linux")]
    unsafe {
        const CLOSE_RANGE_CLOEXEC: u32 = 1 << 2;
        libc::syscall(libc::SYS_close_range, 3u32, u32::MAX, CLOSE_RANGE_CLOEXEC);
    }
    let cstr = |s: &std::ffi::OsStr| {
        use std::os::unix::ffi::OsStrExt;
        std::ffi::CString::new(s.as_bytes()).unwrap_or_default()
    };
    let argv: Vec<std::ffi::CString> = std::iter::once(child.as_os_str())
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
    format!(
        "cannot start {}: {}",
        child.display(),
        std::io::Error::last_os_error()
    )
}

/// The protections in force, from the launcher's status frame, as the
/// report's protections line says them.
pub fn describe_status(status: &str) -> String {
    let field = |key: &str| {
        status
            .split_whitespace()
            .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
            .unwrap_or("")
    };
    let landlock = match field("landlock") {
        "" | "0" => "Landlock off (the kernel has none: student code can read files)".to_string(),
        abi => format!("Landlock ABI {abi} (no files, no network, no signals out)"),
    };
    let memory = field("memory")
        .parse::<u64>()
        .map(|m| format!("memory cap {}", format_bytes(m)))
        .unwrap_or_else(|_| "memory cap unknown".into());
    let user = match field("user") {
        "nobody" => ", user nobody",
        _ => "",
    };
    let filter = match field("seccomp") {
        "1" => ", seccomp (no new processes, no sockets, no IPC)",
        _ => ", no seccomp filter",
    };
    format!("protections: {landlock}, {memory}, own process group{user}{filter}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_well() {
        assert_eq!(format_bytes(2 << 30), "2 GiB");
        assert_eq!(format_bytes(512 << 20), "512 MiB");
        assert_eq!(format_bytes(3 << 29), "1.5 GiB");
    }

    #[test]
    fn the_status_line_names_each_protection() {
        let line = describe_status("landlock=6 memory=2147483648 user=nobody group=own seccomp=1");
        assert_eq!(
            line,
            "protections: Landlock ABI 6 (no files, no network, no signals out), \
             memory cap 2 GiB, own process group, user nobody, \
             seccomp (no new processes, no sockets, no IPC)"
        );
        let off = describe_status("landlock=0 memory=1073741824 user=same group=own");
        assert!(off.contains("Landlock off"), "{off}");
        assert!(!off.contains("nobody"), "{off}");
    }

    #[test]
    fn launcher_arguments_parse_back() {
        let limits = Limits {
            memory: 123,
            drop_user: false,
            landlock: false,
        };
        let args = launcher_args(&limits, Path::new("/x/child"), &["a".into()]);
        let (l, c, rest) = parse_launch(&args[1..]).unwrap();
        assert_eq!(l, limits);
        assert_eq!(c, PathBuf::from("/x/child"));
        assert_eq!(rest, vec![OsString::from("a")]);
    }
}
