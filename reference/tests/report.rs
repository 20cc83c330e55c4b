//! `--report` in a real browser: the grader writes a report for a known
//! mistake, headless Chromium lays it out, and a probe page reads the
//! rendered report (which marks are there, where, in what colour) back out
//! of the DOM. Needs Debian's `chromium` (or `CHROMIUM=/path/to/chrome`):
//! `cargo xtask test` finds or installs it; plain `cargo test` without it
//! says SKIPPED (a failure under CI).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

mod common;
use common::scratch;

/// Grades an implementation of the catalogue with `--report DIR`: the exit
/// code and standard output.
fn grade(args: &[&str], report: &Path) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_reference"))
        .arg("grade")
        .args(args)
        .arg("--report")
        .arg(report)
        .output()
        .expect("the reference binary runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        report.join("index.html").is_file(),
        "no index.html in {}; stdout:\n{stdout}\nstderr:\n{}",
        report.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.code().unwrap_or(-1), stdout)
}

/// The browser: `$CHROMIUM`, else `chromium` or `chromium-browser` on the
/// PATH.
fn chromium() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .flat_map(|dir| ["chromium", "chromium-browser"].map(|name| dir.join(name)))
        .find(|exe| exe.is_file())
}

/// Whether the browser tests can run here; if not, the skip says how to
/// get Chromium (and fails under CI or `cargo xtask test`).
fn have_chromium() -> bool {
    let found = chromium().is_some();
    if !found {
        common::skip(
            "the report tests need Chromium and none was found on the PATH: run \
             `cargo xtask test` (installs Debian's `chromium` as root), or install it \
             (`apt-get install chromium`) or set CHROMIUM=/path/to/chrome",
        );
    }
    found
}

