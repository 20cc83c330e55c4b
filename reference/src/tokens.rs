//! Rust source as normalised tokens, and the long runs two sources share.
//!
//! Renaming variables, renumbering or rewording strings, reformatting and
//! recommenting leave the sequence unchanged: identifiers become `I`,
//! numbers `N`, strings and characters `S`, comments and white space go;
//! keywords and punctuation stay. The handout check uses it to prove no
//! shipped file carries the model solution's code, by content rather than
//! by names.

use std::collections::HashMap;

/// One normalised token and the line it starts on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Token {
    pub text: String,
    pub line: usize,
}

const KEYWORDS: &[&str] = &[
    "as", "async", "await", "break", "const", "continue", "crate", "dyn", "else", "enum", "extern",
    "false", "fn", "for", "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub",
    "ref", "return", "self", "Self", "static", "struct", "super", "trait", "true", "type",
    "unsafe", "use", "where", "while",
];

/// The normalised tokens of `source` (Rust, or close enough: a lexing
/// mistake costs a token, never a panic).
pub fn normalized(source: &str) -> Vec<Token> {
    let mut out = Vec::new();
    each_token(source, |text, line| {
        out.push(Token {
            text: text.to_string(),
            line,
        })
    });
    out
}

/// Calls `f` with each normalised token of `source` and the line it starts
/// on, in order, keeping none: what [`normalized`] collects, in memory
/// that does not grow with the tokens (the similarity hints read whole
/// classes).
pub fn each_token(source: &str, mut f: impl FnMut(&str, usize)) {
    let chars: Vec<char> = source.chars().collect();
    let (mut i, mut line) = (0, 1);
    let at = |i: usize| chars.get(i).copied().unwrap_or('\0');
    while i < chars.len() {
        let c = chars[i];
        let start_line = line;
        let mut push = |text: &str| f(text, start_line);
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c == '/' && at(i + 1) == '/' {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && at(i + 1) == '*' {
            // Block comments nest in Rust.
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    line += usize::from(chars[i] == '\n');
                    i += 1;
                }
            }
        } else if c == 'r'
            && (at(i + 1) == '"' || (at(i + 1) == '#' && matches!(at(i + 2), '"' | '#')))
        {
            // A raw string: r"..." or r#"..."#.
            let mut j = i + 1;
            let mut hashes = 0;
            while at(j) == '#' {
                hashes += 1;
                j += 1;
            }
            j += 1;
            while j < chars.len() {
                if chars[j] == '"' && (1..=hashes).all(|k| at(j + k) == '#') {
                    j += 1 + hashes;
                    break;
                }
                line += usize::from(chars[j] == '\n');
                j += 1;
            }
            push("S");
            i = j;
        } else if c == '"' || (c == 'b' && at(i + 1) == '"') {
            let mut j = i + if c == 'b' { 2 } else { 1 };
            while j < chars.len() && chars[j] != '"' {
                if chars[j] == '\\' {
                    j += 1;
                }
                line += usize::from(at(j) == '\n');
                j += 1;
            }
            push("S");
            i = j + 1;
        } else if c == '\'' {
            // A character ('a', '\n', '\u{1b}') or a lifetime ('a).
            if at(i + 1) == '\\' {
                let mut j = i + 2;
                while j < chars.len() && chars[j] != '\'' {
                    j += 1;
                }
                push("S");
                i = j + 1;
            } else if at(i + 2) == '\'' {
                push("S");
                i += 3;
            } else {
                let mut j = i + 1;
                while is_ident(at(j)) {
                    j += 1;
                }
                push("'I");
                i = j.max(i + 1);
            }
        } else if c.is_ascii_digit() {
            let mut j = i;
            // Digits, suffixes and exponents; a `.` only when a digit
            // follows, so that `0..n` stays a range.
            while is_ident(at(j)) || (at(j) == '.' && at(j + 1).is_ascii_digit()) {
                j += 1;
            }
            push("N");
            i = j;
        } else if is_ident(c) {
            let mut j = i;
            while is_ident(at(j)) {
                j += 1;
            }
            let word: String = chars[i..j].iter().collect();
            push(if KEYWORDS.contains(&word.as_str()) {
                &word
            } else {
                "I"
            });
            i = j;
        } else {
            push(&c.to_string());
            i += 1;
        }
    }
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// A run of tokens that two sources share.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Shared {
    /// How many tokens long.
    pub tokens: usize,
    /// Where it starts in the first source and in the second (lines).
    pub line: usize,
    pub their_line: usize,
}

/// The longest run of at least `min` normalised tokens that `ours` shares
/// with `theirs`, if any: windows of `min` tokens are matched by hash, then
/// each match is grown as far as both go.
pub fn longest_shared<'t>(ours: &'t [Token], theirs: &'t [Token], min: usize) -> Option<Shared> {
    if min == 0 || ours.len() < min || theirs.len() < min {
        return None;
    }
    // Token texts as small numbers, so that windows hash cheaply.
    let mut ids: HashMap<&'t str, u32> = HashMap::new();
    let mut intern = |tokens: &'t [Token]| -> Vec<u32> {
        tokens
            .iter()
            .map(|t| {
                let next = ids.len() as u32;
                *ids.entry(&t.text).or_insert(next)
            })
            .collect()
    };
    let (a, b) = (intern(ours), intern(theirs));
    let mut windows: HashMap<&[u32], Vec<usize>> = HashMap::new();
    for j in 0..=b.len() - min {
        windows.entry(&b[j..j + min]).or_default().push(j);
    }
    let mut best: Option<Shared> = None;
    for i in 0..=a.len() - min {
        for &j in windows.get(&a[i..i + min]).into_iter().flatten() {
            let mut n = min;
            while i + n < a.len() && j + n < b.len() && a[i + n] == b[j + n] {
                n += 1;
            }
            if best.as_ref().is_none_or(|s| n > s.tokens) {
                best = Some(Shared {
                    tokens: n,
                    line: ours[i].line,
                    their_line: theirs[j].line,
                });
            }
        }
    }
    best
}
