//! The parent side of a case: starts the sandboxed child (see
//! [`crate::isolate::sandbox`]), sends it the requests of a case one by one
//! ([`Session`]), enforces each call's time limit from the moment the
//! student's function is called, says how it ended ([`CaseEnd`]), and kills
//! everything the child started.
//!
//! Three pipes: the requests go in on the launcher's stdin (the child
//! reads it on [`crate::isolate::wire::REQUEST_FD`], its stdin is `/dev/null`);
//! frames come back on its stdout (see [`crate::isolate::wire`]); whatever the
//! student's code prints (stdout and stderr both) arrives on its stderr.
//! No pipe is waited on past the deadline: the launcher starts in a
//! session and process group of its own, which is killed at the deadline,
//! after a call that did not come back, and after every case; where the launcher could make a PID namespace,
//! the case ends with it and nothing is swept; elsewhere the grader is a
//! "child subreaper", so a process that left the group becomes the
//! grader's child when its parent dies and is found and killed too.
//! Before its first case the grader makes itself non-dumpable
//! ([`guard_grader`]); a root grader runs a child program `nobody` may not
//! execute from a private copy.

use std::ffi::OsString;
use std::io::{Read, Write};
use std::path::PathBuf;
use std::process::{Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};
use std::thread;
use std::time::{Duration, Instant};

use crate::isolate::protections::Protections;
use crate::isolate::sandbox::{self, Limits};
use halfedge::Mesh;

use crate::isolate::end::CaseEnd;
use crate::isolate::wire::{self, Frame, Ran, Recorded, Request};

/// The most of the student's output kept for the report.
const OUTPUT_CAP: usize = 8 * 1024;

/// How long the child may take to be ready to call the student's function
/// (start, decode the request, build the mesh: milliseconds for any lab
/// mesh), beyond the time limit itself.
const SETUP_GRACE: Duration = Duration::from_secs(2);

/// How long to wait for pipes to close once the child is dead.
const CLOSE_GRACE: Duration = Duration::from_millis(500);

/// How long ending a child waits for it to be reaped after SIGKILL.
const END_GRACE: Duration = Duration::from_secs(2);

/// How to start the child program (the one linked with the functions
/// being graded). The launcher (this program) starts it.
#[derive(Clone, Debug)]
pub struct ChildProgram {
    pub exe: PathBuf,
    pub args: Vec<OsString>,
}

/// A finished child, as the runner saw it: how the case ended and what
/// the student's code printed, with what the reports keep beside them.
#[derive(Clone, Debug)]
pub struct ChildReport {
    pub end: CaseEnd,
    /// What the student's code printed, cut at 8 KiB.
    pub output: String,
    /// The launcher's description of the protections in force.
    pub sandbox: Option<Protections>,
    /// The CPU time of the call, from the request sent to the result read
    /// (the child decoding the request, building the mesh, the call and
    /// sending the result back), read by the grader from the kernel's
    /// accounting of the child process: only in a timed session
    /// ([`Session::timed`]), none when the call did not finish or the child
    /// could not be found. Never a clock of the child's own: a student's
    /// `clock_gettime` replaces libc's in the child.
    pub cpu: Option<Duration>,
    /// The mesh the function left, when it came back with one (a return
    /// or a sequence), as it was sent back.
    pub mesh: Option<Mesh>,
    /// A subdivision's recording, when the request asked for one.
    pub recorded: Option<Recorded>,
}

impl ChildReport {
    /// A report of an end with nothing else to say (no output, no mesh).
    pub fn bare(end: CaseEnd) -> ChildReport {
        ChildReport {
            end,
            output: String::new(),
            sandbox: None,
            cpu: None,
            mesh: None,
            recorded: None,
        }
    }
}

/// What the threads watching a child tell the loop waiting on a call.
enum Event {
    /// The launcher's report of the protections in force.
    Sandbox(Protections),
    /// The child program waits for its first request.
    Ready,
    /// A call started: its clock starts.
    Started,
    /// A call's whole result frame.
    Result(Vec<u8>),
    /// The launcher could not start the child program (with the nonce it
    /// was given, if the frame is its own).
    LaunchFailed {
        nonce: [u8; wire::NONCE_LEN],
        why: String,
    },
    /// A result frame announced this many bytes, more than allowed.
    TooLarge(usize),
    /// The channel held something that is not a frame.
    Garbled(String),
    /// The frames' pipe closed.
    StreamEnd,
    Exited(ExitStatus),
}

/// Becomes a child subreaper: orphans of our children are reparented to
/// us, so [`kill_descendants`] can find them. Idempotent.
pub fn become_subreaper() {
    // SAFETY: a plain prctl call. (Linux only: elsewhere the process group
    // kill is the only sweep.)
    #[cfg(target_os = "linux")]
    unsafe {
        libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0);
    }
}

