//! Order-independent comparison of a result with the expected one.
//!
//! Student vertices are matched to expected vertices by position, one to
//! one, within the tolerance, through a hash grid of cells two tolerances
//! wide (so each lookup checks at most 8 cells: linear time overall).
//! Edges are then compared as unordered pairs of matched expected indices.
//!
//! Where vertices coincide (an unwelded seam, two shells touching), position
//! alone cannot tell them apart: [`match_by_neighbourhood`] settles those
//! by which matched neighbours they have.
//!
//! This runs for every labelling of every case in the dev profile students
//! build (unoptimised): the grid is kept cheap per lookup for that reason.

use std::collections::{BTreeSet, HashMap};
use std::hash::{BuildHasherDefault, Hash, Hasher};

type P = [f64; 3];

fn dist(a: P, b: P) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// A grid cell's coordinates, hashed in one multiply.
#[derive(Clone, Copy, PartialEq, Eq)]
struct Cell([i64; 3]);

impl Cell {
    fn of(p: P, size: f64) -> Cell {
        // `as` saturates: a finite but huge coordinate (1e300) has a cell
        // at the end of i64's range, a NaN cell 0.
        Cell(p.map(|x| (x / size).floor() as i64))
    }
}

impl Hash for Cell {
    fn hash<H: Hasher>(&self, state: &mut H) {
        let [x, y, z] = self.0.map(|c| c as u64);
        state.write_u64(
            x.wrapping_mul(0x9e37_79b9_7f4a_7c15)
                ^ y.wrapping_mul(0xc2b2_ae3d_27d4_eb4f).rotate_left(21)
                ^ z.wrapping_mul(0x1656_67b1_9e37_79f9).rotate_left(42),
        );
    }
}

/// Passes on the one word a [`Cell`] writes. The grid holds the fixture's
/// points, not the student's, so SipHash's defence against chosen keys buys
/// nothing here, and unoptimised it was most of the matching's time.
#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write_u64(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(29) ^ word).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }
}

/// Expected positions bucketed by grid cell.
struct Grid {
    size: f64,
    /// How far around a point [`Grid::near`] looks: the tolerance and a
    /// little more, so that no point `dist` accepts is in a cell left out.
    reach: f64,
    cells: HashMap<Cell, Vec<usize>, BuildHasherDefault<CellHasher>>,
}

impl Grid {
    fn new(points: &[P], tolerance: f64) -> Grid {
        let size = 2.0 * tolerance;
        let mut cells: HashMap<Cell, Vec<usize>, _> = HashMap::default();
        for (i, &p) in points.iter().enumerate() {
            cells.entry(Cell::of(p, size)).or_default().push(i);
        }
        Grid {
            size,
            reach: tolerance * (1.0 + 1e-9),
            cells,
        }
    }

    /// Indices of points in the cells that `p`'s reach overlaps: 2 per
    /// axis with cells two tolerances wide (3 only where rounding says
    /// so), 1 where the reach lies within one cell.
    fn near(&self, p: P) -> impl Iterator<Item = usize> + '_ {
        let lo = Cell::of(p.map(|x| x - self.reach), self.size).0;
        let hi = Cell::of(p.map(|x| x + self.reach), self.size).0;
        (lo[0]..=hi[0]).flat_map(move |x| {
            (lo[1]..=hi[1]).flat_map(move |y| {
                (lo[2]..=hi[2]).flat_map(move |z| {
                    self.cells
                        .get(&Cell([x, y, z]))
                        .into_iter()
                        .flatten()
                        .copied()
                })
            })
        })
    }
}

/// The result of matching student vertices to expected ones.
#[derive(Clone, Debug, PartialEq)]
pub struct VertexMatch {
    /// For each student vertex, the expected vertex it matched.
    pub to_expected: Vec<Option<usize>>,
    /// Expected vertices no student vertex matched, in index order.
    pub unmatched_expected: Vec<usize>,
}

impl VertexMatch {
    pub fn is_perfect(&self) -> bool {
        self.unmatched_expected.is_empty() && self.to_expected.iter().all(Option::is_some)
    }
}

