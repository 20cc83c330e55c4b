//! Judging one case: turns the child's report into the lab's messages, in
//! the lab's order, with details and a hint under a failure.
//!
//! Beside the words, a case's report carries its findings as data, for
//! every renderer (text, JSON, Gradescope, HTML) and for later notes: how
//! the case ended ([`CaseEnd`]), the elements each line is about
//! ([`Named`]), the judge's comparison ([`Comparison`]), the broken link
//! `validate()` found ([`InvalidFact`]), the labelling it failed on
//! ([`LabellingFacts`]) and the mistake recognised ([`Hint`], an id whose
//! words are rendered from it). Nothing here decides anything from a
//! message's words: [`set_rewording`] rewrites every one, and the tests
//! check that no verdict, hint or element moves.

use std::sync::atomic::{AtomicBool, Ordering};

use halfedge::{Check, EdgeId, Element, FaceId, VertexId};
use serde::{Serialize, Serializer};

use crate::isolate::child::{
    Counts, Finished, MeshResult, Problem, Returned, SequenceRan, SplitIds,
};
use crate::isolate::runner::ChildReport;
use crate::isolate::wire::{StepAnswer, StepRan};
use crate::judge::fixture::{Fixture, Group, Operation, Returns, Stage};
use crate::judge::matching::{self, VertexMatch};
use crate::report::quoted::Quoted;

/// Whether every message is rewritten (see [`set_rewording`]).
static REWORDING: AtomicBool = AtomicBool::new(false);

/// For the tests that prove no decision reads a message: from now on, in
/// this process, every line the judge says and every `validate()` message
/// the parent reads is rewritten ([`words`]). Off in normal use.
pub fn set_rewording(on: bool) {
    REWORDING.store(on, Ordering::Relaxed);
}

/// A message as the grader says it: unchanged, or rewritten when
/// [`set_rewording`] is on (upper case behind a marker, so any code that
/// still matched words would stop matching).
pub fn words(text: String) -> String {
    if REWORDING.load(Ordering::Relaxed) {
        format!("REWORDED: {}", text.to_uppercase())
    } else {
        text
    }
}

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
fn pointer_of(check: Check) -> Option<Pointer> {
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

struct Log {
    entries: Vec<Entry>,
    passed: bool,
    hint: Option<String>,
    hint_id: Option<Hint>,
    comparison: Option<Comparison>,
    invalid: Option<InvalidFact>,
    pointer: Option<Pointer>,
}

impl Log {
    fn new() -> Log {
        Log {
            entries: Vec::new(),
            passed: true,
            hint: None,
            hint_id: None,
            comparison: None,
            invalid: None,
            pointer: None,
        }
    }

    /// The log that adds lines to `report`, above its "end testing" line
    /// (put back by [`Log::finish`]).
    fn resume(report: &mut CaseReport) -> (Log, Option<Entry>) {
        let end = report.entries.pop();
        let log = Log {
            entries: std::mem::take(&mut report.entries),
            passed: report.passed,
            hint: report.hint.take(),
            hint_id: report.hint_id.take(),
            comparison: None,
            invalid: None,
            pointer: None,
        };
        (log, end)
    }

    fn finish(self, report: &mut CaseReport, end: Option<Entry>) {
        report.entries = self.entries;
        report.entries.extend(end);
        report.passed = self.passed;
        report.hint = self.hint;
        report.hint_id = self.hint_id;
    }

    /// Names the elements the last line is about.
    fn about(&mut self, elements: impl IntoIterator<Item = Element>) {
        if let Some(e) = self.entries.last_mut() {
            e.elements.extend(elements.into_iter().map(Named::seen));
        }
    }

    /// Records the broken link as data on the line just said (the first
    /// warning's, as the case stops there).
    fn invalid_found(&mut self, problem: &Problem) {
        self.about(problem.element());
        self.first_about(problem.check().and_then(pointer_of));
        self.invalid = Some(InvalidFact {
            check: problem.check(),
            element: problem.element().map(Named::seen),
        });
    }

    /// Says the first failure is about `pointer`, if it is the first.
    fn first_about(&mut self, pointer: Option<Pointer>) {
        let warns = self
            .entries
            .iter()
            .filter(|e| e.level == Level::Warn)
            .count();
        if warns == 1 && self.pointer.is_none() {
            self.pointer = pointer;
        }
    }

    /// A detail line `hint: ...` for `hint`, and the case's hint if it had
    /// none yet.
    fn hint(&mut self, f: &Fixture, hint: Hint, file: &'static str, line: u32) {
        let text = hint.text(f);
        self.push(Level::Detail, format!("hint: {text}"), None, file, line);
        if let Some(e) = self.entries.last_mut() {
            e.hint = Some(hint.clone());
        }
        if self.hint.is_none() {
            self.hint = Some(text);
            self.hint_id = Some(hint);
        }
    }
}

/// A detail line `hint: ...`, and the case's hint if it had none yet.
macro_rules! hint {
    ($log:expr, $f:expr, $hint:expr) => {
        $log.hint($f, $hint, file!(), line!())
    };
}

macro_rules! say {
    ($log:expr, $level:ident, $($arg:tt)*) => {
        $log.push(Level::$level, format!($($arg)*), None, file!(), line!())
    };
}

/// A line of the grader's words followed by student text (`quote`, a
/// [`Quoted`]), which is shown as data.
macro_rules! quote {
    ($log:expr, $level:ident, $quote:expr, $($arg:tt)*) => {
        $log.push(Level::$level, format!($($arg)*), Some(Quoted::new($quote)), file!(), line!())
    };
}

impl Log {
    fn push(
        &mut self,
        level: Level,
        text: String,
        quote: Option<Quoted>,
        file: &'static str,
        line: u32,
    ) {
        if level == Level::Warn {
            self.passed = false;
        }
        self.entries.push(Entry {
            level,
            text: words(text),
            quote,
            elements: Vec::new(),
            hint: None,
            file,
            line,
        });
    }
}

impl Entry {
    /// The entry on one line: the grader's words, then the quoted text's
    /// first line (escaped, cut) if any.
    pub fn one_line(&self) -> String {
        crate::report::quoted::quoting(&self.text, self.quote.as_ref(), "").0
    }

    /// The quoted text's lines under `indent` when they did not all fit
    /// on the entry's line.
    pub fn quote_below(&self, indent: &str) -> String {
        crate::report::quoted::quoting(&self.text, self.quote.as_ref(), indent).1
    }
}

fn fmt_p(p: [f64; 3]) -> String {
    format!("({:.6}, {:.6}, {:.6})", p[0], p[1], p[2])
}

/// `cube` for one round, `cube (2 rounds)` for more; `cube, edge 0-1` for
/// flips and splits.
fn subject(f: &Fixture) -> String {
    match f.operation {
        Operation::Subdivide { rounds: 1 } => f.object.clone(),
        Operation::Subdivide { rounds } => format!("{} ({rounds} rounds)", f.object),
        Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] } => {
            format!("{}, edge {a}-{b}", f.object)
        }
        Operation::Sequence { seed } => {
            format!("{} ({} operations, seed {seed})", f.object, f.steps.len())
        }
    }
}

