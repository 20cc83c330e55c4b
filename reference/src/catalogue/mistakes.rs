//! What a student might get wrong: the handout's stubs and one
//! implementation per common mistake, each a catalogue entry.
//!
//! They serve twice: the fixture generator runs the subdivision mistakes
//! ([`subdivision_mistakes`]) to store what each produces, so the grader can
//! name a mistake it sees, and the tests grade every entry to prove the
//! grader rejects each with the right message. Nothing here is hostile:
//! attacks ([`super::attacks`]) may build on these, never the reverse.

use halfedge::{DVec3, EdgeId, HalfedgeId, Mesh, VertexId};

use super::alternatives::{split_old, steps};
use super::entry::{model, Entry};
use crate::solution::{self, Weights};

/// The mistakes, the stubs first.
pub fn entries() -> Vec<Entry> {
    let e = Entry::new;
    vec![
        e("stubs", "the handout's todo!() stubs", model().flip(stub_flip).split(stub_split).subdivide(stub_subdivide)),
        e("flip-none", "flip_edge always returns None", model().flip(|_, _| None).subdivide(sub_flip_none)),
        e("flip-wrong-return", "flip_edge returns another edge", model().flip(flip_returns_other).subdivide(sub_flip_returns_other)),
        e("flip-stale-vertex", "flip_edge does not update the halfedge of a and b", model().flip(flip_stale_vertices).subdivide(sub_flip_stale_vertices)),
        e("flip-stale-face", "flip_edge does not update the faces' halfedge", model().flip(flip_stale_faces).subdivide(sub_flip_stale_faces)),
        e("flip-face-labels", "flip_edge does not update the face of the halfedges that change face", model().flip(flip_face_labels).subdivide(sub_flip_face_labels)),
        e("flip-boundary", "flip_edge does not refuse boundary edges (every other rule kept)", model().flip(flip_boundary).subdivide(sub_flip_boundary)),
        e("flip-index-panic", "flip_edge indexes past the end of a Vec", model().flip(flip_index_panic)),
        e("flip-unset-link", "flip_edge indexes the mesh with the unset link of a new halfedge", model().flip(flip_unset_link)),
        e("flip-duplicates", "flip_edge does not refuse a flip whose new edge exists already", model().flip(flip_without_duplicate_check)),
        e("flip-moves-vertex", "flip_edge relinks right but moves a vertex", model().flip(flip_moves_vertex)),
        e("split-any-face", "split_edge splits beside faces that are not triangles", model().split(split_any_face)),
        e("split-marks-new", "split_edge marks the new vertex is_new and gives it a new_pos", model().split(split_marks_new)),
        e("split-renames-edge", "split_edge leaves e naming an edge across, not half of the old edge", model().split(split_renames_edge)),
        e("split-not-midpoint", "split_edge puts the new vertex a third of the way", model().split(split_third).subdivide(sub_split_third)),
        e("split-vertex-across", "split_edge points the new vertex's halfedge across, not along", model().split(split_vertex_across).subdivide(sub_split_vertex_across)),
        e("split-none", "split_edge always returns None", model().split(|_, _| None)),
        e("split-refuses-boundary", "split_edge refuses boundary edges, like flip_edge", model().split(split_refuses_boundary).subdivide(sub_split_refuses_boundary)),
        e("split-stale-vertex", "split_edge does not update b's halfedge", model().split(split_stale_vertex).subdivide(sub_split_stale_vertex)),
        e("split-after-split", "split_edge repairs b's halfedge with the halfedge it made in its previous call (kept in a static): right on a split alone, broken on the next", model().split(split_reuses_last_half)),
        e("flip-after-split", "flip_edge points a at h once split_edge has run in the process (kept in a static), as if every vertex still pointed where from_faces put it: right on a flip alone, broken after a split", model().flip(flip_after_split).split(split_noting)),
        e("loop-weights", "Loop's original weights instead of the lab's", model().subdivide(sub_loop_weights)),
        e("n3-rule", "3/(8n) also for n = 3", model().subdivide(sub_n3_rule)),
        e("old-not-moved", "old vertices keep their positions", model().subdivide(sub_old_not_moved)),
        e("plain-midpoints", "new vertices at edge midpoints", model().subdivide(sub_midpoints)),
        e("moved-first", "edge points computed from vertices already moved", model().subdivide(sub_moved_first)),
        e("no-flip", "no edge flipped", model().subdivide(sub_no_flip)),
        e("flip-all-new", "every new edge flipped, new-new ones too", model().subdivide(sub_flip_all_new)),
        e("flip-halves", "halves of old edges marked new and flipped too", model().subdivide(sub_flip_halves)),
        e("split-new-again", "splits edges created by split_edge again, without end", model().subdivide(sub_split_new_again)),
        e("endless", "loop_subdivide never returns", model().subdivide(sub_endless)),
        e("recursion", "loop_subdivide recurses without end", model().subdivide(sub_recursion)),
        e("abort", "loop_subdivide aborts the process", model().subdivide(sub_abort)),
        e("exit", "loop_subdivide calls std::process::exit(0)", model().subdivide(sub_exit)),
        e("new-at-origin", "never gives the split vertex its new_pos", model().subdivide(sub_new_at_origin)),
        e("in-place", "moves old vertices while computing their new positions", model().subdivide(sub_in_place)),
        e("in-place-vertices-first", "the handout's loop order, moving each vertex inside the vertex loop", model().subdivide(sub_in_place_vertices_first)),
        e("swapped-edge-weights", "1/8 on the edge's ends, 3/8 on the far corners", model().subdivide(sub_swapped_edge_weights)),
        e("edge-points-while-splitting", "computes each edge's point just before splitting it", model().subdivide(sub_edge_points_while_splitting)),
        e("neighbour-skipped", "the walk around a vertex misses one neighbour", model().subdivide(sub_neighbour_skipped)),
        e("wrong-corner", "the far corners read one step short (mesh[h.next].vertex)", model().subdivide(sub_wrong_corner)),
        e("integer-u", "u = 3 / (8 * n) in integers, 0 for n other than 3", model().subdivide(sub_integer_u)),
        e("flip-all-new-checked", "every new edge flipped, with a flip that refuses duplicate edges", model().subdivide(sub_flip_all_new_checked)),
        e("flip-halves-checked", "all four edges at a new vertex marked new, with a flip that refuses duplicate edges", model().subdivide(sub_flip_halves_checked)),
        e("stale-flags", "never resets is_new at the start of a round", model().subdivide(sub_stale_flags)),
        e("split-returns-old", "split_edge returns an end of the edge instead of the new vertex", model().split(split_returns_old)),
        e("split-stale-faces", "split_edge never resets the halfedge of the faces it shrinks", model().split(split_stale_faces)),
        e("split-assumes-inside", "split_edge refuses a boundary edge given by its halfedge in the hole", model().split(split_assumes_inside)),
        e("flip-any-face", "flip_edge flips beside faces that are not triangles", model().flip(flip_any_face)),
        e("flip-one-face", "flip_edge checks only the face of mesh[e].halfedge for being a triangle", model().flip(flip_one_face)),
        e("flip-twin-face", "flip_edge checks only the face of the twin of mesh[e].halfedge for being a triangle", model().flip(flip_twin_face)),
        e("flip-refuses-degree-3", "flip_edge also refuses edges with an end of degree 3", model().flip(flip_refuses_degree_3)),
        e("flip-boundary-one-side", "flip_edge refuses a boundary edge only when mesh[e].halfedge lies in the hole", model().flip(flip_boundary_one_side)),
        e("flip-refuses-rim-ends", "flip_edge also refuses interior edges whose end is on the boundary", model().flip(flip_refuses_rim_ends)),
        e("flip-refuses-high-degree", "flip_edge also refuses edges with an end of degree 8 or more", model().flip(flip_refuses_high_degree)),
        e("flip-duplicates-by-degree", "flip_edge refuses for a duplicate edge only when an end has degree 3 (true on a tetrahedron, not elsewhere)", model().flip(flip_duplicates_by_degree)),
        e("split-one-face", "split_edge checks only the face of mesh[e].halfedge (or its twin, in a hole) for being a triangle", model().split(split_one_face)),
        e("split-twin-face", "split_edge checks only the face across from the one it splits in for being a triangle", model().split(split_twin_face)),
        e("split-refuses-rim-ends", "split_edge also refuses interior edges whose end is on the boundary", model().split(split_refuses_rim_ends)),
        e("subdivide-skips-quads", "loop_subdivide returns quietly on a mesh that is not all triangles", model().subdivide(subdivide_skips_quads)),
        e("nan-position", "loop_subdivide leaves one vertex at NaN", model().subdivide(nan_position)),
        e("quadratic", "right results, but after each split it finds the edges at the new vertex by scanning every edge of the mesh: quadratic time", model().subdivide(sub_quadratic)),
    ]
}