/// Whether the grader made itself non-dumpable (see [`guard_grader`]).
static NOT_DUMPABLE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Protects the grading process before its first case, whichever program
/// grades: a subreaper (for the sweep), and not dumpable, so that no
/// process of its user opens its `/proc/PID/mem` (its heap holds every
/// expected answer) or attaches to it, with or without Landlock. Idempotent.
pub fn guard_grader() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        become_subreaper();
        // SAFETY: plain prctl calls.
        #[cfg(target_os = "linux")]
        unsafe {
            if libc::prctl(libc::PR_SET_DUMPABLE, 0, 0, 0, 0) == 0
                && libc::prctl(libc::PR_GET_DUMPABLE, 0, 0, 0, 0) == 0
            {
                NOT_DUMPABLE.store(true, std::sync::atomic::Ordering::Relaxed);
            }
        }
    });
}

/// Whether [`guard_grader`] made this process non-dumpable.
pub fn grader_not_dumpable() -> bool {
    NOT_DUMPABLE.load(std::sync::atomic::Ordering::Relaxed)
}

/// Private copies of child programs `nobody` may not run (see
/// [`runnable_program`]): (the program, its copy's folder, the copy).
static COPIES: std::sync::Mutex<Vec<(PathBuf, PathBuf, PathBuf)>> =
    std::sync::Mutex::new(Vec::new());

/// Removes the private copies when the grader exits.
extern "C" fn remove_copies() {
    let copies = COPIES.lock().unwrap_or_else(|e| e.into_inner());
    for (_, dir, _) in copies.iter() {
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// The program to start for a case: `exe` itself, unless the grader is
/// root and `nobody` may not execute it (a build made with umask 077):
/// then a copy that `nobody` may execute, in a folder only root can enter
/// (the launcher opens it as root and runs it by descriptor), made once
/// and removed when the grader exits. Student code never runs as root: if
/// no copy can be made, grading stops with why.
fn runnable_program(exe: &std::path::Path, limits: &Limits) -> Result<PathBuf, String> {
    // SAFETY: geteuid only reads.
    let root = unsafe { libc::geteuid() } == 0;
    if !root || !limits.drop_user || crate::isolate::sys::runnable_by_others(exe) {
        return Ok(exe.to_path_buf());
    }
    let mut copies = COPIES.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, _, copy)) = copies.iter().find(|(p, _, _)| p == exe) {
        return Ok(copy.clone());
    }
    let fail = |e: &dyn std::fmt::Display| {
        format!(
            "the child program {} may not be run by user nobody, and no copy that may \
             could be made in {} ({e}); student code never runs as root: make the \
             program executable by others (chmod o+x) or grade as another user",
            exe.display(),
            std::env::temp_dir().display()
        )
    };
    use std::os::unix::fs::{DirBuilderExt, PermissionsExt};
    let stamp = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let dir = std::env::temp_dir().join(format!("meshlab-child-{}-{stamp:x}", std::process::id()));
    std::fs::DirBuilder::new()
        .mode(0o700)
        .create(&dir)
        .map_err(|e| fail(&e))?;
    let name = exe.file_name().unwrap_or(std::ffi::OsStr::new("child"));
    let copy = dir.join(name);
    let made = std::fs::copy(exe, &copy)
        .and_then(|_| std::fs::set_permissions(&copy, std::fs::Permissions::from_mode(0o755)));
    if let Err(e) = made {
        let _ = std::fs::remove_dir_all(&dir);
        return Err(fail(&e));
    }
    if copies.is_empty() {
        // SAFETY: registers a plain function, once.
        unsafe { libc::atexit(remove_copies) };
    }
    copies.push((exe.to_path_buf(), dir, copy.clone()));
    Ok(copy)
}

/// The ids of the processes whose parent is `parent`, from /proc (none
/// where there is no /proc).
fn children_of(parent: u32) -> Vec<u32> {
    let Ok(dir) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    dir.filter_map(|e| e.ok()?.file_name().to_str()?.parse::<u32>().ok())
        .filter(|&pid| {
            let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
                return false;
            };
            // "pid (comm) state ppid ...": comm may hold spaces and parens.
            let after = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
            after.split_whitespace().nth(1) == Some(&parent.to_string())
        })
        .collect()
}

/// The children of cases still running (cases may run side by side): the
/// sweep leaves them alone. Spawning holds the lock too, so a sweep never
/// sees a child before it is listed.
static ACTIVE: std::sync::Mutex<Vec<u32>> = std::sync::Mutex::new(Vec::new());

