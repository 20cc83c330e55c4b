//! Every way `Mesh::from_faces` and the OBJ reader refuse input.

use halfedge::{DVec3, Mesh, MeshError};

fn square() -> Vec<DVec3> {
    vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
    ]
}

fn build_err(positions: &[DVec3], faces: &[Vec<usize>]) -> MeshError {
    match Mesh::from_faces(positions, faces) {
        Ok(_) => panic!("expected an error for faces {faces:?}"),
        Err(e) => e,
    }
}

#[test]
fn empty_mesh() {
    assert_eq!(build_err(&[], &[]), MeshError::Empty);
    assert_eq!(build_err(&square(), &[]), MeshError::Empty);
    assert!(MeshError::Empty.to_string().contains("empty"));
}

#[test]
fn index_out_of_range_names_face_and_index() {
    let e = build_err(&square(), &[vec![0, 1, 2], vec![0, 2, 7]]);
    assert_eq!(
        e,
        MeshError::IndexOutOfRange {
            face: 1,
            index: 7,
            vertex_count: 4
        }
    );
    assert_eq!(
        e.to_string(),
        "face 1 refers to vertex 7, but the vertices are numbered 0 to 3"
    );
}

#[test]
fn too_few_vertices() {
    let e = build_err(&square(), &[vec![0, 1, 2], vec![2, 3]]);
    assert_eq!(e, MeshError::TooFewVertices { face: 1, count: 2 });
    assert_eq!(
        e.to_string(),
        "face 1 has 2 vertices; a face needs at least 3"
    );
}

#[test]
fn repeated_vertex() {
    let e = build_err(&square(), &[vec![0, 1, 2, 1]]);
    assert_eq!(e, MeshError::RepeatedVertex { face: 0, vertex: 1 });
    assert_eq!(e.to_string(), "face 0 uses vertex 1 more than once");
}

#[test]
fn edge_from_a_vertex_to_itself() {
    // `f 3 3 1` in a file: vertex 2 twice in a row, also across the wrap.
    for (face, v) in [(vec![2, 2, 0], 2), (vec![0, 1, 2, 0], 0)] {
        let e = build_err(&square(), &[vec![0, 1, 3], face]);
        assert_eq!(e, MeshError::EdgeToItself { face: 1, vertex: v });
        assert_eq!(
            e.to_string(),
            format!(
                "face 1 lists vertex {v} twice in a row: that would be an edge from a vertex \
                 to itself"
            )
        );
    }
}

#[test]
fn duplicate_faces_are_called_duplicates() {
    let p = square();
    // The same triangle twice, same winding: once said "orientations disagree".
    let same = build_err(&p, &[vec![0, 1, 2], vec![0, 2, 3], vec![1, 2, 0]]);
    assert_eq!(
        same,
        MeshError::DuplicateFace {
            first: 0,
            second: 2
        }
    );
    assert_eq!(
        same.to_string(),
        "face 2 duplicates face 0: both use the same vertices (a polygon may appear only once)"
    );
    // The "pillow": the same triangle with opposite windings is closed and
    // consistently oriented, so it used to be accepted, and flipping any of
    // its edges made an edge from a vertex to itself.
    let pillow = build_err(&p[..3], &[vec![0, 1, 2], vec![0, 2, 1]]);
    assert_eq!(
        pillow,
        MeshError::DuplicateFace {
            first: 0,
            second: 1
        }
    );
}

#[test]
fn the_first_duplicate_in_face_order_is_named_with_its_earliest_twin() {
    // Faces are compared in groups by their smallest vertex: the error must
    // still be the earliest face that repeats one, named with the earliest
    // face it repeats, whichever group each is in.
    let p: Vec<DVec3> = (0..8)
        .map(|i| DVec3::new(i as f64, (i * i) as f64, 0.0))
        .collect();
    let faces = vec![
        vec![4, 5, 6, 7], // 0
        vec![0, 1, 2],    // 1
        vec![3, 6, 5],    // 2
        vec![5, 3, 6],    // 3: repeats 2
        vec![2, 0, 1],    // 4: repeats 1, but comes later
        vec![6, 5, 3],    // 5: repeats 2 again
        vec![7, 6, 5, 4], // 6: repeats 0, a quad
    ];
    assert_eq!(
        build_err(&p, &faces),
        MeshError::DuplicateFace {
            first: 2,
            second: 3
        }
    );
    // The same vertices in another order are the same polygon; fewer or
    // more vertices are not.
    let quads = vec![vec![0, 1, 2, 3], vec![0, 1, 2], vec![0, 2, 1, 3]];
    assert_eq!(
        build_err(&p, &quads),
        MeshError::DuplicateFace {
            first: 0,
            second: 2
        }
    );
}

