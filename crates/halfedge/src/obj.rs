//! Reading and writing Wavefront OBJ, positions and faces only.
//!
//! The reader keeps the file's vertex numbering (the `i`-th `v` line becomes
//! `VertexId(i-1)`) and its line numbers, so that fixtures can name edges by
//! the indices a TA sees in the file and every error points at a line. tobj,
//! by contrast, renumbers vertices by first use within each object and drops
//! unused ones; the tests use it as an independent check of this reader.
//!
//! Nothing is skipped silently: a statement that OBJ allows but the lab does
//! not use (`vn`, `vt`, `o`, `g`, `usemtl`, `l`, ...) becomes an
//! [`ObjWarning`] naming the file, line and statement, and [`summary`] says
//! in one line what was dropped; anything else (`F 6 4 5`, `fo`, a stray
//! word) is an error with its line. A UTF-8 byte-order mark is skipped and
//! CRLF line ends are accepted.
//!
//! Coordinates are read as f64 and written as the shortest decimal that reads
//! back to the same f64, so writing a mesh and reading it back changes nothing.

use std::fmt::{self, Write as _};
use std::path::Path;

use glam::DVec3;

use crate::build::MeshError;
use crate::mesh::Mesh;

/// The positions and polygons of an OBJ file, with the line of each, and
/// what the reader dropped.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjData {
    pub positions: Vec<DVec3>,
    pub faces: Vec<Vec<usize>>,
    /// The line (1-based) of each `v` statement.
    pub position_lines: Vec<usize>,
    /// The line (1-based) of each `f` statement.
    pub face_lines: Vec<usize>,
    /// Every statement (or part of one) the lab does not use, in file order.
    pub warnings: Vec<ObjWarning>,
}

/// Something in an OBJ file that is valid OBJ but that the lab ignores.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ObjWarning {
    /// The file's name, as given to the reader.
    pub path: String,
    /// The line (1-based).
    pub line: usize,
    /// What was dropped, as [`summary`] counts it: a keyword between
    /// backquotes (`` `vn` ``) or a phrase ("vertex colour").
    pub dropped: String,
    /// The statement as written, without its comment.
    pub statement: String,
}

impl fmt::Display for ObjWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}: warning: ignored {} (the lab reads only vertex positions and faces): `{}`",
            self.path, self.line, self.dropped, self.statement
        )
    }
}

/// One line saying what the reader dropped, e.g. "cow.obj: ignored 3 `vn`,
/// 3 `vt`, 1 `o` (the lab reads only vertex positions and faces)", or `None`
/// when nothing was. Kinds are listed in the order they first appear.
pub fn summary(warnings: &[ObjWarning]) -> Option<String> {
    let first = warnings.first()?;
    let mut counts: Vec<(&str, usize)> = Vec::new();
    for w in warnings {
        match counts.iter_mut().find(|(kind, _)| *kind == w.dropped) {
            Some((_, n)) => *n += 1,
            None => counts.push((&w.dropped, 1)),
        }
    }
    let list: Vec<String> = counts.iter().map(|(k, n)| format!("{n} {k}")).collect();
    Some(format!(
        "{}: ignored {} (the lab reads only vertex positions and faces)",
        first.path,
        list.join(", ")
    ))
}

/// Statements of the OBJ format that describe something the lab does not
/// use: normals, texture coordinates, names, groups, materials, lines,
/// points and free-form geometry.
const IGNORED_STATEMENTS: &[&str] = &[
    "vt",
    "vn",
    "vp",
    "o",
    "g",
    "s",
    "mg",
    "usemtl",
    "mtllib",
    "l",
    "p",
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "bevel",
    "c_interp",
    "d_interp",
    "lod",
    "usemap",
    "maplib",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "call",
    "csh",
];

