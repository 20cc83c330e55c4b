//! Meshes to test with: the four objects of the original lab, exactly as the
//! lab ships them, and generators for more shapes with any resolution.
//!
//! The lab's objects and most generators are triangle meshes. For polygon
//! meshes: [`quad_cube`], [`quad_torus`] and [`quad_grid`] (all quads, the
//! grid open), [`prism`] (two n-gons and n quads) and [`house`] (triangles,
//! quads and pentagons together).
//!
//! Every shape is built through [`Mesh::from_faces`], so each is checked like
//! any input. The generated closed shapes face outwards (counter-clockwise
//! seen from outside); of the lab's objects the torus, cylinder and cone do
//! too, but the lab's cube is wound clockwise seen from outside (see
//! [`crate::mesh`] on orientation).

use std::collections::HashMap;
use std::f64::consts::TAU;

use glam::DVec3;

use crate::mesh::Mesh;

/// The names of the lab's objects, in the order the lab tests them.
pub const LAB_OBJECTS: [&str; 4] = ["cube", "torus", "cylinder", "cone"];

/// The OBJ text of a lab object (copied from the lab unchanged), if `name` is one.
pub fn lab_object_obj(name: &str) -> Option<&'static str> {
    match name {
        "cube" => Some(include_str!("../objects/cube.obj")),
        "torus" => Some(include_str!("../objects/torus.obj")),
        "cylinder" => Some(include_str!("../objects/cylinder.obj")),
        "cone" => Some(include_str!("../objects/cone.obj")),
        _ => None,
    }
}

/// A lab object as a mesh, if `name` is one of [`LAB_OBJECTS`].
pub fn lab_object(name: &str) -> Option<Mesh> {
    let text = lab_object_obj(name)?;
    let file = format!("{name}.obj");
    Some(Mesh::from_obj_str(text, &file).expect("the lab objects are valid meshes"))
}

fn build(positions: Vec<DVec3>, faces: Vec<Vec<usize>>, what: &str) -> Mesh {
    Mesh::from_faces(&positions, &faces)
        .unwrap_or_else(|e| panic!("the {what} generator made a bad mesh: {e}"))
}

/// The squares of an `n` x `n` lattice on each side of the cube
/// `[0, n]^3`: the lattice points in the order they are first used, and each
/// square's corners counter-clockwise seen from outside.
fn cube_squares(n: usize) -> (Vec<[i64; 3]>, Vec<[usize; 4]>) {
    let n_i = n as i64;
    // (origin, u, v) on the integer lattice 0..=n, with u x v pointing outwards.
    let sides: [([i64; 3], [i64; 3], [i64; 3]); 6] = [
        ([n_i, 0, 0], [0, 1, 0], [0, 0, 1]),
        ([0, 0, 0], [0, 0, 1], [0, 1, 0]),
        ([0, n_i, 0], [0, 0, 1], [1, 0, 0]),
        ([0, 0, 0], [1, 0, 0], [0, 0, 1]),
        ([0, 0, n_i], [1, 0, 0], [0, 1, 0]),
        ([0, 0, 0], [0, 1, 0], [1, 0, 0]),
    ];
    let mut index: HashMap<[i64; 3], usize> = HashMap::new();
    let mut points = Vec::new();
    let mut squares = Vec::new();
    let mut vertex = |p: [i64; 3]| {
        *index.entry(p).or_insert_with(|| {
            points.push(p);
            points.len() - 1
        })
    };
    for (o, u, v) in sides {
        let at = |i: i64, j: i64| {
            [
                o[0] + i * u[0] + j * v[0],
                o[1] + i * u[1] + j * v[1],
                o[2] + i * u[2] + j * v[2],
            ]
        };
        for i in 0..n_i {
            for j in 0..n_i {
                let a = vertex(at(i, j));
                let b = vertex(at(i + 1, j));
                let c = vertex(at(i + 1, j + 1));
                let d = vertex(at(i, j + 1));
                squares.push([a, b, c, d]);
            }
        }
    }
    (points, squares)
}

