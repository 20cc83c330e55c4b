//! What a student might get wrong in the Catmull-Clark lab: one round of
//! subdivision per common mistake, each a `fn(&mut Mesh)` with a name and a
//! one-line hint, for the grader to recognise a result by (as the Loop
//! lab's fixtures store what each of its mistakes produces).
//!
//! Each differs from the model ([`super::catmull_clark`]) in one step
//! only, built from the model's own steps, so that what it produces is
//! exactly that one mistake's.

use halfedge::{DVec3, EdgeId, FaceId, HalfedgeId, Mesh};

use super::catmull_clark::{
    self as model, around_vertex, bisect_edge, clear_marks, edge_points, face_points,
    interior_point, join_centre, move_vertices, split_faces, vertex_points,
};

/// One named mistake: a whole round of subdivision done wrong one way.
#[derive(Clone, Copy, Debug)]
pub struct Mistake {
    /// A stable name for data (kebab-case).
    pub name: &'static str,
    /// What to tell a student whose result is this one.
    pub hint: &'static str,
    /// The round, with the student's signature.
    pub subdivide: fn(&mut Mesh),
}

/// Every named mistake.
pub const MISTAKES: [Mistake; 7] = [
    Mistake {
        name: "edge-point-midpoint",
        hint: "an edge point is the mean of the edge's two ends and the face points of its two \
               faces, (a + b + f0 + f1) / 4; the plain midpoint is for edges on a hole only",
        subdivide: edge_point_midpoint,
    },
    Mistake {
        name: "r-from-edge-points",
        hint: "R in (F + 2R + (n - 3) P) / n is the mean of the midpoints of the vertex's edges, \
               not of their edge points",
        subdivide: r_from_edge_points,
    },
    Mistake {
        name: "vertex-weights-r-once",
        hint: "the vertex rule is (F + 2R + (n - 3) P) / n: R, the mean of the edge midpoints, \
               counts twice and P n - 3 times",
        subdivide: vertex_weights_r_once,
    },
    Mistake {
        name: "vertex-weights-f-twice",
        hint: "the vertex rule is (F + 2R + (n - 3) P) / n: it is R, the mean of the edge \
               midpoints, that counts twice, not F, the mean of the face points",
        subdivide: vertex_weights_f_twice,
    },
    Mistake {
        name: "face-points-from-moved-vertices",
        hint: "the face points were placed at the mean of corners that had already moved: \
               compute every point on the unchanged mesh, and move the vertices last",
        subdivide: face_points_from_moved_vertices,
    },
    Mistake {
        name: "split-before-bisecting-all",
        hint: "faces were split before all their edges were bisected: bisect every old edge \
               first, then split every old face (split_face_to_quads refuses a face whose \
               corners do not alternate)",
        subdivide: split_before_bisecting_all,
    },
    Mistake {
        name: "old-vertices-not-moved",
        hint: "the old vertices kept their positions: each moves to (F + 2R + (n - 3) P) / n \
               (on a hole, (x + 6P + y) / 8 unless it is a corner)",
        subdivide: old_vertices_not_moved,
    },
];

/// The mistake named `name`, if there is one.
pub fn mistake(name: &str) -> Option<Mistake> {
    MISTAKES.into_iter().find(|m| m.name == name)
}

/// The model's round with the vertex rule away from holes replaced, and
/// `edges` (if given) run after the model's edge points.
fn round_with(mesh: &mut Mesh, interior: model::InteriorRule, edges: Option<fn(&mut Mesh)>) {
    clear_marks(mesh);
    let points = face_points(mesh);
    edge_points(mesh, &points);
    if let Some(change) = edges {
        change(mesh);
    }
    vertex_points(mesh, &points, interior);
    let old_edges: Vec<EdgeId> = mesh.edge_ids().collect();
    let old_faces = mesh.real_face_ids();
    model::bisect_edges(mesh, &old_edges);
    split_faces(mesh, &old_faces, &points);
    move_vertices(mesh);
}

/// Every edge point at the edge's midpoint, interior edges too.
pub fn edge_point_midpoint(mesh: &mut Mesh) {
    round_with(
        mesh,
        interior_point,
        Some(|mesh: &mut Mesh| {
            for e in mesh.edge_ids() {
                mesh[e].new_pos = mesh.edge_center(e);
            }
        }),
    );
}

/// R as the mean of the edge points (already in the edges' `new_pos`).
pub fn r_from_edge_points(mesh: &mut Mesh) {
    round_with(
        mesh,
        |mesh, v, points| {
            let (n, f, _) = around_vertex(mesh, v, points);
            let out = mesh.vertex_halfedges(v);
            let r = out
                .iter()
                .map(|&h| mesh[mesh[h].edge].new_pos)
                .sum::<DVec3>()
                / n as f64;
            let n_f = n as f64;
            (f + 2.0 * r + (n_f - 3.0) * mesh[v].pos) / n_f
        },
        None,
    );
}

