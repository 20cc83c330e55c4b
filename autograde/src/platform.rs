//! Turning a graded (or ungraded) submission into each platform's result
//! file: Gradescope's `results.json`, Classroom 50's `result.json`
//! (`classroom50/result/v1`) and PrairieLearn's external grader
//! `results.json`. Every platform gets the same facts: points per function
//! (one per counted case), and, for a submission that was not graded, why
//! (student text, such as the compiler's words, already quoted).

use serde_json::{json, Value};

use crate::grade::{StageRun, STAGES};

/// What grading a submission came to, for any platform.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// Every stage was run (some may have been stopped at their deadline).
    Graded {
        stages: Vec<StageRun>,
        /// Lines for the student above the cases (compiler warnings).
        notes: Vec<String>,
        bonus: bool,
    },
    /// Not graded: no file, a compile error, a build stopped at a limit.
    NotGraded {
        /// Shown first ("Your code does not compile:").
        message: String,
        /// Counted cases per stage, all lost.
        counts: [usize; 4],
    },
}

impl Outcome {
    /// (passed, counted) per stage, in [`STAGES`] order; a stage stopped
    /// at its deadline, or not graded, passes none of its cases.
    pub fn per_function(&self) -> [(usize, usize); 4] {
        match self {
            Outcome::NotGraded { counts, .. } => counts.map(|n| (0, n)),
            Outcome::Graded { stages, .. } => {
                let mut out = [(0, 0); 4];
                for run in stages {
                    let k = STAGES.iter().position(|s| *s == run.stage).unwrap_or(0);
                    let passed = run
                        .results
                        .as_ref()
                        .and_then(|r| r["tests"].as_array().cloned())
                        .unwrap_or_default()
                        .iter()
                        .filter(|t| t["status"] == "passed")
                        .count();
                    out[k] = (passed.min(run.cases), run.cases);
                }
                out
            }
        }
    }

    pub fn score(&self) -> usize {
        self.per_function().iter().map(|f| f.0).sum()
    }

    pub fn max(&self) -> usize {
        self.per_function().iter().map(|f| f.1).sum()
    }
}

/// Gradescope's `results.json`: one test per counted case (the grader's
/// own, hidden cases `after_published`), a failing test worth the stage's
/// points for a stage that was stopped or failed, and a summary naming the
/// visible cases passed. No total is shown to students while hidden tests
/// wait for publication (Gradescope hides the score then).
pub fn gradescope(outcome: &Outcome) -> Value {
    match outcome {
        Outcome::NotGraded { message, counts } => gradescope_zero(message, counts.iter().sum()),
        Outcome::Graded {
            stages,
            notes,
            bonus,
        } => {
            let mut tests = Vec::new();
            let mut summary = Vec::new();
            for run in stages {
                let function = run.stage.function;
                match &run.results {
                    Some(results) => {
                        let stage_tests = results["tests"].as_array().cloned().unwrap_or_default();
                        let shown: Vec<&Value> = stage_tests
                            .iter()
                            .filter(|t| t["visibility"] == "visible")
                            .collect();
                        let ok = shown.iter().filter(|t| t["status"] == "passed").count();
                        summary.push(format!(
                            "{function}: {ok}/{} visible cases passed",
                            shown.len()
                        ));
                        tests.extend(stage_tests);
                    }
                    None => {
                        tests.push(json!({
                            "name": format!("{function}: all cases"),
                            "score": 0.0,
                            "max_score": run.cases as f64,
                            "status": "failed",
                            "output": run.why_not_graded(),
                            "visibility": "visible",
                        }));
                        summary.push(if run.code.is_none() {
                            format!("{function}: stopped (time budget)")
                        } else {
                            format!("{function}: not graded")
                        });
                    }
                }
            }
            let hidden = tests
                .iter()
                .filter(|t| t["visibility"] == "after_published")
                .count();
            if hidden > 0 {
                summary.push(format!(
                    "{hidden} hidden cases: shown once grades are published"
                ));
            }
            if !bonus {
                summary.push(
                    "bonus cases (meshes with boundary) are not graded here: run `cargo run -p \
                     grader -- --bonus` to try them"
                        .into(),
                );
            }
            let score: f64 = tests.iter().filter_map(|t| t["score"].as_f64()).sum();
            let mut output = notes.clone();
            output.push(summary.join("\n"));
            json!({
                "score": score,
                "output": output.join("\n"),
                "output_format": "text",
                "stdout_visibility": "hidden",
                "tests": tests,
            })
        }
    }
}

