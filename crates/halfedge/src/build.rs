//! Building a mesh from indexed polygons, and exporting it back.
//!
//! Every way an indexed face list can fail to be an oriented 2-manifold is a
//! [`MeshError`] that names the face, vertex or edge concerned.

use std::collections::HashMap;
use std::fmt;

use glam::DVec3;

use crate::ids::{EdgeId, FaceId, HalfedgeId, VertexId};
use crate::mesh::Mesh;

/// Why a mesh could not be built or read. Vertex and face numbers count from
/// 0 in [`Mesh::from_faces`]; errors read from an OBJ file are wrapped in
/// [`MeshError::Obj`], which gives the file's line and 1-based numbers.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshError {
    /// No vertices or no faces at all.
    Empty,
    /// A coordinate is NaN or infinite.
    NonFiniteCoordinate { vertex: usize },
    /// A face names a vertex that does not exist.
    IndexOutOfRange {
        face: usize,
        index: usize,
        vertex_count: usize,
    },
    /// A face with fewer than three corners.
    TooFewVertices { face: usize, count: usize },
    /// A face that lists the same vertex twice in a row, which would make
    /// an edge from that vertex to itself.
    EdgeToItself { face: usize, vertex: usize },
    /// A face that visits the same vertex twice.
    RepeatedVertex { face: usize, vertex: usize },
    /// Two faces with the same vertices: the same polygon twice (with
    /// opposite windings they would close into a flat two-faced "pillow").
    DuplicateFace { first: usize, second: usize },
    /// An edge used by more than two faces.
    EdgeSharedByMoreThanTwoFaces {
        a: usize,
        b: usize,
        faces: Vec<usize>,
    },
    /// Two faces that run along their shared edge the same way: one of them is
    /// wound clockwise.
    InconsistentOrientation {
        a: usize,
        b: usize,
        first: usize,
        second: usize,
    },
    /// The faces around a vertex do not form a single fan (e.g. two cones
    /// touching at their tips).
    NonManifoldVertex { vertex: usize },
    /// A vertex that no face uses.
    UnreferencedVertex { vertex: usize },
    /// A file could not be read at all.
    UnreadableFile { path: String, reason: String },
    /// A problem in an OBJ file, at a line (0 when it concerns the whole file).
    Obj {
        path: String,
        line: usize,
        message: String,
    },
}

impl MeshError {
    /// The face the error is about, if any.
    pub fn face(&self) -> Option<usize> {
        match *self {
            MeshError::IndexOutOfRange { face, .. }
            | MeshError::TooFewVertices { face, .. }
            | MeshError::EdgeToItself { face, .. }
            | MeshError::RepeatedVertex { face, .. } => Some(face),
            MeshError::DuplicateFace { second, .. } => Some(second),
            MeshError::EdgeSharedByMoreThanTwoFaces { ref faces, .. } => faces.last().copied(),
            MeshError::InconsistentOrientation { second, .. } => Some(second),
            _ => None,
        }
    }

    /// The vertex the error is about, if it is about one vertex.
    pub fn vertex(&self) -> Option<usize> {
        match *self {
            MeshError::NonFiniteCoordinate { vertex }
            | MeshError::NonManifoldVertex { vertex }
            | MeshError::UnreferencedVertex { vertex } => Some(vertex),
            _ => None,
        }
    }

    /// The message with vertex and face numbers counted from `base` (0 for
    /// indexed faces, 1 for OBJ files).
    pub fn describe(&self, base: usize) -> String {
        // Saturating: an absurd index in the input must not overflow here.
        let n = |i: usize| i.saturating_add(base);
        match self {
            MeshError::Empty => {
                "the mesh is empty: it needs at least one vertex and one face".into()
            }
            MeshError::NonFiniteCoordinate { vertex } => {
                format!(
                    "vertex {} has a coordinate that is NaN or infinite",
                    n(*vertex)
                )
            }
            MeshError::IndexOutOfRange {
                face,
                index,
                vertex_count,
            } => format!(
                "face {} refers to vertex {}, but the vertices are numbered {} to {}",
                n(*face),
                n(*index),
                n(0),
                (n(*vertex_count)).saturating_sub(1)
            ),
            MeshError::TooFewVertices { face, count } => format!(
                "face {} has {count} vertices; a face needs at least 3",
                n(*face)
            ),
            MeshError::EdgeToItself { face, vertex } => format!(
                "face {} lists vertex {} twice in a row: that would be an edge from a vertex \
                 to itself",
                n(*face),
                n(*vertex)
            ),
            MeshError::DuplicateFace { first, second } => format!(
                "face {} duplicates face {}: both use the same vertices (a polygon may appear \
                 only once)",
                n(*second),
                n(*first)
            ),
            MeshError::RepeatedVertex { face, vertex } => format!(
                "face {} uses vertex {} more than once",
                n(*face),
                n(*vertex)
            ),
            MeshError::EdgeSharedByMoreThanTwoFaces { a, b, faces } => format!(
                "the edge between vertices {} and {} is shared by more than two faces ({}): \
                 the surface is not a manifold",
                n(*a),
                n(*b),
                faces
                    .iter()
                    .map(|f| format!("face {}", n(*f)))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            MeshError::InconsistentOrientation {
                a,
                b,
                first,
                second,
            } => format!(
                "faces {} and {} both run from vertex {} to vertex {}: their orientations \
                 disagree (one of them is wound clockwise)",
                n(*first),
                n(*second),
                n(*a),
                n(*b)
            ),
            MeshError::NonManifoldVertex { vertex } => format!(
                "vertex {} is non-manifold: the faces around it do not form a single fan",
                n(*vertex)
            ),
            MeshError::UnreferencedVertex { vertex } => {
                format!("vertex {} is not used by any face", n(*vertex))
            }
            MeshError::UnreadableFile { path, reason } => {
                format!("cannot read {path}: {reason}")
            }
            MeshError::Obj {
                path,
                line,
                message,
            } => {
                if *line == 0 {
                    format!("{path}: {message}")
                } else {
                    format!("{path}:{line}: {message}")
                }
            }
        }
    }
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.describe(0))
    }
}

