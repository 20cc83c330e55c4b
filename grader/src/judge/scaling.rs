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
//! ([`runner::Session::timed`]), never from a clock inside the child: the
//! student's code shares the child's address space, and a `#[no_mangle]
//! extern "C" fn clock_gettime` in `lib.rs` replaces libc's there (it once
//! made a quadratic answer 0.001 ms and "scales well"). Linear code grows
//! about 16x (11x to 28x measured under load), quadratic code about 256x
//! (210x to 317x); above
//! [`THRESHOLD`] (64x, n^1.5) the grader warns, naming the exponent.
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

use std::time::{Duration, Instant};

use halfedge::Mesh;
use serde::Serialize;

use crate::isolate::end::CaseEnd;
use crate::isolate::runner::{self, ChildProgram};
use crate::isolate::sandbox::Limits;
use crate::isolate::wire;

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
const CERTAIN: f64 = 4.0;

/// Runs of the small size, the fastest of which counts.
const SMALL_RUNS: usize = 3;

/// The larger size's limit, in multiples of the smaller's time (at least
/// [`MIN_LARGE_LIMIT`], at most the run's own limit): past that the code is
/// slow beyond doubt, and waiting longer tells nothing more.
const LARGE_LIMIT_FACTOR: f64 = 1000.0;
const MIN_LARGE_LIMIT: f64 = 2.0;