/// The lines of `text`: ends are `\n` or `\r\n`, and a byte-order mark at the
/// start is skipped. A carriage return anywhere else is reported, because a
/// file with old Mac line ends (`\r` alone) would otherwise read as one line.
fn lines<'t>(text: &'t str) -> impl Iterator<Item = (usize, &'t str)> + 't {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let text = text.strip_suffix('\n').unwrap_or(text);
    // An empty text still yields one empty line, which is harmless.
    text.split('\n').enumerate().map(|(i, line)| {
        let line = line.strip_suffix('\r').unwrap_or(line);
        (i + 1, line)
    })
}

/// Shortens a statement for a message: a garbage line can be long.
fn shown(statement: &str) -> String {
    const MAX: usize = 80;
    match statement.char_indices().nth(MAX) {
        Some((cut, _)) => format!("{}...", &statement[..cut]),
        None => statement.to_string(),
    }
}

/// Parses OBJ text. `name` is only used in messages.
pub fn parse_obj(text: &str, name: &str) -> Result<ObjData, MeshError> {
    let mut data = ObjData::default();
    let err = |line: usize, message: String| MeshError::Obj {
        path: name.to_string(),
        line,
        message,
    };
    for (line_no, raw) in lines(text) {
        let content = raw.split('#').next().unwrap_or("");
        let statement = shown(content.trim());
        if content.contains('\r') {
            return Err(err(
                line_no,
                "a carriage return in the middle of a line: lines must end with \\n or \\r\\n \
                 (old Mac line ends, \\r alone, are not supported)"
                    .into(),
            ));
        }
        let mut tokens = content.split_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        let warn = |data: &mut ObjData, dropped: String| {
            data.warnings.push(ObjWarning {
                path: name.to_string(),
                line: line_no,
                dropped,
                statement: statement.clone(),
            });
        };
        match keyword {
            "v" => {
                let coords: Vec<&str> = tokens.collect();
                let mut numbers = Vec::with_capacity(coords.len());
                for c in &coords {
                    numbers.push(c.parse::<f64>().map_err(|_| {
                        err(
                            line_no,
                            format!("`{}` is not a number: `{statement}`", shown(c)),
                        )
                    })?);
                }
                match numbers.len() {
                    3 => {}
                    // x y z w: the weight only matters for rational curves.
                    4 => warn(&mut data, "vertex weight".into()),
                    // x y z r g b: a common extension for vertex colours.
                    6 => warn(&mut data, "vertex colour".into()),
                    n => {
                        return Err(err(
                            line_no,
                            format!(
                                "a vertex needs three coordinates (four with a weight, six with \
                                 a colour), found {n}: `{statement}`"
                            ),
                        ))
                    }
                }
                data.positions
                    .push(DVec3::new(numbers[0], numbers[1], numbers[2]));
                data.position_lines.push(line_no);
            }
            "f" => {
                let mut face = Vec::new();
                for corner in tokens {
                    face.push(parse_corner(corner, data.positions.len()).map_err(|why| {
                        err(line_no, format!("{why}: `{statement}`"))
                    })?);
                }
                data.faces.push(face);
                data.face_lines.push(line_no);
            }
            "fo" => {
                return Err(err(
                    line_no,
                    format!("`fo` is the old form of `f`, which this reader does not take: write `f`: `{statement}`"),
                ))
            }
            k if IGNORED_STATEMENTS.contains(&k) => warn(&mut data, format!("`{k}`")),
            k => {
                let lower = k.to_ascii_lowercase();
                let hint = if lower == "v" || lower == "f" || IGNORED_STATEMENTS.contains(&lower.as_str()) {
                    format!(" (OBJ keywords are lower case: did you mean `{lower}`?)")
                } else {
                    String::new()
                };
                return Err(err(
                    line_no,
                    format!("`{}` is not an OBJ statement{hint}: `{statement}`", shown(k)),
                ));
            }
        }
    }
    Ok(data)
}

/// One corner of an `f` statement: `7`, `7/2`, `7//3` or `7/2/3` all name
/// position 7; negative numbers count back from the last vertex so far.
fn parse_corner(corner: &str, count: usize) -> Result<usize, String> {
    let not_a_reference = || format!("`{}` is not a vertex reference", shown(corner));
    let mut parts = corner.split('/');
    let first = parts.next().unwrap_or("");
    let rest: Vec<&str> = parts.collect();
    if rest.len() > 2
        || rest
            .iter()
            .any(|p| !p.is_empty() && p.parse::<i64>().is_err())
    {
        return Err(not_a_reference());
    }
    let index: i64 = first.parse().map_err(|_| not_a_reference())?;
    match index {
        0 => Err("vertex references start at 1 (or -1 for the last); 0 is not one".into()),
        i if i > 0 => usize::try_from(i - 1).map_err(|_| not_a_reference()),
        // Negative references count back from the latest vertex.
        i => {
            let back = i.unsigned_abs();
            if back > count as u64 {
                Err(format!(
                    "`{corner}` counts back past the first vertex \
                     (only {count} are defined above this line)"
                ))
            } else {
                Ok(count - back as usize)
            }
        }
    }
}

/// Reads a file as UTF-8 text; invalid UTF-8 is reported with its line.
fn read_text(path: &Path) -> Result<String, MeshError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| MeshError::UnreadableFile {
        path: name.clone(),
        reason: e.to_string(),
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        MeshError::Obj {
            path: name,
            line: 1 + good.iter().filter(|&&b| b == b'\n').count(),
            message: "the file is not UTF-8 text (is it a binary file, or in another encoding?)"
                .into(),
        }
    })
}

impl Mesh {
    /// Builds a mesh from OBJ text and returns it with what the reader
    /// ignored (print each [`ObjWarning`], or just [`summary`]). `name` (a
    /// file name) appears in messages; errors give the line and the file's
    /// 1-based vertex and face numbers.
    pub fn read_obj_str(text: &str, name: &str) -> Result<(Mesh, Vec<ObjWarning>), MeshError> {
        let data = parse_obj(text, name)?;
        let mesh = Mesh::from_faces(&data.positions, &data.faces).map_err(|e| {
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
        })?;
        Ok((mesh, data.warnings))
    }

    /// Reads an OBJ file and returns the mesh with what the reader ignored
    /// (see [`Mesh::read_obj_str`]).
    pub fn read_obj_file(path: impl AsRef<Path>) -> Result<(Mesh, Vec<ObjWarning>), MeshError> {
        let path = path.as_ref();
        let text = read_text(path)?;
        Mesh::read_obj_str(&text, &path.display().to_string())
    }

    /// Builds a mesh from OBJ text (see [`Mesh::read_obj_str`]); what the
    /// reader ignored goes to `log::warn!`, one line per statement and the
    /// summary.
    pub fn from_obj_str(text: &str, name: &str) -> Result<Mesh, MeshError> {
        let (mesh, warnings) = Mesh::read_obj_str(text, name)?;
        log_warnings(&warnings);
        Ok(mesh)
    }

    /// Reads an OBJ file (see [`Mesh::read_obj_file`]); what the reader
    /// ignored goes to `log::warn!`.
    pub fn from_obj_file(path: impl AsRef<Path>) -> Result<Mesh, MeshError> {
        let (mesh, warnings) = Mesh::read_obj_file(path)?;
        log_warnings(&warnings);
        Ok(mesh)
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

fn log_warnings(warnings: &[ObjWarning]) {
    for w in warnings {
        log::warn!("{w}");
    }
    if let Some(line) = summary(warnings) {
        log::warn!("{line}");
    }
}
