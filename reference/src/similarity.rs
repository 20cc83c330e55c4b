//! Similarity hints for class grading: which pairs of submissions share
//! much of their code once names, numbers, strings, comments and layout are
//! set aside.
//!
//! Each file becomes its normalised tokens ([`crate::tokens`]), then the set
//! of its runs of [`RUN`] tokens in a row. Runs the starting stubs already
//! have are dropped (every student starts from them), and so are runs that
//! many submissions share (the lab's API calls in the order the handout
//! gives them are common to honest answers). A pair's *shared fraction* is
//! the number of runs both have over the runs of the smaller of the two.
//! Byte-identical files come first, then pairs by shared fraction.
//!
//! These are hints for a person to look at, never a score change: two
//! correct `flip_edge`s written from the same table can look alike. And
//! like MOSS's `-m`, code more than half the class shares counts as common:
//! a source most of a class copied (a leaked solution) shows as every
//! submission failing the same way, not as pairs.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use grader::report::quoted;

use crate::tokens;

/// Tokens in a row that make one run. Long enough that two independent
/// answers rarely share one by chance (a `set_neighbors` call with its
/// arguments is about 15 tokens), short enough that moving whole functions
/// around or renaming keeps most runs.
pub const RUN: usize = 24;

/// Pairs at or above this shared fraction are listed by default.
pub const THRESHOLD: f64 = 0.5;

/// A run shared by more than this fraction of the class (and by more than
/// [`COMMON_MIN`] files) counts as common knowledge, not as copying.
const COMMON: f64 = 0.5;
/// In a small class a handful of copies would be "half the class".
const COMMON_MIN: usize = 5;

/// One pair of submissions that look alike.
#[derive(Clone, Debug, PartialEq)]
pub struct Pair {
    pub first: String,
    pub second: String,
    /// The files are the same bytes.
    pub identical: bool,
    /// Runs both share over the runs of the smaller file, 0 to 1.
    pub shared: f64,
    /// Runs both share (after the stubs' and the common runs are dropped).
    pub runs: usize,
}

/// Every run of [`RUN`] normalised tokens in `source`, hashed.
fn runs(source: &str) -> HashSet<u64> {
    use std::hash::{Hash, Hasher};
    let toks: Vec<String> = tokens::normalized(source)
        .into_iter()
        .map(|t| t.text)
        .collect();
    toks.windows(RUN)
        .map(|w| {
            let mut h = std::collections::hash_map::DefaultHasher::new();
            w.hash(&mut h);
            h.finish()
        })
        .collect()
}

/// The pairs of `files` (name, source) whose shared fraction is at least
/// `threshold`, and every byte-identical pair; `stubs` is the source every
/// student started from. Identical pairs first, then by shared fraction,
/// then by name.
pub fn similar_pairs(files: &[(String, String)], stubs: &str, threshold: f64) -> Vec<Pair> {
    let stub_runs = runs(stubs);
    let mut sets: Vec<HashSet<u64>> = files
        .iter()
        .map(|(_, source)| &runs(source) - &stub_runs)
        .collect();
    let mut seen: HashMap<u64, usize> = HashMap::new();
    for set in &sets {
        for &r in set {
            *seen.entry(r).or_default() += 1;
        }
    }
    let limit = ((files.len() as f64 * COMMON) as usize).max(COMMON_MIN);
    let common: HashSet<u64> = seen
        .into_iter()
        .filter(|&(_, n)| n > limit)
        .map(|(r, _)| r)
        .collect();
    for set in &mut sets {
        set.retain(|r| !common.contains(r));
    }
    let mut pairs = Vec::new();
    for i in 0..files.len() {
        for j in i + 1..files.len() {
            let identical = files[i].1 == files[j].1;
            let (a, b) = (&sets[i], &sets[j]);
            let smaller = a.len().min(b.len());
            let both = a.intersection(b).count();
            let shared = if smaller == 0 {
                0.0
            } else {
                both as f64 / smaller as f64
            };
            // A file of nothing but the stubs shares nothing worth a look.
            let identical = identical && !(a.is_empty() && files[i].1.trim() == stubs.trim());
            if identical || (smaller > 0 && shared >= threshold) {
                pairs.push(Pair {
                    first: files[i].0.clone(),
                    second: files[j].0.clone(),
                    identical,
                    shared: if identical { 1.0 } else { shared },
                    runs: both,
                });
            }
        }
    }
    pairs.sort_by(|x, y| {
        y.identical
            .cmp(&x.identical)
            .then(y.shared.total_cmp(&x.shared))
            .then_with(|| (&x.first, &x.second).cmp(&(&y.first, &y.second)))
    });
    pairs
}

