//! `try --report`'s page: the student's own mesh before and after their
//! function, what `try` said, the inspector on both (no expected result),
//! and the static pictures in a `<noscript>`; the same style and script as
//! the report's page.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use halfedge::{Element, Mesh};

use super::card::{inspector_html, printed_html};
use super::escape;
use super::faces::Shape;
use super::inspector;
use super::marks::{resolve_names, Marks, LABEL_LIMIT};
use super::page::{INSPECTOR_CSS, INSPECTOR_JS, STYLE};
use super::svg::{draw, shade_css};
use super::view::{Camera, Prepared};

/// What `grader try --report` shows: the student's own mesh before and
/// after their function, and what was said about it.
pub struct TrialPage<'a> {
    /// `flip_edge on my.obj, edge 1-2` (in the file's numbering).
    pub title: String,
    /// The lines `try` printed: warning or not, and the text.
    pub lines: Vec<(bool, String)>,
    /// What the student's code printed.
    pub output: String,
    pub input: &'a Mesh,
    pub result: Option<&'a Mesh>,
    /// The operation's edge (the mesh's ids) and whether it is a split.
    pub edge: Option<([usize; 2], bool)>,
}

/// Writes `try`'s page into `dir` (created if needed) and returns the path
/// of its `index.html`. When the result is invalid, the element
/// `validate()` names is the one "select error" picks, and is selected.
pub fn write_trial_report(dir: &Path, page: &TrialPage) -> Result<PathBuf, String> {
    let io = |p: &Path, e: std::io::Error| format!("{}: {e}", p.display());
    std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    let invalid = page.result.and_then(|m| m.validate().err());
    let named: Vec<Element> = invalid.iter().map(|i| i.element).collect();
    let input_shape = Shape::from_mesh(page.input);
    let yours_shape = page.result.map(Shape::from_mesh);
    let labels = |n: usize| {
        if n < LABEL_LIMIT {
            (0..n).map(|i| Some(format!("v{i}"))).collect()
        } else {
            Vec::new()
        }
    };
    let case_edge = page.edge.map(|([a, b], _)| [a.min(b), a.max(b)]);
    let marks_input = Marks {
        focus_edges: case_edge.into_iter().collect(),
        labels: labels(input_shape.len()),
        side: "input",
        ..Marks::default()
    };
    let mut marks_yours = Marks {
        labels: yours_shape.as_ref().map_or(Vec::new(), |s| labels(s.len())),
        side: "yours",
        ..Marks::default()
    };
    if let Some(result) = page.result {
        marks_yours.named = resolve_names(result, &named);
    }
    let error = invalid.as_ref().map(|i| i.element);
    let data = trial_data(page, &marks_input, &marks_yours, &named, error);

    let verdict = if invalid.is_some() || page.result.is_none() {
        "failed"
    } else {
        "passed"
    };
    let mut html = String::new();
    let _ = write!(
        html,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>grader try: {0}</title>\n<style>{STYLE}{1}{INSPECTOR_CSS}</style>\n</head><body>\n<h1>grader try</h1>\n<section class=\"case {verdict}\" id=\"case-try\" data-case=\"try\">\n<h2>{0}</h2>\n<div class=\"body\">\n<div class=\"log\">\n<ol>",
        escape(&page.title),
        shade_css()
    );
    for (warn, text) in &page.lines {
        let class = if *warn { "warn" } else { "info" };
        let _ = write!(html, "<li class=\"{class}\">{}</li>", escape(text));
    }
    html.push_str("</ol>\n");
    let printed = crate::quoted::Quoted::new(page.output.clone());
    printed_html(&mut html, &printed, false);
    html.push_str("</div>\n<div class=\"pictures\">");
    inspector_html(&mut html, &data);
    // The static pictures: input and yours, from a corner.
    html.push_str("<noscript><details class=\"static\" open><summary>static pictures</summary>\n<table class=\"pics\"><thead><tr><th>input</th><th>yours</th></tr></thead><tbody><tr><td class=\"input\">");
    let dir3 = halfedge::DVec3::new(0.55, 0.45, 0.75);
    let input_p = Prepared::new(&input_shape);
    draw(
        &mut html,
        &Camera::fit(dir3, &input_shape.points),
        &input_p,
        &marks_input,
        "input",
    );
    html.push_str("</td>");
    match &yours_shape {
        Some(y) => {
            html.push_str("<td class=\"yours\">");
            draw(
                &mut html,
                &Camera::fit(dir3, &input_shape.points),
                &Prepared::new(y),
                &marks_yours,
                "your result",
            );
            html.push_str("</td>");
        }
        None => html.push_str("<td class=\"yours none\">no mesh to show</td>"),
    }
    html.push_str(
        "</tr></tbody></table></details></noscript></div>\n</div>\n</section>\n<script>\n",
    );
    html.push_str(INSPECTOR_JS);
    html.push_str("</script>\n</body></html>\n");
    let index = dir.join("index.html");
    std::fs::write(&index, html).map_err(|e| io(&index, e))?;
    Ok(index)
}

/// The inspector's data for `try`'s page: input and yours, no expected
/// result; `error`, the element `validate()` names, selected on opening.
fn trial_data(
    page: &TrialPage,
    marks_input: &Marks,
    marks_yours: &Marks,
    named: &[Element],
    error: Option<Element>,
) -> String {
    let mut data = String::from("{\"name\":\"try\",\"op\":\"try\",\"passed\":");
    let _ = write!(data, "{}", error.is_none() && page.result.is_some());
    data.push_str(",\"input\":");
    inspector::mesh_json(&mut data, page.input);
    data.push_str(",\"expected\":null,\"yours\":");
    match page.result {
        Some(m) => inspector::mesh_json(&mut data, m),
        None => data.push_str("null"),
    }
    data.push_str(",\"marks\":{\"input\":");
    inspector::marks_json(&mut data, marks_input, &[]);
    data.push_str(",\"yours\":");
    inspector::marks_json(
        &mut data,
        marks_yours,
        &inspector::named_found(marks_yours, named),
    );
    data.push_str("},\"names\":");
    match page.edge {
        Some((edge, split)) => {
            let (before, after) = inspector::handout_names(page.input, edge, split, page.result);
            data.push_str("{\"input\":");
            inspector::names_json(&mut data, &before);
            data.push_str(",\"yours\":");
            inspector::names_json(&mut data, &after);
            data.push('}');
        }
        None => data.push_str("null"),
    }
    data.push_str(",\"caseIds\":null,\"error\":");
    match error {
        Some(e) => {
            let _ = write!(data, "{{\"pane\":\"yours\",\"el\":\"{e}\"}}");
        }
        None => data.push_str("null"),
    }
    data.push_str(",\"frames\":null,\"select\":true}");
    data
}