/// What the lab calls the operation in "start testing X for ...".
fn activity(stage: Stage) -> &'static str {
    match stage {
        Stage::Flip => "flip_edge",
        Stage::Split => "split_edge",
        Stage::Sequence => "flips and splits in sequence",
        Stage::Subdivide => "subdivision",
    }
}

/// Judges a case from its child's report.
pub fn judge(f: &Fixture, child: &ChildReport) -> CaseReport {
    judge_end(f, &child.end, &child.output, None)
}

/// The report of a case whose judging panicked (`message`: the panic's):
/// the grader's bug, said as such.
pub fn judge_failed(f: &Fixture, message: &str, output: &str) -> CaseReport {
    judge_end(f, &CaseEnd::JudgeFailed, output, Some(message))
}

fn judge_end(f: &Fixture, end: &CaseEnd, output: &str, failed: Option<&str>) -> CaseReport {
    let stage = f.operation.stage();
    let mut log = Log::new();
    let what = subject(f);
    say!(log, Info, "start testing {} for {what}", activity(stage));
    judge_run(f, end, failed, &mut log);
    say!(log, Info, "end testing {} for {what}", activity(stage));
    CaseReport {
        name: f.name.clone(),
        object: f.object.clone(),
        group: f.group,
        stage,
        passed: log.passed,
        entries: log.entries,
        output: Quoted::new(output.to_string()),
        timed_out: end.timed_out(),
        input: None,
        result: None,
        hint: log.hint,
        hint_id: log.hint_id,
        end: end.clone(),
        comparison: log.comparison,
        invalid: log.invalid,
        labelling: None,
        pointer: log.pointer,
        frames: None,
    }
}

fn judge_run(f: &Fixture, end: &CaseEnd, failed: Option<&str>, log: &mut Log) {
    let function = f.operation.stage().function();
    let must_panic = f.expected.returns == Some(Returns::Panic);
    match end {
        CaseEnd::TimedOut { limit } => {
            say!(
                log,
                Warn,
                "{function} did not finish within {} s",
                limit.as_secs_f64()
            );
            say!(log, Detail, "an endless loop? a walk around a face or vertex that never gets back to its start?");
        }
        CaseEnd::StuckBeforeCall { limit } => {
            say!(
                log,
                Warn,
                "{function} was never reached: the program was still starting after {} s",
                limit.as_secs_f64()
            );
            say!(
                log,
                Detail,
                "does your crate run code before main (a static initialiser) that never ends?"
            );
        }
        CaseEnd::StackOverflow => {
            say!(log, Warn, "{function} overflowed the stack");
            say!(log, Detail, "a function that calls itself without end?");
        }
        CaseEnd::OutOfMemory { cap } => {
            say!(
                log,
                Warn,
                "{function} used more than {} of memory",
                crate::isolate::sandbox::format_bytes(*cap)
            );
            say!(log, Detail, "a loop that never stops adding elements or growing a Vec? (--memory changes the cap)");
        }
        CaseEnd::Signal { signal: sig } => {
            say!(log, Warn, "{function} crashed: {}", signal_name(*sig));
        }
        CaseEnd::Exited { code } => {
            let code = code.map_or("unknown".to_string(), |c| c.to_string());
            say!(
                log,
                Warn,
                "{function} ended the program (exit status {code}) before returning"
            );
            say!(log, Detail, "does your code call std::process::exit?");
        }
        CaseEnd::Garbled { why } => {
            say!(
                log,
                Warn,
                "{function}'s result could not be read: the grader's channel was written to ({why})"
            );
            say!(
                log,
                Detail,
                "does your code write to file descriptors it did not open?"
            );
        }
        CaseEnd::TooLarge { bytes } => {
            say!(
                log,
                Warn,
                "{function} returned a mesh far larger than any right answer ({} MiB of data)",
                bytes >> 20
            );
            hint!(log, f, Hint::Grader(GraderHint::RunawayResult));
        }
        // A sandbox that failed stops grading before any judging (`lib.rs`):
        // here only for completeness, said as the grader's problem.
        CaseEnd::JudgeFailed | CaseEnd::SandboxFailed { .. } => {
            let why = match end {
                CaseEnd::SandboxFailed { why } => why.as_str(),
                _ => failed.unwrap_or_default(),
            };
            quote!(
                log,
                Warn,
                why,
                "the grader could not judge this result: tell a TA, with your code; the grader's message:"
            );
        }
        CaseEnd::Panicked {
            message,
            location,
            grew_past,
        } if must_panic => {
            if is_stub(message) {
                quote!(log, Warn, message.as_str(), "{function} panicked:");
                say!(
                    log,
                    Detail,
                    "the function is still a todo!() stub: write it in crates/meshedit/src/lib.rs"
                );
            } else if grew_past.is_none() && names_a_non_triangle(message) {
                quote!(
                    log,
                    Info,
                    message.as_str(),
                    "{function} panicked, as it must:"
                );
            } else {
                quote!(
                    log,
                    Warn,
                    message.as_str(),
                    "{function} panicked, but its message does not say a face is not a triangle:"
                );
                if let Some(loc) = location {
                    quote!(log, Detail, loc.as_str(), "at");
                }
                say!(log, Detail, "check first: mesh.first_non_triangle() finds such a face; name it in the panic message");
            }
        }
        CaseEnd::Panicked {
            message,
            location,
            grew_past,
        } => {
            quote!(log, Warn, message.as_str(), "{function} panicked:");
            if let Some(loc) = location {
                quote!(log, Detail, loc.as_str(), "at");
            }
            if grew_past.is_some() {
                hint!(log, f, Hint::Grader(GraderHint::GrewPast));
            } else if is_stub(message) {
                say!(
                    log,
                    Detail,
                    "the function is still a todo!() stub: write it in crates/meshedit/src/lib.rs"
                );
            }
        }
        CaseEnd::Returned(_) if must_panic => {
            say!(log, Warn, "{function} returned, but the mesh has a face that is not a triangle: it must panic with a message that says so");
        }
        CaseEnd::Sequence(seq) => {
            let SequenceRan {
                steps,
                panic,
                before,
                after,
                invalid,
                mesh,
            } = seq.as_ref();
            judge_sequence(
                f,
                steps,
                panic.as_ref(),
                (*before, *after),
                invalid.as_ref(),
                mesh.as_deref(),
                log,
            )
        }
        CaseEnd::Returned(finished) => {
            let Finished {
                returned,
                before,
                after,
                invalid,
                mesh,
                unchanged,
            } = finished.as_ref();
            judge_finished(
                f,
                returned,
                (*before, *after),
                *unchanged,
                invalid.as_ref(),
                mesh.as_deref(),
                log,
            );
            // A check before the shape (the return, the counts) stopped
            // the verdict: the comparison is still made, silently, as
            // data for the report's pictures.
            if let (None, None, Some(mesh)) = (&log.comparison, invalid, mesh) {
                log.comparison = Some(comparison_of(f, mesh));
            }
        }
    }
}

