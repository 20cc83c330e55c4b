//! The student's child program: built from the student's crate through
//! cargo when the grader runs under it (`cargo run -p grader`), and
//! refused where hidden cases are within reach.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use crate::isolate::runner;

/// Why there is no child program to grade with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NoChild {
    /// The student's code does not compile, or the program is missing:
    /// the run fails (exit 1).
    Failed(String),
    /// The grader does not build the student's code here (see
    /// [`student_child_program`]): said, exit 2.
    Refused(String),
}

/// The hidden cases within this run's reach, if any: `fixtures/hidden` in
/// the lab this grader was built from, in the folder it runs in, or in
/// the fixtures folder it reads.
fn hidden_cases_in_reach(fixtures: Option<&Path>) -> Option<PathBuf> {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lab = manifest.parent().unwrap_or(manifest).join("fixtures");
    [
        Some(lab),
        Some(PathBuf::from("fixtures")),
        fixtures.map(Path::to_path_buf),
    ]
    .into_iter()
    .flatten()
    .map(|f| f.join("hidden"))
    .find(|h| h.exists())
}

/// The `grader` program: the student's functions live in `grader-child`
/// (package `grader-child`), next to this program. Run through cargo
/// (`cargo run -p grader`), it builds that program first, so it always
/// holds the code as it is now; that build is the one that compiles the
/// student's crate, so its output (warnings, errors) goes to the student.
///
/// That build runs with the rights of whoever runs the grader, and
/// compiling is running the crate's code (`include_str!` reads any file
/// the compiler can): where hidden cases are within reach (a TA's lab),
/// it is refused, pointing at the TA's guide, whose way to grade one
/// student's file builds it locked in, in a copy without them.
pub fn student_child_program(fixtures: Option<&Path>) -> Result<runner::ChildProgram, NoChild> {
    let failed = |e: String| NoChild::Failed(e);
    let exe =
        std::env::current_exe().map_err(|e| failed(format!("cannot find this program: {e}")))?;
    let dir = exe
        .parent()
        .ok_or_else(|| failed("this program has no folder".into()))?;
    let child = dir.join(format!("grader-child{}", std::env::consts::EXE_SUFFIX));
    if let Some(cargo) = std::env::var_os("CARGO") {
        if let Some(hidden) = hidden_cases_in_reach(fixtures) {
            return Err(NoChild::Refused(format!(
                "hidden cases are within reach here ({}): the grader does not compile \
                 crates/meshedit where they are, since the code it compiles could read them \
                 (include_str!) with your rights. Grade a student's file as a class of one \
                 (\"Grade a class\", one student by hand, in the guide that came with the \
                 hidden cases), which builds it locked in, in a copy of the lab without them; \
                 to try your own code, grade it in a copy of the lab without fixtures/hidden",
                hidden.display()
            )));
        }
        let profile = match dir.file_name().and_then(|n| n.to_str()) {
            Some("debug") | None => "dev".to_string(),
            Some(name) => name.to_string(),
        };
        let target = dir
            .parent()
            .ok_or_else(|| failed("this program's folder has no parent".into()))?;
        // `cargo run -p grader` did not compile crates/meshedit (this
        // package does not depend on it): this build does, and its
        // warnings and errors go straight to the student, once.
        let built = std::process::Command::new(cargo)
            .args([
                "build",
                "--quiet",
                "-p",
                "grader-child",
                "--bin",
                "grader-child",
            ])
            .arg("--profile")
            .arg(&profile)
            .arg("--target-dir")
            .arg(target)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .status()
            .map_err(|e| failed(format!("cannot run cargo: {e}")))?;
        if !built.success() {
            return Err(failed(
                "your code does not compile: the compiler's messages are above".to_string(),
            ));
        }
    }
    if !child.is_file() {
        return Err(failed(format!(
            "{} is missing: build it with `cargo build -p grader-child`",
            child.display()
        )));
    }
    Ok(runner::ChildProgram {
        exe: child,
        args: Vec::<OsString>::new(),
    })
}