fn active() -> std::sync::MutexGuard<'static, Vec<u32>> {
    ACTIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Kills every process this process is the parent of (orphans reparented
/// to us by the subreaper flag) but the children of running cases, and
/// reaps them, until none is left.
pub fn kill_descendants() {
    let me = std::process::id();
    let running = active();
    for _ in 0..200 {
        let found: Vec<u32> = children_of(me)
            .into_iter()
            .filter(|p| !running.contains(p))
            .collect();
        if found.is_empty() {
            return;
        }
        for pid in found {
            // SAFETY: plain system calls on a pid that is our child.
            unsafe {
                libc::kill(pid as i32, libc::SIGKILL);
                libc::waitpid(pid as i32, std::ptr::null_mut(), 0);
            }
        }
    }
}

/// [`kill_descendants`], unless the launcher reported a PID namespace:
/// then every process of the case lives in it (an orphan there goes to its
/// init, never to the grader) and dies with it, and the sweep, a walk of
/// all `/proc`, would find nothing.
fn sweep_unless_contained(launched: &Option<Protections>) {
    let contained = launched.is_some_and(|p| p.pid_namespace);
    if !contained {
        kill_descendants();
    }
}

/// Kills process group `pgid` (SIGKILL): the one way the lab kills a
/// group. Ids 0 and 1 are refused, since `kill(0)` would signal our own
/// group and `kill(-1)` every process we may signal.
pub fn kill_group(pgid: u32) {
    if let Ok(pgid) = libc::pid_t::try_from(pgid) {
        if pgid > 1 {
            // SAFETY: kill only sends a signal; a negative pid names a group.
            unsafe { libc::kill(-pgid, libc::SIGKILL) };
        }
    }
}

/// Reads the frames as they come, telling the waiting loop of each as it
/// is whole: the launcher's report, each call's start, CPU time and
/// result. A result announced larger than `cap` is refused unread; a
/// stream that holds something other than frames is said once, and the
/// rest drained so the child never blocks on a full pipe.
fn watch_frames(
    mut stream: impl Read + Send + 'static,
    cap: Arc<AtomicUsize>,
    tx: mpsc::Sender<Event>,
) {
    thread::spawn(move || {
        let mut bytes: Vec<u8> = Vec::new();
        let mut buf = vec![0u8; 64 * 1024];
        let mut broken = false;
        while let Ok(n) = stream.read(&mut buf) {
            if n == 0 {
                break;
            }
            if broken {
                continue;
            }
            bytes.extend_from_slice(&buf[..n]);
            loop {
                match wire::frame_at(&bytes) {
                    Ok(wire::Pending::Whole(len)) => {
                        let frame: Vec<u8> = bytes.drain(..len).collect();
                        let event = match frame[0] {
                            wire::SANDBOX_TAG => match wire::decode_frames(&frame) {
                                Ok(mut f) => match f.pop() {
                                    Some(Frame::Sandbox(s)) => Event::Sandbox(s),
                                    _ => Event::Garbled("no launcher report".into()),
                                },
                                Err(e) => Event::Garbled(e.to_string()),
                            },
                            wire::STARTED_TAG => Event::Started,
                            wire::READY_TAG => Event::Ready,
                            wire::RESULT_TAG => {
                                if len > cap.load(Ordering::Relaxed) {
                                    Event::TooLarge(len)
                                } else {
                                    Event::Result(frame)
                                }
                            }
                            _ => match wire::decode_frames(&frame) {
                                Ok(mut f) => match f.pop() {
                                    Some(Frame::LaunchFailed { nonce, why }) => {
                                        Event::LaunchFailed { nonce, why }
                                    }
                                    _ => Event::Garbled("an unexpected frame".into()),
                                },
                                Err(e) => Event::Garbled(e.to_string()),
                            },
                        };
                        broken = matches!(event, Event::Garbled(_) | Event::TooLarge(_));
                        let _ = tx.send(event);
                        if broken {
                            bytes = Vec::new();
                            break;
                        }
                    }
                    Ok(wire::Pending::Partial(Some(total)))
                        if total > cap.load(Ordering::Relaxed) =>
                    {
                        // Refused before it is read: no memory for it.
                        let _ = tx.send(Event::TooLarge(total));
                        broken = true;
                        bytes = Vec::new();
                        break;
                    }
                    Ok(wire::Pending::Partial(_)) => break,
                    Err(e) => {
                        let _ = tx.send(Event::Garbled(e.to_string()));
                        broken = true;
                        bytes = Vec::new();
                        break;
                    }
                }
            }
        }
        let _ = tx.send(Event::StreamEnd);
    });
}

/// Reads what the student's code printed, cut into one text per call at
/// each [`wire::CALL_END`] (each cut at 8 KiB); at the end of the stream,
/// what the last call printed before the child died or exited.
fn drain(mut stream: impl Read + Send + 'static) -> mpsc::Receiver<String> {
    let (tx, rx) = mpsc::channel();
    thread::spawn(move || {
        let mark = wire::CALL_END;
        let mut kept = Vec::new();
        let mut cut = false;
        // How much of the mark the latest bytes matched.
        let mut matched = 0;
        let mut buf = vec![0u8; 64 * 1024];
        let finish = |kept: &mut Vec<u8>, cut: &mut bool| {
            let mut s = String::from_utf8_lossy(kept).into_owned();
            if *cut {
                s.push_str("\n[... output cut ...]\n");
            }
            kept.clear();
            *cut = false;
            s
        };
        let keep = |kept: &mut Vec<u8>, cut: &mut bool, bytes: &[u8]| {
            let room = OUTPUT_CAP.saturating_sub(kept.len());
            kept.extend_from_slice(&bytes[..bytes.len().min(room)]);
            *cut |= bytes.len() > room;
        };
        // Keep reading past the cap so the child never blocks on a full pipe.
        while let Ok(n) = stream.read(&mut buf) {
            if n == 0 {
                break;
            }
            let chunk = &buf[..n];
            let mut i = 0;
            while i < n {
                if matched == 0 {
                    // Up to the next byte that can start the mark, found
                    // by the C library (a flood must cost no time, even
                    // in a debug build).
                    let rest = &chunk[i..];
                    let at = first_nul(rest).unwrap_or(rest.len());
                    keep(&mut kept, &mut cut, &rest[..at]);
                    i += at;
                    if i == n {
                        break;
                    }
                }
                let b = chunk[i];
                i += 1;
                if b == mark[matched] {
                    matched += 1;
                    if matched == mark.len() {
                        matched = 0;
                        let _ = tx.send(finish(&mut kept, &mut cut));
                    }
                    continue;
                }
                // Not the mark after all: what it matched was output. The
                // mark's first byte occurs once in it, so a mismatch can
                // only restart the match at this byte.
                keep(&mut kept, &mut cut, &mark[..matched]);
                matched = usize::from(b == mark[0]);
                if matched == 0 {
                    keep(&mut kept, &mut cut, &[b]);
                }
            }
        }
        keep(&mut kept, &mut cut, &mark[..matched]);
        let _ = tx.send(finish(&mut kept, &mut cut));
    });
    rx
}

/// Where the first NUL byte (the mark's first) is.
fn first_nul(bytes: &[u8]) -> Option<usize> {
    // SAFETY: memchr reads `bytes.len()` bytes from a valid slice.
    let p = unsafe { libc::memchr(bytes.as_ptr().cast(), 0, bytes.len()) };
    (!p.is_null()).then(|| p as usize - bytes.as_ptr() as usize)
}

/// A started launcher: its pid (its session and process group too), the
/// grader's ends of its pipes, and how to reap it.
struct Launched {
    pid: u32,
    stdin: Box<dyn Write + Send>,
    stdout: Box<dyn Read + Send>,
    stderr: Box<dyn Read + Send>,
    wait: Box<dyn FnOnce() -> std::io::Result<ExitStatus> + Send>,
}

/// Starts the launcher in a session of its own (and so its own process
/// group, killed as one) from before it runs any code: it never holds the
/// grader's terminal, and code stuck before `main` is in the group too.
/// On Linux without copying the grader's memory ([`spawn`](super::spawn));
/// elsewhere, or on a C library without `POSIX_SPAWN_SETSID`, by `fork`
/// with `setsid` before the exec.
fn start_launcher(
    launcher: &std::path::Path,
    args: &[OsString],
    env: &[(OsString, OsString)],
) -> std::io::Result<Launched> {
    #[cfg(target_os = "linux")]
    {
        use super::spawn::{self, SpawnError};
        match spawn::start(launcher, args, env) {
            Ok(s) => {
                let pid = s.pid;
                return Ok(Launched {
                    pid,
                    stdin: Box::new(s.stdin),
                    stdout: Box::new(s.stdout),
                    stderr: Box::new(s.stderr),
                    wait: Box::new(move || spawn::wait(pid)),
                });
            }
            Err(SpawnError::Io(e)) => return Err(e),
            Err(SpawnError::NoSessionFlag) => {}
        }
    }
    let mut cmd = Command::new(launcher);
    cmd.args(args)
        .env_clear()
        .envs(env.iter().map(|(k, v)| (k, v)))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    // SAFETY: setsid is async-signal-safe and touches no memory.
    unsafe {
        use std::os::unix::process::CommandExt;
        cmd.pre_exec(|| {
            if libc::setsid() < 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let mut child = cmd.spawn()?;
    Ok(Launched {
        pid: child.id(),
        stdin: Box::new(child.stdin.take().expect("piped")),
        stdout: Box::new(child.stdout.take().expect("piped")),
        stderr: Box::new(child.stderr.take().expect("piped")),
        wait: Box::new(move || child.wait()),
    })
}

/// A child that is alive between calls.
struct Live {
    pid: u32,
    /// Requests to write on the child's request pipe; dropping it closes
    /// the pipe, which ends a child waiting for its next call.
    requests: Option<mpsc::Sender<Vec<u8>>>,
    events: mpsc::Receiver<Event>,
    output: mpsc::Receiver<String>,
    /// The most bytes a result may have, set per call.
    cap: Arc<AtomicUsize>,
    sandbox: Option<Protections>,
    status: Option<ExitStatus>,
    /// Calls it has served.
    served: usize,
    /// What the launcher must send with a failure of its own (see
    /// [`wire::Frame::LaunchFailed`]).
    nonce: [u8; wire::NONCE_LEN],
    /// The child program said it waits for its first request.
    ready: bool,
    /// The kernel's CPU-time clock of the child process, once found.
    clock: Option<CpuClock>,
}

impl Live {
    /// A started child; `Ok(Err(report))` when the sandbox cannot be set
    /// up, `Err` when no process could be started.
    fn start(
        program: &ChildProgram,
        limits: &Limits,
    ) -> std::io::Result<Result<Live, ChildReport>> {
        let exe = match runnable_program(&program.exe, limits) {
            Ok(exe) => exe,
            Err(why) => return Ok(Err(ChildReport::bare(CaseEnd::SandboxFailed { why }))),
        };
        let launcher = std::env::current_exe()?;
        let args = sandbox::launcher_args(limits, &exe, &program.args);
        let env: Vec<(OsString, OsString)> = std::env::var_os("RUST_LOG")
            .map(|log| ("RUST_LOG".into(), log))
            .into_iter()
            .collect();
        let started = {
            // Listed before the sweep can see it.
            let mut running = active();
            let started = start_launcher(&launcher, &args, &env)?;
            running.push(started.pid);
            started
        };
        let Launched {
            pid,
            mut stdin,
            stdout,
            stderr,
            wait,
        } = started;
        let (tx, events) = mpsc::channel();
        let (requests, queued) = mpsc::channel::<Vec<u8>>();
        // The launcher's nonce goes first, before any request.
        let nonce = nonce();
        let _ = requests.send(nonce.to_vec());
        thread::spawn(move || {
            // Fails harmlessly if the child never reads them.
            for request in queued {
                if stdin.write_all(&request).is_err() {
                    return;
                }
            }
        });
        let cap = Arc::new(AtomicUsize::new(0));
        watch_frames(stdout, cap.clone(), tx.clone());
        let output = drain(stderr);
        thread::spawn(move || {
            if let Ok(status) = wait() {
                let _ = tx.send(Event::Exited(status));
            }
        });
        Ok(Ok(Live {
            pid,
            requests: Some(requests),
            events,
            output,
            cap,
            sandbox: None,
            status: None,
            served: 0,
            nonce,
            ready: false,
            clock: None,
        }))
    }

    /// Kills the child's group and whatever it left (see
    /// [`sweep_unless_contained`]).
    fn end(&mut self) {
        self.requests = None;
        kill_group(self.pid);
        // SIGKILL is delivered, not done: wait (briefly) until the launcher
        // is reaped, so nothing of the case is still running when the
        // grader moves on or exits.
        let deadline = Instant::now() + END_GRACE;
        while self.status.is_none() {
            match self
                .events
                .recv_timeout(deadline.saturating_duration_since(Instant::now()))
            {
                Ok(Event::Exited(s)) => self.status = Some(s),
                Ok(_) => {}
                Err(_) => break,
            }
        }
        active().retain(|&p| p != self.pid);
        sweep_unless_contained(&self.sandbox);
    }
}

/// Runs requests in sandboxed children: one child serves the calls of a
/// session one after another while each comes back (returns or panics);
/// a call that kills it, times out or garbles the channel ends it, and the
/// next call starts a fresh one. Every call has its own time limit from
/// its own start, its own growth budget and result cap; the memory cap is
/// the process's. Dropping the session ends its child.
pub struct Session<'a> {
    program: &'a ChildProgram,
    limits: &'a Limits,
    live: Option<Live>,
    /// Whether the last call ran in a child that served no call before it.
    fresh: bool,
    /// Whether each call's CPU time is measured ([`Session::timed`]).
    timing: bool,
}

impl<'a> Session<'a> {
    pub fn new(program: &'a ChildProgram, limits: &'a Limits) -> Session<'a> {
        guard_grader();
        Session {
            program,
            limits,
            live: None,
            fresh: true,
            timing: false,
        }
    }

    /// A session whose calls are timed ([`ChildReport::cpu`]): a fresh
    /// child gets its request only once it says it is ready, so that what
    /// is counted, from the request sent to the result read, is the call's
    /// work (with the child's decoding and encoding of the mesh), not the
    /// program's start.
    pub fn timed(program: &'a ChildProgram, limits: &'a Limits) -> Session<'a> {
        let mut session = Session::new(program, limits);
        session.timing = true;
        session
    }

    /// Whether the last call ran in a child of its own (no call before it
    /// in that process), as a single call always does.
    pub fn last_was_fresh(&self) -> bool {
        self.fresh
    }

    /// Ends the current child: the next call starts a fresh one.
    pub fn restart(&mut self) {
        if let Some(mut live) = self.live.take() {
            live.end();
        }
    }

    /// Runs one request (`record`: ask for a subdivision's recording) and
    /// reads what came back. `Err` only when no process could be started.
    pub fn run(
        &mut self,
        request: &Request,
        record: bool,
        timeout: Duration,
        max_result: usize,
    ) -> std::io::Result<ChildReport> {
        let mut live = match self.live.take() {
            Some(live) => live,
            None => match Live::start(self.program, self.limits)? {
                Ok(live) => live,
                Err(report) => return Ok(report),
            },
        };
        self.fresh = live.served == 0;
        live.served += 1;
        live.cap.store(max_result, Ordering::Relaxed);
        // A timed call goes to a child that is ready, the clock read just
        // before it is sent; any other goes at once.
        let mut pending = Some(wire::framed_request(request, record));
        let mut cpu_start: Option<Duration> = None;
        let send =
            |live: &Live, pending: &mut Option<Vec<u8>>, cpu_start: &mut Option<Duration>| {
                if self.timing {
                    *cpu_start = live.clock.and_then(CpuClock::now);
                }
                if let (Some(requests), Some(bytes)) = (&live.requests, pending.take()) {
                    let _ = requests.send(bytes);
                }
            };
        if !self.timing || live.ready {
            send(&live, &mut pending, &mut cpu_start);
        }
        let begun = Instant::now();
        let mut started: Option<Instant> = None;
        let mut result: Option<Vec<u8>> = None;
        let mut cpu_end: Option<Duration> = None;
        let mut garbled: Option<String> = None;
        let mut limit_hit: Option<CaseEnd> = None;
        let mut stream_ended = false;
        loop {
            if result.is_some() || (live.status.is_some() && stream_ended) {
                break;
            }
            let deadline = match (limit_hit.is_some() || live.status.is_some(), started) {
                // Dead or killed: only wait for the pipes to close.
                (true, _) => Instant::now() + CLOSE_GRACE,
                (false, Some(t)) => t + timeout,
                (false, None) => begun + timeout + SETUP_GRACE,
            };
            match live
                .events
                .recv_timeout(deadline.saturating_duration_since(Instant::now()))
            {
                // The launcher's report is the first frame, before any
                // student code runs: a later one is the student's.
                Ok(Event::Sandbox(s)) if live.sandbox.is_none() => {
                    live.clock = CpuClock::of_child(&s, live.pid);
                    live.sandbox = Some(s);
                }
                Ok(Event::Sandbox(_)) => {
                    live.requests = None;
                    garbled.get_or_insert("a second launcher report".into());
                }
                Ok(Event::Ready) => {
                    live.ready = true;
                    send(&live, &mut pending, &mut cpu_start);
                }
                Ok(Event::Started) => started = Some(Instant::now()),
                Ok(Event::Result(bytes)) => {
                    if self.timing {
                        cpu_end = live.clock.and_then(CpuClock::now);
                    }
                    result = Some(bytes);
                }
                Ok(Event::LaunchFailed { nonce, why }) if nonce == live.nonce => {
                    // The launcher's own: the machine's failure, never the
                    // student's.
                    kill_group(live.pid);
                    limit_hit = Some(CaseEnd::SandboxFailed { why });
                }
                Ok(Event::LaunchFailed { .. }) => {
                    live.requests = None;
                    garbled.get_or_insert("a forged launcher failure".into());
                }
                Ok(Event::TooLarge(n)) => {
                    kill_group(live.pid);
                    limit_hit = Some(CaseEnd::TooLarge { bytes: n });
                }
                Ok(Event::Garbled(why)) => {
                    // Let the child finish its call and exit, as it does
                    // when no call follows: then it is said by how it ended.
                    live.requests = None;
                    garbled.get_or_insert(why);
                }
                Ok(Event::StreamEnd) => stream_ended = true,
                Ok(Event::Exited(s)) => {
                    live.status = Some(s);
                    // Whatever it started dies with it, and lets go of the pipes.
                    kill_group(live.pid);
                    sweep_unless_contained(&live.sandbox);
                }
                Err(_) if live.status.is_some() || limit_hit.is_some() => break,
                Err(_) => {
                    kill_group(live.pid);
                    sweep_unless_contained(&live.sandbox);
                    limit_hit = Some(match started {
                        Some(_) => CaseEnd::TimedOut { limit: timeout },
                        None => CaseEnd::StuckBeforeCall {
                            limit: timeout + SETUP_GRACE,
                        },
                    });
                }
            }
        }
        // A result that came back: the child lives on for the next call.
        let came_back = result.is_some() && limit_hit.is_none() && garbled.is_none();
        if !came_back {
            live.end();
        } else {
            // Anything the call started outside the group is swept now.
            sweep_unless_contained(&live.sandbox);
        }
        let output = live.output.recv_timeout(CLOSE_GRACE).unwrap_or_default();
        let sandbox_status = live.sandbox;
        let end = classify(
            limit_hit,
            live.status,
            result,
            garbled,
            &output,
            sandbox_status.is_some(),
        );
        let (mut mesh, mut recorded) = (None, None);
        let end = match end {
            Ok(mut ran) => {
                if let Ran::Returned { mesh: m, .. } | Ran::Sequence { mesh: m, .. } = &ran {
                    mesh = Some(m.clone());
                }
                if let Ran::Returned { recorded: r, .. } | Ran::Panicked { recorded: r, .. } =
                    &mut ran
                {
                    recorded = r.take();
                }
                crate::isolate::analyze::analyze(request.op, &request.mesh, ran)
            }
            Err(CaseEnd::OutOfMemory { .. }) => CaseEnd::OutOfMemory {
                cap: self.limits.memory,
            },
            Err(end) => end,
        };
        if came_back {
            self.live = Some(live);
        }
        let cpu = match (cpu_start, cpu_end) {
            (Some(a), Some(b)) if came_back && b > a => Some(b - a),
            _ => None,
        };
        Ok(ChildReport {
            end,
            output: strip_notices(&output),
            sandbox: sandbox_status,
            cpu,
            mesh,
            recorded,
        })
    }
}

impl Drop for Session<'_> {
    fn drop(&mut self) {
        self.restart();
    }
}