/// Whether a panic is `todo!()`'s: std's own words for the stubs, the
/// one panic the grader tells by its message (std gives no other sign).
fn is_stub(message: &str) -> bool {
    message.starts_with("not yet implemented")
}

/// Whether the student's panic message says a face is not a triangle, as
/// the contract asks of `loop_subdivide` on a mesh with another face: the
/// student's words are what is judged here (like a position), never a
/// message of the grader or the mesh library.
fn names_a_non_triangle(student_message: &str) -> bool {
    student_message.to_lowercase().contains("triangle")
}

fn signal_name(sig: i32) -> String {
    let name = match sig {
        6 => "SIGABRT: the program aborted",
        9 => "SIGKILL: killed, perhaps for using too much memory",
        11 => "SIGSEGV: invalid memory access",
        4 => "SIGILL: illegal instruction",
        8 => "SIGFPE: arithmetic error",
        _ => "",
    };
    if name.is_empty() {
        format!("signal {sig}")
    } else {
        format!("signal {sig} ({name})")
    }
}

fn judge_finished(
    f: &Fixture,
    returned: &Returned,
    (before, after): (Counts, Counts),
    unchanged: bool,
    invalid: Option<&Problem>,
    mesh: Option<&MeshResult>,
    log: &mut Log,
) {
    let stage = f.operation.stage();
    let function = stage.function();
    if !check_returned(f, returned, before, log) {
        return;
    }
    if f.expected.returns == Some(Returns::Refused) && !unchanged {
        say!(
            log,
            Warn,
            "{function} returned None but changed the mesh: a refusal must leave every link as it was"
        );
        say!(
            log,
            Detail,
            "check whether to refuse before changing anything"
        );
        return;
    }
    say!(log, Info, "validate the mesh...");
    if let Some(problem) = invalid {
        let result_of = match stage {
            Stage::Subdivide => "subdivision".to_string(),
            _ => function.to_string(),
        };
        say!(
            log,
            Warn,
            "the result of {result_of} is a invalid mesh: {problem}"
        );
        log.invalid_found(problem);
        // A known mistake that breaks the mesh the same way (the same
        // check of validate()), named.
        if let Some(m) = f
            .expected
            .mistakes
            .iter()
            .find(|m| m.invalid_check().is_some() && m.invalid_check() == problem.check())
        {
            hint!(log, f, Hint::Catalogue(m.id.clone()));
        }
        return;
    }
    say!(log, Info, "passed");
    let Some(mesh) = mesh else {
        say!(log, Warn, "the mesh validated but could not be read back");
        return;
    };
    if !check_counts(f, before, after, log) {
        return;
    }
    let Some(matched) = compare_vertices(f, mesh, before, log) else {
        return;
    };
    if !compare_edges(f, mesh, before, &matched, log) {
        return;
    }
    check_returned_shape(f, returned, mesh, &matched, log);
}

