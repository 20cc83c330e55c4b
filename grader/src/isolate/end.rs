//! How a case ended: [`CaseEnd`], the one type for it, and the result
//! types inside it ([`Finished`], [`SequenceRan`], [`Problem`], ...). The
//! runner ([`crate::isolate::runner`]) produces it, converting the wire's
//! result ([`crate::isolate::wire::Ran`], the bytes on the pipe) through
//! the parent's reading of it ([`crate::isolate::analyze`]) and its own
//! view of the process (killed at the limit, a signal, a garbled channel);
//! the judge decides from it and every renderer reads it.
//!
//! Its JSON (`"end"` in a case's report) says how the case ended and no
//! more: the result itself is rendered by the judge's findings.

use std::time::Duration;

use serde::ser::{SerializeMap, Serializer};

use halfedge::{Mesh, VertexId};
use serde::{Deserialize, Serialize};

use crate::isolate::wire::StepRan;

/// How a case ended.
#[derive(Clone, Debug, PartialEq)]
pub enum CaseEnd {
    /// The function returned; its result as the parent read it.
    Returned(Box<Finished>),
    /// A sequence ran: each step that did, and the panic that ended it
    /// early, if one did.
    Sequence(Box<SequenceRan>),
    /// It panicked (a `todo!()` included); `grew_past` when the mesh
    /// library's growth budget (that many elements) raised the panic: a
    /// fact the child sends, so the panic's words are never read for it.
    Panicked {
        message: String,
        location: Option<String>,
        grew_past: Option<u64>,
    },
    /// Still running at the time limit, and killed.
    TimedOut { limit: Duration },
    /// Never reached the student's function within the setup time (code
    /// that runs before `main`, or a machine far too slow).
    StuckBeforeCall { limit: Duration },
    /// Killed by the stack overflow guard.
    StackOverflow,
    /// An allocation failed under the memory cap (bytes).
    OutOfMemory { cap: u64 },
    /// Ended by a signal (abort, segfault...).
    Signal { signal: i32 },
    /// Exited without sending a result (e.g. `std::process::exit`).
    Exited { code: Option<i32> },
    /// What came back on the result channel is not a result.
    Garbled { why: String },
    /// The result was this many bytes, far more than any answer.
    TooLarge { bytes: usize },
    /// The sandbox could not be set up: the grader's problem, not the
    /// student's (grading stops with it; no case report carries it).
    SandboxFailed { why: String },
    /// Judging the result panicked: the grader's bug.
    JudgeFailed,
}

impl CaseEnd {
    /// The case ran out of time, or never reached the call.
    pub fn timed_out(&self) -> bool {
        matches!(
            self,
            CaseEnd::TimedOut { .. } | CaseEnd::StuckBeforeCall { .. }
        )
    }

    /// The function came back (returned or panicked) rather than the
    /// process dying or being killed: the child is still in a state to
    /// serve another call.
    pub fn came_back(&self) -> bool {
        matches!(
            self,
            CaseEnd::Returned(_) | CaseEnd::Sequence(_) | CaseEnd::Panicked { .. }
        )
    }
}

