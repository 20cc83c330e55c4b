//! The documents tell the truth about the grader: every warning it can
//! print, read from its source, has a row in `docs/grader-messages.md` and
//! in both handouts' section 9 table.

mod common;
use common::lab_root;

/// The text of a Rust string literal starting at `s[i]` (a `"`), escapes
/// and line continuations resolved, and the index past it.
fn literal_at(s: &[char], i: usize) -> (String, usize) {
    let (mut out, mut j) = (String::new(), i + 1);
    while j < s.len() {
        match s[j] {
            '\\' if s.get(j + 1) == Some(&'\n') => {
                j += 2;
                while j < s.len() && s[j].is_whitespace() {
                    j += 1;
                }
            }
            '\\' => {
                out.push(match s.get(j + 1) {
                    Some('n') => '\n',
                    Some('t') => '\t',
                    Some(&c) => c,
                    None => '\\',
                });
                j += 2;
            }
            '"' => return (out, j + 1),
            c => {
                out.push(c);
                j += 1;
            }
        }
    }
    (out, j)
}

/// An argument of a call as written: its string literals (text), or its
/// code with every literal replaced by `""`.
#[derive(Debug)]
struct Arg {
    code: String,
    literals: Vec<String>,
}

/// The top-level arguments of the call whose `(` is at `s[open]`.
fn args_at(s: &[char], open: usize) -> Vec<Arg> {
    let (mut depth, mut j) = (0usize, open);
    let mut args = Vec::new();
    let mut cur = Arg {
        code: String::new(),
        literals: Vec::new(),
    };
    while j < s.len() {
        let c = s[j];
        match c {
            '"' => {
                let (text, end) = literal_at(s, j);
                cur.literals.push(text);
                cur.code.push_str("\"\"");
                j = end;
                continue;
            }
            // A char literal ('(' or '"'), not a lifetime.
            '\'' if s.get(j + 2) == Some(&'\'') => {
                j += 3;
                continue;
            }
            '(' | '[' | '{' => depth += 1,
            ')' | ']' | '}' => {
                depth -= 1;
                if depth == 0 {
                    args.push(cur);
                    return args;
                }
            }
            ',' if depth == 1 => {
                args.push(std::mem::replace(
                    &mut cur,
                    Arg {
                        code: String::new(),
                        literals: Vec::new(),
                    },
                ));
                j += 1;
                continue;
            }
            _ => {}
        }
        if j != open {
            cur.code.push(c);
        }
        j += 1;
    }
    args
}

/// Every call `name!(` or `name(` in `text`, as its arguments.
fn calls(text: &str, name: &str) -> Vec<Vec<Arg>> {
    let s: Vec<char> = text.chars().collect();
    let pattern: Vec<char> = name.chars().collect();
    let mut out = Vec::new();
    for i in 0..s.len().saturating_sub(pattern.len()) {
        let before = i.checked_sub(1).map(|k| s[k]);
        if s[i..].starts_with(&pattern)
            && s[i + pattern.len()] == '('
            && !before.is_some_and(|b| b.is_alphanumeric() || b == '_')
        {
            out.push(args_at(&s, i + pattern.len()));
        }
    }
    out
}

fn read(path: &str) -> String {
    let p = lab_root().join(path);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn rust_files(dir: &str) -> Vec<(String, String)> {
    let mut files: Vec<_> = std::fs::read_dir(lab_root().join(dir))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            let name = p.strip_prefix(lab_root()).unwrap().display().to_string();
            (name, std::fs::read_to_string(p).unwrap())
        })
        .collect()
}

/// Every warning the grader can print, from its source, with where it is
/// written: the `[warn]` lines and hints of `say!`, `quote!`, `hint!` (and
/// `try`'s `say!(true, ...)`, the report's `log_line(.., true, ..)`), the
/// scaling check's lines, `validate()`'s messages, and the mesh library's
/// panics a student's code triggers (shown as `... panicked: <message>`).
fn warnings() -> Vec<(String, String)> {
    let mut out = Vec::new();
    let first = |a: &Arg| a.literals.first().cloned();
    for (file, text) in rust_files("grader/src") {
        for a in calls(&text, "say!") {
            match a.as_slice() {
                [_, level, fmt, ..] if level.code.trim() == "Warn" => {
                    out.extend(first(fmt).map(|m| (file.clone(), m)))
                }
                [warn, text, ..] if warn.code.trim() == "true" => {
                    out.extend(first(text).map(|m| (file.clone(), m)))
                }
                _ => {}
            }
        }
        for a in calls(&text, "quote!") {
            if let [_, level, _, fmt, ..] = a.as_slice() {
                if level.code.trim() == "Warn" {
                    out.extend(first(fmt).map(|m| (file.clone(), m)));
                }
            }
        }
        for a in calls(&text, "hint!") {
            if let [_, fmt, ..] = a.as_slice() {
                out.extend(first(fmt).map(|m| (file.clone(), m)));
            }
        }
        for a in calls(&text, "log_line") {
            if let [_, _, _, warn, text, ..] = a.as_slice() {
                if warn.code.trim() == "true" {
                    out.extend(first(text).map(|m| (file.clone(), m)));
                }
            }
        }
    }
    let scaling = read("grader/src/scaling.rs");
    for a in calls(&scaling, "format!") {
        if let Some(m) = a.first().and_then(first) {
            if m.starts_with("loop_subdivide") {
                out.push(("grader/src/scaling.rs".into(), m));
            }
        }
    }
    let validate = read("crates/halfedge/src/validate.rs");
    for a in calls(&validate, "fail") {
        if let Some(m) = a.get(1).and_then(first) {
            out.push(("crates/halfedge/src/validate.rs".into(), m));
        }
    }
    for file in [
        "crates/halfedge/src/mesh.rs",
        "crates/halfedge/src/traverse.rs",
    ] {
        for a in calls(&read(file), "panic!") {
            if let Some(m) = a.first().and_then(first) {
                out.push((file.into(), m));
            }
        }
    }
    out
}

