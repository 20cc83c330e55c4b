//! # The lab: flip, split, subdivide
//!
//! This is the one file you edit. Write the three functions below, in this
//! order (subdivision uses the other two), and run `cargo run -p grader`
//! after each. The handout (`docs/handout.en.md`, `docs/handout.zh.md`)
//! explains the ideas; these doc comments are the exact contracts.
//! Everything about the mesh itself is in the `halfedge` crate's
//! documentation ([`halfedge`]): how to walk around a face or a vertex, how
//! to create elements, and [`Mesh::validate`] to find broken links while you
//! work.
//!
//! The pictures name things the same way in all three exercises: the edge
//! `e` joins `a` and `b`; its halfedge `h` runs a -> b inside triangle
//! (a, b, c), followed by `h1` (b -> c) and `h2` (c -> a); its twin `t` runs
//! b -> a inside triangle (b, a, d), followed by `t1` (a -> d) and `t2`
//! (d -> b). Faces wind counter-clockwise in the pictures.
//!
#![doc = include_str!("../../../docs/figures/halfedge.svg")]
//!
//! Two things every function here needs:
//! - Positions are `halfedge::DVec3` (glam's `f64` vector, re-exported):
//!   write `use halfedge::DVec3;` (this crate does not depend on glam
//!   itself). `(p + q) / 2.0`, `0.375 * p`, `DVec3::ZERO` all work.
//! - Elements are never deleted, and new ones start with every link unset,
//!   `is_new == false` and `new_pos == DVec3::ZERO` (see
//!   [`halfedge::mesh`]). Set what you need yourself.

use halfedge::{EdgeId, Mesh, VertexId};

/// Flips edge `e`: rotates it inside its two triangles, so that it joins
/// the two vertices that faced it (`c` and `d`).
///
#[doc = include_str!("../../../docs/figures/flip.svg")]
///
/// In the picture (faces counter-clockwise) the edge turns
/// counter-clockwise; on a mesh wound the other way, such as the lab's
/// `cube.obj`, the same code turns it the other way seen from outside. The
/// result is the same edge `c`-`d` either way, which is what is graded.
///
/// Contract:
/// - Returns `Some(e)`: the same edge id, now joining `c` and `d`.
/// - Adds and removes nothing: the same vertices, edges, faces and
///   halfedges, only relinked. Every position stays where it is.
/// - Returns `None`, changing nothing, when `e` is on the boundary (one of
///   its faces is a hole: `mesh.edge_on_boundary(e)`), and when either face
///   is not a triangle.
/// - Returns `None`, changing nothing, when the flip would create an edge
///   that already exists: `c` and `d` are already joined by another edge
///   (as on a tetrahedron), so `mesh.find_edge(c, d)` is `Some`.
/// - Afterwards `mesh.validate()` is `Ok`.
///
/// What changes (one way to do it, as in the picture):
///
/// | halfedge | runs | `next` | `face` |
/// |---|---|---|---|
/// | `h`  | d -> c | `h2` | `f0` |
/// | `h2` | c -> a | `t1` | `f0` |
/// | `t1` | a -> d | `h`  | `f0` |
/// | `t`  | c -> d | `t2` | `f1` |
/// | `t2` | d -> b | `h1` | `f1` |
/// | `h1` | b -> c | `t`  | `f1` |
///
/// `twin` and `edge` of all six stay as they were. Then the pointers *into*
/// the picture: `a` and `b` may have pointed at `h` or `t`, which no longer
/// start there (`mesh[a].halfedge = t1`, `mesh[b].halfedge = h1` are always
/// right); `c` and `d` are fine; each face may have pointed at a halfedge
/// that is now in the other face (`mesh[f0].halfedge = h`,
/// `mesh[f1].halfedge = t`). `mesh[e].halfedge` is still `h` or `t`: fine.
///
/// Pitfalls: reading a field after you overwrote it (read all ten names
/// `h, h1, h2, t, t1, t2, a, b, c, d` and both faces first, then write);
/// forgetting the `face` of `h1` and `t1`, the two halfedges that change
/// face; returning another edge.
pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let _ = (mesh, e);
    todo!("flip_edge: rotate edge e counter-clockwise inside its two triangles")
}

