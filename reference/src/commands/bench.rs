//! `bench`: the figures of `docs/performance.md` (the work is in the
//! binary's `bench` module, with its counting allocator).

use std::path::PathBuf;

use reference::lab_root;

use super::Outcome;
use crate::bench;

#[derive(clap::Args)]
pub struct Args {
    /// Timed runs of every figure (median and spread are printed).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..=1000))]
    runs: u64,
    /// Icosphere levels to subdivide, 0 to 8 (level 8 needs about 3 GB for
    /// two rounds).
    #[arg(long, value_delimiter = ',', default_value = "4,5,6,7",
          value_parser = clap::value_parser!(u64).range(0..=8))]
    levels: Vec<u64>,
    /// Leave out the 200 x 100 torus.
    #[arg(long)]
    no_torus: bool,
    /// Where the input meshes are written as OBJ [default: target/bench-meshes].
    #[arg(long, value_name = "DIR")]
    obj_dir: Option<PathBuf>,
    /// Leave out the full grades of the reference.
    #[arg(long)]
    no_grade: bool,
    /// Leave out edit -> verdict (it runs cargo on a handout copy of the lab).
    #[arg(long)]
    no_edit: bool,
    /// The reference's side of the peers' comparison
    /// (reference/bench/peers/run.sh): write the --levels icospheres as
    /// OBJ to --obj-dir and stop, or, with --peer-obj, time one call.
    #[arg(long)]
    peers: bool,
    /// With --peers: read this OBJ, time `loop_subdivide` for --rounds
    /// rounds once, print one line of figures.
    #[arg(long, value_name = "FILE", requires = "peers")]
    peer_obj: Option<PathBuf>,
    /// Let large blocks fault in page by page as they are first written,
    /// as the system allocator does, instead of at once (to measure what
    /// the prefault is worth; see docs/performance.md).
    #[arg(long)]
    no_prefault: bool,
    /// Rounds for --peer-obj.
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u64).range(1..=4))]
    rounds: u64,
}

pub fn run(args: Args) -> Outcome {
    let obj_dir = args
        .obj_dir
        .unwrap_or_else(|| lab_root().join("target").join("bench-meshes"));
    let levels: Vec<usize> = args.levels.into_iter().map(|l| l as usize).collect();
    bench::set_prefault(!args.no_prefault);
    if let Some(file) = args.peer_obj {
        return bench::peer_run(&file, args.rounds as usize);
    }
    if args.peers {
        return bench::write_peer_inputs(&levels, &obj_dir);
    }
    bench::run(&bench::Options {
        runs: args.runs as usize,
        levels,
        torus: !args.no_torus,
        obj_dir,
        grade: !args.no_grade,
        edit: !args.no_edit,
    })
}