fn lattice_point(p: [i64; 3]) -> DVec3 {
    DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)
}

/// A cube of side 1 centred at the origin, each side cut into `n` x `n`
/// squares, each square into two triangles. `cube(1)` has 8 vertices and 12
/// faces (triangulated differently from the lab's cube).
pub fn cube(n: usize) -> Mesh {
    assert!(n >= 1, "a cube needs at least one square per side");
    let (points, squares) = cube_squares(n);
    let positions = points
        .into_iter()
        .map(|p| lattice_point(p) / n as f64 - 0.5)
        .collect();
    let faces = squares
        .into_iter()
        .flat_map(|[a, b, c, d]| [vec![a, b, c], vec![a, c, d]])
        .collect();
    build(positions, faces, "cube")
}

/// A cube of **side 2** centred at the origin (corners at `(+-1, +-1, +-1)`),
/// each side cut into `n` x `n` quads, facing outwards. `quad_cube(1)` is
/// the six-quad cube: 8 vertices, 12 edges, 6 faces.
pub fn quad_cube(n: usize) -> Mesh {
    assert!(n >= 1, "a cube needs at least one square per side");
    let (points, squares) = cube_squares(n);
    let positions = points
        .into_iter()
        .map(|p| lattice_point(p) * 2.0 / n as f64 - 1.0)
        .collect();
    let faces = squares.into_iter().map(|s| s.to_vec()).collect();
    build(positions, faces, "quad cube")
}

/// Points on a circle of `radius` at height `y` around the y axis.
fn ring(segments: usize, radius: f64, y: f64) -> impl Iterator<Item = DVec3> {
    (0..segments).map(move |i| {
        let t = TAU * i as f64 / segments as f64;
        DVec3::new(radius * t.cos(), y, radius * t.sin())
    })
}

/// A frustum around the y axis from y = 0 (radius `bottom`) to y = `height`
/// (radius `top`), its side cut into `rings` bands of `segments` quads, each
/// split into two triangles. A radius of 0 makes a single apex vertex (a cone).
/// With `capped`, each non-apex end gets a centre vertex and a fan of
/// triangles; without, the ends are holes (boundary loops).
pub fn frustum(
    segments: usize,
    rings: usize,
    bottom: f64,
    top: f64,
    height: f64,
    capped: bool,
) -> Mesh {
    assert!(segments >= 3, "a frustum needs at least 3 segments");
    assert!(rings >= 1, "a frustum needs at least 1 ring");
    assert!(bottom > 0.0, "the bottom radius must be positive");
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    let apex = top == 0.0;
    let full_rings = if apex { rings } else { rings + 1 };
    for k in 0..full_rings {
        let s = k as f64 / rings as f64;
        positions.extend(ring(segments, bottom + (top - bottom) * s, height * s));
    }
    let at = |k: usize, i: usize| k * segments + i % segments;
    for k in 0..rings {
        for i in 0..segments {
            if apex && k + 1 == rings {
                continue;
            }
            // Up the side, along the ring, down: counter-clockwise from outside.
            faces.push(vec![at(k, i), at(k + 1, i), at(k + 1, i + 1)]);
            faces.push(vec![at(k, i), at(k + 1, i + 1), at(k, i + 1)]);
        }
    }
    if apex {
        let tip = positions.len();
        positions.push(DVec3::new(0.0, height, 0.0));
        let k = rings - 1;
        for i in 0..segments {
            faces.push(vec![at(k, i), tip, at(k, i + 1)]);
        }
    }
    if capped {
        let centre = positions.len();
        positions.push(DVec3::ZERO);
        for i in 0..segments {
            faces.push(vec![centre, at(0, i), at(0, i + 1)]);
        }
        if !apex {
            let centre = positions.len();
            positions.push(DVec3::new(0.0, height, 0.0));
            for i in 0..segments {
                faces.push(vec![centre, at(rings, i + 1), at(rings, i)]);
            }
        }
    }
    build(positions, faces, "frustum")
}

