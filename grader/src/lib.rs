//! # The grader
//!
//! Grades the three functions of `crates/meshedit` against the cases in
//! `fixtures/`, and reports in the lab's words. Each case runs in a child
//! process that is locked in before any student code runs and never learns
//! the expected answer: it gets the input mesh over a pipe and sends the
//! resulting mesh back; the verdict is reached here, in the parent.
//!
//! The crate is laid out by job:
//!
//! - [`isolate`]: locking the child in and running it (launcher, seccomp
//!   filter, runner, wire format, the child's side); also the build's
//!   lock-in.
//! - [`judge`]: fixtures, relabelling, matching and the verdict of a case,
//!   with its findings as data.
//! - [`report`]: text, JSON, Gradescope and HTML renderings of those
//!   findings.
//! - [`trial`] (`grader try`) and [`watch`] (`--watch`): the student's own
//!   meshes and the edit loop.
//!
//! Two programs: `grader` (`main.rs`, the parent and launcher; this package
//! does not depend on the student's crate) and `grader-child` (its own
//! package, `grader/child/`: [`child::serve`] with the student's
//! functions). Tests run other implementations through the same protocol.

#[cfg(not(unix))]
compile_error!(
    "the grader runs each case in a locked-in child process, which needs Linux or macOS: \
     on Windows, work in WSL (Windows Subsystem for Linux)"
);

pub mod cli;
pub mod isolate;
pub mod judge;
pub mod plan;
pub mod program;
pub mod quoted;
pub mod report;
pub mod run;
pub mod text;
pub mod timing;
pub mod trial;
#[cfg(unix)]
pub mod watch;

use std::ffi::OsString;
use std::path::Path;
use std::process::ExitCode;

use clap::Parser;

pub use cli::{Cli, Format};
pub use isolate::child::Implementation;
pub use plan::Plan;
pub use program::{student_child_program, NoChild};
pub use run::run;

use cli::fixtures_root;
use isolate::runner;

/// The `grader` program's `main` after the launcher check: `try ...` or
/// grading, with the student's functions in `program` (given the fixtures
/// folder a grading run reads, none for `try`).
pub fn main_with(
    program: impl FnOnce(Option<&Path>) -> Result<runner::ChildProgram, NoChild>,
) -> ExitCode {
    let args: Vec<OsString> = std::env::args_os().collect();
    let trying = args.get(1).is_some_and(|a| a == "try");
    // Parse before building anything, so a usage error is quick.
    let (grade_cli, try_cli) = if trying {
        (None, Some(trial::TryCli::parse_from(args.iter().skip(1))))
    } else {
        (Some(Cli::parse()), None)
    };
    let fixtures = grade_cli.as_ref().map(fixtures_root);
    let program = match program(fixtures.as_deref()) {
        Ok(p) => p,
        Err(NoChild::Failed(e)) => {
            eprintln!("grader: {e}");
            println!("test failed");
            return ExitCode::from(1);
        }
        Err(NoChild::Refused(e)) => {
            eprintln!("grader: {e}");
            return ExitCode::from(2);
        }
    };
    match (grade_cli, try_cli) {
        (_, Some(t)) => trial::run_try(&t, &program),
        (Some(c), _) => run(&c, &program),
        (None, None) => unreachable!("one of the two was parsed"),
    }
}
