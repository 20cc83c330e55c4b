//! The run: every selected case graded on its labellings, side by side,
//! its report made by the judge in one call; then the scaling check, and
//! the reports written (text or JSON, Gradescope's, the HTML page).

use std::process::ExitCode;
use std::time::Duration;

use crate::cli::{fixtures_root, partial_run, use_color, Cli, Format};
use crate::isolate::{self, runner, sandbox, wire};
use crate::judge::fixture::{self, Fixture, Operation, Stage};
use crate::judge::{grade, scaling, verdict};
use crate::plan::{budget, workers, Case, Plan, MIN_TIMEOUT, SHORT_LIMIT};
use crate::report::{self, html};
#[cfg(unix)]
use crate::watch;
use crate::{text, timing};

pub(crate) fn usage_error(message: &str) -> ExitCode {
    eprintln!("grader: {message}");
    ExitCode::from(2)
}

/// What one case's run is given besides the case: the per-call limit,
/// the cut it may carry, the failed functions its function calls.
struct Given {
    timeout: Duration,
    limit_cut: Option<(f64, String)>,
    calls_failed: Vec<Stage>,
}

/// Grades one case on every labelling of its input, stopping at the first
/// that fails. `Err` when the sandbox could not be set up.
fn grade_case(
    case: &Case,
    program: &runner::ChildProgram,
    limits: &sandbox::Limits,
    given: &Given,
    protections: &mut Option<isolate::protections::Protections>,
) -> Result<verdict::CaseReport, String> {
    let timeout = given.timeout;
    use crate::isolate::end::CaseEnd;
    let f = case.fixture;
    let (seed, labellings) = (case.seed, &case.labellings);
    let budget = budget(f);
    let mut first = None;
    // The labellings of this case share a child while their calls come
    // back (see `docs/architecture.md`).
    let mut session = runner::Session::new(program, limits);
    for (i, l) in labellings.iter().enumerate() {
        let op = match (f.operation, l.edge) {
            (Operation::Flip { .. }, Some(e)) => wire::Op::Flip(e),
            (Operation::Split { .. }, Some(e)) => wire::Op::Split(e),
            (Operation::Subdivide { rounds }, _) => wire::Op::Subdivide {
                rounds: rounds as u32,
            },
            (Operation::Sequence { .. }, _) => wire::Op::Sequence,
            _ => return Err(format!("{}: the case's edge was lost", f.name)),
        };
        // Input vertices by their id in this labelling; a split's vertex
        // keeps its name past them (the child resolves it).
        let n = l.vertices.len();
        let name = |v: usize| {
            if v < n {
                l.vertices[v].0
            } else {
                v as u32
            }
        };
        let steps = f
            .steps
            .iter()
            .map(|s| wire::WireStep {
                split: s.is_split(),
                ends: s.edge().map(name),
            })
            .collect();
        let request = wire::Request {
            op,
            steps,
            budget: budget as u64,
            mesh: l.mesh.clone(),
        };
        let record = case.record && matches!(op, wire::Op::Subdivide { .. });
        // A recording adds its frames (at most its byte bound, and their
        // counts) to the result.
        let recording = if record {
            halfedge::recording::Limits::default().bytes + (1 << 20)
        } else {
            0
        };
        let max_result = budget * 64 + (1 << 20) + recording;
        let run = |session: &mut runner::Session| -> Result<runner::ChildReport, String> {
            let mut report = session
                .run(&request, record, timeout, max_result)
                .map_err(|e| format!("cannot start a grading process: {e}"))?;
            match &mut report.end {
                CaseEnd::SandboxFailed { why } => {
                    return Err(format!("the grading sandbox could not be set up: {why}"))
                }
                CaseEnd::Sequence(seq) => to_input_names(&mut seq.steps, &l.vertices),
                _ => {}
            }
            Ok(report)
        };
        let judged = |child: runner::ChildReport| {
            grade::judge_case(
                f,
                grade::CaseRun {
                    child,
                    sent: l,
                    labelling: (i, labellings.len(), seed),
                    limit_cut: given.limit_cut.clone(),
                    calls_failed: given.calls_failed.clone(),
                },
            )
        };
        let child = run(&mut session)?;
        let launched = child.sandbox;
        let mut report = judged(child);
        // A call that did not pass in a child that served an earlier one
        // is run again in a fresh child, and that run is judged: nothing
        // an earlier call left behind (a static, a thread, a leak against
        // the memory cap) decides a failure.
        if !report.passed && !session.last_was_fresh() {
            session.restart();
            report = judged(run(&mut session)?);
        }
        if protections.is_none() {
            *protections = launched;
        }
        if !report.passed {
            return Ok(report);
        }
        first.get_or_insert(report);
    }
    first.ok_or_else(|| format!("{}: no labelling ran", f.name))
}

