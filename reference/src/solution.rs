//! The model answer: `flip_edge`, `split_edge` and `loop_subdivide` written
//! the way the lab asks, with the same signatures as `crates/meshedit`, so a
//! TA can paste them in. Beyond the lab: meshes with boundary, and a choice
//! of vertex weights.

use std::f64::consts::TAU;

use halfedge::{DVec3, EdgeId, HalfedgeId, Mesh, VertexId};

/// How an old vertex's new position weighs its neighbours.
// No clap derive here: this file must compile pasted into a student's crate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Weights {
    /// The lab's (Warren's): u = 3/16 when n = 3, else 3/(8n).
    #[default]
    Warren,
    /// Loop's original: beta = (1/n) (5/8 - (3/8 + 1/4 cos(2 pi / n))^2).
    Loop,
}

impl Weights {
    /// The weight u of each neighbour of an interior vertex of degree `n`.
    pub fn neighbour_weight(self, n: usize) -> f64 {
        let n_f = n as f64;
        match self {
            Weights::Warren if n == 3 => 3.0 / 16.0,
            Weights::Warren => 3.0 / (8.0 * n_f),
            Weights::Loop => {
                let c = 3.0 / 8.0 + (TAU / n_f).cos() / 4.0;
                (5.0 / 8.0 - c * c) / n_f
            }
        }
    }

    /// The name used on the command line and in fixtures.
    pub fn name(self) -> &'static str {
        match self {
            Weights::Warren => "warren",
            Weights::Loop => "loop",
        }
    }

    /// The inverse of [`Weights::name`].
    pub fn from_name(name: &str) -> Option<Weights> {
        match name {
            "warren" => Some(Weights::Warren),
            "loop" => Some(Weights::Loop),
            _ => None,
        }
    }
}

pub(crate) fn is_triangle(mesh: &Mesh, h: HalfedgeId) -> bool {
    mesh[mesh[mesh[h].next].next].next == h
}

/// See `meshedit::flip_edge`.
pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    if mesh.edge_on_boundary(e) {
        return None;
    }
    // Before: h = a->b, h1 = b->c, h2 = c->a;  t = b->a, t1 = a->d, t2 = d->b.
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    if !is_triangle(mesh, h) || !is_triangle(mesh, t) {
        return None;
    }
    // c and d already joined (every edge of a tetrahedron): the flip would
    // make a second edge between them.
    let (h1, t1) = (mesh[h].next, mesh[t].next);
    let c = mesh[mesh[h1].next].vertex;
    let d = mesh[mesh[t1].next].vertex;
    // d == a or b only on a degenerate triangle; find_edge(c, d) would
    // find the edge c-a or c-b there, which the walk below skips.
    if c == d || d == mesh[h].vertex || d == mesh[t].vertex || joined_elsewhere(mesh, h1, d) {
        return None;
    }
    relink_flip(mesh, e);
    Some(e)
}

/// Whether `c`, where `h1` (b->c) ends, already has an edge to `d`. The
/// walk around c starts after c->a (its halfedge in h's triangle) and stops
/// at c->b (twin of h1): those two lead to a and b, never to d, and their
/// records are the ones the flip just read. It is `find_edge(c, d)` without
/// the two steps, the most time a flip spends.
fn joined_elsewhere(mesh: &Mesh, h1: HalfedgeId, d: VertexId) -> bool {
    let h2 = mesh[h1].next; // c->a
    let last = mesh[h1].twin; // c->b
    let mut g = mesh[mesh[h2].twin].next;
    let mut steps = 0;
    while g != last {
        let t = mesh[g].twin;
        if mesh[t].vertex == d {
            return true;
        }
        g = mesh[t].next;
        steps += 1;
        if g == h2 || steps > mesh.num_halfedges() {
            panic!(
                "the walk around {} never came back to where it started: the mesh's links \
                 are broken (call mesh.validate() to find where)",
                mesh[h2].vertex
            );
        }
    }
    false
}

