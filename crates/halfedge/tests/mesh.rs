//! Ids, traversal helpers, creation, the growth budget, export and OBJ.

use std::panic;

use halfedge::{shapes, DVec3, EdgeId, FaceId, HalfedgeId, Mesh, VertexId};

#[test]
fn ids_print_with_their_kind() {
    assert_eq!(VertexId(12).to_string(), "v12");
    assert_eq!(EdgeId(7).to_string(), "e7");
    assert_eq!(FaceId(3).to_string(), "f3");
    assert_eq!(HalfedgeId(40).to_string(), "h40");
    assert_eq!(format!("{:?}", HalfedgeId::NONE), "h-none");
    assert!(VertexId(1) < VertexId(2));
}

#[test]
fn id_iterators_do_not_borrow_and_skip_new_elements() {
    let mut m = shapes::lab_object("cube").unwrap();
    let mut visited = 0;
    for e in m.edge_ids() {
        visited += 1;
        let v = m.new_vertex(m.edge_center(e));
        m[v].is_new = true;
    }
    assert_eq!(visited, 18);
    assert_eq!(m.num_vertices(), 8 + 18);
    assert_eq!(m.vertex_ids().len(), 26);
}

#[test]
fn traversal_helpers_on_the_lab_cube() {
    let m = shapes::lab_object("cube").unwrap();
    let total: usize = m.vertex_ids().map(|v| m.vertex_degree(v)).sum();
    assert_eq!(total, 2 * m.num_edges());
    for v in m.vertex_ids() {
        let ns = m.vertex_neighbors(v);
        assert_eq!(ns.len(), m.vertex_degree(v));
        for &n in &ns {
            assert!(m.find_edge(v, n).is_some());
            assert!(m.vertex_neighbors(n).contains(&v), "edges go both ways");
        }
        assert!(!m.vertex_on_boundary(v));
    }
    for f in m.face_ids() {
        assert_eq!(m.face_degree(f), 3);
        let hs = m.face_halfedges(f);
        assert_eq!(hs[0], m[f].halfedge);
        for w in 0..3 {
            assert_eq!(m[hs[w]].next, hs[(w + 1) % 3]);
        }
    }
    // The lab cube's first face is "f 3 1 2": vertices 2, 0, 1.
    assert_eq!(
        m.face_vertices(FaceId(0)),
        vec![VertexId(2), VertexId(0), VertexId(1)]
    );
    assert_eq!(m.edge_between(2, 0), m.find_edge(VertexId(0), VertexId(2)));
    assert!(
        m.edge_between(0, 5).is_none(),
        "0 and 5 are opposite corners of a side"
    );
    assert!(m.edge_between(0, 99).is_none());
}

#[test]
fn describe_shows_links() {
    let m = shapes::lab_object("cube").unwrap();
    let h = HalfedgeId(0);
    let r = m[h];
    assert_eq!(
        m.describe(h),
        format!(
            "h0: from v2 to v0, twin {}, next h1, edge e0, face f0",
            r.twin
        )
    );
    assert!(m
        .describe(VertexId(0))
        .starts_with("v0: at (-0.5, -0.5, -0.5)"));
    assert!(m.describe(EdgeId(0)).starts_with("e0: halfedges h0 and "));
    assert_eq!(m.describe(FaceId(0)), "f0: halfedge h0");
    let g = shapes::grid(1, 1);
    assert!(g.describe(FaceId(2)).starts_with("f2: boundary, "));
}

#[test]
fn set_neighbors_sets_all_five() {
    let mut m = Mesh::new();
    let h = m.new_halfedge();
    let t = m.new_halfedge();
    let v = m.new_vertex(DVec3::ZERO);
    let e = m.new_edge();
    let f = m.new_face();
    m.set_neighbors(h, t, t, v, e, f);
    let r = m[h];
    assert_eq!((r.next, r.twin, r.vertex, r.edge, r.face), (t, t, v, e, f));
    assert!(m[t].next.is_none(), "t untouched");
}