/// The child names a sequence's input vertices by their ids in the
/// labelling sent (and split vertices past them): back to input indices,
/// the fixture's names.
fn to_input_names(steps: &mut [wire::StepRan], vertices: &[halfedge::VertexId]) {
    let mut input = vec![0; vertices.len()];
    for (i, v) in vertices.iter().enumerate() {
        input[v.index()] = i as u32;
    }
    let name = |x: &mut u32| {
        if let Some(&i) = input.get(*x as usize) {
            *x = i;
        }
    };
    for s in steps {
        match &mut s.answer {
            wire::StepAnswer::Edge {
                ends: Some([a, b]), ..
            } => {
                name(a);
                name(b);
            }
            wire::StepAnswer::Vertex { name: Some(v), .. } => name(v),
            _ => {}
        }
    }
}

/// Grades every case, two or more side by side (one per core, at most
/// four), and returns the reports in the cases' order and the launcher's
/// status. Once a function has timed out, its cases that start later get a
/// short limit: an endless loop should cost the full limit once, not once
/// per case. A case whose function calls others' ([`Stage::calls`]) is
/// graded once their cases are (they come first), so that its report
/// says whether they failed.
fn grade_all(
    cases: &[Case],
    timeout: f64,
    program: &runner::ChildProgram,
    limits: &sandbox::Limits,
) -> Result<
    (
        Vec<verdict::CaseReport>,
        Option<isolate::protections::Protections>,
    ),
    String,
> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::{Condvar, Mutex};
    let workers = workers(cases.len());
    let next = AtomicUsize::new(0);
    let timed_out: Mutex<Vec<(Stage, String)>> = Mutex::new(Vec::new());
    let protections: Mutex<Option<isolate::protections::Protections>> = Mutex::new(None);
    let results: Mutex<Vec<Option<Result<verdict::CaseReport, String>>>> =
        Mutex::new(vec![None; cases.len()]);
    let finished = Condvar::new();
    let stage_of = |j: usize| cases[j].fixture.operation.stage();
    // The failed stages among `calls`, in its order, once every case of
    // them is graded (earlier cases: taken already, so always finishing).
    let failed_calls = |calls: &[Stage]| -> Vec<Stage> {
        let mut done = results.lock().unwrap_or_else(|e| e.into_inner());
        loop {
            let pending =
                (0..cases.len()).any(|j| calls.contains(&stage_of(j)) && done[j].is_none());
            if !pending {
                break;
            }
            done = finished.wait(done).unwrap_or_else(|e| e.into_inner());
        }
        calls
            .iter()
            .copied()
            .filter(|&s| {
                (0..cases.len()).any(|j| {
                    stage_of(j) == s
                        && done[j]
                            .as_ref()
                            .is_some_and(|r| r.as_ref().is_ok_and(|r| !r.passed))
                })
            })
            .collect()
    };
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(case) = cases.get(i) else {
                    return;
                };
                let stage = case.fixture.operation.stage();
                let earlier = timed_out
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .iter()
                    .find(|(s, _)| *s == stage)
                    .map(|(_, n)| n.clone());
                let limit = match &earlier {
                    Some(_) => timeout.min(SHORT_LIMIT),
                    None => timeout,
                } * case.calls() as f64;
                let given = Given {
                    timeout: Duration::from_secs_f64(limit),
                    limit_cut: earlier.clone().map(|name| (limit, name)),
                    calls_failed: failed_calls(stage.calls()),
                };
                let mut status = None;
                let result = grade_case(case, program, limits, &given, &mut status).inspect(|r| {
                    if r.timed_out && earlier.is_none() {
                        timed_out
                            .lock()
                            .unwrap_or_else(|e| e.into_inner())
                            .push((stage, r.name.clone()));
                    }
                });
                let mut first = protections.lock().unwrap_or_else(|e| e.into_inner());
                if first.is_none() {
                    *first = status;
                }
                drop(first);
                results.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(result);
                finished.notify_all();
            });
        }
    });
    let reports = results
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .map(|r| r.unwrap_or_else(|| Err("a case was not graded".into())))
        .collect::<Result<Vec<_>, String>>()?;
    Ok((
        reports,
        protections.into_inner().unwrap_or_else(|e| e.into_inner()),
    ))
}

