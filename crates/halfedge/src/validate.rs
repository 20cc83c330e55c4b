//! Checking that a mesh's links are consistent.
//!
//! The checks and their messages follow Scotty3D's `Halfedge_Mesh::validate`,
//! word for word where they apply, plus a few for mistakes Scotty3D could
//! not make (unset ids) or did not look for. Every walk is bounded.

use std::fmt;

use crate::ids::{Element, FaceId, VertexId};
use crate::mesh::Mesh;

/// Which of `validate()`'s checks failed: the fact a program decides by
/// (the message is for people and may be reworded; the check is not).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Check {
    /// `A vertex position was set to a non-finite value.`
    VertexPositionNotFinite,
    /// `A vertex's halfedge was never set (or names no halfedge)!`
    VertexHalfedgeUnset,
    /// `An edge's halfedge was never set (or names no halfedge)!`
    EdgeHalfedgeUnset,
    /// `A face's halfedge was never set (or names no halfedge)!`
    FaceHalfedgeUnset,
    /// `A halfedge's next was never set (or names no halfedge)!`
    NextUnset,
    /// `A halfedge's twin was never set (or names no halfedge)!`
    TwinUnset,
    /// `A halfedge's vertex was never set (or names no vertex)!`
    HalfedgeVertexUnset,
    /// `A halfedge's edge was never set (or names no edge)!`
    HalfedgeEdgeUnset,
    /// `A halfedge's face was never set (or names no face)!`
    HalfedgeFaceUnset,
    /// `A halfedge is the next of multiple halfedges!`
    NextOfSeveral,
    /// `A halfedge's twin points to itself!`
    TwinIsSelf,
    /// `A halfedge's twin's twin is not itself!`
    TwinNotMutual,
    /// `A vertex's halfedge does not point to that vertex!`
    VertexHalfedgeElsewhere,
    /// `An edge's halfedge does not point to that edge!`
    EdgeHalfedgeElsewhere,
    /// `A face's halfedge does not point to that face!`
    FaceHalfedgeElsewhere,
    /// `A halfedge does not point to its vertex!`
    HalfedgeNotItsVertex,
    /// `A vertex's halfedges do not form a single fan around it (non-manifold vertex)!`
    VertexNotOneFan,
    /// `A halfedge does not point to its edge!`
    HalfedgeNotItsEdge,
    /// `A halfedge does not point to its face!`
    HalfedgeNotItsFace,
    /// `An edge has boundary faces on both sides!`
    EdgeBoundaryBothSides,
    /// `A face has fewer than three sides!`
    FaceTooFewSides,
    /// `A halfedge starts and ends at the same vertex!`
    HalfedgeLoop,
    /// `A face visits the same vertex more than once!`
    FaceRepeatsVertex,
    /// `Two edges join the same pair of vertices!`
    DuplicateEdge,
}

impl Check {
    /// Every check, in the order `validate()` runs them.
    pub const ALL: [Check; 24] = [
        Check::VertexPositionNotFinite,
        Check::VertexHalfedgeUnset,
        Check::EdgeHalfedgeUnset,
        Check::FaceHalfedgeUnset,
        Check::NextUnset,
        Check::TwinUnset,
        Check::HalfedgeVertexUnset,
        Check::HalfedgeEdgeUnset,
        Check::HalfedgeFaceUnset,
        Check::NextOfSeveral,
        Check::TwinIsSelf,
        Check::TwinNotMutual,
        Check::VertexHalfedgeElsewhere,
        Check::EdgeHalfedgeElsewhere,
        Check::FaceHalfedgeElsewhere,
        Check::HalfedgeNotItsVertex,
        Check::VertexNotOneFan,
        Check::HalfedgeNotItsEdge,
        Check::HalfedgeNotItsFace,
        Check::EdgeBoundaryBothSides,
        Check::FaceTooFewSides,
        Check::HalfedgeLoop,
        Check::FaceRepeatsVertex,
        Check::DuplicateEdge,
    ];

