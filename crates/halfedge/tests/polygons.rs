//! Meshes of any polygon: the quad and mixed generators, the face helpers
//! (degrees, canonical lists, triangles, area, corners in one line) and the
//! walks' bounds on faces of more than three sides.

use std::f64::consts::TAU;
use std::panic;

use halfedge::{shapes, DVec3, FaceDegrees, FaceId, HalfedgeId, Mesh, VertexId};

/// V - E + F over real faces.
fn euler(m: &Mesh) -> i64 {
    m.num_vertices() as i64 - m.num_edges() as i64 + m.num_real_faces() as i64
}

/// Volume enclosed by the real faces (positive when they face outwards),
/// from the indexed faces fanned here, not through `to_triangles`.
fn signed_volume(m: &Mesh) -> f64 {
    let (p, faces) = m.to_faces();
    faces
        .iter()
        .flat_map(|f| (1..f.len() - 1).map(move |i| (f[0], f[i], f[i + 1])))
        .map(|(a, b, c)| p[a].dot(p[b].cross(p[c])) / 6.0)
        .sum()
}

/// Degree to count, as the test states it.
fn degrees(pairs: &[(usize, usize)]) -> FaceDegrees {
    FaceDegrees {
        counts: pairs.iter().copied().collect(),
    }
}

#[track_caller]
fn check(m: &Mesh, what: &str, v: usize, e: usize, f: usize, chi: i64) {
    if let Err(bad) = m.validate() {
        panic!("{what} is invalid: {bad}");
    }
    let got = (
        m.num_vertices(),
        m.num_edges(),
        m.num_real_faces(),
        euler(m),
    );
    assert_eq!(got, (v, e, f, chi), "{what}: (V, E, F, V-E+F)");
}

#[test]
fn quad_cube_is_six_quads_of_side_two() {
    let m = shapes::quad_cube(1);
    check(&m, "quad_cube(1)", 8, 12, 6, 2);
    assert_eq!(m.face_degrees(), degrees(&[(4, 6)]));
    assert!(m.is_quad_mesh() && !m.is_triangle_mesh());
    for v in m.vertex_ids() {
        let p = m[v].pos;
        assert_eq!(p.abs(), DVec3::ONE, "{v} at {p}: a corner of [-1, 1]^3");
        assert_eq!(m.vertex_degree(v), 3);
    }
    // Each face centre is the middle of one side, normal pointing at it.
    let mut centres: Vec<[i64; 3]> = m
        .real_face_ids()
        .into_iter()
        .map(|f| {
            let c = m.face_center(f);
            assert!((m.face_normal(f) - c).length() < 1e-12, "{}", m.describe(f));
            assert_eq!(m.face_area(f), 4.0);
            c.to_array().map(|x| x as i64)
        })
        .collect();
    centres.sort();
    let mut sides = vec![
        [1, 0, 0],
        [-1, 0, 0],
        [0, 1, 0],
        [0, -1, 0],
        [0, 0, 1],
        [0, 0, -1],
    ];
    sides.sort();
    assert_eq!(centres, sides);
    assert!((signed_volume(&m) - 8.0).abs() < 1e-12);
}

#[test]
fn finer_quad_cubes_and_the_triangle_cube_share_their_lattice() {
    let q = shapes::quad_cube(3);
    check(&q, "quad_cube(3)", 56, 108, 54, 2);
    assert!(q.is_quad_mesh());
    assert!((signed_volume(&q) - 8.0).abs() < 1e-12);
    // cube(n) is the same lattice, each square cut along one diagonal, at
    // half the size: the same vertex numbering and every triangle inside
    // the quad at the same place in the list.
    for n in [1, 2] {
        let (qp, qf) = shapes::quad_cube(n).to_faces();
        let (tp, tf) = shapes::cube(n).to_faces();
        assert_eq!(qp.len(), tp.len());
        for (a, b) in qp.iter().zip(&tp) {
            assert!((*a / 2.0 - *b).length() < 1e-15, "{a} vs {b}");
        }
        assert_eq!(tf.len(), 2 * qf.len());
        for (i, quad) in qf.iter().enumerate() {
            let [a, b, c, d] = [quad[0], quad[1], quad[2], quad[3]];
            assert_eq!(tf[2 * i], vec![a, b, c]);
            assert_eq!(tf[2 * i + 1], vec![a, c, d]);
        }
    }
}

