//! # The √3 lab's model solution
//!
//! √3 subdivision (Leif Kobbelt, "√3-Subdivision", SIGGRAPH 2000) built
//! from two local operations: a face split and the Loop lab's edge flip.
//! Written the way the lab asks, with the student's signatures (the
//! exercise is `sqrt3_stubs.rs.txt` beside this file; its contracts are
//! these doc comments, word for word), so a TA can paste it in.
//!
//! - [`split_face`]: a vertex at a triangle's centroid, joined to its
//!   corners.
//! - [`flip_edge`]: the Loop lab's, unchanged ([`crate::solution::flip_edge`]).
//! - [`sqrt3_subdivide`]: one round on a closed mesh.
//! - [`sqrt3_subdivide_round`]: one round on any mesh, with Kobbelt's
//!   boundary rule (the bonus); it needs the round's number, and
//!   [`split_edge`] (the Loop lab's) for cutting boundary edges.
//!
//! The numbers, where the doc comments state them exactly:
//! - interior vertices, every round: Kobbelt 2000, the smoothing rule
//!   `(1 - a_n) p + a_n / n * sum`, `a_n = (4 - 2 cos(2 pi / n)) / 9`
//!   (also CGAL's `Sqrt3_mask_3::vertex_node`);
//! - the boundary, every other round: Kobbelt 2000, the section on
//!   boundaries, the univariate ternary (cubic B-spline) rule with weights
//!   `1/27 (4, 19, 4)`, `1/27 (1, 16, 10)` and `1/27 (10, 16, 1)`; CGAL's
//!   `Sqrt3_mask_3::border_node` and `Sqrt3_1step` (boundary refined on
//!   the second, fourth, ... step, boundary vertices fixed on the others)
//!   and OpenMesh's `Sqrt3T` do the same.

use std::f64::consts::TAU;

use halfedge::{DVec3, EdgeId, FaceId, HalfedgeId, Mesh, VertexId};

/// The Loop lab's flip, the same contract (see `meshedit::flip_edge`).
pub use crate::solution::flip_edge;
/// The Loop lab's split, used by the boundary rule only (see
/// `meshedit::split_edge`).
pub use crate::solution::split_edge;

