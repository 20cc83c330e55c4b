//! A seccomp filter for the case's child: the system calls Landlock does not
//! cover and no lab function needs are refused (`EPERM`).
//!
//! - New processes (`fork`, `vfork`, `clone` without `CLONE_THREAD`):
//!   threads stay allowed; a process can neither outlive the case, nor
//!   hold the grader's pipes, nor multiply the memory cap. Nor can it
//!   leave its session or process group (`setsid`, `setpgid`).
//! - Sockets of any kind (UDP, Unix sockets by path: Landlock covers only TCP
//!   and abstract sockets; socket pairs, whose buffers are kernel memory no
//!   cap counts) and `io_uring` (which can make sockets without a system
//!   call of its own).
//! - System V and POSIX IPC, every call (shared memory outlives the process
//!   and the cap; objects others made are found by index without `*get`).
//! - Opening a file to write, create or truncate it; truncating, moving,
//!   linking, removing or making one (Landlock stops these too; without
//!   it, a grader's own user's files would be open to them).
//! - A file's mode, owner, times, extended attributes and flags (`chmod`,
//!   `chown`, `utimensat`, `setxattr`, `file_setattr`... and their
//!   variants): Landlock guards opening a file, not its metadata.
//! - Reaching another process: signals other than to itself (`kill`,
//!   `tgkill`, `rt_sigqueueinfo`... only with its own pid, `tkill` and
//!   pidfds not at all, `F_SETOWN`/`FIOSETOWN`, which aim `SIGIO`), its
//!   priority, scheduling, CPUs and limits (`setpriority`, `ioprio_set`,
//!   `sched_setattr`, `sched_setscheduler`, `sched_setparam`,
//!   `sched_setaffinity`, `prlimit64`: only on pid 0 or its own),
//!   `ptrace`, `process_vm_*`, `kcmp`, `process_madvise`, page migration.
//! - `prctl`: an allow-list of what the Rust and C runtimes use (naming
//!   threads and mappings, reading settings); every option that would undo
//!   a protection (`PR_SET_PDEATHSIG`, `PR_SET_DUMPABLE`, `PR_SET_PTRACER`,
//!   `PR_SET_KEEPCAPS`, `PR_SET_CHILD_SUBREAPER`, ambient capabilities...)
//!   is refused.
//! - The terminal: `ioctl` `TIOCSTI` (typing into it), `TIOCLINUX`,
//!   `TIOCSCTTY`, `TIOCSPGRP`, `TIOCSETD`, `TIOCCONS`, `TIOCSIG`.
//! - File watches (`inotify`, `fanotify`), file handles
//!   (`open_by_handle_at`), namespaces, mounts, `chroot`, keyrings, `bpf`,
//!   `perf_event_open`, `userfaultfd`, changing users or capabilities, and
//!   the system-wide calls (`reboot`, `swapon`, modules, the clock, `acct`,
//!   `personality`...) that need a privilege it should never have.
//!
//! `clone3` answers `ENOSYS`, so the C library falls back to `clone`, whose
//! flags the filter can read. A system call of another architecture (x32)
//! kills the process. Linux on x86-64 and AArch64 only; elsewhere the filter
//! is not applied and the protections line says so.

/// Whether this build can apply the filter.
pub const SUPPORTED: bool = cfg!(all(
    target_os = "linux",
    any(target_arch = "x86_64", target_arch = "aarch64")
));

#[cfg(all(
    target_os = "linux",
    any(target_arch = "x86_64", target_arch = "aarch64")
))]
mod filter {
    #[repr(C)]
    struct SockFilter {
        code: u16,
        jt: u8,
        jf: u8,
        k: u32,
    }

    #[repr(C)]
    struct SockFprog {
        len: u16,
        filter: *const SockFilter,
    }

    const LD_W_ABS: u16 = 0x20;
    const JEQ_K: u16 = 0x15;
    #[cfg(target_arch = "x86_64")]
    const JGE_K: u16 = 0x35;
    const JSET_K: u16 = 0x45;
    const RET_K: u16 = 0x06;
    const RET_ALLOW: u32 = 0x7fff_0000;
    const RET_KILL_PROCESS: u32 = 0x8000_0000;
    const RET_ERRNO: u32 = 0x0005_0000;
    /// Offsets in `struct seccomp_data`: nr, arch, args[0] (low half).
    const NR: u32 = 0;
    const ARCH: u32 = 4;
    const ARG0: u32 = 16;

