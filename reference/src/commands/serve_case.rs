//! `serve-case` (hidden): the child side of `grade` and `try`, one case
//! read from standard input, locked in by the grader that started it.

use super::implementations::find;
use super::Outcome;

#[derive(clap::Args)]
pub struct Args {
    #[arg(long = "implementation")]
    implementation: String,
}

pub fn run(args: Args) -> Outcome {
    let entry = find(&args.implementation)?;
    grader::isolate::child::serve(&entry.imp)
}
