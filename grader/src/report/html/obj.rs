//! The OBJ files beside the page (MeshLab, Blender): a case's input, its
//! expected result (faces rebuilt from the fixture's edges) and the
//! student's result, exact when valid, else as much as can be read of it.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::Path;

use halfedge::Mesh;

use super::card::operation;
use super::faces::Shape;
use super::sides;
use crate::judge::fixture::Fixture;
use crate::judge::verdict::CaseReport;

/// Writes a case's OBJ files into `dir`: each with what the card's links
/// call it (`input`, `expected`, `yours`) and its file name.
pub(super) fn write_obj_files(
    dir: &Path,
    f: &Fixture,
    r: &CaseReport,
) -> Result<Vec<(&'static str, String)>, String> {
    let write = |name: String, text: String| -> Result<String, String> {
        let path = dir.join(&name);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
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
    Ok(files)
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
