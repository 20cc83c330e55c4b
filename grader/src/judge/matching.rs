//! Order-independent comparison of a result with the expected one.
//!
//! Student vertices are matched to expected vertices by position, one to
//! one, within the tolerance, through a hash grid of cells one tolerance
//! wide (so each lookup checks 27 cells: linear time overall). Edges are
//! then compared as unordered pairs of matched expected indices.
//!
//! Where vertices coincide (an unwelded seam, two shells touching), position
//! alone cannot tell them apart: [`match_by_neighbourhood`] settles those
//! by which matched neighbours they have.

use std::collections::{BTreeSet, HashMap};

type P = [f64; 3];

fn dist(a: P, b: P) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn cell(p: P, size: f64) -> [i64; 3] {
    p.map(|x| (x / size).floor() as i64)
}

/// Expected positions bucketed by grid cell.
struct Grid {
    size: f64,
    cells: HashMap<[i64; 3], Vec<usize>>,
}

impl Grid {
    fn new(points: &[P], size: f64) -> Grid {
        let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (i, &p) in points.iter().enumerate() {
            cells.entry(cell(p, size)).or_default().push(i);
        }
        Grid { size, cells }
    }

    /// Indices of points in the 27 cells around `p`.
    fn near(&self, p: P) -> impl Iterator<Item = usize> + '_ {
        let c = cell(p, self.size);
        (-1..=1).flat_map(move |dx| {
            (-1..=1).flat_map(move |dy| {
                (-1..=1).flat_map(move |dz| {
                    // Saturating: a finite but huge coordinate (1e300) has a
                    // cell at the end of i64's range.
                    self.cells
                        .get(&[
                            c[0].saturating_add(dx),
                            c[1].saturating_add(dy),
                            c[2].saturating_add(dz),
                        ])
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
    if ambiguous == 0 || ambiguous > MAX_AMBIGUOUS {
        return match_vertices(student, expected, tolerance);
    }
    let mine = adjacency(student.len(), student_edges);
    let theirs = adjacency(expected.len(), expected_edges);
    let mut to_expected: Vec<Option<usize>> = vec![None; student.len()];
    let mut taken = vec![false; expected.len()];
    // Unique candidates first.
    for (s, c) in candidates.iter().enumerate() {
        if let [x] = c[..] {
            if !taken[x] {
                taken[x] = true;
                to_expected[s] = Some(x);
            }
        }
    }
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

    #[test]
    fn nearest_finds_the_closest() {
        let s = [[0.0; 3], [2.0, 0.0, 0.0]];
        assert_eq!(nearest(&s, [1.5, 0.0, 0.0]), Some((1, 0.5)));
        assert_eq!(nearest(&[], [0.0; 3]), None);
    }
}
