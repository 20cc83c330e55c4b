//! `--report` in a real browser: the grader writes a report for a known
//! mistake, headless Chromium lays it out, and a probe page reads the
//! rendered report (which marks are there, where, in what colour) back out
//! of the DOM. The static pictures are read with the page's script off
//! (the fallback a page without script shows); the inspector is driven
//! with it on: clicks at screen positions, keys, buttons, the slider. Needs Debian's `chromium` (or `CHROMIUM=/path/to/chrome`):
//! `cargo xtask test` finds or installs it; plain `cargo test` without it
//! says SKIPPED (a failure under CI).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use serde_json::Value;

mod common;
use common::{browse, have_chromium, scratch};

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

/// A page that loads the report in a frame and writes, once it is laid
/// out, what it shows as JSON into `<pre id="probe">`: the case list, the
/// cases in page order, and per case and column every red mark with its
/// colour and place, and the orange case's edge.
const PROBE: &str = r#"<!doctype html><meta charset="utf-8">
<iframe id="f" src="index.html" sandbox="allow-same-origin" style="width:1400px;height:900px"></iframe>
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

/// What a probe page at `url` wrote into its `<pre id="probe">`, once
/// headless Chromium (a window `height` pixels high) has laid it out.
fn probe_text(report: &Path, url: &str, height: u32) -> String {
    let window = format!("--window-size=1500,{height}");
    let dom = browse(
        report,
        &[
            "--allow-file-access-from-files",
            "--virtual-time-budget=10000",
            &window,
            "--dump-dom",
        ],
        url,
    );
    let start = dom
        .find("<pre id=\"probe\">")
        .expect("the probe is in the DOM")
        + 16;
    let end = start + dom[start..].find("</pre>").expect("the probe ends");
    dom[start..end]
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&")
}

/// Loads `report/index.html` through the probe and returns what it read.
fn probe(report: &Path) -> Value {
    std::fs::write(report.join("probe.html"), PROBE).unwrap();
    let url = format!("file://{}", report.join("probe.html").display());
    let text = probe_text(report, &url, 1000);
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

/// A page that loads the report in a frame (script on), then runs the
/// steps of the plan in its URL's fragment on one case's inspector, as a
/// student would (mouse events at screen positions, key presses, button
/// clicks, the slider), and writes what the panel said after each step
/// into `<pre id="probe">`.
const INSPECT: &str = r#"<!doctype html><meta charset="utf-8">
<iframe id="f" src="index.html" style="width:1500px;height:1300px"></iframe>
<pre id="probe">not run</pre>
<script>
document.getElementById('f').onload = function () {
  var out = document.getElementById('probe');
  try {
    var doc = this.contentDocument, win = this.contentWindow;
    var plan = JSON.parse(decodeURIComponent(location.hash.slice(1)));
    var insp = win.meshlabInspect ? win.meshlabInspect(plan.case) : null;
    if (!insp) { throw new Error('no inspector for ' + plan.case); }
    var root = insp.root;
    root.scrollIntoView();
    var panel = function () {
      var lines = {};
      root.querySelectorAll('.panel .line').forEach(function (d) {
        lines[d.querySelector('.k').textContent.trim()] = d.querySelector('.v').textContent;
      });
      var t = root.querySelector('.panel .title');
      return { title: t ? t.textContent : null, lines: lines, sel: insp.sel, status: insp.status.textContent };
    };
    var click = function (pane, kind, id) {
      var at = insp.screenOf(pane, kind, id);
      if (!at) { return { missing: kind + id }; }
      var target = doc.elementFromPoint(at.x, at.y);
      ['mousedown', 'mouseup', 'click'].forEach(function (type) {
        target.dispatchEvent(new win.MouseEvent(type, { clientX: at.x, clientY: at.y, bubbles: true, button: 0, view: win }));
      });
      var p = panel();
      p.target = target.tagName + '.' + (target.closest('.pane') || {dataset: {}}).dataset.pane;
      return p;
    };
    var res = { error: insp.data.error, steps: [] };
    plan.steps.forEach(function (s) {
      var r;
      if (s[0] === 'click') { r = click(s[1], s[2], s[3]); }
      else if (s[0] === 'clickError') { var e = insp.data.error; r = click(e.pane, e.el[0], +e.el.slice(1)); }
      else if (s[0] === 'key') { root.dispatchEvent(new win.KeyboardEvent('keydown', { key: s[1], bubbles: true })); r = panel(); }
      else if (s[0] === 'reset') { root.querySelector('button.reset').click(); insp.key('Escape'); r = panel(); r.cam = { yaw: insp.cam.yaw, pitch: insp.cam.pitch }; }
      else if (s[0] === 'turn') { insp.cam.yaw += s[1]; insp.cam.pitch = s[2]; insp.draw(); r = { cam: { yaw: insp.cam.yaw, pitch: insp.cam.pitch } }; }
      else if (s[0] === 'selectError') { root.querySelector('button.select-error').click(); r = panel(); r.cam = { yaw: insp.cam.yaw, pitch: insp.cam.pitch }; }
      else if (s[0] === 'toggle') { var b = root.querySelector('input[data-layer="' + s[1] + '"]'); b.click(); r = { checked: b.checked }; }
      else if (s[0] === 'marks') { r = { shown: insp.panes[s[1]].marksShown }; }
      else if (s[0] === 'set') { var c = root.querySelector('input[data-layer="' + s[1] + '"]'); if (c.checked !== s[2]) { c.click(); } r = { checked: c.checked }; }
      else if (s[0] === 'select') { insp.select(s[1], s[2], s[3]); r = panel(); }
      else if (s[0] === 'labels') {
        r = { sel: insp.sel, panes: {} };
        Object.keys(insp.panes).forEach(function (k) {
          if (insp.layers[k]) { r.panes[k] = { placed: insp.panes[k].labels || null, skipped: insp.panes[k].labelsSkipped }; }
        });
      }
      else if (s[0] === 'frame') {
        var sl = root.querySelector('input.frame-slider');
        sl.value = String(s[1]);
        sl.dispatchEvent(new win.Event('input', { bubbles: true }));
        var br = root.querySelector('.frame-broken');
        r = { text: root.querySelector('.frame-text').textContent, broken: br.textContent, shown: br.style.display !== 'none', max: +sl.max,
              note: (root.querySelector('.frame-note') || {}).textContent || null, vertices: insp.models.yours.nv,
              links: Array.prototype.slice.call(insp.models.yours.hr), heads: Array.prototype.slice.call(insp.models.yours.vh) };
      }
      res.steps.push(r);
    });
    var sec = root.closest('section');
    res.note = (sec.querySelector('p.relabelled') || {}).textContent || null;
    res.staticShown = !!sec.querySelector('details.static');
    out.textContent = JSON.stringify(res);
  } catch (e) {
    out.textContent = 'ERROR ' + e + ' ' + (e.stack || '');
  }
};
</script>
"#;

/// Runs `steps` (a JSON array) on case `name`'s inspector in `report`
/// through [`INSPECT`]; returns what it read, and saves a screenshot of the
/// page after the steps as `shot` (in the test's target folder).
fn inspect(report: &Path, name: &str, steps: Value, shot: &str) -> Value {
    std::fs::write(report.join("inspect.html"), INSPECT).unwrap();
    let plan = serde_json::json!({ "case": name, "steps": steps }).to_string();
    let hash: String = plan
        .bytes()
        .map(|b| {
            if b.is_ascii_alphanumeric() {
                (b as char).to_string()
            } else {
                format!("%{b:02X}")
            }
        })
        .collect();
    let url = format!("file://{}#{hash}", report.join("inspect.html").display());
    let text = probe_text(report, &url, 1300);
    assert!(
        !text.starts_with("ERROR") && text != "not run",
        "the inspector probe failed: {text}"
    );
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(shot);
    let _ = std::fs::remove_file(&path);
    browse(
        report,
        &[
            "--allow-file-access-from-files",
            "--virtual-time-budget=10000",
            "--window-size=1500,1300",
            &format!("--screenshot={}", path.display()),
        ],
        &url,
    );
    assert!(path.is_file(), "chromium wrote {path:?}");
    println!("screenshot: {}", path.display());
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("probe output {text:?}: {e}"))
}

