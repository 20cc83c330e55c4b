//! `cargo run -p reference -- <command>`: the TAs' tool.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};
use grader::fixture::{self, Group, MeshData, Operation};
use halfedge::Mesh;
use reference::cases::{self, Case};
use reference::solution::{self, Weights};
use reference::{handout, lab_root, mutants};

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
        /// Subdivide this many rounds (the default operation, 1 round).
        #[arg(long, value_name = "ROUNDS", conflicts_with_all = ["flip", "split"])]
        subdivide: Option<usize>,
        /// Flip the edge between vertices A and B.
        #[arg(long, num_args = 2, value_names = ["A", "B"], conflicts_with = "split")]
        flip: Option<Vec<usize>>,
        /// Split the edge between vertices A and B.
        #[arg(long, num_args = 2, value_names = ["A", "B"])]
        split: Option<Vec<usize>>,
        /// Largest distance a vertex may be off.
        #[arg(long, default_value_t = cases::TOLERANCE)]
        tolerance: f64,
        /// The fixtures folder [default: the lab's fixtures/].
        #[arg(long, value_name = "DIR")]
        dir: Option<PathBuf>,
        #[command(flatten)]
        weights: WeightOpt,
    },
    /// Subdivide an OBJ with the reference and write the result.
    Subdivide {
        input: PathBuf,
        /// Rounds of subdivision.
        #[arg(short = 'n', long, default_value_t = 1)]
        rounds: usize,
        #[arg(short = 'o', long)]
        output: PathBuf,
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
    /// Write the student workspace (no solution, no hidden cases, with the
    /// GitHub Classroom workflow) to DIR.
    Handout {
        dir: PathBuf,
        /// Refresh a handout given out before: fixtures, docs, grader and
        /// library; the student's crates/meshedit is left as it is.
        #[arg(long)]
        update: bool,
        /// Also write .github/classroom/autograding.json (Classroom's own
        /// test list, one test per function).
        #[arg(long)]
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
    /// NAME.log (full), NAME.results.json (Gradescope's format) and
    /// summary.csv. Builds go to $CARGO_TARGET_DIR, else target/class.
    Class {
        submissions: PathBuf,
        /// Where the reports go.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Seconds each case may run.
        #[arg(long, default_value_t = 5.0)]
        timeout: f64,
        /// Seconds one submission's grading may take, all cases together.
        #[arg(long, default_value_t = 300.0)]
        budget: f64,
        /// Count the bonus cases.
        #[arg(long)]
        bonus: bool,
        /// No progress lines.
        #[arg(short, long)]
        quiet: bool,
    },
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
    },
    /// List the implementations `grade` knows: correct ones and mistakes.
    Implementations,
    /// The child side of `grade`: runs one case sent on standard input
    /// (started by the grader, locked in; of no use by hand).
    #[command(hide = true)]
    ServeCase {
        #[arg(long = "implementation")]
        implementation: String,
    },
    /// Print timings: a full grade of the reference (child processes and
    /// all) and the reference's subdivision of growing meshes.
    Bench {
        /// Full grades to time.
        #[arg(long, default_value_t = 5)]
        runs: usize,
    },
}

fn fail(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("reference: {message}");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    grader::sandbox::launch_if_asked();
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(code) => code,
        Err(message) => fail(message),
    }
}

fn fixtures_dir(dir: Option<PathBuf>) -> PathBuf {
    dir.unwrap_or_else(|| lab_root().join("fixtures"))
}

fn read_obj(path: &Path) -> Result<Mesh, String> {
    Mesh::from_obj_file(path).map_err(|e| e.to_string())
}

