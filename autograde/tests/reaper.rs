//! The reaper (`autograde --meshlab-reap SECONDS COMMAND...`) that every
//! stage's grader runs under: what the command leaves behind, even in a
//! session of its own, is gone when the reaper exits; a command past its
//! deadline is stopped and said to be.

use std::process::Command;
use std::time::{Duration, Instant};

fn alive(pid: i32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .is_ok_and(|s| !s.contains(") Z ") && !s.contains(") X "))
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("autograde-reaper-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn an_orphan_in_its_own_session_does_not_outlive_the_reaper() {
    let dir = scratch("orphan");
    let pid_file = dir.join("pid");
    // The orphan: a new session, its parent gone at once (as a student's
    // process that cleared its parent-death signal would be).
    let script = format!("setsid sleep 300 & echo $! > {}", pid_file.display());
    let out = Command::new(env!("CARGO_BIN_EXE_autograde"))
        .args(["--meshlab-reap", "30", "sh", "-c", &script])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let pid: i32 = std::fs::read_to_string(&pid_file)
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    // Reparented to init once the reaper is gone, so no zombie of ours.
    let start = Instant::now();
    while alive(pid) && start.elapsed() < Duration::from_secs(5) {
        std::thread::sleep(Duration::from_millis(50));
    }
    assert!(!alive(pid), "the orphan {pid} outlived the reaper");

    // Control: the same orphan without the reaper survives its parent.
    let control = dir.join("control");
    let script = format!("setsid sleep 300 & echo $! > {}", control.display());
    assert!(Command::new("sh")
        .args(["-c", &script])
        .status()
        .unwrap()
        .success());
    std::thread::sleep(Duration::from_millis(300));
    let pid: i32 = std::fs::read_to_string(&control)
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    let survived = alive(pid);
    // SAFETY: kills the control process this test started.
    unsafe { libc::kill(pid, libc::SIGKILL) };
    assert!(survived, "the control orphan should outlive its parent");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_command_past_its_deadline_is_stopped_with_its_own_exit_code() {
    let start = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_autograde"))
        .args(["--meshlab-reap", "0.5", "sh", "-c", "sleep 300 & sleep 300"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(autograde::process::REAPED_AT_DEADLINE)
    );
    assert!(start.elapsed() < Duration::from_secs(10));
}
