//! `split`: the reference's split of one edge of an OBJ.

use std::process::ExitCode;

use reference::solution;

use super::obj::EdgeArgs;
use super::Outcome;

/// `split`'s arguments: the OBJ, the edge, the output.
pub type Args = EdgeArgs;

pub fn run(args: Args) -> Outcome {
    let (mut mesh, e) = args.mesh_and_edge()?;
    let (a, b) = (args.a, args.b);
    let Some(m) = solution::split_edge(&mut mesh, e) else {
        return Err(format!(
            "the edge {a}-{b} cannot be split: a face beside it is not a triangle"
        ));
    };
    args.write(&mesh, "the split")?;
    println!(
        "wrote {} (the new vertex is {})",
        args.output.display(),
        m.index() + 1
    );
    Ok(ExitCode::SUCCESS)
}
