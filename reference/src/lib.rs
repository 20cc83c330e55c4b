//! # The reference: model solution and TA tool
//!
//! Never shipped to students (`handout` leaves this crate out).
//!
//! - [`solution`]: the model answer, in the lab's four steps, plus boundary
//!   rules and a choice of weights.
//! - [`catalogue`]: the implementations the grader is tested with: other
//!   correct answers, one per common mistake (also the fixtures' hints) and
//!   attacks on the grader, among them the visible cases' lookup table.
//! - [`cases`]: the built-in cases; [`local`]: the local shapes each
//!   counted flip and split rule is tried on; [`render`]: a case made a
//!   fixture by running the model solution on it.
//! - [`fresh`]: cases on meshes nobody has seen, drawn per submission.
//! - [`deadline`]: the last commit before a deadline, read out of a
//!   student's repository without running anything of theirs.
//! - [`handout`]: exporting the student workspace.
//! - [`labs`]: the labs beyond Loop subdivision (√3), not wired in yet.
//! - [`class`]: grading a folder of submissions; [`similarity`]: pairs of
//!   submissions that look alike (hints for the TA); [`overview`]: the
//!   class overview page; [`scratch`]: its private temporary folders,
//!   swept when a killed run left them.
//! - [`tokens`]: Rust source as normalised tokens, and the runs two
//!   sources share (the handout's no-solution check).
//!
//! The command line (`cargo run -p reference -- --help`) is in `main.rs`.

pub mod cases;
pub mod catalogue;
pub mod class;
pub mod deadline;
pub mod fresh;
pub mod handout;
pub mod labs;
pub mod local;
pub mod overview;
pub mod platforms;
pub mod render;
pub mod roster;
pub mod scratch;
pub mod similarity;
pub mod solution;
pub mod tokens;

use std::path::PathBuf;

/// The lab's root folder (the workspace root), found from this crate.
pub fn lab_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("reference/ has a parent")
        .to_path_buf()
}
