//! OBJ files named on the command line (`add`, `subdivide`, `flip`,
//! `split`): reading them with the reader's warnings shown, edges named by
//! OBJ vertex numbers (from 1), the round and size limits, and writing a
//! result only once it validates.

use std::path::{Path, PathBuf};

use halfedge::{EdgeId, Mesh};

/// Most rounds `subdivide` and `add --subdivide` take.
pub const MAX_ROUNDS: usize = 10;
/// Reader warnings printed one by one; the summary line counts them all.
const MAX_WARNINGS_SHOWN: usize = 10;

/// An OBJ file, one of its edges by its two vertices' numbers, and where
/// the result goes (`flip`, `split`).
#[derive(clap::Args)]
pub struct EdgeArgs {
    pub input: PathBuf,
    pub a: usize,
    pub b: usize,
    #[arg(short = 'o', long)]
    pub output: PathBuf,
}

/// Reads an OBJ file and prints what the reader ignored to stderr.
pub fn read_obj(path: &Path) -> Result<Mesh, String> {
    let (mesh, warnings) = Mesh::read_obj_file(path).map_err(|e| e.to_string())?;
    for w in warnings.iter().take(MAX_WARNINGS_SHOWN) {
        eprintln!("{w}");
    }
    if warnings.len() > MAX_WARNINGS_SHOWN {
        eprintln!(
            "... and {} more warnings",
            warnings.len() - MAX_WARNINGS_SHOWN
        );
    }
    if let Some(line) = halfedge::obj::summary(&warnings) {
        eprintln!("{line}");
    }
    Ok(mesh)
}

/// Checks a number of rounds, and that the result stays under `max_faces`.
pub fn check_rounds(
    flag: &str,
    rounds: usize,
    mesh: &Mesh,
    max_faces: usize,
) -> Result<(), String> {
    if !(1..=MAX_ROUNDS).contains(&rounds) {
        return Err(format!(
            "{flag} {rounds}: the number of rounds must be 1 to {MAX_ROUNDS}"
        ));
    }
    let faces = mesh.num_real_faces();
    let after = |r: usize| {
        4usize
            .checked_pow(r as u32)
            .and_then(|k| k.checked_mul(faces))
    };
    if after(rounds).is_none_or(|n| n > max_faces) {
        let fits = (0..rounds)
            .rev()
            .find(|&r| after(r).is_some_and(|n| n <= max_faces))
            .unwrap_or(0);
        let advice = if fits == 0 {
            "this mesh is too big for even one round".to_string()
        } else {
            format!("use at most {fits} rounds for this mesh")
        };
        return Err(format!(
            "{flag} {rounds}: {faces} faces would become {}, more than the {max_faces} allowed: \
             {advice}",
            after(rounds).map_or_else(|| "more than can be counted".to_string(), |n| n.to_string())
        ));
    }
    Ok(())
}

/// Why edge `e` cannot be flipped, if it cannot: on the boundary, beside a
/// face that is not a triangle, or facing two vertices that are one or
/// already joined (the flip would make a second edge between them).
pub fn flip_refusal(mesh: &Mesh, e: EdgeId) -> Option<String> {
    let h = mesh[e].halfedge;
    let t = mesh[h].twin;
    if mesh.edge_on_boundary(e) {
        return Some("it is on the boundary (a hole is on one side)".into());
    }
    if mesh.face_degree(mesh[h].face) != 3 || mesh.face_degree(mesh[t].face) != 3 {
        return Some("the faces on its two sides are not both triangles".into());
    }
    let c = mesh[mesh[mesh[h].next].next].vertex;
    let d = mesh[mesh[mesh[t].next].next].vertex;
    if c == d {
        return Some(format!(
            "vertex {} faces it on both sides, so the flip would join it to itself",
            c.index() + 1
        ));
    }
    if mesh.find_edge(c, d).is_some() {
        return Some(format!(
            "vertices {} and {}, which face it, are already joined by an edge, so the flip \
             would make a second edge between them (on a tetrahedron, every edge is like this)",
            c.index() + 1,
            d.index() + 1
        ));
    }
    None
}

/// OBJ vertex numbers (from 1) to indices (from 0).
pub fn obj_edge(mesh: &Mesh, a: usize, b: usize) -> Result<[usize; 2], String> {
    let n = mesh.num_vertices();
    if a == b {
        return Err(format!(
            "vertex {a} given twice: an edge joins two different vertices"
        ));
    }
    for v in [a, b] {
        if v == 0 || v > n {
            return Err(format!(
                "vertex {v} does not exist: the file's vertices are 1 to {n}"
            ));
        }
    }
    if mesh.edge_between(a - 1, b - 1).is_none() {
        return Err(format!("vertices {a} and {b} are not joined by an edge"));
    }
    Ok([a - 1, b - 1])
}

impl EdgeArgs {
    /// The OBJ file and the edge between its vertices `a` and `b`.
    pub fn mesh_and_edge(&self) -> Result<(Mesh, EdgeId), String> {
        let mesh = read_obj(&self.input)?;
        let [i, j] = obj_edge(&mesh, self.a, self.b)?;
        let e = mesh.edge_between(i, j).expect("obj_edge checked it exists");
        Ok((mesh, e))
    }

    /// Writes the result of `what` to `--output` once it validates.
    pub fn write(&self, mesh: &Mesh, what: &str) -> Result<(), String> {
        write_obj(mesh, &self.input, what, &self.output)
    }
}

/// Writes the result of `what` on `input`, after checking it.
pub fn write_obj(mesh: &Mesh, input: &Path, what: &str, path: &Path) -> Result<(), String> {
    // The reader refuses every degenerate input the reference is known to
    // trip on; if one still gets through, say so rather than guess who is
    // to blame.
    mesh.validate().map_err(|e| {
        format!(
            "{}: the result of {what} does not validate ({e}); the input passed every check \
             of the reader, so either it is degenerate in a way they miss or the reference \
             has a bug: please report it with the file",
            input.display()
        )
    })?;
    mesh.write_obj_file(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}
