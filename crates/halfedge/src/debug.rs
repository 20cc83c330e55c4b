//! Debugging helpers, as in the lab: describe an element, find its centre,
//! its normal. Handy in `log::info!` lines while you work on an operation.

use glam::DVec3;

use crate::ids::{EdgeId, Element, FaceId, HalfedgeId, VertexId};
use crate::mesh::Mesh;

impl Mesh {
    /// A one-line description of any element and its links, e.g.
    /// `h4: from v1 to v2, twin h9, next h5, edge e2, face f1`.
    pub fn describe(&self, element: impl Into<Element>) -> String {
        match element.into() {
            Element::Vertex(v) => {
                let r = self[v];
                format!(
                    "{v}: at ({}, {}, {}), halfedge {}, new_pos ({}, {}, {}), is_new {}",
                    r.pos.x,
                    r.pos.y,
                    r.pos.z,
                    r.halfedge,
                    r.new_pos.x,
                    r.new_pos.y,
                    r.new_pos.z,
                    r.is_new
                )
            }
            Element::Edge(e) => {
                let r = self[e];
                let h = r.halfedge;
                format!(
                    "{e}: halfedges {h} and {}, joins {} and {}, is_new {}",
                    self[h].twin, self[h].vertex, self[self[h].twin].vertex, r.is_new
                )
            }
            Element::Face(f) => {
                let r = self[f];
                format!(
                    "{f}: {}halfedge {}",
                    if r.is_boundary { "boundary, " } else { "" },
                    r.halfedge
                )
            }
            Element::Halfedge(h) => {
                let r = self[h];
                format!(
                    "{h}: from {} to {}, twin {}, next {}, edge {}, face {}",
                    r.vertex, self[r.twin].vertex, r.twin, r.next, r.edge, r.face
                )
            }
        }
    }

    /// The average of the face's corners.
    pub fn face_center(&self, f: FaceId) -> DVec3 {
        let corners = self.face_vertices(f);
        corners.iter().map(|&v| self[v].pos).sum::<DVec3>() / corners.len() as f64
    }

    /// The face's unit normal (Newell's method, so it works for any polygon);
    /// zero for a degenerate face.
    pub fn face_normal(&self, f: FaceId) -> DVec3 {
        let corners = self.face_vertices(f);
        let mut n = DVec3::ZERO;
        for (i, &a) in corners.iter().enumerate() {
            let b = corners[(i + 1) % corners.len()];
            n += self[a].pos.cross(self[b].pos);
        }
        n.normalize_or_zero()
    }

    /// The midpoint of the edge.
    pub fn edge_center(&self, e: EdgeId) -> DVec3 {
        let (a, b) = self.edge_vertices(e);
        (self[a].pos + self[b].pos) / 2.0
    }

    /// The midpoint of the halfedge's edge.
    pub fn halfedge_center(&self, h: HalfedgeId) -> DVec3 {
        self.edge_center(self[h].edge)
    }

    /// The area-weighted average of the normals of the real faces at `v`.
    pub fn vertex_normal(&self, v: VertexId) -> DVec3 {
        let mut n = DVec3::ZERO;
        for h in self.vertex_halfedges(v) {
            let f = self[h].face;
            if !self[f].is_boundary {
                let a = self[v].pos;
                let b = self[self.halfedge_dst(h)].pos;
                let c = self[self.halfedge_dst(self[h].next)].pos;
                n += (b - a).cross(c - a);
            }
        }
        n.normalize_or_zero()
    }
}
