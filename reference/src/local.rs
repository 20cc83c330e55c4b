//! The local shapes every counted rule of `flip_edge` and `split_edge`
//! must hold on, generated rather than picked from the lab's objects.
//!
//! A rule checked on one shape only can be broken on the others and still
//! pass: a flip that tests only one of its two faces for being a triangle
//! passed every case while the only non-triangle cases had `c` and `d`
//! joined anyway, and a flip that refuses every edge with an end of degree 3
//! passed because on a closed mesh such a flip must be refused for another
//! reason. So the cases here are made around one edge `a`-`b` (the handout's
//! names: `c` faces it on the side of `a -> b`, `d` on the side of `b -> a`),
//! varying what each rule depends on:
//!
//! - the ends' degrees, 3 to 8, with both ends on the rim of an open fan
//!   (every flip legal, a degree-3 end included) and inside a closed mesh
//!   (a degree-3 end makes `c` and `d` neighbours: the flip must refuse);
//! - a face that is not a triangle, on either side of the edge, where no
//!   other rule would refuse (`c` and `d` not joined), and beside a hole;
//! - a hole on either side, shaped like a triangle, so that only the
//!   boundary rule refuses a flip;
//! - `c` and `d` joined by an edge far from `a` and `b`, both ends of
//!   degree 4 or more (so no degree test stands in for the real one);
//! - the smallest meshes: one triangle and two.
//!
//! Which side `mesh[e].halfedge` lies on is the grader's to vary: each case
//! also runs on labellings with it on either side (`judge::relabel`).
//! [`facts`] reads what a case exercises back from any mesh and edge, so
//! the contract test checks coverage by content, not by case names.

use halfedge::{DVec3, Mesh, VertexId};

/// What is on one side of the case's edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// A real face with this many corners.
    Face(usize),
    /// A hole with this many corners.
    Hole(usize),
}

impl Side {
    pub fn is_hole(self) -> bool {
        matches!(self, Side::Hole(_))
    }

    /// A real face that is not a triangle.
    pub fn is_polygon(self) -> bool {
        matches!(self, Side::Face(n) if n != 3)
    }
}

/// What a case around edge `a`-`b` exercises, read off the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Facts {
    /// The degrees of `a` and `b`.
    pub degrees: [usize; 2],
    /// Whether `a` and `b` are on a hole.
    pub on_rim: [bool; 2],
    /// No hole anywhere in the mesh.
    pub closed: bool,
    /// The side of `a -> b` and the side of `b -> a`.
    pub sides: [Side; 2],
    /// The corners two steps on from `a -> b` and from `b -> a` (`c` and
    /// `d` on triangles) are joined by an edge, or are the same vertex.
    pub joined: bool,
    /// Real faces in the mesh.
    pub faces: usize,
}

impl Facts {
    /// The contract's refusals of a flip, as (boundary, not a triangle,
    /// would duplicate an edge).
    pub fn flip_refusals(&self) -> [bool; 3] {
        [
            self.sides.iter().any(|s| s.is_hole()),
            self.sides.iter().any(|s| s.is_polygon()),
            self.joined,
        ]
    }

    /// Whether the contract lets `flip_edge` flip this edge.
    pub fn flip_legal(&self) -> bool {
        self.flip_refusals() == [false; 3]
    }

    /// Whether `split_edge` must split it (a hole beside it is fine: that
    /// is boundary support, the bonus).
    pub fn split_legal(&self) -> bool {
        !self.sides.iter().any(|s| s.is_polygon())
    }
}

