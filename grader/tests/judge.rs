//! The grader's judgement on fixture data alone: an expected result
//! compared with itself passes, and each kind of perturbation gets its
//! message. No student code runs here.

use std::path::{Path, PathBuf};
use std::time::Duration;

use grader::isolate::end::CaseEnd;
use grader::isolate::end::{Counts, Finished, MeshResult, Returned, SplitIds};
use grader::isolate::runner::ChildReport;
use grader::judge::fixture::{self, Fixture, Returns};
use grader::judge::grade::judge;
use grader::judge::verdict::{CaseReport, Level};

fn fixtures_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

fn load(rel: &str) -> Fixture {
    let path = fixtures_dir().join(rel);
    Fixture::from_json(&std::fs::read_to_string(&path).unwrap(), &path).unwrap()
}

/// The input's edges as sorted pairs, each with the number of faces it
/// borders (1 on a hole's rim).
fn input_edges(f: &Fixture) -> std::collections::BTreeMap<(usize, usize), usize> {
    let mut edges = std::collections::BTreeMap::new();
    for face in &f.input.faces {
        for i in 0..face.len() {
            let (a, b) = (face[i], face[(i + 1) % face.len()]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    edges
}

/// How many holes the input has: connected runs of rim edges (the lab's
/// meshes have no two holes touching at a vertex).
fn input_holes(f: &Fixture) -> usize {
    let mut parent: Vec<usize> = (0..f.input.positions.len()).collect();
    fn find(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    let rim: Vec<(usize, usize)> = input_edges(f)
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .map(|(e, _)| e)
        .collect();
    let mut on_rim = std::collections::BTreeSet::new();
    for &(a, b) in &rim {
        on_rim.extend([a, b]);
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        parent[ra] = rb;
    }
    let roots: std::collections::BTreeSet<usize> =
        on_rim.into_iter().map(|v| find(&mut parent, v)).collect();
    roots.len()
}

/// Counts of the mesh the library builds from the input: a face per
/// polygon and per hole, two halfedges per edge.
fn input_counts(f: &Fixture) -> Counts {
    let edges = input_edges(f).len();
    Counts {
        vertices: f.input.positions.len(),
        edges,
        faces: f.input.faces.len() + input_holes(f),
        halfedges: 2 * edges,
    }
}

/// Counts of the expected result, from its own vertices and edges; faces
/// (holes included) from the Euler characteristic V - E + F, which a split
/// and a subdivision keep: an argument apart from the grader's count of
/// divided triangles and its rule per round.
fn expected_counts(f: &Fixture) -> Counts {
    let before = input_counts(f);
    let euler = before.vertices as i64 - before.edges as i64 + before.faces as i64;
    let (v, e) = (f.expected.positions.len(), f.expected.edges.len());
    Counts {
        vertices: v,
        edges: e,
        faces: (euler - v as i64 + e as i64) as usize,
        halfedges: 2 * e,
    }
}

/// What a perfect student would report for this fixture.
fn perfect(f: &Fixture) -> (Returned, Counts, MeshResult) {
    let e = &f.expected;
    let mut mesh = MeshResult {
        positions: e.positions.clone(),
        edges: e.edges.clone(),
        returned_edge_ends: None,
        returned_vertex_leads_to: None,
        split: None,
    };
    let returned = match (&e.returns, f.operation) {
        (None, _) => Returned::Unit,
        (Some(Returns::Refused), _) => Returned::Nothing,
        (Some(Returns::Edge { ends }), _) => {
            mesh.returned_edge_ends = Some(*ends);
            Returned::Edge { given: 4, got: 4 }
        }
        (Some(Returns::Vertex { position }), fixture::Operation::Split { edge }) => {
            mesh.returned_vertex_leads_to = Some(edge[1]);
            let m = e.positions.len() - 1;
            mesh.split = Some(SplitIds {
                is_new: false,
                new_pos: [0.0; 3],
                edge: 0,
                edge_ends: [m, edge[0]],
                faces_away: Vec::new(),
            });
            Returned::Vertex {
                id: e.positions.len() as u32 - 1,
                position: Some(*position),
            }
        }
        _ => unreachable!(),
    };
    // Splits and subdivision keep the Euler characteristic: faces follow.
    (returned, expected_counts(f), mesh)
}

fn finished(
    f: &Fixture,
    returned: Returned,
    after: Counts,
    invalid: Option<halfedge::Invalid>,
    mesh: Option<MeshResult>,
) -> CaseReport {
    let child = ChildReport::bare(CaseEnd::Returned(Box::new(Finished {
        before: input_counts(f),
        after,
        invalid: invalid.map(grader::isolate::end::Problem::of),
        mesh: mesh.map(Box::new),
        // A refusal that returns None is taken to have left the mesh alone.
        unchanged: returned == Returned::Nothing,
        returned,
    })));
    judge(f, &child)
}

fn lines(r: &CaseReport, level: Level) -> Vec<String> {
    r.entries
        .iter()
        .filter(|e| e.level == level)
        .map(|e| e.one_line())
        .collect()
}

/// Asserts the report failed with exactly one warning, `warning`.
#[track_caller]
fn assert_fails_with(r: &CaseReport, warning: &str) {
    let warns = lines(r, Level::Warn);
    assert!(!r.passed, "expected a failure, but the case passed");
    assert_eq!(
        warns,
        vec![warning],
        "\nexpected warning: {warning}\n     got warnings: {warns:?}"
    );
}

#[track_caller]
fn assert_detail(r: &CaseReport, needle: &str) {
    let details = lines(r, Level::Detail);
    assert!(
        details.iter().any(|d| d.contains(needle)),
        "\nexpected a detail containing: {needle}\n     got details: {details:#?}"
    );
}

#[test]
fn every_committed_fixture_compared_with_itself_passes() {
    let all = fixture::load_all(&fixtures_dir()).unwrap();
    assert!(all.len() >= 28, "the lab and bonus cases at least");
    // Subdivision of a mesh that is not all triangles must panic: judged apart.
    for f in all
        .iter()
        .filter(|f| f.expected.returns != Some(Returns::Panic))
    {
        let (returned, after, mesh) = perfect(f);
        let r = finished(f, returned, after, None, Some(mesh));
        assert!(r.passed, "{}: {:#?}", f.name, r.entries);
        let info = lines(&r, Level::Info);
        assert_eq!(
            info.first().map(|s| s.starts_with("start testing")),
            Some(true)
        );
        assert_eq!(
            info.last().map(|s| s.starts_with("end testing")),
            Some(true)
        );
    }
}

#[test]
fn subdivision_follows_the_lab_script() {
    let f = load("lab/cube-subdivide-1.json");
    let (returned, after, mesh) = perfect(&f);
    let r = finished(&f, returned, after, None, Some(mesh));
    assert_eq!(
        lines(&r, Level::Info),
        vec![
            "start testing subdivision for cube",
            "validate the mesh...",
            "passed",
            "compare all vertices...",
            "passed",
            "compare all edges...",
            "passed",
            "end testing subdivision for cube",
        ]
    );
    let two = load("lab/cube-subdivide-2.json");
    let (returned, after, mesh) = perfect(&two);
    let r = finished(&two, returned, after, None, Some(mesh));
    assert_eq!(
        lines(&r, Level::Info)[0],
        "start testing subdivision for cube (2 rounds)"
    );
}

#[test]
fn order_does_not_matter() {
    let f = load("lab/torus-subdivide-1.json");
    let (returned, after, mut mesh) = perfect(&f);
    let n = mesh.positions.len();
    // Reverse the vertex order and renumber the edges to match.
    mesh.positions.reverse();
    for e in &mut mesh.edges {
        *e = [n - 1 - e[1], n - 1 - e[0]];
    }
    mesh.edges.reverse();
    let r = finished(&f, returned, after, None, Some(mesh));
    assert!(r.passed, "{:#?}", r.entries);
}

#[test]
fn a_vertex_missing() {
    let f = load("lab/cube-subdivide-1.json");
    let (returned, after, mut mesh) = perfect(&f);
    mesh.positions.pop();
    let r = finished(&f, returned, after, None, Some(mesh));
    assert_fails_with(&r, "number of vertices is wrong: 25 (should be 26)");
    assert_detail(&r, "fewer vertices than one per old edge");
}

#[test]
fn too_many_or_no_new_vertices() {
    let f = load("lab/cube-subdivide-1.json");
    let (returned, after, mut mesh) = perfect(&f);
    mesh.positions.push([9.0, 9.0, 9.0]);
    let r = finished(&f, returned.clone(), after, None, Some(mesh));
    assert_fails_with(&r, "number of vertices is wrong: 27 (should be 26)");
    assert_detail(&r, "were edges created by split_edge split again?");

    let (_, _, mut mesh) = perfect(&f);
    mesh.positions.truncate(8);
    let r = finished(&f, returned, after, None, Some(mesh));
    assert_detail(&r, "no vertex was added");
}

#[test]
fn a_vertex_moved() {
    let f = load("lab/cube-subdivide-1.json");
    let (returned, after, mut mesh) = perfect(&f);
    mesh.positions[3][0] += 0.01;
    let moved = mesh.positions[3];
    let r = finished(&f, returned.clone(), after, None, Some(mesh));
    assert_fails_with(&r, "at least one of the vertices has incorrect position");
    assert_detail(
        &r,
        "1 of 26 expected vertices have no vertex of yours within 0.00001 of them",
    );
    assert_detail(
        &r,
        &format!(
            "your nearest vertex is v3 at ({:.6}, {:.6}, {:.6}) (0.010000 away)",
            moved[0], moved[1], moved[2]
        ),
    );

    // Within the tolerance is fine.
    let (_, _, mut mesh) = perfect(&f);
    mesh.positions[3][0] += 0.9e-5;
    assert!(finished(&f, returned, after, None, Some(mesh)).passed);
}

#[test]
fn a_known_mistake_is_named() {
    let f = load("lab/cube-subdivide-1.json");
    let mistake = f
        .expected
        .mistakes
        .iter()
        .find(|m| m.id == "old-not-moved")
        .expect("the cube records it");
    let (returned, after, mut mesh) = perfect(&f);
    mesh.positions = mistake.positions.clone().unwrap();
    let r = finished(&f, returned.clone(), after, None, Some(mesh));
    assert_fails_with(&r, "at least one of the vertices has incorrect position");
    assert_detail(&r, &format!("hint: {}", mistake.hint));

    let no_flip = f
        .expected
        .mistakes
        .iter()
        .find(|m| m.id == "no-flip")
        .unwrap();
    let (_, _, mut mesh) = perfect(&f);
    mesh.edges = no_flip.edges.clone().unwrap();
    let r = finished(&f, returned, after, None, Some(mesh));
    assert_fails_with(&r, "at least one of the edges connects incorrect vertices");
    assert_detail(&r, "hint: no edge was flipped");
}

#[test]
fn edges_wrong() {
    let f = load("lab/cube-subdivide-1.json");
    let (returned, after, mut mesh) = perfect(&f);
    mesh.edges.pop();
    let r = finished(&f, returned.clone(), after, None, Some(mesh));
    assert_fails_with(&r, "number of edges is wrong: 71 (should be 72)");

    let (_, _, mut mesh) = perfect(&f);
    let [a, b] = mesh.edges[0];
    // Re-point one edge at a vertex it should not reach.
    let c = (0..mesh.positions.len())
        .find(|&c| c != a && c != b && !mesh.edges.contains(&[a.min(c), a.max(c)]))
        .unwrap();
    mesh.edges[0] = [a.min(c), a.max(c)];
    let r = finished(&f, returned, after, None, Some(mesh));
    assert_fails_with(&r, "at least one of the edges connects incorrect vertices");
    assert_detail(&r, &format!("missing: an edge between v{a} "));
    assert_detail(&r, &format!("extra: your edge between v{} ", a.min(c)));
}

#[test]
fn an_invalid_mesh_stops_the_case() {
    let f = load("lab/cube-subdivide-1.json");
    let (returned, after, _) = perfect(&f);
    let r = finished(
        &f,
        returned,
        after,
        Some(halfedge::Invalid {
            element: halfedge::HalfedgeId(3).into(),
            check: halfedge::Check::TwinNotMutual,
            message: halfedge::Check::TwinNotMutual.message().into(),
        }),
        None,
    );
    assert_fails_with(
        &r,
        "the result of subdivision is a invalid mesh: A halfedge's twin's twin is not itself! (h3)",
    );
    assert!(!lines(&r, Level::Info).contains(&"compare all vertices...".to_string()));
}

fn faulted(f: &Fixture, end: CaseEnd) -> CaseReport {
    let mut child = ChildReport::bare(end);
    child.output = "debug print\n".into();
    judge(f, &child)
}

#[test]
fn faults() {
    let f = load("lab/cube-subdivide-1.json");
    let r = faulted(
        &f,
        CaseEnd::TimedOut {
            limit: Duration::from_secs(10),
        },
    );
    assert_fails_with(&r, "loop_subdivide did not finish within 10 s");
    assert_fails_with(
        &faulted(&f, CaseEnd::StackOverflow),
        "loop_subdivide overflowed the stack",
    );
    assert_fails_with(
        &faulted(&f, CaseEnd::Signal { signal: 11 }),
        "loop_subdivide crashed: signal 11 (SIGSEGV: invalid memory access)",
    );
    assert_fails_with(
        &faulted(&f, CaseEnd::Exited { code: Some(3) }),
        "loop_subdivide ended the program (exit status 3) before returning",
    );
    let r = faulted(
        &f,
        CaseEnd::Panicked {
            message: "not yet implemented".into(),
            location: Some("crates/meshedit/src/lib.rs:9:5".into()),
            grew_past: None,
        },
    );
    assert_fails_with(&r, "loop_subdivide panicked: not yet implemented");
    assert_detail(&r, "at crates/meshedit/src/lib.rs:9:5");
    assert_detail(&r, "still a todo!() stub");
    assert_eq!(
        r.output.raw(),
        "debug print\n",
        "the student's output is kept"
    );
    let r = faulted(&f, CaseEnd::OutOfMemory { cap: 2 << 30 });
    assert_fails_with(&r, "loop_subdivide used more than 2 GiB of memory");
    assert_detail(&r, "--memory changes the cap");
    let r = faulted(
        &f,
        CaseEnd::Garbled {
            why: "unknown frame 7".into(),
        },
    );
    assert_fails_with(
        &r,
        "loop_subdivide's result could not be read: the grader's channel was written to (unknown frame 7)",
    );
    let r = faulted(&f, CaseEnd::TooLarge { bytes: 300 << 20 });
    assert_fails_with(
        &r,
        "loop_subdivide returned a mesh far larger than any right answer (300 MiB of data)",
    );
    let r = faulted(
        &f,
        CaseEnd::StuckBeforeCall {
            limit: Duration::from_secs(20),
        },
    );
    assert_fails_with(
        &r,
        "loop_subdivide was never reached: the program was still starting after 20 s",
    );
    assert_detail(&r, "before main");
}

#[test]
fn flip_return_values_and_counts() {
    let f = load("lab/cube-flip-1.json");
    let (_, after, mesh) = perfect(&f);
    let r = finished(&f, Returned::Nothing, after, None, Some(mesh.clone()));
    assert_fails_with(
        &r,
        "flip_edge returned None for an edge between two triangles: it must flip it",
    );
    let r = finished(
        &f,
        Returned::Edge { given: 4, got: 7 },
        after,
        None,
        Some(mesh.clone()),
    );
    assert_fails_with(
        &r,
        "flip_edge returned Some(e7), but it must return the edge it was given (e4)",
    );

    let mut grown = after;
    grown.edges += 1;
    grown.halfedges += 2;
    let r = finished(
        &f,
        Returned::Edge { given: 4, got: 4 },
        grown,
        None,
        Some(mesh.clone()),
    );
    assert_fails_with(
        &r,
        "flip_edge added or removed elements: a flip only relinks",
    );
    assert_detail(&r, "after:  8 vertices, 19 edges, 12 faces, 38 halfedges");
    assert_detail(&r, "should: 8 vertices, 18 edges, 12 faces, 36 halfedges");

    let mut wrong_ends = mesh;
    wrong_ends.returned_edge_ends = Some([0, 1]);
    let r = finished(
        &f,
        Returned::Edge { given: 4, got: 4 },
        after,
        None,
        Some(wrong_ends),
    );
    assert_fails_with(
        &r,
        "the returned edge e4 does not join the two vertices that faced it",
    );
}

#[test]
fn refusing_boundary_edges() {
    let f = load("lab/grid-flip-boundary.json");
    let (_, after, mesh) = perfect(&f);
    let r = finished(
        &f,
        Returned::Edge { given: 2, got: 2 },
        after,
        None,
        Some(mesh.clone()),
    );
    assert_fails_with(
        &r,
        "flip_edge changed a boundary edge: it must return None and leave the mesh unchanged",
    );
    let mut moved = mesh;
    moved.positions[0][2] += 1.0;
    let r = finished(&f, Returned::Nothing, after, None, Some(moved));
    assert_fails_with(&r, "at least one of the vertices has incorrect position");

    let s = load("bonus/grid-split-boundary.json");
    let (_, after, mesh) = perfect(&s);
    let r = finished(&s, Returned::Nothing, after, None, Some(mesh));
    assert_fails_with(&r, "split_edge returned None for a boundary edge: it must divide the one real triangle beside it");
}

#[test]
fn split_checks() {
    let f = load("lab/cube-split.json");
    let (returned, after, mesh) = perfect(&f);
    let Returned::Vertex {
        id,
        position: Some(mid),
    } = returned
    else {
        unreachable!()
    };
    let off = [mid[0] + 0.1, mid[1], mid[2]];
    let r = finished(
        &f,
        Returned::Vertex {
            id,
            position: Some(off),
        },
        after,
        None,
        Some(mesh.clone()),
    );
    assert_fails_with(
        &r,
        &format!(
            "split vertex is not at the midpoint of the edge: v{id} is at ({:.6}, {:.6}, {:.6})",
            off[0], off[1], off[2]
        ),
    );
    assert_detail(&r, "(0.100000 away)");

    let mut fewer = after;
    fewer.faces -= 1;
    let r = finished(&f, returned.clone(), fewer, None, Some(mesh.clone()));
    assert_fails_with(&r, "split_edge added the wrong number of elements");

    let fixture::Operation::Split { edge: [a, b] } = f.operation else {
        unreachable!()
    };
    let across = (0..f.input.positions.len())
        .find(|&c| c != a && c != b)
        .unwrap();
    let mut astray = mesh.clone();
    astray.returned_vertex_leads_to = Some(across);
    let r = finished(&f, returned.clone(), after, None, Some(astray));
    assert_fails_with(
        &r,
        "the new vertex's halfedge does not run along the split edge",
    );
    assert_detail(&r, &format!("must lead to vertex {a} or {b}"));

    // The ids the contract pins down.
    let with_ids = |change: &dyn Fn(&mut SplitIds)| {
        let mut m = mesh.clone();
        change(m.split.as_mut().unwrap());
        finished(&f, returned.clone(), after, None, Some(m))
    };
    let r = with_ids(&|s| s.is_new = true);
    assert_fails_with(&r, "split_edge set is_new or new_pos on the new vertex: a split leaves them false and zero (loop_subdivide sets them after the call)");
    assert_detail(&r, &format!("mesh[v{id}].is_new is true"));
    let r = with_ids(&|s| s.new_pos = [0.0, 0.5, 0.0]);
    assert_fails_with(&r, "split_edge set is_new or new_pos on the new vertex: a split leaves them false and zero (loop_subdivide sets them after the call)");
    let r = with_ids(&|s| s.edge_ends = [id as usize, across]);
    assert_fails_with(&r, "after split_edge, edge e0 is not half of the edge that was split: it must join the new vertex to one of its ends");
    let r = with_ids(&|s| s.edge_ends = [a, b]);
    assert_fails_with(&r, "after split_edge, edge e0 is not half of the edge that was split: it must join the new vertex to one of its ends");
    let r = with_ids(&|s| s.faces_away = vec![3]);
    assert_fails_with(&r, "after split_edge, face f3 is not one of the triangles around the new vertex: each old face beside the edge must become one of them");
    let r = with_ids(&|s| s.edge_ends = [b, id as usize]);
    assert!(
        r.passed,
        "e as the other half passes too: {:?}",
        lines(&r, Level::Warn)
    );
}

/// The counts the tests feed the judge, against counts made by hand from
/// the meshes' pictures.
#[test]
fn the_tests_counts_are_the_hand_counts() {
    let c = |vertices, edges, faces, halfedges| Counts {
        vertices,
        edges,
        faces,
        halfedges,
    };
    // The cube: 8 corners, 12 sides + 6 diagonals, 12 triangles.
    let cube = load("lab/cube-split.json");
    assert_eq!(input_counts(&cube), c(8, 18, 12, 36));
    // A split adds the midpoint, the other half and two edges across, two faces.
    assert_eq!(expected_counts(&cube), c(9, 21, 14, 42));
    // The 3x3 grid: 16 vertices, 24 sides + 9 diagonals, 18 triangles and a hole.
    let grid = load("bonus/grid-split-boundary.json");
    assert_eq!(input_counts(&grid), c(16, 33, 19, 66));
    // Beside a hole only one triangle is divided: one edge across, one face.
    assert_eq!(expected_counts(&grid), c(17, 35, 20, 70));
    // The octahedron without a face: 7 triangles and a triangular hole.
    let open = load("lab/open-octahedron-flip.json");
    assert_eq!(input_counts(&open), c(6, 12, 8, 24));
    assert_eq!(expected_counts(&open), c(6, 12, 8, 24));
}

#[test]
fn fixture_files_round_trip_and_bad_ones_are_named() {
    let f = load("lab/cone-subdivide-1.json");
    let text = fixture::to_json_text(&f);
    let p = Path::new("x/cone.json");
    assert_eq!(Fixture::from_json(&text, p).unwrap(), f);

    let bad = |edit: &dyn Fn(&str) -> String| {
        Fixture::from_json(&edit(&text), p).unwrap_err().to_string()
    };
    assert!(bad(&|t| t.replacen("\"schema\": 3", "\"schema\": 2", 1))
        .starts_with("x/cone.json: schema 2, but this grader reads schema 3"));
    assert!(bad(&|t| t.replacen("\"schema\": 3,", "", 1)).contains("no \"schema\" number"));
    // The cone is about 3 units across: tolerances from 3e-12 to 3e-2.
    for absurd in ["0", "1e-20", "1e300", "0.5"] {
        let e = bad(&|t| {
            t.replacen(
                "\"tolerance\": 0.00001",
                &format!("\"tolerance\": {absurd}"),
                1,
            )
        });
        assert!(
            e.contains("is out of range: must be between"),
            "{absurd}: {e}"
        );
    }
    assert!(bad(&|t| t.replacen(
        "\"edges\": [\n      [0, 7],\n      [0, 9]",
        "\"edges\": [\n      [0, 9],\n      [0, 7]",
        1
    ))
    .contains("are not sorted and distinct"));
    assert!(bad(&|t| t.replacen("\"rounds\": 1", "\"rounds\": 0", 1))
        .contains("0 rounds tests nothing"));
    assert!(bad(&|t| t.replacen("\"object\": \"cone\",", "", 1))
        .contains("not a valid fixture: missing field `object`"));
    assert!(
        bad(&|t| t.replacen("\"edges\": [\n      [0, ", "\"edges\": [\n      [99, ", 1))
            .contains("expected edge [99,")
    );
    assert!(bad(&|t| t[..t.len() / 2].to_string()).contains("not valid JSON"));
}

#[test]
fn a_fixture_in_the_wrong_folder_is_named() {
    let dir = std::env::temp_dir().join(format!("grader-misplaced-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("bonus")).unwrap();
    let f = load("lab/cube-flip-1.json");
    std::fs::write(
        dir.join("bonus/cube-flip-1.json"),
        fixture::to_json_text(&f),
    )
    .unwrap();
    let e = fixture::load_all(&dir).unwrap_err().to_string();
    assert!(
        e.ends_with("cube-flip-1.json: says group \"lab\" but lives in bonus/"),
        "{e}"
    );
    std::fs::remove_dir_all(dir.join("bonus")).unwrap();
    std::fs::create_dir_all(dir.join("lab")).unwrap();
    std::fs::write(dir.join("lab/renamed.json"), fixture::to_json_text(&f)).unwrap();
    let e = fixture::load_all(&dir).unwrap_err().to_string();
    assert!(
        e.ends_with("renamed.json: is named \"cube-flip-1\" inside: rename one of them"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn warnings_are_red_only_with_colour_and_the_verdict_is_last() {
    let f = load("lab/cube-subdivide-1.json");
    let failed = faulted(&f, CaseEnd::StackOverflow);
    let plain = grader::report::text(std::slice::from_ref(&failed), &opts(false));
    assert!(!plain.contains('\u{1b}'), "{plain}");
    assert!(plain.trim_end().ends_with("[warn] test failed"), "{plain}");
    assert!(
        plain.contains("    your code printed:\n    | debug print\n"),
        "{plain}"
    );
    let red = grader::report::text(std::slice::from_ref(&failed), &opts(true));
    assert!(
        red.contains(" \u{1b}[31m[warn] test failed\u{1b}[0m\n"),
        "{red}"
    );
    assert!(
        red.contains(" [info] start testing subdivision for cube\n"),
        "info stays plain: {red}"
    );

    let (returned, after, mesh) = perfect(&f);
    let passed = finished(&f, returned, after, None, Some(mesh));
    let text = grader::report::text(&[passed], &opts(true));
    assert!(
        text.trim_end()
            .ends_with("[info] all tests passed, congratulations!"),
        "{text}"
    );
}

fn opts(color: bool) -> grader::report::TextOptions {
    grader::report::TextOptions {
        color,
        protections: "protections: test".into(),
        ..Default::default()
    }
}

#[test]
fn subdivision_counts_come_before_shape_in_plain_words() {
    let f = load("lab/cube-subdivide-1.json");
    let (returned, after, mesh) = perfect(&f);
    // The original lab's hand counts of its cube after one round.
    assert_eq!((after.vertices, after.edges), (26, 72));
    let mut more_edges = after;
    more_edges.edges += 1;
    more_edges.halfedges += 2;
    let r = finished(&f, returned.clone(), more_edges, None, Some(mesh.clone()));
    assert_fails_with(&r, "number of edges is wrong: 73 (should be 72)");
    assert_detail(&r, "from 8 vertices, 18 edges and 12 triangles, 1 round gives 26 vertices, 72 edges, 48 triangles");
    let mut fewer_faces = after;
    fewer_faces.faces -= 2;
    let r = finished(&f, returned.clone(), fewer_faces, None, Some(mesh.clone()));
    assert_fails_with(&r, "number of faces is wrong: 46 (should be 48)");

    // Only the new vertices (ids 8 and up) moved: the edge rule.
    let mut new_moved = mesh.clone();
    for p in &mut new_moved.positions[8..] {
        p[1] += 0.01;
    }
    let r = finished(&f, returned.clone(), after, None, Some(new_moved));
    assert_fails_with(&r, "at least one of the vertices has incorrect position");
    assert_detail(
        &r,
        "every old vertex is right; 18 of 18 new vertices are wrong: look at the edge rule",
    );
    let mut old_moved = mesh.clone();
    for p in &mut old_moved.positions[..3] {
        p[0] += 0.01;
    }
    let r = finished(&f, returned.clone(), after, None, Some(old_moved));
    assert_detail(
        &r,
        "every new vertex is right; 3 of 8 old vertices are wrong: look at the vertex rule",
    );

    // Two rounds: the old vertices are the first round's 26.
    let g = load("lab/cube-subdivide-2.json");
    let (returned2, after2, mesh2) = perfect(&g);
    let mut last_new = mesh2;
    for p in &mut last_new.positions[26..] {
        p[2] -= 0.01;
    }
    let r = finished(&g, returned2, after2, None, Some(last_new));
    assert_detail(
        &r,
        &format!(
            "every old vertex is right; {} of {} new vertices are wrong",
            after2.vertices - 26,
            after2.vertices - 26
        ),
    );
}

#[test]
fn wrong_subdivision_edges_say_which_vertices_they_join() {
    let f = load("lab/cube-subdivide-1.json");
    let (returned, after, mesh) = perfect(&f);
    // One edge between two new vertices (x, y) moved to join x and an old
    // vertex z instead: as if an old-new edge had stayed unflipped.
    let (i, &[x, _]) = mesh
        .edges
        .iter()
        .enumerate()
        .find(|(_, e)| e[0] >= 8 && e[1] >= 8)
        .expect("a new-new edge");
    let z = (0..8)
        .find(|&z| !mesh.edges.iter().any(|e| e == &[x, z] || e == &[z, x]))
        .expect("an old vertex not joined to x");
    let mut swapped = mesh.clone();
    swapped.edges[i] = [x, z];
    let r = finished(&f, returned, after, None, Some(swapped));
    assert_fails_with(&r, "at least one of the edges connects incorrect vertices");
    assert_detail(&r, "of the missing edges 1 join two new vertices; of your extra edges 1 join an old and a new vertex");
    assert_detail(
        &r,
        "new edges joining an old and a new vertex were left unflipped",
    );
}

/// A mistake's broken mesh is stored as `validate()`'s check key and read
/// back as the check: the message's words play no part (the rewording
/// test changes every one of them), and a key that names no check is a
/// fixture error that says so.
#[test]
fn a_mistakes_broken_mesh_is_a_check_key() {
    let f = load("lab/cone-subdivide-1.json");
    let broken: Vec<_> = f
        .expected
        .mistakes
        .iter()
        .filter_map(|m| m.invalid)
        .collect();
    assert!(
        !broken.is_empty(),
        "the cone records mistakes that break the mesh"
    );
    let text = fixture::to_json_text(&f);
    for check in &broken {
        assert!(text.contains(&format!("\"invalid\": \"{}\"", check.key())));
        assert!(!text.contains(check.message()), "{}", check.message());
    }
    let p = Path::new("x/cone.json");
    let bad = text.replacen(
        &format!("\"invalid\": \"{}\"", broken[0].key()),
        "\"invalid\": \"Two edges join the same pair of vertices!\"",
        1,
    );
    let e = Fixture::from_json(&bad, p).unwrap_err().to_string();
    assert!(e.contains("is not a check of validate()"), "{e}");
}
