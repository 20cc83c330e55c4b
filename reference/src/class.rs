//! Grading a whole class: each submission's `lib.rs` is built into a scratch
//! copy of the lab (hidden cases included, solution left out) and graded;
//! the reports land in one folder with a CSV summary.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::handout::{self, Purpose};

/// One student's file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Submission {
    pub name: String,
    pub lib_rs: PathBuf,
}

/// The submissions in `dir`: `NAME.rs`, `NAME/lib.rs`, or a whole workspace
/// `NAME/crates/meshedit/src/lib.rs`. Anything else is named as an error,
/// so no student is skipped silently.
pub fn find_submissions(dir: &Path) -> Result<Vec<Submission>, String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut out = Vec::new();
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for path in paths {
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("")
            .to_string();
        if name.starts_with('.') {
            continue;
        }
        let lib_rs = if path.is_dir() {
            [path.join("lib.rs"), path.join("crates/meshedit/src/lib.rs")]
                .into_iter()
                .find(|p| p.is_file())
                .ok_or_else(|| {
                    format!(
                        "{}: no lib.rs or crates/meshedit/src/lib.rs inside",
                        path.display()
                    )
                })?
        } else if path.extension().is_some_and(|x| x == "rs") {
            path.clone()
        } else {
            return Err(format!(
                "{}: not a submission (expected NAME.rs or a folder)",
                path.display()
            ));
        };
        out.push(Submission { name, lib_rs });
    }
    if out.is_empty() {
        return Err(format!("{}: no submissions found", dir.display()));
    }
    Ok(out)
}

/// How one submission did.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub name: String,
    pub score: f64,
    pub max: f64,
    /// `passed`, `failed` or `does not compile`.
    pub status: String,
}

/// Grades every submission in `submissions` into `out`: `NAME.txt` (the
/// grader's report, or the compiler's errors), `NAME.results.json`
/// (Gradescope's format) and `summary.csv`. Builds go to `target`.
pub fn grade_class(
    root: &Path,
    submissions: &Path,
    out: &Path,
    target: &Path,
    timeout: f64,
) -> Result<Vec<Row>, String> {
    let students = find_submissions(submissions)?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let out = out.canonicalize().map_err(|e| e.to_string())?;
    // Outside the lab (a copy may not land inside what it copies).
    let workspace = std::env::temp_dir().join(format!("meshlab-class-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&workspace);
    handout::copy_lab(root, &workspace, Purpose::Grading)?;
    let student_file = workspace.join("crates/meshedit/src/lib.rs");

    let mut rows = Vec::new();
    for s in students {
        std::fs::copy(&s.lib_rs, &student_file)
            .map_err(|e| format!("{}: {e}", s.lib_rs.display()))?;
        let report = out.join(format!("{}.txt", s.name));
        let results = out.join(format!("{}.results.json", s.name));
        let build = Command::new(env!("CARGO"))
            .args(["build", "--quiet", "-p", "grader"])
            .current_dir(&workspace)
            .env("CARGO_TARGET_DIR", target)
            .output()
            .map_err(|e| format!("cannot run cargo: {e}"))?;
        if !build.status.success() {
            std::fs::write(&report, &build.stderr).map_err(|e| e.to_string())?;
            rows.push(Row {
                name: s.name,
                score: 0.0,
                max: 0.0,
                status: "does not compile".into(),
            });
            continue;
        }
        let exe = target
            .join("debug")
            .join(format!("grader{}", std::env::consts::EXE_SUFFIX));
        let graded = Command::new(exe)
            .args([
                "--no-color",
                "--timeout",
                &timeout.to_string(),
                "--gradescope",
            ])
            .arg(&results)
            .current_dir(&workspace)
            .output()
            .map_err(|e| format!("cannot run the grader: {e}"))?;
        std::fs::write(&report, &graded.stdout).map_err(|e| e.to_string())?;
        let json: serde_json::Value = std::fs::read_to_string(&results)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .ok_or_else(|| {
                format!(
                    "{}: the grader wrote no results ({})",
                    s.name,
                    String::from_utf8_lossy(&graded.stderr).trim()
                )
            })?;
        let max: f64 = json["tests"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(|t| t["max_score"].as_f64())
            .sum();
        let status = if graded.status.code() == Some(0) {
            "passed"
        } else {
            "failed"
        };
        rows.push(Row {
            name: s.name,
            score: json["score"].as_f64().unwrap_or(0.0),
            max,
            status: status.into(),
        });
    }
    let mut csv = String::from("student,score,max_score,status\n");
    for r in &rows {
        csv.push_str(&format!("{},{},{},{}\n", r.name, r.score, r.max, r.status));
    }
    std::fs::write(out.join("summary.csv"), csv).map_err(|e| e.to_string())?;
    let _ = std::fs::remove_dir_all(&workspace);
    Ok(rows)
}
