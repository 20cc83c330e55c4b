//! `cargo run -p reference -- <command>`: the TAs' tool.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};
use grader::judge::fixture::{self, Group, MeshData, Operation};
use halfedge::Mesh;
use reference::cases::{self, Case};
use reference::solution::{self, Weights};
use reference::{handout, lab_root, mutants};

mod bench;

/// Counts heap bytes for `bench`'s peak figures (a pass-through otherwise).
#[global_allocator]
static ALLOCATOR: bench::Counting = bench::Counting;

/// The reference solution and the TAs' tool: regenerate fixtures, add cases,
/// run the reference on any OBJ, export the student handout, grade.
///
/// Vertex numbers on this command line are the OBJ file's: the first `v`
/// line is vertex 1.
#[derive(Parser)]
#[command(name = "reference", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The command line's name for [`Weights`] (the solution stays free of clap,
/// so that it compiles pasted into a student's crate).
#[derive(Clone, Copy, ValueEnum)]
enum WeightArg {
    /// The lab's: u = 3/16 for n = 3, else 3/(8n).
    Warren,
    /// Loop's original: beta = (1/n) (5/8 - (3/8 + 1/4 cos(2 pi / n))^2).
    Loop,
}

impl From<WeightArg> for Weights {
    fn from(w: WeightArg) -> Weights {
        match w {
            WeightArg::Warren => Weights::Warren,
            WeightArg::Loop => Weights::Loop,
        }
    }
}

#[derive(Args)]
struct WeightOpt {
    /// Vertex weight rule for subdivision.
    #[arg(long, value_enum, default_value = "warren")]
    weights: WeightArg,
}