/// A sequence, step by step: each step's return and element counts and
/// the mesh's validity after it, then the shape the last step left. The
/// first step that goes wrong is named with everything needed to find it:
/// how many steps went before, the seed, the function and the edge.
fn judge_sequence(
    f: &Fixture,
    steps: &[StepRan],
    panic: Option<&(String, Option<String>)>,
    (before, after): (Counts, Counts),
    invalid: Option<&Problem>,
    mesh: Option<&MeshResult>,
    log: &mut Log,
) {
    let Operation::Sequence { seed } = f.operation else {
        return;
    };
    let n = f.input.positions.len();
    let mut counts = [
        before.vertices,
        before.edges,
        before.faces,
        before.halfedges,
    ];
    let mut made = 0;
    say!(
        log,
        Info,
        "run {} flips and splits, validating after each...",
        f.steps.len()
    );
    for (i, (step, want)) in f.steps.iter().zip(&f.expected.steps).enumerate() {
        let function = step.function();
        let [a, b] = step.edge();
        let done = format!(
            "after {i} operation{} (seed {seed})",
            if i == 1 { "" } else { "s" }
        );
        let at = format!("{done}, {function} on edge {a}-{b}");
        let Some(got) = steps.get(i) else {
            if let Some((message, location)) = panic {
                // Worded as for one operation, so that a panic every case
                // shares is one line in the summary; where it came follows.
                quote!(log, Warn, message.as_str(), "{function} panicked:");
                if let Some(loc) = location {
                    quote!(log, Detail, loc.as_str(), "at");
                }
                say!(log, Detail, "{at} (step {} of {})", i + 1, f.steps.len());
                if message.starts_with("not yet implemented") {
                    say!(log, Detail, "the function is still a todo!() stub: write it in crates/meshedit/src/lib.rs");
                } else {
                    say!(log, Detail, "the same call works on the mesh as built? Then an earlier operation left a pointer that this one follows");
                }
            } else {
                say!(log, Warn, "{at} never ran: the sequence stopped early");
            }
            return;
        };
        if got.edge.is_none() {
            say!(
                log,
                Warn,
                "{done}, vertices {a} and {b} are not joined by an edge, but they must be: an earlier operation relinked the wrong vertices"
            );
            return;
        }
        let mut expected_counts = counts;
        let ok = match (want, &got.answer) {
            (Returns::Refused, StepAnswer::Nothing) => true,
            (Returns::Refused, _) => {
                say!(log, Warn, "{at} must return None (its flip would join two vertices already joined by an edge), but it did not");
                false
            }
            (_, StepAnswer::Nothing) => {
                say!(
                    log,
                    Warn,
                    "{at} returned None, but the edge lies between two triangles: it must {}",
                    if step.is_split() {
                        "split it"
                    } else {
                        "flip it"
                    }
                );
                false
            }
            (Returns::Edge { ends }, StepAnswer::Edge { id, ends: got_ends }) => {
                let same = |x: &[u32; 2]| {
                    let x = [x[0] as usize, x[1] as usize];
                    x == *ends || [x[1], x[0]] == *ends
                };
                if Some(*id) != got.edge {
                    say!(
                        log,
                        Warn,
                        "{at} returned Some(e{id}), but it must return the edge it was given (e{})",
                        got.edge.unwrap_or_default()
                    );
                    false
                } else if got.valid && !got_ends.as_ref().is_some_and(same) {
                    say!(log, Warn, "{at} left the edge joining the wrong vertices: it must join {} and {} after the flip", ends[0], ends[1]);
                    false
                } else {
                    true
                }
            }
            (
                Returns::Vertex { position },
                StepAnswer::Vertex {
                    name,
                    position: got_p,
                },
            ) => {
                let new_name = (n + made) as u32;
                made += 1;
                expected_counts[0] += 1;
                // A split between two triangles adds an edge for the other
                // half and one across each, and a face and two halfedges per triangle.
                expected_counts[1] += 3;
                expected_counts[2] += 2;
                expected_counts[3] += 6;
                let off = got_p.map_or(f64::INFINITY, |p| {
                    matching::nearest(&[p], *position).map_or(f64::INFINITY, |n| n.1)
                });
                if *name != Some(new_name) {
                    say!(log, Warn, "{at} did not return the new vertex");
                    false
                } else if off.is_nan() || off > f.tolerance {
                    say!(
                        log,
                        Warn,
                        "{at} put the new vertex away from the midpoint {} of the edge",
                        fmt_p(*position)
                    );
                    false
                } else {
                    true
                }
            }
            _ => {
                say!(log, Warn, "{at} returned the wrong kind of value");
                false
            }
        };
        if !ok {
            return;
        }
        if !got.valid {
            say!(
                log,
                Warn,
                "{at} left an invalid mesh: {}",
                invalid.map_or("validate() failed".to_string(), Problem::to_string)
            );
            if let Some(problem) = invalid {
                log.invalid_found(problem);
            }
            say!(log, Detail, "it passes alone? Then it relies on something the earlier operations changed: a vertex, edge or face pointing at a halfedge that moved");
            return;
        }
        let got_counts = got.counts.map(|c| c as usize);
        if got_counts != expected_counts {
            let c = |c: [usize; 4]| {
                format!(
                    "{} vertices, {} edges, {} faces, {} halfedges",
                    c[0], c[1], c[2], c[3]
                )
            };
            say!(log, Warn, "{at} added or removed the wrong elements");
            say!(log, Detail, "before: {}", c(counts));
            say!(log, Detail, "after:  {}", c(got_counts));
            say!(log, Detail, "should: {}", c(expected_counts));
            return;
        }
        counts = expected_counts;
    }
    if let Some((message, _)) = panic {
        quote!(
            log,
            Warn,
            message.as_str(),
            "the sequence panicked after its last step:"
        );
        return;
    }
    if steps.len() != f.steps.len() {
        say!(
            log,
            Warn,
            "the sequence ran {} steps, not {}",
            steps.len(),
            f.steps.len()
        );
        return;
    }
    say!(log, Info, "passed");
    let Some(mesh) = mesh else {
        say!(
            log,
            Warn,
            "the mesh validated after every step but could not be read back"
        );
        return;
    };
    let _ = after;
    let Some(matched) = compare_vertices(f, mesh, before, log) else {
        return;
    };
    compare_edges(f, mesh, before, &matched, log);
}

/// The input faces beside the case's edge (none for subdivision).
fn faces_beside(f: &Fixture) -> Vec<&Vec<usize>> {
    let (Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] }) = f.operation else {
        return Vec::new();
    };
    f.input
        .faces
        .iter()
        .filter(|face| {
            (0..face.len()).any(|i| {
                let (x, y) = (face[i], face[(i + 1) % face.len()]);
                (x, y) == (a, b) || (x, y) == (b, a)
            })
        })
        .collect()
}

/// The lower degree of the case's edge's ends in the input, where it is 3
/// or less (a refusal that tests degrees refuses legal flips there).
fn low_degree_end(f: &Fixture) -> Option<usize> {
    let (Operation::Flip { edge } | Operation::Split { edge }) = f.operation else {
        return None;
    };
    let degree = |v: usize| {
        let mut neighbours: Vec<usize> = f
            .input
            .faces
            .iter()
            .flat_map(|face| {
                (0..face.len()).filter_map(move |i| {
                    let (x, y) = (face[i], face[(i + 1) % face.len()]);
                    (x == v).then_some(y).or((y == v).then_some(x))
                })
            })
            .collect();
        neighbours.sort_unstable();
        neighbours.dedup();
        neighbours.len()
    };
    let low = edge.map(degree).into_iter().min()?;
    (low <= 3).then_some(low)
}