/// Runs headless Chromium on `url` with `extra` options and returns its
/// standard output; killed after a minute.
fn browse(work: &Path, extra: &[&str], url: &str) -> String {
    let profile = work.join("chromium-profile");
    std::fs::create_dir_all(&profile).unwrap();
    let mut child = Command::new(chromium().expect("checked by have_chromium"))
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(url)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("chromium starts");
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        if child
            .try_wait()
            .expect("chromium can be waited for")
            .is_some()
        {
            break;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish within a minute on {url}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "chromium failed on {url}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A page that loads the report in a frame and writes, once it is laid
/// out, what it shows as JSON into `<pre id="probe">`: the case list, the
/// cases in page order, and per case and column every red mark with its
/// colour and place, and the orange case's edge.
const PROBE: &str = r#"<!doctype html><meta charset="utf-8">
<iframe id="f" src="index.html" style="width:1400px;height:900px"></iframe>
<pre id="probe">not run</pre>
<script>
document.getElementById('f').onload = function () {
  var out = document.getElementById('probe');
  try {
    var doc = this.contentDocument;
    var win = this.contentWindow;
    var mark = function (el, svg) {
      var r = el.getBoundingClientRect(), s = svg.getBoundingClientRect();
      var st = win.getComputedStyle(el);
      return {
        cls: el.getAttribute('class'),
        vertex: el.getAttribute('data-vertex'),
        edge: el.getAttribute('data-edge'),
        fill: st.fill, stroke: st.stroke, opacity: st.opacity,
        w: r.width, h: r.height,
        inside: r.left >= s.left - 1 && r.right <= s.right + 1 && r.top >= s.top - 1 && r.bottom <= s.bottom + 1
      };
    };
    var column = function (sec, name) {
      var cells = sec.querySelectorAll('td.' + name);
      var res = { pictures: 0, faces: 0, wrong: [], caseEdges: [] };
      cells.forEach(function (td) {
        td.querySelectorAll('svg').forEach(function (svg) {
          res.pictures += 1;
          res.faces += svg.querySelectorAll('.faces path').length;
          svg.querySelectorAll('.wrong').forEach(function (el) { res.wrong.push(mark(el, svg)); });
          svg.querySelectorAll('.case-edge, .case-vertex').forEach(function (el) { res.caseEdges.push(mark(el, svg)); });
        });
      });
      return res;
    };
    var result = {
      list: Array.prototype.map.call(doc.querySelectorAll('#cases a'), function (a) { return a.getAttribute('href'); }),
      cases: Array.prototype.map.call(doc.querySelectorAll('section.case'), function (sec) {
        return {
          id: sec.id,
          failed: sec.classList.contains('failed'),
          hints: sec.querySelectorAll('li.hint').length,
          warnColor: (function () { var w = sec.querySelector('li.warn'); return w ? win.getComputedStyle(w).color : null; })(),
          input: column(sec, 'input'),
          expected: column(sec, 'expected'),
          yours: column(sec, 'yours'),
          noMesh: sec.querySelectorAll('td.none').length
        };
      })
    };
    out.textContent = JSON.stringify(result);
  } catch (e) {
    out.textContent = 'ERROR ' + e;
  }
};
</script>
"#;

/// Loads `report/index.html` through the probe and returns what it read.
fn probe(report: &Path) -> Value {
    std::fs::write(report.join("probe.html"), PROBE).unwrap();
    let url = format!("file://{}", report.join("probe.html").display());
    let dom = browse(
        report,
        &[
            "--allow-file-access-from-files",
            "--virtual-time-budget=10000",
            "--window-size=1500,1000",
            "--dump-dom",
        ],
        &url,
    );
    let start = dom
        .find("<pre id=\"probe\">")
        .expect("the probe is in the DOM")
        + 16;
    let end = start + dom[start..].find("</pre>").expect("the probe ends");
    let text = dom[start..end]
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    assert!(
        !text.starts_with("ERROR") && text != "not run",
        "the probe could not read the report: {text}"
    );
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("probe output {text:?}: {e}"))
}

fn is_red(colour: &Value) -> bool {
    // rgb(r, g, b) with a strong red and little else.
    let s = colour.as_str().unwrap_or("");
    let n: Vec<f64> = s
        .trim_start_matches("rgba(")
        .trim_start_matches("rgb(")
        .trim_end_matches(')')
        .split(',')
        .filter_map(|x| x.trim().parse().ok())
        .collect();
    n.len() >= 3 && n[0] >= 180.0 && n[1] <= 60.0 && n[2] <= 60.0
}

#[test]
fn a_misplaced_split_vertex_is_red_in_the_browser() {
    if !have_chromium() {
        return;
    }
    let dir = scratch("report-split");
    let (code, stdout) = grade(
        &[
            "--implementation",
            "split-not-midpoint",
            "--case",
            "cube-split",
        ],
        &dir,
    );
    assert_eq!(code, 1, "the mistake fails:\n{stdout}");
    assert!(
        stdout.contains(&dir.join("index.html").display().to_string()),
        "the run says where the report is:\n{stdout}"
    );
    for file in ["input", "expected", "yours"] {
        let path = dir.join(format!("cube-split.{file}.obj"));
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        assert!(text.lines().any(|l| l.starts_with("v ")), "{path:?}");
        assert!(
            text.lines().any(|l| l.starts_with("f ")),
            "{path:?} has faces"
        );
    }
    // The student's new vertex, a third of the way, is v8 in the message.
    assert!(stdout.contains("v8 is at"), "{stdout}");

    let seen = probe(&dir);
    assert_eq!(seen["list"], serde_json::json!(["#case-cube-split"]));
    let case = &seen["cases"][0];
    assert_eq!(case["id"], "case-cube-split");
    assert_eq!(case["failed"], true);
    assert!(is_red(&case["warnColor"]), "the warning is red: {case}");
    for column in ["input", "expected", "yours"] {
        assert_eq!(case[column]["pictures"], 3, "three views of {column}");
        assert!(
            case[column]["faces"].as_u64().unwrap() >= 3 * 6,
            "{column} is drawn with its faces: {case}"
        );
    }
    // Yours: v8 drawn red, visible, inside its picture, in every view.
    let v8: Vec<&Value> = case["yours"]["wrong"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["vertex"] == "v8")
        .collect();
    assert_eq!(v8.len(), 3, "v8 is marked once per view: {case}");
    for m in &v8 {
        assert!(m["cls"].as_str().unwrap().contains("wrong-vertex"), "{m}");
        assert!(is_red(&m["fill"]), "v8 is filled red: {m}");
        assert!(
            m["w"].as_f64().unwrap() >= 4.0,
            "v8 is big enough to see: {m}"
        );
        assert_eq!(m["inside"], true, "v8 lies inside its picture: {m}");
    }
    // Expected: the midpoint nobody matched, red, named by the student's id.
    let missing: Vec<&Value> = case["expected"]["wrong"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["cls"].as_str().unwrap().contains("missing-vertex"))
        .collect();
    assert_eq!(missing.len(), 3, "{case}");
    assert!(missing
        .iter()
        .all(|m| m["vertex"] == "v8" && is_red(&m["fill"])));
    // Only the vertex is wrong: no edge is called extra or missing.
    assert!(
        !case["yours"]["wrong"]
            .as_array()
            .unwrap()
            .iter()
            .any(|m| m["cls"].as_str().unwrap().contains("extra-edge")),
        "{case}"
    );
    // The split edge is orange in the input.
    let edge = &case["input"]["caseEdges"][0];
    assert!(
        edge["stroke"]
            .as_str()
            .unwrap()
            .starts_with("rgb(239, 108, 0"),
        "{edge}"
    );

    // A picture for people: cargo test -p reference --test report, then
    // open the file named below.
    let shot = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-cube-split.png");
    let _ = std::fs::remove_file(&shot);
    browse(
        &dir,
        &[
            "--window-size=1400,1100",
            &format!("--screenshot={}", shot.display()),
        ],
        &format!("file://{}", dir.join("index.html").display()),
    );
    let png = std::fs::read(&shot).expect("chromium wrote the screenshot");
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 20_000,
        "{shot:?}"
    );
    println!("screenshot: {}", shot.display());
}