#[derive(Subcommand)]
enum Command {
    /// Regenerate fixtures/ from the reference (the built-in cases and every
    /// case a TA added). Unchanged cases are rewritten byte for byte.
    Fixtures {
        /// Write nothing; exit 1 naming every file that is stale or missing.
        #[arg(long)]
        check: bool,
        /// The fixtures folder [default: the lab's fixtures/].
        #[arg(long, value_name = "DIR")]
        dir: Option<PathBuf>,
        #[command(flatten)]
        weights: WeightOpt,
    },
    /// Turn an OBJ file into a new fixture case (one operation per case).
    Add {
        /// The input mesh.
        obj: PathBuf,
        /// Case name, also the file name [default: the OBJ's name and the operation].
        #[arg(long)]
        name: Option<String>,
        /// How messages name the mesh [default: the OBJ's file name].
        #[arg(long)]
        object: Option<String>,
        /// Which set the case joins.
        #[arg(long, value_enum, default_value = "hidden")]
        group: Group,
        /// Subdivide this many rounds (the default operation, 1 round);
        /// 1 to 10, and at most 50000 faces in the result. The mesh must be
        /// all triangles.
        #[arg(long, value_name = "ROUNDS", conflicts_with_all = ["flip", "split"])]
        subdivide: Option<usize>,
        /// Flip the edge between vertices A and B.
        #[arg(long, num_args = 2, value_names = ["A", "B"], conflicts_with = "split")]
        flip: Option<Vec<usize>>,
        /// Split the edge between vertices A and B.
        #[arg(long, num_args = 2, value_names = ["A", "B"])]
        split: Option<Vec<usize>>,
        /// Largest distance a vertex may be off: between 1e-12 and 1e-2 of
        /// the mesh's size (the diagonal of its bounding box).
        #[arg(long, default_value_t = cases::TOLERANCE)]
        tolerance: f64,
        /// The fixtures folder [default: the lab's fixtures/].
        #[arg(long, value_name = "DIR")]
        dir: Option<PathBuf>,
        #[command(flatten)]
        weights: WeightOpt,
    },
    /// Subdivide an OBJ with the reference and write the result. The size of
    /// the result is estimated first; long runs report each round.
    Subdivide {
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
        weights: WeightOpt,
    },
    /// Flip the edge between vertices A and B of an OBJ and write the result.
    Flip {
        input: PathBuf,
        a: usize,
        b: usize,
        #[arg(short = 'o', long)]
        output: PathBuf,
    },
    /// Split the edge between vertices A and B of an OBJ and write the result.
    Split {
        input: PathBuf,
        a: usize,
        b: usize,
        #[arg(short = 'o', long)]
        output: PathBuf,
    },
    /// Write the fresh cases of a seed (as a class report names it) into
    /// DIR's hidden/ and bonus/, to replay them: then `grade --fixtures DIR`.
    Fresh {
        /// The seed, 16 hex digits (`fresh-SEED-...` in the case names).
        #[arg(long, value_parser = parse_seed)]
        seed: u64,
        /// The fixtures folder to add them to (new or existing).
        #[arg(long, value_name = "DIR")]
        dir: PathBuf,
        #[command(flatten)]
        weights: WeightOpt,
    },
    /// Write the student workspace (no solution, no hidden cases, with a
    /// GitHub Actions workflow that grades on push) to DIR.
    Handout {
        dir: PathBuf,
        /// Refresh a handout given out before: fixtures, docs, grader and
        /// library; the student's crates/meshedit is left as it is.
        #[arg(long)]
        update: bool,
        /// Gone with GitHub Classroom (shut down on 2026-08-28); refused
        /// with a message saying what replaced it.
        #[arg(long, hide = true)]
        autograding: bool,
    },
    /// Grade an implementation from the catalogue (default: the reference)
    /// with the grader; the grader's options follow.
    Grade {
        /// Which implementation (see `implementations`).
        #[arg(long = "implementation", default_value = "reference")]
        implementation: String,
        #[command(flatten)]
        grader: grader::Cli,
    },
    /// Grade every entry of SUBMISSIONS (NAME.rs, or a folder holding lib.rs
    /// or the workspace), hidden cases included: writes NAME.txt (short),
    /// NAME.log (full), NAME.results.json (Gradescope's format),
    /// summary.csv, canvas.csv and overview.html. Every build is locked in
    /// (see the TA guide).
    Class(reference::class::ClassArgs),
    /// Write a Gradescope autograder into DIR: setup.sh, run_autograder and
    /// lab/ (the lab with hidden cases, without the solution). Zip DIR's
    /// contents and upload.
    Gradescope {
        dir: PathBuf,
        /// Count the bonus cases, as extra credit.
        #[arg(long)]
        bonus: bool,
        /// Seconds a whole run may take; keep it below the assignment's
        /// limit (Gradescope's default is 10 minutes).
        #[arg(long, default_value_t = 480.0)]
        budget: f64,
        /// Seconds each case may take at most (less when the budget is short).
        #[arg(long, default_value_t = 10.0)]
        timeout: f64,
        /// Sets of fresh cases (random meshes nobody has seen) the bundle
        /// carries; each upload is graded on one, chosen from its bytes
        /// (0: none).
        #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u16).range(0..=256))]
        fresh_sets: u16,
    },
    /// Write Classroom 50's autograder into DIR (new or empty): autograder.py
    /// and lab/ (visible cases only: Classroom 50 publishes these files).
    /// Copy DIR's contents to CLASSROOM/autograders/ASSIGNMENT/ in the
    /// classroom50 config repository.
    Classroom50 { dir: PathBuf },
    /// Write PrairieLearn's external grader into DIR (new or empty): run.sh,
    /// lab/ and fixtures/ (hidden cases included). Copy DIR to the course's
    /// serverFilesCourse/meshlab/.
    Prairielearn { dir: PathBuf },
    /// List the implementations `grade` knows: correct ones and mistakes.
    Implementations,
    /// Run an implementation from the catalogue on any OBJ, as a student's
    /// `cargo run -p grader -- try` does.
    Try {
        /// Which implementation (see `implementations`).
        #[arg(long = "implementation", default_value = "reference")]
        implementation: String,
        #[command(flatten)]
        args: grader::trial::TryCli,
    },
    /// The child side of `grade`: runs one case sent on standard input
    /// (started by the grader, locked in; of no use by hand).
    #[command(hide = true)]
    ServeCase {
        #[arg(long = "implementation")]
        implementation: String,
    },
    /// Print figures (build it with --release): building and subdividing
    /// icospheres and a torus, per phase, peak bytes; a full grade of the
    /// reference; a student's edit -> verdict. See docs/performance.md.
    Bench {
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
        /// Leave out edit -> verdict (it runs cargo on the lab's workspace).
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
        /// Rounds for --peer-obj.
        #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u64).range(1..=4))]
        rounds: u64,
    },
}

