//! The model answer of the Catmull-Clark lab: `bisect_edge`,
//! `split_face_to_quads` and `catmull_clark_subdivide`, written the way the
//! lab asks (Catmull and Clark 1978, in the textbook's four steps), with
//! the signatures of the student's stubs (`catmull_clark_stubs.rs.txt`), so
//! a TA can paste them in. The doc comments of the three are the stubs'
//! contracts, word for word (a test holds them equal). Beyond the lab:
//! meshes with boundary, the bonus.
//!
//! The helpers below the three (`face_points`, `edge_points`,
//! `vertex_points`, ...) are the steps, public so that the named mistakes
//! ([`super::catmull_clark_mistakes`]) can swap one step each.

use halfedge::{DVec3, EdgeId, FaceId, HalfedgeId, Mesh, VertexId};

/// Bisects edge `e`: inserts a vertex `m` at its midpoint, so that each
/// of the two faces beside it (or the face and the hole) gains a corner.
/// No face is added and none is cut: a quad beside `e` becomes a pentagon,
/// a triangle a quad.
///
/// The names: `h = mesh[e].halfedge` runs a -> b inside face `f0` and is
/// followed by `h_next`; its twin `t` runs b -> a inside face `f1`, and
/// `t_prev = mesh.prev(t)` comes just before `t`. Either face may be a hole
/// (`is_boundary`): the code is the same for both sides.
///
/// Contract:
/// - Returns `Some(m)`, the new vertex, at the midpoint of `a` and `b`
///   (`(mesh[a].pos + mesh[b].pos) / 2.0`), marked `mesh[m].is_new = true`:
///   the mark [`split_face_to_quads`] tells its corners by. Its `new_pos`
///   is left `DVec3::ZERO`.
/// - Never returns `None`: every edge of a valid mesh can take a vertex.
///   Its two sides only gain a corner (a hole's loop as well as a face),
///   so no face loses a side and no edge is doubled: there is nothing to
///   refuse. (The `Option` matches the other operations' signatures.)
/// - Adds exactly 1 vertex, 1 edge and 2 halfedges, and no face. `e`
///   becomes the half a-m: `mesh[e].halfedge` is still `h`, now running
///   a -> m, so `mesh.edge_vertices(e) == (a, m)`. The new edge `eb` joins
///   m and b, with `is_new == false` and `new_pos == DVec3::ZERO` like any
///   new edge; `e` keeps its own `is_new` and `new_pos`.
/// - `mesh[m].halfedge` is `hb`, running m -> b inside `f0`.
/// - Changes no position, and no mark but `m`'s.
/// - Afterwards `mesh.validate()` is `Ok`, and `f0` and `f1` each have one
///   corner more, `m`, between `a` and `b`.
///
/// The elements: new vertex `m`; new edge `eb`; new halfedges `hb` (m -> b,
/// in `f0`, followed by `h_next`) and `tb` (b -> m, in `f1`, followed by
/// `t`), twins of each other on `eb`. `h` and `t` stay twins on `e`: `h`
/// still leaves `a` and is now followed by `hb`; `t` now leaves `m` (its
/// `vertex` changes) and is now preceded by `tb`, so `t_prev`'s `next`
/// becomes `tb`. Then the pointers *into* the picture: `mesh[b].halfedge`
/// may have been `t`, which no longer leaves `b` (`tb` does); the faces'
/// halfedges are all still in their faces.
///
/// Pitfalls: take `mesh.prev(t)` before relinking anything (the walk needs
/// the old links); forgetting that `t` now starts at `m`; forgetting
/// `mesh[b].halfedge`; forgetting the mark on `m`, without which
/// [`split_face_to_quads`] refuses every face.
pub fn bisect_edge(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let h = mesh[e].halfedge; // a -> b in f0
    let t = mesh[h].twin; // b -> a in f1
    let (a, b) = (mesh[h].vertex, mesh[t].vertex);
    let (f0, f1) = (mesh[h].face, mesh[t].face);
    let h_next = mesh[h].next;
    let t_prev = mesh.prev(t);

    let m = mesh.new_vertex((mesh[a].pos + mesh[b].pos) / 2.0);
    let eb = mesh.new_edge(); // m - b, the other half
    let hb = mesh.new_halfedge(); // m -> b, in f0
    let tb = mesh.new_halfedge(); // b -> m, in f1

    // f0: ... -> h (a -> m) -> hb (m -> b) -> h_next -> ...
    mesh[h].next = hb;
    mesh.set_neighbors(hb, h_next, tb, m, eb, f0);
    // f1: ... -> t_prev -> tb (b -> m) -> t (m -> a) -> ...
    mesh[t_prev].next = tb;
    mesh.set_neighbors(tb, t, hb, b, eb, f1);
    mesh[t].vertex = m;

    mesh[m].halfedge = hb;
    mesh[m].is_new = true;
    mesh[eb].halfedge = hb;
    if mesh[b].halfedge == t {
        mesh[b].halfedge = tb;
    }
    Some(m)
}

