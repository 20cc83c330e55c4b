//! `gradescope`: the Gradescope bundle written out, and the per-call limit
//! its budget gives.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use reference::{handout, lab_root};

use super::{check_seconds, Outcome};

#[derive(clap::Args)]
pub struct Args {
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
}

pub fn run(args: Args) -> Outcome {
    let Args {
        dir,
        bonus,
        budget,
        timeout,
        fresh_sets,
    } = args;
    check_seconds(budget, "--budget")?;
    check_seconds(timeout, "--timeout")?;
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
    println!("{}", limit(&dir, budget, timeout)?);
    Ok(ExitCode::SUCCESS)
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
fn limit(dir: &Path, budget: f64, timeout: f64) -> Result<String, String> {
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
