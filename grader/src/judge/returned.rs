//! What a flip or split returned, judged first (it says most about an
//! operation that did the wrong thing altogether), and the shape around
//! what it returned, judged last: the flipped edge's new ends, the split
//! vertex's halfedge and the ids a split keeps.

use halfedge::{EdgeId, FaceId, VertexId};

use crate::isolate::end::{Counts, MeshResult, Returned, SplitIds};
use crate::judge::fixture::{Fixture, Operation, Returns, Stage};
use crate::judge::log::{fmt_p, say, Log};
use crate::judge::matching::{self, VertexMatch};
use crate::judge::verdict::Pointer;

/// The input faces beside the case's edge (none for subdivision).
fn faces_beside(f: &Fixture) -> Vec<&Vec<usize>> {
    let (Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] }) = f.operation else {
        return Vec::new();
    };
    f.input
        .faces
        .iter()
        .filter(|face| {
            (0..face.len()).any(|i| {
                let (x, y) = (face[i], face[(i + 1) % face.len()]);
                (x, y) == (a, b) || (x, y) == (b, a)
            })
        })
        .collect()
}

/// The lower degree of the case's edge's ends in the input, where it is 3
/// or less (a refusal that tests degrees refuses legal flips there).
fn low_degree_end(f: &Fixture) -> Option<usize> {
    let (Operation::Flip { edge } | Operation::Split { edge }) = f.operation else {
        return None;
    };
    let degree = |v: usize| {
        let mut neighbours: Vec<usize> = f
            .input
            .faces
            .iter()
            .flat_map(|face| {
                (0..face.len()).filter_map(move |i| {
                    let (x, y) = (face[i], face[(i + 1) % face.len()]);
                    (x == v).then_some(y).or((y == v).then_some(x))
                })
            })
            .collect();
        neighbours.sort_unstable();
        neighbours.dedup();
        neighbours.len()
    };
    let low = edge.map(degree).into_iter().min()?;
    (low <= 3).then_some(low)
}

/// Whether the case's edge borders a hole in the input: it is used by one
/// face only.
fn on_boundary(f: &Fixture) -> bool {
    faces_beside(f).len() == 1
}

/// Why the case's edge must be refused, from the input faces.
fn refusal_reason(f: &Fixture) -> &'static str {
    let beside = faces_beside(f);
    if beside.iter().any(|face| face.len() != 3) {
        "an edge beside a face that is not a triangle"
    } else if on_boundary(f) {
        "a boundary edge"
    } else {
        "an edge whose flip would join two vertices already joined by an edge"
    }
}

/// The return value, judged before anything else: it says most about a flip
/// or split that did the wrong thing altogether.
pub(super) fn check_returned(
    f: &Fixture,
    returned: &Returned,
    before: Counts,
    log: &mut Log,
) -> bool {
    let function = f.operation.stage().function();
    match (&f.expected.returns, returned) {
        (None, _) => true,
        (Some(Returns::Refused), Returned::Nothing) => true,
        (Some(Returns::Refused), _) => {
            say!(
                log,
                Warn,
                "{function} changed {}: it must return None and leave the mesh unchanged",
                refusal_reason(f)
            );
            false
        }
        (Some(Returns::Vertex { .. }), Returned::Nothing) if on_boundary(f) => {
            say!(log, Warn, "split_edge returned None for a boundary edge: it must divide the one real triangle beside it");
            false
        }
        (Some(_), Returned::Nothing) => {
            let flip = f.operation.stage() == Stage::Flip;
            say!(
                log,
                Warn,
                "{function} returned None for an edge between two triangles: it must {} it",
                if flip { "flip" } else { "split" }
            );
            if flip {
                say!(log, Detail, "no rule of the contract refuses it: it is not on the boundary, both faces are triangles, and c and d are not joined yet");
            }
            if let Some(low) = low_degree_end(f) {
                say!(log, Detail, "an end of degree {low} is no reason to refuse: the contract lists every refusal");
            }
            false
        }
        (Some(Returns::Edge { .. }), Returned::Edge { given, got }) if given != got => {
            say!(log, Warn, "flip_edge returned Some(e{got}), but it must return the edge it was given (e{given})");
            log.about([EdgeId(*got).into(), EdgeId(*given).into()]);
            false
        }
        (Some(Returns::Vertex { .. }), Returned::Vertex { id, .. })
            if (*id as usize) < before.vertices =>
        {
            say!(
                log,
                Warn,
                "split_edge returned v{id}, a vertex that was there before the split: it must return the new vertex"
            );
            log.about([VertexId(*id).into()]);
            false
        }
        (Some(Returns::Vertex { position }), Returned::Vertex { id, position: got }) => {
            let Some(got) = got else {
                say!(
                    log,
                    Warn,
                    "split_edge returned v{id}, which is not a vertex of the mesh"
                );
                return false;
            };
            let off = matching::nearest(&[*got], *position).map_or(f64::INFINITY, |n| n.1);
            // A NaN position is off too.
            if off.is_nan() || off > f.tolerance {
                say!(
                    log,
                    Warn,
                    "split vertex is not at the midpoint of the edge: v{id} is at {}",
                    fmt_p(*got)
                );
                log.about([VertexId(*id).into()]);
                say!(
                    log,
                    Detail,
                    "the midpoint is {} ({off:.6} away)",
                    fmt_p(*position)
                );
                return false;
            }
            true
        }
        _ => true,
    }
}

