//! The labs beyond the first (Loop subdivision, in [`crate::solution`]),
//! each a model solution with the student's signatures, to be plugged into
//! the grader's lab definitions.
//!
//! - [`catmull_clark`]: Catmull-Clark subdivision on polygon meshes (issue
//!   35).

pub mod catmull_clark;
