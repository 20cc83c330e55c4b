//! # A half-edge mesh for the subdivision lab
//!
//! A triangle mesh stored so that every neighbour of every element is one or
//! two steps away. Each edge is split into two **halfedges** running in
//! opposite directions, one inside each of the two faces the edge borders:
//!
//! ```text
//!              v2
//!             /  ^
//!       next /    \  (h's face is on its left)
//!           v  f0  \ next
//!         v0 -----> v1        h  : from v0 to v1, face f0
//!            <-----           twin(h): from v1 to v0, face f1
//!              f1
//! ```
//!
//! A halfedge knows its `twin` (the other side), its `next` (the following
//! halfedge around its face, counter-clockwise), the `vertex` it starts from,
//! its `edge` and its `face`. A vertex, edge and face each know one halfedge;
//! everything else is found by walking. Holes are **boundary faces**
//! (`is_boundary`), so every halfedge has a twin, even on an open surface.
//!
//! ## Ids and records
//!
//! Elements are named by typed ids ([`VertexId`], [`EdgeId`], [`FaceId`],
//! [`HalfedgeId`]) that print as `v3`, `e7`, `f2`, `h40`. Index the mesh with
//! an id to read or write the record: `mesh[v].pos`, `mesh[h].twin = t`.
//! Elements are never deleted, so an id stays valid for the mesh's life.
//!
//! ## A walk around
//!
//! ```
//! use halfedge::{shapes, Mesh};
//!
//! let mesh: Mesh = shapes::lab_object("cube").unwrap();
//! let e = mesh.edge_ids().next().unwrap();
//!
//! // The two halfedges of an edge and the vertices they start from.
//! let h = mesh[e].halfedge;
//! let t = mesh[h].twin;
//! let (a, b) = (mesh[h].vertex, mesh[t].vertex);
//! assert_eq!(mesh.edge_vertices(e), (a, b));
//!
//! // Around h's triangle: three `next` steps come back to h.
//! let h1 = mesh[h].next;
//! let h2 = mesh[h1].next;
//! assert_eq!(mesh[h2].next, h);
//! let opposite = mesh[h2].vertex; // the corner facing edge e
//! assert!(opposite != a && opposite != b);
//!
//! // Around vertex a: `twin` then `next` turns to the following edge.
//! let mut around = vec![];
//! let mut g = mesh[a].halfedge;
//! loop {
//!     around.push(mesh[mesh[g].twin].vertex);
//!     g = mesh[mesh[g].twin].next;
//!     if g == mesh[a].halfedge { break; }
//! }
//! assert_eq!(around, mesh.vertex_neighbors(a));
//! assert_eq!(around.len(), mesh.vertex_degree(a));
//! ```
//!
//! ## Changing the mesh
//!
//! New elements come from [`Mesh::new_vertex`], [`Mesh::new_edge`],
//! [`Mesh::new_face`] and [`Mesh::new_halfedge`]; their links start unset
//! (`HalfedgeId::NONE`, ...) until you set them, for a halfedge most easily
//! with [`Mesh::set_neighbors`]. Loop over the elements that exist *now* with
//! [`Mesh::edge_ids`] and friends: the iterator holds no borrow, so the loop
//! may add elements, and those are not visited.
//!
//! ```
//! use halfedge::shapes;
//! let mut mesh = shapes::lab_object("cone").unwrap();
//! for v in mesh.vertex_ids() {
//!     mesh[v].is_new = false;
//!     let p = mesh.new_vertex(mesh[v].pos); // allowed inside the loop
//!     mesh[p].is_new = true;
//! }
//! assert_eq!(mesh.num_vertices(), 14);
//! ```
//!
//! After a change, [`Mesh::validate`] finds broken links and says which
//! element is wrong, in Scotty3D's words.
//!
//! ## Modules
//! - [`mesh`]: the records and the arenas; [`ids`]: the ids.
//! - [`traverse`]: walks around faces and vertices.
//! - [`build`]: from indexed polygons, with an error for every bad input.
//! - [`obj`]: OBJ files in and out; [`shapes`]: the lab's objects and more.
//! - [`validate`]: consistency checks; [`debug`]: describe, centre, normal.
//! - [`logging`]: the lab's `file.rs:LINE [info] message` log format.

pub mod build;
pub mod debug;
pub mod ids;
pub mod logging;
pub mod mesh;
pub mod obj;
pub mod shapes;
pub mod traverse;
pub mod validate;

pub use build::MeshError;
pub use glam::DVec3;
pub use ids::{EdgeId, Element, FaceId, HalfedgeId, Ids, VertexId};
pub use mesh::{Edge, Face, Halfedge, Mesh, Vertex};
pub use validate::Invalid;
