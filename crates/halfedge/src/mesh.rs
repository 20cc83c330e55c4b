//! The mesh itself: four arenas of element records, linked by ids.
//!
//! Elements are never removed in this lab, so ids stay valid forever and the
//! ids that exist at one moment are simply `0..count`.
//!
//! **Orientation.** The library expects every face to be wound the same way
//! as its neighbours: a halfedge has its face on its left, seen from the side
//! the faces are counter-clockwise from. For a closed mesh that is normally
//! the outside, and the generated [`crate::shapes`] are built that way. The
//! lab's own `cube.obj` is wound the other way (clockwise seen from outside,
//! so its faces face inwards and its signed volume is -1); it is kept exactly
//! as the lab ships it. Nothing in the lab depends on which side is out:
//! flips, splits and Loop subdivision only use the links and the positions,
//! so they give the same surface either way. Only normals
//! ([`Mesh::face_normal`]) point inwards on that cube.
//!
//! **Defaults of new elements.** [`Mesh::new_vertex`] and [`Mesh::new_edge`]
//! create records with `is_new: false` and `new_pos: DVec3::ZERO`, and every
//! link (`halfedge`, and all five fields of a new halfedge) unset (`NONE`).
//! Set what the new element needs yourself: in subdivision, a split vertex
//! is *not* new and has no `new_pos` until you say so.

use std::ops::{Index, IndexMut};
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::DVec3;

use crate::ids::{EdgeId, FaceId, HalfedgeId, Ids, VertexId};

/// One side of an edge, running from `vertex` to `mesh[next].vertex`, with its
/// face on the left. The faces around `next` are wound consistently; the
/// library does not require that to be counter-clockwise seen from outside
/// (the lab's `cube.obj` is clockwise): see the module documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Halfedge {
    /// The halfedge on the other side of the same edge, running the other way.
    pub twin: HalfedgeId,
    /// The next halfedge around `face`, in the face's winding (its corners in
    /// the order the input listed them). [`Mesh::prev`] goes the other way.
    pub next: HalfedgeId,
    /// The vertex this halfedge starts from.
    pub vertex: VertexId,
    /// The edge this halfedge is one side of.
    pub edge: EdgeId,
    /// The face this halfedge runs around (maybe a boundary face).
    pub face: FaceId,
}

/// A point of the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Where the vertex is.
    pub pos: DVec3,
    /// Scratch space for subdivision: where the vertex will move to.
    /// `DVec3::ZERO` for every vertex until you write it, including one that
    /// `split_edge` just created.
    pub new_pos: DVec3,
    /// Scratch flag for subdivision: whether the vertex was created by it.
    /// `false` for every vertex, new ones included, until you set it.
    pub is_new: bool,
    /// Any one halfedge that starts at this vertex.
    pub halfedge: HalfedgeId,
}

/// An undirected edge: a pair of twin halfedges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// Either of the edge's two halfedges.
    pub halfedge: HalfedgeId,
    /// Scratch space for subdivision: where the vertex that splits this edge
    /// will be placed. `DVec3::ZERO` until you write it.
    pub new_pos: DVec3,
    /// Scratch flag for subdivision: whether the edge was created by it.
    /// `false` for every edge, new ones included, until you set it.
    pub is_new: bool,
}

/// A polygon of the mesh, or a hole in it (`is_boundary`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// Any one halfedge running around this face.
    pub halfedge: HalfedgeId,
    /// True for the virtual face that fills a hole: it is not part of the
    /// surface, but it gives every halfedge a twin.
    pub is_boundary: bool,
}

/// A half-edge mesh. See the crate documentation for a tour.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub(crate) vertices: Vec<Vertex>,
    pub(crate) edges: Vec<Edge>,
    pub(crate) faces: Vec<Face>,
    pub(crate) halfedges: Vec<Halfedge>,
    element_budget: Option<usize>,
}

impl Mesh {
    /// An empty mesh. Most meshes come from [`Mesh::from_faces`],
    /// [`Mesh::from_obj_file`] or [`crate::shapes`].
    pub fn new() -> Self {
        Self::default()
    }

    #[inline]
    pub fn num_vertices(&self) -> usize {
        self.vertices.len()
    }
    #[inline]
    pub fn num_edges(&self) -> usize {
        self.edges.len()
    }
    /// Counts boundary faces too; see [`Mesh::num_real_faces`].
    #[inline]
    pub fn num_faces(&self) -> usize {
        self.faces.len()
    }
    /// Faces that are polygons of the surface, not holes.
    pub fn num_real_faces(&self) -> usize {
        self.faces.iter().filter(|f| !f.is_boundary).count()
    }
    #[inline]
    pub fn num_halfedges(&self) -> usize {
        self.halfedges.len()
    }
    /// Vertices + edges + faces + halfedges: what the growth budget counts.
    #[inline]
    pub fn num_elements(&self) -> usize {
        self.vertices.len() + self.edges.len() + self.faces.len() + self.halfedges.len()
    }

