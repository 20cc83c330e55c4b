//! The parent side: runs each case in a child process (this same program,
//! started again with the case in its environment), with a time limit, and
//! captures what the student's code printed.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::thread;
use std::time::{Duration, Instant};

use crate::child::Outcome;

/// Environment variables that turn a grader process into a case runner.
pub const CHILD_FIXTURE_ENV: &str = "MESHLAB_GRADER_CASE";
pub const CHILD_RESULT_ENV: &str = "MESHLAB_GRADER_RESULT";

/// The most of each output stream kept for the report.
const OUTPUT_CAP: usize = 8 * 1024;

/// How a case's child process ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Run {
    /// It wrote an outcome.
    Done(Outcome),
    /// Still running at the time limit, and killed.
    TimedOut(Duration),
    /// Killed by the stack overflow guard.
    StackOverflow,
    /// Ended by a signal (abort, segfault, out of memory...).
    Signal(i32),
    /// Exited without writing an outcome (e.g. `std::process::exit`).
    Exited(Option<i32>),
}

/// A finished child: how it ended and what it printed.
#[derive(Clone, Debug)]
pub struct ChildReport {
    pub run: Run,
    /// stdout then stderr, each cut at 8 KiB.
    pub output: String,
}

fn drain(mut stream: impl Read + Send + 'static) -> thread::JoinHandle<(Vec<u8>, bool)> {
    thread::spawn(move || {
        let mut kept = Vec::new();
        let mut buf = [0u8; 4096];
        let mut cut = false;
        // Keep reading past the cap so the child never blocks on a full pipe.
        while let Ok(n) = stream.read(&mut buf) {
            if n == 0 {
                break;
            }
            let room = OUTPUT_CAP.saturating_sub(kept.len());
            kept.extend_from_slice(&buf[..n.min(room)]);
            cut |= n > room;
        }
        (kept, cut)
    })
}

fn text((bytes, cut): (Vec<u8>, bool)) -> String {
    let mut s = String::from_utf8_lossy(&bytes).into_owned();
    if cut {
        s.push_str("\n[... output cut ...]\n");
    }
    s
}

/// A fresh file path for one child's outcome.
fn result_path(case: &str) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static SEQ: AtomicUsize = AtomicUsize::new(0);
    let n = SEQ.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!(
        "meshlab-grader-{}-{n}-{case}.json",
        std::process::id()
    ))
}

/// Runs one case in a child process.
pub fn run_child(
    fixture_path: &Path,
    case: &str,
    timeout: Duration,
) -> std::io::Result<ChildReport> {
    let exe = std::env::current_exe()?;
    let result = result_path(case);
    let _ = std::fs::remove_file(&result);
    let mut child = Command::new(exe)
        .args(std::env::args_os().skip(1))
        .env(CHILD_FIXTURE_ENV, fixture_path)
        .env(CHILD_RESULT_ENV, &result)
        .env("RUST_BACKTRACE", "0")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()?;
    let out = drain(child.stdout.take().expect("piped"));
    let err = drain(child.stderr.take().expect("piped"));

    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait()? {
            break Some(status);
        }
        if start.elapsed() >= timeout {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        thread::sleep(Duration::from_millis(2));
    };
    let stdout = text(out.join().unwrap_or_default());
    let stderr = text(err.join().unwrap_or_default());
    let outcome = std::fs::read_to_string(&result)
        .ok()
        .and_then(|t| serde_json::from_str::<Outcome>(&t).ok());
    let _ = std::fs::remove_file(&result);

    let run = match (status, outcome) {
        (None, _) => Run::TimedOut(timeout),
        (Some(_), Some(outcome)) => Run::Done(outcome),
        (Some(status), None) => {
            if stderr.contains("has overflowed its stack") {
                Run::StackOverflow
            } else if let Some(sig) = signal_of(&status) {
                Run::Signal(sig)
            } else {
                Run::Exited(status.code())
            }
        }
    };
    // The overflow notice is ours to report, not the student's output.
    let stderr: String = stderr
        .lines()
        .filter(|l| {
            !l.contains("has overflowed its stack") && !l.starts_with("fatal runtime error")
        })
        .map(|l| format!("{l}\n"))
        .collect();
    Ok(ChildReport {
        run,
        output: format!("{stdout}{stderr}"),
    })
}

#[cfg(unix)]
fn signal_of(status: &std::process::ExitStatus) -> Option<i32> {
    use std::os::unix::process::ExitStatusExt;
    status.signal()
}

#[cfg(not(unix))]
fn signal_of(_: &std::process::ExitStatus) -> Option<i32> {
    None
}
