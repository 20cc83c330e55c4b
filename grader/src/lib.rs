//! # The grader
//!
//! Grades the three functions of `crates/meshedit` against the cases in
//! `fixtures/`, and reports in the lab's words. Each case runs in a child
//! process (this program started again, see [`runner`]), so a student
//! function that panics, loops, overflows the stack or aborts fails its case
//! and the grader carries on.
//!
//! - [`fixture`]: the case format, shared with the reference's generator.
//! - [`child`]: what runs in the child: the student function, then a
//!   description of the result.
//! - [`runner`]: starting the child, the time limit, capturing output.
//! - [`matching`]: order-independent comparison of vertices and edges.
//! - [`grade`]: the verdict and messages for one case.
//! - [`report`]: text, JSON and Gradescope output.
//!
//! The binary is `main.rs`: [`main_with`] the student's functions. Tests
//! call [`main_with`] with other implementations (see `reference/`).

pub mod child;
pub mod fixture;
pub mod grade;
pub mod matching;
pub mod report;
pub mod runner;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Parser, ValueEnum};
use halfedge::{EdgeId, Mesh, VertexId};

use crate::fixture::{Fixture, Stage};

/// The three functions being graded.
#[derive(Clone, Copy)]
pub struct Implementation {
    pub flip_edge: fn(&mut Mesh, EdgeId) -> Option<EdgeId>,
    pub split_edge: fn(&mut Mesh, EdgeId) -> Option<VertexId>,
    pub loop_subdivide: fn(&mut Mesh),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Text,
    Json,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum StageArg {
    Flip,
    Split,
    Subdivide,
}

impl StageArg {
    fn stage(self) -> Stage {
        match self {
            StageArg::Flip => Stage::Flip,
            StageArg::Split => Stage::Split,
            StageArg::Subdivide => Stage::Subdivide,
        }
    }
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
    pub stage: Option<StageArg>,
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
    /// Seconds each case may run before it counts as an endless loop.
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
    pub timeout: f64,
    /// Never colour `[warn]` lines (also off when NO_COLOR is set or output is
    /// not a terminal).
    #[arg(long)]
    pub no_color: bool,
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

/// The grader's `main`, for any implementation of the three functions.
/// In a child process (see [`runner`]) it runs one case instead.
pub fn main_with(imp: Implementation) -> ExitCode {
    if let Some(code) = run_child_if_asked(&imp) {
        return code;
    }
    let cli = Cli::parse();
    run(&cli)
}

/// In a child process started by [`runner`], runs its one case with `imp`
/// and returns the exit code; otherwise `None`. A program that grades must
/// call this before anything else (after choosing `imp` the same way the
/// parent did).
pub fn run_child_if_asked(imp: &Implementation) -> Option<ExitCode> {
    let case = std::env::var_os(runner::CHILD_FIXTURE_ENV)?;
    let result = std::env::var_os(runner::CHILD_RESULT_ENV)?;
    let code = child::child_main(Path::new(&case), Path::new(&result), imp);
    Some(ExitCode::from(code as u8))
}

/// Grades per the command line; the child processes run the cases.
pub fn run(cli: &Cli) -> ExitCode {
    if !(cli.timeout > 0.0 && cli.timeout.is_finite()) {
        return usage_error("--timeout must be a positive number of seconds");
    }
    let root = fixtures_root(cli);
    let all = match fixture::load_all(&root) {
        Ok(all) => all,
        Err(e) => return usage_error(&format!("bad fixture: {e}")),
    };
    let selected: Vec<&Fixture> = all
        .iter()
        .filter(|f| cli.case.as_ref().is_none_or(|c| *c == f.name))
        .filter(|f| cli.stage.is_none_or(|s| s.stage() == f.operation.stage()))
        .collect();
    if let Some(name) = &cli.case {
        if selected.is_empty() {
            let names: Vec<&str> = all.iter().map(|f| f.name.as_str()).collect();
            return usage_error(&format!(
                "no case named {name:?} (with the --stage given); the cases are: {}",
                names.join(", ")
            ));
        }
    }
    if selected.is_empty() {
        return usage_error(&format!("no cases found in {}", root.display()));
    }
    if cli.list {
        for f in &selected {
            println!(
                "{:<28} {:<7} {}",
                f.name,
                f.group.name(),
                f.operation.stage().function()
            );
        }
        return ExitCode::SUCCESS;
    }

    let timeout = Duration::from_secs_f64(cli.timeout);
    let mut reports = Vec::new();
    for f in &selected {
        let path = root.join(f.relative_path());
        let child = match runner::run_child(&path, &f.name, timeout) {
            Ok(c) => c,
            Err(e) => return usage_error(&format!("cannot start a grading process: {e}")),
        };
        reports.push(grade::judge(f, &child));
    }
    grade::note_dependencies(&mut reports);
    // Naming a bonus case is asking for it to count.
    let bonus = cli.bonus || cli.case.is_some();

    let output = match cli.format {
        Format::Text => report::text(&reports, bonus, use_color(cli)),
        Format::Json => report::json(&reports, bonus),
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