/// The facts of edge `[a, b]` (input vertex indices) of `mesh`, or `None`
/// when the two are not joined.
pub fn facts(mesh: &Mesh, [a, b]: [usize; 2]) -> Option<Facts> {
    let (a, b) = (VertexId::from_index(a), VertexId::from_index(b));
    let e = mesh.find_edge(a, b)?;
    let h = mesh[e].halfedge;
    let (ab, ba) = if mesh[h].vertex == a {
        (h, mesh[h].twin)
    } else {
        (mesh[h].twin, h)
    };
    let side = |g: halfedge::HalfedgeId| {
        let f = mesh[g].face;
        let n = mesh.face_degree(f);
        if mesh[f].is_boundary {
            Side::Hole(n)
        } else {
            Side::Face(n)
        }
    };
    let two_on = |g: halfedge::HalfedgeId| mesh[mesh[mesh[g].next].next].vertex;
    let (c, d) = (two_on(ab), two_on(ba));
    Some(Facts {
        degrees: [mesh.vertex_degree(a), mesh.vertex_degree(b)],
        on_rim: [mesh.vertex_on_boundary(a), mesh.vertex_on_boundary(b)],
        closed: mesh.edge_ids().all(|e| !mesh.edge_on_boundary(e)),
        sides: [side(ab), side(ba)],
        joined: c == d || mesh.find_edge(c, d).is_some(),
        faces: mesh.face_ids().filter(|&f| !mesh[f].is_boundary).count(),
    })
}

/// How the mesh around the edge is closed off.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Closure {
    /// No more faces: a disk.
    Open,
    /// A cone from one more vertex over the disk's rim: a closed mesh.
    Apex,
    /// The rim's polygon fanned from `c`: a closed mesh in which `c` and
    /// `d` are joined across it.
    FanFromC,
}

/// A fan of triangles around edge `a`-`b`, as vertex indices 0 = a, 1 = b,
/// 2 = c, 3 = d, then `a`'s other neighbours, then `b`'s.
struct Fan {
    degrees: [usize; 2],
    /// Whether each end's fan is left open (the end on the rim).
    open: [bool; 2],
    closure: Closure,
}

impl Fan {
    /// Its faces, counter-clockwise: (a, b, c), (b, a, d), then each end's
    /// fan from its side of `c` round to `d`.
    fn faces(&self) -> (usize, Vec<Vec<usize>>) {
        let [ka, kb] = self.degrees;
        assert!(ka >= 3 && kb >= 3, "a fan's ends have degree 3 or more");
        let ps: Vec<usize> = (4..4 + ka - 3).collect();
        let qs: Vec<usize> = (4 + ka - 3..4 + ka - 3 + kb - 3).collect();
        let vertices = 4 + ps.len() + qs.len();
        let mut faces = vec![vec![0, 1, 2], vec![1, 0, 3]];
        // Around a, counter-clockwise: b, c, p..., d.
        let ring_a: Vec<usize> = std::iter::once(2).chain(ps).chain([3]).collect();
        // Around b, counter-clockwise: a, d, q..., c.
        let ring_b: Vec<usize> = std::iter::once(3).chain(qs).chain([2]).collect();
        // An open end lacks its fan's first triangle (the one at c for a,
        // at d for b), so the triangles beside each of the edge's faces at
        // the far end are there to be merged into a quad.
        for (end, ring) in [(0, &ring_a), (1, &ring_b)] {
            let first = usize::from(self.open[end]);
            for i in first..ring.len() - 1 {
                faces.push(vec![end, ring[i], ring[i + 1]]);
            }
        }
        (vertices, faces)
    }
}

/// The directed edges of `faces` that have no reverse: the rim, in a
/// successor map (each rim vertex once: the shapes here are disks).
fn rim(faces: &[Vec<usize>]) -> Vec<(usize, usize)> {
    let directed: std::collections::HashSet<(usize, usize)> = faces
        .iter()
        .flat_map(|f| (0..f.len()).map(move |i| (f[i], f[(i + 1) % f.len()])))
        .collect();
    let mut out: Vec<(usize, usize)> = directed
        .iter()
        .copied()
        .filter(|&(u, v)| !directed.contains(&(v, u)))
        .collect();
    out.sort_unstable();
    out
}

/// The rim as a loop of vertices, in the order its real faces run along it.
fn rim_loop(faces: &[Vec<usize>]) -> Vec<usize> {
    let edges = rim(faces);
    let next: std::collections::HashMap<usize, usize> = edges.iter().copied().collect();
    let Some(&(start, _)) = edges.first() else {
        return Vec::new();
    };
    let mut out = vec![start];
    let mut v = next[&start];
    while v != start {
        out.push(v);
        v = next[&v];
    }
    assert_eq!(
        out.len(),
        edges.len(),
        "a shape's rim is one loop: {faces:?}"
    );
    out
}

