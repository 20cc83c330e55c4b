//! Grading one submission on a machine of its own (a Classroom 50 runner,
//! a PrairieLearn grading container): the lab the autograder brought (its
//! grader and fixtures, never the student's copies), the student's
//! `lib.rs` found in their checkout or upload and copied into it, built
//! locked in (vendored crates beside the lab, the toolchain `rustc` names,
//! a target folder of its own), graded one stage at a time within a budget.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use crate::build::{Build, Outcome as BuildOutcome};

use crate::grade::{self, Grading};
use crate::platform::Outcome;

/// What a local grading needs.
#[derive(Clone, Debug)]
pub struct Local {
    /// The autograder's lab: a copy of the lab with its fixtures (and the
    /// `vendor/` folder `cargo vendor` wrote beside it, as `../vendor`).
    pub lab: PathBuf,
    /// The fixtures graded against (default: `lab/fixtures`).
    pub fixtures: PathBuf,
    /// The student's checkout or upload.
    pub submission: PathBuf,
    /// Seconds the whole grading may take, build included.
    pub budget: f64,
    /// Seconds each call may take at most.
    pub timeout: f64,
    pub bonus: bool,
    /// The build's target folder (default: a new one for this grading;
    /// tests keep one between gradings). The vendored crates:
    /// `vendor` (default: `../vendor` beside the lab).
    pub target: Option<PathBuf>,
    pub vendor: Option<PathBuf>,
}

/// The toolchain's root, as `rustc` in `lab` names it (its
/// `rust-toolchain.toml` chooses).
pub fn sysroot(lab: &Path) -> Result<PathBuf, String> {
    let out = Command::new("rustc")
        .args(["--print", "sysroot"])
        .current_dir(lab)
        .output()
        .map_err(|e| format!("cannot run rustc: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout).trim().to_string();
    if !out.status.success() || text.is_empty() {
        return Err(format!(
            "rustc --print sysroot failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    Ok(PathBuf::from(text))
}

/// Grades the submission; an error is the setup's (no lab, no toolchain),
/// never the student's.
pub fn grade(local: &Local, log: &dyn Fn(&str)) -> Result<Outcome, String> {
    let start = Instant::now();
    let left = || local.budget - start.elapsed().as_secs_f64();
    let counts = grade::counted(&local.fixtures, local.bonus);
    // The student's to refuse (a named pipe, a device, a file too large),
    // never the setup's: see `read_source`.
    let text = match crate::upload::take_lib_rs(&local.submission) {
        Ok((_, text)) => text,
        Err(why) => {
            return Ok(Outcome::NotGraded {
                message: why.message(),
                counts,
            })
        }
    };
    let student = local.lab.join("crates/meshedit/src/lib.rs");
    std::fs::write(&student, text).map_err(|e| format!("{}: {e}", student.display()))?;
    let vendor = match &local.vendor {
        Some(v) => v.clone(),
        None => local
            .lab
            .parent()
            .ok_or("the lab has no parent folder")?
            .join("vendor"),
    };
    let work_dir = crate::private_temp_dir("meshlab-local-")?;
    let work = work_dir.path().to_path_buf();
    let target = local.target.clone().unwrap_or_else(|| work.join("target"));
    let build = Build {
        lab: local.lab.clone(),
        vendor,
        sysroot: sysroot(&local.lab)?,
        target: target.clone(),
        memory: crate::gradescope::BUILD_MEMORY,
        seconds: (left() - 30.0).max(60.0).round(),
        status: work.join("build.status"),
        // Landlock keeps the build in; a grading container or runner is
        // the submission's alone.
        drop_user: false,
        landlock: true,
        empty_root: true,
    };
    let me = std::env::current_exe().map_err(|e| e.to_string())?;
    let built = grade::build(&build, &me, &work)?;
    log(&built.report.protections());
    let compiler = built.compiler();
    let outcome = match built.report.outcome {
        BuildOutcome::NotLockedIn => Err(built.report.failure().unwrap_or_default()),
        BuildOutcome::OutOfMemory | BuildOutcome::OutOfTime => Ok(Outcome::NotGraded {
            message: crate::does_not_compile(built.report.failure().as_deref(), &compiler),
            counts,
        }),
        BuildOutcome::Failed => Ok(Outcome::NotGraded {
            message: crate::does_not_compile(None, &compiler),
            counts,
        }),
        BuildOutcome::Built => {
            let grading = Grading {
                exe: grade::programs_dir(&target).join(grade::PROGRAMS[0]),
                cwd: local.lab.clone(),
                fixtures: local.fixtures.clone(),
                timeout: local.timeout,
                bonus: local.bonus,
                logs: work.clone(),
                reaper: me,
                extra_args: Vec::new(),
            };
            let stages = grade::grade_stages(&grading, &left);
            let notes = if built.said_something() {
                vec![format!(
                    "Your code compiles with warnings:\n\n{}",
                    grader::report::quoted::Quoted::new(compiler).block("")
                )]
            } else {
                Vec::new()
            };
            Ok(Outcome::Graded {
                stages,
                notes,
                bonus: local.bonus,
            })
        }
    };
    let _ = std::fs::remove_dir_all(&work);
    crate::process::sweep(None);
    outcome
}
