//! `--watch`: grade, then grade again on every save of the student's file.
//!
//! Each grading pass is this program run again with the same arguments (and
//! [`INNER`] set, so it grades once), in a process group of its own: a save
//! during a pass kills that group and starts over, and Ctrl-C kills it and
//! ends the watch. The case children die with their grader (parent-death
//! signal, PID namespace), so nothing is left running. Changes are seen
//! through the `notify` crate (inotify, FSEvents...), not by polling: the
//! folder is watched, since editors often save by renaming a new file over
//! the old one.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Set in the environment of a grading pass started by the watch.
pub const INNER: &str = "MESHLAB_WATCHED";

/// Quiet time after the last change before grading starts: one save often
/// writes the file several times.
const DEBOUNCE: Duration = Duration::from_millis(150);

/// How often the loop looks at Ctrl-C and at the running pass.
const TICK: Duration = Duration::from_millis(25);

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

extern "C" fn on_interrupt(_: libc::c_int) {
    INTERRUPTED.store(true, Ordering::SeqCst);
}

/// The file a watch follows by default: the student's crate.
pub fn default_file() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../crates/meshedit/src/lib.rs")
}

/// Whether this process is a grading pass of a watch.
pub fn is_inner() -> bool {
    std::env::var_os(INNER).is_some()
}

/// Starts one grading pass: this program again, same arguments.
fn start_pass() -> Result<Child, String> {
    use std::os::unix::process::CommandExt;
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
    Command::new(exe)
        .args(std::env::args_os().skip(1))
        .env(INNER, "1")
        .process_group(0)
        .spawn()
        .map_err(|e| format!("cannot start a grading pass: {e}"))
}

/// Ends a pass and everything in its process group.
fn stop_pass(child: &mut Child) {
    // The pass's own process group: its id is the pass's pid.
    crate::isolate::process::kill_group(child.id());
    let _ = child.wait();
}

fn clear_screen() {
    use std::io::{IsTerminal, Write};
    let mut out = std::io::stdout();
    if out.is_terminal() {
        let _ = out.write_all(b"\x1b[2J\x1b[H");
        let _ = out.flush();
    }
}

/// Whether a file event is about `file` (by name: the folder is watched).
fn touches(event: &notify::Event, file: &Path) -> bool {
    use notify::EventKind;
    matches!(
        event.kind,
        EventKind::Create(_) | EventKind::Modify(_) | EventKind::Remove(_) | EventKind::Any
    ) && event
        .paths
        .iter()
        .any(|p| p.file_name() == file.file_name())
}

/// What ended a wait.
enum Woke {
    Changed,
    PassEnded,
    Interrupted,
}

/// Waits for a change of `file`, the end of `pass` (if one runs) or Ctrl-C.
fn wait(
    rx: &mpsc::Receiver<notify::Result<notify::Event>>,
    file: &Path,
    mut pass: Option<&mut Child>,
) -> Woke {
    loop {
        if INTERRUPTED.load(Ordering::SeqCst) {
            return Woke::Interrupted;
        }
        match rx.recv_timeout(TICK) {
            Ok(Ok(event)) if touches(&event, file) => return Woke::Changed,
            Ok(_) | Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => return Woke::Interrupted,
        }
        if let Some(p) = pass.as_deref_mut() {
            if !matches!(p.try_wait(), Ok(None)) {
                return Woke::PassEnded;
            }
        }
    }
}

/// Lets a burst of writes settle: returns once no change came for
/// [`DEBOUNCE`] (or at Ctrl-C).
fn settle(rx: &mpsc::Receiver<notify::Result<notify::Event>>, file: &Path) {
    let mut quiet_since = Instant::now();
    while quiet_since.elapsed() < DEBOUNCE && !INTERRUPTED.load(Ordering::SeqCst) {
        if let Ok(Ok(event)) = rx.recv_timeout(TICK) {
            if touches(&event, file) {
                quiet_since = Instant::now();
            }
        }
    }
}

/// Grades, then again on every save of `file`, until Ctrl-C.
pub fn watch(file: &Path) -> ExitCode {
    use notify::Watcher;
    let Some(folder) = file.parent().filter(|f| f.is_dir()) else {
        eprintln!(
            "grader: --watch: {} is not in a folder that exists",
            file.display()
        );
        return ExitCode::from(2);
    };
    let (tx, rx) = mpsc::channel();
    let mut watcher = match notify::recommended_watcher(tx) {
        Ok(w) => w,
        Err(e) => {
            eprintln!("grader: --watch: cannot watch files here: {e}");
            return ExitCode::from(2);
        }
    };
    if let Err(e) = watcher.watch(folder, notify::RecursiveMode::NonRecursive) {
        eprintln!("grader: --watch: cannot watch {}: {e}", folder.display());
        return ExitCode::from(2);
    }
    // SAFETY: the handler only stores to an atomic.
    unsafe {
        libc::signal(
            libc::SIGINT,
            on_interrupt as *const () as libc::sighandler_t,
        );
    }
    // Named as the student would type it: from here, without `..`.
    let file_abs = file.canonicalize().unwrap_or_else(|_| file.to_path_buf());
    let here = std::env::current_dir()
        .and_then(|d| d.canonicalize())
        .unwrap_or_default();
    let shown = file_abs.strip_prefix(&here).unwrap_or(&file_abs);
    loop {
        clear_screen();
        let mut pass = match start_pass() {
            Ok(p) => p,
            Err(e) => {
                eprintln!("grader: --watch: {e}");
                return ExitCode::from(2);
            }
        };
        match wait(&rx, file, Some(&mut pass)) {
            Woke::Interrupted => {
                stop_pass(&mut pass);
                println!("stopped watching {}", shown.display());
                return ExitCode::SUCCESS;
            }
            Woke::Changed => {
                // Saved while grading: that pass is out of date.
                stop_pass(&mut pass);
                settle(&rx, file);
                continue;
            }
            Woke::PassEnded => {
                let _ = pass.wait();
                println!(
                    "watching {}: save it to grade again (Ctrl-C to stop)",
                    shown.display()
                );
            }
        }
        match wait(&rx, file, None) {
            Woke::Interrupted => {
                println!("stopped watching {}", shown.display());
                return ExitCode::SUCCESS;
            }
            _ => settle(&rx, file),
        }
    }
}
