//! The page: the case list, and per case its verdict, messages, OBJ files,
//! the inspector and the static pictures (in a `<noscript>`); the OBJ files
//! beside it. Also `try --report`'s page, on the same pieces.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use halfedge::Mesh;

use super::escape;
use super::faces::Shape;
use halfedge::{Element, VertexId};

use super::inspector::{self, Frames};
use super::marks::{named_elements, pictures, resolve_names, CasePictures, Marks, LABEL_LIMIT};
use super::sides;
use super::svg::{draw, legend, shade_css};
use super::view::{Camera, Prepared, View};
use crate::judge::fixture::{Fixture, Group, Operation, Returns};
use crate::judge::verdict::{CaseReport, Level};

/// The inspector: its script and style, inlined once per page.
const INSPECTOR_JS: &str = include_str!("inspector.js");
const INSPECTOR_CSS: &str = include_str!("inspector.css");

/// Static pictures of meshes with more vertices show one view, not three.
const STATIC_VIEWS_LIMIT: usize = 200;

/// Characters of what the student's code printed kept in the page.
pub(super) const OUTPUT_LIMIT: usize = 6000;

/// What a case is, in words: `split_edge on cube, edge 2-0`.
pub(super) fn operation(f: &Fixture) -> String {
    let function = f.operation.stage().function();
    match f.operation {
        Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] } => {
            format!("{function} on {}, edge {a}-{b}", f.object)
        }
        Operation::Subdivide { rounds: 1 } => format!("{function} on {}, 1 round", f.object),
        Operation::Subdivide { rounds } => format!("{function} on {}, {rounds} rounds", f.object),
        Operation::Sequence { seed } => format!(
            "{} flips and splits on {} (seed {seed})",
            f.steps.len(),
            f.object
        ),
    }
}

/// The expected result as OBJ: its vertices, the faces rebuilt from its
/// edges, and as `l` lines the edges no face has.
pub(super) fn expected_obj(f: &Fixture, shape: &Shape) -> String {
    let mut out = format!(
        "# expected result of {} ({})\n# fixtures keep edges, not faces: the faces below are rebuilt from the edges\n",
        f.name,
        operation(f)
    );
    for p in &f.expected.positions {
        let _ = writeln!(out, "v {} {} {}", p[0], p[1], p[2]);
    }
    obj_faces_and_lines(&mut out, shape);
    out
}

pub(super) fn obj_faces_and_lines(out: &mut String, shape: &Shape) {
    for face in &shape.faces {
        out.push('f');
        for v in face {
            let _ = write!(out, " {}", v + 1);
        }
        out.push('\n');
    }
    let in_faces: HashSet<[usize; 2]> = shape.faces.iter().flat_map(|f| sides(f)).collect();
    for e in shape.edges.iter().filter(|e| !in_faces.contains(*e)) {
        let _ = writeln!(out, "l {} {}", e[0] + 1, e[1] + 1);
    }
}

/// The student's result as OBJ: exactly the mesh when it is valid, else
/// what could be read of it (faces that close, other edges as `l` lines).
pub(super) fn yours_obj(f: &Fixture, mesh: &Mesh, shape: &Shape) -> String {
    match mesh.validate() {
        Ok(()) => format!("# your result for {}\n{}", f.name, mesh.to_obj_string()),
        Err(problem) => {
            let mut out = format!(
                "# your result for {}: NOT a valid mesh ({problem})\n# below: every vertex, the faces whose next-loop closes, other edges as l lines\n",
                f.name
            );
            for p in mesh.positions() {
                let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
            }
            obj_faces_and_lines(&mut out, shape);
            out
        }
    }
}

/// The first warning as shown, student text in it escaped.
pub(super) fn first_warning_shown(r: &CaseReport) -> Option<String> {
    crate::report::first_warning(r)
}

