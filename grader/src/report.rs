//! Printing the reports: the lab's text format, JSON, and Gradescope's
//! `results.json`.

use std::fmt::Write as _;

use serde::Serialize;
use serde_json::json;

use crate::fixture::Group;
use crate::grade::{CaseReport, Level};

/// Whether a case's verdict counts toward the final one.
pub fn counts(case: &CaseReport, bonus: bool) -> bool {
    case.group != Group::Bonus || bonus
}

/// Whether the whole run passed.
pub fn all_passed(cases: &[CaseReport], bonus: bool) -> bool {
    cases.iter().filter(|c| counts(c, bonus)).all(|c| c.passed)
}

fn location(file: &str, line: u32) -> String {
    format!("{}:{line}", halfedge::logging::short_file(file))
}

/// A log line in the lab's format, `[warn]` in red when `color`.
fn log_line(out: &mut String, file: &str, line: u32, warn: bool, text: &str, color: bool) {
    let (word, on, off) = match (warn, color) {
        (true, true) => ("warn", "\x1b[31m", "\x1b[0m"),
        (true, false) => ("warn", "", ""),
        (false, _) => ("info", "", ""),
    };
    let _ = writeln!(out, "{} {on}[{word}] {text}{off}", location(file, line));
}

fn render_case(out: &mut String, case: &CaseReport, color: bool) {
    for (i, e) in case.entries.iter().enumerate() {
        match e.level {
            Level::Info => log_line(out, e.file, e.line, false, &e.text, color),
            Level::Warn => log_line(out, e.file, e.line, true, &e.text, color),
            Level::Detail => {
                let _ = writeln!(out, "        {}", e.text);
            }
        }
        // The student's output goes right under "start testing", where it ran.
        if i == 0 && !case.output.trim().is_empty() {
            let _ = writeln!(out, "    your code printed:");
            for l in case.output.trim_end().lines() {
                let _ = writeln!(out, "    | {l}");
            }
        }
    }
}

/// The whole text report: the protections in force, lab (and hidden)
/// cases, then bonus cases apart, a summary per function, and the verdict
/// as the last line.
pub fn text(cases: &[CaseReport], bonus: bool, color: bool, protections: &str) -> String {
    let mut out = String::new();
    log_line(&mut out, file!(), line!(), false, protections, color);
    let (main, extra): (Vec<_>, Vec<_>) = cases.iter().partition(|c| c.group != Group::Bonus);
    for case in &main {
        render_case(&mut out, case, color);
    }
    if !extra.is_empty() {
        let counted = if bonus {
            "counted"
        } else {
            "not counted; pass --bonus to count them"
        };
        log_line(
            &mut out,
            file!(),
            line!(),
            false,
            &format!("bonus cases: meshes with boundary ({counted})"),
            color,
        );
        for case in &extra {
            render_case(&mut out, case, color);
        }
    }
    for (label, group) in [("lab", false), ("bonus", true)] {
        let set: Vec<_> = cases
            .iter()
            .filter(|c| (c.group == Group::Bonus) == group)
            .collect();
        if set.is_empty() {
            continue;
        }
        let mut parts = Vec::new();
        for stage in ["flip_edge", "split_edge", "loop_subdivide"] {
            let of: Vec<_> = set.iter().filter(|c| c.stage.function() == stage).collect();
            if !of.is_empty() {
                let ok = of.iter().filter(|c| c.passed).count();
                parts.push(format!("{stage} {ok}/{}", of.len()));
            }
        }
        log_line(
            &mut out,
            file!(),
            line!(),
            false,
            &format!("{label} cases passed: {}", parts.join(", ")),
            color,
        );
    }
    if all_passed(cases, bonus) {
        log_line(
            &mut out,
            file!(),
            line!(),
            false,
            "all tests passed, congratulations!",
            color,
        );
    } else {
        log_line(&mut out, file!(), line!(), true, "test failed", color);
    }
    out
}

#[derive(Serialize)]
struct JsonReport<'a> {
    passed: bool,
    bonus_counted: bool,
    protections: &'a str,
    cases: &'a [CaseReport],
}

/// The report as JSON, for scripts.
pub fn json(cases: &[CaseReport], bonus: bool, protections: &str) -> String {
    serde_json::to_string_pretty(&JsonReport {
        passed: all_passed(cases, bonus),
        bonus_counted: bonus,
        protections,
        cases,
    })
    .expect("reports serialize")
}

/// Gradescope's `results.json`: one test per case, one point each (bonus
/// cases are worth points only with `--bonus`), with the case's text.
pub fn gradescope(cases: &[CaseReport], bonus: bool) -> String {
    let tests: Vec<_> = cases
        .iter()
        .map(|c| {
            let mut output = String::new();
            render_case(&mut output, c, false);
            let max = if counts(c, bonus) { 1.0 } else { 0.0 };
            json!({
                "name": format!("{} ({})", c.name, c.stage.function()),
                "score": if c.passed { max } else { 0.0 },
                "max_score": max,
                "status": if c.passed { "passed" } else { "failed" },
                "output": output,
                "visibility": "visible",
            })
        })
        .collect();
    let score: f64 = tests.iter().filter_map(|t| t["score"].as_f64()).sum();
    let verdict = if all_passed(cases, bonus) {
        "all tests passed, congratulations!"
    } else {
        "test failed"
    };
    serde_json::to_string_pretty(&json!({
        "score": score,
        "output": verdict,
        "tests": tests,
    }))
    .expect("results serialize")
}