/// Whether the case's edge borders a hole in the input: it is used by one
/// face only.
fn on_boundary(f: &Fixture) -> bool {
    faces_beside(f).len() == 1
}

/// Why the case's edge must be refused, from the input faces.
fn refusal_reason(f: &Fixture) -> &'static str {
    let beside = faces_beside(f);
    if beside.iter().any(|face| face.len() != 3) {
        "an edge beside a face that is not a triangle"
    } else if on_boundary(f) {
        "a boundary edge"
    } else {
        "an edge whose flip would join two vertices already joined by an edge"
    }
}

/// The return value, judged before anything else: it says most about a flip
/// or split that did the wrong thing altogether.
fn check_returned(f: &Fixture, returned: &Returned, before: Counts, log: &mut Log) -> bool {
    let function = f.operation.stage().function();
    match (&f.expected.returns, returned) {
        (None, _) => true,
        (Some(Returns::Refused), Returned::Nothing) => true,
        (Some(Returns::Refused), _) => {
            say!(
                log,
                Warn,
                "{function} changed {}: it must return None and leave the mesh unchanged",
                refusal_reason(f)
            );
            false
        }
        (Some(Returns::Vertex { .. }), Returned::Nothing) if on_boundary(f) => {
            say!(log, Warn, "split_edge returned None for a boundary edge: it must divide the one real triangle beside it");
            false
        }
        (Some(_), Returned::Nothing) => {
            let flip = f.operation.stage() == Stage::Flip;
            say!(
                log,
                Warn,
                "{function} returned None for an edge between two triangles: it must {} it",
                if flip { "flip" } else { "split" }
            );
            if flip {
                say!(log, Detail, "no rule of the contract refuses it: it is not on the boundary, both faces are triangles, and c and d are not joined yet");
            }
            if let Some(low) = low_degree_end(f) {
                say!(log, Detail, "an end of degree {low} is no reason to refuse: the contract lists every refusal");
            }
            false
        }
        (Some(Returns::Edge { .. }), Returned::Edge { given, got }) if given != got => {
            say!(log, Warn, "flip_edge returned Some(e{got}), but it must return the edge it was given (e{given})");
            log.about([EdgeId(*got).into(), EdgeId(*given).into()]);
            false
        }
        (Some(Returns::Vertex { .. }), Returned::Vertex { id, .. })
            if (*id as usize) < before.vertices =>
        {
            say!(
                log,
                Warn,
                "split_edge returned v{id}, a vertex that was there before the split: it must return the new vertex"
            );
            log.about([VertexId(*id).into()]);
            false
        }
        (Some(Returns::Vertex { position }), Returned::Vertex { id, position: got }) => {
            let Some(got) = got else {
                say!(
                    log,
                    Warn,
                    "split_edge returned v{id}, which is not a vertex of the mesh"
                );
                return false;
            };
            let off = matching::nearest(&[*got], *position).map_or(f64::INFINITY, |n| n.1);
            // A NaN position is off too.
            if off.is_nan() || off > f.tolerance {
                say!(
                    log,
                    Warn,
                    "split vertex is not at the midpoint of the edge: v{id} is at {}",
                    fmt_p(*got)
                );
                log.about([VertexId(*id).into()]);
                say!(
                    log,
                    Detail,
                    "the midpoint is {} ({off:.6} away)",
                    fmt_p(*position)
                );
                return false;
            }
            true
        }
        _ => true,
    }
}

/// Flips and splits add an exact number of elements.
fn check_counts(f: &Fixture, before: Counts, after: Counts, log: &mut Log) -> bool {
    let function = f.operation.stage().function();
    let expected = match (&f.operation, &f.expected.returns) {
        (Operation::Flip { .. }, _) | (_, Some(Returns::Refused)) => before,
        (Operation::Split { .. }, _) => {
            // Split adds one vertex, an edge for the other half of the old
            // one, and an edge and a face per triangle it divides.
            let divided = f.expected.edges.len().saturating_sub(before.edges + 1);
            Counts {
                vertices: before.vertices + 1,
                edges: before.edges + 1 + divided,
                faces: before.faces + divided,
                halfedges: before.halfedges + 2 + 2 * divided,
            }
        }
        (Operation::Subdivide { rounds }, _) => {
            return check_subdivided_counts(f, before, after, *rounds, log)
        }
        // Judged step by step in `judge_sequence`.
        (Operation::Sequence { .. }, _) => return true,
    };
    if after == expected {
        return true;
    }
    let c = |c: Counts| {
        format!(
            "{} vertices, {} edges, {} faces, {} halfedges",
            c.vertices, c.edges, c.faces, c.halfedges
        )
    };
    match f.operation {
        Operation::Flip { .. } => say!(
            log,
            Warn,
            "flip_edge added or removed elements: a flip only relinks"
        ),
        _ if f.expected.returns == Some(Returns::Refused) => {
            say!(
                log,
                Warn,
                "{function} added or removed elements on an edge it must refuse"
            )
        }
        _ => say!(log, Warn, "split_edge added the wrong number of elements"),
    }
    say!(log, Detail, "before: {}", c(before));
    say!(log, Detail, "after:  {}", c(after));
    say!(log, Detail, "should: {}", c(expected));
    false
}

/// What `rounds` of the lab's subdivision make of the input's counts: each
/// round adds a vertex per edge (V' = V + E), splits every edge in two and
/// adds three inside every triangle (E' = 2E + 3T), and makes every
/// triangle four (T' = 4T); holes stay holes.
struct Subdivided {
    vertices: usize,
    edges: usize,
    triangles: usize,
    holes: usize,
}

fn subdivided(f: &Fixture, before: Counts, rounds: usize) -> Subdivided {
    let triangles = f.input.faces.len();
    let mut s = Subdivided {
        vertices: before.vertices,
        edges: before.edges,
        triangles,
        holes: before.faces.saturating_sub(triangles),
    };
    for _ in 0..rounds {
        s.vertices += s.edges;
        s.edges = 2 * s.edges + 3 * s.triangles;
        s.triangles *= 4;
    }
    s
}

