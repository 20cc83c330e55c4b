//! The grader, fed the catalogue of implementations through the real
//! binary (child processes and all): it accepts the correct ones and
//! rejects each wrong one with its message and hint. Transcripts are insta
//! snapshots, so any change of wording is a reviewed change.

use std::process::Command;

struct Graded {
    code: i32,
    stdout: String,
    stderr: String,
}

fn grade(implementation: &str, args: &[&str]) -> Graded {
    let out = Command::new(env!("CARGO_BIN_EXE_reference"))
        .args(["grade", "--implementation", implementation, "--no-color"])
        .args(args)
        // Even with backtraces asked for, none may reach the student.
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("the reference binary runs");
    Graded {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Drops the `file.rs:LINE ` prefix of log lines and the line and column
/// of panic locations, which move whenever code is edited.
fn normalize(text: &str) -> String {
    text.lines()
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
    ("flip-boundary", "grid-flip-boundary", "flip_edge changed a boundary edge: it must return None and leave the mesh unchanged", None),
    ("flip-index-panic", "cube-flip-1", "flip_edge panicked: index out of bounds", Some("reference/src/mutants.rs")),
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
    ("flip-all-new", "cube-subdivide-1", "the result of subdivision is a invalid mesh: Two edges join the same pair of vertices!", None),
    ("flip-halves", "cube-subdivide-1", "the result of subdivision is a invalid mesh:", None),
    ("split-new-again", "cube-subdivide-1", "loop_subdivide panicked: the mesh grew past", Some("hint: are edges created while splitting split again?")),
    ("endless", "cube-subdivide-1", "loop_subdivide did not finish within 1 s", Some("an endless loop?")),
    ("recursion", "cube-subdivide-1", "loop_subdivide overflowed the stack", Some("calls itself without end")),
    ("abort", "cube-subdivide-1", "loop_subdivide crashed: signal 6 (SIGABRT: the program aborted)", None),
    ("exit", "cube-subdivide-1", "loop_subdivide ended the program (exit status 0) before returning", Some("std::process::exit")),
    ("fake-verdict", "cube-subdivide-1", "at least one of the edges connects incorrect vertices", Some("    | grade.rs:1 [info] all tests passed, congratulations!")),
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

#[test]
fn bonus_cases_count_only_when_asked() {
    // Refusing to split boundary edges fails only the bonus case.
    let quiet = grade("split-refuses-boundary", &["--stage", "split"]);
    assert_eq!(quiet.code, 0, "{}", quiet.stdout);
    assert!(quiet
        .stdout
        .contains("bonus cases: meshes with boundary (not counted"));
    assert!(quiet
        .stdout
        .contains("[warn] split_edge returned None for a boundary edge"));
    let counted = grade("split-refuses-boundary", &["--stage", "split", "--bonus"]);
    assert_eq!(counted.code, 1);
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
    assert!(
        !tests
            .iter()
            .any(|t| t["name"].as_str().unwrap().contains("grid-")),
        "no bonus test without --bonus"
    );
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
            .contains("schema 7, but this grader reads schema 1"),
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
