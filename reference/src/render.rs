//! Turning a case into a fixture: the model solution run on its input
//! (and, for subdivision, every known mistake, so that the grader can name
//! one it sees), written as the stable JSON the grader reads, with each
//! folder's `SHA256SUMS`. The cases themselves are [`crate::cases`]'.

use std::path::{Path, PathBuf};

use grader::judge::fixture::{
    self, Expected, Fixture, Group, Mistake, Operation, Returns, Step, WeightRule, SCHEMA,
};
use halfedge::Mesh;

use crate::cases::{builtin, ends, Case};
use crate::catalogue;
use crate::solution::{self, Weights};

fn rule(w: Weights) -> WeightRule {
    match w {
        Weights::Warren => WeightRule::Warren,
        Weights::Loop => WeightRule::Loop,
    }
}

fn from_rule(w: WeightRule) -> Weights {
    match w {
        WeightRule::Warren => Weights::Warren,
        WeightRule::Loop => Weights::Loop,
    }
}

fn positions(mesh: &Mesh) -> Vec<[f64; 3]> {
    mesh.positions().iter().map(|p| p.to_array()).collect()
}

fn sorted_edges(mesh: &Mesh) -> Vec<[usize; 2]> {
    let mut edges = mesh.edge_list();
    edges.sort_unstable();
    edges
}

/// Runs a sequence's steps with the reference, checking the mesh after
/// each, and returns what each step returned.
fn run_steps(mesh: &mut Mesh, steps: &[Step]) -> Result<Vec<Returns>, String> {
    let mut out = Vec::with_capacity(steps.len());
    for (i, step) in steps.iter().enumerate() {
        let [a, b] = step.edge();
        let e = mesh
            .edge_between(a, b)
            .ok_or_else(|| format!("step {}: no edge between vertices {a} and {b}", i + 1))?;
        let returned = match step {
            Step::Flip { .. } => solution::flip_edge(mesh, e).map(|e| Returns::Edge {
                ends: ends(mesh, e),
            }),
            Step::Split { .. } => solution::split_edge(mesh, e).map(|m| Returns::Vertex {
                position: mesh[m].pos.to_array(),
            }),
        };
        mesh.validate()
            .map_err(|e| format!("step {}: the reference left an invalid mesh: {e}", i + 1))?;
        out.push(returned.unwrap_or(Returns::Refused));
    }
    Ok(out)
}

/// Runs the reference on the case and returns the fixture, or why not.
pub fn make_fixture(case: &Case) -> Result<Fixture, String> {
    let input = case
        .input
        .to_mesh()
        .map_err(|e| format!("input mesh: {e}"))?;
    let mut mesh = input.clone();
    let edge_at = |[a, b]: [usize; 2]| {
        input
            .edge_between(a, b)
            .ok_or_else(|| format!("the input has no edge between vertices {a} and {b}"))
    };
    let mut step_returns = Vec::new();
    let returns = match case.operation {
        Operation::Flip { edge } => {
            let e = edge_at(edge)?;
            match solution::flip_edge(&mut mesh, e) {
                Some(e) => Some(Returns::Edge {
                    ends: ends(&mesh, e),
                }),
                None => Some(Returns::Refused),
            }
        }
        Operation::Split { edge } => {
            let e = edge_at(edge)?;
            match solution::split_edge(&mut mesh, e) {
                Some(m) => Some(Returns::Vertex {
                    position: mesh[m].pos.to_array(),
                }),
                None => Some(Returns::Refused),
            }
        }
        // Not a triangle mesh: the contract says subdivision panics.
        Operation::Subdivide { .. } if !input.is_triangle_mesh() => Some(Returns::Panic),
        Operation::Subdivide { rounds } => {
            for _ in 0..rounds {
                solution::loop_subdivide_with(&mut mesh, case.weights);
            }
            None
        }
        Operation::Sequence { .. } => {
            step_returns = run_steps(&mut mesh, &case.steps)?;
            None
        }
    };
    mesh.validate().map_err(|e| {
        format!(
            "the result does not validate ({e}): the input passed every check of the reader \
                 and builder, so it is degenerate in a way they miss, or the reference has a bug"
        )
    })?;
    let mut expected = Expected {
        returns,
        steps: step_returns,
        positions: positions(&mesh),
        edges: sorted_edges(&mesh),
        mistakes: Vec::new(),
    };
    let closed = input.edge_ids().all(|e| !input.edge_on_boundary(e));
    if closed && case.weights == Weights::Warren && expected.returns.is_none() {
        match case.operation {
            Operation::Subdivide { rounds: 1 } => {
                expected.mistakes = mistakes(&input, &expected, case.tolerance);
            }
            Operation::Subdivide { rounds: 2 } => {
                expected.mistakes =
                    second_round_mistakes(&input, case.weights, &expected, case.tolerance);
            }
            _ => {}
        }
    }
    Ok(Fixture {
        schema: SCHEMA,
        name: case.name.clone(),
        object: case.object.clone(),
        group: case.group,
        input: case.input.clone(),
        operation: case.operation,
        steps: case.steps.clone(),
        weights: rule(case.weights),
        tolerance: case.tolerance,
        expected,
    })
}

