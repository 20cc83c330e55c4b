//! The class list a TA grades against (`class --roster FILE.csv`) and the
//! gradebook file made from it (`canvas.csv`).
//!
//! A roster is a CSV file with a header row. The columns it recognises
//! (case and spaces around them ignored) are in [`ID_COLUMNS`],
//! [`EMAIL_COLUMNS`], [`NAME_COLUMNS`] and [`SECTION_COLUMNS`]; any other
//! column is left alone, so Canvas's own gradebook export (Student, ID, SIS
//! User ID, SIS Login ID, Section, then one column per assignment) is a
//! roster as it is. A submission belongs to the roster student one of
//! whose ids or whose e-mail address is its row name (the e-mail without
//! regard to case).

use std::fmt::Write as _;
use std::path::Path;

use grader::report::quoted;

/// Columns holding an id a submission may be named by, in the order
/// [`Student::key`] prefers them.
pub const ID_COLUMNS: [&str; 8] = [
    "sis login id",
    "login",
    "username",
    "github",
    "sis user id",
    "student id",
    "student_id",
    "id",
];
/// Columns holding the student's e-mail address.
pub const EMAIL_COLUMNS: [&str; 4] = ["email", "e-mail", "email address", "mail"];
/// Columns holding the student's name as the gradebook shows it.
pub const NAME_COLUMNS: [&str; 3] = ["student", "name", "student name"];
/// The column holding the section.
pub const SECTION_COLUMNS: [&str; 1] = ["section"];

/// One student of the roster.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Student {
    pub name: String,
    /// Canvas's columns, when the roster has them (a Canvas export).
    pub canvas_id: String,
    pub sis_user_id: String,
    pub sis_login_id: String,
    pub section: String,
    /// Every id and e-mail address the student may be found by.
    pub ids: Vec<String>,
}

impl Student {
    /// The name of the row of a student without a submission: their first
    /// id (or e-mail), as their submission would have been named.
    pub fn key(&self) -> &str {
        self.ids.first().map_or(self.name.as_str(), String::as_str)
    }

    /// Whether the submission named `name` is this student's.
    pub fn owns(&self, name: &str) -> bool {
        let name = name.trim();
        self.ids.iter().any(|id| id.eq_ignore_ascii_case(name))
    }
}

/// The rows of a CSV text (RFC 4180: quoted fields, doubled quotes,
/// newlines inside quotes, CRLF; a byte-order mark is skipped).
pub fn parse_csv(text: &str) -> Result<Vec<Vec<String>>, String> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut rows = Vec::new();
    let mut row = Vec::new();
    let mut field = String::new();
    let mut chars = text.chars().peekable();
    let mut line = 1;
    let mut quoted = false;
    while let Some(c) = chars.next() {
        if quoted {
            match c {
                '"' if chars.peek() == Some(&'"') => {
                    chars.next();
                    field.push('"');
                }
                '"' => quoted = false,
                _ => {
                    if c == '\n' {
                        line += 1;
                    }
                    field.push(c);
                }
            }
            continue;
        }
        match c {
            '"' if field.is_empty() => quoted = true,
            ',' => row.push(std::mem::take(&mut field)),
            '\r' if chars.peek() == Some(&'\n') => {}
            '\n' => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
                line += 1;
            }
            _ => field.push(c),
        }
    }
    if quoted {
        return Err(format!("a quoted field opened by line {line} never ends"));
    }
    if !field.is_empty() || !row.is_empty() {
        row.push(field);
        rows.push(row);
    }
    Ok(rows)
}

/// Reads the roster at `path`: an error names the file and what is wrong
/// (no header, no column to join by, a student without an id).
pub fn read(path: &Path) -> Result<Vec<Student>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse(&text).map_err(|e| format!("--roster {}: {e}", path.display()))
}