/// The relinking part of a flip, with no checks: `e`'s two faces are taken
/// to be triangles.
pub(crate) fn relink_flip(mesh: &mut Mesh, e: EdgeId) {
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    let (h1, t1) = (mesh[h].next, mesh[t].next);
    let (h2, t2) = (mesh[h1].next, mesh[t1].next);
    let (a, b) = (mesh[h].vertex, mesh[t].vertex);
    let (c, d) = (mesh[h2].vertex, mesh[t2].vertex);
    let (f0, f1) = (mesh[h].face, mesh[t].face);

    // After: h = d->c in (d, c, a);  t = c->d in (c, d, b).
    mesh.set_neighbors(h, h2, t, d, e, f0);
    mesh.set_neighbors(h2, t1, mesh[h2].twin, c, mesh[h2].edge, f0);
    mesh.set_neighbors(t1, h, mesh[t1].twin, a, mesh[t1].edge, f0);
    mesh.set_neighbors(t, t2, h, c, e, f1);
    mesh.set_neighbors(t2, h1, mesh[t2].twin, d, mesh[t2].edge, f1);
    mesh.set_neighbors(h1, t, mesh[h1].twin, b, mesh[h1].edge, f1);

    // a and b may have pointed at h or t, which no longer start there.
    mesh[a].halfedge = t1;
    mesh[b].halfedge = h1;
    mesh[f0].halfedge = h;
    mesh[f1].halfedge = t;
}

/// See `meshedit::split_edge`.
pub fn split_edge(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    // Let h be a halfedge of e inside a real triangle.
    let mut h = mesh[e].halfedge;
    if mesh[mesh[h].face].is_boundary {
        h = mesh[h].twin;
    }
    let t = mesh[h].twin;
    let on_boundary = mesh[mesh[t].face].is_boundary;
    if !is_triangle(mesh, h) || (!on_boundary && !is_triangle(mesh, t)) {
        return None;
    }
    Some(relink_split(mesh, e, h))
}

/// The creating and relinking part of a split, with no checks: `h`, `e`'s
/// halfedge in a real face, and its twin's face (unless a hole) are taken
/// to be triangles. Returns the new vertex.
pub(crate) fn relink_split(mesh: &mut Mesh, e: EdgeId, h: HalfedgeId) -> VertexId {
    let t = mesh[h].twin;
    let on_boundary = mesh[mesh[t].face].is_boundary;
    // Before: h = a->b, h1 = b->c, h2 = c->a in f0; t = b->a in f1.
    let (h1, h2) = (mesh[h].next, mesh[mesh[h].next].next);
    let (a, b, c) = (mesh[h].vertex, mesh[t].vertex, mesh[h2].vertex);
    let f0 = mesh[h].face;
    let mid = (mesh[a].pos + mesh[b].pos) / 2.0;

    let m = mesh.new_vertex(mid);
    let eb = mesh.new_edge(); // m - b, the other half of the old edge
    let ec = mesh.new_edge(); // m - c, across triangle f0
    let f2 = mesh.new_face(); // (m, b, c)
    let hb = mesh.new_halfedge(); // m -> b
    let tb = mesh.new_halfedge(); // b -> m
    let hc = mesh.new_halfedge(); // m -> c
    let tc = mesh.new_halfedge(); // c -> m

    // f0 = (a, m, c), f2 = (m, b, c).
    mesh.set_neighbors(h, hc, t, a, e, f0);
    mesh.set_neighbors(hc, h2, tc, m, ec, f0);
    mesh.set_neighbors(hb, h1, tb, m, eb, f2);
    mesh.set_neighbors(h1, tc, mesh[h1].twin, b, mesh[h1].edge, f2);
    mesh.set_neighbors(tc, hb, hc, c, ec, f2);

    let f1 = mesh[t].face;
    if on_boundary {
        // The hole's loop ran ... -> t (b->a) -> ...; now ... -> tb -> t.
        let before_t = mesh
            .face_halfedges(f1)
            .into_iter()
            .find(|&g| mesh[g].next == t)
            .expect("a boundary loop is a cycle");
        mesh[before_t].next = tb;
        mesh.set_neighbors(tb, t, hb, b, eb, f1);
        mesh.set_neighbors(t, mesh[t].next, h, m, e, f1);
    } else {
        // Before: t = b->a, t1 = a->d, t2 = d->b in f1.
        // After: f1 = (m, a, d), f3 = (b, m, d).
        let t1 = mesh[t].next;
        let t2 = mesh[t1].next;
        let d = mesh[t2].vertex;
        let ed = mesh.new_edge();
        let f3 = mesh.new_face();
        let hd = mesh.new_halfedge(); // m -> d
        let td = mesh.new_halfedge(); // d -> m
        mesh.set_neighbors(t, t1, h, m, e, f1);
        mesh.set_neighbors(t1, td, mesh[t1].twin, a, mesh[t1].edge, f1);
        mesh.set_neighbors(td, t, hd, d, ed, f1);
        mesh.set_neighbors(tb, hd, hb, b, eb, f3);
        mesh.set_neighbors(hd, t2, td, m, ed, f3);
        mesh.set_neighbors(t2, tb, mesh[t2].twin, d, mesh[t2].edge, f3);
        mesh[ed].halfedge = hd;
        mesh[f3].halfedge = tb;
        mesh[f1].halfedge = t;
    }

    mesh[m].halfedge = hb; // along the old edge, as the contract asks
    mesh[b].halfedge = h1; // b may have pointed at t, which now starts at m
    mesh[eb].halfedge = hb;
    mesh[ec].halfedge = hc;
    mesh[e].halfedge = h;
    mesh[f0].halfedge = h;
    mesh[f2].halfedge = hb;
    m
}

