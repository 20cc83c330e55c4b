//! The `autograde` program: one submission graded for a platform.
//!
//! - `autograde gradescope --budget S --timeout S [--bonus]`: Gradescope's
//!   per-submission step (`run_autograder` execs it); `MESHLAB_BUDGET` and
//!   `MESHLAB_CASE_TIMEOUT` replace the two limits (tests).
//! - `autograde gradescope-setup`: once per image, after `run_autograder
//!   --setup` built this program (`setup::gradescope`: fixtures, vendored
//!   crates, the build user's toolchain and target folder, the first
//!   locked-in build); `MESHLAB_BUILD_TARGET` and `MESHLAB_VENDOR` name
//!   the target folder and the vendored crates (tests).
//! - `autograde gradescope-warm`: the first locked-in build alone.
//! - `autograde classroom50 --lab DIR`: Classroom 50's step (its
//!   `autograder.py` runs it in the student's checkout): writes
//!   `./result.json` (`classroom50/result/v1`).
//! - `autograde prairielearn --lab DIR [--root /grade]`: PrairieLearn's
//!   external grader: the upload in `ROOT/student`, the results in
//!   `ROOT/results/results.json`.
//!
//! The last two grade on `--fixtures` (default `LAB/fixtures`: keep hidden
//! cases outside the lab, which the build may read); `MESHLAB_BUILD_TARGET`
//! and `MESHLAB_VENDOR` name the build's target folder and vendored crates
//! (tests keep them between runs).
//!
//! It is also the build launcher its builds go through (the grader's
//! `--meshlab-build-launch`) and the reaper its graders run under
//! (`--meshlab-reap`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use autograde::gradescope::{self, Options, Places};
use autograde::local::Local;
use autograde::platform::{self, Classroom50};

const USAGE: &str = "usage: autograde gradescope --budget SECONDS --timeout SECONDS [--bonus]\n       \
                     autograde gradescope-setup\n       \
                     autograde gradescope-warm\n       \
                     autograde classroom50 --lab DIR [--fixtures DIR] [--budget SECONDS] [--timeout SECONDS]\n       \
                     autograde prairielearn --lab DIR --fixtures DIR [--root DIR] [--budget SECONDS] \
                     [--timeout SECONDS]";

/// `--key value` pairs and flags after a command.
fn options(
    rest: Vec<String>,
    keys: &[&str],
    flags: &[&str],
) -> Result<Vec<(String, String)>, String> {
    let mut out = Vec::new();
    let mut it = rest.into_iter();
    while let Some(arg) = it.next() {
        if flags.contains(&arg.as_str()) {
            out.push((arg, String::new()));
        } else if keys.contains(&arg.as_str()) {
            let value = it.next().ok_or(format!("{arg} needs a value\n{USAGE}"))?;
            out.push((arg, value));
        } else {
            return Err(format!("unknown option {arg:?}\n{USAGE}"));
        }
    }
    Ok(out)
}

fn get(opts: &[(String, String)], key: &str) -> Option<String> {
    opts.iter()
        .rev()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.clone())
}

fn local(opts: &[(String, String)], submission: PathBuf) -> Result<Local, String> {
    let lab = get(opts, "--lab").ok_or(format!("--lab is missing\n{USAGE}"))?;
    let lab = std::path::absolute(&lab).map_err(|e| e.to_string())?;
    if !lab.join("Cargo.toml").is_file() {
        return Err(format!(
            "{}: not the autograder's lab (no Cargo.toml)",
            lab.display()
        ));
    }
    let fixtures = match get(opts, "--fixtures") {
        Some(f) => std::path::absolute(f).map_err(|e| e.to_string())?,
        None => lab.join("fixtures"),
    };
    let env_path = |k: &str| std::env::var_os(k).map(PathBuf::from);
    Ok(Local {
        fixtures,
        target: env_path("MESHLAB_BUILD_TARGET"),
        vendor: env_path("MESHLAB_VENDOR"),
        lab,
        submission,
        budget: seconds(
            get(opts, "--budget").or(Some("600".into())),
            "MESHLAB_BUDGET",
            "--budget",
        )?,
        timeout: seconds(
            get(opts, "--timeout").or(Some("10".into())),
            "MESHLAB_CASE_TIMEOUT",
            "--timeout",
        )?,
        bonus: false,
    })
}