#[test]
fn of_several_edge_problems_the_first_in_face_order_is_named() {
    // The twins are found vertex by vertex, not face by face: the error is
    // still the first problem met walking the faces in order.
    let p: Vec<DVec3> = (0..6)
        .map(|i| DVec3::new(i as f64, (i * i) as f64, 0.0))
        .collect();
    let faces = vec![
        vec![3, 4, 5],
        vec![0, 1, 2],
        vec![4, 3, 0], // 4 -> 3 is the twin of 3 -> 4
        vec![0, 2, 5], // 0 -> 2 is the twin of 2 -> 0
        vec![4, 5, 1], // 4 -> 5 again (face 0 runs 4 -> 5): the first problem
        vec![1, 2, 3], // 1 -> 2 again: found first vertex by vertex
    ];
    assert_eq!(
        build_err(&p, &faces),
        MeshError::InconsistentOrientation {
            a: 4,
            b: 5,
            first: 0,
            second: 4
        }
    );
}

#[test]
fn two_edges_between_the_same_vertices_cannot_be_built() {
    // An indexed face list names an edge by its two vertices, so a second
    // edge between them can only come from a third face on it or a second
    // face running the same way; both are refused naming the vertices.
    let mut p = square();
    p.push(DVec3::new(0.5, 0.5, 1.0));
    let third = build_err(&p, &[vec![0, 1, 2], vec![2, 1, 4], vec![1, 2, 3]]);
    assert!(
        matches!(
            third,
            MeshError::EdgeSharedByMoreThanTwoFaces { a: 1, b: 2, .. }
        ),
        "{third:?}"
    );
    let same_way = build_err(&p, &[vec![0, 1, 2], vec![1, 2, 4]]);
    assert!(
        same_way.to_string().contains("from vertex 1 to vertex 2"),
        "{same_way}"
    );
}

#[test]
fn absurd_indices_do_not_overflow_the_message() {
    let e = build_err(&square(), &[vec![0, 1, usize::MAX]]);
    assert!(e.describe(1).contains("refers to vertex"), "{e}");
}

#[test]
fn a_face_with_many_corners_is_checked_in_linear_time() {
    // A quadratic repeated-vertex scan would take minutes here.
    let n = 200_000;
    let p: Vec<DVec3> = (0..n)
        .map(|i| DVec3::new(i as f64, (i % 7) as f64, 0.0))
        .collect();
    let mut big: Vec<usize> = (0..n).collect();
    big.push(5);
    let e = build_err(&p, &[big]);
    assert_eq!(e, MeshError::RepeatedVertex { face: 0, vertex: 5 });
}

#[test]
fn edge_shared_by_three_faces() {
    let mut p = square();
    p.push(DVec3::new(0.5, 0.5, 1.0));
    // Three triangles hinged on edge 0-2, like pages of a book.
    let e = build_err(&p, &[vec![0, 1, 2], vec![2, 3, 0], vec![0, 4, 2]]);
    assert_eq!(
        e,
        MeshError::EdgeSharedByMoreThanTwoFaces {
            a: 0,
            b: 2,
            faces: vec![0, 1, 2]
        }
    );
    assert!(e.to_string().contains("vertices 0 and 2"), "{e}");
    assert!(e.to_string().contains("face 0, face 1, face 2"), "{e}");
}

#[test]
fn inconsistent_orientation() {
    // Faces 0 and 2 both run 1 -> 2.
    let e = build_err(
        &square(),
        &[vec![0, 1, 2], vec![0, 2, 3], vec![1, 2, 3], vec![0, 1, 3]],
    );
    assert!(
        matches!(e, MeshError::InconsistentOrientation { .. }),
        "{e:?}"
    );
    let two = build_err(&square(), &[vec![0, 1, 2], vec![0, 1, 3]]);
    assert_eq!(
        two,
        MeshError::InconsistentOrientation {
            a: 0,
            b: 1,
            first: 0,
            second: 1
        }
    );
    assert!(two
        .to_string()
        .contains("faces 0 and 1 both run from vertex 0 to vertex 1"));
}

#[test]
fn non_manifold_vertex_two_fans() {
    // Two triangles touching only at vertex 0: a bow tie.
    let p = vec![
        DVec3::ZERO,
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(-1.0, 0.0, 0.0),
        DVec3::new(-1.0, -1.0, 0.0),
    ];
    let e = build_err(&p, &[vec![0, 1, 2], vec![0, 3, 4]]);
    assert_eq!(e, MeshError::NonManifoldVertex { vertex: 0 });
    assert!(e.to_string().contains("vertex 0 is non-manifold"));
}