    #[cfg(target_arch = "x86_64")]
    const AUDIT_ARCH: u32 = 0xC000_003E;
    #[cfg(target_arch = "aarch64")]
    const AUDIT_ARCH: u32 = 0xC000_00B7;

    fn stmt(code: u16, k: u32) -> SockFilter {
        SockFilter {
            code,
            jt: 0,
            jf: 0,
            k,
        }
    }

    fn jump(code: u16, k: u32, jt: u8, jf: u8) -> SockFilter {
        SockFilter { code, jt, jf, k }
    }

    /// Calls newer than the C library's headers (the same number on every
    /// architecture since 5.1's common table).
    const FCHMODAT2: libc::c_long = 452;
    const SETXATTRAT: libc::c_long = 463;
    const REMOVEXATTRAT: libc::c_long = 466;
    const OPEN_TREE_ATTR: libc::c_long = 467;
    const FILE_SETATTR: libc::c_long = 469;

    /// The system calls refused outright.
    fn refused() -> Vec<libc::c_long> {
        let mut calls = vec![
            // Sockets (a pair needs no `socket`, and buffers kernel memory
            // no cap counts), IPC, io_uring.
            libc::SYS_socket,
            libc::SYS_socketpair,
            libc::SYS_io_uring_setup,
            // IPC, every call: objects others made are found by index,
            // with no `*get`.
            libc::SYS_shmget,
            libc::SYS_shmat,
            libc::SYS_shmctl,
            libc::SYS_msgget,
            libc::SYS_msgsnd,
            libc::SYS_msgrcv,
            libc::SYS_msgctl,
            libc::SYS_semget,
            libc::SYS_semop,
            libc::SYS_semtimedop,
            libc::SYS_semctl,
            libc::SYS_mq_open,
            libc::SYS_mq_unlink,
            libc::SYS_mq_timedsend,
            libc::SYS_mq_timedreceive,
            libc::SYS_mq_notify,
            libc::SYS_mq_getsetattr,
            // A file's metadata, which Landlock does not guard: any file
            // of the child's user (as a TA's own user, the lab itself)
            // could be made unreadable, world-writable or re-dated.
            libc::SYS_fchmod,
            libc::SYS_fchmodat,
            FCHMODAT2,
            libc::SYS_fchown,
            libc::SYS_fchownat,
            libc::SYS_utimensat,
            libc::SYS_setxattr,
            libc::SYS_lsetxattr,
            libc::SYS_fsetxattr,
            libc::SYS_removexattr,
            libc::SYS_lremovexattr,
            libc::SYS_fremovexattr,
            SETXATTRAT,
            REMOVEXATTRAT,
            // The inode flags (append-only off, no-dump...), by path.
            FILE_SETATTR,
            // Emptying, moving, linking, removing or making a file: Landlock
            // stops these, and without it so does the filter (`RLIMIT_FSIZE`
            // stops only growth). `openat2`'s flags are behind a pointer.
            libc::SYS_truncate,
            libc::SYS_unlinkat,
            libc::SYS_renameat2,
            libc::SYS_linkat,
            libc::SYS_symlinkat,
            libc::SYS_mkdirat,
            libc::SYS_mknodat,
            libc::SYS_openat2,
            // Other processes.
            libc::SYS_setpriority,
            libc::SYS_ioprio_set,
            libc::SYS_ptrace,
            libc::SYS_process_vm_readv,
            libc::SYS_process_vm_writev,
            libc::SYS_process_madvise,
            libc::SYS_process_mrelease,
            libc::SYS_kcmp,
            libc::SYS_pidfd_open,
            libc::SYS_pidfd_send_signal,
            libc::SYS_pidfd_getfd,
            libc::SYS_tkill,
            libc::SYS_migrate_pages,
            libc::SYS_move_pages,
            // Its session and process group.
            libc::SYS_setsid,
            libc::SYS_setpgid,
            // Namespaces, mounts, file handles, watches.
            libc::SYS_unshare,
            libc::SYS_setns,
            libc::SYS_mount,
            libc::SYS_umount2,
            libc::SYS_pivot_root,
            libc::SYS_chroot,
            libc::SYS_fsopen,
            libc::SYS_fsconfig,
            libc::SYS_fsmount,
            libc::SYS_fspick,
            libc::SYS_move_mount,
            libc::SYS_open_tree,
            OPEN_TREE_ATTR,
            libc::SYS_mount_setattr,
            libc::SYS_open_by_handle_at,
            libc::SYS_name_to_handle_at,
            libc::SYS_inotify_init1,
            libc::SYS_inotify_add_watch,
            libc::SYS_fanotify_init,
            libc::SYS_fanotify_mark,
            // Users and capabilities.
            libc::SYS_setuid,
            libc::SYS_setgid,
            libc::SYS_setreuid,
            libc::SYS_setregid,
            libc::SYS_setresuid,
            libc::SYS_setresgid,
            libc::SYS_setfsuid,
            libc::SYS_setfsgid,
            libc::SYS_setgroups,
            libc::SYS_capset,
            // Keyrings, BPF, performance counters, page faults by proxy.
            libc::SYS_add_key,
            libc::SYS_request_key,
            libc::SYS_keyctl,
            libc::SYS_bpf,
            libc::SYS_perf_event_open,
            libc::SYS_userfaultfd,
            // The whole system.
            libc::SYS_personality,
            libc::SYS_acct,
            libc::SYS_swapon,
            libc::SYS_swapoff,
            libc::SYS_reboot,
            libc::SYS_kexec_load,
            libc::SYS_kexec_file_load,
            libc::SYS_init_module,
            libc::SYS_finit_module,
            libc::SYS_delete_module,
            libc::SYS_sethostname,
            libc::SYS_setdomainname,
            libc::SYS_settimeofday,
            libc::SYS_clock_settime,
            libc::SYS_clock_adjtime,
            libc::SYS_adjtimex,
            libc::SYS_syslog,
            libc::SYS_quotactl,
            libc::SYS_quotactl_fd,
            libc::SYS_vhangup,
            libc::SYS_lookup_dcookie,
        ];
        // Calls only x86-64 has (AArch64 makes processes with clone alone).
        #[cfg(target_arch = "x86_64")]
        let arch_only = [
            libc::SYS_fork,
            libc::SYS_vfork,
            libc::SYS_chmod,
            libc::SYS_chown,
            libc::SYS_lchown,
            libc::SYS_utime,
            libc::SYS_utimes,
            libc::SYS_futimesat,
            libc::SYS_unlink,
            libc::SYS_rmdir,
            libc::SYS_rename,
            libc::SYS_renameat,
            libc::SYS_link,
            libc::SYS_symlink,
            libc::SYS_mkdir,
            libc::SYS_mknod,
            libc::SYS_creat,
            libc::SYS_inotify_init,
            libc::SYS_iopl,
            libc::SYS_ioperm,
            libc::SYS_uselib,
        ];
        #[cfg(target_arch = "aarch64")]
        let arch_only: [libc::c_long; 0] = [];
        calls.extend(arch_only);
        calls
    }