/// Splits face `f`, whose corners alternate between marked ones
/// (`is_new`: the vertices [`bisect_edge`] made) and unmarked ones (the
/// face's own corners), into quads: a new vertex `c` inside, joined to
/// every marked corner. A face of 2k corners becomes k quads, each
/// (c, m_i, v_i, m_(i+1)): the centre, a marked corner, the unmarked corner
/// after it and the marked corner after that.
///
/// How it tells the corners: by the marks alone. Walking around `f` from
/// `mesh[f].halfedge` (its `next` links), `m_0` is the first marked corner
/// met; from there the corners must alternate, marked, unmarked, marked,
/// ..., all the way round: `m_0, v_0, m_1, v_1, ..., m_(k-1), v_(k-1)`.
///
/// Contract:
/// - Returns `Some(c)`, the new vertex, at the **face point**: the mean of
///   the unmarked corners' positions, `(v_0 + ... + v_(k-1)) / k` (the
///   face's corners from before its edges were bisected; the marked ones
///   do not count). `mesh[c].is_new = true`; its `new_pos` is left
///   `DVec3::ZERO`.
/// - Returns `None`, changing nothing, when `f` is a hole
///   (`mesh[f].is_boundary`), when `f` has an odd number of corners (a
///   triangle; a quad with one edge bisected), when none of its corners is
///   marked, and when the marks do not alternate (two marked or two
///   unmarked corners side by side: an edge of the face was not bisected,
///   or a corner is marked that should not be).
/// - Adds 1 vertex, k edges (the spokes c-m_i, marked `is_new = true`),
///   k - 1 faces and 2k halfedges. `f` stays as the quad (c, m_0, v_0,
///   m_1); the other k - 1 quads are new faces.
/// - `mesh[c].halfedge` runs c -> m_0, inside `f`.
/// - Changes no position and no mark but the new elements'. Every old
///   halfedge of `f` keeps its `vertex`, `twin` and `edge`; its `face`
///   changes (but in the quad that keeps `f`), and so does the `next` of
///   each one arriving at a marked corner.
/// - Afterwards `mesh.validate()` is `Ok`.
///
/// The elements: call the old halfedges around `f`, from the one leaving
/// `m_0`, `g_0 ... g_(2k-1)`: `g_2i` runs m_i -> v_i and `g_(2i+1)` runs
/// v_i -> m_(i+1). For each marked corner m_i a spoke edge `s_i` with
/// halfedges `out_i` (c -> m_i) and `in_i` (m_i -> c), twins. Quad i is
/// the loop `out_i -> g_2i -> g_(2i+1) -> in_(i+1) -> out_i`, indices mod k
/// (the last quad ends with `in_0`): `in_(i+1)` lies in quad i, its twin
/// `out_(i+1)` in quad i + 1. Each quad's `halfedge` can be its `out_i`.
/// No old vertex's `halfedge` needs to change: each still leaves it.
///
/// Pitfalls: collect the corners and halfedges before creating anything;
/// counting the marked corners in the face point; forgetting that the
/// last quad wraps round to `m_0`; setting the `face` of the `g`s but not
/// of the spokes' halfedges; splitting a face before all its edges are
/// bisected (its marks do not alternate yet: refused).
pub fn split_face_to_quads(mesh: &mut Mesh, f: FaceId) -> Option<VertexId> {
    if mesh[f].is_boundary {
        return None;
    }
    let mut around = mesh.face_halfedges(f);
    if around.len() % 2 != 0 {
        return None;
    }
    let first = around.iter().position(|&g| mesh[mesh[g].vertex].is_new)?;
    around.rotate_left(first);
    let alternates = around
        .iter()
        .enumerate()
        .all(|(i, &g)| mesh[mesh[g].vertex].is_new == (i % 2 == 0));
    if !alternates {
        return None;
    }
    let marked: Vec<usize> = (0..around.len()).step_by(2).collect();
    let centre = unmarked_mean(mesh, &around);
    Some(join_centre(mesh, &around, &marked, centre))
}