/// A student's `loop_subdivide` calls their own `flip_edge` and
/// `split_edge`: this makes that subdivision for a flip or split mistake.
macro_rules! subdividing_with {
    ($name:ident, $split:expr, $flip:expr) => {
        fn $name(mesh: &mut Mesh) {
            steps(mesh, Weights::Warren, $split, $flip);
        }
    };
}

subdividing_with!(sub_flip_none, solution::split_edge, |_, _| None);
subdividing_with!(
    sub_flip_returns_other,
    solution::split_edge,
    flip_returns_other
);
subdividing_with!(
    sub_flip_stale_vertices,
    solution::split_edge,
    flip_stale_vertices
);
subdividing_with!(sub_flip_stale_faces, solution::split_edge, flip_stale_faces);
subdividing_with!(sub_flip_face_labels, solution::split_edge, flip_face_labels);
subdividing_with!(sub_flip_boundary, solution::split_edge, flip_boundary);
subdividing_with!(sub_split_third, split_third, solution::flip_edge);
subdividing_with!(
    sub_split_vertex_across,
    split_vertex_across,
    solution::flip_edge
);
subdividing_with!(
    sub_split_refuses_boundary,
    split_refuses_boundary,
    solution::flip_edge
);
subdividing_with!(
    sub_split_stale_vertex,
    split_stale_vertex,
    solution::flip_edge
);

