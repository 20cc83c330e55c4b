//! Properties of the reader, the builder and `validate()` on generated
//! input (proptest): valid, near-valid and garbage OBJ text, random face
//! lists, manifold meshes with their elements in random order, and meshes
//! with random links broken.
//!
//! - the reader and the builder never panic; every refusal names a line, a
//!   face or a vertex;
//! - every mesh they accept validates, and `from_faces` then `to_faces`
//!   gives back exactly the input;
//! - `validate()` never panics or hangs, and what it accepts rebuilds.
//!
//! Each property runs a few hundred cases (about 2000 in all); set
//! `PROPTEST_CASES` to run that many per property instead.

use halfedge::obj;
use halfedge::{shapes, DVec3, EdgeId, FaceId, HalfedgeId, Mesh, MeshError, VertexId};
use proptest::prelude::*;
use proptest::sample::Index;

/// `default` cases, or `PROPTEST_CASES` when it is set.
fn config(default: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default);
    ProptestConfig {
        cases,
        // The tests hold no state between cases; no file for regressions.
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Every mesh shape the generators make, small, with its Euler
/// characteristic as built.
fn base_shape() -> impl Strategy<Value = Mesh> {
    prop_oneof![
        prop::sample::select(shapes::LAB_OBJECTS.to_vec())
            .prop_map(|n| shapes::lab_object(n).unwrap()),
        (1usize..=3).prop_map(shapes::cube),
        (3usize..=6, 3usize..=5).prop_map(|(a, b)| shapes::torus(a, b, 2.0, 0.5)),
        (0usize..=1).prop_map(shapes::icosphere),
        (1usize..=4, 1usize..=4).prop_map(|(x, y)| shapes::grid(x, y)),
        (3usize..=7, 1usize..=3, any::<bool>())
            .prop_map(|(s, r, capped)| shapes::cylinder(s, r, 1.0, 2.0, capped)),
        (3usize..=7).prop_map(|s| shapes::cone(s, 1.0, 1.0)),
    ]
}

/// A manifold mesh as indexed faces, with vertices renumbered, faces
/// reordered and each face starting at a random corner; and the Euler
/// characteristic it must have.
fn manifold() -> impl Strategy<Value = (Vec<DVec3>, Vec<Vec<usize>>, i64)> {
    base_shape().prop_flat_map(|mesh| {
        let (positions, faces) = mesh.to_faces();
        let chi = euler(&mesh);
        let (nv, nf) = (positions.len(), faces.len());
        (
            Just(positions),
            Just(faces),
            Just(chi),
            Just((0..nv).collect::<Vec<_>>()).prop_shuffle(),
            Just((0..nf).collect::<Vec<_>>()).prop_shuffle(),
            prop::collection::vec(0usize..4, nf),
        )
            .prop_map(|(positions, faces, chi, vperm, forder, turns)| {
                // Vertex i goes to vperm[i].
                let mut moved = vec![DVec3::ZERO; positions.len()];
                for (i, &p) in positions.iter().enumerate() {
                    moved[vperm[i]] = p;
                }
                let faces = forder
                    .iter()
                    .map(|&f| {
                        let mut face: Vec<usize> = faces[f].iter().map(|&v| vperm[v]).collect();
                        let k = turns[f] % face.len();
                        face.rotate_left(k);
                        face
                    })
                    .collect();
                (moved, faces, chi)
            })
    })
}

/// A few polygons over a few vertices, renumbered so that every vertex is
/// used: often a valid mesh (a fan, a strip, a closed pair), often not.
fn polygon_soup() -> impl Strategy<Value = (usize, Vec<Vec<usize>>)> {
    prop::collection::vec(prop::collection::vec(0usize..6, 3..5), 1..6).prop_map(renumber)
}

/// The faces with vertices renumbered in order of first use, so that every
/// vertex is used; and how many there are.
fn renumber(faces: impl IntoIterator<Item = Vec<usize>>) -> (usize, Vec<Vec<usize>>) {
    let mut number = std::collections::HashMap::new();
    let faces: Vec<Vec<usize>> = faces
        .into_iter()
        .map(|f| {
            f.into_iter()
                .map(|v| {
                    let next = number.len();
                    *number.entry(v).or_insert(next)
                })
                .collect()
        })
        .collect();
    (number.len(), faces)
}

/// A manifold mesh with random faces removed and the vertices renumbered
/// so that every one is used: holes of every shape, some of them touching
/// at a vertex (which the builder must refuse).
fn punctured() -> impl Strategy<Value = (usize, Vec<Vec<usize>>)> {
    manifold().prop_flat_map(|(_, faces, _)| {
        let nf = faces.len();
        (
            Just(faces),
            prop::collection::vec(prop::bool::weighted(0.12), nf),
        )
            .prop_map(|(faces, drop)| {
                renumber(
                    faces
                        .into_iter()
                        .zip(drop)
                        .filter(|(_, d)| !d)
                        .map(|(f, _)| f),
                )
            })
    })
}

fn euler(mesh: &Mesh) -> i64 {
    mesh.num_vertices() as i64 - mesh.num_edges() as i64 + mesh.num_real_faces() as i64
}

/// The OBJ text of indexed faces, one statement a line.
fn obj_lines(positions: &[DVec3], faces: &[Vec<usize>]) -> Vec<String> {
    let mut lines: Vec<String> = positions
        .iter()
        .map(|p| format!("v {} {} {}", p.x, p.y, p.z))
        .collect();
    for f in faces {
        let corners: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
        lines.push(format!("f {}", corners.join(" ")));
    }
    lines
}

/// An error from the OBJ reader names a line, unless the file as a whole
/// is at fault (empty).
fn assert_names_a_line(e: &MeshError) {
    match e {
        MeshError::Obj { line, message, .. } => {
            assert!(*line >= 1 || message.contains("empty"), "no line in: {e}");
            assert!(!message.is_empty());
        }
        other => panic!("the reader returned a bare {other:?}"),
    }
}

/// A statement the lab ignores, as a line, with what `dropped` says.
fn ignored_line() -> impl Strategy<Value = (String, &'static str)> {
    prop::sample::select(vec![
        ("vn 0 0 1", "`vn`"),
        ("vt 0.5 0.5", "`vt`"),
        ("o thing", "`o`"),
        ("g group", "`g`"),
        ("s off", "`s`"),
        ("usemtl red", "`usemtl`"),
        ("mtllib a.mtl", "`mtllib`"),
        ("l 1 2", "`l`"),
        ("p 1", "`p`"),
    ])
    .prop_map(|(l, d)| (l.to_string(), d))
}

/// Ways to damage one line of an OBJ file.
#[derive(Clone, Debug)]
enum Damage {
    Delete(Index),
    Duplicate(Index),
    Swap(Index, Index),
    UpperCase(Index),
    ReplaceToken(Index, Index, String),
    AppendToken(Index, String),
    Insert(Index, String),
    Truncate(Index),
}

fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "x",
            "0",
            "-1",
            "-99",
            "1e999",
            "nan",
            "inf",
            "-0",
            "99999999999999999999",
            "1//",
            "1/2/3/4",
            "/",
            "\u{feff}",
            "#",
            "\\",
            "F",
            "fo",
            "v",
            "f",
            "1/x",
        ])
        .prop_map(String::from),
        (-20i64..20).prop_map(|i| i.to_string()),
        "[ -~]{0,6}",
    ]
}

