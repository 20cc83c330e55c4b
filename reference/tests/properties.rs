//! Properties of the reference's `flip_edge`, `split_edge` and
//! `loop_subdivide` on generated manifold meshes whose vertices and faces
//! come in random orders (proptest):
//!
//! - random flips and splits keep `validate()` clean, change the counts as
//!   the contract says and keep the Euler characteristic;
//! - one round of subdivision validates, multiplies the faces by four, keeps
//!   the Euler characteristic, and does not depend on the element order.
//!
//! A few hundred cases each; `PROPTEST_CASES` asks for that many per
//! property instead.

use std::collections::HashMap;

use halfedge::{shapes, DVec3, EdgeId, Mesh};
use proptest::prelude::*;
use proptest::sample::Index;
use reference::solution::{self, Weights};

fn config(default: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default);
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Small triangle meshes of every shape the generators make, closed and open.
fn base_shape() -> impl Strategy<Value = Mesh> {
    prop_oneof![
        prop::sample::select(shapes::LAB_OBJECTS.to_vec())
            .prop_map(|n| shapes::lab_object(n).unwrap()),
        (1usize..=2).prop_map(shapes::cube),
        (3usize..=6, 3usize..=5).prop_map(|(a, b)| shapes::torus(a, b, 2.0, 0.5)),
        (0usize..=1).prop_map(shapes::icosphere),
        (1usize..=4, 1usize..=3).prop_map(|(x, y)| shapes::grid(x, y)),
        (3usize..=7, 1usize..=3, any::<bool>())
            .prop_map(|(s, r, capped)| shapes::cylinder(s, r, 1.0, 2.0, capped)),
        (3usize..=7).prop_map(|s| shapes::cone(s, 1.0, 1.0)),
        Just(tetrahedron()),
    ]
}

/// Every edge's flip would duplicate an edge.
fn tetrahedron() -> Mesh {
    let p = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    Mesh::from_faces(
        &p,
        &[vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![2, 0, 3]],
    )
    .expect("a tetrahedron")
}

/// The same surface rebuilt with vertices renumbered, faces reordered and
/// each face starting at a random corner: edge and halfedge ids come out in
/// another order too.
fn shuffled() -> impl Strategy<Value = (Mesh, Mesh)> {
    base_shape().prop_flat_map(|mesh| {
        let (nv, nf) = (mesh.num_vertices(), mesh.num_real_faces());
        (
            Just(mesh),
            Just((0..nv).collect::<Vec<_>>()).prop_shuffle(),
            Just((0..nf).collect::<Vec<_>>()).prop_shuffle(),
            prop::collection::vec(0usize..3, nf),
        )
            .prop_map(|(mesh, vperm, forder, turns)| {
                let (positions, faces) = mesh.to_faces();
                let mut moved = vec![DVec3::ZERO; positions.len()];
                for (i, &p) in positions.iter().enumerate() {
                    moved[vperm[i]] = p;
                }
                let faces: Vec<Vec<usize>> = forder
                    .iter()
                    .map(|&f| {
                        let mut face: Vec<usize> = faces[f].iter().map(|&v| vperm[v]).collect();
                        let k = turns[f] % face.len();
                        face.rotate_left(k);
                        face
                    })
                    .collect();
                let other = Mesh::from_faces(&moved, &faces).expect("a renumbered valid mesh");
                (mesh, other)
            })
    })
}

fn euler(mesh: &Mesh) -> i64 {
    mesh.num_vertices() as i64 - mesh.num_edges() as i64 + mesh.num_real_faces() as i64
}

fn counts(mesh: &Mesh) -> [usize; 4] {
    [
        mesh.num_vertices(),
        mesh.num_edges(),
        mesh.num_faces(),
        mesh.num_halfedges(),
    ]
}

/// Whether flipping `e` would join two vertices that are one or already
/// joined: such a flip makes a double edge.
fn flip_duplicates_an_edge(mesh: &Mesh, e: EdgeId) -> bool {
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    let c = mesh[mesh[mesh[h].next].next].vertex;
    let d = mesh[mesh[mesh[t].next].next].vertex;
    c == d || mesh.find_edge(c, d).is_some()
}

/// Whether two point sets are the same up to order, within `tol`: a hash
/// grid of `tol`-sized cells, each point matched once.
fn same_points(a: &[DVec3], b: &[DVec3], tol: f64) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let cell = |p: DVec3| (p / tol).floor().as_i64vec3().to_array();
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, &p) in a.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(i);
    }
    let mut used = vec![false; a.len()];
    'points: for &q in b {
        let c = cell(q);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                    for &i in grid.get(&key).map(Vec::as_slice).unwrap_or(&[]) {
                        if !used[i] && a[i].distance(q) <= tol {
                            used[i] = true;
                            continue 'points;
                        }
                    }
                }
            }
        }
        return false;
    }
    true
}