/// Gradescope's results for a submission that was not graded: zero out of
/// the full score, with why.
pub fn gradescope_zero(message: &str, max: usize) -> Value {
    let mut tests = Vec::new();
    if max > 0 {
        tests.push(json!({
            "name": "your code compiles and can be graded",
            "score": 0.0,
            "max_score": max as f64,
            "status": "failed",
            "output": message,
            "visibility": "visible",
        }));
    }
    json!({
        "score": 0.0,
        "output": message,
        "output_format": "text",
        "stdout_visibility": "hidden",
        "tests": tests,
    })
}

/// Why a submission has no leaderboard entry.
#[derive(Clone, Debug, PartialEq)]
pub enum Untimed {
    /// Not graded, or the subdivision stage was stopped or failed to run.
    NotGraded,
    /// A counted subdivision case failed: a wrong answer is not timed.
    Failing,
    /// The larger icosphere did not finish within the limit (seconds).
    TooSlow { faces: usize, limit: f64 },
    /// Subdivision passed, yet no time came back (a run failed, or too
    /// little of the budget was left).
    NotMeasured,
}

impl Untimed {
    /// The line the student reads in place of a time.
    fn message(&self) -> String {
        let why = match self {
            Untimed::NotGraded => "loop_subdivide was not graded".to_string(),
            Untimed::Failing => "loop_subdivide does not pass every case yet".to_string(),
            Untimed::TooSlow { faces, limit } => format!(
                "one round of loop_subdivide on an icosphere of {faces} faces did not finish \
                 within {limit:.2} s"
            ),
            Untimed::NotMeasured => {
                "loop_subdivide could not be timed within the time left".to_string()
            }
        };
        format!("leaderboard: no time ({why})")
    }
}

/// The leaderboard's figure: the CPU time, in milliseconds, of one round
/// of `loop_subdivide` on the grader's larger icosphere (its scaling
/// check, `scaling` in the subdivision stage's JSON report), with that
/// icosphere's faces. Only for a subdivision that passed every counted case
/// and finished: a time-out is a limit, not a time.
pub fn subdivision_time(outcome: &Outcome) -> Result<(usize, f64), Untimed> {
    let Outcome::Graded { stages, .. } = outcome else {
        return Err(Untimed::NotGraded);
    };
    let run = stages
        .iter()
        .find(|r| r.stage.stage == "subdivide")
        .ok_or(Untimed::NotGraded)?;
    let report = run.report.as_ref().ok_or(Untimed::NotGraded)?;
    let scaling = &report["scaling"];
    if scaling.is_null() {
        let counted_all_passed = run
            .case_reports()
            .iter()
            .filter(|c| c["group"] != "bonus")
            .all(|c| c["passed"] == true);
        return Err(if counted_all_passed && run.cases > 0 {
            Untimed::NotMeasured
        } else {
            Untimed::Failing
        });
    }
    let faces = scaling["faces"][1].as_u64().unwrap_or(0) as usize;
    let seconds = scaling["seconds"][1].as_f64().unwrap_or(0.0);
    if scaling["timed_out"] == true {
        return Err(Untimed::TooSlow {
            faces,
            limit: seconds,
        });
    }
    if faces == 0 || seconds.is_nan() || seconds <= 0.0 {
        return Err(Untimed::NotMeasured);
    }
    Ok((faces, seconds * 1000.0))
}