/// The inspector's data for case `name`, read from the page (what the
/// script was given), to check the script's answers against.
fn case_data(report: &Path, name: &str) -> Value {
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    let tag = "<script type=\"application/json\" class=\"inspector-data\">";
    for chunk in html.split(tag).skip(1) {
        let json = &chunk[..chunk.find("</script>").expect("the data ends")];
        let v: Value = serde_json::from_str(json).expect("the data is JSON");
        if v["name"] == name {
            return v;
        }
    }
    panic!("no inspector data for {name}");
}

/// A halfedge's field (0 twin, 1 next, 2 vertex, 3 edge, 4 face) in a mesh
/// of the inspector's data.
fn link(mesh: &Value, h: u64, field: u64) -> u64 {
    mesh["h"][(5 * h + field) as usize]
        .as_u64()
        .unwrap_or_else(|| panic!("h{h} field {field} in {mesh}"))
}

fn sel(step: &Value) -> String {
    format!(
        "{}{}",
        step["sel"]["kind"].as_str().unwrap_or("?"),
        step["sel"]["id"]
    )
}

#[test]
fn the_inspector_walks_a_wrong_flip_by_click_and_keys() {
    if !have_chromium() {
        return;
    }
    let dir = scratch("inspect-flip");
    let (code, stdout) = grade(
        &[
            "--implementation",
            "flip-face-labels",
            "--case",
            "cube-flip-1",
        ],
        &dir,
    );
    assert_eq!(code, 1, "{stdout}");
    // The message names the halfedge whose face is wrong.
    let named: u64 = stdout
        .split("point to its face! (h")
        .nth(1)
        .and_then(|t| t.split(')').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("a halfedge is named:\n{stdout}"));
    let data = case_data(&dir, "cube-flip-1");
    let yours = &data["yours"];
    let steps = serde_json::json!([
        ["clickError"],
        ["key", "n"],
        ["key", "t"],
        ["key", "f"],
        ["key", "h"],
        ["reset"],
        ["turn", 2.0, -0.3],
        ["selectError"],
        ["toggle", "only"]
    ]);
    let seen = inspect(&dir, "cube-flip-1", steps, "inspector-flip.png");
    assert_eq!(seen["error"]["pane"], "yours", "{seen}");
    assert_eq!(seen["error"]["el"], format!("h{named}"), "{seen}");
    let s = seen["steps"].as_array().unwrap();
    // A click where the halfedge's arrow is drawn selects it.
    assert_eq!(s[0]["target"], "CANVAS.yours", "{}", s[0]);
    assert_eq!(sel(&s[0]), format!("h{named}"), "{}", s[0]);
    let lines = &s[0]["lines"];
    let next = link(yours, named, 1);
    let twin = link(yours, named, 0);
    assert_eq!(lines["next"], format!("h{next}"), "{}", s[0]);
    assert_eq!(lines["twin"], format!("h{twin}"), "{}", s[0]);
    assert_eq!(lines["face"], format!("f{}", link(yours, named, 4)));
    assert_eq!(lines["vertex"], format!("v{}", link(yours, named, 2)));
    // The handout's names: the flip moves h1 and t1 to the other face,
    // and this mistake leaves their face as it was.
    let name = lines["handout name"].as_str().unwrap_or("");
    assert!(["h1", "t1"].contains(&name), "{}", s[0]);
    // n goes to next, t to its twin, f to that one's face, h to the face's halfedge.
    assert_eq!(sel(&s[1]), format!("h{next}"), "{}", s[1]);
    let twin_of_next = link(yours, next, 0);
    assert_eq!(sel(&s[2]), format!("h{twin_of_next}"), "{}", s[2]);
    let face = link(yours, twin_of_next, 4);
    assert_eq!(sel(&s[3]), format!("f{face}"), "{}", s[3]);
    let fh = yours["fh"][face as usize].as_u64().unwrap();
    assert_eq!(sel(&s[4]), format!("h{fh}"), "{}", s[4]);
    assert_eq!(s[4]["lines"]["is_boundary"], "false", "{}", s[4]);
    // Reset clears nothing but the view; after turning away, select error
    // selects the named halfedge and turns the view back to it.
    assert!(s[5]["sel"].is_null(), "{}", s[5]);
    assert_eq!(sel(&s[7]), format!("h{named}"), "{}", s[7]);
    assert_eq!(
        s[7]["cam"], s[5]["cam"],
        "select error turns to where the view first looked (the error): {}",
        s[7]
    );
    assert_ne!(s[6]["cam"], s[5]["cam"]);
    assert_eq!(s[8]["checked"], true);
    assert_eq!(
        seen["staticShown"], false,
        "with script, the static pictures stay in their noscript"
    );
    assert!(seen["note"].is_null(), "{seen}");
}

/// `reference grade --implementation NAME --format json --bonus --report
/// DIR ARGS`: the JSON report, parsed.
fn grade_json(implementation: &str, args: &[&str], report: &Path) -> Value {
    let mut all = vec![
        "--implementation",
        implementation,
        "--format",
        "json",
        "--bonus",
    ];
    all.extend_from_slice(args);
    let (code, stdout) = grade(&all, report);
    assert!(code == 0 || code == 1, "{implementation}: exit {code}");
    serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("{implementation}: {e}\n{stdout}"))
}

/// Every case's inspector data on the page, by case name.
fn all_case_data(report: &Path) -> std::collections::BTreeMap<String, Value> {
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    let tag = "<script type=\"application/json\" class=\"inspector-data\">";
    html.split(tag)
        .skip(1)
        .map(|chunk| {
            let json = &chunk[..chunk.find("</script>").expect("the data ends")];
            let v: Value = serde_json::from_str(json).expect("the data is JSON");
            (v["name"].as_str().unwrap().to_string(), v)
        })
        .collect()
}

type Ids = std::collections::BTreeSet<u64>;
type Pairs = std::collections::BTreeSet<[u64; 2]>;

/// A list of ids (`[3, 7]`) as a set.
fn id_set(list: &Value) -> Ids {
    list.as_array()
        .map(|l| l.iter().map(|x| x.as_u64().unwrap()).collect())
        .unwrap_or_default()
}

/// Edges as unordered pairs: from the page's flat list (`[a, b, c, d]`)
/// or from the comparison's list of pairs (`[[a, b], [c, d]]`, null when
/// the edges were not compared).
fn pair_set(list: &Value) -> Pairs {
    let Some(l) = list.as_array() else {
        return Pairs::new();
    };
    let flat: Vec<u64> = l
        .iter()
        .flat_map(|x| match x.as_array() {
            Some(p) => p.iter().map(|y| y.as_u64().unwrap()).collect(),
            None => vec![x.as_u64().unwrap()],
        })
        .collect();
    flat.chunks(2)
        .map(|c| [c[0].min(c[1]), c[0].max(c[1])])
        .collect()
}