#[derive(Clone, Debug)]
enum Op {
    Flip(Index),
    Split(Index),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        2 => any::<Index>().prop_map(Op::Flip),
        1 => any::<Index>().prop_map(Op::Split),
    ]
}

proptest! {
    #![proptest_config(config(400))]

    /// Random flips and splits: every step validates, adds what the
    /// contract says, and keeps V - E + F.
    #[test]
    fn flips_and_splits_keep_the_mesh_valid((_, mut mesh) in shuffled(),
                                            ops in prop::collection::vec(op(), 1..25)) {
        let chi = euler(&mesh);
        for (step, op) in ops.iter().enumerate() {
            let before = counts(&mesh);
            match op {
                Op::Flip(i) => {
                    let e = EdgeId::from_index(i.index(mesh.num_edges()));
                    let boundary = mesh.edge_on_boundary(e);
                    // The reference refuses such a flip: the property below
                    // checks that; here only flips that happen are counted.
                    if !boundary && flip_duplicates_an_edge(&mesh, e) {
                        continue;
                    }
                    let r = solution::flip_edge(&mut mesh, e);
                    prop_assert_eq!(r.is_none(), boundary, "step {}: refuses exactly the boundary", step);
                    prop_assert_eq!(counts(&mesh), before);
                }
                Op::Split(i) => {
                    let e = EdgeId::from_index(i.index(mesh.num_edges()));
                    let k = if mesh.edge_on_boundary(e) { 1 } else { 2 };
                    let (a, b) = mesh.edge_vertices(e);
                    let mid = (mesh[a].pos + mesh[b].pos) / 2.0;
                    let m = solution::split_edge(&mut mesh, e).expect("triangles only");
                    prop_assert_eq!(mesh[m].pos, mid);
                    prop_assert_eq!(
                        counts(&mesh),
                        [before[0] + 1, before[1] + 1 + k, before[2] + k, before[3] + 2 + 2 * k]
                    );
                }
            }
            if let Err(bad) = mesh.validate() {
                return Err(TestCaseError::fail(format!("step {step} ({op:?}): {bad}")));
            }
            prop_assert_eq!(euler(&mesh), chi, "step {}", step);
        }
    }

    /// One round of subdivision: valid, V + E vertices, 2E + 3F edges, 4F
    /// faces, the same Euler characteristic, and the same points whatever
    /// order the elements come in.
    #[test]
    fn subdivision_counts_and_order_independence((original, shuffled) in shuffled(),
                                                 loop_weights in any::<bool>()) {
        let weights = if loop_weights { Weights::Loop } else { Weights::Warren };
        let (v, e, f) = (shuffled.num_vertices(), shuffled.num_edges(), shuffled.num_real_faces());
        let mut a = original;
        let mut b = shuffled;
        solution::loop_subdivide_with(&mut a, weights);
        solution::loop_subdivide_with(&mut b, weights);
        if let Err(bad) = b.validate() {
            return Err(TestCaseError::fail(bad.to_string()));
        }
        prop_assert_eq!(
            (b.num_vertices(), b.num_edges(), b.num_real_faces()),
            (v + e, 2 * e + 3 * f, 4 * f)
        );
        prop_assert_eq!(euler(&b), v as i64 - e as i64 + f as i64);
        prop_assert!(same_points(&a.positions(), &b.positions(), 1e-9));
    }
}

proptest! {
    #![proptest_config(config(100))]

    /// A flip that would join two vertices already joined (every edge of a
    /// tetrahedron) returns None and changes nothing.
    #[test]
    fn flips_that_would_duplicate_an_edge_are_refused((_, mesh) in shuffled(), at in any::<Index>()) {
        let mut mesh = mesh;
        let candidates: Vec<EdgeId> = mesh
            .edge_ids()
            .filter(|&e| !mesh.edge_on_boundary(e) && flip_duplicates_an_edge(&mesh, e))
            .collect();
        if let Some(&e) = candidates.get(at.index(candidates.len().max(1))) {
            let before = format!("{:?}", mesh);
            prop_assert_eq!(solution::flip_edge(&mut mesh, e), None);
            prop_assert_eq!(format!("{:?}", mesh), before);
        }
    }
}
