//! Judging one case: turns the child's report into the lab's messages, in
//! the lab's order, with details and a hint under a failure, and the
//! findings as data beside the words ([`crate::judge::verdict`]). The
//! checks live beside it by job: how a call ended ([`super::ended`]), what
//! it returned ([`super::returned`]), the counts ([`super::counts`]), the
//! shape ([`super::compare`]), a sequence ([`super::sequence`]). Nothing
//! here decides anything from a message's words:
//! [`crate::text::set_rewording`] rewrites every one, and the tests check
//! that no verdict, hint or element moves.

use crate::isolate::end::CaseEnd;
use crate::isolate::end::{Counts, Finished, MeshResult, Problem, Returned, SequenceRan};
use crate::isolate::runner::ChildReport;
use crate::judge::compare::{compare_edges, compare_vertices, comparison_of};
use crate::judge::counts::check_counts;
use crate::judge::fixture::{Fixture, Operation, Returns, Stage};
use crate::judge::log::{hint, say, Log};
use crate::judge::returned::{check_returned, check_returned_shape};
pub use crate::judge::verdict::CaseReport;
use crate::judge::verdict::{GraderHint, Hint, LabellingFacts, Pointer};
use crate::quoted::Quoted;

// Until the isolate layer and scaling stop reaching up here (issue 33).
pub use crate::text::{set_rewording, words};

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
    say!(
        log,
        Info,
        "start testing {} for {what}",
        stage.names().heading
    );
    judge_run(f, end, failed, &mut log);
    say!(
        log,
        Info,
        "end testing {} for {what}",
        stage.names().heading
    );
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
    let must_panic = f.expected.returns == Some(Returns::Panic);
    match end {
        CaseEnd::Sequence(seq) => {
            let SequenceRan {
                steps,
                panic,
                before,
                after,
                invalid,
                mesh,
            } = seq.as_ref();
            super::sequence::judge_sequence(
                f,
                steps,
                panic.as_ref(),
                (*before, *after),
                invalid.as_ref(),
                mesh.as_deref(),
                log,
            )
        }
        CaseEnd::Returned(finished) if !must_panic => {
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
        _ => super::ended::say_how(f, end, failed, log),
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
            .find(|m| m.invalid.is_some() && m.invalid == problem.check())
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

/// Adds a detail line to a case's report, above its "end testing" line.
fn add_detail(report: &mut CaseReport, text: String) {
    let (mut log, end) = Log::resume(report);
    say!(log, Detail, "{text}");
    log.finish(report, end);
}

/// Adds the step-through's finding to a failed case: which split broke
/// the mesh, with the elements it names.
fn note_frames(report: &mut CaseReport, frames: crate::judge::frames::Frames) {
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
fn note_labelling(
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

/// Says, under a failure, which functions it calls failed their own
/// cases (`loop_subdivide` is built on `split_edge` and `flip_edge`).
fn note_calls_failed(report: &mut CaseReport, failed: &[Stage]) {
    let names: Vec<&str> = failed.iter().map(|s| s.function()).collect();
    let function = report.stage.function();
    let (mut log, end) = Log::resume(report);
    say!(
        log,
        Detail,
        "{function} calls your {}, which failed above: fix that first",
        names.join(" and ")
    );
    log.finish(report, end);
}

/// Everything known about a case's call when its report is made.
pub struct CaseRun<'a> {
    /// How the call ended, what it printed, the mesh it left and what it
    /// recorded.
    pub child: ChildReport,
    /// The input as it was sent.
    pub sent: &'a crate::judge::relabel::Labelling,
    /// Which labelling it was (0: the mesh as built), of how many, and the
    /// seed they came from.
    pub labelling: (usize, usize, u64),
    /// The call's limit was cut to this many seconds because the function
    /// already timed out on the case named.
    pub limit_cut: Option<(f64, String)>,
    /// Of the stages this one's function calls ([`Stage::calls`]), those
    /// that failed their own cases.
    pub calls_failed: Vec<Stage>,
}

/// The case's finished report: the judge's verdict on the call with
/// everything said about it (the step-through's finding, the note on a
/// relabelled input, a cut limit, the functions it calls that failed).
/// The one entry point: nothing amends a report afterwards. The judge
/// walks data the student's code made, so a panic in it is the grader's
/// bug, said as such, never a crash of the whole run.
pub fn judge_case(f: &Fixture, run: CaseRun) -> CaseReport {
    let CaseRun {
        mut child,
        sent,
        labelling: (index, total, seed),
        limit_cut,
        calls_failed,
    } = run;
    let mut report = match crate::isolate::guard::guarded(|| judge(f, &child)) {
        Ok(r) => r,
        Err((message, _)) => judge_failed(f, &message, &child.output),
    };
    report.input = Some(sent.mesh.clone());
    report.result = child.mesh.take();
    if let Some(recorded) = child.recorded.take() {
        let frames =
            crate::judge::frames::read(recorded, report.result.as_ref(), &sent.mesh, f.tolerance);
        note_frames(&mut report, frames);
    }
    if !report.passed && index > 0 {
        note_labelling(&mut report, f, sent, index, total, seed);
    }
    if let (true, Some((limit, earlier))) = (report.timed_out, limit_cut) {
        let function = report.stage.function();
        add_detail(
            &mut report,
            format!(
                "the limit was cut to {limit} s because {function} already timed out on {earlier}"
            ),
        );
    }
    if !report.passed && !calls_failed.is_empty() {
        note_calls_failed(&mut report, &calls_failed);
    }
    report
}
