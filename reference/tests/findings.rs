//! The grader's findings as data: its JSON report carries, beside the
//! words, how each case ended, the elements each line is about (in the
//! case's numbering and the labelling's), the comparison, the broken link
//! and the mistake recognised, by id. No module decides from another's
//! words: with every message rewritten (`--reword-messages`, a hidden
//! option for this test), no verdict, hint, element or comparison moves.

mod common;
use common::grade;

use serde_json::Value;

/// `reference grade --implementation NAME --format json --bonus`, parsed.
fn report(name: &str, extra: &[&str]) -> Value {
    let mut args = vec!["--format", "json", "--bonus"];
    args.extend_from_slice(extra);
    let g = grade(name, &args);
    assert!(
        g.code == 0 || g.code == 1,
        "{name}: exit {}\n{}{}",
        g.code,
        g.stdout,
        g.stderr
    );
    serde_json::from_str(&g.stdout).unwrap_or_else(|e| panic!("{name}: {e}\n{}", g.stdout))
}

/// Everything about a case that must not depend on the words.
fn facts(case: &Value) -> Value {
    let elements: Vec<&Value> = case["entries"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| &e["elements"])
        .collect();
    let hints: Vec<&Value> = case["entries"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| &e["hint"])
        .collect();
    let levels: Vec<&Value> = case["entries"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| &e["level"])
        .collect();
    serde_json::json!({
        "name": case["name"],
        "passed": case["passed"],
        "end": case["end"],
        "hint_id": case["hint_id"],
        "hint": case["hint"],
        "invalid": case["invalid"],
        "comparison": case["comparison"],
        "labelling": case["labelling"],
        "levels": levels,
        "elements": elements,
        "hints": hints,
    })
}

/// Mistakes whose hints come from each kind of fact: a broken link's
/// check (the labelling note by the pointer it is about), the fixture's
/// known positions and edges, the growth budget, a sequence's invalid step,
/// the returned vertex's halfedge.
const MISTAKES: &[&str] = &[
    "flip-stale-vertex",
    "flip-stale-face",
    "split-stale-vertex",
    "split-vertex-across",
    "loop-weights",
    "flip-all-new",
    "split-new-again",
    "split-after-split",
    "stubs",
];

#[test]
fn rewording_every_message_changes_no_verdict_hint_or_element() {
    for name in MISTAKES {
        let plain = report(name, &[]);
        let reworded = report(name, &["--reword-messages"]);
        assert_eq!(plain["passed"], reworded["passed"], "{name}");
        let (a, b) = (
            plain["cases"].as_array().unwrap(),
            reworded["cases"].as_array().unwrap(),
        );
        assert_eq!(a.len(), b.len(), "{name}");
        let mut failed = 0;
        for (x, y) in a.iter().zip(b) {
            assert_eq!(facts(x), facts(y), "{name}");
            failed += usize::from(x["passed"] == false);
            // The rewording did reach the words: the test would prove
            // nothing otherwise.
            let texts = |c: &Value| -> Vec<String> {
                c["entries"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|e| e["text"].as_str().unwrap().to_string())
                    .collect()
            };
            assert!(
                texts(y).iter().all(|t| t.starts_with("REWORDED: ")),
                "{name}: {:?}",
                texts(y)
            );
            assert_ne!(texts(x), texts(y));
        }
        assert!(failed > 0, "{name} fails somewhere");
    }
}

/// The cases a report failed.
fn failed(r: &Value) -> impl Iterator<Item = &Value> {
    r["cases"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["passed"] == false)
}

#[test]
fn a_failure_on_a_relabelled_input_names_its_elements_in_both_numberings() {
    let r = report("split-stale-vertex", &["--case", "cone-split"]);
    let case = failed(&r).next().expect("cone-split fails");
    let labelling = &case["labelling"];
    assert!(labelling["index"].as_u64().unwrap() >= 1, "{case:#}");
    let p = &labelling["permutation"]["vertices"];
    // The broken vertex: b, whose halfedge the split left elsewhere.
    let named = &case["invalid"]["element"];
    assert_eq!(named["element"]["kind"], "vertex");
    let (case_id, labelled_id) = (
        named["element"]["id"].as_u64().unwrap(),
        named["labelled"]["id"].as_u64().unwrap(),
    );
    assert_eq!(p[case_id as usize].as_u64(), Some(labelled_id), "{case:#}");
    // The words use the labelling's id, as the student's mesh had it.
    let warning = case["first_warning"].as_str().unwrap();
    assert!(warning.ends_with(&format!("(v{labelled_id})")), "{warning}");
    assert_eq!(
        case["invalid"]["check"], "vertex-halfedge-elsewhere",
        "{case:#}"
    );
    assert_eq!(
        case["hint_id"],
        serde_json::json!({"from": "grader", "id": "labelling-vertex-pointer"})
    );
    assert_eq!(case["end"]["kind"], "returned");
}

