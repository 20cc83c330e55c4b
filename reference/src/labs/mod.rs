//! The labs beyond the first (Loop subdivision, in [`crate::solution`]),
//! each a model solution in the student's signatures, in files of their
//! own until the grader reads labs as data (issue 34). Each lab's stubs,
//! the exercise the student gets, are a text file beside it
//! (`*_stubs.rs.txt`, not compiled here).
//!
//! - [`sqrt3`]: √3 subdivision (Kobbelt, SIGGRAPH 2000); [`sqrt3_mistakes`]:
//!   its named mistakes with their hints.
//! - [`catmull_clark`]: Catmull-Clark subdivision on polygon meshes (issue
//!   35); [`catmull_clark_mistakes`]: its named mistakes.

pub mod catmull_clark;
pub mod catmull_clark_mistakes;
pub mod sqrt3;
pub mod sqrt3_mistakes;
