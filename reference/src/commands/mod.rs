//! The TA command line by job: one module per command, each with its own
//! `Args` (clap) and `run`; `main.rs` holds only the command enum and the
//! dispatch. What several commands share is here ([`Weighting`],
//! [`check_seconds`], [`fixtures_dir`]), in [`obj`] (OBJ files named on the
//! command line) and in [`implementations`] (the catalogue's entries by
//! name).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, ValueEnum};
use reference::lab_root;
use reference::solution::Weights;

pub mod add;
pub mod bench;
pub mod classroom50;
pub mod fixtures;
pub mod flip;
pub mod fresh;
pub mod grade;
pub mod gradescope;
pub mod handout;
pub mod implementations;
pub mod obj;
pub mod prairielearn;
pub mod serve_case;
pub mod split;
pub mod subdivide;
pub mod trial;

/// What a command's `run` returns: its exit code, or the message `main`
/// prints before exiting 2.
pub type Outcome = Result<ExitCode, String>;

/// The command line's name for [`Weights`] (the solution stays free of clap,
/// so that it compiles pasted into a student's crate).
#[derive(Clone, Copy, ValueEnum)]
pub enum WeightArg {
    /// The lab's: u = 3/16 for n = 3, else 3/(8n).
    Warren,
    /// Loop's original: beta = (1/n) (5/8 - (3/8 + 1/4 cos(2 pi / n))^2).
    Loop,
}

/// `--weights`, flattened into every command that subdivides.
#[derive(Args)]
pub struct Weighting {
    /// Vertex weight rule for subdivision.
    #[arg(long, value_enum, default_value = "warren")]
    weights: WeightArg,
}

impl Weighting {
    pub fn weights(&self) -> Weights {
        match self.weights {
            WeightArg::Warren => Weights::Warren,
            WeightArg::Loop => Weights::Loop,
        }
    }
}

/// The fixtures folder a `--dir` names, by default the lab's.
pub fn fixtures_dir(dir: Option<PathBuf>) -> PathBuf {
    dir.unwrap_or_else(|| lab_root().join("fixtures"))
}

/// Checks a `--budget` or `--timeout`: seconds, above 0 and at most a day.
pub fn check_seconds(value: f64, option: &str) -> Result<(), String> {
    if value > 0.0 && value <= 86_400.0 {
        Ok(())
    } else {
        Err(format!(
            "{option} must be a number of seconds, above 0 and at most a day"
        ))
    }
}
