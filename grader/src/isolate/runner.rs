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

use crate::isolate::process::{
    active, guard_grader, kill_group, runnable_program, sweep_unless_contained, CpuClock,
};
use crate::isolate::protections::Protections;
use crate::isolate::sandbox::{self, Limits};
use halfedge::Mesh;

use crate::isolate::end::CaseEnd;
use crate::isolate::streams::{drain, watch_frames, Event};
use crate::isolate::wire::{self, Frame, Ran, Recorded, Request};

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
