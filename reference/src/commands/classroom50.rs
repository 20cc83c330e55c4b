//! `classroom50`: Classroom 50's autograder bundle written out.

use std::path::PathBuf;
use std::process::ExitCode;

use reference::lab_root;

use super::Outcome;

#[derive(clap::Args)]
pub struct Args {
    dir: PathBuf,
}

pub fn run(args: Args) -> Outcome {
    let version = reference::platforms::classroom50(&lab_root(), &args.dir)?;
    println!(
        "wrote {}: copy its contents to CLASSROOM/autograders/ASSIGNMENT/ in your \
         classroom50 repository; the runtime needs Rust {version} (lab/rust-toolchain.toml \
         pins it)",
        args.dir.display()
    );
    Ok(ExitCode::SUCCESS)
}