/// OBJ vertex numbers (from 1) to indices (from 0).
fn obj_edge(mesh: &Mesh, a: usize, b: usize) -> Result<[usize; 2], String> {
    let n = mesh.num_vertices();
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

fn write_obj(mesh: &Mesh, path: &Path) -> Result<(), String> {
    mesh.validate()
        .map_err(|e| format!("the reference broke the mesh: {e}"))?;
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
            let (operation, suffix) = match (flip, split, subdivide) {
                (Some(ab), _, _) => {
                    let edge = obj_edge(&mesh, ab[0], ab[1])?;
                    (
                        Operation::Flip { edge },
                        format!("flip-{}-{}", ab[0], ab[1]),
                    )
                }
                (_, Some(ab), _) => {
                    let edge = obj_edge(&mesh, ab[0], ab[1])?;
                    (
                        Operation::Split { edge },
                        format!("split-{}-{}", ab[0], ab[1]),
                    )
                }
                (_, _, rounds) => {
                    let rounds = rounds.unwrap_or(1);
                    if rounds == 0 {
                        return Err("--subdivide 0 tests nothing".into());
                    }
                    (
                        Operation::Subdivide { rounds },
                        format!("subdivide-{rounds}"),
                    )
                }
            };
            if !(tolerance > 0.0 && tolerance.is_finite()) {
                return Err("--tolerance must be a positive number".into());
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
            weights,
        } => {
            let mut mesh = read_obj(&input)?;
            if let Some(f) = mesh.first_non_triangle() {
                return Err(format!(
                    "{}: subdivision needs triangles, but face {} has {} sides",
                    input.display(),
                    f.index() + 1,
                    mesh.face_degree(f)
                ));
            }
            for _ in 0..rounds {
                solution::loop_subdivide_with(&mut mesh, Weights::from(weights.weights));
            }
            write_obj(&mesh, &output)?;
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
            if solution::flip_edge(&mut mesh, e).is_none() {
                return Err(format!("the edge {a}-{b} cannot be flipped: it is on the boundary or not between two triangles"));
            }
            write_obj(&mesh, &output)?;
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
            write_obj(&mesh, &output)?;
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
            if update {
                let done = handout::update(&lab_root(), &dir, autograding)?;
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
            let done = handout::export(&lab_root(), &dir, autograding)?;
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
            // The child is this program again, serving the implementation.
            let program = grader::runner::ChildProgram {
                exe: std::env::current_exe().map_err(|e| e.to_string())?,
                args: vec![
                    "serve-case".into(),
                    "--implementation".into(),
                    implementation.into(),
                ],
            };
            Ok(grader::run(&cli, &program))
        }
        Command::ServeCase { implementation } => {
            let entry = find_implementation(&implementation)?;
            grader::child::serve(&entry.imp)
        }
        Command::Bench { runs } => bench(runs.max(1)),
        Command::Gradescope {
            dir,
            bonus,
            budget,
            timeout,
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
            };
            handout::gradescope(&lab_root(), &dir, options)?;
            println!(
                "wrote {}: zip its contents (setup.sh at the top) and upload them",
                dir.display()
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Class {
            submissions,
            out,
            timeout,
            budget,
            bonus,
            quiet,
        } => {
            for (value, option) in [(budget, "--budget"), (timeout, "--timeout")] {
                if !(value > 0.0 && value <= 86_400.0) {
                    return Err(format!(
                        "{option} must be a number of seconds, above 0 and at most a day"
                    ));
                }
            }
            // Absolute: cargo runs in the scratch copy, not here.
            let here = std::env::current_dir().map_err(|e| e.to_string())?;
            let target = std::env::var_os("CARGO_TARGET_DIR")
                .map(|t| here.join(t))
                .unwrap_or_else(|| lab_root().join("target").join("class"));
            let options = reference::class::Options {
                timeout,
                budget,
                bonus,
                target,
                progress: !quiet,
            };
            let rows = reference::class::grade_class(&lab_root(), &submissions, &out, &options)?;
            for r in &rows {
                println!(
                    "{:<24} {:>5} / {:<5} {:<16} {}",
                    r.name, r.score, r.max, r.status, r.first_failure
                );
            }
            println!(
                "wrote {} reports and {}",
                rows.len(),
                out.join("summary.csv").display()
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

fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn bench(runs: usize) -> Result<ExitCode, String> {
    use std::time::Instant;
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let cases = cases::builtin(Weights::Warren).len();
    let mut times = Vec::new();
    for _ in 0..runs {
        let start = Instant::now();
        let status = std::process::Command::new(&exe)
            .args(["grade", "--bonus", "--format", "json"])
            .stdout(std::process::Stdio::null())
            .status()
            .map_err(|e| e.to_string())?;
        if !status.success() {
            return Err("the reference did not pass its own grade".into());
        }
        times.push(start.elapsed().as_secs_f64());
    }
    println!(
        "full grade of the reference, {cases} cases in child processes: median {:.3} s, min {:.3} s over {runs} runs",
        median(times.clone()),
        times.iter().copied().fold(f64::INFINITY, f64::min)
    );
    for level in 0..=4 {
        let mesh = halfedge::shapes::icosphere(level);
        let mut ts = Vec::new();
        let mut faces = 0;
        for _ in 0..3 {
            let mut m = mesh.clone();
            let start = Instant::now();
            solution::loop_subdivide(&mut m);
            ts.push(start.elapsed().as_secs_f64());
            faces = m.num_real_faces();
        }
        println!(
            "loop_subdivide, icosphere({level}): {} -> {faces} faces in {:.2} ms (median of 3)",
            mesh.num_real_faces(),
            median(ts) * 1e3
        );
    }
    Ok(ExitCode::SUCCESS)
}