    /// The calls allowed only on this process: (call, whether pid 0, "the
    /// caller", counts as this process too). `kill(0)` is the process
    /// group, not the caller: refused.
    fn self_only() -> [(libc::c_long, bool); 9] {
        [
            (libc::SYS_prlimit64, true),
            (libc::SYS_sched_setaffinity, true),
            (libc::SYS_sched_setattr, true),
            (libc::SYS_sched_setscheduler, true),
            (libc::SYS_sched_setparam, true),
            (libc::SYS_kill, false),
            (libc::SYS_tgkill, false),
            (libc::SYS_rt_sigqueueinfo, false),
            (libc::SYS_rt_tgsigqueueinfo, false),
        ]
    }

    /// The `prctl` options allowed: those the Rust and C runtimes use
    /// (naming threads and memory mappings) and those that only read.
    const PRCTL_ALLOWED: [u32; 20] = [
        15,          // PR_SET_NAME (std names its threads)
        16,          // PR_GET_NAME
        0x5356_4d41, // PR_SET_VMA (glibc names its mappings)
        0x4155_5856, // PR_GET_AUXV
        2,           // PR_GET_PDEATHSIG
        3,           // PR_GET_DUMPABLE
        7,           // PR_GET_KEEPCAPS
        21,          // PR_GET_SECCOMP
        23,          // PR_CAPBSET_READ
        27,          // PR_GET_SECUREBITS
        30,          // PR_GET_TIMERSLACK
        34,          // PR_MCE_KILL_GET
        37,          // PR_GET_CHILD_SUBREAPER
        39,          // PR_GET_NO_NEW_PRIVS
        42,          // PR_GET_THP_DISABLE
        46,          // PR_GET_FP_MODE
        51,          // PR_SVE_GET_VL
        52,          // PR_GET_SPECULATION_CTRL
        56,          // PR_GET_TAGGED_ADDR_CTRL
        74,          // PR_GET_SHADOW_STACK_STATUS
    ];

