//! `subdivide`: the reference's Loop subdivision of any OBJ, its size
//! estimated first (faces and memory), long runs reporting each round.

use std::path::PathBuf;
use std::process::ExitCode;

use halfedge::Mesh;
use reference::solution;

use super::obj::{check_rounds, read_obj, write_obj, MAX_ROUNDS};
use super::{Outcome, Weighting};

/// Most faces `subdivide` makes unless `--max-faces` says more: each round
/// multiplies them by four, and two million faces take about 0.6 GB until
/// they are written.
const MAX_SUBDIVIDE_FACES: usize = 2_000_000;
/// Results at least this big report each round as it ends.
const PROGRESS_FACES: usize = 1_000_000;

#[derive(clap::Args)]
pub struct Args {
    input: PathBuf,
    /// Rounds of subdivision: 1 to 10, and at most --max-faces faces in
    /// the result.
    #[arg(short = 'n', long, default_value_t = 1)]
    rounds: usize,
    #[arg(short = 'o', long)]
    output: PathBuf,
    /// Most faces the result may have (each takes about 300 bytes of
    /// memory until it is written).
    #[arg(long, value_name = "N", default_value_t = MAX_SUBDIVIDE_FACES)]
    max_faces: usize,
    #[command(flatten)]
    weights: Weighting,
}

/// What `rounds` of Loop subdivision make of a triangle mesh, counted
/// exactly (each edge gains a vertex and becomes two edges, each face four
/// faces and three edges), and about how much memory that takes until it is
/// written.
struct SubdivisionSize {
    vertices: usize,
    faces: usize,
    bytes: usize,
}

impl SubdivisionSize {
    fn of(mesh: &Mesh, rounds: usize) -> SubdivisionSize {
        let (mut v, mut e, mut f) = (mesh.num_vertices(), mesh.num_edges(), mesh.num_real_faces());
        let holes = mesh.num_faces() - f;
        for _ in 0..rounds {
            v = v.saturating_add(e);
            e = e.saturating_mul(2).saturating_add(f.saturating_mul(3));
            f = f.saturating_mul(4);
        }
        // The arenas (56, 32, 8 bytes a vertex, edge, face; two 20-byte
        // halfedges an edge), then writing: the indexed faces (24 a vertex,
        // about 64 a face) and the OBJ text (about 60 a vertex, 25 a face).
        let bytes = v
            .saturating_mul(56 + 24 + 60)
            .saturating_add(e.saturating_mul(32 + 40))
            .saturating_add(f.saturating_add(holes).saturating_mul(8 + 64 + 25));
        SubdivisionSize {
            vertices: v,
            faces: f,
            bytes,
        }
    }
}

/// The memory the system could give this process now (Linux's
/// `MemAvailable`), if it says.
fn memory_available() -> Option<usize> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: usize = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

pub fn run(args: Args) -> Outcome {
    let Args {
        input,
        rounds,
        output,
        max_faces,
        weights,
    } = args;
    let mut mesh = read_obj(&input)?;
    check_rounds("--rounds", rounds, &mesh, max_faces).map_err(|e| {
        if rounds <= MAX_ROUNDS {
            format!("{e} (or raise --max-faces)")
        } else {
            e
        }
    })?;
    if let Some(f) = mesh.first_non_triangle() {
        return Err(format!(
            "{}: subdivision needs triangles, but face {} has {} sides",
            input.display(),
            f.index() + 1,
            mesh.face_degree(f)
        ));
    }
    let size = SubdivisionSize::of(&mesh, rounds);
    if let Some(available) = memory_available() {
        if size.bytes > available {
            return Err(format!(
                "--rounds {rounds}: the result ({} faces) needs about {:.1} GB of \
                 memory until it is written, but only {:.1} GB are available: use \
                 fewer rounds",
                size.faces,
                size.bytes as f64 / 1e9,
                available as f64 / 1e9
            ));
        }
    }
    let progress = size.faces >= PROGRESS_FACES;
    if progress {
        eprintln!(
            "subdividing {} faces {rounds} times: about {} vertices and {} faces, \
             {:.1} GB of memory",
            mesh.num_real_faces(),
            size.vertices,
            size.faces,
            size.bytes as f64 / 1e9
        );
    }
    let start = std::time::Instant::now();
    // The rounds reserve their arenas exactly: fault them in at once. Not
    // the writing after it, whose text grows by doubling.
    crate::bench::set_prefault(true);
    for round in 1..=rounds {
        solution::loop_subdivide_with(&mut mesh, weights.weights());
        if progress {
            eprintln!(
                "round {round} of {rounds} done: {} faces, {:.1} s",
                mesh.num_real_faces(),
                start.elapsed().as_secs_f64()
            );
        }
    }
    crate::bench::set_prefault(false);
    if progress {
        eprintln!("checking the result and writing {}...", output.display());
    }
    write_obj(&mesh, &input, "subdivision", &output)?;
    println!(
        "wrote {} ({} vertices, {} faces)",
        output.display(),
        mesh.num_vertices(),
        mesh.num_real_faces()
    );
    Ok(ExitCode::SUCCESS)
}