/// Grades per the command line, running the cases in `program`.
pub fn run(cli: &Cli, program: &runner::ChildProgram) -> ExitCode {
    let started = std::time::Instant::now();
    #[cfg(unix)]
    if cli.watch && !watch::is_inner() {
        let file = cli.watch_file.clone().unwrap_or_else(watch::default_file);
        return watch::watch(&file);
    }
    if !(cli.timeout >= MIN_TIMEOUT && cli.timeout <= 3600.0) {
        return usage_error(&format!(
            "--timeout {} is out of range: give a number of seconds from 0.1 to 3600",
            cli.timeout
        ));
    }
    text::set_rewording(cli.reword_messages);
    let root = fixtures_root(cli);
    let all = match fixture::load_all(&root) {
        Ok(all) => all,
        Err(e) => return usage_error(&format!("bad fixture: {e}: tell a TA")),
    };
    let mut cases = Vec::new();
    for f in &all {
        match f.input_mesh() {
            Ok(input) => cases.push((f, input)),
            Err(e) => {
                return usage_error(&format!(
                    "bad fixture: {}: {e}: tell a TA",
                    root.join(f.relative_path()).display()
                ))
            }
        }
    }
    cases.retain(|(f, _)| {
        cli.case.as_ref().is_none_or(|n| *n == f.name)
            && cli.stage.is_none_or(|s| s == f.operation.stage())
    });
    let cases: Vec<Case> = cases
        .into_iter()
        .map(|(f, input)| Case::new(f, input, cli))
        .collect();
    if let Some(name) = &cli.case {
        if cases.is_empty() {
            let names: Vec<&str> = all.iter().map(|f| f.name.as_str()).collect();
            let stage = if cli.stage.is_some() {
                " with the --stage given"
            } else {
                ""
            };
            return usage_error(&format!(
                "no case named {name:?}{stage}; the cases are: {}",
                names.join(", ")
            ));
        }
    }
    if cases.is_empty() {
        return usage_error(&format!("no cases found in {}", root.display()));
    }
    if cli.list && cli.format == Format::Json {
        // What scripts need to share out a time budget: the runs per case.
        let list: Vec<serde_json::Value> = cases
            .iter()
            .map(|c| {
                serde_json::json!({
                    "name": c.fixture.name,
                    "group": c.fixture.group,
                    "stage": c.fixture.operation.stage(),
                    "runs": c.runs(),
                })
            })
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&list).expect("the list serializes")
        );
        return ExitCode::SUCCESS;
    }
    if cli.list {
        for c in &cases {
            let f = c.fixture;
            println!(
                "{:<28} {:<7} {}",
                f.name,
                f.group.name(),
                f.operation.stage().function()
            );
        }
        return ExitCode::SUCCESS;
    }

    isolate::process::become_subreaper();
    let limits = sandbox::Limits {
        memory: cli.memory,
        drop_user: true,
        landlock: !cli.without_landlock,
        pid_namespace: !cli.without_pid_namespace,
    };
    if let Some(b) = cli.budget {
        if !(b > 0.0 && b <= 86_400.0) {
            return usage_error(&format!(
                "--budget {b} is out of range: give a number of seconds up to 86400"
            ));
        }
    }
    let plan = Plan::of(&cases, cli);
    let reports = match grade_all(&cases, plan.timeout, program, &limits) {
        Ok(r) => r,
        Err(e) => return usage_error(&e),
    };
    let (reports, protections): (Vec<_>, Option<isolate::protections::Protections>) = reports;
    // Quadratic code: timed once subdivision is right (a warning only).
    let asked = cli.case.is_none()
        && cli.stage.is_none_or(|s| s == Stage::Subdivide)
        && (cli.budget.is_none() || cli.time_subdivision);
    let deadline = cli.budget.map(|b| started + Duration::from_secs_f64(b));
    let scaling = scaling::wanted(&reports, asked)
        .then(|| timing::measure(program, &limits, plan.timeout, deadline))
        .flatten();
    // Naming a bonus case is asking for it to count.
    let bonus = cli.bonus || cli.case.is_some();
    let protections = report::protections::line(
        protections.as_ref(),
        isolate::process::grader_not_dumpable(),
    );
    let time_line = plan.describe(cli.timeout);
    let protections_json = protections.clone();
    let report_path = match &cli.report {
        None => None,
        Some(dir) => {
            let pairs: Vec<(&Fixture, &verdict::CaseReport)> =
                cases.iter().map(|c| c.fixture).zip(&reports).collect();
            #[cfg(unix)]
            let live = watch::is_inner();
            #[cfg(not(unix))]
            let live = false;
            match html::write_report_live(dir, &pairs, live) {
                Ok(index) => Some(index),
                Err(e) => return usage_error(&format!("cannot write the report: {e}")),
            }
        }
    };

    let output = match cli.format {
        Format::Text => report::text(
            &reports,
            &report::TextOptions {
                bonus,
                color: use_color(cli),
                protections,
                verbose: cli.verbose,
                quiet: cli.quiet,
                partial: partial_run(cli),
                report: report_path.as_ref().map(|p| p.display().to_string()),
                focus: cli.case.clone(),
                time: time_line,
                scaling: scaling.clone(),
            },
        ),
        Format::Json => report::json(&reports, bonus, &protections_json, &plan, scaling.as_ref()),
    };
    print!("{output}");
    if let Some(path) = &cli.gradescope {
        if let Err(e) = std::fs::write(path, report::gradescope(&reports, bonus)) {
            return usage_error(&format!("cannot write {}: {e}", path.display()));
        }
    }
    if report::all_passed(&reports, bonus) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
