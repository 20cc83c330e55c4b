//! Reporting: renderings of the judge's findings. This module prints the
//! lab's text format, JSON and Gradescope's `results.json`; [`html`] draws
//! the `--report` page; [`protections`] the protections line; [`quoted`]
//! (the crate's, re-exported here) is how anything the student's code said
//! is shown (as data, under `| `).
//!
//! Nothing here decides a verdict: every function reads
//! [`CaseReport`]s, never another module's message text.

pub mod html;
pub mod protections;
pub use crate::quoted;

use std::fmt::Write as _;

use serde::Serialize;
use serde_json::json;

use crate::judge::fixture::{Group, Stage};
use crate::judge::verdict::{CaseReport, Level};

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
            Level::Info => log_line(out, e.file, e.line, false, &e.one_line(), color),
            Level::Warn => log_line(out, e.file, e.line, true, &e.one_line(), color),
            Level::Detail => {
                let _ = writeln!(out, "        {}", e.one_line());
            }
        }
        out.push_str(&e.quote_below("        "));
        // The student's output goes right under "start testing", where it ran.
        if i == 0 && !case.output.is_blank() {
            let _ = writeln!(out, "    your code printed:");
            out.push_str(&case.output.block("    "));
        }
    }
}

/// A failed case's first warning on one line (student text in it escaped
/// and cut), as the summary, JSON and the class reports show it.
pub fn first_warning(case: &CaseReport) -> Option<String> {
    case.entries
        .iter()
        .find(|e| e.level == Level::Warn)
        .map(|e| e.one_line())
}

/// How the text report is shown.
#[derive(Clone, Debug, Default)]
pub struct TextOptions {
    /// Bonus cases count toward the verdict.
    pub bonus: bool,
    pub color: bool,
    /// The protections line.
    pub protections: String,
    /// Show every bonus case in full even when they do not count.
    pub verbose: bool,
    /// Only the summary and the verdict.
    pub quiet: bool,
    /// What part of the lab was graded (`--stage flip`, `--case X`), for a
    /// run that graded only part: it never ends with the lab's
    /// congratulations.
    pub partial: Option<String>,
    /// Where `--report` wrote its index.html, said above the verdict.
    pub report: Option<String>,
    /// The case the run was limited to (`--case NAME`): `next:` never
    /// suggests the command just run.
    pub focus: Option<String>,
    /// The per-call limit, when `--budget` shortened it.
    pub time: Option<String>,
    /// `loop_subdivide` timed on two sizes, when it was.
    pub scaling: Option<crate::judge::scaling::Scaling>,
}

/// At most this many failing cases are listed in the summary.
const SUMMARY_FAILURES: usize = 8;

/// The whole text report: the protections in force, lab (and hidden)
/// cases, bonus cases apart (one line when they do not count), then a
/// summary a student reads at a glance: cases passed per function, each
/// failing case with its first warning, the next command to run, and the
/// verdict as the last line.
pub fn text(cases: &[CaseReport], opts: &TextOptions) -> String {
    let color = opts.color;
    let mut out = String::new();
    log_line(&mut out, file!(), line!(), false, &opts.protections, color);
    if let Some(time) = &opts.time {
        log_line(&mut out, file!(), line!(), false, time, color);
    }
    let (main, extra): (Vec<_>, Vec<_>) = cases.iter().partition(|c| c.group != Group::Bonus);
    if !opts.quiet {
        for case in &main {
            render_case(&mut out, case, color);
        }
    }
    if !extra.is_empty() {
        let ok = extra.iter().filter(|c| c.passed).count();
        let shown = opts.bonus || opts.verbose;
        let counted = if opts.bonus {
            "counted".to_string()
        } else if shown {
            "not counted; pass --bonus to count them".to_string()
        } else {
            format!(
                "not counted: {ok} of {} passed; --bonus to count them, -v to see them",
                extra.len()
            )
        };
        if !opts.quiet || !opts.bonus {
            log_line(
                &mut out,
                file!(),
                line!(),
                false,
                &format!("bonus cases: meshes with boundary ({counted})"),
                color,
            );
        }
        if shown && !opts.quiet {
            for case in &extra {
                render_case(&mut out, case, color);
            }
        }
    }
    summary(&mut out, cases, opts);
    out
}

/// (text, case) pairs grouped by text, in first-seen order: cases that
/// failed alike, or got the same hint, share a line.
fn alike<'a>(items: impl Iterator<Item = (String, &'a str)>) -> Vec<(String, Vec<&'a str>)> {
    let mut groups: Vec<(String, Vec<&str>)> = Vec::new();
    for (text, name) in items {
        match groups.iter_mut().find(|(t, _)| *t == text) {
            Some((_, names)) => names.push(name),
            None => groups.push((text, vec![name])),
        }
    }
    groups
}

