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
        let corners = check_faces(positions, faces)?;
        let twins = find_twins(faces, &corners, positions.len())?;
        if let Some(vertex) = corners.used.iter().position(|&u| !u) {
            return Err(MeshError::UnreferencedVertex { vertex });
        }

        // Every count is known but the holes': the arenas are made once.
        let interior = corners.src.len();
        let open = twins.iter().filter(|t| t.is_none()).count();
        let mut mesh = Mesh::new();
        mesh.reserve(
            positions.len(),
            (interior + open) / 2,
            faces.len(),
            interior + open,
        );
        for &p in positions {
            mesh.new_vertex(p);
        }
        // Interior halfedges: face f's corners in order, consecutive ids.
        for (f_index, corner_list) in faces.iter().enumerate() {
            let f = mesh.new_face();
            let first = corners.first[f_index] as usize;
            for i in 0..corner_list.len() {
                let h = mesh.new_halfedge();
                let next = first + (i + 1) % corner_list.len();
                mesh[h].next = HalfedgeId::from_index(next);
                mesh[h].vertex = VertexId::from_index(corner_list[i]);
                mesh[h].face = f;
            }
            mesh[f].halfedge = HalfedgeId::from_index(first);
        }

        // Twins and edges, in the order the interior halfedges were made.
        // `boundary_from[v]`: the hole's halfedge leaving v, if any.
        let mut boundary_from = vec![HalfedgeId::NONE; positions.len()];
        for h in mesh.halfedge_ids() {
            if !mesh[h].twin.is_none() {
                continue;
            }
            let e = mesh.new_edge();
            mesh[e].halfedge = h;
            mesh[h].edge = e;
            let t = match twins[h.index()] {
                Some(t) => t,
                None => {
                    // No face on the other side: a hole. Its halfedge runs b -> a.
                    let b = mesh[mesh[h].next].vertex;
                    let t = mesh.new_halfedge();
                    mesh[t].vertex = b;
                    if !boundary_from[b.index()].is_none() {
                        return Err(MeshError::NonManifoldVertex { vertex: b.index() });
                    }
                    boundary_from[b.index()] = t;
                    t
                }
            };
            mesh[h].twin = t;
            mesh[t].twin = h;
            mesh[t].edge = e;
        }

        // Link each hole's halfedges into loops, and give each loop a face.
        // Each vertex has at most one boundary halfedge leaving it (checked
        // above), and one arrives wherever one leaves (a vertex's faces have
        // as many unmatched sides going out as coming in), so the one
        // leaving where `t` ends is its successor.
        for t in interior..mesh.num_halfedges() {
            let t = HalfedgeId::from_index(t);
            let to = mesh[mesh[t].twin].vertex;
            mesh[t].next = boundary_from[to.index()];
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
        let mut outgoing = vec![0u32; mesh.num_vertices()];
        for h in mesh.halfedge_ids() {
            outgoing[mesh[h].vertex.index()] += 1;
        }
        for v in mesh.vertex_ids() {
            if mesh.vertex_degree(v) != outgoing[v.index()] as usize {
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

/// The corners of a checked face list, as the interior halfedges they
/// become: halfedge `first[f] + i` leaves corner `i` of face `f`.
struct Corners {
    first: Vec<u32>,
    /// The vertex each interior halfedge leaves.
    src: Vec<u32>,
    /// The interior halfedge after each one around its face.
    next: Vec<u32>,
    /// The halfedge before each one around its face.
    prev: Vec<u32>,
    /// Whether each vertex is a corner of some face.
    used: Vec<bool>,
}

/// Everything that can be wrong with an indexed face list before any
/// halfedge is made, but its edges (see [`find_twins`]) and unused vertices.
///
/// Linear and without hashing: building used to cost more than
/// subdividing.
fn check_faces(positions: &[DVec3], faces: &[Vec<usize>]) -> Result<Corners, MeshError> {
    if positions.is_empty() || faces.is_empty() {
        return Err(MeshError::Empty);
    }
    if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
        return Err(MeshError::NonFiniteCoordinate { vertex });
    }
    let total: usize = faces.iter().map(Vec::len).sum();
    if u32::try_from(total).is_err() || u32::try_from(positions.len()).is_err() {
        panic!("element index does not fit in u32: the mesh is far too large");
    }
    let mut corners = Corners {
        first: Vec::with_capacity(faces.len()),
        src: Vec::with_capacity(total),
        next: Vec::with_capacity(total),
        prev: Vec::with_capacity(total),
        used: vec![false; positions.len()],
    };
    let mut seen_in = vec![usize::MAX; positions.len()];
    for (face, list) in faces.iter().enumerate() {
        if list.len() < 3 {
            return Err(MeshError::TooFewVertices {
                face,
                count: list.len(),
            });
        }
        if let Some(&index) = list.iter().find(|&&i| i >= positions.len()) {
            return Err(MeshError::IndexOutOfRange {
                face,
                index,
                vertex_count: positions.len(),
            });
        }
        // Twice in a row first: it is the more specific message.
        for (i, &a) in list.iter().enumerate() {
            if a == list[(i + 1) % list.len()] {
                return Err(MeshError::EdgeToItself { face, vertex: a });
            }
        }
        // `seen_in[v]` is the last face that used v: linear even for a face
        // with very many corners.
        for &index in list {
            if seen_in[index] == face {
                return Err(MeshError::RepeatedVertex {
                    face,
                    vertex: index,
                });
            }
            seen_in[index] = face;
            corners.used[index] = true;
        }
        let first = corners.src.len();
        let n = list.len();
        corners.first.push(first as u32);
        for (i, &a) in list.iter().enumerate() {
            corners.src.push(a as u32);
            corners.next.push((first + (i + 1) % n) as u32);
            corners.prev.push((first + (i + n - 1) % n) as u32);
        }
    }

    // Before the edges: a duplicate would otherwise be reported as
    // disagreeing orientations, or not at all (the two-faced pillow).
    if let Some((first, second)) = first_duplicate(faces, &corners, positions.len()) {
        return Err(MeshError::DuplicateFace { first, second });
    }
    Ok(corners)
}

/// The first face (lowest index) with the same vertices as an earlier one,
/// and the earliest such face: `(first, second)`.
///
/// Two such faces share their smallest vertex, so faces are sorted into one
/// bucket per smallest vertex (a counting sort), and only a bucket's few
/// faces are compared.
fn first_duplicate(
    faces: &[Vec<usize>],
    corners: &Corners,
    vertex_count: usize,
) -> Option<(usize, usize)> {
    let smallest: Vec<u32> = faces
        .iter()
        .map(|list| *list.iter().min().expect("faces have corners") as u32)
        .collect();
    let mut start = vec![0u32; vertex_count + 1];
    for &v in &smallest {
        start[v as usize + 1] += 1;
    }
    for v in 0..vertex_count {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut by_smallest = vec![0u32; faces.len()];
    for (face, &v) in smallest.iter().enumerate() {
        by_smallest[fill[v as usize] as usize] = face as u32;
        fill[v as usize] += 1;
    }

    let mut found: Option<(usize, usize)> = None;
    // A bucket's faces' sorted corners, one after the other (no allocation
    // per face), and (start in `sorted`, face) for each.
    let mut sorted: Vec<u32> = Vec::new();
    let mut keys: Vec<(usize, usize)> = Vec::new();
    for v in 0..vertex_count {
        let bucket = &by_smallest[start[v] as usize..start[v + 1] as usize];
        if bucket.len() < 2 {
            continue;
        }
        sorted.clear();
        keys.clear();
        for &face in bucket {
            let face = face as usize;
            let first = corners.first[face] as usize;
            let at = sorted.len();
            sorted.extend_from_slice(&corners.src[first..first + faces[face].len()]);
            sorted[at..].sort_unstable();
            keys.push((at, face));
        }
        let key = |&(at, face): &(usize, usize)| &sorted[at..at + faces[face].len()];
        // By vertices, then by face: each run of equal vertices starts with
        // its earliest two faces.
        keys.sort_unstable_by(|x, y| key(x).cmp(key(y)).then(x.1.cmp(&y.1)));
        for pair in keys.windows(2) {
            if key(&pair[0]) == key(&pair[1]) && found.is_none_or(|(_, second)| pair[1].1 < second)
            {
                found = Some((pair[0].1, pair[1].1));
            }
        }
    }
    // Within a run, `windows` also pairs later faces (the 2nd and 3rd): a run
    // is sorted by face, so its first pair has the smallest second face and
    // the comparison above keeps it.
    found
}

/// The twin of every interior halfedge (`None`: a hole is on the other
/// side), or the first problem with the edges: an edge used by more than
/// two faces, or twice in the same direction.
///
/// The halfedges leaving each vertex are listed together (a counting sort);
/// the twin of `c -> a` is found among those leaving `a`.
fn find_twins(
    faces: &[Vec<usize>],
    corners: &Corners,
    vertex_count: usize,
) -> Result<Vec<Option<HalfedgeId>>, MeshError> {
    let n = corners.src.len();
    let dst = |h: usize| corners.src[corners.next[h] as usize] as usize;
    let mut start = vec![0u32; vertex_count + 1];
    for &a in &corners.src {
        start[a as usize + 1] += 1;
    }
    for v in 0..vertex_count {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut leaving = vec![0u32; n];
    for (h, &a) in corners.src.iter().enumerate() {
        leaving[fill[a as usize] as usize] = h as u32;
        fill[a as usize] += 1;
    }
    drop(fill);

    let mut twins: Vec<Option<HalfedgeId>> = vec![None; n];
    // `stamp[b] == a`: `to[b]` is the halfedge a -> b.
    let mut stamp = vec![u32::MAX; vertex_count];
    let mut to = vec![0u32; vertex_count];
    for a in 0..vertex_count {
        let out = &leaving[start[a] as usize..start[a + 1] as usize];
        for &h in out {
            let b = dst(h as usize);
            if stamp[b] == a as u32 {
                // The same directed edge twice. The full check names the
                // first problem in face order, as the error always has.
                return Err(edge_problem(faces).expect(
                    "a directed edge used twice is one of the problems edge_problem names",
                ));
            }
            stamp[b] = a as u32;
            to[b] = h;
        }
        // Each halfedge arriving at a is the one before a halfedge leaving it.
        for &h in out {
            let arriving = corners.prev[h as usize] as usize;
            let c = corners.src[arriving] as usize;
            if stamp[c] == a as u32 {
                twins[arriving] = Some(HalfedgeId(to[c]));
            }
        }
    }
    // No directed edge twice means no edge has three faces either: three
    // uses in two directions would repeat one.
    Ok(twins)
}

/// The first problem with the edges in face and corner order, as the error
/// reports it: an edge shared by more than two faces, or two faces that run
/// along an edge the same way. Hashing, so only called once one is known.
fn edge_problem(faces: &[Vec<usize>]) -> Option<MeshError> {
    let mut by_edge: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
    for (face, corners) in faces.iter().enumerate() {
        for (i, &a) in corners.iter().enumerate() {
            let b = corners[(i + 1) % corners.len()];
            let users = by_edge.entry((a.min(b), a.max(b))).or_default();
            users.push(face);
            if users.len() > 2 {
                return Some(MeshError::EdgeSharedByMoreThanTwoFaces {
                    a: a.min(b),
                    b: a.max(b),
                    faces: users.clone(),
                });
            }
            if let Some(&first) = directed.get(&(a, b)) {
                return Some(MeshError::InconsistentOrientation {
                    a,
                    b,
                    first,
                    second: face,
                });
            }
            directed.insert((a, b), face);
        }
    }
    None
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
