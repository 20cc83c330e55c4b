//! Hostile implementations: what a student who has read the grader's
//! source might try, each an entry of the catalogue in [`crate::mutants`].
//! Every attack prints what it managed (`attack: ...`), so the tests can
//! assert that it was stopped as well as that the verdict is right.
//!
//! They run only inside the grader's child process; nothing here is
//! called by the TA tool itself.

use std::io::Write;
use std::time::Duration;

use halfedge::{EdgeId, Mesh, VertexId};

use crate::solution;

/// Where the attacks that "win" leave their mark, for the tests to look.
pub const MARK_DIR: &str = "/tmp/meshlab-attack";

fn report(what: &str, result: std::io::Result<()>) {
    match result {
        Ok(()) => println!("attack: {what}: done"),
        Err(e) => println!("attack: {what}: denied ({})", e.kind()),
    }
}

/// The grader's command line, read from /proc: where the fixtures and the
/// results file are.
fn parent_args() -> std::io::Result<Vec<String>> {
    // SAFETY: a plain system call.
    let ppid = unsafe { libc::getppid() };
    let raw = std::fs::read(format!("/proc/{ppid}/cmdline"))?;
    Ok(raw
        .split(|&b| b == 0)
        .map(|s| String::from_utf8_lossy(s).into_owned())
        .collect())
}

fn arg_after(args: &[String], flag: &str) -> Option<String> {
    let i = args.iter().position(|a| a == flag)?;
    args.get(i + 1).cloned()
}

/// Reads the expected answers and tampers with everything it can reach:
/// the fixtures named on the grader's command line (tolerance 1e300 and the
/// digest list), the Gradescope results file, a file of its own. Then makes
/// the no-flip mistake, which only a tampered tolerance would let pass.
pub fn tamper(mesh: &mut Mesh) {
    let fixtures = parent_args().map(|a| {
        arg_after(&a, "--fixtures")
            .unwrap_or_else(|| format!("{}/../fixtures", env!("CARGO_MANIFEST_DIR")))
    });
    let fixtures = fixtures.unwrap_or_else(|e| {
        report("read the grader's command line", Err(e));
        format!("{}/../fixtures", env!("CARGO_MANIFEST_DIR"))
    });
    let case = format!("{fixtures}/lab/cube-subdivide-1.json");
    report(
        "read the expected answer",
        std::fs::read_to_string(&case).map(drop),
    );
    report(
        "tamper with a fixture",
        std::fs::read_to_string(&case).and_then(|text| {
            std::fs::write(
                &case,
                text.replace("\"tolerance\": 0.00001", "\"tolerance\": 1e300"),
            )
        }),
    );
    report(
        "rewrite the digest list",
        std::fs::write(format!("{fixtures}/lab/SHA256SUMS"), "forged\n"),
    );
    if let Ok(args) = parent_args() {
        if let Some(results) = arg_after(&args, "--gradescope") {
            report(
                "forge results.json",
                std::fs::write(results, "{\"score\": 1000, \"tests\": []}"),
            );
        }
    }
    report(
        "write a file",
        std::fs::create_dir_all(MARK_DIR)
            .and_then(|()| std::fs::write(format!("{MARK_DIR}/tamper"), "was here")),
    );
    let _ = std::io::stdout().flush();
    crate::mutants::no_flip(mesh);
}

/// Writes a result frame of its own (the input, returned as the answer) on
/// every descriptor it might find the grader's channel on, then exits.
pub fn forge_frames(mesh: &mut Mesh) {
    use std::os::fd::FromRawFd;
    let frame = grader::wire::result_frame(&grader::wire::Ran::Returned {
        answer: grader::wire::Answer::Unit,
        mesh: mesh.clone(),
    });
    for fd in 3..64 {
        // SAFETY: descriptors we do not own; the File is forgotten, not closed.
        let mut file = unsafe { std::fs::File::from_raw_fd(fd) };
        let _ = file.write_all(&frame);
        std::mem::forget(file);
    }
    std::process::exit(0);
}

