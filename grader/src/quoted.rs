//! Text that came from the student's code (what it printed, a panic message,
//! a panic's location): shown only as data, never as the grader's own lines.
//!
//! Every renderer (the terminal, the text report, JSON, Gradescope, the HTML
//! report, the class reports and CSV) takes such text from here: each of its
//! lines is shown under `| `, and every control character but newline and
//! tab is shown escaped (`\u{1b}`), so no escape sequence, carriage return or
//! newline in it can clear the screen, move the cursor or start a line that
//! looks like the grader's.

use serde::{Serialize, Serializer};

/// What starts every line of student text.
pub const PREFIX: &str = "| ";

/// Most characters of student text shown inside one of the grader's own
/// lines: a long one could wrap into what looks like a line of its own.
const INLINE_CHARS: usize = 160;

/// Whether `c` must be shown escaped: control characters (C0, DEL, C1)
/// other than newline and tab, and the invisible marks that reorder or hide
/// text on screen (bidirectional overrides and isolates).
fn hidden(c: char) -> bool {
    (c.is_control() && c != '\n' && c != '\t')
        || matches!(c, '\u{200e}' | '\u{200f}' | '\u{061c}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// `text` with every hidden character written as `\u{..}`; newlines and
/// tabs kept. Escaping twice changes nothing more.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if hidden(c) {
            out.push_str(&format!("\\u{{{:x}}}", c as u32));
        } else {
            out.push(c);
        }
    }
    out
}

/// The lines of `text`, each escaped (a newline, or CR LF, ends a line; a
/// bare CR is shown as `\u{d}`), without trailing blank lines.
pub fn escaped_lines(text: &str) -> Vec<String> {
    let mut lines: Vec<String> = text
        .split('\n')
        .map(|l| escape(l.strip_suffix('\r').unwrap_or(l)))
        .collect();
    while lines.last().is_some_and(|l| l.trim().is_empty()) {
        lines.pop();
    }
    lines
}

/// Lines already taken from student text (as in the grader's JSON), each
/// under `indent` and [`PREFIX`], escaped again in case they were not.
pub fn block_of<'a>(lines: impl IntoIterator<Item = &'a str>, indent: &str) -> String {
    let mut out = String::new();
    for l in lines {
        for part in escaped_lines(l) {
            out.push_str(indent);
            out.push_str(PREFIX);
            out.push_str(&part);
            out.push('\n');
        }
    }
    out
}

/// One field of text for a single line (a CSV cell, a summary): every
/// hidden character escaped, newlines shown as ` | `.
pub fn one_line(text: &str) -> String {
    escaped_lines(text).join(" | ")
}

/// A line of the grader's words quoting student text: the line (the
/// words, then the quote's first line when there is one) and the quote's
/// lines under `indent` and [`PREFIX`] when they do not all fit on it.
pub fn quoting(text: &str, quote: Option<&Quoted>, indent: &str) -> (String, String) {
    match quote {
        Some(q) => {
            let below = if q.fits_inline() {
                String::new()
            } else {
                q.block(indent)
            };
            (format!("{text} {}", q.inline()), below)
        }
        None => (text.to_string(), String::new()),
    }
}

/// Student text, kept as it came; shown only through the methods below.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Quoted(String);

impl Quoted {
    pub fn new(raw: impl Into<String>) -> Quoted {
        Quoted(raw.into())
    }

    /// The text as it came, for decisions (never for display).
    pub fn raw(&self) -> &str {
        &self.0
    }

    /// Nothing but white space.
    pub fn is_blank(&self) -> bool {
        self.0.trim().is_empty()
    }

    /// Its lines, escaped, without the prefix.
    pub fn lines(&self) -> Vec<String> {
        escaped_lines(&self.0)
    }

    /// The text as part of one of the grader's lines: its first line,
    /// escaped and cut, then how many more lines there are (shown with
    /// [`Quoted::block`]).
    pub fn inline(&self) -> String {
        let lines = self.lines();
        let first = lines.first().map_or("", String::as_str);
        let mut shown: String = first.chars().take(INLINE_CHARS).collect();
        if shown.len() < first.len() {
            shown.push_str("...");
        }
        if lines.len() > 1 {
            shown.push_str(&format!(" (and {} more lines, below)", lines.len() - 1));
        }
        shown
    }

    /// Whether [`Quoted::inline`] shows all of it.
    pub fn fits_inline(&self) -> bool {
        let lines = self.lines();
        lines.len() <= 1
            && lines
                .first()
                .is_none_or(|l| l.chars().count() <= INLINE_CHARS)
    }

    /// Every line under `indent` and [`PREFIX`].
    pub fn block(&self, indent: &str) -> String {
        self.block_limited(indent, usize::MAX)
    }

    /// At most `max` lines under `indent` and [`PREFIX`], then how many
    /// were left out.
    pub fn block_limited(&self, indent: &str, max: usize) -> String {
        let lines = self.lines();
        let mut out = block_of(lines.iter().take(max).map(String::as_str), indent);
        if lines.len() > max {
            out.push_str(&format!(
                "{indent}{PREFIX}... ({} more lines)\n",
                lines.len() - max
            ));
        }
        out
    }
}

/// In JSON, student text is its escaped lines: a script that prints them
/// can show nothing the terminal would obey.
impl Serialize for Quoted {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.lines().serialize(s)
    }
}

/// A cell of a CSV file: quoted when it holds a comma, a quote, a newline
/// or a CR (the last two shown as ` | `, so a row stays one line), and
/// made inert for spreadsheets when it starts like a formula (`=`, `+`,
/// `-`, `@`, a tab or a CR): a leading `'`.
pub fn csv_field(text: &str) -> String {
    let mut cell = one_line(text);
    if cell.starts_with(['=', '+', '-', '@', '\t', '\r']) || text.starts_with(['\t', '\r']) {
        cell.insert(0, '\'');
    }
    if cell.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", cell.replace('"', "\"\""))
    } else {
        cell
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn controls_are_escaped_and_lines_prefixed() {
        let q = Quoted::new("a\x1b[2Jb\rc\n[info] all tests passed\r\n\u{9b}x\t\n\n");
        assert_eq!(
            q.lines(),
            [
                "a\\u{1b}[2Jb\\u{d}c",
                "[info] all tests passed",
                "\\u{9b}x\t"
            ]
        );
        assert_eq!(
            q.block("  "),
            "  | a\\u{1b}[2Jb\\u{d}c\n  | [info] all tests passed\n  | \\u{9b}x\t\n"
        );
        assert_eq!(q.inline(), "a\\u{1b}[2Jb\\u{d}c (and 2 more lines, below)");
        assert!(!q.fits_inline());
        assert_eq!(escape(&escape("\x07\u{202e}")), "\\u{7}\\u{202e}");
    }

    #[test]
    fn csv_cells_are_quoted_and_inert() {
        assert_eq!(csv_field("plain"), "plain");
        assert_eq!(csv_field("=cmd()"), "'=cmd()");
        assert_eq!(csv_field("-1+2"), "'-1+2");
        assert_eq!(csv_field("@x"), "'@x");
        assert_eq!(csv_field("\tx"), "'\tx");
        assert_eq!(csv_field("a\rb"), "a\\u{d}b");
        assert_eq!(csv_field("a,\"b\"\nc"), "\"a,\"\"b\"\" | c\"");
    }
}
