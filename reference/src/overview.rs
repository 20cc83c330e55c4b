//! The class overview page (`overview.html` beside `summary.csv`): what a TA
//! looks at first after grading a class. One offline file (inline CSS and
//! SVG, no script, nothing fetched): the score histogram, how many rows
//! ended how, the pass rate of every case (worst first), the most common
//! first failures with their counts, the similarity hints, and one line per
//! student linking to their report.
//!
//! Every string that came from a submission (names, first failures, which
//! quote the student's panics) is escaped: a student named `<script>` shows
//! as text. Links lead only to the reports this tool wrote, by the file
//! names it chose ([`crate::class::file_stem`]), written as a relative path
//! (`./`, every byte but a few escaped for URLs), so no link has a scheme;
//! and the page's policy (`Content-Security-Policy`) runs no script at all,
//! a `javascript:` URL included.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use crate::similarity::{NotCompared, Pair};

/// One case of one student's grade.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseResult {
    pub name: String,
    /// `flip_edge`, `split_edge`, `in_sequence` or `loop_subdivide`.
    pub function: String,
    pub passed: bool,
}

/// One row of the class, as the overview needs it.
#[derive(Clone, Debug, PartialEq)]
pub struct Student {
    pub name: String,
    pub score: f64,
    pub max: f64,
    /// How grading ended (`passed`, `failed`, `does not compile`, ...).
    pub status: String,
    /// The first failed case and its first warning, or why it was not graded.
    pub first_failure: String,
    /// Every counted case the grader ran (none when it did not compile).
    pub cases: Vec<CaseResult>,
    /// The student's report: a file this tool wrote beside the overview
    /// page, by its name there.
    pub report: Option<String>,
}

/// Bars of the histogram: 0-10%, 10-20%, ..., 90-100% (100% in the last).
const BINS: usize = 10;
/// First failures listed, most common first.
const TOP_FAILURES: usize = 15;

fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c if c.is_control() && c != '\n' && c != '\t' => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    out
}

/// `path` (a file name in the page's folder) as a relative URL: `./` and
/// every byte but letters, digits and `-._~` percent-encoded, so that no
/// `:` can make it a scheme and no `/`, `?` or `#` can change its meaning.
fn relative_url(path: &str) -> String {
    let mut out = String::from("./");
    for b in path.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
            out.push(b as char);
        } else {
            let _ = write!(out, "%{b:02X}");
        }
    }
    out
}

/// No script, no fetch, no form; the inline style and nothing else.
const POLICY: &str = "default-src 'none'; style-src 'unsafe-inline'; base-uri 'none'; \
                      form-action 'none'";