/// What each known mistake makes of the input, where it differs from the
/// expected result enough for the grader to tell.
fn mistakes(input: &Mesh, expected: &Expected, tolerance: f64) -> Vec<Mistake> {
    let mut out = Vec::new();
    for known in catalogue::subdivision_mistakes() {
        let mut mesh = input.clone();
        (known.run)(&mut mesh);
        if let Some(m) = mistake_of(&known, &mesh, expected, tolerance) {
            out.push(m);
        }
    }
    out
}

/// What a mistake's result looks like next to the expected one: its
/// positions (when it moves vertices), its edges (when it only relinks), or
/// `validate()`'s message (when it breaks the mesh). `None` when the grader
/// could not tell it from the right answer.
fn mistake_of(
    known: &catalogue::KnownMistake,
    mesh: &Mesh,
    expected: &Expected,
    tolerance: f64,
) -> Option<Mistake> {
    let mut m = Mistake {
        id: known.id.to_string(),
        hint: known.hint.to_string(),
        positions: None,
        edges: None,
        invalid: None,
    };
    if let Err(e) = mesh.validate() {
        m.invalid = Some(e.check);
        return Some(m);
    }
    let ps = positions(mesh);
    let edges = sorted_edges(mesh);
    let moved = !grader::judge::matching::same_positions(&ps, &expected.positions, tolerance);
    let relinked = edges != expected.edges;
    if !(moved || relinked) {
        return None;
    }
    // Stored to 1e-7, well inside any tolerance the grader matches them
    // with (at least 1e-12 of the mesh's size, 1e-5 here): less than half
    // the digits to write, and to parse on every grader run.
    m.positions = moved.then(|| {
        ps.iter()
            .map(|p| p.map(|x| (x * 1e7).round() / 1e7))
            .collect()
    });
    m.edges = (relinked && !moved).then_some(edges);
    Some(m)
}

/// What each known mistake makes of two rounds: the mistake made twice,
/// as a student's code would (stale flags show only then); one that breaks
/// the mesh in round one is stored as round one's broken mesh, which is
/// what the grader sees.
fn second_round_mistakes(
    input: &Mesh,
    weights: Weights,
    expected: &Expected,
    tolerance: f64,
) -> Vec<Mistake> {
    let mut right = input.clone();
    solution::loop_subdivide_with(&mut right, weights);
    let one_round = Expected {
        returns: None,
        steps: Vec::new(),
        positions: positions(&right),
        edges: sorted_edges(&right),
        mistakes: Vec::new(),
    };
    let mut out = Vec::new();
    for known in catalogue::subdivision_mistakes() {
        let mut mesh = input.clone();
        (known.run)(&mut mesh);
        // A mistake round one shows already broke the mesh there: a second
        // round would only walk its broken links.
        if mesh.validate().is_err() {
            if let Some(m) = mistake_of(&known, &mesh, &one_round, tolerance) {
                out.push(m);
            }
            continue;
        }
        (known.run)(&mut mesh);
        if let Some(m) = mistake_of(&known, &mesh, expected, tolerance) {
            out.push(m);
        }
    }
    out
}