/// "cube-split", or "cube-split and 3 more".
fn who(names: &[&str]) -> String {
    match names {
        [one] => one.to_string(),
        [first, rest @ ..] => format!("{first} and {} more", rest.len()),
        [] => String::new(),
    }
}

/// The last lines: tallies, failures, what to do next, the verdict.
fn summary(out: &mut String, cases: &[CaseReport], opts: &TextOptions) {
    let color = opts.color;
    for (label, group) in [("lab", false), ("bonus", true)] {
        let set: Vec<_> = cases
            .iter()
            .filter(|c| (c.group == Group::Bonus) == group)
            .collect();
        if set.is_empty() {
            continue;
        }
        let mut parts = Vec::new();
        for stage in Stage::ALL {
            let of: Vec<_> = set.iter().filter(|c| c.stage == stage).collect();
            if !of.is_empty() {
                let ok = of.iter().filter(|c| c.passed).count();
                parts.push(format!("{} {ok}/{}", stage.names().tally, of.len()));
            }
        }
        log_line(
            out,
            file!(),
            line!(),
            false,
            &format!("{label} cases passed: {}", parts.join(", ")),
            color,
        );
    }
    if let Some(s) = &opts.scaling {
        // A warning that counts for nothing: the verdict stays the cases'.
        log_line(out, file!(), line!(), s.quadratic, &s.message(), color);
    }
    let failed: Vec<&CaseReport> = cases
        .iter()
        .filter(|c| !c.passed && counts(c, opts.bonus))
        .collect();
    // Cases that failed with the same first warning share one line.
    let groups = alike(failed.iter().map(|c| {
        let text = first_warning(c).unwrap_or_else(|| "failed".to_string());
        (text, c.name.as_str())
    }));
    for (text, names) in groups.iter().take(SUMMARY_FAILURES) {
        log_line(
            out,
            file!(),
            line!(),
            true,
            &format!("{}: {text}", who(names)),
            color,
        );
    }
    if groups.len() > SUMMARY_FAILURES {
        let rest: usize = groups[SUMMARY_FAILURES..]
            .iter()
            .map(|(_, n)| n.len())
            .sum();
        log_line(
            out,
            file!(),
            line!(),
            true,
            &format!("... and {rest} more failing cases"),
            color,
        );
    }
    // Each hint once, under the failures, in its own words: where students
    // read, not only above under its case.
    let hints = alike(
        failed
            .iter()
            .filter_map(|c| Some((c.hint.clone()?, c.name.as_str()))),
    );
    for (hint, names) in hints.iter().take(SUMMARY_FAILURES) {
        log_line(
            out,
            file!(),
            line!(),
            false,
            &format!("hint for {}: {hint}", who(names)),
            color,
        );
    }
    if let Some(index) = &opts.report {
        log_line(
            out,
            file!(),
            line!(),
            false,
            &format!("pictures of every case: open {index} in a browser"),
            color,
        );
    }
    if let Some(first) = failed.first() {
        let function = first.stage.function();
        let next = match (&opts.focus, &opts.report) {
            // Already that case alone with pictures: what to look at, then
            // what to run once it is fixed.
            (Some(case), Some(index)) if *case == first.name => format!(
                "next: fix {function}, looking at the messages above and the pictures in {index}; \
                 then run this command again, and `cargo run -p grader` for the whole lab"
            ),
            (Some(case), None) if *case == first.name => format!(
                "next: fix {function}; to see the case, with pictures: cargo run -p grader -- --case {case} --report"
            ),
            _ => format!(
                "next: fix {function} first; see that case alone, with pictures: cargo run -p grader -- --case {} --report",
                first.name
            ),
        };
        log_line(out, file!(), line!(), false, &next, color);
        log_line(out, file!(), line!(), true, "test failed", color);
    } else if let Some(part) = &opts.partial {
        let n = cases.iter().filter(|c| counts(c, opts.bonus)).count();
        log_line(
            out,
            file!(),
            line!(),
            false,
            &format!(
                "{part}: all {n} counted cases passed; run `cargo run -p grader` without it for the whole lab"
            ),
            color,
        );
    } else {
        log_line(
            out,
            file!(),
            line!(),
            false,
            "all tests passed, congratulations!",
            color,
        );
    }
}

#[derive(Serialize)]
struct JsonReport<'a, P: Serialize> {
    passed: bool,
    bonus_counted: bool,
    protections: &'a str,
    /// Every stage of the lab with its names, in grading order: how
    /// scripts (the grading workflow's summary) name them.
    stages: &'static [crate::judge::fixture::StageNames],
    /// The runs and the per-call limit they were given (the run's plan,
    /// as the run serialises it).
    plan: &'a P,
    /// `loop_subdivide` timed on two sizes, when it was.
    #[serde(skip_serializing_if = "Option::is_none")]
    scaling: Option<&'a crate::judge::scaling::Scaling>,
    cases: Vec<JsonCase<'a>>,
}