/// `{"kind": ...}` and the facts of the kind, as the reports have always
/// written them: a sequence reads as `returned` (no value) or `panicked`.
impl Serialize for CaseEnd {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        match self {
            CaseEnd::Returned(f) => {
                m.serialize_entry("kind", "returned")?;
                m.serialize_entry("returned", &Some(&f.returned))?;
            }
            CaseEnd::Sequence(seq) if seq.panic.is_none() => {
                m.serialize_entry("kind", "returned")?;
                m.serialize_entry("returned", &None::<()>)?;
            }
            CaseEnd::Sequence(_) => m.serialize_entry("kind", "panicked")?,
            CaseEnd::Panicked { grew_past, .. } => {
                m.serialize_entry("kind", "panicked")?;
                if let Some(limit) = grew_past {
                    m.serialize_entry("grew_past", limit)?;
                }
            }
            CaseEnd::TimedOut { limit } => {
                m.serialize_entry("kind", "timed-out")?;
                m.serialize_entry("limit", &limit.as_secs_f64())?;
            }
            CaseEnd::StuckBeforeCall { limit } => {
                m.serialize_entry("kind", "stuck-before-call")?;
                m.serialize_entry("limit", &limit.as_secs_f64())?;
            }
            CaseEnd::StackOverflow => m.serialize_entry("kind", "stack-overflow")?,
            CaseEnd::OutOfMemory { cap } => {
                m.serialize_entry("kind", "out-of-memory")?;
                m.serialize_entry("cap", cap)?;
            }
            CaseEnd::Signal { signal } => {
                m.serialize_entry("kind", "signal")?;
                m.serialize_entry("signal", signal)?;
            }
            CaseEnd::Exited { code } => {
                m.serialize_entry("kind", "exited")?;
                m.serialize_entry("code", code)?;
            }
            CaseEnd::Garbled { .. } => m.serialize_entry("kind", "garbled")?,
            CaseEnd::TooLarge { bytes } => {
                m.serialize_entry("kind", "too-large")?;
                m.serialize_entry("bytes", bytes)?;
            }
            CaseEnd::SandboxFailed { .. } => m.serialize_entry("kind", "sandbox-failed")?,
            CaseEnd::JudgeFailed => m.serialize_entry("kind", "judge-failed")?,
        }
        m.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The JSON the reports wrote before the types were merged.
    #[test]
    fn the_json_names_each_end_as_before() {
        let json = |e: &CaseEnd| serde_json::to_value(e).unwrap();
        assert_eq!(
            json(&CaseEnd::TimedOut {
                limit: Duration::from_millis(1500)
            }),
            serde_json::json!({"kind": "timed-out", "limit": 1.5})
        );
        assert_eq!(
            json(&CaseEnd::Panicked {
                message: "m".into(),
                location: None,
                grew_past: Some(40)
            }),
            serde_json::json!({"kind": "panicked", "grew_past": 40})
        );
        assert_eq!(
            json(&CaseEnd::Panicked {
                message: "m".into(),
                location: None,
                grew_past: None
            }),
            serde_json::json!({"kind": "panicked"})
        );
        assert_eq!(
            json(&CaseEnd::Exited { code: None }),
            serde_json::json!({"kind": "exited", "code": null})
        );
        assert_eq!(
            json(&CaseEnd::Garbled { why: "x".into() }),
            serde_json::json!({"kind": "garbled"})
        );
        assert_eq!(
            json(&CaseEnd::StackOverflow),
            serde_json::json!({"kind": "stack-overflow"})
        );
    }
}

/// Element counts: vertices, edges, faces (with holes), halfedges.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counts {
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    pub halfedges: usize,
}

impl Counts {
    pub fn of(mesh: &Mesh) -> Counts {
        Counts {
            vertices: mesh.num_vertices(),
            edges: mesh.num_edges(),
            faces: mesh.num_faces(),
            halfedges: mesh.num_halfedges(),
        }
    }
}

/// What a student function returned.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Returned {
    /// `loop_subdivide` returns nothing.
    Unit,
    Nothing,
    Edge {
        given: u32,
        got: u32,
    },
    Vertex {
        id: u32,
        /// Missing when the id names no vertex.
        position: Option<[f64; 3]>,
    },
}

/// The mesh after the operation, read only when it validated.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshResult {
    pub positions: Vec<[f64; 3]>,
    pub edges: Vec<[usize; 2]>,
    /// For a returned edge: the vertices it joins.
    pub returned_edge_ends: Option<[usize; 2]>,
    /// For a returned vertex: where its halfedge leads.
    pub returned_vertex_leads_to: Option<usize>,
    /// After a split that returned a new vertex, what the contract pins
    /// down besides the shape: see [`SplitIds`].
    pub split: Option<SplitIds>,
}