    /// The `ioctl` requests refused, on any descriptor: typing into a
    /// terminal, the console, taking or steering a terminal, aiming SIGIO.
    const IOCTL_REFUSED: [u32; 9] = [
        libc::TIOCSTI as u32,
        libc::TIOCLINUX as u32,
        libc::TIOCSCTTY as u32,
        libc::TIOCSPGRP as u32,
        libc::TIOCSETD as u32,
        libc::TIOCCONS as u32,
        libc::TIOCSIG as u32,
        0x8901, // FIOSETOWN
        0x8902, // SIOCSPGRP
    ];

    /// The `fcntl` commands refused: `F_SETOWN` and `F_SETOWN_EX` aim
    /// `SIGIO` at any process.
    const FCNTL_REFUSED: [u32; 2] = [libc::F_SETOWN as u32, 15];

    /// Appends: if the call is `call`, its argument `arg` decides: EPERM
    /// if it is one of `values`, else allowed.
    fn refuse_values(p: &mut Vec<SockFilter>, call: libc::c_long, arg: u32, values: &[u32]) {
        let n = values.len() as u8;
        p.push(jump(JEQ_K, call as u32, 0, n + 3));
        p.push(stmt(LD_W_ABS, ARG0 + 8 * arg));
        for (i, &v) in values.iter().enumerate() {
            // Past the other values and the allow, onto the refusal.
            p.push(jump(JEQ_K, v, n - i as u8, 0));
        }
        p.push(stmt(RET_K, RET_ALLOW));
        p.push(stmt(RET_K, RET_ERRNO | libc::EPERM as u32));
    }

    /// The `open` flags refused: writing, creating, truncating. The child
    /// opens files only to read (the loader, `/proc/self`); its
    /// descriptors for writing were opened before the filter.
    const OPEN_WRITE: u32 = (libc::O_ACCMODE | libc::O_CREAT | libc::O_TRUNC) as u32;

    /// Appends: if the call is `call`, EPERM when its argument `arg` has
    /// any bit of `mask`, else allowed.
    fn refuse_flags(p: &mut Vec<SockFilter>, call: libc::c_long, arg: u32, mask: u32) {
        p.push(jump(JEQ_K, call as u32, 0, 4));
        p.push(stmt(LD_W_ABS, ARG0 + 8 * arg));
        p.push(jump(JSET_K, mask, 0, 1));
        p.push(stmt(RET_K, RET_ERRNO | libc::EPERM as u32));
        p.push(stmt(RET_K, RET_ALLOW));
    }