/// A cylinder of `radius` and `height` around the y axis (see [`frustum`]).
pub fn cylinder(segments: usize, rings: usize, radius: f64, height: f64, capped: bool) -> Mesh {
    frustum(segments, rings, radius, radius, height, capped)
}

/// A closed cone of base `radius` and `height` around the y axis.
pub fn cone(segments: usize, radius: f64, height: f64) -> Mesh {
    frustum(segments, 1, radius, 0.0, height, true)
}

/// A closed prism around the y axis: two regular polygons of `sides`
/// corners and circumradius `radius`, at y = 0 and y = `height`, joined by
/// `sides` quads. `prism(3, ..)` has two triangles and three quads (6
/// vertices, 9 edges); `prism(5, ..)` two pentagons and five quads. Faces
/// outwards, corner `i` of the bottom at angle `i / sides` of a turn, as in
/// [`frustum`].
pub fn prism(sides: usize, radius: f64, height: f64) -> Mesh {
    assert!(sides >= 3, "a prism needs at least 3 sides");
    assert!(radius > 0.0, "the radius must be positive");
    let mut positions: Vec<DVec3> = ring(sides, radius, 0.0).collect();
    positions.extend(ring(sides, radius, height));
    let at = |k: usize, i: usize| k * sides + i % sides;
    // Each side quad is the union of the frustum's two triangles there.
    let mut faces: Vec<Vec<usize>> = (0..sides)
        .map(|i| vec![at(0, i), at(1, i), at(1, i + 1), at(0, i + 1)])
        .collect();
    faces.push((0..sides).map(|i| at(0, i)).collect());
    faces.push((0..sides).rev().map(|i| at(1, i)).collect());
    build(positions, faces, "prism")
}

/// The vertices of a torus, ring by ring (see [`torus`]).
fn torus_points(major: usize, minor: usize, big_r: f64, small_r: f64) -> Vec<DVec3> {
    let mut positions = Vec::with_capacity(major * minor);
    for i in 0..major {
        let t = TAU * i as f64 / major as f64;
        for j in 0..minor {
            let p = TAU * j as f64 / minor as f64;
            let r = big_r + small_r * p.cos();
            positions.push(DVec3::new(r * t.cos(), small_r * p.sin(), r * t.sin()));
        }
    }
    positions
}

/// A torus around the y axis: `major` segments around the ring, `minor`
/// around the tube, ring radius `big_r`, tube radius `small_r`.
pub fn torus(major: usize, minor: usize, big_r: f64, small_r: f64) -> Mesh {
    assert!(
        major >= 3 && minor >= 3,
        "a torus needs at least 3 x 3 segments"
    );
    let positions = torus_points(major, minor, big_r, small_r);
    let at = |i: usize, j: usize| (i % major) * minor + j % minor;
    let mut faces = Vec::new();
    for i in 0..major {
        for j in 0..minor {
            faces.push(vec![at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
            faces.push(vec![at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
        }
    }
    build(positions, faces, "torus")
}

/// The torus of [`torus`] (the same vertices, in the same order) with each
/// pair of triangles made one quad: `major * minor` quads, facing outwards.
pub fn quad_torus(major: usize, minor: usize, big_r: f64, small_r: f64) -> Mesh {
    assert!(
        major >= 3 && minor >= 3,
        "a torus needs at least 3 x 3 segments"
    );
    let positions = torus_points(major, minor, big_r, small_r);
    let at = |i: usize, j: usize| (i % major) * minor + j % minor;
    let mut faces = Vec::new();
    for i in 0..major {
        for j in 0..minor {
            faces.push(vec![at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)]);
        }
    }
    build(positions, faces, "quad torus")
}

/// A unit sphere: an icosahedron whose triangles are cut in four
/// `subdivisions` times, new points pushed out onto the sphere.
/// 0 gives the icosahedron (12 vertices, 20 faces).
pub fn icosphere(subdivisions: usize) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut positions: Vec<DVec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|p| DVec3::from_array(*p).normalize())
    .collect();
    let mut faces: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints: HashMap<(usize, usize), usize> = HashMap::new();
        let mut mid = |a: usize, b: usize, positions: &mut Vec<DVec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push(((positions[a] + positions[b]) / 2.0).normalize());
                positions.len() - 1
            })
        };
        let mut finer = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let ab = mid(a, b, &mut positions);
            let bc = mid(b, c, &mut positions);
            let ca = mid(c, a, &mut positions);
            finer.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = finer;
    }
    build(
        positions,
        faces.into_iter().map(|f| f.to_vec()).collect(),
        "icosphere",
    )
}

