//! An element a line of a report is about, as data ([`Named`]), in the
//! case's numbering and the labelling's, with its JSON form: what the
//! verdict's lines and the step-through's findings both name.

use halfedge::Element;
use serde::{Serialize, Serializer};

/// Serialises an [`Element`] as `{"kind": "vertex", "id": 3}`.
fn element_json<S: Serializer>(e: &Element, s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeStruct;
    let (kind, id) = element_parts(*e);
    let mut st = s.serialize_struct("Element", 2)?;
    st.serialize_field("kind", kind)?;
    st.serialize_field("id", &id)?;
    st.end()
}

fn opt_element_json<S: Serializer>(e: &Option<Element>, s: S) -> Result<S::Ok, S::Error> {
    match e {
        Some(e) => element_json(e, s),
        None => s.serialize_none(),
    }
}

/// An element's kind (`vertex`, `edge`, `face`, `halfedge`) and index.
pub fn element_parts(e: Element) -> (&'static str, u32) {
    match e {
        Element::Vertex(v) => ("vertex", v.0),
        Element::Edge(x) => ("edge", x.0),
        Element::Face(f) => ("face", f.0),
        Element::Halfedge(h) => ("halfedge", h.0),
    }
}

/// An element a line of the report is about, in both numberings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Named {
    /// In the case's numbering: the fixture's input ids (vertex `i` is
    /// input vertex `i`), and, for an element the student's code made,
    /// the id it got (labellings permute only the input's elements).
    #[serde(serialize_with = "element_json")]
    pub element: Element,
    /// In the labelling's numbering, the ids the message uses, when the
    /// case failed on a relabelled input (else the two are the same).
    #[serde(serialize_with = "opt_element_json")]
    pub labelled: Option<Element>,
}

impl Named {
    /// An element as the child saw it (in the numbering of the mesh sent);
    /// `lib.rs` adds the case's numbering for a relabelled input.
    pub fn seen(element: impl Into<Element>) -> Named {
        Named {
            element: element.into(),
            labelled: None,
        }
    }
}