/// What the returned element looks like in the result: the flipped edge's
/// new ends, the split vertex's halfedge.
pub(super) fn check_returned_shape(
    f: &Fixture,
    returned: &Returned,
    mesh: &MeshResult,
    m: &VertexMatch,
    log: &mut Log,
) {
    let to_expected = |i: usize| m.to_expected.get(i).copied().flatten();
    match (&f.expected.returns, returned, f.operation) {
        (Some(Returns::Edge { ends }), Returned::Edge { got, .. }, _) => {
            let got_ends = mesh
                .returned_edge_ends
                .map(|[a, b]| [to_expected(a), to_expected(b)]);
            let want = [Some(ends[0].min(ends[1])), Some(ends[0].max(ends[1]))];
            let got_sorted = got_ends.map(|[a, b]| [a.min(b), a.max(b)]);
            if got_sorted != Some(want) {
                say!(
                    log,
                    Warn,
                    "the returned edge e{got} does not join the two vertices that faced it"
                );
                log.about([EdgeId(*got).into()]);
            }
        }
        (
            Some(Returns::Vertex { .. }),
            Returned::Vertex { id, .. },
            Operation::Split { edge: [a, b] },
        ) => {
            let leads = mesh.returned_vertex_leads_to.and_then(to_expected);
            if leads != Some(a) && leads != Some(b) {
                say!(
                    log,
                    Warn,
                    "the new vertex's halfedge does not run along the split edge"
                );
                log.about([VertexId(*id).into()]);
                log.first_about(Some(Pointer::Vertex));
                say!(log, Detail, "mesh[v{id}].halfedge must lead to vertex {a} or {b}, the ends of the edge that was split");
            }
            if let Some(ids) = &mesh.split {
                check_split_ids(ids, *id, [a, b], &to_expected, log);
            }
        }
        _ => {}
    }
}

/// The contract's rules on ids after a split: the new vertex keeps its
/// defaults, the edge's id names one half of the old edge, the old faces
/// are triangles around the new vertex.
fn check_split_ids(
    ids: &SplitIds,
    m: u32,
    [a, b]: [usize; 2],
    to_expected: &dyn Fn(usize) -> Option<usize>,
    log: &mut Log,
) {
    if ids.is_new || ids.new_pos != [0.0; 3] {
        say!(
            log,
            Warn,
            "split_edge set is_new or new_pos on the new vertex: a split leaves them false and zero (loop_subdivide sets them after the call)"
        );
        say!(
            log,
            Detail,
            "mesh[v{m}].is_new is {}, mesh[v{m}].new_pos is {}",
            ids.is_new,
            fmt_p(ids.new_pos)
        );
        log.about([VertexId(m).into()]);
    }
    let [x, y] = ids.edge_ends;
    let other = if x == m as usize { y } else { x };
    let half = (x == m as usize || y == m as usize)
        && matches!(to_expected(other), Some(o) if o == a || o == b);
    if !half {
        say!(
            log,
            Warn,
            "after split_edge, edge e{} is not half of the edge that was split: it must join the new vertex to one of its ends",
            ids.edge
        );
        say!(
            log,
            Detail,
            "e{} joins v{x} and v{y}; the new vertex is v{m}",
            ids.edge
        );
        log.about([
            EdgeId(ids.edge as u32).into(),
            VertexId(x as u32).into(),
            VertexId(y as u32).into(),
            VertexId(m).into(),
        ]);
    }
    if let Some(f) = ids.faces_away.first() {
        say!(
            log,
            Warn,
            "after split_edge, face f{f} is not one of the triangles around the new vertex: each old face beside the edge must become one of them"
        );
        log.about([FaceId(*f as u32).into()]);
    }
}
