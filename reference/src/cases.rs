//! The built-in fixture cases: the lab's objects and the refusals of the
//! contract (lab), boundary support (bonus), more objects (hidden), and the
//! local shapes of [`crate::local`]. [`crate::render`] makes them fixtures.

use grader::judge::fixture::{Group, MeshData, Operation, Step};
use halfedge::{shapes, EdgeId, Mesh};

use crate::local;
use crate::solution::{self, Weights};

/// The tolerance of the built-in cases.
pub const TOLERANCE: f64 = 1e-5;

/// A case before it has an expected result.
#[derive(Clone, Debug)]
pub struct Case {
    pub name: String,
    pub object: String,
    pub group: Group,
    pub input: MeshData,
    pub operation: Operation,
    /// For a sequence: its steps.
    pub steps: Vec<Step>,
    pub weights: Weights,
    pub tolerance: f64,
}

pub(crate) fn ends(mesh: &Mesh, e: EdgeId) -> [usize; 2] {
    let (a, b) = mesh.edge_vertices(e);
    [a.index(), b.index()]
}

/// Flip edges chosen so that leaving a stale pointer behind shows: one
/// whose start vertex points at it (a's `halfedge` must move) and one whose
/// face points at the halfedge that changes face.
///
/// Both kinds prefer edges whose flip leaves a valid mesh: the two vertices
/// facing the edge are not joined already (on a cone's apex they are).
fn flip_edges(mesh: &Mesh) -> [[usize; 2]; 2] {
    let flippable: Vec<EdgeId> = mesh
        .edge_ids()
        .filter(|&e| {
            let h = mesh[e].halfedge;
            let t = mesh[h].twin;
            let c = mesh[mesh[mesh[h].next].next].vertex;
            let d = mesh[mesh[mesh[t].next].next].vertex;
            !mesh.edge_on_boundary(e) && mesh.find_edge(c, d).is_none()
        })
        .collect();
    let pick = |wanted: &dyn Fn(EdgeId) -> bool| {
        let e = flippable
            .iter()
            .copied()
            .find(|&e| wanted(e))
            .or(flippable.first().copied());
        ends(mesh, e.expect("a mesh with a flippable edge"))
    };
    let stale_vertex = pick(&|e| {
        let h = mesh[e].halfedge;
        mesh[mesh[h].vertex].halfedge == h
    });
    let stale_face = pick(&|e| {
        let h = mesh[e].halfedge;
        mesh[mesh[h].face].halfedge == mesh[h].next
    });
    [stale_vertex, stale_face]
}

/// The first interior edge. (On a freshly built mesh no vertex points at
/// a halfedge a split moves, so stale pointers show in subdivision instead.)
fn split_edge_choice(mesh: &Mesh) -> [usize; 2] {
    let e = mesh
        .edge_ids()
        .find(|&e| !mesh.edge_on_boundary(e))
        .expect("an interior edge");
    ends(mesh, e)
}

pub(crate) fn case(
    name: &str,
    object: &str,
    group: Group,
    mesh: &Mesh,
    operation: Operation,
    weights: Weights,
) -> Case {
    Case {
        name: name.to_string(),
        object: object.to_string(),
        group,
        input: MeshData::from_mesh(mesh),
        operation,
        steps: Vec::new(),
        weights,
        tolerance: TOLERANCE,
    }
}

/// How many flips and splits a sequence has, at least and at most.
pub const SEQUENCE_LENGTH: (usize, usize) = (10, 30);

/// A sequence of flips and splits drawn from `seed` (Scotty3D's
/// `a2.local.mix`): each step flips or splits, half the time an edge at
/// the vertex the last split made (so operations land beside earlier
/// ones), else any edge. Vertices are named as in [`Step`]: the
/// reference's split appends its vertex, so its id is that name.
pub fn draw_sequence(input: &Mesh, seed: u64) -> Vec<Step> {
    let mut rng = grader::judge::relabel::Rng::new(seed);
    let (lo, hi) = SEQUENCE_LENGTH;
    let length = lo + rng.below(hi - lo + 1);
    let mut mesh = input.clone();
    let mut last_split = None;
    let mut steps = Vec::with_capacity(length);
    for _ in 0..length {
        let near: Vec<EdgeId> = match last_split {
            Some(v) if rng.below(2) == 0 => mesh
                .vertex_halfedges(v)
                .into_iter()
                .map(|h| mesh[h].edge)
                .collect(),
            _ => mesh.edge_ids().collect(),
        };
        let e = near[rng.below(near.len())];
        let edge = ends(&mesh, e);
        if rng.below(2) == 0 {
            steps.push(Step::Flip { edge });
            solution::flip_edge(&mut mesh, e);
        } else {
            steps.push(Step::Split { edge });
            last_split = solution::split_edge(&mut mesh, e).or(last_split);
        }
    }
    steps
}

