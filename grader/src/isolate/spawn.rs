//! Starting the launcher in a session of its own without copying the
//! grader (the OS layer under [`runner`](super::runner)).
//!
//! ```text
//!   grader (every fixture in memory)
//!     | posix_spawn, POSIX_SPAWN_SETSID: no page tables copied
//!     v
//!   launcher, session and group leader before its first instruction
//!     | locks itself in, then exec
//!     v
//!   child (the student's code)
//! ```
//!
//! `fork` with `setsid` in `pre_exec` copied the grader's page tables once
//! per case, only for `exec` to throw them away: a fifth of a warm grade.
//! glibc's `posix_spawn` clones with the memory shared (the parent waits
//! until the exec), and `POSIX_SPAWN_SETSID` makes the new session in the
//! new process before the exec, as the `pre_exec` did: a kill of the
//! launcher's group can never miss it, and it never holds the grader's
//! terminal. Where that flag is refused (a C library older than glibc
//! 2.26), [`start`] says so and the runner forks as before.

use std::ffi::{CString, OsStr, OsString};
use std::fs::File;
use std::os::fd::{FromRawFd, OwnedFd};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::ExitStatus;

/// A started launcher: its pid (also its session and group) and the
/// grader's ends of its three pipes.
pub struct Spawned {
    pub pid: u32,
    pub stdin: File,
    pub stdout: File,
    pub stderr: File,
}

/// How a start failed.
#[derive(Debug)]
pub enum SpawnError {
    /// This C library has no `POSIX_SPAWN_SETSID`: start it another way.
    NoSessionFlag,
    Io(std::io::Error),
}

impl From<std::io::Error> for SpawnError {
    fn from(e: std::io::Error) -> Self {
        SpawnError::Io(e)
    }
}

fn c_string(s: &OsStr) -> std::io::Result<CString> {
    CString::new(s.as_bytes()).map_err(|_| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{} holds a NUL byte", s.to_string_lossy()),
        )
    })
}

/// A pipe whose two ends are close-on-exec and numbered 3 or more, so
/// that putting one on 0, 1 or 2 in the new process is always a real
/// `dup2` (which clears close-on-exec), even if the grader's own standard
/// streams are closed.
fn pipe() -> std::io::Result<(OwnedFd, OwnedFd)> {
    let mut fds = [0; 2];
    // SAFETY: pipe2 writes two descriptors into `fds`.
    if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) } < 0 {
        return Err(std::io::Error::last_os_error());
    }
    // SAFETY: both are open descriptors this function now owns.
    let (r, w) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
    Ok((above_stdio(r)?, above_stdio(w)?))
}

fn above_stdio(fd: OwnedFd) -> std::io::Result<OwnedFd> {
    use std::os::fd::AsRawFd;
    if fd.as_raw_fd() > 2 {
        return Ok(fd);
    }
    // SAFETY: duplicates an open descriptor; the copy is owned here.
    let copy = unsafe { libc::fcntl(fd.as_raw_fd(), libc::F_DUPFD_CLOEXEC, 3) };
    if copy < 0 {
        return Err(std::io::Error::last_os_error());
    }
    // SAFETY: `copy` was just opened.
    Ok(unsafe { OwnedFd::from_raw_fd(copy) })
}

/// Fails with the error code a posix_spawn function returned.
fn check(code: libc::c_int) -> std::io::Result<()> {
    if code == 0 {
        Ok(())
    } else {
        Err(std::io::Error::from_raw_os_error(code))
    }
}

/// The attributes and file actions, destroyed however the start ends.
struct Setup {
    attr: libc::posix_spawnattr_t,
    actions: libc::posix_spawn_file_actions_t,
}

impl Drop for Setup {
    fn drop(&mut self) {
        // SAFETY: both were initialised in `start` before a Setup existed.
        unsafe {
            libc::posix_spawnattr_destroy(&mut self.attr);
            libc::posix_spawn_file_actions_destroy(&mut self.actions);
        }
    }
}