    /// The message `validate()` gives (Scotty3D's words where they apply).
    pub fn message(self) -> &'static str {
        match self {
            Check::VertexPositionNotFinite => "A vertex position was set to a non-finite value.",
            Check::VertexHalfedgeUnset => {
                "A vertex's halfedge was never set (or names no halfedge)!"
            }
            Check::EdgeHalfedgeUnset => "An edge's halfedge was never set (or names no halfedge)!",
            Check::FaceHalfedgeUnset => "A face's halfedge was never set (or names no halfedge)!",
            Check::NextUnset => "A halfedge's next was never set (or names no halfedge)!",
            Check::TwinUnset => "A halfedge's twin was never set (or names no halfedge)!",
            Check::HalfedgeVertexUnset => "A halfedge's vertex was never set (or names no vertex)!",
            Check::HalfedgeEdgeUnset => "A halfedge's edge was never set (or names no edge)!",
            Check::HalfedgeFaceUnset => "A halfedge's face was never set (or names no face)!",
            Check::NextOfSeveral => "A halfedge is the next of multiple halfedges!",
            Check::TwinIsSelf => "A halfedge's twin points to itself!",
            Check::TwinNotMutual => "A halfedge's twin's twin is not itself!",
            Check::VertexHalfedgeElsewhere => "A vertex's halfedge does not point to that vertex!",
            Check::EdgeHalfedgeElsewhere => "An edge's halfedge does not point to that edge!",
            Check::FaceHalfedgeElsewhere => "A face's halfedge does not point to that face!",
            Check::HalfedgeNotItsVertex => "A halfedge does not point to its vertex!",
            Check::VertexNotOneFan => {
                "A vertex's halfedges do not form a single fan around it (non-manifold vertex)!"
            }
            Check::HalfedgeNotItsEdge => "A halfedge does not point to its edge!",
            Check::HalfedgeNotItsFace => "A halfedge does not point to its face!",
            Check::EdgeBoundaryBothSides => "An edge has boundary faces on both sides!",
            Check::FaceTooFewSides => "A face has fewer than three sides!",
            Check::HalfedgeLoop => "A halfedge starts and ends at the same vertex!",
            Check::FaceRepeatsVertex => "A face visits the same vertex more than once!",
            Check::DuplicateEdge => "Two edges join the same pair of vertices!",
        }
    }

    /// A stable name for data (JSON, fixtures): kebab-case, never reworded.
    pub fn key(self) -> &'static str {
        match self {
            Check::VertexPositionNotFinite => "vertex-position-not-finite",
            Check::VertexHalfedgeUnset => "vertex-halfedge-unset",
            Check::EdgeHalfedgeUnset => "edge-halfedge-unset",
            Check::FaceHalfedgeUnset => "face-halfedge-unset",
            Check::NextUnset => "next-unset",
            Check::TwinUnset => "twin-unset",
            Check::HalfedgeVertexUnset => "halfedge-vertex-unset",
            Check::HalfedgeEdgeUnset => "halfedge-edge-unset",
            Check::HalfedgeFaceUnset => "halfedge-face-unset",
            Check::NextOfSeveral => "next-of-several",
            Check::TwinIsSelf => "twin-is-self",
            Check::TwinNotMutual => "twin-not-mutual",
            Check::VertexHalfedgeElsewhere => "vertex-halfedge-elsewhere",
            Check::EdgeHalfedgeElsewhere => "edge-halfedge-elsewhere",
            Check::FaceHalfedgeElsewhere => "face-halfedge-elsewhere",
            Check::HalfedgeNotItsVertex => "halfedge-not-its-vertex",
            Check::VertexNotOneFan => "vertex-not-one-fan",
            Check::HalfedgeNotItsEdge => "halfedge-not-its-edge",
            Check::HalfedgeNotItsFace => "halfedge-not-its-face",
            Check::EdgeBoundaryBothSides => "edge-boundary-both-sides",
            Check::FaceTooFewSides => "face-too-few-sides",
            Check::HalfedgeLoop => "halfedge-loop",
            Check::FaceRepeatsVertex => "face-repeats-vertex",
            Check::DuplicateEdge => "duplicate-edge",
        }
    }

    /// The check whose [`Check::message`] is `text`, for data that stored
    /// the message (fixtures record a mistake's `validate()` message).
    pub fn from_message(text: &str) -> Option<Check> {
        Check::ALL.into_iter().find(|c| c.message() == text)
    }

    /// The check whose [`Check::key`] is `key`.
    pub fn from_key(key: &str) -> Option<Check> {
        Check::ALL.into_iter().find(|c| c.key() == key)
    }
}