    /// The ids of the vertices that exist now. The iterator holds no borrow,
    /// so you may create elements inside the loop; the new ones are not visited.
    #[inline]
    pub fn vertex_ids(&self) -> Ids<VertexId> {
        Ids::new(self.vertices.len(), VertexId)
    }
    /// The ids of the edges that exist now (see [`Mesh::vertex_ids`]).
    #[inline]
    pub fn edge_ids(&self) -> Ids<EdgeId> {
        Ids::new(self.edges.len(), EdgeId)
    }
    /// The ids of the faces that exist now, boundary faces included.
    #[inline]
    pub fn face_ids(&self) -> Ids<FaceId> {
        Ids::new(self.faces.len(), FaceId)
    }
    /// The ids of the halfedges that exist now.
    #[inline]
    pub fn halfedge_ids(&self) -> Ids<HalfedgeId> {
        Ids::new(self.halfedges.len(), HalfedgeId)
    }

    /// Caps the number of elements the mesh may hold: creating one more than
    /// `limit` panics with a message saying so. The grader uses it to stop
    /// code that splits without end before it eats the machine's memory.
    pub fn set_element_budget(&mut self, limit: Option<usize>) {
        self.element_budget = limit;
    }

    #[inline]
    #[track_caller]
    fn charge_one(&self) {
        let process = match PROCESS_BUDGET.load(Ordering::Relaxed) {
            0 => None,
            n => Some(n),
        };
        if let Some(limit) = self.element_budget.or(process) {
            if self.num_elements() >= limit {
                grew_past(limit);
            }
        }
    }

    /// Makes room for `vertices`, `edges`, `faces` and `halfedges` more
    /// elements, so that creating them never moves an arena. Optional: it
    /// changes no id and no result, only speed and peak memory. Splitting an
    /// edge between two triangles adds 1 vertex, 3 edges, 2 faces and 6
    /// halfedges (1, 2, 1 and 4 beside a hole), so one round of Loop
    /// subdivision of a closed triangle mesh with E edges adds E vertices,
    /// 3E edges, 2E faces and 6E halfedges.
    pub fn reserve(&mut self, vertices: usize, edges: usize, faces: usize, halfedges: usize) {
        // Exact: an arena doubled past what is needed would cost more memory
        // than the whole rest of a round.
        self.vertices.reserve_exact(vertices);
        self.edges.reserve_exact(edges);
        self.faces.reserve_exact(faces);
        self.halfedges.reserve_exact(halfedges);
    }

    /// Builds a mesh from its four arenas as they are, links unchecked: the
    /// grader uses it to rebuild a mesh sent between processes. Call
    /// [`Mesh::validate`] before walking the result.
    pub fn from_records(
        vertices: Vec<Vertex>,
        edges: Vec<Edge>,
        faces: Vec<Face>,
        halfedges: Vec<Halfedge>,
    ) -> Mesh {
        Mesh {
            vertices,
            edges,
            faces,
            halfedges,
            element_budget: None,
        }
    }

    /// The four arenas, indexed by id: vertices, edges, faces, halfedges.
    pub fn records(&self) -> (&[Vertex], &[Edge], &[Face], &[Halfedge]) {
        (&self.vertices, &self.edges, &self.faces, &self.halfedges)
    }

    /// Adds a vertex at `pos` whose `halfedge` is not set yet, with
    /// `new_pos = DVec3::ZERO` and `is_new = false`.
    #[inline]
    #[track_caller]
    pub fn new_vertex(&mut self, pos: DVec3) -> VertexId {
        self.charge_vertex();
        self.vertices.push(Vertex {
            pos,
            new_pos: DVec3::ZERO,
            is_new: false,
            halfedge: HalfedgeId::NONE,
        });
        VertexId::from_index(self.vertices.len() - 1)
    }

    /// Adds an edge whose `halfedge` is not set yet, with
    /// `new_pos = DVec3::ZERO` and `is_new = false`.
    #[inline]
    #[track_caller]
    pub fn new_edge(&mut self) -> EdgeId {
        self.charge_one();
        self.edges.push(Edge {
            halfedge: HalfedgeId::NONE,
            new_pos: DVec3::ZERO,
            is_new: false,
        });
        EdgeId::from_index(self.edges.len() - 1)
    }

    /// Adds a real (not boundary) face whose `halfedge` is not set yet.
    #[inline]
    #[track_caller]
    pub fn new_face(&mut self) -> FaceId {
        self.new_face_with(false)
    }

