//! The student's loop in an exported handout, as a student runs it:
//! `cargo run -p grader` shows each compiler warning once. Builds into the
//! TA tests' shared target folder (`target/ta-tests`).

use std::process::Command;

mod common;
use common::*;

#[test]
fn a_compiler_warning_reaches_the_student_once() {
    let dir = scratch("student-loop").join("lab");
    let r = run(&["handout", dir.to_str().unwrap()]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    // The stubs with one unused variable in flip_edge.
    let lib = dir.join("crates/meshedit/src/lib.rs");
    let stubs = std::fs::read_to_string(&lib).unwrap();
    let warned = stubs.replacen(
        "    let _ = (mesh, e);\n    todo!(\"flip_edge",
        "    let _ = (mesh, e);\n    let spare_halfedge = 1;\n    todo!(\"flip_edge",
        1,
    );
    assert_ne!(
        warned, stubs,
        "the stub's first line changed: update this test"
    );
    std::fs::write(&lib, warned).unwrap();
    let out = Command::new(env!("CARGO"))
        .args([
            "run",
            "-q",
            "-p",
            "grader",
            "--",
            "-q",
            "--case",
            "cube-flip-1",
        ])
        .current_dir(&dir)
        .env("CARGO_TARGET_DIR", lab_root().join("target/ta-tests"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(1),
        "the stub fails:\n{stdout}\n{stderr}"
    );
    assert_eq!(
        stderr.matches("unused variable: `spare_halfedge`").count(),
        1,
        "the warning once:\n{stderr}"
    );
    std::fs::remove_dir_all(dir.parent().unwrap()).unwrap();
}
