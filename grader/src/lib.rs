//! # The grader
//!
//! Grades the three functions of `crates/meshedit` against the cases in
//! `fixtures/`, and reports in the lab's words. Each case runs in a child
//! process that is locked in before any student code runs and never learns
//! the expected answer: it gets the input mesh over a pipe and sends the
//! resulting mesh back; the verdict is reached here, in the parent.
//!
//! The crate is laid out by job:
//!
//! - [`isolate`]: locking the child in and running it (launcher, seccomp
//!   filter, runner, wire format, the child's side); also the build's
//!   lock-in.
//! - [`judge`]: fixtures, relabelling, matching and the verdict of a case,
//!   with its findings as data.
//! - [`report`]: text, JSON, Gradescope and HTML renderings of those
//!   findings.
//! - [`trial`] (`grader try`) and [`watch`] (`--watch`): the student's own
//!   meshes and the edit loop.
//!
//! Two programs: `grader` (`main.rs`, the parent and launcher; this package
//! does not depend on the student's crate) and `grader-child` (its own
//! package, `grader/child/`: [`child::serve`] with the student's
//! functions). Tests run other implementations through the same protocol.

#[cfg(not(unix))]
compile_error!(
    "the grader runs each case in a locked-in child process, which needs Linux or macOS: \
     on Windows, work in WSL (Windows Subsystem for Linux)"
);

pub mod isolate;
pub mod judge;
pub mod quoted;
pub mod report;
pub mod text;
pub mod timing;
pub mod trial;
#[cfg(unix)]
pub mod watch;

use isolate::{runner, sandbox, wire};
use judge::{fixture, frames, grade, relabel, scaling, verdict};
use report::html;

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Parser, ValueEnum};

use crate::judge::fixture::{Fixture, Operation, Stage};

pub use isolate::child::Implementation;

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Text,
    Json,
}

/// Grades crates/meshedit: flip_edge, split_edge and loop_subdivide.
///
/// Exit status: 0 when every counted case passes, 1 when one fails, 2 when
/// the command line or a fixture is wrong.
#[derive(Parser, Debug)]
#[command(name = "grader", version)]
pub struct Cli {
    /// Run only this case (see --list).
    #[arg(long, value_name = "NAME")]
    pub case: Option<String>,
    /// Run only the cases of one function.
    #[arg(long, value_enum)]
    pub stage: Option<Stage>,
    /// Where the fixtures are [default: ./fixtures, else the lab's own].
    #[arg(long, value_name = "DIR")]
    pub fixtures: Option<PathBuf>,
    /// Count the bonus cases (meshes with boundary) toward the verdict
    /// (a case named with --case always counts).
    #[arg(long)]
    pub bonus: bool,
    /// List the cases and exit.
    #[arg(long)]
    pub list: bool,
    /// Report format on standard output.
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
    /// Also write Gradescope's results.json to PATH.
    #[arg(long, value_name = "PATH")]
    pub gradescope: Option<PathBuf>,
    /// Seconds each case may run, from the call of the function, before it
    /// counts as an endless loop (0.1 to 3600).
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
    pub timeout: f64,
    /// Seconds the whole run may take: the limit of each call is shortened
    /// if need be, so that every run of every selected case fits (each case
    /// runs once per labelling of its input; the runs are counted).
    #[arg(long, value_name = "SECONDS")]
    pub budget: Option<f64>,
    /// Time loop_subdivide on two icospheres (the scaling check) even with
    /// --budget, within what the cases left of it (for leaderboards).
    #[arg(long)]
    pub time_subdivision: bool,
    /// The most memory a case may use, e.g. 2G or 512M (64M to 64G).
    #[arg(long, value_name = "SIZE", default_value = "2G", value_parser = parse_memory)]
    pub memory: u64,
    /// Grade without Landlock, as on a kernel that lacks it (to test the
    /// other protections).
    #[arg(long, hide = true)]
    pub without_landlock: bool,
    /// Grade without a PID namespace, as on a machine that has none (to
    /// test the fallback: the sweep and the parent-death signals).
    #[arg(long, hide = true)]
    pub without_pid_namespace: bool,
    /// Seed of the relabelled inputs each case also runs on [default: one
    /// per case, fixed]; a failure prints the seed that shows it.
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,
    /// Also write, for every case, the input, your result and the expected
    /// result as OBJ files and an index.html with pictures, into DIR
    /// [default: target/grader-report].
    #[arg(long, value_name = "DIR", num_args = 0..=1, default_missing_value = "target/grader-report")]
    pub report: Option<PathBuf>,
    /// Show every bonus case in full, even when they do not count.
    #[arg(short, long)]
    pub verbose: bool,
    /// Print only the summary and the verdict.
    #[arg(short, long, conflicts_with = "verbose")]
    pub quiet: bool,
    /// Never colour `[warn]` lines (also off when NO_COLOR is set or output is
    /// not a terminal).
    #[arg(long)]
    pub no_color: bool,
    /// Grade, then grade again every time crates/meshedit/src/lib.rs is
    /// saved (a save during a run starts it over); Ctrl-C stops.
    #[arg(short, long)]
    pub watch: bool,
    /// Record every subdivision's splits, as --report does (to measure
    /// what the recording costs).
    #[arg(long, hide = true)]
    pub record_subdivision: bool,
    /// Rewrite every message the judge says (for the lab's own tests:
    /// no verdict, hint or element may change with the words).
    #[arg(long, hide = true)]
    pub reword_messages: bool,
    /// The file --watch follows (for the lab's own tests).
    #[arg(long, hide = true, value_name = "PATH", requires = "watch")]
    pub watch_file: Option<PathBuf>,
}