/// The first problem `validate()` found: the element, which check failed
/// and its message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Invalid {
    pub element: Element,
    pub check: Check,
    pub message: String,
}

impl fmt::Display for Invalid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.message, self.element)
    }
}

impl std::error::Error for Invalid {}

fn fail(element: impl Into<Element>, check: Check) -> Result<(), Invalid> {
    Err(Invalid {
        element: element.into(),
        check,
        message: check.message().to_string(),
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
                return fail(v, Check::VertexPositionNotFinite);
            }
            if self[v].halfedge.index() >= nh {
                return fail(v, Check::VertexHalfedgeUnset);
            }
        }
        for e in self.edge_ids() {
            if self[e].halfedge.index() >= nh {
                return fail(e, Check::EdgeHalfedgeUnset);
            }
        }
        for f in self.face_ids() {
            if self[f].halfedge.index() >= nh {
                return fail(f, Check::FaceHalfedgeUnset);
            }
        }
        for h in self.halfedge_ids() {
            let r = self[h];
            if r.next.index() >= nh {
                return fail(h, Check::NextUnset);
            }
            if r.twin.index() >= nh {
                return fail(h, Check::TwinUnset);
            }
            if r.vertex.index() >= nv {
                return fail(h, Check::HalfedgeVertexUnset);
            }
            if r.edge.index() >= ne {
                return fail(h, Check::HalfedgeEdgeUnset);
            }
            if r.face.index() >= nf {
                return fail(h, Check::HalfedgeFaceUnset);
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
                return fail(h, Check::NextOfSeveral);
            }
            follows[n.index()] = true;
        }
        Ok(())
    }

    fn check_twins(&self) -> Result<(), Invalid> {
        for h in self.halfedge_ids() {
            let t = self[h].twin;
            if t == h {
                return fail(h, Check::TwinIsSelf);
            }
            if self[t].twin != h {
                return fail(h, Check::TwinNotMutual);
            }
        }
        Ok(())
    }

    /// Each vertex, edge and face points to a halfedge that points back.
    fn check_owners(&self) -> Result<(), Invalid> {
        for v in self.vertex_ids() {
            if self[self[v].halfedge].vertex != v {
                return fail(v, Check::VertexHalfedgeElsewhere);
            }
        }
        for e in self.edge_ids() {
            if self[self[e].halfedge].edge != e {
                return fail(e, Check::EdgeHalfedgeElsewhere);
            }
        }
        for f in self.face_ids() {
            if self[self[f].halfedge].face != f {
                return fail(f, Check::FaceHalfedgeElsewhere);
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
                    return fail(h, Check::HalfedgeNotItsVertex);
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
            return fail(v, Check::VertexNotOneFan);
        }
        for e in self.edge_ids() {
            let h = self[e].halfedge;
            let t = self[h].twin;
            // `h` itself points to `e` (check_owners), so look at its twin.
            if self[t].edge != e {
                return fail(t, Check::HalfedgeNotItsEdge);
            }
        }
        for f in self.face_ids() {
            for h in self.face_halfedges(f) {
                if self[h].face != f {
                    return fail(h, Check::HalfedgeNotItsFace);
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
                return fail(e, Check::EdgeBoundaryBothSides);
            }
        }
        for f in self.face_ids() {
            if self.face_degree(f) < 3 {
                return fail(f, Check::FaceTooFewSides);
            }
        }
        for h in self.halfedge_ids() {
            if self[h].vertex == self.halfedge_dst(h) {
                return fail(h, Check::HalfedgeLoop);
            }
        }
        // `last_face[v]` is the last face seen at v: one pass over all faces.
        let mut last_face = vec![FaceId::NONE; self.num_vertices()];
        for f in self.face_ids() {
            for v in self.face_vertices(f) {
                if last_face[v.index()] == f {
                    return fail(f, Check::FaceRepeatsVertex);
                }
                last_face[v.index()] = f;
            }
        }
        // Two edges joining the same pair of vertices.
        let mut seen = std::collections::HashSet::new();
        for e in self.edge_ids() {
            let (a, b) = self.edge_vertices(e);
            if !seen.insert((a.min(b), a.max(b))) {
                return fail(e, Check::DuplicateEdge);
            }
        }
        Ok(())
    }
}