/// A time-out of the larger size is taken as a lower bound of its time only
/// when the limit was this many times [`THRESHOLD`] the smaller's time: the
/// limit is wall time, which a loaded machine stretches.
const TIMEOUT_MARGIN: f64 = 8.0;

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
    fn new(faces: [usize; 2], seconds: [f64; 2], timed_out: bool, runs: usize) -> Scaling {
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

/// How one timed run ended.
enum Run {
    Took(Duration),
    /// Still running at the limit.
    TimedOut,
    /// Anything else: a panic, a crash, a wrong face count, no CPU time.
    Failed,
}

/// One round of `loop_subdivide` on `mesh` in a child of its own, timed by
/// the grader.
fn time_once(program: &ChildProgram, limits: &Limits, mesh: &Mesh, limit: Duration) -> Run {
    let (v, e, f) = (mesh.num_vertices(), mesh.num_edges(), mesh.num_faces());
    // Every element one round makes (V + E, 2E + 3F, 4F, twice the
    // edges), with the room the cases give.
    let elements = (v + e) + (2 * e + 3 * f) + 4 * f + 2 * (2 * e + 3 * f);
    let budget = (elements * 16).max(10_000);
    let request = wire::Request {
        op: wire::Op::Subdivide { rounds: 1 },
        steps: Vec::new(),
        budget: budget as u64,
        mesh: mesh.clone(),
    };
    let Ok(report) = runner::Session::timed(program, limits).run(
        &request,
        false,
        limit,
        budget * 64 + (1 << 20),
    ) else {
        return Run::Failed;
    };
    match (&report.end, report.cpu) {
        (CaseEnd::Returned(r), Some(cpu)) if r.after.faces == 4 * f => Run::Took(cpu),
        (CaseEnd::TimedOut { .. }, _) => Run::TimedOut,
        _ => Run::Failed,
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

/// The least time left worth starting a timed run with: below it, the
/// timing is given up rather than cut short.
const MIN_LEFT: f64 = 0.5;

/// Seconds kept back from a deadline for starting each child and for the
/// grader to write its report once the timing is over.
const DEADLINE_MARGIN: f64 = 0.5;

/// The limits of the timed runs: the run's own, cut to what is left before
/// a deadline (`--budget`'s end), if any.
struct Clock {
    deadline: Option<Instant>,
}

impl Clock {
    /// `limit`, or the time left if shorter; `None` when too little is left.
    fn cap(&self, limit: Duration) -> Option<Duration> {
        let Some(deadline) = self.deadline else {
            return Some(limit);
        };
        let left = deadline
            .saturating_duration_since(Instant::now())
            .as_secs_f64()
            - DEADLINE_MARGIN;
        (left >= MIN_LEFT).then(|| limit.min(Duration::from_secs_f64(left)))
    }

    /// One timed run within the deadline; a time-out of a run cut short by
    /// the deadline proves nothing, and counts as a failure.
    fn time(&self, program: &ChildProgram, limits: &Limits, mesh: &Mesh, limit: Duration) -> Run {
        let Some(capped) = self.cap(limit) else {
            return Run::Failed;
        };
        match time_once(program, limits, mesh, capped) {
            Run::TimedOut if capped < limit => Run::Failed,
            other => other,
        }
    }

    /// The fastest of `n` runs, or `None` when one did not finish right.
    fn fastest(
        &self,
        program: &ChildProgram,
        limits: &Limits,
        mesh: &Mesh,
        limit: Duration,
        n: usize,
    ) -> Option<Duration> {
        let mut best: Option<Duration> = None;
        for _ in 0..n {
            match self.time(program, limits, mesh, limit) {
                Run::Took(t) => best = Some(best.map_or(t, |b| b.min(t))),
                Run::TimedOut | Run::Failed => return None,
            }
        }
        best
    }
}

/// Times `loop_subdivide` on the two icospheres, `timeout` seconds being
/// the run's limit per call, every run ending before `deadline` when one is
/// given. `None` when it could not be measured (a run failed, a time-out
/// that proves nothing, too little time left): then nothing is said.
pub fn measure(
    program: &ChildProgram,
    limits: &Limits,
    timeout: f64,
    deadline: Option<Instant>,
) -> Option<Scaling> {
    let clock = Clock { deadline };
    let small = halfedge::shapes::icosphere(SMALL_LEVEL);
    let large = halfedge::shapes::icosphere(LARGE_LEVEL);
    let faces = [small.num_faces(), large.num_faces()];
    let limit = Duration::from_secs_f64(timeout);
    let mut runs = SMALL_RUNS;
    let small_time = clock
        .fastest(program, limits, &small, limit, SMALL_RUNS)?
        .as_secs_f64();
    let large_limit = (small_time * LARGE_LIMIT_FACTOR)
        .max(MIN_LARGE_LIMIT)
        .min(timeout);
    runs += 1;
    let large_time = match clock.time(
        program,
        limits,
        &large,
        Duration::from_secs_f64(large_limit),
    ) {
        Run::Took(t) => t.as_secs_f64(),
        Run::TimedOut if large_limit >= THRESHOLD * TIMEOUT_MARGIN * small_time => {
            return Some(Scaling::new(faces, [small_time, large_limit], true, runs));
        }
        Run::TimedOut | Run::Failed => return None,
    };
    let first = Scaling::new(faces, [small_time, large_time], false, runs);
    if !first.quadratic || first.ratio > CERTAIN * THRESHOLD {
        return Some(first);
    }
    // Above the threshold, not far: measured again before it is said, the
    // fastest run of each size counting (a time-out now keeps the first).
    let again_small = clock
        .fastest(program, limits, &small, limit, 2)?
        .as_secs_f64();
    let again_large = match clock.time(
        program,
        limits,
        &large,
        Duration::from_secs_f64(large_limit),
    ) {
        Run::Took(t) => t.as_secs_f64(),
        Run::TimedOut => large_time,
        Run::Failed => return None,
    };
    Some(Scaling::new(
        faces,
        [small_time.min(again_small), large_time.min(again_large)],
        false,
        runs + 3,
    ))
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

    #[test]
    fn a_deadline_cuts_the_limits_and_gives_up_when_too_little_is_left() {
        let free = Clock { deadline: None };
        let ten = Duration::from_secs(10);
        assert_eq!(free.cap(ten), Some(ten));
        let soon = Clock {
            deadline: Some(Instant::now() + Duration::from_secs(3)),
        };
        let capped = soon.cap(ten).expect("time is left");
        assert!(capped < Duration::from_secs(3) && capped > Duration::from_secs(1));
        assert_eq!(
            soon.cap(Duration::from_millis(200)),
            Some(Duration::from_millis(200))
        );
        let past = Clock {
            deadline: Some(Instant::now() + Duration::from_millis(700)),
        };
        assert_eq!(past.cap(ten), None, "less than MIN_LEFT after the margin");
    }
}