/// `(F + R + (n - 2) P) / n`.
pub fn vertex_weights_r_once(mesh: &mut Mesh) {
    round_with(
        mesh,
        |mesh, v, points| {
            let (n, f, r) = around_vertex(mesh, v, points);
            let n_f = n as f64;
            (f + r + (n_f - 2.0) * mesh[v].pos) / n_f
        },
        None,
    );
}

/// `(2F + R + (n - 3) P) / n`.
pub fn vertex_weights_f_twice(mesh: &mut Mesh) {
    round_with(
        mesh,
        |mesh, v, points| {
            let (n, f, r) = around_vertex(mesh, v, points);
            let n_f = n as f64;
            (2.0 * f + r + (n_f - 3.0) * mesh[v].pos) / n_f
        },
        None,
    );
}

/// The old vertices moved after bisecting and before splitting, so each
/// face point lands at the mean of the moved corners (the edge points and
/// the vertex points are right).
pub fn face_points_from_moved_vertices(mesh: &mut Mesh) {
    clear_marks(mesh);
    let points = face_points(mesh);
    edge_points(mesh, &points);
    vertex_points(mesh, &points, interior_point);
    let old_vertices = mesh.num_vertices();
    let old_edges: Vec<EdgeId> = mesh.edge_ids().collect();
    let old_faces = mesh.real_face_ids();
    model::bisect_edges(mesh, &old_edges);
    for v in mesh.vertex_ids().take(old_vertices) {
        mesh[v].pos = mesh[v].new_pos;
    }
    for f in old_faces {
        let c = model::split_face_to_quads(mesh, f).expect("every edge is bisected");
        mesh[c].new_pos = mesh[c].pos;
    }
    move_vertices(mesh);
}

/// One pass over the old edges, each bisected and then each old face
/// beside it split at once, at its (right) face point, as soon as it has
/// two marked corners, by a split that joins whatever corners are marked
/// (the model's refuses such a face). The face's later bisections add
/// corners to its pieces, which are never split: faces of 5 and more sides
/// remain.
pub fn split_before_bisecting_all(mesh: &mut Mesh) {
    clear_marks(mesh);
    let points = face_points(mesh);
    edge_points(mesh, &points);
    vertex_points(mesh, &points, interior_point);
    let old_edges: Vec<EdgeId> = mesh.edge_ids().collect();
    // Each old edge's two faces, read before anything changes.
    let beside: Vec<[FaceId; 2]> = old_edges
        .iter()
        .map(|&e| {
            let h = mesh[e].halfedge;
            [mesh[h].face, mesh[mesh[h].twin].face]
        })
        .collect();
    let mut split = vec![false; mesh.num_faces()];
    for (&e, faces) in old_edges.iter().zip(&beside) {
        let m = bisect_edge(mesh, e).expect("bisect_edge refuses nothing");
        mesh[m].new_pos = mesh[e].new_pos;
        for &f in faces {
            if mesh[f].is_boundary || split[f.index()] {
                continue;
            }
            let mut around = mesh.face_halfedges(f);
            let is_marked = |mesh: &Mesh, h: HalfedgeId| mesh[mesh[h].vertex].is_new;
            let Some(first) = around.iter().position(|&h| is_marked(mesh, h)) else {
                continue;
            };
            around.rotate_left(first);
            let marked: Vec<usize> = (0..around.len())
                .filter(|&i| is_marked(mesh, around[i]))
                .collect();
            if marked.len() < 2 {
                continue;
            }
            let c = join_centre(mesh, &around, &marked, points[f.index()]);
            mesh[c].new_pos = points[f.index()];
            split[f.index()] = true;
        }
    }
    move_vertices(mesh);
}

/// Every old vertex's `new_pos` is its own position, on a hole too (the
/// new vertices are right).
pub fn old_vertices_not_moved(mesh: &mut Mesh) {
    clear_marks(mesh);
    let points = face_points(mesh);
    edge_points(mesh, &points);
    for v in mesh.vertex_ids() {
        mesh[v].new_pos = mesh[v].pos;
    }
    let old_edges: Vec<EdgeId> = mesh.edge_ids().collect();
    let old_faces = mesh.real_face_ids();
    model::bisect_edges(mesh, &old_edges);
    split_faces(mesh, &old_faces, &points);
    move_vertices(mesh);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_kebab_case_and_hints_one_line() {
        let mut names: Vec<&str> = MISTAKES.iter().map(|m| m.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), MISTAKES.len());
        for m in MISTAKES {
            assert!(
                m.name.chars().all(|c| c.is_ascii_lowercase() || c == '-'),
                "{}",
                m.name
            );
            assert!(
                !m.hint.contains('\n') && !m.hint.contains("  "),
                "{}",
                m.hint
            );
            assert!(mistake(m.name).is_some());
        }
        assert!(mistake("no-such-mistake").is_none());
    }
}
