//! `implementations`: the catalogue's entries, which `grade`, `try` and
//! `serve-case` name with `--implementation`; and finding one by name.

use std::process::ExitCode;

use grader::isolate::runner::ChildProgram;
use reference::catalogue;

use super::Outcome;

#[derive(clap::Args)]
pub struct Args {}

pub fn run(_: Args) -> Outcome {
    for e in catalogue::catalogue() {
        println!("{:<28} {}", e.name, e.what);
    }
    Ok(ExitCode::SUCCESS)
}

/// The catalogue's entry `name`, or a message listing them all.
pub fn find(name: &str) -> Result<catalogue::Entry, String> {
    catalogue::find(name).ok_or_else(|| {
        let names: Vec<&str> = catalogue::catalogue().iter().map(|e| e.name).collect();
        format!(
            "no implementation {name:?}; there are: {}",
            names.join(", ")
        )
    })
}

/// The child program for `implementation` (checked to exist): this program
/// again, serving it (`serve-case`).
pub fn serving(implementation: String) -> Result<ChildProgram, String> {
    find(&implementation)?;
    Ok(ChildProgram {
        exe: std::env::current_exe().map_err(|e| e.to_string())?,
        args: vec![
            "serve-case".into(),
            "--implementation".into(),
            implementation.into(),
        ],
    })
}