impl std::error::Error for MeshError {}

impl Mesh {
    /// Builds a mesh from vertex positions and polygons given as lists of
    /// vertex indices, counter-clockwise seen from outside.
    ///
    /// Vertex `i` of the input becomes `VertexId(i)`. Every hole gets a
    /// boundary face, so every halfedge has a twin.
    pub fn from_faces(positions: &[DVec3], faces: &[Vec<usize>]) -> Result<Mesh, MeshError> {
        check_faces(positions, faces)?;

        let mut mesh = Mesh::new();
        for &p in positions {
            mesh.new_vertex(p);
        }

        // Interior halfedges, keyed by (from, to).
        let mut directed: HashMap<(usize, usize), HalfedgeId> = HashMap::new();
        for corners in faces {
            let f = mesh.new_face();
            let first = HalfedgeId::from_index(mesh.num_halfedges());
            for (i, &a) in corners.iter().enumerate() {
                let h = mesh.new_halfedge();
                let b = corners[(i + 1) % corners.len()];
                let next = HalfedgeId::from_index(first.index() + (i + 1) % corners.len());
                mesh[h].next = next;
                mesh[h].vertex = VertexId::from_index(a);
                mesh[h].face = f;
                directed.insert((a, b), h);
            }
            mesh[f].halfedge = first;
        }

        // Twins and edges, in the order the interior halfedges were made.
        let mut boundary_from: HashMap<VertexId, HalfedgeId> = HashMap::new();
        for h in mesh.halfedge_ids() {
            if !mesh[h].twin.is_none() {
                continue;
            }
            let a = mesh[h].vertex;
            let b = mesh[mesh[h].next].vertex;
            let e = mesh.new_edge();
            mesh[e].halfedge = h;
            mesh[h].edge = e;
            let t = match directed.get(&(b.index(), a.index())) {
                Some(&t) => t,
                None => {
                    // No face on the other side: a hole. Its halfedge runs b -> a.
                    let t = mesh.new_halfedge();
                    mesh[t].vertex = b;
                    if boundary_from.insert(b, t).is_some() {
                        return Err(MeshError::NonManifoldVertex { vertex: b.index() });
                    }
                    t
                }
            };
            mesh[h].twin = t;
            mesh[t].twin = h;
            mesh[t].edge = e;
        }

        // Link each hole's halfedges into loops, and give each loop a face.
        // Each vertex has at most one boundary halfedge leaving it (checked
        // above), so the one leaving where `t` ends is its successor.
        for &t in boundary_from.values() {
            let to = mesh[mesh[t].twin].vertex;
            mesh[t].next = boundary_from[&to];
        }
        for t in mesh.halfedge_ids() {
            if mesh[t].face.is_none() {
                let f = mesh.new_face_with(true);
                mesh[f].halfedge = t;
                let mut h = t;
                loop {
                    mesh[h].face = f;
                    h = mesh[h].next;
                    if h == t {
                        break;
                    }
                }
            }
        }

        for h in mesh.halfedge_ids() {
            let v = mesh[h].vertex;
            if mesh[v].halfedge.is_none() {
                mesh[v].halfedge = h;
            }
        }

        // A vertex whose fan does not reach all its halfedges is two surfaces
        // touching at a point.
        let mut outgoing = vec![0usize; mesh.num_vertices()];
        for h in mesh.halfedge_ids() {
            outgoing[mesh[h].vertex.index()] += 1;
        }
        for v in mesh.vertex_ids() {
            if mesh.vertex_degree(v) != outgoing[v.index()] {
                return Err(MeshError::NonManifoldVertex { vertex: v.index() });
            }
        }
        Ok(mesh)
    }

