//! One case's inspector data, the JSON blob its card holds: the meshes, the
//! marks, the handout's names, both numberings of a relabelled input, the
//! element "select error" picks and the frames, put together from the
//! pieces `inspector.rs` writes.

use std::fmt::Write as _;

use halfedge::{Element, VertexId};

use super::inspector::{self, Frames};
use super::marks::{named_elements, CasePictures};
use crate::judge::fixture::{Fixture, Operation};
use crate::judge::verdict::CaseReport;

/// How the input as sent differs from the mesh built from the case's faces.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Labelled {
    AsBuilt,
    /// The same ids, other pointers (`mesh[v].halfedge` and the like).
    Pointers,
    /// Other ids.
    Ids,
}

/// The inspector's data for one case (see `inspector.rs`), and how the
/// input was relabelled.
pub(super) fn case_data(
    f: &Fixture,
    r: &CaseReport,
    pics: &CasePictures,
    frames: Option<&Frames>,
) -> (String, Labelled) {
    let mut out = String::with_capacity(4096);
    let op = f.operation.stage().key();
    out.push_str("{\"name\":");
    inspector::string(&mut out, &f.name);
    let _ = write!(out, ",\"op\":\"{op}\",\"passed\":{}", r.passed);
    // The elements the messages are about, in the mesh they are about.
    let named = if r.passed {
        Vec::new()
    } else {
        named_elements(&r.entries)
    };
    let (named_yours, named_input) = match (&r.result, &r.input) {
        (Some(_), _) => (
            inspector::named_found(&pics.marks_yours, &named),
            Vec::new(),
        ),
        (None, Some(_)) => (
            Vec::new(),
            inspector::named_found(&pics.marks_input, &named),
        ),
        (None, None) => (Vec::new(), Vec::new()),
    };
    meshes_json(&mut out, r, pics);
    out.push_str(",\"marks\":{\"input\":");
    inspector::marks_json(&mut out, &pics.marks_input, &named_input);
    out.push_str(",\"expected\":");
    inspector::marks_json(&mut out, &pics.marks_expected, &[]);
    out.push_str(",\"yours\":");
    inspector::marks_json(&mut out, &pics.marks_yours, &named_yours);
    out.push('}');
    out.push_str(",\"names\":");
    names_json(&mut out, f, r, pics);
    out.push_str(",\"caseIds\":");
    let relabelled = case_ids_json(&mut out, f, r, pics);
    out.push_str(",\"error\":");
    let error = first_error(r, pics, &named_yours, &named_input);
    match error.filter(|_| !r.passed) {
        Some((pane, e)) => {
            let _ = write!(out, "{{\"pane\":\"{pane}\",\"el\":\"{e}\"}}");
        }
        None => out.push_str("null"),
    }
    out.push_str(",\"frames\":");
    match frames {
        Some(fr) => inspector::frames_json(&mut out, fr),
        None => out.push_str("null"),
    }
    out.push('}');
    (out, relabelled)
}

/// The input and the student's result with every record, the expected
/// result by positions and faces (none on a pass: it is yours).
fn meshes_json(out: &mut String, r: &CaseReport, pics: &CasePictures) {
    out.push_str(",\"input\":");
    match &r.input {
        Some(m) => inspector::mesh_json(out, m),
        None => out.push_str("null"),
    }
    out.push_str(",\"expected\":");
    if r.passed {
        out.push_str("null");
    } else {
        inspector::shape_json(
            out,
            &pics.expected,
            &pics.student_of_expected,
            &pics.input_of_expected,
        );
    }
    out.push_str(",\"yours\":");
    match &r.result {
        Some(m) => inspector::mesh_json(out, m),
        None => out.push_str("null"),
    }
}

/// The handout's names, for a flip or split; `null` otherwise.
fn names_json(out: &mut String, f: &Fixture, r: &CaseReport, pics: &CasePictures) {
    match (&r.input, pics.case_edge, f.operation) {
        (Some(input), Some(edge), Operation::Flip { .. } | Operation::Split { .. }) => {
            let split = matches!(f.operation, Operation::Split { .. });
            let (before, after) = inspector::handout_names(input, edge, split, r.result.as_ref());
            out.push_str("{\"input\":");
            inspector::names_json(out, &before);
            out.push_str(",\"yours\":");
            inspector::names_json(out, &after);
            // In the expected result, by the case's vertex numbering.
            let expected: Vec<(Element, &str)> = after
                .iter()
                .filter_map(|&(e, n)| match e {
                    Element::Vertex(_) if n == "m" => pics
                        .new_vertex
                        .map(|k| (Element::Vertex(VertexId(k as u32)), n)),
                    Element::Vertex(v) => pics
                        .case_of
                        .get(v.index())
                        .copied()
                        .flatten()
                        .map(|k| (Element::Vertex(VertexId(k as u32)), n)),
                    _ => None,
                })
                .collect();
            out.push_str(",\"expected\":");
            inspector::names_json(out, &expected);
            out.push('}');
        }
        _ => out.push_str("null"),
    }
}

/// Both numberings, when the input was relabelled (`null` when its ids
/// are the case's); returns how it was relabelled.
fn case_ids_json(out: &mut String, f: &Fixture, r: &CaseReport, pics: &CasePictures) -> Labelled {
    let numbering = match (&r.input, f.input.to_mesh()) {
        (Some(sent), Ok(case)) => inspector::case_numbering(sent, &case, &pics.case_of),
        _ => None,
    };
    let relabelled = if numbering.is_some() {
        Labelled::Ids
    } else {
        match (&r.input, f.input.to_mesh()) {
            (Some(sent), Ok(case)) if sent.records() != case.records() => Labelled::Pointers,
            _ => Labelled::AsBuilt,
        }
    };
    match numbering {
        Some([v, e, fs, h]) => {
            let put = |out: &mut String, key: &str, m: &[i64]| {
                let _ = write!(out, "\"{key}\":[");
                for (k, x) in m.iter().enumerate() {
                    if k > 0 {
                        out.push(',');
                    }
                    let _ = write!(out, "{x}");
                }
                out.push(']');
            };
            out.push('{');
            put(out, "v", &v);
            out.push(',');
            put(out, "e", &e);
            out.push(',');
            put(out, "f", &fs);
            out.push(',');
            put(out, "h", &h);
            out.push('}');
        }
        None => out.push_str("null"),
    }
    relabelled
}

/// What "select error" picks: the first element the messages name,
/// else the first wrong vertex, missing vertex, extra or missing edge.
fn first_error(
    r: &CaseReport,
    pics: &CasePictures,
    named_yours: &[Element],
    named_input: &[Element],
) -> Option<(&'static str, Element)> {
    named_yours
        .first()
        .map(|&e| ("yours", e))
        .or_else(|| named_input.first().map(|&e| ("input", e)))
        .or_else(|| {
            let (v, _) = pics.marks_yours.wrong_points.first()?;
            Some(("yours", Element::Vertex(VertexId(*v as u32))))
        })
        .or_else(|| {
            let (v, _) = pics.marks_expected.wrong_points.first()?;
            Some(("expected", Element::Vertex(VertexId(*v as u32))))
        })
        .or_else(|| {
            let [a, b] = *pics.marks_yours.wrong_edges.first()?;
            let e = r.result.as_ref()?.edge_between(a, b)?;
            Some(("yours", Element::Edge(e)))
        })
        .or_else(|| {
            let [a, _] = *pics.marks_expected.wrong_edges.first()?;
            Some(("expected", Element::Vertex(VertexId(a as u32))))
        })
}
