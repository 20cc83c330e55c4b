//! `--watch` as a student uses it: grade, save twice, Ctrl-C. Alone in its
//! test binary, so that any process left behind is this test's to find:
//! the test is a child subreaper, and orphans of the watch become its
//! children.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

mod common;

/// This process's children, from /proc.
fn children() -> Vec<(u32, String)> {
    let me = std::process::id().to_string();
    let mut out = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(status) = std::fs::read_to_string(entry.path().join("status")) else {
            continue;
        };
        let field = |name: &str| {
            status
                .lines()
                .find_map(|l| l.strip_prefix(name))
                .map(|v| v.trim().to_string())
        };
        if field("PPid:").as_deref() == Some(me.as_str()) {
            let pid = entry.file_name().to_string_lossy().parse().unwrap_or(0);
            out.push((pid, field("Name:").unwrap_or_default()));
        }
    }
    out
}

#[test]
fn a_watch_grades_on_every_save_and_ctrl_c_leaves_nothing_running() {
    // SAFETY: marks this process as the reaper of its orphaned descendants.
    unsafe {
        libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0);
    }
    let dir = common::scratch("watch");
    let file = dir.join("lib.rs");
    std::fs::write(&file, "// first\n").unwrap();
    let mut watcher = Command::new(env!("CARGO_BIN_EXE_reference"))
        .args([
            "grade",
            "--no-color",
            "--case",
            "cube-split",
            "--watch",
            "--watch-file",
        ])
        .arg(&file)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let (tx, rx) = mpsc::channel();
    let stdout = watcher.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    // Every pass ends with its verdict and then the watch's prompt.
    let mut transcript = Vec::new();
    let next_prompt = |transcript: &mut Vec<String>| loop {
        let line = rx
            .recv_timeout(Duration::from_secs(120))
            .unwrap_or_else(|_| panic!("no prompt; so far:\n{}", transcript.join("\n")));
        let prompt = line.starts_with("watching ");
        transcript.push(line);
        if prompt {
            return;
        }
    };
    next_prompt(&mut transcript);
    // A save by writing in place, then one by renaming a new file over it,
    // as many editors do.
    std::fs::write(&file, "// second\n").unwrap();
    next_prompt(&mut transcript);
    let new = dir.join("lib.rs.new");
    std::fs::write(&new, "// third\n").unwrap();
    std::fs::rename(&new, &file).unwrap();
    next_prompt(&mut transcript);
    // SAFETY: a signal to the watch, as Ctrl-C sends it.
    unsafe {
        libc::kill(watcher.id() as libc::pid_t, libc::SIGINT);
    }
    let status = watcher.wait().unwrap();
    while let Ok(line) = rx.recv_timeout(Duration::from_secs(5)) {
        transcript.push(line);
    }
    let text = transcript.join("\n");
    assert!(
        status.success(),
        "Ctrl-C ends the watch cleanly: {status}\n{text}"
    );
    let verdicts = transcript
        .iter()
        .filter(|l| l.contains("--case cube-split: all 1 counted cases passed"))
        .count();
    assert_eq!(verdicts, 3, "graded once, then once per save:\n{text}");
    assert!(
        text.ends_with(&format!("stopped watching {}", file.display())),
        "{text}"
    );
    // Reap what is already gone, then look for anything left.
    std::thread::sleep(Duration::from_millis(300));
    // SAFETY: reaps exited children without blocking.
    while unsafe { libc::waitpid(-1, std::ptr::null_mut(), libc::WNOHANG) } > 0 {}
    assert_eq!(
        children(),
        Vec::new(),
        "nothing of the watch is still running"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