    /// The mesh as indexed polygons: all vertex positions, in id order, and
    /// the real (non-boundary) faces as lists of vertex indices.
    pub fn to_faces(&self) -> (Vec<DVec3>, Vec<Vec<usize>>) {
        let positions = self.vertices.iter().map(|v| v.pos).collect();
        let faces = self
            .face_ids()
            .filter(|&f| !self[f].is_boundary)
            .map(|f| {
                self.face_vertices(f)
                    .into_iter()
                    .map(VertexId::index)
                    .collect()
            })
            .collect();
        (positions, faces)
    }

    /// Every edge as the pair of vertex indices it joins, smaller index first,
    /// in edge id order.
    pub fn edge_list(&self) -> Vec<[usize; 2]> {
        self.edge_ids()
            .map(|e| {
                let (a, b) = self.edge_vertices(e);
                let (a, b) = (a.index(), b.index());
                [a.min(b), a.max(b)]
            })
            .collect()
    }

    /// The positions of all vertices, in id order.
    pub fn positions(&self) -> Vec<DVec3> {
        self.vertices.iter().map(|v| v.pos).collect()
    }
}

/// Everything that can be wrong with an indexed face list before any
/// halfedge is made.
fn check_faces(positions: &[DVec3], faces: &[Vec<usize>]) -> Result<(), MeshError> {
    if positions.is_empty() || faces.is_empty() {
        return Err(MeshError::Empty);
    }
    if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
        return Err(MeshError::NonFiniteCoordinate { vertex });
    }
    let mut used = vec![false; positions.len()];
    let mut seen_in = vec![usize::MAX; positions.len()];
    for (face, corners) in faces.iter().enumerate() {
        if corners.len() < 3 {
            return Err(MeshError::TooFewVertices {
                face,
                count: corners.len(),
            });
        }
        if let Some(&index) = corners.iter().find(|&&i| i >= positions.len()) {
            return Err(MeshError::IndexOutOfRange {
                face,
                index,
                vertex_count: positions.len(),
            });
        }
        // Twice in a row first: it is the more specific message.
        for (i, &a) in corners.iter().enumerate() {
            if a == corners[(i + 1) % corners.len()] {
                return Err(MeshError::EdgeToItself { face, vertex: a });
            }
        }
        // `seen_in[v]` is the last face that used v: linear even for a face
        // with very many corners.
        for &index in corners {
            if seen_in[index] == face {
                return Err(MeshError::RepeatedVertex {
                    face,
                    vertex: index,
                });
            }
            seen_in[index] = face;
            used[index] = true;
        }
    }

    // Before the edges: a duplicate would otherwise be reported as
    // disagreeing orientations, or not at all (the two-faced pillow).
    let mut by_vertices: HashMap<Vec<usize>, usize> = HashMap::new();
    for (face, corners) in faces.iter().enumerate() {
        let mut key = corners.clone();
        key.sort_unstable();
        if let Some(&first) = by_vertices.get(&key) {
            return Err(MeshError::DuplicateFace {
                first,
                second: face,
            });
        }
        by_vertices.insert(key, face);
    }

    let mut by_edge: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
    for (face, corners) in faces.iter().enumerate() {
        for (i, &a) in corners.iter().enumerate() {
            let b = corners[(i + 1) % corners.len()];
            let users = by_edge.entry((a.min(b), a.max(b))).or_default();
            users.push(face);
            if users.len() > 2 {
                return Err(MeshError::EdgeSharedByMoreThanTwoFaces {
                    a: a.min(b),
                    b: a.max(b),
                    faces: users.clone(),
                });
            }
            if let Some(&first) = directed.get(&(a, b)) {
                return Err(MeshError::InconsistentOrientation {
                    a,
                    b,
                    first,
                    second: face,
                });
            }
            directed.insert((a, b), face);
        }
    }

    if let Some(vertex) = used.iter().position(|&u| !u) {
        return Err(MeshError::UnreferencedVertex { vertex });
    }
    Ok(())
}

impl Mesh {
    /// Edge ids are an implementation detail of building; this names the edge
    /// between two input vertex indices, as fixtures do.
    pub fn edge_between(&self, a: usize, b: usize) -> Option<EdgeId> {
        if a >= self.num_vertices() || b >= self.num_vertices() {
            return None;
        }
        self.find_edge(VertexId::from_index(a), VertexId::from_index(b))
    }

    /// Whether every real face is a triangle.
    pub fn is_triangle_mesh(&self) -> bool {
        self.face_ids()
            .filter(|&f| !self[f].is_boundary)
            .all(|f| self.face_degree(f) == 3)
    }

    /// The first real face that is not a triangle, if any.
    pub fn first_non_triangle(&self) -> Option<FaceId> {
        self.face_ids()
            .find(|&f| !self[f].is_boundary && self.face_degree(f) != 3)
    }
}