/// The page's red marks of a case against the judge's comparison in the
/// JSON report: yours red where the judge found your vertex or edge
/// extra, the expected result red where it found one missing, nothing
/// red where the judge compared nothing.
fn marks_match_comparison(case: &Value, data: &Value) -> Result<(), String> {
    let marks = &data["marks"];
    let c = &case["comparison"];
    let seen = (
        id_set(&marks["yours"]["v"]),
        id_set(&marks["expected"]["v"]),
        pair_set(&marks["yours"]["e"]),
        pair_set(&marks["expected"]["e"]),
    );
    let judged = (
        id_set(&c["extra_vertices"]),
        id_set(&c["missing_vertices"]),
        pair_set(&c["extra_edges"]),
        pair_set(&c["missing_edges"]),
    );
    if seen == judged {
        Ok(())
    } else {
        Err(format!(
            "{}: the page marks (extra v, missing v, extra e, missing e) {seen:?}, the judge found {judged:?}",
            case["name"]
        ))
    }
}

#[test]
fn the_pages_marks_are_the_judges_comparison_for_every_failing_case() {
    // Vertices wrong (one round and two), edges wrong, counts wrong, a
    // broken mesh, a failure seen only on a relabelled input.
    let mut checked = 0;
    let mut compared = 0;
    for (imp, stage) in [
        ("loop-weights", "subdivide"),
        ("no-flip", "subdivide"),
        ("flip-halves", "subdivide"),
        ("split-not-midpoint", "split"),
        ("split-not-midpoint", "sequence"),
        ("flip-face-labels", "flip"),
        ("flip-wrong-return", "flip"),
        ("split-stale-vertex", "split"),
    ] {
        let dir = scratch(&format!("marks-{imp}-{stage}"));
        let json = grade_json(imp, &["--stage", stage], &dir);
        let pages = all_case_data(&dir);
        let failed: Vec<&Value> = json["cases"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|c| c["passed"] == false)
            .collect();
        assert!(!failed.is_empty(), "{imp} fails somewhere");
        for case in failed {
            let name = case["name"].as_str().unwrap();
            let data = pages
                .get(name)
                .unwrap_or_else(|| panic!("{imp}: no inspector data for {name}"));
            if let Err(e) = marks_match_comparison(case, data) {
                panic!("{imp}: {e}");
            }
            checked += 1;
            compared += usize::from(!case["comparison"].is_null());
        }
    }
    assert!(
        compared >= 10 && checked > compared,
        "cases with and without a comparison: {compared} of {checked}"
    );
}

/// The section of case `name` in the page, as HTML text.
fn case_section(report: &Path, name: &str) -> String {
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    let start = html
        .find(&format!("data-case=\"{name}\""))
        .unwrap_or_else(|| panic!("no section for {name}"));
    let end = html[start..]
        .find("</section>")
        .map_or(html.len(), |e| start + e);
    html[start..end].to_string()
}

#[test]
fn pictures_that_disagreed_with_the_verdict_now_mark_what_it_says() {
    // Halves of old edges flipped too: the result is not a valid mesh, so
    // the judge compared nothing; the page's own matcher drew 21 extra and
    // 30 missing edges on it. Now only the element validate() names.
    let dir = scratch("disagreed-invalid");
    let json = grade_json("flip-halves", &["--case", "cube-subdivide-1"], &dir);
    let case = &json["cases"][0];
    assert_eq!(case["passed"], false);
    assert!(case["comparison"].is_null(), "{case:#}");
    let bad = &case["invalid"]["element"]["element"];
    let data = case_data(&dir, "cube-subdivide-1");
    marks_match_comparison(case, &data).unwrap();
    assert_eq!(
        data["marks"]["yours"]["named"][0],
        serde_json::json!([&bad["kind"].as_str().unwrap()[..1], bad["id"]]),
        "the element validate() names is marked first: {}",
        data["marks"]
    );
    assert_eq!(data["error"]["el"], format!("h{}", bad["id"]));
    let section = case_section(&dir, "cube-subdivide-1");
    assert!(
        section.contains("nothing is red: your mesh is not valid, so the grader compared none"),
        "the card says why nothing is red"
    );
    assert!(
        !section.contains("class=\"wrong"),
        "no red in the static pictures"
    );
    // The hint line is styled as one by its data: with every message
    // reworded, it still is.
    let dir = scratch("disagreed-reworded");
    grade_json(
        "flip-halves",
        &["--case", "cube-subdivide-1", "--reword-messages"],
        &dir,
    );
    let reworded = case_section(&dir, "cube-subdivide-1");
    let hints = |html: &str| html.matches("<li class=\"detail hint\">").count();
    assert!(hints(&section) >= 1, "a hint line");
    assert_eq!(hints(&reworded), hints(&section));

    // No flip, two rounds: the vertices are wrong, so the judge never
    // compared edges; the page's matcher paired the leftovers and drew
    // edges the verdict never named. Now the vertices only.
    let dir = scratch("disagreed-vertices");
    let json = grade_json("no-flip", &["--case", "cube-subdivide-2"], &dir);
    let case = &json["cases"][0];
    let c = &case["comparison"];
    assert!(c["missing_edges"].is_null(), "{c:#}");
    assert!(!c["missing_vertices"].as_array().unwrap().is_empty());
    let data = case_data(&dir, "cube-subdivide-2");
    marks_match_comparison(case, &data).unwrap();
    assert_eq!(data["marks"]["yours"]["e"], serde_json::json!([]));
    assert_eq!(data["marks"]["expected"]["e"], serde_json::json!([]));
    let section = case_section(&dir, "cube-subdivide-2");
    assert!(section.contains("the edges were not compared: the vertices were wrong first"));
    assert!(!section.contains("missing-edge"), "no missing edge drawn");
}

/// The grader's judgement of a split's result, as the child's report would
/// give it: the first `validate()` problem.
fn invalid_report(
    f: &grader::judge::fixture::Fixture,
    input: halfedge::Mesh,
    result: halfedge::Mesh,
) -> grader::judge::verdict::CaseReport {
    let problem = result.validate().expect_err("the result is broken");
    failed_report(
        f,
        input,
        result,
        format!("the result of split_edge is a invalid mesh: {problem}"),
        vec![grader::judge::verdict::Named::seen(problem.element)],
    )
}

/// A failed case as the grader reports it: one warning `text` about
/// `elements`, the input as sent and the student's `result`.
fn failed_report(
    f: &grader::judge::fixture::Fixture,
    input: halfedge::Mesh,
    result: halfedge::Mesh,
    text: String,
    elements: Vec<grader::judge::verdict::Named>,
) -> grader::judge::verdict::CaseReport {
    grader::judge::verdict::CaseReport {
        name: f.name.clone(),
        object: f.object.clone(),
        group: f.group,
        stage: f.operation.stage(),
        passed: false,
        entries: vec![grader::judge::verdict::Entry {
            level: grader::judge::verdict::Level::Warn,
            text,
            quote: None,
            elements,
            hint: None,
            file: file!(),
            line: line!(),
        }],
        output: grader::report::quoted::Quoted::new(String::new()),
        timed_out: false,
        input: Some(input),
        result: Some(result),
        hint: None,
        hint_id: None,
        end: grader::judge::verdict::CaseEnd::JudgeFailed,
        comparison: None,
        invalid: None,
        labelling: None,
        pointer: None,
        frames: None,
    }
}