/// Matches each student position to the nearest unmatched expected position
/// within `tolerance`.
pub fn match_vertices(student: &[P], expected: &[P], tolerance: f64) -> VertexMatch {
    let grid = Grid::new(expected, tolerance);
    let mut taken = vec![false; expected.len()];
    let to_expected = student
        .iter()
        .map(|&p| {
            let best = grid
                .near(p)
                .filter(|&i| !taken[i])
                .map(|i| (dist(p, expected[i]), i))
                .filter(|&(d, _)| d <= tolerance)
                .min_by(|a, b| a.0.total_cmp(&b.0))?;
            taken[best.1] = true;
            Some(best.1)
        })
        .collect();
    let unmatched_expected = (0..expected.len()).filter(|&i| !taken[i]).collect();
    VertexMatch {
        to_expected,
        unmatched_expected,
    }
}

/// Each vertex's neighbours, sorted and without repeats; edges naming a
/// vertex past `n` are left out (a student's result may hold any ids).
pub fn adjacency(n: usize, edges: &[[usize; 2]]) -> Vec<Vec<usize>> {
    let mut adj = vec![Vec::new(); n];
    for &[a, b] in edges {
        if a < n && b < n {
            adj[a].push(b);
            adj[b].push(a);
        }
    }
    for list in &mut adj {
        list.sort_unstable();
        list.dedup();
    }
    adj
}

/// Above this many vertices with more than one candidate, neighbourhoods
/// are not consulted (each settled pair costs a pass over the rest).
const MAX_AMBIGUOUS: usize = 4000;

/// Matches student vertices to expected ones by position and, where
/// several expected vertices lie within `tolerance` of a student vertex, by
/// neighbourhood: each such vertex takes the candidate that shares the most
/// already-matched neighbours with it. Most-certain pairs are settled first,
/// so a seam is resolved from its unambiguous surroundings inward.
pub fn match_by_neighbourhood(
    student: &[P],
    student_edges: &[[usize; 2]],
    expected: &[P],
    expected_edges: &[[usize; 2]],
    tolerance: f64,
) -> VertexMatch {
    let grid = Grid::new(expected, tolerance);
    let candidates: Vec<Vec<usize>> = student
        .iter()
        .map(|&p| {
            grid.near(p)
                .filter(|&i| dist(p, expected[i]) <= tolerance)
                .collect()
        })
        .collect();
    let ambiguous = candidates.iter().filter(|c| c.len() > 1).count();
    if ambiguous > MAX_AMBIGUOUS {
        return match_vertices(student, expected, tolerance);
    }
    let mut to_expected: Vec<Option<usize>> = vec![None; student.len()];
    let mut taken = vec![false; expected.len()];
    // Unique candidates first. With no ambiguity this is all of it, and
    // what `match_vertices` would give: each vertex takes its one
    // candidate unless an earlier vertex took it.
    for (s, c) in candidates.iter().enumerate() {
        if let [x] = c[..] {
            if !taken[x] {
                taken[x] = true;
                to_expected[s] = Some(x);
            }
        }
    }
    if ambiguous > 0 {
        let mine = adjacency(student.len(), student_edges);
        let theirs = adjacency(expected.len(), expected_edges);
        let mut open: Vec<usize> = (0..student.len())
            .filter(|&s| to_expected[s].is_none() && !candidates[s].is_empty())
            .collect();
        while !open.is_empty() {
            // The pair with the most matched neighbours in common, then the nearest.
            let mut best: Option<(usize, f64, usize, usize)> = None;
            for (k, &s) in open.iter().enumerate() {
                for &x in candidates[s].iter().filter(|&&x| !taken[x]) {
                    let shared = mine[s]
                        .iter()
                        .filter(|&&n| to_expected[n].is_some_and(|m| theirs[x].contains(&m)))
                        .count();
                    let d = dist(student[s], expected[x]);
                    let better =
                        best.is_none_or(|(bs, bd, _, _)| shared > bs || (shared == bs && d < bd));
                    if better {
                        best = Some((shared, d, k, x));
                    }
                }
            }
            let Some((_, _, k, x)) = best else {
                break;
            };
            let s = open.swap_remove(k);
            taken[x] = true;
            to_expected[s] = Some(x);
        }
    }
    let unmatched_expected = (0..expected.len()).filter(|&i| !taken[i]).collect();
    VertexMatch {
        to_expected,
        unmatched_expected,
    }
}