/// Adds Gradescope's `leaderboard` to its `results.json` (lowest time
/// first), or, when there is no time, the line saying why to its output
/// (not for a submission that was not graded at all: its output already
/// says why).
pub fn add_gradescope_leaderboard(results: &mut Value, outcome: &Outcome) {
    match subdivision_time(outcome) {
        Err(_) if matches!(outcome, Outcome::NotGraded { .. }) => {}
        Ok((faces, ms)) => {
            results["leaderboard"] = json!([{
                "name": format!("loop_subdivide (ms, icosphere {faces} faces)"),
                // Microseconds are below what a loaded machine keeps steady.
                "value": (ms * 1000.0).round() / 1000.0,
                "order": "asc",
            }]);
        }
        Err(why) => {
            let mut output = results["output"].as_str().unwrap_or_default().to_string();
            if !output.is_empty() {
                output.push('\n');
            }
            output.push_str(&why.message());
            results["output"] = json!(output);
        }
    }
}

/// What Classroom 50's runner gives an autograder (its environment), for
/// the identity fields of `result.json`.
#[derive(Clone, Debug, Default)]
pub struct Classroom50 {
    pub classroom: String,
    pub assignment: String,
    pub submission: String,
    pub commit: String,
    pub release: String,
    pub review: String,
    /// UTC, ISO 8601: when the autograder ran, by the runner's clock (the
    /// graded commit's date is the student's to set).
    pub datetime: String,
}

/// Classroom 50's `result.json` (schema `classroom50/result/v1`): one test
/// per function worth its counted cases, integer points; a submission not
/// graded has one extra failing test, `compiles`, carrying why (a test's
/// extra fields are kept by the runner).
pub fn classroom50(outcome: &Outcome, ids: &Classroom50) -> Value {
    let mut tests: Vec<Value> = STAGES
        .iter()
        .zip(outcome.per_function())
        .filter(|(_, (_, of))| *of > 0)
        .map(|(stage, (passed, of))| {
            json!({
                "test-name": stage.column,
                "passed": passed == of,
                "score": passed,
                "max-score": of,
            })
        })
        .collect();
    if let Outcome::NotGraded { message, .. } = outcome {
        tests.insert(
            0,
            json!({"test-name": "compiles", "passed": false, "score": 0, "max-score": 0,
                   "message": message}),
        );
    }
    let review = if ids.review.is_empty() {
        &ids.commit
    } else {
        &ids.review
    };
    json!({
        "schema": "classroom50/result/v1",
        "classroom": ids.classroom,
        "assignment": ids.assignment,
        "submission": ids.submission,
        "commit": ids.commit,
        "release": ids.release,
        "review": review,
        "datetime": ids.datetime,
        "score": outcome.score(),
        "max-score": outcome.max(),
        "tests": tests,
    })
}

/// The first failure of each stage, for messages: "case: first warning".
fn first_failures(run: &StageRun) -> Vec<String> {
    run.case_reports()
        .iter()
        .filter(|c| c["passed"] == false)
        .map(|c| {
            grader::report::quoted::one_line(&format!(
                "{}: {}",
                c["name"].as_str().unwrap_or("?"),
                c["first_warning"].as_str().unwrap_or("failed")
            ))
        })
        .collect()
}