/// A subdivision mistake the fixtures record.
pub struct KnownMistake {
    pub id: &'static str,
    /// What the grader says when a result matches this mistake's.
    pub hint: &'static str,
    pub run: fn(&mut Mesh),
}

/// Subdivision mistakes whose results the fixtures store, with the hint the
/// grader prints when a result matches. Each hint says what went wrong and
/// what the lab asks for instead.
pub fn subdivision_mistakes() -> Vec<KnownMistake> {
    let m = |id, hint, run| KnownMistake { id, hint, run };
    vec![
        m("loop-weights", "the old vertices moved with Loop's original weight beta = (1/n)(5/8 - (3/8 + cos(2 pi/n)/4)^2); the lab uses u = 3/16 when n = 3, else 3/(8n)", sub_loop_weights),
        m("n3-rule", "vertices with 3 neighbours moved with u = 3/(8n) = 1/8; the lab uses u = 3/16 when n = 3", sub_n3_rule),
        m("old-not-moved", "the old vertices did not move (or u came out 0, as 3 / (8 * n) does in integers): each goes to (1 - n*u) * v + u * (sum of its neighbours)", sub_old_not_moved),
        m("plain-midpoints", "the new vertices sit at edge midpoints (also what the far corners read one step short give: mesh[h.next].vertex is b itself, c is mesh[mesh[h.next].next].vertex): each goes to 3/8 * (a + b) + 1/8 * (c + d), c and d the corners facing the edge", sub_midpoints),
        m("swapped-edge-weights", "the edge rule's weights are swapped: 3/8 goes to the edge's ends a and b, 1/8 to the far corners c and d", sub_swapped_edge_weights),
        m("edge-points-while-splitting", "the new vertices were placed while splitting, after earlier splits had put new vertices where the far corners were: compute every edge's new_pos before the first split", sub_edge_points_while_splitting),
        m("neighbour-skipped", "the walk around each old vertex missed one neighbour (n one short, its position left out of the sum): count every neighbour once, from mesh[v].halfedge until the walk is back there", sub_neighbour_skipped),
        m("integer-u", "u came out 0 for vertices with n other than 3, as integer division gives (3 / (8 * n) is 0): compute it in floats, 3.0 / (8.0 * n as f64)", sub_integer_u),
        m("moved-first", "the new vertices were computed from old vertices that had already moved: compute every new position before moving any vertex", sub_moved_first),
        m("no-flip", "no edge was flipped: after splitting, flip every new edge that joins an old and a new vertex", sub_no_flip),
        m("flip-all-new", "edges joining two new vertices were flipped too: flip only new edges that join an old and a new vertex", sub_flip_all_new),
        m("flip-halves", "halves of the old edges were flipped too: of the four edges at a split vertex, only the two across the old edge are new", sub_flip_halves),
        m("new-at-origin", "the new vertices ended at the origin: after split_edge, give the new vertex its edge's new_pos (mesh[m].new_pos = mesh[e].new_pos)", sub_new_at_origin),
        m("in-place", "the old vertices were moved while their new positions were still being computed: store each in new_pos and move every vertex at the end", sub_in_place),
        m("in-place-vertices-first", "the old vertices were moved inside the vertex loop (pos = new_pos there), so later vertices and every edge point read moved positions: store each in new_pos and move every vertex only at the end", sub_in_place_vertices_first),
        m("flip-all-new-checked", "edges joining two new vertices were flipped too (your flip refused some, which hid the broken mesh): flip only new edges that join an old and a new vertex", sub_flip_all_new_checked),
        m("flip-halves-checked", "halves of the old edges were flipped too (all four edges at each new vertex were marked new): of the four, only the two across the old edge are new", sub_flip_halves_checked),
        m("stale-flags", "the second round went wrong: reset is_new to false on every vertex and edge at the start of each round (the new ones of the last round are old now)", sub_stale_flags),
    ]
}

// ---- the stubs -------------------------------------------------------------

fn stub_flip(_: &mut Mesh, _: EdgeId) -> Option<EdgeId> {
    todo!("flip_edge: rotate edge e counter-clockwise inside its two triangles")
}
fn stub_split(_: &mut Mesh, _: EdgeId) -> Option<VertexId> {
    todo!("split_edge: insert the midpoint of edge e and join it to the opposite corners")
}
fn stub_subdivide(_: &mut Mesh) {
    todo!("loop_subdivide: compute new positions, split old edges, flip old-new edges, move")
}

// ---- flip mistakes -----------------------------------------------------------

fn flip_returns_other(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    solution::flip_edge(mesh, e)?;
    let h = mesh[e].halfedge;
    Some(mesh[mesh[h].next].edge)
}