#[test]
fn non_manifold_vertex_closed_fans() {
    // Two tetrahedra sharing one tip: every edge has two faces, yet vertex 0
    // has two separate fans and no hole to give it away.
    let mut p = vec![DVec3::ZERO];
    let tet = |o: f64| {
        vec![
            DVec3::new(o, 0.0, 0.0),
            DVec3::new(o, 1.0, 0.0),
            DVec3::new(o, 0.0, 1.0),
        ]
    };
    p.extend(tet(1.0));
    p.extend(tet(-1.0));
    let fan = |a: usize, b: usize, c: usize| {
        vec![vec![0, b, a], vec![0, c, b], vec![0, a, c], vec![a, b, c]]
    };
    let mut faces = fan(1, 2, 3);
    faces.extend(fan(4, 5, 6));
    assert_eq!(
        build_err(&p, &faces),
        MeshError::NonManifoldVertex { vertex: 0 }
    );
}

#[test]
fn unreferenced_vertex() {
    let mut p = square();
    p.push(DVec3::new(9.0, 9.0, 9.0));
    let e = build_err(&p, &[vec![0, 1, 2, 3]]);
    assert_eq!(e, MeshError::UnreferencedVertex { vertex: 4 });
    assert_eq!(e.to_string(), "vertex 4 is not used by any face");
}

#[test]
fn non_finite_coordinate() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut p = square();
        p[2].y = bad;
        let e = build_err(&p, &[vec![0, 1, 2, 3]]);
        assert_eq!(e, MeshError::NonFiniteCoordinate { vertex: 2 });
        assert!(e.to_string().contains("NaN or infinite"));
    }
}

fn obj_err(text: &str) -> String {
    match Mesh::from_obj_str(text, "t.obj") {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e.to_string(),
    }
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn obj_errors_name_the_line_and_use_file_numbers() {
    assert_eq!(
        obj_err("v 0 0 0\nv 1 zero 0\n"),
        "t.obj:2: `zero` is not a number: `v 1 zero 0`"
    );
    assert_eq!(
        obj_err("# a comment\nv 0 0\n"),
        "t.obj:2: a vertex needs three coordinates (four with a weight, six with a colour), \
         found 2: `v 0 0`"
    );
    assert_eq!(
        obj_err(&format!("{TRI}f 1 2 x\n")),
        "t.obj:4: `x` is not a vertex reference: `f 1 2 x`"
    );
    assert_eq!(
        obj_err(&format!("{TRI}f 0 1 2\n")),
        "t.obj:4: vertex references start at 1 (or -1 for the last); 0 is not one: `f 0 1 2`"
    );
    assert_eq!(
        obj_err(&format!("{TRI}f -1 -2 -4\n")),
        "t.obj:4: `-4` counts back past the first vertex (only 3 are defined above this line): \
         `f -1 -2 -4`"
    );
    // Errors found while building give the face's line and 1-based numbers.
    assert_eq!(
        obj_err(&format!("{TRI}f 1 2 3\n\nf 1 3 4\n")),
        "t.obj:6: face 2 refers to vertex 4, but the vertices are numbered 1 to 3"
    );
    assert_eq!(
        obj_err(&format!("{TRI}f 1 2\n")),
        "t.obj:4: face 1 has 2 vertices; a face needs at least 3"
    );
    assert_eq!(
        obj_err(&format!("{TRI}v 5 5 5\nf 1 2 3\n")),
        "t.obj:4: vertex 4 is not used by any face"
    );
    assert_eq!(
        obj_err("v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        "t.obj:1: vertex 1 has a coordinate that is NaN or infinite"
    );
    assert_eq!(
        obj_err("# nothing\n"),
        "t.obj: the mesh is empty: it needs at least one vertex and one face"
    );
}

#[test]
fn obj_accepts_slashes_negative_references_and_other_statements() {
    let text = "o thing\nv 0 0 0\nv 1 0 0 0.5 0.5 0.5\nvt 0 0\nvn 0 0 1\nv 0 1 0\ng side\ns off\nf 1/1/1 -2//1 3/1\n";
    let mesh = Mesh::from_obj_str(text, "t.obj").unwrap();
    let (_, faces) = mesh.to_faces();
    assert_eq!(faces, vec![vec![0, 1, 2]]);
}

#[test]
fn unreadable_file() {
    let e = Mesh::from_obj_file("/definitely/not/here.obj").unwrap_err();
    assert!(matches!(e, MeshError::UnreadableFile { .. }));
    assert!(
        e.to_string()
            .starts_with("cannot read /definitely/not/here.obj: "),
        "{e}"
    );
}
