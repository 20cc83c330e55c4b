//! The step-through of a student's `loop_subdivide`: the frames the child
//! recorded (the mesh before each vertex the code created, see
//! `halfedge::recording`), the end state, and the first frame after which
//! the mesh no longer validates or a split's vertex is away from the
//! midpoint of the edge it split. Judged here, in the parent, on data only.

use halfedge::{EdgeId, Element, Mesh, VertexId};
use serde::Serialize;

use crate::isolate::end::Problem;
use crate::isolate::wire::Recorded;
use crate::judge::named::Named;

/// A subdivision's frames, for the report's slider.
#[derive(Clone, Debug, Serialize)]
pub struct Frames {
    /// Each frame's label ("before split 3", "after loop_subdivide") and
    /// mesh (in the numbering of the input sent, new elements appended).
    #[serde(skip)]
    pub frames: Vec<(String, Mesh)>,
    /// The labels alone, for JSON.
    pub labels: Vec<String>,
    /// The first frame that shows a broken mesh or a misplaced split
    /// vertex (an index into `frames`).
    pub first_broken: Option<usize>,
    /// What is wrong there, as data.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub broken: Option<Broken>,
    /// Why the recording stopped early, when a bound cut it.
    pub cut: Option<String>,
    /// Why frames were not judged, when they could not be (the code
    /// changes the mesh before it creates a split's vertex, so no frame
    /// falls between two splits).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unjudged: Option<String>,
}

/// What the first broken frame shows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Broken {
    /// Which split (1 for the first) left it.
    pub split: usize,
    /// `invalid` or `off-midpoint`.
    pub kind: &'static str,
    /// The edge the split divided, when it could be found, and the
    /// split's vertex.
    pub edge: Option<Named>,
    pub vertex: Named,
    /// The detail line under the failure.
    #[serde(skip)]
    pub line: String,
    /// The elements the line names.
    #[serde(skip)]
    pub elements: Vec<Element>,
}

/// "1st", "2nd", "3rd", "7th", "11th", "22nd".
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// The neighbours of `v` from the raw records (the mesh may be broken:
/// nothing is walked, every index is checked).
fn raw_neighbours(mesh: &Mesh, v: VertexId) -> Vec<VertexId> {
    let (_, _, _, hs) = mesh.records();
    let mut out: Vec<VertexId> = hs
        .iter()
        .filter(|h| h.vertex == v)
        .filter_map(|h| hs.get(h.twin.index()).map(|t| t.vertex))
        .filter(|&w| w != v && w.index() < mesh.num_vertices())
        .collect();
    out.sort();
    out.dedup();
    out
}

/// Whether some halfedge runs from `a` to `b` (raw records).
fn raw_joined(mesh: &Mesh, a: VertexId, b: VertexId) -> bool {
    let (_, _, _, hs) = mesh.records();
    hs.iter()
        .any(|h| h.vertex == a && hs.get(h.twin.index()).is_some_and(|t| t.vertex == b))
}

/// The edge split `k` divided: two neighbours of its vertex `m` in
/// `after` that were joined in `before` and are not any more.
fn split_edge_of(before: &Mesh, after: &Mesh, m: VertexId) -> Option<(EdgeId, VertexId, VertexId)> {
    let old = before.num_vertices();
    let ns: Vec<VertexId> = raw_neighbours(after, m)
        .into_iter()
        .filter(|w| w.index() < old)
        .collect();
    for (i, &a) in ns.iter().enumerate() {
        for &b in &ns[i + 1..] {
            if raw_joined(before, a, b) && !raw_joined(after, a, b) {
                let e = before.edge_between(a.index(), b.index())?;
                return Some((e, a, b));
            }
        }
    }
    None
}

