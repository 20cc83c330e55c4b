//! The scaling check: `loop_subdivide` timed on two icospheres in the same
//! run. A quadratic answer with right results (the catalogue's
//! `quadratic`) is named with its exponent and still passes; the model
//! solution is not named; the check counts for nothing and runs only when
//! it can say something (every counted subdivision case passed, no
//! `--budget`, no single case).

mod common;
use common::grade;

/// The summary line of the check, if the run printed one.
fn scaling_line(stdout: &str) -> Option<&str> {
    stdout.lines().find(|l| {
        l.contains("loop_subdivide's time grew") || l.contains("loop_subdivide scales well")
    })
}

#[test]
fn a_quadratic_subdivision_is_named_and_still_passes() {
    let g = grade("quadratic", &["--stage", "subdivide"]);
    assert_eq!(g.code, 0, "a warning only:\n{}{}", g.stdout, g.stderr);
    let line = scaling_line(&g.stdout).unwrap_or_else(|| panic!("no scaling line:\n{}", g.stdout));
    assert!(
        line.contains("[warn] loop_subdivide's time grew ")
            && line.contains("x for 16x the faces")
            && line.contains("is there a loop over all edges (or vertices) inside a loop?")
            && line.contains("it does not count toward the grade"),
        "{line}"
    );
    // The exponent is said, and it is a quadratic's (or the larger size
    // timed out, which says "more than").
    if let Some(rest) = line.split("about n^").nth(1) {
        let exponent: f64 = rest.split(':').next().unwrap().parse().unwrap();
        assert!(exponent > 1.5, "{line}");
    } else {
        assert!(line.contains("grew more than "), "{line}");
    }
    let last = g.stdout.lines().last().unwrap_or("");
    assert!(
        last.contains("[info] --stage subdivide: all ") && last.contains(" counted cases passed"),
        "{last}"
    );
}

#[test]
fn the_model_solution_is_not_named_and_json_carries_the_figures() {
    let g = grade("reference", &["--stage", "subdivide", "--format", "json"]);
    assert_eq!(g.code, 0, "{}{}", g.stdout, g.stderr);
    let report: serde_json::Value = serde_json::from_str(&g.stdout).unwrap();
    let s = &report["scaling"];
    assert_eq!(s["quadratic"], false, "{s}");
    assert_eq!(s["faces"], serde_json::json!([80, 1280]), "{s}");
    let ratio = s["ratio"].as_f64().unwrap();
    assert!(ratio > 4.0 && ratio < 64.0, "a linear solution: {s}");
    let g = grade("reference", &["--stage", "subdivide"]);
    let line = scaling_line(&g.stdout).unwrap_or_else(|| panic!("{}", g.stdout));
    assert!(line.contains("[info] loop_subdivide scales well"), "{line}");
    assert!(!g.stdout.contains("[warn]"), "{}", g.stdout);
}

#[test]
fn the_check_runs_only_where_it_can_say_something() {
    // A wrong subdivision: fix it first, nothing timed.
    let g = grade("no-flip", &["--stage", "subdivide"]);
    assert_eq!(g.code, 1);
    assert_eq!(scaling_line(&g.stdout), None, "{}", g.stdout);
    // One case, another stage, or a budget to keep: nothing timed.
    for args in [
        &["--case", "cube-subdivide-1"][..],
        &["--stage", "flip"][..],
        &["--stage", "subdivide", "--budget", "600"][..],
    ] {
        let g = grade("quadratic", args);
        assert_eq!(g.code, 0, "{args:?}:\n{}", g.stdout);
        assert_eq!(scaling_line(&g.stdout), None, "{args:?}:\n{}", g.stdout);
    }
}

#[test]
fn time_subdivision_times_under_a_budget_within_it() {
    // Gradescope's leaderboard: asked for, the timing runs under --budget.
    let args = [
        "--stage",
        "subdivide",
        "--budget",
        "600",
        "--time-subdivision",
        "--format",
        "json",
    ];
    let g = grade("reference", &args);
    assert_eq!(g.code, 0, "{}{}", g.stdout, g.stderr);
    let report: serde_json::Value = serde_json::from_str(&g.stdout).unwrap();
    let s = &report["scaling"];
    assert_eq!(s["faces"], serde_json::json!([80, 1280]), "{report}");
    let large = s["seconds"][1].as_f64().unwrap();
    assert!(large > 0.0 && s["timed_out"] == false, "{s}");
    eprintln!("loop_subdivide on 1280 faces: {:.3} ms", large * 1000.0);
}
