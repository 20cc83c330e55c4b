//! A catalogue entry and the builder entries are made with: the model
//! solution with some of its three functions replaced.

use grader::Implementation;
use halfedge::{EdgeId, Mesh, VertexId};

use crate::solution;

/// One implementation in the catalogue.
pub struct Entry {
    pub name: &'static str,
    /// What it does wrong (or how it differs, for the correct ones).
    pub what: &'static str,
    pub imp: Implementation,
}

impl Entry {
    pub fn new(name: &'static str, what: &'static str, imp: Build) -> Entry {
        Entry {
            name,
            what,
            imp: imp.0,
        }
    }
}

/// An implementation being put together: `model().flip(f).subdivide(s)`
/// is the model solution with its `flip_edge` and `loop_subdivide`
/// replaced.
pub struct Build(Implementation);

/// The model solution, to replace functions of.
pub fn model() -> Build {
    Build(Implementation {
        flip_edge: solution::flip_edge,
        split_edge: solution::split_edge,
        loop_subdivide: solution::loop_subdivide,
    })
}

impl Build {
    pub fn flip(mut self, f: fn(&mut Mesh, EdgeId) -> Option<EdgeId>) -> Build {
        self.0.flip_edge = f;
        self
    }

    pub fn split(mut self, f: fn(&mut Mesh, EdgeId) -> Option<VertexId>) -> Build {
        self.0.split_edge = f;
        self
    }

    pub fn subdivide(mut self, f: fn(&mut Mesh)) -> Build {
        self.0.loop_subdivide = f;
        self
    }

    /// The implementation put together.
    pub fn done(self) -> Implementation {
        self.0
    }
}