/// The plain-words account of a subdivision's counts, for the first count
/// that is off.
fn counts_rule(f: &Fixture, before: Counts, rounds: usize) -> String {
    let want = subdivided(f, before, rounds);
    let t = f.input.faces.len();
    let holes = if want.holes > 0 {
        format!(
            " (and {} hole{}, which stay holes)",
            want.holes,
            if want.holes == 1 { "" } else { "s" }
        )
    } else {
        String::new()
    };
    format!(
        "each round adds one vertex per edge (V' = V + E), splits every edge in two and adds three \
         inside every triangle (E' = 2E + 3F), and makes every triangle four (F' = 4F): from {} \
         vertices, {} edges and {t} triangles{holes}, {rounds} round{} {} vertices, {} edges, {} \
         triangles",
        before.vertices,
        before.edges,
        if rounds == 1 { " gives" } else { "s give" },
        want.vertices,
        want.edges,
        want.triangles
    )
}

/// Subdivision's counts: vertices first (their message and hints are
/// [`compare_vertices`]'s), then edges, then faces, before any shape.
fn check_subdivided_counts(
    f: &Fixture,
    before: Counts,
    after: Counts,
    rounds: usize,
    log: &mut Log,
) -> bool {
    let want = subdivided(f, before, rounds);
    if after.vertices != want.vertices {
        return true;
    }
    if after.edges != want.edges {
        say!(
            log,
            Warn,
            "number of edges is wrong: {} (should be {})",
            after.edges,
            want.edges
        );
        say!(log, Detail, "{}", counts_rule(f, before, rounds));
        say!(log, Detail, "the vertices are counted right, so the edges made around each new vertex are off: split_edge adds 3 edges (2 beside a hole)");
        return false;
    }
    let faces = want.triangles + want.holes;
    if after.faces != faces {
        say!(
            log,
            Warn,
            "number of faces is wrong: {} (should be {faces})",
            after.faces
        );
        say!(log, Detail, "{}", counts_rule(f, before, rounds));
        say!(
            log,
            Detail,
            "split_edge adds 2 faces (1 beside a hole); a flip adds none"
        );
        return false;
    }
    true
}

/// How many of the expected result's vertices were there before the last
/// operation (the expected result keeps their ids and appends new ones): the
/// input's for a flip or split, the last round's input for subdivision.
fn old_vertices(f: &Fixture, before: Counts) -> usize {
    match f.operation {
        Operation::Subdivide { rounds } => subdivided(f, before, rounds.saturating_sub(1)).vertices,
        _ => before.vertices,
    }
}

/// Your vertices matched to the expected ones, as the comparison's data.
fn vertex_comparison(f: &Fixture, mesh: &MeshResult) -> (VertexMatch, Comparison) {
    let m = matching::match_by_neighbourhood(
        &mesh.positions,
        &mesh.edges,
        &f.expected.positions,
        &f.expected.edges,
        f.tolerance,
    );
    let comparison = Comparison {
        matched: m.to_expected.clone(),
        missing_vertices: m.unmatched_expected.clone(),
        extra_vertices: (0..m.to_expected.len())
            .filter(|&i| m.to_expected[i].is_none())
            .collect(),
        missing_edges: None,
        extra_edges: None,
    };
    (m, comparison)
}

/// Expected vertex -> your id, for a perfect match.
fn student_ids(f: &Fixture, m: &VertexMatch) -> Vec<usize> {
    let mut student_of = vec![0; f.expected.positions.len()];
    for (s, e) in m.to_expected.iter().enumerate() {
        if let Some(e) = e {
            student_of[*e] = s;
        }
    }
    student_of
}

/// The edge difference into the comparison: missing in expected ids,
/// extra in yours.
fn add_edge_comparison(c: &mut Comparison, diff: &matching::EdgeDiff, student_of: &[usize]) {
    c.missing_edges = Some(diff.missing.clone());
    c.extra_edges = Some(
        diff.extra
            .iter()
            .map(|&[a, b]| [student_of[a], student_of[b]])
            .collect(),
    );
}

/// The comparison alone, without a word said: what
/// [`compare_vertices`] and [`compare_edges`] would record, for a case
/// whose verdict stopped before them.
fn comparison_of(f: &Fixture, mesh: &MeshResult) -> Comparison {
    let (m, mut c) = vertex_comparison(f, mesh);
    if m.is_perfect() {
        let diff =
            matching::diff_edges(&matching::mapped_edges(&mesh.edges, &m), &f.expected.edges);
        add_edge_comparison(&mut c, &diff, &student_ids(f, &m));
    }
    c
}