/// The ids a split must keep sensible, read in the labelling that was sent.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SplitIds {
    /// The new vertex's `is_new` and `new_pos`: a split leaves them at their
    /// defaults (`false`, zero); subdivision sets them after the call.
    pub is_new: bool,
    pub new_pos: [f64; 3],
    /// The split edge's id, and the vertices it joins now: the new vertex
    /// and an end of the old edge.
    pub edge: usize,
    pub edge_ends: [usize; 2],
    /// The old faces beside the edge that no longer have the new vertex as
    /// a corner (each must become one of the triangles around it).
    pub faces_away: Vec<usize>,
}

/// A function that returned, as the parent read its result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Finished {
    pub returned: Returned,
    pub before: Counts,
    pub after: Counts,
    /// The first thing wrong with the result's links or positions.
    pub invalid: Option<Problem>,
    pub mesh: Option<Box<MeshResult>>,
    /// Every record, positions to the bit, is as it was sent.
    #[serde(default)]
    pub unchanged: bool,
}

/// A sequence: what each step that ran did (the child stops at the first
/// step that leaves an invalid mesh, panics or names two vertices no edge
/// joins), and the mesh the last one left, read as for one operation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SequenceRan {
    pub steps: Vec<StepRan>,
    pub panic: Option<(String, Option<String>)>,
    pub before: Counts,
    pub after: Counts,
    pub invalid: Option<Problem>,
    pub mesh: Option<Box<MeshResult>>,
}

/// The first thing wrong with a result's links or positions, as data
/// (its message is [`Problem`]'s `Display`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Problem {
    /// `validate()` failed: the check, the element and its message (the
    /// message as the parent read it, see [`crate::text::words`]).
    Invalid {
        #[serde(skip)]
        invalid: Option<halfedge::Invalid>,
        message: String,
    },
    /// A vertex whose position is not a finite number.
    NotFinite { vertex: u32, position: [f64; 3] },
    /// Walking the mesh panicked (the library's message).
    Unwalkable { message: String },
}

impl Problem {
    /// `validate()`'s finding, its message as the grader says it.
    pub fn of(invalid: halfedge::Invalid) -> Problem {
        let mut invalid = invalid;
        invalid.message = crate::text::words(invalid.message);
        Problem::Invalid {
            message: invalid.to_string(),
            invalid: Some(invalid),
        }
    }

    /// The check of `validate()` that failed, if it was one.
    pub fn check(&self) -> Option<halfedge::Check> {
        match self {
            Problem::Invalid { invalid, .. } => invalid.as_ref().map(|i| i.check),
            _ => None,
        }
    }

    /// The element at fault, in the numbering of the mesh checked.
    pub fn element(&self) -> Option<halfedge::Element> {
        match self {
            Problem::Invalid { invalid, .. } => invalid.as_ref().map(|i| i.element),
            Problem::NotFinite { vertex, .. } => Some(VertexId(*vertex).into()),
            Problem::Unwalkable { .. } => None,
        }
    }

    /// The first problem with `mesh`: a non-finite position, else
    /// `validate()`'s. Guard the call: it walks what the student made.
    pub(crate) fn find(mesh: &Mesh) -> Option<Problem> {
        non_finite(mesh).or_else(|| mesh.validate().err().map(Problem::of))
    }
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Problem::Invalid { message, .. } => f.write_str(message),
            Problem::NotFinite {
                vertex,
                position: p,
            } => write!(
                f,
                "vertex v{vertex} is at ({}, {}, {}): a position must be a finite number",
                p[0], p[1], p[2]
            ),
            Problem::Unwalkable { message } => {
                write!(f, "the mesh could not be walked: {message}")
            }
        }
    }
}

/// The first vertex whose position is not a finite number ("vertex v7 is
/// at (NaN, 0, 1)").
pub(crate) fn non_finite(mesh: &Mesh) -> Option<Problem> {
    let (vertices, ..) = mesh.records();
    let (i, v) = vertices
        .iter()
        .enumerate()
        .find(|(_, v)| !v.pos.is_finite())?;
    Some(Problem::NotFinite {
        vertex: i as u32,
        position: v.pos.to_array(),
    })
}
