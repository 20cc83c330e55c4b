//! Labs beyond the first (issue 34), each in files of its own until the
//! grader reads labs as data.
//!
//! - [`sqrt3`]: √3 subdivision (Kobbelt, SIGGRAPH 2000), the model
//!   solution in the student's signatures; `sqrt3_stubs.rs.txt` beside it
//!   is the exercise the student gets (a text file, not compiled here).
//! - [`sqrt3_mistakes`]: the √3 lab's named mistakes with their hints.

pub mod sqrt3;
pub mod sqrt3_mistakes;
