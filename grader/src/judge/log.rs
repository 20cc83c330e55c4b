//! The judge's notebook: the lines of a case said so far (with where in
//! the grader each was said), the verdict they add up to, and the facts
//! noted beside them, with the `say!`, `quote!` and `hint!` macros that
//! write to it.

use halfedge::Element;

use crate::isolate::end::Problem;
use crate::judge::fixture::Fixture;
use crate::judge::verdict::{
    pointer_of, CaseReport, Comparison, Entry, Hint, InvalidFact, Level, Named, Pointer,
};
use crate::quoted::Quoted;
use crate::text::words;

/// A case's lines so far and the facts beside them.
pub(crate) struct Log {
    pub(crate) entries: Vec<Entry>,
    pub(crate) passed: bool,
    pub(crate) hint: Option<String>,
    pub(crate) hint_id: Option<Hint>,
    pub(crate) comparison: Option<Comparison>,
    pub(crate) invalid: Option<InvalidFact>,
    pub(crate) pointer: Option<Pointer>,
}

impl Log {
    pub(crate) fn new() -> Log {
        Log {
            entries: Vec::new(),
            passed: true,
            hint: None,
            hint_id: None,
            comparison: None,
            invalid: None,
            pointer: None,
        }
    }

    /// The log that adds lines to `report`, above its "end testing" line
    /// (put back by [`Log::finish`]).
    pub(crate) fn resume(report: &mut CaseReport) -> (Log, Option<Entry>) {
        let end = report.entries.pop();
        let log = Log {
            entries: std::mem::take(&mut report.entries),
            passed: report.passed,
            hint: report.hint.take(),
            hint_id: report.hint_id.take(),
            comparison: None,
            invalid: None,
            pointer: None,
        };
        (log, end)
    }

    pub(crate) fn finish(self, report: &mut CaseReport, end: Option<Entry>) {
        report.entries = self.entries;
        report.entries.extend(end);
        report.passed = self.passed;
        report.hint = self.hint;
        report.hint_id = self.hint_id;
    }

    /// Names the elements the last line is about.
    pub(crate) fn about(&mut self, elements: impl IntoIterator<Item = Element>) {
        if let Some(e) = self.entries.last_mut() {
            e.elements.extend(elements.into_iter().map(Named::seen));
        }
    }

    /// Records the broken link as data on the line just said (the first
    /// warning's, as the case stops there).
    pub(crate) fn invalid_found(&mut self, problem: &Problem) {
        self.about(problem.element());
        self.first_about(problem.check().and_then(pointer_of));
        self.invalid = Some(InvalidFact {
            check: problem.check(),
            element: problem.element().map(Named::seen),
        });
    }

    /// Says the first failure is about `pointer`, if it is the first.
    pub(crate) fn first_about(&mut self, pointer: Option<Pointer>) {
        let warns = self
            .entries
            .iter()
            .filter(|e| e.level == Level::Warn)
            .count();
        if warns == 1 && self.pointer.is_none() {
            self.pointer = pointer;
        }
    }

    /// A detail line `hint: ...` for `hint`, and the case's hint if it had
    /// none yet.
    pub(crate) fn hint(&mut self, f: &Fixture, hint: Hint, file: &'static str, line: u32) {
        let text = hint.text(f);
        self.push(Level::Detail, format!("hint: {text}"), None, file, line);
        if let Some(e) = self.entries.last_mut() {
            e.hint = Some(hint.clone());
        }
        if self.hint.is_none() {
            self.hint = Some(text);
            self.hint_id = Some(hint);
        }
    }
}

/// A detail line `hint: ...`, and the case's hint if it had none yet.
macro_rules! hint {
    ($log:expr, $f:expr, $hint:expr) => {
        $log.hint($f, $hint, file!(), line!())
    };
}
pub(crate) use hint;

/// A line of the grader's words at `level` (`Info`, `Warn`, `Detail`).
macro_rules! say {
    ($log:expr, $level:ident, $($arg:tt)*) => {
        $log.push($crate::judge::verdict::Level::$level, format!($($arg)*), None, file!(), line!())
    };
}
pub(crate) use say;

/// A line of the grader's words followed by student text (`quote`, a
/// [`Quoted`]), which is shown as data.
macro_rules! quote {
    ($log:expr, $level:ident, $quote:expr, $($arg:tt)*) => {
        $log.push(
            $crate::judge::verdict::Level::$level,
            format!($($arg)*),
            Some($crate::quoted::Quoted::new($quote)),
            file!(),
            line!(),
        )
    };
}
pub(crate) use quote;

impl Log {
    pub(crate) fn push(
        &mut self,
        level: Level,
        text: String,
        quote: Option<Quoted>,
        file: &'static str,
        line: u32,
    ) {
        if level == Level::Warn {
            self.passed = false;
        }
        self.entries.push(Entry {
            level,
            text: words(text),
            quote,
            elements: Vec::new(),
            hint: None,
            file,
            line,
        });
    }
}

pub(crate) fn fmt_p(p: [f64; 3]) -> String {
    format!("({:.6}, {:.6}, {:.6})", p[0], p[1], p[2])
}
