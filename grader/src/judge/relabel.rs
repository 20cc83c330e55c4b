//! Relabelled copies of a case's input, so that order-dependent bugs show.
//!
//! `Mesh::from_faces` numbers elements in one particular order and points
//! every vertex, edge and face at its lowest-numbered halfedge. Code that
//! forgets to update a pointer can pass on that mesh by luck. Each case is
//! therefore also run on copies with every id permuted and every pointer
//! (`mesh[v].halfedge`, `mesh[e].halfedge`, `mesh[f].halfedge`) chosen
//! afresh among the valid ones: same surface, different labels. A correct
//! function passes on all of them.
//!
//! For a flip or split, two copies are chosen to be hard: both ends of the
//! edge point along the edge itself, and each face of the edge points at a
//! halfedge that the operation moves to another face; once with
//! `mesh[e].halfedge` on one side, once on the other (on a boundary edge,
//! that other side is the hole). The rest are random, from a seed.

use halfedge::{Edge, EdgeId, Face, FaceId, Halfedge, HalfedgeId, Mesh, Vertex, VertexId};

/// One labelling of a case's input.
#[derive(Clone, Debug)]
pub struct Labelling {
    pub mesh: Mesh,
    /// The case's edge in this labelling.
    pub edge: Option<EdgeId>,
    /// `vertices[i]`: input vertex `i`'s id in this labelling (a sequence
    /// names its vertices by input index).
    pub vertices: Vec<VertexId>,
    /// How the pointers were set, in the contract's names, for a message.
    pub what: String,
    pub kind: Kind,
    /// Every element's id in this labelling.
    pub permutation: Permutation,
}

/// Where each input element went in a labelling: `vertices[i]` is the id
/// input vertex `i` has there; the same for edges, faces and halfedges.
/// Elements made later (by the student's code) are not permuted.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Permutation {
    pub vertices: Vec<u32>,
    pub edges: Vec<u32>,
    pub faces: Vec<u32>,
    pub halfedges: Vec<u32>,
}

impl Permutation {
    fn identity(mesh: &Mesh) -> Permutation {
        let ids = |n: usize| (0..n as u32).collect();
        Permutation {
            vertices: ids(mesh.num_vertices()),
            edges: ids(mesh.num_edges()),
            faces: ids(mesh.num_faces()),
            halfedges: ids(mesh.num_halfedges()),
        }
    }

    fn of(p: [&[usize]; 4]) -> Permutation {
        let ids = |p: &[usize]| p.iter().map(|&x| x as u32).collect();
        Permutation {
            vertices: ids(p[0]),
            edges: ids(p[1]),
            faces: ids(p[2]),
            halfedges: ids(p[3]),
        }
    }

    /// The case's (input's) id of an element named in the labelling; an
    /// id past the input's elements is the same in both.
    pub fn to_case(&self, e: halfedge::Element) -> halfedge::Element {
        use halfedge::Element as E;
        let back = |p: &[u32], id: u32| p.iter().position(|&x| x == id).map_or(id, |i| i as u32);
        match e {
            E::Vertex(v) => E::Vertex(VertexId(back(&self.vertices, v.0))),
            E::Edge(x) => E::Edge(EdgeId(back(&self.edges, x.0))),
            E::Face(f) => E::Face(FaceId(back(&self.faces, f.0))),
            E::Halfedge(h) => E::Halfedge(HalfedgeId(back(&self.halfedges, h.0))),
        }
    }

    /// The labelling's id of an input element (the inverse of [`Permutation::to_case`]).
    pub fn to_labelling(&self, e: halfedge::Element) -> halfedge::Element {
        use halfedge::Element as E;
        let fwd = |p: &[u32], id: u32| p.get(id as usize).copied().unwrap_or(id);
        match e {
            E::Vertex(v) => E::Vertex(VertexId(fwd(&self.vertices, v.0))),
            E::Edge(x) => E::Edge(EdgeId(fwd(&self.edges, x.0))),
            E::Face(f) => E::Face(FaceId(fwd(&self.faces, f.0))),
            E::Halfedge(h) => E::Halfedge(HalfedgeId(fwd(&self.halfedges, h.0))),
        }
    }
}

/// What a labelling is meant to catch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// The mesh as `from_faces` built it.
    AsBuilt,
    /// The edge's ends and faces point where an operation moves things.
    Pointers,
    /// As `Pointers`, with `mesh[e].halfedge` in the hole.
    HoleSide,
    /// Ids and pointers at random.
    Random,
}

impl Kind {
    /// A stable name for data.
    pub fn key(self) -> &'static str {
        match self {
            Kind::AsBuilt => "as-built",
            Kind::Pointers => "pointers",
            Kind::HoleSide => "hole-side",
            Kind::Random => "random",
        }
    }
}

/// A small, seedable generator (SplitMix64): the same seed gives the same
/// labellings on every machine.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// A number in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    /// A random permutation of `0..n`: `p[old] = new`.
    pub fn permutation(&mut self, n: usize) -> Vec<usize> {
        let mut p: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            p.swap(i, self.below(i + 1));
        }
        p
    }
}

