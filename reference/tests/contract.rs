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
use reference::local::Facts;

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
        &[
            ("cube-flip-1", "flip-wrong-return"),
            ("local-flip-open-3-8", "flip-refuses-degree-3"),
            ("local-flip-open-4-7", "flip-refuses-rim-ends"),
            ("local-flip-closed-4-8", "flip-refuses-high-degree"),
        ],
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
            ("local-flip-hole-left", "flip-boundary-one-side"),
            ("local-flip-hole-right", "flip-boundary-one-side"),
            ("local-flip-quad-left", "flip-one-face"),
            ("local-flip-quad-right", "flip-twin-face"),
        ],
    ),
    (
        "flip_edge",
        "Returns `None`, changing nothing, when the flip would create an edge",
        Counted::Yes,
        &[
            ("tetrahedron-flip", "flip-duplicates"),
            ("local-flip-joined-far", "flip-duplicates-by-degree"),
        ],
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
            ("local-split-open-3-8", "split-refuses-rim-ends"),
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
        &[
            ("quad-box-split", "split-any-face"),
            ("local-split-quad-left", "split-one-face"),
            ("local-split-quad-right", "split-one-face"),
            ("local-split-quad-hole", "split-twin-face"),
        ],
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

/// A local shape a rule must hold on, told by what a case's input shows
/// around its edge (`reference::local::facts`): (what, the test).
type Need = (String, Box<dyn Fn(&Facts) -> bool>);

fn need(what: impl Into<String>, test: impl Fn(&Facts) -> bool + 'static) -> Need {
    (what.into(), Box::new(test))
}

/// Flips and splits that the contract lets through: ends of degree 3 to
/// 8 on the rim of an open mesh and inside a closed one (a degree-3 end
/// inside a closed mesh only for a split: a flip there must refuse), and
/// the smallest mesh with an inner edge.
fn legal(flip: bool) -> Vec<Need> {
    let ok = move |f: &Facts| {
        if flip {
            f.flip_legal()
        } else {
            f.split_legal()
        }
    };
    let mut out = Vec::new();
    for d in 3..=8 {
        out.push(need(
            format!("an end of degree {d} on the rim of an open mesh"),
            move |f: &Facts| ok(f) && !f.closed && (0..2).any(|i| f.degrees[i] == d && f.on_rim[i]),
        ));
        if d > 3 || !flip {
            out.push(need(
                format!("an end of degree {d} inside a closed mesh"),
                move |f: &Facts| ok(f) && f.closed && f.degrees.contains(&d),
            ));
        }
    }
    out.push(need("two triangles, nothing else", move |f: &Facts| {
        ok(f) && f.faces == 2
    }));
    out
}

/// The refusals: a non-triangle (or a hole) on either side where no other
/// rule refuses; for splits a non-triangle beside a hole.
fn refused(flip: bool, sides: bool, holes: bool) -> Vec<Need> {
    let mut out = Vec::new();
    for (i, side) in ["a -> b", "b -> a"].into_iter().enumerate() {
        if holes {
            out.push(need(
                format!("a hole on the side of {side}, only the boundary rule refusing"),
                move |f: &Facts| {
                    f.sides[i].is_hole() && (!flip || f.flip_refusals() == [true, false, false])
                },
            ));
        }
        if sides {
            out.push(need(
                format!("a non-triangle on the side of {side}, only the triangle rule refusing"),
                move |f: &Facts| {
                    f.sides[i].is_polygon() && (!flip || f.flip_refusals() == [false, true, false])
                },
            ));
        }
    }
    out
}

/// The local shapes each flip and split bullet must be tried on, keyed by
/// the bullet's first words as in `RULES`.
fn needs(function: &str, start: &str) -> Option<Vec<Need>> {
    let flip = function == "flip_edge";
    Some(match (function, start) {
        ("flip_edge", "Returns `Some(e)`")
        | ("flip_edge", "Adds and removes nothing")
        | ("flip_edge", "Afterwards `mesh.validate()` is `Ok`")
        | ("split_edge", "Returns `Some(m)`, the new vertex, at the midpoint")
        | ("split_edge", "`mesh[m].halfedge` runs along the edge")
        | ("split_edge", "Only adds elements")
        | ("split_edge", "Sets nothing else on `m`")
        | ("split_edge", "Afterwards `mesh.validate()` is `Ok`") => legal(flip),
        ("flip_edge", "Returns `None`, changing nothing, when `e` is on the boundary") => {
            let mut out = refused(true, true, true);
            out.push(need("one triangle, nothing else", |f: &Facts| f.faces == 1));
            out
        }
        ("flip_edge", "Returns `None`, changing nothing, when the flip would create an edge") => {
            vec![
                need("an end of degree 3 inside a closed mesh", |f: &Facts| {
                    f.closed && f.degrees.contains(&3) && f.flip_refusals() == [false, false, true]
                }),
                need(
                    "c and d joined far from a and b, both ends of degree 4 or more",
                    |f: &Facts| {
                        f.flip_refusals() == [false, false, true]
                            && f.degrees.iter().all(|&d| d >= 4)
                    },
                ),
            ]
        }
        ("split_edge", "On a boundary edge") => {
            let mut out = refused(false, false, true);
            out.push(need("one triangle, nothing else", |f: &Facts| f.faces == 1));
            out
        }
        ("split_edge", "Returns `None`, changing nothing, when a real face") => {
            let mut out = refused(false, true, false);
            out.push(need("a non-triangle beside a hole", |f: &Facts| {
                f.sides.iter().any(|s| s.is_polygon()) && f.sides.iter().any(|s| s.is_hole())
            }));
            out
        }
        _ => return None,
    })
}

/// (case name, group, facts) of every fixture of one operation kind.
fn local_facts(kind: &str) -> Vec<(String, grader::judge::fixture::Group, Facts)> {
    use grader::judge::fixture::Operation;
    let mut out = Vec::new();
    for group in ["lab", "bonus", "hidden"] {
        for path in common::case_files(group) {
            let f = grader::judge::fixture::load(&path).unwrap();
            let edge = match (kind, f.operation) {
                ("flip", Operation::Flip { edge }) | ("split", Operation::Split { edge }) => edge,
                _ => continue,
            };
            let mesh = f.input.to_mesh().unwrap();
            let facts = reference::local::facts(&mesh, edge).expect("a case's edge is an edge");
            out.push((f.name.clone(), f.group, facts));
        }
    }
    out
}

/// Every bullet of `flip_edge`'s and `split_edge`'s contracts is tried on
/// each local shape it must hold on, in a case that counts for it (lab or
/// hidden; bonus for boundary support): found by what the cases' inputs
/// show around their edges, not by their names.
#[test]
fn every_rule_is_tried_on_every_local_shape_in_a_counted_case() {
    use grader::judge::fixture::Group;
    let source = std::fs::read_to_string(root().join("crates/meshedit/src/lib.rs")).unwrap();
    let mut missing = Vec::new();
    let mut tried = 0;
    for (function, rule) in contract_rules(&source) {
        let kind = match function.as_str() {
            "flip_edge" => "flip",
            "split_edge" => "split",
            _ => continue,
        };
        let (_, start, counted, _) = RULES
            .iter()
            .find(|(f, start, ..)| *f == function && rule.starts_with(start))
            .unwrap_or_else(|| panic!("{function}: no row in RULES for: {rule}"));
        let needs = needs(&function, start).unwrap_or_else(|| {
            panic!("{function}: name the local shapes this rule must hold on: {rule}")
        });
        assert!(!needs.is_empty(), "{function}: {start}: no shape");
        let cases = local_facts(kind);
        for (what, test) in needs {
            let counts = |g: Group| match counted {
                Counted::Yes => g != Group::Bonus,
                Counted::Bonus => g == Group::Bonus,
            };
            match cases.iter().find(|(_, g, f)| counts(*g) && test(f)) {
                Some((name, ..)) => {
                    tried += 1;
                    eprintln!("{function}: {start}: {what}: {name}");
                }
                None => missing.push(format!("{function}: {start}: {what}")),
            }
        }
    }
    assert!(
        missing.is_empty(),
        "no counted case tries these rules on these shapes (add them to reference/src/local.rs):\n{}",
        missing.join("\n")
    );
    assert!(tried > 40, "only {tried} pairs");
}

/// The needs can fail: the lab's objects alone (no local shapes) leave
/// most of them without a case.
#[test]
fn the_lab_objects_alone_miss_most_local_shapes() {
    let objects: Vec<Facts> = local_facts("flip")
        .into_iter()
        .filter(|(name, ..)| {
            halfedge::shapes::LAB_OBJECTS
                .iter()
                .any(|o| name.starts_with(o))
        })
        .map(|(.., f)| f)
        .collect();
    assert!(!objects.is_empty());
    let unmet = legal(true)
        .into_iter()
        .chain(refused(true, true, true))
        .filter(|(_, test)| !objects.iter().any(test))
        .count();
    assert!(unmet >= 8, "{unmet}");
}

/// A flip or split that breaks a counted rule (on one side only, or
/// everywhere: the two refusals once graded only as bonus among them), or
/// refuses more than the contract does, fails the plain run, which grades
/// exactly the counted cases, and the summary's line names the rule.
#[test]
fn one_sided_and_over_refusing_operations_fail_the_default_run() {
    const BOUNDARY: &str = "changed a boundary edge: it must return None";
    const NOT_TRIANGLE: &str =
        "changed an edge beside a face that is not a triangle: it must return None";
    const DUPLICATE: &str =
        "changed an edge whose flip would join two vertices already joined by an edge";
    const FLIP_IT: &str =
        "flip_edge returned None for an edge between two triangles: it must flip it";
    const SPLIT_IT: &str =
        "split_edge returned None for an edge between two triangles: it must split it";
    for (mistake, case, says) in [
        ("flip-duplicates", "local-flip-closed-3-6", DUPLICATE),
        ("flip-boundary", "local-flip-hole-left", BOUNDARY),
        ("flip-one-face", "local-flip-quad-left", NOT_TRIANGLE),
        ("flip-twin-face", "local-flip-quad-left", NOT_TRIANGLE),
        ("flip-boundary-one-side", "local-flip-hole-left", BOUNDARY),
        (
            "flip-duplicates-by-degree",
            "local-flip-joined-far",
            DUPLICATE,
        ),
        ("flip-refuses-degree-3", "local-flip-open-3-8", FLIP_IT),
        ("flip-refuses-rim-ends", "local-flip-open-3-8", FLIP_IT),
        ("flip-refuses-high-degree", "cylinder-flip-1", FLIP_IT),
        ("split-one-face", "local-split-quad-left", NOT_TRIANGLE),
        ("split-twin-face", "local-split-quad-hole", NOT_TRIANGLE),
        ("split-refuses-rim-ends", "local-split-open-3-8", SPLIT_IT),
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
                .any(|l| l.contains("[warn] ") && l.contains(case) && l.contains(says)),
            "{mistake}: the summary names {case} and the rule ({says}):\n{}",
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
