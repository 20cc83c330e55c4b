//! The √3 lab's model solution against the paper: values worked out by hand
//! from Kobbelt's formulas on small meshes, and a second construction of
//! each round written here from the paper's description on plain triangle
//! lists (no halfedges, no code shared with the model), compared vertex by
//! vertex and triangle by triangle on the lab's objects and open meshes.

use std::collections::{BTreeSet, HashMap};
use std::f64::consts::TAU;
use std::panic::{catch_unwind, AssertUnwindSafe};

use halfedge::{shapes, DVec3, FaceId, Mesh, VertexId};
use reference::labs::sqrt3::{split_face, sqrt3_subdivide, sqrt3_subdivide_round};
use reference::labs::sqrt3_mistakes::sqrt3_mistakes;

const TOL: f64 = 1e-12;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn assert_close(got: DVec3, want: DVec3, what: &str) {
    assert!(
        got.distance(want) < TOL,
        "{what}: at {got}, the formula gives {want}"
    );
}

/// `a_n = (4 - 2 cos(2 pi / n)) / 9`, written out again here.
fn a(n: usize) -> f64 {
    (4.0 - 2.0 * (TAU / n as f64).cos()) / 9.0
}

fn counts(mesh: &Mesh) -> (usize, usize, usize, usize) {
    (
        mesh.num_vertices(),
        mesh.num_edges(),
        mesh.num_real_faces(),
        mesh.num_halfedges(),
    )
}

fn valid(mesh: &Mesh, what: &str) {
    if let Err(bad) = mesh.validate() {
        panic!("{what}: {bad}");
    }
}

fn vid(i: usize) -> VertexId {
    VertexId::from_index(i)
}

fn tetra_corners() -> [DVec3; 4] {
    [
        v(1.0, 1.0, 1.0),
        v(1.0, -1.0, -1.0),
        v(-1.0, 1.0, -1.0),
        v(-1.0, -1.0, 1.0),
    ]
}

/// A regular tetrahedron centred at the origin, faces wound consistently.
fn tetrahedron() -> Mesh {
    let faces = vec![vec![0, 1, 2], vec![0, 3, 1], vec![0, 2, 3], vec![1, 3, 2]];
    Mesh::from_faces(&tetra_corners(), &faces).unwrap()
}

/// The octahedron on +-x, +-y, +-z (vertices 0..6 in that order), one
/// face per octant, counter-clockwise from outside.
fn octahedron() -> Mesh {
    let positions = [
        v(1.0, 0.0, 0.0),
        v(-1.0, 0.0, 0.0),
        v(0.0, 1.0, 0.0),
        v(0.0, -1.0, 0.0),
        v(0.0, 0.0, 1.0),
        v(0.0, 0.0, -1.0),
    ];
    let mut faces = Vec::new();
    for sx in [0, 1] {
        for sy in [0, 1] {
            for sz in [0, 1] {
                let mut f = vec![sx, 2 + sy, 4 + sz];
                if (sx + sy + sz) % 2 == 1 {
                    f.reverse();
                }
                faces.push(f);
            }
        }
    }
    Mesh::from_faces(&positions, &faces).unwrap()
}

/// Every vertex whose position is within `TOL` of `p`.
fn vertices_at(mesh: &Mesh, p: DVec3) -> Vec<VertexId> {
    mesh.vertex_ids()
        .filter(|&w| mesh[w].pos.distance(p) < TOL)
        .collect()
}

/// The one vertex at `p`, among ids `from..`.
fn the_vertex_at(mesh: &Mesh, p: DVec3, from: usize, what: &str) -> VertexId {
    let found: Vec<VertexId> = vertices_at(mesh, p)
        .into_iter()
        .filter(|w| w.index() >= from)
        .collect();
    assert_eq!(found.len(), 1, "{what}: vertices at {p}: {found:?}");
    found[0]
}

fn joined(mesh: &Mesh, p: VertexId, q: VertexId) -> bool {
    mesh.find_edge(p, q).is_some()
}

// ---- split_face --------------------------------------------------------------

#[test]
fn split_face_adds_a_centroid_joined_to_the_corners() {
    let mut meshes: Vec<(String, Mesh)> = vec![
        ("tetrahedron".into(), tetrahedron()),
        ("grid".into(), shapes::grid(2, 2)),
    ];
    for name in shapes::LAB_OBJECTS {
        meshes.push((name.into(), shapes::lab_object(name).unwrap()));
    }
    for (name, mut mesh) in meshes {
        let real: Vec<FaceId> = mesh.face_ids().filter(|&f| !mesh[f].is_boundary).collect();
        for f in real {
            let (v0, e0, f0, h0) = counts(&mesh);
            let faces_before = mesh.num_faces();
            let h = mesh[f].halfedge;
            let corners = mesh.face_vertices(f);
            let (pa, pb, pc) = (
                mesh[corners[0]].pos,
                mesh[corners[1]].pos,
                mesh[corners[2]].pos,
            );
            let old_edges: Vec<_> = mesh.edge_ids().map(|e| mesh.edge_vertices(e)).collect();
            let what = format!("{name}: split_face({f})");

            let m = split_face(&mut mesh, f).unwrap_or_else(|| panic!("{what} refused"));
            valid(&mesh, &what);
            assert_eq!(counts(&mesh), (v0 + 1, e0 + 3, f0 + 2, h0 + 6), "{what}");
            assert_eq!(m.index(), v0, "{what}: the new vertex is the next id");
            assert_close(mesh[m].pos, (pa + pb + pc) / 3.0, &what);
            assert!(!mesh[m].is_new && mesh[m].new_pos == DVec3::ZERO, "{what}");
            // f is (a, b, m), h still a -> b in it; the new faces (b, c, m)
            // and (c, a, m).
            let [ca, cb, cc] = [corners[0], corners[1], corners[2]];
            assert_eq!(mesh[h].face, f, "{what}: h stays in f");
            let rotations = |f: FaceId| {
                let fv = mesh.face_vertices(f);
                (0..fv.len())
                    .map(|k| [fv[k], fv[(k + 1) % 3], fv[(k + 2) % 3]])
                    .collect::<Vec<_>>()
            };
            assert!(
                rotations(f).contains(&[ca, cb, m]),
                "{what}: f is (a, b, m)"
            );
            let new: Vec<FaceId> = (faces_before..mesh.num_faces())
                .map(FaceId::from_index)
                .collect();
            let mut found = [false, false];
            for g in new {
                found[0] |= rotations(g).contains(&[cb, cc, m]);
                found[1] |= rotations(g).contains(&[cc, ca, m]);
            }
            assert_eq!(found, [true, true], "{what}: (b, c, m) and (c, a, m)");
            let mut ring = mesh.vertex_neighbors(m);
            ring.sort();
            let mut want = vec![ca, cb, cc];
            want.sort();
            assert_eq!(ring, want, "{what}: m joined to the three corners");
            for (e, ends) in old_edges.iter().enumerate() {
                let now = mesh.edge_vertices(halfedge::EdgeId::from_index(e));
                assert_eq!(&now, ends, "{what}: e{e} joins what it joined");
            }
        }
    }
}