#[test]
fn failing_cases_come_first_and_the_list_links_every_case() {
    if !have_chromium() {
        return;
    }
    let dir = scratch("report-stage");
    let (code, stdout) = grade(
        &["--implementation", "split-not-midpoint", "--stage", "split"],
        &dir,
    );
    assert_eq!(code, 1, "{stdout}");
    let seen = probe(&dir);
    let cases = seen["cases"].as_array().unwrap();
    let failed: Vec<bool> = cases.iter().map(|c| c["failed"] == true).collect();
    assert!(
        failed.contains(&true) && failed.contains(&false),
        "{failed:?}"
    );
    let first_pass = failed.iter().position(|f| !f).unwrap();
    assert!(
        failed[first_pass..].iter().all(|f| !f),
        "failing cases come first: {failed:?}"
    );
    let ids: Vec<String> = cases
        .iter()
        .map(|c| format!("#{}", c["id"].as_str().unwrap()))
        .collect();
    let list: Vec<String> = seen["list"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap().to_string())
        .collect();
    assert_eq!(list, ids, "the list links every case, in page order");
    // Every failing split shows a red mark in yours; no passing one does.
    for c in cases {
        let marks = c["yours"]["wrong"].as_array().unwrap().len();
        if c["failed"] == true {
            assert!(marks > 0, "a failing split is marked: {c}");
        } else {
            assert_eq!(marks, 0, "a passing case has no red: {c}");
        }
    }
}

#[test]
fn a_passing_case_has_pictures_and_no_red() {
    if !have_chromium() {
        return;
    }
    let dir = scratch("report-pass");
    let (code, stdout) = grade(&["--case", "cube-flip-1"], &dir);
    assert_eq!(code, 0, "the reference passes:\n{stdout}");
    let seen = probe(&dir);
    let case = &seen["cases"][0];
    assert_eq!(case["failed"], false);
    assert_eq!(
        case["expected"]["pictures"], 0,
        "a pass shows input and yours"
    );
    assert!(case["yours"]["pictures"].as_u64().unwrap() >= 2, "{case}");
    assert!(case["yours"]["faces"].as_u64().unwrap() > 0, "{case}");
    for column in ["input", "yours"] {
        assert_eq!(case[column]["wrong"], serde_json::json!([]), "{case}");
    }
    // The flipped edge is orange before and after.
    assert!(!case["input"]["caseEdges"].as_array().unwrap().is_empty());
    assert!(!case["yours"]["caseEdges"].as_array().unwrap().is_empty());
}

#[test]
fn a_function_that_panics_leaves_no_mesh_and_says_so() {
    if !have_chromium() {
        return;
    }
    let dir = scratch("report-stubs");
    let (code, _) = grade(
        &["--implementation", "stubs", "--case", "cube-flip-1"],
        &dir,
    );
    assert_eq!(code, 1);
    let seen = probe(&dir);
    let case = &seen["cases"][0];
    assert_eq!(case["failed"], true);
    assert_eq!(case["noMesh"], 1, "{case}");
    assert_eq!(case["yours"]["pictures"], 0, "{case}");
    assert_eq!(case["expected"]["pictures"], 3, "{case}");
    assert!(!dir.join("cube-flip-1.yours.obj").exists());
}
