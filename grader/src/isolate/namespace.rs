//! The case's PID namespace and its empty root: a fresh, read-only tmpfs
//! holding only the child program (at [`ROOTED_PROGRAM`]), the library
//! folders and the case's own `/proc`, so that `stat` finds nothing of the
//! machine. Linux only; elsewhere there is no namespace, and the runner's
//! sweep of orphans and the machine's tree remain (the protections line
//! says which).

use std::path::Path;

use crate::isolate::sys::{die_with_parent, end_like, fork, let_go_of_pipes, os_error, wait_for};

/// Enters a new PID namespace for the processes this one starts: as root
/// directly, otherwise inside a user namespace of its own that maps only
/// this user (an unprivileged user namespace, where the kernel allows
/// them). `false` where neither can be had: the grader's sweep of
/// orphans is then the only catch.
#[cfg(target_os = "linux")]
pub fn enter_pid_namespace() -> Result<bool, String> {
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
pub fn enter_pid_namespace() -> Result<bool, String> {
    Ok(false)
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
pub fn split_for_namespace() -> Result<(), String> {
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
pub fn split_for_namespace() -> Result<(), String> {
    Ok(())
}

/// Where the child program is in its empty root: a name that says nothing
/// of the lab's folder.
pub const ROOTED_PROGRAM: &str = "/child";

/// The folders (or links) the dynamic loader and the shared libraries live
/// in, and its cache: all the child needs of the system. They hold nothing
/// secret.
#[cfg(target_os = "linux")]
pub const SYSTEM_PATHS: [&str; 5] = [
    "/lib",
    "/lib64",
    "/usr/lib",
    "/usr/lib64",
    "/etc/ld.so.cache",
];

#[cfg(target_os = "linux")]
pub fn cpath(path: &Path) -> Result<std::ffi::CString, String> {
    use std::os::unix::ffi::OsStrExt;
    std::ffi::CString::new(path.as_os_str().as_bytes())
        .map_err(|_| format!("{} holds a NUL byte", path.display()))
}

/// `mount(2)` with Rust arguments; `None` for a null pointer.
#[cfg(target_os = "linux")]
pub fn mount(
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
pub fn bind_read_only(source: &Path, target: &Path) -> Result<(), String> {
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
pub fn remount_read_only(target: &Path) -> Result<(), String> {
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
pub fn open_folders(root: &Path, dir: &Path) -> Result<(), String> {
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
pub fn furnish_root(new: &Path, program_tree: &std::os::fd::OwnedFd) -> Result<(), String> {
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
pub fn program_mount(program: &std::fs::File) -> Option<std::os::fd::OwnedFd> {
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
pub fn empty_root(program: &std::fs::File) -> Result<Option<std::fs::File>, String> {
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
pub fn empty_root(_: &std::fs::File) -> Result<Option<std::fs::File>, String> {
    Ok(None)
}
