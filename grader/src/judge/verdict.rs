//! A case's verdict as data: the [`CaseReport`] every renderer reads,
//! its lines ([`Entry`]) and the findings beside the words: how the case
//! ended ([`CaseEnd`]), the elements each line is about ([`Named`]), the
//! judge's comparison ([`Comparison`]), the broken link `validate()` found
//! ([`InvalidFact`]), the labelling it failed on ([`LabellingFacts`]) and
//! the mistake recognised ([`Hint`], an id whose words are rendered from
//! it). Nothing here decides anything from a message's words.

use halfedge::Check;
use serde::{Serialize, Serializer};

use crate::judge::fixture::{Fixture, Group, Stage};
use crate::quoted::Quoted;

pub use crate::judge::named::Named;

/// How a case ended: the runner's, read here and by every renderer.
pub use crate::isolate::end::CaseEnd;

/// The judge's comparison of the student's mesh with the expected one.
/// "Yours" are ids of the mesh the function left (the labelling's
/// numbering, new elements appended); "expected" are indices of the
/// fixture's expected positions. The vertices are matched whenever the
/// result was compared at all, even when their number is wrong (the
/// verdict is then the count; the report draws the matching).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Comparison {
    /// `matched[i]`: the expected vertex your vertex `i` matched, if any.
    pub matched: Vec<Option<usize>>,
    /// Expected vertices no vertex of yours matched.
    pub missing_vertices: Vec<usize>,
    /// Your vertices that matched no expected one.
    pub extra_vertices: Vec<usize>,
    /// Expected edges (expected indices) you lack; `None` when the edges
    /// were not compared (the vertices were wrong first).
    pub missing_edges: Option<Vec<[usize; 2]>>,
    /// Your edges (your ids) the expected result lacks.
    pub extra_edges: Option<Vec<[usize; 2]>>,
}

/// The broken link `validate()` (or the grader's own checks) found in the
/// result, as data.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InvalidFact {
    /// `validate()`'s check, by its key (`None`: a non-finite position or
    /// a mesh that could not be walked).
    #[serde(serialize_with = "check_json")]
    pub check: Option<Check>,
    pub element: Option<Named>,
}

fn check_json<S: Serializer>(c: &Option<Check>, s: S) -> Result<S::Ok, S::Error> {
    match c {
        Some(c) => s.serialize_str(c.key()),
        None => s.serialize_none(),
    }
}

/// The labelling a case failed on (never the mesh as built).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LabellingFacts {
    /// 1 to `of`: which relabelled input.
    pub index: usize,
    pub of: usize,
    pub seed: u64,
    #[serde(serialize_with = "kind_json")]
    pub kind: crate::judge::relabel::Kind,
    /// `vertices[i]`: the id input vertex `i` has in the labelling; the
    /// same for edges, faces and halfedges.
    pub permutation: crate::judge::relabel::Permutation,
}

fn kind_json<S: Serializer>(k: &crate::judge::relabel::Kind, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(k.key())
}

/// A mistake the grader recognised: an id, whose words [`Hint::text`]
/// renders.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "from", content = "id", rename_all = "lowercase")]
pub enum Hint {
    /// A known mistake of the fixture (`expected.mistakes[].id`).
    Catalogue(String),
    /// One of the grader's own.
    Grader(GraderHint),
}

/// The grader's own hints.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum GraderHint {
    /// The result was far too large.
    RunawayResult,
    /// The mesh library's growth budget stopped the function.
    GrewPast,
    NoVertexAdded,
    TooManyVertices,
    TooFewVertices,
    /// Failed only on a relabelled input, with `mesh[e].halfedge` in the hole.
    LabellingHoleSide,
    /// Subdivision failed only on a relabelled input.
    LabellingSubdivide,
    /// Failed only on a relabelled input, about a vertex's halfedge.
    LabellingVertexPointer,
    /// Failed only on a relabelled input, about a face's halfedge.
    LabellingFacePointer,
    /// Failed only on a relabelled input, otherwise.
    LabellingAnyPointer,
}

impl Hint {
    /// The hint's words for case `f`.
    pub fn text(&self, f: &Fixture) -> String {
        let function = f.operation.stage().function();
        match self {
            Hint::Catalogue(id) => f
                .expected
                .mistakes
                .iter()
                .find(|m| m.id == *id)
                .map_or_else(|| id.clone(), |m| m.hint.clone()),
            Hint::Grader(g) => match g {
                GraderHint::RunawayResult => "are edges created while splitting split again? Loop over the edge ids taken before splitting.".to_string(),
                GraderHint::GrewPast => "are edges created while splitting split again? Loop over the edge ids taken before splitting (mesh.edge_ids() is a snapshot).".to_string(),
                GraderHint::NoVertexAdded => "no vertex was added: does loop_subdivide call split_edge on every old edge?".to_string(),
                GraderHint::TooManyVertices => "more vertices than one per old edge: were edges created by split_edge split again? Loop over the edge ids taken before splitting.".to_string(),
                GraderHint::TooFewVertices => "fewer vertices than one per old edge: was every old edge split exactly once?".to_string(),
                GraderHint::LabellingHoleSide => format!(
                    "does {function} work when mesh[e].halfedge lies in the hole? Start from the halfedge whose face is real"
                ),
                GraderHint::LabellingSubdivide => "your code depends on which halfedge each element points at, or on the order of ids: split_edge or flip_edge may leave a vertex or face pointing at a halfedge that moved (their own cases pass only by luck of the pointers), or the code assumes mesh[e].halfedge runs a particular way".to_string(),
                GraderHint::LabellingVertexPointer => format!(
                    "does {function} update mesh[a].halfedge and mesh[b].halfedge when the halfedge they point at no longer starts there?"
                ),
                GraderHint::LabellingFacePointer => format!(
                    "does {function} reset mesh[f].halfedge of each face it changes? A face may point at a halfedge that moves to another face"
                ),
                GraderHint::LabellingAnyPointer => format!(
                    "does {function} assume which halfedge mesh[e].halfedge, mesh[v].halfedge or mesh[f].halfedge is? Any of them may be any valid one"
                ),
            },
        }
    }
}

