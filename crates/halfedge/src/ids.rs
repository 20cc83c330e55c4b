//! Typed element ids.
//!
//! An id is an index into one of the mesh's arenas. Each kind has its own type,
//! so a `VertexId` can never be used where an `EdgeId` is meant, and each prints
//! with a letter (`v12`, `e7`, `f3`, `h40`) so a log line says what it names.

use std::fmt;

macro_rules! define_id {
    ($(#[$doc:meta])* $name:ident, $letter:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub u32);

        impl $name {
            /// The id of nothing: what a freshly created element points to
            /// until you set it. `validate()` reports any that remain.
            pub const NONE: $name = $name(u32::MAX);

            /// The position of this element in its arena.
            pub fn index(self) -> usize {
                self.0 as usize
            }

            /// The id of the element at `index` in its arena.
            ///
            /// # Panics
            /// If `index` does not fit in a `u32`: no lab mesh comes near that.
            pub fn from_index(index: usize) -> Self {
                $name(u32::try_from(index).expect("element index does not fit in u32"))
            }

            /// Whether this is [`Self::NONE`].
            pub fn is_none(self) -> bool {
                self == Self::NONE
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                if self.is_none() {
                    write!(f, concat!($letter, "-none"))
                } else {
                    write!(f, concat!($letter, "{}"), self.0)
                }
            }
        }

        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                fmt::Display::fmt(self, f)
            }
        }
    };
}

define_id!(
    /// Names a vertex: `mesh[v].pos` is its position.
    VertexId,
    "v"
);
define_id!(
    /// Names an (undirected) edge: the pair of halfedges `mesh[e].halfedge`
    /// and its twin.
    EdgeId,
    "e"
);
define_id!(
    /// Names a face, either a real polygon or a boundary loop (a hole).
    FaceId,
    "f"
);
define_id!(
    /// Names a halfedge: one side of an edge, directed, inside one face.
    HalfedgeId,
    "h"
);

/// Any element of the mesh, for messages that may name any kind.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Element {
    Vertex(VertexId),
    Edge(EdgeId),
    Face(FaceId),
    Halfedge(HalfedgeId),
}

impl fmt::Display for Element {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Element::Vertex(v) => write!(f, "{v}"),
            Element::Edge(e) => write!(f, "{e}"),
            Element::Face(x) => write!(f, "{x}"),
            Element::Halfedge(h) => write!(f, "{h}"),
        }
    }
}

impl From<VertexId> for Element {
    fn from(v: VertexId) -> Self {
        Element::Vertex(v)
    }
}
impl From<EdgeId> for Element {
    fn from(e: EdgeId) -> Self {
        Element::Edge(e)
    }
}
impl From<FaceId> for Element {
    fn from(f: FaceId) -> Self {
        Element::Face(f)
    }
}
impl From<HalfedgeId> for Element {
    fn from(h: HalfedgeId) -> Self {
        Element::Halfedge(h)
    }
}

/// The ids `0..len` of one kind, as an owned iterator: looping over it holds
/// no borrow of the mesh, so the loop body may add and change elements.
#[derive(Clone, Debug)]
pub struct Ids<T> {
    next: u32,
    end: u32,
    make: fn(u32) -> T,
}

impl<T> Ids<T> {
    pub(crate) fn new(len: usize, make: fn(u32) -> T) -> Self {
        let end = u32::try_from(len).expect("arena larger than u32");
        Ids { next: 0, end, make }
    }
}

impl<T> Iterator for Ids<T> {
    type Item = T;
    fn next(&mut self) -> Option<T> {
        if self.next < self.end {
            self.next += 1;
            Some((self.make)(self.next - 1))
        } else {
            None
        }
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = (self.end - self.next) as usize;
        (n, Some(n))
    }
}

impl<T> ExactSizeIterator for Ids<T> {}