/// Splits triangle `f` at its centroid: a new vertex `m` inside it, joined
/// to its three corners, so that one triangle becomes three.
///
/// The names: `h = mesh[f].halfedge` runs a -> b, followed by `h1`
/// (b -> c) and `h2` (c -> a).
///
/// Contract:
/// - Returns `Some(m)`, the new vertex, at the centroid of the corners:
///   `(mesh[a].pos + mesh[b].pos + mesh[c].pos) / 3.0`.
/// - Only adds elements: 1 vertex, 3 edges (m-a, m-b, m-c), 2 faces and
///   6 halfedges. `f` becomes the triangle (a, b, m); the two new faces are
///   (b, c, m) and (c, a, m), wound the way `f` was.
/// - `h`, `h1` and `h2` keep their `vertex`, `twin` and `edge`: the three
///   old edges are untouched, and `a`, `b` and `c` may keep their
///   `halfedge` (it still starts at them).
/// - Returns `None`, changing nothing, when `f` is a hole
///   (`mesh[f].is_boundary`) and when it is not a triangle
///   (`mesh.face_degree(f) != 3`).
/// - Sets nothing else on `m`: like every new vertex it has
///   `is_new == false` and `new_pos == DVec3::ZERO`.
/// - Afterwards `mesh.validate()` is `Ok`.
///
/// What changes (one way to do it): new vertex `m`, new edges `ea` (m-a),
/// `eb` (m-b), `ec` (m-c), new faces `f1` = (b, c, m) and `f2` = (c, a, m),
/// new halfedges `ma`, `am`, `mb`, `bm`, `mc`, `cm` (`ma` runs m -> a):
///
/// | halfedge | runs | `next` | `twin` | `edge` | `face` |
/// |---|---|---|---|---|---|
/// | `h`  | a -> b | `bm` | as before | as before | `f`  |
/// | `bm` | b -> m | `ma` | `mb` | `eb` | `f`  |
/// | `ma` | m -> a | `h`  | `am` | `ea` | `f`  |
/// | `h1` | b -> c | `cm` | as before | as before | `f1` |
/// | `cm` | c -> m | `mb` | `mc` | `ec` | `f1` |
/// | `mb` | m -> b | `h1` | `bm` | `eb` | `f1` |
/// | `h2` | c -> a | `am` | as before | as before | `f2` |
/// | `am` | a -> m | `mc` | `ma` | `ea` | `f2` |
/// | `mc` | m -> c | `h2` | `cm` | `ec` | `f2` |
///
/// Then every record that points *at* a halfedge: `mesh[m].halfedge` (one
/// of `ma`, `mb`, `mc`), each new edge's `halfedge`, `mesh[f1].halfedge =
/// h1`, `mesh[f2].halfedge = h2`. `mesh[f].halfedge` is still `h`: fine.
///
/// Pitfalls: reading `h1`, `h2` or a corner after you changed `h`'s `next`
/// (read them all first); forgetting the `face` of `h1` and `h2`, which
/// move to the new faces; leaving a new face's or edge's `halfedge` unset;
/// splitting a hole (its `halfedge` loop can be a triangle too: check
/// `is_boundary`).
pub fn split_face(mesh: &mut Mesh, f: FaceId) -> Option<VertexId> {
    if mesh[f].is_boundary {
        return None;
    }
    let h = mesh[f].halfedge;
    let h1 = mesh[h].next;
    let h2 = mesh[h1].next;
    if mesh[h2].next != h {
        return None;
    }
    let (a, b, c) = (mesh[h].vertex, mesh[h1].vertex, mesh[h2].vertex);

    let m = mesh.new_vertex((mesh[a].pos + mesh[b].pos + mesh[c].pos) / 3.0);
    let (ea, eb, ec) = (mesh.new_edge(), mesh.new_edge(), mesh.new_edge());
    let (f1, f2) = (mesh.new_face(), mesh.new_face());
    let (ma, am) = (mesh.new_halfedge(), mesh.new_halfedge());
    let (mb, bm) = (mesh.new_halfedge(), mesh.new_halfedge());
    let (mc, cm) = (mesh.new_halfedge(), mesh.new_halfedge());

    // f = (a, b, m)
    mesh.set_neighbors(h, bm, mesh[h].twin, a, mesh[h].edge, f);
    mesh.set_neighbors(bm, ma, mb, b, eb, f);
    mesh.set_neighbors(ma, h, am, m, ea, f);
    // f1 = (b, c, m)
    mesh.set_neighbors(h1, cm, mesh[h1].twin, b, mesh[h1].edge, f1);
    mesh.set_neighbors(cm, mb, mc, c, ec, f1);
    mesh.set_neighbors(mb, h1, bm, m, eb, f1);
    // f2 = (c, a, m)
    mesh.set_neighbors(h2, am, mesh[h2].twin, c, mesh[h2].edge, f2);
    mesh.set_neighbors(am, mc, ma, a, ea, f2);
    mesh.set_neighbors(mc, h2, cm, m, ec, f2);

    mesh[m].halfedge = ma;
    mesh[ea].halfedge = ma;
    mesh[eb].halfedge = mb;
    mesh[ec].halfedge = mc;
    mesh[f1].halfedge = h1;
    mesh[f2].halfedge = h2;
    Some(m)
}

/// The weight `a_n` of √3 subdivision's vertex rule for degree `n`:
/// `(4 - 2 cos(2 pi / n)) / 9` (Kobbelt 2000).
pub fn alpha(n: usize) -> f64 {
    (4.0 - 2.0 * (TAU / n as f64).cos()) / 9.0
}

