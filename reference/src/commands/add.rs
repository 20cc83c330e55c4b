//! `add`: turn an OBJ file into a new fixture case (one operation a case).

use std::path::PathBuf;
use std::process::ExitCode;

use grader::judge::fixture::{self, Group, MeshData, Operation};
use halfedge::Mesh;
use reference::cases::{self, Case};
use reference::render;
use reference::solution::{self, Weights};

use super::obj::{check_rounds, flip_refusal, obj_edge, read_obj};
use super::{fixtures_dir, Outcome, Weighting};

/// Most faces a fixture from `add` may expect: every grade reads the file.
const MAX_FIXTURE_FACES: usize = 50_000;

#[derive(clap::Args)]
pub struct Args {
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
    weights: Weighting,
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

/// The operation the options ask for, and the case name's suffix for it.
fn operation(args: &Args, mesh: &Mesh) -> Result<(Operation, String), String> {
    Ok(match (&args.flip, &args.split, args.subdivide) {
        (Some(ab), _, _) => {
            let edge = obj_edge(mesh, ab[0], ab[1])?;
            // Named by 0-based indices, as the grader's messages
            // ("edge 0-2") name the same edge.
            (
                Operation::Flip { edge },
                format!("flip-{}-{}", edge[0], edge[1]),
            )
        }
        (_, Some(ab), _) => {
            let edge = obj_edge(mesh, ab[0], ab[1])?;
            (
                Operation::Split { edge },
                format!("split-{}-{}", edge[0], edge[1]),
            )
        }
        (_, _, rounds) => {
            let rounds = rounds.unwrap_or(1);
            check_rounds("--subdivide", rounds, mesh, MAX_FIXTURE_FACES)?;
            (
                Operation::Subdivide { rounds },
                format!("subdivide-{rounds}"),
            )
        }
    })
}

pub fn run(args: Args) -> Outcome {
    let obj = &args.obj;
    let mesh = read_obj(obj)?;
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
    if args.flip.is_none() && args.split.is_none() {
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
    let (operation, suffix) = operation(&args, &mesh)?;
    check_tolerance(args.tolerance, &mesh)?;
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
    let name = args.name.unwrap_or_else(|| format!("{stem}-{suffix}"));
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    {
        return Err(format!("case name {name:?}: use letters, digits, - and _"));
    }
    let root = fixtures_dir(args.dir);
    let taken = cases::builtin(Weights::Warren)
        .iter()
        .map(|c| c.name.clone())
        .chain(render::added_cases(&root, &[])?.into_iter().map(|c| c.name))
        .any(|n| n == name);
    if taken {
        return Err(format!("a case named {name:?} exists already: pass --name"));
    }
    let case = Case {
        name,
        object: args.object.unwrap_or(stem),
        group: args.group,
        input: MeshData::from_mesh(&mesh),
        operation,
        steps: Vec::new(),
        weights: args.weights.weights(),
        tolerance: args.tolerance,
    };
    let f = render::make_fixture(&case)?;
    let path = root.join(f.relative_path());
    std::fs::create_dir_all(path.parent().expect("a group folder")).map_err(|e| e.to_string())?;
    std::fs::write(&path, fixture::to_json_text(&f))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    render::write_sums(&root)?;
    println!("wrote {}", path.display());
    Ok(ExitCode::SUCCESS)
}
