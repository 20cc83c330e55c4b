//! The Catmull-Clark lab's model solution, checked independently: the
//! first rounds worked out by hand on the quad cube, a tetrahedron, a
//! triangle, an open grid and the lab's cube; every shape's round compared
//! with a second implementation written here from indexed faces (no
//! half-edges, none of the model's code); the counts after one to three
//! rounds; the contracts of `bisect_edge` and `split_face_to_quads`,
//! refusals included; the student's stubs; and the named mistakes.

use std::collections::{BTreeSet, HashMap};
use std::panic;

use halfedge::{shapes, DVec3, EdgeId, FaceId, Mesh, VertexId};
use reference::labs::catmull_clark::{bisect_edge, catmull_clark_subdivide, split_face_to_quads};
use reference::labs::catmull_clark_mistakes::MISTAKES;

/// The stubs the student gets, compiled here as they are.
#[path = "../src/labs/catmull_clark_stubs.rs.txt"]
mod stubs;

const EPS: f64 = 1e-12;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

#[track_caller]
fn near(got: DVec3, want: DVec3, what: &str) {
    assert!(
        (got - want).length() < EPS,
        "{what}: at {got}, expected {want}"
    );
}

#[track_caller]
fn valid(m: &Mesh, what: &str) {
    if let Err(bad) = m.validate() {
        panic!("{what} is invalid: {bad}");
    }
}

fn subdivided(mesh: &Mesh, rounds: usize) -> Mesh {
    let mut m = mesh.clone();
    for _ in 0..rounds {
        catmull_clark_subdivide(&mut m);
    }
    m
}

fn counts(m: &Mesh) -> (usize, usize, usize) {
    (m.num_vertices(), m.num_edges(), m.num_real_faces())
}

/// The neighbours of every vertex, from the indexed edges.
fn adjacency(m: &Mesh) -> Vec<BTreeSet<usize>> {
    let mut adj = vec![BTreeSet::new(); m.num_vertices()];
    for [a, b] in m.edge_list() {
        adj[a].insert(b);
        adj[b].insert(a);
    }
    adj
}

/// The one vertex numbered `from` or more joined to both `a` and `b`.
#[track_caller]
fn common_new_neighbour(adj: &[BTreeSet<usize>], a: usize, b: usize, from: usize) -> usize {
    let common: Vec<usize> = adj[a]
        .intersection(&adj[b])
        .copied()
        .filter(|&x| x >= from)
        .collect();
    assert_eq!(common.len(), 1, "new vertices joined to both {a} and {b}");
    common[0]
}

/// A cycle turned to start at its smallest entry.
fn canonical(mut cycle: Vec<usize>) -> Vec<usize> {
    let at = (0..cycle.len()).min_by_key(|&i| cycle[i]).unwrap();
    cycle.rotate_left(at);
    cycle
}

/// One round by the textbook, on indexed faces: a second implementation,
/// sharing nothing with the model but the mesh it reads.
struct ByHand {
    /// Where each old vertex goes.
    vertex: Vec<DVec3>,
    /// The edge point of each edge, by its ends (smaller first).
    edge: HashMap<(usize, usize), DVec3>,
    /// The face point of each face, in the order of `to_faces`.
    face: Vec<DVec3>,
    faces: Vec<Vec<usize>>,
}

