//! The reference keeps meshes valid and subdivides by the numbers.

use halfedge::{shapes, DVec3, EdgeId, Mesh, VertexId};
use reference::solution::{self, Weights};

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);
impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n as u64) as usize
    }
}

fn primitives() -> Vec<(&'static str, Mesh)> {
    let mut v: Vec<(&'static str, Mesh)> = shapes::LAB_OBJECTS
        .iter()
        .map(|&n| (n, shapes::lab_object(n).unwrap()))
        .collect();
    v.push(("icosphere", shapes::icosphere(1)));
    v.push(("grid", shapes::grid(4, 3)));
    v.push(("open cylinder", shapes::cylinder(6, 2, 1.0, 1.0, false)));
    v
}

#[test]
fn random_flips_and_splits_keep_every_mesh_valid() {
    for (name, mut mesh) in primitives() {
        let mut rng = Rng(0x9e3779b97f4a7c15 ^ name.len() as u64);
        for step in 0..300 {
            let e = EdgeId::from_index(rng.below(mesh.num_edges()));
            let before = (
                mesh.num_vertices(),
                mesh.num_edges(),
                mesh.num_faces(),
                mesh.num_halfedges(),
            );
            let boundary = mesh.edge_on_boundary(e);
            if rng.below(3) == 0 {
                let (a, b) = mesh.edge_vertices(e);
                let m = solution::split_edge(&mut mesh, e).expect("triangles only");
                assert_eq!(mesh[m].pos, (mesh[a].pos + mesh[b].pos) / 2.0);
                let to = mesh.halfedge_dst(mesh[m].halfedge);
                assert!(
                    to == a || to == b,
                    "{name} step {step}: split vertex points along the edge"
                );
                let k = if boundary { 1 } else { 2 };
                assert_eq!(
                    (
                        mesh.num_vertices(),
                        mesh.num_edges(),
                        mesh.num_faces(),
                        mesh.num_halfedges()
                    ),
                    (
                        before.0 + 1,
                        before.1 + 1 + k,
                        before.2 + k,
                        before.3 + 2 + 2 * k
                    )
                );
            } else {
                // A flip where the facing vertices are joined already makes
                // a double edge (legal for flip_edge, not a surface): skip.
                if !boundary {
                    let h = mesh[e].halfedge;
                    let c = mesh[mesh[mesh[h].next].next].vertex;
                    let t = mesh[h].twin;
                    let d = mesh[mesh[mesh[t].next].next].vertex;
                    if mesh.find_edge(c, d).is_some() {
                        continue;
                    }
                }
                let r = solution::flip_edge(&mut mesh, e);
                assert_eq!(
                    r.is_none(),
                    boundary,
                    "{name} step {step}: refuses exactly the boundary"
                );
                let after = (
                    mesh.num_vertices(),
                    mesh.num_edges(),
                    mesh.num_faces(),
                    mesh.num_halfedges(),
                );
                assert_eq!(after, before, "a flip adds nothing");
            }
            if let Err(bad) = mesh.validate() {
                panic!("{name}, step {step}: {bad}");
            }
        }
    }
}

#[test]
fn flip_joins_the_facing_vertices_counter_clockwise() {
    let mut mesh = shapes::grid(1, 1);
    // The diagonal 0-3 faces vertices 1 and 2.
    let e = mesh.edge_between(0, 3).unwrap();
    let h = mesh[e].halfedge;
    let (a, b) = (mesh[h].vertex, mesh.halfedge_dst(h));
    let c = mesh[mesh[mesh[h].next].next].vertex;
    assert_eq!(solution::flip_edge(&mut mesh, e), Some(e));
    let (x, y) = mesh.edge_vertices(e);
    let mut ends = [x.index(), y.index()];
    ends.sort();
    assert_eq!(ends, [1, 2]);
    // Counter-clockwise: the halfedge that ran a -> b now runs d -> c.
    assert_eq!(mesh.halfedge_dst(h), c, "h ends where it faced");
    assert!(mesh[h].vertex != a && mesh[h].vertex != b);
    mesh.validate().unwrap();
}

#[test]
fn flipping_twice_more_returns_the_edge() {
    // Four counter-clockwise quarter turns bring a diagonal back.
    let mut mesh = shapes::lab_object("torus").unwrap();
    let e = EdgeId(10);
    let ends = |m: &Mesh| {
        let (a, b) = m.edge_vertices(e);
        [a.index().min(b.index()), a.index().max(b.index())]
    };
    let start = ends(&mesh);
    solution::flip_edge(&mut mesh, e);
    assert_ne!(ends(&mesh), start);
    solution::flip_edge(&mut mesh, e);
    assert_eq!(ends(&mesh), start);
}

/// V - E + F over real faces.
fn euler(m: &Mesh) -> i64 {
    m.num_vertices() as i64 - m.num_edges() as i64 + m.num_real_faces() as i64
}

#[test]
fn subdivision_counts_follow_the_formulas() {
    for (name, mesh) in primitives() {
        let (v, e, f, chi) = (
            mesh.num_vertices(),
            mesh.num_edges(),
            mesh.num_real_faces(),
            euler(&mesh),
        );
        let mut once = mesh.clone();
        solution::loop_subdivide(&mut once);
        once.validate()
            .unwrap_or_else(|bad| panic!("{name}: {bad}"));
        let boundary = mesh
            .edge_ids()
            .filter(|&x| mesh.edge_on_boundary(x))
            .count();
        assert_eq!(once.num_vertices(), v + e, "{name}: V' = V + E");
        assert_eq!(once.num_edges(), 2 * e + 3 * f, "{name}: E' = 2E + 3F");
        assert_eq!(once.num_real_faces(), 4 * f, "{name}: F' = 4F");
        assert_eq!(euler(&once), chi, "{name}: same topology");
        let after = once
            .edge_ids()
            .filter(|&x| once.edge_on_boundary(x))
            .count();
        assert_eq!(
            after,
            2 * boundary,
            "{name}: each boundary edge becomes two"
        );
        assert!(once.is_triangle_mesh());
    }
}

#[test]
fn lab_counts_after_one_round() {
    for (name, v, e) in [
        ("cube", 26, 72),
        ("torus", 288, 864),
        ("cylinder", 66, 192),
        ("cone", 22, 60),
    ] {
        let mut m = shapes::lab_object(name).unwrap();
        solution::loop_subdivide(&mut m);
        assert_eq!((m.num_vertices(), m.num_edges()), (v, e), "{name}");
    }
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-12
}

#[test]
fn lab_cube_positions_computed_by_hand() {
    let mut m = shapes::lab_object("cube").unwrap();
    solution::loop_subdivide(&mut m);
    // v0 = (-1/2, -1/2, -1/2) has 5 neighbours (1, 2, 4, 6, 7), so u = 3/40:
    // 25/40 * v0 + 3/40 * (-1/2, -1/2, 1/2) = (-0.35, -0.35, -0.275).
    assert!(
        close(m[VertexId(0)].pos, DVec3::new(-0.35, -0.35, -0.275)),
        "{}",
        m[VertexId(0)].pos
    );
    // Edge 0-1 faces vertices 2 and 4, which sum to zero:
    // 3/8 * (v0 + v1) = (0, -0.375, -0.375). Some new vertex sits there.
    let want = DVec3::new(0.0, -0.375, -0.375);
    assert!(m.vertex_ids().any(|v| close(m[v].pos, want)));
}

#[test]
fn boundary_rules() {
    // Rim vertices move along the rim: 3/4 v + 1/8 of the rim neighbours.
    let mut g = shapes::grid(2, 2);
    let corner = VertexId(0); // (-0.5, -0.5), rim neighbours 1 and 3
    let (p, n1, n3) = (g[corner].pos, g[VertexId(1)].pos, g[VertexId(3)].pos);
    let mid01 = (g[VertexId(0)].pos + g[VertexId(1)].pos) / 2.0;
    solution::loop_subdivide(&mut g);
    assert!(close(g[corner].pos, 0.75 * p + 0.125 * (n1 + n3)));
    assert!(
        g.vertex_ids().any(|v| close(g[v].pos, mid01)),
        "rim edges split at their midpoint"
    );
}

#[test]
fn weights() {
    assert_eq!(Weights::Warren.neighbour_weight(3), 3.0 / 16.0);
    assert_eq!(Weights::Warren.neighbour_weight(4), 3.0 / 32.0);
    // Loop's beta agrees with the lab's at n = 3 and n = 6 and nowhere else
    // near: (5/8 - (3/8 - 1/8)^2) / 3 = 3/16; (5/8 - (1/2)^2) / 6 = 1/16.
    assert!((Weights::Loop.neighbour_weight(3) - 3.0 / 16.0).abs() < 1e-15);
    assert!((Weights::Loop.neighbour_weight(6) - 1.0 / 16.0).abs() < 1e-15);
    assert!((Weights::Loop.neighbour_weight(5) - Weights::Warren.neighbour_weight(5)).abs() > 1e-3);
    assert_eq!(Weights::from_name("loop"), Some(Weights::Loop));
    assert_eq!(
        Weights::from_name(Weights::Warren.name()),
        Some(Weights::Warren)
    );
    assert_eq!(Weights::from_name("catmull"), None);
}

#[test]
#[should_panic(expected = "loop_subdivide needs a triangle mesh, but f0 has 4 sides")]
fn subdividing_quads_says_so() {
    let p = [DVec3::ZERO, DVec3::X, DVec3::ONE, DVec3::Y];
    let mut quad = Mesh::from_faces(&p, &[vec![0, 1, 2, 3]]).unwrap();
    solution::loop_subdivide(&mut quad);
}

#[test]
fn flip_refuses_non_triangles_and_split_too() {
    let p = [
        DVec3::ZERO,
        DVec3::X,
        DVec3::ONE,
        DVec3::Y,
        DVec3::new(2.0, 0.5, 0.0),
    ];
    let mut m = Mesh::from_faces(&p, &[vec![0, 1, 2, 3], vec![1, 4, 2]]).unwrap();
    let e = m.edge_between(1, 2).unwrap();
    assert_eq!(solution::flip_edge(&mut m, e), None);
    assert_eq!(solution::split_edge(&mut m, e), None);
    assert_eq!(m.num_vertices(), 5);
    m.validate().unwrap();
}

/// `loop_subdivide` flips the list `split_edges` returns instead of
/// looking at every edge afterwards: on every primitive (holes too), and on
/// a mesh already subdivided and flipped at random, the list must be the
/// old-new edges, in id order, that `flip_old_new` would flip.
#[test]
fn the_split_pass_lists_exactly_the_edges_to_flip() {
    let mut meshes = primitives();
    let mut scrambled = shapes::torus(6, 4, 2.0, 0.5);
    solution::loop_subdivide(&mut scrambled);
    let mut rng = Rng(0x5eed);
    for _ in 0..200 {
        let e = EdgeId::from_index(rng.below(scrambled.num_edges()));
        solution::flip_edge(&mut scrambled, e);
    }
    meshes.push(("torus, subdivided and flipped", scrambled));
    for (name, mut mesh) in meshes {
        solution::vertex_points(&mut mesh, Weights::Warren);
        assert!(solution::edge_points(&mut mesh), "{name}");
        solution::reserve_round(&mut mesh);
        let old: Vec<EdgeId> = mesh.edge_ids().collect();
        let listed = solution::split_edges(&mut mesh, &old, solution::split_edge);
        let wanted: Vec<EdgeId> = mesh
            .edge_ids()
            .filter(|&e| {
                let (a, b) = mesh.edge_vertices(e);
                mesh[e].is_new && mesh[a].is_new != mesh[b].is_new
            })
            .collect();
        assert!(!wanted.is_empty(), "{name}");
        assert_eq!(listed, wanted, "{name}");
    }
}