/// Positions that draw a disk without folds: the rim on a circle, in its
/// order, and every inner vertex at the mean of its neighbours (Tutte's
/// embedding, a few hundred sweeps), lifted into a low dome.
fn layout(vertices: usize, faces: &[Vec<usize>]) -> Vec<DVec3> {
    let ring = rim_loop(faces);
    let mut pos = vec![DVec3::ZERO; vertices];
    let mut fixed = vec![false; vertices];
    for (i, &v) in ring.iter().enumerate() {
        let t = std::f64::consts::TAU * i as f64 / ring.len() as f64;
        pos[v] = DVec3::new(t.cos(), t.sin(), 0.0);
        fixed[v] = true;
    }
    let mut neighbours = vec![Vec::new(); vertices];
    for f in faces {
        for i in 0..f.len() {
            let (u, v) = (f[i], f[(i + 1) % f.len()]);
            if !neighbours[u].contains(&v) {
                neighbours[u].push(v);
                neighbours[v].push(u);
            }
        }
    }
    for _ in 0..500 {
        for v in 0..vertices {
            if !fixed[v] {
                let sum: DVec3 = neighbours[v].iter().map(|&u| pos[u]).sum();
                pos[v] = sum / neighbours[v].len() as f64;
            }
        }
    }
    for v in 0..vertices {
        if !fixed[v] {
            pos[v].z = 0.4;
        }
        // Rounded, so that the inputs print short and the same everywhere.
        pos[v] = (pos[v] * 1e6).round() / 1e6;
    }
    pos
}

/// The fan made a mesh: `edit` applied to its faces, laid out, closed
/// off, and then `open` applied (a hole cut into the closed mesh).
fn build(
    fan: &Fan,
    edit: impl FnOnce(&mut Vec<Vec<usize>>),
    open: impl FnOnce(&mut Vec<Vec<usize>>),
) -> Mesh {
    let (vertices, mut faces) = fan.faces();
    edit(&mut faces);
    let mut pos = layout(vertices, &faces);
    let ring = rim_loop(&faces);
    match fan.closure {
        Closure::Open => {}
        Closure::Apex => {
            let z = pos.len();
            pos.push(DVec3::new(0.0, 0.0, -0.8));
            // Each rim edge u -> v of a real face gets its reverse.
            for i in 0..ring.len() {
                faces.push(vec![z, ring[(i + 1) % ring.len()], ring[i]]);
            }
        }
        Closure::FanFromC => {
            let at = ring.iter().position(|&v| v == 2).expect("c is on the rim");
            let from_c: Vec<usize> = (0..ring.len())
                .map(|i| ring[(at + i) % ring.len()])
                .collect();
            for i in 1..from_c.len() - 1 {
                faces.push(vec![2, from_c[i + 1], from_c[i]]);
            }
        }
    }
    open(&mut faces);
    Mesh::from_faces(&pos, &faces).expect("a local shape is a valid mesh")
}

fn mesh_of(positions: &[[f64; 3]], faces: &[Vec<usize>]) -> Mesh {
    let pos: Vec<DVec3> = positions.iter().map(|p| DVec3::from_array(*p)).collect();
    Mesh::from_faces(&pos, faces).expect("a local shape is a valid mesh")
}

/// One shape: a slug for case names, the object's description, the mesh
/// and its edge `[a, b]`.
pub struct Shape {
    pub slug: String,
    pub object: String,
    pub mesh: Mesh,
}

/// The ends' degrees the fans are made with: every degree from 3 to 8 at
/// some end, open and closed.
const OPEN_DEGREES: [[usize; 2]; 3] = [[3, 8], [4, 7], [5, 6]];
const CLOSED_DEGREES: [[usize; 2]; 3] = [[3, 6], [4, 8], [5, 7]];

