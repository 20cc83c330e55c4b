//! Grading a whole class: every entry of the submissions folder gets a row,
//! whatever it is. Each submission's `lib.rs` is built into its own pristine
//! copy of the lab (solution and hidden cases left out), restored from a
//! template at the same path each time so that cargo rebuilds only the
//! student's crate and the grader; then graded within a time budget against
//! the fixtures (hidden cases included) in a folder outside that copy. The
//! reports land in one folder with a CSV summary. Finding the file,
//! building, grading stage by stage and sweeping what a submission left are
//! the `autograde` crate's, the same code every platform runs; this module
//! adds the class: the template, the fresh cases, the rows and reports.
//!
//! Compiling is running the student's code (`include_str!`, `env!`): every
//! build goes through the grader's build launcher
//! ([`autograde::build`]), which lets it read only the toolchain, the
//! vendored dependencies and that copy, write only its target folder (in a
//! folder of its own outside the lab, under a name nobody can guess), with
//! an environment of its own, no network, a memory cap and a time limit. So
//! a TA grading as themselves is as safe as one using a separate user.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use autograde::build::{Build, Outcome};
use autograde::grade::{self, STAGES};
use autograde::platform;
use autograde::upload::{is_link, read_source, take_lib_rs};
use grader::report::quoted::{self, Quoted};

use crate::handout::{self, Purpose};
use crate::scratch::{make_private, run_dir, RunDir};

/// One entry of the submissions folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Submission {
    pub name: String,
    /// The student's file, or why there is none.
    pub lib_rs: Result<PathBuf, String>,
}

/// The entries of `dir`, each with its file or the reason it has none:
/// `NAME.rs`, a folder (see [`take_lib_rs`]), or anything else (named as not
/// a submission). Only names starting with `.` are left out (`.DS_Store`).
/// Names are unique: entries that would share one keep their file names.
/// Each file is looked at as [`read_source`] reads it: a named pipe, a
/// device or a file over the cap is that entry's reason, never opened.
/// `dir` may also be one `NAME.rs` (one student, graded by hand).
pub fn find_submissions(dir: &Path) -> Result<Vec<Submission>, String> {
    if let Some(one) = single_file(dir)? {
        return Ok(vec![one]);
    }
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
            (
                file_name.clone(),
                take_lib_rs(&path)
                    .map(|(lib_rs, _)| lib_rs)
                    .map_err(|e| e.message()),
            )
        } else if let Some(stem) = file_name.strip_suffix(".rs") {
            let lib_rs = read_source(&path)
                .map(|_| path.clone())
                .map_err(|why| why.message(&file_name));
            (stem.to_string(), lib_rs)
        } else {
            let why = if file_name.ends_with(".zip") {
                "a zip archive: unpack it into a folder of the same name".to_string()
            } else {
                "not a submission: expected NAME.rs or a folder".to_string()
            };
            (file_name.clone(), Err(why))
        };
        out.push((file_name, Submission { name, lib_rs }));
    }
    if out.is_empty() {
        return Err(format!("{}: no submissions found", dir.display()));
    }
    // One row and one set of reports per entry: where two entries would
    // share a name (`bob.rs` and `bob/`), each keeps its whole file name.
    let names: Vec<String> = out.iter().map(|(_, s)| s.name.clone()).collect();
    Ok(out
        .into_iter()
        .map(|(file_name, mut s)| {
            if names.iter().filter(|n| **n == s.name).count() > 1 {
                s.name = file_name;
            }
            s
        })
        .collect())
}

/// Longest a report's file name may start with a row's name (in bytes):
/// with `.results.json` it stays within a file system's 255.
const STEM_BYTES: usize = 100;

/// The name (before `.txt`, `.log`, ...) a row's files are written under:
/// the row's name itself where it is plain (letters and digits of any
/// script and `-_.@+=,()~`, not starting with `.`, at most [`STEM_BYTES`]
/// bytes, and not ending as a name chosen here does), else its plain
/// characters (any other as `_`, cut at [`STEM_BYTES`]) and `-` with 16
/// hex digits of its SHA-256, so that two names never share one. So no
/// name a student chose becomes a path, a URL scheme (`javascript:`), a
/// control or bidirectional character in a file name, or a name too long
/// to write: the files are the tool's, and so are the pages' links.
pub fn file_stem(name: &str) -> String {
    let plain = |c: char| c.is_alphanumeric() || "-_.@+=,()~".contains(c);
    let looks_chosen = name.len() >= 17
        && name.is_char_boundary(name.len() - 17)
        && name[name.len() - 17..].starts_with('-')
        && name[name.len() - 16..]
            .bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b));
    if !name.is_empty()
        && name.len() <= STEM_BYTES
        && !name.starts_with('.')
        && name.chars().all(plain)
        && !looks_chosen
    {
        return name.to_string();
    }
    let mut stem = String::new();
    for c in name.chars() {
        let c = if plain(c) { c } else { '_' };
        if stem.len() + c.len_utf8() > STEM_BYTES {
            break;
        }
        stem.push(if stem.is_empty() && c == '.' { '_' } else { c });
    }
    let digest = sha256::sha256_hex(name.as_bytes());
    format!("{stem}-{}", &digest[..16])
}

