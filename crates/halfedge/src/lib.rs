//! # A half-edge mesh for the subdivision lab
//!
//! A polygon mesh (the Loop lab's are all triangles) stored so that every
//! neighbour of every element is one or two steps away. Each edge is split into two **halfedges** running in
//! opposite directions, one inside each of the two faces the edge borders.
//! A halfedge knows its `twin` (the other side), its `next` (the following
//! halfedge around its face), the `vertex` it starts from, its `edge` and its
//! `face`. A vertex, edge and face each know one halfedge; everything else is
//! found by walking. Holes are **boundary faces** (`is_boundary`), so every
//! halfedge has a twin, even on an open surface.
//!
#![doc = include_str!("../../../docs/figures/halfedge.svg")]
//!
//! ## Ids and records
//!
//! Elements are named by typed ids ([`VertexId`], [`EdgeId`], [`FaceId`],
//! [`HalfedgeId`]) that print as `v3`, `e7`, `f2`, `h40`. Index the mesh with
//! an id to read or write the record: `mesh[v].pos`, `mesh[h].twin = t`.
//! Records are `Copy`: `let r = mesh[h];` takes a snapshot, and writing
//! `mesh[h].next = ...` afterwards does not change `r`. Elements are never
//! deleted, so an id stays valid for the mesh's life.
//!
//! Positions are [`DVec3`] (glam's `f64` vector), re-exported here: write
//! `use halfedge::DVec3;`, not `use glam::DVec3;` (the lab's crate does not
//! depend on glam). It has `+`, `-`, `* f64`, `/ f64`, `DVec3::ZERO`,
//! `.length()`, `.distance(q)` and `std::iter::Sum`.
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
//! assert_eq!(mesh.prev(h), h2); // the step back, walking the face once
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
//! Which way the walks turn: `next` follows the face's winding; the walk
//! around a vertex ([`Mesh::vertex_halfedges`], `twin` then `next`) turns
//! the *other* way, clockwise seen from the side the faces are
//! counter-clockwise from. `mesh[mesh.prev(g)].twin` steps back.
//!
#![doc = include_str!("../../../docs/figures/vertex-walk.svg")]
//!
//! **Orientation.** The faces must be wound consistently (each edge's two
//! halfedges run opposite ways), but not necessarily counter-clockwise seen
//! from outside: the lab's `cube.obj` is wound clockwise seen from outside
//! (it faces inwards, signed volume -1). Flips, splits and subdivision never
//! look at which side is out, so they give the same result either way; only
//! normals ([`Mesh::face_normal`]) point inwards on that cube. See
//! [`mesh`].
//!
//! ## Changing the mesh
//!
//! New elements come from [`Mesh::new_vertex`], [`Mesh::new_edge`],
//! [`Mesh::new_face`] and [`Mesh::new_halfedge`]; their links start unset
//! (`HalfedgeId::NONE`, ...) until you set them, for a halfedge most easily
//! with [`Mesh::set_neighbors`]. A new vertex or edge also starts with
//! `is_new == false` and `new_pos == DVec3::ZERO`: nothing is marked new
//! for you. Loop over the elements that exist *now* with
//! [`Mesh::edge_ids`] and friends: the iterator is a snapshot of the count
//! and holds no borrow, so the loop may add elements, and those are not
//! visited.
//!
//! ```
//! use halfedge::{shapes, DVec3};
//! let mut mesh = shapes::lab_object("cone").unwrap();
//! for v in mesh.vertex_ids() {
//!     mesh[v].is_new = false;
//!     let up = DVec3::new(0.0, 1.0, 0.0);
//!     let p = mesh.new_vertex(mesh[v].pos + up); // allowed inside the loop
//!     // The defaults: not new, no new position.
//!     assert!(!mesh[p].is_new && mesh[p].new_pos == DVec3::ZERO);
//!     mesh[p].is_new = true;
//! }
//! assert_eq!(mesh.num_vertices(), 14);
//! ```
//!
//! ## Finding mistakes
//!
//! - [`Mesh::validate`] checks every link and returns the first problem with
//!   the element, in Scotty3D's words (`A vertex's halfedge does not point
//!   to that vertex! (v12)`). Call it after each step while you work:
//!   `if let Err(bad) = mesh.validate() { log::warn!("after the flip: {bad}"); }`.
//! - [`Mesh::describe`] prints any element and its links in one line:
//!   `h4: from v1 to v2, twin h9, next h5, edge e2, face f1`.
//! - `log::info!` and `log::warn!` print in the lab's `file.rs:LINE [info]`
//!   format under the grader (see [`logging`]); the grader shows what your
//!   code printed under each case.
//! - Every walk is bounded: a broken `next` or `twin` makes it panic with a
//!   message instead of hanging.
//!
//! ## Modules
//! - [`mesh`]: the records and the arenas; [`ids`]: the ids.
//! - [`traverse`]: walks around faces and vertices.
//! - [`build`]: from indexed polygons, with an error for every bad input.
//! - [`obj`]: OBJ files in and out; [`shapes`]: the lab's objects and more.
//! - [`polygons`]: faces of any size: counts by degree, canonical face
//!   lists to compare meshes by, triangles to draw.
//! - [`validate`]: consistency checks; [`debug`]: describe, centre, normal.
//! - [`logging`]: the lab's `file.rs:LINE [info] message` log format.
//! - [`recording`]: the grader's step-through switch (off in normal use).

pub mod build;
pub mod debug;
pub mod ids;
pub mod logging;
pub mod mesh;
pub mod obj;
pub mod polygons;
pub mod recording;
pub mod shapes;
pub mod traverse;
pub mod validate;

pub use build::MeshError;
pub use glam::DVec3;
pub use ids::{EdgeId, Element, FaceId, HalfedgeId, Ids, VertexId};
pub use mesh::{Edge, Face, Halfedge, Mesh, Vertex};
pub use polygons::FaceDegrees;
pub use validate::{Check, Invalid};