/// The whole mesh, every field of every record.
fn snapshot(mesh: &Mesh) -> String {
    format!("{:?}", mesh.records())
}

#[test]
fn split_face_refuses_quads_and_holes_and_changes_nothing() {
    // A square pyramid: a quad base and four triangles.
    let positions = [
        v(0.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(1.0, 1.0, 0.0),
        v(0.0, 1.0, 0.0),
        v(0.5, 0.5, 1.0),
    ];
    let faces = vec![
        vec![3, 2, 1, 0],
        vec![0, 1, 4],
        vec![1, 2, 4],
        vec![2, 3, 4],
        vec![3, 0, 4],
    ];
    let mut pyramid = Mesh::from_faces(&positions, &faces).unwrap();
    let quad = pyramid
        .face_ids()
        .find(|&f| pyramid.face_degree(f) == 4)
        .unwrap();
    let before = snapshot(&pyramid);
    assert_eq!(split_face(&mut pyramid, quad), None, "a quad");
    assert_eq!(snapshot(&pyramid), before, "a refused quad changes nothing");

    // The hole of an open mesh, and the holes of an open cylinder (a loop
    // of six: no triangle either way).
    for (name, mut mesh) in [
        ("grid", shapes::grid(2, 2)),
        ("open cylinder", shapes::cylinder(3, 1, 1.0, 1.0, false)),
    ] {
        let holes: Vec<FaceId> = mesh.face_ids().filter(|&f| mesh[f].is_boundary).collect();
        assert!(!holes.is_empty(), "{name} has holes");
        for f in holes {
            let before = snapshot(&mesh);
            assert_eq!(split_face(&mut mesh, f), None, "{name}: the hole {f}");
            assert_eq!(
                snapshot(&mesh),
                before,
                "{name}: a refused hole changes nothing"
            );
        }
    }
    // A hole that is a triangle: one triangle alone has two faces of three
    // halfedges, one of them the hole.
    let mut single = Mesh::from_faces(
        &[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)],
        &[vec![0, 1, 2]],
    )
    .unwrap();
    let hole = single.face_ids().find(|&f| single[f].is_boundary).unwrap();
    assert_eq!(single.face_degree(hole), 3);
    let before = snapshot(&single);
    assert_eq!(split_face(&mut single, hole), None, "a triangular hole");
    assert_eq!(snapshot(&single), before);
}

// ---- closed meshes by hand -----------------------------------------------------

/// The tetrahedron's corners P_i sum to 0, so each one's three neighbours
/// sum to -P_i, and the face opposite P_i has its centroid at -P_i / 3.
/// Round 1 (a_3 = 5/9): P_i -> 4/9 P_i + 5/27 (-P_i) = 7/27 P_i.
#[test]
fn tetrahedron_one_round_by_hand() {
    let p = tetra_corners();
    let mut mesh = tetrahedron();
    sqrt3_subdivide(&mut mesh);
    valid(&mesh, "tetrahedron, round 1");
    // V + F, E + 3F, 3F, and 6 halfedges per split.
    assert_eq!(counts(&mesh), (8, 18, 12, 36));
    for i in 0..4 {
        assert_close(mesh[vid(i)].pos, 7.0 / 27.0 * p[i], &format!("old v{i}"));
        assert_eq!(mesh.vertex_degree(vid(i)), 3, "old v{i} keeps its degree");
        let c = the_vertex_at(&mesh, -p[i] / 3.0, 4, "the centroid opposite P_i");
        assert_eq!(mesh.vertex_degree(c), 6, "a new vertex has degree 6");
        // Joined to the three corners of its face and, through the flips,
        // to the three other centroids; never to P_i.
        let mut ring: BTreeSet<usize> = BTreeSet::new();
        for w in mesh.vertex_neighbors(c) {
            ring.insert(w.index());
        }
        let mut want: BTreeSet<usize> = (0..4).filter(|&j| j != i).collect();
        want.extend((4..8).filter(|&w| w != c.index()));
        assert_eq!(ring, want, "centroid opposite P_{i}");
    }
    // The old edges are gone: no two old vertices are joined any more.
    for i in 0..4 {
        for j in 0..4 {
            assert!(i == j || !joined(&mesh, vid(i), vid(j)));
        }
    }
}