/// `2G`, `512M`, `1.5G` or a number of bytes, between 64 MiB and 64 GiB.
pub(crate) fn parse_memory(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let (number, unit) = match t.char_indices().find(|(_, c)| c.is_ascii_alphabetic()) {
        Some((i, _)) => (&t[..i], t[i..].to_ascii_uppercase()),
        None => (t, String::new()),
    };
    let scale: u64 = match unit.trim_end_matches("IB").trim_end_matches('B') {
        "" => 1,
        "K" => 1 << 10,
        "M" => 1 << 20,
        "G" => 1 << 30,
        _ => {
            return Err(format!(
                "{text:?}: give a size like 2G or 512M, from 64M to 64G"
            ))
        }
    };
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|_| format!("{text:?}: give a size like 2G or 512M, from 64M to 64G"))?;
    let bytes = value * scale as f64;
    if !(bytes >= (64u64 << 20) as f64 && bytes <= (64u64 << 30) as f64) {
        return Err(format!("{text:?} is out of range: between 64M and 64G"));
    }
    Ok(bytes as u64)
}

/// The fixtures folder: `--fixtures`, else `./fixtures`, else the one next
/// to this crate (so `cargo run -p grader` works from any folder of the lab).
fn fixtures_root(cli: &Cli) -> PathBuf {
    if let Some(dir) = &cli.fixtures {
        return dir.clone();
    }
    let here = PathBuf::from("fixtures");
    if here.is_dir() {
        return here;
    }
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("fixtures")
}

fn use_color(cli: &Cli) -> bool {
    use std::io::IsTerminal;
    !cli.no_color && std::env::var_os("NO_COLOR").is_none() && std::io::stdout().is_terminal()
}

fn usage_error(message: &str) -> ExitCode {
    eprintln!("grader: {message}");
    ExitCode::from(2)
}

/// Why there is no child program to grade with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NoChild {
    /// The student's code does not compile, or the program is missing:
    /// the run fails (exit 1).
    Failed(String),
    /// The grader does not build the student's code here (see
    /// [`student_child_program`]): said, exit 2.
    Refused(String),
}

