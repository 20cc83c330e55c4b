//! One case's card: its verdict, messages, OBJ links and what the code
//! printed beside its inspector (the data from `case_data.rs`), and the
//! static pictures in a `<noscript>` below.

use std::fmt::Write as _;

use super::case_data::{case_data, Labelled};
use super::escape;
use super::inspector::Frames;
use super::marks::{pictures, CasePictures};
use super::svg::draw;
use super::view::{Prepared, View};
use crate::judge::fixture::{Fixture, Group, Operation, Returns};
use crate::judge::verdict::{CaseReport, Level};
use crate::quoted::Quoted;

/// Static pictures of meshes with more vertices show one view, not three.
const STATIC_VIEWS_LIMIT: usize = 200;

/// Characters of what the student's code printed kept in the page.
const OUTPUT_LIMIT: usize = 6000;

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

/// The first warning as shown, student text in it escaped.
pub(super) fn first_warning_shown(r: &CaseReport) -> Option<String> {
    crate::report::first_warning(r)
}

/// The inspector's place in a case: its data, and the element the script
/// fills (hidden until it runs, so a page without script shows nothing
/// of it).
pub(super) fn inspector_html(html: &mut String, data: &str) {
    html.push_str("<div class=\"inspector\" hidden>");
    html.push_str("<script type=\"application/json\" class=\"inspector-data\">");
    html.push_str(data);
    html.push_str("</script></div>\n");
}

/// The card of case `f` (its OBJ files already written: `files`).
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
    log_html(html, r, files, &pics);
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
    static_pictures(html, f, r, &pics);
    html.push_str("</details></noscript></div>\n</div>\n</section>\n");
}

/// The card's left column: the first warning, every entry, the OBJ links,
/// what the code printed, the pictures' notes.
fn log_html(html: &mut String, r: &CaseReport, files: &[(&str, String)], pics: &CasePictures) {
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
    printed_html(html, &r.output, true);
    if !pics.notes.is_empty() {
        html.push_str("<ul class=\"notes\">");
        for n in &pics.notes {
            let _ = write!(html, "<li>{}</li>", escape(n));
        }
        html.push_str("</ul>\n");
    }
}

/// What the student's code printed, folded: each line under `| `, control
/// characters escaped, as everywhere, and cut at [`OUTPUT_LIMIT`]
/// characters; with `count_lines`, the summary says how many lines.
pub(super) fn printed_html(html: &mut String, output: &Quoted, count_lines: bool) {
    if output.is_blank() {
        return;
    }
    let all = output.block("");
    let mut shown: String = all.chars().take(OUTPUT_LIMIT).collect();
    if shown.len() < all.len() {
        shown.push_str("\n… (cut)");
    }
    let lines = if count_lines {
        format!(" ({} lines)", all.lines().count())
    } else {
        String::new()
    };
    let _ = writeln!(
        html,
        "<details class=\"output\"><summary>what your code printed{lines}</summary><pre>{}</pre></details>",
        escape(&shown)
    );
}

/// The static pictures' table: a row per view; columns input, expected
/// (failed cases only: on a pass it is the same as yours), yours.
fn static_pictures(html: &mut String, f: &Fixture, r: &CaseReport, pics: &CasePictures) {
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
    html.push_str("</tbody></table>\n");
}
