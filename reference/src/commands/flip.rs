//! `flip`: the reference's flip of one edge of an OBJ, or why it refuses.

use std::process::ExitCode;

use reference::solution;

use super::obj::{flip_refusal, obj_with_edge, write_obj, EdgeArgs};
use super::Outcome;

/// `flip`'s arguments: the OBJ, the edge, the output.
pub type Args = EdgeArgs;

pub fn run(args: Args) -> Outcome {
    let EdgeArgs {
        input,
        a,
        b,
        output,
    } = args;
    let (mut mesh, e) = obj_with_edge(&input, a, b)?;
    // Checked here too, so that the message says why.
    if let Some(why) = flip_refusal(&mesh, e) {
        return Err(format!("the edge {a}-{b} cannot be flipped: {why}"));
    }
    if solution::flip_edge(&mut mesh, e).is_none() {
        return Err(format!("the edge {a}-{b} cannot be flipped"));
    }
    write_obj(&mesh, &input, "the flip", &output)?;
    println!("wrote {}", output.display());
    Ok(ExitCode::SUCCESS)
}
