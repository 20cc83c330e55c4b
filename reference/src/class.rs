//! Grading a whole class: every entry of the submissions folder gets a row,
//! whatever it is. Each submission's `lib.rs` is built into its own pristine
//! copy of the lab (solution and hidden cases left out), restored from a
//! template at the same path each time so that cargo rebuilds only the
//! student's crate and the grader; then graded within a time budget against
//! the fixtures (hidden cases included) in a folder outside that copy. The
//! reports land in one folder with a CSV summary.
//!
//! Compiling is running the student's code (`include_str!`, `env!`): every
//! build goes through the grader's build launcher
//! ([`grader::build_sandbox`]), which lets it read only the toolchain, the
//! vendored dependencies and that copy, write only its target folder (in a
//! folder of its own outside the lab, under a name nobody can guess), with
//! an environment of its own, no network, a memory cap and a time limit. So
//! a TA grading as themselves is as safe as one using a separate user.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use grader::build_sandbox::Outcome;
use grader::quoted::{self, Quoted};

use crate::handout::{self, Purpose};

/// The three functions and the sequence stage, in grading order: (stage,
/// also the fixture kind; column name).
const FUNCTIONS: [(&str, &str); 4] = [
    ("flip", "flip_edge"),
    ("split", "split_edge"),
    ("sequence", "in_sequence"),
    ("subdivide", "loop_subdivide"),
];

/// Folders of an upload that never hold the student's file.
const SKIP_DIRS: [&str; 3] = ["target", ".git", "__MACOSX"];
/// Seconds of a submission's budget kept from the grader's own (for its
/// start and end): the deadline that kills it is the whole budget.
const GRADER_MARGIN: f64 = 2.0;
/// Crates of the lab other than the student's: their `lib.rs` is never taken.
const OTHER_CRATES: [&str; 4] = ["halfedge", "grader", "reference", "crates"];

/// One entry of the submissions folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Submission {
    pub name: String,
    /// The student's file, or why there is none.
    pub lib_rs: Result<PathBuf, String>,
}

/// Whether `path` is a symbolic link. A submission's links are never
/// followed: one could name any file the TA can read (a hidden case), which
/// the compiler would then quote in the student's report.
fn is_link(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
}

/// Every `.rs` file under `dir`, relative, shallowest first; symbolic
/// links left out.
fn rust_files(dir: &Path, rel: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir.join(rel)) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for path in paths {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let rel_path = rel.join(&*name);
        if is_link(&path) {
            continue;
        }
        if path.is_dir() {
            if !name.starts_with('.') && !SKIP_DIRS.contains(&&*name) {
                rust_files(dir, &rel_path, out);
            }
        } else if name.ends_with(".rs") {
            out.push(rel_path);
        }
    }
}

/// The student's `lib.rs` inside an uploaded folder: `meshedit/src/lib.rs`
/// at any depth (the workspace, or the workspace inside one folder), else a
/// single `lib.rs` outside any other crate of the lab, else the folder's
/// only Rust file. Never another crate's `lib.rs`.
pub fn find_lib_rs(dir: &Path) -> Result<PathBuf, String> {
    let mut found = Vec::new();
    rust_files(dir, Path::new(""), &mut found);
    let parts = |p: &PathBuf| -> Vec<String> {
        p.components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect()
    };
    let is_lib = |p: &&PathBuf| p.file_name().is_some_and(|n| n == "lib.rs");
    let mut meshedit: Vec<&PathBuf> = found
        .iter()
        .filter(is_lib)
        .filter(|p| parts(p).ends_with(&["meshedit".into(), "src".into(), "lib.rs".into()]))
        .collect();
    meshedit.sort_by_key(|p| (parts(p).len(), p.to_path_buf()));
    match meshedit.as_slice() {
        [one] => return Ok(dir.join(one)),
        [a, b, ..] if parts(a).len() < parts(b).len() => return Ok(dir.join(a)),
        [_, _, ..] => {
            let list: Vec<String> = meshedit.iter().map(|p| p.display().to_string()).collect();
            return Err(format!(
                "several copies of meshedit/src/lib.rs: {}",
                list.join(", ")
            ));
        }
        [] => {}
    }
    let loose: Vec<&PathBuf> = found
        .iter()
        .filter(is_lib)
        .filter(|p| {
            let ps = parts(p);
            !ps[..ps.len() - 1]
                .iter()
                .any(|c| OTHER_CRATES.contains(&c.as_str()))
        })
        .collect();
    match loose.as_slice() {
        [one] => return Ok(dir.join(one)),
        [_, _, ..] => {
            let list: Vec<String> = loose.iter().map(|p| p.display().to_string()).collect();
            return Err(format!("several lib.rs files: {}", list.join(", ")));
        }
        [] => {}
    }
    if let [only] = found.as_slice() {
        if parts(only).len() == 1 {
            return Ok(dir.join(only));
        }
    }
    let seen: Vec<String> = found
        .iter()
        .take(8)
        .map(|p| p.display().to_string())
        .collect();
    Err(format!(
        "no crates/meshedit/src/lib.rs inside (found: {})",
        if seen.is_empty() {
            "no .rs file".to_string()
        } else {
            seen.join(", ")
        }
    ))
}