/// The `grader` program's `main` after the launcher check: `try ...` or
/// grading, with the student's functions in `program` (given the fixtures
/// folder a grading run reads, none for `try`).
pub fn main_with(
    program: impl FnOnce(Option<&Path>) -> Result<runner::ChildProgram, NoChild>,
) -> ExitCode {
    let args: Vec<OsString> = std::env::args_os().collect();
    let trying = args.get(1).is_some_and(|a| a == "try");
    // Parse before building anything, so a usage error is quick.
    let (grade_cli, try_cli) = if trying {
        (None, Some(trial::TryCli::parse_from(args.iter().skip(1))))
    } else {
        (Some(Cli::parse()), None)
    };
    let fixtures = grade_cli.as_ref().map(fixtures_root);
    let program = match program(fixtures.as_deref()) {
        Ok(p) => p,
        Err(NoChild::Failed(e)) => {
            eprintln!("grader: {e}");
            println!("test failed");
            return ExitCode::from(1);
        }
        Err(NoChild::Refused(e)) => {
            eprintln!("grader: {e}");
            return ExitCode::from(2);
        }
    };
    match (grade_cli, try_cli) {
        (_, Some(t)) => trial::run_try(&t, &program),
        (Some(c), _) => run(&c, &program),
        (None, None) => unreachable!("one of the two was parsed"),
    }
}

/// The hidden cases within this run's reach, if any: `fixtures/hidden` in
/// the lab this grader was built from, in the folder it runs in, or in
/// the fixtures folder it reads.
fn hidden_cases_in_reach(fixtures: Option<&Path>) -> Option<PathBuf> {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lab = manifest.parent().unwrap_or(manifest).join("fixtures");
    [
        Some(lab),
        Some(PathBuf::from("fixtures")),
        fixtures.map(Path::to_path_buf),
    ]
    .into_iter()
    .flatten()
    .map(|f| f.join("hidden"))
    .find(|h| h.exists())
}

/// The `grader` program: the student's functions live in `grader-child`
/// (package `grader-child`), next to this program. Run through cargo
/// (`cargo run -p grader`), it builds that program first, so it always
/// holds the code as it is now; that build is the one that compiles the
/// student's crate, so its output (warnings, errors) goes to the student.
///
/// That build runs with the rights of whoever runs the grader, and
/// compiling is running the crate's code (`include_str!` reads any file
/// the compiler can): where hidden cases are within reach (a TA's lab),
/// it is refused, pointing at the TA's guide, whose way to grade one
/// student's file builds it locked in, in a copy without them.
pub fn student_child_program(fixtures: Option<&Path>) -> Result<runner::ChildProgram, NoChild> {
    let failed = |e: String| NoChild::Failed(e);
    let exe =
        std::env::current_exe().map_err(|e| failed(format!("cannot find this program: {e}")))?;
    let dir = exe
        .parent()
        .ok_or_else(|| failed("this program has no folder".into()))?;
    let child = dir.join(format!("grader-child{}", std::env::consts::EXE_SUFFIX));
    if let Some(cargo) = std::env::var_os("CARGO") {
        if let Some(hidden) = hidden_cases_in_reach(fixtures) {
            return Err(NoChild::Refused(format!(
                "hidden cases are within reach here ({}): the grader does not compile \
                 crates/meshedit where they are, since the code it compiles could read them \
                 (include_str!) with your rights. Grade a student's file as a class of one \
                 (\"Grade a class\", one student by hand, in the guide that came with the \
                 hidden cases), which builds it locked in, in a copy of the lab without them; \
                 to try your own code, grade it in a copy of the lab without fixtures/hidden",
                hidden.display()
            )));
        }
        let profile = match dir.file_name().and_then(|n| n.to_str()) {
            Some("debug") | None => "dev".to_string(),
            Some(name) => name.to_string(),
        };
        let target = dir
            .parent()
            .ok_or_else(|| failed("this program's folder has no parent".into()))?;
        // `cargo run -p grader` did not compile crates/meshedit (this
        // package does not depend on it): this build does, and its
        // warnings and errors go straight to the student, once.
        let built = std::process::Command::new(cargo)
            .args([
                "build",
                "--quiet",
                "-p",
                "grader-child",
                "--bin",
                "grader-child",
            ])
            .arg("--profile")
            .arg(&profile)
            .arg("--target-dir")
            .arg(target)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .status()
            .map_err(|e| failed(format!("cannot run cargo: {e}")))?;
        if !built.success() {
            return Err(failed(
                "your code does not compile: the compiler's messages are above".to_string(),
            ));
        }
    }
    if !child.is_file() {
        return Err(failed(format!(
            "{} is missing: build it with `cargo build -p grader-child`",
            child.display()
        )));
    }
    Ok(runner::ChildProgram {
        exe: child,
        args: Vec::<OsString>::new(),
    })
}