/// √3 subdivision, one round, done the lab's way: a new vertex in every
/// triangle, every old edge flipped so that it joins the new vertices on
/// either side of it, and every old vertex smoothed. Each triangle becomes
/// three; two rounds cut every original edge in three (each original
/// triangle becomes nine, lined up with the original edges again).
///
/// 1. **Compute all new positions first**, while the mesh is unchanged.
///    Store them in `mesh[v].new_pos`; move nothing yet. Each old vertex
///    `v` of degree `n`, with neighbours `p_1 ... p_n`:
///    `new_pos = (1 - a_n) * v + a_n / n * (p_1 + ... + p_n)`, with
///    `a_n = (4 - 2 cos(2 pi / n)) / 9`, in Rust
///    `(4.0 - 2.0 * (std::f64::consts::TAU / n as f64).cos()) / 9.0`:
///    `a_3 = 5/9`, `a_4 = 4/9`, `a_6 = 1/3`.
/// 2. **Split every old face** with [`split_face`]. Take the lists first,
///    before the first split: `let old_faces: Vec<FaceId> =
///    mesh.face_ids().collect();` and `let old_edges: Vec<EdgeId> =
///    mesh.edge_ids().collect();` (the edges step 3 flips). The new vertex
///    stays where `split_face` puts it, at the centroid of the face's
///    corners, unmoved: it has no position rule of its own this round.
/// 3. **Flip every old edge** with [`flip_edge`]: the edges in
///    `old_edges`, exactly those that existed before the round. Never the
///    new ones `split_face` made (corner to new vertex). Each old edge then
///    joins the new vertices of its two faces.
/// 4. **Move every old vertex** to its `new_pos`:
///    `mesh[v].pos = mesh[v].new_pos`, for the old vertices only (a new
///    vertex's `new_pos` is `DVec3::ZERO`).
///
/// Precondition: a triangle mesh. If a face is not a triangle, panic with
/// a message that says so (`mesh.first_non_triangle()` finds one).
///
/// Graded: the positions and the connectivity. `is_new` and `new_pos` are
/// yours to use as scratch.
///
/// After one round a closed mesh with V vertices, E edges and F triangles
/// has V + F vertices, E + 3F edges and 3F triangles; every old vertex
/// keeps its degree and every new one has degree 6. The lab's objects:
/// cube 20 vertices / 54 edges / 36 faces, torus 216 / 648 / 432,
/// cylinder 50 / 144 / 96, cone 17 / 45 / 30.
///
/// On a mesh with holes this is round 1 of [`sqrt3_subdivide_round`]:
/// boundary edges are not flipped ([`flip_edge`] refuses them) and the
/// vertices on a hole stay where they are.
///
/// Pitfalls: writing a vertex's new position into `pos` while its
/// neighbours still need the old one; moving the old vertices before the
/// splits (the centroids must come from the old positions); flipping the
/// new edges too (loop over `old_edges`, never over `mesh.edge_ids()` taken
/// after the splits); the Loop lab's weights in place of `a_n`; `n` or
/// `a_n` computed in integers; moving the new vertices to their unset
/// `new_pos`.
pub fn sqrt3_subdivide(mesh: &mut Mesh) {
    sqrt3_subdivide_round(mesh, 1);
}

