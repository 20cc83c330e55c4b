//! `--report DIR`: what a student looks at when a case fails.
//!
//! For every case: the input, the student's result and the expected result
//! as OBJ files (MeshLab, Blender), and one self-contained offline
//! `index.html` (inline CSS and SVG, no script but under `--watch`,
//! nothing fetched): the case
//! list at the top, failing cases first, and for each case its verdict and
//! messages beside pictures of the input, the expected result and the
//! student's result from three angles.
//!
//! The pictures are orthographic projections drawn here: faces filled with
//! flat shading by normal, painted far to near (back faces culled on a closed
//! surface, drawn lighter on an open one), vertices as dots, the student's
//! ids beside the vertices of small meshes (so "v7" in a message can be
//! found). What the comparison found wrong is red (SVG class `wrong`): the
//! student's vertices no expected vertex matches, expected vertices nobody
//! matched, extra and missing edges. The case's edge is orange.
//!
//! The student's mesh may be anything: every id is bounds-checked, every
//! walk is bounded, non-finite or far-off positions are left out or pinned
//! to the picture's border. Fixtures keep no faces, so the expected result's
//! faces are rebuilt from its edges (the input's faces that survive, then
//! the smallest triangles of the edge graph, at most two per edge).

use std::collections::{BTreeSet, HashMap, HashSet, VecDeque};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use halfedge::{DVec3, Mesh};

use crate::fixture::{Fixture, Group, Operation, Returns};
use crate::grade::{CaseReport, Level};
use crate::matching::{self, VertexMatch};

/// Side of one picture, in CSS pixels.
const SIZE: f64 = 230.0;
/// Room left around the mesh's bounding sphere in a picture.
const MARGIN: f64 = 14.0;
/// Meshes with fewer vertices get their ids written beside the vertices.
const LABEL_LIMIT: usize = 60;
/// Vertex dots are drawn on meshes up to this many vertices (beyond, they
/// would hide the faces).
const DOT_LIMIT: usize = 400;
/// A face whose `next` walk is longer than this is not drawn.
const MAX_DEGREE: usize = 64;
/// Characters of what the student's code printed kept in the page.
const OUTPUT_LIMIT: usize = 6000;

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

/// A mesh reduced to what a picture needs. Every index is in range.
#[derive(Clone, Debug, Default)]
struct Shape {
    /// Positions by vertex id; `None` when not finite.
    points: Vec<Option<DVec3>>,
    /// Distinct edges, smaller index first.
    edges: Vec<[usize; 2]>,
    /// Polygons, each in its winding order.
    faces: Vec<Vec<usize>>,
}

impl Shape {
    /// What can be drawn of a mesh the student's code left, valid or not:
    /// the positions, an edge for each halfedge whose twin and vertices are
    /// in range, and each real face whose `next` walk comes back to its start
    /// through halfedges of that face.
    fn from_mesh(mesh: &Mesh) -> Shape {
        let (vertices, _, faces, halfedges) = mesh.records();
        let (nv, nh) = (vertices.len(), halfedges.len());
        let points = vertices
            .iter()
            .map(|v| v.pos.is_finite().then_some(v.pos))
            .collect();
        let mut seen = HashSet::new();
        let mut edges = Vec::new();
        for h in halfedges {
            let Some(twin) = halfedges.get(h.twin.index()) else {
                continue;
            };
            let (a, b) = (h.vertex.index(), twin.vertex.index());
            if a < nv && b < nv && a != b && seen.insert(pair(a, b)) {
                edges.push(pair(a, b));
            }
        }
        let mut polygons = Vec::new();
        for (f, face) in faces.iter().enumerate() {
            if face.is_boundary {
                continue;
            }
            let start = face.halfedge.index();
            let mut h = start;
            let mut polygon = Vec::new();
            let closed = loop {
                let Some(record) = halfedges.get(h) else {
                    break false;
                };
                let v = record.vertex.index();
                if record.face.index() != f || v >= nv || polygon.len() >= MAX_DEGREE {
                    break false;
                }
                polygon.push(v);
                h = record.next.index();
                if h == start {
                    break true;
                }
            };
            if closed && polygon.len() >= 3 && h < nh {
                polygons.push(polygon);
            }
        }
        Shape {
            points,
            edges,
            faces: polygons,
        }
    }

    /// Positions and faces given as indexed polygons (the fixture's input).
    fn from_faces(positions: &[[f64; 3]], faces: &[Vec<usize>]) -> Shape {
        let n = positions.len();
        let faces: Vec<Vec<usize>> = faces
            .iter()
            .filter(|f| f.len() >= 3 && f.iter().all(|&v| v < n))
            .cloned()
            .collect();
        let edges: BTreeSet<[usize; 2]> = faces
            .iter()
            .flat_map(|f| sides(f))
            .filter(|[a, b]| a != b)
            .collect();
        Shape {
            points: positions.iter().map(|&p| finite(p)).collect(),
            edges: edges.into_iter().collect(),
            faces,
        }
    }

    /// The expected result: its positions and edges, and faces rebuilt.
    fn expected(f: &Fixture) -> Shape {
        let points: Vec<Option<DVec3>> = f.expected.positions.iter().map(|&p| finite(p)).collect();
        let n = points.len();
        let edges: BTreeSet<[usize; 2]> = f
            .expected
            .edges
            .iter()
            .filter(|[a, b]| a != b && *a < n && *b < n)
            .map(|&[a, b]| pair(a, b))
            .collect();
        let edges: Vec<[usize; 2]> = edges.into_iter().collect();
        let input = Shape::from_faces(&f.input.positions, &f.input.faces);
        let faces = rebuild_faces(&input, &points, &edges);
        Shape {
            points,
            edges,
            faces,
        }
    }

    fn len(&self) -> usize {
        self.points.len()
    }

    fn point(&self, i: usize) -> Option<DVec3> {
        self.points.get(i).copied().flatten()
    }

    /// The centre and radius of the finite points' bounding box.
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut pts = self.points.iter().flatten();
        let first = *pts.next()?;
        Some(pts.fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))))
    }

    /// Area-weighted normal of a face (Newell's method), if drawable.
    fn face_normal(&self, face: &[usize]) -> Option<DVec3> {
        let pts: Vec<DVec3> = face.iter().map(|&v| self.point(v)).collect::<Option<_>>()?;
        let mut n = DVec3::ZERO;
        for i in 0..pts.len() {
            n += pts[i].cross(pts[(i + 1) % pts.len()]);
        }
        Some(n * 0.5)
    }

    fn face_center(&self, face: &[usize]) -> Option<DVec3> {
        let sum = face.iter().map(|&v| self.point(v)).sum::<Option<DVec3>>()?;
        Some(sum / face.len() as f64)
    }

    /// `(Σ (centre_f - c)·N_f, Σ N_f)` over `faces` (indices into
    /// `self.faces`): three times the enclosed volume for a closed surface,
    /// positive when the faces wind counter-clockwise seen from outside;
    /// the summed normal tells an open sheet's side.
    fn orientation(&self, faces: &[usize]) -> (f64, DVec3) {
        let pts: Vec<DVec3> = faces
            .iter()
            .flat_map(|&f| self.faces[f].iter().filter_map(|&v| self.point(v)))
            .collect();
        if pts.is_empty() {
            return (0.0, DVec3::ZERO);
        }
        let c = pts.iter().sum::<DVec3>() / pts.len() as f64;
        let mut volume = 0.0;
        let mut normal = DVec3::ZERO;
        for &f in faces {
            let face = &self.faces[f];
            if let (Some(n), Some(m)) = (self.face_normal(face), self.face_center(face)) {
                volume += (m - c).dot(n);
                normal += n;
            }
        }
        (volume, normal)
    }

    /// Whether every side of every face is used once each way: a closed,
    /// consistently wound surface, whose back faces are never seen.
    fn is_closed(&self) -> bool {
        if self.faces.is_empty() {
            return false;
        }
        let mut directed: HashMap<(usize, usize), u32> = HashMap::new();
        for f in &self.faces {
            for i in 0..f.len() {
                *directed.entry((f[i], f[(i + 1) % f.len()])).or_default() += 1;
            }
        }
        directed
            .iter()
            .all(|(&(a, b), &k)| k == 1 && directed.get(&(b, a)) == Some(&1))
    }
}

fn finite(p: [f64; 3]) -> Option<DVec3> {
    let p = DVec3::from_array(p);
    p.is_finite().then_some(p)
}

