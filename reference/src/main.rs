//! `cargo run -p reference -- <command>`: the TAs' tool. This file is the
//! command enum and the dispatch; each command's options and work are in
//! its module under `commands/`.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod bench;
mod commands;

use commands::*;

/// Counts heap bytes for `bench`'s peak figures (a pass-through otherwise).
#[global_allocator]
static ALLOCATOR: bench::Counting = bench::Counting;

/// The reference solution and the TAs' tool: regenerate fixtures, add cases,
/// run the reference on any OBJ, export the student handout, grade.
///
/// Vertex numbers on this command line are the OBJ file's: the first `v`
/// line is vertex 1.
#[derive(Parser)]
#[command(name = "reference", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Regenerate fixtures/ from the reference (the built-in cases and every
    /// case a TA added). Unchanged cases are rewritten byte for byte.
    Fixtures(fixtures::Args),
    /// Turn an OBJ file into a new fixture case (one operation per case).
    Add(add::Args),
    /// Subdivide an OBJ with the reference and write the result. The size of
    /// the result is estimated first; long runs report each round.
    Subdivide(subdivide::Args),
    /// Flip the edge between vertices A and B of an OBJ and write the result.
    Flip(flip::Args),
    /// Split the edge between vertices A and B of an OBJ and write the result.
    Split(split::Args),
    /// Write the fresh cases of a seed (as a class report names it) into
    /// DIR's hidden/ and bonus/, to replay them: then `grade --fixtures DIR`.
    Fresh(fresh::Args),
    /// Write the student workspace (no solution, no hidden cases, with a
    /// GitHub Actions workflow that grades on push) to DIR.
    Handout(handout::Args),
    /// Grade an implementation from the catalogue (default: the reference)
    /// with the grader; the grader's options follow.
    Grade(grade::Args),
    /// Grade every entry of SUBMISSIONS (NAME.rs, or a folder holding lib.rs
    /// or the workspace), hidden cases included: writes NAME.txt (short),
    /// NAME.log (full), NAME.results.json (Gradescope's format),
    /// summary.csv, canvas.csv and overview.html. Every build is locked in
    /// (see the TA guide).
    Class(reference::class::ClassArgs),
    /// Write a Gradescope autograder into DIR: setup.sh, run_autograder and
    /// lab/ (the lab with hidden cases, without the solution). Zip DIR's
    /// contents and upload.
    Gradescope(gradescope::Args),
    /// Write Classroom 50's autograder into DIR (new or empty): autograder.py
    /// and lab/ (visible cases only: Classroom 50 publishes these files).
    /// Copy DIR's contents to CLASSROOM/autograders/ASSIGNMENT/ in the
    /// classroom50 config repository.
    Classroom50(classroom50::Args),
    /// Write PrairieLearn's external grader into DIR (new or empty): run.sh,
    /// lab/ and fixtures/ (hidden cases included). Copy DIR to the course's
    /// serverFilesCourse/meshlab/.
    Prairielearn(prairielearn::Args),
    /// List the implementations `grade` knows: correct ones and mistakes.
    Implementations(implementations::Args),
    /// Run an implementation from the catalogue on any OBJ, as a student's
    /// `cargo run -p grader -- try` does.
    Try(trial::Args),
    /// The child side of `grade`: runs one case sent on standard input
    /// (started by the grader, locked in; of no use by hand).
    #[command(hide = true)]
    ServeCase(serve_case::Args),
    /// Print figures (build it with --release): building and subdividing
    /// icospheres and a torus, per phase, peak bytes; a full grade of the
    /// reference; a student's edit -> verdict. See docs/performance.md.
    Bench(commands::bench::Args),
}

fn main() -> ExitCode {
    grader::isolate::sandbox::launch_if_asked();
    autograde::build::launch_if_asked();
    // Class grading runs each stage's grader under this program as a reaper.
    autograde::process::reap_if_asked();
    let outcome = match Cli::parse().command {
        Command::Fixtures(args) => fixtures::run(args),
        Command::Add(args) => add::run(args),
        Command::Subdivide(args) => subdivide::run(args),
        Command::Flip(args) => flip::run(args),
        Command::Split(args) => split::run(args),
        Command::Fresh(args) => fresh::run(args),
        Command::Handout(args) => handout::run(args),
        Command::Grade(args) => grade::run(args),
        Command::Class(args) => reference::class::run(args),
        Command::Gradescope(args) => gradescope::run(args),
        Command::Classroom50(args) => classroom50::run(args),
        Command::Prairielearn(args) => prairielearn::run(args),
        Command::Implementations(args) => implementations::run(args),
        Command::Try(args) => trial::run(args),
        Command::ServeCase(args) => serve_case::run(args),
        Command::Bench(args) => commands::bench::run(args),
    };
    outcome.unwrap_or_else(|message| {
        eprintln!("reference: {message}");
        ExitCode::from(2)
    })
}