/// `path` as the one submission of a class, when it is a file rather
/// than a folder: a regular `NAME.rs`, never a link (nor a pipe or a
/// device), whose row is `NAME`.
fn single_file(path: &Path) -> Result<Option<Submission>, String> {
    let meta = std::fs::symlink_metadata(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if meta.is_dir() {
        return Ok(None);
    }
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    match name.strip_suffix(".rs") {
        Some(stem) if meta.is_file() && !stem.is_empty() => Ok(Some(Submission {
            name: stem.to_string(),
            lib_rs: Ok(path.to_path_buf()),
        })),
        _ => Err(format!(
            "{}: give a folder of submissions or one student's NAME.rs (a regular file)",
            path.display()
        )),
    }
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
    /// Passed and counted cases per function, in [`STAGES`] order.
    pub functions: [(usize, usize); 4],
    /// The first failed case and its first warning (or why it was not graded).
    pub first_failure: String,
    /// Seconds spent on this submission.
    pub seconds: f64,
    /// Every case the grader ran and whether it passed (for the overview's
    /// pass rates); empty when nothing was graded.
    pub cases: Vec<crate::overview::CaseResult>,
    /// The student whose identical file was graded for this row (a file
    /// is graded once however many submit it).
    pub same_as: Option<String>,
    /// With `--before`: the commit graded and when it was handed in, by
    /// which clock (the student's own when only commit dates were there).
    pub handed_in: Option<crate::deadline::HandedIn>,
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
    /// [`autograde::build::launch_if_asked`] (the reference binary).
    pub launcher: PathBuf,
    /// The memory cap of each compiler process, in bytes.
    pub build_memory: u64,
    /// Seconds one submission's build may take (`None`: the budget, at
    /// least 60 s).
    pub build_seconds: Option<f64>,
    /// Print a progress line per submission on standard error.
    pub progress: bool,
    /// Grade only these submissions (by row name) and merge their rows
    /// into the reports folder's last summary; empty: all.
    pub only: Vec<String>,
    /// Lock builds in with Landlock (off only to test the fallback a
    /// kernel without it gets).
    pub landlock: bool,
    /// More options for every grader run (tests: `--without-pid-namespace`,
    /// as on a machine without PID namespaces).
    pub grader_args: Vec<String>,
    /// Submissions are git repositories: grade what each had handed in by
    /// this date and time (with its zone), read out without checking
    /// anything out (see [`crate::deadline`]).
    pub before: Option<String>,
    /// With `before`: the platform's record of when each repository was
    /// pushed to (see [`crate::deadline::read_records`]); without it, or for
    /// a repository it does not name, commit dates, which are the student's.
    pub pushes: Option<PathBuf>,
    /// Submissions graded at once, each in its own copy of the lab and its
    /// own target folder (the dependencies compiled once, then copied).
    pub jobs: usize,
    /// Grade every submission again, even one whose finished result in the
    /// reports folder is for the same file and settings.
    pub regrade: bool,
    /// The class list to join the rows with (see [`crate::roster`]).
    pub roster: Option<PathBuf>,
    /// The assignment's column in `canvas.csv`.
    pub assignment: String,
}

/// `reference class`: its options, each a field of [`Options`] or of the
/// command line only.
#[derive(clap::Args, Debug)]
pub struct ClassArgs {
    /// The folder of submissions, one entry per student, or one
    /// student's NAME.rs.
    pub submissions: PathBuf,
    /// Where the reports go.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Keep the builds (target/ and vendor/) in DIR, outside the lab, to
    /// reuse the compiled dependencies next time; by default a new
    /// private temporary folder, removed at the end.
    #[arg(long, value_name = "DIR")]
    pub build_dir: Option<PathBuf>,
    /// Seconds each case may run.
    #[arg(long, default_value_t = 5.0)]
    pub timeout: f64,
    /// Seconds one submission's grading may take, all cases together.
    #[arg(long, default_value_t = 300.0)]
    pub budget: f64,
    /// Count the bonus cases.
    #[arg(long)]
    pub bonus: bool,
    /// Grade on the fixtures alone, without each submission's fresh
    /// cases (random meshes drawn from a seed per submission).
    #[arg(long)]
    pub no_fresh: bool,
    /// No progress lines.
    #[arg(short, long)]
    pub quiet: bool,
    /// Regrade only these submissions (row names) and merge their rows
    /// into the summary already in --out.
    #[arg(long, value_name = "NAME", num_args = 1..)]
    pub only: Vec<String>,
    /// Submissions are git repositories (one per student): grade what
    /// each had handed in by DATE ("2026-12-01 23:59 +0100", its zone
    /// required), read out without checking anything out; commits.csv
    /// names the commits and the clock that dated them.
    #[arg(long, value_name = "DATE")]
    pub before: Option<String>,
    /// With --before: when each repository was pushed to, by the
    /// platform's clock (a CSV of student,commit,pushed_at; Classroom 50's
    /// scores.json; or a folder of NAME.json from GitHub's events or
    /// activity API). Without it, commit dates decide, and the student
    /// sets those.
    #[arg(long, value_name = "FILE|DIR", requires = "before")]
    pub pushes: Option<PathBuf>,
    /// Grade N submissions at once (each still built and run alone, in
    /// its own copy of the lab and target folder).
    #[arg(short, long, value_name = "N", default_value_t = 1,
          value_parser = clap::value_parser!(u16).range(1..=64))]
    pub jobs: u16,
    /// Grade every submission again: by default a submission whose
    /// finished result in --out is for the same file and settings keeps it
    /// (an interrupted run resumes where it stopped).
    #[arg(long)]
    pub regrade: bool,
    /// The class list (CSV with a header): rows join by student id or
    /// e-mail (see the TA guide for the columns read); students without a
    /// submission get 0, submissions of no roster student are listed.
    #[arg(long, value_name = "FILE.csv")]
    pub roster: Option<PathBuf>,
    /// The assignment's column in canvas.csv ("Mesh lab (1234)" to fill an
    /// existing Canvas assignment, 1234 its id).
    #[arg(long, value_name = "NAME", default_value = "Mesh lab")]
    pub assignment: String,
}

/// Runs `reference class`.
pub fn run(args: ClassArgs) -> Result<std::process::ExitCode, String> {
    for (value, option) in [(args.budget, "--budget"), (args.timeout, "--timeout")] {
        if !(value > 0.0 && value <= 86_400.0) {
            return Err(format!(
                "{option} must be a number of seconds, above 0 and at most a day"
            ));
        }
    }
    // Absolute: cargo runs in the scratch copy, not here.
    let here = std::env::current_dir().map_err(|e| e.to_string())?;
    let options = Options {
        timeout: args.timeout,
        budget: args.budget,
        bonus: args.bonus,
        build_dir: args.build_dir.map(|d| here.join(d)),
        // This program: its main starts the build launcher.
        launcher: std::env::current_exe().map_err(|e| e.to_string())?,
        build_memory: autograde::build::DEFAULT_MEMORY,
        build_seconds: None,
        fresh: !args.no_fresh,
        progress: !args.quiet,
        grader_args: Vec::new(),
        landlock: true,
        only: args.only,
        before: args.before,
        pushes: args.pushes.map(|p| here.join(p)),
        jobs: args.jobs.into(),
        regrade: args.regrade,
        roster: args.roster.map(|r| here.join(r)),
        assignment: args.assignment,
    };
    let out = &args.out;
    let rows = grade_class(&crate::lab_root(), &args.submissions, out, &options)?;
    for r in &rows {
        let dated = match &r.handed_in {
            Some(h) if h.clock.is_students() => "  [dated by its commit: the student's own clock]",
            _ => "",
        };
        println!(
            "{:<24} {:>5} / {:<5} {:<16} {}{dated}",
            quoted::one_line(&r.name),
            r.score,
            r.max,
            r.status,
            quoted::one_line(&r.first_failure)
        );
    }
    println!(
        "wrote {} rows into {} (summary.csv, canvas.csv, overview.html)",
        rows.len(),
        out.display()
    );
    Ok(std::process::ExitCode::SUCCESS)
}

/// A private copy of the class's `fixtures` with the fresh cases of the
/// submission whose file holds `bytes` added (its seed from the hidden
/// cases' digest list and those bytes), and that seed.
fn fresh_fixtures(fixtures: &Path, bytes: &[u8]) -> Result<(RunDir, u64), String> {
    let secret = crate::fresh::secret_of(fixtures)?;
    let seed = crate::fresh::seed_for(&secret, bytes);
    Ok((fixtures_with_fresh(fixtures, seed)?.0, seed))
}

/// A private copy of `fixtures` with the fresh cases of `seed` added: what
/// one submission is graded on (also timed by `reference bench`), and the
/// names of the fresh cases. Its folders 0700 and files 0600 (it holds
/// the hidden cases), swept by the next run if this one is killed.
pub fn fixtures_with_fresh(fixtures: &Path, seed: u64) -> Result<(RunDir, Vec<String>), String> {
    let dir = run_dir("meshlab-fresh-")?;
    // The groups only: not the lock file of a run's own copy.
    for group in ["lab", "bonus", "hidden"] {
        let from = fixtures.join(group);
        if from.is_dir() {
            copy_keeping_times(&from, &dir.path().join(group))?;
        }
    }
    let names = crate::fresh::write(dir.path(), seed, crate::solution::Weights::Warren)?;
    make_private(dir.path())?;
    Ok((dir, names))
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

/// Readies the builds to run as user `nobody` (root only, where Landlock
/// is missing): the scratch and build folders passable (not listable),
/// the target folder nobody's, and a toolchain nobody can run (a copy of
/// hard links when the TA's is out of reach, as under `/root`). Returns
/// that toolchain's root.
fn for_nobody(
    scratch: &Path,
    build_dir: &Path,
    target: &Path,
    sysroot: &Path,
) -> Result<PathBuf, String> {
    use std::os::unix::fs::PermissionsExt;
    for dir in [scratch, build_dir] {
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o711))
            .map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    to_nobody(target)?;
    // The Gradescope setup's own way to a toolchain nobody can run.
    let (root, _copied) = autograde::setup::reachable_toolchain(
        sysroot,
        &build_dir.join("toolchain"),
        nobody_ids()?,
    )?;
    Ok(root)
}