fn compare_vertices(
    f: &Fixture,
    mesh: &MeshResult,
    before: Counts,
    log: &mut Log,
) -> Option<VertexMatch> {
    let expected = &f.expected;
    say!(log, Info, "compare all vertices...");
    let (got, want) = (mesh.positions.len(), expected.positions.len());
    // Matched even when the counts differ: the verdict is the count, but
    // the report draws which expected vertices none of yours is at.
    let (m, comparison) = vertex_comparison(f, mesh);
    log.comparison = Some(comparison);
    if got != want {
        say!(
            log,
            Warn,
            "number of vertices is wrong: {got} (should be {want})"
        );
        if let Operation::Subdivide { rounds } = f.operation {
            say!(log, Detail, "{}", counts_rule(f, before, rounds));
            if got == before.vertices {
                hint!(log, f, Hint::Grader(GraderHint::NoVertexAdded));
            } else if got > want {
                hint!(log, f, Hint::Grader(GraderHint::TooManyVertices));
            } else {
                hint!(log, f, Hint::Grader(GraderHint::TooFewVertices));
            }
        }
        return None;
    }
    if !m.is_perfect() {
        say!(
            log,
            Warn,
            "at least one of the vertices has incorrect position"
        );
        let wrong = m.unmatched_expected.len();
        say!(
            log,
            Detail,
            "{wrong} of {want} expected vertices have no vertex of yours within {} of them",
            f.tolerance
        );
        if let Operation::Subdivide { .. } = f.operation {
            let old = old_vertices(f, before);
            let old_wrong = m.unmatched_expected.iter().filter(|&&i| i < old).count();
            let new_wrong = wrong - old_wrong;
            let new = want - old;
            let text = match (old_wrong, new_wrong) {
                (0, n) => format!("every old vertex is right; {n} of {new} new vertices are wrong: look at the edge rule (3/8 of the edge's ends, 1/8 of the two far corners, each from the mesh before any change)"),
                (o, 0) => format!("every new vertex is right; {o} of {old} old vertices are wrong: look at the vertex rule (u = 3/16 when n = 3, else 3/(8n), from the neighbours' old positions)"),
                (o, n) => format!("{o} of {old} old vertices and {n} of {new} new vertices are wrong"),
            };
            say!(log, Detail, "{text}");
        }
        if let Some(&i) = m.unmatched_expected.first() {
            let p = expected.positions[i];
            say!(log, Detail, "expected a vertex at {}", fmt_p(p));
            if let Some((j, d)) = matching::nearest(&mesh.positions, p) {
                say!(
                    log,
                    Detail,
                    "your nearest vertex is v{j} at {} ({d:.6} away)",
                    fmt_p(mesh.positions[j])
                );
                log.about([VertexId(j as u32).into()]);
            }
        }
        for mistake in &expected.mistakes {
            if let Some(ps) = &mistake.positions {
                if matching::same_positions(&mesh.positions, ps, f.tolerance) {
                    hint!(log, f, Hint::Catalogue(mistake.id.clone()));
                    break;
                }
            }
        }
        return None;
    }
    say!(log, Info, "passed");
    Some(m)
}

fn compare_edges(
    f: &Fixture,
    mesh: &MeshResult,
    before: Counts,
    m: &VertexMatch,
    log: &mut Log,
) -> bool {
    let expected = &f.expected;
    say!(log, Info, "compare all edges...");
    let (got, want) = (mesh.edges.len(), expected.edges.len());
    // Compared before the count is checked: the report draws the
    // difference even when the verdict is the count.
    let mine = matching::mapped_edges(&mesh.edges, m);
    let diff = matching::diff_edges(&mine, &expected.edges);
    let student_of = student_ids(f, m);
    if let Some(c) = &mut log.comparison {
        add_edge_comparison(c, &diff, &student_of);
    }
    if got != want {
        say!(
            log,
            Warn,
            "number of edges is wrong: {got} (should be {want})"
        );
        return false;
    }
    if diff.is_empty() && mine.len() == want {
        say!(log, Info, "passed");
        return true;
    }
    say!(
        log,
        Warn,
        "at least one of the edges connects incorrect vertices"
    );
    let p = |i: usize| fmt_p(expected.positions[i]);
    if let Some(&[a, b]) = diff.missing.first() {
        say!(
            log,
            Detail,
            "missing: an edge between v{} {} and v{} {}",
            student_of[a],
            p(a),
            student_of[b],
            p(b)
        );
        log.about([a, b].map(|x| VertexId(student_of[x] as u32).into()));
    }
    if let Some(&[a, b]) = diff.extra.first() {
        say!(
            log,
            Detail,
            "extra: your edge between v{} {} and v{} {}",
            student_of[a],
            p(a),
            student_of[b],
            p(b)
        );
        log.about([a, b].map(|x| VertexId(student_of[x] as u32).into()));
    }
    if mine.len() != want {
        say!(
            log,
            Detail,
            "two of your edges join the same pair of vertices"
        );
    }
    if let Operation::Subdivide { .. } = f.operation {
        edge_kinds(&diff.missing, &diff.extra, old_vertices(f, before), log);
    }
    for mistake in &expected.mistakes {
        if let Some(edges) = &mistake.edges {
            if matching::diff_edges(&mine, edges).is_empty() {
                hint!(log, f, Hint::Catalogue(mistake.id.clone()));
                break;
            }
        }
    }
    false
}

/// Which kinds of vertex the missing and extra edges of a subdivision join
/// (old: there before the last round), and what that usually means.
fn edge_kinds(missing: &[[usize; 2]], extra: &[[usize; 2]], old: usize, log: &mut Log) {
    // [old-old, old-new, new-new]
    let tally = |edges: &[[usize; 2]]| {
        let mut k = [0usize; 3];
        for &[a, b] in edges {
            k[usize::from(a >= old) + usize::from(b >= old)] += 1;
        }
        k
    };
    let describe = |k: [usize; 3]| {
        let names = [
            "two old vertices",
            "an old and a new vertex",
            "two new vertices",
        ];
        let parts: Vec<String> = k
            .iter()
            .zip(names)
            .filter(|(n, _)| **n > 0)
            .map(|(n, what)| format!("{n} join {what}"))
            .collect();
        parts.join(", ")
    };
    let (lost, added) = (tally(missing), tally(extra));
    if missing.is_empty() && extra.is_empty() {
        return;
    }
    say!(
        log,
        Detail,
        "of the missing edges {}; of your extra edges {}",
        if missing.is_empty() {
            "none".to_string()
        } else {
            describe(lost)
        },
        if extra.is_empty() {
            "none".to_string()
        } else {
            describe(added)
        }
    );
    if added[2] > 0 && lost[1] > 0 {
        say!(log, Detail, "were edges between two new vertices flipped? flip only new edges that join an old and a new vertex");
    } else if lost[2] > 0 && added[1] > 0 {
        say!(
            log,
            Detail,
            "new edges joining an old and a new vertex were left unflipped: flip each of them once"
        );
    }
}