fn flip_stale_vertices(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    let (a, b) = (mesh[h].vertex, mesh[mesh[h].twin].vertex);
    let (ha, hb) = (mesh[a].halfedge, mesh[b].halfedge);
    let r = solution::flip_edge(mesh, e);
    mesh[a].halfedge = ha;
    mesh[b].halfedge = hb;
    r
}

fn flip_stale_faces(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    let (f0, f1) = (mesh[h].face, mesh[mesh[h].twin].face);
    let (h0, h1) = (mesh[f0].halfedge, mesh[f1].halfedge);
    let r = solution::flip_edge(mesh, e);
    mesh[f0].halfedge = h0;
    mesh[f1].halfedge = h1;
    r
}

fn flip_face_labels(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    let (h1, t1) = (mesh[h].next, mesh[t].next);
    let (f0, f1) = (mesh[h].face, mesh[t].face);
    let r = solution::flip_edge(mesh, e);
    // h1 moved to t's face and t1 to h's: leave their labels behind.
    mesh[h1].face = f0;
    mesh[t1].face = f1;
    r
}

/// Every rule of the contract but the boundary one: a hole shaped like a
/// triangle passes the triangle rule.
fn flip_boundary(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    if !solution::is_triangle(mesh, h) || !solution::is_triangle(mesh, t) {
        return None;
    }
    let c = mesh[mesh[mesh[h].next].next].vertex;
    let d = mesh[mesh[mesh[t].next].next].vertex;
    if c == d || mesh.find_edge(c, d).is_some() {
        return None;
    }
    solution::relink_flip(mesh, e);
    Some(e)
}

/// Reads a link a new element never got: indexing with an unset id.
fn flip_unset_link(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let stray = mesh.new_halfedge();
    let next = mesh[stray].next;
    let _ = mesh[next].vertex;
    solution::flip_edge(mesh, e)
}

#[allow(clippy::useless_vec)]
fn flip_index_panic(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let corners = vec![mesh[e].halfedge; 3];
    let fourth = corners[corners.len() + e.index() % 2];
    let _ = fourth;
    solution::flip_edge(mesh, e)
}

/// Right links, but a vertex moved: a flip keeps every position.
fn flip_moves_vertex(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let (a, _) = mesh.edge_vertices(e);
    let flipped = solution::flip_edge(mesh, e)?;
    mesh[a].pos *= 1.01;
    Some(flipped)
}

// ---- split mistakes ----------------------------------------------------------

/// No triangle check: relinks beside a quad as if it were a triangle.
fn split_any_face(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let mut h = mesh[e].halfedge;
    if mesh[mesh[h].face].is_boundary {
        h = mesh[h].twin;
    }
    Some(solution::relink_split(mesh, e, h))
}

/// Does subdivision's marking inside the split.
fn split_marks_new(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let m = solution::split_edge(mesh, e)?;
    mesh[m].is_new = true;
    mesh[m].new_pos = mesh[m].pos;
    Some(m)
}

/// A halfedge leaving the split vertex `m` across the old edge `a`-`b`
/// (its far end neither `a` nor `b`).
fn halfedge_across(mesh: &Mesh, m: VertexId, a: VertexId, b: VertexId) -> Option<HalfedgeId> {
    mesh.vertex_halfedges(m).into_iter().find(|&h| {
        let end = mesh.halfedge_dst(h);
        end != a && end != b
    })
}

/// A valid split whose edge `e` became the new edge across the first
/// triangle instead of half of the old edge (the ids of two edges swapped).
fn split_renames_edge(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let (a, b) = mesh.edge_vertices(e);
    let m = solution::split_edge(mesh, e)?;
    let across = mesh[halfedge_across(mesh, m, a, b)?].edge;
    let (he, hx) = (mesh[e].halfedge, mesh[across].halfedge);
    for h in [he, mesh[he].twin] {
        mesh[h].edge = across;
    }
    for h in [hx, mesh[hx].twin] {
        mesh[h].edge = e;
    }
    mesh[e].halfedge = hx;
    mesh[across].halfedge = he;
    Some(m)
}

fn split_third(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let (a, b) = mesh.edge_vertices(e);
    let m = solution::split_edge(mesh, e)?;
    mesh[m].pos = (2.0 * mesh[a].pos + mesh[b].pos) / 3.0;
    Some(m)
}

fn split_vertex_across(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let (a, b) = mesh.edge_vertices(e);
    let m = solution::split_edge(mesh, e)?;
    let across = halfedge_across(mesh, m, a, b).expect("a split vertex has edges across");
    mesh[m].halfedge = across;
    Some(m)
}

fn split_refuses_boundary(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    if mesh.edge_on_boundary(e) {
        return None;
    }
    solution::split_edge(mesh, e)
}

fn split_stale_vertex(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let verts: Vec<(VertexId, HalfedgeId)> = {
        let (a, b) = mesh.edge_vertices(e);
        vec![(a, mesh[a].halfedge), (b, mesh[b].halfedge)]
    };
    let m = solution::split_edge(mesh, e)?;
    for (v, h) in verts {
        mesh[v].halfedge = h;
    }
    Some(m)
}