/// Faces for the expected result, which fixtures keep only as edges: the
/// input's faces whose sides are all still edges, then triangles of the
/// edge graph, smallest first, while each edge has fewer than two faces.
/// Faces are wound like their neighbours, and each piece like the input.
fn rebuild_faces(input: &Shape, points: &[Option<DVec3>], edges: &[[usize; 2]]) -> Vec<Vec<usize>> {
    let n = points.len();
    let set: HashSet<[usize; 2]> = edges.iter().copied().collect();
    let mut uses: HashMap<[usize; 2], u32> = HashMap::new();
    let mut faces: Vec<Vec<usize>> = Vec::new();
    for face in &input.faces {
        let fits = face.iter().all(|&v| v < n)
            && sides(face).all(|s| set.contains(&s) && uses.get(&s).copied().unwrap_or(0) < 2);
        if fits {
            for s in sides(face) {
                *uses.entry(s).or_default() += 1;
            }
            faces.push(face.clone());
        }
    }
    let kept = faces.len();
    let mut adjacent = vec![Vec::new(); n];
    for &[a, b] in edges {
        adjacent[a].push(b);
        adjacent[b].push(a);
    }
    for list in &mut adjacent {
        list.sort_unstable();
        list.dedup();
    }
    let mut seen = HashSet::new();
    let mut candidates: Vec<(f64, [usize; 3])> = Vec::new();
    for &[a, b] in edges {
        if uses.get(&[a, b]).copied().unwrap_or(0) >= 2 {
            continue;
        }
        for &c in &adjacent[a] {
            if c == b || adjacent[b].binary_search(&c).is_err() {
                continue;
            }
            let mut t = [a, b, c];
            t.sort_unstable();
            if seen.insert(t) {
                let area = match (points[t[0]], points[t[1]], points[t[2]]) {
                    (Some(p), Some(q), Some(r)) => (q - p).cross(r - p).length(),
                    _ => f64::INFINITY,
                };
                candidates.push((area, t));
            }
        }
    }
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    for (_, t) in candidates {
        if sides(&t).all(|s| uses.get(&s).copied().unwrap_or(0) < 2) {
            for s in sides(&t) {
                *uses.entry(s).or_default() += 1;
            }
            faces.push(t.to_vec());
        }
    }
    orient(&mut faces, kept, input, points);
    faces
}

/// Winds `faces` consistently: the first `kept` are wound already (the
/// input's), each other face takes the opposite direction of a wound
/// neighbour along their shared side; a piece with no wound face is wound
/// like the input as a whole.
fn orient(faces: &mut [Vec<usize>], kept: usize, input: &Shape, points: &[Option<DVec3>]) {
    let mut by_side: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
    for (i, f) in faces.iter().enumerate() {
        for s in sides(f) {
            by_side.entry(s).or_default().push(i);
        }
    }
    let runs = |f: &[usize], a: usize, b: usize| {
        (0..f.len()).any(|i| f[i] == a && f[(i + 1) % f.len()] == b)
    };
    let all_input: Vec<usize> = (0..input.faces.len()).collect();
    let (input_volume, input_normal) = input.orientation(&all_input);
    let mut visited = vec![false; faces.len()];
    let seeds: Vec<Vec<usize>> = std::iter::once((0..kept).collect())
        .chain((kept..faces.len()).map(|i| vec![i]))
        .collect();
    for seed in seeds {
        let seed: Vec<usize> = seed.into_iter().filter(|&i| !visited[i]).collect();
        if seed.is_empty() {
            continue;
        }
        let free = seed[0] >= kept;
        let mut piece = seed.clone();
        let mut queue: VecDeque<usize> = seed.into_iter().collect();
        for &i in &queue {
            visited[i] = true;
        }
        while let Some(i) = queue.pop_front() {
            let face = faces[i].clone();
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                for &j in by_side.get(&pair(a, b)).map_or(&[][..], |v| &v[..]) {
                    if visited[j] {
                        continue;
                    }
                    visited[j] = true;
                    if j >= kept && runs(&faces[j], a, b) {
                        faces[j].reverse();
                    }
                    piece.push(j);
                    queue.push_back(j);
                }
            }
        }
        if free {
            let shape = Shape {
                points: points.to_vec(),
                edges: Vec::new(),
                faces: piece.iter().map(|&i| faces[i].clone()).collect(),
            };
            let all: Vec<usize> = (0..piece.len()).collect();
            let (volume, normal) = shape.orientation(&all);
            let scale = shape
                .bounds()
                .map_or(1.0, |(lo, hi)| (hi - lo).length().max(1e-300));
            let closed_enough =
                volume.abs() > 1e-9 * scale.powi(3) && input_volume.abs() > 1e-12 * scale.powi(3);
            let flip = if closed_enough {
                (volume > 0.0) != (input_volume > 0.0)
            } else {
                normal.dot(input_normal) < 0.0
            };
            if flip {
                for &i in &piece {
                    faces[i].reverse();
                }
            }
        }
    }
}

/// What is marked on one picture.
#[derive(Clone, Debug, Default)]
struct Marks {
    /// Vertices drawn red, with their tooltip.
    wrong_points: Vec<(usize, String)>,
    /// Edges drawn red.
    wrong_edges: Vec<[usize; 2]>,
    /// Where an expected vertex nobody matched is: a hollow red ring.
    ghost_points: Vec<(DVec3, String)>,
    /// Expected edges the student lacks, at the expected positions: dashed red.
    ghost_edges: Vec<[DVec3; 2]>,
    /// From a vertex of yours to where it should be: dashed red.
    moves: Vec<[DVec3; 2]>,
    /// The case's edge or new vertex, orange.
    focus_edges: Vec<[usize; 2]>,
    focus_points: Vec<usize>,
    /// Elements the messages name (`v7`, `e229`, `h40`, `f3`), purple.
    named: Vec<Named>,
    /// A vertex's label (the student's id), for small meshes.
    labels: Vec<Option<String>>,
    /// The `data-kind` of this picture's red markers: `yours`, `expected`.
    side: &'static str,
}

/// An element a message names, found in the mesh it names it in.
#[derive(Clone, Debug)]
enum Named {
    Vertex(usize, String),
    /// An edge or a halfedge: its two ends.
    Edge([usize; 2], String),
    /// A face: its corners, as far as its `next` walk goes.
    Face(Vec<usize>, String),
}

/// The most named elements drawn per case.
const NAMED_LIMIT: usize = 12;

/// The element ids in `texts`, in order, each once: `v7`, `e229`, `h40`,
/// `f3`, as the halfedge crate prints them.
fn element_names(texts: &[&str]) -> Vec<(char, usize)> {
    let mut found = Vec::new();
    for text in texts {
        let chars: Vec<char> = text.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            let starts = i == 0 || !chars[i - 1].is_alphanumeric() && chars[i - 1] != '_';
            if starts && matches!(chars[i], 'v' | 'e' | 'h' | 'f') {
                let digits: String = chars[i + 1..]
                    .iter()
                    .take_while(|c| c.is_ascii_digit())
                    .collect();
                let after = chars.get(i + 1 + digits.len());
                let ends = after.is_none_or(|c| !c.is_alphanumeric() && *c != '_');
                if !digits.is_empty() && ends {
                    if let Ok(n) = digits.parse::<usize>() {
                        if !found.contains(&(chars[i], n)) {
                            found.push((chars[i], n));
                        }
                    }
                }
                i += 1 + digits.len();
            } else {
                i += 1;
            }
        }
    }
    found
}

/// Finds named elements in `mesh`, every id bounds-checked.
fn resolve_names(mesh: &Mesh, names: &[(char, usize)]) -> Vec<Named> {
    let (vertices, edges, faces, halfedges) = mesh.records();
    let nv = vertices.len();
    let ends = |h: usize| -> Option<[usize; 2]> {
        let record = halfedges.get(h)?;
        let to = halfedges
            .get(record.twin.index())
            .or_else(|| halfedges.get(record.next.index()))?;
        let (a, b) = (record.vertex.index(), to.vertex.index());
        (a < nv && b < nv && a != b).then_some([a, b])
    };
    names
        .iter()
        .filter_map(|&(kind, n)| {
            let name = format!("{kind}{n}");
            match kind {
                'v' if n < nv => Some(Named::Vertex(n, name)),
                'e' => Some(Named::Edge(ends(edges.get(n)?.halfedge.index())?, name)),
                'h' => Some(Named::Edge(ends(n)?, name)),
                'f' => {
                    let start = faces.get(n)?.halfedge.index();
                    let mut corners = Vec::new();
                    let mut h = start;
                    while let Some(record) = halfedges.get(h) {
                        if record.vertex.index() >= nv || corners.len() >= MAX_DEGREE {
                            break;
                        }
                        corners.push(record.vertex.index());
                        h = record.next.index();
                        if h == start {
                            break;
                        }
                    }
                    (corners.len() >= 2).then_some(Named::Face(corners, name))
                }
                _ => None,
            }
        })
        .take(NAMED_LIMIT)
        .collect()
}

/// The student's result compared with the expected one, for marking: the
/// grader's own matching, run on whatever the student left, then the
/// leftovers paired (a vertex of yours in the wrong place and the expected
/// vertex it stands for), so that a misplaced vertex does not also make
/// every edge around it look wrong.
struct Comparison {
    /// Student vertex -> the expected vertex matched by position.
    matched: Vec<Option<usize>>,
    /// Expected vertices no student vertex is near, in index order.
    unmatched_expected: Vec<usize>,
    /// Expected vertex -> the student's vertex matched or paired with it.
    student_of: Vec<Option<usize>>,
    /// Student vertex -> the expected vertex it was paired with, though
    /// not in place.
    displaced: Vec<Option<usize>>,
    /// Expected edges no student edge maps to (expected numbering).
    missing: Vec<[usize; 2]>,
    /// Student edges that are not expected (student numbering).
    extra: Vec<[usize; 2]>,
}

/// Leftovers paired only when there are few of them, by distance.
const PAIR_BY_DISTANCE: usize = 300;

