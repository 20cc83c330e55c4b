//! The grader's command line: its options ([`Cli`], parsed by clap),
//! where the fixtures are by default, whether to colour, and how a run
//! that graded part of the lab names what it graded.

use std::path::{Path, PathBuf};

use clap::{Parser, ValueEnum};

use crate::judge::fixture::Stage;

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
pub(crate) fn fixtures_root(cli: &Cli) -> PathBuf {
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

pub(crate) fn use_color(cli: &Cli) -> bool {
    use std::io::IsTerminal;
    !cli.no_color && std::env::var_os("NO_COLOR").is_none() && std::io::stdout().is_terminal()
}

/// What a run that graded only part of the lab graded, in words.
pub(crate) fn partial_run(cli: &Cli) -> Option<String> {
    match (&cli.case, cli.stage) {
        (Some(case), _) => Some(format!("--case {case}")),
        (None, Some(stage)) => Some(format!("--stage {}", stage.key())),
        (None, None) => None,
    }
}