#[test]
fn growth_budget_panics_with_a_message() {
    let mut m = shapes::lab_object("cone").unwrap();
    let limit = m.num_elements() + 2;
    m.set_element_budget(Some(limit));
    m.new_vertex(DVec3::ZERO);
    m.new_edge();
    let err = panic::catch_unwind(panic::AssertUnwindSafe(|| {
        m.new_halfedge();
    }))
    .unwrap_err();
    let msg = err.downcast_ref::<String>().unwrap();
    assert!(
        msg.starts_with(&format!("the mesh grew past {limit} elements")),
        "{msg}"
    );
    m.set_element_budget(None);
    m.new_halfedge();
}

#[test]
fn indexing_a_missing_element_says_so() {
    let m = shapes::lab_object("cone").unwrap();
    let err = panic::catch_unwind(|| m[VertexId(70)].pos).unwrap_err();
    let msg = err.downcast_ref::<String>().unwrap();
    assert!(
        msg.starts_with(
            "there is no vertex v70 (the mesh has 7): an unset or stale id? (found by the mesh \
             library's indexing, crates/halfedge/src/mesh.rs:"
        ),
        "{msg}"
    );
}

/// A panic in the library is placed at the caller's line (the student's),
/// the library's own place said in the message.
#[test]
fn a_panic_in_the_library_is_placed_at_the_line_that_called_it() {
    let m = shapes::lab_object("cone").unwrap();
    let place = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
    let seen = place.clone();
    // Tests run side by side: record only this thread's panics.
    let me = std::thread::current().id();
    let old = panic::take_hook();
    panic::set_hook(Box::new(move |info| {
        if std::thread::current().id() != me {
            return;
        }
        if let Some(l) = info.location() {
            *seen.lock().unwrap() = format!("{}:{}", l.file(), l.line());
        }
    }));
    let line = line!() + 1;
    let _ = panic::catch_unwind(|| m[halfedge::HalfedgeId::NONE].next);
    let _ = panic::catch_unwind(|| m.vertex_halfedges(VertexId(99)));
    panic::set_hook(old);
    assert_eq!(
        *place.lock().unwrap(),
        format!("crates/halfedge/tests/mesh.rs:{}", line + 1)
    );
}

#[test]
fn broken_links_make_walks_panic_not_hang() {
    let mut m = shapes::lab_object("cube").unwrap();
    // A face loop that never comes back to the face's halfedge.
    let f = FaceId(0);
    let h0 = m[f].halfedge;
    let h1 = m[h0].next;
    m[h1].next = h1;
    let err = panic::catch_unwind(|| m.face_halfedges(f)).unwrap_err();
    let msg = err.downcast_ref::<String>().unwrap();
    assert!(
        msg.starts_with("the walk around f0 never came back"),
        "{msg}"
    );
}

#[test]
fn export_faces_and_edges() {
    let g = shapes::grid(1, 1);
    let (p, faces) = g.to_faces();
    assert_eq!(p.len(), 4);
    assert_eq!(faces, vec![vec![0, 1, 3], vec![0, 3, 2]]);
    let mut edges = g.edge_list();
    edges.sort();
    assert_eq!(edges, vec![[0, 1], [0, 2], [0, 3], [1, 3], [2, 3]]);
}

fn awkward_positions(mesh: &mut Mesh) {
    let odd = [
        0.1 + 0.2,
        -0.0,
        1e-300,
        -123456789.12345679,
        f64::MIN_POSITIVE,
        1.0 / 3.0,
        2f64.sqrt(),
        1e21,
    ];
    for (i, v) in mesh.vertex_ids().enumerate() {
        let k = odd[i % odd.len()];
        mesh[v].pos = DVec3::new(k, mesh[v].pos.y * k, mesh[v].pos.z + k);
    }
}