fn nobody_ids() -> Result<(u32, u32), String> {
    autograde::setup::build_user_ids().ok_or_else(|| "there is no user nobody to build as".into())
}

/// Makes `target` (a build's target folder) user nobody's.
fn to_nobody(target: &Path) -> Result<(), String> {
    autograde::setup::chown_tree(target, nobody_ids()?)
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

/// Grades every entry of `submissions` into `out`: `NAME.txt` (a short
/// report), `NAME.log` (the build and every case in full),
/// `NAME.results.json` (Gradescope's format) and `summary.csv`, `NAME`
/// being the row's [`file_stem`].
pub fn grade_class(
    root: &Path,
    submissions: &Path,
    out: &Path,
    options: &Options,
) -> Result<Vec<Row>, String> {
    let mut students = find_submissions(submissions)?;
    if !options.only.is_empty() {
        let known: Vec<&str> = students.iter().map(|s| s.name.as_str()).collect();
        if let Some(missing) = options.only.iter().find(|n| !known.contains(&n.as_str())) {
            return Err(format!(
                "--only {missing}: no such submission in {} (there are: {})",
                submissions.display(),
                known.join(", ")
            ));
        }
    }
    // Read first: a roster that cannot be joined is refused before an
    // hour of grading, not after.
    let roster = match &options.roster {
        Some(path) => Some(crate::roster::read(path)?),
        None => None,
    };
    let deadline = match &options.before {
        Some(before) => Some(crate::deadline::parse_deadline(before)?),
        None => None,
    };
    let records = match &options.pushes {
        Some(path) => Some(crate::deadline::read_records(path)?),
        None => None,
    };
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let out = out.canonicalize().map_err(|e| e.to_string())?;
    // What a killed run left (its copy of the hidden cases among it).
    let swept = crate::scratch::sweep(&std::env::temp_dir());
    if options.progress && !swept.is_empty() {
        eprintln!(
            "removed {} temporary folders a class run that was stopped left behind",
            swept.len()
        );
    }
    // Outside the lab (a copy may not land inside what it copies), under
    // names no student can guess.
    // Private (0700) and removed when dropped, whichever way grading ends;
    // swept by the next run when this one is killed.
    let scratch_dir = run_dir("meshlab-class-")?;
    let fixtures_dir = run_dir("meshlab-fixtures-")?;
    let (scratch, fixtures) = (scratch_dir.path(), fixtures_dir.path());
    let template = scratch.join("template");
    handout::copy_lab(root, &template, Purpose::Grading)?;
    let mut commits = String::new();
    let mut handed_in = HandedInByName::new();
    if let Some(deadline) = deadline {
        (commits, handed_in) = at_deadline(
            &mut students,
            submissions,
            deadline,
            records.as_ref(),
            &scratch.join("snapshots"),
        )?;
        let dated = handed_in.values().filter(|h| h.clock.is_students()).count();
        if dated > 0 {
            eprintln!(
                "warning: {dated} of {} repositories are {}",
                students.len(),
                crate::deadline::COMMIT_DATE_WARNING
            );
        }
    }
    // The whole class for the similarity hints, the ones asked for graded.
    let everyone = students.clone();
    if !options.only.is_empty() {
        students.retain(|s| options.only.contains(&s.name));
    }
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
    // The hidden cases and their digest list: this user's alone.
    make_private(fixtures)?;
    let mut counts = grade::counted(fixtures, options.bonus);
    if options.fresh {
        // Fresh cases are single operations: flip, split, subdivide.
        for (k, n) in [0, 1, 3]
            .into_iter()
            .zip(crate::fresh::counted(options.bonus))
        {
            counts[k] += n;
        }
    }
    // What a finished result is for: the file's bytes and every setting
    // that changes a grade. A result in `out` with the same key is reused
    // (a run that was interrupted resumes; an identical file is graded once).
    let settings = settings_key(root, options);
    let keys: Vec<Option<String>> = students
        .iter()
        .map(|s| {
            let mut all = settings.clone().into_bytes();
            match &s.lib_rs {
                Ok(path) => all.extend_from_slice(&read_source(path).ok()?),
                // Not graded, for a reason that is part of the result.
                Err(why) => all.extend_from_slice(format!("no file: {why}").as_bytes()),
            }
            Some(sha256::sha256_hex(&all))
        })
        .collect();
    let mut done: Vec<Option<Row>> = vec![None; students.len()];
    let mut resumed = 0;
    if options.only.is_empty() && !options.regrade {
        for (i, s) in students.iter().enumerate() {
            if let (Some(key), Some((row, row_key))) = (&keys[i], read_row(&out, &s.name)) {
                if *key == row_key {
                    done[i] = Some(row);
                    resumed += 1;
                }
            }
        }
    }
    // Each distinct file is graded once: the first student with it, unless
    // a finished result for it is already there.
    let mut first_with: std::collections::HashMap<&str, usize> = Default::default();
    let mut copies: Vec<(usize, usize)> = Vec::new();
    let mut queue: std::collections::VecDeque<usize> = Default::default();
    for i in 0..students.len() {
        if let (Some(key), Ok(_)) = (&keys[i], &students[i].lib_rs) {
            if let Some(&first) = first_with.get(key.as_str()) {
                if done[i].is_none() {
                    copies.push((i, first));
                }
                continue;
            }
            first_with.insert(key, i);
        }
        if done[i].is_none() {
            queue.push_back(i);
        }
    }
    if options.progress && resumed > 0 {
        eprintln!(
            "resuming: {resumed} of {} already have a finished result in {} for the same file \
             and settings (--regrade grades them again)",
            students.len(),
            out.display()
        );
    }
    if options.progress && !copies.is_empty() {
        eprintln!(
            "{} submissions are identical to another one: each file is graded once",
            copies.len()
        );
    }

    let jobs = options.jobs.clamp(1, queue.len().max(1));
    // Nothing to build when every result is already there.
    let (workers, _cleanup_build) = if queue.is_empty() {
        (Vec::new(), None)
    } else {
        prepare_workers(root, &template, scratch, jobs, options)?
    };

    let started = Instant::now();
    let to_grade = queue.len();
    let queue = std::sync::Mutex::new(queue);
    let failed = std::sync::atomic::AtomicBool::new(false);
    let (sender, results) = std::sync::mpsc::channel::<(usize, Result<Row, String>)>();
    let mut error = None;
    let mut own = 0.0;
    std::thread::scope(|scope| {
        for (jail, exe) in &workers {
            let sender = sender.clone();
            let (queue, failed, students, keys) = (&queue, &failed, &students, &keys);
            let (template, fixtures, out) = (&template, &fixtures, &out);
            scope.spawn(move || loop {
                if failed.load(std::sync::atomic::Ordering::SeqCst) {
                    break;
                }
                let Some(i) = queue.lock().unwrap_or_else(|p| p.into_inner()).pop_front() else {
                    break;
                };
                let t0 = Instant::now();
                let s = &students[i];
                let row = grade_one(s, template, jail, fixtures, out, exe, counts, options)
                    .and_then(|row| {
                        let row = Row {
                            seconds: t0.elapsed().as_secs_f64(),
                            ..row
                        };
                        // Last, and whole: a result file means its reports
                        // are all there.
                        write_row(out, &row, keys[i].as_deref())?;
                        Ok(row)
                    });
                if row.is_err() {
                    failed.store(true, std::sync::atomic::Ordering::SeqCst);
                }
                if sender.send((i, row)).is_err() {
                    break;
                }
            });
        }
        drop(sender);
        let mut finished = 0;
        for (i, row) in results {
            match row {
                Ok(row) => {
                    finished += 1;
                    own += row.seconds;
                    if options.progress {
                        let wall = started.elapsed().as_secs_f64();
                        let left = wall / finished as f64 * (to_grade - finished) as f64;
                        eprintln!(
                            "[{finished:>3}/{to_grade}] {:<20} {:>5}/{:<3} {:<16} {:>5.1} s  \
                             (about {left:.0} s left)",
                            quoted::one_line(&row.name),
                            row.score,
                            row.max,
                            row.status,
                            row.seconds,
                        );
                    }
                    done[i] = Some(row);
                }
                Err(e) => {
                    error.get_or_insert(e);
                }
            }
        }
    });
    if let Some(e) = error {
        return Err(e);
    }
    if options.progress && to_grade > 0 {
        let wall = started.elapsed().as_secs_f64();
        eprintln!(
            "graded {to_grade} files in {wall:.1} s with {} job(s) ({:.1} s a file; their own \
             times add up to {own:.1} s)",
            workers.len(),
            wall / to_grade as f64
        );
    }
    // An identical file's result, under this student's name: the reports
    // are copied (the short one says so), the row says whose was graded.
    for (i, first) in copies {
        let source = done[first]
            .clone()
            .ok_or("an identical file was not graded")?;
        let name = &students[i].name;
        let row = Row {
            name: name.clone(),
            same_as: Some(source.same_as.clone().unwrap_or(source.name.clone())),
            seconds: 0.0,
            ..source.clone()
        };
        copy_reports(&out, &source.name, name)?;
        write_row(&out, &row, keys[i].as_deref())?;
        done[i] = Some(row);
    }
    let mut rows: Vec<Row> = done.into_iter().flatten().collect();
    for r in &mut rows {
        r.handed_in = handed_in.get(&r.name).cloned();
    }

    // The summary, rebuilt from every student's finished result: with
    // --only, the others' results stay as they were (their result files,
    // or the last summary's rows for reports written before those).
    let summary = out.join("summary.json");
    let last = if options.only.is_empty() {
        Vec::new()
    } else {
        read_rows(&summary)?
    };
    let mut all: Vec<Row> = Vec::new();
    for s in &everyone {
        if let Some(r) = rows.iter().find(|r| r.name == s.name) {
            all.push(r.clone());
        } else if let Some((r, _)) = read_row(&out, &s.name) {
            all.push(r);
        } else if let Some(r) = last.iter().find(|r| r.name == s.name) {
            all.push(r.clone());
        }
    }
    // This run's deadline, also for rows kept from an earlier run.
    for r in &mut all {
        r.handed_in = handed_in.get(&r.name).cloned();
    }
    if let Some(roster) = &roster {
        join_roster(&mut all, roster, counts);
    }
    all.sort_by(|a, b| a.name.cmp(&b.name));
    let json: Vec<serde_json::Value> = all.iter().map(Row::to_json).collect();
    write_atomically(&summary, &pretty(&serde_json::Value::Array(json)))?;
    write_atomically(
        &out.join("summary.csv"),
        &summary_csv(&all, roster.as_deref()),
    )?;
    write_atomically(
        &out.join("canvas.csv"),
        &canvas_csv(&all, roster.as_deref(), &options.assignment, counts),
    )?;
    if options.before.is_some() {
        std::fs::write(out.join("commits.csv"), commits).map_err(|e| e.to_string())?;
    }
    // Hints for the TA over the whole class (every entry of the folder,
    // also with --only), and the page that shows the class at a glance.
    let stubs = std::fs::read_to_string(template.join("crates/meshedit/src/lib.rs"))
        .map_err(|e| format!("the lab's stubs: {e}"))?;
    let (pairs, not_compared) = similar_submissions(&everyone, &stubs);
    std::fs::write(out.join("similarity.csv"), crate::similarity::csv(&pairs))
        .map_err(|e| e.to_string())?;
    for f in &not_compared {
        eprintln!(
            "similarity: {} ({} bytes) is larger than the {} KiB compared: left out of \
             similarity.csv but for an identical file",
            quoted::one_line(&f.name),
            f.bytes,
            crate::similarity::MAX_BYTES >> 10
        );
    }
    let overview: Vec<crate::overview::Student> = all
        .iter()
        .map(|r| {
            // The report this tool wrote, by the name it chose.
            let report = format!("{}.txt", file_stem(&r.name));
            crate::overview::Student {
                name: r.name.clone(),
                score: r.score,
                max: r.max,
                status: r.status.clone(),
                first_failure: r.first_failure.clone(),
                cases: r.cases.clone(),
                report: out.join(&report).is_file().then_some(report),
            }
        })
        .collect();
    std::fs::write(
        out.join("overview.html"),
        crate::overview::page("Class overview", &overview, &pairs, &not_compared),
    )
    .map_err(|e| e.to_string())?;
    Ok(rows)
}

/// Each worker's build and grader program.
type Workers = Vec<(Build, PathBuf)>;

/// The workers' builds: the build folder (vendored dependencies, and the
/// lab built once there, locked in like every build), then per worker a
/// copy of the lab and a target folder of its own. Returns each worker's
/// build and grader program, and the build folder's remover (a temporary
/// one, when no `--build-dir` was given).
fn prepare_workers(
    root: &Path,
    template: &Path,
    scratch: &Path,
    jobs: usize,
    options: &Options,
) -> Result<(Workers, Option<RunDir>), String> {
    let (build_dir, _cleanup_build) = match &options.build_dir {
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
            (dir, None)
        }
        None => {
            let dir = run_dir("meshlab-build-")?;
            (dir.path().to_path_buf(), Some(dir))
        }
    };
    // Each worker's copy of the lab, at the same place in every run, so
    // that cargo finds the lab's own crates built (their paths are in
    // their fingerprints); restored from the template for each student.
    let work = build_dir.join("lab");
    let target = build_dir.join("target");
    let vendor = build_dir.join("vendor");
    // The dependencies' sources, out of the TA's cargo home (which holds
    // more than sources), at a fixed place beside the target folder (their
    // path is in the compiled dependencies' fingerprints).
    // Vendored again only when the lock file changed: a stamp of the lock
    // file it was vendored from, written last.
    let lock =
        std::fs::read(template.join("Cargo.lock")).map_err(|e| format!("Cargo.lock: {e}"))?;
    let stamp = build_dir.join("vendor.lock");
    if std::fs::read(&stamp).ok().as_ref() != Some(&lock) || !vendor.is_dir() {
        let _ = std::fs::remove_file(&stamp);
        let _ = std::fs::remove_dir_all(&vendor);
        let vendor_offline = || {
            Command::new(handout::cargo())
                .args(["vendor", "--locked", "--offline", "--quiet"])
                .arg(&vendor)
                .current_dir(template)
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
                .current_dir(template)
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
        std::fs::write(&stamp, &lock).map_err(|e| format!("{}: {e}", stamp.display()))?;
    }
    let mut sysroot = autograde::local::sysroot(template)?;
    let mut drop_user = false;
    let build = |seconds: f64, status: PathBuf, sysroot: &Path, drop_user: bool| Build {
        lab: work.clone(),
        vendor: vendor.clone(),
        sysroot: sysroot.to_path_buf(),
        target: target.clone(),
        memory: options.build_memory,
        seconds,
        status,
        drop_user,
        landlock: options.landlock,
        empty_root: true,
    };
    let exe = grade::programs_dir(&target).join(format!(
        "{}{}",
        grade::PROGRAMS[0],
        std::env::consts::EXE_SUFFIX
    ));

    // Build the lab once, with no budget: the dependencies' first build
    // (a minute or more) must not count against the first student. Locked
    // in like every build, so that the students' builds find it fresh.
    if options.progress {
        eprintln!("building the lab once (the first time takes a minute or two)...");
    }
    let _ = std::fs::remove_dir_all(&work);
    copy_keeping_times(template, &work)?;
    let logs = scratch.join("logs");
    std::fs::create_dir_all(&logs).map_err(|e| e.to_string())?;
    let warm_build = |sysroot: &Path, drop_user: bool| {
        let b = build(3600.0, logs.join("warm.status"), sysroot, drop_user);
        let warm = grade::build(&b, &options.launcher, &logs)?;
        if warm.report.outcome != Outcome::Built {
            return Err(format!(
                "the lab itself does not build ({}):\n{}",
                warm.report.failure().unwrap_or_default(),
                warm.log
            ));
        }
        Ok(warm)
    };
    let mut warm = warm_build(&sysroot, false)?;
    if warm.report.landlock == 0 {
        if autograde::process::is_root() {
            // No Landlock to keep the build from the TA's files: the next
            // strongest, a user of its own (`nobody`, who can read only
            // what everyone may) building a private copy of the lab (the
            // hidden cases out of it, in a folder only root may enter).
            sysroot = for_nobody(scratch, &build_dir, &target, &sysroot)?;
            drop_user = true;
            warm = warm_build(&sysroot, true)?;
            if options.progress {
                eprintln!(
                    "this kernel has no Landlock: students' builds run as user nobody, on a \
                     private copy of the lab (they can read what every user may)"
                );
            }
        } else if options.progress {
            eprintln!(
                "warning: this kernel has no Landlock: students' builds can read every file you \
                 can (run class grading as root, which builds as user nobody, or as a user who \
                 can read only the lab, or on a newer kernel)"
            );
        }
    }
    if options.progress {
        eprintln!("{}", warm.report.protections());
    }

    // One worker per job, each with its own copy of the lab and its own
    // target folder: cargo locks a target folder for the whole build, and
    // each student's crate must be built where no other student's is. The
    // dependencies, compiled once above, are copied into the others'.
    let seconds = options.build_seconds.unwrap_or(options.budget.max(60.0));
    // Without Landlock nothing keeps one build out of another's copy of the
    // lab or target folder (as nobody, the target folders are all
    // nobody's): one at a time, then.
    let jobs = if warm.report.landlock == 0 && jobs > 1 {
        eprintln!(
            "without Landlock the builds cannot be kept apart from each other: grading one \
             submission at a time (-j {jobs} ignored)"
        );
        1
    } else {
        jobs
    };
    let mut workers = vec![(
        build(seconds, logs.join("build.status"), &sysroot, drop_user),
        exe.clone(),
    )];
    for k in 1..jobs {
        let lab = build_dir.join(format!("lab-{k}"));
        let own_target = build_dir.join(format!("target-{k}"));
        if !own_target.is_dir() {
            copy_dependencies(&target, &own_target)?;
        }
        if drop_user {
            to_nobody(&own_target)?;
        }
        forget_submission(&own_target);
        copy_keeping_times(template, &lab)?;
        let jail = Build {
            lab,
            target: own_target.clone(),
            status: logs.join(format!("warm-{k}.status")),
            seconds: 3600.0,
            ..build(seconds, PathBuf::new(), &sysroot, drop_user)
        };
        let warm = grade::build(&jail, &options.launcher, &logs)?;
        if warm.report.outcome != Outcome::Built {
            return Err(format!(
                "the lab does not build in worker {k}'s copy ({}):\n{}",
                warm.report.failure().unwrap_or_default(),
                warm.log
            ));
        }
        let exe = grade::programs_dir(&own_target).join(format!(
            "{}{}",
            grade::PROGRAMS[0],
            std::env::consts::EXE_SUFFIX
        ));
        workers.push((
            Build {
                seconds,
                status: logs.join(format!("build-{k}.status")),
                ..jail
            },
            exe,
        ));
    }

    Ok((workers, _cleanup_build))
}

/// The compiled dependencies of `target` into a new target folder `to`
/// (without the incremental caches, which are the lab's crates' only), so
/// that another worker's builds start where the first one's did.
fn copy_dependencies(target: &Path, to: &Path) -> Result<(), String> {
    let debug = to.join("debug");
    std::fs::create_dir_all(&debug).map_err(|e| format!("{}: {e}", debug.display()))?;
    let from = target.join("debug");
    for entry in std::fs::read_dir(&from).map_err(|e| format!("{}: {e}", from.display()))? {
        let path = entry.map_err(|e| e.to_string())?.path();
        if path.file_name().is_some_and(|n| n == "incremental") {
            continue;
        }
        let copied = Command::new("cp")
            .args(["-a", "--reflink=auto"])
            .arg(&path)
            .arg(&debug)
            .status()
            .map_err(|e| format!("cannot run cp: {e}"))?;
        if !copied.success() {
            let _ = std::fs::remove_dir_all(to);
            return Err(format!(
                "cannot copy {} to {}",
                path.display(),
                debug.display()
            ));
        }
    }
    Ok(())
}

/// Everything besides the file that decides a grade, as text: the
/// options, this program's version and the fixtures' digests. A finished
/// result is reused only under the same settings.
fn settings_key(root: &Path, options: &Options) -> String {
    let mut key = format!(
        "reference {} timeout {} budget {} bonus {} fresh {} before {:?} args {:?}\n",
        env!("CARGO_PKG_VERSION"),
        options.timeout,
        options.budget,
        options.bonus,
        options.fresh,
        options.before,
        options.grader_args
    );
    for group in ["lab", "bonus", "hidden"] {
        let sums = root.join("fixtures").join(group).join("SHA256SUMS");
        key.push_str(&std::fs::read_to_string(sums).unwrap_or_default());
    }
    key
}

/// `NAME.row.json`: a student's finished result and the key it was graded
/// under.
fn row_path(out: &Path, name: &str) -> PathBuf {
    out.join(format!("{}.row.json", file_stem(name)))
}

/// A student's finished result in `out` and its key ("" when the entry had
/// no file), if there is one that reads.
fn read_row(out: &Path, name: &str) -> Option<(Row, String)> {
    let text = std::fs::read_to_string(row_path(out, name)).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    let row = Row::from_json(&v["row"])?;
    (row.name == name).then(|| (row, v["key"].as_str().unwrap_or("").to_string()))
}

fn write_row(out: &Path, row: &Row, key: Option<&str>) -> Result<(), String> {
    let v = serde_json::json!({ "key": key, "row": row.to_json() });
    write_atomically(&row_path(out, &row.name), &pretty(&v))
}

/// Writes `path` whole or not at all (a run killed midway leaves either
/// the old file or the new one): a file beside it, then a rename.
fn write_atomically(path: &Path, text: &str) -> Result<(), String> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let temporary = path.with_file_name(format!(
        ".{name}.{}-{}.part",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::SeqCst)
    ));
    std::fs::write(&temporary, text).map_err(|e| format!("{}: {e}", temporary.display()))?;
    std::fs::rename(&temporary, path).map_err(|e| format!("{}: {e}", path.display()))
}