fn write_json(path: &Path, value: &serde_json::Value) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let text = serde_json::to_string_pretty(value).expect("JSON");
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

fn seconds(value: Option<String>, env: &str, what: &str) -> Result<f64, String> {
    let text = std::env::var(env)
        .ok()
        .or(value)
        .ok_or(format!("{what} is missing\n{USAGE}"))?;
    match text.parse::<f64>() {
        Ok(s) if s > 0.0 && s <= 86_400.0 => Ok(s),
        _ => Err(format!(
            "{what}: expected a number of seconds above 0 and at most a day, got {text:?}"
        )),
    }
}

fn run(args: Vec<String>) -> Result<(), String> {
    let mut it = args.into_iter();
    let command = it.next().ok_or(USAGE)?;
    let rest: Vec<String> = it.collect();
    match command.as_str() {
        "gradescope" => {
            let (mut budget, mut timeout, mut bonus) = (None, None, false);
            let mut it = rest.into_iter();
            while let Some(arg) = it.next() {
                match arg.as_str() {
                    "--budget" => budget = it.next(),
                    "--timeout" => timeout = it.next(),
                    "--bonus" => bonus = true,
                    other => return Err(format!("unknown option {other:?}\n{USAGE}")),
                }
            }
            let options = Options {
                budget: seconds(budget, "MESHLAB_BUDGET", "--budget")?,
                timeout: seconds(timeout, "MESHLAB_CASE_TIMEOUT", "--timeout")?,
                bonus,
            };
            gradescope::run(&Places::from_env(), &options)
        }
        "classroom50" => {
            let opts = options(rest, &["--lab", "--fixtures", "--budget", "--timeout"], &[])?;
            let here = std::env::current_dir().map_err(|e| e.to_string())?;
            let local = local(&opts, here.clone())?;
            autograde::process::become_subreaper();
            let outcome = autograde::local::grade(&local, &|line| eprintln!("{line}"))?;
            let var = |k: &str| std::env::var(k).unwrap_or_default();
            let ids = Classroom50 {
                classroom: var("CLASSROOM"),
                assignment: var("ASSIGNMENT"),
                submission: var("SUBMISSION_TAG"),
                commit: var("COMMIT_URL"),
                release: var("RELEASE_URL"),
                review: var("REVIEW_URL"),
                // The runner's clock, now: the checkout's commit dates are
                // the student's to set, and reading them ran git with the
                // student's configuration (a `gpg.program` of theirs).
                datetime: autograde::clock::iso8601(autograde::clock::now()),
            };
            let result = platform::classroom50(&outcome, &ids);
            write_json(&here.join("result.json"), &result)?;
            println!("{}/{} points", result["score"], result["max-score"]);
            Ok(())
        }
        "prairielearn" => {
            let opts = options(
                rest,
                &["--lab", "--fixtures", "--root", "--budget", "--timeout"],
                &[],
            )?;
            let root = PathBuf::from(get(&opts, "--root").unwrap_or_else(|| "/grade".into()));
            let local = local(&opts, root.join("student"))?;
            autograde::process::become_subreaper();
            let results = match autograde::local::grade(&local, &|line| eprintln!("{line}")) {
                Ok(outcome) => platform::prairielearn(&outcome),
                // The student still gets a result; the reason is the TA's.
                Err(why) => serde_json::json!({
                    "gradable": false,
                    "message": "The autograder failed; tell your TA.",
                    "format_errors": [format!("autograder error: {why}")],
                }),
            };
            write_json(&root.join("results/results.json"), &results)
        }
        "gradescope-setup" if rest.is_empty() => {
            let start = std::time::Instant::now();
            autograde::setup::gradescope(&Places::from_env(), &|line| {
                println!("[{:6.1} s] {line}", start.elapsed().as_secs_f64())
            })
        }
        "gradescope-warm" if rest.is_empty() => {
            println!("{}", gradescope::warm(&Places::from_env())?);
            Ok(())
        }
        _ => Err(USAGE.into()),
    }
}

fn main() -> ExitCode {
    autograde::build::launch_if_asked();
    autograde::process::reap_if_asked();
    match run(std::env::args().skip(1).collect()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("autograde: {e}");
            ExitCode::from(2)
        }
    }
}
