//! `grade`: the grader run on an implementation from the catalogue.

use super::implementations::serving;
use super::Outcome;

#[derive(clap::Args)]
pub struct Args {
    /// Which implementation (see `implementations`).
    #[arg(long = "implementation", default_value = "reference")]
    implementation: String,
    #[command(flatten)]
    grader: grader::Cli,
}

pub fn run(args: Args) -> Outcome {
    Ok(grader::run(&args.grader, &serving(args.implementation)?))
}