fn compare(f: &Fixture, yours: &Shape, expected: &Shape) -> Comparison {
    // Positions the hash grid can take: a cell index must fit an i64.
    let tol = f.tolerance.max(1e-300);
    let sane = |p: &Option<DVec3>| match p {
        Some(p) if p.abs().max_element() / tol < 1e15 => p.to_array(),
        _ => [f64::NAN; 3],
    };
    let mine: Vec<[f64; 3]> = yours.points.iter().map(sane).collect();
    let theirs: Vec<[f64; 3]> = expected.points.iter().map(sane).collect();
    let m: VertexMatch =
        matching::match_by_neighbourhood(&mine, &yours.edges, &theirs, &expected.edges, tol);
    let mut to_expected = m.to_expected.clone();
    let mut student_of = vec![None; expected.len()];
    for (s, e) in to_expected.iter().enumerate() {
        if let Some(slot) = e.and_then(|e| student_of.get_mut(e)) {
            *slot = Some(s);
        }
    }
    // Pair leftovers: each takes the free expected vertex that shares the
    // most already-paired neighbours with it, nearest first; twice, so that
    // pairs found in the first round help the second.
    let mine_adj = crate::matching::adjacency(yours.len(), &yours.edges);
    let theirs_adj = crate::matching::adjacency(expected.len(), &expected.edges);
    let mut displaced = vec![None; yours.len()];
    for round in 0..3 {
        let left: Vec<usize> = (0..yours.len())
            .filter(|&s| to_expected[s].is_none() && yours.point(s).is_some())
            .collect();
        let free: Vec<usize> = (0..expected.len())
            .filter(|&e| student_of[e].is_none())
            .collect();
        if left.is_empty() || free.is_empty() {
            break;
        }
        for s in left {
            let p = yours.point(s).unwrap_or(DVec3::ZERO);
            let dist = |e: usize| expected.point(e).map_or(f64::INFINITY, |q| q.distance(p));
            let candidates: Vec<usize> = if round < 2 {
                // Expected neighbours of the expected vertices my neighbours stand for.
                let mut c: Vec<usize> = mine_adj[s]
                    .iter()
                    .filter_map(|&n| to_expected[n])
                    .flat_map(|e| theirs_adj[e].iter().copied())
                    .filter(|&e| student_of[e].is_none())
                    .collect();
                c.sort_unstable();
                c.dedup();
                c
            } else if free.len() <= PAIR_BY_DISTANCE {
                free.iter()
                    .copied()
                    .filter(|&e| student_of[e].is_none())
                    .collect()
            } else {
                Vec::new()
            };
            let shared = |e: usize| {
                mine_adj[s]
                    .iter()
                    .filter(|&&n| {
                        to_expected[n].is_some_and(|x| theirs_adj[e].binary_search(&x).is_ok())
                    })
                    .count()
            };
            let best = candidates
                .into_iter()
                .map(|e| (shared(e), dist(e), e))
                .filter(|&(k, _, _)| round == 2 || k >= 2 - round)
                .max_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)));
            if let Some((_, _, e)) = best {
                to_expected[s] = Some(e);
                student_of[e] = Some(s);
                displaced[s] = Some(e);
            }
        }
    }
    let paired = VertexMatch {
        to_expected: to_expected.clone(),
        unmatched_expected: Vec::new(),
    };
    let mapped = matching::mapped_edges(&yours.edges, &paired);
    let diff = matching::diff_edges(&mapped, &expected.edges);
    let extra = diff
        .extra
        .iter()
        .filter_map(|&[a, b]| {
            Some(pair(
                student_of.get(a).copied()??,
                student_of.get(b).copied()??,
            ))
        })
        .collect();
    Comparison {
        matched: m.to_expected,
        unmatched_expected: m.unmatched_expected,
        student_of,
        displaced,
        missing: diff.missing,
        extra,
    }
}

/// A camera looking at the mesh from `dir`, orthographic.
struct Camera {
    dir: DVec3,
    right: DVec3,
    up: DVec3,
    center: DVec3,
    scale: f64,
    light: DVec3,
}

/// A projected point: screen x, y (pixels, y down), depth (pixels, larger
/// is nearer), and whether it was pinned to the border.
#[derive(Clone, Copy, Debug)]
struct Screen {
    x: f64,
    y: f64,
    depth: f64,
    pinned: bool,
}

impl Camera {
    /// Looks from `dir`, framing `points` as tightly as the picture allows.
    fn fit(dir: DVec3, points: &[Option<DVec3>]) -> Camera {
        let dir = dir.try_normalize().unwrap_or(DVec3::Z);
        let world_up = if dir.y.abs() > 0.97 {
            DVec3::NEG_Z
        } else {
            DVec3::Y
        };
        let right = world_up.cross(dir).normalize();
        let up = dir.cross(right);
        let light = (dir * 0.8 + up * 0.55 - right * 0.35).normalize();
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in points.iter().flatten() {
            let q = DVec3::new(p.dot(right), p.dot(up), p.dot(dir));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        if !(lo.is_finite() && hi.is_finite()) {
            (lo, hi) = (DVec3::splat(-1.0), DVec3::ONE);
        }
        let mid = (lo + hi) / 2.0;
        let extent = (hi.x - lo.x)
            .max(hi.y - lo.y)
            .max(1e-9 * (hi - lo).length())
            .max(1e-300);
        Camera {
            dir,
            right,
            up,
            center: right * mid.x + up * mid.y + dir * mid.z,
            scale: (SIZE - 2.0 * MARGIN) / extent,
            light,
        }
    }

    fn project(&self, p: DVec3) -> Screen {
        let q = p - self.center;
        let x = SIZE / 2.0 + q.dot(self.right) * self.scale;
        let y = SIZE / 2.0 - q.dot(self.up) * self.scale;
        let depth = q.dot(self.dir) * self.scale;
        let (lo, hi) = (1.0, SIZE - 1.0);
        let pinned = !(lo..=hi).contains(&x) || !(lo..=hi).contains(&y);
        Screen {
            x: x.clamp(lo, hi),
            y: y.clamp(lo, hi),
            depth: if depth.is_finite() { depth } else { 0.0 },
            pinned,
        }
    }
}

/// A position in a picture in tenths of a pixel (pictures use one
/// decimal: finer is invisible, coarser makes dense meshes jagged).
fn tenths(x: f64) -> i64 {
    (x.clamp(0.0, SIZE) * 10.0).round() as i64
}

/// A number of tenths as SVG writes it: `12.3`, `-0.4`, `7`.
fn put(out: &mut String, t: i64) {
    if t < 0 {
        out.push('-');
    }
    let t = t.abs();
    if t % 10 == 0 {
        let _ = write!(out, "{}", t / 10);
    } else {
        let _ = write!(out, "{}.{}", t / 10, t % 10);
    }
}

fn coord(out: &mut String, x: f64) {
    put(out, tenths(x));
}

/// Path data: `M` to the first point, then relative moves (shorter than
/// absolute ones, and exact since both ends are rounded first).
fn polyline(out: &mut String, pts: &[Screen], close: bool) {
    let mut last = (0, 0);
    for (k, s) in pts.iter().enumerate() {
        let t = (tenths(s.x), tenths(s.y));
        if k == 0 {
            out.push('M');
            put(out, t.0);
            out.push(' ');
            put(out, t.1);
            out.push('l');
        } else {
            // A minus sign separates numbers as well as a space does.
            let (dx, dy) = (t.0 - last.0, t.1 - last.1);
            if k > 1 && dx >= 0 {
                out.push(' ');
            }
            put(out, dx);
            if dy >= 0 {
                out.push(' ');
            }
            put(out, dy);
        }
        last = t;
    }
    if pts.len() == 1 {
        out.push_str("0 0");
    }
    if close {
        out.push('z');
    }
}

/// Projected faces bucketed in a coarse screen grid, to tell whether a
/// point is behind the surface.
struct Occluder {
    triangles: Vec<[Screen; 3]>,
    cells: Vec<Vec<u32>>,
}

const CELLS: usize = 24;

impl Occluder {
    fn new(triangles: Vec<[Screen; 3]>) -> Occluder {
        let mut cells = vec![Vec::new(); CELLS * CELLS];
        let cell = |v: f64| ((v / SIZE * CELLS as f64) as usize).min(CELLS - 1);
        for (i, t) in triangles.iter().enumerate() {
            let (x0, x1) = (
                t.iter().map(|s| s.x).fold(f64::MAX, f64::min),
                t.iter().map(|s| s.x).fold(f64::MIN, f64::max),
            );
            let (y0, y1) = (
                t.iter().map(|s| s.y).fold(f64::MAX, f64::min),
                t.iter().map(|s| s.y).fold(f64::MIN, f64::max),
            );
            for cy in cell(y0)..=cell(y1) {
                for cx in cell(x0)..=cell(x1) {
                    cells[cy * CELLS + cx].push(i as u32);
                }
            }
        }
        Occluder { triangles, cells }
    }