/// What identifies a message in a row: its longest fixed part (the text
/// between `{...}` placeholders) up to the first colon, at most 60
/// characters, without the punctuation at its ends; `None` for a message
/// that is all placeholder (a hint read from the fixtures).
fn key(message: &str) -> Option<String> {
    let mut parts = Vec::new();
    let mut cur = String::new();
    let mut depth = 0;
    for c in message.chars() {
        match c {
            '{' => {
                depth += 1;
                parts.push(std::mem::take(&mut cur));
            }
            '}' if depth > 0 => depth -= 1,
            c if depth == 0 => cur.push(c),
            _ => {}
        }
    }
    parts.push(cur);
    let longest = parts.into_iter().max_by_key(|p| p.chars().count())?;
    let head = longest
        .split(": ")
        .find(|p| p.chars().any(char::is_alphanumeric))?;
    let head: String = head.chars().take(60).collect();
    let head = head.trim_matches(|c: char| !c.is_alphanumeric());
    (head.chars().count() >= 4).then(|| normal(head))
}

/// Lower case, backticks gone, white space collapsed.
fn normal(text: &str) -> String {
    text.replace('`', "")
        .replace("\\|", "|")
        .to_lowercase()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// The table rows (`| ... |` lines) of `text`, normalised.
fn rows(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.trim_start().starts_with('|'))
        .map(normal)
        .collect()
}

/// The section of a handout that starts with `## 9.`, to the next `## `.
fn section_9(path: &str) -> String {
    let text = read(path);
    let start = text
        .find("\n## 9.")
        .unwrap_or_else(|| panic!("{path} has no section 9"));
    let rest = &text[start + 1..];
    let end = rest[3..].find("\n## ").map_or(rest.len(), |e| e + 3);
    rest[..end].to_string()
}

#[test]
fn the_extraction_finds_the_messages_it_must() {
    let all = warnings();
    let has = |m: &str| all.iter().any(|(_, w)| w == m);
    // One of each source, as written there.
    for m in [
        "flip_edge added or removed elements: a flip only relinks",
        "{function} overflowed the stack",
        "fewer vertices than one per old edge: was every old edge split exactly once?",
        "test failed",
        "A halfedge does not point to its vertex!",
        "A vertex's halfedge does not point to that vertex!",
    ] {
        assert!(has(m), "{m:?} not extracted from {all:#?}");
    }
    assert!(all.len() > 80, "{}", all.len());
    assert!(all
        .iter()
        .any(|(f, m)| f.ends_with("scaling.rs") && m.contains("inside a loop")));
    assert!(all
        .iter()
        .any(|(f, m)| f.ends_with("mesh.rs") && m.starts_with("there is no {kind}")));
    assert_eq!(
        key("{at} left an invalid mesh: {}").as_deref(),
        Some("left an invalid mesh")
    );
    assert_eq!(
        key("flip_edge returned Some(e{got}), but it must return the edge it was given (e{given})")
            .as_deref(),
        Some("but it must return the edge it was given (e")
    );
    assert_eq!(key("{advice}"), None);
}

/// Every warning has a row in each document that lists them.
#[test]
fn every_warning_has_a_row_in_the_messages_and_both_handouts() {
    let documents = [
        (
            "docs/grader-messages.md",
            rows(&read("docs/grader-messages.md")),
        ),
        (
            "docs/handout.en.md section 9",
            rows(&section_9("docs/handout.en.md")),
        ),
        (
            "docs/handout.zh.md section 9",
            rows(&section_9("docs/handout.zh.md")),
        ),
    ];
    let mut missing = Vec::new();
    for (file, message) in warnings() {
        let Some(key) = key(&message) else {
            continue;
        };
        for (doc, rows) in &documents {
            if !rows.iter().any(|r| r.contains(&key)) {
                missing.push(format!("{doc}: {key:?} (from {file}: {message:?})"));
            }
        }
    }
    missing.sort();
    missing.dedup();
    assert!(
        missing.is_empty(),
        "{} messages without a row:\n{}",
        missing.len(),
        missing.join("\n")
    );
}

/// Rows of the Chinese handout explain in Chinese.
#[test]
fn the_chinese_table_explains_in_chinese() {
    let section = section_9("docs/handout.zh.md");
    for row in section.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = row.split(" | ").collect();
        let last = cells.last().unwrap();
        assert!(
            last.chars().any(|c| ('\u{4e00}'..='\u{9fff}').contains(&c)),
            "a row explained without Chinese: {row}"
        );
    }
}