fn lab_fixture(name: &str) -> grader::judge::fixture::Fixture {
    grader::judge::fixture::load_all(&common::lab_root().join("fixtures"))
        .expect("the fixtures load")
        .into_iter()
        .find(|f| f.name == name)
        .unwrap_or_else(|| panic!("no fixture {name}"))
}

#[test]
fn a_split_failing_on_a_relabelled_input_shows_both_numberings() {
    if !have_chromium() {
        return;
    }
    // The catalogue's stale-vertex split on the first random labelling of
    // cube-split (ids permuted): the grader would report this labelling.
    let f = lab_fixture("cube-split");
    let input = f.input.to_mesh().unwrap();
    let split = reference::catalogue::find("split-stale-vertex")
        .unwrap()
        .imp
        .split_edge;
    let fails = |l: &grader::judge::relabel::Labelling| {
        let mut m = l.mesh.clone();
        split(&mut m, l.edge.unwrap());
        let permuted = l.vertices.iter().enumerate().any(|(i, v)| v.index() != i);
        l.kind == grader::judge::relabel::Kind::Random && permuted && m.validate().is_err()
    };
    let l = (0..200)
        .flat_map(|seed| grader::judge::relabel::labellings(&input, f.edge_in(&input), seed, 2))
        .find(fails)
        .expect("a random labelling the mistake fails on");
    let mut result = l.mesh.clone();
    split(&mut result, l.edge.unwrap());
    let mut report = invalid_report(&f, l.mesh.clone(), result);
    // As the grader reports a case that failed only there: the labelling's
    // facts, and each named element in both numberings.
    report.labelling = Some(grader::judge::verdict::LabellingFacts {
        index: 1,
        of: 4,
        seed: 0,
        kind: l.kind,
        permutation: l.permutation.clone(),
    });
    report.name_in_case(&l.permutation);
    let dir = scratch("inspect-relabelled");
    grader::report::html::write_report(&dir, &[(&f, &report)]).unwrap();
    let data = case_data(&dir, "cube-split");
    let steps = serde_json::json!([["clickError"], ["selectError"], ["key", "h"]]);
    let seen = inspect(&dir, "cube-split", steps, "inspector-relabelled.png");
    let s = seen["steps"].as_array().unwrap();
    let err = seen["error"]["el"].as_str().unwrap().to_string();
    assert_eq!(sel(&s[0]), err, "{}", s[0]);
    // The named vertex, in both numberings: the case's id is where the
    // labelling put... the other way round: l.vertices[case] = sent.
    let kind = &err[..1];
    let id: usize = err[1..].parse().unwrap();
    assert_eq!(kind, "v", "validate names a vertex: {seen}");
    let case_id = l.vertices.iter().position(|v| v.index() == id).unwrap();
    assert_eq!(
        s[0]["lines"]["in the case's numbering"],
        format!("v{case_id}"),
        "{}",
        s[0]
    );
    assert_eq!(data["caseIds"]["v"][id], case_id as u64);
    // It is b, whose halfedge this mistake leaves pointing at t.
    assert_eq!(s[0]["lines"]["handout name"], "b", "{}", s[0]);
    assert_eq!(sel(&s[1]), err);
    assert_eq!(s[2]["sel"]["kind"], "h", "{}", s[2]);
    let note = seen["note"].as_str().unwrap_or("");
    assert!(note.contains("relabelled copy"), "the card says so: {seen}");
}