/// Reads a recording: `result` is the mesh the function left (the last
/// frame), `input` the mesh sent, `tolerance` the case's.
pub fn read(recorded: Recorded, result: Option<&Mesh>, input: &Mesh, tolerance: f64) -> Frames {
    let cut = recorded.cut.map(|c| match c {
        halfedge::recording::Cut::Frames(n) => {
            format!("the recording stopped at its limit of {n} frames")
        }
        halfedge::recording::Cut::Bytes(n) => {
            format!("the recording stopped at its limit of {} MiB", n >> 20)
        }
    });
    let n = recorded.frames.len();
    let mut frames: Vec<(String, Mesh)> = recorded
        .frames
        .into_iter()
        .enumerate()
        .map(|(i, m)| (format!("before split {}", i + 1), m))
        .collect();
    // The end state follows only an uncut recording: after a cut, frames
    // are missing in between.
    if let (Some(r), None) = (result, &cut) {
        frames.push(("after loop_subdivide".to_string(), r.clone()));
    }
    let mut out = Frames {
        labels: frames.iter().map(|(l, _)| l.clone()).collect(),
        frames: Vec::new(),
        first_broken: None,
        broken: None,
        cut,
        unjudged: None,
    };
    let valid = |m: &Mesh| -> Result<(), Problem> {
        crate::isolate::guard::guarded(|| m.validate().map_err(Problem::of))
            .unwrap_or_else(|(message, _)| Err(Problem::Unwalkable { message }))
    };
    if n == 0 {
        out.frames = frames;
        return out;
    }
    if input.validate().is_ok() && valid(&frames[0].1).is_err() {
        out.unjudged = Some(
            "your split_edge changes the mesh before it creates its vertex, so no frame falls between two splits".to_string(),
        );
        out.frames = frames;
        return out;
    }
    // The splits that end a round: the frame after one holds the round's
    // flips and moves too.
    let mut round_ends = Vec::new();
    let (mut edges, mut triangles, mut total) = (input.num_edges(), input.num_real_faces(), 0);
    while total <= frames.len() {
        total += edges;
        round_ends.push(total);
        edges = 2 * edges + 3 * triangles;
        triangles *= 4;
    }
    for k in 0..frames.len() - 1 {
        let (before, after) = (&frames[k].1, &frames[k + 1].1);
        let last = k + 1 == frames.len() - 1 && out.cut.is_none() && result.is_some();
        let m = VertexId(before.num_vertices() as u32);
        let split = k + 1;
        let found = split_edge_of(before, after, m);
        let edge_words = |found: Option<(EdgeId, VertexId, VertexId)>| match found {
            Some((e, a, b)) => {
                let made = [a, b]
                    .into_iter()
                    .filter(|x| x.index() >= input.num_vertices())
                    .map(|x| format!("{x}"))
                    .collect::<Vec<_>>();
                let beside = match made.as_slice() {
                    [] => String::new(),
                    [x] => format!(", beside {x}, which an earlier split made"),
                    _ => ", between two vertices earlier splits made".to_string(),
                };
                format!(" (edge {e} between {a} and {b}{beside})")
            }
            None => String::new(),
        };
        let mut elements: Vec<Element> = vec![m.into()];
        if let Some((e, a, b)) = found {
            elements.extend([Element::from(e), a.into(), b.into()]);
        }
        let broken = |kind, line: String, elements: Vec<Element>| Broken {
            split,
            kind,
            edge: found.map(|(e, ..)| Named::seen(e)),
            vertex: Named::seen(m),
            line,
            elements,
        };
        if let Err(problem) = valid(after) {
            let round_end = round_ends.iter().position(|&e| e == split);
            let when = if let Some(r) = round_end {
                format!(
                    "'s {} split, the last of round {}, or the flips and moves after it in that round,",
                    ordinal(split),
                    r + 1
                )
            } else if last {
                format!(
                    "after its {} split, by the end (the flips and moves after it included)",
                    ordinal(split)
                )
            } else {
                format!("'s {} split{}", ordinal(split), edge_words(found))
            };
            let line = if last && round_end.is_none() {
                format!("your loop_subdivide left an invalid mesh {when}: {problem}")
            } else {
                format!("your loop_subdivide{when} left an invalid mesh: {problem}")
            };
            elements.extend(problem.element());
            out.first_broken = Some(k + 1);
            out.broken = Some(broken("invalid", line, elements));
            break;
        }
        if last {
            break;
        }
        // After a round's last split come its flips and moves: positions
        // are no longer the splits' there.
        if round_ends.contains(&split) {
            continue;
        }
        if let Some((_, a, b)) = found {
            let mid = (before[a].pos + before[b].pos) / 2.0;
            let p = after[m].pos;
            // A NaN distance is off too.
            let off = p.distance(mid);
            if off.is_nan() || off > tolerance {
                let line = format!(
                    "your loop_subdivide's {} split{} put {m} at ({:.6}, {:.6}, {:.6}), not at the edge's midpoint ({:.6}, {:.6}, {:.6})",
                    ordinal(split),
                    edge_words(found),
                    p.x, p.y, p.z, mid.x, mid.y, mid.z
                );
                out.first_broken = Some(k + 1);
                out.broken = Some(broken("off-midpoint", line, elements));
                break;
            }
        }
    }
    out.frames = frames;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ordinals() {
        let got: Vec<String> = [1, 2, 3, 4, 7, 11, 12, 13, 21, 22, 101, 111]
            .into_iter()
            .map(ordinal)
            .collect();
        assert_eq!(
            got,
            [
                "1st", "2nd", "3rd", "4th", "7th", "11th", "12th", "13th", "21st", "22nd", "101st",
                "111th"
            ]
        );
    }
}