    /// Whether some face lies in front of `s` (by more than a pixel).
    fn hides(&self, s: Screen) -> bool {
        let cell = |v: f64| ((v / SIZE * CELLS as f64) as usize).min(CELLS - 1);
        self.cells[cell(s.y) * CELLS + cell(s.x)].iter().any(|&i| {
            let [a, b, c] = self.triangles[i as usize];
            let d = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
            if d.abs() < 1e-9 {
                return false;
            }
            let l1 = ((b.y - c.y) * (s.x - c.x) + (c.x - b.x) * (s.y - c.y)) / d;
            let l2 = ((c.y - a.y) * (s.x - c.x) + (a.x - c.x) * (s.y - c.y)) / d;
            let l3 = 1.0 - l1 - l2;
            let inside = l1 >= -1e-6 && l2 >= -1e-6 && l3 >= -1e-6;
            inside && l1 * a.depth + l2 * b.depth + l3 * c.depth > s.depth + 1.0
        })
    }
}

/// One shape ready for its pictures: its winding sense and closedness,
/// computed once for the three views.
struct Prepared<'a> {
    shape: &'a Shape,
    /// +1 when faces wind counter-clockwise seen from outside, else -1.
    outward: f64,
    closed: bool,
    /// Edges that are no face's side, drawn as lines.
    loose: Vec<[usize; 2]>,
}

impl<'a> Prepared<'a> {
    fn new(shape: &'a Shape) -> Prepared<'a> {
        let all: Vec<usize> = (0..shape.faces.len()).collect();
        let outward = if shape.orientation(&all).0 < 0.0 {
            -1.0
        } else {
            1.0
        };
        let in_faces: HashSet<[usize; 2]> = shape.faces.iter().flat_map(|f| sides(f)).collect();
        let loose = shape
            .edges
            .iter()
            .filter(|e| !in_faces.contains(*e))
            .copied()
            .collect();
        Prepared {
            shape,
            outward,
            closed: shape.is_closed(),
            loose,
        }
    }
}

fn shade(base: [f64; 3], k: f64) -> String {
    let c = base.map(|x| (x * k).round().clamp(0.0, 255.0) as u8);
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The face shades: flat shading by the angle to a light beside the eye.
fn shade_css() -> String {
    let mut css = String::new();
    for k in 0..=15 {
        let light = k as f64 / 15.0;
        let _ = write!(
            css,
            ".s{k}{{fill:{}}}",
            shade([150.0, 182.0, 226.0], 0.5 + 0.55 * light)
        );
    }
    for k in 0..=3 {
        let light = k as f64 / 3.0;
        let _ = write!(
            css,
            ".b{k}{{fill:{}}}",
            shade([240.0, 222.0, 190.0], 0.82 + 0.2 * light)
        );
    }
    css
}

/// Red marks drawn one element each (with `data-` attributes and a
/// tooltip) up to this many per kind and picture; beyond, they are drawn
/// as one path, those behind the surface left out, the ghosts in *yours*
/// too (the expected picture shows them).
const SINGLE_LIMIT: usize = 40;

/// One picture of one shape as an inline `<svg>`.
fn draw(out: &mut String, cam: &Camera, p: &Prepared, marks: &Marks, caption: &str) {
    let shape = p.shape;
    let proj: Vec<Option<Screen>> = shape
        .points
        .iter()
        .map(|q| q.map(|q| cam.project(q)))
        .collect();
    let at = |i: usize| proj.get(i).copied().flatten();
    let _ = write!(
        out,
        "<svg class=\"view\" viewBox=\"0 0 {SIZE} {SIZE}\" width=\"{SIZE}\" height=\"{SIZE}\" role=\"img\" aria-label=\"{}\">",
        escape(caption)
    );
    // Faces, far to near.
    let mut painted: Vec<(f64, String)> = Vec::new();
    let mut triangles = Vec::new();
    for face in &shape.faces {
        let Some(screen) = face.iter().map(|&v| at(v)).collect::<Option<Vec<Screen>>>() else {
            continue;
        };
        let Some(normal) = shape
            .face_normal(face)
            .and_then(|n| (n * p.outward).try_normalize())
        else {
            continue;
        };
        let facing = normal.dot(cam.dir) > 0.0;
        if p.closed && !facing {
            continue;
        }
        // Shades are CSS classes (`s0`..`s15` in front, `b0`..`b3` behind):
        // shorter than a colour per face, and flat shading needs few.
        let light = normal.dot(cam.light).abs();
        let fill = if facing {
            format!("s{}", (light * 15.0).round() as usize)
        } else {
            format!("b{}", (light * 3.0).round() as usize)
        };
        let depth = screen.iter().map(|s| s.depth).sum::<f64>() / screen.len() as f64;
        let mut d = String::from("<path d=\"");
        polyline(&mut d, &screen, true);
        let _ = write!(d, "\" class=\"{fill}\"/>");
        painted.push((depth, d));
        for k in 1..screen.len() - 1 {
            triangles.push([screen[0], screen[k], screen[k + 1]]);
        }
    }
    painted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let _ = write!(
        out,
        "<g class=\"faces\" stroke-width=\"{}\">",
        if painted.len() > 600 { 0.3 } else { 0.6 }
    );
    for (_, path) in &painted {
        out.push_str(path);
    }
    out.push_str("</g>");
    let occluder = Occluder::new(triangles);
    let hidden = |s: Screen| occluder.hides(s);
    let midpoint = |a: Screen, b: Screen| Screen {
        x: (a.x + b.x) / 2.0,
        y: (a.y + b.y) / 2.0,
        depth: (a.depth + b.depth) / 2.0,
        pinned: false,
    };
    // Many segments or dots as one path: `class` styles them.
    let batch = |out: &mut String, class: &str, items: &[Vec<Screen>]| {
        if items.is_empty() {
            return;
        }
        let _ = write!(out, "<path class=\"{class}\" d=\"");
        for item in items {
            polyline(out, item, false);
        }
        out.push_str("\"/>");
    };
    let line = |out: &mut String, a: Screen, b: Screen, attrs: &str| {
        out.push_str("<line x1=\"");
        coord(out, a.x);
        out.push_str("\" y1=\"");
        coord(out, a.y);
        out.push_str("\" x2=\"");
        coord(out, b.x);
        out.push_str("\" y2=\"");
        coord(out, b.y);
        let _ = write!(out, "\"{attrs}/>");
    };
    let circle = |out: &mut String, s: Screen, r: f64, attrs: &str, title: Option<&str>| {
        out.push_str("<circle cx=\"");
        coord(out, s.x);
        out.push_str("\" cy=\"");
        coord(out, s.y);
        let _ = write!(out, "\" r=\"{r}\"{attrs}");
        match title {
            Some(t) => {
                let _ = write!(out, "><title>{}</title></circle>", escape(t));
            }
            None => out.push_str("/>"),
        }
    };
    let behind = |s: Screen| if hidden(s) { " behind" } else { "" };

    // Edges that are no face's side.
    let (mut front, mut back) = (Vec::new(), Vec::new());
    for &[a, b] in &p.loose {
        if let (Some(sa), Some(sb)) = (at(a), at(b)) {
            if hidden(midpoint(sa, sb)) {
                back.push(vec![sa, sb]);
            } else {
                front.push(vec![sa, sb]);
            }
        }
    }
    batch(out, "loose behind", &back);
    batch(out, "loose", &front);
    // Vertex dots, where seen.
    let red: HashSet<usize> = marks.wrong_points.iter().map(|(i, _)| *i).collect();
    if shape.len() <= DOT_LIMIT {
        let dots: Vec<Vec<Screen>> = proj
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.filter(|s| !red.contains(&i) && !hidden(*s)))
            .map(|s| vec![s])
            .collect();
        let class = if shape.len() > 150 {
            "dots small"
        } else {
            "dots"
        };
        batch(out, class, &dots);
    }
    // What the messages name.
    for named in &marks.named {
        let (pts, name, closed): (Vec<Screen>, &str, bool) = match named {
            Named::Vertex(v, name) => (at(*v).into_iter().collect(), name, false),
            Named::Edge([a, b], name) => (at(*a).into_iter().chain(at(*b)).collect(), name, false),
            Named::Face(corners, name) => (
                corners.iter().filter_map(|&v| at(v)).collect(),
                name,
                corners.len() > 2,
            ),
        };
        let Some(&first) = pts.first() else { continue };
        let _ = write!(
            out,
            "<g class=\"named\" data-name=\"{name}\"><title>{name}, named in the messages</title>"
        );
        if pts.len() == 1 {
            circle(out, first, 6.5, "", None);
        } else {
            out.push_str("<path d=\"");
            polyline(out, &pts, closed);
            out.push_str("\"/>");
        }
        let n = pts.len() as f64;
        let mid = Screen {
            x: pts.iter().map(|s| s.x).sum::<f64>() / n,
            y: pts.iter().map(|s| s.y).sum::<f64>() / n,
            ..first
        };
        out.push_str("<text x=\"");
        coord(out, (mid.x + 7.0).min(SIZE - 24.0));
        out.push_str("\" y=\"");
        coord(out, (mid.y + 12.0).min(SIZE - 3.0));
        let _ = write!(out, "\">{name}</text></g>");
    }
    // The case's edge and new vertex.
    for &[a, b] in &marks.focus_edges {
        if let (Some(sa), Some(sb)) = (at(a), at(b)) {
            let class = format!(" class=\"case-edge{}\"", behind(midpoint(sa, sb)));
            line(out, sa, sb, &class);
        }
    }
    for &v in &marks.focus_points {
        if let Some(s) = at(v) {
            circle(
                out,
                s,
                5.0,
                &format!(" class=\"case-vertex{}\"", behind(s)),
                None,
            );
        }
    }
    // Red: edges first, vertices on top.
    let yours = marks.side == "yours";
    let edge_kind = if yours { "extra-edge" } else { "missing-edge" };
    let wrong_edges: Vec<([usize; 2], Screen, Screen)> = marks
        .wrong_edges
        .iter()
        .filter_map(|&[a, b]| Some(([a, b], at(a)?, at(b)?)))
        .collect();
    if wrong_edges.len() <= SINGLE_LIMIT {
        for &([a, b], sa, sb) in &wrong_edges {
            let ends = |v: usize| {
                marks.labels.get(v).cloned().flatten().unwrap_or_else(|| {
                    if yours {
                        format!("v{v}")
                    } else {
                        "?".into()
                    }
                })
            };
            let attrs = format!(
                " class=\"wrong edge {edge_kind}{}\" data-edge=\"{}-{}\"",
                behind(midpoint(sa, sb)),
                ends(a),
                ends(b)
            );
            line(out, sa, sb, &attrs);
        }
    } else {
        let seen: Vec<Vec<Screen>> = wrong_edges
            .iter()
            .filter(|(_, a, b)| !hidden(midpoint(*a, *b)))
            .map(|(_, a, b)| vec![*a, *b])
            .collect();
        batch(out, &format!("wrong edge {edge_kind} many"), &seen);
    }
    if marks.ghost_edges.len() <= SINGLE_LIMIT {
        for &[a, b] in &marks.ghost_edges {
            line(
                out,
                cam.project(a),
                cam.project(b),
                " class=\"wrong edge missing-edge ghost\"",
            );
        }
    }
    if marks.moves.len() <= SINGLE_LIMIT {
        for &[a, b] in &marks.moves {
            line(
                out,
                cam.project(a),
                cam.project(b),
                " class=\"wrong edge move\"",
            );
        }
    }
    if marks.ghost_points.len() <= SINGLE_LIMIT {
        for (q, title) in &marks.ghost_points {
            let attrs = " class=\"wrong vertex missing-vertex ghost\"";
            circle(out, cam.project(*q), 4.0, attrs, Some(title));
        }
    }
    let vertex_kind = if yours {
        "wrong-vertex"
    } else {
        "missing-vertex"
    };
    let wrong_points: Vec<(usize, &str, Screen)> = marks
        .wrong_points
        .iter()
        .filter_map(|(v, title)| Some((*v, title.as_str(), at(*v)?)))
        .collect();
    if wrong_points.len() <= SINGLE_LIMIT {
        for &(v, title, s) in &wrong_points {
            let name = marks.labels.get(v).cloned().flatten();
            let name = match (yours, name) {
                (true, _) => format!("v{v}"),
                (false, Some(n)) => n,
                (false, None) => String::new(),
            };
            let mut title = title.to_string();
            if s.pinned {
                title.push_str(" (outside the picture: pinned to its border)");
            }
            if hidden(s) {
                title.push_str(" (behind the surface in this view)");
            }
            let attrs = format!(
                " class=\"wrong vertex {vertex_kind}{}\" data-vertex=\"{name}\"",
                behind(s)
            );
            circle(out, s, 3.2, &attrs, Some(&title));
        }
    } else {
        let seen: Vec<Vec<Screen>> = wrong_points
            .iter()
            .filter(|(_, _, s)| !hidden(*s))
            .map(|(_, _, s)| vec![*s])
            .collect();
        batch(out, &format!("wrong vertex {vertex_kind} many"), &seen);
    }
    // The student's ids, on small meshes, where seen (red ones always).
    if shape.len() < LABEL_LIMIT {
        out.push_str("<g class=\"labels\">");
        for (i, s) in proj.iter().enumerate() {
            let (Some(s), Some(Some(name))) = (s, marks.labels.get(i)) else {
                continue;
            };
            let is_red = red.contains(&i);
            if hidden(*s) && !is_red {
                continue;
            }
            out.push_str("<text x=\"");
            coord(out, s.x + 3.0);
            out.push_str("\" y=\"");
            coord(out, s.y - 3.0);
            let class = if is_red { " class=\"red\"" } else { "" };
            let _ = write!(out, "\"{class}>{}</text>", escape(name));
        }
        out.push_str("</g>");
    }
    out.push_str("</svg>");
}

/// What a case is, in words: `split_edge on cube, edge 2-0`.
fn operation(f: &Fixture) -> String {
    let function = f.operation.stage().function();
    match f.operation {
        Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] } => {
            format!("{function} on {}, edge {a}-{b}", f.object)
        }
        Operation::Subdivide { rounds: 1 } => format!("{function} on {}, 1 round", f.object),
        Operation::Subdivide { rounds } => format!("{function} on {}, {rounds} rounds", f.object),
        Operation::Sequence { seed } => format!(
            "{} flips and splits on {} (seed {seed})",
            f.steps.len(),
            f.object
        ),
    }
}