/// √3 subdivision, round number `round`, on a mesh that may have holes:
/// [`sqrt3_subdivide`] in the interior, Kobbelt's boundary rule on the
/// holes (the bonus, `cargo run -p grader -- --bonus`).
///
/// `round` counts the rounds applied to the input mesh from 1: the first
/// call on the input is round 1, the next round 2, and so on (`n` rounds
/// are `for r in 1..=n { sqrt3_subdivide_round(mesh, r) }`). Odd and even
/// rounds differ on the boundary only; on a closed mesh every round is
/// [`sqrt3_subdivide`]. Round 0 panics (rounds start at 1).
///
/// Everywhere, every round: a vertex not on a hole moves with the rule of
/// [`sqrt3_subdivide`], `n` counting all its edges (boundary ones too);
/// every old edge that is not on a hole is flipped; a boundary edge is
/// never flipped ([`flip_edge`] refuses it).
///
/// **Odd rounds (1, 3, 5, ...)**: the boundary stays as it is. Every
/// vertex on a hole keeps its position, and every real face, beside a hole
/// or not, is split at its centroid with [`split_face`].
///
/// **Even rounds (2, 4, 6, ...)**: every boundary edge is cut in three and
/// every boundary vertex moves. Name the vertices along the hole in order
/// `... p_(i-1), p_i, p_(i+1), p_(i+2) ...` (the two neighbours of `p_i`
/// along the hole are the far ends of its two boundary edges):
/// - the old vertex `p_i` moves to `(4 p_(i-1) + 19 p_i + 4 p_(i+1)) / 27`;
/// - the edge `p_i`-`p_(i+1)` gets two new vertices: next to `p_i` at
///   `(p_(i-1) + 16 p_i + 10 p_(i+1)) / 27`, next to `p_(i+1)` at
///   `(10 p_i + 16 p_(i+1) + p_(i+2)) / 27`;
/// - the triangle (a, b, c) on boundary edge a-b gets no centroid: its new
///   vertices `x` (next to `a`) and `y` (next to `b`) are joined to `c`,
///   making (a, x, c), (x, y, c) and (y, b, c). One way: `let x =
///   split_edge(mesh, e)` (it joins `x` to `c`, and `e` becomes a-x), then
///   `split_edge` on the edge x-b (`mesh.find_edge(x, b)`), then set both
///   positions. Its edges a-c and b-c are old edges and are flipped;
/// - every other real face is split at its centroid, as in odd rounds.
///
/// All positions come from the mesh as it was at the start of the round,
/// as in [`sqrt3_subdivide`]. The weights are the ternary cubic B-spline's
/// (mask `1/27 (1, 4, 10, 16, 19, 16, 10, 4, 1)`): after two rounds the
/// boundary is cut in three like every interior edge. Sources: Kobbelt,
/// "√3-Subdivision", SIGGRAPH 2000, the section on boundaries (the
/// boundary refined in every other step, with these weights); CGAL's
/// `Sqrt3_mask_3::border_node` (the same three masks) and
/// `Sqrt3_1step`, which refines the boundary on its second, fourth, ...
/// step (`i % 2 == 1` counting from 0) and otherwise leaves boundary
/// vertices in place, as OpenMesh's `Sqrt3T` does.
///
/// Precondition of an even round: no face has two boundary edges (always
/// true after an odd round, which leaves each boundary edge in a triangle
/// whose third corner is a new, interior vertex); it panics with a message
/// otherwise, as on a face that is not a triangle.
///
/// Counts: an odd round adds F vertices, 3F edges, 2F faces, as on a
/// closed mesh. An even round on a mesh with B boundary edges adds
/// F + B vertices, 3F + B edges and 2F faces (F counts the real faces,
/// not the holes).
///
/// Pitfalls: the round number off by one (round 1 leaves the boundary
/// alone); moving the boundary vertices in an odd round; a boundary
/// vertex's two neighbours taken from the walk around it instead of along
/// the hole; the new boundary vertices' weights swapped (16 goes to the
/// nearer end); a centroid in a triangle beside the hole in an even round.
pub fn sqrt3_subdivide_round(mesh: &mut Mesh, round: usize) {
    assert!(
        round >= 1,
        "sqrt3_subdivide_round counts rounds from 1 (the first round on the input mesh), \
         but was given round 0"
    );
    if let Some(f) = mesh.first_non_triangle() {
        panic!(
            "sqrt3_subdivide needs a triangle mesh, but {f} has {} sides",
            mesh.face_degree(f)
        );
    }
    let refine_boundary = round % 2 == 0;

    // 1. Every new position, from the mesh as it is.
    let old_vertices: Vec<VertexId> = mesh.vertex_ids().collect();
    for &v in &old_vertices {
        let p = mesh[v].pos;
        mesh[v].new_pos = if mesh.vertex_on_boundary(v) {
            if refine_boundary {
                let [before, after] = along_hole(mesh, v);
                (4.0 * mesh[before].pos + 19.0 * p + 4.0 * mesh[after].pos) / 27.0
            } else {
                p
            }
        } else {
            let neighbours = mesh.vertex_neighbors(v);
            let n = neighbours.len();
            let sum: DVec3 = neighbours.iter().map(|&q| mesh[q].pos).sum();
            (1.0 - alpha(n)) * p + alpha(n) / n as f64 * sum
        };
    }
    let cuts: Vec<Cut> = if refine_boundary {
        mesh.edge_ids()
            .filter(|&e| mesh.edge_on_boundary(e))
            .map(|e| cut(mesh, e))
            .collect()
    } else {
        Vec::new()
    };

    // 2. The lists, then the splits.
    let old_edges: Vec<EdgeId> = mesh
        .edge_ids()
        .filter(|&e| !mesh.edge_on_boundary(e))
        .collect();
    let mut beside_cut = vec![false; mesh.num_faces()];
    for c in &cuts {
        beside_cut[c.face.index()] = true;
    }
    let old_faces: Vec<FaceId> = mesh
        .face_ids()
        .filter(|&f| !mesh[f].is_boundary && !beside_cut[f.index()])
        .collect();
    for f in old_faces {
        split_face(mesh, f).expect("split_face refused a triangle");
    }
    for c in &cuts {
        let x = split_edge(mesh, c.edge).expect("split_edge refused a boundary edge");
        let rest = mesh
            .find_edge(x, c.b)
            .expect("split_edge leaves the edge from its new vertex to b");
        let y = split_edge(mesh, rest).expect("split_edge refused a boundary edge");
        mesh[x].pos = c.near_a;
        mesh[y].pos = c.near_b;
    }

    // 3. The old interior edges, each now between two new triangles.
    for e in old_edges {
        flip_edge(mesh, e);
    }

    // 4. The old vertices, all at once.
    for v in old_vertices {
        mesh[v].pos = mesh[v].new_pos;
    }
}