/// The mean of the corners at odd places of `around` (the unmarked ones
/// of a face [`split_face_to_quads`] accepted).
fn unmarked_mean(mesh: &Mesh, around: &[HalfedgeId]) -> DVec3 {
    let unmarked: Vec<DVec3> = around
        .iter()
        .skip(1)
        .step_by(2)
        .map(|&g| mesh[mesh[g].vertex].pos)
        .collect();
    unmarked.iter().copied().sum::<DVec3>() / unmarked.len() as f64
}

/// The relinking part of a split, with no checks: a new vertex at `centre`
/// joined to the corners that the halfedges `around[j]` leave, for each
/// `j` in `marked` (increasing, at least two, none side by side, the first
/// 0), `around` being the face's halfedges in order. The first piece keeps
/// the face's id. Returns the new vertex.
///
/// [`split_face_to_quads`] joins every other corner; the named mistake of
/// splitting too early joins whatever corners are marked so far.
pub(crate) fn join_centre(
    mesh: &mut Mesh,
    around: &[HalfedgeId],
    marked: &[usize],
    centre: DVec3,
) -> VertexId {
    let k = marked.len();
    let f = mesh[around[0]].face;
    let c = mesh.new_vertex(centre);
    mesh[c].is_new = true;
    let spokes: Vec<EdgeId> = (0..k).map(|_| mesh.new_edge()).collect();
    let pieces: Vec<FaceId> = (0..k)
        .map(|i| if i == 0 { f } else { mesh.new_face() })
        .collect();
    let outs: Vec<HalfedgeId> = (0..k).map(|_| mesh.new_halfedge()).collect();
    let ins: Vec<HalfedgeId> = (0..k).map(|_| mesh.new_halfedge()).collect();
    let corner = |mesh: &Mesh, i: usize| mesh[around[marked[i]]].vertex;
    for i in 0..k {
        let j = (i + 1) % k;
        let piece = pieces[i];
        let m_j = corner(mesh, j);
        // The old halfedges from m_i up to (not including) m_j's.
        let end = if j == 0 { around.len() } else { marked[j] };
        let run = &around[marked[i]..end];
        mesh.set_neighbors(outs[i], run[0], ins[i], c, spokes[i], piece);
        for &g in run {
            mesh[g].face = piece;
        }
        let last = *run.last().expect("a run holds a halfedge");
        mesh[last].next = ins[j];
        mesh.set_neighbors(ins[j], outs[i], outs[j], m_j, spokes[j], piece);
        mesh[spokes[i]].halfedge = outs[i];
        mesh[spokes[i]].is_new = true;
        mesh[piece].halfedge = outs[i];
    }
    mesh[c].halfedge = outs[0];
    c
}

