//! `cargo run -p grader`: grades your crates/meshedit.
//!
//! This program holds none of your code: it starts `grader-child` (built
//! from your crate) once per case, locked in, and judges what comes back.

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    grader::sandbox::launch_if_asked();
    let cli = grader::Cli::parse();
    let program = match grader::student_child_program() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("grader: {e}");
            println!("test failed");
            return ExitCode::from(1);
        }
    };
    grader::run(&cli, &program)
}