    fn program(own_pid: u32) -> Vec<SockFilter> {
        let errno = |e: i32| RET_ERRNO | e as u32;
        let mut p = vec![
            stmt(LD_W_ABS, ARCH),
            jump(JEQ_K, AUDIT_ARCH, 1, 0),
            stmt(RET_K, RET_KILL_PROCESS),
            stmt(LD_W_ABS, NR),
        ];
        // x32 system calls share the x86-64 architecture value.
        #[cfg(target_arch = "x86_64")]
        {
            p.push(jump(JGE_K, 0x4000_0000, 0, 1));
            p.push(stmt(RET_K, RET_KILL_PROCESS));
        }
        for call in refused() {
            p.push(jump(JEQ_K, call as u32, 0, 1));
            p.push(stmt(RET_K, errno(libc::EPERM)));
        }
        // clone3: its flags are behind a pointer; ENOSYS makes the C library
        // use clone instead.
        p.push(jump(JEQ_K, libc::SYS_clone3 as u32, 0, 1));
        p.push(stmt(RET_K, errno(libc::ENOSYS)));
        // clone: only with CLONE_THREAD (a thread, not a process).
        p.push(jump(JEQ_K, libc::SYS_clone as u32, 0, 4));
        p.push(stmt(LD_W_ABS, ARG0));
        p.push(jump(JSET_K, libc::CLONE_THREAD as u32, 1, 0));
        p.push(stmt(RET_K, errno(libc::EPERM)));
        p.push(stmt(RET_K, RET_ALLOW));
        // Only on this process. (The kernel reads a pid as 32 bits: the low
        // half of the argument is all there is to check.)
        for (call, zero_is_self) in self_only() {
            p.push(jump(JEQ_K, call as u32, 0, 4 + u8::from(zero_is_self)));
            p.push(stmt(LD_W_ABS, ARG0));
            if zero_is_self {
                p.push(jump(JEQ_K, 0, 2, 0));
            }
            p.push(jump(JEQ_K, own_pid, 1, 0));
            p.push(stmt(RET_K, errno(libc::EPERM)));
            p.push(stmt(RET_K, RET_ALLOW));
        }
        // prctl: the allow-list.
        let n = PRCTL_ALLOWED.len() as u8;
        p.push(jump(JEQ_K, libc::SYS_prctl as u32, 0, n + 3));
        p.push(stmt(LD_W_ABS, ARG0));
        for (i, &option) in PRCTL_ALLOWED.iter().enumerate() {
            // Past the other options and the refusal, onto the allow.
            p.push(jump(JEQ_K, option, n - i as u8, 0));
        }
        p.push(stmt(RET_K, errno(libc::EPERM)));
        p.push(stmt(RET_K, RET_ALLOW));
        refuse_values(&mut p, libc::SYS_ioctl, 1, &IOCTL_REFUSED);
        refuse_values(&mut p, libc::SYS_fcntl, 1, &FCNTL_REFUSED);
        refuse_flags(&mut p, libc::SYS_openat, 2, OPEN_WRITE);
        #[cfg(target_arch = "x86_64")]
        refuse_flags(&mut p, libc::SYS_open, 1, OPEN_WRITE);
        p.push(stmt(RET_K, RET_ALLOW));
        p
    }