fn damage() -> impl Strategy<Value = Damage> {
    prop_oneof![
        any::<Index>().prop_map(Damage::Delete),
        any::<Index>().prop_map(Damage::Duplicate),
        (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Damage::Swap(a, b)),
        any::<Index>().prop_map(Damage::UpperCase),
        (any::<Index>(), any::<Index>(), token())
            .prop_map(|(a, b, t)| Damage::ReplaceToken(a, b, t)),
        (any::<Index>(), token()).prop_map(|(a, t)| Damage::AppendToken(a, t)),
        (any::<Index>(), "[ -~]{0,12}").prop_map(|(a, t)| Damage::Insert(a, t)),
        any::<Index>().prop_map(Damage::Truncate),
    ]
}

fn apply(lines: &mut Vec<String>, d: &Damage) {
    if lines.is_empty() {
        return;
    }
    let at = |i: &Index| i.index(lines.len());
    match d {
        Damage::Delete(i) => {
            lines.remove(at(i));
        }
        Damage::Duplicate(i) => {
            let l = lines[at(i)].clone();
            lines.insert(at(i), l);
        }
        Damage::Swap(a, b) => {
            let (a, b) = (at(a), at(b));
            lines.swap(a, b);
        }
        Damage::UpperCase(i) => {
            let k = at(i);
            lines[k] = lines[k].to_uppercase();
        }
        Damage::ReplaceToken(i, j, t) => {
            let k = at(i);
            let mut tokens: Vec<String> = lines[k].split(' ').map(String::from).collect();
            let n = tokens.len();
            tokens[j.index(n)] = t.clone();
            lines[k] = tokens.join(" ");
        }
        Damage::AppendToken(i, t) => {
            let k = at(i);
            lines[k] = format!("{} {t}", lines[k]);
        }
        Damage::Insert(i, t) => {
            let k = at(i);
            lines.insert(k, t.clone());
        }
        Damage::Truncate(i) => {
            let k = at(i);
            lines.truncate(k);
        }
    }
}

