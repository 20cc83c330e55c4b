//! The labs beyond the first (Loop subdivision, in [`crate::solution`]),
//! each a model solution with the student's signatures, to be plugged into
//! the grader's lab definitions.
//!
//! - [`catmull_clark`]: Catmull-Clark subdivision on polygon meshes (issue
//!   35); [`catmull_clark_mistakes`]: its named mistakes. The student's
//!   stubs are `catmull_clark_stubs.rs.txt` beside them (a text file, not
//!   compiled here).

pub mod catmull_clark;
pub mod catmull_clark_mistakes;
