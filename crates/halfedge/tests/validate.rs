//! Each `validate()` message, provoked by corrupting a valid mesh on purpose.

use halfedge::{shapes, DVec3, EdgeId, Element, FaceId, HalfedgeId, Mesh, VertexId};

fn cube() -> Mesh {
    shapes::lab_object("cube").unwrap()
}

/// Asserts that validate() fails on `element` with exactly `message`.
fn assert_invalid(mesh: &Mesh, element: impl Into<Element>, message: &str) {
    let element = element.into();
    match mesh.validate() {
        Ok(()) => panic!("expected `{message}` on {element}, but the mesh validated"),
        Err(got) => {
            assert_eq!(
                (got.message.as_str(), got.element),
                (message, element),
                "\nexpected: {message} ({element})\n     got: {got}"
            );
            // The check is the fact; its message is the one given.
            assert_eq!(got.check.message(), message);
            assert_eq!(halfedge::Check::from_message(message), Some(got.check));
        }
    }
}

#[test]
fn every_check_has_its_own_message_and_key() {
    use halfedge::Check;
    for (i, a) in Check::ALL.iter().enumerate() {
        assert_eq!(Check::from_key(a.key()), Some(*a));
        assert_eq!(Check::from_message(a.message()), Some(*a));
        for b in &Check::ALL[i + 1..] {
            assert_ne!(a.message(), b.message());
            assert_ne!(a.key(), b.key());
        }
    }
}

#[test]
fn valid_meshes_validate() {
    for name in shapes::LAB_OBJECTS {
        shapes::lab_object(name).unwrap().validate().unwrap();
    }
    shapes::grid(3, 2).validate().unwrap();
}

#[test]
fn non_finite_position() {
    let mut m = cube();
    m[VertexId(3)].pos = DVec3::new(0.0, f64::NAN, 0.0);
    assert_invalid(
        &m,
        VertexId(3),
        "A vertex position was set to a non-finite value.",
    );
}

#[test]
fn unset_ids() {
    let mut m = cube();
    m.new_vertex(DVec3::ONE);
    assert_invalid(
        &m,
        VertexId(8),
        "A vertex's halfedge was never set (or names no halfedge)!",
    );

    let mut m = cube();
    let e = m.new_edge();
    assert_invalid(
        &m,
        e,
        "An edge's halfedge was never set (or names no halfedge)!",
    );

    let mut m = cube();
    let f = m.new_face();
    assert_invalid(
        &m,
        f,
        "A face's halfedge was never set (or names no halfedge)!",
    );

    type Corrupt = fn(&mut Mesh, HalfedgeId);
    let fields: [(Corrupt, &str); 5] = [
        (
            |m, h| m[h].next = HalfedgeId::NONE,
            "A halfedge's next was never set (or names no halfedge)!",
        ),
        (
            |m, h| m[h].twin = HalfedgeId(999),
            "A halfedge's twin was never set (or names no halfedge)!",
        ),
        (
            |m, h| m[h].vertex = VertexId::NONE,
            "A halfedge's vertex was never set (or names no vertex)!",
        ),
        (
            |m, h| m[h].edge = EdgeId::NONE,
            "A halfedge's edge was never set (or names no edge)!",
        ),
        (
            |m, h| m[h].face = FaceId::NONE,
            "A halfedge's face was never set (or names no face)!",
        ),
    ];
    for (break_it, message) in fields {
        let mut m = cube();
        break_it(&mut m, HalfedgeId(5));
        assert_invalid(&m, HalfedgeId(5), message);
    }
}

#[test]
fn next_of_multiple_halfedges() {
    let mut m = cube();
    // h1 already follows h0; make h7 point there too.
    let target = m[HalfedgeId(0)].next;
    m[HalfedgeId(7)].next = target;
    // The later of the two halfedges sharing a next is named.
    assert_invalid(
        &m,
        HalfedgeId(7),
        "A halfedge is the next of multiple halfedges!",
    );
}

#[test]
fn twin_points_to_itself() {
    let mut m = cube();
    m[HalfedgeId(0)].twin = HalfedgeId(0);
    assert_invalid(&m, HalfedgeId(0), "A halfedge's twin points to itself!");
}