/// The vertices of the saddle patch, row by row (see [`grid`]).
fn grid_points(nx: usize, ny: usize) -> Vec<DVec3> {
    let mut positions = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            let x = i as f64 / nx as f64 - 0.5;
            let y = j as f64 / ny as f64 - 0.5;
            positions.push(DVec3::new(x, y, 0.5 * x * y));
        }
    }
    positions
}

/// An open, gently curved patch (a saddle z = x*y/2) over [-0.5, 0.5]^2,
/// `nx` by `ny` squares, each split into two triangles. Its rim is a
/// boundary loop: the mesh to test boundary handling on.
pub fn grid(nx: usize, ny: usize) -> Mesh {
    assert!(nx >= 1 && ny >= 1, "a grid needs at least one square");
    let positions = grid_points(nx, ny);
    let at = |i: usize, j: usize| j * (nx + 1) + i;
    let mut faces = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            faces.push(vec![at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            faces.push(vec![at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    build(positions, faces, "grid")
}

/// The open patch of [`grid`] (the same vertices, in the same order) with
/// each pair of triangles made one quad: `nx * ny` quads, facing +z. Its
/// four corners each belong to one quad only (two edges each): the mesh to
/// test boundaries and corners of polygon meshes on.
pub fn quad_grid(nx: usize, ny: usize) -> Mesh {
    assert!(nx >= 1 && ny >= 1, "a grid needs at least one square");
    let positions = grid_points(nx, ny);
    let at = |i: usize, j: usize| j * (nx + 1) + i;
    let mut faces = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            faces.push(vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    build(positions, faces, "quad grid")
}

/// A closed house of mixed faces: a box (floor and walls over
/// [-1, 1] x [0, 1] x [-1, 1]) under a gable roof whose ridge runs along z
/// at height 2. The gable ends are pentagons, the floor, the two walls and
/// the left roof quads, the right roof two triangles: 10 vertices, 16
/// edges, 8 faces (2 triangles, 4 quads, 2 pentagons), facing outwards.
/// Vertices: 0-3 the floor's corners, 4-7 the eaves above them, 8 and 9 the
/// ridge's ends (z = -1 and z = 1).
pub fn house() -> Mesh {
    let positions = [
        [-1.0, 0.0, -1.0],
        [1.0, 0.0, -1.0],
        [1.0, 0.0, 1.0],
        [-1.0, 0.0, 1.0],
        [-1.0, 1.0, -1.0],
        [1.0, 1.0, -1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, 1.0],
        [0.0, 2.0, -1.0],
        [0.0, 2.0, 1.0],
    ]
    .map(DVec3::from_array)
    .to_vec();
    let faces = vec![
        vec![0, 1, 2, 3],    // floor
        vec![0, 4, 8, 5, 1], // back gable (z = -1)
        vec![3, 2, 6, 9, 7], // front gable (z = 1)
        vec![0, 3, 7, 4],    // left wall
        vec![1, 5, 6, 2],    // right wall
        vec![4, 7, 9, 8],    // left roof
        vec![5, 8, 9],       // right roof, back half
        vec![5, 9, 6],       // right roof, front half
    ];
    build(positions, faces, "house")
}
