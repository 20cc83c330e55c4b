//! The scaling check's timed runs (see [`crate::judge::scaling`] for the
//! check itself, its sizes, thresholds and words): one round of
//! `loop_subdivide` on each icosphere, each in a locked-in child like any
//! case, its CPU time read by the grader from the kernel, every run within
//! what a `--budget` left.

use std::time::{Duration, Instant};

use halfedge::Mesh;

use crate::isolate::end::CaseEnd;
use crate::isolate::runner::{self, ChildProgram};
use crate::isolate::sandbox::Limits;
use crate::isolate::wire;
use crate::judge::scaling::{
    Scaling, CERTAIN, LARGE_LEVEL, LARGE_LIMIT_FACTOR, MIN_LARGE_LIMIT, SMALL_LEVEL, SMALL_RUNS,
    THRESHOLD, TIMEOUT_MARGIN,
};

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
