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
//! Memory stays bounded whatever a class hands in: a file is compared only
//! up to [`MAX_BYTES`] (a larger one is still found identical to another
//! by its digest, and is listed as not compared), its tokens are hashed as
//! they are read, and all a file keeps is its distinct runs' hashes (8
//! bytes a run, at most one run a byte): about 2 MiB for a file at the
//! cap, 40 KiB for a solved lab. A 60 MB `lib.rs` once took 4 GB here.
//!
//! These are hints for a person to look at, never a score change: two
//! correct `flip_edge`s written from the same table can look alike. And
//! like MOSS's `-m`, code more than half the class shares counts as common:
//! a source most of a class copied (a leaked solution) shows as every
//! submission failing the same way, not as pairs.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::fmt::Write as _;
use std::hash::{Hash, Hasher};

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

/// The largest file compared, in bytes: 25 times a solved lab's `lib.rs`
/// (its 10 KiB of stubs and a solution of 20-40 KiB).
pub const MAX_BYTES: usize = 256 << 10;

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

/// A file left out of the comparison (its size, in bytes).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NotCompared {
    pub name: String,
    pub bytes: usize,
}

/// What is kept of one file: its digest (identical files are found at any
/// size), whether it is the stubs, and its runs' hashes, sorted and
/// distinct, those of the stubs left out (`None`: larger than
/// [`MAX_BYTES`], not compared).
#[derive(Clone, Debug)]
pub struct Fingerprint {
    pub name: String,
    pub bytes: usize,
    digest: String,
    is_stubs: bool,
    runs: Option<Vec<u64>>,
}

/// Turns each file into its [`Fingerprint`], given the stubs every student
/// started from.
pub struct Fingerprinter {
    stubs: String,
    stub_runs: Vec<u64>,
}

impl Fingerprinter {
    pub fn new(stubs: &str) -> Fingerprinter {
        Fingerprinter {
            stubs: stubs.trim().to_string(),
            stub_runs: runs(stubs),
        }
    }

    pub fn of(&self, name: &str, source: &str) -> Fingerprint {
        let runs = (source.len() <= MAX_BYTES).then(|| {
            let mut own = runs(source);
            own.retain(|r| self.stub_runs.binary_search(r).is_err());
            own.shrink_to_fit();
            own
        });
        Fingerprint {
            name: name.to_string(),
            bytes: source.len(),
            digest: sha256::sha256_hex(source.as_bytes()),
            is_stubs: source.trim() == self.stubs,
            runs,
        }
    }
}

fn hash_of(value: impl Hash) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    value.hash(&mut h);
    h.finish()
}

/// Every run of [`RUN`] normalised tokens in `source`, hashed, sorted and
/// distinct: each token is hashed as it is read and the last [`RUN`] kept.
fn runs(source: &str) -> Vec<u64> {
    let mut window = std::collections::VecDeque::with_capacity(RUN + 1);
    let mut out = Vec::new();
    tokens::each_token(source, |text, _| {
        window.push_back(hash_of(text));
        if window.len() > RUN {
            window.pop_front();
        }
        if window.len() == RUN {
            out.push(hash_of(&window));
        }
    });
    out.sort_unstable();
    out.dedup();
    out
}

/// How many runs two sorted, distinct lists share.
fn shared_count(a: &[u64], b: &[u64]) -> usize {
    let (mut i, mut j, mut n) = (0, 0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                n += 1;
                i += 1;
                j += 1;
            }
        }
    }
    n
}

/// The runs more than `limit` of the lists hold, sorted: a merge of the
/// sorted lists, in memory for one cursor a list.
fn common_runs(lists: &[&[u64]], limit: usize) -> Vec<u64> {
    let mut heap: BinaryHeap<Reverse<(u64, usize, usize)>> = lists
        .iter()
        .enumerate()
        .filter_map(|(k, l)| Some(Reverse((*l.first()?, k, 0))))
        .collect();
    let mut common = Vec::new();
    let mut current: Option<(u64, usize)> = None;
    while let Some(Reverse((value, k, at))) = heap.pop() {
        match &mut current {
            Some((v, n)) if *v == value => *n += 1,
            _ => {
                if let Some((v, n)) = current {
                    if n > limit {
                        common.push(v);
                    }
                }
                current = Some((value, 1));
            }
        }
        if let Some(&next) = lists[k].get(at + 1) {
            heap.push(Reverse((next, k, at + 1)));
        }
    }
    if let Some((v, n)) = current {
        if n > limit {
            common.push(v);
        }
    }
    common
}

/// The pairs of `files` (name, source) whose shared fraction is at least
/// `threshold`, and every byte-identical pair; `stubs` is the source every
/// student started from. Identical pairs first, then by shared fraction,
/// then by name. (A class's files are best turned into fingerprints one
/// at a time, as they are read: [`pairs_of`].)
pub fn similar_pairs(files: &[(String, String)], stubs: &str, threshold: f64) -> Vec<Pair> {
    let fingerprinter = Fingerprinter::new(stubs);
    let prints: Vec<Fingerprint> = files
        .iter()
        .map(|(name, source)| fingerprinter.of(name, source))
        .collect();
    pairs_of(prints, threshold).0
}

/// The pairs of [`similar_pairs`] from each file's fingerprint, and the
/// files too large to compare (still paired when identical).
pub fn pairs_of(mut files: Vec<Fingerprint>, threshold: f64) -> (Vec<Pair>, Vec<NotCompared>) {
    let lists: Vec<&[u64]> = files.iter().filter_map(|f| f.runs.as_deref()).collect();
    // Half of the files compared: one too large to compare shares no run.
    let limit = ((lists.len() as f64 * COMMON) as usize).max(COMMON_MIN);
    let common = common_runs(&lists, limit);
    for f in &mut files {
        if let Some(runs) = &mut f.runs {
            runs.retain(|r| common.binary_search(r).is_err());
        }
    }
    let mut pairs = Vec::new();
    for i in 0..files.len() {
        for j in i + 1..files.len() {
            let (x, y) = (&files[i], &files[j]);
            // A file of nothing but the stubs shares nothing worth a look.
            let identical = x.digest == y.digest && !x.is_stubs;
            let (both, smaller) = match (&x.runs, &y.runs) {
                (Some(a), Some(b)) => (shared_count(a, b), a.len().min(b.len())),
                _ => (0, 0),
            };
            let shared = if smaller == 0 {
                0.0
            } else {
                both as f64 / smaller as f64
            };
            if identical || (smaller > 0 && shared >= threshold) {
                pairs.push(Pair {
                    first: x.name.clone(),
                    second: y.name.clone(),
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
    let not_compared = files
        .iter()
        .filter(|f| f.runs.is_none())
        .map(|f| NotCompared {
            name: f.name.clone(),
            bytes: f.bytes,
        })
        .collect();
    (pairs, not_compared)
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
