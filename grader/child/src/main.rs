//! The grader's child program: runs one case on your functions. The grader
//! starts it, locked in; it is of no use on its own.
//!
//! It is its own package, the only one that depends on `crates/meshedit`:
//! the grader (`grader/`) cannot link a line of the student's code.

fn main() {
    grader::isolate::child::serve(&grader::Implementation {
        flip_edge: meshedit::flip_edge,
        split_edge: meshedit::split_edge,
        loop_subdivide: meshedit::loop_subdivide,
    })
}
