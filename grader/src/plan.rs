//! What a run will do, worked out before it starts: each case ready to run
//! (its labellings), the growth budget of each call, the cases side by
//! side, and the per-call limit a `--budget` allows ([`Plan`], in the JSON
//! report).

use crate::cli::Cli;
use crate::judge::fixture::Fixture;
use crate::judge::relabel;

/// Seconds a function that already timed out gets on its later cases.
pub(crate) const SHORT_LIMIT: f64 = 1.0;

/// How many random labellings each case also runs on, besides the mesh as
/// built and (for a flip or split) the two chosen ones.
pub(crate) const RANDOM_LABELLINGS: usize = 2;

/// How many elements the mesh may grow to: generous for any correct answer,
/// small enough to stop runaway splitting in well under a second.
pub(crate) fn budget(fixture: &Fixture) -> usize {
    let e = &fixture.expected;
    // V + E + F + H of the expected result, bounded by 2E for faces and halfedges.
    let expected = e.positions.len() + e.edges.len() * 5;
    (expected * 16).max(10_000)
}

/// A case ready to run: its fixture, its input mesh and every labelling
/// of it the case runs on.
pub(crate) struct Case<'a> {
    pub(crate) fixture: &'a Fixture,
    pub(crate) seed: u64,
    pub(crate) labellings: Vec<relabel::Labelling>,
    /// Record a subdivision's splits for the step-through (`--report`).
    pub(crate) record: bool,
}

impl<'a> Case<'a> {
    pub(crate) fn new(fixture: &'a Fixture, input: halfedge::Mesh, cli: &Cli) -> Case<'a> {
        let seed = cli
            .seed
            .unwrap_or_else(|| relabel::default_seed(&fixture.name));
        let labellings =
            relabel::labellings(&input, fixture.edge_in(&input), seed, RANDOM_LABELLINGS);
        Case {
            fixture,
            seed,
            labellings,
            record: cli.report.is_some() || cli.record_subdivision,
        }
    }

    /// The student calls one run of the case makes: a sequence's run calls
    /// once per step, so its time limit and its share of a budget are
    /// counted in calls.
    pub(crate) fn calls(&self) -> usize {
        self.fixture.steps.len().max(1)
    }

    /// Calls over every labelling.
    pub(crate) fn runs(&self) -> usize {
        self.labellings.len() * self.calls()
    }
}

/// How many cases run side by side: one per core, at most four.
pub(crate) fn workers(cases: usize) -> usize {
    std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, 4)
        .min(cases.max(1))
}

/// Seconds each child run may cost beyond its call (start, lock-in,
/// sending the mesh, judging), and the run's own start (loading and checking
/// the fixtures), as counted against `--budget`.
const RUN_OVERHEAD: f64 = 0.05;
const RUN_START: f64 = 1.0;

/// How long a run may take, worked out from the runs it makes.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Plan {
    /// Child runs if every case passes (one per labelling).
    pub runs: usize,
    /// Most runs of one case.
    pub longest_case: usize,
    pub workers: usize,
    /// Seconds each call may take.
    pub timeout: f64,
    /// `--budget`, when given.
    pub budget: Option<f64>,
}

impl Plan {
    /// The per-call limit: `timeout`, shortened so that `budget` holds the
    /// worst a run can take. Cases run on `workers` side by side, each
    /// case's runs one after another, so (list scheduling) the run ends
    /// within runs/w + (1 - 1/w) x longest case of run-times; a case that
    /// fails stops early and a function that timed out gets a shorter
    /// limit, so that bound holds whatever the student's code does.
    fn new(
        runs: usize,
        longest_case: usize,
        workers: usize,
        timeout: f64,
        budget: Option<f64>,
    ) -> Plan {
        let w = workers.max(1) as f64;
        let slots = runs as f64 / w + (1.0 - 1.0 / w) * longest_case as f64;
        let timeout = match budget {
            Some(b) if slots > 0.0 => {
                // In hundredths of a second, as the messages show it.
                let share = (((b - RUN_START) / slots - RUN_OVERHEAD) * 100.0).floor() / 100.0;
                // Never below the shortest limit the grader takes; the
                // time line says when the budget cannot hold every run.
                timeout.min(share).max(MIN_TIMEOUT)
            }
            _ => timeout,
        };
        Plan {
            runs,
            longest_case,
            workers,
            timeout,
            budget,
        }
    }

    pub(crate) fn of(cases: &[Case], cli: &Cli) -> Plan {
        let runs = cases.iter().map(Case::runs).sum();
        let longest = cases.iter().map(Case::runs).max().unwrap_or(0);
        Plan::new(runs, longest, workers(cases.len()), cli.timeout, cli.budget)
    }

    /// The line the text report gives it when `--budget` shortened the limit.
    pub fn describe(&self, asked: f64) -> Option<String> {
        let budget = self.budget?;
        (self.timeout < asked).then(|| {
            format!(
                "time: each call may take {:.2} s, not {asked} s, so that {} runs ({} side by side) fit in the budget of {budget} s",
                self.timeout, self.runs, self.workers
            )
        })
    }
}

/// The shortest `--timeout` taken.
pub(crate) const MIN_TIMEOUT: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_budget_shortens_the_limit_by_the_runs_it_must_hold() {
        // Ample: the limit asked for stays.
        assert_eq!(Plan::new(120, 5, 1, 0.4, Some(100.0)).timeout, 0.4);
        // One worker: every run one after another.
        let p = Plan::new(120, 5, 1, 10.0, Some(61.0));
        assert_eq!(p.timeout, 0.45, "{p:?}");
        // Two: half the runs, plus what the longest case may leave over.
        let p = Plan::new(120, 5, 2, 10.0, Some(63.5));
        assert_eq!(p.timeout, 0.95, "{p:?}");
        // No budget, or one too short: the limit asked for, or the shortest.
        assert_eq!(Plan::new(120, 5, 1, 3.0, None).timeout, 3.0);
        assert_eq!(Plan::new(120, 5, 1, 3.0, Some(2.0)).timeout, MIN_TIMEOUT);
    }
}