    #[inline]
    #[track_caller]
    pub(crate) fn new_face_with(&mut self, is_boundary: bool) -> FaceId {
        self.charge_one();
        self.faces.push(Face {
            halfedge: HalfedgeId::NONE,
            is_boundary,
        });
        FaceId::from_index(self.faces.len() - 1)
    }

    /// Adds a halfedge whose fields are all unset: follow with
    /// [`Mesh::set_neighbors`].
    #[inline]
    #[track_caller]
    pub fn new_halfedge(&mut self) -> HalfedgeId {
        self.charge_one();
        self.halfedges.push(Halfedge {
            twin: HalfedgeId::NONE,
            next: HalfedgeId::NONE,
            vertex: VertexId::NONE,
            edge: EdgeId::NONE,
            face: FaceId::NONE,
        });
        HalfedgeId::from_index(self.halfedges.len() - 1)
    }

    /// Sets all five fields of halfedge `h` at once, as Scotty3D's
    /// `setNeighbors` does: writing them together makes it hard to forget one.
    #[inline]
    pub fn set_neighbors(
        &mut self,
        h: HalfedgeId,
        next: HalfedgeId,
        twin: HalfedgeId,
        vertex: VertexId,
        edge: EdgeId,
        face: FaceId,
    ) {
        self[h] = Halfedge {
            twin,
            next,
            vertex,
            edge,
            face,
        };
    }
}

#[cold]
#[inline(never)]
#[track_caller]
fn grew_past(limit: usize) -> ! {
    // The fact, for a program that must tell this panic from others
    // without reading its words.
    BUDGET_HIT.store(limit, Ordering::Relaxed);
    panic!(
        "the mesh grew past {limit} elements (vertices + edges + faces + halfedges): \
         is something splitting without end? (found by the mesh library, {}:{})",
        file!(),
        line!()
    );
}

/// The process-wide growth budget (0: none), see [`set_process_element_budget`].
static PROCESS_BUDGET: AtomicUsize = AtomicUsize::new(0);

/// Caps every mesh in this process, including ones made later with
/// `Mesh::new()` or `clone()`, as [`Mesh::set_element_budget`] caps one mesh.
/// The grader's child sets it, so replacing the mesh does not escape the cap.
pub fn set_process_element_budget(limit: Option<usize>) {
    PROCESS_BUDGET.store(limit.unwrap_or(0), Ordering::Relaxed);
    BUDGET_HIT.store(0, Ordering::Relaxed);
}

/// The last growth budget a mesh of this process hit (0: none since the
/// process budget was last set).
static BUDGET_HIT: AtomicUsize = AtomicUsize::new(0);

/// The growth budget whose panic ("the mesh grew past N elements") a mesh
/// of this process raised since [`set_process_element_budget`] was last
/// called, if any: how the grader's child tells that panic from the
/// student's own.
pub fn element_budget_hit() -> Option<usize> {
    Some(BUDGET_HIT.load(Ordering::Relaxed)).filter(|&n| n > 0)
}

/// The message of an id that names no element, kept out of line: indexing is
/// in every inner loop, and the panic's formatting would bloat each copy.
#[cold]
#[inline(never)]
#[track_caller]
fn no_such(kind: &str, id: &dyn std::fmt::Display, len: usize) -> ! {
    // The location a panic reports is the caller's (`#[track_caller]`): the
    // library's own place goes in the message, second.
    panic!(
        "there is no {kind} {id} (the mesh has {len}): an unset or stale id? (found by the \
         mesh library's indexing, {}:{})",
        file!(),
        line!()
    )
}

macro_rules! arena_index {
    ($id:ty, $record:ty, $field:ident, $kind:literal) => {
        impl Index<$id> for Mesh {
            type Output = $record;
            #[inline]
            #[track_caller]
            fn index(&self, id: $id) -> &$record {
                match self.$field.get(id.index()) {
                    Some(record) => record,
                    None => no_such($kind, &id, self.$field.len()),
                }
            }
        }
        impl IndexMut<$id> for Mesh {
            #[inline]
            #[track_caller]
            fn index_mut(&mut self, id: $id) -> &mut $record {
                let len = self.$field.len();
                match self.$field.get_mut(id.index()) {
                    Some(record) => record,
                    None => no_such($kind, &id, len),
                }
            }
        }
    };
}

arena_index!(VertexId, Vertex, vertices, "vertex");
arena_index!(EdgeId, Edge, edges, "edge");
arena_index!(FaceId, Face, faces, "face");
arena_index!(HalfedgeId, Halfedge, halfedges, "halfedge");

impl Mesh {
    /// [`Mesh::charge_one`] for a vertex, which also lets a running
    /// recording keep the mesh as it is before the vertex is added (see
    /// [`crate::recording`]).
    #[inline]
    #[track_caller]
    fn charge_vertex(&self) {
        crate::recording::before_vertex(self);
        self.charge_one();
    }
}
