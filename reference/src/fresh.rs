//! Fresh cases: meshes nobody has seen, made per submission at grading time.
//!
//! A fixed set of cases can be learned once it leaks (a lookup table of the
//! visible fixtures passed every lab case). So graders add, for each
//! submission, cases on random meshes of the lab's kinds (an icosphere, a
//! torus, a capped cylinder and a cone, every vertex moved at random; an
//! open tube for the bonus) with random edges to flip and split, their
//! expected results computed by the model solution in the grading process.
//! They count like hidden cases and are named by their seed, which
//! `reference fresh --seed S --dir D` turns back into the same fixtures.
//!
//! The seed comes from a secret and the submission's bytes: the same
//! upload gets the same cases (and grade) again, and no student can know
//! them in advance. The secret is the digest list of the hidden cases,
//! which never leaves the TA (see [`secret_of`]).

use std::path::Path;

use grader::judge::fixture::{self, Group, Operation};
use halfedge::{shapes, DVec3, EdgeId, Mesh};

use crate::cases::{self, Case};
use crate::render;
use crate::solution::{self, Weights};

/// A small deterministic generator (SplitMix64): the same seed gives the
/// same cases on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `lo..hi` (`hi > lo`).
    fn below(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next() % (hi - lo) as u64) as usize
    }
    /// Uniform in [-1, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// The seed of a submission's fresh cases: the first 8 bytes of
/// SHA-256(secret, submission).
pub fn seed_for(secret: &[u8], submission: &[u8]) -> u64 {
    let mut bytes = Vec::with_capacity(secret.len() + submission.len() + 1);
    bytes.extend_from_slice(secret);
    bytes.push(0);
    bytes.extend_from_slice(submission);
    let hex = grader::judge::digest::sha256_hex(&bytes);
    u64::from_str_radix(&hex[..16], 16).expect("hex digits")
}

/// The secret behind the seeds: the hidden cases' digest list in
/// `fixtures` (students never see it; a TA who changes the hidden cases
/// changes every seed). Without hidden cases there is no secret to keep,
/// and grading says so rather than inventing one.
pub fn secret_of(fixtures: &Path) -> Result<Vec<u8>, String> {
    let path = fixtures
        .join("hidden")
        .join(grader::judge::digest::SUMS_FILE);
    std::fs::read(&path).map_err(|e| {
        format!(
            "{}: cannot read the hidden cases' digest list, the secret fresh cases are \
             drawn from ({e})",
            path.display()
        )
    })
}

/// Every vertex moved by up to 15% of the shortest edge in each axis:
/// no two meshes alike, no triangle folded.
fn jittered(mut mesh: Mesh, rng: &mut Rng) -> Mesh {
    let shortest = mesh
        .edge_ids()
        .map(|e| {
            let (a, b) = mesh.edge_vertices(e);
            mesh[a].pos.distance(mesh[b].pos)
        })
        .fold(f64::INFINITY, f64::min);
    let step = 0.15 * shortest;
    for v in mesh.vertex_ids() {
        mesh[v].pos += step * DVec3::new(rng.unit(), rng.unit(), rng.unit());
    }
    mesh
}

/// A random edge the model solution flips (an interior one whose flip
/// makes no duplicate edge).
fn flippable(mesh: &Mesh, rng: &mut Rng) -> EdgeId {
    let edges: Vec<EdgeId> = mesh
        .edge_ids()
        .filter(|&e| solution::flip_edge(&mut mesh.clone(), e).is_some())
        .collect();
    edges[rng.below(0, edges.len())]
}

fn any_edge(mesh: &Mesh, rng: &mut Rng, interior: bool) -> EdgeId {
    let edges: Vec<EdgeId> = mesh
        .edge_ids()
        .filter(|&e| mesh.edge_on_boundary(e) != interior)
        .collect();
    edges[rng.below(0, edges.len())]
}