/// See `meshedit::loop_subdivide`: one round with the lab's weights.
pub fn loop_subdivide(mesh: &mut Mesh) {
    loop_subdivide_with(mesh, Weights::Warren);
}

/// The two neighbours of boundary vertex `v` along its hole.
fn boundary_neighbours(mesh: &Mesh, v: VertexId) -> [VertexId; 2] {
    let mut ends = mesh
        .vertex_halfedges(v)
        .into_iter()
        .filter(|&h| mesh.edge_on_boundary(mesh[h].edge))
        .map(|h| mesh.halfedge_dst(h));
    let first = ends.next().expect("a boundary vertex has boundary edges");
    let second = ends
        .next()
        .expect("a boundary vertex has two boundary edges");
    [first, second]
}

/// One round of Loop subdivision with the given vertex weights. Boundary
/// edges split at their midpoint; boundary vertices move to
/// 3/4 v + 1/8 of their two neighbours along the boundary.
///
/// # Panics
/// If a face is not a triangle.
pub fn loop_subdivide_with(mesh: &mut Mesh, weights: Weights) {
    // The triangle check rides on the edge-point pass, which reads every
    // face's third halfedge anyway: a pass of its own cost 4% of a round.
    // Both passes only write the scratch fields, so a mesh refused here is
    // otherwise as it was.
    vertex_points(mesh, weights);
    if !edge_points(mesh) {
        let f = mesh
            .first_non_triangle()
            .expect("edge_points saw a face that is not a triangle");
        panic!(
            "loop_subdivide needs a triangle mesh, but {f} has {} sides",
            mesh.face_degree(f)
        );
    }
    reserve_round(mesh);
    let old_edges: Vec<EdgeId> = mesh.edge_ids().collect();
    let old_new = split_edges(mesh, &old_edges, split_edge);
    drop(old_edges);
    flip_listed(mesh, &old_new, flip_edge);
    move_vertices(mesh);
}