/// `from`'s reports as `to`'s, whose file is identical: the short report
/// names `to` and says whose file was graded.
fn copy_reports(out: &Path, from: &str, to: &str) -> Result<(), String> {
    let (from_file, to_file) = (file_stem(from), file_stem(to));
    for ext in ["log", "results.json"] {
        let (a, b) = (
            out.join(format!("{from_file}.{ext}")),
            out.join(format!("{to_file}.{ext}")),
        );
        std::fs::copy(&a, &b).map_err(|e| format!("{}: {e}", a.display()))?;
    }
    let path = out.join(format!("{from_file}.txt"));
    let short = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let (from_shown, to_shown) = (quoted::one_line(from), quoted::one_line(to));
    let rest = short
        .strip_prefix(from_shown.as_str())
        .unwrap_or(&short)
        .replace(&format!("{from_file}.log"), &format!("{to_file}.log"));
    let (head, tail) = rest.split_once('\n').unwrap_or((&rest, ""));
    let path = out.join(format!("{to_file}.txt"));
    std::fs::write(
        &path,
        format!(
            "{to_shown}{head}\n  (graded once: this file is byte for byte {from_shown}'s)\n{tail}"
        ),
    )
    .map_err(|e| format!("{}: {e}", path.display()))
}

/// Adds a `no submission` row for every roster student without one, and
/// says on standard error which submissions are no roster student's and
/// which students have two.
fn join_roster(all: &mut Vec<Row>, roster: &[crate::roster::Student], counts: [usize; 4]) {
    let unknown: Vec<&str> = all
        .iter()
        .filter(|r| !roster.iter().any(|s| s.owns(&r.name)))
        .map(|r| r.name.as_str())
        .collect();
    if !unknown.is_empty() {
        eprintln!(
            "not in the roster ({} submissions; their rows say in_roster no, canvas.csv leaves \
             them out): {}",
            unknown.len(),
            quoted::one_line(&unknown.join(", "))
        );
    }
    for s in roster {
        let theirs: Vec<&str> = all
            .iter()
            .filter(|r| s.owns(&r.name))
            .map(|r| r.name.as_str())
            .collect();
        if theirs.len() > 1 {
            eprintln!(
                "{} has {} submissions ({}): canvas.csv has the highest score",
                quoted::one_line(&s.name),
                theirs.len(),
                quoted::one_line(&theirs.join(", "))
            );
        }
    }
    let mut missing = Vec::new();
    for s in roster {
        if !all.iter().any(|r| s.owns(&r.name)) {
            missing.push(Row {
                name: s.key().to_string(),
                score: 0.0,
                max: counts.iter().sum::<usize>() as f64,
                status: "no submission".into(),
                functions: counts.map(|n| (0, n)),
                first_failure: "no submission (in the roster, not in the submissions folder)"
                    .into(),
                seconds: 0.0,
                cases: Vec::new(),
                same_as: None,
                handed_in: None,
            });
        }
    }
    all.extend(missing);
}

