//! The student's mesh against the expected one: vertices matched by
//! position (which kind, old or new, is wrong, and where), then edges
//! (which kinds of vertex the wrong ones join), with the comparison kept
//! as data for the report's pictures.

use halfedge::VertexId;

use crate::isolate::end::{Counts, MeshResult};
use crate::judge::counts::{counts_rule, old_vertices};
use crate::judge::fixture::{Fixture, Operation};
use crate::judge::log::{fmt_p, hint, say, Log};
use crate::judge::matching::{self, VertexMatch};
use crate::judge::verdict::{Comparison, GraderHint, Hint};

/// Your vertices matched to the expected ones, as the comparison's data.
fn vertex_comparison(f: &Fixture, mesh: &MeshResult) -> (VertexMatch, Comparison) {
    let m = matching::match_by_neighbourhood(
        &mesh.positions,
        &mesh.edges,
        &f.expected.positions,
        &f.expected.edges,
        f.tolerance,
    );
    let comparison = Comparison {
        matched: m.to_expected.clone(),
        missing_vertices: m.unmatched_expected.clone(),
        extra_vertices: (0..m.to_expected.len())
            .filter(|&i| m.to_expected[i].is_none())
            .collect(),
        missing_edges: None,
        extra_edges: None,
    };
    (m, comparison)
}

/// Expected vertex -> your id, for a perfect match.
fn student_ids(f: &Fixture, m: &VertexMatch) -> Vec<usize> {
    let mut student_of = vec![0; f.expected.positions.len()];
    for (s, e) in m.to_expected.iter().enumerate() {
        if let Some(e) = e {
            student_of[*e] = s;
        }
    }
    student_of
}

/// The edge difference into the comparison: missing in expected ids,
/// extra in yours.
fn add_edge_comparison(c: &mut Comparison, diff: &matching::EdgeDiff, student_of: &[usize]) {
    c.missing_edges = Some(diff.missing.clone());
    c.extra_edges = Some(
        diff.extra
            .iter()
            .map(|&[a, b]| [student_of[a], student_of[b]])
            .collect(),
    );
}

/// The comparison alone, without a word said: what
/// [`compare_vertices`] and [`compare_edges`] would record, for a case
/// whose verdict stopped before them.
pub(super) fn comparison_of(f: &Fixture, mesh: &MeshResult) -> Comparison {
    let (m, mut c) = vertex_comparison(f, mesh);
    if m.is_perfect() {
        let diff =
            matching::diff_edges(&matching::mapped_edges(&mesh.edges, &m), &f.expected.edges);
        add_edge_comparison(&mut c, &diff, &student_ids(f, &m));
    }
    c
}

pub(super) fn compare_vertices(
    f: &Fixture,
    mesh: &MeshResult,
    before: Counts,
    log: &mut Log,
) -> Option<VertexMatch> {
    let expected = &f.expected;
    say!(log, Info, "compare all vertices...");
    let (got, want) = (mesh.positions.len(), expected.positions.len());
    // Matched even when the counts differ: the verdict is the count, but
    // the report draws which expected vertices none of yours is at.
    let (m, comparison) = vertex_comparison(f, mesh);
    log.comparison = Some(comparison);
    if got != want {
        say!(
            log,
            Warn,
            "number of vertices is wrong: {got} (should be {want})"
        );
        if let Operation::Subdivide { rounds } = f.operation {
            say!(log, Detail, "{}", counts_rule(f, before, rounds));
            if got == before.vertices {
                hint!(log, f, Hint::Grader(GraderHint::NoVertexAdded));
            } else if got > want {
                hint!(log, f, Hint::Grader(GraderHint::TooManyVertices));
            } else {
                hint!(log, f, Hint::Grader(GraderHint::TooFewVertices));
            }
        }
        return None;
    }
    if !m.is_perfect() {
        say!(
            log,
            Warn,
            "at least one of the vertices has incorrect position"
        );
        let wrong = m.unmatched_expected.len();
        say!(
            log,
            Detail,
            "{wrong} of {want} expected vertices have no vertex of yours within {} of them",
            f.tolerance
        );
        if let Operation::Subdivide { .. } = f.operation {
            let old = old_vertices(f, before);
            let old_wrong = m.unmatched_expected.iter().filter(|&&i| i < old).count();
            let new_wrong = wrong - old_wrong;
            let new = want - old;
            let text = match (old_wrong, new_wrong) {
                (0, n) => format!("every old vertex is right; {n} of {new} new vertices are wrong: look at the edge rule (3/8 of the edge's ends, 1/8 of the two far corners, each from the mesh before any change)"),
                (o, 0) => format!("every new vertex is right; {o} of {old} old vertices are wrong: look at the vertex rule (u = 3/16 when n = 3, else 3/(8n), from the neighbours' old positions)"),
                (o, n) => format!("{o} of {old} old vertices and {n} of {new} new vertices are wrong"),
            };
            say!(log, Detail, "{text}");
        }
        if let Some(&i) = m.unmatched_expected.first() {
            let p = expected.positions[i];
            say!(log, Detail, "expected a vertex at {}", fmt_p(p));
            if let Some((j, d)) = matching::nearest(&mesh.positions, p) {
                say!(
                    log,
                    Detail,
                    "your nearest vertex is v{j} at {} ({d:.6} away)",
                    fmt_p(mesh.positions[j])
                );
                log.about([VertexId(j as u32).into()]);
            }
        }
        for mistake in &expected.mistakes {
            if let Some(ps) = &mistake.positions {
                if matching::same_positions(&mesh.positions, ps, f.tolerance) {
                    hint!(log, f, Hint::Catalogue(mistake.id.clone()));
                    break;
                }
            }
        }
        return None;
    }
    say!(log, Info, "passed");
    Some(m)
}

