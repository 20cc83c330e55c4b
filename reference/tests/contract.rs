//! Every rule of the three stubs' contracts decides the counted grade.
//!
//! Each bullet of a `Contract:` list in `crates/meshedit/src/lib.rs` (and
//! `loop_subdivide`'s precondition) is read from the file and must have a
//! row below naming a counted case (in `fixtures/lab` or `fixtures/hidden`)
//! and a mistake of the catalogue that breaks that rule, which the case must
//! fail. A new bullet without a row, or a row whose bullet is gone, fails.
//! Boundary *support* (splitting beside a hole) is the one bonus rule.

mod common;
use common::{grade, lab_root as root};

/// How a rule is graded: by counted cases, or only with `--bonus`.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Counted {
    Yes,
    Bonus,
}

/// (function, the bullet's first words, how it counts, [(case, mistake)])
type Rule = (
    &'static str,
    &'static str,
    Counted,
    &'static [(&'static str, &'static str)],
);

const RULES: &[Rule] = &[
    (
        "flip_edge",
        "Returns `Some(e)`",
        Counted::Yes,
        &[("cube-flip-1", "flip-wrong-return")],
    ),
    (
        "flip_edge",
        "Adds and removes nothing",
        Counted::Yes,
        &[("cube-flip-1", "flip-moves-vertex")],
    ),
    (
        "flip_edge",
        "Returns `None`, changing nothing, when `e` is on the boundary",
        Counted::Yes,
        &[
            ("open-octahedron-flip", "flip-boundary"),
            ("quad-box-flip", "flip-any-face"),
        ],
    ),
    (
        "flip_edge",
        "Returns `None`, changing nothing, when the flip would create an edge",
        Counted::Yes,
        &[("tetrahedron-flip", "flip-duplicates")],
    ),
    (
        "flip_edge",
        "Afterwards `mesh.validate()` is `Ok`",
        Counted::Yes,
        &[
            ("cube-flip-1", "flip-stale-vertex"),
            ("cube-flip-2", "flip-stale-face"),
        ],
    ),
    (
        "split_edge",
        "Returns `Some(m)`, the new vertex, at the midpoint",
        Counted::Yes,
        &[
            ("cube-split", "split-not-midpoint"),
            ("cube-split", "split-returns-old"),
        ],
    ),
    (
        "split_edge",
        "`mesh[m].halfedge` runs along the edge",
        Counted::Yes,
        &[("cube-split", "split-vertex-across")],
    ),
    (
        "split_edge",
        "Only adds elements",
        Counted::Yes,
        &[("cube-split", "split-renames-edge")],
    ),
    // Boundary support: the bonus.
    (
        "split_edge",
        "On a boundary edge",
        Counted::Bonus,
        &[("grid-split-boundary", "split-refuses-boundary")],
    ),
    (
        "split_edge",
        "Returns `None`, changing nothing, when a real face",
        Counted::Yes,
        &[("quad-box-split", "split-any-face")],
    ),
    (
        "split_edge",
        "Sets nothing else on `m`",
        Counted::Yes,
        &[("cube-split", "split-marks-new")],
    ),
    (
        "split_edge",
        "Afterwards `mesh.validate()` is `Ok`",
        Counted::Yes,
        &[("cube-split", "split-stale-vertex")],
    ),
    (
        "loop_subdivide",
        "Precondition: a triangle mesh",
        Counted::Yes,
        &[("quad-box-subdivide-1", "subdivide-skips-quads")],
    ),
];

/// The rules of each function's doc comment, as (function, rule text):
/// every bullet of its `Contract:` list, and a `Precondition:` paragraph.
fn contract_rules(source: &str) -> Vec<(String, String)> {
    let mut rules = Vec::new();
    let mut doc: Vec<&str> = Vec::new();
    for line in source.lines() {
        let line = line.trim();
        if let Some(text) = line.strip_prefix("///") {
            doc.push(text.strip_prefix(' ').unwrap_or(text));
            continue;
        }
        if let Some(rest) = line.strip_prefix("pub fn ") {
            let name = rest.split('(').next().unwrap().to_string();
            let mut in_contract = false;
            let mut current: Option<String> = None;
            let mut flush = |current: &mut Option<String>| {
                if let Some(rule) = current.take() {
                    rules.push((name.clone(), rule));
                }
            };
            for text in &doc {
                if *text == "Contract:" {
                    in_contract = true;
                } else if text.starts_with("Precondition:") {
                    flush(&mut current);
                    current = Some(text.to_string());
                } else if text.is_empty() {
                    flush(&mut current);
                    in_contract = false;
                } else if let Some(bullet) = text.strip_prefix("- ").filter(|_| in_contract) {
                    flush(&mut current);
                    current = Some(bullet.to_string());
                } else if let Some(rule) = current.as_mut() {
                    rule.push(' ');
                    rule.push_str(text.trim());
                }
            }
            flush(&mut current);
        }
        if !line.starts_with("#[") {
            doc.clear();
        }
    }
    rules
}

