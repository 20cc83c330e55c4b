//! `--report DIR`: what a student looks at when a case fails.
//!
//! For every case: the input, the student's result and the expected result
//! as OBJ files (MeshLab, Blender), and one self-contained offline
//! `index.html` (inline CSS, script and SVG, nothing fetched): the case
//! list at the top, failing cases first, and for each case its verdict and
//! messages beside an interactive 3D inspector of the input, the expected
//! result and the student's result, with static pictures from three angles
//! as the fallback where script or canvas is missing.
//!
//! One job per file:
//! - `faces.rs`: what can be drawn of a mesh, and the expected result's
//!   faces rebuilt from its edges;
//! - `marks.rs`: what is wrong (the comparison, the elements the messages
//!   name);
//! - `view.rs`: where to look from, and the camera that projects;
//! - `svg.rs`: the static pictures;
//! - `inspector.rs`: the pieces of the data the inspector reads (each
//!   mesh's full connectivity, the marks, the handout's names, the
//!   step-through frames);
//! - `case_data.rs`: one case's inspector data, put together from
//!   `inspector.rs`'s pieces;
//! - `card.rs`: one case's card (verdict, messages, OBJ links, what the
//!   code printed, the inspector's place, the static pictures);
//! - `obj.rs`: the OBJ files beside the page;
//! - `page.rs`: the report's page (the case list, the cards, the live
//!   reload under `--watch`) and the style and script every page inlines;
//! - `trial_page.rs`: `try --report`'s page, on the same pieces;
//! - `inspector.css` and `script/`, the inspector itself: one script,
//!   the files concatenated in the order `page.rs` lists them, inside one
//!   function scope that `model.js` opens and `start.js` closes:
//!   - `model.js`: a mesh as the script draws it (faces from the `next`
//!     loops, every id checked), and the small helpers;
//!   - `inspector.js`: one inspector per case, its layers, bar and panes;
//!   - `frames.js`: the step-through's frames and their slider;
//!   - `camera.js`: where the panes look from, and the projection;
//!   - `render.js`: a pane's picture (faces far to near, halfedges,
//!     marks, the selection);
//!   - `labels.js`: the labels, placed so that none covers another;
//!   - `pick.js`: what is under the pointer;
//!   - `controls.js`: mouse, selection and Scotty3D's keys;
//!   - `panel.js`: the panel that describes the selection;
//!   - `start.js`: each inspector built when its case comes near the
//!     screen, and the static pictures on demand.
//!
//! The student's mesh may be anything: every id is bounds-checked, every
//! walk is bounded, non-finite or far-off positions are left out or pinned
//! to the picture's border, here and in the script.

use halfedge::DVec3;

mod card;
mod case_data;
mod faces;
mod inspector;
mod marks;
mod obj;
mod page;
mod svg;
mod trial_page;
mod view;

pub use inspector::{Frames, FRAME_LIMIT};
pub use page::{write_report, write_report_frames, write_report_live, STAMP_FILE};
pub use trial_page::{write_trial_report, TrialPage};

fn pair(a: usize, b: usize) -> [usize; 2] {
    [a.min(b), a.max(b)]
}

/// A position as the grader's messages print it; huge coordinates (a
/// student's vertex can be anywhere) in exponent form.
fn fmt_p(p: DVec3) -> String {
    let n = |x: f64| {
        if x.abs() < 1e7 {
            format!("{x:.6}")
        } else {
            format!("{x:.3e}")
        }
    };
    format!("({}, {}, {})", n(p.x), n(p.y), n(p.z))
}

/// A distance, `far` past what a float can say.
fn fmt_d(d: f64) -> String {
    if d < 1e7 {
        format!("{d:.6}")
    } else if d.is_finite() {
        format!("{d:.3e}")
    } else {
        "too far to say how".to_string()
    }
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&#39;")
}

