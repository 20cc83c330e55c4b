//! Faces of any size: counting them by degree, listing them in a form two
//! meshes can be compared by, and cutting them into triangles for drawing.
//!
//! The mesh itself holds polygons of any size (the Loop lab's are all
//! triangles; Catmull-Clark subdivision makes quads of anything). Every
//! function here walks each face once with the bounded walks of
//! [`crate::traverse`], so a broken `next` panics with a message instead of
//! hanging. Boundary faces (holes) are left out everywhere: they are not
//! polygons of the surface.

use std::collections::BTreeMap;
use std::fmt;

use crate::ids::FaceId;
use crate::mesh::Mesh;

/// How many real faces a mesh has of each degree (number of sides).
///
/// `Display` gives a line for people: `6 quads`, `2 triangles, 4 quads,
/// 2 pentagons`, `1 face of 7 sides`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FaceDegrees {
    /// Degree to number of real faces of that degree; no zero counts.
    pub counts: BTreeMap<usize, usize>,
}

impl FaceDegrees {
    /// The number of real faces with `degree` sides.
    pub fn of(&self, degree: usize) -> usize {
        self.counts.get(&degree).copied().unwrap_or(0)
    }

    /// The number of real faces.
    pub fn faces(&self) -> usize {
        self.counts.values().sum()
    }

    /// The sum of the real faces' degrees: their corners, which is also the
    /// number of halfedges inside real faces. One round of Catmull-Clark
    /// subdivision makes one quad per corner.
    pub fn corners(&self) -> usize {
        self.counts.iter().map(|(d, n)| d * n).sum()
    }

    /// Whether every real face has `degree` sides (true of a mesh with no
    /// real faces).
    pub fn all(&self, degree: usize) -> bool {
        self.counts.keys().all(|&d| d == degree)
    }
}

/// The name of a face of `degree` sides, singular or plural.
fn polygon_name(degree: usize, plural: bool) -> String {
    let name = match degree {
        3 => "triangle",
        4 => "quad",
        5 => "pentagon",
        6 => "hexagon",
        _ if plural => return format!("faces of {degree} sides"),
        _ => return format!("face of {degree} sides"),
    };
    if plural {
        format!("{name}s")
    } else {
        name.to_string()
    }
}

impl fmt::Display for FaceDegrees {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.counts.is_empty() {
            return write!(f, "no faces");
        }
        let parts: Vec<String> = self
            .counts
            .iter()
            .map(|(&d, &n)| format!("{n} {}", polygon_name(d, n != 1)))
            .collect();
        write!(f, "{}", parts.join(", "))
    }
}

impl Mesh {
    /// How many real faces have each degree (see [`FaceDegrees`]).
    #[track_caller]
    pub fn face_degrees(&self) -> FaceDegrees {
        let mut counts = BTreeMap::new();
        for f in self.real_face_ids() {
            *counts.entry(self.face_degree(f)).or_insert(0) += 1;
        }
        FaceDegrees { counts }
    }

    /// Whether every real face is a quad.
    #[track_caller]
    pub fn is_quad_mesh(&self) -> bool {
        self.first_non_quad().is_none()
    }

    /// The first real face (lowest id) that is not a quad, if any.
    #[track_caller]
    pub fn first_non_quad(&self) -> Option<FaceId> {
        self.first_face_not_of_degree(4)
    }

    /// The first real face (lowest id) that does not have `degree` sides.
    #[track_caller]
    pub fn first_face_not_of_degree(&self, degree: usize) -> Option<FaceId> {
        self.real_face_ids()
            .into_iter()
            .find(|&f| self.face_degree(f) != degree)
    }

    /// The ids of the real faces that exist now, holes left out, in id
    /// order. A list, not a borrow: the loop over it may change the mesh.
    pub fn real_face_ids(&self) -> Vec<FaceId> {
        self.face_ids().filter(|&f| !self[f].is_boundary).collect()
    }

    /// The real faces as lists of vertex indices in a form that does not
    /// depend on face ids or on where each face's walk starts: each face in
    /// its winding order, turned to start at its smallest index, and the
    /// list sorted. Two meshes whose vertices are numbered alike have the
    /// same polygons, wound the same way, exactly when these are equal.
    #[track_caller]
    pub fn canonical_faces(&self) -> Vec<Vec<usize>> {
        let mut faces: Vec<Vec<usize>> = self
            .real_face_ids()
            .into_iter()
            .map(|f| {
                let mut corners: Vec<usize> = self
                    .face_vertices(f)
                    .into_iter()
                    .map(|v| v.index())
                    .collect();
                let smallest = (0..corners.len())
                    .min_by_key(|&i| corners[i])
                    .expect("a face has corners");
                corners.rotate_left(smallest);
                corners
            })
            .collect();
        faces.sort_unstable();
        faces
    }

    /// The real faces cut into triangles for drawing, as vertex indices: a
    /// face of n corners `c0, c1, ..., c(n-1)` (its [`Mesh::face_vertices`])
    /// gives the fan `(c0, c1, c2), (c0, c2, c3), ...`, n - 2 triangles
    /// wound like the face, faces in id order. Exact for convex faces, as
    /// every lab mesh has; a fan across a non-convex face may overlap.
    #[track_caller]
    pub fn to_triangles(&self) -> Vec<[usize; 3]> {
        let mut out = Vec::new();
        for f in self.real_face_ids() {
            let c: Vec<usize> = self
                .face_vertices(f)
                .into_iter()
                .map(|v| v.index())
                .collect();
            for k in 1..c.len().saturating_sub(1) {
                out.push([c[0], c[k], c[k + 1]]);
            }
        }
        out
    }
}