/// A sequence case on `mesh`, its seed fixed by its name.
fn sequence_case(name: &str, object: &str, group: Group, mesh: &Mesh, weights: Weights) -> Case {
    // 32 bits: short enough to read out of a message.
    let seed = grader::judge::relabel::default_seed(name) & 0xffff_ffff;
    Case {
        steps: draw_sequence(mesh, seed),
        ..case(
            name,
            object,
            group,
            mesh,
            Operation::Sequence { seed },
            weights,
        )
    }
}

/// Flip and split cases on chosen edges, and subdivision after `rounds`.
fn standard(
    out: &mut Vec<Case>,
    slug: &str,
    object: &str,
    group: Group,
    mesh: &Mesh,
    rounds: &[usize],
    weights: Weights,
) {
    for (i, edge) in flip_edges(mesh).into_iter().enumerate() {
        let name = format!("{slug}-flip-{}", i + 1);
        out.push(case(
            &name,
            object,
            group,
            mesh,
            Operation::Flip { edge },
            weights,
        ));
    }
    let edge = split_edge_choice(mesh);
    out.push(case(
        &format!("{slug}-split"),
        object,
        group,
        mesh,
        Operation::Split { edge },
        weights,
    ));
    if mesh.is_triangle_mesh() && mesh.edge_ids().all(|e| !mesh.edge_on_boundary(e)) {
        out.push(sequence_case(
            &format!("{slug}-sequence"),
            object,
            group,
            mesh,
            weights,
        ));
    }
    for &r in rounds {
        let name = format!("{slug}-subdivide-{r}");
        out.push(case(
            &name,
            object,
            group,
            mesh,
            Operation::Subdivide { rounds: r },
            weights,
        ));
    }
}

/// Every built-in case, with the weight rule for subdivision.
pub fn builtin(weights: Weights) -> Vec<Case> {
    let mut out = Vec::new();
    for name in shapes::LAB_OBJECTS {
        let mesh = shapes::lab_object(name).expect("a lab object");
        standard(&mut out, name, name, Group::Lab, &mesh, &[1, 2], weights);
    }

    let grid = shapes::grid(3, 3);
    standard(
        &mut out,
        "grid",
        "open grid",
        Group::Bonus,
        &grid,
        &[1, 2],
        weights,
    );
    let rim = grid
        .edge_ids()
        .find(|&e| grid.edge_on_boundary(e))
        .expect("a grid has a rim");
    let rim = ends(&grid, rim);
    // The boundary refusal is the contract's, so it counts; only boundary
    // support (splitting and subdividing beside holes) is bonus.
    out.push(case(
        "grid-flip-boundary",
        "open grid",
        Group::Lab,
        &grid,
        Operation::Flip {
            edge: ends(&grid, rim_edge_only_the_boundary_refuses(&grid)),
        },
        weights,
    ));
    let open = open_octahedron();
    out.push(case(
        "open-octahedron-flip",
        "octahedron with a triangular hole",
        Group::Lab,
        &open,
        Operation::Flip {
            edge: ends(&open, rim_edge_only_the_boundary_refuses(&open)),
        },
        weights,
    ));
    out.push(case(
        "grid-split-boundary",
        "open grid",
        Group::Bonus,
        &grid,
        Operation::Split { edge: rim },
        weights,
    ));
    let tube = shapes::cylinder(6, 2, 0.5, 1.0, false);
    out.push(case(
        "open-cylinder-subdivide-1",
        "open cylinder",
        Group::Bonus,
        &tube,
        Operation::Subdivide { rounds: 1 },
        weights,
    ));

    contract_cases(&mut out, weights);
    local_cases(&mut out, weights);
    let touching = two_octahedra();
    standard(
        &mut out,
        "two-octahedra",
        "two octahedra touching",
        Group::Hidden,
        &touching,
        &[1],
        weights,
    );
    out.push(case(
        "seam-tube-subdivide-1",
        "tube with an unwelded seam",
        Group::Bonus,
        &seam_tube(6, 2),
        Operation::Subdivide { rounds: 1 },
        weights,
    ));

    let hidden: [(&str, &str, Mesh, &[usize]); 6] = [
        ("icosphere", "icosphere", shapes::icosphere(1), &[1, 2]),
        ("cube-2x2", "cube (2x2 sides)", shapes::cube(2), &[1]),
        (
            "torus-8x5",
            "torus (8x5)",
            shapes::torus(8, 5, 1.0, 0.3),
            &[1],
        ),
        (
            "cylinder-10",
            "cylinder (10 sides)",
            shapes::cylinder(10, 2, 0.6, 1.2, true),
            &[1],
        ),
        ("cone-5", "cone (5 sides)", shapes::cone(5, 0.8, 1.5), &[2]),
        (
            "frustum-7",
            "frustum (7 sides)",
            shapes::frustum(7, 2, 1.0, 0.5, 1.5, true),
            &[1],
        ),
    ];
    for (slug, object, mesh, rounds) in hidden {
        standard(
            &mut out,
            slug,
            object,
            Group::Hidden,
            &mesh,
            rounds,
            weights,
        );
    }
    out
}

