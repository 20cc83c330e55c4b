//! The lab exercise (filled in by the student-crate issue).
