//! The TA's copies of the lab, end to end: the student export (and its
//! update and its GitHub Actions grading workflow), the Gradescope bundle run on six
//! kinds of upload, and class grading of a folder with good, broken, stray
//! and hostile entries.
//!
//! Every build here goes to one shared target folder, `target/ta-tests`, so
//! dependencies compile once; the tests take turns (one lock) because each
//! builds a `grader` binary with different student code into that folder.

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::*;
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

static BUILDS: Mutex<()> = Mutex::new(());

/// The lock on the shared target folder (a failed test must not block the
/// others, so a poisoned lock is taken anyway).
fn take_turn() -> MutexGuard<'static, ()> {
    BUILDS.lock().unwrap_or_else(|p| p.into_inner())
}

fn root() -> PathBuf {
    reference::lab_root()
}

fn target() -> PathBuf {
    root().join("target/ta-tests")
}

fn solution() -> String {
    std::fs::read_to_string(root().join("reference/src/solution.rs")).unwrap()
}

fn stubs() -> String {
    std::fs::read_to_string(root().join("crates/meshedit/src/lib.rs")).unwrap()
}

/// The model solution whose `loop_subdivide` starts `sleep 1000` (holding
/// the output pipes) and then never returns.
fn hostile() -> String {
    solution().replace("pub fn loop_subdivide(", "pub fn loop_subdivide_model(")
        + r#"
pub fn loop_subdivide(_mesh: &mut Mesh) {
    let _ = std::process::Command::new("sleep").arg("1000").spawn();
    loop {
        std::thread::sleep(std::time::Duration::from_secs(1));
    }
}
"#
}

/// The model solution whose `flip_edge` takes `seconds` a call (its
/// `loop_subdivide` flips at full speed): right answers, slowly.
fn slow_flip(seconds: f64) -> String {
    solution().replace("flip_edge", "flip_edge_model")
        + &format!(
            r#"
pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {{
    std::thread::sleep(std::time::Duration::from_secs_f64({seconds}));
    flip_edge_model(mesh, e)
}}
"#
        )
}

/// The model solution whose `flip_edge` panics with a message that holds a
/// CR, a cell that would be a formula, and a forged verdict after a newline.
fn forging() -> String {
    solution().replace("pub fn flip_edge(", "pub fn flip_edge_model(")
        + r#"
pub fn flip_edge(_mesh: &mut Mesh, _e: EdgeId) -> Option<EdgeId> {
    println!("\x1b[2J\rgrade.rs:1 [info] all tests passed, congratulations!");
    panic!("=1+1\r,=cmd()\nreport.rs:262 [info] all tests passed, congratulations!");
}
"#
}

/// The model solution that also embeds a fixture file at compile time, by
/// `path` as written in `crates/meshedit/src/lib.rs`: what a student who
/// knows the layout would do to replay the hidden cases' expected answers.
fn embedding(path: &str) -> String {
    solution()
        + &format!(
            "\nconst EMBEDDED: &str = include_str!({path:?});\n\
             pub fn embedded_len() -> usize {{ EMBEDDED.len() }}\n"
        )
}

/// The model solution that also embeds, at compile time, what the Rust
/// expression `source` names (`include_str!(source)`); `bytes` for
/// `include_bytes!`.
fn embedding_expr(source: &str, bytes: bool) -> String {
    let (kind, ty) = if bytes {
        ("include_bytes", "[u8]")
    } else {
        ("include_str", "str")
    };
    solution()
        + &format!(
            "\npub static EMBEDDED: &{ty} = {kind}!({source});\n\
             pub fn embedded_len() -> usize {{ EMBEDDED.len() }}\n"
        )
}

/// The model solution with a macro whose expansion doubles its tokens at
/// every step: the compiler's memory grows without bound until an
/// allocation fails under the cap and it aborts. (A huge constant, or
/// `include_bytes!("/dev/zero")`, rustc refuses with a compile error of
/// its own.)
fn memory_bomb() -> String {
    solution() + "\nmacro_rules! double { ($($t:tt)*) => { double!{$($t)* $($t)*} } }\ndouble!{x}\n"
}

/// A file of the TA's own (in their home folder), holding `token`; removed
/// when dropped.
struct TaFile(PathBuf);

impl TaFile {
    fn new(token: &str) -> TaFile {
        let home = PathBuf::from(std::env::var_os("HOME").expect("HOME"));
        let path = home.join(format!(".meshlab-ta-test-{}", std::process::id()));
        std::fs::write(&path, token).unwrap();
        TaFile(path)
    }
}

impl Drop for TaFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// Every report file in `dir`, concatenated.
fn all_reports(dir: &Path) -> String {
    let mut text = String::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        text += &std::fs::read_to_string(entry.unwrap().path()).unwrap_or_default();
    }
    text
}

/// A student's lookup table of the visible cases, as a `lib.rs`: the model
/// solution, run only on an input whose positions are those of a lab or
/// bonus case (any labelling), else refusing or doing nothing. The table is
/// written out as literals, as a student would paste it from the handout's
/// fixtures.
fn lookup_table() -> String {
    let mut table = String::from("const VISIBLE: &[&[[f64; 3]]] = &[\n");
    for p in case_files("lab").iter().chain(&case_files("bonus")) {
        let f = json(p);
        table.push_str("    &[");
        for q in f["input"]["positions"].as_array().unwrap() {
            let c: Vec<f64> = q
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            table.push_str(&format!("[{:?}, {:?}, {:?}], ", c[0], c[1], c[2]));
        }
        table.push_str("],\n");
    }
    table.push_str("];\n");
    format!(
        "mod model {{\n{}\n}}\n\n{table}\n\
         fn visible(mesh: &halfedge::Mesh) -> bool {{\n\
             let bits = |ps: &mut dyn Iterator<Item = [f64; 3]>| {{\n\
                 let mut v: Vec<[u64; 3]> = ps.map(|p| p.map(f64::to_bits)).collect();\n\
                 v.sort();\n\
                 v\n\
             }};\n\
             let mine = bits(&mut mesh.positions().iter().map(|p| p.to_array()));\n\
             VISIBLE.iter().any(|t| bits(&mut t.iter().copied()) == mine)\n\
         }}\n\
         pub fn flip_edge(mesh: &mut halfedge::Mesh, e: halfedge::EdgeId) -> Option<halfedge::EdgeId> {{\n\
             if visible(mesh) {{ model::flip_edge(mesh, e) }} else {{ None }}\n\
         }}\n\
         pub fn split_edge(mesh: &mut halfedge::Mesh, e: halfedge::EdgeId) -> Option<halfedge::VertexId> {{\n\
             if visible(mesh) {{ model::split_edge(mesh, e) }} else {{ None }}\n\
         }}\n\
         static KNOWN: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);\n\
         pub fn loop_subdivide(mesh: &mut halfedge::Mesh) {{\n\
             use std::sync::atomic::Ordering;\n\
             let known = KNOWN.load(Ordering::Relaxed) || visible(mesh);\n\
             KNOWN.store(known, Ordering::Relaxed);\n\
             if known {{ model::loop_subdivide(mesh) }}\n\
         }}\n",
        solution()
    )
}

/// The first hidden case's file name.
fn a_hidden_case() -> String {
    let first = case_files("hidden")
        .into_iter()
        .next()
        .expect("a hidden case");
    first.file_name().unwrap().to_string_lossy().into_owned()
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// Asserts that cargo reads the workspace at `dir` with its lock file as
/// it is (`cargo metadata --locked --offline`).
fn assert_locked(dir: &Path) {
    let meta = Command::new(env!("CARGO"))
        .args(["metadata", "--locked", "--offline", "--format-version", "1"])
        .arg("--no-deps")
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        meta.status.success(),
        "{}: {}",
        dir.display(),
        String::from_utf8_lossy(&meta.stderr)
    );
}

fn tests_of(results: &serde_json::Value) -> Vec<serde_json::Value> {
    results["tests"].as_array().cloned().unwrap_or_default()
}

fn sum(tests: &[serde_json::Value], key: &str) -> f64 {
    tests.iter().map(|t| t[key].as_f64().unwrap_or(0.0)).sum()
}

