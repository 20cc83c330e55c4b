//! Catching quadratic code: `loop_subdivide` timed on two sizes of the same
//! surface in the same run.
//!
//! A correct `loop_subdivide` can still be slow for its size: a scan over
//! every edge inside the loop over the edges (to find the edges around the
//! vertex a split made, say) passes every case of the lab, whose meshes are
//! small, and takes minutes on a mesh of a million faces. So, once every
//! counted subdivision case has passed, the grader runs one round on
//! icospheres of [`SMALL_LEVEL`] and [`LARGE_LEVEL`] (16 times the faces),
//! each in a locked-in child like any case, and compares the CPU time of the
//! two calls (a loaded machine stretches the wall clock, much less the CPU
//! time). The grader reads that time from the kernel's accounting of the
//! child process, from the request sent to the result read
//! (`runner::Session::timed`), never from a clock inside the child: the
//! student's code shares the child's address space, and a `#[no_mangle]
//! extern "C" fn clock_gettime` in `lib.rs` replaces libc's there (it once
//! made a quadratic answer 0.001 ms and "scales well"). Linear code grows
//! about 16x (11x to 28x measured under load), quadratic code about 256x
//! (210x to 317x); above
//! [`THRESHOLD`] (64x, n^1.5) the grader warns, naming the exponent.
//!
//! This module is the check's verdict and its words; the timed runs, in
//! locked-in children, are the run's (`crate::timing`: the judge starts no
//! process).
//!
//! It is a warning only, never counted: the figures depend on the machine
//! and on what else runs on it, and a grade must not. To keep a loaded
//! machine from making linear code look quadratic, the small size runs
//! several times and the fastest counts, and a ratio above the threshold
//! is measured again (both sizes) before anything is said.
//!
//! With `--budget` it runs only when asked (`--time-subdivision`, which
//! Gradescope's leaderboard uses), and then within what the cases left of
//! the budget: every run's limit is cut to the time left, and the timing
//! is given up (nothing said) when too little is left, so it never
//! shortens a case's limit nor runs the grader past its budget.

use serde::Serialize;

/// The icosphere levels timed: 80 and 1280 faces, one round making 320
/// and 5120. Small enough that a linear debug build takes a few
/// milliseconds on the larger, and quadratic code a fraction of a second
/// (two levels more and it takes seconds, and a loaded machine runs past
/// the time limit).
pub const SMALL_LEVEL: usize = 1;
pub const LARGE_LEVEL: usize = 3;

/// How much faster than the faces the time may grow before the grader
/// warns: 64x for 16x the faces, n^1.5. A correct solution measured 11x
/// to 28x with both cores busy (docs/grader-messages.md).
pub const THRESHOLD: f64 = 64.0;

/// A ratio this many times [`THRESHOLD`] is said without measuring again:
/// no load makes CPU time 4 times what the work needs.
pub const CERTAIN: f64 = 4.0;

/// Runs of the small size, the fastest of which counts.
pub const SMALL_RUNS: usize = 3;

/// The larger size's limit, in multiples of the smaller's time (at least
/// [`MIN_LARGE_LIMIT`], at most the run's own limit): past that the code is
/// slow beyond doubt, and waiting longer tells nothing more.
pub const LARGE_LIMIT_FACTOR: f64 = 1000.0;
pub const MIN_LARGE_LIMIT: f64 = 2.0;

/// A time-out of the larger size is taken as a lower bound of its time only
/// when the limit was this many times [`THRESHOLD`] the smaller's time: the
/// limit is wall time, which a loaded machine stretches.
pub const TIMEOUT_MARGIN: f64 = 8.0;

/// What the timing found.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Scaling {
    /// Faces of the two icospheres.
    pub faces: [usize; 2],
    /// The fastest CPU time of one round on each, in seconds (for a larger
    /// size that timed out: the limit, in wall seconds).
    pub seconds: [f64; 2],
    /// `seconds[1] / seconds[0]`.
    pub ratio: f64,
    /// The power of n the ratio means: ln(ratio) / ln(16).
    pub exponent: f64,
    /// The larger size did not finish within its limit.
    pub timed_out: bool,
    /// The ratio is above [`THRESHOLD`]: the warning is given.
    pub quadratic: bool,
    /// Child runs made.
    pub runs: usize,
}

