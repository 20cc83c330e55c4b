//! Checking that a mesh's links are consistent.
//!
//! The checks and their messages follow Scotty3D's `Halfedge_Mesh::validate`,
//! word for word where they apply, plus a few for mistakes Scotty3D could
//! not make (unset ids) or did not look for. Every walk is bounded.

use std::fmt;

use crate::ids::{Element, FaceId, VertexId};
use crate::mesh::Mesh;

/// The first problem `validate()` found: the element and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Invalid {
    pub element: Element,
    pub message: String,
}

impl fmt::Display for Invalid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.message, self.element)
    }
}

impl std::error::Error for Invalid {}

fn fail(element: impl Into<Element>, message: &str) -> Result<(), Invalid> {
    Err(Invalid {
        element: element.into(),
        message: message.to_string(),
    })
}

impl Mesh {
    /// Returns the first problem with the mesh's connectivity, or `Ok(())`.
    pub fn validate(&self) -> Result<(), Invalid> {
        self.check_ids()?;
        self.check_permutation()?;
        self.check_twins()?;
        self.check_owners()?;
        self.check_orbits()?;
        self.check_shape()
    }

    /// Every id stored in the mesh names an element that exists.
    fn check_ids(&self) -> Result<(), Invalid> {
        let (nv, ne, nf, nh) = (
            self.num_vertices(),
            self.num_edges(),
            self.num_faces(),
            self.num_halfedges(),
        );
        for v in self.vertex_ids() {
            if !self[v].pos.is_finite() {
                return fail(v, "A vertex position was set to a non-finite value.");
            }
            if self[v].halfedge.index() >= nh {
                return fail(
                    v,
                    "A vertex's halfedge was never set (or names no halfedge)!",
                );
            }
        }
        for e in self.edge_ids() {
            if self[e].halfedge.index() >= nh {
                return fail(
                    e,
                    "An edge's halfedge was never set (or names no halfedge)!",
                );
            }
        }
        for f in self.face_ids() {
            if self[f].halfedge.index() >= nh {
                return fail(f, "A face's halfedge was never set (or names no halfedge)!");
            }
        }
        for h in self.halfedge_ids() {
            let r = self[h];
            if r.next.index() >= nh {
                return fail(h, "A halfedge's next was never set (or names no halfedge)!");
            }
            if r.twin.index() >= nh {
                return fail(h, "A halfedge's twin was never set (or names no halfedge)!");
            }
            if r.vertex.index() >= nv {
                return fail(h, "A halfedge's vertex was never set (or names no vertex)!");
            }
            if r.edge.index() >= ne {
                return fail(h, "A halfedge's edge was never set (or names no edge)!");
            }
            if r.face.index() >= nf {
                return fail(h, "A halfedge's face was never set (or names no face)!");
            }
        }
        Ok(())
    }

    /// `next` is a permutation: each halfedge follows exactly one other.
    /// Scotty3D also reports "A halfedge is the next of zero halfedges!", but
    /// with no erased halfedges that can only happen when some halfedge is
    /// the next of several (pigeonhole), which is reported first.
    fn check_permutation(&self) -> Result<(), Invalid> {
        let mut follows = vec![false; self.num_halfedges()];
        for h in self.halfedge_ids() {
            let n = self[h].next;
            if follows[n.index()] {
                return fail(h, "A halfedge is the next of multiple halfedges!");
            }
            follows[n.index()] = true;
        }
        Ok(())
    }

    fn check_twins(&self) -> Result<(), Invalid> {
        for h in self.halfedge_ids() {
            let t = self[h].twin;
            if t == h {
                return fail(h, "A halfedge's twin points to itself!");
            }
            if self[t].twin != h {
                return fail(h, "A halfedge's twin's twin is not itself!");
            }
        }
        Ok(())
    }

    /// Each vertex, edge and face points to a halfedge that points back.
    fn check_owners(&self) -> Result<(), Invalid> {
        for v in self.vertex_ids() {
            if self[self[v].halfedge].vertex != v {
                return fail(v, "A vertex's halfedge does not point to that vertex!");
            }
        }
        for e in self.edge_ids() {
            if self[self[e].halfedge].edge != e {
                return fail(e, "An edge's halfedge does not point to that edge!");
            }
        }
        for f in self.face_ids() {
            if self[self[f].halfedge].face != f {
                return fail(f, "A face's halfedge does not point to that face!");
            }
        }
        Ok(())
    }

    /// Walking around each element only meets halfedges that belong to it.
    /// These walks end: by now `next` is a permutation and `twin` an
    /// involution, so `next` and `twin`-then-`next` both cycle back.
    fn check_orbits(&self) -> Result<(), Invalid> {
        let mut reached = 0;
        for v in self.vertex_ids() {
            for h in self.vertex_halfedges(v) {
                if self[h].vertex != v {
                    return fail(h, "A halfedge does not point to its vertex!");
                }
                reached += 1;
            }
        }
        if reached != self.num_halfedges() {
            // Some halfedges start at a vertex but are not in its fan.
            let v = self
                .vertex_ids()
                .find(|&v| {
                    let fan = self.vertex_degree(v);
                    fan != self.halfedge_ids().filter(|&h| self[h].vertex == v).count()
                })
                .unwrap_or(VertexId(0));
            return fail(
                v,
                "A vertex's halfedges do not form a single fan around it (non-manifold vertex)!",
            );
        }
        for e in self.edge_ids() {
            let h = self[e].halfedge;
            let t = self[h].twin;
            // `h` itself points to `e` (check_owners), so look at its twin.
            if self[t].edge != e {
                return fail(t, "A halfedge does not point to its edge!");
            }
        }
        for f in self.face_ids() {
            for h in self.face_halfedges(f) {
                if self[h].face != f {
                    return fail(h, "A halfedge does not point to its face!");
                }
            }
        }
        Ok(())
    }

    /// Shapes the links allow but a surface cannot have.
    fn check_shape(&self) -> Result<(), Invalid> {
        for e in self.edge_ids() {
            let h = self[e].halfedge;
            if self[self[h].face].is_boundary && self[self[self[h].twin].face].is_boundary {
                return fail(e, "An edge has boundary faces on both sides!");
            }
        }
        for f in self.face_ids() {
            if self.face_degree(f) < 3 {
                return fail(f, "A face has fewer than three sides!");
            }
        }
        for h in self.halfedge_ids() {
            if self[h].vertex == self.halfedge_dst(h) {
                return fail(h, "A halfedge starts and ends at the same vertex!");
            }
        }
        // `last_face[v]` is the last face seen at v: one pass over all faces.
        let mut last_face = vec![FaceId::NONE; self.num_vertices()];
        for f in self.face_ids() {
            for v in self.face_vertices(f) {
                if last_face[v.index()] == f {
                    return fail(f, "A face visits the same vertex more than once!");
                }
                last_face[v.index()] = f;
            }
        }
        // Two edges joining the same pair of vertices.
        let mut seen = std::collections::HashSet::new();
        for e in self.edge_ids() {
            let (a, b) = self.edge_vertices(e);
            if !seen.insert((a.min(b), a.max(b))) {
                return fail(e, "Two edges join the same pair of vertices!");
            }
        }
        Ok(())
    }
}