/// The seed a case uses unless `--seed` says otherwise: fixed per case
/// name, so a grade never changes from one run to the next.
pub fn default_seed(case: &str) -> u64 {
    // FNV-1a: stable across Rust versions, unlike the std hasher.
    case.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Pointer choices, in the input's ids: which halfedge each vertex, edge
/// and face points at.
struct Pointers {
    vertex: Vec<HalfedgeId>,
    edge: Vec<HalfedgeId>,
    face: Vec<HalfedgeId>,
}

fn random_pointers(mesh: &Mesh, rng: &mut Rng) -> Pointers {
    let pick = |hs: Vec<HalfedgeId>, rng: &mut Rng| hs[rng.below(hs.len())];
    Pointers {
        vertex: mesh
            .vertex_ids()
            .map(|v| pick(mesh.vertex_halfedges(v), rng))
            .collect(),
        edge: mesh
            .edge_ids()
            .map(|e| {
                let h = mesh[e].halfedge;
                if rng.below(2) == 0 {
                    h
                } else {
                    mesh[h].twin
                }
            })
            .collect(),
        face: mesh
            .face_ids()
            .map(|f| pick(mesh.face_halfedges(f), rng))
            .collect(),
    }
}

/// The mesh with ids renumbered (`p*[old] = new`) and the pointers given.
fn relabel(
    mesh: &Mesh,
    ptr: &Pointers,
    pv: &[usize],
    pe: &[usize],
    pf: &[usize],
    ph: &[usize],
) -> Mesh {
    let (vs, es, fs, hs) = mesh.records();
    let h = |x: HalfedgeId| HalfedgeId::from_index(ph[x.index()]);
    let mut vertices = vs.to_vec();
    for (i, v) in vs.iter().enumerate() {
        vertices[pv[i]] = Vertex {
            halfedge: h(ptr.vertex[i]),
            ..*v
        };
    }
    let mut edges = es.to_vec();
    for (i, e) in es.iter().enumerate() {
        edges[pe[i]] = Edge {
            halfedge: h(ptr.edge[i]),
            ..*e
        };
    }
    let mut faces = fs.to_vec();
    for (i, f) in fs.iter().enumerate() {
        faces[pf[i]] = Face {
            halfedge: h(ptr.face[i]),
            ..*f
        };
    }
    let mut halfedges = hs.to_vec();
    for (i, r) in hs.iter().enumerate() {
        halfedges[ph[i]] = Halfedge {
            twin: h(r.twin),
            next: h(r.next),
            vertex: VertexId::from_index(pv[r.vertex.index()]),
            edge: EdgeId::from_index(pe[r.edge.index()]),
            face: FaceId::from_index(pf[r.face.index()]),
        };
    }
    Mesh::from_records(vertices, edges, faces, halfedges)
}

/// The labellings a case runs on, the mesh as built first. `input` must be
/// valid; `edge` is the case's edge, if any; `random` is how many random
/// labellings to add.
pub fn labellings(input: &Mesh, edge: Option<EdgeId>, seed: u64, random: usize) -> Vec<Labelling> {
    let mut rng = Rng::new(seed);
    let mut out = vec![Labelling {
        mesh: input.clone(),
        edge,
        vertices: input.vertex_ids().collect(),
        what: "the mesh as built from its faces".into(),
        kind: Kind::AsBuilt,
        permutation: Permutation::identity(input),
    }];
    let shuffled = |ptr: Pointers, rng: &mut Rng| {
        let pv = rng.permutation(input.num_vertices());
        let pe = rng.permutation(input.num_edges());
        let pf = rng.permutation(input.num_faces());
        let ph = rng.permutation(input.num_halfedges());
        let mesh = relabel(input, &ptr, &pv, &pe, &pf, &ph);
        let vertices = pv.iter().map(|&v| VertexId::from_index(v)).collect();
        (
            mesh,
            edge.map(|e| EdgeId::from_index(pe[e.index()])),
            vertices,
            Permutation::of([&pv, &pe, &pf, &ph]),
        )
    };
    if let Some(e) = edge {
        let h = input[e].halfedge;
        let t = input[h].twin;
        let hole_side = [h, t]
            .into_iter()
            .find(|&x| input[input[x].face].is_boundary);
        for side in [h, t] {
            let other = input[side].twin;
            let mut ptr = random_pointers(input, &mut rng);
            // The student's h is mesh[e].halfedge: `side`, running a -> b.
            ptr.edge[e.index()] = side;
            ptr.vertex[input[side].vertex.index()] = side;
            ptr.vertex[input[other].vertex.index()] = other;
            // Each face at the halfedge after (first copy) or before
            // (second copy) the edge's: one of them moves to a new face.
            for g in [side, other] {
                let after = input[g].next;
                let before = input
                    .face_halfedges(input[g].face)
                    .into_iter()
                    .find(|&x| input[x].next == g)
                    .unwrap_or(g);
                ptr.face[input[g].face.index()] = if side == h { after } else { before };
            }
            let in_hole = hole_side == Some(side);
            let what =
                format!(
                "mesh[e].halfedge = h (a -> b){}, mesh[a].halfedge = h and mesh[b].halfedge = t \
                 (b -> a), both along the edge; each face of the edge points at the halfedge {} \
                 h or t",
                if in_hole { ", which lies in the hole" } else { "" },
                if side == h { "after" } else { "before" }
            );
            let (mesh, edge, vertices, permutation) = shuffled(ptr, &mut rng);
            out.push(Labelling {
                mesh,
                edge,
                vertices,
                permutation,
                what,
                kind: if in_hole {
                    Kind::HoleSide
                } else {
                    Kind::Pointers
                },
            });
        }
    }
    for _ in 0..random {
        let ptr = random_pointers(input, &mut rng);
        let (mesh, edge, vertices, permutation) = shuffled(ptr, &mut rng);
        out.push(Labelling {
            mesh,
            edge,
            vertices,
            permutation,
            what: "every id renumbered and every vertex, edge and face pointing at another of its \
                   halfedges, at random"
                .into(),
            kind: Kind::Random,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn surface(mesh: &Mesh) -> Vec<Vec<[u64; 3]>> {
        // Faces as position lists, rotated to start at their smallest, sorted.
        let (positions, faces) = mesh.to_faces();
        let mut out: Vec<Vec<[u64; 3]>> = faces
            .iter()
            .map(|f| {
                let ps: Vec<[u64; 3]> = f
                    .iter()
                    .map(|&i| positions[i].to_array().map(f64::to_bits))
                    .collect();
                let k = (0..ps.len()).min_by_key(|&i| ps[i]).unwrap();
                ps[k..].iter().chain(&ps[..k]).copied().collect()
            })
            .collect();
        out.sort();
        out
    }

    #[test]
    fn every_labelling_is_the_same_valid_surface() {
        for name in ["cube", "cone", "torus"] {
            let mesh = halfedge::shapes::lab_object(name).unwrap();
            let e = mesh.edge_between(0, 1).or(mesh.edge_ids().nth(3));
            let all = labellings(&mesh, e, 7, 3);
            assert_eq!(all.len(), if e.is_some() { 6 } else { 4 });
            for l in &all {
                l.mesh.validate().unwrap();
                assert_eq!(surface(&l.mesh), surface(&mesh), "{name}: {}", l.what);
                let (a, b) = mesh.edge_vertices(e.unwrap());
                let (x, y) = l.mesh.edge_vertices(l.edge.unwrap());
                let pos = |m: &Mesh, v: VertexId| m[v].pos;
                let mut want = [pos(&mesh, a).to_array(), pos(&mesh, b).to_array()];
                let mut got = [pos(&l.mesh, x).to_array(), pos(&l.mesh, y).to_array()];
                want.sort_by(|p, q| p.partial_cmp(q).unwrap());
                got.sort_by(|p, q| p.partial_cmp(q).unwrap());
                assert_eq!(got, want, "the case's edge follows the relabelling");
            }
        }
    }

    #[test]
    fn the_hard_labellings_point_the_ends_along_the_edge() {
        let mesh = halfedge::shapes::lab_object("cube").unwrap();
        let e = mesh.edge_ids().nth(5).unwrap();
        for l in &labellings(&mesh, Some(e), 1, 0)[1..] {
            let m = &l.mesh;
            let h = m[l.edge.unwrap()].halfedge;
            let t = m[h].twin;
            assert_eq!(m[m[h].vertex].halfedge, h);
            assert_eq!(m[m[t].vertex].halfedge, t);
        }
    }

    #[test]
    fn a_boundary_edge_gets_a_labelling_with_its_halfedge_in_the_hole() {
        let grid = halfedge::shapes::grid(2, 2);
        let rim = grid.edge_ids().find(|&e| grid.edge_on_boundary(e)).unwrap();
        let all = labellings(&grid, Some(rim), 3, 1);
        let hole = all.iter().find(|l| l.kind == Kind::HoleSide).expect("one");
        let h = hole.mesh[hole.edge.unwrap()].halfedge;
        assert!(hole.mesh[hole.mesh[h].face].is_boundary);
        assert!(hole.what.contains("lies in the hole"));
    }

    #[test]
    fn the_same_seed_gives_the_same_labellings() {
        let mesh = halfedge::shapes::lab_object("cone").unwrap();
        let a = labellings(&mesh, None, 42, 2);
        let b = labellings(&mesh, None, 42, 2);
        let c = labellings(&mesh, None, 43, 2);
        let recs = |l: &Labelling| format!("{:?}", l.mesh.records().3);
        assert_eq!(recs(&a[2]), recs(&b[2]));
        assert_ne!(recs(&a[2]), recs(&c[2]));
        assert_ne!(default_seed("cube-flip-1"), default_seed("cube-flip-2"));
    }
}