/// Round 2 on the tetrahedron, from round 1's positions:
/// - each triangle is (P_i, C_j, C_k), C_j, C_k the centroids of the two
///   faces on edge P_i P_l: centroid (7/27 P_i + (P_i + P_l) / 3) / 3
///   = (16 P_i + 9 P_l) / 81;
/// - old P_i (degree 3, neighbours C_j, j != i, summing to P_i / 3):
///   4/9 * 7/27 P_i + 5/27 * 1/3 P_i = 43/243 P_i;
/// - C_i = -P_i/3 (degree 6, a_6 = 1/3; neighbours 7/27 P_j and -P_j/3,
///   j != i, summing to 2/27 P_i): 2/3 (-P_i/3) + 1/18 * 2/27 P_i
///   = -53/243 P_i.
#[test]
fn tetrahedron_two_rounds_by_hand_cut_every_edge_in_three() {
    let p = tetra_corners();
    let mut mesh = tetrahedron();
    sqrt3_subdivide(&mut mesh);
    sqrt3_subdivide(&mut mesh);
    valid(&mesh, "tetrahedron, round 2");
    assert_eq!(counts(&mesh), (20, 54, 36, 108), "9 x the 4 faces");
    for i in 0..4 {
        assert_close(mesh[vid(i)].pos, 43.0 / 243.0 * p[i], &format!("old v{i}"));
        assert_eq!(mesh.vertex_degree(vid(i)), 3);
        let c = the_vertex_at(&mesh, -53.0 / 243.0 * p[i], 4, "round 1's centroid");
        assert!(c.index() < 8, "a round-1 vertex");
        assert_eq!(mesh.vertex_degree(c), 6);
    }
    // Each original edge P_i P_l is now P_i - x - y - P_l, x and y round 2's.
    for i in 0..4 {
        for l in 0..4 {
            if i == l {
                continue;
            }
            let x = the_vertex_at(&mesh, (16.0 * p[i] + 9.0 * p[l]) / 81.0, 8, "round 2");
            let y = the_vertex_at(&mesh, (16.0 * p[l] + 9.0 * p[i]) / 81.0, 8, "round 2");
            assert_eq!(mesh.vertex_degree(x), 6);
            assert!(joined(&mesh, vid(i), x), "P_{i} - x");
            assert!(joined(&mesh, x, y), "x - y");
            assert!(joined(&mesh, y, vid(l)), "y - P_{l}");
        }
    }
}

/// The octahedron: every vertex has degree 4 (a_4 = 4/9) and its four
/// neighbours sum to 0; face centroids are (+-1, +-1, +-1) / 3.
/// - round 1: e -> 5/9 e;
/// - round 2: old e (neighbours the four centroids with e's sign, summing
///   to 4/3 e) -> 5/9 * 5/9 e + 1/9 * 4/3 e = 37/81 e;
///   centroid (1, 1, 1)/3 (degree 6; neighbours 5/9 e_x, 5/9 e_y, 5/9 e_z
///   and the three adjacent centroids, summing to 8/9 (1, 1, 1))
///   -> 2/3 * 1/3 + 1/18 * 8/9 = 22/81 (1, 1, 1);
///   the triangle (e_x, C(1,1,1), C(1,1,-1)) has centroid
///   (5/9 e_x + 2/3 (e_x + e_y)) / 3 = 11/27 e_x + 6/27 e_y.
#[test]
fn octahedron_one_and_two_rounds_by_hand() {
    let mut mesh = octahedron();
    let axes: Vec<DVec3> = mesh.vertex_ids().map(|w| mesh[w].pos).collect();
    sqrt3_subdivide(&mut mesh);
    valid(&mesh, "octahedron, round 1");
    assert_eq!(counts(&mesh), (14, 36, 24, 72));
    for (i, &e) in axes.iter().enumerate() {
        assert_close(mesh[vid(i)].pos, 5.0 / 9.0 * e, &format!("v{i}"));
        assert_eq!(mesh.vertex_degree(vid(i)), 4);
    }
    let signs = [-1.0, 1.0];
    for sx in signs {
        for sy in signs {
            for sz in signs {
                let c = the_vertex_at(&mesh, v(sx, sy, sz) / 3.0, 6, "a centroid");
                assert_eq!(mesh.vertex_degree(c), 6);
            }
        }
    }

    sqrt3_subdivide(&mut mesh);
    valid(&mesh, "octahedron, round 2");
    assert_eq!(counts(&mesh), (38, 108, 72, 216), "9 x the 8 faces");
    for (i, &e) in axes.iter().enumerate() {
        assert_close(mesh[vid(i)].pos, 37.0 / 81.0 * e, &format!("v{i}"));
    }
    for sx in signs {
        for sy in signs {
            for sz in signs {
                let c = the_vertex_at(&mesh, 22.0 / 81.0 * v(sx, sy, sz), 6, "round 1's");
                assert!(c.index() < 14);
            }
        }
    }
    // Original edge e_i - e_j: e_i - x - y - e_j.
    for (i, &ei) in axes.iter().enumerate() {
        for (j, &ej) in axes.iter().enumerate() {
            if ei.dot(ej) != 0.0 {
                continue; // the same vertex or the opposite one
            }
            let x = the_vertex_at(&mesh, (11.0 * ei + 6.0 * ej) / 27.0, 14, "round 2");
            let y = the_vertex_at(&mesh, (11.0 * ej + 6.0 * ei) / 27.0, 14, "round 2");
            assert!(joined(&mesh, vid(i), x) && joined(&mesh, x, y) && joined(&mesh, y, vid(j)));
        }
    }
}

