//! `cargo run -p grader -- try FILE.obj --subdivide N | --flip A B |
//! --split A B [-o OUT.obj] [--report DIR]`: runs the student's function on
//! any mesh, in the same locked-in child as a graded case, says what is
//! wrong with the result (naming elements) and writes it as OBJ to look at,
//! and with `--report` the report's page for it (input and result in the
//! inspector, `validate()`'s element selected when it fails).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::Parser;
use halfedge::Mesh;

use crate::cli::parse_memory;
use crate::isolate::end::CaseEnd;
use crate::isolate::end::{Finished, Returned};
use crate::isolate::runner::{self, ChildProgram};
use crate::isolate::sandbox;
use crate::isolate::wire::{self, Op};

/// The most faces `try` will subdivide into unless `--max-faces` says more.
const MAX_FACES: u64 = 5_000_000;

/// Run your function on any OBJ mesh and write the result.
///
/// Vertex numbers are the OBJ file's: the first `v` line is vertex 1.
#[derive(Parser, Debug)]
#[command(name = "grader try")]
pub struct TryCli {
    /// The mesh to start from.
    pub file: PathBuf,
    /// Subdivide this many rounds (1 to 8).
    #[arg(long, value_name = "N", conflicts_with_all = ["flip", "split"])]
    pub subdivide: Option<u32>,
    /// Flip the edge between vertices A and B.
    #[arg(long, num_args = 2, value_names = ["A", "B"], conflicts_with = "split")]
    pub flip: Option<Vec<usize>>,
    /// Split the edge between vertices A and B.
    #[arg(long, num_args = 2, value_names = ["A", "B"])]
    pub split: Option<Vec<usize>>,
    /// Where to write the result [default: FILE's name with the operation, in this folder].
    #[arg(short, long, value_name = "OUT.obj")]
    pub output: Option<PathBuf>,
    /// Seconds your function may run (0.1 to 3600).
    #[arg(long, value_name = "SECONDS", default_value_t = 60.0)]
    pub timeout: f64,
    /// The most memory it may use, e.g. 2G (64M to 64G).
    #[arg(long, value_name = "SIZE", default_value = "2G", value_parser = parse_memory)]
    pub memory: u64,
    /// Subdivide past 5 million faces anyway.
    #[arg(long, value_name = "N")]
    pub max_faces: Option<u64>,
    /// Also write a page to look at the input and your result in (DIR/index.html).
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
}

/// A line in the lab's format, `trial.rs:LINE [info] ...`, also kept for
/// the page `--report` writes.
macro_rules! say {
    ($warn:expr, $text:expr $(,)?) => {{
        let text: &str = $text;
        println!(
            "trial.rs:{} [{}] {}",
            line!(),
            if $warn { "warn" } else { "info" },
            text
        );
        SAID.with(|s| s.borrow_mut().push(($warn, text.to_string())));
    }};
}

thread_local! {
    /// What `say!` said, for the page.
    static SAID: std::cell::RefCell<Vec<(bool, String)>> = const { std::cell::RefCell::new(Vec::new()) };
}

fn fail(text: &str) -> ExitCode {
    eprintln!("grader try: {text}");
    ExitCode::from(2)
}

/// The operation, in the mesh's ids, and a word for file names.
fn operation(cli: &TryCli, mesh: &Mesh) -> Result<(Op, String), String> {
    let edge = |ab: &[usize]| -> Result<halfedge::EdgeId, String> {
        let n = mesh.num_vertices();
        for &v in ab {
            if v == 0 || v > n {
                return Err(format!(
                    "vertex {v} does not exist: the file's vertices are 1 to {n}"
                ));
            }
        }
        mesh.edge_between(ab[0] - 1, ab[1] - 1)
            .ok_or_else(|| format!("vertices {} and {} are not joined by an edge", ab[0], ab[1]))
    };
    match (&cli.flip, &cli.split, cli.subdivide) {
        (Some(ab), _, _) => Ok((Op::Flip(edge(ab)?), format!("flip-{}-{}", ab[0], ab[1]))),
        (_, Some(ab), _) => Ok((Op::Split(edge(ab)?), format!("split-{}-{}", ab[0], ab[1]))),
        (_, _, Some(rounds)) => {
            if !(1..=8).contains(&rounds) {
                return Err(format!("--subdivide {rounds} is out of range: 1 to 8"));
            }
            let faces = mesh.num_real_faces() as u64 * 4u64.pow(rounds);
            let max = cli.max_faces.unwrap_or(MAX_FACES);
            if faces > max {
                return Err(format!(
                    "{rounds} rounds make {faces} faces, more than {max}: fewer rounds, or --max-faces {faces}"
                ));
            }
            Ok((Op::Subdivide { rounds }, format!("subdivide-{rounds}")))
        }
        _ => Err("say what to do: --subdivide N, --flip A B or --split A B".into()),
    }
}