fn fail(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("reference: {message}");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    grader::isolate::sandbox::launch_if_asked();
    grader::isolate::build_sandbox::launch_if_asked();
    // Class grading runs each stage's grader under this program as a reaper.
    autograde::process::reap_if_asked();
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(code) => code,
        Err(message) => fail(message),
    }
}

fn fixtures_dir(dir: Option<PathBuf>) -> PathBuf {
    dir.unwrap_or_else(|| lab_root().join("fixtures"))
}

/// Most rounds `subdivide` and `add --subdivide` take.
const MAX_ROUNDS: usize = 10;
/// Most faces `subdivide` makes unless `--max-faces` says more: each round
/// multiplies them by four, and two million faces take about 0.6 GB until
/// they are written.
const MAX_SUBDIVIDE_FACES: usize = 2_000_000;
/// Results at least this big report each round as it ends.
const PROGRESS_FACES: usize = 1_000_000;
/// Most faces a fixture from `add` may expect: every grade reads the file.
const MAX_FIXTURE_FACES: usize = 50_000;
/// Reader warnings printed one by one; the summary line counts them all.
const MAX_WARNINGS_SHOWN: usize = 10;

/// A fresh-case seed: 16 hex digits, as case names print it.
fn parse_seed(text: &str) -> Result<u64, String> {
    if text.is_empty() || text.len() > 16 {
        return Err(format!("{text:?}: a seed is 1 to 16 hex digits"));
    }
    u64::from_str_radix(text, 16).map_err(|_| format!("{text:?}: a seed is 1 to 16 hex digits"))
}

/// Reads an OBJ file and prints what the reader ignored to stderr.
fn read_obj(path: &Path) -> Result<Mesh, String> {
    let (mesh, warnings) = Mesh::read_obj_file(path).map_err(|e| e.to_string())?;
    for w in warnings.iter().take(MAX_WARNINGS_SHOWN) {
        eprintln!("{w}");
    }
    if warnings.len() > MAX_WARNINGS_SHOWN {
        eprintln!(
            "... and {} more warnings",
            warnings.len() - MAX_WARNINGS_SHOWN
        );
    }
    if let Some(line) = halfedge::obj::summary(&warnings) {
        eprintln!("{line}");
    }
    Ok(mesh)
}

