//! Walking the mesh: around a face, around a vertex, across an edge.
//!
//! Every walk is bounded by the number of halfedges, so a broken `next` or
//! `twin` link makes it panic with a message instead of looping forever.
//!
//! Which way the walks turn: around a face, `next` follows the face's own
//! winding (counter-clockwise seen from the side the faces are wound
//! counter-clockwise from, which for a mesh facing outwards is outside).
//! Around a vertex, [`Mesh::vertex_halfedges`] turns the *other* way:
//! clockwise seen from that same side. [`Mesh::prev`] steps backwards around
//! a face, and so gives the way to turn around a vertex the other way.

use crate::ids::{EdgeId, FaceId, HalfedgeId, VertexId};
use crate::mesh::Mesh;

impl Mesh {
    /// Follows `step` from `start` until it comes back, calling `visit` on
    /// every halfedge on the way (`start` first). Allocates nothing: the
    /// counting walks (degrees, `prev`, `find_edge`) are in every inner loop
    /// of subdivision. `around` names the walk, built only for the panic.
    #[inline]
    #[track_caller]
    fn walk(
        &self,
        start: HalfedgeId,
        step: impl Fn(HalfedgeId) -> HalfedgeId,
        around: impl FnOnce() -> String,
        mut visit: impl FnMut(HalfedgeId),
    ) {
        let limit = self.num_halfedges();
        visit(start);
        let mut seen = 1;
        let mut h = step(start);
        while h != start {
            if seen > limit {
                never_came_back(&around());
            }
            visit(h);
            seen += 1;
            h = step(h);
        }
    }

    /// Follows `step` from `start` until it comes back, collecting every
    /// halfedge on the way (`start` first).
    #[track_caller]
    fn orbit(
        &self,
        start: HalfedgeId,
        step: impl Fn(HalfedgeId) -> HalfedgeId,
        around: impl FnOnce() -> String,
    ) -> Vec<HalfedgeId> {
        let mut out = Vec::with_capacity(8);
        self.walk(start, step, around, |h| out.push(h));
        out
    }

    /// The number of halfedges `step` visits from `start` until it comes back.
    #[inline]
    #[track_caller]
    fn orbit_len(
        &self,
        start: HalfedgeId,
        step: impl Fn(HalfedgeId) -> HalfedgeId,
        around: impl FnOnce() -> String,
    ) -> usize {
        let mut n = 0;
        self.walk(start, step, around, |_| n += 1);
        n
    }

    /// The halfedges around face `f`, following `next` (the face's own
    /// winding), starting with `mesh[f].halfedge`.
    #[track_caller]
    pub fn face_halfedges(&self, f: FaceId) -> Vec<HalfedgeId> {
        self.orbit(self[f].halfedge, |h| self[h].next, || f.to_string())
    }

    /// The vertices of face `f` in order.
    #[track_caller]
    pub fn face_vertices(&self, f: FaceId) -> Vec<VertexId> {
        self.face_halfedges(f)
            .into_iter()
            .map(|h| self[h].vertex)
            .collect()
    }

    /// The number of sides of face `f` (3 for a triangle).
    #[track_caller]
    pub fn face_degree(&self, f: FaceId) -> usize {
        self.orbit_len(self[f].halfedge, |h| self[h].next, || f.to_string())
    }

    /// The edges around face `f`, in the order of [`Mesh::face_halfedges`]:
    /// the edge of `mesh[f].halfedge` first.
    #[track_caller]
    pub fn face_edges(&self, f: FaceId) -> Vec<EdgeId> {
        self.face_halfedges(f)
            .into_iter()
            .map(|h| self[h].edge)
            .collect()
    }

    /// The halfedges that start at `v`, one per incident edge, starting with
    /// `mesh[v].halfedge` and turning by `twin` then `next`.
    ///
    /// Each step goes from `h` to `mesh[mesh[h].twin].next`: into the face on
    /// the far side of `h` (the face of its twin), whose next halfedge out of
    /// `v` comes after `h` going **clockwise** seen from the side the faces
    /// are counter-clockwise from. On a mesh that faces outwards that is
    /// clockwise seen from outside; on the lab's `cube.obj`, which is wound
    /// the other way, it is counter-clockwise seen from outside. To turn the
    /// other way, step with `mesh[mesh.prev(h)].twin`.
    ///
    /// On a boundary vertex the walk passes through the hole's face like any
    /// other face, so it still visits every edge at `v`.
    #[track_caller]
    pub fn vertex_halfedges(&self, v: VertexId) -> Vec<HalfedgeId> {
        self.orbit(
            self[v].halfedge,
            |h| self[self[h].twin].next,
            || v.to_string(),
        )
    }