/// What the page needs beyond what was said.
#[derive(Default)]
struct Seen {
    input: Option<Mesh>,
    result: Option<Mesh>,
    output: String,
    edge: Option<([usize; 2], bool)>,
    title: String,
}

/// Runs `try`, then writes its page if `--report` asks for one.
pub fn run_try(cli: &TryCli, program: &ChildProgram) -> ExitCode {
    let mut seen = Seen::default();
    let code = run(cli, program, &mut seen);
    let (Some(dir), Some(input)) = (&cli.report, &seen.input) else {
        return code;
    };
    let page = crate::report::html::TrialPage {
        title: seen.title.clone(),
        lines: SAID.with(|s| s.borrow().clone()),
        output: seen.output.clone(),
        input,
        result: seen.result.as_ref(),
        edge: seen.edge,
    };
    match crate::report::html::write_trial_report(dir, &page) {
        Ok(index) => {
            println!(
                "trial.rs:{} [info] the page: open {} in a browser",
                line!(),
                index.display()
            );
            code
        }
        Err(e) => fail(&e),
    }
}

fn run(cli: &TryCli, program: &ChildProgram, seen: &mut Seen) -> ExitCode {
    if !(cli.timeout >= 0.1 && cli.timeout <= 3600.0) {
        return fail(&format!(
            "--timeout {} is out of range: give a number of seconds from 0.1 to 3600",
            cli.timeout
        ));
    }
    let mesh = match Mesh::from_obj_file(&cli.file) {
        Ok(m) => m,
        Err(e) => return fail(&e.to_string()),
    };
    let (op, word) = match operation(cli, &mesh) {
        Ok(x) => x,
        Err(e) => return fail(&e),
    };
    seen.input = Some(mesh.clone());
    seen.edge = match (&cli.flip, &cli.split) {
        (Some(ab), _) => Some(([ab[0] - 1, ab[1] - 1], false)),
        (_, Some(ab)) => Some(([ab[0] - 1, ab[1] - 1], true)),
        _ => None,
    };
    let output = cli.output.clone().unwrap_or_else(|| {
        let stem = cli
            .file
            .file_stem()
            .map_or("mesh".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.{word}.obj"))
    });
    // Generous: 16 times what a right answer holds.
    let grows = match op {
        Op::Subdivide { rounds } => 4u64.pow(rounds),
        _ => 2,
    };
    let budget = (mesh.num_elements() as u64 * grows * 16).max(10_000);
    let function = match op {
        Op::Flip(_) => "flip_edge",
        Op::Split(_) => "split_edge",
        Op::Subdivide { .. } => "loop_subdivide",
        // `try` never builds a sequence.
        Op::Sequence => "flip_edge and split_edge",
    };
    say!(
        false,
        &format!(
            "running your {function} on {} ({} vertices, {} faces)...",
            cli.file.display(),
            mesh.num_vertices(),
            mesh.num_real_faces()
        ),
    );
    seen.title = format!("{function} on {} ({word})", cli.file.display());
    crate::isolate::process::become_subreaper();
    let limits = sandbox::Limits {
        memory: cli.memory,
        drop_user: true,
        landlock: true,
        pid_namespace: true,
    };
    let request = wire::Request {
        op,
        steps: Vec::new(),
        budget,
        mesh: mesh.clone(),
    };
    let start = Instant::now();
    // A line every few seconds, so a long run is visibly alive.
    let (done, ticks) = std::sync::mpsc::channel::<()>();
    let ticker = std::thread::spawn(move || {
        let mut waited = 0;
        while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) =
            ticks.recv_timeout(Duration::from_secs(5))
        {
            waited += 5;
            eprintln!("grader try: still running ({waited} s)...");
        }
    });
    let raw = match runner::run_child(
        program,
        &limits,
        &request,
        false,
        Duration::from_secs_f64(cli.timeout),
        budget as usize * 64 + (1 << 20),
    ) {
        Ok(r) => r,
        Err(e) => return fail(&format!("cannot start a process: {e}")),
    };
    let _ = done.send(());
    let _ = ticker.join();
    let took = start.elapsed().as_secs_f64();
    seen.output = raw.output.clone();
    print!(
        "{}",
        crate::quoted::Quoted::new(raw.output.clone()).block("    ")
    );
    let result = raw.mesh;
    seen.result = result.clone();
    match raw.end {
        // `try` sends one operation, never a sequence.
        CaseEnd::Sequence(_) => ExitCode::from(1),
        CaseEnd::Panicked {
            message, location, ..
        } => {
            let message = crate::quoted::Quoted::new(message);
            say!(true, &format!("{function} panicked: {}", message.inline()));
            if !message.fits_inline() {
                print!("{}", message.block("        "));
            }
            if let Some(l) = location {
                println!("        at {}", crate::quoted::Quoted::new(l).inline());
            }
            ExitCode::from(1)
        }
        CaseEnd::Returned(finished) => {
            let Finished {
                returned,
                before,
                after,
                invalid,
                ..
            } = *finished;
            say!(
                false,
                &format!(
                    "{function} returned {} in {took:.2} s",
                    returned_text(&returned)
                )
            );
            say!(
                false,
                &format!(
                    "before: {} vertices, {} edges, {} faces, {} halfedges; after: {}, {}, {}, {}",
                    before.vertices,
                    before.edges,
                    before.faces,
                    before.halfedges,
                    after.vertices,
                    after.edges,
                    after.faces,
                    after.halfedges
                ),
            );
            if let Some(problem) = invalid {
                say!(true, &format!("the result is a invalid mesh: {problem}"));
                println!("        no file written: an invalid mesh has no faces to write");
                return ExitCode::from(1);
            }
            say!(false, "validate the mesh... passed");
            let result = result.expect("a returned mesh");
            match write_obj(&result, &output) {
                Ok(()) => {
                    say!(false, &format!("wrote {}", output.display()));
                    ExitCode::SUCCESS
                }
                Err(e) => fail(&e),
            }
        }
        other => {
            say!(
                true,
                &format!("{function} did not return: {}", describe_exit(&other, cli))
            );
            ExitCode::from(1)
        }
    }
}