/// The lab's cube (cube.obj; vertex k below is the file's k + 1):
/// - v1 = (0.5, -0.5, -0.5) has degree 4 (faces 3 1 2, 4 3 2, 4 2 5,
///   2 1 5), neighbours v0, v2, v3, v4 summing to (0, 0, -1):
///   round 1: 5/9 v1 + 1/9 (0, 0, -1) = (5/18, -5/18, -7/18);
///   its faces' centroids (-1/6, -1/6, -1/2), (1/6, 1/6, -1/2),
///   (1/2, -1/6, -1/6), (1/6, -1/2, -1/6) sum to (2/3, -2/3, -4/3), and
///   are its neighbours after round 1: round 2: 5/9 (5/18, -5/18, -7/18)
///   + 1/9 (2/3, -2/3, -4/3) = (37, -37, -59) / 162.
/// - v0 = (-0.5, -0.5, -0.5) has degree 5, neighbours v1, v2, v4, v6, v7
///   summing to (-0.5, -0.5, 0.5).
#[test]
fn lab_cube_by_hand() {
    let mut mesh = shapes::lab_object("cube").unwrap();
    assert_eq!(mesh.vertex_degree(vid(1)), 4);
    assert_eq!(mesh.vertex_degree(vid(0)), 5);
    sqrt3_subdivide(&mut mesh);
    assert_close(mesh[vid(1)].pos, v(5.0, -5.0, -7.0) / 18.0, "v1, round 1");
    let a5 = a(5);
    let v0 = (1.0 - a5) * v(-0.5, -0.5, -0.5) + a5 / 5.0 * v(-0.5, -0.5, 0.5);
    assert_close(mesh[vid(0)].pos, v0, "v0, round 1");
    let centroids = [
        v(-1.0, -1.0, -3.0) / 6.0,
        v(1.0, 1.0, -3.0) / 6.0,
        v(3.0, -1.0, -1.0) / 6.0,
        v(1.0, -3.0, -1.0) / 6.0,
    ];
    let mut ring: Vec<VertexId> = mesh.vertex_neighbors(vid(1));
    ring.sort();
    let mut want: Vec<VertexId> = centroids
        .iter()
        .map(|&c| the_vertex_at(&mesh, c, 8, "a centroid of v1's faces"))
        .collect();
    want.sort();
    assert_eq!(ring, want, "v1's neighbours are its faces' centroids");
    sqrt3_subdivide(&mut mesh);
    assert_close(
        mesh[vid(1)].pos,
        v(37.0, -37.0, -59.0) / 162.0,
        "v1, round 2",
    );
}

/// The lab's cone: the apex v6 has the six base vertices around it, whose
/// positions sum to 0, so round 1 takes it to (1 - 1/3) of its height.
/// The lab's cylinder: v1 = (0.9, 0, 0) on the bottom rim has degree 5
/// (faces 3 1 2, 2 1 9, 11 10 2, 2 10 3, 9 11 2 of cylinder.obj).
#[test]
fn lab_cone_and_cylinder_by_hand() {
    let mut cone = shapes::lab_object("cone").unwrap();
    assert_eq!(cone.vertex_degree(vid(6)), 6);
    sqrt3_subdivide(&mut cone);
    assert!(
        cone[vid(6)].pos.distance(v(0.0, 2.025420 * 2.0 / 3.0, 0.0)) < 1e-9,
        "the apex at {}",
        cone[vid(6)].pos
    );

    let mut cylinder = shapes::lab_object("cylinder").unwrap();
    assert_eq!(cylinder.vertex_degree(vid(1)), 5);
    let around = [
        v(0.636396, 0.0, 0.636396),
        v(0.0, 0.0, 0.0),
        v(0.636396, 0.0, -0.636396),
        v(0.9, 1.5, 0.0),
        v(0.636396, 1.5, 0.636396),
    ];
    let sum: DVec3 = around.iter().copied().sum();
    sqrt3_subdivide(&mut cylinder);
    let want = (1.0 - a(5)) * v(0.9, 0.0, 0.0) + a(5) / 5.0 * sum;
    assert!(cylinder[vid(1)].pos.distance(want) < 1e-9);
}

// ---- the paper's construction, on triangle lists ---------------------------

/// A triangle mesh as the paper draws it: positions and corner triples.
#[derive(Clone, Debug)]
struct Tris {
    pos: Vec<DVec3>,
    tris: Vec<[usize; 3]>,
}

fn tris_of(mesh: &Mesh) -> Tris {
    let (pos, faces) = mesh.to_faces();
    let tris = faces
        .into_iter()
        .map(|f| <[usize; 3]>::try_from(f).expect("triangles only"))
        .collect();
    Tris { pos, tris }
}

