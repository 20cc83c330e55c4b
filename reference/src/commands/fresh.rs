//! `fresh`: a seed's fresh cases written out as fixtures, to replay what a
//! class report names.

use std::path::PathBuf;
use std::process::ExitCode;

use super::{Outcome, Weighting};

#[derive(clap::Args)]
pub struct Args {
    /// The seed, 16 hex digits (`fresh-SEED-...` in the case names).
    #[arg(long, value_parser = parse_seed)]
    seed: u64,
    /// The fixtures folder to add them to (new or existing).
    #[arg(long, value_name = "DIR")]
    dir: PathBuf,
    #[command(flatten)]
    weights: Weighting,
}

/// A fresh-case seed: 16 hex digits, as case names print it.
fn parse_seed(text: &str) -> Result<u64, String> {
    if text.is_empty() || text.len() > 16 {
        return Err(format!("{text:?}: a seed is 1 to 16 hex digits"));
    }
    u64::from_str_radix(text, 16).map_err(|_| format!("{text:?}: a seed is 1 to 16 hex digits"))
}

pub fn run(args: Args) -> Outcome {
    let Args { seed, dir, weights } = args;
    let n = reference::fresh::write(&dir, seed, weights.weights())?.len();
    println!(
        "wrote {n} fresh cases of seed {seed:016x} into {}; grade them with \
         `cargo run -p reference -- grade --fixtures {}`",
        dir.display(),
        dir.display()
    );
    Ok(ExitCode::SUCCESS)
}