/// Every local shape, each with its edge joining input vertices 0 (`a`)
/// and 1 (`b`).
pub fn shapes() -> Vec<Shape> {
    let mut out = Vec::new();
    let mut push = |slug: String, object: String, mesh: Mesh| {
        out.push(Shape { slug, object, mesh });
    };
    for degrees in OPEN_DEGREES {
        let fan = Fan {
            degrees,
            open: [true, true],
            closure: Closure::Open,
        };
        push(
            format!("open-{}-{}", degrees[0], degrees[1]),
            format!(
                "open fan: a (degree {}) and b (degree {}) on the rim",
                degrees[0], degrees[1]
            ),
            build(&fan, |_| {}, |_| {}),
        );
    }
    for degrees in CLOSED_DEGREES {
        let fan = Fan {
            degrees,
            open: [false, false],
            closure: Closure::Apex,
        };
        push(
            format!("closed-{}-{}", degrees[0], degrees[1]),
            format!(
                "closed fan: a of degree {}, b of degree {}",
                degrees[0], degrees[1]
            ),
            build(&fan, |_| {}, |_| {}),
        );
    }
    // c and d joined across the bottom, both ends of degree 5.
    let fan = Fan {
        degrees: [5, 5],
        open: [false, false],
        closure: Closure::FanFromC,
    };
    push(
        "joined-far".into(),
        "closed fan: c and d joined by an edge across the far side, a and b of degree 5".into(),
        build(&fan, |_| {}, |_| {}),
    );
    // A quad on one side: the triangle (a, b, c) merged with b's last one,
    // (b, q, c), so that the corner two steps on from a -> b is q, which is
    // not joined to d; or the same on the other side.
    let wide = Fan {
        degrees: [6, 6],
        open: [true, true],
        closure: Closure::Open,
    };
    push(
        "quad-left".into(),
        "open fan: the face of a -> b is a quad".into(),
        build(&wide, |faces| merge_quad(faces, 0), |_| {}),
    );
    push(
        "quad-right".into(),
        "open fan: the face of b -> a is a quad".into(),
        build(&wide, |faces| merge_quad(faces, 1), |_| {}),
    );
    // A quad beside a hole: a closed fan whose (a, b, c) is a quad, with
    // (b, a, d) cut out.
    let closed_wide = Fan {
        degrees: [6, 6],
        open: [false, false],
        closure: Closure::Apex,
    };
    push(
        "quad-hole".into(),
        "closed fan: the face of a -> b is a quad, a hole on the other side".into(),
        build(
            &closed_wide,
            |faces| merge_quad(faces, 0),
            |faces| faces.retain(|f| *f != [1, 0, 3]),
        ),
    );
    // A triangular hole on one side of a closed fan: only the boundary
    // rule refuses its flip (c and d are not joined).
    let closed = Fan {
        degrees: [5, 6],
        open: [false, false],
        closure: Closure::Apex,
    };
    push(
        "hole-left".into(),
        "closed fan without the triangle (a, b, c): a hole on the side of a -> b".into(),
        build(&closed, |_| {}, |faces| faces.retain(|f| *f != [0, 1, 2])),
    );
    push(
        "hole-right".into(),
        "closed fan without the triangle (b, a, d): a hole on the side of b -> a".into(),
        build(&closed, |_| {}, |faces| faces.retain(|f| *f != [1, 0, 3])),
    );
    let (a, b, c, d) = (
        [-0.5, 0.0, 0.0],
        [0.5, 0.0, 0.0],
        [0.0, 0.8, 0.0],
        [0.1, -0.7, 0.0],
    );
    push(
        "one-triangle".into(),
        "one triangle".into(),
        mesh_of(&[a, b, c], &[vec![0, 1, 2]]),
    );
    push(
        "two-triangles".into(),
        "two triangles".into(),
        mesh_of(&[a, b, c, d], &[vec![0, 1, 2], vec![1, 0, 3]]),
    );
    out
}