#[test]
fn quad_torus_pairs_the_torus_triangles() {
    let q = shapes::quad_torus(8, 5, 1.0, 0.3);
    check(&q, "quad_torus", 40, 80, 40, 0);
    assert!(q.is_quad_mesh());
    assert!(signed_volume(&q) > 0.0, "faces outwards");
    let t = shapes::torus(8, 5, 1.0, 0.3);
    assert_eq!(q.positions(), t.positions());
    for v in q.vertex_ids() {
        assert_eq!(q.vertex_degree(v), 4);
    }
    // The torus's two triangles (a, b, c), (a, c, d) are this quad.
    let (_, tf) = t.to_faces();
    let (_, qf) = q.to_faces();
    for (i, quad) in qf.iter().enumerate() {
        assert_eq!(tf[2 * i], vec![quad[0], quad[1], quad[2]]);
        assert_eq!(tf[2 * i + 1], vec![quad[0], quad[2], quad[3]]);
    }
}

#[test]
fn prisms_have_two_caps_and_quad_sides() {
    let three = shapes::prism(3, 1.0, 2.0);
    check(&three, "prism(3)", 6, 9, 5, 2);
    assert_eq!(three.face_degrees(), degrees(&[(3, 2), (4, 3)]));
    assert_eq!(three.face_degrees().to_string(), "2 triangles, 3 quads");
    let five = shapes::prism(5, 0.5, 1.0);
    check(&five, "prism(5)", 10, 15, 7, 2);
    assert_eq!(five.face_degrees().to_string(), "5 quads, 2 pentagons");
    for (m, n, r, h) in [(&three, 3.0, 1.0, 2.0), (&five, 5.0, 0.5, 1.0)] {
        // A regular n-gon of circumradius r has area n r^2 sin(2 pi / n) / 2.
        let cap = n * r * r * (TAU / n).sin() / 2.0;
        assert!((signed_volume(m) - cap * h).abs() < 1e-12);
        let caps: Vec<FaceId> = m
            .real_face_ids()
            .into_iter()
            .filter(|&f| m.face_degree(f) == n as usize)
            .collect();
        assert_eq!(caps.len(), 2);
        for f in caps {
            assert!((m.face_area(f) - cap).abs() < 1e-12);
            assert!(m.face_normal(f).y.abs() > 0.999, "a cap is horizontal");
        }
    }
}

#[test]
fn the_house_mixes_triangles_quads_and_pentagons() {
    let m = shapes::house();
    check(&m, "house", 10, 16, 8, 2);
    assert_eq!(m.face_degrees(), degrees(&[(3, 2), (4, 4), (5, 2)]));
    assert_eq!(
        m.face_degrees().to_string(),
        "2 triangles, 4 quads, 2 pentagons"
    );
    assert_eq!(m.face_degrees().corners(), 2 * m.num_edges());
    // A box of 2 x 1 x 2 under a roof of triangular section 2 wide, 1 high.
    assert!((signed_volume(&m) - 6.0).abs() < 1e-12);
    assert_eq!(m.first_non_quad(), Some(FaceId(1)), "the back gable");
    assert_eq!(m.first_face_not_of_degree(5), Some(FaceId(0)), "the floor");
    assert!(!m.is_quad_mesh() && !m.is_triangle_mesh());
    // A gable is a 2 x 1 rectangle under a triangle of base 2, height 1.
    assert_eq!(m.face_area(FaceId(1)), 3.0);
    let gable = m.face_center(FaceId(1));
    assert!((gable - DVec3::new(0.0, 0.8, -1.0)).length() < 1e-15);
}

#[test]
fn quad_grid_is_open_with_four_corners() {
    let g = shapes::quad_grid(4, 3);
    check(&g, "quad_grid", 20, 31, 12, 1);
    assert!(g.is_quad_mesh());
    assert_eq!(g.positions(), shapes::grid(4, 3).positions());
    assert_eq!(g.num_faces(), 12 + 1, "one boundary face for the rim");
    let rim = g.edge_ids().filter(|&e| g.edge_on_boundary(e)).count();
    assert_eq!(rim, 2 * (4 + 3));
    let corners: Vec<VertexId> = g
        .vertex_ids()
        .filter(|&v| g.vertex_on_boundary(v) && g.vertex_degree(v) == 2)
        .collect();
    assert_eq!(corners, [0, 4, 15, 19].map(VertexId).to_vec());
    for f in g.real_face_ids() {
        assert!(g.face_normal(f).z > 0.5, "{}", g.describe(f));
    }
}

