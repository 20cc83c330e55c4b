//! Classroom 50 and PrairieLearn, each run here the way the platform runs
//! it: the bundle `reference` writes, the entry point the platform calls
//! (Classroom 50: `python3 autograder.py` in the student's checkout with
//! the runner's variables, `./result.json` read after; PrairieLearn: the
//! entrypoint `run.sh` with the upload in `/grade/student`, its
//! `/grade/results/results.json` read after), on the model solution, the
//! stubs, a compile error, and files no `lib.rs` can be (a named pipe, a
//! device, links, 60 MB); and each with the student's files set to make
//! the autograder's own build run their programs (a Classroom 50 bundle
//! unpacked inside a checkout whose `.cargo/config.toml` names a
//! `rustc-wrapper`, a PrairieLearn upload holding one).

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::*;

fn solution() -> String {
    std::fs::read_to_string(lab_root().join("reference/src/solution.rs")).unwrap()
}

fn stubs() -> String {
    std::fs::read_to_string(lab_root().join("crates/meshedit/src/lib.rs")).unwrap()
}

const BROKEN: &str = "pub fn flip_edge( {\n";

/// The two tests share the kept folders: one at a time.
static TURN: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Folders kept between runs of these tests (the builds' dependencies
/// compile once), outside the lab.
fn kept(name: &str) -> PathBuf {
    class_build_dir()
        .parent()
        .unwrap()
        .join("platforms")
        .join(name)
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// A program that appends a line to `marks/ran-NAME` each time anything
/// runs it, then fails (a build it wraps breaks, as the student's did).
fn plant(marks: &Path, name: &str) -> String {
    use std::os::unix::fs::PermissionsExt;
    std::fs::create_dir_all(marks).unwrap();
    let program = marks.join(format!("prog-{name}"));
    let text = format!(
        "#!/bin/sh\necho \"$@\" >> {}\nexit 1\n",
        marks.join(format!("ran-{name}")).display()
    );
    std::fs::write(&program, text).unwrap();
    std::fs::set_permissions(&program, std::fs::Permissions::from_mode(0o755)).unwrap();
    program.display().to_string()
}

/// What ran: each planted program's name and how many times.
fn ran(marks: &Path) -> Vec<(String, usize)> {
    let mut out: Vec<(String, usize)> = std::fs::read_dir(marks)
        .unwrap()
        .filter_map(|e| {
            let path = e.ok()?.path();
            let name = path
                .file_name()?
                .to_str()?
                .strip_prefix("ran-")?
                .to_string();
            let runs = std::fs::read_to_string(&path)
                .unwrap_or_default()
                .lines()
                .count();
            Some((name, runs))
        })
        .collect();
    out.sort();
    out
}

fn clear_marks(marks: &Path) {
    for (name, _) in ran(marks) {
        std::fs::remove_file(marks.join(format!("ran-{name}"))).unwrap();
    }
}

/// The host's target triple, for `[target.TRIPLE]` tables.
fn host() -> String {
    let out = Command::new("rustc").arg("-vV").output().unwrap();
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("host: ").map(str::to_string))
        .expect("rustc -vV names the host")
}

/// A `.cargo/config.toml` whose every program-running key names a planted
/// program, and whose other keys point cargo at the student's folders.
fn hostile_cargo_config(marks: &Path, student: &Path) -> String {
    let p = |name: &str| serde_json::to_string(&plant(marks, name)).unwrap();
    let at = |rel: &str| serde_json::to_string(&student.join(rel).to_string_lossy()).unwrap();
    format!(
        "[build]\nrustc-wrapper = {}\nrustc-workspace-wrapper = {}\nrustc = {}\nrustdoc = {}\n\
         target-dir = {}\nrustflags = [\"-C\", {}]\n\
         [target.{}]\nlinker = {}\nrunner = {}\n\
         [env]\nRUSTC_WRAPPER = {}\n\
         [source.crates-io]\nreplace-with = \"theirs\"\n[source.theirs]\ndirectory = {}\n\
         [registry]\nglobal-credential-providers = [{}]\n[net]\ngit-fetch-with-cli = true\n",
        p("rustc-wrapper"),
        p("workspace-wrapper"),
        p("rustc"),
        p("rustdoc"),
        at("their-target"),
        serde_json::to_string(&format!("linker={}", plant(marks, "rustflags-linker"))).unwrap(),
        host(),
        p("linker"),
        p("runner"),
        p("env-wrapper"),
        at("their-vendor"),
        p("credential"),
    )
}

/// A repository in `dir` whose one commit is dated 2020 and signed, with
/// a `gpg.program` of the student's that git runs to show the signature.
fn signed_repository(dir: &Path, marks: &Path) {
    let git = |args: &[&str]| {
        let out = Command::new("git")
            .args(args)
            .current_dir(dir)
            .env("GIT_CONFIG_NOSYSTEM", "1")
            .env("GIT_CONFIG_GLOBAL", "/dev/null")
            .env("GIT_AUTHOR_NAME", "s")
            .env("GIT_AUTHOR_EMAIL", "s@example.org")
            .env("GIT_COMMITTER_NAME", "s")
            .env("GIT_COMMITTER_EMAIL", "s@example.org")
            .env("GIT_AUTHOR_DATE", "2020-01-01T00:00:00Z")
            .env("GIT_COMMITTER_DATE", "2020-01-01T00:00:00Z")
            .output()
            .unwrap();
        assert!(out.status.success(), "git {args:?}: {out:?}");
        String::from_utf8_lossy(&out.stdout).trim().to_string()
    };
    git(&["init", "-q"]);
    git(&["add", "crates"]);
    git(&["commit", "-q", "-m", "work"]);
    let tree = git(&["rev-parse", "HEAD^{tree}"]);
    let raw = format!(
        "tree {tree}\nauthor s <s@example.org> 1577836800 +0000\n\
         committer s <s@example.org> 1577836800 +0000\ngpgsig -----BEGIN PGP SIGNATURE-----\n \n \
         iQEzBAABCAAdFiEE\n -----END PGP SIGNATURE-----\n\nsigned\n"
    );
    let raw_path = dir.join(".git/signed-commit");
    std::fs::write(&raw_path, raw).unwrap();
    let signed = git(&[
        "hash-object",
        "-t",
        "commit",
        "-w",
        raw_path.to_str().unwrap(),
    ]);
    git(&["update-ref", "HEAD", &signed]);
    git(&["config", "log.showSignature", "true"]);
    git(&["config", "gpg.program", &plant(marks, "gpg")]);
    git(&["config", "core.fsmonitor", &plant(marks, "fsmonitor")]);
    git(&["config", "core.pager", &plant(marks, "pager")]);
}

/// A copy of the folder `from` into `to`.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let target = to.join(path.file_name().unwrap());
        if path.is_dir() {
            copy_dir(&path, &target);
        } else {
            std::fs::copy(&path, &target).unwrap();
        }
    }
}