/// Random bytes no student code can hold: from the standard library's
/// per-process random keys (seeded by the operating system), the time and
/// a counter.
fn nonce() -> [u8; wire::NONCE_LEN] {
    use std::hash::{BuildHasher, Hasher};
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    let n = COUNT.fetch_add(1, Ordering::Relaxed);
    let stamp = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let mut out = [0u8; wire::NONCE_LEN];
    for (i, chunk) in out.chunks_mut(8).enumerate() {
        let mut h = std::collections::hash_map::RandomState::new().build_hasher();
        h.write_usize(n);
        h.write_usize(i);
        h.write_u128(stamp);
        h.write_u32(std::process::id());
        chunk.copy_from_slice(&h.finish().to_le_bytes()[..chunk.len()]);
    }
    out
}

/// The kernel's CPU-time clock of a case's child process
/// (`clock_getcpuclockid`: the CPU time of all its threads, ended ones
/// included), read by the grader: nothing in the child can change it.
#[derive(Clone, Copy, Debug)]
struct CpuClock {
    #[cfg(target_os = "linux")]
    id: libc::clockid_t,
}

impl CpuClock {
    /// The clock of the child the launcher `launcher` started, by the id
    /// its report names (`pid=`, read by the launcher before the child
    /// program ran), checked against the process tree: in a PID namespace
    /// the child is the launcher's grandchild (under the namespace's
    /// init), elsewhere the launcher itself, `exec`ed. `None` where it
    /// cannot be found (then nothing is timed).
    #[cfg(target_os = "linux")]
    fn of_child(launched: &Protections, launcher: u32) -> Option<CpuClock> {
        let pid = launched.pid;
        let found = if launched.pid_namespace {
            parent_of(pid).and_then(parent_of) == Some(launcher)
        } else {
            pid == launcher
        };
        if !found {
            return None;
        }
        let mut id: libc::clockid_t = 0;
        // SAFETY: writes the clock id into our own variable.
        if unsafe { libc::clock_getcpuclockid(pid as libc::pid_t, &mut id) } != 0 {
            return None;
        }
        Some(CpuClock { id })
    }