/// PrairieLearn's external grader `results.json`: `score` in [0, 1], one
/// test per function (`points` of `max_points`, its first failure as the
/// message). A submission that does not compile is `gradable: false` with
/// the compiler's words in `format_errors`: PrairieLearn then awards
/// nothing and takes no attempt.
pub fn prairielearn(outcome: &Outcome) -> Value {
    let max = outcome.max();
    let score = if max == 0 {
        0.0
    } else {
        outcome.score() as f64 / max as f64
    };
    match outcome {
        Outcome::NotGraded { message, .. } => json!({
            "gradable": false,
            "score": 0.0,
            "message": message,
            "format_errors": [message],
            "tests": [],
        }),
        Outcome::Graded { stages, notes, .. } => {
            let tests: Vec<Value> = stages
                .iter()
                .zip(outcome.per_function().iter().filter(|f| f.1 > 0))
                .map(|(run, (passed, of))| {
                    let failures = first_failures(run);
                    let message = match (&run.results, failures.first()) {
                        (None, _) => run.why_not_graded(),
                        (Some(_), Some(first)) => format!(
                            "{first}{}",
                            if failures.len() > 1 {
                                format!(" (and {} more failed cases)", failures.len() - 1)
                            } else {
                                String::new()
                            }
                        ),
                        (Some(_), None) => "every case passed".into(),
                    };
                    json!({
                        "name": run.stage.function,
                        "points": passed,
                        "max_points": of,
                        "message": message,
                        "output": failures.join("\n"),
                    })
                })
                .collect();
            json!({
                "gradable": true,
                "score": score,
                "message": format!("{} of {max} cases passed", outcome.score()),
                "output": notes.join("\n"),
                "tests": tests,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(stage: usize, passed: &[bool], hidden: usize) -> StageRun {
        let tests: Vec<Value> = passed
            .iter()
            .enumerate()
            .map(|(i, ok)| {
                json!({"name": format!("c{i}"), "score": if *ok {1.0} else {0.0}, "max_score": 1.0,
                       "status": if *ok {"passed"} else {"failed"},
                       "visibility": if i < hidden {"after_published"} else {"visible"}})
            })
            .collect();
        let cases: Vec<Value> = passed
            .iter()
            .enumerate()
            .map(|(i, ok)| json!({"name": format!("c{i}"), "passed": ok, "first_warning": "wrong"}))
            .collect();
        StageRun {
            stage: STAGES[stage],
            cases: passed.len(),
            budget: 10.0,
            code: Some(if passed.iter().all(|p| *p) { 0 } else { 1 }),
            seconds: 1.0,
            report: Some(
                json!({"cases": cases, "plan": {"timeout": 1.0, "runs": 5, "workers": 1}}),
            ),
            results: Some(json!({"tests": tests})),
            error: String::new(),
        }
    }

    fn graded() -> Outcome {
        let mut stopped = run(3, &[false, false], 0);
        stopped.code = None;
        stopped.results = None;
        stopped.report = None;
        Outcome::Graded {
            stages: vec![
                run(0, &[true, true, true], 1),
                run(1, &[true, false], 0),
                stopped,
            ],
            notes: vec![],
            bonus: false,
        }
    }

    #[test]
    fn points_per_function_follow_the_cases_and_a_stopped_stage_scores_none() {
        let g = graded();
        assert_eq!(g.per_function(), [(3, 3), (1, 2), (0, 0), (0, 2)]);
        let gs = gradescope(&g);
        assert_eq!(gs["score"], 4.0);
        let max: f64 = gs["tests"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t["max_score"].as_f64().unwrap())
            .sum();
        assert_eq!(max, 7.0);
        let out = gs["output"].as_str().unwrap();
        assert!(out.contains("flip_edge: 2/2 visible cases passed"), "{out}");
        assert!(
            out.contains("loop_subdivide: stopped (time budget)"),
            "{out}"
        );
        assert!(out.contains("1 hidden cases"), "{out}");
    }

    /// The grader's JSON report of a subdivision stage, `scaling` as the
    /// grader serializes it (its own type, not a copy of its field names).
    fn subdivision(passed: &[bool], scaling: Option<grader::judge::scaling::Scaling>) -> Outcome {
        let mut sub = run(3, passed, 0);
        if let Some(s) = scaling {
            sub.report.as_mut().unwrap()["scaling"] = serde_json::to_value(s).unwrap();
        }
        Outcome::Graded {
            stages: vec![run(0, &[true], 0), sub],
            notes: vec![],
            bonus: false,
        }
    }

    fn timed(seconds: [f64; 2], timed_out: bool) -> grader::judge::scaling::Scaling {
        grader::judge::scaling::Scaling {
            faces: [80, 1280],
            seconds,
            ratio: seconds[1] / seconds[0],
            exponent: 1.0,
            timed_out,
            quadratic: timed_out,
            runs: 4,
        }
    }

    #[test]
    fn the_leaderboard_has_the_larger_icospheres_time_when_it_was_measured() {
        let outcome = subdivision(&[true, true], Some(timed([0.0011, 0.0123456], false)));
        let mut gs = gradescope(&outcome);
        add_gradescope_leaderboard(&mut gs, &outcome);
        let board = gs["leaderboard"].as_array().expect("a leaderboard");
        assert_eq!(board.len(), 1, "{gs}");
        assert_eq!(
            board[0]["name"],
            "loop_subdivide (ms, icosphere 1280 faces)"
        );
        assert_eq!(board[0]["order"], "asc", "lowest time first");
        let value = board[0]["value"].as_f64().unwrap();
        assert!((value - 12.346).abs() < 1e-9, "{value}");
        assert!(!gs["output"].as_str().unwrap().contains("leaderboard"));
        // The score is the cases' alone.
        assert_eq!(gs["score"], 3.0);
    }

    #[test]
    fn no_leaderboard_entry_without_a_time_and_the_output_says_why() {
        let cases: [(Outcome, &str); 3] = [
            (
                subdivision(&[true, false], None),
                "does not pass every case",
            ),
            (
                subdivision(&[true, true], None),
                "could not be timed within the time left",
            ),
            (
                subdivision(&[true, true], Some(timed([0.002, 2.0], true))),
                "1280 faces did not finish within 2.00 s",
            ),
        ];
        for (outcome, why) in cases {
            let mut gs = gradescope(&outcome);
            add_gradescope_leaderboard(&mut gs, &outcome);
            assert!(gs.get("leaderboard").is_none(), "{gs}");
            let out = gs["output"].as_str().unwrap();
            assert!(
                out.contains("leaderboard: no time (") && out.contains(why),
                "{out}"
            );
        }
        // Not graded at all: no entry, and the output is the compiler's.
        let broken = Outcome::NotGraded {
            message: "does not compile".into(),
            counts: [1, 1, 1, 1],
        };
        let mut gs = gradescope(&broken);
        add_gradescope_leaderboard(&mut gs, &broken);
        assert!(gs.get("leaderboard").is_none());
        assert_eq!(gs["output"], "does not compile");
        // A stopped stage (no report) is not graded either.
        let mut stopped = run(3, &[true], 0);
        stopped.report = None;
        stopped.results = None;
        let outcome = Outcome::Graded {
            stages: vec![stopped],
            notes: vec![],
            bonus: false,
        };
        assert_eq!(subdivision_time(&outcome), Err(Untimed::NotGraded));
    }

    #[test]
    fn classroom50_has_its_schema_and_integer_points_per_function() {
        let ids = Classroom50 {
            classroom: "c".into(),
            assignment: "a".into(),
            submission: "submit/x".into(),
            commit: "u".into(),
            ..Default::default()
        };
        let r = classroom50(&graded(), &ids);
        assert_eq!(r["schema"], "classroom50/result/v1");
        assert_eq!(
            (r["score"].as_u64(), r["max-score"].as_u64()),
            (Some(4), Some(7))
        );
        assert_eq!(r["review"], "u");
        let names: Vec<&str> = r["tests"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t["test-name"].as_str().unwrap())
            .collect();
        assert_eq!(names, ["flip_edge", "split_edge", "loop_subdivide"]);
        let zero = classroom50(
            &Outcome::NotGraded {
                message: "does not compile".into(),
                counts: [3, 2, 1, 2],
            },
            &ids,
        );
        assert_eq!(
            (zero["score"].as_u64(), zero["max-score"].as_u64()),
            (Some(0), Some(8))
        );
        assert_eq!(zero["tests"][0]["message"], "does not compile");
    }

    #[test]
    fn prairielearn_scores_a_fraction_and_refuses_what_does_not_compile() {
        let r = prairielearn(&graded());
        assert_eq!(r["gradable"], true);
        assert!((r["score"].as_f64().unwrap() - 4.0 / 7.0).abs() < 1e-12);
        assert_eq!(r["tests"][1]["message"], "c1: wrong");
        assert_eq!(
            (
                r["tests"][1]["points"].as_u64(),
                r["tests"][1]["max_points"].as_u64()
            ),
            (Some(1), Some(2))
        );
        assert!(r["tests"][2]["message"]
            .as_str()
            .unwrap()
            .contains("was stopped"));
        let bad = prairielearn(&Outcome::NotGraded {
            message: "error: x".into(),
            counts: [1, 1, 1, 1],
        });
        assert_eq!(
            (bad["gradable"].as_bool(), bad["score"].as_f64()),
            (Some(false), Some(0.0))
        );
        assert_eq!(bad["format_errors"][0], "error: x");
    }
}
