//! What the build can see: an empty root holding only what it needs (the
//! toolchain, the system's programs and libraries, the vendored crates, its
//! copy of the lab, its target folder), so that it cannot tell a hidden
//! file from a missing one; and the Landlock rules that keep it to them.

use std::path::{Path, PathBuf};

use super::Build;

/// How a path the build needs goes into its root.
#[cfg(target_os = "linux")]
pub(super) enum Place {
    /// A detached copy of its mount (`open_tree`), read-only or not.
    Tree(std::os::fd::OwnedFd, bool, bool),
    /// The same symbolic link (`/bin -> usr/bin`).
    Link(PathBuf),
}

/// Where a path of the new root is inside the folder `new` it is built in.
pub(super) fn inside(new: &Path, path: &Path) -> PathBuf {
    new.join(path.strip_prefix("/").unwrap_or(path))
}

/// Gives the build (its PID namespace's first process, still privileged
/// there) a mount namespace whose root is a fresh tmpfs holding only what
/// the build needs, each at its own path: the toolchain, the vendored
/// crates, its copy of the lab (read-only), its target folder (the one it
/// may write), the system's programs and libraries (`/usr`, `/lib*`,
/// `/bin`, `/sbin`), the loader's and the alternatives' files in `/etc`,
/// `/dev/null` and a `/proc` of its own PID namespace. Landlock's rules
/// stay as they are; this adds that what the build may not read, it cannot
/// tell from what does not exist (`include_str!` of a hidden case and of a
/// name nobody used fail alike: "No such file or directory").
///
/// Returns whether it did; where the kernel refuses a step before the
/// switch, the machine's tree stays (and the status says so). A failure
/// after the switch is an error: the root would be half made.
#[cfg(target_os = "linux")]
pub(super) fn empty_root(build: &Build) -> Result<bool, String> {
    use grader::isolate::namespace::{cpath, mount, open_folders, remount_read_only};
    use grader::isolate::sys::os_error;
    use std::os::fd::{AsRawFd, FromRawFd};
    if mount(
        None,
        Path::new("/"),
        None,
        libc::MS_REC | libc::MS_PRIVATE,
        None,
    )
    .is_err()
    {
        return Ok(false);
    }
    // (path, read-only, the build's own): the build's own folders are
    // named to cargo by these paths, so each must be its own path, no link
    // on the way.
    let mut wanted: Vec<(PathBuf, bool, bool)> = vec![
        (build.sysroot.clone(), true, true),
        (build.vendor.clone(), true, true),
        (build.lab.clone(), true, true),
        (build.target.clone(), false, true),
    ];
    for path in SYSTEM_PATHS {
        wanted.push((PathBuf::from(path), true, false));
    }
    wanted.push((PathBuf::from("/dev/null"), false, false));
    for (path, _, own) in &wanted {
        if *own && std::fs::canonicalize(path).ok().as_deref() != Some(path.as_path()) {
            return Ok(false);
        }
    }
    wanted.sort_by(|a, b| a.0.cmp(&b.0));
    let mut places: Vec<(PathBuf, Place)> = Vec::new();
    for (path, read_only, _) in wanted {
        // Inside a folder already bound (a toolchain under /usr): there
        // with it.
        let covered = places.iter().any(|(p, place)| {
            matches!(place, Place::Tree(_, _, true)) && path.starts_with(p) && path != *p
        });
        if covered {
            continue;
        }
        let Ok(meta) = std::fs::symlink_metadata(&path) else {
            continue;
        };
        if meta.file_type().is_symlink() {
            let Ok(to) = std::fs::read_link(&path) else {
                return Ok(false);
            };
            places.push((path, Place::Link(to)));
            continue;
        }
        const OPEN_TREE_CLONE: libc::c_uint = 1;
        const AT_RECURSIVE: libc::c_uint = 0x8000;
        // SAFETY: a plain system call on a C string we own; the descriptor
        // it returns is ours.
        let fd = unsafe {
            libc::syscall(
                libc::SYS_open_tree,
                libc::AT_FDCWD,
                cpath(&path)?.as_ptr(),
                OPEN_TREE_CLONE | AT_RECURSIVE | libc::O_CLOEXEC as libc::c_uint,
            )
        };
        if fd < 0 {
            return Ok(false);
        }
        // SAFETY: the descriptor was just returned to us.
        let tree = unsafe { std::os::fd::OwnedFd::from_raw_fd(fd as i32) };
        places.push((path, Place::Tree(tree, read_only, meta.is_dir())));
    }
    // The fresh root, mounted on the target folder (whose copy is taken
    // above): a folder that exists and that nothing else is under.
    let new = build.target.clone();
    if mount(
        Some(Path::new("tmpfs")),
        &new,
        Some("tmpfs"),
        libc::MS_NOSUID | libc::MS_NODEV,
        Some("size=1m,mode=0755"),
    )
    .is_err()
    {
        return Ok(false);
    }
    let furnish = || -> Result<(), String> {
        for (path, place) in &places {
            let at = inside(&new, path);
            if let Some(parent) = at.parent() {
                open_folders(&new, parent)?;
            }
            match place {
                Place::Link(to) => std::os::unix::fs::symlink(to, &at)
                    .map_err(|e| format!("symlink {}: {e}", at.display()))?,
                Place::Tree(tree, _, is_dir) => {
                    if *is_dir {
                        open_folders(&new, &at)?;
                    } else {
                        std::fs::File::create(&at)
                            .map_err(|e| format!("create {}: {e}", at.display()))?;
                    }
                    const MOVE_MOUNT_F_EMPTY_PATH: libc::c_uint = 0x4;
                    // SAFETY: a plain system call on our descriptor and a C
                    // string we own.
                    if unsafe {
                        libc::syscall(
                            libc::SYS_move_mount,
                            tree.as_raw_fd(),
                            c"".as_ptr(),
                            libc::AT_FDCWD,
                            cpath(&at)?.as_ptr(),
                            MOVE_MOUNT_F_EMPTY_PATH,
                        )
                    } != 0
                    {
                        return Err(os_error(&format!("move_mount {}", at.display())));
                    }
                }
            }
        }
        let proc = new.join("proc");
        open_folders(&new, &proc)?;
        mount(
            Some(Path::new("proc")),
            &proc,
            Some("proc"),
            libc::MS_NOSUID | libc::MS_NODEV | libc::MS_NOEXEC,
            None,
        )
    };
    let dot = c".";
    // SAFETY: plain system calls on C strings we own. `pivot_root(".",
    // ".")` stacks the old root on the new one; detaching it leaves only
    // the new.
    let switched = furnish().is_ok()
        && unsafe {
            libc::chdir(cpath(&new)?.as_ptr()) == 0
                && libc::syscall(libc::SYS_pivot_root, dot.as_ptr(), dot.as_ptr()) == 0
        };
    if !switched {
        // SAFETY: plain system calls: back to the machine's tree, whole.
        unsafe {
            libc::chdir(c"/".as_ptr());
            libc::umount2(cpath(&new)?.as_ptr(), libc::MNT_DETACH);
        }
        return Ok(false);
    }
    // SAFETY: as above.
    unsafe {
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
    for (path, place) in &places {
        if let Place::Tree(_, true, _) = place {
            remount_read_only(path)?;
        }
    }
    Ok(true)
}

#[cfg(not(target_os = "linux"))]
pub(super) fn empty_root(_: &Build) -> Result<bool, String> {
    Ok(false)
}

/// The system's paths the build reads (Landlock's rules name the same):
/// the compilers, linkers and libraries, the loader's files, and the
/// alternatives the system's `cc` is a link through.
pub(super) const SYSTEM_PATHS: [&str; 9] = [
    "/usr",
    "/lib",
    "/lib64",
    "/bin",
    "/sbin",
    "/etc/ld.so.cache",
    "/etc/ld.so.conf",
    "/etc/ld.so.conf.d",
    "/etc/alternatives",
];

#[cfg(not(target_os = "linux"))]
pub(super) fn landlock(_: &Build) -> Result<i32, String> {
    Ok(0)
}

/// Applies the build's Landlock rules; the ABI in force (0: none).
#[cfg(target_os = "linux")]
pub(super) fn landlock(build: &Build) -> Result<i32, String> {
    use landlock::{
        Access, AccessFs, BitFlags, LandlockStatus, PathBeneath, PathFd, RulesetCreatedAttr,
        RulesetStatus, ABI,
    };
    let abi = ABI::V6;
    let fail = |e: &dyn std::fmt::Display| format!("Landlock: {e}");
    let mut ruleset = grader::isolate::landlock_rules::denying_everything()?;
    let read: BitFlags<AccessFs> = AccessFs::from_read(abi);
    // The toolchain, the system's compilers, linkers and libraries, the
    // dependencies' sources and the copy of the lab: read only.
    let mut rules: Vec<(PathBuf, BitFlags<AccessFs>)> = vec![
        (build.sysroot.clone(), read),
        (build.vendor.clone(), read),
        (build.lab.clone(), read),
        (build.target.clone(), AccessFs::from_all(abi)),
        ("/dev/null".into(), AccessFs::ReadFile | AccessFs::WriteFile),
    ];
    for dir in ["/usr", "/lib", "/lib64", "/bin", "/sbin"] {
        rules.push((dir.into(), read));
    }
    for file in ["/etc/ld.so.cache", "/etc/ld.so.conf"] {
        rules.push((file.into(), AccessFs::ReadFile.into()));
    }
    for dir in ["/etc/ld.so.conf.d", "/etc/alternatives"] {
        rules.push((dir.into(), read));
    }
    for (path, rights) in rules {
        let Ok(fd) = PathFd::new(&path) else {
            continue;
        };
        // A file takes only the rights a file can have.
        let rights = if path.is_dir() {
            rights
        } else {
            rights & AccessFs::from_file(abi)
        };
        ruleset = ruleset
            .add_rule(PathBeneath::new(fd, rights))
            .map_err(|e| fail(&e))?;
    }
    let status = ruleset.restrict_self().map_err(|e| fail(&e))?;
    Ok(match (status.ruleset, status.landlock) {
        (RulesetStatus::NotEnforced, _) => 0,
        (_, LandlockStatus::Available { effective_abi, .. }) => effective_abi as i32,
        _ => 0,
    })
}
