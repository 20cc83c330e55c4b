//! The documents tell the truth about the grader: every warning it can
//! print, read from its source, has a row in `docs/grader-messages.md` and
//! in both handouts' section 9 table.

mod common;
use common::lab_root;
use std::path::{Path, PathBuf};

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
    // Recursive: the grader is laid out in folders by job.
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|x| x == "rs") {
                out.push(path);
            }
        }
    }
    let mut files = Vec::new();
    walk(&lab_root().join(dir), &mut files);
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
/// The first string of each `match` arm starting with `variant` in the
/// function of `file` whose signature starts `signature`: the words of
/// messages kept as ids (one arm per id).
fn arm_strings(file: &str, signature: &str, variant: &str) -> Vec<String> {
    let text = read(file);
    let start = text
        .find(signature)
        .unwrap_or_else(|| panic!("{file}: no `{signature}`"));
    let end = text[start..]
        .find("\n    }\n")
        .map_or(text.len(), |e| start + e);
    text[start..end]
        .split(variant)
        .skip(1)
        .filter_map(|arm| {
            let rest = &arm[arm.find('"')? + 1..];
            Some(rest[..rest.find('"')?].to_string())
        })
        .collect()
}

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
    // The grader's own hints are ids (`GraderHint`) whose words
    // `Hint::text` gives.
    for m in arm_strings(
        "grader/src/judge/verdict.rs",
        "pub fn text(&self, f: &Fixture)",
        "GraderHint::",
    ) {
        out.push(("grader/src/judge/verdict.rs".into(), m));
    }
    let scaling = read("grader/src/judge/scaling.rs");
    for a in calls(&scaling, "format!") {
        if let Some(m) = a.first().and_then(first) {
            if m.starts_with("loop_subdivide") {
                out.push(("grader/src/judge/scaling.rs".into(), m));
            }
        }
    }
    // validate()'s checks are ids (`Check`) whose words `Check::message`
    // gives.
    for m in arm_strings(
        "crates/halfedge/src/validate.rs",
        "pub fn message(self)",
        "Check::",
    ) {
        out.push(("crates/halfedge/src/validate.rs".into(), m));
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

/// Lab cases per stage as the grader counts them in `fixtures/lab`:
/// `(flip, split, sequence, subdivide)`.
fn lab_counts() -> [usize; 4] {
    let mut n = [0; 4];
    for path in common::case_files("lab") {
        let f = common::json(&path);
        let kind = f["operation"]["kind"].as_str().unwrap().to_string();
        let i = ["flip", "split", "sequence", "subdivide"]
            .iter()
            .position(|k| *k == kind)
            .unwrap_or_else(|| panic!("{}: kind {kind}", path.display()));
        n[i] += 1;
    }
    n
}

/// The case counts each handout's first table states, per stage.
fn stated_counts(path: &str) -> [Option<usize>; 4] {
    let text = read(path);
    let mut n = [None; 4];
    for row in text.lines().take_while(|l| !l.starts_with("## ")) {
        if !row.starts_with("| ") {
            continue;
        }
        let cells: Vec<&str> = row.trim_matches('|').split(" | ").collect();
        let first = cells[0];
        let stage = if first.contains("`flip_edge(") {
            0
        } else if first.contains("`split_edge(") {
            1
        } else if first.contains("in sequence") || first.contains("依次") {
            2
        } else if first.contains("`loop_subdivide(") {
            3
        } else {
            continue;
        };
        let last = cells.last().unwrap();
        let number: String = last
            .chars()
            .skip_while(|c| !c.is_ascii_digit())
            .take_while(char::is_ascii_digit)
            .collect();
        n[stage] = number.parse().ok();
    }
    n
}

#[test]
fn the_handouts_case_counts_come_from_the_fixtures() {
    let counts = lab_counts();
    assert!(counts.iter().all(|&c| c > 0), "{counts:?}");
    for path in ["docs/handout.en.md", "docs/handout.zh.md"] {
        assert_eq!(
            stated_counts(path),
            counts.map(Some),
            "{path}: flip, split, in sequence, subdivide as fixtures/lab has them"
        );
    }
}

/// The first `n` words of `text` before any colon, normalised.
fn words(text: &str, n: usize) -> String {
    normal(text.split(':').next().unwrap_or(text))
        .split(' ')
        .take(n)
        .collect::<Vec<_>>()
        .join(" ")
}

/// Section 1 promises that the grader names the mistakes; section 10
/// names each one the grader recognises, in the hint's words, in both
/// languages (the hints are the grader's English).
#[test]
fn every_mistake_the_grader_names_is_in_both_faqs() {
    for path in ["docs/handout.en.md", "docs/handout.zh.md"] {
        let text = read(path);
        let faq = normal(&text[text.find("\n## 10.").expect("a section 10")..]);
        let one = &text[text.find("\n## 1.").unwrap()..text.find("\n## 2.").unwrap()];
        assert!(
            one.contains("10"),
            "{path}: section 1 points to section 10's list"
        );
        for known in reference::catalogue::subdivision_mistakes() {
            let head = words(known.hint, 5);
            assert!(
                faq.contains(&head),
                "{path}: section 10 never quotes {head:?} ({})",
                known.id
            );
        }
    }
}

/// A heading's anchor as GitHub makes it: lower case, spaces to `-`,
/// every character but letters, digits, `-` and `_` dropped (Chinese
/// punctuation too).
fn slug(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

#[test]
fn both_tables_of_contents_link_to_every_section() {
    assert_eq!(
        slug("6. `loop_subdivide`: the 4-1 split as split + flip"),
        "6-loop_subdivide-the-4-1-split-as-split--flip"
    );
    assert_eq!(slug("7. 边界（附加题）"), "7-边界附加题");
    for path in ["docs/handout.en.md", "docs/handout.zh.md"] {
        let text = read(path);
        let sections: Vec<String> = text
            .lines()
            .filter_map(|l| l.strip_prefix("## "))
            .filter(|h| h.starts_with(|c: char| c.is_ascii_digit()))
            .map(slug)
            .collect();
        assert_eq!(sections.len(), 10, "{path}");
        let links: Vec<String> = text
            .split("](#")
            .skip(1)
            .map(|rest| rest[..rest.find(')').unwrap()].to_string())
            .collect();
        assert_eq!(
            links, sections,
            "{path}: the contents link each section, in order"
        );
    }
}

#[test]
fn the_figures_are_the_generators_and_each_handout_links_its_own() {
    let figures = lab_root().join("docs/figures");
    let svgs = |dir: &std::path::Path| -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".svg"))
            .collect();
        names.sort();
        names
    };
    // Every figure a handout links exists, in its own language.
    for (path, prefix) in [
        ("docs/handout.en.md", "figures/"),
        ("docs/handout.zh.md", "figures/zh/"),
    ] {
        let text = read(path);
        let linked: Vec<&str> = text
            .split("](figures/")
            .skip(1)
            .map(|rest| &rest[..rest.find(')').unwrap()])
            .collect();
        // Drawn figures (make_figures.py's SVG) come in each language;
        // screenshots of the report (PNG) show its English page in both.
        let drawn = linked.iter().filter(|l| l.ends_with(".svg")).count();
        assert_eq!(drawn, svgs(&figures).len(), "{path} links every figure");
        assert!(
            linked.contains(&"inspector.png"),
            "{path} shows the inspector"
        );
        for l in linked {
            let full = format!("figures/{l}");
            let own = if l.ends_with(".svg") {
                prefix
            } else {
                "figures/"
            };
            assert!(
                full.starts_with(own) && !full[own.len()..].contains('/'),
                "{path}: {full}"
            );
            assert!(
                lab_root().join("docs").join(&full).is_file(),
                "{path}: {full} is missing"
            );
        }
    }
    if std::process::Command::new("python3")
        .arg("--version")
        .output()
        .is_err()
    {
        common::skip("python3 is not installed: the figures' generator cannot be checked");
        return;
    }
    for (lang, committed) in [("en", figures.clone()), ("zh", figures.join("zh"))] {
        let out = common::scratch(&format!("figures-{lang}"));
        let run = std::process::Command::new("python3")
            .arg(figures.join("make_figures.py"))
            .args(["--lang", lang, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let made = if lang == "zh" {
            out.join("zh")
        } else {
            out.clone()
        };
        assert_eq!(svgs(&made), svgs(&committed), "{lang}: the same figures");
        for name in svgs(&made) {
            assert!(
                std::fs::read(made.join(&name)).unwrap()
                    == std::fs::read(committed.join(&name)).unwrap(),
                "{lang}/{name} differs from what make_figures.py draws: run it again"
            );
        }
        std::fs::remove_dir_all(&out).unwrap();
    }
}

/// The TA guide's section under `heading` (up to the next `## `).
fn guide_section(heading: &str) -> String {
    let text = read("docs/ta-guide.md");
    let start = text
        .find(&format!("\n## {heading}\n"))
        .unwrap_or_else(|| panic!("the TA guide has no section {heading:?}"));
    let rest = &text[start + 1..];
    let end = rest[3..].find("\n## ").map_or(rest.len(), |i| i + 3);
    rest[..end].to_string()
}

/// Every platform's section pins the toolchain as the bundles do (a
/// version, never the moving `stable` channel), and PrairieLearn's
/// `info.json` uses its current keys: the grading method at the top level,
/// no deprecated `enabled`, only keys PrairieLearn's schema has.
#[test]
fn the_platform_sections_pin_the_toolchain_and_use_current_keys() {
    for heading in ["Classroom 50", "PrairieLearn", "Gradescope"] {
        let section = guide_section(heading);
        assert!(
            !section.contains("\"stable\"") && !section.contains("rust: stable"),
            "{heading}: the toolchain is pinned to a version, not the stable channel"
        );
        assert!(
            section.contains("rust-toolchain.toml") || section.contains("setup.sh"),
            "{heading}: says where the version is pinned"
        );
    }
    let section = guide_section("PrairieLearn");
    let start = section
        .find("```json\n")
        .expect("info.json as a JSON block")
        + 8;
    let end = start + section[start..].find("```").unwrap();
    let info: serde_json::Value =
        serde_json::from_str(&section[start..end]).expect("the info.json example parses");
    assert_eq!(info["gradingMethod"], "External");
    let options = info["externalGradingOptions"].as_object().unwrap();
    // PrairieLearn's infoQuestion schema, less the deprecated `enabled`.
    let known = [
        "image",
        "entrypoint",
        "serverFilesCourse",
        "timeout",
        "enableNetworking",
        "environment",
    ];
    for key in options.keys() {
        assert!(
            known.contains(&key.as_str()),
            "externalGradingOptions.{key} is not a current key"
        );
    }
    assert_eq!(
        options["entrypoint"],
        "/grade/serverFilesCourse/meshlab/run.sh"
    );
}
