//! Rebuilding what can be drawn of a mesh: the positions, edges and faces
//! of whatever the student's code left (every id bounds-checked, every walk
//! bounded), of the fixture's indexed input, and of the expected result,
//! whose faces fixtures do not keep and which are rebuilt from its edges.

use std::collections::{BTreeSet, HashMap, HashSet, VecDeque};

use halfedge::{DVec3, Mesh};

use super::{pair, sides};
use crate::judge::fixture::Fixture;

/// A face whose `next` walk is longer than this is not drawn.
pub(super) const MAX_DEGREE: usize = 64;

/// A mesh reduced to what a picture needs. Every index is in range.
#[derive(Clone, Debug, Default)]
pub(super) struct Shape {
    /// Positions by vertex id; `None` when not finite.
    pub(super) points: Vec<Option<DVec3>>,
    /// Distinct edges, smaller index first.
    pub(super) edges: Vec<[usize; 2]>,
    /// Polygons, each in its winding order.
    pub(super) faces: Vec<Vec<usize>>,
}

impl Shape {
    /// What can be drawn of a mesh the student's code left, valid or not:
    /// the positions, an edge for each halfedge whose twin and vertices are
    /// in range, and each real face whose `next` walk comes back to its start
    /// through halfedges of that face.
    pub(super) fn from_mesh(mesh: &Mesh) -> Shape {
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
    pub(super) fn from_faces(positions: &[[f64; 3]], faces: &[Vec<usize>]) -> Shape {
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
    pub(super) fn expected(f: &Fixture) -> Shape {
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

    pub(super) fn len(&self) -> usize {
        self.points.len()
    }

    pub(super) fn point(&self, i: usize) -> Option<DVec3> {
        self.points.get(i).copied().flatten()
    }

    /// The centre and radius of the finite points' bounding box.
    pub(super) fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut pts = self.points.iter().flatten();
        let first = *pts.next()?;
        Some(pts.fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))))
    }

    /// Area-weighted normal of a face (Newell's method), if drawable.
    pub(super) fn face_normal(&self, face: &[usize]) -> Option<DVec3> {
        let pts: Vec<DVec3> = face.iter().map(|&v| self.point(v)).collect::<Option<_>>()?;
        let mut n = DVec3::ZERO;
        for i in 0..pts.len() {
            n += pts[i].cross(pts[(i + 1) % pts.len()]);
        }
        Some(n * 0.5)
    }

    pub(super) fn face_center(&self, face: &[usize]) -> Option<DVec3> {
        let sum = face.iter().map(|&v| self.point(v)).sum::<Option<DVec3>>()?;
        Some(sum / face.len() as f64)
    }

    /// `(Σ (centre_f - c)·N_f, Σ N_f)` over `faces` (indices into
    /// `self.faces`): three times the enclosed volume for a closed surface,
    /// positive when the faces wind counter-clockwise seen from outside;
    /// the summed normal tells an open sheet's side.
    pub(super) fn orientation(&self, faces: &[usize]) -> (f64, DVec3) {
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
    pub(super) fn is_closed(&self) -> bool {
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

pub(super) fn finite(p: [f64; 3]) -> Option<DVec3> {
    let p = DVec3::from_array(p);
    p.is_finite().then_some(p)
}

/// Faces for the expected result, which fixtures keep only as edges: the
/// input's faces whose sides are all still edges, then triangles of the
/// edge graph, smallest first, while each edge has fewer than two faces.
/// Faces are wound like their neighbours, and each piece like the input.
pub(super) fn rebuild_faces(
    input: &Shape,
    points: &[Option<DVec3>],
    edges: &[[usize; 2]],
) -> Vec<Vec<usize>> {
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
pub(super) fn orient(
    faces: &mut [Vec<usize>],
    kept: usize,
    input: &Shape,
    points: &[Option<DVec3>],
) {
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