/// The sides of a polygon as unordered pairs.
fn sides(face: &[usize]) -> impl Iterator<Item = [usize; 2]> + '_ {
    (0..face.len()).map(move |i| pair(face[i], face[(i + 1) % face.len()]))
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;
    use std::path::{Path, PathBuf};

    use super::faces::Shape;
    use super::inspector;
    use super::marks::compared;
    use super::*;
    use crate::judge::fixture::{Fixture, Operation, Returns};
    use crate::judge::relabel::Rng;
    use crate::judge::verdict::Entry;
    use crate::judge::verdict::{CaseReport, Level};
    use halfedge::Mesh;
    use halfedge::{Edge, EdgeId, Face, FaceId, Halfedge, HalfedgeId, Vertex, VertexId};

    fn fixtures_root() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
    }

    fn fixture(name: &str) -> Fixture {
        crate::judge::fixture::load_all(&fixtures_root())
            .expect("the fixtures load")
            .into_iter()
            .find(|f| f.name == name)
            .unwrap_or_else(|| panic!("no fixture {name}"))
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("grader-html-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    fn failed(f: &Fixture, result: Option<Mesh>, text: &str) -> CaseReport {
        CaseReport {
            name: f.name.clone(),
            object: f.object.clone(),
            group: f.group,
            stage: f.operation.stage(),
            passed: false,
            entries: vec![Entry {
                level: Level::Warn,
                text: text.to_string(),
                quote: None,
                elements: Vec::new(),
                hint: None,
                file: file!(),
                line: line!(),
            }],
            output: crate::quoted::Quoted::new("printed <b>\n".repeat(2000)),
            timed_out: false,
            input: f.input.to_mesh().ok(),
            result,
            hint: None,
            hint_id: None,
            end: crate::judge::verdict::CaseEnd::JudgeFailed,
            comparison: None,
            invalid: None,
            labelling: None,
            pointer: None,
            frames: None,
        }
    }

    /// A mesh whose every link may be anything: ids in range or past it,
    /// positions finite, NaN, infinite or astronomically far.
    fn garbage(rng: &mut Rng, n: usize) -> Mesh {
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
                new_pos: DVec3::ZERO,
                is_new: false,
                halfedge: HalfedgeId(id(rng, nh)),
            })
            .collect();
        let edges = (0..ne)
            .map(|_| Edge {
                halfedge: HalfedgeId(id(rng, nh)),
                new_pos: DVec3::ZERO,
                is_new: false,
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
    fn a_garbage_result_is_drawn_as_far_as_it_goes_and_never_panics() {
        let mut rng = Rng::new(7);
        let cases = [
            "cube-split",
            "cube-flip-1",
            "cube-subdivide-1",
            "grid-split-boundary",
        ];
        let fixtures: Vec<Fixture> = cases.iter().map(|c| fixture(c)).collect();
        let dir = scratch("garbage");
        for round in 0..60 {
            let f = &fixtures[round % fixtures.len()];
            let size = 3 + rng.below(40);
            let mesh = garbage(&mut rng, size);
            let report = failed(
                f,
                Some(mesh),
                "broken (e3) at v1, h999999, f2 and v4294967295",
            );
            let index = write_report(&dir, &[(f, &report)]).expect("the report is written");
            let html = std::fs::read_to_string(index).unwrap();
            assert!(html.contains("<svg class=\"view\""), "pictures are drawn");
            for bad in ["NaN", " inf", "(inf", "-inf", "00000000000000000000"] {
                assert!(!html.contains(bad), "{bad} in the page");
            }
            // The inspector's data is JSON (non-finite numbers as null).
            let tag = "<script type=\"application/json\" class=\"inspector-data\">";
            let blob = html.split(tag).nth(1).expect("the inspector's data");
            let blob = &blob[..blob.find("</script>").expect("the data ends")];
            let data: serde_json::Value = serde_json::from_str(blob).expect("valid JSON");
            assert_eq!(data["name"], f.name.as_str());
            assert!(data["yours"]["h"].is_array(), "{data}");
            let yours = std::fs::read_to_string(dir.join(format!("{}.yours.obj", f.name))).unwrap();
            assert!(yours.contains("NOT a valid mesh"), "{yours}");
        }
        // Empty records, and a mesh with nothing but vertices.
        let f = &fixtures[0];
        for mesh in [Mesh::new(), garbage(&mut rng, 0)] {
            let report = failed(f, Some(mesh), "empty");
            write_report(&dir, &[(f, &report)]).expect("the report is written");
        }
    }

    #[test]
    fn a_live_report_reloads_when_rewritten_and_a_plain_one_has_no_script() {
        let f = fixture("cube-split");
        let report = failed(&f, None, "split_edge panicked");
        let dir = scratch("live");
        let plain = std::fs::read_to_string(write_report(&dir, &[(&f, &report)]).unwrap()).unwrap();
        assert!(
            !plain.contains("watch-stamp.js") && !plain.contains("location.reload()"),
            "no reloading without --watch"
        );
        assert!(!dir.join(STAMP_FILE).exists());
        let page = write_report_live(&dir, &[(&f, &report)], true).unwrap();
        let live = std::fs::read_to_string(&page).unwrap();
        assert!(
            live.contains("<script src=\"watch-stamp.js\"></script>"),
            "{live}"
        );
        assert!(live.contains("location.reload()"));
        let first = std::fs::read_to_string(dir.join(STAMP_FILE)).unwrap();
        std::thread::sleep(std::time::Duration::from_millis(2));
        write_report_live(&dir, &[(&f, &report)], true).unwrap();
        let second = std::fs::read_to_string(dir.join(STAMP_FILE)).unwrap();
        assert!(first.starts_with("window.meshlabStamp = \""), "{first}");
        assert_ne!(
            first, second,
            "each rewrite changes the stamp the page polls"
        );
    }

    #[test]
    fn what_the_student_printed_is_escaped_and_cut() {
        let f = fixture("cube-split");
        let report = failed(&f, None, "split_edge panicked: <script>");
        let dir = scratch("escape");
        let html = std::fs::read_to_string(write_report(&dir, &[(&f, &report)]).unwrap()).unwrap();
        // One script element, the inspector's; the student's text escaped.
        assert_eq!(html.matches("<script>").count(), 1);
        assert!(!html.contains("<b>") && html.contains("panicked: &lt;script&gt;"));
        assert!(html.contains("printed &lt;b&gt;") && html.contains("… (cut)"));
        assert!(html.contains("no mesh to show"));
    }

    #[test]
    fn expected_faces_are_rebuilt_for_every_fixture() {
        for f in crate::judge::fixture::load_all(&fixtures_root()).unwrap() {
            let input = Shape::from_faces(&f.input.positions, &f.input.faces);
            let shape = Shape::expected(&f);
            let mut uses: HashMap<[usize; 2], usize> = HashMap::new();
            for face in &shape.faces {
                for s in sides(face) {
                    *uses.entry(s).or_default() += 1;
                }
            }
            assert!(
                uses.values().all(|&k| k <= 2),
                "{}: an edge with three faces",
                f.name
            );
            // After random flips, a triangle of edges need not be a face:
            // a sequence's picture is drawn from edges as best it can.
            let sequence = matches!(f.operation, Operation::Sequence { .. });
            if input.is_closed() && f.expected.returns != Some(Returns::Refused) && !sequence {
                // A closed surface stays closed: every edge has its two
                // faces, wound consistently, the same way round as the input.
                assert!(shape.is_closed(), "{}: rebuilt faces do not close", f.name);
                assert_eq!(uses.len(), f.expected.edges.len(), "{}", f.name);
                let all = |s: &Shape| (0..s.faces.len()).collect::<Vec<_>>();
                let (v, _) = shape.orientation(&all(&shape));
                let (w, _) = input.orientation(&all(&input));
                assert_eq!(v > 0.0, w > 0.0, "{}: wound the other way", f.name);
            }
        }
    }

    #[test]
    fn the_judges_comparison_is_drawn_as_it_is_and_ids_past_the_mesh_are_dropped() {
        use crate::judge::verdict::Comparison;
        let f = fixture("cube-split");
        let expected = Shape::expected(&f);
        let yours = expected.clone();
        let new = f.input.positions.len();
        let n = expected.len();
        // One vertex of yours matched nothing and one expected vertex was
        // left: the one stands for the other.
        let mut matched: Vec<Option<usize>> = (0..n).map(Some).collect();
        matched[new] = None;
        let c = Comparison {
            matched: matched.clone(),
            missing_vertices: vec![new],
            extra_vertices: vec![new],
            missing_edges: None,
            extra_edges: None,
        };
        let d = compared(&c, &yours, &expected);
        assert_eq!(d.stands_for, Some((new, new)));
        assert_eq!(d.student_of[new], Some(new));
        assert_eq!(d.missing_edges, None, "not compared stays not compared");
        // Two of each: no pairing is certain, none is made.
        matched[0] = None;
        let c = Comparison {
            matched,
            missing_vertices: vec![0, new],
            extra_vertices: vec![0, new, n + 5],
            missing_edges: Some(vec![[1, 0], [0, n + 1]]),
            extra_edges: Some(vec![[2, 3], [n, 0]]),
        };
        let d = compared(&c, &yours, &expected);
        assert_eq!(d.stands_for, None);
        assert_eq!(d.student_of[0], None);
        assert_eq!(
            d.extra_vertices,
            vec![0, new],
            "v{} is past your mesh",
            n + 5
        );
        assert_eq!(d.missing_edges, Some(vec![[0, 1]]));
        assert_eq!(d.extra_edges, Some(vec![[2, 3]]));
    }

    #[test]
    fn handout_names_follow_the_tables_from_the_case_edge() {
        use halfedge::{Element, VertexId};
        let f = fixture("cube-split");
        let input = f.input.to_mesh().unwrap();
        let Operation::Split { edge } = f.operation else {
            panic!("a split")
        };
        let mut result = input.clone();
        // The old elements, on a result that made nothing (no new names).
        let (before, after) = inspector::handout_names(&input, edge, true, Some(&result));
        let get = |name: &str| {
            before
                .iter()
                .find(|(_, n)| *n == name)
                .map(|(e, _)| *e)
                .unwrap_or_else(|| panic!("no {name}"))
        };
        let h = |name: &str| match get(name) {
            Element::Halfedge(h) => h,
            other => panic!("{name} is {other}"),
        };
        let v = |name: &str| match get(name) {
            Element::Vertex(v) => v,
            other => panic!("{name} is {other}"),
        };
        assert_eq!(input[h("h")].twin, h("t"));
        assert_eq!(input[h("h")].next, h("h1"));
        assert_eq!(input[h("h1")].next, h("h2"));
        assert_eq!(input[h("t")].next, h("t1"));
        assert_eq!(input[h("t1")].next, h("t2"));
        assert_eq!(input[h("h")].vertex, v("a"));
        assert_eq!(input[h("t")].vertex, v("b"));
        assert_eq!(input[h("h2")].vertex, v("c"));
        assert_eq!(input[h("t2")].vertex, v("d"));
        let mut ends = [v("a").index(), v("b").index()];
        ends.sort_unstable();
        let mut case = edge;
        case.sort_unstable();
        assert_eq!(ends, case, "a and b are the case's edge");
        assert_eq!(before, after, "nothing new to name");
        // A vertex made, and a halfedge from it to b: m and hb.
        result.new_vertex(DVec3::ZERO);
        let m = VertexId::from_index(input.num_vertices());
        let hb = result.new_halfedge();
        let tb = result.new_halfedge();
        result[hb].vertex = m;
        result[hb].twin = tb;
        result[tb].vertex = v("b");
        result[tb].twin = hb;
        let (_, after) = inspector::handout_names(&input, edge, true, Some(&result));
        assert!(after.contains(&(Element::Vertex(m), "m")), "{after:?}");
        assert!(after.contains(&(Element::Halfedge(hb), "hb")), "{after:?}");
        assert!(after.contains(&(Element::Halfedge(tb), "tb")), "{after:?}");
    }

    #[test]
    fn a_relabelled_input_is_given_the_case_numbering() {
        let f = fixture("cube-split");
        let input = f.input.to_mesh().unwrap();
        let labellings = crate::judge::relabel::labellings(&input, f.edge_in(&input), 5, 2);
        let l = labellings.last().unwrap();
        // Sent vertex -> case vertex, from the labelling itself.
        let mut case_of = vec![None; input.num_vertices()];
        for (case, sent) in l.vertices.iter().enumerate() {
            case_of[sent.index()] = Some(case);
        }
        let [v, e, fs, h] =
            inspector::case_numbering(&l.mesh, &input, &case_of).expect("ids differ");
        let (_, _, _, sh) = l.mesh.records();
        for (i, rec) in sh.iter().enumerate() {
            let c = h[i] as usize;
            assert_eq!(
                input[halfedge::HalfedgeId(c as u32)].vertex.index() as i64,
                v[rec.vertex.index()]
            );
            assert_eq!(
                input[halfedge::HalfedgeId(c as u32)].edge.index() as i64,
                e[rec.edge.index()]
            );
            assert_eq!(
                input[halfedge::HalfedgeId(c as u32)].face.index() as i64,
                fs[rec.face.index()]
            );
        }
        assert_eq!(
            inspector::case_numbering(
                &input,
                &input,
                &(0..input.num_vertices()).map(Some).collect::<Vec<_>>()
            ),
            None
        );
    }

    #[test]
    fn frames_past_the_limits_are_cut_and_the_page_says_so() {
        let f = fixture("cube-subdivide-1");
        let mesh = f.input.to_mesh().unwrap();
        let report = failed(&f, Some(mesh.clone()), "wrong");
        let blob = |frames: &Frames| {
            let dir = scratch("frames");
            let index = write_report_frames(&dir, &[(&f, &report, Some(frames))], false).unwrap();
            let html = std::fs::read_to_string(index).unwrap();
            let tag = "<script type=\"application/json\" class=\"inspector-data\">";
            let blob = html.split(tag).nth(1).unwrap();
            let data: serde_json::Value =
                serde_json::from_str(&blob[..blob.find("</script>").unwrap()]).unwrap();
            data["frames"].clone()
        };
        let many = Frames {
            meshes: (0..FRAME_LIMIT + 50)
                .map(|k| (format!("before split {k}"), mesh.clone()))
                .collect(),
            first_broken: Some(FRAME_LIMIT + 10),
            cut: None,
        };
        let frames = blob(&many);
        assert_eq!(frames["list"].as_array().unwrap().len(), FRAME_LIMIT);
        assert_eq!(frames["list"][3]["label"], "before split 3");
        assert!(
            frames["firstBroken"].is_null(),
            "past the cut: {}",
            frames["firstBroken"]
        );
        assert_eq!(
            frames["cut"],
            format!(
                "the page shows the first {FRAME_LIMIT} of {} frames",
                FRAME_LIMIT + 50
            )
        );
        let few = Frames {
            meshes: vec![("a".into(), mesh.clone()), ("b".into(), mesh)],
            first_broken: Some(1),
            cut: Some("the recording stopped at 32 MB".into()),
        };
        let frames = blob(&few);
        assert_eq!(frames["firstBroken"], 1);
        assert_eq!(frames["cut"], "the recording stopped at 32 MB");
    }
}