/// One round of √3 subdivision built from the paper's description alone:
/// old vertices keep their indices, the new ones follow, face by face.
/// - odd rounds: a centroid in every triangle; every old vertex not on the
///   boundary smoothed with a_n; boundary vertices stay;
/// - even rounds: the same inside; each boundary edge a -> b (in its
///   triangle (a, b, c)) gets x = (a' + 16a + 10b)/27 and
///   y = (10a + 16b + b')/27, a' before a and b' after b along the
///   boundary, and its triangle becomes (x, y, c) plus the triangles at a
///   and b that the flips make; boundary vertices -> (4, 19, 4) / 27;
/// - every old interior edge u -> v is flipped: the two triangles on it,
///   (u, v, s) and (v, u, t), become (u, t, s) and (v, s, t), where s and
///   t are the new points facing the edge on either side.
fn paper_round(m: &Tris, round: usize) -> Tris {
    let even = round % 2 == 0;
    let old = m.pos.len();
    let mut face_edges: HashMap<(usize, usize), usize> = HashMap::new();
    for (f, t) in m.tris.iter().enumerate() {
        for k in 0..3 {
            face_edges.insert((t[k], t[(k + 1) % 3]), f);
        }
    }
    let on_rim = |u: usize, w: usize| !face_edges.contains_key(&(w, u));
    let mut neighbours: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); old];
    // Along the boundary, in the faces' winding: rim_next[u] = w when the
    // boundary edge u -> w is in a face.
    let mut rim_next: HashMap<usize, usize> = HashMap::new();
    let mut rim_prev: HashMap<usize, usize> = HashMap::new();
    for &(u, w) in face_edges.keys() {
        neighbours[u].insert(w);
        neighbours[w].insert(u);
        if on_rim(u, w) {
            assert!(rim_next.insert(u, w).is_none(), "one boundary through v{u}");
            rim_prev.insert(w, u);
        }
    }
    let p = &m.pos;
    let mut pos: Vec<DVec3> = (0..old)
        .map(|i| match (rim_prev.get(&i), rim_next.get(&i)) {
            (Some(&before), Some(&after)) if even => {
                (4.0 * p[before] + 19.0 * p[i] + 4.0 * p[after]) / 27.0
            }
            (Some(_), Some(_)) => p[i],
            _ => {
                let n = neighbours[i].len();
                let sum: DVec3 = neighbours[i].iter().map(|&j| p[j]).sum();
                (1.0 - a(n)) * p[i] + a(n) / n as f64 * sum
            }
        })
        .collect();

    // The new point facing each directed old edge, and the triangles no
    // flip touches.
    let mut facing: HashMap<(usize, usize), usize> = HashMap::new();
    let mut tris = Vec::new();
    for t in &m.tris {
        let rim: Vec<usize> = (0..3).filter(|&k| on_rim(t[k], t[(k + 1) % 3])).collect();
        if even && !rim.is_empty() {
            assert_eq!(
                rim.len(),
                1,
                "an even round's triangle has one boundary edge"
            );
            let k = rim[0];
            let (a_, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            let x = pos.len();
            pos.push((p[rim_prev[&a_]] + 16.0 * p[a_] + 10.0 * p[b]) / 27.0);
            let y = pos.len();
            pos.push((10.0 * p[a_] + 16.0 * p[b] + p[rim_next[&b]]) / 27.0);
            facing.insert((b, c), y);
            facing.insert((c, a_), x);
            tris.push([x, y, c]);
        } else {
            let centroid = pos.len();
            pos.push((p[t[0]] + p[t[1]] + p[t[2]]) / 3.0);
            for k in 0..3 {
                let (u, w) = (t[k], t[(k + 1) % 3]);
                facing.insert((u, w), centroid);
                if on_rim(u, w) {
                    tris.push([u, w, centroid]); // not flipped
                }
            }
        }
    }
    for (&(u, w), &s) in &facing {
        if !on_rim(u, w) {
            tris.push([u, facing[&(w, u)], s]);
        }
    }
    Tris { pos, tris }
}

/// The triangles as sets of rotations, smallest index first (winding kept).
fn normalised(tris: impl IntoIterator<Item = [usize; 3]>) -> Vec<[usize; 3]> {
    let mut out: Vec<[usize; 3]> = tris
        .into_iter()
        .map(|t| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap();
            [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        })
        .collect();
    out.sort();
    out
}

/// The model's mesh is the paper's: old vertices where the paper puts
/// them, every new vertex matched to the one paper point at its position,
/// and then the same triangles. Returns the paper's mesh with its vertices
/// numbered as the model's (the paper's own positions), so that the next
/// round's old vertices compare by id.
fn assert_is_paper(mesh: &Mesh, paper: &Tris, old: usize, what: &str) -> Tris {
    valid(mesh, what);
    let got = tris_of(mesh);
    assert_eq!(got.pos.len(), paper.pos.len(), "{what}: vertices");
    assert_eq!(got.tris.len(), paper.tris.len(), "{what}: triangles");
    let mut to_paper: Vec<usize> = (0..old).collect();
    for i in 0..old {
        assert!(
            got.pos[i].distance(paper.pos[i]) < 1e-9,
            "{what}: old v{i} at {}, the paper's rule gives {}",
            got.pos[i],
            paper.pos[i]
        );
    }
    let mut taken = vec![false; paper.pos.len()];
    for (i, &q) in got.pos.iter().enumerate().skip(old) {
        let near: Vec<usize> = (old..paper.pos.len())
            .filter(|&j| paper.pos[j].distance(q) < 1e-6)
            .collect();
        assert_eq!(
            near.len(),
            1,
            "{what}: new v{i} at {q} near paper points {near:?}"
        );
        let j = near[0];
        assert!(paper.pos[j].distance(q) < 1e-9, "{what}: new v{i}");
        assert!(!taken[j], "{what}: two new vertices at paper point {j}");
        taken[j] = true;
        to_paper.push(j);
    }
    let mapped = normalised(got.tris.iter().map(|t| t.map(|i| to_paper[i])));
    assert_eq!(
        mapped,
        normalised(paper.tris.iter().copied()),
        "{what}: triangles"
    );
    let mut from_paper = vec![0; to_paper.len()];
    for (i, &j) in to_paper.iter().enumerate() {
        from_paper[j] = i;
    }
    Tris {
        pos: to_paper.iter().map(|&j| paper.pos[j]).collect(),
        tris: paper
            .tris
            .iter()
            .map(|t| t.map(|j| from_paper[j]))
            .collect(),
    }
}

