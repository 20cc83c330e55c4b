//! `cargo run -p grader`: grades your crates/meshedit.
//! `cargo run -p grader -- try FILE.obj --subdivide 1`: runs it on any mesh.
//!
//! This program holds none of your code (its package does not depend on
//! your crate): it starts `grader-child` (package `grader/child`, built from
//! your crate) once per case, locked in, and judges what comes back.

use std::process::ExitCode;

fn main() -> ExitCode {
    grader::isolate::sandbox::launch_if_asked();
    grader::main_with(grader::student_child_program)
}