/// The expected result as OBJ: its vertices, the faces rebuilt from its
/// edges, and as `l` lines the edges no face has.
fn expected_obj(f: &Fixture, shape: &Shape) -> String {
    let mut out = format!(
        "# expected result of {} ({})\n# fixtures keep edges, not faces: the faces below are rebuilt from the edges\n",
        f.name,
        operation(f)
    );
    for p in &f.expected.positions {
        let _ = writeln!(out, "v {} {} {}", p[0], p[1], p[2]);
    }
    obj_faces_and_lines(&mut out, shape);
    out
}

fn obj_faces_and_lines(out: &mut String, shape: &Shape) {
    for face in &shape.faces {
        out.push('f');
        for v in face {
            let _ = write!(out, " {}", v + 1);
        }
        out.push('\n');
    }
    let in_faces: HashSet<[usize; 2]> = shape.faces.iter().flat_map(|f| sides(f)).collect();
    for e in shape.edges.iter().filter(|e| !in_faces.contains(*e)) {
        let _ = writeln!(out, "l {} {}", e[0] + 1, e[1] + 1);
    }
}

/// The student's result as OBJ: exactly the mesh when it is valid, else
/// what could be read of it (faces that close, other edges as `l` lines).
fn yours_obj(f: &Fixture, mesh: &Mesh, shape: &Shape) -> String {
    match mesh.validate() {
        Ok(()) => format!("# your result for {}\n{}", f.name, mesh.to_obj_string()),
        Err(problem) => {
            let mut out = format!(
                "# your result for {}: NOT a valid mesh ({problem})\n# below: every vertex, the faces whose next-loop closes, other edges as l lines\n",
                f.name
            );
            for p in mesh.positions() {
                let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
            }
            obj_faces_and_lines(&mut out, shape);
            out
        }
    }
}

/// One direction the case is seen from: a camera framing the input, one
/// framing the expected result (and yours), and why it looks there.
struct View {
    input: Camera,
    result: Camera,
    why: &'static str,
}

/// Everything shown for one case, computed before any HTML is written.
struct CasePictures {
    input: Shape,
    expected: Shape,
    yours: Option<Shape>,
    marks_input: Marks,
    marks_expected: Marks,
    marks_yours: Marks,
    /// Why a view looks where it does, per view.
    cameras: Vec<View>,
    /// Lines said under the pictures (vertices not drawn, and so on).
    notes: Vec<String>,
}

fn labels_for(n: usize, name: impl Fn(usize) -> Option<usize>) -> Vec<Option<String>> {
    if n >= LABEL_LIMIT {
        return Vec::new();
    }
    (0..n).map(|i| name(i).map(|v| format!("v{v}"))).collect()
}