/// Which pointer a failure is about, as a fact for the note on a
/// relabelled input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pointer {
    /// A vertex's `halfedge`.
    Vertex,
    /// A face's `halfedge`, or a halfedge's `face`.
    Face,
}

/// The pointer a failed check of `validate()` is about, if one of the
/// vertex's or face's.
pub(crate) fn pointer_of(check: Check) -> Option<Pointer> {
    match check {
        Check::VertexHalfedgeUnset | Check::VertexHalfedgeElsewhere | Check::VertexNotOneFan => {
            Some(Pointer::Vertex)
        }
        Check::FaceHalfedgeUnset | Check::FaceHalfedgeElsewhere | Check::HalfedgeNotItsFace => {
            Some(Pointer::Face)
        }
        _ => None,
    }
}

/// How a line is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Level {
    Info,
    Warn,
    /// An indented detail under a warning.
    Detail,
}

/// One line of a case's report, with the place in the grader that said it
/// (printed in the lab's `file.rs:LINE [info]` format).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Entry {
    pub level: Level,
    /// The grader's words, never the student's.
    pub text: String,
    /// Student text the line quotes (a panic message, its location), shown
    /// after `text` when it fits on the line, else under it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quote: Option<Quoted>,
    /// The elements the line names, as data (see [`Named`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub elements: Vec<Named>,
    /// On a `hint:` line: the hint it gives, as an id.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hint: Option<Hint>,
    #[serde(skip)]
    pub file: &'static str,
    #[serde(skip)]
    pub line: u32,
}

/// A case's verdict and everything said about it.
#[derive(Clone, Debug, Serialize)]
pub struct CaseReport {
    pub name: String,
    pub object: String,
    pub group: Group,
    pub stage: Stage,
    pub passed: bool,
    pub entries: Vec<Entry>,
    /// What the student's code printed while it ran.
    pub output: Quoted,
    /// The case ran out of time (or never reached the call): later cases
    /// of the same function get a shorter limit.
    #[serde(skip)]
    pub timed_out: bool,
    /// The input as sent on the labelling reported (the first that failed,
    /// else the mesh as built), for pictures and OBJ files.
    #[serde(skip)]
    pub input: Option<halfedge::Mesh>,
    /// The mesh the student's function left, when it returned.
    #[serde(skip)]
    pub result: Option<halfedge::Mesh>,
    /// The first hint the case got (its words, as its `hint:` line says
    /// them): the summary repeats it where students read.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hint: Option<String>,
    /// The first hint as an id: the mistake recognised.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hint_id: Option<Hint>,
    /// How the case ended (on the labelling reported).
    pub end: CaseEnd,
    /// The judge's comparison with the expected result, when it got that far.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comparison: Option<Comparison>,
    /// The broken link in the result, when it did not validate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub invalid: Option<InvalidFact>,
    /// The relabelled input the case failed on, when it failed only there.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub labelling: Option<LabellingFacts>,
    /// Which pointer the first failure is about, for the labelling note.
    #[serde(skip)]
    pub pointer: Option<Pointer>,
    /// A subdivision's step-through, when it was recorded (`--report`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frames: Option<crate::judge::frames::Frames>,
}

impl Entry {
    /// The entry on one line: the grader's words, then the quoted text's
    /// first line (escaped, cut) if any.
    pub fn one_line(&self) -> String {
        crate::quoted::quoting(&self.text, self.quote.as_ref(), "").0
    }

    /// The quoted text's lines under `indent` when they did not all fit
    /// on the entry's line.
    pub fn quote_below(&self, indent: &str) -> String {
        crate::quoted::quoting(&self.text, self.quote.as_ref(), indent).1
    }
}

impl CaseReport {
    /// Every element named so far was seen in a labelling's numbering:
    /// keep that id as `labelled` and give the case's one.
    pub fn name_in_case(&mut self, p: &crate::judge::relabel::Permutation) {
        let renamed = |n: &mut Named| {
            if n.labelled.is_none() {
                n.labelled = Some(n.element);
                n.element = p.to_case(n.element);
            }
        };
        for e in &mut self.entries {
            e.elements.iter_mut().for_each(renamed);
        }
        if let Some(Some(n)) = self.invalid.as_mut().map(|i| i.element.as_mut()) {
            renamed(n);
        }
        if let Some(b) = self.frames.as_mut().and_then(|f| f.broken.as_mut()) {
            renamed(&mut b.vertex);
            b.edge.iter_mut().for_each(renamed);
        }
    }
}