#[test]
fn twins_twin_is_not_itself() {
    let mut m = cube();
    m[HalfedgeId(4)].twin = HalfedgeId(9);
    let first_bad = (0..m.num_halfedges())
        .map(HalfedgeId::from_index)
        .find(|&h| m[m[h].twin].twin != h)
        .unwrap();
    assert_invalid(&m, first_bad, "A halfedge's twin's twin is not itself!");
}

#[test]
fn owners_must_be_pointed_back_at() {
    let mut m = cube();
    let v = VertexId(0);
    let other = m.vertex_halfedges(VertexId(1))[0];
    m[v].halfedge = other;
    assert_invalid(&m, v, "A vertex's halfedge does not point to that vertex!");

    let mut m = cube();
    let e = EdgeId(2);
    m[e].halfedge = m[EdgeId(3)].halfedge;
    assert_invalid(&m, e, "An edge's halfedge does not point to that edge!");

    let mut m = cube();
    let f = FaceId(1);
    m[f].halfedge = m[FaceId(0)].halfedge;
    assert_invalid(&m, f, "A face's halfedge does not point to that face!");
}

#[test]
fn halfedge_does_not_point_to_its_vertex() {
    let mut m = cube();
    let v = VertexId(2);
    // A halfedge of v's fan other than the one v points to.
    let h = m.vertex_halfedges(v)[1];
    m[h].vertex = VertexId(5);
    assert_invalid(&m, h, "A halfedge does not point to its vertex!");
}

#[test]
fn vertex_with_two_fans() {
    let mut m = cube();
    let v = VertexId(0);
    let fan = m.vertex_halfedges(v);
    assert!(fan.len() >= 4);
    // Swapping two successors in v's cycle cuts it into two cycles: both
    // still start at v, but v only reaches one of them.
    let (x, y) = (m[fan[0]].twin, m[fan[2]].twin);
    let (nx, ny) = (m[x].next, m[y].next);
    m[x].next = ny;
    m[y].next = nx;
    assert_invalid(
        &m,
        v,
        "A vertex's halfedges do not form a single fan around it (non-manifold vertex)!",
    );
}

#[test]
fn halfedge_does_not_point_to_its_edge() {
    let mut m = cube();
    let e = EdgeId(0);
    let t = m[m[e].halfedge].twin;
    m[t].edge = EdgeId(5);
    assert_invalid(&m, t, "A halfedge does not point to its edge!");
}

#[test]
fn halfedge_does_not_point_to_its_face() {
    let mut m = cube();
    let f = FaceId(0);
    let h = m.face_halfedges(f)[1];
    m[h].face = FaceId(3);
    assert_invalid(&m, h, "A halfedge does not point to its face!");
}

#[test]
fn edge_with_holes_on_both_sides() {
    let mut m = shapes::grid(2, 2);
    // A real face at the rim, relabelled as a hole.
    let e = m.edge_ids().find(|&e| m.edge_on_boundary(e)).unwrap();
    let h = m[e].halfedge;
    let real = if m[m[h].face].is_boundary {
        m[h].twin
    } else {
        h
    };
    let f = m[real].face;
    m[f].is_boundary = true;
    assert_invalid(&m, e, "An edge has boundary faces on both sides!");
}

/// Two vertices, two edges, two 2-sided faces: links that are consistent but
/// no surface.
fn two_gon_pillow() -> Mesh {
    let mut m = Mesh::new();
    let a = m.new_vertex(DVec3::ZERO);
    let b = m.new_vertex(DVec3::X);
    let (e1, e2) = (m.new_edge(), m.new_edge());
    let (f1, f2) = (m.new_face(), m.new_face());
    let h: Vec<HalfedgeId> = (0..4).map(|_| m.new_halfedge()).collect();
    // f1: h0 (a->b), h1 (b->a). f2: h2 (a->b), h3 (b->a).
    m.set_neighbors(h[0], h[1], h[3], a, e1, f1);
    m.set_neighbors(h[1], h[0], h[2], b, e2, f1);
    m.set_neighbors(h[2], h[3], h[1], a, e2, f2);
    m.set_neighbors(h[3], h[2], h[0], b, e1, f2);
    m[a].halfedge = h[0];
    m[b].halfedge = h[1];
    m[e1].halfedge = h[0];
    m[e2].halfedge = h[1];
    m[f1].halfedge = h[0];
    m[f2].halfedge = h[2];
    m
}