fn pictures(f: &Fixture, r: &CaseReport) -> CasePictures {
    let fixture_input = Shape::from_faces(&f.input.positions, &f.input.faces);
    let input = r
        .input
        .as_ref()
        .map(Shape::from_mesh)
        .unwrap_or_else(|| fixture_input.clone());
    let expected = Shape::expected(f);
    let yours = r.result.as_ref().map(Shape::from_mesh);
    let tol = f.tolerance.max(1e-300);
    let n_in = fixture_input.len();

    // The input as sent has its ids permuted: find each fixture vertex's id.
    let as_array = |s: &Shape| -> Vec<[f64; 3]> {
        s.points
            .iter()
            .map(|p| p.map_or([f64::NAN; 3], |p| p.to_array()))
            .collect()
    };
    let relabel = matching::match_by_neighbourhood(
        &as_array(&input),
        &input.edges,
        &as_array(&fixture_input),
        &fixture_input.edges,
        tol,
    );
    let mut id_of = vec![None; n_in];
    for (sent, fixture) in relabel.to_expected.iter().enumerate() {
        if let Some(slot) = fixture.and_then(|i| id_of.get_mut(i)) {
            *slot = Some(sent);
        }
    }
    let id = |i: usize| id_of.get(i).copied().flatten();

    let cmp = yours.as_ref().map(|y| compare(f, y, &expected));
    let mut notes = Vec::new();

    // Input: the case's edge.
    let case_edge = match f.operation {
        Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] } => {
            id(a).zip(id(b)).map(|(a, b)| pair(a, b))
        }
        Operation::Subdivide { .. } | Operation::Sequence { .. } => None,
    };
    let mut marks_input = Marks {
        focus_edges: case_edge.into_iter().collect(),
        labels: labels_for(input.len(), Some),
        side: "input",
        ..Marks::default()
    };

    // Expected: its labels are the student's ids (matched, else the id the
    // vertex had in the input), its red what nobody matched.
    let student_of = |i: usize| {
        cmp.as_ref()
            .and_then(|c| c.student_of.get(i).copied().flatten())
    };
    let mut marks_expected = Marks {
        labels: labels_for(expected.len(), |i| {
            student_of(i).or_else(|| if i < n_in { id(i) } else { None })
        }),
        side: "expected",
        ..Marks::default()
    };
    let new_vertex = match f.expected.returns {
        Some(Returns::Vertex { position }) => matching::nearest(&as_array(&expected), position)
            .filter(|&(_, d)| d <= tol)
            .map(|(k, _)| k),
        _ => None,
    };
    match (f.expected.returns, f.operation) {
        (Some(Returns::Edge { ends: [c, d] }), _) => marks_expected.focus_edges.push(pair(c, d)),
        (
            Some(Returns::Refused),
            Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] },
        ) => marks_expected.focus_edges.push(pair(a, b)),
        _ => {}
    }
    marks_expected.focus_points.extend(new_vertex);

    let mut marks_yours = Marks {
        side: "yours",
        ..Marks::default()
    };
    if let Some(y) = &yours {
        marks_yours.labels = labels_for(y.len(), Some);
        let not_drawn: Vec<String> = y
            .points
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_none())
            .map(|(i, _)| format!("v{i}"))
            .collect();
        if !not_drawn.is_empty() {
            let more = if not_drawn.len() > 8 {
                format!(" and {} more", not_drawn.len() - 8)
            } else {
                String::new()
            };
            notes.push(format!(
                "not drawn, their position is not a finite number: {}{more}",
                not_drawn[..not_drawn.len().min(8)].join(", ")
            ));
        }
        // The case's element, where the student has it.
        for &[a, b] in &marks_expected.focus_edges {
            if let (Some(a), Some(b)) = (student_of(a), student_of(b)) {
                if y.edges.contains(&pair(a, b)) {
                    marks_yours.focus_edges.push(pair(a, b));
                }
            }
        }
        marks_yours
            .focus_points
            .extend(new_vertex.and_then(student_of));
    }
    // Elements the messages name, where the student's code left them (or
    // in the input, when it left no mesh).
    if !r.passed {
        let texts: Vec<&str> = r
            .entries
            .iter()
            .filter(|e| e.level != Level::Info)
            .map(|e| e.text.as_str())
            .collect();
        let names = element_names(&texts);
        match (&r.result, &r.input) {
            (Some(mesh), _) => marks_yours.named = resolve_names(mesh, &names),
            (None, Some(mesh)) => marks_input.named = resolve_names(mesh, &names),
            (None, None) => {}
        }
    }
    // Red only on a failure (a pass may differ within the tolerance).
    if let (Some(c), Some(y), false) = (&cmp, &yours, r.passed) {
        for (s, e) in c.matched.iter().enumerate() {
            let Some(p) = y.point(s).filter(|_| e.is_none()) else {
                continue;
            };
            let title = match c.displaced[s].and_then(|k| Some((k, expected.point(k)?))) {
                Some((_, q)) => {
                    marks_yours.moves.push([p, q]);
                    format!(
                        "your v{s} is at {}: it should be at {} ({} away)",
                        fmt_p(p),
                        fmt_p(q),
                        fmt_d(p.distance(q))
                    )
                }
                None => format!(
                    "your v{s} at {}: no expected vertex is within {} of it",
                    fmt_p(p),
                    f.tolerance
                ),
            };
            marks_yours.wrong_points.push((s, title));
        }
        for &k in &c.unmatched_expected {
            let Some(q) = expected.point(k) else { continue };
            let stands = match c.student_of[k] {
                Some(s) => format!("; your v{s} stands for it"),
                None => "; none of yours stands for it".to_string(),
            };
            let title = format!(
                "expected a vertex at {}: none of yours is within {}{stands}",
                fmt_p(q),
                f.tolerance
            );
            marks_expected.wrong_points.push((k, title.clone()));
            marks_yours.ghost_points.push((q, title));
        }
        marks_expected.wrong_edges = c.missing.clone();
        // A missing edge is drawn between your vertices where you have them.
        let place = |k: usize| {
            c.student_of[k]
                .and_then(|s| y.point(s))
                .or_else(|| expected.point(k))
        };
        marks_yours.ghost_edges = c
            .missing
            .iter()
            .filter_map(|&[a, b]| Some([place(a)?, place(b)?]))
            .collect();
        marks_yours.wrong_edges = c.extra.clone();
        if marks_yours.wrong_points.is_empty()
            && marks_yours.ghost_points.is_empty()
            && c.missing.is_empty()
            && c.extra.is_empty()
        {
            notes.push(
                "your mesh has the expected vertices and edges: what failed is not in its shape (see the messages)"
                    .to_string(),
            );
        }
    }

    // Where to look from: at the case's edge, else at the first problem,
    // else from a corner.
    let middle = |s: &Shape| s.bounds().map(|(lo, hi)| (lo + hi) / 2.0);
    let input_center = middle(&input).unwrap_or(DVec3::ZERO);
    let center = middle(&expected).unwrap_or(input_center);
    let edge_normal = case_edge.and_then(|[a, b]| {
        let prepared = Prepared::new(&input);
        let n: DVec3 = input
            .faces
            .iter()
            .filter(|face| sides(face).any(|s| s == [a, b]))
            .filter_map(|face| input.face_normal(face))
            .map(|n| n.normalize_or_zero() * prepared.outward)
            .sum();
        n.try_normalize().or_else(|| {
            let m = (input.point(a)? + input.point(b)?) / 2.0 - input_center;
            m.try_normalize()
        })
    });
    // The first problem, seen along the surface's normal there (from the
    // centre where the surface says nothing).
    let looking_at = |s: &Shape, vertices: &[usize]| -> Option<DVec3> {
        let p = vertices.iter().filter_map(|&v| s.point(v)).sum::<DVec3>()
            / vertices.len().max(1) as f64;
        let outward = Prepared::new(s).outward;
        let n: DVec3 = s
            .faces
            .iter()
            .filter(|face| face.iter().any(|v| vertices.contains(v)))
            .filter_map(|face| s.face_normal(face))
            .map(|n| n.normalize_or_zero() * outward)
            .sum();
        n.try_normalize().or_else(|| (p - center).try_normalize())
    };
    let problem = marks_expected
        .wrong_points
        .first()
        .and_then(|(k, _)| looking_at(&expected, &[*k]))
        .or_else(|| {
            let (s, _) = marks_yours.wrong_points.first()?;
            looking_at(yours.as_ref()?, &[*s])
        })
        .or_else(|| {
            let [a, b] = *marks_expected.wrong_edges.first()?;
            looking_at(&expected, &[a, b])
        });
    let (dir, why) = match (edge_normal, problem) {
        (Some(n), _) => (n, "facing the case's edge"),
        (None, Some(n)) => (n, "facing the first problem"),
        (None, None) => (DVec3::new(0.55, 0.45, 0.75), "from a corner"),
    };
    // A little from above, so that no view is exactly edge-on.
    let d1 = (dir + DVec3::new(0.12, 0.3, 0.08))
        .try_normalize()
        .unwrap_or(DVec3::Z);
    let d2 = DVec3::new(d1.z, d1.y, -d1.x);
    let cameras = [
        (d1, why),
        (d2, "turned a quarter round"),
        (-d1, "from the opposite side"),
    ]
    .into_iter()
    .map(|(d, why)| View {
        // The input in its own frame, the expected result and yours in the
        // expected one's (yours may be anywhere: what lies outside is
        // pinned to the border).
        input: Camera::fit(d, &input.points),
        result: Camera::fit(
            d,
            if expected.bounds().is_some() {
                &expected.points
            } else {
                &input.points
            },
        ),
        why,
    })
    .collect();
    CasePictures {
        input,
        expected,
        yours,
        marks_input,
        marks_expected,
        marks_yours,
        cameras,
        notes,
    }
}

/// The first warning as shown, student text in it escaped.
fn first_warning_shown(r: &CaseReport) -> Option<String> {
    crate::report::first_warning(r)
}