/// The entries of `dir`, each with its file or the reason it has none:
/// `NAME.rs`, a folder (see [`find_lib_rs`]), or anything else (named as not
/// a submission). Only names starting with `.` are left out (`.DS_Store`).
pub fn find_submissions(dir: &Path) -> Result<Vec<Submission>, String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    let mut out = Vec::new();
    for path in paths {
        let file_name = path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        if file_name.starts_with('.') {
            continue;
        }
        let (name, lib_rs) = if is_link(&path) {
            let name = file_name.strip_suffix(".rs").unwrap_or(&file_name);
            let why = "a symbolic link: copy the submission itself".to_string();
            (name.to_string(), Err(why))
        } else if path.is_dir() {
            (file_name.clone(), find_lib_rs(&path))
        } else if let Some(stem) = file_name.strip_suffix(".rs") {
            (stem.to_string(), Ok(path.clone()))
        } else {
            let why = if file_name.ends_with(".zip") {
                "a zip archive: unpack it into a folder of the same name".to_string()
            } else {
                "not a submission: expected NAME.rs or a folder".to_string()
            };
            (file_name.clone(), Err(why))
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
    /// `passed`, `failed`, `does not compile`, `no submission`,
    /// `out of time` or `grader error`.
    pub status: String,
    /// Passed and counted cases per function, in [`FUNCTIONS`] order.
    pub functions: [(usize, usize); 4],
    /// The first failed case and its first warning (or why it was not graded).
    pub first_failure: String,
    /// Seconds spent on this submission.
    pub seconds: f64,
}

/// How to grade a class.
#[derive(Clone, Debug)]
pub struct Options {
    /// Seconds each case may run.
    pub timeout: f64,
    /// Seconds one submission may take to grade, all cases together.
    pub budget: f64,
    /// Count the bonus cases.
    pub bonus: bool,
    /// Add each submission's fresh cases (see [`crate::fresh`]).
    pub fresh: bool,
    /// The folder the builds use (`target/` and `vendor/` in it), shared by
    /// every submission; outside the lab. `None`: a new private temporary
    /// folder, removed at the end (the dependencies then compile afresh).
    pub build_dir: Option<PathBuf>,
    /// The program that locks builds in: one whose `main` calls
    /// [`grader::build_sandbox::launch_if_asked`] (the reference binary).
    pub launcher: PathBuf,
    /// The memory cap of each compiler process, in bytes.
    pub build_memory: u64,
    /// Seconds one submission's build may take (`None`: the budget, at
    /// least 60 s).
    pub build_seconds: Option<f64>,
    /// Print a progress line per submission on standard error.
    pub progress: bool,
}

/// Counted cases per function in a fixtures folder.
fn case_counts(fixtures: &Path, bonus: bool) -> [usize; 4] {
    let mut counts = [0; 4];
    let groups: &[&str] = if bonus {
        &["lab", "hidden", "bonus"]
    } else {
        &["lab", "hidden"]
    };
    for group in groups {
        for entry in std::fs::read_dir(fixtures.join(group))
            .into_iter()
            .flatten()
        {
            let Some(f) = entry
                .ok()
                .and_then(|e| std::fs::read_to_string(e.path()).ok())
                .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            else {
                continue;
            };
            if let Some(i) = FUNCTIONS
                .iter()
                .position(|(stage, _)| f["operation"]["kind"] == *stage)
            {
                counts[i] += 1;
            }
        }
    }
    counts
}

/// A name no one can guess: 128 bits from std's `RandomState`, whose keys
/// come from the operating system's random source.
fn unpredictable_name(prefix: &str) -> String {
    use std::hash::BuildHasher;
    let mut name = String::from(prefix);
    for part in 0..2u8 {
        let bits = std::collections::hash_map::RandomState::new().hash_one((part, Instant::now()));
        let _ = write!(name, "{bits:016x}");
    }
    name
}

/// A new folder only this user may enter.
fn private_dir(path: &Path) -> Result<(), String> {
    let mut builder = std::fs::DirBuilder::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::DirBuilderExt;
        builder.mode(0o700);
    }
    builder
        .create(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// A private copy of the class's `fixtures` with the fresh cases of the
/// submission `lib_rs` added (its seed from the hidden cases' digest list
/// and the file's bytes), and that seed.
fn fresh_fixtures(fixtures: &Path, lib_rs: &Path) -> Result<(RemovedAtEnd, u64), String> {
    let secret = crate::fresh::secret_of(fixtures)?;
    let bytes = std::fs::read(lib_rs).map_err(|e| format!("{}: {e}", lib_rs.display()))?;
    let seed = crate::fresh::seed_for(&secret, &bytes);
    let dir = std::env::temp_dir().join(unpredictable_name("meshlab-fresh-"));
    private_dir(&dir)?;
    let guard = RemovedAtEnd(vec![dir.clone()]);
    copy_keeping_times(fixtures, &dir)?;
    crate::fresh::write(&dir, seed, crate::solution::Weights::Warren)?;
    Ok((guard, seed))
}

/// Removes its folders when dropped, whichever way grading ends.
struct RemovedAtEnd(Vec<PathBuf>);

impl Drop for RemovedAtEnd {
    fn drop(&mut self) {
        for dir in &self.0 {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

/// Copies `from` into `to` keeping modification times, so that cargo sees
/// the restored lab as unchanged and rebuilds only what the student touched.
fn copy_keeping_times(from: &Path, to: &Path) -> Result<(), String> {
    std::fs::create_dir_all(to).map_err(|e| format!("{}: {e}", to.display()))?;
    for entry in std::fs::read_dir(from).map_err(|e| format!("{}: {e}", from.display()))? {
        let path = entry.map_err(|e| e.to_string())?.path();
        let target = to.join(path.file_name().expect("a name"));
        if path.is_dir() {
            copy_keeping_times(&path, &target)?;
        } else {
            std::fs::copy(&path, &target).map_err(|e| format!("{}: {e}", path.display()))?;
            let modified = std::fs::metadata(&path)
                .and_then(|m| m.modified())
                .map_err(|e| e.to_string())?;
            std::fs::File::options()
                .write(true)
                .open(&target)
                .and_then(|f| f.set_modified(modified))
                .map_err(|e| format!("{}: {e}", target.display()))?;
        }
    }
    Ok(())
}

/// Runs `cmd` in its own process group with its output in files, killing
/// the whole group at `limit` and when it ends (stray children included).
/// Returns the exit code, `None` when stopped at the limit.
fn run_limited(
    mut cmd: Command,
    stdout: &Path,
    stderr: &Path,
    limit: Duration,
) -> Result<Option<i32>, String> {
    let file = |p: &Path| std::fs::File::create(p).map_err(|e| format!("{}: {e}", p.display()));
    cmd.stdin(Stdio::null())
        .stdout(file(stdout)?)
        .stderr(file(stderr)?);
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        cmd.process_group(0);
    }
    let mut child = cmd
        .spawn()
        .map_err(|e| format!("cannot run {:?}: {e}", cmd.get_program()))?;
    let start = Instant::now();
    let code = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break Some(status.code().unwrap_or(-1));
        }
        if start.elapsed() >= limit {
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    kill_group(child.id());
    let _ = child.kill();
    let _ = child.wait();
    Ok(code)
}

#[cfg(unix)]
fn kill_group(pid: u32) {
    let _ = Command::new("kill")
        .args(["-KILL", "--", &format!("-{pid}")])
        .stderr(Stdio::null())
        .status();
}

#[cfg(not(unix))]
fn kill_group(_: u32) {}

/// A locked-in build of the copy, through the launcher program.
struct BuildJail {
    build: grader::build_sandbox::Build,
    launcher: PathBuf,
}

/// How a locked-in build went: the launcher's status and cargo's output.
struct Built {
    report: grader::build_sandbox::Report,
    log: String,
}

impl BuildJail {
    /// Runs the build, its output in `logs`; an error is the TA's (the
    /// launcher missing), never the student's.
    fn run(&self, logs: &Path) -> Result<Built, String> {
        let _ = std::fs::remove_file(&self.build.status);
        let mut cmd = Command::new(&self.launcher);
        cmd.args(self.build.args()).env_clear();
        let (out, err) = (logs.join("build.out"), logs.join("build.err"));
        // The launcher keeps the time limit itself; this is for a launcher
        // that hangs.
        let limit = Duration::from_secs_f64(self.build.seconds + 30.0);
        run_limited(cmd, &out, &err, limit)?;
        let report = grader::build_sandbox::Report::read(&self.build.status)?;
        let log = std::fs::read_to_string(&err).unwrap_or_default();
        Ok(Built { report, log })
    }
}

/// The toolchain's root, as the lab's `rust-toolchain.toml` chooses it.
fn sysroot(lab: &Path) -> Result<PathBuf, String> {
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

/// Removes what the previous submission's build left in the shared target
/// folder (its compiled crate, its incremental cache, the programs linked
/// with it), so that the next build, which may read that folder, finds
/// nothing of another student's.
fn forget_submission(target: &Path) {
    let debug = target.join("debug");
    for dir in [
        debug.clone(),
        debug.join("deps"),
        debug.join("incremental"),
        debug.join(".fingerprint"),
    ] {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let bin = name == "grader" || name.starts_with("grader-") && dir.ends_with("deps");
            let theirs = name.contains("meshedit")
                || name.contains("grader_child")
                || name.contains("grader-child");
            if theirs || bin && !name.ends_with(".d") {
                let path = entry.path();
                let _ = if path.is_dir() {
                    std::fs::remove_dir_all(&path)
                } else {
                    std::fs::remove_file(&path)
                };
            }
        }
    }
}

/// Cargo's output without its progress lines.
fn compiler_text(stderr: &str) -> String {
    stderr
        .lines()
        .filter(|l| {
            let l = l.trim_start();
            !["Compiling ", "Finished ", "Blocking ", "Locking "]
                .iter()
                .any(|p| l.starts_with(p))
        })
        .collect::<Vec<_>>()
        .join("\n")
        .trim()
        .to_string()
}

/// Text of the student's making (a compiler's errors quote their code, a
/// reason may name their files) as shown in reports: its first line on one
/// line, the rest under `| `, control characters escaped.
fn shown(why: &str) -> String {
    match why.split_once('\n') {
        Some((head, rest)) => format!(
            "{}\n{}",
            quoted::one_line(head),
            Quoted::new(rest.trim_start_matches('\n')).block("")
        ),
        None => quoted::one_line(why),
    }
}

/// Results in Gradescope's format for a submission that was not graded.
fn zero_results(message: &str, max: usize) -> String {
    serde_json::to_string_pretty(&serde_json::json!({
        "score": 0.0,
        "output": message,
        "tests": [{
            "name": "your code compiles and can be graded",
            "score": 0.0,
            "max_score": max as f64,
            "status": "failed",
            "output": message,
        }],
    }))
    .expect("JSON")
}

/// Grades every entry of `submissions` into `out`: `NAME.txt` (a short
/// report), `NAME.log` (the build and every case in full),
/// `NAME.results.json` (Gradescope's format) and `summary.csv`.
pub fn grade_class(
    root: &Path,
    submissions: &Path,
    out: &Path,
    options: &Options,
) -> Result<Vec<Row>, String> {
    let students = find_submissions(submissions)?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let out = out.canonicalize().map_err(|e| e.to_string())?;
    // Outside the lab (a copy may not land inside what it copies), under
    // names no student can guess.
    let scratch = std::env::temp_dir().join(unpredictable_name("meshlab-class-"));
    let fixtures = std::env::temp_dir().join(unpredictable_name("meshlab-fixtures-"));
    let _cleanup = RemovedAtEnd(vec![scratch.clone(), fixtures.clone()]);
    private_dir(&scratch)?;
    private_dir(&fixtures)?;
    let template = scratch.join("template");
    let work = scratch.join("work");
    handout::copy_lab(root, &template, Purpose::Grading)?;
    // The fixtures graded against leave the copy the students' code is
    // built in: the hidden ones are moved out, the others copied.
    for group in ["lab", "bonus", "hidden"] {
        let from = template.join("fixtures").join(group);
        if !from.is_dir() {
            continue;
        }
        copy_keeping_times(&from, &fixtures.join(group))?;
        if group == "hidden" {
            std::fs::remove_dir_all(&from).map_err(|e| format!("{}: {e}", from.display()))?;
        }
    }
    let mut counts = case_counts(&fixtures, options.bonus);
    if options.fresh {
        // Fresh cases are single operations: flip, split, subdivide.
        for (k, n) in [0, 1, 3]
            .into_iter()
            .zip(crate::fresh::counted(options.bonus))
        {
            counts[k] += n;
        }
    }
    let build_dir = match &options.build_dir {
        Some(dir) => {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            let dir = dir.canonicalize().map_err(|e| e.to_string())?;
            let lab = root.canonicalize().map_err(|e| e.to_string())?;
            if dir.starts_with(&lab) {
                return Err(format!(
                    "{}: the build folder must be outside the lab (its path is visible \
                     to the student's code at compile time)",
                    dir.display()
                ));
            }
            dir
        }
        None => {
            let dir = std::env::temp_dir().join(unpredictable_name("meshlab-build-"));
            private_dir(&dir)?;
            dir
        }
    };
    let _cleanup_build = RemovedAtEnd(if options.build_dir.is_none() {
        vec![build_dir.clone()]
    } else {
        Vec::new()
    });
    let target = build_dir.join("target");
    let vendor = build_dir.join("vendor");
    // The dependencies' sources, out of the TA's cargo home (which holds
    // more than sources), at a fixed place beside the target folder (their
    // path is in the compiled dependencies' fingerprints).
    let _ = std::fs::remove_dir_all(&vendor);
    let vendor_offline = || {
        Command::new(handout::cargo())
            .args(["vendor", "--locked", "--offline", "--quiet"])
            .arg(&vendor)
            .current_dir(&template)
            .stdout(Stdio::null())
            .output()
            .map_err(|e| format!("cannot run cargo: {e}"))
    };
    let mut vendored = vendor_offline()?;
    if !vendored.status.success() {
        // Vendoring takes every platform's crates (the Windows-only ones
        // too), which no build on this machine fetched: fetch them once, as
        // Gradescope's setup.sh does, then vendor again.
        if options.progress {
            eprintln!("fetching the lab's crates for every platform once (cargo fetch)...");
        }
        let fetched = Command::new(handout::cargo())
            .args(["fetch", "--locked", "--quiet"])
            .current_dir(&template)
            .output()
            .map_err(|e| format!("cannot run cargo: {e}"))?;
        if fetched.status.success() {
            vendored = vendor_offline()?;
        }
        if !vendored.status.success() {
            return Err(format!(
                "cargo vendor failed, also after `cargo fetch --locked` (which needs the \
                 network to crates.io once):\n{}{}",
                String::from_utf8_lossy(&fetched.stderr),
                String::from_utf8_lossy(&vendored.stderr)
            ));
        }
    }
    let sysroot = sysroot(&template)?;
    let build = |seconds: f64, status: PathBuf| BuildJail {
        build: grader::build_sandbox::Build {
            lab: work.clone(),
            vendor: vendor.clone(),
            sysroot: sysroot.clone(),
            target: target.clone(),
            memory: options.build_memory,
            seconds,
            status,
            drop_user: false,
            landlock: true,
        },
        launcher: options.launcher.clone(),
    };
    let exe = target
        .join("debug")
        .join(format!("grader{}", std::env::consts::EXE_SUFFIX));

    // Build the lab once, with no budget: the dependencies' first build
    // (a minute or more) must not count against the first student. Locked
    // in like every build, so that the students' builds find it fresh.
    if options.progress {
        eprintln!("building the lab once (the first time takes a minute or two)...");
    }
    let _ = std::fs::remove_dir_all(&work);
    copy_keeping_times(&template, &work)?;
    let logs = scratch.join("logs");
    std::fs::create_dir_all(&logs).map_err(|e| e.to_string())?;
    let warm = build(3600.0, logs.join("warm.status")).run(&logs)?;
    if warm.report.outcome != grader::build_sandbox::Outcome::Built {
        return Err(format!(
            "the lab itself does not build ({}):\n{}",
            warm.report.failure().unwrap_or_default(),
            warm.log
        ));
    }
    if warm.report.landlock == 0 && options.progress {
        eprintln!(
            "warning: this kernel has no Landlock: students' builds can read every file you \
             can (run class grading as a user who can read only the lab, or on a newer kernel)"
        );
    }
    if options.progress {
        eprintln!("{}", warm.report.protections());
    }

    let started = Instant::now();
    let mut rows = Vec::new();
    for (i, s) in students.iter().enumerate() {
        let t0 = Instant::now();
        let seconds = options.build_seconds.unwrap_or(options.budget.max(60.0));
        let jail = build(seconds, logs.join("build.status"));
        let row = grade_one(s, &template, &jail, &fixtures, &out, &exe, counts, options)?;
        let row = Row {
            seconds: t0.elapsed().as_secs_f64(),
            ..row
        };
        if options.progress {
            let done = i + 1;
            let left =
                started.elapsed().as_secs_f64() / done as f64 * (students.len() - done) as f64;
            eprintln!(
                "[{done:>3}/{}] {:<20} {:>5}/{:<3} {:<16} {:>5.1} s  (about {:.0} s left)",
                students.len(),
                quoted::one_line(&row.name),
                row.score,
                row.max,
                row.status,
                row.seconds,
                left
            );
        }
        rows.push(row);
    }
    let mut csv = String::from(
        "student,score,max_score,status,flip_edge,split_edge,in_sequence,loop_subdivide,first_failure\n",
    );
    for r in &rows {
        let f = |k: usize| format!("{}/{}", r.functions[k].0, r.functions[k].1);
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{}",
            quoted::csv_field(&r.name),
            r.score,
            r.max,
            r.status,
            f(0),
            f(1),
            f(2),
            f(3),
            quoted::csv_field(&r.first_failure)
        );
    }
    std::fs::write(out.join("summary.csv"), csv).map_err(|e| e.to_string())?;
    Ok(rows)
}

/// Grades one entry; an error here is the TA's (disk, cargo missing), never
/// the student's: a student's problem becomes the row's status.
#[allow(clippy::too_many_arguments)]
fn grade_one(
    s: &Submission,
    template: &Path,
    jail: &BuildJail,
    fixtures: &Path,
    out: &Path,
    exe: &Path,
    counts: [usize; 4],
    options: &Options,
) -> Result<Row, String> {
    let max: usize = counts.iter().sum();
    let write = |ext: &str, text: &str| {
        let path = out.join(format!("{}.{ext}", s.name));
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
    };
    let mut row = Row {
        name: s.name.clone(),
        score: 0.0,
        max: max as f64,
        status: String::new(),
        functions: counts.map(|n| (0, n)),
        first_failure: String::new(),
        seconds: 0.0,
    };
    let not_graded = |row: &mut Row, status: &str, why: &str, log: &str| -> Result<(), String> {
        row.status = status.into();
        // The compiler's first error rather than the heading above it.
        row.first_failure = why
            .lines()
            .find(|l| l.starts_with("error"))
            .or_else(|| why.lines().next())
            .unwrap_or("")
            .to_string();
        let why = shown(why);
        write(
            "txt",
            &format!(
                "{}: {status} (0 of {max})\n\n{why}\n",
                quoted::one_line(&s.name)
            ),
        )?;
        write("log", &shown(log))?;
        write("results.json", &zero_results(&why, max))
    };
    let lib_rs = match &s.lib_rs {
        Ok(p) => p,
        Err(why) => {
            not_graded(&mut row, "no submission", why, why)?;
            return Ok(row);
        }
    };

    // A pristine copy for each student: nothing a previous submission did
    // to its copy survives, nor its compiled crate in the target folder.
    let work = jail.build.lab.as_path();
    let _ = std::fs::remove_dir_all(work);
    copy_keeping_times(template, work)?;
    std::fs::copy(lib_rs, work.join("crates/meshedit/src/lib.rs"))
        .map_err(|e| format!("{}: {e}", lib_rs.display()))?;
    forget_submission(&jail.build.target);

    // Outside the copy the student's code runs in.
    let logs = work.with_file_name("logs");
    let _ = std::fs::remove_dir_all(&logs);
    std::fs::create_dir_all(&logs).map_err(|e| e.to_string())?;
    let built = jail.run(&logs)?;
    let build_log = format!("{}\n{}", built.report.protections(), built.log);
    let compiler = compiler_text(&built.log);
    match built.report.outcome {
        Outcome::Built => {}
        Outcome::NotLockedIn => {
            return Err(built.report.failure().unwrap_or_default());
        }
        Outcome::OutOfMemory | Outcome::OutOfTime => {
            let message = built.report.failure().unwrap_or_default();
            let why = format!("does not compile: {message}\n\n{compiler}");
            not_graded(&mut row, "does not compile", &why, &build_log)?;
            // The limit it hit, rather than the compiler's last words.
            row.first_failure = message;
            return Ok(row);
        }
        Outcome::Failed => {
            let why = format!("does not compile:\n\n{compiler}");
            not_graded(&mut row, "does not compile", &why, &build_log)?;
            return Ok(row);
        }
    }

    // This submission's fresh cases, in a private copy of the fixtures
    // (removed once it is graded).
    let fresh = if options.fresh {
        Some(fresh_fixtures(fixtures, lib_rs)?)
    } else {
        None
    };
    let fixtures = fresh
        .as_ref()
        .map_or(fixtures, |(dir, _)| dir.0[0].as_path());

    let results = logs.join("results.json");
    let mut grade = Command::new(exe);
    // The grader counts its child runs (a passing case runs once per
    // labelling) and shortens the per-call limit so that all of them fit
    // in the budget; the deadline below only stops what ignores limits.
    let grading_budget = (options.budget - GRADER_MARGIN).max(0.1);
    grade
        .args(["--no-color", "--timeout", &options.timeout.to_string()])
        .args(["--budget", &format!("{grading_budget:.2}")])
        .arg("--fixtures")
        .arg(fixtures)
        .args(["--format", "json", "--gradescope"])
        .arg(&results)
        .current_dir(work)
        // Nothing of the TA's: with CARGO set (as `cargo run -p reference`
        // sets it) the grader would rebuild the student's crate itself,
        // outside the build's lock-in and with the TA's environment.
        .env_clear()
        .env("PATH", "/usr/bin:/bin");
    if options.bonus {
        grade.arg("--bonus");
    }
    let (json_out, grade_err) = (logs.join("report.json"), logs.join("grader.err"));
    let code = run_limited(
        grade,
        &json_out,
        &grade_err,
        Duration::from_secs_f64(options.budget),
    )?;
    let report: Option<serde_json::Value> = std::fs::read_to_string(&json_out)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let (report, results_text) = match (code, report, std::fs::read_to_string(&results)) {
        (Some(0 | 1), Some(r), Ok(t)) => (r, t),
        (None, _, _) => {
            let why = format!(
                "grading took longer than {} s in all: a function loops or waits",
                options.budget
            );
            not_graded(&mut row, "out of time", &why, &build_log)?;
            return Ok(row);
        }
        (code, _, _) => {
            let err = std::fs::read_to_string(&grade_err).unwrap_or_default();
            let why = format!("the grader failed (exit {code:?}): {}", err.trim());
            not_graded(&mut row, "grader error", &why, &why)?;
            return Ok(row);
        }
    };

    let cases = report["cases"].as_array().cloned().unwrap_or_default();
    let bonus = report["bonus_counted"].as_bool().unwrap_or(false);
    let mut full = String::new();
    let fresh_line = fresh.as_ref().map(|(_, seed)| {
        format!(
            "fresh cases: seed {seed:016x} (replay: cargo run -p reference -- fresh --seed \
             {seed:016x} --dir DIR, then grade --fixtures DIR)"
        )
    });
    if let Some(line) = &fresh_line {
        let _ = writeln!(full, "{line}\n");
    }
    let plan = &report["plan"];
    if let (Some(limit), Some(runs)) = (plan["timeout"].as_f64(), plan["runs"].as_u64()) {
        let _ = writeln!(
            full,
            "time: each call may take {limit} s ({runs} runs, {} side by side, in a budget of {} s)\n",
            plan["workers"].as_u64().unwrap_or(1),
            plan["budget"].as_f64().unwrap_or(options.budget)
        );
    }
    if !compiler.is_empty() {
        let _ = writeln!(
            full,
            "compiler output:\n{}",
            Quoted::new(&*compiler).block("")
        );
    }
    let mut counted = [(0, 0); 4];
    let mut failures = Vec::new();
    for c in &cases {
        let name = c["name"].as_str().unwrap_or("?");
        let passed = c["passed"].as_bool().unwrap_or(false);
        let is_counted = c["group"] != "bonus" || bonus;
        let _ = writeln!(
            full,
            "== {name} ({}, {}): {}",
            c["group"].as_str().unwrap_or("?"),
            c["stage"].as_str().unwrap_or("?"),
            if passed { "passed" } else { "FAILED" }
        );
        // Student text comes as lists of lines; shown the grader's way.
        let lines_of = |v: &serde_json::Value| -> Option<Quoted> {
            let lines = v.as_array()?;
            let text: Vec<&str> = lines.iter().filter_map(|l| l.as_str()).collect();
            Some(Quoted::new(text.join("\n")))
        };
        for e in c["entries"].as_array().into_iter().flatten() {
            let level = e["level"].as_str().unwrap_or("info");
            let text = quoted::one_line(e["text"].as_str().unwrap_or(""));
            let quote = lines_of(&e["quote"]);
            let (line, below) = quoted::quoting(&text, quote.as_ref(), "        ");
            match level {
                "detail" => {
                    let _ = writeln!(full, "        {line}");
                }
                _ => {
                    let _ = writeln!(full, "[{}] {line}", quoted::one_line(level));
                }
            }
            full.push_str(&below);
        }
        if let Some(printed) = lines_of(&c["output"]).filter(|o| !o.is_blank()) {
            full.push_str(&printed.block("    "));
        }
        if !is_counted {
            continue;
        }
        let stage = c["stage"].as_str().unwrap_or("");
        if let Some(k) = FUNCTIONS.iter().position(|(s, _)| *s == stage) {
            counted[k].1 += 1;
            if passed {
                counted[k].0 += 1;
            }
        }
        if !passed {
            let first = c["first_warning"].as_str().unwrap_or("failed");
            failures.push(quoted::one_line(&format!("{name}: {first}")));
        }
    }
    let passed: usize = counted.iter().map(|c| c.0).sum();
    let total: usize = counted.iter().map(|c| c.1).sum();
    row.functions = counted;
    row.score = passed as f64;
    row.max = total as f64;
    row.status = if passed == total { "passed" } else { "failed" }.into();
    row.first_failure = failures.first().cloned().unwrap_or_default();

    let mut short = format!(
        "{}: {} ({passed} of {total})\n",
        quoted::one_line(&s.name),
        row.status
    );
    for (k, (_, function)) in FUNCTIONS.iter().enumerate() {
        let _ = writeln!(short, "  {function:<15} {}/{}", counted[k].0, counted[k].1);
    }
    if let Some(line) = &fresh_line {
        let _ = writeln!(short, "  {line}");
    }
    if compiler.contains("warning") {
        let _ = writeln!(short, "\ncompiler warnings: see {}.log", s.name);
    }
    if !failures.is_empty() {
        let _ = writeln!(short, "\nfailed cases:");
        for f in failures.iter().take(10) {
            let _ = writeln!(short, "  {f}");
        }
        if failures.len() > 10 {
            let _ = writeln!(short, "  ... and {} more", failures.len() - 10);
        }
        let _ = writeln!(short, "\nthe full log: {}.log", s.name);
    }
    write("txt", &short)?;
    write("log", &full)?;
    write("results.json", &results_text)?;
    Ok(row)
}
