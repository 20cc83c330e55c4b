//! The build's child locking itself in before cargo runs: its session,
//! namespaces (network, PID, mount), limits, user, Landlock and
//! environment.

use super::root::{empty_root, landlock};
use super::supervise::last_error;
use super::Build;
use grader::isolate::sys::set_limit;

/// The child's lock-in, before cargo is `exec`ed: the status line for the
/// launcher (`landlock=6 network=namespace user=nobody root=empty`).
/// `status` is the status pipe, which a process of the lock-in that stays
/// behind (waiting outside a PID namespace) lets go of.
pub(super) fn lock_in(build: &Build, parent: libc::pid_t, status: i32) -> Result<String, String> {
    // SAFETY: plain system calls on this (single-threaded) process.
    unsafe {
        if libc::setsid() < 0 {
            return Err(format!("setsid: {}", last_error()));
        }
        #[cfg(target_os = "linux")]
        {
            libc::prctl(
                libc::PR_SET_PDEATHSIG,
                libc::SIGKILL as libc::c_ulong,
                0,
                0,
                0,
            );
        }
        if libc::getppid() != parent {
            return Err("the launcher is gone".into());
        }
        let null = c"/dev/null";
        let fd = libc::open(null.as_ptr(), libc::O_RDONLY);
        if fd >= 0 {
            libc::dup2(fd, 0);
            libc::close(fd);
        }
    }
    // Asked before the empty root hides /etc/passwd.
    let caller = user_name();
    let spaces = own_namespaces();
    if spaces.pid {
        // This process waits outside the new PID namespace; its child, the
        // namespace's first process, goes on to lock itself in and run
        // cargo (killed, with all it started, when this one is).
        wait_outside(status)?;
    }
    let rooted = if build.empty_root && spaces.mount && spaces.pid {
        empty_root(build)?
    } else {
        false
    };
    let network = spaces.network;
    set_limit(libc::RLIMIT_AS, build.memory)?;
    // The largest file a build writes is a debug binary of tens of MiB.
    set_limit(libc::RLIMIT_FSIZE, 2 << 30)?;
    set_limit(libc::RLIMIT_CORE, 0)?;
    // SAFETY: plain system calls.
    let root = unsafe { libc::geteuid() } == 0;
    let user = if build.drop_user && root {
        grader::isolate::sys::drop_to_nobody()?;
        // SAFETY: a plain system call.
        unsafe {
            // Dropping the user clears the parent-death signal.
            #[cfg(target_os = "linux")]
            libc::prctl(
                libc::PR_SET_PDEATHSIG,
                libc::SIGKILL as libc::c_ulong,
                0,
                0,
                0,
            );
        }
        "nobody".to_string()
    } else {
        caller
    };
    let abi = if build.landlock { landlock(build)? } else { 0 };
    let network = match network {
        true => "namespace",
        false if abi >= 4 => "landlock",
        false => "none",
    };
    // Descriptors this launcher inherited must not reach the build.
    // SAFETY: a plain system call on our own descriptor table.
    #[cfg(target_os = "linux")]
    unsafe {
        const CLOSE_RANGE_CLOEXEC: u32 = 1 << 2;
        libc::syscall(libc::SYS_close_range, 3u32, u32::MAX, CLOSE_RANGE_CLOEXEC);
    }
    let root = if rooted { "empty" } else { "host" };
    Ok(format!(
        "landlock={abi}\nnetwork={network}\nuser={user}\nroot={root}\n"
    ))
}

/// This process's user's name, for the protections line.
pub(super) fn user_name() -> String {
    // SAFETY: getpwuid returns a pointer to static storage or null.
    unsafe {
        let uid = libc::geteuid();
        let pw = libc::getpwuid(uid);
        if pw.is_null() || (*pw).pw_name.is_null() {
            return uid.to_string();
        }
        std::ffi::CStr::from_ptr((*pw).pw_name)
            .to_string_lossy()
            .into_owned()
    }
}