/// `similarity.csv`: one row per pair, cells safe for spreadsheets.
pub fn csv(pairs: &[Pair]) -> String {
    let mut out = String::from("first,second,identical,shared_percent,shared_runs\n");
    for p in pairs {
        let _ = writeln!(
            out,
            "{},{},{},{:.1},{}",
            quoted::csv_field(&p.first),
            quoted::csv_field(&p.second),
            if p.identical { "yes" } else { "no" },
            p.shared * 100.0,
            p.runs
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const STUBS: &str = "pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {\n    \
                         todo!(\"flip_edge\")\n}\n";

    fn files(list: &[(&str, String)]) -> Vec<(String, String)> {
        list.iter()
            .map(|(n, s)| (n.to_string(), s.clone()))
            .collect()
    }

    #[test]
    fn a_renamed_copy_is_found_and_unrelated_code_is_not() {
        // Real, unrelated code for the honest students; the copy renames,
        // reflows and recomments the model solution.
        let alice = include_str!("solution.rs").to_string();
        let renamed = alice
            .replace("mesh", "m")
            .replace("// ", "// note: ")
            .replace(", ", ",\n    ");
        let carol = include_str!("tokens.rs").to_string();
        let dave = include_str!("fresh.rs").to_string();
        let pairs = similar_pairs(
            &files(&[
                ("alice", alice.clone()),
                ("bob", renamed),
                ("carol", carol),
                ("dave", dave),
                ("erin", alice),
            ]),
            STUBS,
            THRESHOLD,
        );
        // erin handed in alice's bytes: identical, listed first.
        assert_eq!(
            (pairs[0].first.as_str(), pairs[0].second.as_str()),
            ("alice", "erin")
        );
        assert!(pairs[0].identical);
        let names: Vec<(&str, &str)> = pairs
            .iter()
            .map(|p| (p.first.as_str(), p.second.as_str()))
            .collect();
        assert!(names.contains(&("alice", "bob")), "{pairs:?}");
        assert!(names.contains(&("bob", "erin")), "{pairs:?}");
        assert!(
            !names.iter().any(|(a, b)| *a == "carol" || *b == "carol"),
            "a different structure is not a copy: {pairs:?}"
        );
        let bob = pairs.iter().find(|p| p.second == "bob").unwrap();
        assert!(!bob.identical && bob.shared > 0.8, "{bob:?}");
    }

    #[test]
    fn untouched_stubs_are_not_a_pair() {
        let pairs = similar_pairs(
            &files(&[("a", STUBS.to_string()), ("b", STUBS.to_string())]),
            STUBS,
            THRESHOLD,
        );
        assert!(pairs.is_empty(), "{pairs:?}");
    }

    #[test]
    fn the_csv_is_safe_for_spreadsheets() {
        let p = Pair {
            first: "=HYPERLINK(\"x\")".into(),
            second: "b,c".into(),
            identical: false,
            shared: 0.756,
            runs: 31,
        };
        let text = csv(&[p]);
        let row = text.lines().nth(1).unwrap();
        assert!(!row.starts_with('='), "{row}");
        assert!(
            row.contains("\"b,c\"") && row.ends_with(",no,75.6,31"),
            "{row}"
        );
    }
}
