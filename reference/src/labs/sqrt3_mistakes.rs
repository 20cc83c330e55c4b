//! The √3 lab's first named mistakes: each one round of `sqrt3_subdivide`
//! on a closed mesh gone wrong in one way, with the hint the grader is to
//! print when a student's result matches it (the Loop lab's
//! [`KnownMistake`] shape, so the fixture generator can store them the same
//! way once the lab is wired in).

use halfedge::{DVec3, EdgeId, FaceId, Mesh};

use super::sqrt3::{alpha, flip_edge, split_face};
use crate::catalogue::KnownMistake;

/// The mistakes, each a whole round with a one-line hint that says what
/// went wrong and what the lab asks for instead.
pub fn sqrt3_mistakes() -> Vec<KnownMistake> {
    let m = |id, hint, run| KnownMistake { id, hint, run };
    vec![
        m("flip-new-edges", "new edges were flipped too: flip only the edges that existed before the round (take the list before the first split_face), never the ones joining a corner to a new vertex", flip_new_edges),
        m("loop-weights", "the old vertices moved with the Loop lab's weights (u = 3/(8n), 3/16 when n = 3); √3 moves each to (1 - a_n) * v + a_n / n * (sum of its neighbours), a_n = (4 - 2 cos(2 pi / n)) / 9", loop_weights),
        m("in-place", "the old vertices were moved while new positions were still being computed, so later vertices read moved neighbours: store each in new_pos and move every old vertex at the end", in_place),
        m("centroids-moved", "the new vertices sit at centroids of the moved corners: split the faces before moving the old vertices, so each centroid comes from the old positions", centroids_moved),
    ]
}

/// The ways a round here can go wrong (all `false`: the model's round).
#[derive(Clone, Copy, Default)]
struct Slips {
    loop_weights: bool,
    in_place: bool,
    move_before_split: bool,
    flip_new: bool,
}

fn flip_new_edges(mesh: &mut Mesh) {
    round(
        mesh,
        Slips {
            flip_new: true,
            ..Slips::default()
        },
    );
}

fn loop_weights(mesh: &mut Mesh) {
    round(
        mesh,
        Slips {
            loop_weights: true,
            ..Slips::default()
        },
    );
}

fn in_place(mesh: &mut Mesh) {
    round(
        mesh,
        Slips {
            in_place: true,
            ..Slips::default()
        },
    );
}

fn centroids_moved(mesh: &mut Mesh) {
    round(
        mesh,
        Slips {
            move_before_split: true,
            ..Slips::default()
        },
    );
}

/// One round of `sqrt3_subdivide` on a closed triangle mesh, with `slips`.
fn round(mesh: &mut Mesh, slips: Slips) {
    let old_vertices: Vec<_> = mesh.vertex_ids().collect();
    for &v in &old_vertices {
        let neighbours = mesh.vertex_neighbors(v);
        let n = neighbours.len();
        let sum: DVec3 = neighbours.iter().map(|&q| mesh[q].pos).sum();
        let p = mesh[v].pos;
        let new = if slips.loop_weights {
            let u = if n == 3 {
                3.0 / 16.0
            } else {
                3.0 / (8.0 * n as f64)
            };
            (1.0 - n as f64 * u) * p + u * sum
        } else {
            (1.0 - alpha(n)) * p + alpha(n) / n as f64 * sum
        };
        mesh[v].new_pos = new;
        if slips.in_place {
            mesh[v].pos = new;
        }
    }
    let move_old = |mesh: &mut Mesh| {
        for &v in &old_vertices {
            mesh[v].pos = mesh[v].new_pos;
        }
    };
    if slips.move_before_split {
        move_old(mesh);
    }
    let old_faces: Vec<FaceId> = mesh.face_ids().collect();
    let old_edges: Vec<EdgeId> = mesh.edge_ids().collect();
    for f in old_faces {
        split_face(mesh, f);
    }
    let to_flip: Vec<EdgeId> = if slips.flip_new {
        mesh.edge_ids().collect()
    } else {
        old_edges
    };
    for e in to_flip {
        flip_edge(mesh, e);
    }
    move_old(mesh);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With no slip, `round` is the model's round, so each mistake differs
    /// from the model by its one slip only.
    #[test]
    fn without_a_slip_the_round_is_the_model() {
        for name in ["cube", "torus"] {
            let mut ours = halfedge::shapes::lab_object(name).unwrap();
            let mut model = ours.clone();
            round(&mut ours, Slips::default());
            super::super::sqrt3::sqrt3_subdivide(&mut model);
            assert_eq!(ours.to_faces(), model.to_faces(), "{name}");
        }
    }
}
