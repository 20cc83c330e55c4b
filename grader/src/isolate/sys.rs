//! The operating system's part of locking a process in: limits, users,
//! capabilities, sessions, the parent-death signal, descriptors, forking
//! and waiting. Plain system calls with errors in words; the launchers
//! (a case's and a build's) put them together.

use std::path::Path;

use crate::isolate::wire::REQUEST_FD;

/// The ids (uid, gid) of user `nobody`, the user a root grader (and a
/// root build) drops to: the lab's one place for them. From
/// `/etc/passwd` where it lists `nobody`, else the usual 65534; read once
/// (a launcher reads it before its empty root hides the file).
pub fn nobody() -> (u32, u32) {
    static IDS: std::sync::OnceLock<(u32, u32)> = std::sync::OnceLock::new();
    *IDS.get_or_init(|| {
        let passwd = std::fs::read_to_string("/etc/passwd").unwrap_or_default();
        passwd
            .lines()
            .find_map(|l| {
                let fields: Vec<&str> = l.split(':').collect();
                (fields.first() == Some(&"nobody")).then_some(())?;
                Some((fields.get(2)?.parse().ok()?, fields.get(3)?.parse().ok()?))
            })
            .unwrap_or((65534, 65534))
    })
}

/// Drops this process, if root, to [`nobody`]: groups first, while still
/// allowed. Returns whether it dropped.
pub fn drop_to_nobody() -> Result<bool, String> {
    let (uid, gid) = nobody();
    // SAFETY: plain system calls.
    unsafe {
        if libc::geteuid() != 0 {
            return Ok(false);
        }
        if libc::setgroups(0, std::ptr::null()) != 0
            || libc::setgid(gid) != 0
            || libc::setuid(uid) != 0
        {
            return Err(format!(
                "cannot drop to user nobody: {}",
                std::io::Error::last_os_error()
            ));
        }
        if libc::getuid() != uid || libc::geteuid() != uid {
            return Err("still privileged after dropping to nobody".into());
        }
    }
    Ok(true)
}

/// Whether `nobody` could run `exe`, given open by descriptor: the file is
/// executable by others. (The folders above it do not matter: the launcher
/// opens it before dropping privileges.)
pub fn runnable_by_others(exe: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(exe).is_ok_and(|m| m.permissions().mode() & 0o001 != 0)
}

#[cfg(target_os = "linux")]
pub type Resource = libc::__rlimit_resource_t;

#[cfg(not(target_os = "linux"))]
pub type Resource = libc::c_int;

/// Sets both the soft and the hard limit of `resource` to `value`.
pub fn set_limit(resource: Resource, value: u64) -> Result<(), String> {
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

pub fn os_error(what: &str) -> String {
    format!("{what}: {}", std::io::Error::last_os_error())
}

/// Moves the request pipe (the launcher's stdin) to [`REQUEST_FD`] and puts
/// `/dev/null` on stdin. Whatever the grader inherited on `REQUEST_FD` is
/// closed by the move.
pub fn move_request() -> Result<(), String> {
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
pub fn own_session() -> Result<(), String> {
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
pub fn die_with_parent() -> bool {
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
pub fn let_go_of_pipes() {
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

#[cfg(target_os = "linux")]
pub fn fork() -> Result<libc::pid_t, String> {
    // SAFETY: the launcher has one thread; both sides go on with plain
    // system calls and its own code.
    match unsafe { libc::fork() } {
        -1 => Err(os_error("fork")),
        pid => Ok(pid),
    }
}

#[cfg(target_os = "linux")]
/// Waits for `pid` (retrying on interruption) and returns its wait status.
pub fn wait_for(pid: libc::pid_t) -> Option<libc::c_int> {
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
pub fn end_like(status: libc::c_int) -> ! {
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

/// `struct __user_cap_header_struct` and `__user_cap_data_struct`.
#[cfg(target_os = "linux")]
#[repr(C)]
pub struct CapHeader {
    version: u32,
    pid: i32,
}

#[cfg(target_os = "linux")]
#[repr(C)]
#[derive(Clone, Copy, Default)]
pub struct CapData {
    effective: u32,
    permitted: u32,
    inheritable: u32,
}

/// Drops every capability this process holds (a root that became `nobody`
/// holds none already; a launcher in a user namespace holds them all
/// there) and checks none is left.
#[cfg(target_os = "linux")]
pub fn drop_capabilities() -> Result<(), String> {
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
pub fn drop_capabilities() -> Result<(), String> {
    Ok(())
}