#[test]
fn a_failing_two_round_subdivision_is_selected_and_stepped_through() {
    if !have_chromium() {
        return;
    }
    // Graded for real: the catalogue's Loop weights on cube-subdivide-2
    // leave a valid mesh with old vertices in the wrong place.
    let dir = scratch("inspect-subdivide");
    let (code, stdout) = grade(
        &[
            "--implementation",
            "loop-weights",
            "--case",
            "cube-subdivide-2",
        ],
        &dir,
    );
    assert_eq!(code, 1, "{stdout}");
    let data = case_data(&dir, "cube-subdivide-2");
    let wrong: Vec<u64> = data["marks"]["yours"]["v"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    assert!(!wrong.is_empty(), "{data}");
    let seen = inspect(
        &dir,
        "cube-subdivide-2",
        serde_json::json!([
            ["selectError"],
            ["clickError"],
            ["marks", "yours"],
            ["toggle", "only"],
            ["marks", "yours"]
        ]),
        "inspector-subdivide.png",
    );
    let s = seen["steps"].as_array().unwrap();
    let err = seen["error"]["el"].as_str().unwrap();
    assert!(err.starts_with('v'), "{seen}");
    assert!(
        wrong.contains(&err[1..].parse().unwrap()),
        "the first wrong vertex: {seen}"
    );
    assert_eq!(sel(&s[0]), err);
    assert_eq!(sel(&s[1]), err, "clicked where it is drawn: {}", s[1]);
    assert!(s[1]["lines"]["position"].as_str().unwrap().starts_with('('));
    assert_eq!(
        s[1]["lines"]["is_new"], "false",
        "an old vertex is wrong: {}",
        s[1]
    );
    // First problem only: of every wrong vertex, those beside the selected one.
    let all = s[2]["shown"].as_u64().unwrap();
    let near = s[4]["shown"].as_u64().unwrap();
    let named = data["marks"]["yours"]["named"].as_array().unwrap().len();
    assert_eq!(all, (wrong.len() + named) as u64, "{}", s[2]);
    assert!((1..=8).contains(&near), "{near} of {all}");

    // The step-through, with frames made here: two rounds on the cube by
    // the model solution, each split recorded before it is made, the 7th
    // split of round 1 putting its vertex a third of the way.
    let f = lab_fixture("cube-subdivide-2");
    let mut mesh = f.input.to_mesh().unwrap();
    let mut frames = Vec::new();
    use reference::solution;
    solution::vertex_points(&mut mesh, solution::Weights::Warren);
    solution::edge_points(&mut mesh);
    let old: Vec<halfedge::EdgeId> = mesh.edge_ids().collect();
    for (k, &e) in old.iter().enumerate() {
        frames.push((
            format!("round 1, before split {} (edge {e})", k + 1),
            mesh.clone(),
        ));
        let n = mesh.num_vertices();
        solution::split_edges(&mut mesh, &[e], solution::split_edge);
        if k == 6 {
            let m = halfedge::VertexId::from_index(n);
            let (a, b) = (mesh[mesh[m].halfedge].vertex, m);
            let _ = (a, b);
            mesh[m].pos += halfedge::DVec3::new(0.2, 0.1, 0.0);
        }
    }
    frames.push(("round 1, after the splits".to_string(), mesh.clone()));
    let all: Vec<halfedge::EdgeId> = mesh.edge_ids().collect();
    solution::flip_old_new(&mut mesh, &all, solution::flip_edge);
    solution::move_vertices(&mut mesh);
    solution::loop_subdivide(&mut mesh);
    frames.push(("the end".to_string(), mesh.clone()));
    let count = frames.len();
    let frames = grader::report::html::Frames {
        meshes: frames,
        first_broken: Some(7),
        cut: None,
    };
    let mut report = invalid_like(&f, f.input.to_mesh().unwrap(), mesh);
    report.entries[0].text = "positions are wrong".into();
    let dir = scratch("inspect-frames");
    grader::report::html::write_report_frames(&dir, &[(&f, &report, Some(&frames))], false)
        .unwrap();
    let seen = inspect(
        &dir,
        "cube-subdivide-2",
        serde_json::json!([
            ["frame", 0],
            ["frame", 7],
            ["frame", 6],
            ["frame", count - 1]
        ]),
        "inspector-frames.png",
    );
    let s = seen["steps"].as_array().unwrap();
    assert_eq!(s[0]["max"], (count - 1) as u64);
    assert_eq!(
        s[0]["text"],
        format!("frame 1 of {count}: round 1, before split 1 (edge e0)"),
        "{}",
        s[0]
    );
    assert_eq!(s[0]["shown"], false, "{}", s[0]);
    assert_eq!(s[0]["vertices"], 8);
    assert_eq!(s[1]["broken"], "first broken frame", "{}", s[1]);
    assert_eq!(s[1]["shown"], true, "{}", s[1]);
    assert!(s[1]["text"]
        .as_str()
        .unwrap()
        .starts_with(&format!("frame 8 of {count}: round 1, before split 8")));
    assert_eq!(s[1]["vertices"], 8 + 7, "seven splits made");
    assert_eq!(s[2]["shown"], false);
    assert_eq!(s[1]["note"], "the first broken frame is 8");
    assert_eq!(s[3]["vertices"], 98, "the end state");
}

/// The halfedge the `h` key goes to from element `el` (`v3`, `e5`,
/// `f2`, or a halfedge, which stays) in a mesh of the inspector's data.
fn halfedge_of(mesh: &Value, el: &str) -> u64 {
    let id: usize = el[1..].parse().unwrap();
    let list = match &el[..1] {
        "v" => "vh",
        "e" => "eh",
        "f" => "fh",
        _ => return id as u64,
    };
    mesh[list][id].as_u64().unwrap()
}

#[test]
fn a_split_failing_only_on_a_relabelled_input_is_inspected_in_both_numberings() {
    if !have_chromium() {
        return;
    }
    // Graded for real: this mistake passes on the cone as built from its
    // faces and fails on a relabelled copy.
    let dir = scratch("inspect-relabelled-graded");
    let json = grade_json("split-stale-vertex", &["--case", "cone-split"], &dir);
    let case = &json["cases"][0];
    assert_eq!(case["passed"], false);
    assert!(
        !case["labelling"].is_null(),
        "failed only relabelled: {case:#}"
    );
    // The first element the messages name, in both numberings.
    let named = case["entries"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["level"] != "info")
        .flat_map(|e| e["elements"].as_array().unwrap())
        .next()
        .expect("a message names an element")
        .clone();
    let short = |e: &Value| format!("{}{}", &e["kind"].as_str().unwrap()[..1], e["id"]);
    let (in_case, as_sent) = (short(&named["element"]), short(&named["labelled"]));
    assert_ne!(in_case, as_sent, "the labelling renamed it: {named}");
    let data = case_data(&dir, "cone-split");
    let yours = &data["yours"];
    let seen = inspect(
        &dir,
        "cone-split",
        serde_json::json!([
            ["clickError"],
            ["key", "h"],
            ["key", "n"],
            ["key", "t"],
            ["turn", 2.5, 0.6],
            ["selectError"]
        ]),
        "inspector-relabelled-graded.png",
    );
    let s = seen["steps"].as_array().unwrap();
    // The panel shows the element as sent, and its case id.
    assert_eq!(seen["error"]["el"], as_sent.as_str(), "{seen}");
    assert_eq!(sel(&s[0]), as_sent, "{}", s[0]);
    assert_eq!(
        s[0]["lines"]["in the case's numbering"],
        in_case.as_str(),
        "{}",
        s[0]
    );
    // h, n, t walk the mesh the student's function left.
    let h = halfedge_of(yours, &as_sent);
    assert_eq!(sel(&s[1]), format!("h{h}"), "{}", s[1]);
    let next = link(yours, h, 1);
    assert_eq!(sel(&s[2]), format!("h{next}"), "{}", s[2]);
    assert_eq!(s[2]["lines"]["next"], format!("h{}", link(yours, next, 1)));
    let twin = link(yours, next, 0);
    assert_eq!(sel(&s[3]), format!("h{twin}"), "{}", s[3]);
    // Each halfedge has its case id too.
    let case_h = data["caseIds"]["h"][twin as usize].as_i64().unwrap();
    if case_h >= 0 {
        assert_eq!(
            s[3]["lines"]["in the case's numbering"],
            format!("h{case_h}"),
            "{}",
            s[3]
        );
    }
    // Select error comes back to it, and turns the view.
    assert_eq!(sel(&s[5]), as_sent);
    assert_ne!(s[5]["cam"], s[4]["cam"], "the view turned back");
    // Where the judge matched nothing (the mesh is invalid), the expected
    // result's old vertices are labelled with the input's ids as sent.
    let iid = data["expected"]["iid"].as_array().unwrap();
    let input_vertices = data["input"]["p"].as_array().unwrap().len() / 3;
    for (i, sent) in iid.iter().enumerate() {
        let sent = sent.as_i64().unwrap();
        if i < input_vertices {
            let case = data["caseIds"]["v"][sent as usize].as_i64().unwrap();
            assert_eq!(
                case, i as i64,
                "expected v{i} is the case's v{i}, sent as v{sent}"
            );
        } else {
            assert_eq!(sent, -1, "a new vertex has no input id");
        }
    }
    // The card says why the ids differ from its title's.
    let note = seen["note"].as_str().unwrap_or("");
    assert!(note.contains("relabelled copy"), "{seen}");
}

#[test]
fn a_real_two_round_subdivision_is_stepped_through_to_its_first_broken_frame() {
    if !have_chromium() {
        return;
    }
    // Graded for real with --report: the child recorded the student's
    // loop_subdivide, whose split_edge leaves b's halfedge stale.
    let dir = scratch("inspect-recorded");
    let json = grade_json("split-stale-vertex", &["--case", "cube-subdivide-2"], &dir);
    let case = &json["cases"][0];
    assert_eq!(case["passed"], false);
    let recorded = &case["frames"];
    let labels = recorded["labels"].as_array().expect("frames were recorded");
    let k = recorded["first_broken"].as_u64().expect("a broken frame") as usize;
    let data = case_data(&dir, "cube-subdivide-2");
    let list = data["frames"]["list"].as_array().unwrap();
    let count = list.len();
    assert_eq!(count, labels.len(), "every frame on the page");
    assert_eq!(data["frames"]["firstBroken"], k as u64);
    assert!(k >= 1 && k + 1 < count, "{k} of {count}");
    // The first frame is sent whole, the others as what changed.
    assert!(list[0]["mesh"].is_object() && list[1]["delta"].is_object());
    let seen = inspect(
        &dir,
        "cube-subdivide-2",
        serde_json::json!([
            ["frame", 0],
            ["frame", k],
            ["frame", k - 1],
            ["frame", count - 1]
        ]),
        "inspector-recorded.png",
    );
    let s = seen["steps"].as_array().unwrap();
    let text = |i: usize| {
        format!(
            "frame {} of {count}: {}",
            i + 1,
            labels[i].as_str().unwrap()
        )
    };
    assert_eq!(s[0]["max"], (count - 1) as u64);
    assert_eq!(s[0]["text"], text(0), "{}", s[0]);
    assert_eq!(s[0]["shown"], false);
    assert_eq!(s[0]["vertices"], 8, "the cube before the first split");
    assert_eq!(s[1]["text"], text(k), "{}", s[1]);
    assert_eq!(s[1]["shown"], true, "{}", s[1]);
    assert_eq!(s[1]["broken"], "first broken frame");
    assert_eq!(s[1]["note"], format!("the first broken frame is {}", k + 1));
    assert_eq!(s[1]["vertices"], 8 + k as u64, "one vertex per split made");
    assert_eq!(s[2]["shown"], false, "{}", s[2]);
    assert_eq!(s[2]["vertices"], 8 + k as u64 - 1);
    assert_eq!(s[3]["text"], text(count - 1));
    let end = data["yours"]["p"].as_array().unwrap().len() as u64 / 3;
    // A subdivision that passed names no broken frame, though its splits
    // were off the midpoint along the way (the moves put them right).
    let dir = scratch("inspect-recorded-passed");
    let json = grade_json("split-not-midpoint", &["--case", "cube-subdivide-2"], &dir);
    assert_eq!(json["cases"][0]["passed"], true);
    let passed = case_data(&dir, "cube-subdivide-2");
    assert!(passed["frames"]["list"].as_array().unwrap().len() > 1);
    assert!(
        passed["frames"]["firstBroken"].is_null(),
        "{}",
        passed["frames"]["firstBroken"]
    );
    assert_eq!(s[3]["vertices"], end, "the end state is the result");
    // Rebuilt from the first frame and what changed after it, the last
    // frame's links are the result's, record for record.
    assert_eq!(s[3]["links"], data["yours"]["h"]);
    assert_eq!(s[3]["heads"], data["yours"]["vh"]);
    assert_ne!(s[0]["links"], s[3]["links"]);
    assert_eq!(labels[count - 1], "after loop_subdivide");
}

/// A failed report for `result`, with one message.
fn invalid_like(
    f: &grader::judge::fixture::Fixture,
    input: halfedge::Mesh,
    result: halfedge::Mesh,
) -> grader::judge::verdict::CaseReport {
    failed_report(f, input, result, String::new(), Vec::new())
}

/// The heaviest report a student can get: every case of the lab (lab,
/// bonus and hidden) failing with a mesh of the expected size (the model
/// solution's result with one vertex moved). It must stay under 5 MB and
/// be ready to use (parsed, every inspector built) within 2 s.
#[test]
fn the_whole_lab_failing_makes_a_page_under_5_mb_that_opens_in_2_s() {
    if !have_chromium() {
        return;
    }
    use grader::judge::fixture::Operation;
    use reference::solution;
    let fixtures = grader::judge::fixture::load_all(&common::lab_root().join("fixtures")).unwrap();
    let reports: Vec<grader::judge::verdict::CaseReport> = fixtures
        .iter()
        .map(|f| {
            let input = f.input.to_mesh().unwrap();
            let mut mesh = input.clone();
            match f.operation {
                Operation::Flip { .. } => {
                    let _ = solution::flip_edge(&mut mesh, f.edge_in(&input).unwrap());
                }
                Operation::Split { .. } => {
                    let _ = solution::split_edge(&mut mesh, f.edge_in(&input).unwrap());
                }
                // The box of quads is refused: its input is the answer.
                Operation::Subdivide { rounds } if input.is_triangle_mesh() => {
                    for _ in 0..rounds {
                        solution::loop_subdivide(&mut mesh);
                    }
                }
                Operation::Subdivide { .. } | Operation::Sequence { .. } => {}
            }
            let v = halfedge::VertexId::from_index(0);
            mesh[v].pos += halfedge::DVec3::new(0.3, 0.2, 0.1);
            let mut r = invalid_like(f, input, mesh);
            r.entries[0].text = "your v0 is in the wrong place".into();
            r
        })
        .collect();
    let pairs: Vec<(
        &grader::judge::fixture::Fixture,
        &grader::judge::verdict::CaseReport,
    )> = fixtures.iter().zip(&reports).collect();
    let dir = scratch("report-whole-lab");
    let index = grader::report::html::write_report(&dir, &pairs).unwrap();
    let bytes = std::fs::metadata(&index).unwrap().len();
    let start = Instant::now();
    let dom = browse(
        &dir,
        &["--window-size=1500,1000", "--dump-dom"],
        &format!("file://{}", index.display()),
    );
    let wall = start.elapsed();
    let ready: f64 = dom
        .split("data-inspector-ready=\"")
        .nth(1)
        .and_then(|t| t.split('"').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("the inspectors were built: {}", &dom[..dom.len().min(500)]));
    let failed = dom.matches("class=\"inspector-failed\"").count();
    println!(
        "whole lab: {} cases, {bytes} bytes, ready {ready} ms after navigation, chromium run {:.2} s",
        fixtures.len(),
        wall.as_secs_f64()
    );
    assert_eq!(failed, 0, "every inspector was built");
    assert!(bytes < 5_000_000, "{bytes} bytes");
    assert!(ready < 2000.0, "ready after {ready} ms");
}

/// The page of a whole graded run, as a student gets it: every case of
/// the lab and the bonus, the failing ones with the judge's comparison
/// and, for subdivision, the frames the child recorded. The stubs fail
/// everything with no mesh; split-stale-vertex fails every split and
/// every subdivision with a mesh and a step-through (the heaviest page of
/// the catalogue's usual mistakes: 4.6 MB when measured).
#[test]
fn whole_graded_runs_make_pages_under_5_mb_that_open_in_2_s() {
    if !have_chromium() {
        return;
    }
    for imp in ["stubs", "split-stale-vertex"] {
        let dir = scratch(&format!("whole-{imp}"));
        let json = grade_json(imp, &[], &dir);
        let failed = json["cases"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|c| c["passed"] == false)
            .count();
        assert!(failed >= 40, "{imp}: {failed} failed");
        let index = dir.join("index.html");
        let bytes = std::fs::metadata(&index).unwrap().len();
        let dom = browse(
            &dir,
            &["--window-size=1500,1000", "--dump-dom"],
            &format!("file://{}", index.display()),
        );
        let ready: f64 = dom
            .split("data-inspector-ready=\"")
            .nth(1)
            .and_then(|t| t.split('"').next())
            .and_then(|t| t.parse().ok())
            .unwrap_or_else(|| panic!("{imp}: the inspectors were built"));
        println!("{imp}: {failed} cases failed, {bytes} bytes, ready {ready} ms");
        assert_eq!(dom.matches("class=\"inspector-failed\"").count(), 0);
        assert!(bytes < 5_000_000, "{imp}: {bytes} bytes");
        assert!(ready < 2000.0, "{imp}: ready after {ready} ms");
    }
}

#[test]
fn try_report_shows_the_students_own_mesh_with_the_invalid_element_selected() {
    if !have_chromium() {
        return;
    }
    let dir = scratch("try-report");
    let cube = common::lab_root().join("crates/halfedge/objects/cube.obj");
    let out = Command::new(env!("CARGO_BIN_EXE_reference"))
        .args(["try", "--implementation", "flip-stale-vertex"])
        .arg(&cube)
        .args(["--flip", "1", "2", "--report"])
        .arg(&dir)
        .arg("-o")
        .arg(dir.join("flipped.obj"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains(&format!(
            "open {} in a browser",
            dir.join("index.html").display()
        )),
        "{stdout}"
    );
    let named = stdout
        .split("does not point to that vertex! (")
        .nth(1)
        .and_then(|t| t.split(')').next())
        .unwrap_or_else(|| panic!("{stdout}"))
        .to_string();
    let data = case_data(&dir, "try");
    assert!(data["expected"].is_null() && data["yours"]["h"].is_array());
    let seen = inspect(
        &dir,
        "try",
        serde_json::json!([["key", "h"], ["key", "v"]]),
        "inspector-try.png",
    );
    assert_eq!(seen["error"]["el"], named.as_str(), "{seen}");
    // Selected on opening: h goes to its halfedge, v to that one's vertex,
    // which is not the vertex itself (that is the mistake).
    let s = seen["steps"].as_array().unwrap();
    let id: u64 = named[1..].parse().unwrap();
    let vh = data["yours"]["vh"][id as usize].as_u64().unwrap();
    assert_eq!(sel(&s[0]), format!("h{vh}"), "{}", s[0]);
    assert_eq!(s[0]["status"], format!("h: halfedge of {named} is h{vh}"));
    let v = link(&data["yours"], vh, 2);
    assert_ne!(v, id);
    assert_eq!(sel(&s[1]), format!("v{v}"), "{}", s[1]);
    // The flip's names come from the file's edge 1-2 (v0-v1).
    assert_eq!(
        data["names"]["input"][0],
        serde_json::json!([["e", 1], "e"])
    );
}

/// A page that builds every case's inspector, clicks all over each pane,
/// presses every key and button, and reports what threw.
const ROBUST: &str = r#"<!doctype html><meta charset="utf-8">
<iframe id="f" src="index.html" style="width:1500px;height:1300px"></iframe>
<pre id="probe">not run</pre>
<script>
document.getElementById('f').onload = function () {
  var out = document.getElementById('probe');
  var win = this.contentWindow, doc = this.contentDocument, errors = [], built = 0, selected = 0;
  win.addEventListener('error', function (e) { errors.push(String(e.message)); });
  try {
    doc.querySelectorAll('section.case').forEach(function (sec) {
      var insp = win.meshlabInspect(sec.getAttribute('data-case'));
      if (!insp) { errors.push('not built: ' + sec.id); return; }
      built += 1;
      insp.root.scrollIntoView();
      insp.root.querySelectorAll('input[type=checkbox]').forEach(function (b) { b.click(); b.click(); });
      insp.root.querySelector('button.select-error').click();
      insp.root.querySelectorAll('canvas').forEach(function (cv) {
        var r = cv.getBoundingClientRect();
        for (var i = 0; i < 60; i++) {
          var x = r.left + (i * 37 % 360), y = r.top + (i * 53 % 320);
          cv.dispatchEvent(new win.MouseEvent('click', { clientX: x, clientY: y, bubbles: true }));
          if (insp.sel) { selected += 1; }
          'nthvef'.split('').forEach(function (k) {
            insp.root.dispatchEvent(new win.KeyboardEvent('keydown', { key: k, bubbles: true }));
          });
        }
        cv.dispatchEvent(new win.WheelEvent('wheel', { deltaY: 300, bubbles: true, cancelable: true }));
      });
      insp.root.querySelector('button.reset').click();
    });
  } catch (e) { errors.push('threw: ' + e + ' ' + (e.stack || '')); }
  out.textContent = JSON.stringify({ built: built, selected: selected, errors: errors,
    failed: doc.querySelectorAll('.inspector-failed').length });
};
</script>
"#;

/// A mesh whose every link may be anything: ids in range or past it,
/// positions finite, NaN, infinite or astronomically far.
fn garbage(seed: u64, n: usize) -> halfedge::Mesh {
    use grader::judge::relabel::Rng;
    use halfedge::*;
    let rng = &mut Rng::new(seed);
    let id = |rng: &mut Rng, len: usize| -> u32 {
        match rng.below(8) {
            0 => u32::MAX,
            1 => (len + rng.below(5)) as u32,
            _ => rng.below(len.max(1)) as u32,
        }
    };
    let coord = |rng: &mut Rng| match rng.below(12) {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => -1e300,
        3 => 1e9,
        _ => rng.below(2001) as f64 / 1000.0 - 1.0,
    };
    let (nv, ne, nf, nh) = (n, n + 2, n / 2 + 1, 2 * n + 4);
    let vertices = (0..nv)
        .map(|_| Vertex {
            pos: DVec3::new(coord(rng), coord(rng), coord(rng)),
            new_pos: DVec3::new(coord(rng), 0.0, 0.0),
            is_new: rng.below(2) == 0,
            halfedge: HalfedgeId(id(rng, nh)),
        })
        .collect();
    let edges = (0..ne)
        .map(|_| Edge {
            halfedge: HalfedgeId(id(rng, nh)),
            new_pos: DVec3::ZERO,
            is_new: rng.below(2) == 0,
        })
        .collect();
    let faces = (0..nf)
        .map(|_| Face {
            halfedge: HalfedgeId(id(rng, nh)),
            is_boundary: rng.below(4) == 0,
        })
        .collect();
    let halfedges = (0..nh)
        .map(|_| Halfedge {
            twin: HalfedgeId(id(rng, nh)),
            next: HalfedgeId(id(rng, nh)),
            vertex: VertexId(id(rng, nv)),
            edge: EdgeId(id(rng, ne)),
            face: FaceId(id(rng, nf)),
        })
        .collect();
    Mesh::from_records(vertices, edges, faces, halfedges)
}

#[test]
fn the_inspector_survives_any_mesh() {
    if !have_chromium() {
        return;
    }
    let names = [
        "cube-split",
        "cube-flip-1",
        "cube-subdivide-1",
        "grid-split-boundary",
    ];
    let fixtures: Vec<grader::judge::fixture::Fixture> =
        grader::judge::fixture::load_all(&common::lab_root().join("fixtures"))
            .unwrap()
            .into_iter()
            .filter(|f| names.contains(&f.name.as_str()))
            .collect();
    assert_eq!(fixtures.len(), names.len());
    for round in 0..3u64 {
        let reports: Vec<grader::judge::verdict::CaseReport> = fixtures
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let mesh = garbage(
                    round * 10 + i as u64,
                    3 + (round as usize * 13 + i * 7) % 40,
                );
                let mut r = invalid_like(f, f.input.to_mesh().unwrap(), mesh);
                r.entries[0].text = "broken (e3) at v1, h999999, f2, h5 and v4294967295".into();
                r
            })
            .collect();
        let pairs: Vec<_> = fixtures.iter().zip(&reports).collect();
        let dir = scratch(&format!("inspect-garbage-{round}"));
        grader::report::html::write_report(&dir, &pairs).unwrap();
        std::fs::write(dir.join("robust.html"), ROBUST).unwrap();
        let dom = browse(
            &dir,
            &[
                "--allow-file-access-from-files",
                "--virtual-time-budget=10000",
                "--window-size=1500,1300",
                "--dump-dom",
            ],
            &format!("file://{}", dir.join("robust.html").display()),
        );
        let start = dom.find("<pre id=\"probe\">").unwrap() + 16;
        let text = &dom[start..start + dom[start..].find("</pre>").unwrap()];
        let seen: Value = serde_json::from_str(
            &text
                .replace("&amp;", "&")
                .replace("&lt;", "<")
                .replace("&gt;", ">"),
        )
        .unwrap_or_else(|e| panic!("{text}: {e}"));
        assert_eq!(
            seen["errors"],
            serde_json::json!([]),
            "round {round}: {seen}"
        );
        assert_eq!(seen["built"], names.len() as u64, "{seen}");
        assert_eq!(seen["failed"], 0, "{seen}");
        assert!(
            seen["selected"].as_u64().unwrap() > 0,
            "clicks select something: {seen}"
        );
    }
}