/// Merges the triangle on `side` (0: (a, b, c), 1: (b, a, d)) with the
/// next triangle of its far end's fan, removing the edge between them.
fn merge_quad(faces: &mut Vec<Vec<usize>>, side: usize) {
    // (a, b, c) shares b -> c with b's last fan triangle (b, q, c); (b, a,
    // d) shares a -> d with a's last fan triangle (a, p, d).
    let (tri, end, corner) = if side == 0 {
        (vec![0, 1, 2], 1, 2)
    } else {
        (vec![1, 0, 3], 0, 3)
    };
    let at = faces
        .iter()
        .position(|f| f[0] == end && f[2] == corner)
        .expect("the fan triangle beside the edge's face");
    let q = faces[at][1];
    faces.remove(at);
    let i = faces
        .iter()
        .position(|f| *f == tri)
        .expect("the edge's face");
    faces[i] = vec![tri[0], tri[1], q, tri[2]];
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(slug: &str) -> Shape {
        shapes().into_iter().find(|s| s.slug == slug).unwrap()
    }

    #[test]
    fn the_fans_have_the_degrees_asked_for() {
        for degrees in OPEN_DEGREES {
            let f = facts(
                &shape(&format!("open-{}-{}", degrees[0], degrees[1])).mesh,
                [0, 1],
            );
            let f = f.unwrap();
            assert_eq!(f.degrees, degrees);
            assert_eq!(f.on_rim, [true, true]);
            assert!(f.flip_legal(), "{f:?}");
        }
        for degrees in CLOSED_DEGREES {
            let f = facts(
                &shape(&format!("closed-{}-{}", degrees[0], degrees[1])).mesh,
                [0, 1],
            );
            let f = f.unwrap();
            assert_eq!(f.degrees, degrees);
            assert!(f.closed);
            // A degree-3 end inside a closed mesh has c and d as neighbours.
            assert_eq!(f.joined, degrees.contains(&3), "{f:?}");
        }
    }

    #[test]
    fn each_odd_shape_breaks_exactly_the_rule_it_is_for() {
        let refusals = |slug| facts(&shape(slug).mesh, [0, 1]).unwrap().flip_refusals();
        assert_eq!(refusals("quad-left"), [false, true, false]);
        assert_eq!(refusals("quad-right"), [false, true, false]);
        assert_eq!(refusals("hole-left"), [true, false, false]);
        assert_eq!(refusals("hole-right"), [true, false, false]);
        assert_eq!(refusals("joined-far"), [false, false, true]);
        let far = facts(&shape("joined-far").mesh, [0, 1]).unwrap();
        assert!(far.degrees.iter().all(|&d| d >= 4), "{far:?}");
        let quad = facts(&shape("quad-left").mesh, [0, 1]).unwrap();
        assert_eq!(quad.sides, [Side::Face(4), Side::Face(3)]);
        let quad = facts(&shape("quad-right").mesh, [0, 1]).unwrap();
        assert_eq!(quad.sides, [Side::Face(3), Side::Face(4)]);
        let hole = facts(&shape("hole-left").mesh, [0, 1]).unwrap();
        assert_eq!(hole.sides, [Side::Hole(3), Side::Face(3)]);
        let both = facts(&shape("quad-hole").mesh, [0, 1]).unwrap();
        assert_eq!(both.sides[0], Side::Face(4));
        assert!(both.sides[1].is_hole() && !both.split_legal());
        let two = facts(&shape("two-triangles").mesh, [0, 1]).unwrap();
        assert_eq!(
            (two.faces, two.degrees, two.on_rim),
            (2, [3, 3], [true, true])
        );
        assert!(two.flip_legal());
        let one = facts(&shape("one-triangle").mesh, [0, 1]).unwrap();
        assert_eq!(one.faces, 1);
        // Its hole is the same triangle backwards: c and d are one vertex.
        assert_eq!(one.flip_refusals(), [true, false, true]);
    }

    #[test]
    fn the_model_solution_agrees_with_the_facts() {
        for s in shapes() {
            let f = facts(&s.mesh, [0, 1]).unwrap();
            let mut m = s.mesh.clone();
            let e = m.edge_between(0, 1).unwrap();
            let flipped = crate::solution::flip_edge(&mut m, e).is_some();
            assert_eq!(flipped, f.flip_legal(), "{}: {f:?}", s.slug);
            m.validate().unwrap();
            let mut m = s.mesh.clone();
            let split = crate::solution::split_edge(&mut m, e).is_some();
            assert_eq!(split, f.split_legal(), "{}: {f:?}", s.slug);
            m.validate().unwrap();
        }
    }
}
