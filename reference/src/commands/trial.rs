//! `try`: an implementation from the catalogue on any OBJ, as a student's
//! `cargo run -p grader -- try` runs theirs.

use super::implementations::serving;
use super::Outcome;

#[derive(clap::Args)]
pub struct Args {
    /// Which implementation (see `implementations`).
    #[arg(long = "implementation", default_value = "reference")]
    implementation: String,
    #[command(flatten)]
    args: grader::trial::TryCli,
}

pub fn run(args: Args) -> Outcome {
    Ok(grader::trial::run_try(
        &args.args,
        &serving(args.implementation)?,
    ))
}
