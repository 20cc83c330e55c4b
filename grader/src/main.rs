//! `cargo run -p grader`: grades your crates/meshedit.

use std::process::ExitCode;

fn main() -> ExitCode {
    grader::main_with(grader::Implementation {
        flip_edge: meshedit::flip_edge,
        split_edge: meshedit::split_edge,
        loop_subdivide: meshedit::loop_subdivide,
    })
}
