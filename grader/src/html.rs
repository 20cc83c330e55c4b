//! `--report DIR`: what a student looks at when a case fails. For every
//! case: the input, the student's result and the expected result as OBJ
//! files (MeshLab, Blender), and one self-contained offline `index.html`
//! with the verdict beside each case, failing cases first.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::fixture::Fixture;
use crate::grade::{CaseReport, Level};

/// The expected result as OBJ: its vertices and its edges as `l` lines
/// (fixtures keep positions and edges, not faces).
fn expected_obj(f: &Fixture) -> String {
    let mut out = format!("# expected result of {}\n", f.name);
    for p in &f.expected.positions {
        let _ = writeln!(out, "v {} {} {}", p[0], p[1], p[2]);
    }
    for [a, b] in &f.expected.edges {
        let _ = writeln!(out, "l {} {}", a + 1, b + 1);
    }
    out
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Writes the report for `cases` into `dir` (created if needed) and returns
/// the path of its `index.html`.
pub fn write_report(dir: &Path, cases: &[(&Fixture, &CaseReport)]) -> Result<PathBuf, String> {
    let io = |p: &Path, e: std::io::Error| format!("{}: {e}", p.display());
    std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    let mut order: Vec<&(&Fixture, &CaseReport)> = cases.iter().collect();
    order.sort_by_key(|(_, r)| r.passed);
    let mut html = String::from(
        "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>grader report</title></head><body>\n<h1>Grader report</h1>\n<ul id=\"cases\">\n",
    );
    for (f, r) in order {
        let write = |name: String, text: String| -> Result<String, String> {
            let path = dir.join(&name);
            std::fs::write(&path, text).map_err(|e| io(&path, e))?;
            Ok(name)
        };
        let mut files = vec![write(format!("{}.expected.obj", f.name), expected_obj(f))?];
        if let Some(input) = &r.input {
            files.push(write(
                format!("{}.input.obj", f.name),
                input.to_obj_string(),
            )?);
        }
        if let Some(result) = r.result.as_ref().filter(|m| m.validate().is_ok()) {
            files.push(write(
                format!("{}.yours.obj", f.name),
                result.to_obj_string(),
            )?);
        }
        let verdict = if r.passed { "passed" } else { "failed" };
        let _ = write!(
            html,
            "<li class=\"case {verdict}\" id=\"{}\"><h2>{} ({verdict})</h2>\n<pre>",
            escape(&f.name),
            escape(&f.name)
        );
        for e in &r.entries {
            let pad = if e.level == Level::Detail { "    " } else { "" };
            let _ = writeln!(html, "{pad}{}", escape(&e.text));
        }
        html.push_str("</pre>\n<p>");
        for name in files {
            let _ = write!(html, "<a href=\"{0}\">{0}</a> ", escape(&name));
        }
        html.push_str("</p></li>\n");
    }
    html.push_str("</ul>\n</body></html>\n");
    let index = dir.join("index.html");
    std::fs::write(&index, html).map_err(|e| io(&index, e))?;
    Ok(index)
}