/// `canvas.csv` (see [`crate::roster::canvas_csv`]): with a roster, one
/// row per roster student; without, one per row, its name as the SIS login.
fn canvas_csv(
    all: &[Row],
    roster: Option<&[crate::roster::Student]>,
    assignment: &str,
    counts: [usize; 4],
) -> String {
    let max = counts.iter().sum::<usize>() as f64;
    let own: Vec<crate::roster::Student>;
    let students = match roster {
        Some(r) => r,
        None => {
            own = all
                .iter()
                .map(|r| crate::roster::Student {
                    name: r.name.clone(),
                    sis_login_id: r.name.clone(),
                    ids: vec![r.name.clone()],
                    ..Default::default()
                })
                .collect();
            &own
        }
    };
    let grades: Vec<crate::roster::Grade> = students
        .iter()
        .map(|s| crate::roster::Grade {
            student: s,
            score: all
                .iter()
                .filter(|r| s.owns(&r.name))
                .map(|r| r.score)
                .fold(0.0, f64::max),
        })
        .collect();
    crate::roster::canvas_csv(assignment, max, &grades)
}

/// Each repository's commit graded and when it was handed in, by row name.
type HandedInByName = std::collections::HashMap<String, crate::deadline::HandedIn>;

/// `--before`: each submission becomes what its repository had handed in
/// by the deadline (Unix seconds), copied out into `into` (an entry that is
/// no repository, or has nothing by then, gets a row saying so), dated by
/// `records` where they name it, else by its commit dates. Returns
/// `commits.csv` and, by row name, the commit and when it was handed in.
fn at_deadline(
    students: &mut [Submission],
    submissions: &Path,
    deadline: i64,
    records: Option<&crate::deadline::Records>,
    into: &Path,
) -> Result<(String, HandedInByName), String> {
    std::fs::create_dir_all(into).map_err(|e| format!("{}: {e}", into.display()))?;
    let mut csv = String::from("student,commit,date,clock,committer_date\n");
    let mut handed_in = HandedInByName::new();
    for (i, s) in students.iter_mut().enumerate() {
        let repo = submissions.join(&s.name);
        if !crate::deadline::is_repository(&repo) {
            s.lib_rs = Err(format!(
                "not a git repository: --before {} grades what was handed in by the \
                 deadline, and this entry has no history",
                autograde::clock::iso8601(deadline)
            ));
            continue;
        }
        let theirs = records.map(|r| (r.of(&s.name), r.clock));
        let theirs = theirs
            .as_ref()
            .filter(|(list, _)| !list.is_empty())
            .map(|(list, clock)| (list.as_slice(), *clock));
        match crate::deadline::snapshot(&repo, deadline, theirs, &into.join(i.to_string())) {
            Ok(snap) => {
                let _ = writeln!(
                    csv,
                    "{},{},{},{},{}",
                    quoted::csv_field(&s.name),
                    snap.commit,
                    snap.date,
                    snap.clock.label(),
                    snap.committer_date
                );
                handed_in.insert(
                    s.name.clone(),
                    crate::deadline::HandedIn {
                        commit: snap.commit,
                        at: snap.date,
                        clock: snap.clock,
                    },
                );
                s.lib_rs = take_lib_rs(&into.join(i.to_string()))
                    .map(|(lib_rs, _)| lib_rs)
                    .map_err(|e| e.message());
            }
            Err(why) => s.lib_rs = Err(why),
        }
    }
    Ok((csv, handed_in))
}

