//! The lab objects and generated shapes: valid, the right size and topology,
//! and facing outwards.

use halfedge::{shapes, Mesh};

/// V - E + F over real faces.
fn euler(m: &Mesh) -> i64 {
    m.num_vertices() as i64 - m.num_edges() as i64 + m.num_real_faces() as i64
}

/// Volume enclosed by the real faces (positive when they face outwards).
fn signed_volume(m: &Mesh) -> f64 {
    let (p, faces) = m.to_faces();
    faces
        .iter()
        .flat_map(|f| (1..f.len() - 1).map(move |i| (f[0], f[i], f[i + 1])))
        .map(|(a, b, c)| p[a].dot(p[b].cross(p[c])) / 6.0)
        .sum()
}

fn boundary_edges(m: &Mesh) -> usize {
    m.edge_ids().filter(|&e| m.edge_on_boundary(e)).count()
}

#[track_caller]
fn check(m: &Mesh, what: &str, v: usize, e: usize, f: usize, chi: i64) {
    if let Err(bad) = m.validate() {
        panic!("{what} is invalid: {bad}");
    }
    assert!(
        m.is_triangle_mesh(),
        "{what} has a face that is not a triangle"
    );
    let got = (
        m.num_vertices(),
        m.num_edges(),
        m.num_real_faces(),
        euler(m),
    );
    assert_eq!(got, (v, e, f, chi), "{what}: (V, E, F, V-E+F)");
}

#[test]
fn lab_objects_have_the_lab_counts() {
    let expected = [
        ("cube", 8, 18, 12, 2),
        ("torus", 72, 216, 144, 0),
        ("cylinder", 18, 48, 32, 2),
        ("cone", 7, 15, 10, 2),
    ];
    for (name, v, e, f, chi) in expected {
        let m = shapes::lab_object(name).unwrap();
        check(&m, name, v, e, f, chi);
        assert_eq!(boundary_edges(&m), 0, "{name} is closed");
        // The lab's cube is wound clockwise seen from outside (consistently,
        // so it is a valid mesh); the other three face outwards.
        let outwards = name != "cube";
        assert_eq!(
            signed_volume(&m) > 0.0,
            outwards,
            "{name}: which way it faces"
        );
    }
    assert!(shapes::lab_object("teapot").is_none());
}

#[test]
fn lab_cube_encloses_a_unit_volume_facing_inwards() {
    let m = shapes::lab_object("cube").unwrap();
    assert!((signed_volume(&m) + 1.0).abs() < 1e-12);
}

#[test]
fn generated_closed_shapes() {
    check(&shapes::cube(1), "cube(1)", 8, 18, 12, 2);
    check(&shapes::cube(3), "cube(3)", 56, 162, 108, 2);
    check(
        &shapes::cylinder(8, 2, 1.0, 2.0, true),
        "cylinder",
        26,
        72,
        48,
        2,
    );
    check(&shapes::cone(6, 1.0, 2.0), "cone", 8, 18, 12, 2);
    check(
        &shapes::frustum(5, 1, 1.0, 0.5, 1.0, true),
        "frustum",
        12,
        30,
        20,
        2,
    );
    check(
        &shapes::frustum(5, 3, 1.0, 0.0, 1.0, true),
        "tall cone",
        17,
        45,
        30,
        2,
    );
    check(&shapes::torus(8, 5, 1.0, 0.3), "torus", 40, 120, 80, 0);
    check(&shapes::icosphere(0), "icosahedron", 12, 30, 20, 2);
    check(&shapes::icosphere(2), "icosphere(2)", 162, 480, 320, 2);
    for (what, m) in [
        ("cube", shapes::cube(2)),
        ("cylinder", shapes::cylinder(7, 3, 0.5, 1.0, true)),
        ("cone", shapes::cone(9, 1.0, 1.0)),
        ("torus", shapes::torus(6, 4, 2.0, 0.5)),
        ("icosphere", shapes::icosphere(1)),
    ] {
        assert!(signed_volume(&m) > 0.0, "{what} faces outwards");
        assert_eq!(boundary_edges(&m), 0, "{what} is closed");
    }
    // Exact volume where the shape is exact.
    assert!((signed_volume(&shapes::cube(3)) - 1.0).abs() < 1e-12);
}

#[test]
fn generated_open_shapes() {
    let g = shapes::grid(4, 3);
    check(&g, "grid", 20, 43, 24, 1);
    assert_eq!(boundary_edges(&g), 2 * (4 + 3));
    let rim = g.vertex_ids().filter(|&v| g.vertex_on_boundary(v)).count();
    assert_eq!(rim, 2 * (4 + 3));
    assert_eq!(g.num_faces(), 24 + 1, "one boundary face for the rim");

    let open = shapes::cylinder(6, 2, 1.0, 1.0, false);
    check(&open, "open cylinder", 18, 42, 24, 0);
    assert_eq!(boundary_edges(&open), 12);
    assert_eq!(open.num_faces(), 24 + 2, "two holes, two boundary faces");
}

#[test]
fn grid_faces_point_up() {
    let g = shapes::grid(2, 2);
    for f in g.face_ids().filter(|&f| !g[f].is_boundary) {
        assert!(g.face_normal(f).z > 0.5, "{}", g.describe(f));
    }
}

#[test]
fn cube_normals_point_away_from_centre() {
    let m = shapes::cube(1);
    for f in m.face_ids() {
        let n = m.face_normal(f);
        let c = m.face_center(f);
        assert!(n.dot(c) > 0.0, "{}: normal {n} at {c}", m.describe(f));
        assert!((n.length() - 1.0).abs() < 1e-12);
        // Every face of the cube lies on one side: one coordinate is +-0.5.
        assert!(c.abs().max_element() > 0.49);
    }
    let v = halfedge::VertexId(0);
    assert!(m.vertex_normal(v).dot(m[v].pos) > 0.0);
    let e = halfedge::EdgeId(0);
    let (a, b) = m.edge_vertices(e);
    assert_eq!(m.edge_center(e), (m[a].pos + m[b].pos) / 2.0);
    assert_eq!(m.halfedge_center(m[e].halfedge), m.edge_center(e));
}