pub(super) fn compare_edges(
    f: &Fixture,
    mesh: &MeshResult,
    before: Counts,
    m: &VertexMatch,
    log: &mut Log,
) -> bool {
    let expected = &f.expected;
    say!(log, Info, "compare all edges...");
    let (got, want) = (mesh.edges.len(), expected.edges.len());
    // Compared before the count is checked: the report draws the
    // difference even when the verdict is the count.
    let mine = matching::mapped_edges(&mesh.edges, m);
    let diff = matching::diff_edges(&mine, &expected.edges);
    let student_of = student_ids(f, m);
    if let Some(c) = &mut log.comparison {
        add_edge_comparison(c, &diff, &student_of);
    }
    if got != want {
        say!(
            log,
            Warn,
            "number of edges is wrong: {got} (should be {want})"
        );
        return false;
    }
    if diff.is_empty() && mine.len() == want {
        say!(log, Info, "passed");
        return true;
    }
    say!(
        log,
        Warn,
        "at least one of the edges connects incorrect vertices"
    );
    let p = |i: usize| fmt_p(expected.positions[i]);
    if let Some(&[a, b]) = diff.missing.first() {
        say!(
            log,
            Detail,
            "missing: an edge between v{} {} and v{} {}",
            student_of[a],
            p(a),
            student_of[b],
            p(b)
        );
        log.about([a, b].map(|x| VertexId(student_of[x] as u32).into()));
    }
    if let Some(&[a, b]) = diff.extra.first() {
        say!(
            log,
            Detail,
            "extra: your edge between v{} {} and v{} {}",
            student_of[a],
            p(a),
            student_of[b],
            p(b)
        );
        log.about([a, b].map(|x| VertexId(student_of[x] as u32).into()));
    }
    if mine.len() != want {
        say!(
            log,
            Detail,
            "two of your edges join the same pair of vertices"
        );
    }
    if let Operation::Subdivide { .. } = f.operation {
        edge_kinds(&diff.missing, &diff.extra, old_vertices(f, before), log);
    }
    for mistake in &expected.mistakes {
        if let Some(edges) = &mistake.edges {
            if matching::diff_edges(&mine, edges).is_empty() {
                hint!(log, f, Hint::Catalogue(mistake.id.clone()));
                break;
            }
        }
    }
    false
}

/// Which kinds of vertex the missing and extra edges of a subdivision join
/// (old: there before the last round), and what that usually means.
fn edge_kinds(missing: &[[usize; 2]], extra: &[[usize; 2]], old: usize, log: &mut Log) {
    // [old-old, old-new, new-new]
    let tally = |edges: &[[usize; 2]]| {
        let mut k = [0usize; 3];
        for &[a, b] in edges {
            k[usize::from(a >= old) + usize::from(b >= old)] += 1;
        }
        k
    };
    let describe = |k: [usize; 3]| {
        let names = [
            "two old vertices",
            "an old and a new vertex",
            "two new vertices",
        ];
        let parts: Vec<String> = k
            .iter()
            .zip(names)
            .filter(|(n, _)| **n > 0)
            .map(|(n, what)| format!("{n} join {what}"))
            .collect();
        parts.join(", ")
    };
    let (lost, added) = (tally(missing), tally(extra));
    if missing.is_empty() && extra.is_empty() {
        return;
    }
    say!(
        log,
        Detail,
        "of the missing edges {}; of your extra edges {}",
        if missing.is_empty() {
            "none".to_string()
        } else {
            describe(lost)
        },
        if extra.is_empty() {
            "none".to_string()
        } else {
            describe(added)
        }
    );
    if added[2] > 0 && lost[1] > 0 {
        say!(log, Detail, "were edges between two new vertices flipped? flip only new edges that join an old and a new vertex");
    } else if lost[2] > 0 && added[1] > 0 {
        say!(
            log,
            Detail,
            "new edges joining an old and a new vertex were left unflipped: flip each of them once"
        );
    }
}