fn returned_text(r: &Returned) -> String {
    match r {
        Returned::Unit => "()".into(),
        Returned::Nothing => "None".into(),
        Returned::Edge { got, .. } => format!("Some(e{got})"),
        Returned::Vertex { id, position } => match position {
            Some(p) => format!("Some(v{id}) at ({}, {}, {})", p[0], p[1], p[2]),
            None => format!("Some(v{id}), which is not a vertex of the mesh"),
        },
    }
}

fn describe_exit(end: &CaseEnd, cli: &TryCli) -> String {
    match end {
        CaseEnd::TimedOut { limit } => format!(
            "still running after {} s (--timeout changes it)",
            limit.as_secs_f64()
        ),
        CaseEnd::StuckBeforeCall { .. } => "the program never reached it".into(),
        CaseEnd::StackOverflow => "it overflowed the stack".into(),
        CaseEnd::OutOfMemory { .. } => format!(
            "it used more than {} of memory (--memory changes the cap)",
            crate::text::format_bytes(cli.memory)
        ),
        CaseEnd::Signal { signal } => format!("it crashed with signal {signal}"),
        CaseEnd::Exited { code } => format!("it ended the program (exit status {code:?})"),
        CaseEnd::Garbled { why } => format!("its result could not be read ({why})"),
        CaseEnd::TooLarge { bytes } => {
            format!("its result was far too large ({} MiB)", bytes >> 20)
        }
        CaseEnd::SandboxFailed { why } => format!("the sandbox could not be set up: {why}"),
        CaseEnd::Returned(_)
        | CaseEnd::Sequence(_)
        | CaseEnd::Panicked { .. }
        | CaseEnd::JudgeFailed => "it returned".into(),
    }
}

fn write_obj(mesh: &Mesh, path: &Path) -> Result<(), String> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    mesh.write_obj_file(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}