/// Makes room for everything one round adds, so that no arena moves while
/// splitting (a speed-up only: see `Mesh::reserve`). Splitting an edge
/// between two triangles adds 1 vertex, 3 edges, 2 faces and 6 halfedges;
/// beside a hole, 1, 2, 1 and 4.
pub fn reserve_round(mesh: &mut Mesh) {
    let edges = mesh.num_edges();
    // A hole's halfedges are its boundary edges, one each.
    let on_holes: usize = mesh
        .face_ids()
        .filter(|&f| mesh[f].is_boundary)
        .map(|f| mesh.face_degree(f))
        .sum();
    mesh.reserve(
        edges,
        3 * edges - on_holes,
        2 * edges - on_holes,
        6 * edges - 2 * on_holes,
    );
}

/// Walks once around `v` (as `vertex_halfedges` does, without collecting):
/// the number of edges, the sum of the neighbours' positions in the walk's
/// order, and whether a hole touches `v`.
fn around_vertex(mesh: &Mesh, v: VertexId) -> (usize, DVec3, bool) {
    let start = mesh[v].halfedge;
    let (mut n, mut sum, mut on_boundary) = (0, DVec3::ZERO, false);
    let mut h = start;
    loop {
        let t = mesh[h].twin;
        n += 1;
        sum += mesh[mesh[t].vertex].pos;
        on_boundary |= mesh[mesh[h].face].is_boundary;
        h = mesh[t].next;
        if h == start {
            return (n, sum, on_boundary);
        }
        if n > mesh.num_halfedges() {
            panic!(
                "the walk around {v} never came back to where it started: the mesh's links \
                 are broken (call mesh.validate() to find where)"
            );
        }
    }
}

/// Step 1a: where each old vertex goes, into `new_pos`; marks it old.
pub fn vertex_points(mesh: &mut Mesh, weights: Weights) {
    for v in mesh.vertex_ids() {
        let i = v.index();
        // The walk's first three records: the rest depends on what it reads.
        for wave in 0..3 {
            let ahead = mesh.records().0.get(i + (AHEAD >> wave));
            fetch_ahead(mesh, ahead.map(|r| r.halfedge), wave);
        }
        let p = mesh[v].pos;
        let (n, sum, on_boundary) = around_vertex(mesh, v);
        mesh[v].new_pos = if on_boundary {
            let [x, y] = boundary_neighbours(mesh, v);
            0.75 * p + 0.125 * (mesh[x].pos + mesh[y].pos)
        } else {
            let u = weights.neighbour_weight(n);
            (1.0 - n as f64 * u) * p + u * sum
        };
        mesh[v].is_new = false;
    }
}

/// Step 1b: where the vertex splitting each edge goes, into the edge's
/// `new_pos`; marks the edge old. Returns whether every real face it read
/// is a triangle (every real face is read: each has an edge); if not, the
/// points are meaningless.
pub fn edge_points(mesh: &mut Mesh) -> bool {
    let mut triangles = true;
    for e in mesh.edge_ids() {
        for wave in 0..WAVES {
            let ahead = mesh.records().1.get(e.index() + (AHEAD >> wave));
            fetch_ahead(mesh, ahead.map(|r| r.halfedge), wave);
        }
        let h = mesh[e].halfedge;
        let t = mesh[h].twin;
        let (a, b) = (mesh[mesh[h].vertex].pos, mesh[mesh[t].vertex].pos);
        // A triangle's third halfedge leads back to the first.
        let (h_real, t_real) = (
            !mesh[mesh[h].face].is_boundary,
            !mesh[mesh[t].face].is_boundary,
        );
        let (h2, t2) = (mesh[mesh[h].next].next, mesh[mesh[t].next].next);
        triangles &= (!h_real || mesh[h2].next == h) && (!t_real || mesh[t2].next == t);
        mesh[e].new_pos = if !h_real || !t_real {
            (a + b) / 2.0
        } else {
            let (c, d) = (mesh[mesh[h2].vertex].pos, mesh[mesh[t2].vertex].pos);
            0.375 * (a + b) + 0.125 * (c + d)
        };
        mesh[e].is_new = false;
    }
    triangles
}

/// How many edges ahead the split and flip loops ask the CPU to fetch the
/// records they will touch: a split or flip reads about ten records in
/// unrelated places, and waiting for each in turn is most of its time.
const AHEAD: usize = 32;
/// Waves of [`fetch_ahead`], the first `AHEAD` edges ahead, each next one
/// half as far.
const WAVES: usize = 5;

