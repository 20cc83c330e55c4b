//! The model solution and TA tool (filled in by the reference issue).