/// Seconds a function that already timed out gets on its later cases.
const SHORT_LIMIT: f64 = 1.0;

/// How many random labellings each case also runs on, besides the mesh as
/// built and (for a flip or split) the two chosen ones.
const RANDOM_LABELLINGS: usize = 2;

/// How many elements the mesh may grow to: generous for any correct answer,
/// small enough to stop runaway splitting in well under a second.
fn budget(fixture: &Fixture) -> usize {
    let e = &fixture.expected;
    // V + E + F + H of the expected result, bounded by 2E for faces and halfedges.
    let expected = e.positions.len() + e.edges.len() * 5;
    (expected * 16).max(10_000)
}

/// A case ready to run: its fixture, its input mesh and every labelling
/// of it the case runs on.
struct Case<'a> {
    fixture: &'a Fixture,
    seed: u64,
    labellings: Vec<relabel::Labelling>,
    /// Record a subdivision's splits for the step-through (`--report`).
    record: bool,
}

impl<'a> Case<'a> {
    fn new(fixture: &'a Fixture, input: halfedge::Mesh, cli: &Cli) -> Case<'a> {
        let seed = cli
            .seed
            .unwrap_or_else(|| relabel::default_seed(&fixture.name));
        let labellings =
            relabel::labellings(&input, fixture.edge_in(&input), seed, RANDOM_LABELLINGS);
        Case {
            fixture,
            seed,
            labellings,
            record: cli.report.is_some() || cli.record_subdivision,
        }
    }

    /// The student calls one run of the case makes: a sequence's run calls
    /// once per step, so its time limit and its share of a budget are
    /// counted in calls.
    fn calls(&self) -> usize {
        self.fixture.steps.len().max(1)
    }

    /// Calls over every labelling.
    fn runs(&self) -> usize {
        self.labellings.len() * self.calls()
    }
}

/// How many cases run side by side: one per core, at most four.
fn workers(cases: usize) -> usize {
    std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, 4)
        .min(cases.max(1))
}

/// Seconds each child run may cost beyond its call (start, lock-in,
/// sending the mesh, judging), and the run's own start (loading and checking
/// the fixtures), as counted against `--budget`.
const RUN_OVERHEAD: f64 = 0.05;
const RUN_START: f64 = 1.0;

/// How long a run may take, worked out from the runs it makes.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Plan {
    /// Child runs if every case passes (one per labelling).
    pub runs: usize,
    /// Most runs of one case.
    pub longest_case: usize,
    pub workers: usize,
    /// Seconds each call may take.
    pub timeout: f64,
    /// `--budget`, when given.
    pub budget: Option<f64>,
}