    /// The vertices joined to `v` by an edge, in the order of
    /// [`Mesh::vertex_halfedges`].
    #[track_caller]
    pub fn vertex_neighbors(&self, v: VertexId) -> Vec<VertexId> {
        self.vertex_halfedges(v)
            .into_iter()
            .map(|h| self.halfedge_dst(h))
            .collect()
    }

    /// The faces around `v`, one per halfedge leaving it, in the order of
    /// [`Mesh::vertex_halfedges`] (the face of each halfedge). On a boundary
    /// vertex the hole's face is among them, once: keep the real ones with
    /// `.filter(|&f| !mesh[f].is_boundary)`. An interior vertex has as many
    /// faces as edges; a boundary vertex one real face fewer.
    #[track_caller]
    pub fn vertex_faces(&self, v: VertexId) -> Vec<FaceId> {
        self.vertex_halfedges(v)
            .into_iter()
            .map(|h| self[h].face)
            .collect()
    }

    /// The number of edges at `v` (boundary edges included).
    #[track_caller]
    pub fn vertex_degree(&self, v: VertexId) -> usize {
        self.orbit_len(
            self[v].halfedge,
            |h| self[self[h].twin].next,
            || v.to_string(),
        )
    }

    /// Whether `v` lies on a hole: one of the faces around it is a boundary face.
    #[track_caller]
    pub fn vertex_on_boundary(&self, v: VertexId) -> bool {
        // The whole walk, as `vertex_halfedges` would: a broken mesh panics
        // the same way whatever the answer.
        let mut on = false;
        self.walk(
            self[v].halfedge,
            |h| self[self[h].twin].next,
            || v.to_string(),
            |h| on |= self[self[h].face].is_boundary,
        );
        on
    }

    /// Whether edge `e` borders a hole.
    #[inline]
    #[track_caller]
    pub fn edge_on_boundary(&self, e: EdgeId) -> bool {
        let h = self[e].halfedge;
        self[self[h].face].is_boundary || self[self[self[h].twin].face].is_boundary
    }

    /// The two ends of edge `e`: first the start of `mesh[e].halfedge`.
    #[inline]
    #[track_caller]
    pub fn edge_vertices(&self, e: EdgeId) -> (VertexId, VertexId) {
        let h = self[e].halfedge;
        (self[h].vertex, self.halfedge_dst(h))
    }

    /// The halfedge before `h` around its face: the one whose `next` is `h`.
    ///
    /// A halfedge stores only `next`, so this walks once around the face
    /// (3 steps in a triangle, more around a hole) and, like every walk here,
    /// panics with a message rather than loop if the face's `next` links never
    /// come back to `h`. Useful where a link *into* `h` must change, e.g. when
    /// a boundary split inserts a halfedge into a hole's loop before `t`:
    /// `let before = mesh.prev(t); mesh[before].next = new_halfedge;`.
    ///
    /// Around a vertex, `mesh[mesh.prev(h)].twin` is the halfedge out of the
    /// same vertex that comes just *before* `h` in
    /// [`Mesh::vertex_halfedges`]: one step of that walk, backwards.
    #[track_caller]
    pub fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        let mut last = h;
        self.walk(
            h,
            |g| self[g].next,
            || format!("the face of {h}"),
            |g| last = g,
        );
        last
    }

    /// The vertex halfedge `h` points to (where its twin starts).
    #[inline]
    #[track_caller]
    pub fn halfedge_dst(&self, h: HalfedgeId) -> VertexId {
        self[self[h].twin].vertex
    }

    /// The edge joining `a` and `b`, if there is one.
    #[track_caller]
    pub fn find_edge(&self, a: VertexId, b: VertexId) -> Option<EdgeId> {
        // The whole walk, first match kept: a broken mesh panics the same way
        // whether or not the edge comes early.
        let mut found = None;
        self.walk(
            self[a].halfedge,
            |h| self[self[h].twin].next,
            || a.to_string(),
            |h| {
                if found.is_none() && self.halfedge_dst(h) == b {
                    found = Some(h);
                }
            },
        );
        found.map(|h| self[h].edge)
    }
}

#[cold]
#[inline(never)]
#[track_caller]
fn never_came_back(around: &str) -> ! {
    panic!(
        "the walk around {around} never came back to where it started: \
         the mesh's links are broken (call mesh.validate() to find where) (found by the \
         mesh library's walk, {}:{})",
        file!(),
        line!()
    );
}