fn mesh_of(positions: &[[f64; 3]], faces: &[&[usize]]) -> Mesh {
    let positions: Vec<halfedge::DVec3> = positions
        .iter()
        .map(|p| halfedge::DVec3::from_array(*p))
        .collect();
    let faces: Vec<Vec<usize>> = faces.iter().map(|f| f.to_vec()).collect();
    Mesh::from_faces(&positions, &faces).expect("a built-in mesh is valid")
}

/// A box whose six faces are quads.
fn quad_box() -> Mesh {
    let mut ps = Vec::new();
    for i in 0..8 {
        ps.push([(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64]);
    }
    mesh_of(
        &ps,
        &[
            &[0, 2, 3, 1],
            &[4, 5, 7, 6],
            &[0, 1, 5, 4],
            &[2, 6, 7, 3],
            &[0, 4, 6, 2],
            &[1, 3, 7, 5],
        ],
    )
}

/// A pyramid on a pentagon: five triangles and the pentagon.
fn pentagon_pyramid() -> Mesh {
    let mut ps: Vec<[f64; 3]> = (0..5)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 5.0;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    ps.push([0.0, 0.0, 1.0]);
    mesh_of(
        &ps,
        &[
            &[0, 1, 5],
            &[1, 2, 5],
            &[2, 3, 5],
            &[3, 4, 5],
            &[4, 0, 5],
            &[4, 3, 2, 1, 0],
        ],
    )
}

/// The contract's refusals: flip and split beside a face that is not a
/// triangle return `None` and change nothing; subdivision panics.
fn contract_cases(out: &mut Vec<Case>, weights: Weights) {
    let quads = quad_box();
    let pyramid = pentagon_pyramid();
    let object = "box of quads";
    out.push(case(
        "quad-box-flip",
        object,
        Group::Lab,
        &quads,
        Operation::Flip { edge: [0, 1] },
        weights,
    ));
    out.push(case(
        "quad-box-split",
        object,
        Group::Lab,
        &quads,
        Operation::Split { edge: [0, 1] },
        weights,
    ));
    out.push(case(
        "quad-box-subdivide-1",
        object,
        Group::Lab,
        &quads,
        Operation::Subdivide { rounds: 1 },
        weights,
    ));
    // Every edge of a tetrahedron: flipping it would join two vertices
    // already joined.
    let tetra = mesh_of(
        &[
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ],
        &[&[0, 1, 2], &[0, 3, 1], &[0, 2, 3], &[1, 3, 2]],
    );
    out.push(case(
        "tetrahedron-flip",
        "tetrahedron",
        Group::Lab,
        &tetra,
        Operation::Flip { edge: [0, 1] },
        weights,
    ));
    let object = "pentagonal pyramid";
    out.push(case(
        "pentagon-pyramid-flip",
        object,
        Group::Lab,
        &pyramid,
        Operation::Flip { edge: [1, 0] },
        weights,
    ));
    out.push(case(
        "pentagon-pyramid-split",
        object,
        Group::Lab,
        &pyramid,
        Operation::Split { edge: [2, 1] },
        weights,
    ));
}

/// A local shape's cases: a flip of `a`-`b` (counted: every refusal is
/// the contract's), and a split of it (counted, but beside a hole: that is
/// boundary support, the bonus).
fn local_cases(out: &mut Vec<Case>, weights: Weights) {
    for shape in local::shapes() {
        let f = local::facts(&shape.mesh, [0, 1]).expect("a shape's edge joins a and b");
        out.push(case(
            &format!("local-flip-{}", shape.slug),
            &shape.object,
            Group::Lab,
            &shape.mesh,
            Operation::Flip { edge: [0, 1] },
            weights,
        ));
        let beside_hole = f.sides.iter().any(|s| s.is_hole());
        let group = if beside_hole && f.split_legal() {
            Group::Bonus
        } else {
            Group::Lab
        };
        out.push(case(
            &format!("local-split-{}", shape.slug),
            &shape.object,
            group,
            &shape.mesh,
            Operation::Split { edge: [0, 1] },
            weights,
        ));
    }
}

/// An octahedron's six corners, centred at (`cx`, 0, 0): +x, -x, +y, -y,
/// +z, -z.
fn octahedron_corners(cx: f64) -> Vec<[f64; 3]> {
    vec![
        [cx + 1.0, 0.0, 0.0],
        [cx - 1.0, 0.0, 0.0],
        [cx, 1.0, 0.0],
        [cx, -1.0, 0.0],
        [cx, 0.0, 1.0],
        [cx, 0.0, -1.0],
    ]
}

/// The octahedron's faces, counter-clockwise seen from outside; the first
/// is (+x, +y, +z).
const OCTAHEDRON_FACES: [[usize; 3]; 8] = [
    [0, 2, 4],
    [2, 1, 4],
    [1, 3, 4],
    [3, 0, 4],
    [2, 0, 5],
    [1, 2, 5],
    [3, 1, 5],
    [0, 3, 5],
];

/// Two octahedra touching at a point through two distinct vertices at the
/// same place: matching by position alone cannot tell those apart.
fn two_octahedra() -> Mesh {
    // The first's vertex 0 (at x = 1) and the second's vertex 1 coincide.
    let mut ps = octahedron_corners(0.0);
    ps.extend(octahedron_corners(2.0));
    let all: Vec<Vec<usize>> = OCTAHEDRON_FACES
        .iter()
        .map(|f| f.to_vec())
        .chain(
            OCTAHEDRON_FACES
                .iter()
                .map(|f| f.iter().map(|i| i + 6).collect()),
        )
        .collect();
    let refs: Vec<&[usize]> = all.iter().map(|f| f.as_slice()).collect();
    mesh_of(&ps, &refs)
}

/// An octahedron without its first face: the hole is a triangle, so a flip
/// of a hole's edge passes the triangle rule, and the two vertices facing
/// it (+z in the hole, -z in the real face) are not joined, so it passes
/// the duplicate-edge rule too. Only the boundary rule refuses it.
fn open_octahedron() -> Mesh {
    let faces: Vec<&[usize]> = OCTAHEDRON_FACES[1..].iter().map(|f| f.as_slice()).collect();
    mesh_of(&octahedron_corners(0.0), &faces)
}

/// A boundary edge of `mesh` where only the boundary rule refuses a flip:
/// the vertex facing it and the hole's vertex two steps along are not
/// joined (at a grid's corner they are, and the duplicate-edge rule would
/// refuse it too).
fn rim_edge_only_the_boundary_refuses(mesh: &Mesh) -> EdgeId {
    mesh.edge_ids()
        .filter(|&e| mesh.edge_on_boundary(e))
        .find(|&e| {
            let h = mesh[e].halfedge;
            let t = mesh[h].twin;
            let c = mesh[mesh[mesh[h].next].next].vertex;
            let d = mesh[mesh[mesh[t].next].next].vertex;
            c != d && mesh.find_edge(c, d).is_none()
        })
        .expect("a rim edge away from the corners")
}

/// An open tube of `segments` sides and `rings` rows, cut open along one
/// line: the seam's vertices are doubled, one copy for each side.
fn seam_tube(segments: usize, rings: usize) -> Mesh {
    let columns = segments + 1; // the last column sits on the first
    let mut ps = Vec::new();
    for r in 0..=rings {
        for c in 0..columns {
            let a = std::f64::consts::TAU * (c % segments) as f64 / segments as f64;
            ps.push([a.cos(), a.sin(), r as f64 / rings as f64]);
        }
    }
    let at = |r: usize, c: usize| r * columns + c;
    let mut faces = Vec::new();
    for r in 0..rings {
        for c in 0..segments {
            faces.push(vec![at(r, c), at(r, c + 1), at(r + 1, c + 1)]);
            faces.push(vec![at(r, c), at(r + 1, c + 1), at(r + 1, c)]);
        }
    }
    let refs: Vec<&[usize]> = faces.iter().map(|f| f.as_slice()).collect();
    mesh_of(&ps, &refs)
}