/// The similarity hints over every submission whose file can be read (at
/// the deadline's commit with `--before`), and the files too large to
/// compare. One file is held at a time: each is read, fingerprinted and
/// let go.
fn similar_submissions(
    students: &[Submission],
    stubs: &str,
) -> (
    Vec<crate::similarity::Pair>,
    Vec<crate::similarity::NotCompared>,
) {
    let fingerprinter = crate::similarity::Fingerprinter::new(stubs);
    let prints = students
        .iter()
        .filter_map(|s| {
            let bytes = read_source(s.lib_rs.as_ref().ok()?).ok()?;
            let text = String::from_utf8(bytes).ok()?;
            Some(fingerprinter.of(&s.name, &text))
        })
        .collect();
    crate::similarity::pairs_of(prints, crate::similarity::THRESHOLD)
}

/// The rows `summary.json` holds (none when there is no such file).
fn read_rows(path: &Path) -> Result<Vec<Row>, String> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return Ok(Vec::new());
    };
    let v: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    v.as_array()
        .ok_or(format!("{}: not a list of rows", path.display()))?
        .iter()
        .map(|r| Row::from_json(r).ok_or(format!("{}: a row is not one: {r}", path.display())))
        .collect()
}

impl Row {
    fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "name": self.name, "score": self.score, "max": self.max, "status": self.status,
            "functions": self.functions.map(|(p, of)| [p, of]),
            "first_failure": self.first_failure, "seconds": self.seconds,
            "cases": self.cases.iter().map(|c| serde_json::json!([c.name, c.function, c.passed]))
                .collect::<Vec<_>>(),
            "same_as": self.same_as,
            "handed_in": self.handed_in.as_ref().map(crate::deadline::HandedIn::to_json),
        })
    }

    fn from_json(v: &serde_json::Value) -> Option<Row> {
        let mut functions = [(0, 0); 4];
        for (k, f) in v["functions"].as_array()?.iter().enumerate().take(4) {
            functions[k] = (f[0].as_u64()? as usize, f[1].as_u64()? as usize);
        }
        Some(Row {
            name: v["name"].as_str()?.to_string(),
            score: v["score"].as_f64()?,
            max: v["max"].as_f64()?,
            status: v["status"].as_str()?.to_string(),
            functions,
            first_failure: v["first_failure"].as_str()?.to_string(),
            seconds: v["seconds"].as_f64()?,
            // Absent from a summary written before the overview existed.
            cases: v["cases"]
                .as_array()
                .into_iter()
                .flatten()
                .filter_map(|c| {
                    Some(crate::overview::CaseResult {
                        name: c[0].as_str()?.to_string(),
                        function: c[1].as_str()?.to_string(),
                        passed: c[2].as_bool()?,
                    })
                })
                .collect(),
            same_as: v["same_as"].as_str().map(str::to_string),
            handed_in: crate::deadline::HandedIn::from_json(&v["handed_in"]),
        })
    }
}

