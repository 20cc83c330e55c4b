//! Gradescope's side: grading the upload in `/autograder/submission` into
//! `/autograder/results/results.json`, as set up by the bundle's
//! `run_autograder --setup` ([`crate::setup::gradescope`] moved the hidden
//! cases into `meshlab/fixtures`, a folder only root may enter, vendored
//! the dependencies and wrote `meshlab/settings.json`). `run_autograder`
//! execs this for each submission; `AUTOGRADER` replaces `/autograder` in
//! tests.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::build::{Build, Outcome as BuildOutcome};
use serde_json::{json, Value};

use crate::grade::{self, Grading, PROGRAMS};
use crate::platform::{self, Outcome};
use crate::process;

/// Seconds kept back at the end to write the results.
pub const RESERVE: f64 = 10.0;
/// The memory cap of each compiler process (address space: rustc reserves
/// far more than it uses; this lab's build peaks near 1 GiB resident).
pub const BUILD_MEMORY: u64 = 4 << 30;

/// The bundle's settings (`reference gradescope` bakes them into
/// `run_autograder`, which passes them on).
#[derive(Clone, Debug)]
pub struct Options {
    /// Seconds the whole run may take.
    pub budget: f64,
    /// Seconds each call may take at most.
    pub timeout: f64,
    pub bonus: bool,
}

/// Where everything is, under `/autograder` (or `AUTOGRADER`).
#[derive(Clone, Debug)]
pub struct Places {
    pub root: PathBuf,
}

impl Places {
    pub fn from_env() -> Places {
        let root = std::env::var_os("AUTOGRADER")
            .map(PathBuf::from)
            .unwrap_or_else(|| PathBuf::from("/autograder"));
        Places {
            root: std::path::absolute(&root).unwrap_or(root),
        }
    }
    pub fn lab(&self) -> PathBuf {
        self.root.join("source/lab")
    }
    pub(crate) fn state(&self) -> PathBuf {
        self.root.join("meshlab")
    }
    pub fn fixtures(&self) -> PathBuf {
        self.state().join("fixtures")
    }
    pub(crate) fn fresh(&self) -> PathBuf {
        self.state().join("fresh")
    }
    pub(crate) fn vendor(&self) -> PathBuf {
        self.state().join("vendor")
    }
    fn bin(&self) -> PathBuf {
        self.state().join("bin")
    }
    pub(crate) fn settings(&self) -> PathBuf {
        self.state().join("settings.json")
    }
    pub fn results(&self) -> PathBuf {
        self.root.join("results/results.json")
    }
    fn submission(&self) -> PathBuf {
        self.root.join("submission")
    }
}

/// The autograder's own log: Gradescope shows stdout to instructors only.
struct Log(Instant);

impl Log {
    fn say(&self, message: &str) {
        println!("[{:6.1} s] {message}", self.0.elapsed().as_secs_f64());
    }
}

/// Why grading could not start: the TA's problem, never the student's.
fn setup_error(log: &Log, why: &str, max: usize) -> Value {
    log.say(&format!(
        "not set up ({why}): run `run_autograder --setup` first (setup.sh does)"
    ));
    platform::gradescope_zero("The autograder is not set up; tell your TA.", max)
}

/// The fresh-case sets set up, in order (folders `0`, `1`, ...).
pub(crate) fn fresh_sets(places: &Places) -> Vec<String> {
    let mut sets: Vec<u32> = std::fs::read_dir(places.fresh())
        .into_iter()
        .flatten()
        .filter_map(|e| e.ok()?.file_name().to_str()?.parse().ok())
        .collect();
    sets.sort();
    sets.into_iter().map(|n| n.to_string()).collect()
}

