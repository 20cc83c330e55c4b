//! Building one submission locked in and grading it one stage at a time:
//! the same steps for class grading and every platform. The time left is
//! shared out among the stages by the child runs each makes, as the grader
//! counts them (`--list --format json`: a passing case runs once per
//! labelling); each stage's grader shortens its per-call limit to fit its
//! share, and a deadline stops only what ignores limits.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use crate::build::{Build, Report};

use crate::process::run_limited;

/// One stage: (the grader's stage and fixture kind, the class CSV's
/// column, the function's name as students read it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stage {
    pub stage: &'static str,
    pub column: &'static str,
    pub function: &'static str,
}

/// The three functions and the sequence stage, in grading order.
pub const STAGES: [Stage; 4] = [
    Stage {
        stage: "flip",
        column: "flip_edge",
        function: "flip_edge",
    },
    Stage {
        stage: "split",
        column: "split_edge",
        function: "split_edge",
    },
    Stage {
        stage: "sequence",
        column: "in_sequence",
        function: "flips and splits in sequence",
    },
    Stage {
        stage: "subdivide",
        column: "loop_subdivide",
        function: "loop_subdivide",
    },
];

/// Seconds of a stage's share kept from its grader (for its own start and
/// end): the deadline that stops it is the whole share.
const STAGE_MARGIN: f64 = 1.0;
/// Most lines of compiler output shown.
const COMPILER_LINES: usize = 150;

/// The programs a locked-in build makes and grading runs, in the build's
/// `debug` folder: the grader (none of the student's code) and the child
/// (with it). The one place that names them.
pub const PROGRAMS: [&str; 2] = ["grader", "grader-child"];

/// Where the build leaves [`PROGRAMS`].
pub fn programs_dir(target: &Path) -> PathBuf {
    target.join("debug")
}

/// Counted cases per stage (in [`STAGES`] order) in a fixtures folder.
pub fn counted(fixtures: &Path, bonus: bool) -> [usize; 4] {
    let mut counts = [0; 4];
    let groups: &[&str] = if bonus {
        &["lab", "hidden", "bonus"]
    } else {
        &["lab", "hidden"]
    };
    for group in groups {
        let mut paths: Vec<PathBuf> = std::fs::read_dir(fixtures.join(group))
            .into_iter()
            .flatten()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect();
        paths.sort();
        for path in paths {
            let Some(f) = std::fs::read_to_string(&path)
                .ok()
                .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            else {
                continue;
            };
            if let Some(i) = STAGES
                .iter()
                .position(|s| f["operation"]["kind"] == s.stage)
            {
                counts[i] += 1;
            }
        }
    }
    counts
}

/// How a locked-in build went.
#[derive(Clone, Debug)]
pub struct Built {
    /// The launcher's status file.
    pub report: Report,
    /// Cargo's whole output (standard error).
    pub log: String,
    pub seconds: f64,
}

impl Built {
    /// The compiler's words: cargo's output without its progress lines,
    /// at most [`COMPILER_LINES`] lines (raw student text: quote it).
    pub fn compiler(&self) -> String {
        compiler_text(&self.log)
    }

    /// Whether the compiler said anything beyond cargo's progress lines:
    /// on a build that succeeded, that is warnings (rustc prints nothing
    /// else then). A fact about the output, not a reading of its words.
    pub fn said_something(&self) -> bool {
        !self.compiler().is_empty()
    }
}

/// Cargo's output without its progress lines, trimmed.
pub fn compiler_text(stderr: &str) -> String {
    const PROGRESS: [&str; 8] = [
        "Compiling ",
        "Finished ",
        "Blocking ",
        "Locking ",
        "Updating ",
        "Downloading ",
        "Downloaded ",
        "Checking ",
    ];
    let kept: Vec<&str> = stderr
        .lines()
        .filter(|l| !PROGRESS.iter().any(|p| l.trim_start().starts_with(p)))
        .collect();
    let text = kept.join("\n");
    let lines: Vec<&str> = text.trim().lines().collect();
    if lines.len() > COMPILER_LINES {
        format!(
            "{}\n... ({} more lines)",
            lines[..COMPILER_LINES].join("\n"),
            lines.len() - COMPILER_LINES
        )
    } else {
        lines.join("\n")
    }
}