#[test]
fn face_degrees_read_as_counts_and_as_a_line() {
    let empty = FaceDegrees::default();
    assert_eq!(empty.to_string(), "no faces");
    assert!(empty.all(4) && empty.faces() == 0 && empty.corners() == 0);
    let one = degrees(&[(3, 1), (7, 1)]);
    assert_eq!(one.to_string(), "1 triangle, 1 face of 7 sides");
    let many = degrees(&[(4, 1), (6, 2), (8, 3)]);
    assert_eq!(many.to_string(), "1 quad, 2 hexagons, 3 faces of 8 sides");
    assert_eq!((many.of(6), many.of(5)), (2, 0));
    assert_eq!((many.faces(), many.corners()), (6, 4 + 12 + 24));
    assert!(!many.all(4));
    // The lab's objects are triangles.
    let cube = shapes::lab_object("cube").unwrap();
    assert_eq!(cube.face_degrees().to_string(), "12 triangles");
    assert!(cube.face_degrees().all(3));
}

#[test]
fn canonical_faces_ignore_face_order_and_walk_start_but_not_winding() {
    let m = shapes::house();
    let (p, faces) = m.to_faces();
    // The same polygons, listed backwards, each starting at another corner.
    let shuffled: Vec<Vec<usize>> = faces
        .iter()
        .rev()
        .map(|f| {
            let mut f = f.clone();
            let turn = 2 % f.len();
            f.rotate_left(turn);
            f
        })
        .collect();
    let again = Mesh::from_faces(&p, &shuffled).unwrap();
    assert_ne!(again.to_faces().1, faces);
    assert_eq!(again.canonical_faces(), m.canonical_faces());
    // Every face starts at its smallest corner, and the list is sorted.
    let canon = m.canonical_faces();
    for f in &canon {
        assert_eq!(f[0], *f.iter().min().unwrap());
    }
    assert!(canon.windows(2).all(|w| w[0] < w[1]));
    // Turned inside out: the same corners, the other winding.
    let flipped: Vec<Vec<usize>> = faces
        .iter()
        .map(|f| f.iter().rev().copied().collect())
        .collect();
    let inside_out = Mesh::from_faces(&p, &flipped).unwrap();
    assert_ne!(inside_out.canonical_faces(), m.canonical_faces());
    // Holes are not faces.
    let g = shapes::quad_grid(2, 1);
    assert_eq!(
        g.canonical_faces(),
        vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4]]
    );
}

#[test]
fn triangles_for_drawing_fan_each_face() {
    for m in [
        shapes::house(),
        shapes::prism(6, 1.0, 1.0),
        shapes::quad_cube(2),
    ] {
        let tris = m.to_triangles();
        let degrees = m.face_degrees();
        assert_eq!(tris.len(), degrees.corners() - 2 * degrees.faces());
        // Fans of convex planar faces cover each face once: the areas add up
        // (a non-planar quad's fan is not its projection).
        let p = m.positions();
        let fanned: f64 = tris
            .iter()
            .map(|&[a, b, c]| (p[b] - p[a]).cross(p[c] - p[a]).length() / 2.0)
            .sum();
        let faces: f64 = m.real_face_ids().into_iter().map(|f| m.face_area(f)).sum();
        assert!((fanned - faces).abs() < 1e-12, "{fanned} vs {faces}");
        // Wound like their faces: a closed mesh's triangles enclose its volume.
        let volume: f64 = tris
            .iter()
            .map(|&[a, b, c]| p[a].dot(p[b].cross(p[c])) / 6.0)
            .sum();
        assert!((volume - signed_volume(&m)).abs() < 1e-12);
    }
    let (_, faces) = shapes::house().to_faces();
    let tris = shapes::house().to_triangles();
    // The first face (the floor, 0 1 2 3) gives (0 1 2), (0 2 3).
    assert_eq!(&tris[..2], &[[0, 1, 2], [0, 2, 3]]);
    assert_eq!(faces[0], vec![0, 1, 2, 3]);
}

#[test]
fn face_edges_and_vertex_faces_on_polygons() {
    let m = shapes::house();
    for f in m.real_face_ids() {
        let corners = m.face_vertices(f);
        let edges = m.face_edges(f);
        assert_eq!(edges.len(), corners.len());
        for (i, &e) in edges.iter().enumerate() {
            let (a, b) = m.edge_vertices(e);
            let (c, d) = (corners[i], corners[(i + 1) % corners.len()]);
            assert!(
                (a, b) == (c, d) || (a, b) == (d, c),
                "{f}: {e} joins {a} {b}"
            );
        }
        assert_eq!(edges[0], m[m[f].halfedge].edge);
    }
    // The ridge's back end meets the back gable, the left roof and the
    // right roof's back triangle.
    let ridge = VertexId(8);
    let mut around = m.vertex_faces(ridge);
    assert_eq!(around.len(), m.vertex_degree(ridge));
    around.sort();
    assert_eq!(around, [1, 5, 6].map(FaceId).to_vec());
    // On a grid corner: its one quad and the hole.
    let g = shapes::quad_grid(2, 2);
    let faces = g.vertex_faces(VertexId(0));
    assert_eq!(faces.len(), 2);
    assert_eq!(faces.iter().filter(|&&f| g[f].is_boundary).count(), 1);
    assert!(faces.contains(&FaceId(0)));
}