impl Plan {
    /// The per-call limit: `timeout`, shortened so that `budget` holds the
    /// worst a run can take. Cases run on `workers` side by side, each
    /// case's runs one after another, so (list scheduling) the run ends
    /// within runs/w + (1 - 1/w) x longest case of run-times; a case that
    /// fails stops early and a function that timed out gets a shorter
    /// limit, so that bound holds whatever the student's code does.
    fn new(
        runs: usize,
        longest_case: usize,
        workers: usize,
        timeout: f64,
        budget: Option<f64>,
    ) -> Plan {
        let w = workers.max(1) as f64;
        let slots = runs as f64 / w + (1.0 - 1.0 / w) * longest_case as f64;
        let timeout = match budget {
            Some(b) if slots > 0.0 => {
                // In hundredths of a second, as the messages show it.
                let share = (((b - RUN_START) / slots - RUN_OVERHEAD) * 100.0).floor() / 100.0;
                // Never below the shortest limit the grader takes; the
                // time line says when the budget cannot hold every run.
                timeout.min(share).max(MIN_TIMEOUT)
            }
            _ => timeout,
        };
        Plan {
            runs,
            longest_case,
            workers,
            timeout,
            budget,
        }
    }

    fn of(cases: &[Case], cli: &Cli) -> Plan {
        let runs = cases.iter().map(Case::runs).sum();
        let longest = cases.iter().map(Case::runs).max().unwrap_or(0);
        Plan::new(runs, longest, workers(cases.len()), cli.timeout, cli.budget)
    }

    /// The line the text report gives it when `--budget` shortened the limit.
    pub fn describe(&self, asked: f64) -> Option<String> {
        let budget = self.budget?;
        (self.timeout < asked).then(|| {
            format!(
                "time: each call may take {:.2} s, not {asked} s, so that {} runs ({} side by side) fit in the budget of {budget} s",
                self.timeout, self.runs, self.workers
            )
        })
    }
}

/// The shortest `--timeout` taken.
const MIN_TIMEOUT: f64 = 0.1;

/// Grades one case on every labelling of its input, stopping at the first
/// that fails. `Err` when the sandbox could not be set up.
fn grade_case(
    case: &Case,
    program: &runner::ChildProgram,
    limits: &sandbox::Limits,
    timeout: Duration,
    protections: &mut Option<isolate::protections::Protections>,
) -> Result<verdict::CaseReport, String> {
    use crate::isolate::end::CaseEnd;
    let f = case.fixture;
    let (seed, labellings) = (case.seed, &case.labellings);
    let budget = budget(f);
    let mut first = None;
    // The labellings of this case share a child while their calls come
    // back (see `docs/architecture.md`).
    let mut session = runner::Session::new(program, limits);
    for (i, l) in labellings.iter().enumerate() {
        let op = match (f.operation, l.edge) {
            (Operation::Flip { .. }, Some(e)) => wire::Op::Flip(e),
            (Operation::Split { .. }, Some(e)) => wire::Op::Split(e),
            (Operation::Subdivide { rounds }, _) => wire::Op::Subdivide {
                rounds: rounds as u32,
            },
            (Operation::Sequence { .. }, _) => wire::Op::Sequence,
            _ => return Err(format!("{}: the case's edge was lost", f.name)),
        };
        // Input vertices by their id in this labelling; a split's vertex
        // keeps its name past them (the child resolves it).
        let n = l.vertices.len();
        let name = |v: usize| {
            if v < n {
                l.vertices[v].0
            } else {
                v as u32
            }
        };
        let steps = f
            .steps
            .iter()
            .map(|s| wire::WireStep {
                split: s.is_split(),
                ends: s.edge().map(name),
            })
            .collect();
        let request = wire::Request {
            op,
            steps,
            budget: budget as u64,
            mesh: l.mesh.clone(),
        };
        let record = case.record && matches!(op, wire::Op::Subdivide { .. });
        // A recording adds its frames (at most its byte bound, and their
        // counts) to the result.
        let recording = if record {
            halfedge::recording::Limits::default().bytes + (1 << 20)
        } else {
            0
        };
        let max_result = budget * 64 + (1 << 20) + recording;
        let run = |session: &mut runner::Session| -> Result<runner::ChildReport, String> {
            let mut report = session
                .run(&request, record, timeout, max_result)
                .map_err(|e| format!("cannot start a grading process: {e}"))?;
            match &mut report.end {
                CaseEnd::SandboxFailed { why } => {
                    return Err(format!("the grading sandbox could not be set up: {why}"))
                }
                CaseEnd::Sequence(seq) => to_input_names(&mut seq.steps, &l.vertices),
                _ => {}
            }
            Ok(report)
        };
        // The judge walks data the student's code made: a panic there is
        // the grader's bug, said as such, never a crash of the whole run.
        let judged = |child_report: &runner::ChildReport| match isolate::guard::guarded(|| {
            grade::judge(f, child_report)
        }) {
            Ok(r) => r,
            Err((message, _)) => grade::judge_failed(f, &message, &child_report.output),
        };
        let mut child_report = run(&mut session)?;
        let mut report = judged(&child_report);
        // A call that did not pass in a child that served an earlier one
        // is run again in a fresh child, and that run is judged: nothing
        // an earlier call left behind (a static, a thread, a leak against
        // the memory cap) decides a failure.
        if !report.passed && !session.last_was_fresh() {
            session.restart();
            child_report = run(&mut session)?;
            report = judged(&child_report);
        }
        if protections.is_none() {
            *protections = child_report.sandbox;
        }
        let result = child_report.mesh.take();
        let recorded = child_report.recorded.take();
        report.input = Some(l.mesh.clone());
        report.result = result;
        if let Some(recorded) = recorded {
            let frames = frames::read(recorded, report.result.as_ref(), &l.mesh, f.tolerance);
            grade::note_frames(&mut report, frames);
        }
        if !report.passed {
            if i > 0 {
                grade::note_labelling(&mut report, f, l, i, labellings.len(), seed);
            }
            return Ok(report);
        }
        first.get_or_insert(report);
    }
    first.ok_or_else(|| format!("{}: no labelling ran", f.name))
}

