//! The grader, fed the catalogue of implementations through the real
//! binary (child processes and all): it accepts the correct ones and
//! rejects each wrong one with its message and hint. Transcripts are insta
//! snapshots, so any change of wording is a reviewed change.

use std::process::Command;

mod common;
use common::grade;

/// Drops the `file.rs:LINE ` prefix of log lines and the line and column
/// of panic locations, which move whenever code is edited, and the
/// protections line, which depends on the machine (its own test checks it).
fn normalize(text: &str) -> String {
    text.lines()
        .filter(|line| !line.contains("[info] protections: "))
        .map(|line| {
            let line = match line.split_once(' ') {
                Some((loc, rest)) if loc.contains(".rs:") && !line.starts_with(' ') => {
                    rest.to_string()
                }
                _ => line.to_string(),
            };
            match line.trim_start().strip_prefix("at ") {
                Some(place) if place.contains(".rs:") => {
                    let file = place.split(".rs:").next().unwrap_or(place);
                    format!("        at {file}.rs:LINE:COL")
                }
                _ => line,
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn correct_implementations_pass_every_case() {
    for name in ["reference", "alt-order", "alt-reverse"] {
        let g = grade(name, &["--bonus"]);
        assert_eq!(g.code, 0, "{name}:\n{}{}", g.stdout, g.stderr);
        assert!(!g.stdout.contains("[warn]"), "{name}:\n{}", g.stdout);
        let last = g.stdout.lines().last().unwrap_or("");
        assert!(
            last.ends_with("[info] all tests passed, congratulations!"),
            "{name}: {last}"
        );
    }
}

/// A flip or split that is right alone but breaks the mesh after an
/// earlier split passes every single-operation case and fails only the
/// sequence stage, every sequence case of it.
#[test]
fn faults_that_need_an_earlier_operation_fail_only_the_sequence_stage() {
    let sequences = common::counted("sequence");
    assert!(sequences >= 4, "a sequence case per lab object");
    for name in ["split-after-split", "flip-after-split"] {
        for stage in ["flip", "split", "subdivide"] {
            let g = grade(name, &["--stage", stage]);
            assert_eq!(g.code, 0, "{name} --stage {stage}:\n{}", g.stdout);
        }
        let g = grade(name, &["--stage", "sequence"]);
        assert_eq!(g.code, 1, "{name}:\n{}", g.stdout);
        let failed = g
            .stdout
            .lines()
            .filter(|l| l.contains("[warn] after ") && l.contains(" left an invalid mesh: "))
            .count();
        assert_eq!(
            failed, sequences,
            "{name}: every sequence fails\n{}",
            g.stdout
        );
        assert!(
            g.stdout.contains(&format!("in sequence 0/{sequences}")),
            "{name}:\n{}",
            g.stdout
        );
    }
}

/// (implementation, case, the warning it must get, a detail or hint it must get)
const WRONG: &[(&str, &str, &str, Option<&str>)] = &[
    ("stubs", "cube-flip-1", "flip_edge panicked: not yet implemented", Some("the function is still a todo!() stub")),
    ("stubs", "cube-split", "split_edge panicked: not yet implemented", None),
    ("stubs", "cube-subdivide-1", "loop_subdivide panicked: not yet implemented", None),
    ("flip-none", "cube-flip-1", "flip_edge returned None for an edge between two triangles: it must flip it", None),
    ("flip-wrong-return", "cube-flip-1", "but it must return the edge it was given", None),
    ("flip-stale-vertex", "cube-flip-1", "the result of flip_edge is a invalid mesh: A vertex's halfedge does not point to that vertex!", None),
    ("flip-stale-face", "cube-flip-2", "the result of flip_edge is a invalid mesh: A face's halfedge does not point to that face!", None),
    ("flip-face-labels", "cube-flip-1", "the result of flip_edge is a invalid mesh: A halfedge does not point to its face!", None),
    ("flip-boundary", "open-octahedron-flip", "flip_edge changed a boundary edge: it must return None and leave the mesh unchanged", None),
    ("flip-index-panic", "cube-flip-1", "flip_edge panicked: index out of bounds", Some("reference/src/catalogue/mistakes.rs")),
    // A panic inside the mesh library is placed at the line that called it.
    ("flip-unset-link", "cube-flip-1", "flip_edge panicked: there is no halfedge h-none", Some("at reference/src/catalogue/mistakes.rs:")),
    ("split-not-midpoint", "cube-split", "split vertex is not at the midpoint of the edge", Some("the midpoint is")),
    ("split-vertex-across", "cube-split", "the new vertex's halfedge does not run along the split edge", Some("must lead to vertex")),
    ("split-none", "cube-split", "split_edge returned None for an edge between two triangles: it must split it", None),
    ("split-refuses-boundary", "grid-split-boundary", "split_edge returned None for a boundary edge", None),
    ("split-stale-vertex", "torus-subdivide-2", "the result of subdivision is a invalid mesh: A vertex's halfedge does not point to that vertex!", None),
    ("loop-weights", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: the old vertices moved with Loop's original weight")),
    ("n3-rule", "cone-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: vertices with 3 neighbours moved with u = 3/(8n)")),
    ("old-not-moved", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: the old vertices did not move")),
    ("plain-midpoints", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: the new vertices sit at edge midpoints")),
    ("moved-first", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: the new vertices were computed from old vertices that had already moved")),
    ("no-flip", "cube-subdivide-1", "at least one of the edges connects incorrect vertices", Some("hint: no edge was flipped")),
    ("flip-all-new", "cube-subdivide-1", "the result of subdivision is a invalid mesh: Two edges join the same pair of vertices!", Some("hint: edges joining two new vertices were flipped too")),
    ("flip-halves", "cube-subdivide-1", "the result of subdivision is a invalid mesh:", Some("hint: halves of the old edges were flipped too")),
    ("new-at-origin", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: the new vertices ended at the origin")),
    ("in-place", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: the old vertices were moved while their new positions were still being computed")),
    ("in-place-vertices-first", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: the old vertices were moved inside the vertex loop")),
    ("swapped-edge-weights", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: the edge rule's weights are swapped")),
    ("edge-points-while-splitting", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: the new vertices were placed while splitting")),
    ("neighbour-skipped", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: the walk around each old vertex missed one neighbour")),
    ("wrong-corner", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("also what the far corners read one step short give")),
    ("integer-u", "cone-subdivide-1", "at least one of the vertices has incorrect position", Some("hint: u came out 0 for vertices with n other than 3")),
    ("integer-u", "cube-subdivide-1", "at least one of the vertices has incorrect position", Some("as 3 / (8 * n) does in integers")),
    ("flip-all-new-checked", "cube-subdivide-1", "at least one of the edges connects incorrect vertices", Some("hint: edges joining two new vertices were flipped too")),
    ("flip-halves-checked", "cube-subdivide-1", "at least one of the edges connects incorrect vertices", Some("hint: halves of the old edges were flipped too")),
    ("stale-flags", "cube-subdivide-2", "at least one of the edges connects incorrect vertices", Some("hint: the second round went wrong: reset is_new")),
    ("split-returns-old", "cube-split", "split_edge returned v2, a vertex that was there before the split: it must return the new vertex", None),
    ("split-new-again", "cube-subdivide-1", "loop_subdivide panicked: the mesh grew past", Some("hint: are edges created while splitting split again?")),
    ("endless", "cube-subdivide-1", "loop_subdivide did not finish within 1 s", Some("an endless loop?")),
    ("recursion", "cube-subdivide-1", "loop_subdivide overflowed the stack", Some("calls itself without end")),
    ("abort", "cube-subdivide-1", "loop_subdivide crashed: signal 6 (SIGABRT: the program aborted)", None),
    ("exit", "cube-subdivide-1", "loop_subdivide ended the program (exit status 0) before returning", Some("std::process::exit")),
    ("fake-verdict", "cube-subdivide-1", "at least one of the edges connects incorrect vertices", Some("    | grade.rs:1 [info] all tests passed, congratulations!")),
    // Order-dependent bugs: right on the mesh as built, wrong on another labelling.
    ("split-stale-vertex", "cube-split", "the result of split_edge is a invalid mesh: A vertex's halfedge does not point to that vertex!", Some("does split_edge update mesh[a].halfedge and mesh[b].halfedge")),
    ("split-stale-faces", "cube-split", "the result of split_edge is a invalid mesh: A face's halfedge does not point to that face!", Some("does split_edge reset mesh[f].halfedge")),
    ("split-assumes-inside", "grid-split-boundary", "split_edge returned None for a boundary edge", Some("does split_edge work when mesh[e].halfedge lies in the hole?")),
    // Right alone, wrong after an earlier operation: the sequence stage names the step.
    ("split-after-split", "cube-sequence", "after 2 operations (seed 1085576334), split_edge on edge 2-7 left an invalid mesh: A vertex's halfedge does not point to that vertex!", Some("it passes alone? Then it relies on something the earlier operations changed")),
    ("flip-after-split", "torus-sequence", "after 1 operation (seed 2931656512), flip_edge on edge 40-41 left an invalid mesh: A vertex's halfedge does not point to that vertex!", Some("it passes alone?")),
    ("stubs", "cube-sequence", "flip_edge panicked: not yet implemented", Some("after 0 operations (seed 1085576334), flip_edge on edge 2-0 (step 1 of 14)")),
    // The contract's refusals.
    ("flip-any-face", "quad-box-flip", "flip_edge changed an edge beside a face that is not a triangle: it must return None and leave the mesh unchanged", None),
    ("subdivide-skips-quads", "quad-box-subdivide-1", "loop_subdivide returned, but the mesh has a face that is not a triangle: it must panic with a message that says so", None),
    ("flip-index-panic", "pentagon-pyramid-flip", "flip_edge panicked: index out of bounds", None),
    ("flip-duplicates", "tetrahedron-flip", "flip_edge changed an edge whose flip would join two vertices already joined by an edge: it must return None and leave the mesh unchanged", None),
    // Faults named for what they are.
    ("nan-position", "cube-subdivide-1", "the result of subdivision is a invalid mesh: vertex v13 is at (0.375, NaN, -0.125): a position must be a finite number", None),
    ("forge-frames", "cube-subdivide-1", "number of vertices is wrong: 8 (should be 26)", None),
    ("replace-and-grow", "cube-subdivide-1", "loop_subdivide panicked: the mesh grew past 10000 elements", None),
];

#[test]
fn each_wrong_implementation_gets_its_message() {
    let mut distinct = std::collections::BTreeSet::new();
    for &(name, case, warning, detail) in WRONG {
        let g = grade(name, &["--case", case, "--timeout", "1"]);
        let transcript = normalize(&g.stdout);
        let context = format!(
            "{name} on {case}:\n{}\n--- stderr ---\n{}",
            g.stdout, g.stderr
        );
        assert_eq!(g.code, 1, "{context}");
        assert!(
            transcript
                .lines()
                .any(|l| l.starts_with("[warn] ") && l.contains(warning)),
            "expected warning {warning:?}\n{context}"
        );
        if let Some(detail) = detail {
            assert!(g.stdout.contains(detail), "expected {detail:?}\n{context}");
            // A hint is also in the last lines, where students read.
            if let Some(hint) = detail.strip_prefix("hint: ") {
                let tail: Vec<&str> = g.stdout.lines().rev().take(6).collect();
                assert!(
                    tail.iter()
                        .any(|l| l.contains("[info] hint for ") && l.contains(hint)),
                    "the hint is not in the last lines:\n{context}"
                );
            }
        }
        assert_eq!(
            transcript.lines().last(),
            Some("[warn] test failed"),
            "{context}"
        );
        for leak in [
            "stack backtrace",
            "panicked at",
            "RUST_BACKTRACE",
            "note: run with",
        ] {
            assert!(
                !g.stdout.contains(leak) && !g.stderr.contains(leak),
                "{leak:?} leaked\n{context}"
            );
        }
        distinct.insert(name);
        insta::assert_snapshot!(format!("{name}__{case}"), transcript);
    }
    assert!(
        distinct.len() > 15,
        "at least fifteen wrong implementations"
    );
}

/// The bonus split cases, as (name, whether its edge is on a hole),
/// sorted by name as the grader runs them.
fn bonus_splits() -> Vec<(String, bool)> {
    let mut out: Vec<(String, bool)> = common::case_files("bonus")
        .iter()
        .map(|p| grader::judge::fixture::load(p).unwrap())
        .filter_map(|f| match f.operation {
            grader::judge::fixture::Operation::Split { edge } => {
                let mesh = f.input.to_mesh().unwrap();
                let facts = reference::local::facts(&mesh, edge).unwrap();
                Some((f.name, facts.sides.iter().any(|s| s.is_hole())))
            }
            _ => None,
        })
        .collect();
    out.sort();
    out
}

#[test]
fn bonus_cases_count_only_when_asked() {
    // Refusing to split boundary edges fails only the bonus cases beside
    // a hole.
    let bonus = bonus_splits();
    let beside_hole: Vec<&str> = bonus.iter().filter(|b| b.1).map(|b| b.0.as_str()).collect();
    assert!(
        beside_hole.len() >= 2 && beside_hole.len() < bonus.len(),
        "{bonus:?}"
    );
    let quiet = grade("split-refuses-boundary", &["--stage", "split"]);
    assert_eq!(quiet.code, 0, "{}", quiet.stdout);
    // Uncounted bonus cases collapse to one line; -v shows them.
    let line = format!(
        "bonus cases: meshes with boundary (not counted: {} of {} passed; --bonus to count them, -v to see them)",
        bonus.len() - beside_hole.len(),
        bonus.len()
    );
    assert!(quiet.stdout.contains(&line), "{line}\n{}", quiet.stdout);
    assert!(!quiet.stdout.contains("[warn]"), "{}", quiet.stdout);
    // A partial run says what it graded, never the lab's congratulations.
    let last = quiet.stdout.lines().last().unwrap_or("");
    let done = format!(
        "[info] --stage split: all {} counted cases passed; run `cargo run -p grader` without it for the whole lab",
        common::counted("split")
    );
    assert!(last.ends_with(&done), "{last}");
    let verbose = grade("split-refuses-boundary", &["--stage", "split", "-v"]);
    assert!(verbose
        .stdout
        .contains("[warn] split_edge returned None for a boundary edge"));
    let counted = grade("split-refuses-boundary", &["--stage", "split", "--bonus"]);
    assert_eq!(counted.code, 1);
    let tail: Vec<&str> = counted.stdout.lines().rev().take(3).collect();
    assert!(tail[0].ends_with("[warn] test failed"), "{tail:?}");
    let first = beside_hole[0];
    assert!(
        tail[1].ends_with(&format!("[info] next: fix split_edge first; see that case alone, with pictures: cargo run -p grader -- --case {first} --report")),
        "{tail:?}"
    );
    assert!(
        tail[2].ends_with(&format!("[warn] {first} and {} more: split_edge returned None for a boundary edge: it must divide the one real triangle beside it", beside_hole.len() - 1)),
        "{tail:?}"
    );
}

#[test]
fn quiet_prints_the_summary_alone_and_a_loop_costs_the_limit_once() {
    let g = grade("stubs", &["-q"]);
    assert_eq!(g.code, 1);
    assert!(!g.stdout.contains("start testing"), "{}", g.stdout);
    let flips = common::counted_cases("flip");
    // A sequence whose first step is a flip panics the same way.
    let flip_first = ["lab", "hidden"]
        .iter()
        .flat_map(|g| common::case_files(g))
        .map(|p| common::json(&p))
        .filter(|f| f["operation"]["kind"] == "sequence" && f["steps"][0]["kind"] == "flip")
        .count();
    let line = format!(
        "[warn] {} and {} more: flip_edge panicked: not yet implemented",
        flips[0],
        flips.len() + flip_first - 1
    );
    assert!(g.stdout.contains(&line), "{line}\n{}", g.stdout);
    assert!(g.stdout.lines().count() <= 10, "{}", g.stdout);
    // The work is bounded, not the time: the cases already running when the
    // first one timed out wait out the 2 s limit (one per worker, and one
    // more a worker may have picked up before it heard), every later one
    // gets 1 s and says why.
    let g = grade("endless", &["--stage", "subdivide", "--timeout", "2"]);
    let subdivisions = common::counted("subdivide");
    let waited = |limit: &str| {
        g.stdout
            .lines()
            .filter(|l| {
                l.ends_with(&format!(
                    "[warn] loop_subdivide did not finish within {limit}"
                ))
            })
            .count()
    };
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let full = waited("2 s");
    assert!(
        (1..=2 * workers).contains(&full),
        "{full} waited 2 s:\n{}",
        g.stdout
    );
    assert_eq!(waited("1 s"), subdivisions - full, "{}", g.stdout);
    assert_eq!(
        g.stdout
            .matches("the limit was cut to 1 s because loop_subdivide already timed out on ")
            .count(),
        subdivisions - full,
        "{}",
        g.stdout
    );
}

#[test]
fn a_failing_function_is_named_under_subdivision() {
    let g = grade("flip-stale-vertex", &["--case", "cube-flip-1"]);
    assert_eq!(g.code, 1);
    let g = grade("flip-stale-vertex", &["--stage", "subdivide"]);
    assert_eq!(g.code, 1, "stale vertex pointers break subdivision too");
    let all = grade("flip-stale-vertex", &[]);
    assert!(
        all.stdout
            .contains("loop_subdivide calls your flip_edge, which failed above"),
        "{}",
        all.stdout
    );
}

#[test]
fn gradescope_and_json_reports() {
    let dir = std::env::temp_dir().join(format!("gs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("results.json");
    let g = grade(
        "no-flip",
        &["--format", "json", "--gradescope", path.to_str().unwrap()],
    );
    assert_eq!(g.code, 1);
    let report: serde_json::Value =
        serde_json::from_str(&g.stdout).expect("--format json prints JSON");
    assert_eq!(report["passed"], false);
    let cases = report["cases"].as_array().unwrap();
    let failed: Vec<&str> = cases
        .iter()
        .filter(|c| c["passed"] == false)
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert!(failed.contains(&"cube-subdivide-1"));
    assert!(
        !failed
            .iter()
            .any(|n| n.contains("flip") || n.contains("split")),
        "{failed:?}"
    );

    let results: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let tests = results["tests"].as_array().unwrap();
    let bonus_cases = cases.iter().filter(|c| c["group"] == "bonus").count();
    assert!(bonus_cases > 0);
    assert_eq!(
        tests.len(),
        cases.len() - bonus_cases,
        "bonus cases are left out without --bonus"
    );
    let points: f64 = tests.iter().map(|t| t["score"].as_f64().unwrap()).sum();
    assert_eq!(results["score"].as_f64(), Some(points));
    let cube = tests
        .iter()
        .find(|t| t["name"] == "cube-subdivide-1 (loop_subdivide)")
        .unwrap();
    assert_eq!(
        (cube["score"].as_f64(), cube["max_score"].as_f64()),
        (Some(0.0), Some(1.0))
    );
    assert!(cube["output"]
        .as_str()
        .unwrap()
        .contains("hint: no edge was flipped"));
    let bonus_names: Vec<&str> = cases
        .iter()
        .filter(|c| c["group"] == "bonus")
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    for t in tests {
        let name = t["name"].as_str().unwrap();
        assert!(
            !bonus_names
                .iter()
                .any(|b| name.starts_with(&format!("{b} ("))),
            "no bonus test without --bonus: {name}"
        );
    }
}

#[test]
fn usage_and_fixture_errors_exit_2_with_a_message() {
    let g = grade("reference", &["--case", "teapot"]);
    assert_eq!(g.code, 2);
    assert!(
        g.stderr.contains("no case named \"teapot\""),
        "{}",
        g.stderr
    );

    let g = grade("reference", &["--fixtures", "/no/such/dir"]);
    assert_eq!(g.code, 2);
    assert!(
        g.stderr.contains("/no/such/dir: no such fixtures folder"),
        "{}",
        g.stderr
    );

    let dir = std::env::temp_dir().join(format!("bad-fixtures-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("lab")).unwrap();
    std::fs::write(
        dir.join("lab/cube-flip-1.json"),
        "{\"schema\": 1, \"name\": ",
    )
    .unwrap();
    let g = grade("reference", &["--fixtures", dir.to_str().unwrap()]);
    assert_eq!(g.code, 2);
    assert!(
        g.stderr.contains("lab/cube-flip-1.json: not valid JSON"),
        "{}",
        g.stderr
    );
    std::fs::write(dir.join("lab/cube-flip-1.json"), "{\"schema\": 7}").unwrap();
    let g = grade("reference", &["--fixtures", dir.to_str().unwrap()]);
    assert!(
        g.stderr
            .contains("schema 7, but this grader reads schema 3"),
        "{}",
        g.stderr
    );
    std::fs::remove_dir_all(&dir).unwrap();

    let g = grade("reference", &["--timeout", "-3"]);
    assert_eq!(g.code, 2);
    let g = grade("reference", &["--stage", "sideways"]);
    assert_eq!(g.code, 2, "clap's usage errors exit 2 too");
    for text in [&g.stdout, &g.stderr] {
        assert!(!text.contains("panicked"));
    }
}

#[test]
fn list_names_every_case() {
    let g = grade("reference", &["--list"]);
    assert_eq!(g.code, 0);
    assert!(g.stdout.lines().any(|l| l.starts_with("cube-subdivide-1")
        && l.contains("lab")
        && l.contains("loop_subdivide")));
    assert!(g.stdout.lines().count() >= 40);
}

/// Whether this kernel offers Landlock (ABI version > 0).
fn kernel_has_landlock() -> bool {
    // SAFETY: landlock_create_ruleset(NULL, 0, VERSION) only reports the ABI.
    unsafe {
        libc::syscall(
            libc::SYS_landlock_create_ruleset,
            std::ptr::null::<u8>(),
            0usize,
            1u32,
        ) > 0
    }
}

/// Processes still running an implementation's child (`serve-case NAME`).
fn survivors(implementation: &str) -> Vec<String> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(raw) = std::fs::read(entry.path().join("cmdline")) else {
            continue;
        };
        let args: Vec<String> = raw
            .split(|&b| b == 0)
            .map(|a| String::from_utf8_lossy(a).into_owned())
            .collect();
        if args.iter().any(|a| a == "serve-case") && args.iter().any(|a| a == implementation) {
            out.push(format!("{:?}: {}", entry.file_name(), args.join(" ")));
        }
    }
    out
}

#[test]
fn the_protections_line_says_what_is_in_force() {
    let g = grade("reference", &["--case", "cube-flip-1"]);
    let line = g
        .stdout
        .lines()
        .find(|l| l.contains("[info] protections: "))
        .unwrap_or_else(|| panic!("no protections line:\n{}", g.stdout));
    assert!(
        line.contains("memory cap 2 GiB, own process group"),
        "{line}"
    );
    if kernel_has_landlock() {
        assert!(line.contains("Landlock ABI "), "{line}");
        assert!(
            line.contains("no files, no network, no signals out"),
            "{line}"
        );
    } else {
        assert!(line.contains("Landlock off"), "{line}");
    }
    // SAFETY: geteuid only reads.
    if unsafe { libc::geteuid() } == 0 {
        assert!(
            line.contains(", user nobody,"),
            "root drops to nobody: {line}"
        );
    }
    let off = grade(
        "reference",
        &["--case", "cube-flip-1", "--without-landlock"],
    );
    assert!(off.stdout.contains("Landlock off"), "{}", off.stdout);
}

/// A scratch copy of the committed fixtures.
fn fixtures_copy(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let root = reference::lab_root().join("fixtures");
    for group in ["lab", "bonus", "hidden"] {
        std::fs::create_dir_all(dir.join(group)).unwrap();
        for entry in std::fs::read_dir(root.join(group)).unwrap().flatten() {
            std::fs::copy(entry.path(), dir.join(group).join(entry.file_name())).unwrap();
        }
    }
    dir
}

fn snapshot(dir: &std::path::Path) -> Vec<(std::path::PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for group in ["lab", "bonus", "hidden"] {
        for entry in std::fs::read_dir(dir.join(group)).unwrap().flatten() {
            out.push((entry.path(), std::fs::read(entry.path()).unwrap()));
        }
    }
    out.sort();
    out
}

#[test]
fn student_code_can_read_and_write_nothing() {
    let dir = fixtures_copy("tamper");
    let before = snapshot(&dir);
    let results = dir.join("results.json");
    let _ = std::fs::remove_dir_all(reference::catalogue::attacks::MARK_DIR);
    let args = [
        "--case",
        "cube-subdivide-1",
        "--fixtures",
        dir.to_str().unwrap(),
        "--gradescope",
        results.to_str().unwrap(),
    ];
    let g = grade("tamper", &args);
    assert_eq!(g.code, 1, "{}{}", g.stdout, g.stderr);
    assert!(
        g.stdout.contains("hint: no edge was flipped"),
        "{}",
        g.stdout
    );
    if kernel_has_landlock() {
        for attack in [
            "read the grader's command line",
            "read the expected answer",
            "tamper with a fixture",
            "rewrite the digest list",
            "write a file",
        ] {
            assert!(
                g.stdout.contains(&format!("| attack: {attack}: denied")),
                "{attack}:\n{}",
                g.stdout
            );
        }
    }
    assert!(!g.stdout.contains(": done"), "{}", g.stdout);
    assert_eq!(snapshot(&dir), before, "the fixtures are untouched");
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&results).unwrap()).unwrap();
    assert_eq!(written["score"].as_f64(), Some(0.0), "{written}");
    assert!(!std::path::Path::new(reference::catalogue::attacks::MARK_DIR).exists());
    // Graded again, the same verdict: nothing was left tampered.
    let again = grade("tamper", &args);
    assert_eq!(again.code, 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_tampered_fixture_stops_the_run_and_names_the_file() {
    let dir = fixtures_copy("tampered");
    let cube = dir.join("lab/cube-subdivide-1.json");
    let text = std::fs::read_to_string(&cube).unwrap();
    // A tolerance still in range, so only the digest can tell.
    std::fs::write(
        &cube,
        text.replace("\"tolerance\": 0.00001", "\"tolerance\": 0.00002"),
    )
    .unwrap();
    let g = grade("no-flip", &["--fixtures", dir.to_str().unwrap()]);
    assert_eq!(g.code, 2, "{}", g.stdout);
    assert!(
        g.stderr.contains(
            "lab/cube-subdivide-1.json: has been changed since the fixtures were generated"
        ),
        "{}",
        g.stderr
    );
    assert!(g.stdout.is_empty(), "no case is graded: {}", g.stdout);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn processes_left_behind_cannot_hold_or_outlive_the_grader() {
    for without_landlock in [false, true] {
        let mut extra: Vec<&str> = vec![];
        if without_landlock {
            extra.push("--without-landlock");
        }
        // A process holding the pipes for 40 s: the case ends when the function does.
        let start = std::time::Instant::now();
        let mut args = vec!["--case", "cube-subdivide-1", "--timeout", "3"];
        args.extend(&extra);
        let g = grade("orphan", &args);
        let took = start.elapsed();
        assert_eq!(g.code, 1, "{}", g.stdout);
        assert!(
            g.stdout.contains("hint: no edge was flipped"),
            "{}",
            g.stdout
        );
        // The case ends with the function, not when the orphan lets go of
        // the pipes 40 s later (generous for a loaded 2-core machine).
        assert!(took.as_secs_f64() < 30.0, "took {took:?} with a 3 s limit");
        assert_eq!(survivors("orphan"), Vec::<String>::new());

        // A detached process that would rewrite results.json 3 s later.
        let dir = std::env::temp_dir().join(format!("detached-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let results = dir.join("results.json");
        let _ = std::fs::remove_dir_all(reference::catalogue::attacks::MARK_DIR);
        let mut args = vec![
            "--case",
            "cube-subdivide-1",
            "--gradescope",
            results.to_str().unwrap(),
        ];
        args.extend(&extra);
        let g = grade("detached", &args);
        assert_eq!(g.code, 1, "{}", g.stdout);
        assert_eq!(survivors("detached"), Vec::<String>::new());
        let written = std::fs::read_to_string(&results).unwrap();
        std::thread::sleep(std::time::Duration::from_secs(4));
        assert_eq!(
            std::fs::read_to_string(&results).unwrap(),
            written,
            "results.json stays the grader's"
        );
        assert!(
            !std::path::Path::new(reference::catalogue::attacks::MARK_DIR)
                .join("detached")
                .exists()
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn a_memory_hog_is_named_as_one() {
    let g = grade(
        "memory-hog",
        &["--case", "cube-subdivide-1", "--memory", "256M"],
    );
    assert_eq!(g.code, 1, "{}", g.stdout);
    assert!(
        g.stdout
            .contains("[warn] loop_subdivide used more than 256 MiB of memory"),
        "{}",
        g.stdout
    );
    for bad in ["10M", "1T", "lots"] {
        let g = grade("reference", &["--memory", bad]);
        assert_eq!(g.code, 2, "--memory {bad}");
        assert!(g.stderr.contains("64M"), "{bad}: {}", g.stderr);
    }
    let g = grade("reference", &["--timeout", "1e20"]);
    assert_eq!(g.code, 2);
    assert!(g.stderr.contains("from 0.1 to 3600"), "{}", g.stderr);
}

#[test]
fn try_runs_a_function_on_any_mesh() {
    let dir = std::env::temp_dir().join(format!("try-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cube = reference::lab_root().join("crates/halfedge/objects/cube.obj");
    let out = dir.join("cube2.obj");
    let run = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_reference"))
            .arg("try")
            .args(args)
            .current_dir(&dir)
            .output()
            .unwrap();
        (
            o.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&o.stdout).into_owned(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let c = cube.to_str().unwrap();
    let (code, stdout, _) = run(&[c, "--subdivide", "2", "-o", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), 98);
    assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), 192);
    assert!(stdout.contains("[info] wrote "), "{stdout}");

    let (code, stdout, _) = run(&[
        "--implementation",
        "flip-stale-vertex",
        c,
        "--flip",
        "1",
        "2",
    ]);
    assert_eq!(code, 1, "{stdout}");
    assert!(
        stdout.contains("[warn] the result is a invalid mesh: A vertex's halfedge does not point to that vertex! (v"),
        "{stdout}"
    );
    let (code, _, stderr) = run(&[c, "--flip", "1", "9"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("vertex 9 does not exist: the file's vertices are 1 to 8"),
        "{stderr}"
    );
    let (code, _, stderr) = run(&[c, "--subdivide", "12"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("--subdivide 12 is out of range: 1 to 8"),
        "{stderr}"
    );
    let (code, _, stderr) = run(&[c, "--subdivide", "4", "--max-faces", "1000"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains(
            "4 rounds make 3072 faces, more than 1000: fewer rounds, or --max-faces 3072"
        ),
        "{stderr}"
    );
    let (code, stdout, _) = run(&[
        "--implementation",
        "endless",
        c,
        "--subdivide",
        "1",
        "--timeout",
        "1",
    ]);
    assert_eq!(code, 1);
    assert!(
        stdout.contains("[warn] loop_subdivide did not return: still running after 1 s"),
        "{stdout}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every mistake the fixtures record is named on every counted
/// subdivision case it fails, one round or two (the catalogue entry of
/// the same name makes it), and gets its own hint on at least one of them
/// (where two mistakes give the same mesh, as an integer u and unmoved
/// vertices do on the cube, the first one's hint stands for both).
#[test]
fn every_known_mistake_is_named_wherever_it_fails() {
    for known in reference::catalogue::subdivision_mistakes() {
        let g = grade(known.id, &["--stage", "subdivide", "--timeout", "5"]);
        assert_eq!(g.code, 1, "{} passes?\n{}", known.id, g.stdout);
        // Each case's block: from "start testing" to "end testing".
        let (mut failed, mut own) = (0, 0);
        let mut block: Vec<&str> = Vec::new();
        for line in g.stdout.lines() {
            if line.contains("[info] start testing") {
                block.clear();
            }
            block.push(line);
            if line.contains("[info] end testing") {
                let text = block.join("\n");
                if text.contains("[warn] ") && !text.contains("panicked, as it must") {
                    failed += 1;
                    own += usize::from(text.contains(&format!("hint: {}", known.hint)));
                    assert!(
                        text.contains("        hint: "),
                        "{} fails a case without a hint:\n{text}",
                        known.id
                    );
                }
            }
        }
        assert!(
            failed > 0,
            "{}: no failing case seen\n{}",
            known.id,
            g.stdout
        );
        assert!(
            own > 0,
            "{}: its own hint is never given\n{}",
            known.id,
            g.stdout
        );
        // And in the summary, where students read.
        let tail: Vec<&str> = g.stdout.lines().rev().take(12).collect();
        assert!(
            tail.iter()
                .any(|l| l.contains("[info] hint for ") && l.ends_with(known.hint)),
            "{}: the hint is not in the last lines:\n{}",
            known.id,
            tail.join("\n")
        );
    }
}

#[test]
fn quiet_keeps_the_hint_and_a_focused_run_says_what_to_do_next() {
    let g = grade("in-place-vertices-first", &["-q"]);
    assert_eq!(g.code, 1);
    let hint = reference::catalogue::subdivision_mistakes()
        .into_iter()
        .find(|m| m.id == "in-place-vertices-first")
        .unwrap()
        .hint;
    assert!(
        g.stdout
            .lines()
            .any(|l| l.contains("[info] hint for ") && l.ends_with(hint)),
        "{}",
        g.stdout
    );
    assert!(g.stdout.lines().count() <= 12, "{}", g.stdout);

    // After --case X --report, next: names the pictures, not the same command.
    let dir = common::scratch("focused");
    let report = dir.join("report");
    let g = grade(
        "no-flip",
        &[
            "--case",
            "cube-subdivide-1",
            "--report",
            report.to_str().unwrap(),
        ],
    );
    let next = g
        .stdout
        .lines()
        .find(|l| l.contains("[info] next: "))
        .unwrap_or_else(|| panic!("{}", g.stdout));
    assert!(
        !next.contains("cargo run -p grader -- --case cube-subdivide-1 --report"),
        "{next}"
    );
    assert!(
        next.contains(&report.join("index.html").display().to_string()),
        "{next}"
    );
    assert!(next.contains("then run this command again"), "{next}");
    let g = grade("no-flip", &["--case", "cube-subdivide-1"]);
    let next = g
        .stdout
        .lines()
        .find(|l| l.contains("[info] next: "))
        .unwrap();
    assert!(
        next.ends_with("cargo run -p grader -- --case cube-subdivide-1 --report"),
        "{next}"
    );
    assert!(
        next.contains("next: fix loop_subdivide; to see the case"),
        "{next}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