/// Catmull-Clark subdivision, one round, as the textbook teaches it: every
/// face of n corners becomes n quads, and every vertex moves, so the
/// surface gets smoother. Works on triangles, quads and mixed faces;
/// afterwards every face is a quad.
///
/// Contract:
/// - Every old vertex keeps its id and moves to its **vertex point**; a
///   new vertex is added at each old edge's **edge point** and at each old
///   real face's **face point** (the rules in step 1 below).
/// - Each old face of n corners is replaced by n quads, one per corner:
///   (the corner, the edge point of the edge after it, the face point, the
///   edge point of the edge before it), wound like the old face.
/// - With V vertices, E edges and F real faces before, and D the sum of
///   the faces' degrees (their corners): V + E + F vertices, 2E + D edges
///   and D real faces afterwards. A hole stays one hole, with twice as many
///   edges.
/// - Works on any valid mesh (faces of three sides or more), however the
///   `is_new` and `new_pos` fields were left, by an earlier round or
///   anything else. Afterwards `mesh.validate()` is `Ok`.
///
/// 1. **Compute every new position first**, while the mesh is unchanged.
///    Store them; move nothing yet.
///    - Clear the marks: `is_new = false` on every vertex and edge (the
///      previous round left its new vertices marked, and
///      [`split_face_to_quads`] tells corners by the marks).
///    - The **face point** of each real face: the mean of its corners,
///      `(p_1 + ... + p_n) / n`. Keep them in a list indexed by face
///      (`f.index()`): faces have no `new_pos`.
///    - The **edge point** of each edge (a, b) between faces f0 and f1:
///      `mesh[e].new_pos = (a + b + face_point(f0) + face_point(f1)) / 4`.
///    - The **vertex point** of each vertex P with n edges:
///      `mesh[v].new_pos = (F + 2R + (n - 3) P) / n`, where F is the mean
///      of the face points of the n faces around P and R the mean of the
///      **midpoints** of its n edges (`(P + q) / 2` for each neighbour q:
///      not the edge points).
/// 2. **Bisect every old edge** with [`bisect_edge`]. Take the list first
///    (`let old: Vec<EdgeId> = mesh.edge_ids().collect();`), and the real
///    faces too (`mesh.real_face_ids()`), before anything changes. For each
///    old edge `e`: `let m = bisect_edge(mesh, e)`, then
///    `mesh[m].new_pos = mesh[e].new_pos` (the edge point: **a new vertex
///    has no rule of its own**; left alone it moves to the origin in step 4).
/// 3. **Split every old face** with [`split_face_to_quads`] (every real
///    face listed in step 2; not the holes). Each face's edges are all
///    bisected by now, so none is refused. Set `mesh[c].new_pos` to the
///    face's face point (where the split put `c`).
/// 4. **Move every vertex** to its `new_pos`: `mesh[v].pos = mesh[v].new_pos`.
///
/// After one round the lab's objects (all triangles) have: cube 38 vertices / 72 edges / 36 faces, torus
/// 432 / 864 / 432, cylinder 98 / 192 / 96, cone 32 / 60 / 30.
///
/// Boundaries (bonus): an edge with a hole on one side has its edge point
/// at the midpoint, `(a + b) / 2`. A vertex on a hole with exactly two
/// edges (it belongs to one real face only: a **corner**, such as each of
/// a quad grid's four corners) stays where it is. Every other vertex on a
/// hole moves to `(x + 6P + y) / 8`, where x and y are its two neighbours
/// along the hole (the far ends of its two boundary edges,
/// `mesh.edge_on_boundary`), whatever its degree. Vertices and edges not on
/// a hole use the rules above even next to one.
///
/// Pitfalls: computing points after bisecting started (an edge point needs
/// its faces' face points from the unchanged mesh) or after moving a vertex;
/// R from the edge points instead of the midpoints; the weights 1, 2 and
/// n - 3; leaving the previous round's marks on the old vertices (every
/// split is then refused); splitting a face before all its edges are
/// bisected; splitting the holes or the new quads; forgetting
/// `mesh[m].new_pos` or `mesh[c].new_pos`.
pub fn catmull_clark_subdivide(mesh: &mut Mesh) {
    clear_marks(mesh);
    let face_points = face_points(mesh);
    edge_points(mesh, &face_points);
    vertex_points(mesh, &face_points, interior_point);
    let old_edges: Vec<EdgeId> = mesh.edge_ids().collect();
    let old_faces = mesh.real_face_ids();
    reserve_round(mesh);
    bisect_edges(mesh, &old_edges);
    split_faces(mesh, &old_faces, &face_points);
    move_vertices(mesh);
}

/// Step 1a: every vertex and edge unmarked.
pub fn clear_marks(mesh: &mut Mesh) {
    for v in mesh.vertex_ids() {
        mesh[v].is_new = false;
    }
    for e in mesh.edge_ids() {
        mesh[e].is_new = false;
    }
}

/// Step 1b: the face point of every real face (the mean of its corners),
/// by face index; `DVec3::ZERO` for a hole, which has none.
pub fn face_points(mesh: &Mesh) -> Vec<DVec3> {
    mesh.face_ids()
        .map(|f| {
            if mesh[f].is_boundary {
                DVec3::ZERO
            } else {
                mesh.face_center(f)
            }
        })
        .collect()
}

/// Step 1c: every edge's edge point, into its `new_pos`: the mean of its
/// ends and its two faces' points, or its midpoint beside a hole.
pub fn edge_points(mesh: &mut Mesh, face_points: &[DVec3]) {
    for e in mesh.edge_ids() {
        let h = mesh[e].halfedge;
        let t = mesh[h].twin;
        let (a, b) = (mesh[mesh[h].vertex].pos, mesh[mesh[t].vertex].pos);
        mesh[e].new_pos = if mesh.edge_on_boundary(e) {
            (a + b) / 2.0
        } else {
            let (f0, f1) = (mesh[h].face, mesh[t].face);
            (a + b + face_points[f0.index()] + face_points[f1.index()]) / 4.0
        };
    }
}