/// Starts `program` with `args` and exactly `env`, in a new session, its
/// standard streams piped to the grader; signals unblocked and SIGPIPE
/// back to its default, as `std::process::Command` leaves them.
pub fn start(
    program: &Path,
    args: &[OsString],
    env: &[(OsString, OsString)],
) -> Result<Spawned, SpawnError> {
    use std::os::fd::{AsRawFd, IntoRawFd};
    let path = c_string(program.as_os_str())?;
    let argv_owned: Vec<CString> = std::iter::once(Ok(path.clone()))
        .chain(args.iter().map(|a| c_string(a)))
        .collect::<std::io::Result<_>>()?;
    let envp_owned: Vec<CString> = env
        .iter()
        .map(|(k, v)| {
            let mut pair = k.clone();
            pair.push("=");
            pair.push(v);
            c_string(&pair)
        })
        .collect::<std::io::Result<_>>()?;
    let mut argv: Vec<*mut libc::c_char> =
        argv_owned.iter().map(|s| s.as_ptr().cast_mut()).collect();
    argv.push(std::ptr::null_mut());
    let mut envp: Vec<*mut libc::c_char> =
        envp_owned.iter().map(|s| s.as_ptr().cast_mut()).collect();
    envp.push(std::ptr::null_mut());

    let (in_read, in_write) = pipe()?;
    let (out_read, out_write) = pipe()?;
    let (err_read, err_write) = pipe()?;

    // SAFETY: zeroed is a valid bit pattern for these plain C structs
    // before their init functions fill them.
    let mut setup: Setup = unsafe { std::mem::zeroed() };
    // SAFETY: initialising the structs `setup` holds; until both are,
    // Setup's drop must not run (it destroys both).
    unsafe {
        if let Err(e) = check(libc::posix_spawnattr_init(&mut setup.attr)) {
            std::mem::forget(setup);
            return Err(e.into());
        }
        if let Err(e) = check(libc::posix_spawn_file_actions_init(&mut setup.actions)) {
            libc::posix_spawnattr_destroy(&mut setup.attr);
            std::mem::forget(setup);
            return Err(e.into());
        }
    }
    // SAFETY: the calls below only fill the initialised structs; the
    // descriptors named stay open until posix_spawn has returned.
    unsafe {
        let mut none: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut none);
        let mut pipe_only: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut pipe_only);
        libc::sigaddset(&mut pipe_only, libc::SIGPIPE);
        check(libc::posix_spawnattr_setsigmask(&mut setup.attr, &none))?;
        check(libc::posix_spawnattr_setsigdefault(
            &mut setup.attr,
            &pipe_only,
        ))?;
        // libc declares these with two different integer types.
        let flags = libc::POSIX_SPAWN_SETSID
            | libc::POSIX_SPAWN_SETSIGMASK as libc::c_short
            | libc::POSIX_SPAWN_SETSIGDEF as libc::c_short;
        if libc::posix_spawnattr_setflags(&mut setup.attr, flags) == libc::EINVAL {
            return Err(SpawnError::NoSessionFlag);
        }
        for (fd, target) in [
            (in_read.as_raw_fd(), 0),
            (out_write.as_raw_fd(), 1),
            (err_write.as_raw_fd(), 2),
        ] {
            check(libc::posix_spawn_file_actions_adddup2(
                &mut setup.actions,
                fd,
                target,
            ))?;
        }
    }
    let mut pid: libc::pid_t = 0;
    // SAFETY: every pointer is valid until the call returns: the paths and
    // arrays above (NULL-terminated), and the initialised attributes.
    let code = unsafe {
        libc::posix_spawn(
            &mut pid,
            path.as_ptr(),
            &setup.actions,
            &setup.attr,
            argv.as_ptr(),
            envp.as_ptr(),
        )
    };
    drop(setup);
    check(code)?;
    // The new process holds its ends now; the grader keeps only its own.
    drop((in_read, out_write, err_write));
    // SAFETY: each descriptor is owned and handed over once.
    Ok(unsafe {
        Spawned {
            pid: pid as u32,
            stdin: File::from_raw_fd(in_write.into_raw_fd()),
            stdout: File::from_raw_fd(out_read.into_raw_fd()),
            stderr: File::from_raw_fd(err_read.into_raw_fd()),
        }
    })
}

/// Waits for `pid` to end and reaps it.
pub fn wait(pid: u32) -> std::io::Result<ExitStatus> {
    let mut status = 0;
    loop {
        // SAFETY: waitpid writes one int.
        let r = unsafe { libc::waitpid(pid as libc::pid_t, &mut status, 0) };
        if r >= 0 {
            return Ok(ExitStatus::from_raw(status));
        }
        let e = std::io::Error::last_os_error();
        if e.kind() != std::io::ErrorKind::Interrupted {
            return Err(e);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Read, Write};

    /// The new process leads its own session and group, gets exactly the
    /// environment given, and its three streams are the pipes.
    #[test]
    fn the_started_process_leads_a_session_of_its_own() {
        // Shell built-ins only: /proc/PID/stat's fields 5 and 6 are the
        // process group and the session.
        let script = "read -r line; read -r stat < /proc/$$/stat; set -- $stat; \
                      echo \"$line $A $5 $6 ${HOME-none} ${CARGO-none}\"; echo err >&2";
        let started = start(
            Path::new("/bin/sh"),
            &["-c".into(), script.into()],
            &[
                ("A".into(), "b".into()),
                ("PATH".into(), "/usr/bin:/bin".into()),
            ],
        );
        let mut s = match started {
            Ok(s) => s,
            Err(SpawnError::NoSessionFlag) => {
                assert!(
                    std::env::var_os("CI").is_none(),
                    "CI: this C library has no POSIX_SPAWN_SETSID"
                );
                eprintln!("skipped: this C library has no POSIX_SPAWN_SETSID");
                return;
            }
            Err(SpawnError::Io(e)) => panic!("cannot start /bin/sh: {e}"),
        };
        s.stdin.write_all(b"hello\n").unwrap();
        drop(s.stdin);
        let mut out = String::new();
        s.stdout.read_to_string(&mut out).unwrap();
        let mut err = String::new();
        s.stderr.read_to_string(&mut err).unwrap();
        assert!(wait(s.pid).unwrap().success());
        let pid = s.pid.to_string();
        // Nothing of the caller's environment (cargo sets CARGO for tests).
        assert_eq!(
            out.split_whitespace().collect::<Vec<_>>(),
            ["hello", "b", pid.as_str(), pid.as_str(), "none", "none"],
            "{out}"
        );
        assert_eq!(err, "err\n");
    }

    #[test]
    fn a_missing_program_is_an_error_not_a_process() {
        match start(Path::new("/nonexistent/launcher"), &[], &[]) {
            Err(SpawnError::Io(e)) => assert_eq!(e.kind(), std::io::ErrorKind::NotFound),
            Err(SpawnError::NoSessionFlag) => {}
            Ok(s) => panic!("started pid {}", s.pid),
        }
    }
}