/// A boundary edge a-b to cut in three in an even round: its real face
/// (a, b, c), a -> b its halfedge there, and the two new points.
struct Cut {
    edge: EdgeId,
    face: FaceId,
    b: VertexId,
    near_a: DVec3,
    near_b: DVec3,
}

/// The cut of boundary edge `e`, from the positions as they are.
fn cut(mesh: &Mesh, e: EdgeId) -> Cut {
    // h: a -> b in the real face; t: b -> a around the hole, so the hole's
    // loop runs ... -> (b' -> b) -> t -> (a -> a') -> ...
    let mut h = mesh[e].halfedge;
    if mesh[mesh[h].face].is_boundary {
        h = mesh[h].twin;
    }
    let t = mesh[h].twin;
    let face = mesh[h].face;
    let on_hole = mesh
        .face_halfedges(face)
        .into_iter()
        .filter(|&g| mesh.edge_on_boundary(mesh[g].edge))
        .count();
    if on_hole > 1 {
        panic!(
            "an even round of sqrt3_subdivide_round needs every face to have at most one \
             boundary edge, but {face} has {on_hole} (is this round 2 on a mesh that had no \
             round 1?)"
        );
    }
    let (a, b) = (mesh[h].vertex, mesh[t].vertex);
    let a_before = mesh.halfedge_dst(mesh[t].next);
    let b_after = mesh[mesh.prev(t)].vertex;
    let (pa, pb) = (mesh[a].pos, mesh[b].pos);
    Cut {
        edge: e,
        face,
        b,
        near_a: (mesh[a_before].pos + 16.0 * pa + 10.0 * pb) / 27.0,
        near_b: (10.0 * pa + 16.0 * pb + mesh[b_after].pos) / 27.0,
    }
}

/// The two neighbours of boundary vertex `v` along its hole: the far ends
/// of its two boundary edges.
fn along_hole(mesh: &Mesh, v: VertexId) -> [VertexId; 2] {
    let ends: Vec<VertexId> = mesh
        .vertex_halfedges(v)
        .into_iter()
        .filter(|&h: &HalfedgeId| mesh.edge_on_boundary(mesh[h].edge))
        .map(|h| mesh.halfedge_dst(h))
        .collect();
    match ends[..] {
        [p, q] => [p, q],
        _ => panic!(
            "{v} has {} boundary edges: the boundary rule needs exactly two at every boundary \
             vertex (one hole passing through it once)",
            ends.len()
        ),
    }
}