/// `summary.csv`, for spreadsheets and gradebooks: numbers in numeric
/// columns (points and maximum per function, the percentage), the text
/// ones made inert (see [`quoted::csv_field`]).
/// With a roster, each row also says the roster's name, section and
/// whether the student is in it (`in_roster`: `yes` or `no`).
pub fn summary_csv(rows: &[Row], roster: Option<&[crate::roster::Student]>) -> String {
    let mut csv = String::from("student,score,max_score,percent,status");
    for stage in &STAGES {
        let _ = write!(csv, ",{0},{0}_max", stage.column);
    }
    csv.push_str(",first_failure,graded_as");
    let deadline = rows.iter().any(|r| r.handed_in.is_some());
    if deadline {
        csv.push_str(",commit,handed_in_at,clock");
    }
    if roster.is_some() {
        csv.push_str(",name,section,in_roster");
    }
    csv.push('\n');
    for r in rows {
        let percent = if r.max > 0.0 {
            100.0 * r.score / r.max
        } else {
            0.0
        };
        let _ = write!(
            csv,
            "{},{},{},{percent:.1},{}",
            quoted::csv_field(&r.name),
            r.score,
            r.max,
            r.status
        );
        for (passed, of) in r.functions {
            let _ = write!(csv, ",{passed},{of}");
        }
        let _ = write!(
            csv,
            ",{},{}",
            quoted::csv_field(&r.first_failure),
            quoted::csv_field(r.same_as.as_deref().unwrap_or(""))
        );
        if deadline {
            match &r.handed_in {
                Some(h) => {
                    let _ = write!(csv, ",{},{},{}", h.commit, h.at, h.clock.label());
                }
                None => csv.push_str(",,,"),
            }
        }
        if let Some(roster) = roster {
            match roster.iter().find(|s| s.owns(&r.name)) {
                Some(s) => {
                    let _ = write!(
                        csv,
                        ",{},{},yes",
                        quoted::csv_field(&s.name),
                        quoted::csv_field(&s.section)
                    );
                }
                None => csv.push_str(",,,no"),
            }
        }
        csv.push('\n');
    }
    csv
}