/// Forks a process that keeps the grader's pipes open for 40 s, then makes
/// the no-flip mistake and returns at once.
pub fn orphan(mesh: &mut Mesh) {
    // SAFETY: fork in a single-threaded child; the new process only sleeps.
    if unsafe { libc::fork() } == 0 {
        std::thread::sleep(Duration::from_secs(40));
        std::process::exit(0);
    }
    crate::mutants::no_flip(mesh);
}

/// Leaves a detached process (its own session, so not in the killed group)
/// that tries, 3 s later, to forge the results file the grader wrote and
/// to leave a mark; makes the no-flip mistake meanwhile.
pub fn detached(mesh: &mut Mesh) {
    let results = parent_args()
        .ok()
        .and_then(|a| arg_after(&a, "--gradescope"))
        .unwrap_or_else(|| format!("{MARK_DIR}/results.json"));
    // SAFETY: fork and setsid in a single-threaded child.
    unsafe {
        if libc::fork() == 0 {
            libc::setsid();
            if libc::fork() == 0 {
                std::thread::sleep(Duration::from_secs(3));
                let _ = std::fs::create_dir_all(MARK_DIR);
                let _ = std::fs::write(format!("{MARK_DIR}/detached"), "outlived the grader");
                let _ = std::fs::write(&results, "{\"score\": 1000, \"tests\": []}");
                std::process::exit(0);
            }
            std::process::exit(0);
        }
    }
    crate::mutants::no_flip(mesh);
}

/// Touches memory until something stops it: 6 GiB, 64 MiB at a time.
pub fn memory_hog(mesh: &mut Mesh) {
    let mut hoard: Vec<Vec<u8>> = Vec::new();
    for _ in 0..96 {
        let mut block = vec![0u8; 64 << 20];
        for i in (0..block.len()).step_by(4096) {
            block[i] = 1;
        }
        hoard.push(std::hint::black_box(block));
    }
    std::hint::black_box(&hoard);
    crate::mutants::no_flip(mesh);
}

/// Replaces the mesh with a new one: the growth budget must still hold.
pub fn replace_and_grow(mesh: &mut Mesh) {
    *mesh = Mesh::new();
    loop {
        mesh.new_vertex(halfedge::DVec3::ZERO);
    }
}

/// Subdivides right, then leaves one vertex at NaN.
pub fn nan_position(mesh: &mut Mesh) {
    solution::loop_subdivide(mesh);
    let v = VertexId::from_index(mesh.num_vertices() / 2);
    mesh[v].pos.y = f64::NAN;
}

/// A split that never updates b's halfedge: right whenever b happened to
/// point elsewhere (as `from_faces` always leaves it), wrong when b pointed
/// at the halfedge the split moves.
pub fn split_stale_b(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let h = mesh[e].halfedge;
    let b = mesh[mesh[h].twin].vertex;
    let before = mesh[b].halfedge;
    let m = solution::split_edge(mesh, e)?;
    mesh[b].halfedge = before;
    Some(m)
}

/// A split that never resets the halfedge of the faces it shrinks.
pub fn split_stale_faces(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let h = mesh[e].halfedge;
    let faces = [mesh[h].face, mesh[mesh[h].twin].face];
    let before = faces.map(|f| mesh[f].halfedge);
    let m = solution::split_edge(mesh, e)?;
    for (f, old) in faces.into_iter().zip(before) {
        mesh[f].halfedge = old;
    }
    Some(m)
}

/// A split that assumes `mesh[e].halfedge` lies in a real face: on a
/// boundary edge given by its hole side, it divides the hole.
pub fn split_assumes_inside(mesh: &mut Mesh, e: EdgeId) -> Option<VertexId> {
    let h = mesh[e].halfedge;
    if mesh[mesh[h].face].is_boundary {
        return None;
    }
    solution::split_edge(mesh, e)
}

/// A flip with no check that the faces are triangles.
pub fn flip_any_face(mesh: &mut Mesh, e: EdgeId) -> Option<EdgeId> {
    if mesh.edge_on_boundary(e) {
        return None;
    }
    solution::relink_flip(mesh, e);
    Some(e)
}

/// A subdivision that quietly skips a mesh that is not all triangles.
pub fn subdivide_skips_quads(mesh: &mut Mesh) {
    if mesh.first_non_triangle().is_none() {
        solution::loop_subdivide(mesh);
    }
}
