//! The similarity hints' memory, whatever a class hands in: this test
//! binary's allocator counts the bytes each thread holds, so every figure
//! here is exact and the same on any machine (no timing). A 60 MB `lib.rs`
//! once held the step in 4 GB.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use reference::similarity::{pairs_of, Fingerprinter, NotCompared, MAX_BYTES, THRESHOLD};

/// Counts what the calling thread holds and the most it held (the tests
/// run side by side: each thread counts its own).
struct Counting;

thread_local! {
    static HELD: Cell<usize> = const { Cell::new(0) };
    static PEAK: Cell<usize> = const { Cell::new(0) };
}

fn add(bytes: usize) {
    let _ = HELD.try_with(|held| {
        held.set(held.get() + bytes);
        let _ = PEAK.try_with(|peak| peak.set(peak.get().max(held.get())));
    });
}

fn remove(bytes: usize) {
    let _ = HELD.try_with(|held| held.set(held.get().saturating_sub(bytes)));
}

// SAFETY: every call is the system allocator's; the counters only add.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        add(layout.size());
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        remove(layout.size());
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        add(new_size);
        let moved = System.realloc(ptr, layout, new_size);
        remove(layout.size());
        moved
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

/// `f`'s result, the most it held above what was held before, and what it
/// still holds (its result included) once it returned.
fn measured<T>(f: impl FnOnce() -> T) -> (T, usize, usize) {
    let start = HELD.with(Cell::get);
    PEAK.with(|p| p.set(start));
    let out = f();
    let peak = PEAK.with(Cell::get) - start;
    let kept = HELD.with(Cell::get).saturating_sub(start);
    (out, peak, kept)
}

/// `bytes` of tokens no two runs of which are alike (a student's worst
/// case: every run distinct, one token a byte).
fn distinct_runs(bytes: usize) -> String {
    // No `/` (a comment would swallow the rest), no quotes.
    const PUNCT: &[u8] = b";,.+-*%^!&|<>=@#$?:~()[]{}";
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    (0..bytes)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            PUNCT[(state % PUNCT.len() as u64) as usize] as char
        })
        .collect()
}

const STUBS: &str = "pub fn flip_edge(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {\n    \
                     todo!(\"flip_edge\")\n}\n";

#[test]
fn a_file_at_the_cap_costs_a_bounded_few_bytes_a_byte() {
    // At the cap, with room for the copy's edit.
    let source = distinct_runs(MAX_BYTES - 64);
    let fingerprinter = Fingerprinter::new(STUBS);
    let (print, peak, kept) = measured(|| fingerprinter.of("mallory", &source));
    eprintln!(
        "fingerprint of {} KiB: peak {} KiB, kept {} KiB",
        MAX_BYTES >> 10,
        peak >> 10,
        kept >> 10
    );
    // Its characters (4 bytes each) and its runs' hashes (8 bytes each,
    // at most one a byte, twice while the list grows) while read; the
    // distinct runs after.
    assert!(peak <= 20 * MAX_BYTES + (64 << 10), "peak {peak} bytes");
    assert!(kept <= 8 * MAX_BYTES + (4 << 10), "kept {kept} bytes");
    // It is compared: an edited copy of it is found.
    let copy = fingerprinter.of("trudy", &(source.clone() + "\nfn extra() {}"));
    let (pairs, not_compared) = pairs_of(vec![print, copy], THRESHOLD);
    assert_eq!(not_compared, []);
    assert_eq!(pairs.len(), 1, "{pairs:?}");
    assert!(!pairs[0].identical && pairs[0].shared > 0.99, "{pairs:?}");
}

#[test]
fn a_file_over_the_cap_is_named_not_compared_and_costs_nothing_but_its_digest() {
    // 60 MB: the file that once took 4 GB.
    let huge = distinct_runs(60 << 20);
    let fingerprinter = Fingerprinter::new(STUBS);
    let (prints, peak, kept) = measured(|| {
        vec![
            fingerprinter.of("huge", &huge),
            fingerprinter.of("huge-again", &huge),
            fingerprinter.of("honest", STUBS),
        ]
    });
    eprintln!(
        "fingerprints of 2 x 60 MB and the stubs: peak {} KiB, kept {} KiB",
        peak >> 10,
        kept >> 10
    );
    assert!(peak < 64 << 10, "peak {peak} bytes");
    assert!(kept < 16 << 10, "kept {kept} bytes");
    let (pairs, not_compared) = pairs_of(prints, THRESHOLD);
    assert_eq!(
        not_compared,
        [
            NotCompared {
                name: "huge".into(),
                bytes: 60 << 20
            },
            NotCompared {
                name: "huge-again".into(),
                bytes: 60 << 20
            }
        ]
    );
    // Identical files are still found, by their digests.
    assert_eq!(pairs.len(), 1, "{pairs:?}");
    assert!(
        pairs[0].identical && pairs[0].first == "huge" && pairs[0].second == "huge-again",
        "{pairs:?}"
    );
}