/// A case in JSON: its report, and its first warning on one line, ready
/// to show (student text in it escaped).
#[derive(Serialize)]
struct JsonCase<'a> {
    #[serde(flatten)]
    case: &'a CaseReport,
    #[serde(skip_serializing_if = "Option::is_none")]
    first_warning: Option<String>,
}

/// The report as JSON, for scripts. Student text (`output`, an entry's
/// `quote`) is a list of escaped lines; `text` is the grader's words only.
pub fn json(
    cases: &[CaseReport],
    bonus: bool,
    protections: &str,
    plan: &impl Serialize,
    scaling: Option<&crate::judge::scaling::Scaling>,
) -> String {
    serde_json::to_string_pretty(&JsonReport {
        passed: all_passed(cases, bonus),
        bonus_counted: bonus,
        protections,
        stages: &crate::judge::fixture::STAGE_NAMES,
        plan,
        scaling,
        cases: cases
            .iter()
            .map(|case| JsonCase {
                case,
                first_warning: first_warning(case),
            })
            .collect(),
    })
    .expect("reports serialize")
}

/// Most lines of a case's report a Gradescope test shows, and most lines of
/// the student's own output under it: enough to act on, short enough to read.
const GRADESCOPE_REPORT_LINES: usize = 40;
const GRADESCOPE_OUTPUT_LINES: usize = 20;

/// Gradescope's `results.json`: one test per counted case, one point each.
/// Hidden cases are `after_published` (their names and expected values stay
/// out of sight until the TA publishes grades). Bonus cases are tests tagged
/// `bonus` with their own point each when `bonus` is set (the TA sets the
/// assignment's total to the other tests' sum, so they count as extra
/// credit), else left out and named in the top-level output. A test's output
/// is the case's warnings and details (not its progress lines) and the start
/// of what the student's code printed.
pub fn gradescope(cases: &[CaseReport], bonus: bool) -> String {
    let mut tests = Vec::new();
    let mut left_out = 0;
    for c in cases {
        if !counts(c, bonus) {
            left_out += 1;
            continue;
        }
        let mut lines: Vec<String> = Vec::new();
        for e in &c.entries {
            match e.level {
                Level::Info => continue,
                Level::Warn => lines.push(format!("[warn] {}", e.one_line())),
                Level::Detail => lines.push(format!("    {}", e.one_line())),
            }
            lines.extend(e.quote_below("    ").lines().map(str::to_string));
        }
        if lines.len() > GRADESCOPE_REPORT_LINES {
            let more = lines.len() - GRADESCOPE_REPORT_LINES;
            lines.truncate(GRADESCOPE_REPORT_LINES);
            lines.push(format!(
                "... ({more} more lines: run the grader with --case {})",
                c.name
            ));
        }
        let mut output = if c.passed {
            "passed\n".to_string()
        } else {
            lines.join("\n") + "\n"
        };
        if !c.output.is_blank() {
            output.push_str("your code printed:\n");
            output.push_str(&c.output.block_limited("", GRADESCOPE_OUTPUT_LINES));
        }
        // A sequence is its own stage: its title names no single function.
        let function = c.stage.names().title;
        let (name, visibility, tags) = match c.group {
            Group::Lab => (
                format!("{} ({function})", c.name),
                "visible",
                vec![function],
            ),
            Group::Hidden => (
                format!("{} ({function}, hidden)", c.name),
                "after_published",
                vec![function, "hidden"],
            ),
            Group::Bonus => (
                format!("{} ({function}, bonus)", c.name),
                "visible",
                vec![function, "bonus"],
            ),
        };
        tests.push(json!({
            "name": name,
            "score": if c.passed { 1.0 } else { 0.0 },
            "max_score": 1.0,
            "status": if c.passed { "passed" } else { "failed" },
            "output": output,
            "output_format": "text",
            "tags": tags,
            "visibility": visibility,
        }));
    }
    let score: f64 = tests.iter().filter_map(|t| t["score"].as_f64()).sum();
    let mut output = if all_passed(cases, bonus) {
        "all tests passed, congratulations!".to_string()
    } else {
        "test failed".to_string()
    };
    let bonus_cases = cases.iter().filter(|c| c.group == Group::Bonus).count();
    if left_out > 0 {
        let _ = write!(
            output,
            "\n{left_out} bonus cases (meshes with boundary) are not graded here; \
             run `cargo run -p grader -- --bonus` to try them"
        );
    } else if bonus_cases > 0 {
        let _ = write!(output, "\n{bonus_cases} bonus cases count as extra credit");
    }
    if cases.iter().any(|c| c.group == Group::Hidden) {
        let _ = write!(output, "\nhidden cases are shown once grades are published");
    }
    serde_json::to_string_pretty(&json!({
        "score": score,
        "output": output,
        "output_format": "text",
        "stdout_visibility": "hidden",
        "tests": tests,
    }))
    .expect("results serialize")
}