/// A fixture file's case, to regenerate it.
pub fn case_of(f: fixture::CaseFile) -> Case {
    Case {
        name: f.name,
        object: f.object,
        group: f.group,
        input: f.input,
        operation: f.operation,
        steps: f.steps,
        weights: from_rule(f.weights),
        tolerance: f.tolerance,
    }
}

/// Every fixture file under `root` that the built-in cases do not cover:
/// cases a TA added. Read leniently (the expected part may be stale), but
/// a file that is not a fixture at all is an error naming it.
pub fn added_cases(root: &Path, builtin: &[Case]) -> Result<Vec<Case>, String> {
    let mut out = Vec::new();
    for (group, path) in fixture::fixture_files(root).map_err(|e| e.to_string())? {
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
        if builtin.iter().any(|c| c.name == stem && c.group == group) {
            continue;
        }
        let f = fixture::load_case(&path).map_err(|e| e.to_string())?;
        out.push(case_of(f));
    }
    Ok(out)
}

/// Rewrites each group folder's `SHA256SUMS` from the fixture files in it
/// (after `add` wrote a new one).
pub fn write_sums(root: &Path) -> Result<(), String> {
    let files = fixture::fixture_files(root).map_err(|e| e.to_string())?;
    for group in Group::ALL {
        let listed: Vec<(String, Vec<u8>)> = files
            .iter()
            .filter(|(g, _)| *g == group)
            .map(|(_, p)| {
                let bytes = std::fs::read(p).map_err(|e| format!("{}: {e}", p.display()))?;
                Ok((
                    p.file_name()
                        .expect("a file")
                        .to_string_lossy()
                        .into_owned(),
                    bytes,
                ))
            })
            .collect::<Result<_, String>>()?;
        if !listed.is_empty() {
            let path = root
                .join(group.name())
                .join(grader::judge::digest::SUMS_FILE);
            std::fs::write(&path, grader::judge::digest::sums_text(&listed))
                .map_err(|e| format!("{}: {e}", path.display()))?;
        }
    }
    Ok(())
}

/// Every fixture file's path (relative to the root) and text, and each
/// group folder's `SHA256SUMS` of them.
pub fn render_all(root: &Path, weights: Weights) -> Result<Vec<(PathBuf, String)>, String> {
    let builtin = builtin(weights);
    let added = added_cases(root, &builtin)?;
    let mut names = std::collections::HashSet::new();
    let mut files = builtin
        .iter()
        .chain(&added)
        .map(|c| {
            if !names.insert(c.name.clone()) {
                return Err(format!("two cases are named {:?}", c.name));
            }
            let f = make_fixture(c).map_err(|e| format!("case {}: {e}", c.name))?;
            Ok((f.relative_path(), fixture::to_json_text(&f)))
        })
        .collect::<Result<Vec<_>, String>>()?;
    let mut sums = Vec::new();
    for group in Group::ALL {
        let listed: Vec<(String, Vec<u8>)> = files
            .iter()
            .filter(|(p, _)| p.starts_with(group.name()))
            .map(|(p, text)| {
                let name = p
                    .file_name()
                    .expect("a file")
                    .to_string_lossy()
                    .into_owned();
                (name, text.clone().into_bytes())
            })
            .collect();
        if !listed.is_empty() {
            sums.push((
                Path::new(group.name()).join(grader::judge::digest::SUMS_FILE),
                grader::judge::digest::sums_text(&listed),
            ));
        }
    }
    files.extend(sums);
    Ok(files)
}
