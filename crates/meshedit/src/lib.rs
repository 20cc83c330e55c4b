//! # The lab: flip, split, subdivide
//!
//! This is the one file you edit. Write the three functions below; run
//! `cargo run -p grader` to check them. Everything you need about the mesh
//! is in the `halfedge` crate's documentation (`cargo doc -p halfedge --open`):
//! how to walk around a face or a vertex, how to create elements, and
//! `mesh.validate()` to find broken links while you work.
//!
//! The pictures name things the same way in all three exercises: the edge
//! `e` joins `a` and `b`; its halfedge `h` runs a -> b inside triangle
//! (a, b, c); its twin `t` runs b -> a inside triangle (b, a, d).

use halfedge::{EdgeId, Mesh, VertexId};

/// Flips edge `e`: rotates it counter-clockwise inside its two triangles, so
/// that it joins the two vertices that faced it.
///
/// ```text
///          c                        c
///        /   \                    / | \
///       /  h  \                  /  |  \
///      a ----> b      flip      a   |   b
///       \  t  /      ----->      \  |  /
///        \   /                    \ | /
///          d                        d
///   e joins a and b          e joins d and c
/// ```
///
/// Contract:
/// - Returns `Some(e)`: the same edge id, now joining `c` and `d`.
/// - Adds and removes nothing: the same vertices, edges, faces and
///   halfedges, only relinked. Every position stays where it is.
/// - Returns `None`, changing nothing, when `e` is on the boundary (one of
///   its faces is a hole: `mesh.edge_on_boundary(e)`), and when either face
///   is not a triangle.
///
/// Pitfalls: update every halfedge whose `next`, `vertex` or `face`
/// changes (six of them), and the `halfedge` of every vertex and face that
/// pointed at a halfedge which moved: `a` and `b` may have pointed at `h` or
/// `t`, and each face at a halfedge that now lies in the other face.
/// Draw the picture with all six halfedges named before you write code.
pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let _ = (mesh, e);
    todo!("flip_edge: rotate edge e counter-clockwise inside its two triangles")
}

/// Splits edge `e` at its midpoint `m`, and joins `m` to the vertex facing
/// the edge in each of its triangles: two triangles become four.
///
/// ```text
///          c                        c
///        /   \                    / | \
///       /  h  \                  /  |  \
///      a ----> b     split      a -- m -- b
///       \  t  /      ----->      \  |  /
///        \   /                    \ | /
///          d                        d
/// ```
///
/// Contract:
/// - Returns `Some(m)`, the new vertex, at the midpoint of `a` and `b`.
/// - `mesh[m].halfedge` runs along the edge that was split: from `m` to `a`
///   or from `m` to `b`. (Subdivision relies on this to tell the two halves
///   of the old edge from the two new edges across.)
/// - Only adds elements: 1 vertex, 3 edges, 2 faces, 6 halfedges. Existing
///   ids keep naming something sensible: `e` becomes one half of the old edge.
/// - On a boundary edge (one side is a hole), only the real triangle is
///   divided: 1 vertex, 2 edges, 1 face, 4 halfedges, and the hole's loop
///   passes through `m`.
/// - Returns `None`, changing nothing, when a real face of `e` is not a
///   triangle.
///
/// Pitfalls: count the elements in the picture before you create them; set
/// every field of every new halfedge (`set_neighbors` helps); the old
/// faces keep their ids but lose a corner.
pub fn split_edge(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let _ = (mesh, e);
    todo!("split_edge: insert the midpoint of edge e and join it to the opposite corners")
}

/// Loop subdivision, one round, done the lab's way. Every triangle becomes
/// four; the surface gets smoother.
///
/// ```text
///          /\                      /\
///         /  \                    /__\
///        /    \      ----->      /\  /\
///       /______\                /__\/__\
/// ```
///
/// 1. **Compute all new positions first**, while the mesh is unchanged:
///    - each old vertex `v` of degree `n`, with neighbours `p_i`:
///      `new_pos = (1 - n*u) * v + u * (p_1 + ... + p_n)`,
///      with `u = 3/16` if `n == 3`, otherwise `u = 3/(8n)`;
///    - each edge (a, b) with opposite corners c and d: the position of the
///      vertex that will split it,
///      `3/8 * (a + b) + 1/8 * (c + d)`, stored in `mesh[e].new_pos`.
///
///    Mark every old vertex and edge `is_new = false`.
/// 2. **Split every old edge** with `split_edge` (iterate over the edge ids
///    that existed *before* splitting). The new vertex is new; of the edges
///    at it, the two across the old edge are new, the two halves of the old
///    edge are not.
/// 3. **Flip every new edge that joins an old and a new vertex** with
///    `flip_edge`.
/// 4. **Move every vertex** to its `new_pos`.
///
/// Precondition: a triangle mesh. If a face is not a triangle, panic with a
/// message that says so (`mesh.first_non_triangle()` finds one).
///
/// Pitfalls: computing new positions after you started moving vertices;
/// splitting edges you just created; flipping new-new edges or the halves
/// of old edges; forgetting that `n == 3` uses a different weight.
pub fn loop_subdivide(mesh: &mut Mesh) {
    let _ = mesh;
    todo!("loop_subdivide: compute new positions, split old edges, flip old-new edges, move")
}
