//! Other correct answers: implementations that differ from the model
//! solution in every way the lab allows (element order, which halfedge a
//! new vertex points at, the order of the steps) and must pass.

use halfedge::{EdgeId, Mesh, VertexId};

use super::entry::{model, Entry};
use crate::solution::{self, Weights};

/// The correct implementations, the model solution first.
pub fn entries() -> Vec<Entry> {
    let e = Entry::new;
    vec![
        e("reference", "the model solution", model()),
        e("alt-order", "creates elements in another order, points the split vertex at the other half, flips the other way round", model().flip(alt_flip).split(alt_split).subdivide(alt_subdivide)),
        e("alt-reverse", "splits and flips in reverse order, edge points before vertex points", model().subdivide(reverse_subdivide)),
    ]
}

/// A flip that relabels the other way: h ends up running c -> d.
fn alt_flip(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    // Flipping from the twin's side gives the same edge, with h and t swapped.
    mesh[e].halfedge = t;
    let r = solution::flip_edge(mesh, e);
    if r.is_none() {
        mesh[e].halfedge = h;
    }
    r
}

/// A split that starts from the other halfedge: the new elements take the
/// other roles and the new vertex points at the other half of the old edge.
fn alt_split(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let h = mesh[e].halfedge;
    mesh[e].halfedge = mesh[h].twin;
    let m = solution::split_edge(mesh, e);
    if m.is_none() {
        mesh[e].halfedge = h;
    }
    m
}

fn alt_subdivide(mesh: &mut Mesh) {
    steps(mesh, Weights::Warren, alt_split, alt_flip);
}

/// Edge points before vertex points, splits and flips last edge first.
fn reverse_subdivide(mesh: &mut Mesh) {
    solution::edge_points(mesh);
    solution::vertex_points(mesh, Weights::Warren);
    let mut old: Vec<EdgeId> = mesh.edge_ids().collect();
    old.reverse();
    solution::split_edges(mesh, &old, solution::split_edge);
    let mut all: Vec<EdgeId> = mesh.edge_ids().collect();
    all.reverse();
    solution::flip_old_new(mesh, &all, solution::flip_edge);
    solution::move_vertices(mesh);
}

/// The solution's steps with the given weights, split and flip.
pub(super) fn steps(
    mesh: &mut Mesh,
    weights: Weights,
    split: fn(&mut Mesh, EdgeId) -> Option<VertexId>,
    flip: fn(&mut Mesh, EdgeId) -> Option<EdgeId>,
) {
    if let Some(f) = mesh.first_non_triangle() {
        panic!("loop_subdivide needs triangles, but {f} is not a triangle");
    }
    solution::vertex_points(mesh, weights);
    solution::edge_points(mesh);
    split_old(mesh, split);
    let all: Vec<EdgeId> = mesh.edge_ids().collect();
    solution::flip_old_new(mesh, &all, flip);
    solution::move_vertices(mesh);
}

pub(super) fn split_old(mesh: &mut Mesh, split: fn(&mut Mesh, EdgeId) -> Option<VertexId>) {
    let old: Vec<EdgeId> = mesh.edge_ids().collect();
    solution::split_edges(mesh, &old, split);
}