    /// Applies the filter to this thread and all it `exec`s or starts.
    pub fn apply() -> Result<(), String> {
        // SAFETY: a plain system call. The pid stays the same across exec.
        let program = program(unsafe { libc::getpid() } as u32);
        let fprog = SockFprog {
            len: program.len() as u16,
            filter: program.as_ptr(),
        };
        // SAFETY: plain prctl calls; `fprog` and `program` outlive them.
        unsafe {
            if libc::prctl(libc::PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0 {
                return Err(format!("no_new_privs: {}", std::io::Error::last_os_error()));
            }
            if libc::prctl(
                libc::PR_SET_SECCOMP,
                libc::SECCOMP_MODE_FILTER,
                &fprog as *const SockFprog,
            ) != 0
            {
                return Err(format!("seccomp: {}", std::io::Error::last_os_error()));
            }
        }
        Ok(())
    }

    /// The filter run on made-up calls by a small BPF interpreter: every
    /// jump lands inside the program and each call gets its verdict, on
    /// whichever architecture the tests run.
    #[cfg(test)]
    mod tests {
        use super::*;

        const OWN: u32 = 4242;

        /// The verdict for (nr, args) on this architecture.
        fn verdict(nr: libc::c_long, args: [u64; 3]) -> u32 {
            let program = program(OWN);
            let word = |k: u32| -> u32 {
                match k {
                    NR => nr as u32,
                    ARCH => AUDIT_ARCH,
                    k if k >= ARG0 && (k - ARG0) % 8 == 0 => args[((k - ARG0) / 8) as usize] as u32,
                    k if k >= ARG0 => (args[((k - ARG0) / 8) as usize] >> 32) as u32,
                    _ => panic!("load of offset {k}"),
                }
            };
            let (mut pc, mut acc) = (0usize, 0u32);
            loop {
                let i = program.get(pc).expect("a jump past the end");
                pc += 1;
                let taken = |t: bool| if t { i.jt as usize } else { i.jf as usize };
                match i.code {
                    LD_W_ABS => acc = word(i.k),
                    JEQ_K => pc += taken(acc == i.k),
                    JSET_K => pc += taken(acc & i.k != 0),
                    0x35 => pc += taken(acc >= i.k),
                    RET_K => return i.k,
                    c => panic!("unknown instruction {c:#x}"),
                }
            }
        }

        /// An ioctl request as a call argument (its type differs by C library).
        #[allow(clippy::unnecessary_cast)]
        fn request(r: libc::Ioctl) -> u64 {
            r as u64
        }

        fn allowed(nr: libc::c_long, args: [u64; 3]) -> bool {
            let v = verdict(nr, args);
            assert!(
                v == RET_ALLOW || v == RET_ERRNO | libc::EPERM as u32,
                "{v:#x}"
            );
            v == RET_ALLOW
        }

        #[test]
        fn each_call_gets_its_verdict() {
            let own = u64::from(OWN);
            let other = 1u64;
            // What the runtime needs.
            assert!(allowed(libc::SYS_read, [0, 0, 0]));
            assert!(allowed(libc::SYS_prctl, [libc::PR_SET_NAME as u64, 0, 0]));
            assert!(allowed(libc::SYS_prctl, [0x5356_4d41, 0, 0]));
            assert!(allowed(
                libc::SYS_clone,
                [libc::CLONE_THREAD as u64 | 0x3d0f00, 0, 0]
            ));
            assert!(allowed(libc::SYS_tgkill, [own, 7, libc::SIGABRT as u64]));
            assert!(allowed(libc::SYS_kill, [own, libc::SIGABRT as u64, 0]));
            assert!(allowed(libc::SYS_ioctl, [1, request(libc::TCGETS), 0]));
            assert!(allowed(libc::SYS_fcntl, [3, libc::F_GETFD as u64, 0]));
            let read_only = (libc::O_RDONLY | libc::O_CLOEXEC | libc::O_DIRECTORY) as u64;
            assert!(allowed(libc::SYS_openat, [0, 0, read_only]));
            for flags in [libc::O_WRONLY, libc::O_RDWR, libc::O_CREAT, libc::O_TRUNC] {
                let flags = flags as u64 | libc::O_CLOEXEC as u64;
                assert!(!allowed(libc::SYS_openat, [0, 0, flags]), "{flags:#x}");
            }
            for call in [
                libc::SYS_sched_setaffinity,
                libc::SYS_sched_setattr,
                libc::SYS_prlimit64,
            ] {
                assert!(allowed(call, [0, 0, 0]));
                assert!(allowed(call, [own, 0, 0]));
                assert!(!allowed(call, [other, 0, 0]));
            }
            // What undoes a protection or reaches out.
            for option in [
                libc::PR_SET_PDEATHSIG,
                libc::PR_SET_DUMPABLE,
                libc::PR_SET_CHILD_SUBREAPER,
            ] {
                assert!(!allowed(libc::SYS_prctl, [option as u64, 0, 0]));
            }
            assert!(!allowed(libc::SYS_clone, [libc::SIGCHLD as u64, 0, 0]));
            assert!(verdict(libc::SYS_clone3, [0, 0, 0]) == RET_ERRNO | libc::ENOSYS as u32);
            assert!(!allowed(libc::SYS_kill, [other, 9, 0]));
            assert!(!allowed(libc::SYS_kill, [0, 9, 0]));
            assert!(!allowed(libc::SYS_kill, [u64::from(u32::MAX), 9, 0]));
            assert!(!allowed(libc::SYS_tgkill, [other, 1, 9]));
            assert!(!allowed(libc::SYS_ioctl, [0, request(libc::TIOCSTI), 0]));
            assert!(!allowed(libc::SYS_ioctl, [0, request(libc::TIOCLINUX), 0]));
            assert!(!allowed(libc::SYS_fcntl, [3, libc::F_SETOWN as u64, 0]));
            for call in [
                libc::SYS_inotify_init1,
                libc::SYS_fanotify_init,
                libc::SYS_perf_event_open,
                libc::SYS_setsid,
                libc::SYS_pidfd_open,
                libc::SYS_socket,
                libc::SYS_socketpair,
                libc::SYS_msgsnd,
                libc::SYS_shmat,
                libc::SYS_fchmodat,
                libc::SYS_fchownat,
                libc::SYS_utimensat,
                libc::SYS_setxattr,
                FCHMODAT2,
                FILE_SETATTR,
                libc::SYS_unlinkat,
                libc::SYS_renameat2,
                libc::SYS_truncate,
            ] {
                assert!(!allowed(call, [0, 0, 0]), "{call}");
            }
        }
    }
}

/// Applies the filter (see the module docs). `Ok(false)` where this build
/// has none.
pub fn apply() -> Result<bool, String> {
    #[cfg(all(
        target_os = "linux",
        any(target_arch = "x86_64", target_arch = "aarch64")
    ))]
    {
        filter::apply()?;
        Ok(true)
    }
    #[cfg(not(all(
        target_os = "linux",
        any(target_arch = "x86_64", target_arch = "aarch64")
    )))]
    {
        Ok(false)
    }
}