/// The labels a `labels` step of [`INSPECT`] read from pane `pane`,
/// checked to lie apart: no two placed rectangles overlap, and each but
/// the selection's lies inside the 360 x 320 canvas.
fn labels_apart(step: &Value, pane: &str) -> Vec<Value> {
    let placed = step["panes"][pane]["placed"]
        .as_array()
        .unwrap_or_else(|| panic!("pane {pane} exposes its labels: {step}"))
        .clone();
    let rect = |l: &Value| {
        let f = |k: &str| l[k].as_f64().unwrap_or_else(|| panic!("{k} of {l}"));
        (f("x"), f("y"), f("w"), f("h"))
    };
    let mut seen = std::collections::BTreeSet::new();
    for (i, a) in placed.iter().enumerate() {
        assert!(
            seen.insert((a["kind"].to_string(), a["id"].to_string())),
            "{pane}: {a} is labelled twice"
        );
        let (ax, ay, aw, ah) = rect(a);
        assert!(aw > 0.0 && ah > 0.0, "{a}");
        if a["rank"] != 0 {
            assert!(
                ax >= 0.0 && ay >= 0.0 && ax + aw <= 360.0 && ay + ah <= 320.0,
                "{pane}: {a} leaves the canvas"
            );
        }
        for b in &placed[i + 1..] {
            let (bx, by, bw, bh) = rect(b);
            let apart = ax >= bx + bw || bx >= ax + aw || ay >= by + bh || by >= ay + ah;
            assert!(apart, "{pane}: labels {a} and {b} overlap");
        }
    }
    placed
}