/// The namespaces the build got: a network namespace (no interface but a
/// loopback that is down), and mount and PID namespaces for the empty
/// root (a PID namespace for a `/proc` that shows the build's processes
/// only: rustc finds its libraries through `/proc/self/exe`).
#[derive(Clone, Copy, Default)]
pub(super) struct Spaces {
    network: bool,
    mount: bool,
    pid: bool,
}

/// Namespaces of its own: as root directly, otherwise inside a new user
/// namespace mapping this user to itself (tried first in a throwaway
/// process: where a user namespace can be made but not mapped, this one
/// must not be left in it). The most it can get, down to none.
#[cfg(target_os = "linux")]
pub(super) fn own_namespaces() -> Spaces {
    let all = libc::CLONE_NEWNET | libc::CLONE_NEWNS | libc::CLONE_NEWPID;
    // SAFETY: plain system calls on this (single-threaded) process.
    unsafe {
        if libc::geteuid() == 0 {
            if libc::unshare(all) == 0 {
                return Spaces {
                    network: true,
                    mount: true,
                    pid: true,
                };
            }
            return Spaces {
                network: libc::unshare(libc::CLONE_NEWNET) == 0,
                ..Spaces::default()
            };
        }
    }
    // SAFETY: plain system calls.
    let (uid, gid) = unsafe { (libc::geteuid(), libc::getegid()) };
    let maps = [
        ("/proc/self/setgroups", "deny".to_string()),
        ("/proc/self/uid_map", format!("{uid} {uid} 1")),
        ("/proc/self/gid_map", format!("{gid} {gid} 1")),
    ];
    let enter = |flags: libc::c_int| {
        // SAFETY: a plain system call.
        (unsafe { libc::unshare(libc::CLONE_NEWUSER | flags) } == 0)
            && maps.iter().all(|(f, t)| std::fs::write(f, t).is_ok())
    };
    let works = |flags: libc::c_int| match grader::isolate::sys::fork() {
        Ok(0) => {
            let ok = enter(flags);
            // SAFETY: ends the throwaway process.
            unsafe { libc::_exit(if ok { 0 } else { 1 }) }
        }
        Ok(probe) => grader::isolate::sys::wait_for(probe) == Some(0),
        Err(_) => false,
    };
    for (flags, got) in [
        (
            all,
            Spaces {
                network: true,
                mount: true,
                pid: true,
            },
        ),
        (
            libc::CLONE_NEWNET,
            Spaces {
                network: true,
                ..Spaces::default()
            },
        ),
    ] {
        if works(flags) {
            return if enter(flags) { got } else { Spaces::default() };
        }
    }
    Spaces::default()
}

#[cfg(not(target_os = "linux"))]
pub(super) fn own_namespaces() -> Spaces {
    Spaces::default()
}

/// In a new PID namespace: forks its first process, which returns and goes
/// on; this one lets go of the status pipe and its standard streams, waits
/// for it and ends as it ended (the launcher reads cargo's status from
/// this process's).
#[cfg(target_os = "linux")]
pub(super) fn wait_outside(status: i32) -> Result<(), String> {
    let first = grader::isolate::sys::fork()?;
    if first == 0 {
        // SAFETY: a plain prctl call. Its parent is this process's waiter.
        unsafe {
            libc::prctl(
                libc::PR_SET_PDEATHSIG,
                libc::SIGKILL as libc::c_ulong,
                0,
                0,
                0,
            );
        }
        return Ok(());
    }
    // SAFETY: plain system calls on our own descriptor table.
    unsafe {
        libc::close(status);
        let null = libc::open(c"/dev/null".as_ptr(), libc::O_RDWR);
        for fd in [0, 1, 2] {
            libc::dup2(null, fd);
        }
        if null > 2 {
            libc::close(null);
        }
    }
    let ended = grader::isolate::sys::wait_for(first).unwrap_or(libc::SIGKILL);
    grader::isolate::sys::end_like(ended)
}

#[cfg(not(target_os = "linux"))]
pub(super) fn wait_outside(_: i32) -> Result<(), String> {
    Ok(())
}
