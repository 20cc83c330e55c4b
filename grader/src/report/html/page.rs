//! The report's page: the head every page shares (style, the inspector's
//! script and style), the case list, failing cases first, then each case's
//! card (`card.rs`) with its OBJ files beside the page (`obj.rs`); and the
//! live page `--watch` reloads.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::card::{case_html, first_warning_shown, operation};
use super::escape;
use super::inspector::Frames;
use super::obj::write_obj_files;
use super::svg::{legend, shade_css};
use crate::judge::fixture::{Fixture, Group};
use crate::judge::verdict::CaseReport;

/// The inspector's script: the files of `script/`, one script in this
/// order (`model.js` opens the function scope they share, `start.js`
/// starts the inspectors and closes it), inlined once per page.
pub(super) const INSPECTOR_JS: &str = concat!(
    include_str!("script/model.js"),
    include_str!("script/inspector.js"),
    include_str!("script/frames.js"),
    include_str!("script/camera.js"),
    include_str!("script/render.js"),
    include_str!("script/labels.js"),
    include_str!("script/pick.js"),
    include_str!("script/controls.js"),
    include_str!("script/panel.js"),
    include_str!("script/start.js"),
);
/// The inspector's style.
pub(super) const INSPECTOR_CSS: &str = include_str!("inspector.css");

/// The pages' style (the static pictures' shades are `svg.rs`'s).
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

/// Writes the report for `cases` into `dir` (created if needed) and returns
/// the path of its `index.html`.
pub fn write_report(dir: &Path, cases: &[(&Fixture, &CaseReport)]) -> Result<PathBuf, String> {
    write_report_live(dir, cases, false)
}

/// The case list's row for a case: its verdict, a link to its card, what
/// it is and its first problem.
fn list_row(list: &mut String, f: &Fixture, r: &CaseReport) {
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
}

/// The file a live report polls: its stamp changes with every rewrite.
pub const STAMP_FILE: &str = "watch-stamp.js";

/// Reloads the page when the stamp [`STAMP_FILE`] sets changes: a script
/// element, not `fetch`, which pages opened from `file://` may not use.
const LIVE_SCRIPT: &str = "<script src=\"watch-stamp.js\"></script>\n<script>\n// Written by --watch: reload when the grader rewrites this report.\n(function () {\n  var first = window.meshlabStamp;\n  setInterval(function () {\n    var s = document.createElement('script');\n    s.src = 'watch-stamp.js?' + Date.now();\n    s.onload = function () { s.remove(); if (window.meshlabStamp !== first) location.reload(); };\n    s.onerror = function () { s.remove(); };\n    document.head.appendChild(s);\n  }, 1000);\n})();\n</script>\n";

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
        let files = write_obj_files(dir, f, r)?;
        list_row(&mut list, f, r);
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
