//! `class`: a folder of submissions graded (the work is in
//! `reference::class`); this module turns the options into its `Options`
//! and prints one line a row.

use std::path::PathBuf;
use std::process::ExitCode;

use reference::lab_root;

use super::{check_seconds, Outcome};

#[derive(clap::Args)]
pub struct Args {
    submissions: PathBuf,
    /// Where the reports go.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Keep the builds (target/ and vendor/) in DIR, outside the lab, to
    /// reuse the compiled dependencies next time; by default a new
    /// private temporary folder, removed at the end.
    #[arg(long, value_name = "DIR")]
    build_dir: Option<PathBuf>,
    /// Seconds each case may run.
    #[arg(long, default_value_t = 5.0)]
    timeout: f64,
    /// Seconds one submission's grading may take, all cases together.
    #[arg(long, default_value_t = 300.0)]
    budget: f64,
    /// Count the bonus cases.
    #[arg(long)]
    bonus: bool,
    /// Grade on the fixtures alone, without each submission's fresh
    /// cases (random meshes drawn from a seed per submission).
    #[arg(long)]
    no_fresh: bool,
    /// No progress lines.
    #[arg(short, long)]
    quiet: bool,
    /// Regrade only these submissions (row names) and merge their rows
    /// into the summary already in --out.
    #[arg(long, value_name = "NAME", num_args = 1..)]
    only: Vec<String>,
    /// Submissions are git repositories (one per student): grade each
    /// one's last commit before DATE ("2026-12-01 23:59 +0100"), read
    /// out without checking anything out; commits.csv names them.
    #[arg(long, value_name = "DATE")]
    before: Option<String>,
}

pub fn run(args: Args) -> Outcome {
    check_seconds(args.budget, "--budget")?;
    check_seconds(args.timeout, "--timeout")?;
    // Absolute: cargo runs in the scratch copy, not here.
    let here = std::env::current_dir().map_err(|e| e.to_string())?;
    let options = reference::class::Options {
        timeout: args.timeout,
        budget: args.budget,
        bonus: args.bonus,
        build_dir: args.build_dir.map(|d| here.join(d)),
        // This program: its main starts the build launcher.
        launcher: std::env::current_exe().map_err(|e| e.to_string())?,
        build_memory: grader::isolate::build_sandbox::DEFAULT_MEMORY,
        build_seconds: None,
        fresh: !args.no_fresh,
        progress: !args.quiet,
        grader_args: Vec::new(),
        landlock: true,
        only: args.only,
        before: args.before,
    };
    let rows = reference::class::grade_class(&lab_root(), &args.submissions, &args.out, &options)?;
    for r in &rows {
        println!(
            "{:<24} {:>5} / {:<5} {:<16} {}",
            r.name, r.score, r.max, r.status, r.first_failure
        );
    }
    println!(
        "wrote {} reports and {}",
        rows.len(),
        args.out.join("summary.csv").display()
    );
    Ok(ExitCode::SUCCESS)
}