    #[cfg(not(target_os = "linux"))]
    fn of_child(_: &Protections, _: u32) -> Option<CpuClock> {
        None
    }

    /// The CPU time the process has used, `None` once it is gone.
    #[cfg(target_os = "linux")]
    fn now(self) -> Option<Duration> {
        let mut t = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime writes the timespec it is given.
        if unsafe { libc::clock_gettime(self.id, &mut t) } != 0 {
            return None;
        }
        Some(Duration::new(
            t.tv_sec.max(0) as u64,
            t.tv_nsec.clamp(0, 999_999_999) as u32,
        ))
    }

    #[cfg(not(target_os = "linux"))]
    fn now(self) -> Option<Duration> {
        None
    }
}

/// The parent of process `pid`, from `/proc/PID/stat`.
fn parent_of(pid: u32) -> Option<u32> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // "pid (comm) state ppid ...": comm may hold spaces and parens.
    stat.rsplit_once(')')?
        .1
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()
}

/// Runs one request in a sandboxed child of its own (`record`: ask it to
/// record a subdivision) and reads what came back. `Err` only when no
/// process could be started at all.
pub fn run_child(
    program: &ChildProgram,
    limits: &Limits,
    request: &Request,
    record: bool,
    timeout: Duration,
    max_result: usize,
) -> std::io::Result<ChildReport> {
    Session::new(program, limits).run(request, record, timeout, max_result)
}