fn closed_meshes() -> Vec<(String, Mesh)> {
    let mut out: Vec<(String, Mesh)> = shapes::LAB_OBJECTS
        .iter()
        .map(|&n| (n.to_string(), shapes::lab_object(n).unwrap()))
        .collect();
    out.push(("tetrahedron".into(), tetrahedron()));
    out.push(("octahedron".into(), octahedron()));
    out.push(("icosphere".into(), shapes::icosphere(1)));
    out
}

#[test]
fn closed_meshes_three_rounds_are_the_papers() {
    for (name, mut mesh) in closed_meshes() {
        let mut paper = tris_of(&mesh);
        let (v0, e0, f0, _) = counts(&mesh);
        for round in 1..=3 {
            let what = format!("{name}, round {round}");
            let old = mesh.num_vertices();
            let (e, f) = (mesh.num_edges(), mesh.num_real_faces());
            let degrees: Vec<usize> = mesh.vertex_ids().map(|w| mesh.vertex_degree(w)).collect();
            sqrt3_subdivide(&mut mesh);
            paper = assert_is_paper(&mesh, &paper_round(&paper, round), old, &what);
            assert_eq!(
                counts(&mesh),
                (old + f, e + 3 * f, 3 * f, 2 * (e + 3 * f)),
                "{what}"
            );
            for (i, &d) in degrees.iter().enumerate() {
                assert_eq!(
                    mesh.vertex_degree(vid(i)),
                    d,
                    "{what}: old v{i} keeps its degree"
                );
            }
            for w in old..mesh.num_vertices() {
                assert_eq!(mesh.vertex_degree(vid(w)), 6, "{what}: new v{w}");
            }
        }
        // Two rounds made 9 x the faces; three 27 x.
        assert_eq!(mesh.num_real_faces(), 27 * f0, "{name}");
        assert_eq!(mesh.num_edges(), e0 + 3 * f0 + 9 * f0 + 27 * f0, "{name}");
        assert_eq!(mesh.num_vertices(), v0 + f0 + 3 * f0 + 9 * f0, "{name}");
    }
}

#[test]
fn lab_objects_one_round_has_the_documented_counts() {
    let want = [
        ("cube", (20, 54, 36)),
        ("torus", (216, 648, 432)),
        ("cylinder", (50, 144, 96)),
        ("cone", (17, 45, 30)),
    ];
    for (name, (nv, ne, nf)) in want {
        let mut mesh = shapes::lab_object(name).unwrap();
        sqrt3_subdivide(&mut mesh);
        let (v1, e1, f1, _) = counts(&mesh);
        assert_eq!((v1, e1, f1), (nv, ne, nf), "{name}");
    }
}

/// After two rounds every original edge a-b is cut in three: a - x - y - b
/// with x and y made in round 2, and the original vertices' neighbours are
/// all round 2's, one per original edge.
#[test]
fn two_rounds_line_up_with_the_original_edges() {
    for (name, mut mesh) in closed_meshes() {
        let edges: Vec<(VertexId, VertexId)> =
            mesh.edge_ids().map(|e| mesh.edge_vertices(e)).collect();
        let degrees: Vec<usize> = mesh.vertex_ids().map(|w| mesh.vertex_degree(w)).collect();
        sqrt3_subdivide(&mut mesh);
        let v1 = mesh.num_vertices();
        sqrt3_subdivide(&mut mesh);
        for (i, &d) in degrees.iter().enumerate() {
            let ring = mesh.vertex_neighbors(vid(i));
            assert_eq!(ring.len(), d, "{name}: v{i}");
            assert!(
                ring.iter().all(|w| w.index() >= v1),
                "{name}: v{i}'s ring {ring:?}"
            );
        }
        for (p, q) in edges {
            let cut = mesh.vertex_neighbors(p).into_iter().any(|x| {
                mesh.vertex_neighbors(q)
                    .into_iter()
                    .any(|y| joined(&mesh, x, y))
            });
            assert!(cut, "{name}: the original edge {p}-{q} is not cut in three");
        }
    }
}

// ---- boundaries ------------------------------------------------------------------

fn on_boundary(mesh: &Mesh) -> Vec<VertexId> {
    mesh.vertex_ids()
        .filter(|&w| mesh.vertex_on_boundary(w))
        .collect()
}

fn boundary_edges(mesh: &Mesh) -> usize {
    mesh.edge_ids()
        .filter(|&e| mesh.edge_on_boundary(e))
        .count()
}

