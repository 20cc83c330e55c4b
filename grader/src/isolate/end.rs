//! How a case ended: [`CaseEnd`], the one type for it. The runner
//! ([`crate::isolate::runner`]) produces it, converting the wire's result
//! ([`crate::isolate::wire::Ran`], the bytes on the pipe) through the
//! parent's reading of it ([`crate::isolate::child::analyze`]) and its own
//! view of the process (killed at the limit, a signal, a garbled channel);
//! the judge decides from it and every renderer reads it.
//!
//! Its JSON (`"end"` in a case's report) says how the case ended and no
//! more: the result itself is rendered by the judge's findings.

use std::time::Duration;

use serde::ser::{Serialize, SerializeMap, Serializer};

use crate::isolate::child::{Finished, SequenceRan};

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