/// Asks the CPU to bring `records[index]` into the cache (no effect on the
/// result; nothing happens if `index` is out of range or on other CPUs).
#[inline(always)]
fn prefetch<T>(records: &[T], index: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(record) = records.get(index) {
        // SAFETY: a prefetch of a valid address reads nothing and writes nothing.
        unsafe {
            std::arch::x86_64::_mm_prefetch(
                (record as *const T).cast::<i8>(),
                std::arch::x86_64::_MM_HINT_T0,
            )
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (records, index);
}

/// The records a split or flip of `h`'s edge (or a walk around `h`'s
/// vertex) will read, in five waves, each reading only what the previous
/// waves fetched: `wave` 0 fetches h, 1 its twin t, next, vertex and
/// face, 2 t's next, vertex and face and h's face's third halfedge, 3 that
/// one's vertex (c) and t's face's third halfedge, 4 that one's vertex (d).
#[inline(always)]
fn fetch_ahead(mesh: &Mesh, h: Option<HalfedgeId>, wave: usize) {
    let Some(h) = h else { return };
    let (vertices, _, faces, halfedges) = mesh.records();
    if wave == 0 {
        return prefetch(halfedges, h.index());
    }
    let Some(hr) = halfedges.get(h.index()) else {
        return;
    };
    if wave == 1 {
        prefetch(halfedges, hr.twin.index());
        prefetch(halfedges, hr.next.index());
        prefetch(vertices, hr.vertex.index());
        prefetch(faces, hr.face.index());
        return;
    }
    let tr = halfedges.get(hr.twin.index());
    let next = halfedges.get(hr.next.index());
    if wave == 2 {
        if let Some(tr) = tr {
            prefetch(halfedges, tr.next.index());
            prefetch(vertices, tr.vertex.index());
            prefetch(faces, tr.face.index());
        }
        if let Some(next) = next {
            prefetch(halfedges, next.next.index());
        }
        return;
    }
    // The far corners: c (h's third vertex) and d (t's).
    let t1 = tr.and_then(|tr| halfedges.get(tr.next.index()));
    if wave == 3 {
        if let Some(h2) = next.and_then(|n| halfedges.get(n.next.index())) {
            prefetch(vertices, h2.vertex.index());
        }
        if let Some(t1) = t1 {
            prefetch(halfedges, t1.next.index());
        }
        return;
    }
    if let Some(t2) = t1.and_then(|t1| halfedges.get(t1.next.index())) {
        prefetch(vertices, t2.vertex.index());
    }
}

/// Fetches ahead for the loop over `edges` at position `i`.
#[inline(always)]
fn fetch_for(mesh: &Mesh, edges: &[EdgeId], i: usize) {
    for wave in 0..WAVES {
        let ahead = edges.get(i + (AHEAD >> wave));
        fetch_ahead(mesh, ahead.map(|&e| mesh[e].halfedge), wave);
    }
}

/// Step 2: splits each of `edges` (the old ones) with `split`. The new
/// vertex is new; of the edges at it, those across the old edge are new,
/// the two halves of the old edge are not.
///
/// Returns the new edges whose far end is an old vertex: the ones step 3
/// flips, found here where their records are still in the cache. An edge's
/// ends change only when it is split or flipped, and only old edges are
/// split, so they are exactly the old-new edges after the last split. They
/// come in id order (the order [`flip_old_new`] flips in) when `split`
/// gives the edges it makes new ids, as [`split_edge`] does: each split's
/// are sorted.
pub fn split_edges(
    mesh: &mut Mesh,
    edges: &[EdgeId],
    split: fn(&mut Mesh, EdgeId) -> Option<VertexId>,
) -> Vec<EdgeId> {
    // Two across each old edge between triangles, one beside a hole.
    let mut old_new = Vec::with_capacity(2 * edges.len());
    for (i, &e) in edges.iter().enumerate() {
        fetch_for(mesh, edges, i);
        let (a, b) = mesh.edge_vertices(e);
        let m = split(mesh, e).expect("split_edge returned None for an edge of a triangle mesh");
        mesh[m].is_new = true;
        mesh[m].new_pos = mesh[e].new_pos;
        let first = old_new.len();
        // Around m, as `vertex_halfedges(m)` would, without collecting.
        let start = mesh[m].halfedge;
        let mut h = start;
        let mut steps = 0;
        loop {
            let t = mesh[h].twin;
            let end = mesh[t].vertex;
            let edge = mesh[h].edge;
            let across = end != a && end != b;
            mesh[edge].is_new = across;
            if across && !mesh[end].is_new {
                old_new.push(edge);
            }
            h = mesh[t].next;
            steps += 1;
            if h == start {
                break;
            }
            if steps > mesh.num_halfedges() {
                panic!(
                    "the walk around {m} never came back to where it started: the mesh's \
                     links are broken (call mesh.validate() to find where)"
                );
            }
        }
        old_new[first..].sort_unstable();
    }
    old_new
}

/// Step 3 as [`loop_subdivide`] does it: flips each of `edges`, the list
/// [`split_edges`] returned.
pub fn flip_listed(
    mesh: &mut Mesh,
    edges: &[EdgeId],
    flip: fn(&mut Mesh, EdgeId) -> Option<EdgeId>,
) {
    for (i, &e) in edges.iter().enumerate() {
        fetch_for(mesh, edges, i);
        // The duplicate check's walk around c, its first steps.
        for (ahead, step) in [(4, 0), (2, 1), (1, 2)] {
            fetch_ring(mesh, edges.get(i + ahead), step);
        }
        flip(mesh, e);
    }
}

/// Fetches ahead what the first steps of `joined_elsewhere`'s walk around
/// c will read for `e`: `step` 0 the twin of c->a, 1 that one's next (the
/// walk's first halfedge g), 2 g's twin. Each reads only records the
/// earlier waves and steps fetched.
#[inline(always)]
fn fetch_ring(mesh: &Mesh, e: Option<&EdgeId>, step: usize) {
    let Some(&e) = e else { return };
    let (_, _, _, halfedges) = mesh.records();
    let h = mesh[e].halfedge;
    let Some(h2) = halfedges
        .get(h.index())
        .and_then(|hr| halfedges.get(hr.next.index()))
        .and_then(|h1| halfedges.get(h1.next.index()))
    else {
        return;
    };
    if step == 0 {
        return prefetch(halfedges, h2.twin.index());
    }
    let Some(ac) = halfedges.get(h2.twin.index()) else {
        return;
    };
    if step == 1 {
        return prefetch(halfedges, ac.next.index());
    }
    if let Some(g) = halfedges.get(ac.next.index()) {
        prefetch(halfedges, g.twin.index());
    }
}

/// Step 3, from any list of edges: flips each of `edges` that is new and
/// joins an old vertex to a new one, in the list's order.
pub fn flip_old_new(
    mesh: &mut Mesh,
    edges: &[EdgeId],
    flip: fn(&mut Mesh, EdgeId) -> Option<EdgeId>,
) {
    // The flag first, in one pass: half the edges are old, and reading it
    // alone keeps their halfedges and vertices out of the cache, and the
    // fetching ahead below looks only at edges that will be looked at.
    let new: Vec<EdgeId> = edges.iter().copied().filter(|&e| mesh[e].is_new).collect();
    for (i, &e) in new.iter().enumerate() {
        fetch_for(mesh, &new, i);
        let (a, b) = mesh.edge_vertices(e);
        if mesh[a].is_new != mesh[b].is_new {
            flip(mesh, e);
        }
    }
}

/// Step 4: every vertex to its `new_pos`.
pub fn move_vertices(mesh: &mut Mesh) {
    for v in mesh.vertex_ids() {
        mesh[v].pos = mesh[v].new_pos;
    }
}