// ---- mistakes that show only after an earlier operation ---------------------

thread_local! {
    /// The other half of the edge the previous `split_reuses_last_half` made.
    static LAST_HALF: std::cell::Cell<Option<HalfedgeId>> = const { std::cell::Cell::new(None) };
    /// Whether `split_noting` has run in this process.
    static SPLIT_RAN: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// b's end of the edge as the solution's split names it: the far end of
/// the edge's halfedge inside a real triangle.
fn split_far_end(mesh: &Mesh, e: EdgeId) -> VertexId {
    let mut h = mesh[e].halfedge;
    if mesh[mesh[h].face].is_boundary {
        h = mesh[h].twin;
    }
    mesh[mesh[h].twin].vertex
}

fn split_reuses_last_half(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let b = split_far_end(mesh, e);
    let m = solution::split_edge(mesh, e)?;
    // The halfedge remembered from the call before runs b_prev -> m_prev:
    // it starts at this b only by chance.
    if let Some(prev) = LAST_HALF.get() {
        if prev.index() < mesh.num_halfedges() {
            mesh[b].halfedge = mesh[prev].twin;
        }
    }
    LAST_HALF.set(Some(mesh[m].halfedge));
    Some(m)
}

fn split_noting(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    SPLIT_RAN.set(true);
    solution::split_edge(mesh, e)
}

fn flip_after_split(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    let a = mesh[h].vertex;
    let r = solution::flip_edge(mesh, e)?;
    if SPLIT_RAN.get() {
        // h now runs d -> c: a no longer starts it.
        mesh[a].halfedge = h;
    }
    Some(r)
}

// ---- subdivision mistakes: the solution's steps, one of them wrong ----------

fn sub_loop_weights(mesh: &mut Mesh) {
    steps(
        mesh,
        Weights::Loop,
        solution::split_edge,
        solution::flip_edge,
    );
}

fn sub_n3_rule(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    for v in mesh.vertex_ids() {
        let ns = mesh.vertex_neighbors(v);
        if ns.len() == 3 && !mesh.vertex_on_boundary(v) {
            let sum: DVec3 = ns.iter().map(|&n| mesh[n].pos).sum();
            mesh[v].new_pos = (1.0 - 3.0 / 8.0) * mesh[v].pos + sum / 8.0;
        }
    }
    solution::edge_points(mesh);
    after_points(mesh);
}

/// Split, flip and move, as the solution does.
fn after_points(mesh: &mut Mesh) {
    split_old(mesh, solution::split_edge);
    let all: Vec<EdgeId> = mesh.edge_ids().collect();
    solution::flip_old_new(mesh, &all, solution::flip_edge);
    solution::move_vertices(mesh);
}

fn sub_old_not_moved(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    for v in mesh.vertex_ids() {
        mesh[v].new_pos = mesh[v].pos;
    }
    after_points(mesh);
}

fn sub_midpoints(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    for e in mesh.edge_ids() {
        mesh[e].new_pos = mesh.edge_center(e);
    }
    after_points(mesh);
}

/// The four positions of the edge rule: the edge's ends a and b and the
/// corners c and d facing it (`None` on a boundary edge).
fn edge_rule_points(mesh: &Mesh, e: EdgeId) -> Option<[DVec3; 4]> {
    if mesh.edge_on_boundary(e) {
        return None;
    }
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    let corner = |g: HalfedgeId| mesh[mesh[mesh[mesh[g].next].next].vertex].pos;
    Some([
        mesh[mesh[h].vertex].pos,
        mesh[mesh[t].vertex].pos,
        corner(h),
        corner(t),
    ])
}

/// The corners facing the edge taken as `mesh[h.next].vertex`: the edge's
/// own ends, so the rule gives 3/8 (a + b) + 1/8 (b + a), the midpoint.
fn sub_wrong_corner(mesh: &mut Mesh) {
    with_edge_rule(mesh, |[a, b, _, _]| 0.375 * (a + b) + 0.125 * (b + a));
}

fn sub_swapped_edge_weights(mesh: &mut Mesh) {
    with_edge_rule(mesh, |[a, b, c, d]| 0.125 * (a + b) + 0.375 * (c + d));
}

/// The model's steps with `rule` (of a, b, c, d) for interior edge points.
fn with_edge_rule(mesh: &mut Mesh, rule: fn([DVec3; 4]) -> DVec3) {
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    for e in mesh.edge_ids() {
        if let Some(points) = edge_rule_points(mesh, e) {
            mesh[e].new_pos = rule(points);
        }
    }
    after_points(mesh);
}

/// Each edge's point computed just before it is split, from the mesh as
/// the earlier splits left it.
fn sub_edge_points_while_splitting(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    let old: Vec<EdgeId> = mesh.edge_ids().collect();
    for &e in &old {
        if let Some([a, b, c, d]) = edge_rule_points(mesh, e) {
            mesh[e].new_pos = 0.375 * (a + b) + 0.125 * (c + d);
        }
        solution::split_edges(mesh, &[e], solution::split_edge);
    }
    let all: Vec<EdgeId> = mesh.edge_ids().collect();
    solution::flip_old_new(mesh, &all, solution::flip_edge);
    solution::move_vertices(mesh);
}

/// The walk around a vertex starts one step late and stops at its start:
/// one neighbour short, with n one short too.
fn sub_neighbour_skipped(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    for v in mesh.vertex_ids() {
        if mesh.vertex_on_boundary(v) {
            continue;
        }
        let ns = mesh.vertex_neighbors(v);
        let n = ns.len() - 1;
        let u = Weights::Warren.neighbour_weight(n);
        let sum: DVec3 = ns[1..].iter().map(|&w| mesh[w].pos).sum();
        mesh[v].new_pos = (1.0 - n as f64 * u) * mesh[v].pos + u * sum;
    }
    solution::edge_points(mesh);
    after_points(mesh);
}

/// `3 / (8 * n)` in integers: 0 for every n but 3 (which has its own 3/16).
fn sub_integer_u(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    for v in mesh.vertex_ids() {
        let n = mesh.vertex_neighbors(v).len();
        if n != 3 && !mesh.vertex_on_boundary(v) {
            mesh[v].new_pos = mesh[v].pos;
        }
    }
    solution::edge_points(mesh);
    after_points(mesh);
}

/// The handout's loop order, moving in place: each vertex moved inside the
/// vertex loop, then edge points from the moved mesh.
fn sub_in_place_vertices_first(mesh: &mut Mesh) {
    for v in mesh.vertex_ids() {
        let ns = mesh.vertex_neighbors(v);
        let u = Weights::Warren.neighbour_weight(ns.len());
        let sum: DVec3 = ns.iter().map(|&n| mesh[n].pos).sum();
        let p = (1.0 - ns.len() as f64 * u) * mesh[v].pos + u * sum;
        mesh[v].pos = p;
        mesh[v].new_pos = p;
        mesh[v].is_new = false;
    }
    solution::edge_points(mesh);
    after_points(mesh);
}

fn sub_moved_first(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    solution::move_vertices(mesh);
    solution::edge_points(mesh);
    after_points(mesh);
}

/// The no-flip mistake: split, but flip nothing.
pub(crate) fn no_flip(mesh: &mut Mesh) {
    sub_no_flip(mesh);
}

fn sub_no_flip(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    split_old(mesh, solution::split_edge);
    solution::move_vertices(mesh);
}

fn sub_flip_all_new(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    split_old(mesh, solution::split_edge);
    for e in mesh.edge_ids() {
        if mesh[e].is_new {
            flip_without_duplicate_check(mesh, e);
        }
    }
    solution::move_vertices(mesh);
}

/// A flip as students usually write it: boundary and triangles checked, but
/// not whether the new edge exists already. The wrong subdivisions flip
/// with it, so their broken results stay what a student would get.
fn flip_without_duplicate_check(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    let triangle = |g: HalfedgeId| mesh[mesh[mesh[g].next].next].next == g;
    if mesh.edge_on_boundary(e) || !triangle(h) || !triangle(mesh[h].twin) {
        return None;
    }
    solution::relink_flip(mesh, e);
    Some(e)
}

fn sub_flip_all_new_checked(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    split_old(mesh, solution::split_edge);
    for e in mesh.edge_ids() {
        if mesh[e].is_new {
            solution::flip_edge(mesh, e);
        }
    }
    solution::move_vertices(mesh);
}

fn sub_flip_halves_checked(mesh: &mut Mesh) {
    flip_halves_with(mesh, solution::flip_edge);
}

fn sub_flip_halves(mesh: &mut Mesh) {
    flip_halves_with(mesh, flip_without_duplicate_check);
}

/// Every edge at a new vertex marked new (the halves of old edges too),
/// then the old-new ones flipped with `flip`.
fn flip_halves_with(mesh: &mut Mesh, flip: fn(&mut Mesh, EdgeId) -> Option<EdgeId>) {
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    split_old(mesh, solution::split_edge);
    // Every edge at a new vertex marked new: the halves of old edges too.
    let new: Vec<VertexId> = mesh.vertex_ids().filter(|&v| mesh[v].is_new).collect();
    for v in new {
        for h in mesh.vertex_halfedges(v) {
            let e = mesh[h].edge;
            mesh[e].is_new = true;
        }
    }
    let all: Vec<EdgeId> = mesh.edge_ids().collect();
    solution::flip_old_new(mesh, &all, flip);
    solution::move_vertices(mesh);
}

fn sub_split_new_again(mesh: &mut Mesh) {
    // The classic: the loop bound grows with every split.
    let mut i = 0;
    while i < mesh.num_edges() {
        let e = EdgeId::from_index(i);
        if !mesh.edge_on_boundary(e) {
            solution::split_edge(mesh, e);
        }
        i += 1;
    }
}

// Endless on purpose: the grader must stop it.
#[allow(clippy::while_immutable_condition)]
fn sub_endless(mesh: &mut Mesh) {
    // A walk that forgets to step: `h` never changes.
    let start = mesh[mesh.vertex_ids().next().unwrap()].halfedge;
    let h = start;
    let mut steps = 0u64;
    while mesh[h].vertex == mesh[start].vertex {
        steps = std::hint::black_box(steps.wrapping_add(1));
    }
}

#[allow(unconditional_recursion)]
fn sub_recursion(mesh: &mut Mesh) {
    let mut buf = [0u8; 256];
    buf[0] = std::hint::black_box(1);
    sub_recursion(std::hint::black_box(mesh));
    std::hint::black_box(&buf);
}

fn sub_abort(_: &mut Mesh) {
    std::process::abort();
}

fn sub_exit(_: &mut Mesh) {
    std::process::exit(0);
}

fn sub_new_at_origin(mesh: &mut Mesh) {
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    let old: Vec<EdgeId> = mesh.edge_ids().collect();
    solution::split_edges(mesh, &old, solution::split_edge);
    // Forget what split_edges set: the new vertices keep new_pos = 0.
    for v in mesh.vertex_ids() {
        if mesh[v].is_new {
            mesh[v].new_pos = DVec3::ZERO;
        }
    }
    let all: Vec<EdgeId> = mesh.edge_ids().collect();
    solution::flip_old_new(mesh, &all, solution::flip_edge);
    solution::move_vertices(mesh);
}

fn sub_in_place(mesh: &mut Mesh) {
    // Edge points first, from the unmoved mesh; then each vertex moved as
    // soon as its point is known, so later ones see moved neighbours.
    solution::edge_points(mesh);
    for v in mesh.vertex_ids() {
        let ns = mesh.vertex_neighbors(v);
        let u = Weights::Warren.neighbour_weight(ns.len());
        let sum: DVec3 = ns.iter().map(|&n| mesh[n].pos).sum();
        let p = (1.0 - ns.len() as f64 * u) * mesh[v].pos + u * sum;
        mesh[v].pos = p;
        mesh[v].new_pos = p;
        mesh[v].is_new = false;
    }
    after_points(mesh);
}

fn sub_stale_flags(mesh: &mut Mesh) {
    // The model's steps, but the old elements' flags are never reset.
    let keep: Vec<bool> = mesh.vertex_ids().map(|v| mesh[v].is_new).collect();
    let keep_e: Vec<bool> = mesh.edge_ids().map(|e| mesh[e].is_new).collect();
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    for (v, &f) in mesh.vertex_ids().zip(&keep) {
        mesh[v].is_new = f;
    }
    for (e, &f) in mesh.edge_ids().zip(&keep_e) {
        mesh[e].is_new = f;
    }
    after_points(mesh);
}

fn split_returns_old(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let (a, _) = mesh.edge_vertices(e);
    solution::split_edge(mesh, e)?;
    Some(a)
}

/// The lab's steps, but the edges around each split vertex are found by a
/// scan over every edge (instead of the walk around it): the same flags,
/// the same mesh, and time that grows with the square of the mesh.
fn sub_quadratic(mesh: &mut Mesh) {
    if let Some(f) = mesh.first_non_triangle() {
        panic!("loop_subdivide needs triangles, but {f} is not a triangle");
    }
    solution::vertex_points(mesh, Weights::Warren);
    solution::edge_points(mesh);
    let old: Vec<EdgeId> = mesh.edge_ids().collect();
    for e in old {
        let (a, b) = mesh.edge_vertices(e);
        let m = solution::split_edge(mesh, e).expect("an edge of a triangle mesh splits");
        mesh[m].is_new = true;
        mesh[m].new_pos = mesh[e].new_pos;
        for x in mesh.edge_ids() {
            let (p, q) = mesh.edge_vertices(x);
            let other = if p == m {
                q
            } else if q == m {
                p
            } else {
                continue;
            };
            mesh[x].is_new = other != a && other != b;
        }
    }
    let all: Vec<EdgeId> = mesh.edge_ids().collect();
    solution::flip_old_new(mesh, &all, solution::flip_edge);
    solution::move_vertices(mesh);
}

// ---- mistakes once kept among the attacks ----------------------------------

/// Subdivides right, then leaves one vertex at NaN.
pub fn nan_position(mesh: &mut Mesh) {
    solution::loop_subdivide(mesh);
    let v = VertexId::from_index(mesh.num_vertices() / 2);
    mesh[v].pos.y = f64::NAN;
}

/// A split that never resets the halfedge of the faces it shrinks.
pub fn split_stale_faces(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let h = mesh[e].halfedge;
    let faces = [mesh[h].face, mesh[mesh[h].twin].face];
    let before = faces.map(|f| mesh[f].halfedge);
    let m = solution::split_edge(mesh, e)?;
    for (f, old) in faces.into_iter().zip(before) {
        mesh[f].halfedge = old;
    }
    Some(m)
}

/// A split that assumes `mesh[e].halfedge` lies in a real face: on a
/// boundary edge given by its hole side, it divides the hole.
pub fn split_assumes_inside(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let h = mesh[e].halfedge;
    if mesh[mesh[h].face].is_boundary {
        return None;
    }
    solution::split_edge(mesh, e)
}

/// A flip with no check that the faces are triangles.
pub fn flip_any_face(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    if mesh.edge_on_boundary(e) {
        return None;
    }
    solution::relink_flip(mesh, e);
    Some(e)
}

/// The triangle rule on one face only: the face of `mesh[e].halfedge`.
fn flip_one_face(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    if mesh.edge_on_boundary(e) || !solution::is_triangle(mesh, h) {
        return None;
    }
    flip_checked_but_triangles(mesh, e)
}

/// The triangle rule on the twin's face only.
fn flip_twin_face(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let t = mesh[mesh[e].halfedge].twin;
    if mesh.edge_on_boundary(e) || !solution::is_triangle(mesh, t) {
        return None;
    }
    flip_checked_but_triangles(mesh, e)
}

/// The duplicate-edge rule and the relinking, with no triangle check.
fn flip_checked_but_triangles(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    let c = mesh[mesh[mesh[h].next].next].vertex;
    let d = mesh[mesh[mesh[t].next].next].vertex;
    if c == d || mesh.find_edge(c, d).is_some() {
        return None;
    }
    solution::relink_flip(mesh, e);
    Some(e)
}

/// Refuses more than the contract: an edge with an end of degree 3 (on a
/// closed mesh such a flip would duplicate an edge anyway).
fn flip_refuses_degree_3(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let (a, b) = mesh.edge_vertices(e);
    if mesh.vertex_degree(a) == 3 || mesh.vertex_degree(b) == 3 {
        return None;
    }
    solution::flip_edge(mesh, e)
}

/// The boundary rule on one side only: a hole on the twin's side is flipped
/// across (the hole's triangle passes the triangle rule).
fn flip_boundary_one_side(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    if mesh[mesh[h].face].is_boundary
        || !solution::is_triangle(mesh, h)
        || !solution::is_triangle(mesh, t)
    {
        return None;
    }
    flip_checked_but_triangles(mesh, e)
}

/// Refuses more than the contract: any edge with an end on the boundary.
fn flip_refuses_rim_ends(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let (a, b) = mesh.edge_vertices(e);
    if mesh.vertex_on_boundary(a) || mesh.vertex_on_boundary(b) {
        return None;
    }
    solution::flip_edge(mesh, e)
}

/// Refuses more than the contract: an end of degree 8 or more ("keeps the
/// mesh regular").
fn flip_refuses_high_degree(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let (a, b) = mesh.edge_vertices(e);
    if mesh.vertex_degree(a) >= 8 || mesh.vertex_degree(b) >= 8 {
        return None;
    }
    solution::flip_edge(mesh, e)
}

/// Stands a degree test in for the duplicate-edge rule: on a closed mesh
/// an end of degree 3 does make `c` and `d` neighbours, but `c` and `d`
/// can be joined elsewhere too.
fn flip_duplicates_by_degree(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    let (a, b) = mesh.edge_vertices(e);
    if mesh.edge_on_boundary(e)
        || !solution::is_triangle(mesh, h)
        || !solution::is_triangle(mesh, t)
        || mesh.vertex_degree(a) == 3
        || mesh.vertex_degree(b) == 3
    {
        return None;
    }
    solution::relink_flip(mesh, e);
    Some(e)
}

/// The triangle rule on the face the split starts from only.
fn split_one_face(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let mut h = mesh[e].halfedge;
    if mesh[mesh[h].face].is_boundary {
        h = mesh[h].twin;
    }
    if !solution::is_triangle(mesh, h) {
        return None;
    }
    Some(solution::relink_split(mesh, e, h))
}

/// The triangle rule on the face across only (a hole there counts as
/// fine).
fn split_twin_face(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let mut h = mesh[e].halfedge;
    if mesh[mesh[h].face].is_boundary {
        h = mesh[h].twin;
    }
    let t = mesh[h].twin;
    if !mesh[mesh[t].face].is_boundary && !solution::is_triangle(mesh, t) {
        return None;
    }
    Some(solution::relink_split(mesh, e, h))
}

/// Refuses more than the contract: any edge with an end on the boundary.
fn split_refuses_rim_ends(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let (a, b) = mesh.edge_vertices(e);
    if !mesh.edge_on_boundary(e) && (mesh.vertex_on_boundary(a) || mesh.vertex_on_boundary(b)) {
        return None;
    }
    solution::split_edge(mesh, e)
}

/// A subdivision that quietly skips a mesh that is not all triangles.
pub fn subdivide_skips_quads(mesh: &mut Mesh) {
    if mesh.first_non_triangle().is_none() {
        solution::loop_subdivide(mesh);
    }
}
