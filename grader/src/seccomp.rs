//! A seccomp filter for the case's child: the system calls Landlock does not
//! cover and no lab function needs are refused (`EPERM`).
//!
//! - New processes (`fork`, `vfork`, `clone` without `CLONE_THREAD`):
//!   threads stay allowed; a process can neither outlive the case, nor
//!   hold the grader's pipes, nor multiply the memory cap.
//! - Sockets of any kind (UDP, Unix sockets by path: Landlock covers only TCP
//!   and abstract sockets) and `io_uring` (which can make sockets without a
//!   system call of its own).
//! - System V and POSIX IPC (shared memory outlives the process and the cap).
//! - Changing another process's priority or limits (`setpriority`,
//!   `prlimit64` on a pid other than 0), `ptrace`, namespaces, keyrings,
//!   `bpf`, `perf_event_open`, `userfaultfd`.
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

    /// The system calls refused outright.
    fn refused() -> Vec<libc::c_long> {
        let mut calls = vec![
            libc::SYS_socket,
            libc::SYS_io_uring_setup,
            libc::SYS_shmget,
            libc::SYS_msgget,
            libc::SYS_semget,
            libc::SYS_mq_open,
            libc::SYS_setpriority,
            libc::SYS_ptrace,
            libc::SYS_process_vm_readv,
            libc::SYS_process_vm_writev,
            libc::SYS_unshare,
            libc::SYS_setns,
            libc::SYS_add_key,
            libc::SYS_request_key,
            libc::SYS_keyctl,
            libc::SYS_bpf,
            libc::SYS_perf_event_open,
            libc::SYS_userfaultfd,
        ];
        #[cfg(target_arch = "x86_64")]
        calls.extend([libc::SYS_fork, libc::SYS_vfork]);
        calls
    }

    fn program() -> Vec<SockFilter> {
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
        // prlimit64: only on this process (pid 0).
        p.push(jump(JEQ_K, libc::SYS_prlimit64 as u32, 0, 3));
        p.push(stmt(LD_W_ABS, ARG0));
        p.push(jump(JEQ_K, 0, 1, 0));
        p.push(stmt(RET_K, errno(libc::EPERM)));
        p.push(stmt(RET_K, RET_ALLOW));
        p
    }

    /// Applies the filter to this thread and all it `exec`s or starts.
    pub fn apply() -> Result<(), String> {
        let program = program();
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