/// "1.2 ms", "0.85 s".
fn human(seconds: f64) -> String {
    if seconds < 0.01 {
        format!("{:.2} ms", seconds * 1000.0)
    } else if seconds < 1.0 {
        format!("{:.1} ms", seconds * 1000.0)
    } else {
        format!("{seconds:.2} s")
    }
}

impl Scaling {
    pub fn new(faces: [usize; 2], seconds: [f64; 2], timed_out: bool, runs: usize) -> Scaling {
        let ratio = seconds[1] / seconds[0].max(1e-9);
        let sizes = faces[1] as f64 / faces[0] as f64;
        Scaling {
            faces,
            seconds,
            ratio,
            exponent: ratio.ln() / sizes.ln(),
            timed_out,
            quadratic: ratio > THRESHOLD,
            runs,
        }
    }

    /// The line the summary prints.
    pub fn message(&self) -> String {
        let [small, large] = self.faces;
        let sizes = large / small.max(1);
        if self.timed_out {
            return format!(
                "loop_subdivide's time grew more than {:.0}x for {sizes}x the faces: one round took \
                 {} of CPU time on an icosphere of {small} faces, and did not finish within {} on \
                 one of {large}: is there a loop over all edges (or vertices) inside a loop? \
                 (a warning only: it does not count toward the grade)",
                self.ratio,
                human(self.seconds[0]),
                human(self.seconds[1]),
            );
        }
        let measured = format!(
            "CPU time of one round on icospheres of {small} and {large} faces: {} and {}",
            human(self.seconds[0]),
            human(self.seconds[1])
        );
        if self.quadratic {
            format!(
                "loop_subdivide's time grew {:.0}x for {sizes}x the faces, about n^{:.1}: is there \
                 a loop over all edges (or vertices) inside a loop? ({measured}; linear code grows \
                 about {sizes}x; a warning only: it does not count toward the grade)",
                self.ratio, self.exponent
            )
        } else {
            format!(
                "loop_subdivide scales well: its time grew {:.0}x for {sizes}x the faces, about \
                 n^{:.1} ({measured})",
                self.ratio, self.exponent
            )
        }
    }
}

/// Whether the run times `loop_subdivide`: it graded subdivision (`asked`:
/// no `--case`, no `--stage` but `subdivide`, no `--budget` unless
/// `--time-subdivision`), and every counted subdivision case passed (a slow
/// answer is worth fixing once it is right).
pub fn wanted(reports: &[crate::judge::grade::CaseReport], asked: bool) -> bool {
    use crate::judge::fixture::{Group, Stage};
    let counted: Vec<_> = reports
        .iter()
        .filter(|r| r.stage == Stage::Subdivide && r.group != Group::Bonus)
        .collect();
    asked && !counted.is_empty() && counted.iter().all(|r| r.passed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_exponent_and_the_warning_follow_the_ratio() {
        let linear = Scaling::new([80, 1280], [0.0012, 0.024], false, 4);
        assert!((linear.ratio - 20.0).abs() < 1e-9, "{linear:?}");
        assert!(!linear.quadratic);
        assert!(
            linear.message().starts_with(
                "loop_subdivide scales well: its time grew 20x for 16x the faces, about n^1.1"
            ),
            "{}",
            linear.message()
        );
        let quadratic = Scaling::new([80, 1280], [0.005, 0.9], false, 7);
        assert!(quadratic.quadratic);
        assert!(
            quadratic.message().starts_with(
                "loop_subdivide's time grew 180x for 16x the faces, about n^1.9: is there a loop over all edges"
            ),
            "{}",
            quadratic.message()
        );
        // Just under and over the threshold.
        assert!(!Scaling::new([80, 1280], [0.001, 0.064], false, 4).quadratic);
        assert!(Scaling::new([80, 1280], [0.001, 0.0641], false, 4).quadratic);
        let slow = Scaling::new([80, 1280], [0.002, 2.0], true, 4);
        assert!(slow.quadratic && slow.message().contains("did not finish within 2.00 s"));
    }
}