const STYLE: &str = r#"
body{font:14px/1.45 system-ui,-apple-system,"Segoe UI",sans-serif;margin:0 auto;padding:12px 20px 60px;max-width:1500px;color:#1b1f24;background:#f6f7f9}
h1{font-size:22px;margin:8px 0}
h2{font-size:17px;margin:0 0 6px}
a{color:#0b57d0}
code,pre{font:12.5px/1.4 ui-monospace,"SFMono-Regular",Menlo,Consolas,monospace}
.summary{font-size:15px}
.badge{display:inline-block;padding:0 7px;border-radius:9px;font-size:12px;font-weight:600;color:#fff;vertical-align:1px}
.badge.failed{background:#c62828}.badge.passed{background:#2e7d32}.badge.bonus{background:#8a6d00}
table.list{border-collapse:collapse;background:#fff;box-shadow:0 1px 2px #0002}
table.list td,table.list th{padding:3px 10px;border-bottom:1px solid #e4e6ea;text-align:left;vertical-align:top}
table.list tr.failed td:first-child{border-left:4px solid #c62828}
table.list tr.passed td:first-child{border-left:4px solid #2e7d32}
.legend{display:flex;flex-wrap:wrap;gap:4px 18px;margin:10px 0 18px;font-size:13px}
.legend svg{vertical-align:middle}
.case{background:#fff;border-radius:6px;box-shadow:0 1px 3px #0002;margin:18px 0;padding:12px 14px}
.case.failed{border-left:5px solid #c62828}.case.passed{border-left:5px solid #2e7d32}
.case>summary{cursor:pointer;font-weight:600}
.meta{color:#555;margin:0 0 8px}
.body{display:flex;flex-wrap:wrap;gap:14px;align-items:flex-start}
.log{flex:1 1 380px;min-width:320px;max-width:560px}
.log ol{list-style:none;margin:0;padding:8px 10px;background:#f3f4f6;border-radius:4px;font:12.5px/1.45 ui-monospace,Menlo,Consolas,monospace;white-space:pre-wrap;overflow-wrap:anywhere}
.log li.info{color:#59636e}
.log li.warn{color:#b71c1c;font-weight:600}
.log li.detail{padding-left:2em;color:#1b1f24}
.log li.hint{background:#fff3bf;border-left:3px solid #f08c00;padding:2px 4px 2px calc(2em - 3px);font-weight:600;margin:2px 0}
.verdict{font-weight:600;color:#b71c1c;margin:0 0 6px}
.files a{margin-right:10px}
.notes{color:#6d4c00;font-size:13px;margin:6px 0 0;padding-left:18px}
table.pics{border-collapse:collapse}
table.pics th{font-size:12px;font-weight:600;color:#444;padding:2px 4px;text-align:center}
table.pics th.row{text-align:right;width:64px;font-weight:400}
table.pics td{padding:2px}
td.none{width:230px;vertical-align:top;text-align:center;color:#777;background:#fafafa;border:1px dashed #ccc;font-size:13px;padding:10px}
svg.view{background:#fff;border:1px solid #dde1e6;border-radius:3px;display:block}
svg.view .faces{stroke:#2a3a4f;stroke-opacity:.55;stroke-linejoin:round}
svg.view .loose{fill:none;stroke:#41536b;stroke-width:.8}
svg.view .loose.behind{stroke-opacity:.3;stroke-dasharray:2 2}
svg.view .dots{fill:none;stroke:#1d2733;stroke-width:3.2;stroke-linecap:round}
svg.view .dots.small{stroke-width:2}
svg.view .case-edge{stroke:#ef6c00;stroke-width:3.2;stroke-linecap:round}
svg.view .case-vertex{fill:none;stroke:#ef6c00;stroke-width:2.2}
svg.view .named path,svg.view .named circle{fill:none;stroke:#8e24aa;stroke-width:3;stroke-opacity:.75;stroke-linejoin:round;stroke-linecap:round}
svg.view .named text{font:bold 10px ui-monospace,Menlo,Consolas,monospace;fill:#8e24aa;paint-order:stroke;stroke:#fff;stroke-width:3px}
svg.view .wrong.edge{fill:none;stroke:#e00000;stroke-width:2.2;stroke-linecap:round}
svg.view .wrong.edge.ghost{stroke-width:1.6;stroke-dasharray:4 3}
svg.view .wrong.edge.move{stroke-width:1;stroke-dasharray:2 2}
svg.view circle.wrong.vertex{fill:#e00000;stroke:#fff;stroke-width:1}
svg.view path.wrong.vertex{fill:none;stroke:#e00000;stroke-width:5;stroke-linecap:round}
svg.view circle.wrong.ghost{fill:none;stroke:#e00000;stroke-width:1.6;stroke-dasharray:3 2}
svg.view .behind{opacity:.45}
svg.view .labels{font:9px ui-monospace,Menlo,Consolas,monospace;fill:#1d2733;paint-order:stroke;stroke:#fff;stroke-width:2.5px;stroke-linejoin:round}
svg.view .labels .red{fill:#c00000;font-weight:700}
details.output pre{max-height:16em;overflow:auto;background:#f3f4f6;padding:6px}
pre.quote{margin:2px 0;white-space:pre-wrap}
"#;

/// The legend, drawn with the pictures' own classes.
fn legend() -> String {
    let item = |svg: &str, text: &str| {
        format!(
            "<span><svg class=\"view\" width=\"34\" height=\"16\" viewBox=\"0 0 34 16\" style=\"display:inline;border:0;background:none\">{svg}</svg> {text}</span>"
        )
    };
    [
        item("<circle cx=\"17\" cy=\"8\" r=\"3.2\" class=\"wrong vertex\"/>", "a vertex of yours that no expected vertex matches (in <i>yours</i>), an expected vertex no vertex of yours matches (in <i>expected</i>)"),
        item("<circle cx=\"17\" cy=\"8\" r=\"4\" class=\"wrong vertex ghost\"/>", "where that expected vertex is"),
        item("<line x1=\"3\" y1=\"8\" x2=\"31\" y2=\"8\" class=\"wrong edge\"/>", "an edge of yours that is not expected (in <i>yours</i>), an expected edge you lack (in <i>expected</i>)"),
        item("<line x1=\"3\" y1=\"8\" x2=\"31\" y2=\"8\" class=\"wrong edge ghost\"/>", "where that missing edge should be"),
        item("<line x1=\"3\" y1=\"8\" x2=\"31\" y2=\"8\" class=\"wrong edge move\"/>", "from a vertex of yours to where it should be"),
        item("<line x1=\"3\" y1=\"8\" x2=\"31\" y2=\"8\" class=\"case-edge\"/>", "the case's edge (flipped, split or refused), or its new vertex"),
        item("<g class=\"named\"><path d=\"M3 8h28\"/></g>", "an element the messages name (<code>v7</code>, <code>e229</code>, <code>h40</code>, <code>f3</code>), labelled"),
        item("<rect x=\"4\" y=\"2\" width=\"26\" height=\"12\" fill=\"#f0dfbf\" stroke=\"#2a3a4f\" stroke-opacity=\".55\"/>", "the back of a face (seen through a hole)"),
        "<span>faded: behind the surface in that view. <code>v7</code>: your vertex ids (meshes under 60 vertices); hover a red mark for where it is</span>".to_string(),
    ]
    .join("\n")
}

fn case_html(html: &mut String, f: &Fixture, r: &CaseReport, files: &[(&str, String)]) {
    let verdict = if r.passed { "passed" } else { "failed" };
    let pics = pictures(f, r);
    let group = match f.group {
        Group::Lab => "lab case",
        Group::Hidden => "hidden case",
        Group::Bonus => "bonus case (counted only with --bonus)",
    };
    let _ = write!(
        html,
        "<section class=\"case {verdict}\" id=\"case-{0}\" data-case=\"{0}\">\n<h2><span class=\"badge {verdict}\">{verdict}</span> {0}</h2>\n<p class=\"meta\">{1} · {group} · tolerance {2}</p>\n<div class=\"body\">\n<div class=\"log\">\n",
        escape(&f.name),
        escape(&operation(f)),
        f.tolerance
    );
    if let Some(w) = first_warning_shown(r) {
        let _ = writeln!(html, "<p class=\"verdict\">{}</p>", escape(&w));
    }
    html.push_str("<ol>");
    for e in &r.entries {
        let class = match e.level {
            Level::Info => "info",
            Level::Warn => "warn",
            Level::Detail if e.text.starts_with("hint:") => "detail hint",
            Level::Detail => "detail",
        };
        let below = e.quote_below("");
        let _ = write!(html, "<li class=\"{class}\">{}", escape(&e.one_line()));
        if !below.is_empty() {
            let _ = write!(html, "<pre class=\"quote\">{}</pre>", escape(&below));
        }
        html.push_str("</li>");
    }
    html.push_str("</ol>\n<p class=\"files\">OBJ files: ");
    for (what, name) in files {
        let _ = write!(html, "<a href=\"{0}\">{1}</a>", escape(name), what);
    }
    html.push_str("</p>\n");
    if !r.output.is_blank() {
        // Each line under `| `, control characters escaped, as everywhere.
        let all = r.output.block("");
        let lines = all.lines().count();
        let mut shown: String = all.chars().take(OUTPUT_LIMIT).collect();
        if shown.len() < all.len() {
            shown.push_str("\n… (cut)");
        }
        let _ = writeln!(
            html,
            "<details class=\"output\"><summary>what your code printed ({lines} lines)</summary><pre>{}</pre></details>",
            escape(&shown)
        );
    }
    if !pics.notes.is_empty() {
        html.push_str("<ul class=\"notes\">");
        for n in &pics.notes {
            let _ = write!(html, "<li>{}</li>", escape(n));
        }
        html.push_str("</ul>\n");
    }
    html.push_str("</div>\n");

    // Pictures: a row per view; columns input, expected (failed cases
    // only: on a pass it is the same as yours), yours.
    let input = Prepared::new(&pics.input);
    let expected = Prepared::new(&pics.expected);
    let yours = pics.yours.as_ref().map(Prepared::new);
    let show_expected = !r.passed;
    html.push_str("<table class=\"pics\"><thead><tr><th></th><th>input (as sent)</th>");
    if show_expected {
        let what = match f.expected.returns {
            Some(Returns::Refused) => "expected<br><small>unchanged: it must return None</small>",
            Some(Returns::Panic) => "expected<br><small>unchanged: it must panic</small>",
            _ => "expected",
        };
        let _ = write!(html, "<th>{what}</th>");
    }
    html.push_str("<th>yours</th></tr></thead><tbody>\n");
    // A passing case needs fewer pictures: the first view and the opposite.
    let views: Vec<(usize, &View)> = pics
        .cameras
        .iter()
        .enumerate()
        .filter(|(k, _)| !r.passed || *k != 1)
        .collect();
    for &(k, view) in &views {
        let _ = write!(
            html,
            "<tr><th class=\"row\">view {}<br><small>{}</small></th><td class=\"input\">",
            k + 1,
            view.why
        );
        draw(
            html,
            &view.input,
            &input,
            &pics.marks_input,
            &format!("input, view {}", k + 1),
        );
        html.push_str("</td>");
        if show_expected {
            html.push_str("<td class=\"expected\">");
            draw(
                html,
                &view.result,
                &expected,
                &pics.marks_expected,
                &format!("expected result, view {}", k + 1),
            );
            html.push_str("</td>");
        }
        match &yours {
            Some(y) => {
                html.push_str("<td class=\"yours\">");
                draw(
                    html,
                    &view.result,
                    y,
                    &pics.marks_yours,
                    &format!("your result, view {}", k + 1),
                );
                html.push_str("</td>");
            }
            None if k == views[0].0 => {
                let why = first_warning_shown(r)
                    .unwrap_or_else(|| "the function did not return a mesh".to_string());
                let _ = write!(
                    html,
                    "<td class=\"yours none\" rowspan=\"{}\">no mesh to show:<br>{}</td>",
                    views.len(),
                    escape(&why)
                );
            }
            None => {}
        }
        html.push_str("</tr>\n");
    }
    html.push_str("</tbody></table>\n</div>\n</section>\n");
}

/// Writes the report for `cases` into `dir` (created if needed) and returns
/// the path of its `index.html`.
pub fn write_report(dir: &Path, cases: &[(&Fixture, &CaseReport)]) -> Result<PathBuf, String> {
    write_report_live(dir, cases, false)
}

/// The file a live report polls: its stamp changes with every rewrite.
pub const STAMP_FILE: &str = "watch-stamp.js";

/// Reloads the page when the stamp [`STAMP_FILE`] sets changes: a script
/// element, not `fetch`, which pages opened from `file://` may not use.
const LIVE_SCRIPT: &str = "<script src=\"watch-stamp.js\"></script>\n<script>\n// Written by --watch: reload when the grader rewrites this report.\n(function () {\n  var first = window.meshlabStamp;\n  setInterval(function () {\n    var s = document.createElement('script');\n    s.src = 'watch-stamp.js?' + Date.now();\n    s.onload = function () { s.remove(); if (window.meshlabStamp !== first) location.reload(); };\n    s.onerror = function () { s.remove(); };\n    document.head.appendChild(s);\n  }, 1000);\n})();\n</script>\n";

/// [`write_report`], and with `live` (under `--watch`) a page that reloads
/// itself when a later run rewrites it.
pub fn write_report_live(
    dir: &Path,
    cases: &[(&Fixture, &CaseReport)],
    live: bool,
) -> Result<PathBuf, String> {
    let io = |p: &Path, e: std::io::Error| format!("{}: {e}", p.display());
    std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    // Failing cases first, the counted ones before the bonus; otherwise in
    // the grader's order.
    let mut order: Vec<&(&Fixture, &CaseReport)> = cases.iter().collect();
    order.sort_by_key(|(f, r)| (r.passed, f.group == Group::Bonus));
    let failed = order.iter().filter(|(_, r)| !r.passed).count();

    let mut list = String::new();
    let mut body = String::new();
    for &&(f, r) in &order {
        let write = |name: String, text: String| -> Result<String, String> {
            let path = dir.join(&name);
            std::fs::write(&path, text).map_err(|e| io(&path, e))?;
            Ok(name)
        };
        let expected_shape = Shape::expected(f);
        let mut files = Vec::new();
        if let Some(input) = &r.input {
            files.push((
                "input",
                write(format!("{}.input.obj", f.name), input.to_obj_string())?,
            ));
        }
        files.push((
            "expected",
            write(
                format!("{}.expected.obj", f.name),
                expected_obj(f, &expected_shape),
            )?,
        ));
        if let Some(result) = &r.result {
            let shape = Shape::from_mesh(result);
            files.push((
                "yours",
                write(
                    format!("{}.yours.obj", f.name),
                    yours_obj(f, result, &shape),
                )?,
            ));
        }
        let verdict = if r.passed { "passed" } else { "failed" };
        let bonus = if f.group == Group::Bonus {
            " <span class=\"badge bonus\">bonus</span>"
        } else {
            ""
        };
        let _ = writeln!(
            list,
            "<tr class=\"{verdict}\"><td><span class=\"badge {verdict}\">{verdict}</span>{bonus}</td><td><a href=\"#case-{0}\">{0}</a></td><td>{1}</td><td>{2}</td></tr>",
            escape(&f.name),
            escape(&operation(f)),
            escape(&first_warning_shown(r).unwrap_or_default())
        );
        case_html(&mut body, f, r, &files);
    }

    let mut html = String::with_capacity(body.len() + list.len() + 8192);
    let _ = write!(
        html,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>grader report: {failed} of {} failed</title>\n<style>{STYLE}{}</style>\n{}</head><body>\n<h1>Grader report</h1>\n",
        order.len(),
        shade_css(),
        if live { LIVE_SCRIPT } else { "" }
    );
    let summary = if failed == 0 {
        format!("All {} cases passed.", order.len())
    } else {
        format!(
            "{failed} of {} cases failed; they come first. Start with the first one: later functions build on earlier ones.",
            order.len()
        )
    };
    let _ = writeln!(html, "<p class=\"summary\">{}</p>", escape(&summary));
    let _ = writeln!(
        html,
        "<table class=\"list\" id=\"cases\"><thead><tr><th>verdict</th><th>case</th><th>what</th><th>first problem</th></tr></thead><tbody>\n{list}</tbody></table>"
    );
    let _ = writeln!(html, "<div class=\"legend\">{}</div>", legend());
    html.push_str(&body);
    html.push_str("</body></html>\n");
    let index = dir.join("index.html");
    std::fs::write(&index, html).map_err(|e| io(&index, e))?;
    if live {
        // Written after the page, so a reload finds the new one.
        let stamp = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let path = dir.join(STAMP_FILE);
        std::fs::write(&path, format!("window.meshlabStamp = \"{stamp}\";\n"))
            .map_err(|e| io(&path, e))?;
    }
    Ok(index)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grade::Entry;
    use crate::relabel::Rng;
    use halfedge::{Edge, EdgeId, Face, FaceId, Halfedge, HalfedgeId, Vertex, VertexId};

    fn fixtures_root() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
    }

    fn fixture(name: &str) -> Fixture {
        crate::fixture::load_all(&fixtures_root())
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
            end: crate::grade::CaseEnd::JudgeFailed,
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
        assert!(!plain.contains("<script"), "no script without --watch");
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
        assert!(!html.contains("<script>") && !html.contains("<b>"));
        assert!(html.contains("printed &lt;b&gt;") && html.contains("… (cut)"));
        assert!(html.contains("no mesh to show"));
    }

    #[test]
    fn expected_faces_are_rebuilt_for_every_fixture() {
        for f in crate::fixture::load_all(&fixtures_root()).unwrap() {
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
    fn element_names_are_found_in_messages() {
        let names = element_names(&[
            "v8 is at (1, 2); A vertex's halfedge (e229), h40 and f3",
            "between v9 and v10, v8 again; not: ev3, v3x, mesh[e].halfedge",
        ]);
        assert_eq!(
            names,
            vec![
                ('v', 8),
                ('e', 229),
                ('h', 40),
                ('f', 3),
                ('v', 9),
                ('v', 10)
            ]
        );
    }

    #[test]
    fn a_misplaced_vertex_is_paired_and_its_edges_are_not_called_wrong() {
        let f = fixture("cube-split");
        let expected = Shape::expected(&f);
        let mut yours = expected.clone();
        let new = f.input.positions.len();
        yours.points[new] = Some(DVec3::new(9.0, 9.0, 9.0));
        let c = compare(&f, &yours, &expected);
        assert_eq!(c.matched[new], None);
        assert_eq!(c.unmatched_expected, vec![new]);
        assert_eq!(c.displaced[new], Some(new));
        assert!(c.missing.is_empty() && c.extra.is_empty());
        // An edge moved: one missing, one extra.
        let gone = yours.edges.pop().unwrap();
        let new_edge = (0..yours.len())
            .map(|b| pair(gone[0], b))
            .find(|e| e[0] != e[1] && *e != gone && !yours.edges.contains(e))
            .unwrap();
        yours.edges.push(new_edge);
        let c = compare(&f, &yours, &expected);
        assert_eq!(c.missing, vec![gone]);
        assert_eq!(c.extra.len(), 1);
    }
}