#[test]
fn describe_corners_names_every_corner_and_never_panics() {
    let m = shapes::house();
    assert_eq!(
        m.describe_corners(FaceId(1)),
        "f1: 5 corners v0 v4 v8 v5 v1"
    );
    let g = shapes::quad_grid(1, 1);
    assert_eq!(g.describe_corners(FaceId(0)), "f0: 4 corners v0 v1 v3 v2");
    let rim = g.describe_corners(FaceId(1));
    assert!(rim.starts_with("f1, boundary: 4 corners "), "{rim}");
    assert_eq!(
        g.describe_corners(FaceId(9)),
        "f9: no such face (the mesh has 2)"
    );

    // A broken walk: the back gable's third halfedge leads back to its
    // second, so the walk from the first never returns.
    let mut broken = shapes::house();
    let start = broken[FaceId(1)].halfedge;
    let h1 = broken[start].next;
    let h2 = broken[h1].next;
    broken[h2].next = h1;
    let line = broken.describe_corners(FaceId(1));
    assert!(
        line.starts_with("f1: the walk from ")
            && line.contains("does not come back after")
            && line.ends_with("...): call mesh.validate()"),
        "{line}"
    );
    // An unset link.
    broken[h2].next = HalfedgeId::NONE;
    let line = broken.describe_corners(FaceId(1));
    assert!(
        line.contains("reaches h-none, which names no halfedge"),
        "{line}"
    );
    assert!(line.contains("corners so far: v0 v4 v8"), "{line}");
    // A long face (a prism's 12-gon) is named whole.
    let p = shapes::prism(12, 1.0, 1.0);
    let cap = p.first_non_quad().unwrap();
    let line = p.describe_corners(cap);
    assert!(line.contains(": 12 corners v0 v1 v2"), "{line}");
    assert!(line.ends_with(" v11"), "{line}");
}

#[test]
fn walks_around_broken_polygons_panic_with_a_message() {
    let mut m = shapes::house();
    let start = m[FaceId(0)].halfedge;
    let h1 = m[start].next;
    let h2 = m[h1].next;
    m[h2].next = h1; // a loop of two that never returns to `start`
    type Walk = (&'static str, fn(&Mesh));
    let walks: [Walk; 7] = [
        ("face_halfedges", |m| {
            let _ = m.face_halfedges(FaceId(0));
        }),
        ("face_edges", |m| {
            let _ = m.face_edges(FaceId(0));
        }),
        ("face_degrees", |m| {
            let _ = m.face_degrees();
        }),
        ("canonical_faces", |m| {
            let _ = m.canonical_faces();
        }),
        ("to_triangles", |m| {
            let _ = m.to_triangles();
        }),
        ("face_area", |m| {
            let _ = m.face_area(FaceId(0));
        }),
        ("is_quad_mesh", |m| {
            let _ = m.is_quad_mesh();
        }),
    ];
    for (what, walk) in walks {
        let err = panic::catch_unwind(|| walk(&m)).expect_err(what);
        let msg = err.downcast_ref::<String>().unwrap();
        assert!(
            msg.starts_with("the walk around f0 never came back"),
            "{what}: {msg}"
        );
    }
    assert!(m.validate().is_err());
}

#[test]
fn polygon_meshes_survive_an_obj_round_trip() {
    for m in [
        shapes::house(),
        shapes::quad_torus(5, 4, 1.0, 0.25),
        shapes::prism(7, 1.0, 0.5),
        shapes::quad_grid(3, 2),
    ] {
        let text = m.to_obj_string();
        // Each face on one `f` line with all its corners.
        let lines: Vec<&str> = text.lines().filter(|l| l.starts_with("f ")).collect();
        assert_eq!(lines.len(), m.num_real_faces());
        let longest = lines.iter().map(|l| l.split(' ').count() - 1).max();
        assert_eq!(longest, m.face_degrees().counts.keys().last().copied());
        let back = Mesh::from_obj_str(&text, "polygons.obj").unwrap();
        assert_eq!(back.to_faces(), m.to_faces());
        assert_eq!(back.canonical_faces(), m.canonical_faces());
    }
}