/// The child names a sequence's input vertices by their ids in the
/// labelling sent (and split vertices past them): back to input indices,
/// the fixture's names.
fn to_input_names(steps: &mut [wire::StepRan], vertices: &[halfedge::VertexId]) {
    let mut input = vec![0; vertices.len()];
    for (i, v) in vertices.iter().enumerate() {
        input[v.index()] = i as u32;
    }
    let name = |x: &mut u32| {
        if let Some(&i) = input.get(*x as usize) {
            *x = i;
        }
    };
    for s in steps {
        match &mut s.answer {
            wire::StepAnswer::Edge {
                ends: Some([a, b]), ..
            } => {
                name(a);
                name(b);
            }
            wire::StepAnswer::Vertex { name: Some(v), .. } => name(v),
            _ => {}
        }
    }
}

/// Grades every case, two or more side by side (one per core, at most
/// four), and returns the reports in the cases' order and the launcher's
/// status. Once a function has timed out, its cases that start later get a
/// short limit: an endless loop should cost the full limit once, not once
/// per case.
fn grade_all(
    cases: &[Case],
    timeout: f64,
    program: &runner::ChildProgram,
    limits: &sandbox::Limits,
) -> Result<
    (
        Vec<verdict::CaseReport>,
        Option<isolate::protections::Protections>,
    ),
    String,
> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Mutex;
    let workers = workers(cases.len());
    let next = AtomicUsize::new(0);
    let timed_out: Mutex<Vec<(Stage, String)>> = Mutex::new(Vec::new());
    let protections: Mutex<Option<isolate::protections::Protections>> = Mutex::new(None);
    let results: Mutex<Vec<Option<Result<verdict::CaseReport, String>>>> =
        Mutex::new(vec![None; cases.len()]);
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(case) = cases.get(i) else {
                    return;
                };
                let stage = case.fixture.operation.stage();
                let earlier = timed_out
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .iter()
                    .find(|(s, _)| *s == stage)
                    .map(|(_, n)| n.clone());
                let limit = match &earlier {
                    Some(_) => timeout.min(SHORT_LIMIT),
                    None => timeout,
                } * case.calls() as f64;
                let mut status = None;
                let result = grade_case(
                    case,
                    program,
                    limits,
                    Duration::from_secs_f64(limit),
                    &mut status,
                )
                .map(|mut r| {
                    if r.timed_out {
                        match &earlier {
                            Some(name) => grade::add_detail(
                                &mut r,
                                format!(
                                    "the limit was cut to {limit} s because {} already timed out on {name}",
                                    stage.function()
                                ),
                            ),
                            None => timed_out
                                .lock()
                                .unwrap_or_else(|e| e.into_inner())
                                .push((stage, r.name.clone())),
                        }
                    }
                    r
                });
                let mut first = protections.lock().unwrap_or_else(|e| e.into_inner());
                if first.is_none() {
                    *first = status;
                }
                drop(first);
                results.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(result);
            });
        }
    });
    let reports = results
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .map(|r| r.unwrap_or_else(|| Err("a case was not graded".into())))
        .collect::<Result<Vec<_>, String>>()?;
    Ok((
        reports,
        protections.into_inner().unwrap_or_else(|e| e.into_inner()),
    ))
}

/// What a run that graded only part of the lab graded, in words.
fn partial_run(cli: &Cli) -> Option<String> {
    match (&cli.case, cli.stage) {
        (Some(case), _) => Some(format!("--case {case}")),
        (None, Some(stage)) => Some(format!("--stage {}", stage.key())),
        (None, None) => None,
    }
}

