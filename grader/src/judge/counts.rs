//! How many elements a result must have: exact numbers for a flip or a
//! split, and for subdivision the counts each round's rule gives, said
//! with the rule.

use crate::isolate::end::Counts;
use crate::judge::fixture::{Fixture, Operation, Returns};
use crate::judge::log::{say, Log};

/// Flips and splits add an exact number of elements.
pub(super) fn check_counts(f: &Fixture, before: Counts, after: Counts, log: &mut Log) -> bool {
    let function = f.operation.stage().function();
    let expected = match (&f.operation, &f.expected.returns) {
        (Operation::Flip { .. }, _) | (_, Some(Returns::Refused)) => before,
        (Operation::Split { .. }, _) => {
            // Split adds one vertex, an edge for the other half of the old
            // one, and an edge and a face per triangle it divides.
            let divided = f.expected.edges.len().saturating_sub(before.edges + 1);
            Counts {
                vertices: before.vertices + 1,
                edges: before.edges + 1 + divided,
                faces: before.faces + divided,
                halfedges: before.halfedges + 2 + 2 * divided,
            }
        }
        (Operation::Subdivide { rounds }, _) => {
            return check_subdivided_counts(f, before, after, *rounds, log)
        }
        // Judged step by step in `judge_sequence`.
        (Operation::Sequence { .. }, _) => return true,
    };
    if after == expected {
        return true;
    }
    let c = |c: Counts| {
        format!(
            "{} vertices, {} edges, {} faces, {} halfedges",
            c.vertices, c.edges, c.faces, c.halfedges
        )
    };
    match f.operation {
        Operation::Flip { .. } => say!(
            log,
            Warn,
            "flip_edge added or removed elements: a flip only relinks"
        ),
        _ if f.expected.returns == Some(Returns::Refused) => {
            say!(
                log,
                Warn,
                "{function} added or removed elements on an edge it must refuse"
            )
        }
        _ => say!(log, Warn, "split_edge added the wrong number of elements"),
    }
    say!(log, Detail, "before: {}", c(before));
    say!(log, Detail, "after:  {}", c(after));
    say!(log, Detail, "should: {}", c(expected));
    false
}

/// What `rounds` of the lab's subdivision make of the input's counts: each
/// round adds a vertex per edge (V' = V + E), splits every edge in two and
/// adds three inside every triangle (E' = 2E + 3T), and makes every
/// triangle four (T' = 4T); holes stay holes.
struct Subdivided {
    vertices: usize,
    edges: usize,
    triangles: usize,
    holes: usize,
}

fn subdivided(f: &Fixture, before: Counts, rounds: usize) -> Subdivided {
    let triangles = f.input.faces.len();
    let mut s = Subdivided {
        vertices: before.vertices,
        edges: before.edges,
        triangles,
        holes: before.faces.saturating_sub(triangles),
    };
    for _ in 0..rounds {
        s.vertices += s.edges;
        s.edges = 2 * s.edges + 3 * s.triangles;
        s.triangles *= 4;
    }
    s
}

/// The plain-words account of a subdivision's counts, for the first count
/// that is off.
pub(super) fn counts_rule(f: &Fixture, before: Counts, rounds: usize) -> String {
    let want = subdivided(f, before, rounds);
    let t = f.input.faces.len();
    let holes = if want.holes > 0 {
        format!(
            " (and {} hole{}, which stay holes)",
            want.holes,
            if want.holes == 1 { "" } else { "s" }
        )
    } else {
        String::new()
    };
    format!(
        "each round adds one vertex per edge (V' = V + E), splits every edge in two and adds three \
         inside every triangle (E' = 2E + 3F), and makes every triangle four (F' = 4F): from {} \
         vertices, {} edges and {t} triangles{holes}, {rounds} round{} {} vertices, {} edges, {} \
         triangles",
        before.vertices,
        before.edges,
        if rounds == 1 { " gives" } else { "s give" },
        want.vertices,
        want.edges,
        want.triangles
    )
}

/// Subdivision's counts: vertices first (their message and hints are
/// [`compare_vertices`]'s), then edges, then faces, before any shape.
fn check_subdivided_counts(
    f: &Fixture,
    before: Counts,
    after: Counts,
    rounds: usize,
    log: &mut Log,
) -> bool {
    let want = subdivided(f, before, rounds);
    if after.vertices != want.vertices {
        return true;
    }
    if after.edges != want.edges {
        say!(
            log,
            Warn,
            "number of edges is wrong: {} (should be {})",
            after.edges,
            want.edges
        );
        say!(log, Detail, "{}", counts_rule(f, before, rounds));
        say!(log, Detail, "the vertices are counted right, so the edges made around each new vertex are off: split_edge adds 3 edges (2 beside a hole)");
        return false;
    }
    let faces = want.triangles + want.holes;
    if after.faces != faces {
        say!(
            log,
            Warn,
            "number of faces is wrong: {} (should be {faces})",
            after.faces
        );
        say!(log, Detail, "{}", counts_rule(f, before, rounds));
        say!(
            log,
            Detail,
            "split_edge adds 2 faces (1 beside a hole); a flip adds none"
        );
        return false;
    }
    true
}

/// How many of the expected result's vertices were there before the last
/// operation (the expected result keeps their ids and appends new ones): the
/// input's for a flip or split, the last round's input for subdivision.
pub(super) fn old_vertices(f: &Fixture, before: Counts) -> usize {
    match f.operation {
        Operation::Subdivide { rounds } => subdivided(f, before, rounds.saturating_sub(1)).vertices,
        _ => before.vertices,
    }
}