#[test]
fn face_with_two_sides() {
    let m = two_gon_pillow();
    assert_invalid(&m, FaceId(0), "A face has fewer than three sides!");
}

/// Links polygons by hand, with no checks: each `(cycle, is_boundary)` is a
/// face; halfedge a->b is twinned with b->a. Lets a test build the shapes
/// the builder refuses.
fn link_by_hand(positions: &[DVec3], faces: &[(&[usize], bool)]) -> Mesh {
    let mut m = Mesh::new();
    for &p in positions {
        m.new_vertex(p);
    }
    let mut by_ends = std::collections::HashMap::new();
    for &(cycle, is_boundary) in faces {
        let f = m.new_face();
        m[f].is_boundary = is_boundary;
        let hs: Vec<HalfedgeId> = cycle.iter().map(|_| m.new_halfedge()).collect();
        for (i, &h) in hs.iter().enumerate() {
            let (a, b) = (cycle[i], cycle[(i + 1) % cycle.len()]);
            m[h].next = hs[(i + 1) % hs.len()];
            m[h].vertex = VertexId::from_index(a);
            m[h].face = f;
            m[VertexId::from_index(a)].halfedge = h;
            by_ends.insert((a, b), h);
        }
        m[f].halfedge = hs[0];
    }
    for h in m.halfedge_ids() {
        if m[h].edge.is_none() {
            let a = m[h].vertex.index();
            let b = m[m[h].next].vertex.index();
            let t = by_ends[&(b, a)];
            let e = m.new_edge();
            m[e].halfedge = h;
            m[h].edge = e;
            m[t].edge = e;
            m[h].twin = t;
            m[t].twin = h;
        }
    }
    m
}

#[test]
fn halfedge_from_a_vertex_to_itself() {
    // The "pillow" (one triangle twice, opposite windings) with its edge 0-1
    // flipped: the vertex facing that edge is 2 on both sides, so the
    // flipped edge runs from 2 to 2 inside faces (2, 2, 0) and (2, 2, 1).
    // Its links are otherwise consistent, and validate() once let it
    // through. Built from the faces, as a flip would leave them.
    let p = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let m = link_by_hand(&p, &[(&[2, 2, 0], false), (&[2, 2, 1], false)]);
    let looped = m
        .halfedge_ids()
        .find(|&h| m[h].vertex == m[m[h].twin].vertex)
        .expect("the flipped edge's halfedges");
    assert_eq!(m[looped].vertex.index(), 2);
    assert_invalid(&m, looped, "A halfedge starts and ends at the same vertex!");
}

#[test]
fn face_visiting_a_vertex_twice() {
    // A bow tie: two triangles touching at vertex 0, with one hole around
    // both that passes through vertex 0 twice. Every link is consistent and
    // vertex 0's halfedges form one fan through the hole.
    let p = [
        DVec3::ZERO,
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(-1.0, 0.0, 0.0),
        DVec3::new(-1.0, -1.0, 0.0),
    ];
    let m = link_by_hand(
        &p,
        &[
            (&[0, 1, 2], false),
            (&[0, 3, 4], false),
            (&[0, 2, 1, 0, 4, 3], true),
        ],
    );
    assert_invalid(
        &m,
        FaceId(2),
        "A face visits the same vertex more than once!",
    );
}

#[test]
fn corrupted_cycles_are_reported_not_looped_on() {
    // next of every halfedge pointing to itself, twin cycles of length 3:
    // nothing here may hang.
    let mut m = cube();
    for h in m.halfedge_ids() {
        m[h].next = h;
    }
    assert!(m.validate().is_err());
    let mut m = cube();
    let n = m.num_halfedges();
    for h in m.halfedge_ids() {
        m[h].twin = HalfedgeId::from_index((h.index() + 1) % n);
    }
    assert!(m.validate().is_err());
}

#[test]
fn display_names_the_element() {
    let mut m = cube();
    m[HalfedgeId(0)].twin = HalfedgeId(0);
    assert_eq!(
        m.validate().unwrap_err().to_string(),
        "A halfedge's twin points to itself! (h0)"
    );
}