#[test]
fn every_contract_rule_has_a_row_and_every_row_a_rule() {
    let source = std::fs::read_to_string(root().join("crates/meshedit/src/lib.rs")).unwrap();
    let rules = contract_rules(&source);
    for function in ["flip_edge", "split_edge", "loop_subdivide"] {
        assert!(
            rules.iter().any(|(f, _)| f == function),
            "no contract rules read for {function}: {rules:#?}"
        );
    }
    for (function, rule) in &rules {
        let rows: Vec<_> = RULES
            .iter()
            .filter(|(f, start, ..)| f == function && rule.starts_with(start))
            .collect();
        assert_eq!(
            rows.len(),
            1,
            "{function}'s contract rule has no row in RULES (name a counted case and a mistake that breaks it): {rule}"
        );
    }
    for (function, start, ..) in RULES {
        assert!(
            rules
                .iter()
                .any(|(f, r)| f == function && r.starts_with(start)),
            "RULES names a rule of {function} that its contract no longer has: {start}"
        );
    }
}

#[test]
fn each_rule_is_graded_by_a_case_that_its_mistake_fails() {
    for &(function, start, counted, cases) in RULES {
        assert!(!cases.is_empty(), "{function}: {start}: no case");
        for &(case, mistake) in cases {
            let folders: &[&str] = match counted {
                Counted::Yes => &["lab", "hidden"],
                Counted::Bonus => &["bonus"],
            };
            assert!(
                folders.iter().any(|d| root()
                    .join("fixtures")
                    .join(d)
                    .join(format!("{case}.json"))
                    .is_file()),
                "{function}: {start}: {case} is not in fixtures/{folders:?}"
            );
            let mut args = vec!["--case", case, "--timeout", "2"];
            if counted == Counted::Bonus {
                args.push("--bonus");
            }
            let g = grade(mistake, &args);
            assert_eq!(
                g.code, 1,
                "{function}: {start}: {mistake} must fail {case}:\n{}",
                g.stdout
            );
            let r = grade("reference", &args);
            assert_eq!(r.code, 0, "the reference passes {case}:\n{}", r.stdout);
        }
    }
}

/// The two refusals once graded only as bonus fail the plain run, which
/// grades exactly the counted cases.
#[test]
fn a_flip_missing_a_refusal_fails_the_default_run() {
    for (mistake, case) in [
        ("flip-duplicates", "tetrahedron-flip"),
        ("flip-boundary", "open-octahedron-flip"),
    ] {
        let g = grade(mistake, &["-q"]);
        assert_eq!(g.code, 1, "{mistake}:\n{}", g.stdout);
        assert!(
            g.stdout
                .lines()
                .last()
                .is_some_and(|l| l.ends_with("[warn] test failed")),
            "{mistake}:\n{}",
            g.stdout
        );
        assert!(
            g.stdout
                .lines()
                .any(|l| l.contains("[warn] ") && l.contains(case)),
            "{mistake}: the summary names {case}:\n{}",
            g.stdout
        );
    }
}

/// The flip relinking `crates/halfedge/tests/validate.rs` once shipped to
/// students: the model solution's `relink_flip` line for line, with `m`
/// for `mesh` and no comments.
fn shipped_flip(solution: &str) -> String {
    let start = solution.find("pub(crate) fn relink_flip").unwrap();
    let end = start + solution[start..].find("\n}\n").unwrap() + 3;
    solution[start..end]
        .lines()
        .filter(|l| !l.trim_start().starts_with("//") && !l.trim().is_empty())
        .map(|l| l.replace("mesh", "m"))
        .collect::<Vec<_>>()
        .join("\n")
        .replace(
            "pub(crate) fn relink_flip(m: &mut Mesh",
            "fn flip_by_hand(m: &mut Mesh",
        )
}

/// The export's copy check finds the model solution by content: the flip
/// once shipped in a test file, and the solution's split renamed and
/// reformatted, each planted in an otherwise clean folder.
#[test]
fn the_copy_check_finds_the_solution_under_other_names() {
    let dir = common::scratch("copies");
    let plant = |rel: &str, text: &str| {
        let path = dir.join(rel);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    };
    plant(
        "crates/meshedit/src/lib.rs",
        &std::fs::read_to_string(root().join("crates/meshedit/src/lib.rs")).unwrap(),
    );
    assert_eq!(
        reference::handout::solution_copies(&dir).unwrap(),
        Vec::<String>::new(),
        "the stubs are clean"
    );
    let solution = std::fs::read_to_string(root().join("reference/src/solution.rs")).unwrap();
    let flip = shipped_flip(&solution);
    assert!(
        flip.starts_with("fn flip_by_hand(m: &mut Mesh, e: EdgeId) {"),
        "{flip}"
    );
    plant("crates/halfedge/tests/validate.rs", &flip);
    // The split, renamed throughout and laid out differently.
    let start = solution.find("pub(crate) fn relink_split").unwrap();
    let end = start + solution[start..].find("\n}\n").unwrap() + 3;
    let mut renamed = solution[start..end].to_string();
    for (from, to) in [
        ("mesh", "g"),
        ("hb", "p"),
        ("tb", "q"),
        ("f0", "left"),
        ("set_neighbors", "link"),
    ] {
        renamed = renamed.replace(from, to);
    }
    plant(
        "grader/src/helper.rs",
        &renamed.replace(", ", ",\n    ").replace("//", "// note:"),
    );
    let found = reference::handout::solution_copies(&dir).unwrap();
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(
        found[0].starts_with("crates/halfedge/tests/validate.rs:"),
        "{found:?}"
    );
    assert!(found[1].starts_with("grader/src/helper.rs:"), "{found:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}
