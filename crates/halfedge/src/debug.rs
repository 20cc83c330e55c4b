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

    /// The mean of the face's corners' positions, however many corners it
    /// has (not the centre of its area, which differs on an irregular
    /// polygon).
    #[track_caller]
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

    /// The face's area: half the length of Newell's vector area, so any
    /// planar polygon's exact area (a non-planar one's projected on its
    /// best plane); 0 for a degenerate face.
    #[track_caller]
    pub fn face_area(&self, f: FaceId) -> f64 {
        let corners = self.face_vertices(f);
        let mut n = DVec3::ZERO;
        for (i, &a) in corners.iter().enumerate() {
            let b = corners[(i + 1) % corners.len()];
            n += self[a].pos.cross(self[b].pos);
        }
        n.length() / 2.0
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

    /// A face's corners in one line, for polygons of any size:
    /// `f3: 4 corners v0 v1 v5 v4` (`f9, boundary: ...` for a hole), in the
    /// order of [`Mesh::face_vertices`].
    ///
    /// Unlike the walks, this never panics, so it can be logged on a mesh
    /// being rebuilt: an id that names nothing and a `next` walk that does
    /// not come back (bounded by the number of halfedges) are said in the
    /// line, e.g. `f3: the walk from h7 does not come back after 40 steps
    /// (v0 v1 v0 v1 ...): call mesh.validate()`.
    pub fn describe_corners(&self, f: FaceId) -> String {
        let (vertices, _, faces, halfedges) = self.records();
        let Some(face) = faces.get(f.index()) else {
            return format!("{f}: no such face (the mesh has {})", faces.len());
        };
        let head = if face.is_boundary {
            format!("{f}, boundary")
        } else {
            f.to_string()
        };
        let name = |v: VertexId| {
            if v.index() < vertices.len() {
                v.to_string()
            } else {
                format!("{v} (no such vertex)")
            }
        };
        // A broken walk names only its first corners: a line, not a page.
        let first = |corners: &[VertexId]| {
            let mut text: Vec<String> = corners.iter().take(8).map(|&v| name(v)).collect();
            if corners.len() > 8 {
                text.push("...".into());
            }
            if text.is_empty() {
                "none".into()
            } else {
                text.join(" ")
            }
        };
        let start = face.halfedge;
        let mut corners = Vec::new();
        let mut h = start;
        loop {
            let Some(record) = halfedges.get(h.index()) else {
                return format!(
                    "{head}: the walk from {start} reaches {h}, which names no halfedge \
                     (corners so far: {}): call mesh.validate()",
                    first(&corners)
                );
            };
            corners.push(record.vertex);
            h = record.next;
            if h == start {
                break;
            }
            if corners.len() >= halfedges.len() {
                return format!(
                    "{head}: the walk from {start} does not come back after {} steps \
                     (corners: {}): call mesh.validate()",
                    corners.len(),
                    first(&corners)
                );
            }
        }
        let all: Vec<String> = corners.iter().map(|&v| name(v)).collect();
        format!("{head}: {} corners {}", corners.len(), all.join(" "))
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