/// Grades one entry; an error here is the TA's (disk, cargo missing), never
/// the student's: a student's problem becomes the row's status.
#[allow(clippy::too_many_arguments)]
fn grade_one(
    s: &Submission,
    template: &Path,
    jail: &Build,
    fixtures: &Path,
    out: &Path,
    exe: &Path,
    counts: [usize; 4],
    options: &Options,
) -> Result<Row, String> {
    let max: usize = counts.iter().sum();
    let write = |ext: &str, text: &str| {
        let path = out.join(format!("{}.{ext}", file_stem(&s.name)));
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
        cases: Vec::new(),
        same_as: None,
        handed_in: None,
    };
    // `why` is the student's message (its first line is the gist), `log`
    // the build's whole output.
    let not_graded = |row: &mut Row, status: &str, why: &str, log: &str| -> Result<(), String> {
        row.status = status.into();
        // The compiler's first error rather than the heading above it.
        row.first_failure = why
            .lines()
            .map(|l| l.trim_start_matches("| "))
            .find(|l| l.starts_with("error"))
            .or_else(|| why.lines().next())
            .unwrap_or("")
            .to_string();
        write(
            "txt",
            &format!(
                "{}: {status} (0 of {max})\n\n{why}\n",
                quoted::one_line(&s.name)
            ),
        )?;
        write("log", &autograde::shown(log))?;
        let results = platform::gradescope(&platform::Outcome::NotGraded {
            message: why.to_string(),
            counts,
        });
        write("results.json", &pretty(&results))
    };
    let lib_rs = match &s.lib_rs {
        Ok(p) => p,
        Err(why) => {
            not_graded(&mut row, "no submission", &autograde::shown(why), why)?;
            return Ok(row);
        }
    };

    // A pristine copy for each student: nothing a previous submission did
    // to its copy survives, nor its compiled crate in the target folder.
    // Read as every platform reads it: a file that changed into a pipe, a
    // device or a large file since it was found is this row's reason.
    let bytes = match read_source(lib_rs) {
        Ok(bytes) => bytes,
        Err(why) => {
            let shown = lib_rs.file_name().unwrap_or_default().to_string_lossy();
            let why = why.message(&shown);
            not_graded(&mut row, "no submission", &autograde::shown(&why), &why)?;
            return Ok(row);
        }
    };
    let work = jail.lab.as_path();
    let _ = std::fs::remove_dir_all(work);
    copy_keeping_times(template, work)?;
    let student = work.join("crates/meshedit/src/lib.rs");
    std::fs::write(&student, &bytes).map_err(|e| format!("{}: {e}", student.display()))?;
    forget_submission(&jail.target);

    // Outside the copy the student's code runs in.
    let logs = work.with_file_name(format!(
        "{}-logs",
        work.file_name().unwrap_or_default().to_string_lossy()
    ));
    let _ = std::fs::remove_dir_all(&logs);
    std::fs::create_dir_all(&logs).map_err(|e| e.to_string())?;
    let built = grade::build(jail, &options.launcher, &logs)?;
    let build_log = format!("{}\n{}", built.report.protections(), built.log);
    let compiler = built.compiler();
    match built.report.outcome {
        Outcome::Built => {}
        Outcome::NotLockedIn => {
            return Err(built.report.failure().unwrap_or_default());
        }
        Outcome::OutOfMemory | Outcome::OutOfTime => {
            let message = built.report.failure().unwrap_or_default();
            let why = autograde::does_not_compile(Some(&message), &compiler);
            not_graded(&mut row, "does not compile", &why, &build_log)?;
            // The limit it hit, rather than the compiler's last words.
            row.first_failure = message;
            return Ok(row);
        }
        Outcome::Failed => {
            let why = autograde::does_not_compile(None, &compiler);
            not_graded(&mut row, "does not compile", &why, &build_log)?;
            return Ok(row);
        }
    }

    // This submission's fresh cases, in a private copy of the fixtures
    // (removed once it is graded).
    let fresh = if options.fresh {
        Some(fresh_fixtures(fixtures, &bytes)?)
    } else {
        None
    };
    let fixtures = fresh.as_ref().map_or(fixtures, |(dir, _)| dir.path());

    // One grader run per stage, the budget shared out by the runs each
    // makes; each under a reaper that sweeps what the submission left.
    let grading = grade::Grading {
        exe: exe.to_path_buf(),
        cwd: work.to_path_buf(),
        fixtures: fixtures.to_path_buf(),
        timeout: options.timeout,
        bonus: options.bonus,
        logs: logs.clone(),
        reaper: options.launcher.clone(),
        extra_args: options.grader_args.clone(),
    };
    let start = Instant::now();
    let left = || options.budget - start.elapsed().as_secs_f64();
    let stages = grade::grade_stages(&grading, &left);
    let notes = if compiler.contains("warning") {
        vec![format!(
            "Your code compiles with warnings:\n\n{}",
            Quoted::new(&*compiler).block("")
        )]
    } else {
        Vec::new()
    };
    let outcome = platform::Outcome::Graded {
        stages,
        notes,
        bonus: options.bonus,
    };
    let platform::Outcome::Graded { stages, .. } = &outcome else {
        unreachable!("graded just above")
    };

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
    for run in stages {
        let _ = writeln!(
            full,
            "time: {}: each call may take {} in a budget of {:.1} s",
            run.stage.function,
            run.limit(),
            run.budget
        );
    }
    full.push('\n');
    if !compiler.is_empty() {
        let _ = writeln!(
            full,
            "compiler output:\n{}",
            Quoted::new(&*compiler).block("")
        );
    }
    let mut failures = Vec::new();
    for run in stages {
        if !run.graded() {
            let why = run.why_not_graded();
            let _ = writeln!(full, "== {}: not graded: {why}", run.stage.function);
            if !run.error.trim().is_empty() {
                full.push_str(&Quoted::new(run.error.trim()).block("    "));
            }
            failures.push(why);
            continue;
        }
        let bonus = run
            .report
            .as_ref()
            .is_some_and(|r| r["bonus_counted"] == true);
        for c in run.case_reports() {
            let name = c["name"].as_str().unwrap_or("?");
            let passed = c["passed"].as_bool().unwrap_or(false);
            row.cases.push(crate::overview::CaseResult {
                name: name.to_string(),
                function: run.stage.function.to_string(),
                passed,
            });
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
            let is_counted = c["group"] != "bonus" || bonus;
            if is_counted && !passed {
                let first = c["first_warning"].as_str().unwrap_or("failed");
                failures.push(quoted::one_line(&format!("{name}: {first}")));
            }
        }
    }
    let counted = outcome.per_function();
    let (passed, total) = (outcome.score(), outcome.max());
    row.functions = counted;
    row.score = passed as f64;
    row.max = total as f64;
    row.status = if passed == total {
        "passed"
    } else if stages.iter().any(|r| r.code.is_none()) {
        "out of time"
    } else {
        "failed"
    }
    .into();
    row.first_failure = failures.first().cloned().unwrap_or_default();

    let mut short = format!(
        "{}: {} ({passed} of {total})\n",
        quoted::one_line(&s.name),
        row.status
    );
    for (k, stage) in STAGES.iter().enumerate() {
        let _ = writeln!(
            short,
            "  {:<15} {}/{}",
            stage.column, counted[k].0, counted[k].1
        );
    }
    if let Some(line) = &fresh_line {
        let _ = writeln!(short, "  {line}");
    }
    if compiler.contains("warning") {
        let _ = writeln!(short, "\ncompiler warnings: see {}.log", file_stem(&s.name));
    }
    if !failures.is_empty() {
        let _ = writeln!(short, "\nfailed cases:");
        for f in failures.iter().take(10) {
            let _ = writeln!(short, "  {f}");
        }
        if failures.len() > 10 {
            let _ = writeln!(short, "  ... and {} more", failures.len() - 10);
        }
        let _ = writeln!(short, "\nthe full log: {}.log", file_stem(&s.name));
    }
    write("txt", &short)?;
    write("log", &full)?;
    write("results.json", &pretty(&platform::gradescope(&outcome)))?;
    Ok(row)
}

fn pretty(v: &serde_json::Value) -> String {
    serde_json::to_string_pretty(v).expect("JSON")
}

#[cfg(test)]
mod tests {
    use super::file_stem;

    #[test]
    fn plain_names_keep_their_files_and_no_other_name_shapes_one() {
        for plain in [
            "alice",
            "bob.rs",
            "=cmd()",
            "+1",
            "-2",
            "@loopy",
            "pia@uni.edu",
            "张三",
        ] {
            assert_eq!(file_stem(plain), plain);
        }
        let hostile = [
            "javascript:alert(document.title)",
            "a b",
            "a_b",
            "line\nbreak",
            "\u{202e}gnp.exe",
            "..",
            ".hidden",
            "a/b",
            "",
            &"x".repeat(250),
            &"x".repeat(251),
        ];
        let mut seen = std::collections::HashSet::new();
        for name in hostile {
            let stem = file_stem(name);
            assert!(seen.insert(stem.clone()), "{name:?} shares {stem}");
            assert!(stem.len() <= 100 + 17, "{name:?}: {stem}");
            assert!(!stem.starts_with('.'), "{name:?}: {stem}");
            assert!(
                stem.chars()
                    .all(|c| c.is_alphanumeric() || "-_.@+=,()~".contains(c)),
                "{name:?}: {stem}"
            );
            // What a plain name keeps is never what a chosen one is.
            assert_eq!(file_stem(&stem) == stem, name == "a_b", "{name:?}: {stem}");
        }
        let chosen = file_stem("javascript:alert(document.title)");
        assert!(
            chosen.starts_with("javascript_alert(document.title)-"),
            "{chosen}"
        );
        assert_ne!(
            file_stem(&chosen),
            chosen,
            "a name shaped like a chosen one"
        );
    }
}