/// grid(2, 2): 9 vertices at x, y in {-1/2, 0, 1/2}, z = xy/2, 8 triangles,
/// 16 edges, 8 of them on the rim. Round 1 (odd) keeps the rim; the
/// centre (0, 0, 0) has degree 6 (four axis neighbours summing to 0, and
/// the diagonal (+-1/2, +-1/2, 1/8) on the cut diagonal), so it moves to
/// 1/18 * (0, 0, 1/4) = (0, 0, 1/72).
#[test]
fn grid_one_round_keeps_the_boundary() {
    let mut mesh = shapes::grid(2, 2);
    let before: Vec<DVec3> = mesh.positions();
    let rim = on_boundary(&mesh);
    let rim_edges: Vec<(VertexId, VertexId)> = mesh
        .edge_ids()
        .filter(|&e| mesh.edge_on_boundary(e))
        .map(|e| mesh.edge_vertices(e))
        .collect();
    assert_eq!((rim.len(), rim_edges.len()), (8, 8));
    sqrt3_subdivide_round(&mut mesh, 1);
    valid(&mesh, "grid, round 1");
    assert_eq!(counts(&mesh).0, 9 + 8);
    assert_eq!(counts(&mesh).1, 16 + 3 * 8);
    assert_eq!(counts(&mesh).2, 3 * 8);
    for &w in &rim {
        assert_eq!(mesh[w].pos, before[w.index()], "{w} on the rim stays");
    }
    assert_close(mesh[vid(4)].pos, v(0.0, 0.0, 1.0 / 72.0), "the centre");
    for (p, q) in rim_edges {
        let e = mesh
            .find_edge(p, q)
            .expect("a boundary edge is not flipped");
        assert!(mesh.edge_on_boundary(e));
    }
    assert_eq!(boundary_edges(&mesh), 8);
    // sqrt3_subdivide is round 1.
    let mut again = shapes::grid(2, 2);
    sqrt3_subdivide(&mut again);
    assert_eq!(again.to_faces(), mesh.to_faces());
}

/// Round 2 (even) on grid(2, 2), from round 1's rim (unmoved):
/// - corner v0 = (-1/2, -1/2, 1/8), its rim neighbours v1 = (0, -1/2, 0)
///   and v3 = (-1/2, 0, 0): (4 v1 + 4 v3 + 19 v0) / 27
///   = (-23/54, -23/54, 19/216);
/// - the rim edge v0-v1 (v3 before v0, v2 = (1/2, -1/2, -1/8) after v1)
///   gets (v3 + 16 v0 + 10 v1) / 27 = (-17/54, -13/27, 2/27) and
///   (10 v0 + 16 v1 + v2) / 27 = (-1/6, -1/2, 1/24);
/// - v1, the middle of a straight side, stays: (4 v0 + 19 v1 + 4 v2) / 27
///   = v1 (the rule keeps lines).
#[test]
fn grid_two_rounds_cut_the_boundary_in_three() {
    let mut mesh = shapes::grid(2, 2);
    sqrt3_subdivide_round(&mut mesh, 1);
    let (v1_, e1, f1, _) = counts(&mesh);
    let rim1 = boundary_edges(&mesh);
    sqrt3_subdivide_round(&mut mesh, 2);
    valid(&mesh, "grid, round 2");
    // F + B vertices, 3F + B edges, 2F faces more (B = 8 rim edges).
    assert_eq!(
        (mesh.num_vertices(), mesh.num_edges(), mesh.num_real_faces()),
        (v1_ + f1 + rim1, e1 + 3 * f1 + rim1, 3 * f1)
    );
    assert_eq!(counts(&mesh), (49, 120, 72, 240));
    assert_eq!(boundary_edges(&mesh), 24, "each rim edge in three");
    assert_eq!(mesh.num_real_faces(), 9 * 8, "9 x the grid's triangles");
    assert_close(
        mesh[vid(0)].pos,
        v(-23.0 / 54.0, -23.0 / 54.0, 19.0 / 216.0),
        "corner v0",
    );
    assert_close(mesh[vid(1)].pos, v(0.0, -0.5, 0.0), "v1");
    let x = the_vertex_at(&mesh, v(-17.0 / 54.0, -13.0 / 27.0, 2.0 / 27.0), 17, "x");
    let y = the_vertex_at(&mesh, v(-1.0 / 6.0, -0.5, 1.0 / 24.0), 17, "y");
    for (p, q) in [(vid(0), x), (x, y), (y, vid(1))] {
        let e = mesh.find_edge(p, q).unwrap_or_else(|| panic!("{p}-{q}"));
        assert!(mesh.edge_on_boundary(e), "{p}-{q} is on the rim");
    }
    assert!(!joined(&mesh, vid(0), vid(1)));
    // A new rim vertex of a straight rim has degree 4, like the regular
    // boundary vertices of a triangle grid.
    assert_eq!(mesh.vertex_degree(x), 4);
    assert_eq!(mesh.vertex_degree(y), 4);
}

fn open_meshes() -> Vec<(String, Mesh)> {
    vec![
        ("grid 2x2".into(), shapes::grid(2, 2)),
        ("grid 3x2".into(), shapes::grid(3, 2)),
        (
            "open cylinder".into(),
            shapes::cylinder(6, 2, 1.0, 1.0, false),
        ),
        (
            "open cone".into(),
            shapes::frustum(5, 2, 1.0, 0.5, 1.0, false),
        ),
    ]
}

#[test]
fn open_meshes_four_rounds_are_the_papers() {
    for (name, mut mesh) in open_meshes() {
        let mut paper = tris_of(&mesh);
        for round in 1..=4 {
            let what = format!("{name}, round {round}");
            let old = mesh.num_vertices();
            let (e, f, b) = (
                mesh.num_edges(),
                mesh.num_real_faces(),
                boundary_edges(&mesh),
            );
            sqrt3_subdivide_round(&mut mesh, round);
            paper = assert_is_paper(&mesh, &paper_round(&paper, round), old, &what);
            let (nv, ne, nf, _) = counts(&mesh);
            if round % 2 == 1 {
                assert_eq!((nv, ne, nf), (old + f, e + 3 * f, 3 * f), "{what}");
                assert_eq!(boundary_edges(&mesh), b, "{what}: the rim as it was");
            } else {
                assert_eq!((nv, ne, nf), (old + f + b, e + 3 * f + b, 3 * f), "{what}");
                assert_eq!(boundary_edges(&mesh), 3 * b, "{what}: the rim in three");
            }
        }
    }
}