#[test]
fn handout_is_clean_builds_locked_updates_and_its_grading_workflow_runs() {
    let _turn = take_turn();
    let dir = scratch("handout").join("lab");
    // The Classroom option is refused, saying what replaced it.
    let old = run(&["handout", dir.to_str().unwrap(), "--autograding"]);
    assert_eq!(old.code, 2, "{}", old.stderr);
    assert!(
        old.stderr.contains("GitHub Classroom was shut down"),
        "{}",
        old.stderr
    );
    assert!(!dir.exists(), "nothing written");
    let r = run(&["handout", dir.to_str().unwrap()]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let all = reference::handout::list_files(&dir).unwrap();
    for gone in [
        "reference/",
        // The autograder: no solution, but never the students'.
        "autograde/",
        "fixtures/hidden/",
        "docs/ta-guide.md",
        ".git/",
        "target/",
        ".ci/",
    ] {
        assert!(
            !all.iter().any(|f| f.starts_with(gone)),
            "{gone} was exported"
        );
    }
    for kept in [
        "Cargo.toml",
        "Cargo.lock",
        "README.md",
        "rust-toolchain.toml",
        "docs/architecture.md",
        "crates/meshedit/src/lib.rs",
        "grader/src/main.rs",
        "fixtures/lab/cube-subdivide-1.json",
        "fixtures/bonus/grid-subdivide-1.json",
        ".github/workflows/grade.yml",
        ".github/grading/summary.py",
    ] {
        assert!(all.iter().any(|f| f == kept), "{kept} is missing");
    }
    // No trace of the solution (found by content, below) or of TA
    // material in any text file.
    assert_eq!(
        reference::handout::ta_talk(&dir).unwrap(),
        Vec::<String>::new()
    );
    assert_eq!(
        reference::handout::solution_copies(&dir).unwrap(),
        Vec::<String>::new(),
        "no shipped file carries the model solution's code"
    );
    for doc in all.iter().filter(|f| f.ends_with(".md")) {
        let text = std::fs::read_to_string(dir.join(doc)).unwrap();
        assert!(
            !text.contains("reference/") && !text.contains("ta-guide"),
            "{doc} points students at TA material"
        );
    }
    let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
    assert!(
        !manifest.contains("insta"),
        "TA-only dependency: {manifest}"
    );
    assert!(
        !manifest.contains("autograde"),
        "the autograder is no member: {manifest}"
    );
    let student = std::fs::read_to_string(dir.join("crates/meshedit/src/lib.rs")).unwrap();
    assert_eq!(student.matches("todo!(").count(), 3, "the three stubs");

    // The lock file is the lab's, less what only the TA tool uses: every
    // package keeps its version, and cargo finds nothing to change.
    let lab_lock = std::fs::read_to_string(root().join("Cargo.lock")).unwrap();
    let lock = std::fs::read_to_string(dir.join("Cargo.lock")).unwrap();
    assert!(!lock.contains("name = \"insta\""));
    assert!(!lock.contains("name = \"autograde\""));
    for block in lock.split("\n\n").filter(|b| b.contains("[[package]]")) {
        assert!(lab_lock.contains(block.trim()), "changed: {block}");
    }
    assert_locked(&dir);

    // Exporting into a folder that has files is refused, naming --update.
    let again = run(&["handout", dir.to_str().unwrap()]);
    assert_eq!(again.code, 2);
    assert!(again.stderr.contains("exists and is not empty"));
    assert!(again.stderr.contains("--update"));

    // It builds --locked, and its grader fails the stubs cleanly.
    let cargo = |args: &[&str]| {
        Command::new(env!("CARGO"))
            .args(args)
            .current_dir(&dir)
            .env("CARGO_TARGET_DIR", target())
            .env("RUST_BACKTRACE", "1")
            .output()
            .unwrap()
    };
    let out = cargo(&[
        "run",
        "--locked",
        "--offline",
        "--quiet",
        "-p",
        "grader",
        "--",
        "--no-color",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stdout}\n{stderr}");
    assert!(
        stdout.trim_end().ends_with("[warn] test failed"),
        "{stdout}"
    );
    assert!(
        stdout.contains("flip_edge panicked: not yet implemented"),
        "{stdout}"
    );
    assert!(
        !stdout.contains("hidden") && !stdout.contains("icosphere"),
        "no hidden cases in the handout"
    );
    assert!(!stderr.contains("panicked at"), "{stderr}");

    // The grading workflow, as GitHub Actions runs it: valid YAML, each
    // command it runs exists, and its job summary is right for the model
    // solution (every point, green), the stubs (none, red) and code that
    // does not compile (the compiler's error, red).
    let workflow = dir.join(".github/workflows/grade.yml");
    let yml = std::fs::read_to_string(&workflow).unwrap();
    let version = reference::handout::rust_version(&root()).unwrap();
    assert!(
        yml.contains(&format!("RUSTUP_TOOLCHAIN: \"{version}\"")),
        "{yml}"
    );
    assert!(
        !yml.contains("classroom"),
        "nothing of GitHub Classroom: {yml}"
    );
    let steps = workflow_steps(&workflow);
    let lab_points = case_files("lab").len();
    let run_workflow = |lib_rs: &str, tag: &str| -> (bool, String) {
        std::fs::write(dir.join("crates/meshedit/src/lib.rs"), lib_rs).unwrap();
        let summary = dir.join(format!("summary-{tag}.md"));
        let mut last_ok = true;
        for (name, run) in &steps {
            let program = run.split_whitespace().next().unwrap();
            let which = Command::new("sh")
                .args(["-c", &format!("command -v {program}")])
                .output()
                .unwrap();
            assert!(which.status.success(), "step {name}: no {program}");
            if program == "rustup" {
                // Installing a toolchain needs the network; the pin is checked above.
                continue;
            }
            let out = Command::new("bash")
                .args(["-eo", "pipefail", "-c", run])
                .current_dir(&dir)
                .env("CARGO_TARGET_DIR", target())
                .env("GITHUB_STEP_SUMMARY", &summary)
                .output()
                .unwrap();
            last_ok = out.status.success();
            if name != "Grade" {
                assert!(
                    last_ok,
                    "step {name} failed:\n{}{}",
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                );
            }
        }
        (
            last_ok,
            std::fs::read_to_string(&summary).unwrap_or_default(),
        )
    };
    let (green, text) = run_workflow(&solution(), "solution");
    assert!(green, "{text}");
    assert!(
        text.starts_with(&format!(
            "## Mesh lab: {lab_points}/{lab_points} points, all tests passed"
        )),
        "{text}"
    );
    for (function, kind) in [
        ("flip_edge", "flip"),
        ("split_edge", "split"),
        ("flips and splits in sequence", "sequence"),
        ("loop_subdivide", "subdivide"),
    ] {
        let n = ["lab"]
            .iter()
            .flat_map(|g| case_files(g))
            .filter(|p| json(p)["operation"]["kind"] == kind)
            .count();
        assert!(
            text.contains(&format!("| `{function}` | {n}/{n} |  |")),
            "{text}"
        );
    }
    let (green, text) = run_workflow(&stubs(), "stubs");
    assert!(!green, "the stubs fail the check: {text}");
    assert!(
        text.starts_with(&format!("## Mesh lab: 0/{lab_points} points, test failed")),
        "{text}"
    );
    assert!(
        text.contains("flip_edge panicked: not yet implemented"),
        "{text}"
    );
    let (green, text) = run_workflow("pub fn flip_edge( {\n", "broken");
    assert!(!green);
    assert!(text.starts_with("## Mesh lab: not graded"), "{text}");
    assert!(text.contains("The code does not compile"), "{text}");
    assert!(
        text.contains("error"),
        "the compiler's error is shown: {text}"
    );
    std::fs::write(dir.join("crates/meshedit/src/lib.rs"), solution()).unwrap();

    // --update refreshes fixtures and docs, removes a dropped case and
    // leaves the student's work alone.
    let student_code = "// my work\n".to_string() + &solution();
    std::fs::write(dir.join("crates/meshedit/src/lib.rs"), &student_code).unwrap();
    std::fs::write(dir.join("crates/meshedit/src/notes.rs"), "// mine").unwrap();
    std::fs::write(dir.join("fixtures/lab/cube-split.json"), "{}").unwrap();
    std::fs::write(dir.join("fixtures/lab/old-case.json"), "{}").unwrap();
    std::fs::remove_file(dir.join("docs/architecture.md")).unwrap();
    let r = run(&["handout", dir.to_str().unwrap(), "--update"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(
        r.stdout.contains("updated fixtures/lab/cube-split.json"),
        "{}",
        r.stdout
    );
    assert!(
        r.stdout.contains("updated docs/architecture.md"),
        "{}",
        r.stdout
    );
    assert!(
        r.stdout.contains("removed fixtures/lab/old-case.json"),
        "{}",
        r.stdout
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("crates/meshedit/src/lib.rs")).unwrap(),
        student_code
    );
    assert!(dir.join("crates/meshedit/src/notes.rs").is_file());
    assert_eq!(
        std::fs::read(dir.join("fixtures/lab/cube-split.json")).unwrap(),
        std::fs::read(root().join("fixtures/lab/cube-split.json")).unwrap()
    );
    let r = run(&[
        "handout",
        root().join("crates").to_str().unwrap(),
        "--update",
    ]);
    assert_eq!(r.code, 2);
    assert!(r.stderr.contains("is not a handout"), "{}", r.stderr);
    std::fs::remove_dir_all(dir.parent().unwrap()).unwrap();
}

/// The `run:` commands of a workflow's steps, by step name (the file must
/// parse as YAML: checked with Python's yaml module, as GitHub would).
fn workflow_steps(path: &Path) -> Vec<(String, String)> {
    let script = "import json, sys, yaml\n\
        w = yaml.safe_load(open(sys.argv[1]))\n\
        steps = [s for job in w['jobs'].values() for s in job['steps']]\n\
        assert all('uses' in s or 'run' in s for s in steps)\n\
        print(json.dumps([[s['name'], s['run']] for s in steps if 'run' in s]))";
    let out = Command::new("python3")
        .args(["-c", script])
        .arg(path)
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "the workflow does not parse: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice::<Vec<(String, String)>>(&out.stdout).unwrap()
}

/// Gradescope's /autograder for the tests (outside the lab, as a bundle
/// must be), and the build's target folder (outside the lab too, as the
/// build's must be: its path is visible to the student's code). The target
/// folder and the vendored crates are class grading's (the tests'
/// [`class_build_dir`], as platforms.rs does), so that the dependencies,
/// whose fingerprints hold the vendored sources' path, compile once per
/// checkout for all of them.
/// A `.cargo/config.toml` whose program-running keys name programs that
/// leave `marks/ran-NAME` (whoever runs them: the folder is everyone's).
fn cargo_config_running(marks: &Path) -> String {
    use std::os::unix::fs::PermissionsExt;
    std::fs::create_dir_all(marks).unwrap();
    std::fs::set_permissions(marks, std::fs::Permissions::from_mode(0o777)).unwrap();
    let plant = |name: &str| {
        let program = marks.join(format!("prog-{name}"));
        let text = format!(
            "#!/bin/sh\ntouch {}\nexit 1\n",
            marks.join(format!("ran-{name}")).display()
        );
        std::fs::write(&program, text).unwrap();
        std::fs::set_permissions(&program, std::fs::Permissions::from_mode(0o755)).unwrap();
        serde_json::to_string(&program.to_string_lossy()).unwrap()
    };
    format!(
        "[build]\nrustc-wrapper = {}\nrustc-workspace-wrapper = {}\nrustc = {}\n\
         [target.'cfg(all())']\nrunner = {}\n[env]\nRUSTC_WRAPPER = {}\n",
        plant("rustc-wrapper"),
        plant("workspace-wrapper"),
        plant("rustc"),
        plant("runner"),
        plant("env-wrapper"),
    )
}

/// The planted programs that ran.
fn ran_from(marks: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(marks)
        .unwrap()
        .filter_map(|e| {
            let name = e.ok()?.file_name().to_string_lossy().into_owned();
            name.strip_prefix("ran-").map(str::to_string)
        })
        .collect();
    names.sort();
    names
}

fn gradescope_places() -> (PathBuf, PathBuf) {
    let tmp = class_build_dir().parent().unwrap().to_path_buf();
    (tmp.join("autograder"), class_build_dir().join("target"))
}

#[test]
fn the_gradescope_bundle_grades_every_kind_of_upload() {
    let _turn = take_turn();
    // Laid out as on Gradescope: the bundle unzipped into source/, the
    // script copied next to it.
    let (ag, build_target) = gradescope_places();
    let _ = std::fs::remove_dir_all(&ag);
    let marks = scratch("gradescope-marks");
    let bundle = ag.join("source");
    // Four sets of fresh cases keep the bundle small here (16 by default).
    let r = run(&["gradescope", bundle.to_str().unwrap(), "--fresh-sets", "4"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let lab = bundle.join("lab");
    assert!(lab.join("fixtures/hidden").is_dir(), "hidden cases graded");
    assert!(!lab.join("reference").exists(), "no solution on the server");
    assert!(
        lab.join("autograde/src/gradescope.rs").is_file(),
        "the autograder goes along"
    );
    let setup = std::fs::read_to_string(bundle.join("setup.sh")).unwrap();
    let version = reference::handout::rust_version(&root()).unwrap();
    assert!(
        setup.contains(&format!("RUST_VERSION=\"{version}\"")),
        "{setup}"
    );
    assert!(setup.contains("run_autograder\" --setup"), "{setup}");
    let script = std::fs::read_to_string(bundle.join("run_autograder")).unwrap();
    assert!(!script.contains('@'), "every setting filled in");
    std::fs::copy(bundle.join("run_autograder"), ag.join("run_autograder")).unwrap();

    // setup.sh's download, as it runs it: every platform's crates (vendoring
    // needs the Windows-only ones too, which no build here ever fetched).
    let fetched = Command::new(env!("CARGO"))
        .args(["fetch", "--locked"])
        .current_dir(&lab)
        .output()
        .unwrap();
    assert!(
        fetched.status.success(),
        "setup.sh's `cargo fetch --locked` fails in the bundle's lab: {}",
        String::from_utf8_lossy(&fetched.stderr)
    );
    // The rest of setup.sh, past installing the toolchain: as root, it moves
    // the hidden cases into a folder only root may enter and builds as nobody.
    let out = Command::new(bundle.join("run_autograder"))
        .arg("--setup")
        .env("AUTOGRADER", &ag)
        .env("CARGO_TARGET_DIR", &build_target)
        .env("MESHLAB_VENDOR", class_build_dir().join("vendor"))
        // The autograder's own build, kept between runs of this test and
        // shared with platforms.rs.
        .env(
            "MESHLAB_AUTOGRADE_TARGET",
            class_build_dir().parent().unwrap().join("autograde-target"),
        )
        .output()
        .unwrap();
    let setup_log = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{setup_log}");
    assert!(
        !lab.join("fixtures/hidden").exists(),
        "the hidden cases left the lab"
    );
    let grading = ag.join("meshlab/fixtures");
    assert!(grading.join("hidden").join(a_hidden_case()).is_file());
    assert!(grading.join("lab/cube-flip-1.json").is_file());
    {
        use std::os::unix::fs::{MetadataExt, PermissionsExt};
        let meta = std::fs::metadata(&grading).unwrap();
        assert_eq!(meta.permissions().mode() & 0o777, 0o700);
        if is_root() {
            assert_eq!(meta.uid(), 0);
            assert!(
                setup_log.contains("built the grader as nobody"),
                "{setup_log}"
            );
            assert_eq!(
                std::fs::metadata(&build_target).unwrap().uid(),
                65534,
                "the build's target folder is nobody's"
            );
        }
    }

    // Each upload is also graded on one of the bundle's sets of fresh cases,
    // counted like hidden ones.
    let fresh: usize = reference::fresh::counted(false).iter().sum();
    let max =
        (counted("flip") + counted("split") + counted("sequence") + counted("subdivide") + fresh)
            as f64;
    // An upload of these files and symbolic links (path, target), graded
    // with a budget and a per-call limit when given, on one CPU when asked
    // (Gradescope's default machine has one).
    let upload_with = |files: &[(&str, String)],
                       links: &[(&str, &Path)],
                       limits: Option<(f64, f64)>,
                       one_cpu: bool| {
        let _ = std::fs::remove_dir_all(ag.join("submission"));
        std::fs::create_dir_all(ag.join("submission")).unwrap();
        for (rel, text) in files {
            write(&ag.join("submission").join(rel), text);
        }
        for (rel, to) in links {
            std::os::unix::fs::symlink(to, ag.join("submission").join(rel)).unwrap();
        }
        let mut cmd = if one_cpu {
            let mut c = Command::new("taskset");
            c.args(["-c", "0"]).arg(ag.join("run_autograder"));
            c
        } else {
            Command::new(ag.join("run_autograder"))
        };
        // A secret in the grading machine's environment, for the build to miss.
        cmd.env("AUTOGRADER", &ag)
            .env("MESHLAB_TA_SECRET", "TA-ENV-TOKEN");
        if let Some((budget, timeout)) = limits {
            cmd.env("MESHLAB_BUDGET", budget.to_string())
                .env("MESHLAB_CASE_TIMEOUT", timeout.to_string());
        }
        let start = Instant::now();
        let out = cmd.output().unwrap();
        let took = start.elapsed();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        (
            json(&ag.join("results/results.json")),
            took,
            String::from_utf8_lossy(&out.stdout).into_owned(),
        )
    };
    let upload = |files: &[(&str, String)], links: &[(&str, &Path)], budget: Option<u32>| {
        upload_with(files, links, budget.map(|b| (b as f64, 1.0)), false)
    };
    let grade = |files: &[(&str, String)], budget: Option<u32>| upload(files, &[], budget);

    // The model solution alone: full marks, hidden cases after publication.
    let (good, good_took, log) = grade(&[("lib.rs", solution())], None);
    let tests = tests_of(&good);
    assert_eq!(sum(&tests, "max_score"), max, "{log}");
    assert_eq!(good["score"].as_f64(), Some(max), "{good}");
    if is_root() {
        assert!(log.contains("cargo build as nobody: exit 0"), "{log}");
        assert!(
            log.contains("user nobody"),
            "the case child drops too: {log}"
        );
    }
    let hidden = tests
        .iter()
        .filter(|t| t["visibility"] == "after_published")
        .count();
    assert_eq!(hidden, case_files("hidden").len() + fresh);
    let fresh_tests: Vec<&str> = tests
        .iter()
        .filter_map(|t| t["name"].as_str())
        .filter(|n| n.starts_with("fresh-"))
        .collect();
    assert_eq!(fresh_tests.len(), fresh, "{fresh_tests:?}");
    let set_of = |log: &str| {
        log.lines()
            .find_map(|l| l.split("fresh cases: set ").nth(1))
            .map(|rest| rest.split_whitespace().next().unwrap_or("").to_string())
            .unwrap_or_else(|| panic!("no fresh set named: {log}"))
    };
    let good_set = set_of(&log);
    assert!(tests
        .iter()
        .filter(|t| t["visibility"] != "after_published")
        .all(|t| !t["name"].as_str().unwrap().contains("hidden")));
    // No bonus case (some grid cases are lab cases now: named by file).
    assert!(
        !tests
            .iter()
            .any(|t| t["tags"].as_array().unwrap().contains(&"bonus".into())),
        "no bonus"
    );
    // Whole seconds of the autograder's own run: within the launch's.
    let seconds = good["execution_time"].as_u64().expect("execution_time");
    assert!(
        seconds <= good_took.as_secs() && seconds + 30 >= good_took.as_secs(),
        "execution_time {seconds} s, the run took {good_took:?}"
    );
    // The leaderboard: loop_subdivide's time on the grader's larger
    // icosphere, timed within the subdivision stage's budget.
    let board = good["leaderboard"]
        .as_array()
        .unwrap_or_else(|| panic!("no leaderboard: {log}\n{}", good["output"]));
    assert_eq!(board.len(), 1, "{board:?}");
    let faces = halfedge::shapes::icosphere(grader::judge::scaling::LARGE_LEVEL).num_faces();
    assert_eq!(
        board[0]["name"],
        format!("loop_subdivide (ms, icosphere {faces} faces)")
    );
    assert_eq!(board[0]["order"], "asc");
    let ms = board[0]["value"].as_f64().unwrap();
    assert!(ms > 0.0 && ms < good_took.as_secs_f64() * 1000.0, "{ms} ms");
    assert!(log.contains("leaderboard: loop_subdivide"), "{log}");
    // A student whose program has its own clock_gettime (1 us a call) and a
    // quadratic subdivision: the grader times the child from the kernel,
    // so the leaderboard shows the work, never 0.001 ms. (A per-call limit
    // of 5 s: the larger round takes a few tenths of a second here.)
    let (own, _, own_log) = upload_with(
        &[("lib.rs", own_clock_quadratic())],
        &[],
        Some((480.0, 5.0)),
        false,
    );
    assert_eq!(own["score"].as_f64(), Some(max), "{own_log}\n{own}");
    let own_ms = own["leaderboard"][0]["value"]
        .as_f64()
        .unwrap_or_else(|| panic!("no leaderboard: {own_log}\n{own}"));
    eprintln!("leaderboard: the model solution {ms} ms, the own-clock quadratic {own_ms} ms");
    assert!(own_ms > 4.0 * ms, "{own_ms} ms against the model's {ms} ms");

    // What no upload's lib.rs can be: each gets its results.json at once,
    // saying what the file is, with nothing built or read; the uploads
    // after them are graded as ever.
    let ta_secret = ag.join("ta-secret.txt");
    std::fs::write(&ta_secret, "TA-FILE-TOKEN").unwrap();
    for unfit in unfit_files(&ta_secret) {
        let sub = ag.join("submission");
        let _ = std::fs::remove_dir_all(&sub);
        std::fs::create_dir_all(sub.join("crates/meshedit/src")).unwrap();
        (unfit.make)(&sub.join("crates/meshedit/src/lib.rs"));
        let ran = output_within(
            Command::new(ag.join("run_autograder")).env("AUTOGRADER", &ag),
            120,
        );
        let log = String::from_utf8_lossy(&ran.stdout).into_owned();
        assert!(
            ran.status.success(),
            "{log}\n{}",
            String::from_utf8_lossy(&ran.stderr)
        );
        let results = json(&ag.join("results/results.json"));
        assert_eq!(results["score"].as_f64(), Some(0.0), "{log}\n{results}");
        assert_eq!(sum(&tests_of(&results), "max_score"), max, "{results}");
        let output = results["output"].as_str().unwrap();
        assert!(
            output.contains(&format!("crates/meshedit/src/lib.rs {}", unfit.says)),
            "{}: {output}",
            unfit.says
        );
        assert!(
            !log.contains("build:") && !log.contains("TA-FILE-TOKEN"),
            "{log}"
        );
    }

    // A whole workspace: the student's file, never another crate's lib.rs
    // (which sorts first).
    let workspace = [
        (
            "crates/halfedge/src/lib.rs",
            "pub fn nothing() {}".to_string(),
        ),
        ("crates/meshedit/src/lib.rs", solution()),
        ("grader/src/lib.rs", "this is not Rust".to_string()),
        ("Cargo.toml", "[workspace]".to_string()),
        // The student's cargo config, naming programs for cargo to run:
        // no build reads the upload's configuration.
        (".cargo/config.toml", cargo_config_running(&marks)),
    ];
    let (ws, _, log) = grade(&workspace, None);
    assert_eq!(ws["score"].as_f64(), Some(max), "{log}\n{ws}");
    assert_eq!(ran_from(&marks), Vec::<String>::new(), "{log}");

    // The same inside one folder, as a zip of the folder unpacks.
    let nested: Vec<(String, String)> = workspace
        .iter()
        .map(|(p, t)| (format!("lab-2026/{p}"), t.clone()))
        .collect();
    let nested: Vec<(&str, String)> = nested
        .iter()
        .map(|(p, t)| (p.as_str(), t.clone()))
        .collect();
    let (nest, _, nest_log) = grade(&nested, None);
    assert_eq!(nest["score"].as_f64(), Some(max), "{nest}");
    assert_eq!(ran_from(&marks), Vec::<String>::new(), "{nest_log}");
    // The same file, uploaded again in another layout: the same fresh set.
    assert_eq!(set_of(&nest_log), good_set, "{nest_log}");

    // The stubs: zero, every case reported.
    let (stub, _, _) = grade(&[("crates/meshedit/src/lib.rs", stubs())], None);
    assert_eq!(stub["score"].as_f64(), Some(0.0));
    assert_eq!(sum(&tests_of(&stub), "max_score"), max);
    // No time for code that does not subdivide right, and the output says so.
    assert!(stub.get("leaderboard").is_none(), "{stub}");
    assert!(
        stub["output"]
            .as_str()
            .unwrap()
            .contains("leaderboard: no time (loop_subdivide does not pass every case yet)"),
        "{}",
        stub["output"]
    );

    // A compile error: zero out of the full score, with the compiler's words.
    let (broken, _, _) = grade(&[("lib.rs", "pub fn flip_edge( {\n".into())], None);
    assert_eq!(broken["score"].as_f64(), Some(0.0));
    assert_eq!(sum(&tests_of(&broken), "max_score"), max);
    assert!(broken.get("leaderboard").is_none(), "{broken}");
    let output = broken["output"].as_str().unwrap();
    assert!(
        output.starts_with("Your code does not compile:"),
        "{output}"
    );
    assert!(output.contains("unclosed delimiter"), "{output}");
    assert!(!output.contains("Compiling "), "{output}");

    // Only another crate's file: refused, saying what was expected.
    let (none, _, _) = grade(&[("crates/halfedge/src/lib.rs", solution())], None);
    assert_eq!(none["score"].as_f64(), Some(0.0));
    assert!(
        none["output"]
            .as_str()
            .unwrap()
            .contains("No crates/meshedit/src/lib.rs in your upload"),
        "{none}"
    );

    // Hostile at compile time: embedding a hidden case's expected answer
    // does not compile, by the path from the student's file into the lab's
    // fixtures (the hidden cases left the lab at setup)...
    let hidden_case = a_hidden_case();
    let does_not_compile = |results: &serde_json::Value, log: &str, why: &str| {
        assert_eq!(results["score"].as_f64(), Some(0.0), "{log}\n{results}");
        assert_eq!(sum(&tests_of(results), "max_score"), max, "{results}");
        let output = results["output"].as_str().unwrap();
        assert!(
            output.starts_with("Your code does not compile:"),
            "{output}"
        );
        assert!(output.contains("couldn't read"), "{output}");
        assert!(output.contains(why), "{output}");
    };
    let relative = format!("../../../fixtures/hidden/{hidden_case}");
    let (leak, _, log) = grade(&[("lib.rs", embedding(&relative))], None);
    does_not_compile(&leak, &log, "No such file or directory");
    // ... while the same path to a lab case compiles and grades: the path
    // is right, only the hidden cases are out of reach. (The same upload
    // carries a warning: it is shown, the grade is unaffected.)
    let warned = embedding("../../../fixtures/lab/cube-flip-1.json") + "\nfn unused_helper() {}\n";
    let (control, _, warn_log) = grade(&[("lib.rs", warned)], None);
    assert_eq!(
        control["score"].as_f64(),
        Some(max),
        "{warn_log}\n{control}"
    );
    assert!(
        control["output"]
            .as_str()
            .unwrap()
            .contains("unused_helper"),
        "{}",
        control["output"]
    );
    // ... and by the absolute path of the folder they moved to (published
    // with this bundle): root only, and out of the locked-in build's reach,
    // whoever runs it.
    let absolute = grading.join("hidden").join(&hidden_case);
    let (leak, _, log) = grade(&[("lib.rs", embedding(absolute.to_str().unwrap()))], None);
    does_not_compile(&leak, &log, "No such file or directory");
    // ... with the very words a name no case has gets: what the build may
    // not read, it cannot tell from what does not exist (a compile error
    // costs no attempt on PrairieLearn: one upload could test many names).
    // (As long as the real name: the compiler shortens a long line it quotes.)
    let guessed = grading
        .join("hidden")
        .join(format!("{}.json", "z".repeat(hidden_case.len() - 5)));
    assert!(!guessed.exists());
    let (miss, _, miss_log) = grade(&[("lib.rs", embedding(guessed.to_str().unwrap()))], None);
    does_not_compile(&miss, &miss_log, "No such file or directory");
    let words = |results: &serde_json::Value, path: &Path| {
        results["output"]
            .as_str()
            .unwrap()
            .lines()
            .filter(|l| l.contains(path.to_str().unwrap()))
            .map(|l| l.replace(path.to_str().unwrap(), "PATH"))
            .collect::<Vec<_>>()
    };
    let there = words(&leak, &absolute);
    assert!(!there.is_empty(), "{leak}");
    assert_eq!(there, words(&miss, &guessed), "{leak}\n{miss}");
    assert!(
        log.contains("empty root (no other file even seen to exist)"),
        "{log}"
    );
    // ... by the path from the build's own target folder (in
    // CARGO_TARGET_DIR at compile time), which leads nowhere...
    let from_target =
        format!("concat!(env!(\"CARGO_TARGET_DIR\"), \"/../../fixtures/hidden/{hidden_case}\")");
    let (leak, _, log) = grade(&[("lib.rs", embedding_expr(&from_target, false))], None);
    does_not_compile(&leak, &log, "No such file or directory");
    // ... and files of the machine's that anyone may read: the TA's own
    // lab with its hidden cases and model solution, the environment.
    // (Not in the build's root; its own /proc is, closed by Landlock.)
    for (path, why) in [
        (
            root().join("fixtures/hidden").join(&hidden_case),
            "No such file or directory",
        ),
        (
            root().join("reference/src/solution.rs"),
            "No such file or directory",
        ),
        (PathBuf::from("/proc/self/environ"), "Permission denied"),
    ] {
        let (leak, _, log) = grade(&[("lib.rs", embedding(path.to_str().unwrap()))], None);
        does_not_compile(&leak, &log, why);
        assert!(log.contains("Landlock ABI"), "{log}");
    }
    // Memory without bound at compile time: stopped by the memory cap, named.
    let (bomb, _, log) = grade(&[("lib.rs", memory_bomb())], None);
    assert_eq!(bomb["score"].as_f64(), Some(0.0), "{log}\n{bomb}");
    let output = bomb["output"].as_str().unwrap();
    assert!(
        output.starts_with("Your code does not compile: the build used more than 4 GiB"),
        "{output}"
    );

    // A symbolic link in the upload is never followed: root copies the
    // student's file, and the compiler would quote a hidden case's lines.
    let (link, _, log) = upload(&[], &[("lib.rs", &absolute)], None);
    assert_eq!(link["score"].as_f64(), Some(0.0), "{log}\n{link}");
    let output = link["output"].as_str().unwrap();
    assert!(output.contains("lib.rs is a symbolic link"), "{output}");
    assert!(!output.contains("\"schema\""), "{output}");

    // Hostile: loop_subdivide spawns `sleep 1000` and never returns. The
    // run ends within its budget; flips and splits still earn their points.
    let budget = 45;
    let (bad, took, log) = grade(&[("lib.rs", hostile())], Some(budget));
    assert!(
        took < Duration::from_secs(budget as u64 + 10),
        "{took:?}\n{log}"
    );
    assert!(!log.contains("TA-ENV-TOKEN"), "{log}");
    let tests = tests_of(&bad);
    let earned = |function: &str| {
        tests
            .iter()
            .filter(|t| t["name"].as_str().unwrap().contains(function))
            .map(|t| t["score"].as_f64().unwrap())
            .sum::<f64>()
    };
    let fresh_per = reference::fresh::counted(false);
    assert_eq!(
        earned("flip_edge"),
        (counted("flip") + fresh_per[0]) as f64,
        "{log}"
    );
    assert_eq!(
        earned("split_edge"),
        (counted("split") + fresh_per[1]) as f64,
        "{log}"
    );
    assert_eq!(earned("loop_subdivide"), 0.0, "{log}");
    assert_eq!(sum(&tests, "max_score"), max, "{log}\n{bad}");

    // A correct solution whose flip_edge takes 90% of the per-call limit
    // (0.18 s of 0.2 s), on one CPU as on Gradescope's default machine: the
    // time left after the build is shared out by the child runs each
    // function makes (five labellings per flip case, the bonus ones run
    // too: 145 of 283 before the fresh cases), so it gets full marks.
    // Shared out by cases, flip_edge got a third of it, less than its 145
    // runs take, and was stopped. The budget: the time this upload's build
    // takes (as the last one's did), the reserve, and 0.325 s a run to grade
    // (the limit plus 0.125 s for a run's start and judging; from about
    // 0.07 s over the limit a run, the limit holds for every run), the runs
    // as the grader counted them for the last upload. A 0.2 s limit rather
    // than the default 0.6 s: the claim is the same at any limit, and the
    // sleeps (in the sequences' flips too) are most of this test's time.
    let build = warn_log
        .lines()
        .find_map(|l| l.split("exit 0 in ").nth(1))
        .and_then(|t| t.trim_end_matches(" s").parse::<f64>().ok())
        .unwrap_or_else(|| panic!("the build's time: {warn_log}"));
    let runs: usize = warn_log
        .lines()
        .filter_map(|l| {
            l.split(" runs, ")
                .next()?
                .rsplit('(')
                .next()?
                .parse::<usize>()
                .ok()
        })
        .sum();
    assert!(runs > 0, "the runs the grader counted: {warn_log}");
    let (slow, _, log) = upload_with(
        &[("lib.rs", slow_flip(0.18))],
        &[],
        Some((build + 10.0 + 0.325 * runs as f64, 0.2)),
        true,
    );
    assert_eq!(slow["score"].as_f64(), Some(max), "{log}\n{slow}");
    let flips = ["lab", "hidden", "bonus"]
        .iter()
        .flat_map(|g| case_files(g))
        .filter(|p| json(p)["operation"]["kind"] == "flip")
        .count();
    assert!(
        log.contains(&format!(
            "flip_edge: {} cases, 0.20 s a call ({} runs, 1 side by side)",
            counted("flip") + fresh_per[0],
            5 * (flips + fresh_per[0])
        )),
        "the grader counted the runs: {log}"
    );
    std::fs::remove_dir_all(&ag).unwrap();
}

#[test]
fn a_class_folder_gets_a_row_for_every_entry() {
    let _turn = take_turn();
    let dir = scratch("class");
    let subs = dir.join("submissions");
    write(&subs.join("alice.rs"), &stubs());
    // The workspace inside one folder, with other crates' lib.rs around.
    write(
        &subs.join("bob/lab/crates/meshedit/src/lib.rs"),
        &solution(),
    );
    write(&subs.join("bob/lab/crates/halfedge/src/lib.rs"), "broken {");
    // Another bob, as a file: both keep a row and reports of their own.
    write(&subs.join("bob.rs"), &stubs());
    write(&subs.join("carol.rs"), "pub fn flip_edge( {\n");
    std::fs::create_dir_all(subs.join("dave")).unwrap();
    write(&subs.join("notes.txt"), "grading notes");
    write(&subs.join("mallory.rs"), &hostile());
    // A name a spreadsheet would run, and a message with a CR and lines
    // that look like the grader's.
    write(&subs.join("=cmd().rs"), &forging());
    // Embeds a hidden case by the path from the student's file to the
    // copy's fixtures: the copy has no hidden cases. Frank embeds a lab case
    // by the same path, to show the path is right.
    let hidden_case = a_hidden_case();
    write(
        &subs.join("eve.rs"),
        &embedding(&format!("../../../fixtures/hidden/{hidden_case}")),
    );
    write(
        &subs.join("frank.rs"),
        &embedding("../../../fixtures/lab/cube-flip-1.json"),
    );
    // Links to the hidden case: as a whole entry, and as the file inside a
    // workspace. Never followed.
    let hidden_file = root().join("fixtures/hidden").join(&hidden_case);
    std::os::unix::fs::symlink(&hidden_file, subs.join("grace.rs")).unwrap();
    std::fs::create_dir_all(subs.join("heidi/crates/meshedit/src")).unwrap();
    std::os::unix::fs::symlink(&hidden_file, subs.join("heidi/crates/meshedit/src/lib.rs"))
        .unwrap();
    // At compile time, run as the TA themselves: the hidden case by the
    // path from the build's own target folder, by the lab's absolute path,
    // a file in the TA's home, /dev/zero, and a macro growing without
    // bound. Each is refused or stopped, and scores as a compile error.
    write(
        &subs.join("ivan.rs"),
        &embedding_expr(
            &format!(
                "concat!(env!(\"CARGO_TARGET_DIR\"), \"/../../fixtures/hidden/{hidden_case}\")"
            ),
            false,
        ),
    );
    // The previous student's program, left in the shared target folder
    // (frank's, built just before): removed before each build.
    write(
        &subs.join("frankie.rs"),
        &embedding_expr(
            "concat!(env!(\"CARGO_TARGET_DIR\"), \"/debug/grader-child\")",
            true,
        ),
    );
    let lab_hidden = root().join("fixtures/hidden").join(&hidden_case);
    write(
        &subs.join("judy.rs"),
        &embedding(lab_hidden.to_str().unwrap()),
    );
    let ta_token = format!("TA-HOME-TOKEN-{}", std::process::id());
    let ta_file = TaFile::new(&ta_token);
    write(
        &subs.join("ken.rs"),
        &embedding(ta_file.0.to_str().unwrap()),
    );
    write(&subs.join("leo.rs"), &embedding_expr("\"/dev/zero\"", true));
    write(&subs.join("mia.rs"), &memory_bomb());
    write(&subs.join("lena.rs"), &lookup_table());
    // Files no student's lib.rs can be, as a tarball unpacked by root makes
    // them: named pipes (opening one to read blocks), devices that read
    // without end, links to a device and to the TA's file, files of 60 MB;
    // each as a whole entry and inside a folder. None is opened, each is
    // its row's reason, and nothing else changes.
    mkfifo(&subs.join("pipe.rs"));
    std::fs::create_dir_all(subs.join("quinn/crates/meshedit/src")).unwrap();
    mkfifo(&subs.join("quinn/crates/meshedit/src/lib.rs"));
    let devices = mknod_zero(&subs.join("device.rs"));
    if devices {
        std::fs::create_dir_all(subs.join("rita/crates/meshedit/src")).unwrap();
        assert!(mknod_zero(&subs.join("rita/crates/meshedit/src/lib.rs")));
    }
    std::os::unix::fs::symlink("/dev/zero", subs.join("zero.rs")).unwrap();
    std::fs::create_dir_all(subs.join("sam/crates/meshedit/src")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", subs.join("sam/crates/meshedit/src/lib.rs")).unwrap();
    std::os::unix::fs::symlink(&ta_file.0, subs.join("tina.rs")).unwrap();
    std::fs::create_dir_all(subs.join("uma/crates/meshedit/src")).unwrap();
    std::os::unix::fs::symlink(&ta_file.0, subs.join("uma/crates/meshedit/src/lib.rs")).unwrap();
    huge_file(&subs.join("huge.rs"), 60 << 20);
    huge_file(&subs.join("vera/crates/meshedit/src/lib.rs"), 60 << 20);
    // Names a page or a file system would trip on: a URL scheme, 250
    // bytes (NAME.results.json would be 263), a bidirectional override.
    // The stubs, alice's file: graded once, copied.
    let scheme = "javascript:alert(document.title)";
    let long = "x".repeat(250);
    let bidi = "evil\u{202e}gnp";
    for name in [scheme, long.as_str(), bidi] {
        write(&subs.join(format!("{name}.rs")), &stubs());
    }
    // Over the 256 KiB the similarity hints compare (under the 1 MiB a
    // file may hold): graded, and listed as not compared but identical.
    let padded = stubs() + &format!("// {}\n", "pad ".repeat(80_000));
    write(&subs.join("big1.rs"), &padded);
    write(&subs.join("big2.rs"), &padded);
    let out = dir.join("out");
    let options = reference::class::Options {
        budget: 60.0,
        ..class_options(1.0, 8.0)
    };
    let start = Instant::now();
    let rows = {
        let _watch = Watchdog::new(1200, "class grading of a folder with pipes and devices");
        reference::class::grade_class(&root(), &subs, &out, &options).unwrap()
    };
    let took = start.elapsed();
    let names: Vec<&str> = rows.iter().map(|r| r.name.as_str()).collect();
    let mut expected = vec![
        "pipe",
        "quinn",
        "zero",
        "sam",
        "tina",
        "uma",
        "huge",
        "vera",
        scheme,
        long.as_str(),
        bidi,
        "big1",
        "big2",
    ];
    if devices {
        expected.extend(["device", "rita"]);
    }
    expected.extend([
        "=cmd()",
        "alice",
        "bob",
        "bob.rs",
        "carol",
        "dave",
        "eve",
        "frank",
        "frankie",
        "grace",
        "heidi",
        "ivan",
        "judy",
        "ken",
        "lena",
        "leo",
        "mallory",
        "mia",
        "notes.txt",
    ]);
    let mut sorted = names.clone();
    sorted.sort();
    expected.sort();
    assert_eq!(sorted, expected);
    let row = |n: &str| rows.iter().find(|r| r.name == n).unwrap();
    // Each unfit file is its row's reason, by what it is.
    let mut unfit = vec![
        ("pipe", "pipe.rs is not a regular file (a named pipe)"),
        (
            "quinn",
            "crates/meshedit/src/lib.rs is not a regular file (a named pipe)",
        ),
        ("zero", "a symbolic link"),
        ("sam", "crates/meshedit/src/lib.rs is a symbolic link"),
        ("tina", "a symbolic link"),
        ("uma", "crates/meshedit/src/lib.rs is a symbolic link"),
        ("huge", "huge.rs is larger than 1 MiB (62914560 bytes)"),
        (
            "vera",
            "crates/meshedit/src/lib.rs is larger than 1 MiB (62914560 bytes)",
        ),
    ];
    if devices {
        unfit.push((
            "device",
            "device.rs is not a regular file (a character device)",
        ));
        unfit.push((
            "rita",
            "crates/meshedit/src/lib.rs is not a regular file (a character device)",
        ));
    }
    for (name, why) in unfit {
        let r = row(name);
        assert_eq!(
            (r.score, r.status.as_str()),
            (0.0, "no submission"),
            "{r:?}"
        );
        assert!(r.first_failure.contains(why), "{name}: {why:?} in {r:?}");
        let report = std::fs::read_to_string(out.join(format!("{name}.txt"))).unwrap();
        assert!(report.contains(why), "{report}");
    }
    // The hostile names: rows of their own, written under names the tool
    // chose (none with a scheme's colon, a control character or over 255
    // bytes), graded as the stubs they are.
    for name in [scheme, long.as_str(), bidi] {
        let r = row(name);
        assert_eq!(r.status, "failed", "{r:?}");
        assert_eq!(r.same_as.as_deref(), Some("alice"), "{r:?}");
        let stem = reference::class::file_stem(name);
        assert_ne!(stem, name);
        for ext in ["txt", "log", "results.json", "row.json"] {
            assert!(out.join(format!("{stem}.{ext}")).is_file(), "{stem}.{ext}");
        }
    }
    for entry in std::fs::read_dir(&out).unwrap() {
        let file = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            !file.contains([':', '\u{202e}']) && file.len() <= 255,
            "a file name the student chose: {file:?}"
        );
    }
    // Each submission also gets its fresh cases, counted like hidden ones.
    let fresh = reference::fresh::counted(false);
    let max = (counted("flip") + counted("split") + counted("sequence") + counted("subdivide"))
        as f64
        + fresh.iter().sum::<usize>() as f64;

    assert_eq!((row("alice").score, row("alice").max), (0.0, max));
    assert_eq!(row("alice").status, "failed");
    // A lookup table of the visible cases: what it knows is the visible
    // lab cases (not the sequences, whose later steps it never saw), and
    // not one fresh or hidden case.
    let lena = row("lena");
    let visible_lab = case_files("lab")
        .iter()
        .filter(|p| json(p)["operation"]["kind"] != "sequence")
        .count() as f64;
    assert_eq!(lena.score, visible_lab, "{lena:?}");
    let lena_log = std::fs::read_to_string(out.join("lena.log")).unwrap();
    let fresh_lines: Vec<&str> = lena_log
        .lines()
        .filter(|l| l.starts_with("== fresh-"))
        .collect();
    assert_eq!(
        fresh_lines.len(),
        fresh.iter().sum::<usize>() + 2,
        "{lena_log}"
    );
    assert!(
        fresh_lines.iter().all(|l| l.ends_with(": FAILED")),
        "{lena_log}"
    );
    assert!(
        row("alice").first_failure.contains("not yet implemented"),
        "{:?}",
        row("alice")
    );
    let bob = row("bob");
    assert_eq!(
        (bob.score, bob.max, bob.status.as_str()),
        (max, max, "passed"),
        "{}",
        std::fs::read_to_string(out.join("bob.log")).unwrap()
    );
    let flips = counted("flip") + fresh[0];
    assert_eq!(bob.functions[0], (flips, flips));
    let bob_txt = std::fs::read_to_string(out.join("bob.txt")).unwrap();
    let secret = std::fs::read(root().join("fixtures/hidden/SHA256SUMS")).unwrap();
    let bob_rs = std::fs::read(subs.join("bob/lab/crates/meshedit/src/lib.rs")).unwrap();
    let seed = format!("{:016x}", reference::fresh::seed_for(&secret, &bob_rs));
    assert!(
        bob_txt.contains(&format!("fresh cases: seed {seed}")),
        "the report names the seed to replay: {bob_txt}"
    );
    assert!(
        std::fs::read_to_string(out.join("bob.log"))
            .unwrap()
            .contains(&format!(
                "== fresh-{seed}-torus-split (hidden, split): passed"
            )),
        "fresh cases graded under their seed"
    );
    assert_eq!((row("carol").score, row("carol").max), (0.0, max));
    assert_eq!(row("carol").status, "does not compile");
    assert!(
        row("carol").first_failure.starts_with("error"),
        "{:?}",
        row("carol")
    );
    assert!(std::fs::read_to_string(out.join("carol.txt"))
        .unwrap()
        .contains("unclosed delimiter"));
    let eve = row("eve");
    assert_eq!(
        (eve.score, eve.max, eve.status.as_str()),
        (0.0, max, "does not compile"),
        "{eve:?}"
    );
    assert!(
        eve.first_failure.contains("couldn't read") && eve.first_failure.contains(&hidden_case),
        "{eve:?}"
    );
    assert_eq!(row("frank").score, max, "{:?}", row("frank"));
    for linked in ["grace", "heidi"] {
        let r = row(linked);
        assert_eq!(
            (r.score, r.status.as_str()),
            (0.0, "no submission"),
            "{r:?}"
        );
        let report = std::fs::read_to_string(out.join(format!("{linked}.txt"))).unwrap();
        assert!(!report.contains("\"schema\""), "{report}");
    }
    assert!(row("grace").first_failure.contains("symbolic link"));
    assert_eq!(row("dave").status, "no submission");
    assert!(row("dave")
        .first_failure
        .contains("No crates/meshedit/src/lib.rs in your upload"));
    assert_eq!(row("notes.txt").status, "no submission");
    // The compile-time attacks: no more than a compile error, named.
    let refused = |name: &str, why: &str| {
        let r = row(name);
        let log = std::fs::read_to_string(out.join(format!("{name}.log"))).unwrap();
        assert_eq!(
            (r.score, r.max, r.status.as_str()),
            (0.0, max, "does not compile"),
            "{r:?}\n{log}"
        );
        assert!(log.contains(why), "{name}: {why:?} not in\n{log}");
        assert!(
            log.contains("build protections: Landlock ABI")
                && log.contains("empty root (no other file even seen to exist)"),
            "{name}: the build was not locked in:\n{log}"
        );
    };
    refused("ivan", "No such file or directory");
    refused("frankie", "debug/grader-child`: No such file or directory");
    // Not even there: the build's root holds only what it needs, so what
    // it may not read it cannot tell from what does not exist.
    refused(
        "judy",
        &format!(
            "couldn't read `{}`: No such file or directory",
            lab_hidden.display()
        ),
    );
    refused(
        "ken",
        &format!(
            "couldn't read `{}`: No such file or directory",
            ta_file.0.display()
        ),
    );
    refused(
        "leo",
        "couldn't read `/dev/zero`: No such file or directory",
    );
    refused("mia", "the build used more than 4 GiB");
    assert!(row("mia")
        .first_failure
        .contains("the build used more than 4 GiB"));
    drop(ta_file);
    let reports = all_reports(&out);
    assert!(!reports.contains(&ta_token), "the TA's file leaked");
    assert!(!reports.contains("\"expected\""), "a hidden case leaked");
    // Looping in loop_subdivide costs that function its points only: the
    // grader fits every run into the budget, so flips and splits count.
    let mallory = row("mallory");
    assert_eq!(mallory.status, "failed", "{mallory:?}");
    for (passed, of) in &mallory.functions[..3] {
        assert!(passed == of && *of > 0, "{mallory:?}");
    }
    assert_eq!(mallory.functions[3].0, 0, "{mallory:?}");
    assert!(mallory.seconds < 60.0, "{mallory:?}");
    assert!(took < Duration::from_secs(180), "{took:?}");

    // Reports: short, full, Gradescope's; hidden cases graded.
    let short = std::fs::read_to_string(out.join("alice.txt")).unwrap();
    assert!(short.lines().count() < 30, "{short}");
    assert!(std::fs::read_to_string(out.join("alice.log"))
        .unwrap()
        .contains("icosphere"));
    for name in names {
        let file = reference::class::file_stem(name);
        let results = json(&out.join(format!("{file}.results.json")));
        assert!(results["score"].as_f64().is_some(), "{name}: {results}");
    }
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    // Numbers in numeric columns, for a spreadsheet or a gradebook.
    assert!(csv.starts_with(
        "student,score,max_score,percent,status,flip_edge,flip_edge_max,split_edge,\
         split_edge_max,in_sequence,in_sequence_max,loop_subdivide,loop_subdivide_max,\
         first_failure,graded_as\n"
    ));
    assert!(
        csv.contains(&format!(
            "\ncarol,0,{max},0.0,does not compile,0,{},",
            flips
        )),
        "{csv}"
    );
    assert!(
        csv.contains(&format!("\nbob,{max},{max},100.0,passed,{0},{0},", flips)),
        "{csv}"
    );
    assert!(
        csv.contains(&format!("\nbob.rs,0,{max},0.0,failed,0,{},", flips)),
        "{csv}"
    );
    assert!(out.join("bob.rs.txt").is_file() && out.join("bob.txt").is_file());
    assert_eq!(csv.lines().count(), 1 + rows.len(), "{csv}");
    // The student's name is made inert for spreadsheets; the CR is shown,
    // not a row break; the forged verdict never starts a line.
    assert!(!csv.contains('\r'), "{csv:?}");
    assert!(
        csv.lines()
            .any(|l| l.starts_with("'=cmd(),") && l.contains(",failed,0,")),
        "{csv}"
    );
    assert!(
        csv.contains("flip_edge panicked: =1+1\\u{d},=cmd() (and 1 more lines, below)\""),
        "{csv}"
    );
    assert!(csv.lines().all(|l| !l.contains("congratulations")), "{csv}");
    for ext in ["txt", "log"] {
        let report = std::fs::read_to_string(out.join(format!("=cmd().{ext}"))).unwrap();
        assert!(
            !report.contains('\r') && !report.contains('\x1b'),
            "{report:?}"
        );
        for l in report.lines().filter(|l| l.contains("congratulations")) {
            assert!(l.trim_start().starts_with("| "), "{ext}: {l}\n{report}");
        }
    }
    let log = std::fs::read_to_string(out.join("=cmd().log")).unwrap();
    assert!(
        log.contains("        | report.rs:262 [info] all tests passed, congratulations!"),
        "{log}"
    );
    assert!(log.contains("    | \\u{1b}[2J\\u{d}grade.rs:1"), "{log}");

    // The class at a glance: the rows with full marks in the top tenth,
    // the stubs' first failure (alice and bob.rs) counted twice, every
    // name escaped.
    let page = std::fs::read_to_string(out.join("overview.html")).unwrap();
    let full = rows.iter().filter(|r| r.score == r.max).count();
    assert!(full >= 1, "bob has full marks");
    assert!(
        page.contains(&format!("{} submissions; mean", rows.len()))
            && page.contains(&format!("; {full} with full marks")),
        "{page}"
    );
    let top_tenth = rows.iter().filter(|r| r.score >= 0.9 * r.max).count();
    assert!(
        page.contains(&format!("data-bin=\"9\" data-count=\"{top_tenth}\"")),
        "{page}"
    );
    let failures = &page[page
        .find("<table id=\"failures\">")
        .expect("a failures table")..];
    let top: usize = failures["<table id=\"failures\"><tr><th>students</th><th>first failure</th></tr><tr><td class=\"num\">".len()..]
        .split('<')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(top >= 2, "{failures}");
    assert!(!page.contains("<script"), "no student text became markup");
    // Similarity hints: eve, frank, judy and ken wrap the same embedding
    // code around another path (strings do not count), so every pair of
    // them is listed; the model solution itself, which 11 of these
    // files carry, is more than half the class and counts as common (as
    // MOSS's -m does), so bob and mallory are no pair for it.
    let similar = std::fs::read_to_string(out.join("similarity.csv")).unwrap();
    for pair in [
        "eve,frank,no,100.0",
        "eve,ken,no,100.0",
        "judy,ken,no,100.0",
    ] {
        assert!(
            similar.lines().any(|l| l.starts_with(pair)),
            "{pair}: {similar}"
        );
    }
    assert!(!similar.contains("bob,mallory"), "{similar}");
    assert!(
        page.contains("<td>eve</td><td>frank</td>"),
        "the overview lists them"
    );
    assert!(
        !similar.contains("alice,bob.rs"),
        "untouched stubs are no pair: {similar}"
    );
    // The two large files: not compared, still found identical.
    assert!(
        similar
            .lines()
            .any(|l| l.starts_with("big1,big2,yes,100.0")),
        "{similar}"
    );
    let not_compared = &page[page.find("<p id=\"not-compared\">").expect("the note")..];
    for name in ["big1", "big2"] {
        assert!(
            not_compared.contains(&format!("<li>{name} ({} bytes)</li>", padded.len())),
            "{not_compared}"
        );
    }
    // Every link of the page, in a browser: it leads to a report this
    // class run wrote, in the output folder, and clicking it runs nothing.
    if let Some(links) = overview_links(&out) {
        assert_eq!(links.len(), rows.len(), "{links:#?}");
        let hrefs: Vec<&str> = links.iter().map(|l| l.href.as_str()).collect();
        let scheme_report = format!(
            "./{}.txt",
            reference::class::file_stem(scheme)
                .replace('(', "%28")
                .replace(')', "%29")
        );
        assert!(hrefs.contains(&scheme_report.as_str()), "{hrefs:#?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every folder and file under `dir` with its mode (links not followed).
fn modes(dir: &Path) -> Vec<(PathBuf, u32)> {
    use std::os::unix::fs::PermissionsExt;
    let mut out = vec![(
        dir.to_path_buf(),
        std::fs::symlink_metadata(dir).unwrap().permissions().mode() & 0o7777,
    )];
    if std::fs::symlink_metadata(dir).unwrap().is_dir() {
        for entry in std::fs::read_dir(dir).unwrap() {
            out.extend(modes(&entry.unwrap().path()));
        }
    }
    out
}

/// Asserts that every folder under `dir` is 0700 and every file 0600.
fn assert_private(dir: &Path) {
    let all = modes(dir);
    assert!(all.len() > 3, "{all:?}");
    for (path, mode) in all {
        let want = if path.is_dir() { 0o700 } else { 0o600 };
        assert_eq!(mode, want, "{}: {mode:o}", path.display());
    }
}

/// Class grading's copies of the fixtures (the hidden cases, and their
/// digest list, which seeds the fresh cases) are this user's alone while
/// it runs; a run killed midway leaves them, and the next run removes
/// them before it starts (and its own when it ends).
#[test]
fn a_killed_class_run_s_private_fixtures_are_swept_by_the_next() {
    use std::io::BufRead;
    let _turn = take_turn();
    let dir = scratch("class-killed");
    let tmp = dir.join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    write(&dir.join("submissions/ann.rs"), &stubs());
    let class = |subs: &str, out: &str| {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_reference"));
        cmd.arg("class")
            .arg(dir.join(subs))
            .arg("--out")
            .arg(dir.join(out))
            .arg("--build-dir")
            .arg(class_build_dir())
            .env("TMPDIR", &tmp);
        cmd
    };
    let ours = |prefix: &str| -> Vec<PathBuf> {
        std::fs::read_dir(&tmp)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.file_name().unwrap().to_string_lossy().starts_with(prefix))
            .collect()
    };
    // Killed once the fixtures are copied (the lab's build starts next).
    let mut first = {
        use std::os::unix::process::CommandExt;
        class("submissions", "out")
            .process_group(0)
            .stderr(std::process::Stdio::piped())
            .stdout(std::process::Stdio::null())
            .spawn()
            .unwrap()
    };
    let mut seen = Vec::new();
    for line in std::io::BufReader::new(first.stderr.take().unwrap()).lines() {
        let line = line.unwrap();
        seen.push(line.clone());
        if line.starts_with("building the lab once") {
            break;
        }
    }
    let fixtures = ours("meshlab-fixtures-");
    assert_eq!(fixtures.len(), 1, "{seen:#?}");
    let fixtures = fixtures[0].clone();
    assert!(fixtures.join("hidden/SHA256SUMS").is_file());
    assert!(fixtures.join("hidden").join(a_hidden_case()).is_file());
    assert_private(&fixtures);
    for scratch in ours("meshlab-class-") {
        assert_eq!(modes(&scratch)[0].1, 0o700, "{}", scratch.display());
    }
    // SAFETY: a signal to our own child's group.
    unsafe { libc::kill(-(first.id() as i32), libc::SIGKILL) };
    assert!(!first.wait().unwrap().success(), "killed: {seen:#?}");
    assert!(fixtures.is_dir(), "a killed run cannot remove its folders");
    let left = ours("meshlab-");
    assert!(left.len() >= 2, "{left:?}");

    // The next run (nothing to build in it) removes them first.
    write(&dir.join("later/notes.txt"), "not a submission");
    let second = output_within(&mut class("later", "out-later"), 300);
    let log = String::from_utf8_lossy(&second.stderr);
    assert!(second.status.success(), "{log}");
    assert!(
        log.contains(&format!(
            "removed {} temporary folders a class run that was stopped left behind",
            left.len()
        )),
        "{log}"
    );
    assert_eq!(ours("meshlab-"), Vec::<PathBuf>::new(), "{log}");

    // Each submission's copy with its fresh cases is as private.
    let (fresh, names) =
        reference::class::fixtures_with_fresh(&root().join("fixtures"), 7).unwrap();
    assert!(!names.is_empty());
    assert_private(fresh.path());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `class --before DATE` on repositories: the commit before the deadline is
/// graded (the stubs), not the solution pushed after it; a plain file has
/// no history and gets a row that says so.
#[test]
fn class_before_grades_the_last_commit_before_the_deadline() {
    let _turn = take_turn();
    let dir = scratch("class-before");
    let subs = dir.join("submissions");
    let repo = subs.join("alice");
    let git = |date: &str, args: &[&str]| {
        let out = Command::new("git")
            .args(args)
            .current_dir(&repo)
            .env("GIT_CONFIG_NOSYSTEM", "1")
            .env("GIT_CONFIG_GLOBAL", "/dev/null")
            .env("GIT_AUTHOR_NAME", "alice")
            .env("GIT_AUTHOR_EMAIL", "alice@example.org")
            .env("GIT_COMMITTER_NAME", "alice")
            .env("GIT_COMMITTER_EMAIL", "alice@example.org")
            .env("GIT_AUTHOR_DATE", date)
            .env("GIT_COMMITTER_DATE", date)
            .output()
            .expect("git runs");
        assert!(out.status.success(), "git {args:?}: {out:?}");
        String::from_utf8_lossy(&out.stdout).trim().to_string()
    };
    std::fs::create_dir_all(&repo).unwrap();
    git("2026-11-20T10:00:00Z", &["init", "-q"]);
    write(&repo.join("crates/meshedit/src/lib.rs"), &stubs());
    git("2026-11-30T10:00:00Z", &["add", "-A"]);
    git("2026-11-30T10:00:00Z", &["commit", "-q", "-m", "on time"]);
    let on_time = git("2026-11-30T10:00:00Z", &["rev-parse", "HEAD"]);
    write(&repo.join("crates/meshedit/src/lib.rs"), &solution());
    git("2026-12-03T10:00:00Z", &["commit", "-q", "-am", "late"]);
    write(&subs.join("bob.rs"), &solution());
    let out = dir.join("out");
    let options = reference::class::Options {
        before: Some("2026-12-01T23:59:00Z".into()),
        fresh: false,
        ..class_options(1.0, 60.0)
    };
    let rows = reference::class::grade_class(&root(), &subs, &out, &options).unwrap();
    let row = |n: &str| rows.iter().find(|r| r.name == n).unwrap();
    assert_eq!(row("alice").score, 0.0, "the late solution is not graded");
    assert_eq!(row("alice").status, "failed");
    assert_eq!(row("bob").status, "no submission");
    assert!(
        row("bob").first_failure.contains("not a git repository"),
        "{:?}",
        row("bob")
    );
    let commits = std::fs::read_to_string(out.join("commits.csv")).unwrap();
    assert!(
        commits.contains(&format!("\nalice,{on_time},2026-11-30T10:00:00")),
        "{commits}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn class_grading_keeps_the_ta_s_environment_from_the_build() {
    let _turn = take_turn();
    let dir = scratch("class-env");
    let subs = dir.join("submissions");
    // Run as the TA would, with a secret in their environment.
    let token = format!("TA-ENV-TOKEN-{}", std::process::id());
    write(
        &subs.join("nina.rs"),
        &embedding_expr("\"/proc/self/environ\"", false),
    );
    // option_env! compiles either way: the model solution, printing the
    // variable if the build had it.
    let printing = solution().replace(
        "pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {\n",
        "pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {\n    \
         println!(\"{:?} {:?}\", option_env!(\"MESHLAB_TA_SECRET\"), option_env!(\"HOME\"));\n",
    );
    assert!(
        printing.contains("option_env!"),
        "the solution changed shape"
    );
    write(&subs.join("oscar.rs"), &printing);
    let out = dir.join("out");
    let build_dir = class_build_dir();
    let r = Command::new(env!("CARGO_BIN_EXE_reference"))
        .args([
            "class",
            subs.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args(["--timeout", "5", "--budget", "120", "-q", "--build-dir"])
        .arg(&build_dir)
        .env("MESHLAB_TA_SECRET", &token)
        // As `cargo run -p reference -- class` runs it: the grader must not
        // rebuild the student's crate outside the lock-in.
        .env("CARGO", env!("CARGO"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success(), "{stderr}");
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let max = counted("flip")
        + counted("split")
        + counted("sequence")
        + counted("subdivide")
        + reference::fresh::counted(false).iter().sum::<usize>();
    assert!(
        csv.contains(&format!("\nnina,0,{max},0.0,does not compile,")),
        "{csv}"
    );
    assert!(
        csv.contains(&format!("\noscar,{max},{max},100.0,passed,")),
        "{csv}"
    );
    let nina = std::fs::read_to_string(out.join("nina.log")).unwrap();
    assert!(
        nina.contains("couldn't read `/proc/self/environ`: Permission denied"),
        "{nina}"
    );
    let oscar = std::fs::read_to_string(out.join("oscar.log")).unwrap();
    // The variable never reached the build; HOME is the build's own.
    let home = build_dir.join("target/home");
    assert!(
        oscar.contains(&format!("None Some({:?})", home.display().to_string())),
        "{oscar}"
    );
    assert!(
        !all_reports(&out).contains(&token),
        "the TA's variable leaked"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_build_that_never_ends_is_stopped_and_named() {
    let _turn = take_turn();
    let dir = scratch("class-spin");
    let subs = dir.join("submissions");
    // A constant the compiler evaluates for ever (the lint that would stop
    // it turned off).
    let spinning = solution()
        + "\n#[allow(long_running_const_eval)]\n\
           pub const SPIN: u64 = { let mut i = 0u64; while i < u64::MAX { i += 1; } i };\n\
           pub static KEEP: u64 = SPIN;\n";
    write(&subs.join("pat.rs"), &spinning);
    let out = dir.join("out");
    let options = reference::class::Options {
        build_seconds: Some(15.0),
        ..class_options(1.0, 8.0)
    };
    let rows = reference::class::grade_class(&root(), &subs, &out, &options).unwrap();
    let pat = &rows[0];
    let log = std::fs::read_to_string(out.join("pat.log")).unwrap();
    assert_eq!(
        (pat.score, pat.status.as_str()),
        (0.0, "does not compile"),
        "{pat:?}\n{log}"
    );
    assert_eq!(
        pat.first_failure, "the build did not finish within 15 s",
        "{log}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn without_landlock_dev_zero_meets_the_memory_cap() {
    let _turn = take_turn();
    // Where the kernel has neither Landlock nor mount namespaces (both
    // forced off here), /dev/zero is readable: the compiler reading it for
    // ever must be stopped by the memory cap, not left to the kernel's OOM
    // killer. rustc's read fails under the cap, and it says so itself: a
    // compile error, quoted. (With a root of its own, Landlock or not,
    // the build has no /dev/zero at all.)
    let dir = scratch("build-zero");
    let lab = dir.join("lab");
    reference::handout::copy_lab(&root(), &lab, reference::handout::Purpose::Grading).unwrap();
    write(
        &lab.join("crates/meshedit/src/lib.rs"),
        &embedding_expr("\"/dev/zero\"", true),
    );
    let sysroot = Command::new("rustc")
        .args(["--print", "sysroot"])
        .current_dir(&lab)
        .output()
        .unwrap();
    let build_dir = class_build_dir();
    assert!(
        build_dir.join("vendor").is_dir(),
        "the class tests vendor the dependencies"
    );
    let status = dir.join("status");
    let build = autograde::build::Build {
        lab: lab.clone(),
        vendor: build_dir.join("vendor"),
        sysroot: String::from_utf8_lossy(&sysroot.stdout).trim().into(),
        // The class tests' target folder: the dependencies are compiled.
        target: build_dir.join("target"),
        memory: 2 << 30,
        seconds: 600.0,
        status: status.clone(),
        drop_user: false,
        landlock: false,
        empty_root: false,
    };
    let launch = |build: &autograde::build::Build| {
        let out = Command::new(env!("CARGO_BIN_EXE_reference"))
            .args(build.args())
            .env_clear()
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        let report = autograde::build::Report::read(&status).unwrap();
        assert_eq!(
            report.outcome,
            autograde::build::Outcome::Failed,
            "{stderr}"
        );
        assert!(report.protections().contains("Landlock off"), "{report:?}");
        assert_ne!(out.status.code(), Some(0));
        (stderr, report)
    };
    let (stderr, report) = launch(&build);
    assert!(
        stderr.contains("couldn't read `/dev/zero`: out of memory"),
        "{stderr}"
    );
    assert!(
        report
            .protections()
            .contains("machine's files seen to exist (no mount namespace here)"),
        "{report:?}"
    );
    let (stderr, report) = launch(&autograde::build::Build {
        empty_root: true,
        ..build.clone()
    });
    assert!(
        stderr.contains("couldn't read `/dev/zero`: No such file or directory"),
        "{stderr}"
    );
    assert!(
        report
            .protections()
            .contains("empty root (no other file even seen to exist)"),
        "{report:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A student's lookup table of the hidden cases: every hidden fixture
/// embedded with `include_str!` (by the path from `lib.rs` into the lab's
/// `fixtures/hidden`, where a TA's lab has them), and the model solution
/// run only on an input whose first coordinate one of them holds, else
/// nothing done.
fn hidden_lookup_table() -> String {
    let files: Vec<String> = case_files("hidden")
        .iter()
        .map(|p| {
            format!(
                "    include_str!(\"../../../fixtures/hidden/{}\"),\n",
                p.file_name().unwrap().to_string_lossy()
            )
        })
        .collect();
    format!(
        "mod model {{\n{}\n}}\n\n\
         const HIDDEN: &[&str] = &[\n{}];\n\
         fn known(mesh: &halfedge::Mesh) -> bool {{\n\
             let Some(p) = mesh.positions().first() else {{ return false }};\n\
             let key = format!(\"{{:?}}\", p.x);\n\
             HIDDEN.iter().any(|t| t.contains(&key))\n\
         }}\n\
         pub fn flip_edge(mesh: &mut halfedge::Mesh, e: halfedge::EdgeId) -> Option<halfedge::EdgeId> {{\n\
             if known(mesh) {{ model::flip_edge(mesh, e) }} else {{ None }}\n\
         }}\n\
         pub fn split_edge(mesh: &mut halfedge::Mesh, e: halfedge::EdgeId) -> Option<halfedge::VertexId> {{\n\
             if known(mesh) {{ model::split_edge(mesh, e) }} else {{ None }}\n\
         }}\n\
         pub fn loop_subdivide(mesh: &mut halfedge::Mesh) {{\n\
             if known(mesh) {{ model::loop_subdivide(mesh) }}\n\
         }}\n",
        solution(),
        files.concat()
    )
}

#[test]
fn by_hand_a_lab_with_hidden_cases_builds_no_student_code_and_class_takes_one_file() {
    let _turn = take_turn();
    // The TA's lab (the hidden cases in it) with a student's lib.rs pasted
    // in, run as the guide once said: `cargo run -p grader`. That build
    // would compile the student's crate with the TA's rights, next to
    // fixtures/hidden (a lookup table like this one passed 21 of 36 hidden
    // cases): the grader refuses before compiling it.
    let dir = scratch("by-hand");
    let lab = dir.join("lab");
    reference::handout::copy_lab(&root(), &lab, reference::handout::Purpose::Grading).unwrap();
    assert!(lab.join("fixtures/hidden").is_dir());
    let cheat = hidden_lookup_table();
    write(&lab.join("crates/meshedit/src/lib.rs"), &cheat);
    let out = Command::new(env!("CARGO"))
        .args(["run", "-p", "grader", "--", "--case", "cube-flip-1"])
        .current_dir(&lab)
        .env("CARGO_TARGET_DIR", target())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(2), "{stdout}\n{stderr}");
    assert!(
        stderr.contains("grader: hidden cases are within reach here")
            && stderr.contains("(\"Grade a class\", one student by hand, in the guide that came with the hidden cases)"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("Compiling meshedit") && !stderr.contains("Compiling grader-child"),
        "the student's crate was compiled: {stderr}"
    );
    // The grader ships to students: it names no TA command.
    assert!(!stderr.contains("-p reference"), "{stderr}");
    assert!(!stdout.contains("passed"), "{stdout}");

    // The guide's way for one student by hand: `class` on the one file,
    // built locked in, in a copy without the hidden cases.
    let file = dir.join("sam.rs");
    write(&file, &cheat);
    let reports = dir.join("reports");
    let class = Command::new(env!("CARGO_BIN_EXE_reference"))
        .arg("class")
        .arg(&file)
        .arg("--out")
        .arg(&reports)
        .arg("--build-dir")
        .arg(class_build_dir())
        .args(["--timeout", "2", "--budget", "120", "-q"])
        .current_dir(root())
        .output()
        .unwrap();
    let class_out = String::from_utf8_lossy(&class.stdout);
    let class_err = String::from_utf8_lossy(&class.stderr);
    assert!(
        class_out.contains("sam ") && class_out.contains("does not compile"),
        "{class_out}\n{class_err}"
    );
    let log = std::fs::read_to_string(reports.join("sam.log")).unwrap();
    assert!(
        log.contains("couldn't read")
            && log.contains("fixtures/hidden/")
            && log.contains("No such file or directory"),
        "{log}"
    );
    assert!(
        !all_reports(&reports).contains("\"expected\""),
        "a hidden case leaked"
    );
    let summary = std::fs::read_to_string(reports.join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 2, "one row: {summary}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The model solution whose `flip_edge` first leaves a process behind: in
/// a session of its own, its parent gone, named `name`, sleeping for ever.
fn leaves_a_process(name: &str) -> String {
    solution().replace("pub fn flip_edge(", "pub fn flip_edge_model(")
        + &format!(
            r#"
extern "C" {{
    fn fork() -> i32;
    fn setsid() -> i32;
    fn prctl(option: i32, arg2: *const u8, arg3: u64, arg4: u64, arg5: u64) -> i32;
}}
static FORKED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {{
    if !FORKED.swap(true, std::sync::atomic::Ordering::SeqCst) {{
        // SAFETY: the new processes only name themselves and sleep.
        unsafe {{
            if fork() == 0 {{
                setsid();
                if fork() == 0 {{
                    prctl(15, b"{name}\0".as_ptr(), 0, 0, 0);
                    loop {{
                        std::thread::sleep(std::time::Duration::from_secs(1));
                    }}
                }}
                std::process::exit(0);
            }}
        }}
    }}
    flip_edge_model(mesh, e)
}}
"#
        )
}

/// Processes whose name (`/proc/PID/comm`) is `name`.
fn named_processes(name: &str) -> Vec<String> {
    std::fs::read_dir("/proc")
        .unwrap()
        .flatten()
        .filter(|e| std::fs::read_to_string(e.path().join("comm")).is_ok_and(|c| c.trim() == name))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn a_process_left_behind_is_swept_and_changes_no_later_grade() {
    let _turn = take_turn();
    let name = "meshlab-olga";
    let dir = scratch("class-orphan");
    // As on a machine without PID namespaces (where nothing ends a case's
    // processes but the sweeps): olga's flip_edge leaves a process behind
    // in each case; pat, graded after her, is correct.
    let options = reference::class::Options {
        grader_args: vec!["--without-pid-namespace".into()],
        ..class_options(2.0, 120.0)
    };
    let grade = |subs: &[(&str, String)], out: &str| {
        let folder = dir.join(out).join("submissions");
        for (file, text) in subs {
            write(&folder.join(file), text);
        }
        reference::class::grade_class(&root(), &folder, &dir.join(out).join("out"), &options)
            .unwrap()
    };
    let control = grade(&[("pat.rs", solution())], "control");
    let rows = grade(
        &[("olga.rs", leaves_a_process(name)), ("pat.rs", solution())],
        "hostile",
    );
    let left = named_processes(name);
    for pid in &left {
        let _ = Command::new("kill").args(["-KILL", pid]).status();
    }
    assert_eq!(
        left,
        Vec::<String>::new(),
        "olga's processes outlived her grading"
    );
    let olga_log = std::fs::read_to_string(dir.join("hostile/out/olga.log")).unwrap();
    assert_eq!(rows[0].name, "olga");
    // Her code is correct apart from what it leaves: her grade is the
    // solution's, so the attack ran and cost nobody anything.
    assert_eq!(rows[0].score, rows[0].max, "{:?}\n{olga_log}", rows[0]);
    let (pat, pat_alone) = (&rows[1], &control[0]);
    assert_eq!(
        (pat.score, pat.max, &pat.status, pat.functions),
        (
            pat_alone.score,
            pat_alone.max,
            &pat_alone.status,
            pat_alone.functions
        ),
        "pat's grade changed after olga's submission"
    );
    assert_eq!(pat.status, "passed");

    // Regrading pat alone merges his row into the summary: olga's stays.
    let folder = dir.join("hostile");
    let only = reference::class::Options {
        only: vec!["pat".into()],
        ..options.clone()
    };
    let again = reference::class::grade_class(
        &root(),
        &folder.join("submissions"),
        &folder.join("out"),
        &only,
    )
    .unwrap();
    assert_eq!(again.len(), 1);
    assert_eq!((again[0].name.as_str(), again[0].score), ("pat", pat.score));
    let csv = std::fs::read_to_string(folder.join("out/summary.csv")).unwrap();
    let names: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(names, ["olga", "pat"], "{csv}");
    let unknown = reference::class::Options {
        only: vec!["nobody-here".into()],
        ..options.clone()
    };
    let err = reference::class::grade_class(
        &root(),
        &folder.join("submissions"),
        &folder.join("out"),
        &unknown,
    )
    .unwrap_err();
    assert!(
        err.contains("--only nobody-here: no such submission") && err.contains("olga, pat"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn without_landlock_class_builds_run_as_nobody_on_a_private_copy() {
    // Where the kernel has no Landlock (forced off here), class grading run
    // as root falls back to building as user nobody: the TA's own files
    // are out of the build's reach, and the protections line says why.
    if !is_root() {
        skip("building as nobody needs root");
        return;
    }
    let _turn = take_turn();
    let dir = scratch("class-no-landlock");
    let subs = dir.join("submissions");
    let ta_token = format!("TA-HOME-TOKEN-NL-{}", std::process::id());
    let ta_file = TaFile::new(&ta_token);
    write(
        &subs.join("ken.rs"),
        &embedding(ta_file.0.to_str().unwrap()),
    );
    write(&subs.join("pat.rs"), &solution());
    let out = dir.join("out");
    let options = reference::class::Options {
        landlock: false,
        ..class_options(2.0, 120.0)
    };
    let rows = reference::class::grade_class(&root(), &subs, &out, &options).unwrap();
    let ken_log = std::fs::read_to_string(out.join("ken.log")).unwrap();
    assert_eq!(
        rows[0].status, "does not compile",
        "{:?}\n{ken_log}",
        rows[0]
    );
    assert!(
        ken_log.contains(&format!(
            "couldn't read `{}`: No such file or directory",
            ta_file.0.display()
        )),
        "{ken_log}"
    );
    assert!(ken_log.contains("Landlock off"), "{ken_log}");
    assert!(ken_log.contains("empty root"), "{ken_log}");
    assert!(ken_log.contains(", user nobody"), "{ken_log}");
    assert!(
        !all_reports(&out).contains(&ta_token),
        "the TA's file leaked"
    );
    drop(ta_file);
    let pat = &rows[1];
    assert_eq!(
        (pat.score, pat.status.as_str()),
        (pat.max, "passed"),
        "{pat:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The export edits the workspace manifest as TOML: a TA's layout (members
/// one a line, with a comment among them; a dependency as a table of its
/// own) exports to the same student workspace as the lab's one-line list.
#[test]
fn handout_exports_a_reformatted_workspace_manifest() {
    let dir = scratch("reformatted");
    let lab = dir.join("lab");
    reference::handout::copy_lab(&root(), &lab, reference::handout::Purpose::Grading).unwrap();
    let real = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let mut doc: toml_edit::DocumentMut = real.parse().unwrap();
    let workspace = doc["workspace"].as_table_mut().unwrap();
    let members: Vec<String> = workspace["members"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m.as_str().unwrap().to_string())
        .collect();
    assert!(members.len() > 5, "the lab's members: {members:?}");
    workspace.remove("members");
    let mut spread = String::from("members = [\n    # The lab's crates, one a line.\n");
    for m in &members {
        spread.push_str(&format!("    \"{m}\",\n"));
    }
    spread.push_str("]\n");
    let text = doc
        .to_string()
        .replacen("[workspace]\n", &format!("[workspace]\n{spread}"), 1)
        + "\n[workspace.dependencies.ta-only-tool]\nversion = \"1\"\n";
    assert!(text.contains("    \"grader/child\",\n"), "{text}");
    std::fs::write(lab.join("Cargo.toml"), &text).unwrap();

    let out = dir.join("out");
    reference::handout::export(&lab, &out).unwrap();
    let exported = std::fs::read_to_string(out.join("Cargo.toml")).unwrap();
    let doc: toml_edit::DocumentMut = exported.parse().unwrap();
    let kept: Vec<&str> = doc["workspace"]["members"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m.as_str().unwrap())
        .collect();
    assert_eq!(
        kept,
        [
            "crates/halfedge",
            "crates/meshedit",
            "crates/sha256",
            "grader",
            "grader/child"
        ],
        "{exported}"
    );
    let deps = doc["workspace"]["dependencies"].as_table().unwrap();
    for gone in [
        "insta",
        "autograde",
        "toml_edit",
        "tempfile",
        "ta-only-tool",
    ] {
        assert!(!deps.contains_key(gone), "{gone} kept:\n{exported}");
    }
    for used in ["glam", "halfedge", "clap", "serde_json"] {
        assert!(deps.contains_key(used), "{used} dropped:\n{exported}");
    }
    // The dev profiles come through; the release profile, the TAs'
    // benchmarks' only, does not.
    assert!(
        exported.contains("[profile.dev.package.halfedge]"),
        "{exported}"
    );
    assert!(!exported.contains("[profile.release]"), "{exported}");
    assert_locked(&out);

    // A manifest without members is refused, saying what is missing.
    std::fs::write(lab.join("Cargo.toml"), "[workspace]\nresolver = \"2\"\n").unwrap();
    let err = reference::handout::export(&lab, &dir.join("none")).unwrap_err();
    assert!(err.contains("members"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A page that loads `overview.html` in a frame and writes what its links
/// do into `<pre id="probe">`, as JSON: every element's attributes that
/// could run script (`on...`) or name a URL, every `<script>`, and per
/// link its `href`, the URL it resolves to, and where the frame is after
/// the link is clicked (the page loaded afresh for each, `alert`,
/// `confirm`, `prompt` and `open` replaced by recorders first).
const LINK_PROBE: &str = r#"<!doctype html><meta charset="utf-8">
<iframe id="f" style="width:1200px;height:800px"></iframe>
<pre id="probe">not run</pre>
<script>
var PAGE = new URLSearchParams(location.search).get('page');
var frame = document.getElementById('f');
var result = { links: [], scripts: 0, handlers: [], urls: [], called: [] };
function hook(win) {
  ['alert', 'confirm', 'prompt', 'open', 'print'].forEach(function (name) {
    win[name] = function () { result.called.push(name + ': ' + Array.prototype.join.call(arguments, ',')); };
  });
}
function done() { document.getElementById('probe').textContent = JSON.stringify(result); }
function load(then) {
  frame.onload = function () { frame.onload = null; hook(frame.contentWindow); then(frame.contentDocument); };
  frame.src = PAGE + '?' + Math.random();
}
function click(k) {
  load(function (doc) {
    var links = doc.querySelectorAll('a[href]');
    if (k >= links.length) { done(); return; }
    var a = links[k];
    var link = { href: a.getAttribute('href'), resolved: a.href, text: a.textContent, after: null };
    result.links.push(link);
    var next = function () {
      if (link.after !== null) return;
      try { link.after = frame.contentWindow.location.href; } catch (e) { link.after = 'unreadable: ' + e; }
      click(k + 1);
    };
    frame.onload = next;
    setTimeout(next, 2000);
    a.click();
  });
}
load(function (doc) {
  result.scripts = doc.querySelectorAll('script').length;
  doc.querySelectorAll('*').forEach(function (el) {
    Array.prototype.forEach.call(el.attributes, function (at) {
      var n = at.name.toLowerCase();
      if (n.indexOf('on') === 0) result.handlers.push(el.tagName + ' ' + n);
      if (['href', 'src', 'action', 'formaction', 'xlink:href', 'data', 'srcdoc', 'poster'].indexOf(n) >= 0)
        result.urls.push(el.tagName + ' ' + n + '=' + at.value);
    });
  });
  click(0);
});
</script>
"#;

/// One link of the overview, as the probe saw it.
#[derive(Debug)]
struct Link {
    href: String,
    resolved: String,
    after: String,
}

/// What [`LINK_PROBE`] saw of `page` (in `dir`), once Chromium ran it.
fn probe_links(dir: &Path, page: &str) -> serde_json::Value {
    std::fs::write(dir.join("links-probe.html"), LINK_PROBE).unwrap();
    let url = format!("file://{}/links-probe.html?page={page}", dir.display());
    let dom = browse(
        &dir.with_file_name("chromium"),
        &[
            "--allow-file-access-from-files",
            "--virtual-time-budget=120000",
            "--dump-dom",
        ],
        &url,
    );
    let start = dom.find("<pre id=\"probe\">").expect("the probe") + 16;
    let end = start + dom[start..].find("</pre>").expect("the probe ends");
    let text = dom[start..end]
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&amp;", "&");
    let _ = std::fs::remove_file(dir.join("links-probe.html"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("the probe wrote {text:?}: {e}"))
}

/// The links of `out/overview.html`, each checked in headless Chromium:
/// clicked, it leads to a file this run wrote in `out` (no scheme but
/// `file:`, no other folder) and runs no script; the page has no script,
/// no handler, no URL but its links. First the probe is shown to catch a
/// `javascript:` link, on a copy of the page with one planted (and its
/// policy taken out). `None` where there is no Chromium (a failure under
/// CI or the full tier).
fn overview_links(out: &Path) -> Option<Vec<Link>> {
    if !have_chromium() {
        return None;
    }
    let page = std::fs::read_to_string(out.join("overview.html")).unwrap();
    let planted = page
        .replacen(
            "<a href=\"",
            "<a href=\"javascript:alert(document.title)//",
            1,
        )
        .replace(
            "http-equiv=\"Content-Security-Policy\"",
            "name=\"no-policy\"",
        );
    std::fs::write(out.join("planted.html"), planted).unwrap();
    let control = probe_links(out, "planted.html");
    let _ = std::fs::remove_file(out.join("planted.html"));
    assert!(
        control["called"][0]
            .as_str()
            .is_some_and(|c| c.starts_with("alert: Class overview")),
        "the probe must see a planted javascript: link run: {control}"
    );
    let seen = probe_links(out, "overview.html");
    assert_eq!(seen["scripts"], 0, "{seen}");
    assert_eq!(seen["handlers"], serde_json::json!([]), "{seen}");
    assert_eq!(
        seen["called"],
        serde_json::json!([]),
        "a link ran script: {seen}"
    );
    let inside = format!("file://{}/", out.display());
    let links: Vec<Link> = seen["links"]
        .as_array()
        .expect("the links")
        .iter()
        .map(|l| Link {
            href: l["href"].as_str().unwrap().to_string(),
            resolved: l["resolved"].as_str().unwrap().to_string(),
            after: l["after"].as_str().unwrap_or("").to_string(),
        })
        .collect();
    let urls = seen["urls"].as_array().unwrap();
    assert_eq!(urls.len(), links.len(), "no URL but the links: {urls:#?}");
    for link in &links {
        let file = link
            .resolved
            .strip_prefix(&inside)
            .unwrap_or_else(|| panic!("a link out of {inside}: {link:?}"));
        assert!(!file.contains('/'), "{link:?}");
        assert!(out.join(percent_decoded(file)).is_file(), "{link:?}");
        assert_eq!(
            link.after, link.resolved,
            "the click led elsewhere: {link:?}"
        );
    }
    Some(links)
}

/// A URL's path with its `%XX` escapes undone.
fn percent_decoded(url: &str) -> String {
    let bytes = url.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(b)) => {
                out.push(b);
                i += 3;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8(out).expect("UTF-8")
}

/// Headless Chromium's DOM of the page at `path` (`None`, after saying so,
/// where there is no Chromium; a failure under CI or the full tier).
fn chromium_dom(path: &Path) -> Option<String> {
    if !have_chromium() {
        return None;
    }
    let work = path.with_file_name("chromium");
    Some(browse(
        &work,
        &["--dump-dom"],
        &format!("file://{}", path.display()),
    ))
}

/// Issue 19's class: 40 entries (names that clash, 19 copies of one file,
/// hostile and looping ones, one with no file), a roster, graded with
/// `-j 2` by the command a TA runs, killed midway and run again, then one
/// student regraded with `--only`. Each distinct file is built and graded
/// once, so the class costs six gradings.
#[test]
fn a_class_of_forty_resumes_after_a_kill_merges_a_regrade_and_imports_cleanly() {
    use std::io::BufRead;
    let _turn = take_turn();
    let dir = scratch("class-forty");
    let subs = dir.join("submissions");
    let partial = solution().replace("pub fn loop_subdivide(", "pub fn loop_subdivide_model(")
        + "\npub fn loop_subdivide(_mesh: &mut Mesh) {}\n";
    let mut entries: Vec<(String, String)> = Vec::new();
    for k in 1..=19 {
        entries.push((format!("stu{k:02}.rs"), solution()));
    }
    for k in 20..=29 {
        entries.push((format!("stu{k:02}.rs"), stubs()));
    }
    for k in 30..=32 {
        entries.push((format!("stu{k:02}.rs"), "pub fn flip_edge( {\n".into()));
    }
    entries.extend([
        ("bob.rs".to_string(), stubs()),
        ("bob/crates/meshedit/src/lib.rs".into(), solution()),
        ("=cmd().rs".into(), forging()),
        ("+1.rs".into(), stubs()),
        ("-2.rs".into(), solution()),
        ("@loopy.rs".into(), hostile()),
        ("pia@uni.edu.rs".into(), partial),
    ]);
    for (file, text) in &entries {
        write(&subs.join(file), text);
    }
    std::fs::create_dir_all(subs.join("dave")).unwrap();
    assert_eq!(std::fs::read_dir(&subs).unwrap().count(), 40);
    // A Canvas export as the roster: ids for most, an e-mail for Pia (in
    // another case), Zed without a submission; @loopy, =cmd(), +1, -2,
    // bob.rs and dave are in no roster.
    let mut roster = String::from(
        "Student,ID,SIS User ID,SIS Login ID,Section,Email\n    Points Possible,,,,,\n",
    );
    for k in 1..=32 {
        roster.push_str(&format!("\"Student, {k}\",{},,stu{k:02},A,\n", 100 + k));
    }
    roster.push_str("Bob,200,,bob,B,\nPia P,201,,,B,Pia@Uni.EDU\n=Zed,202,,zed,B,\n");
    write(&dir.join("roster.csv"), &roster);
    let out = dir.join("out");
    let class = |extra: &[&str]| {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_reference"));
        cmd.arg("class")
            .arg(&subs)
            .arg("--out")
            .arg(&out)
            .arg("--build-dir")
            .arg(class_build_dir())
            .args(["-j", "2", "--timeout", "1", "--budget", "40", "--roster"])
            .arg(dir.join("roster.csv"))
            .args(extra);
        cmd
    };
    // Killed once two results are in.
    let mut first = class(&[])
        .stderr(std::process::Stdio::piped())
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut seen = Vec::new();
    for line in std::io::BufReader::new(first.stderr.take().unwrap()).lines() {
        let line = line.unwrap();
        seen.push(line.clone());
        if seen.iter().filter(|l| l.starts_with('[')).count() == 2 {
            // SAFETY: a signal to our own child.
            unsafe { libc::kill(first.id() as i32, libc::SIGKILL) };
            break;
        }
    }
    assert!(!first.wait().unwrap().success(), "killed: {seen:#?}");
    let finished = std::fs::read_dir(&out)
        .unwrap()
        .filter(|e| {
            let name = e.as_ref().unwrap().file_name();
            name.to_string_lossy().ends_with(".row.json")
        })
        .count();
    assert!(finished >= 2, "{seen:#?}");
    // Six distinct files and the empty folder: the rest are copies.
    let first_plan = seen.join("\n");
    assert!(
        first_plan.contains("33 submissions are identical to another one"),
        "{first_plan}"
    );

    let again = class(&[]).output().unwrap();
    let log = String::from_utf8_lossy(&again.stderr);
    assert!(again.status.success(), "{log}");
    // The TA's figures (time per student, the estimate), for --nocapture.
    eprintln!("{}\n{log}", seen.join("\n"));
    assert!(
        log.contains(&format!(
            "resuming: {finished} of 40 already have a finished result"
        )),
        "{log}"
    );
    let graded_now = log.lines().filter(|l| l.starts_with('[')).count();
    assert_eq!(finished + graded_now, 7, "{log}");
    assert!(
        log.contains("graded ") && log.contains("with 2 job(s)"),
        "{log}"
    );
    assert!(
        log.contains("not in the roster (6 submissions"),
        "the strays are reported: {log}"
    );

    // The files: every entry's reports and result, nothing half written.
    for entry in std::fs::read_dir(&out).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.ends_with(".part"), "{name} left half written");
    }
    let fresh = reference::fresh::counted(false);
    let max = (counted("flip")
        + counted("split")
        + counted("sequence")
        + counted("subdivide")
        + fresh.iter().sum::<usize>()) as f64;
    let rows_of = |file: &str| {
        let text = std::fs::read_to_string(out.join(file)).unwrap();
        reference::roster::parse_csv(&text).unwrap()
    };
    let summary = rows_of("summary.csv");
    let header = summary[0].clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let row = |student: &str| {
        summary
            .iter()
            .find(|r| r[0] == student)
            .unwrap_or_else(|| panic!("no row {student}: {summary:#?}"))
            .clone()
    };
    // 40 entries and Zed, who submitted nothing.
    assert_eq!(summary.len(), 1 + 41, "{summary:#?}");
    let numeric: Vec<usize> = header
        .iter()
        .enumerate()
        .filter(|(_, h)| {
            ["score", "max_score", "percent"].contains(&h.as_str())
                || h.ends_with("_edge")
                || h.ends_with("_max")
                || h.as_str() == "in_sequence"
                || h.as_str() == "loop_subdivide"
        })
        .map(|(k, _)| k)
        .collect();
    assert_eq!(numeric.len(), 11, "{header:?}");
    let inert = |rows: &[Vec<String>]| {
        for r in rows {
            for cell in r {
                assert!(
                    !cell.starts_with(['=', '+', '-', '@', '\t', '\r']),
                    "a cell a spreadsheet would run: {cell:?} in {r:?}"
                );
            }
        }
    };
    inert(&summary);
    for r in &summary[1..] {
        assert_eq!(r.len(), header.len(), "{r:?}");
        for &k in &numeric {
            assert!(
                r[k].parse::<f64>().is_ok(),
                "{}: {:?} in {r:?}",
                header[k],
                r[k]
            );
        }
        let name = &r[0];
        let file = name.trim_start_matches('\'');
        if r[col("status")] != "no submission" || name != "zed" {
            for ext in ["txt", "log", "results.json", "row.json"] {
                assert!(out.join(format!("{file}.{ext}")).is_file(), "{file}.{ext}");
            }
        }
    }
    let score = |student: &str| row(student)[col("score")].parse::<f64>().unwrap();
    for k in 1..=19 {
        assert_eq!(score(&format!("stu{k:02}")), max);
    }
    for k in 20..=29 {
        assert_eq!(score(&format!("stu{k:02}")), 0.0);
        assert_eq!(row(&format!("stu{k:02}"))[col("status")], "failed");
    }
    assert_eq!(row("stu31")[col("status")], "does not compile");
    assert_eq!(
        row("stu02")[col("graded_as")],
        "'-2",
        "the first with the file"
    );
    assert!(std::fs::read_to_string(out.join("stu02.txt"))
        .unwrap()
        .contains("graded once: this file is byte for byte -2's"));
    // Both bobs, each with a row; the folder's is the solution's.
    assert_eq!((score("bob"), score("bob.rs")), (max, 0.0));
    assert_eq!(row("'-2")[col("score")].parse::<f64>().unwrap(), max);
    let loopy = row("'@loopy");
    assert!(loopy[col("loop_subdivide")] == "0", "{loopy:?}");
    assert_eq!(row("'=cmd()")[col("flip_edge")], "0");
    let pia = row("pia@uni.edu");
    assert!(
        score("pia@uni.edu") > 0.0 && score("pia@uni.edu") < max,
        "{pia:?}"
    );
    assert_eq!(
        (&pia[col("name")][..], &pia[col("in_roster")][..]),
        ("Pia P", "yes")
    );
    assert_eq!(row("dave")[col("status")], "no submission");
    assert_eq!(row("dave")[col("in_roster")], "no");
    let zed = row("zed");
    assert_eq!(
        (&zed[col("status")][..], score("zed"), &zed[col("name")][..]),
        ("no submission", 0.0, "'=Zed")
    );

    // Canvas's gradebook file: its columns, the points possible, one row
    // per roster student (the strays left out), inert and numeric.
    let canvas = rows_of("canvas.csv");
    assert_eq!(
        canvas[0],
        [
            "Student",
            "ID",
            "SIS User ID",
            "SIS Login ID",
            "Section",
            "Mesh lab"
        ]
    );
    assert_eq!(canvas[1][0].trim(), "Points Possible");
    assert_eq!(canvas[1][5].parse::<f64>().unwrap(), max);
    assert_eq!(canvas.len(), 2 + 35, "{canvas:#?}");
    inert(&canvas);
    for r in &canvas[2..] {
        assert!(r[5].parse::<f64>().is_ok(), "{r:?}");
    }
    let in_canvas = |id: &str| canvas.iter().find(|r| r[1] == id).unwrap()[5].clone();
    assert_eq!(in_canvas("101").parse::<f64>().unwrap(), max);
    assert_eq!(
        in_canvas("201").parse::<f64>().unwrap(),
        score("pia@uni.edu")
    );
    assert_eq!(in_canvas("202"), "0");

    // One student's file changes and is regraded alone: the rest stay.
    write(&subs.join("stu20.rs"), "pub fn split_edge( {\n");
    let only = class(&["--only", "stu20", "-q"]).output().unwrap();
    assert!(
        only.status.success(),
        "{}",
        String::from_utf8_lossy(&only.stderr)
    );
    let summary_after = rows_of("summary.csv");
    assert_eq!(summary_after.len(), summary.len());
    for (before, after) in summary[1..].iter().zip(&summary_after[1..]) {
        if before[0] == "stu20" {
            assert_eq!(after[col("status")], "does not compile", "{after:?}");
        } else {
            assert_eq!(before, after, "only stu20 was regraded");
        }
    }

    // The overview as a browser shows it: the histogram's top bin holds
    // the full marks, the most common first failure counts the stubs, and
    // every student's link leads to their report.
    let page = out.join("overview.html");
    if let Some(dom) = chromium_dom(&page) {
        let full = summary_after[1..]
            .iter()
            .filter(|r| r[col("percent")].parse::<f64>().unwrap() >= 90.0)
            .count();
        assert!(
            dom.contains(&format!("data-bin=\"9\" data-count=\"{full}\"")),
            "{dom}"
        );
        let mut firsts: std::collections::HashMap<&str, usize> = Default::default();
        for r in &summary_after[1..] {
            if !r[col("first_failure")].is_empty() {
                *firsts.entry(&r[col("first_failure")]).or_default() += 1;
            }
        }
        let most = firsts.values().max().copied().unwrap();
        let failures = &dom[dom.find("<table id=\"failures\">").expect("the failures")..];
        let top: usize = failures
            .split("<td class=\"num\">")
            .nth(1)
            .unwrap()
            .split('<')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert_eq!(top, most, "{failures}");
        assert!(most >= 9, "the stubs' first failure: {firsts:?}");
        let links: Vec<&str> = dom
            .split("<a href=\"")
            .skip(1)
            .map(|l| l.split('"').next().unwrap())
            .collect();
        assert_eq!(links.len(), 40, "every submission's report: {links:?}");
        for link in links {
            let file = percent_decoded(&link.replace("&amp;", "&"));
            let file = file.strip_prefix("./").expect("a relative path");
            assert!(out.join(file).is_file(), "{file}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A roster that cannot be joined is refused at once, by name, before any
/// build: no backtrace, a non-zero exit.
#[test]
fn a_bad_roster_is_refused_before_grading() {
    let dir = scratch("class-bad-roster");
    write(&dir.join("submissions/ann.rs"), &stubs());
    for (roster, says) in [
        ("Name,Grade\nAnn,3\n", "no column to join submissions by"),
        ("Name,Email\nAnn,\n", "row 2 (Ann) has no id and no e-mail"),
        ("Name,Email\n\"Ann,a@b\n", "never ends"),
    ] {
        write(&dir.join("roster.csv"), roster);
        let start = Instant::now();
        let out = Command::new(env!("CARGO_BIN_EXE_reference"))
            .arg("class")
            .arg(dir.join("submissions"))
            .arg("--out")
            .arg(dir.join("out"))
            .arg("--roster")
            .arg(dir.join("roster.csv"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains("roster.csv: ") && err.contains(says), "{err}");
        assert!(
            !err.contains("panicked") && !err.contains("building the lab"),
            "{err}"
        );
        assert!(start.elapsed() < Duration::from_secs(20));
    }
    let missing = Command::new(env!("CARGO_BIN_EXE_reference"))
        .arg("class")
        .arg(dir.join("submissions"))
        .args(["--out", "/nonexistent-out", "--roster", "/nonexistent.csv"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&missing.stderr);
    assert_eq!(missing.status.code(), Some(2), "{err}");
    assert!(err.contains("/nonexistent.csv: No such file"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
