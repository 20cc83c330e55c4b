//! Where the pictures look from and how they project: an orthographic
//! [`Camera`] framing a shape, a shape [`Prepared`] for drawing (its
//! winding sense and closedness), and the case's three [`View`]s, chosen
//! from the case's edge, else its first problem (as [`Problems`], what
//! the marks found), else a corner. The static pictures (`svg.rs`) draw with them; the marks
//! (`marks.rs`) decide what is red, not where to look.

use std::collections::HashSet;

use halfedge::DVec3;

use super::faces::Shape;
use super::sides;

/// Side of one picture, in CSS pixels.
pub(super) const SIZE: f64 = 230.0;
/// Room left around the mesh's bounding sphere in a picture.
pub(super) const MARGIN: f64 = 14.0;
/// A camera looking at the mesh from `dir`, orthographic.
pub(super) struct Camera {
    pub(super) dir: DVec3,
    pub(super) right: DVec3,
    pub(super) up: DVec3,
    pub(super) center: DVec3,
    pub(super) scale: f64,
    pub(super) light: DVec3,
}

/// A projected point: screen x, y (pixels, y down), depth (pixels, larger
/// is nearer), and whether it was pinned to the border.
#[derive(Clone, Copy, Debug)]
pub(super) struct Screen {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) depth: f64,
    pub(super) pinned: bool,
}

impl Camera {
    /// Looks from `dir`, framing `points` as tightly as the picture allows.
    pub(super) fn fit(dir: DVec3, points: &[Option<DVec3>]) -> Camera {
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

    pub(super) fn project(&self, p: DVec3) -> Screen {
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

/// One shape ready for its pictures: its winding sense and closedness,
/// computed once for the three views.
pub(super) struct Prepared<'a> {
    pub(super) shape: &'a Shape,
    /// +1 when faces wind counter-clockwise seen from outside, else -1.
    pub(super) outward: f64,
    pub(super) closed: bool,
    /// Edges that are no face's side, drawn as lines.
    pub(super) loose: Vec<[usize; 2]>,
}

impl<'a> Prepared<'a> {
    pub(super) fn new(shape: &'a Shape) -> Prepared<'a> {
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

/// One direction the case is seen from: a camera framing the input, one
/// framing the expected result (and yours), and why it looks there.
pub(super) struct View {
    pub(super) input: Camera,
    pub(super) result: Camera,
    pub(super) why: &'static str,
}

/// Where the first problems are, as the marks found them: the first
/// wrong vertex of the expected result, the first of yours, the first
/// wrong edge of the expected result.
pub(super) struct Problems {
    pub(super) expected_point: Option<usize>,
    pub(super) yours_point: Option<usize>,
    pub(super) expected_edge: Option<[usize; 2]>,
}

/// The three views of a case: facing its edge (`case_edge`, in the input
/// as sent), else its first problem, else from a corner; then a quarter
/// round and the opposite side.
pub(super) fn views(
    input: &Shape,
    expected: &Shape,
    yours: Option<&Shape>,
    case_edge: Option<[usize; 2]>,
    problems: Problems,
) -> Vec<View> {
    // Where to look from: at the case's edge, else at the first problem,
    // else from a corner.
    let middle = |s: &Shape| s.bounds().map(|(lo, hi)| (lo + hi) / 2.0);
    let input_center = middle(input).unwrap_or(DVec3::ZERO);
    let center = middle(expected).unwrap_or(input_center);
    let edge_normal = case_edge.and_then(|[a, b]| {
        let prepared = Prepared::new(input);
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
    let problem = problems
        .expected_point
        .and_then(|k| looking_at(expected, &[k]))
        .or_else(|| looking_at(yours?, &[problems.yours_point?]))
        .or_else(|| {
            let [a, b] = problems.expected_edge?;
            looking_at(expected, &[a, b])
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
    [
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
    .collect()
}