/// The rule for a vertex away from the holes, from the mesh, the vertex
/// and the face points: the model's is [`interior_point`].
pub type InteriorRule = fn(&Mesh, VertexId, &[DVec3]) -> DVec3;

/// What the vertex rule reads around an interior vertex `v`: its degree n,
/// F (the mean of the face points around it) and R (the mean of its edges'
/// midpoints).
pub fn around_vertex(mesh: &Mesh, v: VertexId, face_points: &[DVec3]) -> (usize, DVec3, DVec3) {
    let p = mesh[v].pos;
    let out = mesh.vertex_halfedges(v);
    let n = out.len();
    let f = out
        .iter()
        .map(|&h| face_points[mesh[h].face.index()])
        .sum::<DVec3>()
        / n as f64;
    let r = out
        .iter()
        .map(|&h| (p + mesh[mesh.halfedge_dst(h)].pos) / 2.0)
        .sum::<DVec3>()
        / n as f64;
    (n, f, r)
}

/// The textbook's rule: `(F + 2R + (n - 3) P) / n`.
pub fn interior_point(mesh: &Mesh, v: VertexId, face_points: &[DVec3]) -> DVec3 {
    let (n, f, r) = around_vertex(mesh, v, face_points);
    let n_f = n as f64;
    (f + 2.0 * r + (n_f - 3.0) * mesh[v].pos) / n_f
}

/// Whether `v` is a corner: on a hole, with exactly two edges (so in one
/// real face only). Corners stay where they are.
pub fn is_corner(mesh: &Mesh, v: VertexId) -> bool {
    mesh.vertex_on_boundary(v) && mesh.vertex_degree(v) == 2
}

/// The two neighbours of boundary vertex `v` along its hole: the far ends
/// of its two boundary edges.
pub fn boundary_neighbours(mesh: &Mesh, v: VertexId) -> [VertexId; 2] {
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

/// Step 1d: every vertex's new position, into its `new_pos`: corners stay,
/// other boundary vertices take `(x + 6P + y) / 8`, the rest `interior`.
pub fn vertex_points(mesh: &mut Mesh, face_points: &[DVec3], interior: InteriorRule) {
    for v in mesh.vertex_ids() {
        let p = mesh[v].pos;
        mesh[v].new_pos = if !mesh.vertex_on_boundary(v) {
            interior(mesh, v, face_points)
        } else if is_corner(mesh, v) {
            p
        } else {
            let [x, y] = boundary_neighbours(mesh, v);
            (mesh[x].pos + 6.0 * p + mesh[y].pos) / 8.0
        };
    }
}

/// Makes room for everything one round adds (a speed-up only, see
/// `Mesh::reserve`): E bisections of 1 vertex, 1 edge and 2 halfedges,
/// then per face of degree d 1 vertex, d edges, d - 1 faces, 2d halfedges.
pub fn reserve_round(mesh: &mut Mesh) {
    let edges = mesh.num_edges();
    let degrees = mesh.face_degrees();
    let (faces, corners) = (degrees.faces(), degrees.corners());
    mesh.reserve(
        edges + faces,
        edges + corners,
        corners - faces,
        2 * edges + 2 * corners,
    );
}

/// Step 2: bisects each of `edges` (the old ones); each new vertex gets the
/// edge's point as its `new_pos`.
pub fn bisect_edges(mesh: &mut Mesh, edges: &[EdgeId]) {
    for &e in edges {
        let m = bisect_edge(mesh, e).expect("bisect_edge refuses nothing");
        mesh[m].new_pos = mesh[e].new_pos;
    }
}

/// Step 3: splits each of `faces` (the old real ones, all edges bisected);
/// each centre gets its face's point as its `new_pos`.
///
/// # Panics
/// If a face is refused, naming it: on a valid mesh whose old vertices
/// were unmarked, none is.
pub fn split_faces(mesh: &mut Mesh, faces: &[FaceId], face_points: &[DVec3]) {
    for &f in faces {
        let Some(c) = split_face_to_quads(mesh, f) else {
            panic!(
                "split_face_to_quads refused {}: were all its edges bisected and \
                 the old vertices unmarked?",
                mesh.describe_corners(f)
            );
        };
        mesh[c].new_pos = face_points[f.index()];
    }
}

/// Step 4: every vertex to its `new_pos`.
pub fn move_vertices(mesh: &mut Mesh) {
    for v in mesh.vertex_ids() {
        mesh[v].pos = mesh[v].new_pos;
    }
}