/// What the child sent, when it sent a result; else how it ended.
fn classify(
    limit_hit: Option<CaseEnd>,
    status: Option<ExitStatus>,
    result: Option<Vec<u8>>,
    garbled: Option<String>,
    output: &str,
    sandbox_reported: bool,
) -> Result<Ran, CaseEnd> {
    use std::os::unix::process::ExitStatusExt;
    if let Some(end) = limit_hit {
        return Err(end);
    }
    if let Some(bytes) = result {
        return match wire::decode_frames(&bytes).map(|mut f| f.pop()) {
            Ok(Some(Frame::Result(ran))) => Ok(ran),
            Ok(_) => Err(CaseEnd::Garbled {
                why: "no result".into(),
            }),
            Err(e) => Err(CaseEnd::Garbled { why: e.to_string() }),
        };
    }
    let Some(status) = status else {
        return Err(CaseEnd::Exited { code: None });
    };
    // Only the launcher, before it reported and exec'd, can fail this way:
    // student code that prints the same line after that is just exiting.
    if !sandbox_reported
        && status.code() == Some(sandbox::LAUNCH_FAILED)
        && output.contains("grader sandbox:")
    {
        return Err(CaseEnd::SandboxFailed {
            why: output.trim().to_string(),
        });
    }
    if let Some(why) = garbled {
        if status.success() {
            return Err(CaseEnd::Garbled { why });
        }
    }
    // The runtime's own notices: the child's last words, which no fact
    // on the channel can carry (the process is past sending frames).
    Err(if output.contains("has overflowed its stack") {
        CaseEnd::StackOverflow
    } else if output.contains("memory allocation of ") && output.contains(" failed") {
        // The cap is the caller's: filled in by `run_child`.
        CaseEnd::OutOfMemory { cap: 0 }
    } else if let Some(sig) = status.signal() {
        CaseEnd::Signal { signal: sig }
    } else {
        CaseEnd::Exited {
            code: status.code(),
        }
    })
}