/// Checks a number of rounds, and that the result stays under `max_faces`.
fn check_rounds(flag: &str, rounds: usize, mesh: &Mesh, max_faces: usize) -> Result<(), String> {
    if !(1..=MAX_ROUNDS).contains(&rounds) {
        return Err(format!(
            "{flag} {rounds}: the number of rounds must be 1 to {MAX_ROUNDS}"
        ));
    }
    let faces = mesh.num_real_faces();
    let after = |r: usize| {
        4usize
            .checked_pow(r as u32)
            .and_then(|k| k.checked_mul(faces))
    };
    if after(rounds).is_none_or(|n| n > max_faces) {
        let fits = (0..rounds)
            .rev()
            .find(|&r| after(r).is_some_and(|n| n <= max_faces))
            .unwrap_or(0);
        let advice = if fits == 0 {
            "this mesh is too big for even one round".to_string()
        } else {
            format!("use at most {fits} rounds for this mesh")
        };
        return Err(format!(
            "{flag} {rounds}: {faces} faces would become {}, more than the {max_faces} allowed: \
             {advice}",
            after(rounds).map_or_else(|| "more than can be counted".to_string(), |n| n.to_string())
        ));
    }
    Ok(())
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

/// Checks a tolerance against the range fixtures allow (the grader's own
/// rule, [`fixture::TOLERANCE_RANGE`] of the mesh's size): below, f64
/// rounding alone would fail a correct answer; above, wrong ones pass.
fn check_tolerance(tolerance: f64, mesh: &Mesh) -> Result<(), String> {
    let positions: Vec<[f64; 3]> = mesh.positions().iter().map(|p| p.to_array()).collect();
    match fixture::tolerance_problem(tolerance, fixture::mesh_size(&positions)) {
        None => Ok(()),
        Some(problem) => Err(format!("--tolerance {tolerance}: {problem}")),
    }
}

/// Why edge `e` cannot be flipped, if it cannot: on the boundary, beside a
/// face that is not a triangle, or facing two vertices that are one or
/// already joined (the flip would make a second edge between them).
fn flip_refusal(mesh: &Mesh, e: halfedge::EdgeId) -> Option<String> {
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    if mesh.edge_on_boundary(e) {
        return Some("it is on the boundary (a hole is on one side)".into());
    }
    if mesh.face_degree(mesh[h].face) != 3 || mesh.face_degree(mesh[t].face) != 3 {
        return Some("the faces on its two sides are not both triangles".into());
    }
    let c = mesh[mesh[mesh[h].next].next].vertex;
    let d = mesh[mesh[mesh[t].next].next].vertex;
    if c == d {
        return Some(format!(
            "vertex {} faces it on both sides, so the flip would join it to itself",
            c.index() + 1
        ));
    }
    if mesh.find_edge(c, d).is_some() {
        return Some(format!(
            "vertices {} and {}, which face it, are already joined by an edge, so the flip \
             would make a second edge between them (on a tetrahedron, every edge is like this)",
            c.index() + 1,
            d.index() + 1
        ));
    }
    None
}

/// OBJ vertex numbers (from 1) to indices (from 0).
fn obj_edge(mesh: &Mesh, a: usize, b: usize) -> Result<[usize; 2], String> {
    let n = mesh.num_vertices();
    if a == b {
        return Err(format!(
            "vertex {a} given twice: an edge joins two different vertices"
        ));
    }
    for v in [a, b] {
        if v == 0 || v > n {
            return Err(format!(
                "vertex {v} does not exist: the file's vertices are 1 to {n}"
            ));
        }
    }
    if mesh.edge_between(a - 1, b - 1).is_none() {
        return Err(format!("vertices {a} and {b} are not joined by an edge"));
    }
    Ok([a - 1, b - 1])
}

/// An OBJ file and the edge between its vertices `a` and `b` (1-based).
fn obj_with_edge(path: &Path, a: usize, b: usize) -> Result<(Mesh, halfedge::EdgeId), String> {
    let mesh = read_obj(path)?;
    let [i, j] = obj_edge(&mesh, a, b)?;
    let e = mesh.edge_between(i, j).expect("obj_edge checked it exists");
    Ok((mesh, e))
}

/// Writes the result of `what` on `input`, after checking it.
fn write_obj(mesh: &Mesh, input: &Path, what: &str, path: &Path) -> Result<(), String> {
    // The reader refuses every degenerate input the reference is known to
    // trip on; if one still gets through, say so rather than guess who is
    // to blame.
    mesh.validate().map_err(|e| {
        format!(
            "{}: the result of {what} does not validate ({e}); the input passed every check \
             of the reader, so either it is degenerate in a way they miss or the reference \
             has a bug: please report it with the file",
            input.display()
        )
    })?;
    mesh.write_obj_file(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

fn find_implementation(name: &str) -> Result<mutants::Entry, String> {
    mutants::find(name).ok_or_else(|| {
        let names: Vec<&str> = mutants::catalogue().iter().map(|e| e.name).collect();
        format!(
            "no implementation {name:?}; there are: {}",
            names.join(", ")
        )
    })
}

/// The child program for `implementation`: this program again, serving it.
fn serving(implementation: String) -> Result<grader::isolate::runner::ChildProgram, String> {
    Ok(grader::isolate::runner::ChildProgram {
        exe: std::env::current_exe().map_err(|e| e.to_string())?,
        args: vec![
            "serve-case".into(),
            "--implementation".into(),
            implementation.into(),
        ],
    })
}

fn run(command: Command) -> Result<ExitCode, String> {
    match command {
        Command::Fixtures {
            check,
            dir,
            weights,
        } => fixtures(&fixtures_dir(dir), check, Weights::from(weights.weights)),
        Command::Add {
            obj,
            name,
            object,
            group,
            subdivide,
            flip,
            split,
            tolerance,
            dir,
            weights,
        } => {
            let mesh = read_obj(&obj)?;
            let stem = obj
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("mesh")
                .to_string();
            // One size rule for every case: the input too stays within what
            // a result may hold (a 240k-face flip made a 32 MB fixture).
            if mesh.num_real_faces() > MAX_FIXTURE_FACES {
                return Err(format!(
                    "{}: {} faces: a case's meshes have at most {MAX_FIXTURE_FACES} faces \
                     (fixtures stay small and quick to grade); take a coarser mesh",
                    obj.display(),
                    mesh.num_real_faces()
                ));
            }
            if flip.is_none() && split.is_none() {
                if let Some(f) = mesh.first_non_triangle() {
                    return Err(format!(
                        "{}: face {} has {} sides: loop_subdivide takes triangle meshes only, \
                         so this makes no subdivision case (the refusal on a mesh of quads is \
                         built in: quad-box-subdivide-1)",
                        obj.display(),
                        f.index() + 1,
                        mesh.face_degree(f)
                    ));
                }
            }
            let (operation, suffix) = match (flip, split, subdivide) {
                (Some(ab), _, _) => {
                    let edge = obj_edge(&mesh, ab[0], ab[1])?;
                    // Named by 0-based indices, as the grader's messages
                    // ("edge 0-2") name the same edge.
                    (
                        Operation::Flip { edge },
                        format!("flip-{}-{}", edge[0], edge[1]),
                    )
                }
                (_, Some(ab), _) => {
                    let edge = obj_edge(&mesh, ab[0], ab[1])?;
                    (
                        Operation::Split { edge },
                        format!("split-{}-{}", edge[0], edge[1]),
                    )
                }
                (_, _, rounds) => {
                    let rounds = rounds.unwrap_or(1);
                    check_rounds("--subdivide", rounds, &mesh, MAX_FIXTURE_FACES)?;
                    (
                        Operation::Subdivide { rounds },
                        format!("subdivide-{rounds}"),
                    )
                }
            };
            check_tolerance(tolerance, &mesh)?;
            if let Operation::Flip { edge: [i, j] } = operation {
                let e = mesh.edge_between(i, j).expect("obj_edge checked it exists");
                if let Some(why) = flip_refusal(&mesh, e) {
                    let what = format!("the edge {}-{} cannot be flipped: {why}", i + 1, j + 1);
                    // A refused flip is a fine case (it expects None); one
                    // the reference would carry out anyway makes no case.
                    if solution::flip_edge(&mut mesh.clone(), e).is_some() {
                        return Err(what);
                    }
                    eprintln!("note: {what}; the case expects None and the mesh unchanged");
                }
            }
            let name = name.unwrap_or_else(|| format!("{stem}-{suffix}"));
            if name.is_empty()
                || !name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
            {
                return Err(format!("case name {name:?}: use letters, digits, - and _"));
            }
            let root = fixtures_dir(dir);
            let taken = cases::builtin(Weights::Warren)
                .iter()
                .map(|c| c.name.clone())
                .chain(cases::added_cases(&root, &[])?.into_iter().map(|c| c.name))
                .any(|n| n == name);
            if taken {
                return Err(format!("a case named {name:?} exists already: pass --name"));
            }
            let case = Case {
                name,
                object: object.unwrap_or(stem),
                group,
                input: MeshData::from_mesh(&mesh),
                operation,
                steps: Vec::new(),
                weights: Weights::from(weights.weights),
                tolerance,
            };
            let f = cases::make_fixture(&case)?;
            let path = root.join(f.relative_path());
            std::fs::create_dir_all(path.parent().expect("a group folder"))
                .map_err(|e| e.to_string())?;
            std::fs::write(&path, fixture::to_json_text(&f))
                .map_err(|e| format!("{}: {e}", path.display()))?;
            cases::write_sums(&root)?;
            println!("wrote {}", path.display());
            Ok(ExitCode::SUCCESS)
        }
        Command::Subdivide {
            input,
            rounds,
            output,
            max_faces,
            weights,
        } => {
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
            for round in 1..=rounds {
                solution::loop_subdivide_with(&mut mesh, Weights::from(weights.weights));
                if progress {
                    eprintln!(
                        "round {round} of {rounds} done: {} faces, {:.1} s",
                        mesh.num_real_faces(),
                        start.elapsed().as_secs_f64()
                    );
                }
            }
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
        Command::Flip {
            input,
            a,
            b,
            output,
        } => {
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
        Command::Split {
            input,
            a,
            b,
            output,
        } => {
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
        Command::Handout {
            dir,
            update,
            autograding,
        } => {
            if autograding {
                return Err(
                    "--autograding wrote GitHub Classroom's test list, and GitHub \
                     Classroom was shut down on 2026-08-28: every export now carries a plain \
                     GitHub Actions workflow (.github/workflows/grade.yml) that grades on push \
                     and writes the result as the job summary; see docs/ta-guide.md"
                        .to_string(),
                );
            }
            if update {
                let done = handout::update(&lab_root(), &dir)?;
                for f in &done.written {
                    println!("updated {f}");
                }
                for f in &done.removed {
                    println!("removed {f}");
                }
                println!(
                    "{}: {} files updated, {} removed; crates/meshedit left as it was",
                    dir.display(),
                    done.written.len(),
                    done.removed.len()
                );
                return Ok(ExitCode::SUCCESS);
            }
            let done = handout::export(&lab_root(), &dir)?;
            println!(
                "wrote the student workspace to {} ({} files)",
                dir.display(),
                done.files
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Grade {
            implementation,
            grader: cli,
        } => {
            find_implementation(&implementation)?;
            Ok(grader::run(&cli, &serving(implementation)?))
        }
        Command::Try {
            implementation,
            args,
        } => {
            find_implementation(&implementation)?;
            Ok(grader::trial::run_try(&args, &serving(implementation)?))
        }
        Command::ServeCase { implementation } => {
            let entry = find_implementation(&implementation)?;
            grader::isolate::child::serve(&entry.imp)
        }
        Command::Bench {
            runs,
            levels,
            no_torus,
            obj_dir,
            no_grade,
            no_edit,
            peers,
            peer_obj,
            rounds,
        } => {
            let obj_dir = obj_dir.unwrap_or_else(|| lab_root().join("target").join("bench-meshes"));
            let levels: Vec<usize> = levels.into_iter().map(|l| l as usize).collect();
            if let Some(file) = peer_obj {
                return bench::peer_run(&file, rounds as usize);
            }
            if peers {
                return bench::write_peer_inputs(&levels, &obj_dir);
            }
            bench::run(&bench::Options {
                runs: runs as usize,
                levels,
                torus: !no_torus,
                obj_dir,
                grade: !no_grade,
                edit: !no_edit,
            })
        }
        Command::Gradescope {
            dir,
            bonus,
            budget,
            timeout,
            fresh_sets,
        } => {
            for (value, option) in [(budget, "--budget"), (timeout, "--timeout")] {
                if !(value > 0.0 && value <= 86_400.0) {
                    return Err(format!(
                        "{option} must be a number of seconds, above 0 and at most a day"
                    ));
                }
            }
            if budget < 120.0 {
                return Err("--budget must leave time to build: at least 120 seconds".into());
            }
            let options = handout::GradescopeOptions {
                bonus,
                budget,
                timeout,
                fresh_sets: usize::from(fresh_sets),
            };
            handout::gradescope(&lab_root(), &dir, options)?;
            println!(
                "wrote {}: zip its contents (setup.sh at the top) and upload them",
                dir.display()
            );
            println!("{}", gradescope_limit(&dir, budget, timeout)?);
            Ok(ExitCode::SUCCESS)
        }
        Command::Fresh { seed, dir, weights } => {
            let n = reference::fresh::write(&dir, seed, Weights::from(weights.weights))?;
            println!(
                "wrote {n} fresh cases of seed {seed:016x} into {}; grade them with \
                 `cargo run -p reference -- grade --fixtures {}`",
                dir.display(),
                dir.display()
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Class(args) => reference::class::run(args),
        Command::Classroom50 { dir } => {
            reference::platforms::classroom50(&lab_root(), &dir)?;
            println!(
                "wrote {}: copy its contents to CLASSROOM/autograders/ASSIGNMENT/ in your \
                 classroom50 repository",
                dir.display()
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Prairielearn { dir } => {
            reference::platforms::prairielearn(&lab_root(), &dir)?;
            println!(
                "wrote {}: copy it to serverFilesCourse/meshlab/ and set the question's \
                 entrypoint to /grade/serverFilesCourse/meshlab/run.sh",
                dir.display()
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Implementations => {
            for e in mutants::catalogue() {
                println!("{:<28} {}", e.name, e.what);
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// Child runs if every case passes in a fixtures folder, as the grader
/// counts them (`--list --format json`, run by this program).
fn child_runs(fixtures: &Path) -> Result<usize, String> {
    let out = std::process::Command::new(std::env::current_exe().map_err(|e| e.to_string())?)
        .args(["grade", "--list", "--format", "json", "--fixtures"])
        .arg(fixtures)
        .output()
        .map_err(|e| e.to_string())?;
    let list: Vec<serde_json::Value> = serde_json::from_slice(&out.stdout).map_err(|e| {
        format!(
            "cannot count the runs in {}: {e}: {}",
            fixtures.display(),
            String::from_utf8_lossy(&out.stderr)
        )
    })?;
    Ok(list.iter().filter_map(|c| c["runs"].as_u64()).sum::<u64>() as usize)
}

/// What per-call limit a Gradescope bundle's budget gives, as the
/// autograder shares it out (issue 16): the budget less its reserve, a
/// build of about a minute (Gradescope's one-CPU machine) and each
/// stage's start, over every child run of a correct solution (the lab's
/// cases and one fresh set).
fn gradescope_limit(dir: &Path, budget: f64, timeout: f64) -> Result<String, String> {
    const BUILD: f64 = 60.0;
    let mut runs = child_runs(&dir.join("lab/fixtures"))?;
    let fresh = dir.join("fresh/0");
    if fresh.is_dir() {
        runs += child_runs(&fresh)?;
    }
    let left = budget - autograde::gradescope::RESERVE - BUILD - 4.0 * 2.0;
    let per_call = left / runs.max(1) as f64 - 0.05;
    let limit = per_call.min(timeout);
    Ok(if per_call <= 0.05 {
        format!(
            "per-call limit: none left: {runs} child runs in {budget} s less about {:.0} s for \
             the build and the autograder: raise --budget",
            budget - left
        )
    } else {
        format!(
            "per-call limit: about {limit:.2} s a call ({runs} child runs if every case passes, \
             in the {budget} s budget less about {:.0} s for a one-minute build and the \
             autograder; --timeout {timeout} s caps it); the log of each upload says the limit \
             it got",
            budget - left
        )
    })
}

fn fixtures(root: &Path, check: bool, weights: Weights) -> Result<ExitCode, String> {
    let files = cases::render_all(root, weights)?;
    let mut stale = Vec::new();
    for (rel, text) in &files {
        let path = root.join(rel);
        let now = std::fs::read_to_string(&path).ok();
        if now.as_deref() == Some(text.as_str()) {
            continue;
        }
        let what = if now.is_none() { "missing" } else { "stale" };
        if check {
            stale.push(format!("{what}: {}", path.display()));
        } else {
            std::fs::create_dir_all(path.parent().expect("a group folder"))
                .map_err(|e| e.to_string())?;
            std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
            stale.push(format!("wrote {}", path.display()));
        }
    }
    for line in &stale {
        println!("{line}");
    }
    if check && !stale.is_empty() {
        println!(
            "{} of {} fixtures are out of date: run `cargo run -p reference -- fixtures`",
            stale.len(),
            files.len()
        );
        return Ok(ExitCode::from(1));
    }
    if check {
        println!("{} fixtures, all up to date", files.len());
    } else {
        println!(
            "{} fixtures, {} written, the rest unchanged",
            files.len(),
            stale.len()
        );
    }
    Ok(ExitCode::SUCCESS)
}