/// The fresh cases of `seed`: for each of four closed meshes a flip, a
/// split and one round of subdivision (counted, in the hidden group); for
/// an open tube a split of a rim edge and a subdivision (bonus).
pub fn cases(seed: u64, weights: Weights) -> Vec<Case> {
    let mut rng = Rng(seed);
    let mut kinds: Vec<(&str, Mesh)> = Vec::new();
    kinds.push(("icosphere", shapes::icosphere(1)));
    let (major, minor) = (rng.below(5, 10), rng.below(3, 6));
    kinds.push((
        "torus",
        shapes::torus(major, minor, 1.0, 0.25 + 0.1 * rng.unit().abs()),
    ));
    let sides = rng.below(5, 11);
    kinds.push((
        "cylinder",
        shapes::cylinder(sides, rng.below(1, 4), 0.6, 1.2, true),
    ));
    let sides = rng.below(4, 9);
    kinds.push(("cone", shapes::cone(sides, 0.8, 1.0 + rng.unit().abs())));
    let mut out = Vec::new();
    let name = |kind: &str, op: &str| format!("fresh-{seed:016x}-{kind}-{op}");
    for (kind, mesh) in kinds {
        let mesh = jittered(mesh, &mut rng);
        let object = format!("fresh {kind} (seed {seed:016x})");
        let flip = cases::ends(&mesh, flippable(&mesh, &mut rng));
        let split = cases::ends(&mesh, any_edge(&mesh, &mut rng, true));
        for (op, operation) in [
            ("flip", Operation::Flip { edge: flip }),
            ("split", Operation::Split { edge: split }),
            ("subdivide-1", Operation::Subdivide { rounds: 1 }),
        ] {
            out.push(cases::case(
                &name(kind, op),
                &object,
                Group::Hidden,
                &mesh,
                operation,
                weights,
            ));
        }
    }
    let tube = jittered(
        shapes::cylinder(rng.below(5, 9), 2, 0.5, 1.0, false),
        &mut rng,
    );
    let object = format!("fresh open tube (seed {seed:016x})");
    let rim = cases::ends(&tube, any_edge(&tube, &mut rng, false));
    for (op, operation) in [
        ("split", Operation::Split { edge: rim }),
        ("subdivide-1", Operation::Subdivide { rounds: 1 }),
    ] {
        out.push(cases::case(
            &name("tube", op),
            &object,
            Group::Bonus,
            &tube,
            operation,
            weights,
        ));
    }
    out
}

/// Writes the fresh cases of `seed` into `dir`'s `hidden/` and `bonus/`
/// folders beside whatever is there, and rewrites their `SHA256SUMS` so
/// the grader's digest check covers them. Returns the names of the cases
/// it wrote.
pub fn write(dir: &Path, seed: u64, weights: Weights) -> Result<Vec<String>, String> {
    let io = |e: std::io::Error, p: &Path| format!("{}: {e}", p.display());
    let cases = cases(seed, weights);
    for case in &cases {
        let f = render::make_fixture(case).map_err(|e| format!("fresh case {}: {e}", case.name))?;
        let path = dir.join(f.relative_path());
        std::fs::create_dir_all(path.parent().expect("a group folder"))
            .map_err(|e| io(e, &path))?;
        std::fs::write(&path, fixture::to_json_text(&f)).map_err(|e| io(e, &path))?;
    }
    for group in [Group::Hidden, Group::Bonus] {
        let folder = dir.join(group.name());
        std::fs::create_dir_all(&folder).map_err(|e| io(e, &folder))?;
        let mut files = Vec::new();
        for entry in std::fs::read_dir(&folder).map_err(|e| io(e, &folder))? {
            let path = entry.map_err(|e| io(e, &folder))?.path();
            if path.extension().is_some_and(|x| x == "json") {
                let name = path
                    .file_name()
                    .expect("a file")
                    .to_string_lossy()
                    .into_owned();
                files.push((name, std::fs::read(&path).map_err(|e| io(e, &path))?));
            }
        }
        let sums = folder.join(grader::judge::digest::SUMS_FILE);
        std::fs::write(&sums, grader::judge::digest::sums_text(&files))
            .map_err(|e| io(e, &sums))?;
    }
    Ok(cases.into_iter().map(|c| c.name).collect())
}

/// How many fresh cases count per function (flip, split, subdivide): the
/// hidden ones, and the bonus ones when bonus cases count.
pub fn counted(bonus: bool) -> [usize; 3] {
    let mut counts = [0; 3];
    for c in cases(0, Weights::Warren) {
        if c.group == Group::Bonus && !bonus {
            continue;
        }
        let k = match c.operation {
            Operation::Flip { .. } => 0,
            Operation::Split { .. } => 1,
            Operation::Subdivide { .. } => 2,
            // Fresh cases are single operations.
            Operation::Sequence { .. } => continue,
        };
        counts[k] += 1;
    }
    counts
}