/// The roster in `text` (see [`read`]).
pub fn parse(text: &str) -> Result<Vec<Student>, String> {
    let rows = parse_csv(text)?;
    let Some((header, rows)) = rows.split_first() else {
        return Err("empty: a roster needs a header row, then one row per student".into());
    };
    let header: Vec<String> = header.iter().map(|h| h.trim().to_lowercase()).collect();
    let column = |names: &[&str]| -> Vec<usize> {
        names
            .iter()
            .filter_map(|n| header.iter().position(|h| h == n))
            .collect()
    };
    let (ids, emails) = (column(&ID_COLUMNS), column(&EMAIL_COLUMNS));
    if ids.is_empty() && emails.is_empty() {
        return Err(format!(
            "no column to join submissions by: the header has {}; name one of {} (an id) or {} \
             (an e-mail address)",
            header.join(", "),
            ID_COLUMNS.join(", "),
            EMAIL_COLUMNS.join(", ")
        ));
    }
    let first = |row: &[String], names: &[&str]| -> String {
        column(names)
            .into_iter()
            .filter_map(|k| row.get(k))
            .map(|v| v.trim().to_string())
            .find(|v| !v.is_empty())
            .unwrap_or_default()
    };
    let exact = |row: &[String], name: &str| -> String {
        header
            .iter()
            .position(|h| h == name)
            .and_then(|k| row.get(k))
            .map(|v| v.trim().to_string())
            .unwrap_or_default()
    };
    let mut out = Vec::new();
    for (n, row) in rows.iter().enumerate() {
        if row.iter().all(|f| f.trim().is_empty()) {
            continue;
        }
        let name = first(row, &NAME_COLUMNS);
        // Canvas's export has a second row of maximum points, no student.
        if name == "Points Possible" {
            continue;
        }
        let found: Vec<String> = ids
            .iter()
            .chain(&emails)
            .filter_map(|&k| row.get(k))
            .map(|v| v.trim().to_string())
            .filter(|v| !v.is_empty())
            .collect();
        if found.is_empty() {
            return Err(format!(
                "row {} ({}) has no id and no e-mail address to find a submission by",
                n + 2,
                if name.is_empty() { "no name" } else { &name }
            ));
        }
        out.push(Student {
            name,
            canvas_id: exact(row, "id"),
            sis_user_id: exact(row, "sis user id"),
            sis_login_id: exact(row, "sis login id"),
            section: first(row, &SECTION_COLUMNS),
            ids: found,
        });
    }
    Ok(out)
}

/// One row of the gradebook: who, and their points.
pub struct Grade<'a> {
    pub student: &'a Student,
    pub score: f64,
}

/// Canvas's gradebook import file: `Student, ID, SIS User ID, SIS Login
/// ID, Section`, then the assignment's column (its name as the TA gave
/// it), a `Points Possible` row with `max` first, then a row per student;
/// every text cell made inert for spreadsheets.
pub fn canvas_csv(assignment: &str, max: f64, grades: &[Grade]) -> String {
    let mut csv = format!(
        "Student,ID,SIS User ID,SIS Login ID,Section,{}\n",
        quoted::csv_field(assignment)
    );
    let _ = writeln!(csv, "    Points Possible,,,,,{max}");
    for g in grades {
        let s = g.student;
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{}",
            quoted::csv_field(&s.name),
            quoted::csv_field(&s.canvas_id),
            quoted::csv_field(&s.sis_user_id),
            quoted::csv_field(&s.sis_login_id),
            quoted::csv_field(&s.section),
            g.score
        );
    }
    csv
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_canvas_export_is_a_roster() {
        let text = "\u{feff}Student,ID,SIS User ID,SIS Login ID,Section,Lab 1 (12)\r\n\
                    \"    Points Possible\",,,,,10\r\n\
                    \"Smith, Jane\",101,2001,jsmith,\"CS 1, A\",\r\n\
                    \"Lee \"\"Al\"\"\",102,,alee,CS 1,\r\n";
        let roster = parse(text).unwrap();
        assert_eq!(roster.len(), 2);
        assert_eq!(roster[0].name, "Smith, Jane");
        assert_eq!(roster[0].key(), "jsmith");
        assert_eq!(roster[0].section, "CS 1, A");
        assert!(roster[0].owns("2001") && roster[0].owns("101") && !roster[0].owns("alee"));
        assert_eq!(roster[1].name, "Lee \"Al\"");
        assert_eq!(roster[1].sis_user_id, "");
    }

    #[test]
    fn e_mail_joins_without_regard_to_case_and_a_bad_roster_is_named() {
        let roster = parse("Name,E-mail\nAda,Ada@Uni.EDU\n").unwrap();
        assert!(roster[0].owns("ada@uni.edu"));
        let err = parse("Name,Grade\nAda,3\n").unwrap_err();
        assert!(err.contains("no column to join submissions by"), "{err}");
        let err = parse("Name,Email\nAda,\n").unwrap_err();
        assert!(err.contains("row 2 (Ada) has no id"), "{err}");
        assert!(parse("").unwrap_err().contains("empty"));
        assert!(parse_csv("a,\"b\n").unwrap_err().contains("never ends"));
    }

    #[test]
    fn the_gradebook_file_is_inert_and_numeric() {
        let s = Student {
            name: "=HYPERLINK(\"x\")".into(),
            sis_login_id: "@bob".into(),
            ..Student::default()
        };
        let csv = canvas_csv(
            "Mesh lab",
            40.0,
            &[Grade {
                student: &s,
                score: 12.0,
            }],
        );
        let rows = parse_csv(&csv).unwrap();
        assert_eq!(rows[0][5], "Mesh lab");
        assert_eq!(rows[1][5], "40");
        assert_eq!(rows[2][0], "'=HYPERLINK(\"x\")");
        assert_eq!(rows[2][3], "'@bob");
        assert_eq!(rows[2][5].parse::<f64>().unwrap(), 12.0);
    }
}
