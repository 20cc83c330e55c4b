//! `split`: the reference's split of one edge of an OBJ.

use std::process::ExitCode;

use reference::solution;

use super::obj::{obj_with_edge, write_obj, EdgeArgs};
use super::Outcome;

/// `split`'s arguments: the OBJ, the edge, the output.
pub type Args = EdgeArgs;

pub fn run(args: Args) -> Outcome {
    let EdgeArgs {
        input,
        a,
        b,
        output,
    } = args;
    let (mut mesh, e) = obj_with_edge(&input, a, b)?;
    let Some(m) = solution::split_edge(&mut mesh, e) else {
        return Err(format!(
            "the edge {a}-{b} cannot be split: a face beside it is not a triangle"
        ));
    };
    write_obj(&mesh, &input, "the split", &output)?;
    println!(
        "wrote {} (the new vertex is {})",
        output.display(),
        m.index() + 1
    );
    Ok(ExitCode::SUCCESS)
}