/// The fixtures this upload is graded on: a copy of the grading fixtures
/// with one set of fresh cases added, chosen from the upload's bytes and
/// the hidden cases' digest list (never shown to students), so the same
/// upload gets the same cases again. Returns (folder, set chosen).
fn with_fresh_cases(
    places: &Places,
    text: &[u8],
    work: &Path,
) -> Result<(PathBuf, Option<String>), String> {
    let sets = fresh_sets(places);
    if sets.is_empty() {
        return Ok((places.fixtures(), None));
    }
    let secret = std::fs::read(places.fixtures().join("hidden/SHA256SUMS")).unwrap_or_default();
    let mut keyed = secret;
    keyed.push(0);
    keyed.extend_from_slice(text);
    let digest = sha256::sha256_hex(&keyed);
    let pick = u64::from_str_radix(&digest[..16], 16).map_err(|e| e.to_string())?;
    let chosen = sets[(pick % sets.len() as u64) as usize].clone();
    let folder = work.join("fixtures");
    crate::copy_tree(&places.fixtures(), &folder)?;
    for group in ["hidden", "bonus"] {
        let src = places.fresh().join(&chosen).join(group);
        if !src.is_dir() {
            continue;
        }
        let dst = folder.join(group);
        crate::copy_tree(&src, &dst)?;
        // The digest list the grader checks, as `sha256sum` writes it.
        let mut names: Vec<String> = std::fs::read_dir(&dst)
            .map_err(|e| e.to_string())?
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|n| n.ends_with(".json"))
            .collect();
        names.sort();
        let mut sums = String::new();
        for name in names {
            let data = std::fs::read(dst.join(&name)).map_err(|e| e.to_string())?;
            sums.push_str(&format!("{}  {name}\n", sha256::sha256_hex(&data)));
        }
        std::fs::write(dst.join("SHA256SUMS"), sums).map_err(|e| e.to_string())?;
    }
    Ok((folder, Some(chosen)))
}

/// The build user's settings written at setup.
struct Settings {
    toolchain: PathBuf,
    target: PathBuf,
    /// The vendored crates the builds compile.
    vendor: PathBuf,
    /// Build (and run the case child) as `nobody`.
    drop_user: bool,
}

fn read_settings(places: &Places) -> Result<Settings, String> {
    let text = std::fs::read_to_string(places.settings()).map_err(|e| e.to_string())?;
    let v: Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    let path = |key: &str| {
        v[key]
            .as_str()
            .map(PathBuf::from)
            .ok_or(format!("settings.json: no {key}"))
    };
    let drop_user = !v["user"].is_null();
    if drop_user && !process::is_root() {
        return Err("set up as root: run it as root".into());
    }
    Ok(Settings {
        toolchain: path("toolchain")?,
        target: path("target")?,
        vendor: path("vendor")?,
        drop_user,
    })
}

/// The locked-in build of `lab/` with the bundle's settings.
fn locked_build(
    places: &Places,
    settings: &Settings,
    seconds: f64,
    work: &Path,
) -> Result<grade::Built, String> {
    let build = Build {
        lab: places.lab(),
        vendor: settings.vendor.clone(),
        sysroot: settings.toolchain.clone(),
        target: settings.target.clone(),
        memory: BUILD_MEMORY,
        seconds: seconds.round(),
        status: work.join("build.status"),
        drop_user: settings.drop_user,
        landlock: true,
        empty_root: true,
    };
    let me = std::env::current_exe().map_err(|e| e.to_string())?;
    grade::build(&build, &me, work)
}

fn who(settings: &Settings) -> String {
    if settings.drop_user {
        "nobody".into()
    } else {
        std::env::var("USER").unwrap_or_else(|_| "this user".into())
    }
}

/// At setup, once: the whole lab built locked in as every submission's
/// build will be (each then compiles only the student's crate and the
/// grader). Returns a message for the setup log, or the failure.
pub fn warm(places: &Places) -> Result<String, String> {
    let settings = read_settings(places)?;
    let work = places.state().join("warm");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
    let built = locked_build(places, &settings, 3600.0, &work)?;
    let _ = std::fs::remove_dir_all(&work);
    if built.report.outcome != BuildOutcome::Built {
        return Err(format!(
            "the locked-in build (as {}) failed: {}\n{}",
            who(&settings),
            built.report.failure().unwrap_or_default(),
            built
                .log
                .chars()
                .rev()
                .take(3000)
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .collect::<String>()
        ));
    }
    let mut out = format!(
        "built the grader as {} in {:.0} s into {}\n{}",
        who(&settings),
        built.seconds,
        settings.target.display(),
        built.report.protections()
    );
    if built.report.landlock == 0 {
        out.push_str(&format!(
            "\nwarning: this kernel has no Landlock: the build is kept from the hidden cases \
             only by running as {}{}",
            who(&settings),
            if settings.drop_user {
                ""
            } else {
                " (not root: it can read them)"
            }
        ));
    }
    Ok(out)
}

