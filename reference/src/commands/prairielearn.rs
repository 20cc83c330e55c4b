//! `prairielearn`: PrairieLearn's external grader written out.

use std::path::PathBuf;
use std::process::ExitCode;

use reference::lab_root;

use super::Outcome;

#[derive(clap::Args)]
pub struct Args {
    dir: PathBuf,
}

pub fn run(args: Args) -> Outcome {
    let version = reference::platforms::prairielearn(&lab_root(), &args.dir)?;
    println!(
        "wrote {}: copy it to serverFilesCourse/meshlab/ and set the question's \
         entrypoint to /grade/serverFilesCourse/meshlab/run.sh; the image needs Rust \
         {version} (lab/rust-toolchain.toml pins it)",
        args.dir.display()
    );
    Ok(ExitCode::SUCCESS)
}