/// Drops the runtime's own notices (stack overflow, failed allocation),
/// which the grader reports in its own words.
fn strip_notices(output: &str) -> String {
    output
        .lines()
        .filter(|l| {
            let oom = l.starts_with("memory allocation of ") && l.ends_with(" failed");
            !(oom || l.contains("has overflowed its stack") || l.starts_with("fatal runtime error"))
        })
        .map(|l| format!("{l}\n"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The output is cut at each call's mark, a mark cut across reads or
    /// begun and abandoned is output, and the last text comes at the end.
    #[test]
    fn output_is_cut_per_call_at_the_mark() {
        let mut stream = b"first\n".to_vec();
        stream.extend_from_slice(wire::CALL_END);
        // A mark's start that is not a mark, then the second call's mark.
        stream.extend_from_slice(b"\x00mesh\x00second");
        stream.extend_from_slice(wire::CALL_END);
        stream.extend_from_slice(b"dying words");
        let rx = drain(std::io::Cursor::new(stream));
        let got: Vec<String> = rx.iter().collect();
        assert_eq!(got, ["first\n", "\u{0}mesh\u{0}second", "dying words"]);
    }

    #[test]
    fn a_flood_is_cut_for_each_call() {
        let mut stream = vec![b'x'; 3 * OUTPUT_CAP];
        stream.extend_from_slice(wire::CALL_END);
        stream.extend_from_slice(b"short");
        let got: Vec<String> = drain(std::io::Cursor::new(stream)).iter().collect();
        assert_eq!(got.len(), 2);
        assert!(got[0].ends_with("[... output cut ...]\n") && got[0].len() < OUTPUT_CAP + 64);
        assert_eq!(got[1], "short");
    }
}