/// Grades per the command line, running the cases in `program`.
pub fn run(cli: &Cli, program: &runner::ChildProgram) -> ExitCode {
    let started = std::time::Instant::now();
    #[cfg(unix)]
    if cli.watch && !watch::is_inner() {
        let file = cli.watch_file.clone().unwrap_or_else(watch::default_file);
        return watch::watch(&file);
    }
    if !(cli.timeout >= MIN_TIMEOUT && cli.timeout <= 3600.0) {
        return usage_error(&format!(
            "--timeout {} is out of range: give a number of seconds from 0.1 to 3600",
            cli.timeout
        ));
    }
    text::set_rewording(cli.reword_messages);
    let root = fixtures_root(cli);
    let all = match fixture::load_all(&root) {
        Ok(all) => all,
        Err(e) => return usage_error(&format!("bad fixture: {e}: tell a TA")),
    };
    let mut cases = Vec::new();
    for f in &all {
        match f.input_mesh() {
            Ok(input) => cases.push((f, input)),
            Err(e) => {
                return usage_error(&format!(
                    "bad fixture: {}: {e}: tell a TA",
                    root.join(f.relative_path()).display()
                ))
            }
        }
    }
    cases.retain(|(f, _)| {
        cli.case.as_ref().is_none_or(|n| *n == f.name)
            && cli.stage.is_none_or(|s| s == f.operation.stage())
    });
    let cases: Vec<Case> = cases
        .into_iter()
        .map(|(f, input)| Case::new(f, input, cli))
        .collect();
    if let Some(name) = &cli.case {
        if cases.is_empty() {
            let names: Vec<&str> = all.iter().map(|f| f.name.as_str()).collect();
            let stage = if cli.stage.is_some() {
                " with the --stage given"
            } else {
                ""
            };
            return usage_error(&format!(
                "no case named {name:?}{stage}; the cases are: {}",
                names.join(", ")
            ));
        }
    }
    if cases.is_empty() {
        return usage_error(&format!("no cases found in {}", root.display()));
    }
    if cli.list && cli.format == Format::Json {
        // What scripts need to share out a time budget: the runs per case.
        let list: Vec<serde_json::Value> = cases
            .iter()
            .map(|c| {
                serde_json::json!({
                    "name": c.fixture.name,
                    "group": c.fixture.group,
                    "stage": c.fixture.operation.stage(),
                    "runs": c.runs(),
                })
            })
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&list).expect("the list serializes")
        );
        return ExitCode::SUCCESS;
    }
    if cli.list {
        for c in &cases {
            let f = c.fixture;
            println!(
                "{:<28} {:<7} {}",
                f.name,
                f.group.name(),
                f.operation.stage().function()
            );
        }
        return ExitCode::SUCCESS;
    }

    isolate::process::become_subreaper();
    let limits = sandbox::Limits {
        memory: cli.memory,
        drop_user: true,
        landlock: !cli.without_landlock,
        pid_namespace: !cli.without_pid_namespace,
    };
    if let Some(b) = cli.budget {
        if !(b > 0.0 && b <= 86_400.0) {
            return usage_error(&format!(
                "--budget {b} is out of range: give a number of seconds up to 86400"
            ));
        }
    }
    let plan = Plan::of(&cases, cli);
    let reports = match grade_all(&cases, plan.timeout, program, &limits) {
        Ok(r) => r,
        Err(e) => return usage_error(&e),
    };
    let (mut reports, protections): (Vec<_>, Option<isolate::protections::Protections>) = reports;
    grade::note_dependencies(&mut reports);
    // Quadratic code: timed once subdivision is right (a warning only).
    let asked = cli.case.is_none()
        && cli.stage.is_none_or(|s| s == Stage::Subdivide)
        && (cli.budget.is_none() || cli.time_subdivision);
    let deadline = cli.budget.map(|b| started + Duration::from_secs_f64(b));
    let scaling = scaling::wanted(&reports, asked)
        .then(|| timing::measure(program, &limits, plan.timeout, deadline))
        .flatten();
    // Naming a bonus case is asking for it to count.
    let bonus = cli.bonus || cli.case.is_some();
    let protections = report::protections::line(
        protections.as_ref(),
        isolate::process::grader_not_dumpable(),
    );
    let time_line = plan.describe(cli.timeout);
    let protections_json = protections.clone();
    let report_path = match &cli.report {
        None => None,
        Some(dir) => {
            let pairs: Vec<(&Fixture, &verdict::CaseReport)> =
                cases.iter().map(|c| c.fixture).zip(&reports).collect();
            #[cfg(unix)]
            let live = watch::is_inner();
            #[cfg(not(unix))]
            let live = false;
            match html::write_report_live(dir, &pairs, live) {
                Ok(index) => Some(index),
                Err(e) => return usage_error(&format!("cannot write the report: {e}")),
            }
        }
    };

    let output = match cli.format {
        Format::Text => report::text(
            &reports,
            &report::TextOptions {
                bonus,
                color: use_color(cli),
                protections,
                verbose: cli.verbose,
                quiet: cli.quiet,
                partial: partial_run(cli),
                report: report_path.as_ref().map(|p| p.display().to_string()),
                focus: cli.case.clone(),
                time: time_line,
                scaling: scaling.clone(),
            },
        ),
        Format::Json => report::json(&reports, bonus, &protections_json, &plan, scaling.as_ref()),
    };
    print!("{output}");
    if let Some(path) = &cli.gradescope {
        if let Err(e) = std::fs::write(path, report::gradescope(&reports, bonus)) {
            return usage_error(&format!("cannot write {}: {e}", path.display()));
        }
    }
    if report::all_passed(&reports, bonus) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_budget_shortens_the_limit_by_the_runs_it_must_hold() {
        // Ample: the limit asked for stays.
        assert_eq!(Plan::new(120, 5, 1, 0.4, Some(100.0)).timeout, 0.4);
        // One worker: every run one after another.
        let p = Plan::new(120, 5, 1, 10.0, Some(61.0));
        assert_eq!(p.timeout, 0.45, "{p:?}");
        // Two: half the runs, plus what the longest case may leave over.
        let p = Plan::new(120, 5, 2, 10.0, Some(63.5));
        assert_eq!(p.timeout, 0.95, "{p:?}");
        // No budget, or one too short: the limit asked for, or the shortest.
        assert_eq!(Plan::new(120, 5, 1, 3.0, None).timeout, 3.0);
        assert_eq!(Plan::new(120, 5, 1, 3.0, Some(2.0)).timeout, MIN_TIMEOUT);
    }
}