/// Splits edge `e` at its midpoint `m`, and joins `m` to the vertex facing
/// the edge in each of its triangles: two triangles become four.
///
#[doc = include_str!("../../../docs/figures/split.svg")]
///
/// Contract:
/// - Returns `Some(m)`, the new vertex, at the midpoint of `a` and `b`
///   (`(mesh[a].pos + mesh[b].pos) / 2.0`).
/// - `mesh[m].halfedge` runs along the edge that was split: from `m` to `a`
///   or from `m` to `b` (`hb` in the picture). Subdivision relies on this
///   to tell the two halves of the old edge from the two new edges across.
/// - Only adds elements: 1 vertex, 3 edges, 2 faces, 6 halfedges. Existing
///   ids keep naming something sensible: `e` becomes one half of the old
///   edge, and `f0` and `f1` each one of the four triangles (in the picture
///   `e` is `a`-`m`, and `f0`, `f1` keep their corner at `a`).
/// - On a boundary edge (one side is a hole), only the real triangle is
///   divided: 1 vertex, 2 edges, 1 face, 4 halfedges, and the hole's loop
///   passes through `m` (see below).
/// - Returns `None`, changing nothing, when a real face of `e` is not a
///   triangle.
/// - Sets nothing else on `m`: like every new vertex it has
///   `is_new == false` and `new_pos == DVec3::ZERO`. Subdivision sets those
///   after the call (see [`loop_subdivide`]).
/// - Afterwards `mesh.validate()` is `Ok`.
///
/// The elements, as named in the picture: new vertex `m`; new edges `eb`
/// (m-b, the other half of the old edge), `ec` (m-c) and `ed` (m-d); new
/// faces `f2` = (m, b, c) and `f3` = (b, m, d); new halfedges `hb` (m -> b),
/// `tb` (b -> m), `hc` (m -> c), `tc` (c -> m), `hd` (m -> d), `td` (d -> m).
/// The old `h` now runs a -> m and `t` runs m -> a. Every new halfedge needs
/// all five fields ([`Mesh::set_neighbors`] sets them at once); every old
/// halfedge whose `next`, `vertex` or `face` changed needs them updated
/// (`h`, `h1`, `t`, `t1`, `t2`; `h2` keeps all five); and every record that
/// points *at* a halfedge must point at one that still fits:
/// `mesh[b].halfedge` may have been `t`, which now starts at `m`;
/// `mesh[f0].halfedge` may have been `h1`, which is now in `f2`.
///
/// On a boundary edge, `t` (or `h`: the edge's halfedge may lie in the hole;
/// start from the one in the real face) runs inside the hole's face. After
/// the split the hole's loop must run `... -> tb -> t -> ...`: the halfedge
/// that came before `t` ([`Mesh::prev`]) now leads to `tb`.
///
#[doc = include_str!("../../../docs/figures/split-boundary.svg")]
///
/// Pitfalls: count the elements in the picture before you create them; set
/// every field of every new halfedge; the old faces keep their ids but
/// lose a corner; take `prev(t)` *before* you relink anything.
pub fn split_edge(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let _ = (mesh, e);
    todo!("split_edge: insert the midpoint of edge e and join it to the opposite corners")
}

/// Loop subdivision, one round, done the lab's way: every triangle becomes
/// four, and every vertex moves to a weighted average of its neighbours, so
/// the surface gets smoother.
///
#[doc = include_str!("../../../docs/figures/split-flip-steps.svg")]
///
/// 1. **Compute all new positions first**, while the mesh is unchanged.
///    Store them; move nothing yet.
///    - Each old vertex `v` of degree `n`, with neighbours `p_1 ... p_n`:
///      `mesh[v].new_pos = (1 - n*u) * v + u * (p_1 + ... + p_n)`,
///      with `u = 3/16` if `n == 3`, otherwise `u = 3/(8n)`.
///    - Each edge `e` = (a, b) with opposite corners `c` and `d`: where the
///      vertex that will split it goes,
///      `mesh[e].new_pos = 3/8 * (a + b) + 1/8 * (c + d)`.
///    - Mark every old vertex and edge `is_new = false`.
///
#[doc = include_str!("../../../docs/figures/loop-masks.svg")]
///
/// 2. **Split every old edge** with [`split_edge`]. Take the list first:
///    `let old: Vec<EdgeId> = mesh.edge_ids().collect();` (or iterate
///    `mesh.edge_ids()`, which stops at the edges that existed when it was
///    made), never a loop bound that grows with every split. For each old
///    edge `e`, before splitting note its ends `(a, b) = mesh.edge_vertices(e)`
///    and its `new_pos`; then `let m = split_edge(mesh, e)` and
///    - `mesh[m].new_pos` = the edge's `new_pos`: **a new vertex has no
///      position rule of its own**; left alone it is `DVec3::ZERO` and moves
///      to the origin in step 4;
///    - `mesh[m].is_new = true`;
///    - of the four edges at `m` (`mesh.vertex_halfedges(m)`), the two whose
///      far end (`mesh.halfedge_dst(h)`) is neither `a` nor `b` are the new
///      edges *across* the old one: `is_new = true`. The other two are the
///      halves of the old edge: `is_new = false` (the new half starts
///      `false` already, but saying so costs nothing).
/// 3. **Flip every new edge that joins an old and a new vertex** with
///    [`flip_edge`]: `mesh[e].is_new && mesh[a].is_new != mesh[b].is_new`.
///    Not the halves of old edges (not new), not edges between two new
///    vertices. Exactly one edge per old triangle is flipped.
/// 4. **Move every vertex** to its `new_pos`: `mesh[v].pos = mesh[v].new_pos`.
///
/// Precondition: a triangle mesh. If a face is not a triangle, panic with a
/// message that says so (`mesh.first_non_triangle()` finds one).
///
/// Boundaries (bonus, `cargo run -p grader -- --bonus`): on an edge with a
/// hole on one side the new vertex is the midpoint, `1/2 * (a + b)`; an old
/// vertex on a hole moves to `3/4 * v + 1/8 * (p + q)`, where `p` and `q`
/// are its two neighbours along the hole (the ends of its two boundary
/// edges, `mesh.edge_on_boundary`), whatever its degree. [`flip_edge`]
/// refuses boundary edges, and no edge across is ever on the boundary.
///
#[doc = include_str!("../../../docs/figures/boundary-masks.svg")]
///
/// After one round the lab's objects have: cube 26 vertices / 72 edges,
/// torus 288 / 864, cylinder 66 / 192, cone 22 / 60.
///
/// Pitfalls: computing new positions after you started moving vertices, or
/// writing a vertex's new position into `pos` while its neighbours still
/// need the old one; splitting edges you just created; flipping new-new
/// edges or the halves of old edges; forgetting that `n == 3` uses a
/// different weight; forgetting `mesh[m].new_pos`.
pub fn loop_subdivide(mesh: &mut Mesh) {
    let _ = mesh;
    todo!("loop_subdivide: compute new positions, split old edges, flip old-new edges, move")
}