/// What the returned element looks like in the result: the flipped edge's
/// new ends, the split vertex's halfedge.
fn check_returned_shape(
    f: &Fixture,
    returned: &Returned,
    mesh: &MeshResult,
    m: &VertexMatch,
    log: &mut Log,
) {
    let to_expected = |i: usize| m.to_expected.get(i).copied().flatten();
    match (&f.expected.returns, returned, f.operation) {
        (Some(Returns::Edge { ends }), Returned::Edge { got, .. }, _) => {
            let got_ends = mesh
                .returned_edge_ends
                .map(|[a, b]| [to_expected(a), to_expected(b)]);
            let want = [Some(ends[0].min(ends[1])), Some(ends[0].max(ends[1]))];
            let got_sorted = got_ends.map(|[a, b]| [a.min(b), a.max(b)]);
            if got_sorted != Some(want) {
                say!(
                    log,
                    Warn,
                    "the returned edge e{got} does not join the two vertices that faced it"
                );
                log.about([EdgeId(*got).into()]);
            }
        }
        (
            Some(Returns::Vertex { .. }),
            Returned::Vertex { id, .. },
            Operation::Split { edge: [a, b] },
        ) => {
            let leads = mesh.returned_vertex_leads_to.and_then(to_expected);
            if leads != Some(a) && leads != Some(b) {
                say!(
                    log,
                    Warn,
                    "the new vertex's halfedge does not run along the split edge"
                );
                log.about([VertexId(*id).into()]);
                log.first_about(Some(Pointer::Vertex));
                say!(log, Detail, "mesh[v{id}].halfedge must lead to vertex {a} or {b}, the ends of the edge that was split");
            }
            if let Some(ids) = &mesh.split {
                check_split_ids(ids, *id, [a, b], &to_expected, log);
            }
        }
        _ => {}
    }
}

/// The contract's rules on ids after a split: the new vertex keeps its
/// defaults, the edge's id names one half of the old edge, the old faces
/// are triangles around the new vertex.
fn check_split_ids(
    ids: &SplitIds,
    m: u32,
    [a, b]: [usize; 2],
    to_expected: &dyn Fn(usize) -> Option<usize>,
    log: &mut Log,
) {
    if ids.is_new || ids.new_pos != [0.0; 3] {
        say!(
            log,
            Warn,
            "split_edge set is_new or new_pos on the new vertex: a split leaves them false and zero (loop_subdivide sets them after the call)"
        );
        say!(
            log,
            Detail,
            "mesh[v{m}].is_new is {}, mesh[v{m}].new_pos is {}",
            ids.is_new,
            fmt_p(ids.new_pos)
        );
        log.about([VertexId(m).into()]);
    }
    let [x, y] = ids.edge_ends;
    let other = if x == m as usize { y } else { x };
    let half = (x == m as usize || y == m as usize)
        && matches!(to_expected(other), Some(o) if o == a || o == b);
    if !half {
        say!(
            log,
            Warn,
            "after split_edge, edge e{} is not half of the edge that was split: it must join the new vertex to one of its ends",
            ids.edge
        );
        say!(
            log,
            Detail,
            "e{} joins v{x} and v{y}; the new vertex is v{m}",
            ids.edge
        );
        log.about([
            EdgeId(ids.edge as u32).into(),
            VertexId(x as u32).into(),
            VertexId(y as u32).into(),
            VertexId(m).into(),
        ]);
    }
    if let Some(f) = ids.faces_away.first() {
        say!(
            log,
            Warn,
            "after split_edge, face f{f} is not one of the triangles around the new vertex: each old face beside the edge must become one of them"
        );
        log.about([FaceId(*f as u32).into()]);
    }
}

/// Adds a detail line to a case's report, above its "end testing" line.
pub fn add_detail(report: &mut CaseReport, text: String) {
    let (mut log, end) = Log::resume(report);
    say!(log, Detail, "{text}");
    log.finish(report, end);
}

/// Adds the step-through's finding to a failed case: which split broke
/// the mesh, with the elements it names.
pub fn note_frames(report: &mut CaseReport, frames: crate::judge::frames::Frames) {
    if let (false, Some(b)) = (report.passed, &frames.broken) {
        let (mut log, end) = Log::resume(report);
        say!(log, Detail, "{}", b.line);
        log.about(b.elements.iter().copied());
        log.finish(report, end);
    }
    report.frames = Some(frames);
}

/// Says, under a failure, that it showed only on a relabelled input, what
/// that input looked like, and what to check (chosen from what the
/// failure is about: [`CaseReport::pointer`], never its words).
pub fn note_labelling(
    report: &mut CaseReport,
    f: &Fixture,
    labelling: &crate::judge::relabel::Labelling,
    index: usize,
    total: usize,
    seed: u64,
) {
    use crate::judge::relabel::Kind;
    let (mut log, end) = Log::resume(report);
    log.passed = false;
    say!(
        log,
        Detail,
        "this case passes on the mesh as built from its faces, and fails on labelling {index} of {} (seed {seed}; replay: cargo run -p grader -- --case {} --seed {seed})",
        total - 1,
        f.name
    );
    say!(log, Detail, "there, before the call: {}", labelling.what);
    let advice = match (labelling.kind, f.operation.stage(), report.pointer) {
        (Kind::HoleSide, _, _) => GraderHint::LabellingHoleSide,
        (_, Stage::Subdivide, _) => GraderHint::LabellingSubdivide,
        (_, _, Some(Pointer::Vertex)) => GraderHint::LabellingVertexPointer,
        (_, _, Some(Pointer::Face)) => GraderHint::LabellingFacePointer,
        _ => GraderHint::LabellingAnyPointer,
    };
    hint!(log, f, Hint::Grader(advice));
    log.finish(report, end);
    report.labelling = Some(LabellingFacts {
        index,
        of: total - 1,
        seed,
        kind: labelling.kind,
        permutation: labelling.permutation.clone(),
    });
    report.name_in_case(&labelling.permutation);
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

/// `loop_subdivide` is built on `split_edge` and `flip_edge`: when those
/// failed their own cases, say so under each failed subdivision.
pub fn note_dependencies(reports: &mut [CaseReport]) {
    let broken: Vec<&'static str> = [Stage::Split, Stage::Flip]
        .into_iter()
        .filter(|&s| reports.iter().any(|r| r.stage == s && !r.passed))
        .map(Stage::function)
        .collect();
    if broken.is_empty() {
        return;
    }
    for r in reports
        .iter_mut()
        .filter(|r| r.stage == Stage::Subdivide && !r.passed)
    {
        let (mut log, end) = Log::resume(r);
        say!(
            log,
            Detail,
            "loop_subdivide calls your {}, which failed above: fix that first",
            broken.join(" and ")
        );
        log.finish(r, end);
    }
}