#[test]
fn the_comparison_and_the_known_mistake_are_data() {
    let r = report("loop-weights", &["--case", "cube-subdivide-1"]);
    let case = failed(&r).next().expect("loop-weights fails on the cube");
    let c = &case["comparison"];
    let missing = c["missing_vertices"].as_array().unwrap();
    assert!(!missing.is_empty(), "{c:#}");
    assert_eq!(
        c["extra_vertices"].as_array().unwrap().len(),
        missing.len(),
        "as many of yours matched nothing"
    );
    assert_eq!(c["missing_edges"], Value::Null, "edges come after vertices");
    assert_eq!(case["hint_id"]["from"], "catalogue", "{case:#}");
    // The hint's words are the fixture's for that id.
    let id = case["hint_id"]["id"].as_str().unwrap();
    let fixture = common::json(&common::lab_root().join("fixtures/lab/cube-subdivide-1.json"));
    let known = fixture["expected"]["mistakes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["id"] == id)
        .expect("the id is one of the fixture's mistakes");
    assert_eq!(case["hint"], known["hint"]);

    let r = report("no-flip", &["--case", "cube-subdivide-1"]);
    let case = failed(&r).next().expect("no-flip fails on the cube");
    let c = &case["comparison"];
    assert!(c["missing_vertices"].as_array().unwrap().is_empty());
    let (missing, extra) = (
        c["missing_edges"].as_array().unwrap(),
        c["extra_edges"].as_array().unwrap(),
    );
    assert!(!missing.is_empty() && !extra.is_empty(), "{c:#}");
    assert_eq!(
        case["hint_id"],
        serde_json::json!({"from": "catalogue", "id": "no-flip"})
    );
    // The extra edge the words name is the first of the data's, in your ids.
    let line = case["entries"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["text"].as_str().unwrap().starts_with("extra: "))
        .unwrap();
    let ids: Vec<u64> = line["elements"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["element"]["id"].as_u64().unwrap())
        .collect();
    let first: Vec<u64> = extra[0]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap())
        .collect();
    assert_eq!(ids, first, "{line:#}");
}

#[test]
fn how_a_case_ended_is_one_field() {
    let r = report("split-new-again", &["--case", "cube-subdivide-1"]);
    let case = failed(&r).next().unwrap();
    assert_eq!(case["end"]["kind"], "panicked");
    assert_eq!(case["end"]["grew_past"], 10_000);
    assert_eq!(
        case["hint_id"],
        serde_json::json!({"from": "grader", "id": "grew-past"})
    );
    let r = report(
        "endless",
        &["--case", "cube-subdivide-1", "--timeout", "0.3"],
    );
    let case = failed(&r).next().unwrap();
    assert_eq!(case["end"]["kind"], "timed-out", "{case:#}");
    assert_eq!(case["end"]["limit"], 0.3);
}

/// With `--report`, each subdivision is recorded split by split: a split
/// that breaks the mesh is named by its frame, with its edge; the model
/// solutions have no broken frame anywhere.
#[test]
fn the_step_through_names_the_split_that_broke_the_mesh() {
    let dir = common::scratch("findings-frames");
    let r = report(
        "split-stale-vertex",
        &[
            "--case",
            "cube-subdivide-1",
            "--report",
            dir.to_str().unwrap(),
        ],
    );
    let case = failed(&r)
        .next()
        .expect("split-stale-vertex fails on the cube");
    let frames = &case["frames"];
    let k = frames["first_broken"].as_u64().expect("a broken frame") as usize;
    let labels = frames["labels"].as_array().unwrap();
    assert!(k >= 1 && k < labels.len(), "{frames:#}");
    assert_eq!(labels[0], "before split 1");
    assert_eq!(labels.last().unwrap(), "after loop_subdivide");
    assert_eq!(frames["cut"], Value::Null);
    let broken = &frames["broken"];
    assert_eq!(broken["kind"], "invalid");
    assert_eq!(broken["split"].as_u64(), Some(k as u64));
    assert_eq!(broken["edge"]["element"]["kind"], "edge");
    // The detail line under the failure names the split and its edge, as
    // the student's mesh numbered it.
    let ordinal = match k {
        1 => "1st".to_string(),
        2 => "2nd".to_string(),
        3 => "3rd".to_string(),
        n => format!("{n}th"),
    };
    let edge = broken["edge"]["labelled"]["id"]
        .as_u64()
        .or(broken["edge"]["element"]["id"].as_u64())
        .unwrap();
    let line = case["entries"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| {
            e["text"].as_str().unwrap().starts_with(&format!(
                "your loop_subdivide's {ordinal} split (edge e{edge} "
            ))
        })
        .unwrap_or_else(|| panic!("no line for split {k}: {case:#}"));
    assert!(
        line["text"]
            .as_str()
            .unwrap()
            .contains(" left an invalid mesh: "),
        "{line:#}"
    );
    assert!(!line["elements"].as_array().unwrap().is_empty());
    std::fs::remove_dir_all(&dir).unwrap();

    // A split vertex away from its midpoint is named too, even where the
    // subdivision's moves hide it in the end.
    let r = report(
        "split-not-midpoint",
        &["--case", "cube-subdivide-1", "--record-subdivision"],
    );
    let frames = &r["cases"][0]["frames"];
    assert_eq!(frames["first_broken"], 1, "{frames:#}");
    assert_eq!(frames["broken"]["kind"], "off-midpoint");

    for name in ["reference", "alt-order", "alt-reverse"] {
        let r = report(name, &["--stage", "subdivide", "--record-subdivision"]);
        let recorded = r["cases"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|c| {
                c["frames"]["labels"]
                    .as_array()
                    .is_some_and(|l| l.len() > 1)
            })
            .count();
        assert!(recorded > 10, "{name}: {recorded} cases recorded");
        for case in r["cases"].as_array().unwrap() {
            let frames = &case["frames"];
            assert_eq!(
                (&frames["first_broken"], &frames["unjudged"]),
                (&Value::Null, &Value::Null),
                "{name}, {}: {frames:#}",
                case["name"]
            );
        }
    }
}