/// The student's share of the points, 0 to 1 (0 when nothing counted).
fn fraction(s: &Student) -> f64 {
    if s.max > 0.0 {
        (s.score / s.max).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// How many students fall in each tenth of the points.
pub fn histogram(students: &[Student]) -> [usize; BINS] {
    let mut bins = [0; BINS];
    for s in students {
        let bin = ((fraction(s) * BINS as f64) as usize).min(BINS - 1);
        bins[bin] += 1;
    }
    bins
}

/// Per case (in first-seen order): students who ran it and who passed it.
pub fn pass_rates(students: &[Student]) -> Vec<(String, String, usize, usize)> {
    let mut order: Vec<(String, String)> = Vec::new();
    let mut counts: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    for s in students {
        for c in &s.cases {
            let entry = counts.entry(c.name.clone()).or_insert_with(|| {
                order.push((c.name.clone(), c.function.clone()));
                (0, 0)
            });
            entry.0 += 1;
            entry.1 += usize::from(c.passed);
        }
    }
    let mut rates: Vec<(String, String, usize, usize)> = order
        .into_iter()
        .map(|(name, function)| {
            let (ran, passed) = counts[&name];
            (name, function, ran, passed)
        })
        .collect();
    // Worst first: a case most students fail is the one to look at.
    rates.sort_by(|a, b| {
        let ra = a.3 as f64 / a.2.max(1) as f64;
        let rb = b.3 as f64 / b.2.max(1) as f64;
        ra.total_cmp(&rb).then_with(|| a.0.cmp(&b.0))
    });
    rates
}

/// The first failures students share, most common first (ties by text).
pub fn common_failures(students: &[Student]) -> Vec<(String, usize)> {
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for s in students.iter().filter(|s| !s.first_failure.is_empty()) {
        *counts.entry(s.first_failure.as_str()).or_default() += 1;
    }
    let mut list: Vec<(String, usize)> = counts
        .into_iter()
        .map(|(text, n)| (text.to_string(), n))
        .collect();
    list.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
    list.truncate(TOP_FAILURES);
    list
}

/// The histogram as an inline SVG bar chart with its counts written on it.
fn histogram_svg(bins: &[usize; BINS]) -> String {
    let (w, h, bar) = (420.0, 160.0, 36.0);
    let top = (*bins.iter().max().unwrap_or(&0)).max(1) as f64;
    let mut svg = format!(
        "<svg class=\"histogram\" viewBox=\"0 0 {w} {}\" width=\"{w}\" height=\"{}\" \
         role=\"img\" aria-label=\"score histogram\">",
        h + 34.0,
        h + 34.0
    );
    for (i, &n) in bins.iter().enumerate() {
        let x = 8.0 + i as f64 * (bar + 5.0);
        let height = n as f64 / top * (h - 18.0);
        let y = h - height;
        let _ = write!(
            svg,
            "<rect class=\"bin\" data-bin=\"{i}\" data-count=\"{n}\" x=\"{x}\" y=\"{y:.1}\" \
             width=\"{bar}\" height=\"{height:.1}\"/>\
             <text x=\"{:.1}\" y=\"{:.1}\" class=\"count\">{n}</text>\
             <text x=\"{:.1}\" y=\"{:.1}\" class=\"axis\">{}%</text>",
            x + bar / 2.0,
            y - 4.0,
            x + bar / 2.0,
            h + 14.0,
            i * 100 / BINS
        );
    }
    let _ = write!(
        svg,
        "<text x=\"{:.1}\" y=\"{:.1}\" class=\"axis\">share of the points</text></svg>",
        w / 2.0,
        h + 30.0
    );
    svg
}

const STYLE: &str = "body{font:14px/1.4 system-ui,sans-serif;margin:1.5em;color:#222}\
table{border-collapse:collapse;margin:.5em 0 1.5em}td,th{border:1px solid #ccc;padding:2px 8px;\
text-align:left;vertical-align:top}th{background:#f3f3f3}td.num{text-align:right}\
.bin{fill:#4a7ebb}.count{font-size:11px;text-anchor:middle}.axis{font-size:11px;\
text-anchor:middle;fill:#555}.bad{color:#b00}.text{white-space:pre-wrap;font-family:monospace}";

/// The whole page (`not_compared`: the files too large for the similarity
/// hints).
pub fn page(
    title: &str,
    students: &[Student],
    pairs: &[Pair],
    not_compared: &[NotCompared],
) -> String {
    let mut html = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta http-equiv=\"Content-Security-Policy\" content=\"{POLICY}\">\
         <title>{}</title><style>{STYLE}</style></head><body>\n<h1>{}</h1>\n",
        escape(title),
        escape(title)
    );
    let total = students.len();
    let mean = if total == 0 {
        0.0
    } else {
        students.iter().map(fraction).sum::<f64>() / total as f64 * 100.0
    };
    let full = students.iter().filter(|s| fraction(s) >= 1.0).count();
    let _ = writeln!(
        html,
        "<p id=\"totals\">{total} submissions; mean {mean:.1}% of the points; \
         {full} with full marks.</p>"
    );
    html.push_str("<h2>Scores</h2>\n");
    html.push_str(&histogram_svg(&histogram(students)));
    let mut statuses: BTreeMap<&str, usize> = BTreeMap::new();
    for s in students {
        *statuses.entry(s.status.as_str()).or_default() += 1;
    }
    html.push_str("\n<table id=\"statuses\"><tr><th>how grading ended</th><th>rows</th></tr>");
    for (status, n) in statuses {
        let _ = write!(
            html,
            "<tr><td>{}</td><td class=\"num\">{n}</td></tr>",
            escape(status)
        );
    }
    html.push_str("</table>\n<h2>Most common first failures</h2>\n");
    let failures = common_failures(students);
    if failures.is_empty() {
        html.push_str("<p>No submission failed.</p>\n");
    } else {
        html.push_str("<table id=\"failures\"><tr><th>students</th><th>first failure</th></tr>");
        for (text, n) in failures {
            let _ = write!(
                html,
                "<tr><td class=\"num\">{n}</td><td class=\"text\">{}</td></tr>",
                escape(&text)
            );
        }
        html.push_str("</table>\n");
    }
    html.push_str("<h2>Pass rate per case (worst first)</h2>\n");
    html.push_str(
        "<table id=\"cases\"><tr><th>case</th><th>function</th><th>passed</th>\
         <th>ran</th><th>rate</th></tr>",
    );
    for (name, function, ran, passed) in pass_rates(students) {
        let rate = passed as f64 / ran.max(1) as f64 * 100.0;
        let _ = write!(
            html,
            "<tr><td>{}</td><td>{}</td><td class=\"num\">{passed}</td><td class=\"num\">{ran}</td>\
             <td class=\"num{}\">{rate:.0}%</td></tr>",
            escape(&name),
            escape(&function),
            if rate < 50.0 { " bad" } else { "" }
        );
    }
    html.push_str("</table>\n<h2>Similar submissions (hints, not verdicts)</h2>\n");
    if pairs.is_empty() {
        html.push_str("<p id=\"similar\">No pair shares most of its code.</p>\n");
    } else {
        html.push_str(
            "<table id=\"similar\"><tr><th>first</th><th>second</th><th>shared</th></tr>",
        );
        for p in pairs {
            let shared = if p.identical {
                "identical files".to_string()
            } else {
                format!("{:.0}% of the smaller file's code", p.shared * 100.0)
            };
            let _ = write!(
                html,
                "<tr><td>{}</td><td>{}</td><td>{shared}</td></tr>",
                escape(&p.first),
                escape(&p.second)
            );
        }
        html.push_str("</table>\n");
    }
    if !not_compared.is_empty() {
        html.push_str(&format!(
            "<p id=\"not-compared\">Not compared (larger than {} KiB; only an identical file \
             would be listed):</p>\n<ul>",
            crate::similarity::MAX_BYTES >> 10
        ));
        for f in not_compared {
            let _ = write!(html, "<li>{} ({} bytes)</li>", escape(&f.name), f.bytes);
        }
        html.push_str("</ul>\n");
    }
    html.push_str(
        "<h2>Students</h2>\n<table id=\"students\"><tr><th>student</th><th>score</th>\
         <th>status</th><th>first failure</th></tr>",
    );
    for s in students {
        let name = match &s.report {
            Some(link) => format!(
                "<a href=\"{}\">{}</a>",
                escape(&relative_url(link)),
                escape(&s.name)
            ),
            None => escape(&s.name),
        };
        let _ = write!(
            html,
            "<tr><td>{name}</td><td class=\"num\">{}/{}</td><td>{}</td><td class=\"text\">{}</td></tr>",
            s.score,
            s.max,
            escape(&s.status),
            escape(&s.first_failure)
        );
    }
    html.push_str("</table>\n</body></html>\n");
    html
}

#[cfg(test)]
mod tests {
    use super::*;

    fn student(name: &str, score: f64, failure: &str, cases: &[(&str, bool)]) -> Student {
        Student {
            name: name.to_string(),
            score,
            max: 10.0,
            status: if score >= 10.0 { "passed" } else { "failed" }.to_string(),
            first_failure: failure.to_string(),
            cases: cases
                .iter()
                .map(|(n, p)| CaseResult {
                    name: n.to_string(),
                    function: "flip_edge".to_string(),
                    passed: *p,
                })
                .collect(),
            report: Some(format!("{name}.txt")),
        }
    }

    fn class() -> Vec<Student> {
        vec![
            student("ann", 10.0, "", &[("a", true), ("b", true)]),
            student("ben", 5.0, "b: wrong", &[("a", true), ("b", false)]),
            student("cat", 0.0, "a: panicked", &[("a", false), ("b", false)]),
            student(
                "<script>x</script>",
                5.0,
                "b: wrong",
                &[("a", true), ("b", false)],
            ),
        ]
    }

    #[test]
    fn the_histogram_puts_each_student_in_their_tenth() {
        assert_eq!(histogram(&class()), [1, 0, 0, 0, 0, 2, 0, 0, 0, 1]);
    }

    #[test]
    fn cases_come_worst_first_and_failures_most_common_first() {
        let rates = pass_rates(&class());
        assert_eq!(rates[0].0, "b");
        assert_eq!((rates[0].2, rates[0].3), (4, 1));
        assert_eq!((rates[1].2, rates[1].3), (4, 3));
        let failures = common_failures(&class());
        assert_eq!(failures[0], ("b: wrong".to_string(), 2));
        assert_eq!(failures[1], ("a: panicked".to_string(), 1));
    }

    #[test]
    fn student_text_is_escaped() {
        let html = page("class <1>", &class(), &[], &[]);
        assert!(!html.contains("<script>"), "{html}");
        assert!(html.contains("&lt;script&gt;x&lt;/script&gt;"));
        assert!(html.contains("<title>class &lt;1&gt;</title>"));
        assert!(html.contains("data-bin=\"5\" data-count=\"2\""));
        assert!(html.contains("4 submissions; mean 50.0% of the points; 1 with full marks"));
    }

    #[test]
    fn a_link_is_a_relative_path_whatever_the_name_and_no_script_runs() {
        let name = "javascript:alert(document.title)";
        let mut hostile = student(name, 0.0, "", &[]);
        // As class grading gives it, and as a page given the raw name.
        for report in [
            format!("{}.txt", crate::class::file_stem(name)),
            format!("{name}.txt"),
        ] {
            hostile.report = Some(report);
            let html = page("class", std::slice::from_ref(&hostile), &[], &[]);
            let href = html
                .split("<a href=\"")
                .nth(1)
                .and_then(|l| l.split('"').next())
                .expect("a link");
            assert!(
                href.starts_with("./") && !href[2..].contains(['/', ':']),
                "{href}"
            );
            assert!(
                html.contains(">javascript:alert(document.title)</a>"),
                "{html}"
            );
        }
        assert_eq!(relative_url("a b/c:d#e?.txt"), "./a%20b%2Fc%3Ad%23e%3F.txt");
        assert_eq!(relative_url("张.txt"), "./%E5%BC%A0.txt");
        let html = page("class", &class(), &[], &[]);
        assert!(
            html.contains(
                "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none';"
            ),
            "{html}"
        );
    }
}