/// After a `select` step and a `labels` step: the selected element's label
/// is among those placed in its pane, placed first.
fn selection_labelled(step: &Value) {
    let sel = &step["sel"];
    let pane = sel["pane"]
        .as_str()
        .unwrap_or_else(|| panic!("a selection: {step}"));
    let placed = labels_apart(step, pane);
    let mine: Vec<&Value> = placed
        .iter()
        .filter(|l| l["kind"] == sel["kind"] && l["id"] == sel["id"])
        .collect();
    assert_eq!(
        mine.len(),
        1,
        "the selection's label is placed once: {step}"
    );
    assert_eq!(mine[0]["rank"], 0, "{}", mine[0]);
}

/// The steps that select each of `els` in `pane` in turn and read the
/// labels after each.
fn select_each(pane: &str, els: &[(String, u64)]) -> Vec<Value> {
    els.iter()
        .flat_map(|(k, id)| {
            [
                serde_json::json!(["select", pane, k, id]),
                serde_json::json!(["labels"]),
            ]
        })
        .collect()
}

/// The elements the handout names in `pane` of case data `data`.
fn named_elements(data: &Value, pane: &str) -> Vec<(String, u64)> {
    data["names"][pane]
        .as_array()
        .map(|a| {
            a.iter()
                .map(|n| {
                    (
                        n[0][0].as_str().unwrap().to_string(),
                        n[0][1].as_u64().unwrap(),
                    )
                })
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn labels_never_overlap_and_the_selection_is_always_labelled_in_small_meshes() {
    if !have_chromium() {
        return;
    }
    // A wrong flip and a split seen only on a relabelled input: small
    // meshes where the handout's names (h, t, h1, a, b, ...) crowd the
    // flipped or split edge.
    for (imp, case) in [
        ("flip-face-labels", "cube-flip-1"),
        ("split-stale-vertex", "cone-split"),
    ] {
        let dir = scratch(&format!("labels-{case}"));
        let (code, stdout) = grade(&["--implementation", imp, "--case", case], &dir);
        assert_eq!(code, 1, "{stdout}");
        let data = case_data(&dir, case);
        let named = named_elements(&data, "yours");
        assert!(named.len() >= 4, "the handout names elements: {data}");
        let mut steps = vec![
            serde_json::json!(["set", "labels", true]),
            serde_json::json!(["labels"]),
            serde_json::json!(["selectError"]),
            serde_json::json!(["labels"]),
        ];
        steps.extend(select_each("yours", &named));
        let seen = inspect(
            &dir,
            case,
            Value::Array(steps),
            &format!("labels-{case}.png"),
        );
        let s = seen["steps"].as_array().unwrap();
        for pane in s[1]["panes"].as_object().unwrap().keys() {
            let placed = labels_apart(&s[1], pane);
            assert!(!placed.is_empty(), "{case}: {pane} has labels: {}", s[1]);
        }
        // Every handout name is shown when nothing is selected... or
        // skipped only for lack of room, which the count says.
        let yours = labels_apart(&s[1], "yours");
        let shown_names = yours
            .iter()
            .filter(|l| l["text"].as_str().unwrap_or("").contains('('))
            .count();
        assert!(shown_names >= 2, "{case}: {yours:?}");
        selection_labelled(&s[3]);
        for step in s[4..].iter().skip(1).step_by(2) {
            selection_labelled(step);
            for pane in step["panes"].as_object().unwrap().keys() {
                labels_apart(step, pane);
            }
        }
    }
}

#[test]
fn labels_never_overlap_on_a_two_round_cone_with_many_errors() {
    if !have_chromium() {
        return;
    }
    let dir = scratch("labels-cone-subdivide-2");
    let (code, stdout) = grade(
        &[
            "--implementation",
            "loop-weights",
            "--case",
            "cone-subdivide-2",
        ],
        &dir,
    );
    assert_eq!(code, 1, "{stdout}");
    let data = case_data(&dir, "cone-subdivide-2");
    let wrong: Vec<(String, u64)> = data["marks"]["yours"]["v"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| ("v".to_string(), v.as_u64().unwrap()))
        .collect();
    assert!(wrong.len() >= 10, "many errors: {wrong:?}");
    let mut steps = vec![
        serde_json::json!(["labels"]),
        serde_json::json!(["set", "labels", true]),
        serde_json::json!(["labels"]),
        serde_json::json!(["selectError"]),
        serde_json::json!(["labels"]),
    ];
    steps.extend(select_each("yours", &wrong[..wrong.len().min(12)]));
    steps.push(serde_json::json!(["select", "expected", "v", 3]));
    steps.push(serde_json::json!(["labels"]));
    let seen = inspect(
        &dir,
        "cone-subdivide-2",
        Value::Array(steps),
        "labels-cone-subdivide-2.png",
    );
    let s = seen["steps"].as_array().unwrap();
    // With the labels layer on, more labels want room than the pane has:
    // some are skipped, none overlap.
    let yours = labels_apart(&s[2], "yours");
    assert!(yours.len() >= 10, "{}", s[2]);
    assert!(
        s[2]["panes"]["yours"]["skipped"].as_u64().unwrap() > 0,
        "{}",
        s[2]
    );
    for pane in s[2]["panes"].as_object().unwrap().keys() {
        labels_apart(&s[2], pane);
    }
    for step in s[3..].iter().skip(1).step_by(2) {
        selection_labelled(step);
    }
}