pub(super) const STYLE: &str = r#"
body{font:14px/1.45 system-ui,-apple-system,"Segoe UI",sans-serif;margin:0 auto;padding:12px 20px 60px;max-width:1500px;color:#1b1f24;background:#f6f7f9}
h1{font-size:22px;margin:8px 0}
h2{font-size:17px;margin:0 0 6px}
a{color:#0b57d0}
code,pre{font:12.5px/1.4 ui-monospace,"SFMono-Regular",Menlo,Consolas,monospace}
.summary{font-size:15px}
.badge{display:inline-block;padding:0 7px;border-radius:9px;font-size:12px;font-weight:600;color:#fff;vertical-align:1px}
.badge.failed{background:#c62828}.badge.passed{background:#2e7d32}.badge.bonus{background:#8a6d00}
table.list{border-collapse:collapse;background:#fff;box-shadow:0 1px 2px #0002}
table.list td,table.list th{padding:3px 10px;border-bottom:1px solid #e4e6ea;text-align:left;vertical-align:top}
table.list tr.failed td:first-child{border-left:4px solid #c62828}
table.list tr.passed td:first-child{border-left:4px solid #2e7d32}
.legend{display:flex;flex-wrap:wrap;gap:4px 18px;margin:10px 0 18px;font-size:13px}
.legend svg{vertical-align:middle}
.case{background:#fff;border-radius:6px;box-shadow:0 1px 3px #0002;margin:18px 0;padding:12px 14px}
.case.failed{border-left:5px solid #c62828}.case.passed{border-left:5px solid #2e7d32}
.case>summary{cursor:pointer;font-weight:600}
.meta{color:#555;margin:0 0 8px}
.body{display:flex;flex-wrap:wrap;gap:14px;align-items:flex-start}
.log{flex:1 1 380px;min-width:320px;max-width:560px}
.log ol{list-style:none;margin:0;padding:8px 10px;background:#f3f4f6;border-radius:4px;font:12.5px/1.45 ui-monospace,Menlo,Consolas,monospace;white-space:pre-wrap;overflow-wrap:anywhere}
.log li.info{color:#59636e}
.log li.warn{color:#b71c1c;font-weight:600}
.log li.detail{padding-left:2em;color:#1b1f24}
.log li.hint{background:#fff3bf;border-left:3px solid #f08c00;padding:2px 4px 2px calc(2em - 3px);font-weight:600;margin:2px 0}
.verdict{font-weight:600;color:#b71c1c;margin:0 0 6px}
.files a{margin-right:10px}
.notes{color:#6d4c00;font-size:13px;margin:6px 0 0;padding-left:18px}
table.pics{border-collapse:collapse}
table.pics th{font-size:12px;font-weight:600;color:#444;padding:2px 4px;text-align:center}
table.pics th.row{text-align:right;width:64px;font-weight:400}
table.pics td{padding:2px}
td.none{width:230px;vertical-align:top;text-align:center;color:#777;background:#fafafa;border:1px dashed #ccc;font-size:13px;padding:10px}
svg.view{background:#fff;border:1px solid #dde1e6;border-radius:3px;display:block}
svg.view .faces{stroke:#2a3a4f;stroke-opacity:.55;stroke-linejoin:round}
svg.view .loose{fill:none;stroke:#41536b;stroke-width:.8}
svg.view .loose.behind{stroke-opacity:.3;stroke-dasharray:2 2}
svg.view .dots{fill:none;stroke:#1d2733;stroke-width:3.2;stroke-linecap:round}
svg.view .dots.small{stroke-width:2}
svg.view .case-edge{stroke:#ef6c00;stroke-width:3.2;stroke-linecap:round}
svg.view .case-vertex{fill:none;stroke:#ef6c00;stroke-width:2.2}
svg.view .named path,svg.view .named circle{fill:none;stroke:#8e24aa;stroke-width:3;stroke-opacity:.75;stroke-linejoin:round;stroke-linecap:round}
svg.view .named text{font:bold 10px ui-monospace,Menlo,Consolas,monospace;fill:#8e24aa;paint-order:stroke;stroke:#fff;stroke-width:3px}
svg.view .wrong.edge{fill:none;stroke:#e00000;stroke-width:2.2;stroke-linecap:round}
svg.view .wrong.edge.ghost{stroke-width:1.6;stroke-dasharray:4 3}
svg.view .wrong.edge.move{stroke-width:1;stroke-dasharray:2 2}
svg.view circle.wrong.vertex{fill:#e00000;stroke:#fff;stroke-width:1}
svg.view path.wrong.vertex{fill:none;stroke:#e00000;stroke-width:5;stroke-linecap:round}
svg.view circle.wrong.ghost{fill:none;stroke:#e00000;stroke-width:1.6;stroke-dasharray:3 2}
svg.view .behind{opacity:.45}
svg.view .labels{font:9px ui-monospace,Menlo,Consolas,monospace;fill:#1d2733;paint-order:stroke;stroke:#fff;stroke-width:2.5px;stroke-linejoin:round}
svg.view .labels .red{fill:#c00000;font-weight:700}
details.output pre{max-height:16em;overflow:auto;background:#f3f4f6;padding:6px}
pre.quote{margin:2px 0;white-space:pre-wrap}
"#;

/// The inspector's data for one case (see `inspector.rs`).
/// How the input as sent differs from the mesh built from the case's faces.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Labelled {
    AsBuilt,
    /// The same ids, other pointers (`mesh[v].halfedge` and the like).
    Pointers,
    /// Other ids.
    Ids,
}

/// Also how the input was relabelled.
fn case_data(
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
    out.push_str(",\"input\":");
    match &r.input {
        Some(m) => inspector::mesh_json(&mut out, m),
        None => out.push_str("null"),
    }
    out.push_str(",\"expected\":");
    if r.passed {
        out.push_str("null");
    } else {
        inspector::shape_json(
            &mut out,
            &pics.expected,
            &pics.student_of_expected,
            &pics.input_of_expected,
        );
    }
    out.push_str(",\"yours\":");
    match &r.result {
        Some(m) => inspector::mesh_json(&mut out, m),
        None => out.push_str("null"),
    }
    out.push_str(",\"marks\":{\"input\":");
    inspector::marks_json(&mut out, &pics.marks_input, &named_input);
    out.push_str(",\"expected\":");
    inspector::marks_json(&mut out, &pics.marks_expected, &[]);
    out.push_str(",\"yours\":");
    inspector::marks_json(&mut out, &pics.marks_yours, &named_yours);
    out.push('}');
    // The handout's names, for a flip or split.
    out.push_str(",\"names\":");
    match (&r.input, pics.case_edge, f.operation) {
        (Some(input), Some(edge), Operation::Flip { .. } | Operation::Split { .. }) => {
            let split = matches!(f.operation, Operation::Split { .. });
            let (before, after) = inspector::handout_names(input, edge, split, r.result.as_ref());
            out.push_str("{\"input\":");
            inspector::names_json(&mut out, &before);
            out.push_str(",\"yours\":");
            inspector::names_json(&mut out, &after);
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
            inspector::names_json(&mut out, &expected);
            out.push('}');
        }
        _ => out.push_str("null"),
    }
    // Both numberings, when the input was relabelled.
    out.push_str(",\"caseIds\":");
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
            put(&mut out, "v", &v);
            out.push(',');
            put(&mut out, "e", &e);
            out.push(',');
            put(&mut out, "f", &fs);
            out.push(',');
            put(&mut out, "h", &h);
            out.push('}');
        }
        None => out.push_str("null"),
    }
    // What "select error" picks: the first element the messages name,
    // else the first wrong vertex, missing vertex, extra or missing edge.
    out.push_str(",\"error\":");
    let error: Option<(&str, Element)> = named_yours
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
        });
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

/// The inspector's place in a case: its data, and the element the script
/// fills (hidden until it runs, so a page without script shows nothing
/// of it).
fn inspector_html(html: &mut String, data: &str) {
    html.push_str("<div class=\"inspector\" hidden>");
    html.push_str("<script type=\"application/json\" class=\"inspector-data\">");
    html.push_str(data);
    html.push_str("</script></div>\n");
}

pub(super) fn case_html(
    html: &mut String,
    f: &Fixture,
    r: &CaseReport,
    files: &[(&str, String)],
    frames: Option<&Frames>,
) {
    let verdict = if r.passed { "passed" } else { "failed" };
    let pics = pictures(f, r);
    let group = match f.group {
        Group::Lab => "lab case",
        Group::Hidden => "hidden case",
        Group::Bonus => "bonus case (counted only with --bonus)",
    };
    let _ = write!(
        html,
        "<section class=\"case {verdict}\" id=\"case-{0}\" data-case=\"{0}\">\n<h2><span class=\"badge {verdict}\">{verdict}</span> {0}</h2>\n<p class=\"meta\">{1} · {group} · tolerance {2}</p>\n<div class=\"body\">\n<div class=\"log\">\n",
        escape(&f.name),
        escape(&operation(f)),
        f.tolerance
    );
    if let Some(w) = first_warning_shown(r) {
        let _ = writeln!(html, "<p class=\"verdict\">{}</p>", escape(&w));
    }
    html.push_str("<ol>");
    for e in &r.entries {
        let class = match e.level {
            Level::Info => "info",
            Level::Warn => "warn",
            // A hint line by its data (`Entry::hint`), not its words.
            Level::Detail if e.hint.is_some() => "detail hint",
            Level::Detail => "detail",
        };
        let below = e.quote_below("");
        let _ = write!(html, "<li class=\"{class}\">{}", escape(&e.one_line()));
        if !below.is_empty() {
            let _ = write!(html, "<pre class=\"quote\">{}</pre>", escape(&below));
        }
        html.push_str("</li>");
    }
    html.push_str("</ol>\n<p class=\"files\">OBJ files: ");
    for (what, name) in files {
        let _ = write!(html, "<a href=\"{0}\">{1}</a>", escape(name), what);
    }
    html.push_str("</p>\n");
    if !r.output.is_blank() {
        // Each line under `| `, control characters escaped, as everywhere.
        let all = r.output.block("");
        let lines = all.lines().count();
        let mut shown: String = all.chars().take(OUTPUT_LIMIT).collect();
        if shown.len() < all.len() {
            shown.push_str("\n… (cut)");
        }
        let _ = writeln!(
            html,
            "<details class=\"output\"><summary>what your code printed ({lines} lines)</summary><pre>{}</pre></details>",
            escape(&shown)
        );
    }
    if !pics.notes.is_empty() {
        html.push_str("<ul class=\"notes\">");
        for n in &pics.notes {
            let _ = write!(html, "<li>{}</li>", escape(n));
        }
        html.push_str("</ul>\n");
    }
    html.push_str("</div>\n");

    let (data, relabelled) = case_data(f, r, &pics, frames);
    html.push_str("<div class=\"pictures\">");
    match relabelled {
        Labelled::Ids => html.push_str(
            "<p class=\"relabelled\">This failure showed on a relabelled copy of the input: the pictures and the messages use that copy's ids (<i>input (as sent)</i>), not the ids in the title; the inspector's panel gives both.</p>",
        ),
        Labelled::Pointers => html.push_str(
            "<p class=\"relabelled\">This failure showed on a copy of the input whose pointers (<code>mesh[v].halfedge</code>, <code>mesh[e].halfedge</code>, <code>mesh[f].halfedge</code>) were chosen afresh; its ids are the case's.</p>",
        ),
        Labelled::AsBuilt => {}
    }
    inspector_html(html, &data);
    html.push_str(
        "<noscript><details class=\"static\" open><summary>static pictures, three fixed views</summary>\n",
    );

    // Pictures: a row per view; columns input, expected (failed cases
    // only: on a pass it is the same as yours), yours.
    let input = Prepared::new(&pics.input);
    let expected = Prepared::new(&pics.expected);
    let yours = pics.yours.as_ref().map(Prepared::new);
    let show_expected = !r.passed;
    html.push_str("<table class=\"pics\"><thead><tr><th></th><th>input (as sent)</th>");
    if show_expected {
        let what = match f.expected.returns {
            Some(Returns::Refused) => "expected<br><small>unchanged: it must return None</small>",
            Some(Returns::Panic) => "expected<br><small>unchanged: it must panic</small>",
            _ => "expected",
        };
        let _ = write!(html, "<th>{what}</th>");
    }
    html.push_str("<th>yours</th></tr></thead><tbody>\n");
    // A passing case needs fewer pictures: the first view and the opposite.
    // A large mesh gets one: the inspector turns it any way, and three
    // views of every large case would make the page too heavy to open.
    let large = pics
        .expected
        .len()
        .max(pics.yours.as_ref().map_or(0, |y| y.len()))
        > STATIC_VIEWS_LIMIT;
    let views: Vec<(usize, &View)> = pics
        .cameras
        .iter()
        .enumerate()
        .filter(|(k, _)| (!r.passed || *k != 1) && (!large || *k == 0))
        .collect();
    for &(k, view) in &views {
        let _ = write!(
            html,
            "<tr><th class=\"row\">view {}<br><small>{}</small></th><td class=\"input\">",
            k + 1,
            view.why
        );
        draw(
            html,
            &view.input,
            &input,
            &pics.marks_input,
            &format!("input, view {}", k + 1),
        );
        html.push_str("</td>");
        if show_expected {
            html.push_str("<td class=\"expected\">");
            draw(
                html,
                &view.result,
                &expected,
                &pics.marks_expected,
                &format!("expected result, view {}", k + 1),
            );
            html.push_str("</td>");
        }
        match &yours {
            Some(y) => {
                html.push_str("<td class=\"yours\">");
                draw(
                    html,
                    &view.result,
                    y,
                    &pics.marks_yours,
                    &format!("your result, view {}", k + 1),
                );
                html.push_str("</td>");
            }
            None if k == views[0].0 => {
                let why = first_warning_shown(r)
                    .unwrap_or_else(|| "the function did not return a mesh".to_string());
                let _ = write!(
                    html,
                    "<td class=\"yours none\" rowspan=\"{}\">no mesh to show:<br>{}</td>",
                    views.len(),
                    escape(&why)
                );
            }
            None => {}
        }
        html.push_str("</tr>\n");
    }
    html.push_str("</tbody></table>\n</details></noscript></div>\n</div>\n</section>\n");
}

/// Writes the report for `cases` into `dir` (created if needed) and returns
/// the path of its `index.html`.
pub fn write_report(dir: &Path, cases: &[(&Fixture, &CaseReport)]) -> Result<PathBuf, String> {
    write_report_live(dir, cases, false)
}

/// The file a live report polls: its stamp changes with every rewrite.
pub const STAMP_FILE: &str = "watch-stamp.js";

/// Reloads the page when the stamp [`STAMP_FILE`] sets changes: a script
/// element, not `fetch`, which pages opened from `file://` may not use.
pub(super) const LIVE_SCRIPT: &str = "<script src=\"watch-stamp.js\"></script>\n<script>\n// Written by --watch: reload when the grader rewrites this report.\n(function () {\n  var first = window.meshlabStamp;\n  setInterval(function () {\n    var s = document.createElement('script');\n    s.src = 'watch-stamp.js?' + Date.now();\n    s.onload = function () { s.remove(); if (window.meshlabStamp !== first) location.reload(); };\n    s.onerror = function () { s.remove(); };\n    document.head.appendChild(s);\n  }, 1000);\n})();\n</script>\n";

/// [`write_report`], and with `live` (under `--watch`) a page that reloads
/// itself when a later run rewrites it.
pub fn write_report_live(
    dir: &Path,
    cases: &[(&Fixture, &CaseReport)],
    live: bool,
) -> Result<PathBuf, String> {
    // Each subdivision's step-through, where the grader recorded one.
    let frames: Vec<Option<Frames>> = cases
        .iter()
        .map(|(_, r)| {
            r.frames.as_ref().map(Frames::from_recorded).map(|mut fr| {
                // A case that passed has nothing broken to point at, even
                // where a frame looked wrong along the way (a split off
                // the midpoint that the round's moves put right).
                if r.passed {
                    fr.first_broken = None;
                }
                fr
            })
        })
        .collect();
    let cases: Vec<(&Fixture, &CaseReport, Option<&Frames>)> = cases
        .iter()
        .zip(&frames)
        .map(|(&(f, r), frames)| (f, r, frames.as_ref()))
        .collect();
    write_report_frames(dir, &cases, live)
}

/// [`write_report_live`] with, per case, the frames of a step-through
/// (the mesh before each of the student's operations) where there are any.
pub fn write_report_frames(
    dir: &Path,
    cases: &[(&Fixture, &CaseReport, Option<&Frames>)],
    live: bool,
) -> Result<PathBuf, String> {
    let io = |p: &Path, e: std::io::Error| format!("{}: {e}", p.display());
    std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    // Failing cases first, the counted ones before the bonus; otherwise in
    // the grader's order.
    let mut order: Vec<&(&Fixture, &CaseReport, Option<&Frames>)> = cases.iter().collect();
    order.sort_by_key(|(f, r, _)| (r.passed, f.group == Group::Bonus));
    let failed = order.iter().filter(|(_, r, _)| !r.passed).count();

    let mut list = String::new();
    let mut body = String::new();
    for &&(f, r, frames) in &order {
        let write = |name: String, text: String| -> Result<String, String> {
            let path = dir.join(&name);
            std::fs::write(&path, text).map_err(|e| io(&path, e))?;
            Ok(name)
        };
        let expected_shape = Shape::expected(f);
        let mut files = Vec::new();
        if let Some(input) = &r.input {
            files.push((
                "input",
                write(format!("{}.input.obj", f.name), input.to_obj_string())?,
            ));
        }
        files.push((
            "expected",
            write(
                format!("{}.expected.obj", f.name),
                expected_obj(f, &expected_shape),
            )?,
        ));
        if let Some(result) = &r.result {
            let shape = Shape::from_mesh(result);
            files.push((
                "yours",
                write(
                    format!("{}.yours.obj", f.name),
                    yours_obj(f, result, &shape),
                )?,
            ));
        }
        let verdict = if r.passed { "passed" } else { "failed" };
        let bonus = if f.group == Group::Bonus {
            " <span class=\"badge bonus\">bonus</span>"
        } else {
            ""
        };
        let _ = writeln!(
            list,
            "<tr class=\"{verdict}\"><td><span class=\"badge {verdict}\">{verdict}</span>{bonus}</td><td><a href=\"#case-{0}\">{0}</a></td><td>{1}</td><td>{2}</td></tr>",
            escape(&f.name),
            escape(&operation(f)),
            escape(&first_warning_shown(r).unwrap_or_default())
        );
        case_html(&mut body, f, r, &files, frames);
    }

    let mut html = String::with_capacity(body.len() + list.len() + 8192);
    let _ = write!(
        html,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>grader report: {failed} of {} failed</title>\n<style>{STYLE}{}{INSPECTOR_CSS}</style>\n{}</head><body>\n<h1>Grader report</h1>\n",
        order.len(),
        shade_css(),
        if live { LIVE_SCRIPT } else { "" }
    );
    let summary = if failed == 0 {
        format!("All {} cases passed.", order.len())
    } else {
        format!(
            "{failed} of {} cases failed; they come first. Start with the first one: later functions build on earlier ones.",
            order.len()
        )
    };
    let _ = writeln!(html, "<p class=\"summary\">{}</p>", escape(&summary));
    let _ = writeln!(
        html,
        "<table class=\"list\" id=\"cases\"><thead><tr><th>verdict</th><th>case</th><th>what</th><th>first problem</th></tr></thead><tbody>\n{list}</tbody></table>"
    );
    let _ = writeln!(html, "<div class=\"legend\">{}</div>", legend());
    html.push_str(&body);
    html.push_str("<script>\n");
    html.push_str(INSPECTOR_JS);
    html.push_str("</script>\n</body></html>\n");
    let index = dir.join("index.html");
    std::fs::write(&index, html).map_err(|e| io(&index, e))?;
    if live {
        // Written after the page, so a reload finds the new one.
        let stamp = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let path = dir.join(STAMP_FILE);
        std::fs::write(&path, format!("window.meshlabStamp = \"{stamp}\";\n"))
            .map_err(|e| io(&path, e))?;
    }
    Ok(index)
}

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
    // The data: input and yours, no expected result.
    let mut data = String::from("{\"name\":\"try\",\"op\":\"try\",\"passed\":");
    let _ = write!(data, "{}", invalid.is_none() && page.result.is_some());
    data.push_str(",\"input\":");
    inspector::mesh_json(&mut data, page.input);
    data.push_str(",\"expected\":null,\"yours\":");
    match page.result {
        Some(m) => inspector::mesh_json(&mut data, m),
        None => data.push_str("null"),
    }
    data.push_str(",\"marks\":{\"input\":");
    inspector::marks_json(&mut data, &marks_input, &[]);
    data.push_str(",\"yours\":");
    inspector::marks_json(
        &mut data,
        &marks_yours,
        &inspector::named_found(&marks_yours, &named),
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
    match invalid.as_ref() {
        Some(i) => {
            let _ = write!(data, "{{\"pane\":\"yours\",\"el\":\"{}\"}}", i.element);
        }
        None => data.push_str("null"),
    }
    data.push_str(",\"frames\":null,\"select\":true}");

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
    let shown = crate::quoted::Quoted::new(page.output.clone());
    if !shown.is_blank() {
        let all = shown.block("");
        let mut cut: String = all.chars().take(OUTPUT_LIMIT).collect();
        if cut.len() < all.len() {
            cut.push_str("\n… (cut)");
        }
        let _ = writeln!(
            html,
            "<details class=\"output\"><summary>what your code printed</summary><pre>{}</pre></details>",
            escape(&cut)
        );
    }
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
