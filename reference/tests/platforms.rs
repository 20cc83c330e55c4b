//! Classroom 50 and PrairieLearn, each run here the way the platform runs
//! it: the bundle `reference` writes, the entry point the platform calls
//! (Classroom 50: `python3 autograder.py` in the student's checkout with
//! the runner's variables, `./result.json` read after; PrairieLearn: the
//! entrypoint `run.sh` with the upload in `/grade/student`, its
//! `/grade/results/results.json` read after), on the model solution, the
//! stubs, a compile error, and files no `lib.rs` can be (a named pipe, a
//! device, links, 60 MB).

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

#[test]
fn classroom50_s_runner_gets_points_per_function() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let (dir, env) = bundle("classroom50");
    let checkout = kept("checkout");
    let grade = |lib_rs: &str| {
        let _ = std::fs::remove_dir_all(&checkout);
        write(&checkout.join("crates/meshedit/src/lib.rs"), lib_rs);
        let out = Command::new("python3")
            .arg(dir.join("autograder.py"))
            .current_dir(&checkout)
            .envs(env.iter().map(|(k, v)| (*k, v.as_os_str())))
            .env("CARGO_NET_OFFLINE", "true")
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
        (json(&checkout.join("result.json")), stderr)
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

#[test]
fn prairielearn_s_external_grader_scores_and_refuses_what_does_not_compile() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let (dir, env) = bundle("prairielearn");
    assert!(
        dir.join("fixtures/hidden").is_dir(),
        "hidden cases graded, outside the lab"
    );
    let root = kept("grade");
    let grade = |lib_rs: &str| {
        let _ = std::fs::remove_dir_all(&root);
        write(&root.join("student/lib.rs"), lib_rs);
        let out = Command::new("sh")
            .arg(dir.join("run.sh"))
            .envs(env.iter().map(|(k, v)| (*k, v.as_os_str())))
            .env("CARGO_NET_OFFLINE", "true")
            .env("MESHLAB_GRADE_ROOT", &root)
            .output()
            .unwrap();
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
}
