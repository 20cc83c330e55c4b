//! `handout`: the student workspace written out, or a given-out one
//! refreshed (`--update`).

use std::path::PathBuf;
use std::process::ExitCode;

use reference::{handout, lab_root};

use super::Outcome;

#[derive(clap::Args)]
pub struct Args {
    dir: PathBuf,
    /// Refresh a handout given out before: fixtures, docs, grader and
    /// library; the student's crates/meshedit is left as it is.
    #[arg(long)]
    update: bool,
    /// Gone with GitHub Classroom (shut down on 2026-08-28); refused
    /// with a message saying what replaced it.
    #[arg(long, hide = true)]
    autograding: bool,
}

pub fn run(args: Args) -> Outcome {
    let Args {
        dir,
        update,
        autograding,
    } = args;
    if autograding {
        return Err(
            "--autograding wrote GitHub Classroom's test list, and GitHub \
             Classroom was shut down on 2026-08-28: every export now carries a plain \
             GitHub Actions workflow (.github/workflows/grade.yml) that grades on push \
             and writes the result as the job summary; see docs/ta-guide.md"
                .to_string(),
        );
    }
    if update {
        let done = handout::update(&lab_root(), &dir)?;
        for f in &done.written {
            println!("updated {f}");
        }
        for f in &done.removed {
            println!("removed {f}");
        }
        println!(
            "{}: {} files updated, {} removed; crates/meshedit left as it was",
            dir.display(),
            done.written.len(),
            done.removed.len()
        );
        return Ok(ExitCode::SUCCESS);
    }
    let done = handout::export(&lab_root(), &dir)?;
    println!(
        "wrote the student workspace to {} ({} files)",
        dir.display(),
        done.files
    );
    Ok(ExitCode::SUCCESS)
}