/// A new bundle from `reference COMMAND DIR`, its crates fetched (as the
/// platform's network would), and the environment its builds share.
fn bundle(command: &str) -> (PathBuf, Vec<(&'static str, PathBuf)>) {
    let dir = kept(command);
    let _ = std::fs::remove_dir_all(&dir);
    let r = run(&[command, dir.to_str().unwrap()]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(
        !dir.join("lab/reference").exists(),
        "no solution in the bundle"
    );
    assert!(
        !dir.join("lab/fixtures/hidden").exists(),
        "no hidden case the build could read"
    );
    // The toolchain is the one the TA runs, pinned as Gradescope's setup
    // and the grading workflow pin it, and the command says which.
    let version = reference::handout::rust_version(&reference::lab_root()).unwrap();
    let pin = std::fs::read_to_string(dir.join("lab/rust-toolchain.toml")).unwrap();
    assert!(pin.contains(&format!("channel = \"{version}\"")), "{pin}");
    assert!(
        r.stdout.contains(&format!("Rust {version}")),
        "{}",
        r.stdout
    );
    let fetched = Command::new("cargo")
        .args(["fetch", "--locked"])
        .current_dir(dir.join("lab"))
        .output()
        .unwrap();
    assert!(
        fetched.status.success(),
        "{}",
        String::from_utf8_lossy(&fetched.stderr)
    );
    // The locked-in build's vendored crates and target folder are class
    // grading's (the tests' class_build_dir): the platforms build the lab
    // the same way, so its dependencies compile once per checkout. Vendored
    // afresh here, as class grading does each run.
    let vendor = class_build_dir().join("vendor");
    let _ = std::fs::remove_dir_all(&vendor);
    let env = vec![
        ("MESHLAB_VENDOR", vendor),
        // The autograde program's build, shared with the Gradescope test's
        // (exports.rs): its dependencies compile once per checkout.
        (
            "MESHLAB_AUTOGRADE_TARGET",
            class_build_dir().parent().unwrap().join("autograde-target"),
        ),
        ("MESHLAB_BUILD_TARGET", class_build_dir().join("target")),
    ];
    (dir, env)
}

/// Counted cases per function, as the stage order lists them.
fn cases(groups: &[&str]) -> usize {
    groups.iter().flat_map(|g| case_files(g)).count()
}

/// Runs Classroom 50's `autograder.py` (at `script`) in `checkout` as
/// its runner does: the runner's variables, `$RUNNER_TEMP` its own folder.
/// Returns `./result.json` and the standard error.
fn run_classroom50(
    script: &Path,
    checkout: &Path,
    env: &[(&'static str, PathBuf)],
) -> (serde_json::Value, String) {
    let runner_temp = kept("runner-temp");
    std::fs::create_dir_all(&runner_temp).unwrap();
    let out = Command::new("python3")
        .arg(script)
        .current_dir(checkout)
        .envs(env.iter().map(|(k, v)| (*k, v.as_os_str())))
        .env("CARGO_NET_OFFLINE", "true")
        .env("RUNNER_TEMP", &runner_temp)
        .env("CLASSROOM", "cg-2026")
        .env("ASSIGNMENT", "meshedit")
        .env("SUBMISSION_TAG", "submit/2026-12-01T10-00-00Z-abc1234")
        .env("COMMIT_URL", "https://github.com/o/r/commit/abc")
        .env(
            "RELEASE_URL",
            "https://github.com/o/r/releases/tag/submit%2F1",
        )
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(
        !runner_temp.join("meshlab-autograder").exists(),
        "the private copy of the lab is removed"
    );
    (json(&checkout.join("result.json")), stderr)
}

#[test]
fn classroom50_s_runner_gets_points_per_function() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let (dir, env) = bundle("classroom50");
    assert!(dir.join("lab.sha256").is_file(), "the lab's list of files");
    let checkout = kept("checkout");
    let grade = |lib_rs: &str| {
        let _ = std::fs::remove_dir_all(&checkout);
        write(&checkout.join("crates/meshedit/src/lib.rs"), lib_rs);
        run_classroom50(&dir.join("autograder.py"), &checkout, &env)
    };
    // The visible lab cases only (Classroom 50 publishes the bundle).
    let max = cases(&["lab"]) as u64;
    let (good, log) = grade(&solution());
    assert_eq!(good["schema"], "classroom50/result/v1");
    assert_eq!(
        (good["classroom"].as_str(), good["assignment"].as_str()),
        (Some("cg-2026"), Some("meshedit"))
    );
    assert_eq!(
        good["review"], good["commit"],
        "review falls back to the commit"
    );
    assert!(good["datetime"].as_str().unwrap().ends_with('Z'));
    assert_eq!(
        (good["score"].as_u64(), good["max-score"].as_u64()),
        (Some(max), Some(max)),
        "{log}\n{good}"
    );
    let names: Vec<&str> = good["tests"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["test-name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        ["flip_edge", "split_edge", "in_sequence", "loop_subdivide"]
    );
    assert!(good["tests"]
        .as_array()
        .unwrap()
        .iter()
        .all(|t| t["passed"] == true && t["score"] == t["max-score"]));
    assert!(log.contains("build protections:"), "{log}");

    let (stub, _) = grade(&stubs());
    assert_eq!(
        (stub["score"].as_u64(), stub["max-score"].as_u64()),
        (Some(0), Some(max)),
        "{stub}"
    );

    let (broken, _) = grade(BROKEN);
    assert_eq!(
        (broken["score"].as_u64(), broken["max-score"].as_u64()),
        (Some(0), Some(max)),
        "{broken}"
    );
    assert_eq!(broken["tests"][0]["test-name"], "compiles");
    let message = broken["tests"][0]["message"].as_str().unwrap();
    assert!(
        message.starts_with("Your code does not compile:"),
        "{message}"
    );
    assert!(
        message.contains("| error: this file contains an unclosed delimiter"),
        "{message}"
    );

    // What no lib.rs can be, in the checkout: each a result at once,
    // saying what the file is; nothing of it read or built.
    let secret = kept("ta-secret.txt");
    std::fs::write(&secret, "TA-FILE-TOKEN").unwrap();
    for unfit in unfit_files(&secret) {
        let _ = std::fs::remove_dir_all(&checkout);
        std::fs::create_dir_all(checkout.join("crates/meshedit/src")).unwrap();
        (unfit.make)(&checkout.join("crates/meshedit/src/lib.rs"));
        let out = output_within(
            Command::new("python3")
                .arg(dir.join("autograder.py"))
                .current_dir(&checkout)
                .envs(env.iter().map(|(k, v)| (*k, v.as_os_str())))
                .env("CARGO_NET_OFFLINE", "true"),
            600,
        );
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(0), "{stderr}");
        let result = json(&checkout.join("result.json"));
        assert_eq!(
            (result["score"].as_u64(), result["max-score"].as_u64()),
            (Some(0), Some(max)),
            "{result}"
        );
        let text = result.to_string();
        assert!(
            text.contains(&format!("crates/meshedit/src/lib.rs {}", unfit.says)),
            "{}: {text}",
            unfit.says
        );
        assert!(
            !text.contains("TA-FILE-TOKEN") && !stderr.contains("build protections"),
            "{text}\n{stderr}"
        );
    }
}

/// The bundle unpacked inside the student's checkout, under a
/// `.cargo/config.toml` of theirs whose every program-running key names a
/// program that leaves a mark, with one planted in the bundle's own `lab/`
/// too, in a repository whose `gpg.program` git would run to show its
/// signed commit (dated 2020): nothing of it runs, the model solution gets
/// every point, and `datetime` is the runner's clock, not the commit's.
#[test]
fn classroom50_s_bundle_inside_a_hostile_checkout_runs_nothing_of_it() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let (dir, env) = bundle("classroom50");
    let checkout = kept("hostile-checkout");
    let marks = kept("hostile-marks");
    for d in [&checkout, &marks] {
        let _ = std::fs::remove_dir_all(d);
    }
    write(&checkout.join("crates/meshedit/src/lib.rs"), &solution());
    signed_repository(&checkout, &marks);
    write(
        &checkout.join(".cargo/config.toml"),
        &hostile_cargo_config(&marks, &checkout),
    );
    // The bundle inside the checkout, with a config the student planted
    // where its lab unpacks (the bundle has none there).
    let inner = checkout.join(".classroom50/meshedit");
    copy_dir(&dir, &inner);
    write(
        &inner.join("lab/.cargo/config.toml"),
        &format!(
            "[build]\nrustc-wrapper = {}\n",
            serde_json::to_string(&plant(&marks, "planted-in-lab")).unwrap()
        ),
    );
    // The plants are live: cargo in the checkout runs them, and so does
    // the student's own git.
    write(
        &checkout.join("probe/Cargo.toml"),
        "[package]\nname = \"probe\"\nversion = \"0.0.0\"\nedition = \"2021\"\n[workspace]\n",
    );
    write(&checkout.join("probe/src/lib.rs"), "");
    let _ = Command::new("cargo")
        .args(["build", "--offline"])
        .current_dir(checkout.join("probe"))
        .output()
        .unwrap();
    let _ = Command::new("git")
        .args(["log", "-1", "--format=%ct"])
        .current_dir(&checkout)
        .env("GIT_CONFIG_NOSYSTEM", "1")
        .env("GIT_CONFIG_GLOBAL", "/dev/null")
        .output()
        .unwrap();
    let live: Vec<String> = ran(&marks).into_iter().map(|(n, _)| n).collect();
    assert!(
        live.iter().any(|n| n.starts_with("rustc")) && live.contains(&"gpg".to_string()),
        "the planted programs would run: {live:?}"
    );
    clear_marks(&marks);
    std::fs::remove_dir_all(checkout.join("probe")).unwrap();
    let _ = std::fs::remove_dir_all(checkout.join("their-target"));

    let before = autograde::clock::now();
    let (result, log) = run_classroom50(&inner.join("autograder.py"), &checkout, &env);
    let after = autograde::clock::now();
    assert_eq!(ran(&marks), Vec::<(String, usize)>::new(), "{log}");
    let max = cases(&["lab"]) as u64;
    assert_eq!(
        (result["score"].as_u64(), result["max-score"].as_u64()),
        (Some(max), Some(max)),
        "{log}\n{result}"
    );
    let datetime = result["datetime"].as_str().unwrap();
    let when = autograde::clock::parse_instant(datetime).expect("an instant");
    assert!(
        (before..=after).contains(&when),
        "datetime {datetime} is the runner's clock while grading, not the commit's (2020)"
    );
    assert!(!checkout.join("their-target").exists(), "{log}");
}

#[test]
fn prairielearn_s_external_grader_scores_and_refuses_what_does_not_compile() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let (dir, env) = bundle("prairielearn");
    assert!(
        dir.join("fixtures/hidden").is_dir(),
        "hidden cases graded, outside the lab"
    );
    let root = kept("grade");
    let marks = kept("grade-marks");
    let _ = std::fs::remove_dir_all(&marks);
    let run = |lib_rs: &str, hostile: bool| {
        let _ = std::fs::remove_dir_all(&root);
        write(&root.join("student/lib.rs"), lib_rs);
        if hostile {
            // An upload that brings a cargo config, and one above it.
            for at in [root.join("student"), root.clone()] {
                write(
                    &at.join(".cargo/config.toml"),
                    &hostile_cargo_config(&marks, &root),
                );
            }
        }
        Command::new("sh")
            .arg(dir.join("run.sh"))
            .envs(env.iter().map(|(k, v)| (*k, v.as_os_str())))
            .env("CARGO_NET_OFFLINE", "true")
            .env("MESHLAB_GRADE_ROOT", &root)
            .env("RUSTC_WRAPPER", plant(&marks, "caller-wrapper"))
            .output()
            .unwrap()
    };
    let grade = |lib_rs: &str| {
        let out = run(lib_rs, false);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(0), "{stderr}");
        (json(&root.join("results/results.json")), stderr)
    };
    let max = cases(&["lab", "hidden"]) as u64;
    let points = |r: &serde_json::Value, key: &str| -> u64 {
        r["tests"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t[key].as_u64().unwrap())
            .sum()
    };
    let (good, log) = grade(&solution());
    assert_eq!(
        (good["gradable"].as_bool(), good["score"].as_f64()),
        (Some(true), Some(1.0)),
        "{log}\n{good}"
    );
    assert_eq!(
        (points(&good, "points"), points(&good, "max_points")),
        (max, max)
    );
    assert_eq!(good["tests"][0]["name"], "flip_edge");
    assert_eq!(good["tests"][0]["message"], "every case passed");

    let (stub, _) = grade(&stubs());
    assert_eq!(
        (stub["gradable"].as_bool(), stub["score"].as_f64()),
        (Some(true), Some(0.0))
    );
    assert_eq!(
        (points(&stub, "points"), points(&stub, "max_points")),
        (0, max)
    );
    let first = stub["tests"][0]["message"].as_str().unwrap();
    assert!(first.contains("not yet implemented"), "{first}");

    let (broken, _) = grade(BROKEN);
    assert_eq!(broken["gradable"], false, "{broken}");
    let errors = broken["format_errors"][0].as_str().unwrap();
    assert!(
        errors.contains("| error: this file contains an unclosed delimiter"),
        "{errors}"
    );

    // What no upload's lib.rs can be: each a result at once, saying what
    // the file is; nothing of it read or built.
    let secret = kept("ta-secret.txt");
    std::fs::write(&secret, "TA-FILE-TOKEN").unwrap();
    for unfit in unfit_files(&secret) {
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(root.join("student")).unwrap();
        (unfit.make)(&root.join("student/lib.rs"));
        let out = output_within(
            Command::new("sh")
                .arg(dir.join("run.sh"))
                .envs(env.iter().map(|(k, v)| (*k, v.as_os_str())))
                .env("CARGO_NET_OFFLINE", "true")
                .env("MESHLAB_GRADE_ROOT", &root),
            600,
        );
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(0), "{stderr}");
        let results = json(&root.join("results/results.json"));
        let text = results.to_string();
        assert!(
            text.contains(&format!("lib.rs {}", unfit.says)),
            "{}: {text}",
            unfit.says
        );
        assert_ne!(results["score"].as_f64(), Some(1.0), "{text}");
        assert!(
            !text.contains("TA-FILE-TOKEN") && !stderr.contains("build protections"),
            "{text}\n{stderr}"
        );
    }

    // An upload holding cargo configs (and a wrapper in the caller's
    // environment): none is read, the solution gets every point.
    let out = run(&solution(), true);
    let log = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{log}");
    assert_eq!(ran(&marks), Vec::<(String, usize)>::new(), "{log}");
    let good = json(&root.join("results/results.json"));
    assert_eq!(good["score"].as_f64(), Some(1.0), "{log}\n{good}");

    // A cargo config above the bundle's lab: refused, nothing built.
    write(
        &dir.join(".cargo/config.toml"),
        &hostile_cargo_config(&marks, &root),
    );
    let out = run(&solution(), false);
    let log = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{log}");
    assert!(
        log.contains(".cargo/config.toml would configure the autograder's build"),
        "{log}"
    );
    assert_eq!(ran(&marks), Vec::<(String, usize)>::new(), "{log}");
    std::fs::remove_dir_all(dir.join(".cargo")).unwrap();
}