fn key(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

fn by_hand(mesh: &Mesh) -> ByHand {
    let (p, faces) = mesh.to_faces();
    let mean = |points: &mut dyn Iterator<Item = DVec3>| {
        let (sum, n) = points.fold((DVec3::ZERO, 0.0), |(s, n), q| (s + q, n + 1.0));
        sum / n
    };
    let face: Vec<DVec3> = faces
        .iter()
        .map(|f| mean(&mut f.iter().map(|&i| p[i])))
        .collect();
    let mut sides: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (fi, f) in faces.iter().enumerate() {
        for i in 0..f.len() {
            sides
                .entry(key(f[i], f[(i + 1) % f.len()]))
                .or_default()
                .push(fi);
        }
    }
    let edge: HashMap<(usize, usize), DVec3> = sides
        .iter()
        .map(|(&(a, b), by)| {
            let point = match by.as_slice() {
                [_] => (p[a] + p[b]) / 2.0,
                [f0, f1] => (p[a] + p[b] + face[*f0] + face[*f1]) / 4.0,
                _ => unreachable!("a manifold edge has one or two faces"),
            };
            ((a, b), point)
        })
        .collect();
    let mut neighbours = vec![Vec::new(); p.len()];
    let mut rim = vec![Vec::new(); p.len()];
    for (&(a, b), by) in &sides {
        neighbours[a].push(b);
        neighbours[b].push(a);
        if by.len() == 1 {
            rim[a].push(b);
            rim[b].push(a);
        }
    }
    let mut around = vec![Vec::new(); p.len()];
    for (fi, f) in faces.iter().enumerate() {
        for &c in f {
            around[c].push(fi);
        }
    }
    let vertex = (0..p.len())
        .map(|i| {
            let n = neighbours[i].len() as f64;
            match rim[i].as_slice() {
                [] => {
                    let f = mean(&mut around[i].iter().map(|&fi| face[fi]));
                    let r = mean(&mut neighbours[i].iter().map(|&q| (p[i] + p[q]) / 2.0));
                    (f + 2.0 * r + (n - 3.0) * p[i]) / n
                }
                [_, _] if neighbours[i].len() == 2 => p[i],
                [x, y] => (p[*x] + 6.0 * p[i] + p[*y]) / 8.0,
                _ => unreachable!("a manifold boundary vertex has two boundary edges"),
            }
        })
        .collect();
    ByHand {
        vertex,
        edge,
        face,
        faces,
    }
}

/// `out` is one round of `input` exactly as [`by_hand`] computes it: old
/// vertices (same ids) where the rules put them, one new vertex per edge
/// and per face at its point, and one quad per corner, wound like its face.
#[track_caller]
fn matches_by_hand(input: &Mesh, out: &Mesh, what: &str) {
    valid(out, what);
    let want = by_hand(input);
    let (nv, ne, nf) = counts(input);
    let corners: usize = want.faces.iter().map(Vec::len).sum();
    assert_eq!(
        counts(out),
        (nv + ne + nf, 2 * ne + corners, corners),
        "{what}: (V, E, F)"
    );
    assert!(out.is_quad_mesh(), "{what}: {}", out.face_degrees());
    for i in 0..nv {
        let got = out[VertexId::from_index(i)].pos;
        near(got, want.vertex[i], &format!("{what}: old vertex {i}"));
    }
    let adj = adjacency(out);
    let mut edge_vertex = HashMap::new();
    for (&(a, b), &point) in &want.edge {
        let m = common_new_neighbour(&adj, a, b, nv);
        near(
            out[VertexId::from_index(m)].pos,
            point,
            &format!("{what}: edge point of {a}-{b}"),
        );
        edge_vertex.insert((a, b), m);
    }
    let mut expected = Vec::new();
    for (fi, f) in want.faces.iter().enumerate() {
        let n = f.len();
        let e = |i: usize| edge_vertex[&key(f[i % n], f[(i + 1) % n])];
        let c = common_new_neighbour(&adj, e(0), e(1), nv);
        near(
            out[VertexId::from_index(c)].pos,
            want.face[fi],
            &format!("{what}: face point of face {fi}"),
        );
        for (i, &corner) in f.iter().enumerate() {
            expected.push(canonical(vec![corner, e(i), c, e(i + n - 1)]));
        }
    }
    expected.sort();
    let (_, got) = out.to_faces();
    let mut got: Vec<Vec<usize>> = got.into_iter().map(canonical).collect();
    got.sort();
    assert_eq!(got, expected, "{what}: the quads");
}

/// Every shape the lab subdivides, closed and open.
fn shapes_to_subdivide() -> Vec<(String, Mesh)> {
    let mut all: Vec<(String, Mesh)> = shapes::LAB_OBJECTS
        .iter()
        .map(|&n| (n.to_string(), shapes::lab_object(n).unwrap()))
        .collect();
    all.extend([
        ("quad cube".to_string(), shapes::quad_cube(1)),
        ("quad cube(2)".to_string(), shapes::quad_cube(2)),
        ("quad torus".to_string(), shapes::quad_torus(6, 4, 1.0, 0.3)),
        ("prism(3)".to_string(), shapes::prism(3, 1.0, 2.0)),
        ("prism(5)".to_string(), shapes::prism(5, 1.0, 0.5)),
        ("house".to_string(), shapes::house()),
        ("icosahedron".to_string(), shapes::icosphere(0)),
        ("quad grid".to_string(), shapes::quad_grid(3, 2)),
        ("triangle grid".to_string(), shapes::grid(2, 2)),
        (
            "open cylinder".to_string(),
            shapes::cylinder(5, 1, 1.0, 1.0, false),
        ),
    ]);
    all
}

#[test]
fn quad_cube_first_round_by_hand() {
    let cube = shapes::quad_cube(1);
    let out = subdivided(&cube, 1);
    valid(&out, "quad cube, one round");
    // 8 + 12 + 6 vertices, 2 * 12 + 24 edges, one quad per corner.
    assert_eq!(counts(&out), (26, 48, 24));
    assert!(out.is_quad_mesh());
    // A corner P = (1, 1, 1), n = 3: its faces' points (1, 0, 0), (0, 1, 0),
    // (0, 0, 1) give F = (1/3, 1/3, 1/3); its edges' midpoints (1, 1, 0),
    // (1, 0, 1), (0, 1, 1) give R = (2/3, 2/3, 2/3); (F + 2R + 0 P) / 3 =
    // (5/9, 5/9, 5/9). The others by symmetry.
    for i in 0..8 {
        let p = cube[VertexId(i)].pos;
        near(out[VertexId(i)].pos, p * (5.0 / 9.0), "a corner");
    }
    // Face points at the centres of the sides; edge points, e.g. of
    // (1, 1, -1)-(1, 1, 1) between the sides x = 1 and y = 1:
    // ((1, 1, -1) + (1, 1, 1) + (1, 0, 0) + (0, 1, 0)) / 4 = (3/4, 3/4, 0).
    let mut want: Vec<DVec3> = Vec::new();
    for axis in 0..3 {
        for s in [-1.0, 1.0] {
            let mut q = DVec3::ZERO;
            q[axis] = s;
            want.push(q);
            for t in [-1.0, 1.0] {
                let mut q = DVec3::ZERO;
                q[axis] = 0.75 * s;
                q[(axis + 1) % 3] = 0.75 * t;
                want.push(q);
            }
        }
    }
    assert_eq!(want.len(), 6 + 12);
    let mut got: Vec<DVec3> = (8..26).map(|i| out[VertexId(i)].pos).collect();
    for w in want {
        let at = got
            .iter()
            .position(|&g| (g - w).length() < EPS)
            .unwrap_or_else(|| panic!("no new vertex at {w}: {got:?}"));
        got.swap_remove(at);
    }
    // Each quad: an old corner, an edge point, a face point, an edge point.
    for f in out.real_face_ids() {
        let kinds: Vec<usize> = out
            .face_vertices(f)
            .iter()
            .map(|&c| {
                let p = out[c].pos;
                (p.x == 0.0) as usize + (p.y == 0.0) as usize + (p.z == 0.0) as usize
            })
            .collect();
        let mut sorted = kinds.clone();
        sorted.sort();
        assert_eq!(sorted, vec![0, 1, 1, 2], "{}", out.describe_corners(f));
        assert_eq!(
            kinds[(kinds.iter().position(|&k| k == 0).unwrap() + 2) % 4],
            2
        );
    }
}

#[test]
fn quad_cube_second_round_corner_by_hand() {
    // After one round the corner P = (5/9, 5/9, 5/9) has 3 quads, e.g.
    // (P, (3/4, 3/4, 0), (1, 0, 0), (3/4, 0, 3/4)), whose point is
    // (55/72, 47/144, 47/144): F = (17/36, 17/36, 17/36). Its edges'
    // midpoints, e.g. (47/72, 47/72, 5/18), give R = (19/36, 19/36, 19/36).
    // (F + 2R) / 3 = 55/108.
    let out = subdivided(&shapes::quad_cube(1), 2);
    for i in 0..8 {
        let p = shapes::quad_cube(1)[VertexId(i)].pos;
        near(
            out[VertexId(i)].pos,
            p * (55.0 / 108.0),
            "a corner, round 2",
        );
    }
}

#[test]
fn tetrahedron_first_round_by_hand() {
    let p = [
        v(1., 1., 1.),
        v(1., -1., -1.),
        v(-1., 1., -1.),
        v(-1., -1., 1.),
    ];
    let faces = vec![vec![0, 1, 2], vec![0, 3, 1], vec![0, 2, 3], vec![1, 3, 2]];
    let tetra = Mesh::from_faces(&p, &faces).unwrap();
    let out = subdivided(&tetra, 1);
    valid(&out, "tetrahedron, one round");
    assert_eq!(counts(&out), (4 + 6 + 4, 2 * 6 + 12, 12));
    // v0 = (1, 1, 1): its faces' centroids (1/3, 1/3, -1/3), (1/3, -1/3,
    // 1/3), (-1/3, 1/3, 1/3) give F = (1/9, 1/9, 1/9); its edges'
    // midpoints (1, 0, 0), (0, 1, 0), (0, 0, 1) give R = (1/3, 1/3, 1/3);
    // (F + 2R) / 3 = (7/27, 7/27, 7/27). The others by symmetry.
    for (i, &q) in p.iter().enumerate() {
        near(
            out[VertexId::from_index(i)].pos,
            q * (7.0 / 27.0),
            "a vertex",
        );
    }
    // Edge v0-v1: ((2, 0, 0) + (1/3, 1/3, -1/3) + (1/3, -1/3, 1/3)) / 4 =
    // (2/3, 0, 0), two thirds of its midpoint; the others by symmetry.
    let adj = adjacency(&out);
    for a in 0..4 {
        for b in a + 1..4 {
            let m = common_new_neighbour(&adj, a, b, 4);
            let want = (p[a] + p[b]) / 2.0 * (2.0 / 3.0);
            near(out[VertexId::from_index(m)].pos, want, "an edge point");
        }
    }
    // Face points at the centroids, minus a third of the opposite vertex.
    let mut face_points: Vec<DVec3> = (10..14).map(|i| out[VertexId(i)].pos).collect();
    for q in p {
        let at = face_points
            .iter()
            .position(|&g| (g + q / 3.0).length() < EPS)
            .expect("a face point opposite each vertex");
        face_points.swap_remove(at);
    }
}

#[test]
fn single_triangle_keeps_its_corners_by_hand() {
    let p = [v(0., 0., 0.), v(1., 0., 0.), v(0., 1., 0.)];
    let tri = Mesh::from_faces(&p, &[vec![0, 1, 2]]).unwrap();
    let out = subdivided(&tri, 1);
    valid(&out, "triangle, one round");
    assert_eq!(counts(&out), (7, 9, 3));
    assert!(out.is_quad_mesh());
    // Three corners (two edges each) stay; the edges are on the hole, so
    // their points are midpoints; the face point is the centroid.
    for (i, &q) in p.iter().enumerate() {
        assert_eq!(out[VertexId::from_index(i)].pos, q, "a corner stays");
    }
    let adj = adjacency(&out);
    for (a, b) in [(0, 1), (1, 2), (0, 2)] {
        let m = common_new_neighbour(&adj, a, b, 3);
        near(
            out[VertexId::from_index(m)].pos,
            (p[a] + p[b]) / 2.0,
            "a midpoint",
        );
    }
    let c = common_new_neighbour(
        &adj,
        common_new_neighbour(&adj, 0, 1, 3),
        common_new_neighbour(&adj, 1, 2, 3),
        3,
    );
    near(
        out[VertexId::from_index(c)].pos,
        v(1. / 3., 1. / 3., 0.),
        "the centroid",
    );
    // The corners are still corners: two rounds more leave them in place.
    let later = subdivided(&out, 2);
    valid(&later, "triangle, three rounds");
    // Rounds 2 and 3: (19, 30, 12), then (61, 108, 48).
    assert_eq!(counts(&later), (61, 108, 48));
    for (i, &q) in p.iter().enumerate() {
        assert_eq!(later[VertexId::from_index(i)].pos, q, "a corner stays");
    }
}

/// A 2 x 2 grid of unit quads in z = 0, vertex (i, j) numbered 3j + i,
/// with vertex 1, on the rim, lifted to (1, 0, 1).
fn lifted_grid() -> Mesh {
    let mut p = Vec::new();
    for j in 0..3 {
        for i in 0..3 {
            p.push(v(i as f64, j as f64, 0.0));
        }
    }
    p[1].z = 1.0;
    let faces = vec![
        vec![0, 1, 4, 3],
        vec![1, 2, 5, 4],
        vec![3, 4, 7, 6],
        vec![4, 5, 8, 7],
    ];
    Mesh::from_faces(&p, &faces).unwrap()
}

#[test]
fn boundary_rules_on_an_open_grid_by_hand() {
    let grid = lifted_grid();
    let out = subdivided(&grid, 1);
    valid(&out, "grid, one round");
    assert_eq!(counts(&out), (9 + 12 + 4, 24 + 16, 16));
    let rim = out.edge_ids().filter(|&e| out.edge_on_boundary(e)).count();
    assert_eq!(rim, 16, "each rim edge in two halves");
    let at = |i: u32| out[VertexId(i)].pos;
    // Corners (two edges each) stay.
    for i in [0, 2, 6, 8] {
        assert_eq!(at(i), grid[VertexId(i)].pos, "corner {i}");
    }
    // Rim vertex 1: ((0, 0, 0) + 6 (1, 0, 1) + (2, 0, 0)) / 8 = (1, 0, 3/4).
    near(at(1), v(1.0, 0.0, 0.75), "rim vertex 1");
    // Rim vertices 3, 5, 7 lie between their rim neighbours: they stay.
    for i in [3, 5, 7] {
        near(at(i), grid[VertexId(i)].pos, "a straight rim vertex");
    }
    // Face points: (1/2, 1/2, 1/4), (3/2, 1/2, 1/4), (1/2, 3/2, 0),
    // (3/2, 3/2, 0). Vertex 4, n = 4: F = (1, 1, 1/8); the midpoints
    // (1, 1/2, 1/2), (1/2, 1, 0), (3/2, 1, 0), (1, 3/2, 0) give
    // R = (1, 1, 1/8); (F + 2R + P) / 4 = (1, 1, 3/32).
    near(at(4), v(1.0, 1.0, 3.0 / 32.0), "the middle vertex");
    let adj = adjacency(&out);
    let edge_point = |a, b| at(common_new_neighbour(&adj, a, b, 9) as u32);
    // On the rim: midpoints.
    near(edge_point(0, 1), v(0.5, 0.0, 0.5), "rim edge 0-1");
    near(edge_point(1, 2), v(1.5, 0.0, 0.5), "rim edge 1-2");
    near(edge_point(0, 3), v(0.0, 0.5, 0.0), "rim edge 0-3");
    // Inside: 1-4 is ((1, 0, 1) + (1, 1, 0) + (1/2, 1/2, 1/4) +
    // (3/2, 1/2, 1/4)) / 4 = (1, 1/2, 3/8); 3-4, 4-5, 4-7 likewise.
    near(edge_point(1, 4), v(1.0, 0.5, 0.375), "edge 1-4");
    near(edge_point(3, 4), v(0.5, 1.0, 1.0 / 16.0), "edge 3-4");
    near(edge_point(4, 5), v(1.5, 1.0, 1.0 / 16.0), "edge 4-5");
    near(edge_point(4, 7), v(1.0, 1.5, 0.0), "edge 4-7");
    let mut face_points: Vec<DVec3> = (21..25).map(at).collect();
    for want in [
        v(0.5, 0.5, 0.25),
        v(1.5, 0.5, 0.25),
        v(0.5, 1.5, 0.0),
        v(1.5, 1.5, 0.0),
    ] {
        let i = face_points
            .iter()
            .position(|&g| (g - want).length() < EPS)
            .unwrap_or_else(|| panic!("no face point at {want}: {face_points:?}"));
        face_points.swap_remove(i);
    }
}

#[test]
fn grid_corners_stay_and_the_rim_stays_on_its_curve_over_rounds() {
    let grid = shapes::quad_grid(3, 2);
    let corners: Vec<VertexId> = grid
        .vertex_ids()
        .filter(|&v| grid.vertex_on_boundary(v) && grid.vertex_degree(v) == 2)
        .collect();
    assert_eq!(corners.len(), 4);
    let mut m = grid.clone();
    for round in 1..=3 {
        catmull_clark_subdivide(&mut m);
        valid(&m, "quad grid");
        for &c in &corners {
            assert_eq!(m[c].pos, grid[c].pos, "corner {c} after round {round}");
            assert_eq!(m.vertex_degree(c), 2, "still a corner");
        }
        // The rim is cut in two each round: 2 (3 + 2) * 2^round edges.
        let rim = m.edge_ids().filter(|&e| m.edge_on_boundary(e)).count();
        assert_eq!(rim, 10 << round);
        // The saddle's rim lies on x, y = +-1/2: the boundary rules mix
        // only rim points, so it stays there.
        for v in m.vertex_ids().filter(|&v| m.vertex_on_boundary(v)) {
            let p = m[v].pos;
            assert!(
                (p.x.abs() - 0.5).abs() < EPS || (p.y.abs() - 0.5).abs() < EPS,
                "{v} at {p} left the rim"
            );
        }
    }
}

#[test]
fn lab_cube_first_round_by_hand() {
    let cube = shapes::lab_object("cube").unwrap();
    let out = subdivided(&cube, 1);
    valid(&out, "lab cube, one round");
    // OBJ vertex 7 (id 6) = (-1/2, -1/2, 1/2), n = 4, in the triangles
    // (6 5 7), (8 6 7), (8 7 1), (1 7 5) of the file: their centroids give
    // F = (-1/6, -1/6, 1/3); the midpoints towards 5, 6, 8 and 1 give
    // R = (-1/4, -1/4, 3/8); (F + 2R + P) / 4 = (-7/24, -7/24, 19/48).
    near(
        out[VertexId(6)].pos,
        v(-7.0 / 24.0, -7.0 / 24.0, 19.0 / 48.0),
        "OBJ vertex 7",
    );
    // The edge between OBJ vertices 1 and 2, between the triangles (3 1 2),
    // centroid (-1/6, -1/6, -1/2), and (2 1 5), centroid (1/6, -1/2, -1/6):
    // ((0, -1, -1) + both) / 4 = (0, -5/12, -5/12).
    let adj = adjacency(&out);
    let m = common_new_neighbour(&adj, 0, 1, 8);
    near(
        out[VertexId::from_index(m)].pos,
        v(0.0, -5.0 / 12.0, -5.0 / 12.0),
        "the edge point of 1-2",
    );
    // Every triangle's centroid is a vertex, e.g. (3 1 2)'s.
    assert!(out
        .positions()
        .iter()
        .any(|&p| (p - v(-1.0 / 6.0, -1.0 / 6.0, -0.5)).length() < EPS));
}

#[test]
fn lab_objects_counts_after_one_and_two_rounds() {
    // V + E + F vertices, 2E + 3F edges, 3F quads (all triangles first).
    let want = [
        ("cube", [(8, 18, 12), (38, 72, 36), (146, 288, 144)]),
        (
            "torus",
            [(72, 216, 144), (432, 864, 432), (1728, 3456, 1728)],
        ),
        ("cylinder", [(18, 48, 32), (98, 192, 96), (386, 768, 384)]),
        ("cone", [(7, 15, 10), (32, 60, 30), (122, 240, 120)]),
    ];
    for (name, rounds) in want {
        let mut m = shapes::lab_object(name).unwrap();
        assert_eq!(counts(&m), rounds[0], "{name}");
        for (round, &expected) in rounds.iter().enumerate().skip(1) {
            catmull_clark_subdivide(&mut m);
            valid(&m, name);
            assert_eq!(counts(&m), expected, "{name} after {round} rounds");
            assert!(m.is_quad_mesh(), "{name}: {}", m.face_degrees());
        }
    }
}

#[test]
fn quad_cube_counts_over_three_rounds() {
    let mut m = shapes::quad_cube(1);
    for want in [(26, 48, 24), (98, 192, 96), (386, 768, 384)] {
        catmull_clark_subdivide(&mut m);
        valid(&m, "quad cube");
        assert_eq!(counts(&m), want);
        assert!(m.is_quad_mesh());
    }
}

#[test]
fn every_shape_matches_the_rules_applied_by_hand_for_two_rounds() {
    for (name, mesh) in shapes_to_subdivide() {
        let once = subdivided(&mesh, 1);
        matches_by_hand(&mesh, &once, &format!("{name}, round 1"));
        let twice = subdivided(&once, 1);
        matches_by_hand(&once, &twice, &format!("{name}, round 2"));
    }
}

#[test]
fn marks_left_by_a_round_do_not_spoil_the_next() {
    // A round leaves its new vertices marked; the next must clear them.
    let mut m = shapes::house();
    catmull_clark_subdivide(&mut m);
    assert!(m.vertex_ids().any(|v| m[v].is_new));
    let before = m.clone();
    catmull_clark_subdivide(&mut m);
    matches_by_hand(&before, &m, "house, round 2 after marks");
}

/// The four arenas, for "changed nothing".
fn records(m: &Mesh) -> String {
    format!("{:?}", m.records())
}

#[test]
fn bisect_edge_inserts_a_corner_on_both_sides() {
    let meshes = [
        shapes::quad_cube(1),
        shapes::house(),
        shapes::quad_grid(2, 1),
    ];
    // Each edge twice: as built, and with b's halfedge the twin `t`, which
    // the bisection moves to start at m (any halfedge leaving b may be b's).
    for (mesh, b_on_t) in meshes.iter().flat_map(|m| [(m, false), (m, true)]) {
        for e in mesh.edge_ids() {
            let mut m = mesh.clone();
            let h = m[e].halfedge;
            let t = m[h].twin;
            let (a, b) = m.edge_vertices(e);
            if b_on_t {
                m[b].halfedge = t;
            }
            let (f0, f1) = (m[h].face, m[t].face);
            let (d0, d1) = (m.face_degree(f0), m.face_degree(f1));
            let before = (
                m.num_vertices(),
                m.num_edges(),
                m.num_faces(),
                m.num_halfedges(),
            );
            let eb = EdgeId::from_index(m.num_edges());
            let got = bisect_edge(&mut m, e).expect("bisect_edge refuses nothing");
            valid(&m, &format!("after bisecting {e}"));
            assert_eq!(
                (
                    m.num_vertices(),
                    m.num_edges(),
                    m.num_faces(),
                    m.num_halfedges()
                ),
                (before.0 + 1, before.1 + 1, before.2, before.3 + 2)
            );
            assert_eq!(got.index(), before.0, "the new vertex");
            assert_eq!(m[got].pos, (mesh[a].pos + mesh[b].pos) / 2.0);
            assert!(m[got].is_new && m[got].new_pos == DVec3::ZERO);
            assert_eq!(m.edge_vertices(e), (a, got), "e is the half a-m");
            assert_eq!(m[e].halfedge, h);
            assert_eq!(m.find_edge(got, b), Some(eb), "the new half joins m and b");
            assert!(!m[eb].is_new && m[eb].new_pos == DVec3::ZERO);
            let hb = m[got].halfedge;
            assert_eq!(
                (m[hb].face, m.halfedge_dst(hb)),
                (f0, b),
                "m's halfedge: m -> b in f0"
            );
            // Both sides gained m, between a and b; no position moved.
            assert_eq!((m.face_degree(f0), m.face_degree(f1)), (d0 + 1, d1 + 1));
            for (f, from, to) in [(f0, a, b), (f1, b, a)] {
                let c = m.face_vertices(f);
                let i = c.iter().position(|&x| x == got).unwrap();
                assert_eq!(
                    c[(i + c.len() - 1) % c.len()],
                    from,
                    "{}",
                    m.describe_corners(f)
                );
                assert_eq!(c[(i + 1) % c.len()], to, "{}", m.describe_corners(f));
            }
            for x in mesh.vertex_ids() {
                assert_eq!(m[x].pos, mesh[x].pos);
                assert_eq!(m[x].is_new, mesh[x].is_new);
            }
        }
    }
}

#[test]
fn bisections_in_sequence_keep_the_mesh_valid() {
    // Every edge, then every edge again (the halves), then the new ones.
    let mut m = shapes::house();
    for pass in 0..3 {
        for e in m.edge_ids() {
            bisect_edge(&mut m, e).unwrap();
            valid(&m, &format!("pass {pass}, after {e}"));
        }
    }
    assert_eq!(m.num_edges(), 16 * 8);
    assert_eq!(m.face_degrees().corners(), 2 * 16 * 8);
    assert_eq!(m.num_real_faces(), 8, "bisection adds no face");
}

/// `mesh` with every edge of face `f` bisected.
fn bisected_face(mesh: &Mesh, f: FaceId) -> Mesh {
    let mut m = mesh.clone();
    for e in m.face_edges(f) {
        bisect_edge(&mut m, e).unwrap();
    }
    m
}

#[test]
fn split_face_to_quads_joins_the_face_point_to_every_marked_corner() {
    let cases = [
        ("quad", shapes::quad_cube(1), FaceId(0)),
        ("triangle", shapes::lab_object("cube").unwrap(), FaceId(3)),
        ("pentagon", shapes::house(), FaceId(1)),
        ("heptagon", shapes::prism(7, 1.0, 1.0), FaceId(7)),
        ("grid quad", shapes::quad_grid(2, 2), FaceId(0)),
    ];
    for (what, mesh, f) in cases {
        let original: Vec<VertexId> = mesh.face_vertices(f);
        let k = original.len();
        let face_point = original.iter().map(|&c| mesh[c].pos).sum::<DVec3>() / k as f64;
        let mut m = bisected_face(&mesh, f);
        // The first marked corner from the face's halfedge.
        let corners = m.face_vertices(f);
        let m0 = *corners.iter().find(|&&c| m[c].is_new).unwrap();
        // The marked corners do not count in the face point: moved off
        // their midpoints (whose mean is the corners' mean), they must not
        // pull it.
        for &x in &corners {
            if m[x].is_new {
                m[x].pos += v(0.25, -2.0, 10.0);
            }
        }
        let before = (
            m.num_vertices(),
            m.num_edges(),
            m.num_faces(),
            m.num_halfedges(),
        );
        let c = split_face_to_quads(&mut m, f).unwrap_or_else(|| panic!("{what} refused"));
        valid(&m, what);
        assert_eq!(
            (
                m.num_vertices(),
                m.num_edges(),
                m.num_faces(),
                m.num_halfedges()
            ),
            (
                before.0 + 1,
                before.1 + k,
                before.2 + k - 1,
                before.3 + 2 * k
            ),
            "{what}"
        );
        near(m[c].pos, face_point, what);
        assert!(m[c].is_new && m[c].new_pos == DVec3::ZERO, "{what}");
        assert_eq!(m.vertex_degree(c), k, "{what}: a spoke per marked corner");
        let out = m[c].halfedge;
        assert_eq!(
            (m[out].face, m.halfedge_dst(out)),
            (f, m0),
            "{what}: c -> m_0 in f"
        );
        for h in m.vertex_halfedges(c) {
            let e = m[h].edge;
            assert!(m[e].is_new, "{what}: spoke {e} marked");
            let piece = m[h].face;
            let q = m.face_vertices(piece);
            assert_eq!(q.len(), 4, "{what}: {}", m.describe_corners(piece));
            // (c, m_i, v_i, m_(i+1)): marked, unmarked, marked after c.
            let i = q.iter().position(|&x| x == c).unwrap();
            let marks: Vec<bool> = (1..4).map(|j| m[q[(i + j) % 4]].is_new).collect();
            assert_eq!(
                marks,
                [true, false, true],
                "{what}: {}",
                m.describe_corners(piece)
            );
        }
        // The old corners kept their places and marks.
        for x in mesh.vertex_ids() {
            assert_eq!(m[x].pos, mesh[x].pos);
            assert!(!m[x].is_new);
        }
    }
}

#[test]
fn a_quad_with_two_opposite_marks_becomes_two_quads() {
    let mut m = shapes::quad_cube(1);
    let f = FaceId(2);
    let corners = m.face_vertices(f);
    m[corners[1]].is_new = true;
    m[corners[3]].is_new = true;
    let c = split_face_to_quads(&mut m, f).expect("2k = 4 corners, alternating");
    valid(&m, "two quads");
    assert_eq!(m.vertex_degree(c), 2);
    let want = (m[corners[0]].pos + m[corners[2]].pos) / 2.0;
    assert_eq!(m[c].pos, want, "the mean of the two unmarked corners");
    assert_eq!(m.num_real_faces(), 7);
    assert!(m.is_quad_mesh());
}

#[test]
fn split_face_to_quads_refuses_what_it_cannot_tell_and_changes_nothing() {
    let cube = shapes::quad_cube(1);
    let grid = shapes::quad_grid(2, 2);
    let hole = grid.face_ids().find(|&f| grid[f].is_boundary).unwrap();
    let mut refused: Vec<(&str, Mesh, FaceId)> = Vec::new();
    refused.push(("a quad, nothing marked", cube.clone(), FaceId(0)));
    refused.push(("a triangle", shapes::prism(3, 1.0, 1.0), FaceId(3)));
    let edges = cube.face_edges(FaceId(0));
    let mut one = cube.clone();
    bisect_edge(&mut one, edges[0]).unwrap();
    refused.push(("5 corners: one edge bisected", one.clone(), FaceId(0)));
    let mut two = one.clone();
    bisect_edge(&mut two, edges[1]).unwrap();
    refused.push(("6 corners, two edges bisected side by side", two, FaceId(0)));
    let mut stray = bisected_face(&cube, FaceId(0));
    let old = cube.face_vertices(FaceId(0))[0];
    stray[old].is_new = true;
    refused.push(("8 corners, an old corner marked too", stray, FaceId(0)));
    let mut rim = grid.clone();
    for e in rim.face_edges(hole) {
        bisect_edge(&mut rim, e).unwrap();
    }
    refused.push(("the hole, its edges all bisected", rim, hole));
    let mut all = cube.clone();
    for x in all.vertex_ids() {
        all[x].is_new = true;
    }
    refused.push(("a quad, every corner marked", all, FaceId(0)));
    for (what, mut m, f) in refused {
        let before = records(&m);
        assert_eq!(split_face_to_quads(&mut m, f), None, "{what}");
        assert_eq!(records(&m), before, "{what}: changed nothing");
    }
}

#[test]
fn the_stubs_have_the_model_signatures_and_contracts_and_fail() {
    let _: fn(&mut Mesh, EdgeId) -> Option<VertexId> = stubs::bisect_edge;
    let _: fn(&mut Mesh, FaceId) -> Option<VertexId> = stubs::split_face_to_quads;
    let _: fn(&mut Mesh) = stubs::catmull_clark_subdivide;
    let _: fn(&mut Mesh, EdgeId) -> Option<VertexId> = bisect_edge;
    let _: fn(&mut Mesh, FaceId) -> Option<VertexId> = split_face_to_quads;
    let _: fn(&mut Mesh) = catmull_clark_subdivide;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/labs");
    let read = |name: &str| std::fs::read_to_string(root.join(name)).unwrap();
    let (model, stub) = (read("catmull_clark.rs"), read("catmull_clark_stubs.rs.txt"));
    for name in [
        "bisect_edge",
        "split_face_to_quads",
        "catmull_clark_subdivide",
    ] {
        let doc = |text: &str| {
            let lines: Vec<&str> = text.lines().collect();
            let at = lines
                .iter()
                .position(|l| l.starts_with(&format!("pub fn {name}(")))
                .unwrap_or_else(|| panic!("no pub fn {name}"));
            let start = (0..at)
                .rev()
                .find(|&i| !lines[i].starts_with("///"))
                .map_or(0, |i| i + 1);
            lines[start..at].join("\n")
        };
        let contract = doc(&model);
        assert!(contract.contains("/// Contract:"), "{name} has a contract");
        assert_eq!(
            doc(&stub),
            contract,
            "{name}: the stub's contract is the model's"
        );
    }
    // Every stub fails, as the handout's must.
    let mesh = shapes::quad_cube(1);
    type Run = (&'static str, fn(&mut Mesh));
    let runs: [Run; 3] = [
        ("bisect_edge", |m| {
            let _ = stubs::bisect_edge(m, EdgeId(0));
        }),
        ("split_face_to_quads", |m| {
            let _ = stubs::split_face_to_quads(m, FaceId(0));
        }),
        ("catmull_clark_subdivide", stubs::catmull_clark_subdivide),
    ];
    for (name, run) in runs {
        let mut m = mesh.clone();
        let err = panic::catch_unwind(panic::AssertUnwindSafe(|| run(&mut m))).expect_err(name);
        let msg = err
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| err.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default();
        assert!(msg.starts_with("not yet implemented"), "{name}: {msg}");
    }
}

/// Whether two meshes differ: in their counts or in a vertex's position.
fn differ(a: &Mesh, b: &Mesh) -> bool {
    counts(a) != counts(b)
        || a.vertex_ids()
            .any(|v| (a[v].pos - b[v].pos).length() > 1e-9)
}

#[test]
fn every_named_mistake_differs_from_the_model_on_both_cubes() {
    for (what, mesh) in [
        ("quad cube", shapes::quad_cube(1)),
        ("lab cube", shapes::lab_object("cube").unwrap()),
    ] {
        let model = subdivided(&mesh, 1);
        for mistake in MISTAKES {
            let mut m = mesh.clone();
            (mistake.subdivide)(&mut m);
            valid(&m, &format!("{} on the {what}", mistake.name));
            assert!(
                differ(&m, &model),
                "{} gives the model's {what}",
                mistake.name
            );
        }
    }
}

#[test]
fn the_named_mistakes_are_what_their_names_say() {
    let cube = shapes::quad_cube(1);
    let run = |name: &str| {
        let mistake = reference::labs::catmull_clark_mistakes::mistake(name).unwrap();
        let mut m = cube.clone();
        (mistake.subdivide)(&mut m);
        m
    };
    let model = subdivided(&cube, 1);
    let adj = adjacency(&model);
    // Plain midpoints: the edge (1, 1, -1)-(1, 1, 1) at (1, 1, 0), not (3/4, 3/4, 0).
    let m = run("edge-point-midpoint");
    let a = cube
        .vertex_ids()
        .find(|&x| cube[x].pos == v(1., 1., -1.))
        .unwrap();
    let b = cube
        .vertex_ids()
        .find(|&x| cube[x].pos == v(1., 1., 1.))
        .unwrap();
    let e = common_new_neighbour(&adj, a.index(), b.index(), 8);
    near(m[VertexId::from_index(e)].pos, v(1., 1., 0.), "midpoint");
    // R from the edge points: three of (3/4, 3/4, 0) and its turns give
    // R = (1/2, 1/2, 1/2); (F + 2R) / 3 = 4/9 at the corner (1, 1, 1).
    near(
        run("r-from-edge-points")[b].pos,
        v(1., 1., 1.) * (4. / 9.),
        "R from edge points",
    );
    // (F + R + P) / 3 = (1/3 + 2/3 + 1) / 3 = 2/3.
    near(
        run("vertex-weights-r-once")[b].pos,
        v(1., 1., 1.) * (2. / 3.),
        "R once",
    );
    // (2F + R) / 3 = (2/3 + 2/3) / 3 = 4/9.
    near(
        run("vertex-weights-f-twice")[b].pos,
        v(1., 1., 1.) * (4. / 9.),
        "F twice",
    );
    // The face x = 1's point at the mean of its moved corners: (5/9, 0, 0).
    let m = run("face-points-from-moved-vertices");
    assert!(m
        .positions()
        .iter()
        .any(|&p| (p - v(5. / 9., 0., 0.)).length() < EPS));
    assert!(!m
        .positions()
        .iter()
        .any(|&p| (p - v(1., 0., 0.)).length() < EPS));
    // Split early: each square in two pieces, not four quads.
    let m = run("split-before-bisecting-all");
    assert_eq!(counts(&m), (26, 36, 12));
    assert!(!m.is_quad_mesh());
    // Not moved: the corners where they were.
    assert_eq!(run("old-vertices-not-moved")[b].pos, v(1., 1., 1.));
}