proptest! {
    #![proptest_config(config(500))]

    /// Any text at all: an error naming a line, or a mesh that validates.
    #[test]
    fn reader_never_panics_on_garbage(text in prop_oneof![
        any::<String>(),
        "[vf0-9 ./#\\-\r\n]{0,200}",
        prop::collection::vec(any::<u8>(), 0..200)
            .prop_map(|b| String::from_utf8_lossy(&b).into_owned()),
    ]) {
        match Mesh::read_obj_str(&text, "t.obj") {
            Ok((mesh, _)) => prop_assert!(mesh.validate().is_ok()),
            Err(e) => assert_names_a_line(&e),
        }
    }

    /// A valid file with some lines damaged: never a panic; a refusal names
    /// its line; an accepted mesh validates and has no more faces than `f`
    /// lines, so nothing was read that is not there.
    #[test]
    fn reader_on_damaged_files((positions, faces, _) in manifold(),
                               damages in prop::collection::vec(damage(), 1..4),
                               crlf in any::<bool>()) {
        let mut lines = obj_lines(&positions, &faces);
        for d in &damages {
            apply(&mut lines, d);
        }
        let f_lines = lines.iter().filter(|l| l.starts_with("f ")).count();
        let end = if crlf { "\r\n" } else { "\n" };
        let text = lines.join(end);
        match Mesh::read_obj_str(&text, "t.obj") {
            Ok((mesh, _)) => {
                prop_assert!(mesh.validate().is_ok(), "{:?}", mesh.validate());
                prop_assert!(mesh.num_real_faces() <= f_lines);
            }
            Err(e) => assert_names_a_line(&e),
        }
    }

    /// A valid file dressed up (byte-order mark, CRLF, comments, statements
    /// the lab ignores): read exactly, with one warning per ignored line.
    #[test]
    fn reader_reads_valid_files_exactly((positions, faces, chi) in manifold(),
                                        extra in prop::collection::vec((any::<Index>(), ignored_line()), 0..6),
                                        bom in any::<bool>(),
                                        crlf in any::<bool>(),
                                        comment in any::<bool>()) {
        let mut lines = obj_lines(&positions, &faces);
        let mut expected = Vec::new();
        // Insert from the back so earlier positions stay right.
        let mut inserts: Vec<(usize, String, &str)> = extra
            .iter()
            .map(|(i, (l, d))| (i.index(lines.len() + 1), l.clone(), *d))
            .collect();
        inserts.sort_by_key(|(at, _, _)| std::cmp::Reverse(*at));
        for (at, line, _) in &inserts {
            lines.insert(*at, line.clone());
        }
        for (i, l) in lines.iter().enumerate() {
            if let Some((_, (_, d))) = extra.iter().find(|(_, (x, _))| x == l) {
                expected.push((i + 1, *d));
            }
        }
        if comment {
            for l in lines.iter_mut().step_by(3) {
                l.push_str(" # a comment");
            }
        }
        let mut text = lines.join(if crlf { "\r\n" } else { "\n" });
        if bom {
            text.insert(0, '\u{feff}');
        }
        let (mesh, warnings) = Mesh::read_obj_str(&text, "t.obj")
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        let got: Vec<(usize, &str)> = warnings.iter().map(|w| (w.line, w.dropped.as_str())).collect();
        prop_assert_eq!(got, expected);
        prop_assert_eq!(obj::summary(&warnings).is_some(), !warnings.is_empty());
        let (p, f) = mesh.to_faces();
        prop_assert_eq!(p, positions);
        prop_assert_eq!(f, faces);
        prop_assert_eq!(euler(&mesh), chi);
    }

    /// Manifold meshes in any element order build, validate, keep their
    /// Euler characteristic and round-trip through `to_faces` and OBJ text.
    #[test]
    fn manifold_meshes_round_trip((positions, faces, chi) in manifold()) {
        let mesh = Mesh::from_faces(&positions, &faces)
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert!(mesh.validate().is_ok(), "{:?}", mesh.validate());
        prop_assert_eq!(euler(&mesh), chi);
        let (p, f) = mesh.to_faces();
        prop_assert_eq!(&p, &positions);
        prop_assert_eq!(&f, &faces);
        let back = Mesh::from_obj_str(&mesh.to_obj_string(), "round.obj")
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(back.to_faces(), (positions, faces));
    }

    /// Random face lists over a few vertices: the builder never panics; it
    /// names an element that exists, or builds a mesh that validates, has
    /// one edge per pair of vertices, and gives back its input.
    #[test]
    fn builder_on_random_faces((n, faces) in prop_oneof![
        (1usize..7, prop::collection::vec(prop::collection::vec(0usize..8, 0..6), 0..7)),
        polygon_soup(),
        punctured(),
    ]) {
        let positions: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new(i as f64, (i * i % 5) as f64, (i % 3) as f64))
            .collect();
        match Mesh::from_faces(&positions, &faces) {
            Ok(mesh) => {
                prop_assert!(mesh.validate().is_ok(), "{:?}", mesh.validate());
                prop_assert_eq!(mesh.to_faces(), (positions, faces));
                let mut edges = mesh.edge_list();
                let count = edges.len();
                edges.sort_unstable();
                edges.dedup();
                prop_assert_eq!(edges.len(), count);
            }
            Err(e) => {
                if let Some(f) = e.face() {
                    prop_assert!(f < faces.len());
                }
                if let Some(v) = e.vertex() {
                    prop_assert!(v < n);
                }
                prop_assert!(e.face().is_some() || e.vertex().is_some()
                    || matches!(e, MeshError::Empty), "names nothing: {:?}", e);
            }
        }
    }

    /// Random links broken in a valid mesh: `validate()` never panics or
    /// hangs, and a mesh it accepts rebuilds from its faces with the same
    /// counts.
    #[test]
    fn validate_on_broken_links(mesh in base_shape(),
                                breaks in prop::collection::vec((0u8..9, any::<Index>(), any::<Index>()), 1..4)) {
        let mut mesh = mesh;
        for (what, at, to) in &breaks {
            let (nv, ne, nf, nh) = (mesh.num_vertices(), mesh.num_edges(),
                                    mesh.num_faces(), mesh.num_halfedges());
            // One past the end stands for an unset id.
            let h = HalfedgeId::from_index(at.index(nh));
            let hid = |i: &Index| HalfedgeId::from_index(i.index(nh + 1));
            match what {
                0 => mesh[h].next = hid(to),
                1 => mesh[h].twin = hid(to),
                2 => mesh[h].vertex = VertexId::from_index(to.index(nv + 1)),
                3 => mesh[h].edge = EdgeId::from_index(to.index(ne + 1)),
                4 => mesh[h].face = FaceId::from_index(to.index(nf + 1)),
                5 => { let v = VertexId::from_index(at.index(nv)); mesh[v].halfedge = hid(to); }
                6 => { let e = EdgeId::from_index(at.index(ne)); mesh[e].halfedge = hid(to); }
                7 => { let f = FaceId::from_index(at.index(nf)); mesh[f].halfedge = hid(to); }
                _ => {
                    // Swap the `next` of two halfedges: a plausible slip.
                    let g = hid(to);
                    if g.index() < nh {
                        let (a, b) = (mesh[h].next, mesh[g].next);
                        mesh[h].next = b;
                        mesh[g].next = a;
                    }
                }
            }
        }
        if mesh.validate().is_ok() {
            let (p, f) = mesh.to_faces();
            let rebuilt = Mesh::from_faces(&p, &f)
                .map_err(|e| TestCaseError::fail(format!("validated, yet does not rebuild: {e}")))?;
            prop_assert_eq!(
                (rebuilt.num_vertices(), rebuilt.num_edges(), rebuilt.num_halfedges()),
                (mesh.num_vertices(), mesh.num_edges(), mesh.num_halfedges())
            );
        }
    }
}
