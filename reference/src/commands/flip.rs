//! `flip`: the reference's flip of one edge of an OBJ, or why it refuses.

use std::process::ExitCode;

use reference::solution;

use super::obj::{flip_refusal, EdgeArgs};
use super::Outcome;

/// `flip`'s arguments: the OBJ, the edge, the output.
pub type Args = EdgeArgs;

pub fn run(args: Args) -> Outcome {
    let (mut mesh, e) = args.mesh_and_edge()?;
    let (a, b) = (args.a, args.b);
    // Checked here too, so that the message says why.
    if let Some(why) = flip_refusal(&mesh, e) {
        return Err(format!("the edge {a}-{b} cannot be flipped: {why}"));
    }
    if solution::flip_edge(&mut mesh, e).is_none() {
        return Err(format!("the edge {a}-{b} cannot be flipped"));
    }
    args.write(&mesh, "the flip")?;
    println!("wrote {}", args.output.display());
    Ok(ExitCode::SUCCESS)
}