/// Grades the upload and writes the results (always: a student gets a
/// result whatever happens); then sweeps what the submission left.
pub fn run(places: &Places, options: &Options) -> Result<(), String> {
    let start = Instant::now();
    let log = Log(start);
    process::become_subreaper();
    let _ = std::fs::remove_file(places.results());
    let mut results = grade_upload(places, options, &log);
    let drop_user = read_settings(places).is_ok_and(|s| s.drop_user);
    let swept = process::sweep(if drop_user {
        process::nobody_uid()
    } else {
        None
    });
    if swept > 0 {
        log.say(&format!(
            "swept {swept} processes the submission left behind"
        ));
    }
    results["execution_time"] = json!(start.elapsed().as_secs());
    let path = places.results();
    let dir = path.parent().expect("results/ has a parent");
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let tmp = dir.join(".results.json.new");
    let text = serde_json::to_string_pretty(&results).expect("JSON");
    std::fs::write(&tmp, text).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, &path).map_err(|e| format!("{}: {e}", path.display()))?;
    log.say(&format!(
        "wrote {}: score {}",
        path.display(),
        results["score"]
    ));
    Ok(())
}

fn grade_upload(places: &Places, options: &Options, log: &Log) -> Value {
    let remaining = || options.budget - RESERVE - log.0.elapsed().as_secs_f64();
    // Every set holds as many cases: the first one counts for uploads that
    // never get graded.
    let sets = fresh_sets(places);
    let fresh_counts = sets
        .first()
        .map(|s| grade::counted(&places.fresh().join(s), options.bonus))
        .unwrap_or_default();
    let base = grade::counted(&places.fixtures(), options.bonus);
    let counts: [usize; 4] = std::array::from_fn(|k| base[k] + fresh_counts[k]);
    let max: usize = counts.iter().sum();
    let settings = match read_settings(places) {
        Ok(s) => s,
        Err(why) => return setup_error(log, &why, max),
    };
    let not_graded =
        |message: String| platform::gradescope(&Outcome::NotGraded { message, counts });
    // A named pipe or a device in the upload is refused unopened, a
    // large file unread (see `read_source`): the upload still gets its
    // results.json.
    let (uploaded, text) = match crate::upload::take_lib_rs(&places.submission()) {
        Ok(found) => found,
        Err(why) => {
            log.say(&why.message());
            return not_graded(why.message());
        }
    };
    let rel = uploaded
        .strip_prefix(places.submission())
        .unwrap_or(&uploaded)
        .display()
        .to_string();
    log.say(&format!("grading {rel}"));
    // Root's alone: the fixtures copied into it hold the hidden cases.
    let work_dir = match crate::private_temp_dir("meshlab-grading-") {
        Ok(d) => d,
        Err(e) => return setup_error(log, &e, max),
    };
    let work = work_dir.path().to_path_buf();
    let outcome = grade_in(
        places, options, &settings, &text, &work, counts, log, &remaining,
    );
    let _ = std::fs::remove_dir_all(&work);
    match outcome {
        Ok(outcome) => {
            let mut results = platform::gradescope(&outcome);
            platform::add_gradescope_leaderboard(&mut results, &outcome);
            match platform::subdivision_time(&outcome) {
                Ok((faces, ms)) => log.say(&format!(
                    "leaderboard: loop_subdivide {ms:.3} ms of CPU time on {faces} faces"
                )),
                Err(why) => log.say(&format!("leaderboard: no entry ({why:?})")),
            }
            results
        }
        Err(why) => {
            log.say(&format!("autograder error: {why}"));
            platform::gradescope_zero(
                &format!("The autograder failed ({why}); tell your TA."),
                max,
            )
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn grade_in(
    places: &Places,
    options: &Options,
    settings: &Settings,
    text: &[u8],
    work: &Path,
    counts: [usize; 4],
    log: &Log,
    remaining: &dyn Fn() -> f64,
) -> Result<Outcome, String> {
    let (fixtures, chosen) = with_fresh_cases(places, text, work)?;
    if let Some(set) = &chosen {
        log.say(&format!(
            "fresh cases: set {set} of {}",
            fresh_sets(places).len()
        ));
    }
    let counts = if chosen.is_some() {
        grade::counted(&fixtures, options.bonus)
    } else {
        counts
    };
    let student = places.lab().join("crates/meshedit/src/lib.rs");
    std::fs::write(&student, text).map_err(|e| format!("{}: {e}", student.display()))?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(&student, std::fs::Permissions::from_mode(0o644));
    }
    let built = locked_build(places, settings, (remaining() - 60.0).max(30.0), work)?;
    let r = &built.report;
    log.say(&format!(
        "build: {:?}, peak {} MiB resident; {}",
        r.outcome,
        r.peak_kib / 1024,
        r.protections()
    ));
    log.say(&format!(
        "cargo build as {}: exit {} in {:.1} s",
        if r.user.is_empty() {
            "this user"
        } else {
            &r.user
        },
        r.exit.map_or("none".to_string(), |c| c.to_string()),
        built.seconds
    ));
    let compiler = built.compiler();
    match r.outcome {
        BuildOutcome::Built => {}
        BuildOutcome::NotLockedIn => {
            log.say(&format!(
                "the build could not be locked in: {}",
                r.failure().unwrap_or_default()
            ));
            return Ok(Outcome::NotGraded {
                message: "The autograder could not compile your code safely; tell your TA.".into(),
                counts,
            });
        }
        BuildOutcome::OutOfMemory | BuildOutcome::OutOfTime => {
            let limit = r.failure().unwrap_or_default();
            return Ok(Outcome::NotGraded {
                message: crate::does_not_compile(Some(&limit), &compiler),
                counts,
            });
        }
        BuildOutcome::Failed => {
            return Ok(Outcome::NotGraded {
                message: crate::does_not_compile(None, &compiler),
                counts,
            });
        }
    }
    let mut notes = Vec::new();
    if built.said_something() {
        notes.push(format!(
            "Your code compiles with warnings:\n\n{}\n",
            grader::report::quoted::Quoted::new(compiler).block("")
        ));
    }
    // Root runs copies in a folder of its own: the build user (who is also
    // the user the student's code runs as) may write the target folder.
    let bin = places.bin();
    let _ = std::fs::remove_dir_all(&bin);
    std::fs::create_dir_all(&bin).map_err(|e| format!("{}: {e}", bin.display()))?;
    for name in PROGRAMS {
        let from = grade::programs_dir(&settings.target).join(name);
        std::fs::copy(&from, bin.join(name)).map_err(|e| format!("{}: {e}", from.display()))?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let _ =
                std::fs::set_permissions(bin.join(name), std::fs::Permissions::from_mode(0o755));
        }
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(&bin, std::fs::Permissions::from_mode(0o755));
    }
    let grading = Grading {
        exe: bin.join("grader"),
        cwd: places.lab(),
        fixtures,
        timeout: options.timeout,
        bonus: options.bonus,
        logs: work.to_path_buf(),
        reaper: std::env::current_exe().map_err(|e| e.to_string())?,
        // The leaderboard's time: the subdivision stage's grader times
        // loop_subdivide within its budget (the other stages ignore it).
        extra_args: vec!["--time-subdivision".into()],
    };
    let stages = grade::grade_stages(&grading, remaining);
    for run in &stages {
        let protections = run
            .report
            .as_ref()
            .and_then(|r| r["protections"].as_str())
            .unwrap_or("unknown");
        log.say(&format!(
            "{}: {} cases, {}, budget {:.1} s, exit {} in {:.1} s; {protections}",
            run.stage.function,
            run.cases,
            run.limit(),
            run.budget,
            run.code
                .map_or("none (stopped)".to_string(), |c| c.to_string()),
            run.seconds
        ));
        if !run.graded() && !run.error.is_empty() {
            log.say(&format!(
                "{} failed: {}",
                run.stage.function,
                run.error.trim()
            ));
        }
    }
    Ok(Outcome::Graded {
        stages,
        notes,
        bonus: options.bonus,
    })
}
