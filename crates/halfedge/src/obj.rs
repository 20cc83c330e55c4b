//! Reading and writing Wavefront OBJ, positions and faces only.
//!
//! The reader keeps the file's vertex numbering (the `i`-th `v` line becomes
//! `VertexId(i-1)`) and its line numbers, so that fixtures can name edges by
//! the indices a TA sees in the file and every error points at a line. tobj,
//! by contrast, renumbers vertices by first use within each object and drops
//! unused ones; the tests use it as an independent check of this reader.
//!
//! Coordinates are read as f64 and written as the shortest decimal that reads
//! back to the same f64, so writing a mesh and reading it back changes nothing.

use std::fmt::Write as _;
use std::path::Path;

use glam::DVec3;

use crate::build::MeshError;
use crate::mesh::Mesh;

/// The positions and polygons of an OBJ file, with the line of each.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjData {
    pub positions: Vec<DVec3>,
    pub faces: Vec<Vec<usize>>,
    /// The line (1-based) of each `v` statement.
    pub position_lines: Vec<usize>,
    /// The line (1-based) of each `f` statement.
    pub face_lines: Vec<usize>,
}

/// Parses OBJ text. `name` is only used in error messages.
pub fn parse_obj(text: &str, name: &str) -> Result<ObjData, MeshError> {
    let mut data = ObjData::default();
    let err = |line: usize, message: String| MeshError::Obj {
        path: name.to_string(),
        line,
        message,
    };
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut tokens = content.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let coords: Vec<&str> = tokens.collect();
                if coords.len() < 3 {
                    return Err(err(
                        line_no,
                        format!(
                            "a vertex needs three coordinates, found {}: `{}`",
                            coords.len(),
                            raw.trim()
                        ),
                    ));
                }
                let mut xyz = [0.0; 3];
                for (k, c) in coords[..3].iter().enumerate() {
                    xyz[k] = c.parse::<f64>().map_err(|_| {
                        err(line_no, format!("`{c}` is not a number: `{}`", raw.trim()))
                    })?;
                }
                data.positions.push(DVec3::from_array(xyz));
                data.position_lines.push(line_no);
            }
            Some("f") => {
                let mut face = Vec::new();
                for corner in tokens {
                    // `7`, `7/2`, `7//3` and `7/2/3` all name position 7.
                    let first = corner.split('/').next().unwrap_or("");
                    let index: i64 = first.parse().map_err(|_| {
                        err(
                            line_no,
                            format!("`{corner}` is not a vertex reference: `{}`", raw.trim()),
                        )
                    })?;
                    let count = data.positions.len() as i64;
                    let resolved =
                        match index {
                            0 => return Err(err(
                                line_no,
                                "vertex references start at 1 (or -1 for the last); 0 is not one"
                                    .into(),
                            )),
                            i if i > 0 => i - 1,
                            // Negative references count back from the latest vertex.
                            i => count + i,
                        };
                    if resolved < 0 {
                        return Err(err(
                            line_no,
                            format!(
                                "`{corner}` counts back past the first vertex \
                                 (only {count} are defined above this line)"
                            ),
                        ));
                    }
                    face.push(resolved as usize);
                }
                data.faces.push(face);
                data.face_lines.push(line_no);
            }
            // Normals, texture coordinates, groups, materials...: not used here.
            _ => {}
        }
    }
    Ok(data)
}

impl Mesh {
    /// Builds a mesh from OBJ text; `name` (a file name) appears in errors,
    /// which give the line and the file's 1-based vertex and face numbers.
    pub fn from_obj_str(text: &str, name: &str) -> Result<Mesh, MeshError> {
        let data = parse_obj(text, name)?;
        Mesh::from_faces(&data.positions, &data.faces).map_err(|e| {
            let line = e
                .face()
                .and_then(|f| data.face_lines.get(f))
                .or_else(|| e.vertex().and_then(|v| data.position_lines.get(v)))
                .copied()
                .unwrap_or(0);
            MeshError::Obj {
                path: name.to_string(),
                line,
                message: e.describe(1),
            }
        })
    }

    /// Reads an OBJ file.
    pub fn from_obj_file(path: impl AsRef<Path>) -> Result<Mesh, MeshError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| MeshError::UnreadableFile {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        Mesh::from_obj_str(&text, &path.display().to_string())
    }

    /// The mesh as OBJ text: every vertex in id order, then every real face.
    pub fn to_obj_string(&self) -> String {
        let (positions, faces) = self.to_faces();
        let mut out = String::new();
        for p in positions {
            // `{}` on f64 prints the shortest decimal that parses back exactly.
            let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
        }
        for face in faces {
            out.push('f');
            for i in face {
                let _ = write!(out, " {}", i + 1);
            }
            out.push('\n');
        }
        out
    }

    /// Writes the mesh as an OBJ file.
    pub fn write_obj_file(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        std::fs::write(path, self.to_obj_string())
    }
}