/// Runs `build` through `launcher` (a program whose `main` calls
/// [`crate::build::launch_if_asked`]), its output in `logs`. An
/// error is the TA's (the launcher missing), never the student's.
pub fn build(build: &Build, launcher: &Path, logs: &Path) -> Result<Built, String> {
    let _ = std::fs::remove_file(&build.status);
    let mut cmd = Command::new(launcher);
    cmd.args(build.args()).env_clear().current_dir("/");
    let (out, err) = (logs.join("build.out"), logs.join("build.err"));
    let start = Instant::now();
    // The launcher keeps the time limit itself; this is for one that hangs.
    let code = run_limited(
        cmd,
        &out,
        &err,
        Duration::from_secs_f64(build.seconds + 30.0),
    )?;
    let report = Report::read(&build.status).map_err(|e| {
        format!(
            "the build launcher {} failed (exit {code:?}): {e}",
            launcher.display()
        )
    })?;
    let log = std::fs::read_to_string(&err).unwrap_or_default();
    Ok(Built {
        report,
        log,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// How to grade a built submission.
#[derive(Clone, Debug)]
pub struct Grading {
    /// The grader program (with the child beside it).
    pub exe: PathBuf,
    /// Where it runs (the submission's copy of the lab).
    pub cwd: PathBuf,
    pub fixtures: PathBuf,
    /// Seconds each call may take at most.
    pub timeout: f64,
    pub bonus: bool,
    /// Where each stage's output goes.
    pub logs: PathBuf,
    /// The reaper program each stage's grader runs under (see
    /// [`crate::process::reaped`]): this program, or `reference`.
    pub reaper: PathBuf,
    /// More options for every stage's grader.
    pub extra_args: Vec<String>,
}

/// How one stage's grading went.
#[derive(Clone, Debug)]
pub struct StageRun {
    pub stage: Stage,
    /// Counted cases of the stage.
    pub cases: usize,
    /// Seconds it was given.
    pub budget: f64,
    /// The grader's exit code; `None`: stopped at the deadline.
    pub code: Option<i32>,
    pub seconds: f64,
    /// The grader's `--format json` report (cases, plan, protections).
    pub report: Option<serde_json::Value>,
    /// The grader's `--gradescope` results (one test per counted case).
    pub results: Option<serde_json::Value>,
    /// The grader's standard error, when it failed.
    pub error: String,
}

impl StageRun {
    /// Whether the grader finished and judged every case.
    pub fn graded(&self) -> bool {
        self.report.is_some() && self.results.is_some()
    }

    /// The stage's cases as the grader reported them.
    pub fn case_reports(&self) -> Vec<serde_json::Value> {
        self.report
            .as_ref()
            .and_then(|r| r["cases"].as_array().cloned())
            .unwrap_or_default()
    }

    /// "0.60 s a call (145 runs, 1 side by side)", from the grader's plan.
    pub fn limit(&self) -> String {
        let plan = self.report.as_ref().map(|r| &r["plan"]);
        match plan.and_then(|p| Some((p["timeout"].as_f64()?, p["runs"].as_u64()?))) {
            Some((timeout, runs)) => format!(
                "{timeout:.2} s a call ({runs} runs, {} side by side)",
                plan.and_then(|p| p["workers"].as_u64()).unwrap_or(1)
            ),
            None => "unknown limit".into(),
        }
    }

    /// Why the stage has no grade, in the student's words.
    pub fn why_not_graded(&self) -> String {
        match self.code {
            None => format!(
                "{} was stopped after {:.0} s, the time this function may take in all: does \
                 it loop forever, or wait for something?",
                self.stage.function, self.seconds
            ),
            Some(code) => format!(
                "The grader failed on {} (exit {code}); tell your TA.",
                self.stage.function
            ),
        }
    }
}

/// Runs per stage if every case passes, as the grader counts them; by
/// cases when it cannot list them (it still fits its runs in its share).
fn runs_per_stage(g: &Grading, counts: [usize; 4]) -> [usize; 4] {
    let (out, err) = (g.logs.join("list.json"), g.logs.join("list.err"));
    let mut cmd = Command::new(&g.exe);
    cmd.arg("--fixtures")
        .arg(&g.fixtures)
        .args(["--list", "--format", "json"])
        .current_dir(&g.cwd)
        .env_clear()
        .env("PATH", "/usr/local/bin:/usr/bin:/bin")
        .env("LANG", "C.UTF-8");
    let mut runs = [0; 4];
    if let Ok(Some(0)) = run_limited(cmd, &out, &err, Duration::from_secs(60)) {
        let list: Vec<serde_json::Value> = std::fs::read_to_string(&out)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .unwrap_or_default();
        for case in list {
            if let Some(k) = STAGES.iter().position(|s| case["stage"] == s.stage) {
                runs[k] += case["runs"].as_u64().unwrap_or(1) as usize;
            }
        }
    }
    if runs.iter().sum::<usize>() == 0 {
        return counts;
    }
    runs
}

/// Grades every stage that has counted cases, one grader run each, within
/// `seconds_left()` (called before each stage: the time still available).
pub fn grade_stages(g: &Grading, seconds_left: &dyn Fn() -> f64) -> Vec<StageRun> {
    let counts = counted(&g.fixtures, g.bonus);
    let runs = runs_per_stage(g, counts);
    let mut out = Vec::new();
    for (k, stage) in STAGES.iter().enumerate() {
        if counts[k] == 0 {
            continue;
        }
        let runs_left: usize = runs[k..].iter().sum();
        let budget = (seconds_left() * runs[k] as f64 / runs_left.max(1) as f64).max(1.0);
        let results = g.logs.join(format!("{}.results.json", stage.stage));
        let (stdout, stderr) = (
            g.logs.join(format!("{}.json", stage.stage)),
            g.logs.join(format!("{}.err", stage.stage)),
        );
        let _ = std::fs::remove_file(&results);
        let mut cmd = Command::new(&g.exe);
        cmd.arg("--no-color")
            .arg("--fixtures")
            .arg(&g.fixtures)
            .args(["--stage", stage.stage, "--timeout", &g.timeout.to_string()])
            .args([
                "--budget",
                &format!("{:.2}", (budget - STAGE_MARGIN).max(0.1)),
            ])
            .args(["--format", "json", "--gradescope"])
            .arg(&results)
            .current_dir(&g.cwd)
            // Nothing of ours: with CARGO set the grader would rebuild the
            // student's crate itself, outside the build's lock-in.
            .env_clear()
            .env("PATH", "/usr/local/bin:/usr/bin:/bin")
            .env("LANG", "C.UTF-8");
        if g.bonus {
            cmd.arg("--bonus");
        }
        cmd.args(&g.extra_args);
        let start = Instant::now();
        // The reaper stops the grader at its share and sweeps what it left;
        // the outer limit is for a reaper that hangs.
        let reaped = crate::process::reaped(&g.reaper, budget, &cmd);
        let code = run_limited(
            reaped,
            &stdout,
            &stderr,
            Duration::from_secs_f64(budget + 10.0),
        )
        .unwrap_or(Some(-1))
        .filter(|c| *c != crate::process::REAPED_AT_DEADLINE);
        let seconds = start.elapsed().as_secs_f64();
        let read = |p: &Path| {
            std::fs::read_to_string(p)
                .ok()
                .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        };
        let ok = matches!(code, Some(0 | 1));
        let report = if ok { read(&stdout) } else { None };
        let results = if ok { read(&results) } else { None };
        let error = if report.is_none() {
            std::fs::read_to_string(&stderr).unwrap_or_default()
        } else {
            String::new()
        };
        out.push(StageRun {
            stage: *stage,
            cases: counts[k],
            budget,
            code,
            seconds,
            report,
            results,
            error,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compiler_text_keeps_the_errors_only() {
        let log = "   Compiling meshedit v0.1.0\nerror: unclosed delimiter\n --> src/lib.rs:1:20\n    Finished dev\n";
        assert_eq!(
            compiler_text(log),
            "error: unclosed delimiter\n --> src/lib.rs:1:20"
        );
        let long: String = (0..200).map(|i| format!("line {i}\n")).collect();
        let text = compiler_text(&long);
        assert!(text.ends_with("... (50 more lines)"), "{text}");
        assert_eq!(text.lines().count(), COMPILER_LINES + 1);
    }

    #[test]
    fn counted_cases_follow_the_fixtures_and_the_bonus() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
        let lab = counted(&root, false);
        let with_bonus = counted(&root, true);
        assert!(lab.iter().all(|&n| n > 0), "{lab:?}");
        assert!(with_bonus.iter().sum::<usize>() > lab.iter().sum::<usize>());
    }
}