fn panic_text(run: impl FnOnce()) -> String {
    let err = catch_unwind(AssertUnwindSafe(run)).expect_err("it should panic");
    err.downcast_ref::<String>()
        .cloned()
        .or_else(|| err.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default()
}

#[test]
fn rounds_refuse_what_they_cannot_do_with_a_message() {
    // An even round straight on the grid: its corner triangle has two
    // boundary edges, which only an odd round first would have fixed.
    let text = panic_text(|| sqrt3_subdivide_round(&mut shapes::grid(2, 2), 2));
    assert!(text.contains("at most one boundary edge"), "{text}");
    let text = panic_text(|| sqrt3_subdivide_round(&mut shapes::grid(2, 2), 0));
    assert!(text.contains("counts rounds from 1"), "{text}");
    let positions = [
        v(0.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(1.0, 1.0, 0.0),
        v(0.0, 1.0, 0.0),
    ];
    let mut quad = Mesh::from_faces(&positions, &[vec![0, 1, 2, 3]]).unwrap();
    let text = panic_text(|| sqrt3_subdivide(&mut quad));
    assert!(text.contains("needs a triangle mesh"), "{text}");
}

// ---- named mistakes ------------------------------------------------------------

#[test]
fn each_named_mistake_differs_from_the_model_and_the_others() {
    let mistakes = sqrt3_mistakes();
    let ids: BTreeSet<&str> = mistakes.iter().map(|m| m.id).collect();
    assert_eq!(ids.len(), mistakes.len(), "ids are unique");
    for m in &mistakes {
        assert!(
            !m.hint.is_empty() && !m.hint.contains('\n'),
            "{}: one line",
            m.id
        );
    }
    for name in ["cube", "torus"] {
        let input = shapes::lab_object(name).unwrap();
        let mut model = input.clone();
        sqrt3_subdivide(&mut model);
        let mut results: Vec<(&str, Tris)> = vec![("model", tris_of(&model))];
        for m in &mistakes {
            let mut mesh = input.clone();
            (m.run)(&mut mesh);
            results.push((m.id, tris_of(&mesh)));
        }
        for (i, (a_id, a_res)) in results.iter().enumerate() {
            for (b_id, b_res) in &results[i + 1..] {
                assert!(
                    differ(a_res, b_res),
                    "{name}: {a_id} and {b_id} give the same mesh"
                );
            }
        }
    }
}

/// Whether two results differ by more than the grader's tolerance could
/// hide: a position, or a triangle.
fn differ(a_: &Tris, b: &Tris) -> bool {
    a_.pos.len() != b.pos.len()
        || a_
            .pos
            .iter()
            .zip(&b.pos)
            .any(|(p, q)| p.distance(*q) > 1e-6)
        || normalised(a_.tris.iter().copied()) != normalised(b.tris.iter().copied())
}

// ---- the stub file ------------------------------------------------------------

fn read(path: &str) -> String {
    let full = reference::lab_root().join(path);
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{}: {e}", full.display()))
}

/// The doc comment (`///` and `#[doc = ...]` lines) just above `pub fn name(`.
fn doc_of(src: &str, name: &str, file: &str) -> String {
    let at = src
        .find(&format!("pub fn {name}("))
        .unwrap_or_else(|| panic!("{file} has no pub fn {name}"));
    let mut lines: Vec<&str> = src[..at]
        .trim_end_matches('\n')
        .lines()
        .rev()
        .take_while(|l| l.starts_with("///") || l.starts_with("#[doc"))
        .collect();
    lines.reverse();
    assert!(!lines.is_empty(), "{file}: {name} has no doc comment");
    lines.join("\n")
}

/// The stub the student gets states the model's contracts word for word
/// (and the Loop lab's for the flip), and leaves every body to them.
#[test]
fn the_stub_file_carries_the_models_contracts_and_todo_bodies() {
    let stub_file = "reference/src/labs/sqrt3_stubs.rs.txt";
    let stub = read(stub_file);
    let model = read("reference/src/labs/sqrt3.rs");
    let loop_lab = read("crates/meshedit/src/lib.rs");
    assert!(
        stub.starts_with("//! # The lab: √3 subdivision"),
        "a module doc first"
    );
    assert!(stub.contains("\nuse halfedge::{EdgeId, FaceId, Mesh, VertexId};\n"));
    for name in ["split_face", "sqrt3_subdivide", "sqrt3_subdivide_round"] {
        assert_eq!(
            doc_of(&stub, name, stub_file),
            doc_of(&model, name, "sqrt3.rs"),
            "{name}'s contract"
        );
    }
    assert_eq!(
        doc_of(&stub, "flip_edge", stub_file),
        doc_of(&loop_lab, "flip_edge", "meshedit"),
        "flip_edge is the Loop lab's, the same contract"
    );
    let split = doc_of(&stub, "split_edge", stub_file);
    assert!(split.contains("1 vertex, 2 edges, 1 face, 4 halfedges"));
    assert!(
        !split.contains("loop_subdivide"),
        "no link to the other lab"
    );
    let fns: Vec<&str> = stub.matches("\npub fn ").collect();
    assert_eq!(
        fns.len(),
        5,
        "split_face, flip_edge, sqrt3_subdivide, split_edge, sqrt3_subdivide_round"
    );
    for part in stub.split("\npub fn ").skip(1) {
        let body = &part[part.find('{').unwrap()..part.find("\n}").unwrap()];
        assert!(body.contains("todo!("), "a todo!() body: {body}");
        assert!(body.lines().count() <= 3, "nothing but the todo!(): {body}");
    }
}