#[test]
fn obj_round_trip_changes_nothing() {
    let mut m = shapes::icosphere(2);
    awkward_positions(&mut m);
    let text = m.to_obj_string();
    let back = Mesh::from_obj_str(&text, "round.obj").unwrap();
    let (p1, f1) = m.to_faces();
    let (p2, f2) = back.to_faces();
    assert_eq!(f1, f2);
    for (a, b) in p1.iter().zip(&p2) {
        for k in 0..3 {
            assert_eq!(a[k].to_bits(), b[k].to_bits(), "{a} vs {b}");
        }
    }
    assert_eq!(back.to_obj_string(), text);
}

#[test]
fn obj_file_round_trip() {
    let m = shapes::torus(5, 4, 1.0, 0.25);
    let path = std::env::temp_dir().join(format!("halfedge-test-{}.obj", std::process::id()));
    m.write_obj_file(&path).unwrap();
    let back = Mesh::from_obj_file(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(back.to_faces(), m.to_faces());
}

/// tobj numbers vertices by first use; renumber ours the same way and the
/// two parsers must agree on every position and face.
#[test]
fn reader_agrees_with_tobj_on_the_lab_objects() {
    for name in shapes::LAB_OBJECTS {
        let text = shapes::lab_object_obj(name).unwrap();
        let ours = Mesh::from_obj_str(text, name).unwrap();
        let (positions, faces) = ours.to_faces();

        let opts = tobj::LoadOptions {
            single_index: false,
            triangulate: false,
            ..Default::default()
        };
        let (models, _) =
            tobj::load_obj_buf(&mut text.as_bytes(), &opts, |_| Ok(Default::default())).unwrap();
        assert_eq!(models.len(), 1, "{name}");
        let theirs = &models[0].mesh;

        let mut order: Vec<usize> = Vec::new();
        let mut renumber = vec![usize::MAX; positions.len()];
        let mut renumbered = Vec::new();
        for &i in faces.iter().flatten() {
            if renumber[i] == usize::MAX {
                renumber[i] = order.len();
                order.push(i);
            }
            renumbered.push(renumber[i] as u32);
        }
        assert_eq!(renumbered, theirs.indices, "{name}: faces");
        let ours_flat: Vec<f64> = order
            .iter()
            .flat_map(|&i| positions[i].to_array())
            .collect();
        assert_eq!(ours_flat, theirs.positions, "{name}: positions");
    }
}

#[test]
fn prev_is_the_inverse_of_next() {
    // Triangles (the lab cube) and a hole's longer loop (the grid's rim).
    for m in [shapes::lab_object("cube").unwrap(), shapes::grid(3, 2)] {
        for h in m.halfedge_ids() {
            let p = m.prev(h);
            assert_eq!(m[p].next, h, "prev({h}) = {p}");
            assert_eq!(m[p].face, m[h].face, "{p} and {h} share a face");
            assert_eq!(m.halfedge_dst(p), m[h].vertex, "{p} ends where {h} starts");
        }
    }
    let g = shapes::grid(3, 2);
    let rim = g.face_ids().find(|&f| g[f].is_boundary).unwrap();
    let loop_ = g.face_halfedges(rim);
    assert_eq!(loop_.len(), 10, "a 3 by 2 grid's rim has 10 edges");
    assert_eq!(g.prev(loop_[0]), loop_[9]);
}

#[test]
fn prev_twin_steps_back_around_a_vertex() {
    let m = shapes::lab_object("torus").unwrap();
    for v in m.vertex_ids() {
        let around = m.vertex_halfedges(v);
        let n = around.len();
        for i in 0..n {
            let back = m[m.prev(around[(i + 1) % n])].twin;
            assert_eq!(back, around[i], "one step back from {}", around[i]);
        }
    }
}

#[test]
fn prev_panics_with_a_message_on_a_broken_face() {
    let mut m = shapes::lab_object("cube").unwrap();
    let h0 = m[FaceId(0)].halfedge;
    let h1 = m[h0].next;
    m[h1].next = h1;
    let err = panic::catch_unwind(|| m.prev(h0)).unwrap_err();
    let msg = err.downcast_ref::<String>().unwrap();
    assert!(
        msg.starts_with(&format!("the walk around the face of {h0} never came back")),
        "{msg}"
    );
}

/// For each vertex of a convex closed mesh centred at the origin, the sign
/// of the turn from each halfedge around it to the next, seen from outside:
/// +1 counter-clockwise, -1 clockwise (all turns must agree).
fn turn_seen_from_outside(m: &Mesh) -> f64 {
    let mut sign = 0.0;
    for v in m.vertex_ids() {
        let out = m[v].pos; // outwards, for a convex shape around the origin
        let dirs: Vec<DVec3> = m
            .vertex_halfedges(v)
            .into_iter()
            .map(|h| m[m.halfedge_dst(h)].pos - m[v].pos)
            .collect();
        for i in 0..dirs.len() {
            let turn = dirs[i].cross(dirs[(i + 1) % dirs.len()]).dot(out);
            assert!(turn.abs() > 1e-9, "{v}: a flat turn");
            if sign == 0.0 {
                sign = turn.signum();
            }
            assert_eq!(turn.signum(), sign, "{v}: the turns disagree");
        }
    }
    sign
}

#[test]
fn vertex_halfedges_turn_against_the_faces() {
    // Faces counter-clockwise seen from outside: the walk turns clockwise.
    assert_eq!(turn_seen_from_outside(&shapes::icosphere(1)), -1.0);
    // The lab's cube is wound clockwise seen from outside: the walk turns
    // counter-clockwise seen from outside.
    let lab = shapes::lab_object("cube").unwrap();
    let centre = lab.positions().iter().sum::<DVec3>();
    assert!(
        centre.length() < 1e-12,
        "the lab cube is centred on the origin"
    );
    assert_eq!(turn_seen_from_outside(&lab), 1.0);
}

#[test]
fn reserve_creates_nothing_and_changes_no_id() {
    let mut plain = shapes::icosphere(1);
    let mut reserved = plain.clone();
    reserved.reserve(5, 5, 5, 5);
    assert_eq!(reserved.num_elements(), plain.num_elements());
    for mesh in [&mut plain, &mut reserved] {
        let v = mesh.new_vertex(DVec3::X);
        let e = mesh.new_edge();
        let f = mesh.new_face();
        let h = mesh.new_halfedge();
        mesh.set_neighbors(h, h, h, v, e, f);
    }
    assert_eq!(reserved.records(), plain.records());
}

#[test]
fn the_counting_walks_panic_like_the_collecting_ones() {
    // vertex_degree and find_edge no longer collect the walk: a broken link
    // must still end them with the same message, not a loop.
    let mut mesh = shapes::icosphere(0);
    let v = VertexId(0);
    let h = mesh[v].halfedge;
    // A twin pointing at itself: the walk around v circles at h's far side.
    let t = mesh[h].twin;
    let stuck = mesh[t].next;
    mesh[stuck].twin = t;
    mesh[t].next = stuck;
    for (what, result) in [
        (
            "vertex_halfedges",
            panic::catch_unwind(|| mesh.vertex_halfedges(v).len()),
        ),
        (
            "vertex_degree",
            panic::catch_unwind(|| mesh.vertex_degree(v)),
        ),
        (
            "find_edge",
            panic::catch_unwind(|| mesh.find_edge(v, VertexId(99)).map_or(0, |e| e.index())),
        ),
    ] {
        let message = result.expect_err(what);
        let text = message
            .downcast_ref::<String>()
            .cloned()
            .unwrap_or_default();
        assert!(
            text.contains("the walk around v0 never came back to where it started"),
            "{what}: {text:?}"
        );
    }
}