/// The student vertex nearest to `p`: (index, distance).
pub fn nearest(student: &[P], p: P) -> Option<(usize, f64)> {
    student
        .iter()
        .enumerate()
        .map(|(i, &q)| (i, dist(p, q)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Whether every position is within `tolerance` of a distinct expected one.
pub fn same_positions(student: &[P], expected: &[P], tolerance: f64) -> bool {
    student.len() == expected.len() && match_vertices(student, expected, tolerance).is_perfect()
}

fn pair(a: usize, b: usize) -> [usize; 2] {
    [a.min(b), a.max(b)]
}

/// Student edges renamed to expected vertex indices (with a perfect match).
pub fn mapped_edges(student_edges: &[[usize; 2]], m: &VertexMatch) -> BTreeSet<[usize; 2]> {
    student_edges
        .iter()
        .filter_map(|&[a, b]| {
            let a = (*m.to_expected.get(a)?)?;
            let b = (*m.to_expected.get(b)?)?;
            Some(pair(a, b))
        })
        .collect()
}

/// Edges of one side missing from the other, each sorted.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EdgeDiff {
    pub missing: Vec<[usize; 2]>,
    pub extra: Vec<[usize; 2]>,
}

impl EdgeDiff {
    pub fn is_empty(&self) -> bool {
        self.missing.is_empty() && self.extra.is_empty()
    }
}

/// Compares student edges (already in expected numbering) with expected edges.
pub fn diff_edges(student: &BTreeSet<[usize; 2]>, expected: &[[usize; 2]]) -> EdgeDiff {
    let expected: BTreeSet<[usize; 2]> = expected.iter().map(|&[a, b]| pair(a, b)).collect();
    EdgeDiff {
        missing: expected.difference(student).copied().collect(),
        extra: student.difference(&expected).copied().collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_in_any_order_within_tolerance() {
        let expected = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let student = [[0.0, 1.0, 0.0], [1.0 + 4e-6, 0.0, 0.0], [0.0, 0.0, -3e-6]];
        let m = match_vertices(&student, &expected, 1e-5);
        assert_eq!(m.to_expected, vec![Some(2), Some(1), Some(0)]);
        assert!(m.is_perfect());
    }

    #[test]
    fn a_vertex_just_past_the_tolerance_does_not_match() {
        let expected = [[0.5, 0.5, 0.5]];
        let m = match_vertices(&[[0.5 + 1.1e-5, 0.5, 0.5]], &expected, 1e-5);
        assert_eq!(m.to_expected, vec![None]);
        assert_eq!(m.unmatched_expected, vec![0]);
    }

    #[test]
    fn matching_is_one_to_one() {
        // Two student vertices on the same expected point: only one matches.
        let expected = [[0.0; 3], [1.0, 0.0, 0.0]];
        let m = match_vertices(&[[0.0; 3], [0.0; 3]], &expected, 1e-5);
        assert_eq!(m.to_expected, vec![Some(0), None]);
        assert_eq!(m.unmatched_expected, vec![1]);
        assert!(!same_positions(&[[0.0; 3], [0.0; 3]], &expected, 1e-5));
    }

    #[test]
    fn points_across_a_cell_border_still_match() {
        // 1e-5 cells: 2.9999999e-5 and 3.0000001e-5 lie in different cells.
        let expected = [[2.9999999e-5, 0.0, 0.0]];
        let m = match_vertices(&[[3.0000001e-5, 0.0, 0.0]], &expected, 1e-5);
        assert!(m.is_perfect());
    }

    #[test]
    fn edge_diff_names_missing_and_extra() {
        let m = VertexMatch {
            to_expected: vec![Some(2), Some(0), Some(1)],
            unmatched_expected: vec![],
        };
        // Student edges 0-1, 1-2 are expected 0-2, 0-1.
        let got = mapped_edges(&[[0, 1], [1, 2]], &m);
        let d = diff_edges(&got, &[[0, 1], [1, 2]]);
        assert_eq!(d.missing, vec![[1, 2]]);
        assert_eq!(d.extra, vec![[0, 2]]);
        assert!(diff_edges(&got, &[[0, 2], [0, 1]]).is_empty());
    }

    #[test]
    fn coincident_vertices_are_told_apart_by_their_neighbours() {
        // Two triangles touching at the origin through two distinct vertices
        // (0 and 3), listed so that position order pairs them the wrong way.
        let expected = [
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0; 3],
            [-1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
        ];
        let expected_edges = [[0, 1], [1, 2], [0, 2], [3, 4], [4, 5], [3, 5]];
        // The student's copy numbers the second triangle's origin first.
        let student = [
            [0.0; 3],
            [-1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let student_edges = [[0, 1], [1, 2], [0, 2], [3, 4], [4, 5], [3, 5]];
        let greedy = match_vertices(&student, &expected, 1e-5);
        let by_position = mapped_edges(&student_edges, &greedy);
        assert!(
            !diff_edges(&by_position, &expected_edges).is_empty(),
            "greedy pairs them wrongly"
        );
        let m = match_by_neighbourhood(&student, &student_edges, &expected, &expected_edges, 1e-5);
        assert!(m.is_perfect());
        assert_eq!(m.to_expected[0], Some(3));
        assert_eq!(m.to_expected[3], Some(0));
        assert!(diff_edges(&mapped_edges(&student_edges, &m), &expected_edges).is_empty());
    }

    #[test]
    fn huge_coordinates_do_not_overflow_the_grid() {
        let expected = [[0.0; 3], [1.0, 0.0, 0.0]];
        let student = [[1e300, -1e300, 0.0], [1.0, 0.0, 0.0]];
        let m = match_vertices(&student, &expected, 1e-5);
        assert_eq!(m.to_expected, vec![None, Some(1)]);
        let m = match_by_neighbourhood(&student, &[[0, 1]], &expected, &[[0, 1]], 1e-5);
        assert_eq!(m.unmatched_expected, vec![0]);
    }

    /// A small deterministic generator: the tests need many points, not
    /// a dependency.
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn the_grid_finds_every_point_within_the_tolerance() {
        let tol = 1e-5;
        let mut seed = 7;
        // Points on and around cell borders (multiples of 2 tol), and
        // queries at up to the tolerance from them in every direction.
        let expected: Vec<P> = (0..400)
            .map(|_| {
                [0, 1, 2].map(|_| {
                    (lcg(&mut seed) * 20.0).round() * 2.0 * tol + (lcg(&mut seed) - 0.5) * 1e-12
                })
            })
            .collect();
        let grid = Grid::new(&expected, tol);
        for _ in 0..4000 {
            let base = expected[(lcg(&mut seed) * 400.0) as usize];
            let r = tol * (0.9 + 0.1 * lcg(&mut seed));
            let q = [0, 1, 2].map(|k| {
                base[k]
                    + r * (lcg(&mut seed) - 0.5) * 2.0 / 3f64.sqrt()
                        * if k == 0 { 1.0 } else { -1.0 }
            });
            let mut brute: Vec<usize> = (0..expected.len())
                .filter(|&i| dist(q, expected[i]) <= tol)
                .collect();
            let mut found: Vec<usize> = grid
                .near(q)
                .filter(|&i| dist(q, expected[i]) <= tol)
                .collect();
            brute.sort_unstable();
            found.sort_unstable();
            assert!(!brute.is_empty());
            assert_eq!(found, brute, "query {q:?}");
        }
    }

    #[test]
    fn without_coincident_vertices_neighbourhoods_change_nothing() {
        // Distinct expected points; the student has some twice (so one of
        // the two finds its only candidate taken) and some off by far.
        let tol = 1e-5;
        let mut seed = 11;
        let expected: Vec<P> = (0..300)
            .map(|_| [0, 1, 2].map(|_| lcg(&mut seed)))
            .collect();
        let student: Vec<P> = (0..300)
            .map(|i| match i % 7 {
                0 => expected[(i + 1) % 300],
                1 => [2.0 + lcg(&mut seed), 0.0, 0.0],
                _ => expected[(i * 37) % 300].map(|x| x + (lcg(&mut seed) - 0.5) * tol),
            })
            .collect();
        let edges = [[0, 1], [1, 2]];
        assert_eq!(
            match_by_neighbourhood(&student, &edges, &expected, &edges, tol),
            match_vertices(&student, &expected, tol)
        );
    }

    #[test]
    fn nearest_finds_the_closest() {
        let s = [[0.0; 3], [2.0, 0.0, 0.0]];
        assert_eq!(nearest(&s, [1.5, 0.0, 0.0]), Some((1, 0.5)));
        assert_eq!(nearest(&[], [0.0; 3]), None);
    }
}
