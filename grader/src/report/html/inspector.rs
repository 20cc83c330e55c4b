//! The data the inspector (`script/`) reads, one JSON blob per case:
//! each mesh's full connectivity as the student's code left it (halfedges
//! with twin, next, vertex, edge, face; vertices with position, halfedge,
//! `is_new`, `new_pos`; edges; faces), the input and the expected result,
//! the marks, the element "select error" picks, the handout's names for a
//! flip's or split's elements, the case's numbering beside a relabelled
//! input's, and the step-through frames.
//!
//! Ids are written as they are, out of range or not: the script
//! bounds-checks every one. Non-finite numbers are written `null`.

use std::fmt::Write as _;

use halfedge::{Element, Mesh};

use super::faces::Shape;
use super::marks::{Marks, Named};

/// The most frames written per case; the rest are cut (and the page says so).
pub const FRAME_LIMIT: usize = 200;
/// The most bytes of frames written per case (a frame of a large mesh is
/// a few hundred kilobytes): past it, the frames are cut too.
pub const FRAME_BYTES: usize = 4 << 20;

/// A step-through of the student's own subdivision: the mesh before each
/// split or flip their `loop_subdivide` made, and the end state.
#[derive(Clone, Debug, Default)]
pub struct Frames {
    /// Each frame's label (`before split 7 (edge e6)`) and mesh.
    pub meshes: Vec<(String, Mesh)>,
    /// The first frame after which the mesh is broken (invalid, or a split
    /// vertex not at its edge's midpoint).
    pub first_broken: Option<usize>,
    /// Why the recording stops early, when a limit cut it.
    pub cut: Option<String>,
}

impl Frames {
    /// The page's frames from what the grader recorded and judged
    /// (`CaseReport::frames`).
    pub fn from_recorded(recorded: &crate::judge::frames::Frames) -> Frames {
        Frames {
            meshes: recorded.frames.clone(),
            first_broken: recorded.first_broken,
            cut: recorded.cut.clone(),
        }
    }
}

/// A float as JSON: six decimals near the mesh, exponent form far off,
/// `null` when not finite (JSON has no NaN).
fn num(out: &mut String, x: f64) {
    if !x.is_finite() {
        out.push_str("null");
    } else if x.abs() < 1e7 {
        let r = (x * 1e6).round() / 1e6;
        // `{}` prints the shortest text that reads back the same.
        let _ = write!(out, "{}", if r == 0.0 { 0.0 } else { r });
    } else {
        let _ = write!(out, "{x:.6e}");
    }
}

fn list<T>(
    out: &mut String,
    items: impl IntoIterator<Item = T>,
    mut each: impl FnMut(&mut String, T),
) {
    out.push('[');
    for (k, item) in items.into_iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        each(out, item);
    }
    out.push(']');
}

fn ids(out: &mut String, items: impl IntoIterator<Item = u32>) {
    list(out, items, |o, i| {
        let _ = write!(o, "{i}");
    });
}

/// A flag per element, as the list of the elements that have it.
fn flags(out: &mut String, items: impl IntoIterator<Item = bool>) {
    ids(
        out,
        items
            .into_iter()
            .enumerate()
            .filter(|(_, b)| *b)
            .map(|(i, _)| i as u32),
    );
}

/// A JSON string; `</` is written `<\/` so no text ends the script element.
pub(super) fn string(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '/' => out.push_str("\\/"),
            '<' => out.push_str("\\u003c"),
            c if (c as u32) < 0x20 || c == '\u{2028}' || c == '\u{2029}' => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

/// A mesh's four arenas (flags as the list of ids that have them): `p`
/// positions (flat), `vh`, `vn`, `vq` (only
/// when some `new_pos` is set); `eh`, `en`, `eq`; `fh`, `fb`; `h` as
/// twin, next, vertex, edge, face per halfedge (flat).
pub(super) fn mesh_json(out: &mut String, mesh: &Mesh) {
    let (vertices, edges, faces, halfedges) = mesh.records();
    out.push_str("{\"p\":");
    list(out, vertices.iter().flat_map(|v| v.pos.to_array()), num);
    out.push_str(",\"vh\":");
    ids(out, vertices.iter().map(|v| v.halfedge.0));
    out.push_str(",\"vn\":");
    flags(out, vertices.iter().map(|v| v.is_new));
    if vertices.iter().any(|v| v.new_pos != halfedge::DVec3::ZERO) {
        out.push_str(",\"vq\":");
        list(out, vertices.iter().flat_map(|v| v.new_pos.to_array()), num);
    }
    out.push_str(",\"eh\":");
    ids(out, edges.iter().map(|e| e.halfedge.0));
    out.push_str(",\"en\":");
    flags(out, edges.iter().map(|e| e.is_new));
    if edges.iter().any(|e| e.new_pos != halfedge::DVec3::ZERO) {
        out.push_str(",\"eq\":");
        list(out, edges.iter().flat_map(|e| e.new_pos.to_array()), num);
    }
    out.push_str(",\"fh\":");
    ids(out, faces.iter().map(|f| f.halfedge.0));
    out.push_str(",\"fb\":");
    flags(out, faces.iter().map(|f| f.is_boundary));
    out.push_str(",\"h\":");
    ids(
        out,
        halfedges
            .iter()
            .flat_map(|h| [h.twin.0, h.next.0, h.vertex.0, h.edge.0, h.face.0]),
    );
    out.push('}');
}

/// A mesh known only by positions and faces (the expected result): `p`,
/// `fv` (each face as its length then its corners), `le` (edges no face
/// has), `sid` (the student's vertex standing for each, or -1), `iid`
/// (the input vertex, as sent, each old vertex is, or -1: the labels
/// where the judge matched nothing).
pub(super) fn shape_json(
    out: &mut String,
    shape: &Shape,
    student_of: &[Option<usize>],
    input_of: &[Option<usize>],
) {
    out.push_str("{\"p\":");
    list(
        out,
        shape
            .points
            .iter()
            .flat_map(|p| p.map_or([f64::NAN; 3], |p| p.to_array())),
        num,
    );
    out.push_str(",\"fv\":");
    list(
        out,
        shape
            .faces
            .iter()
            .flat_map(|f| std::iter::once(f.len()).chain(f.iter().copied())),
        |o, i| {
            let _ = write!(o, "{i}");
        },
    );
    let in_faces: std::collections::HashSet<[usize; 2]> =
        shape.faces.iter().flat_map(|f| super::sides(f)).collect();
    out.push_str(",\"le\":");
    list(
        out,
        shape
            .edges
            .iter()
            .filter(|e| !in_faces.contains(*e))
            .flat_map(|e| *e),
        |o, i| {
            let _ = write!(o, "{i}");
        },
    );
    out.push_str(",\"sid\":");
    list(
        out,
        (0..shape.len()).map(|i| student_of.get(i).copied().flatten()),
        |o, s| match s {
            Some(s) => {
                let _ = write!(o, "{s}");
            }
            None => o.push_str("-1"),
        },
    );
    out.push_str(",\"iid\":");
    list(
        out,
        (0..shape.len()).map(|i| input_of.get(i).copied().flatten()),
        |o, s| match s {
            Some(s) => {
                let _ = write!(o, "{s}");
            }
            None => o.push_str("-1"),
        },
    );
    out.push('}');
}

/// An element as the script names it: `["h",17]`.
fn element(out: &mut String, e: Element) {
    let (k, i) = match e {
        Element::Vertex(v) => ('v', v.0),
        Element::Edge(x) => ('e', x.0),
        Element::Face(x) => ('f', x.0),
        Element::Halfedge(x) => ('h', x.0),
    };
    let _ = write!(out, "[\"{k}\",{i}]");
}

/// One pane's marks: `v` wrong (or missing) vertices, `e` wrong (or
/// missing) edges as vertex pairs, `named` the elements the messages are
/// about, `fe`/`fv` the case's edge and new vertex.
pub(super) fn marks_json(out: &mut String, marks: &Marks, named: &[Element]) {
    out.push_str("{\"v\":");
    ids(out, marks.wrong_points.iter().map(|(v, _)| *v as u32));
    out.push_str(",\"e\":");
    ids(
        out,
        marks.wrong_edges.iter().flat_map(|e| e.map(|x| x as u32)),
    );
    out.push_str(",\"named\":");
    list(out, named.iter().copied(), element);
    out.push_str(",\"fe\":");
    ids(
        out,
        marks.focus_edges.iter().flat_map(|e| e.map(|x| x as u32)),
    );
    out.push_str(",\"fv\":");
    ids(out, marks.focus_points.iter().map(|&v| v as u32));
    out.push('}');
}

/// The elements of `named` that [`Marks::named`] found in the mesh.
pub(super) fn named_found(marks: &Marks, named: &[Element]) -> Vec<Element> {
    let shown: Vec<String> = marks
        .named
        .iter()
        .map(|n| match n {
            Named::Vertex(_, s) | Named::Edge(_, s) | Named::Face(_, s) => s.clone(),
        })
        .collect();
    named
        .iter()
        .copied()
        .filter(|e| shown.contains(&e.to_string()))
        .collect()
}

/// Elements and the names the handout gives them.
pub(super) type Names = Vec<(Element, &'static str)>;

/// The names the handout's tables give a flip's or split's elements
/// (`h, t, h1, h2, t1, t2, a, b, c, d, f0, f1`, and a split's `m, eb, ec,
/// ed, f2, f3, hb, tb, hc, tc, hd, td`), found from the case's edge `[a, b]`
/// in `input`; in `result`, the old elements keep their ids and a split's
/// new ones are told by their ends. Every id is bounds-checked.
pub(super) fn handout_names(
    input: &Mesh,
    edge: [usize; 2],
    split: bool,
    result: Option<&Mesh>,
) -> (Names, Names) {
    use halfedge::{EdgeId, FaceId, HalfedgeId, VertexId};
    let (_, edges, _, hs) = input.records();
    let Some(e) = input.edge_between(edge[0], edge[1]) else {
        return (Vec::new(), Vec::new());
    };
    let get = |h: u32| hs.get(h as usize);
    let mut names: Vec<(Element, &'static str)> = vec![(Element::Edge(e), "e")];
    let walk = || -> Option<Vec<(Element, &'static str)>> {
        let h = edges.get(e.index())?.halfedge;
        let t = get(h.0)?.twin;
        let h1 = get(h.0)?.next;
        let h2 = get(h1.0)?.next;
        let t1 = get(t.0)?.next;
        let t2 = get(t1.0)?.next;
        let v = |x: HalfedgeId| get(x.0).map(|r| r.vertex);
        let (a, b, c, d) = (v(h)?, v(t)?, v(h2)?, v(t2)?);
        let (f0, f1) = (get(h.0)?.face, get(t.0)?.face);
        Some(vec![
            (Element::Halfedge(h), "h"),
            (Element::Halfedge(t), "t"),
            (Element::Halfedge(h1), "h1"),
            (Element::Halfedge(h2), "h2"),
            (Element::Halfedge(t1), "t1"),
            (Element::Halfedge(t2), "t2"),
            (Element::Vertex(a), "a"),
            (Element::Vertex(b), "b"),
            (Element::Vertex(c), "c"),
            (Element::Vertex(d), "d"),
            (Element::Face(f0), "f0"),
            (Element::Face(f1), "f1"),
        ])
    };
    names.extend(walk().unwrap_or_default());
    let mut after = names.clone();
    if let (true, Some(result)) = (split, result) {
        let (rv, re, rf, rh) = result.records();
        let of = |name: &str| {
            names
                .iter()
                .find(|(_, n)| *n == name)
                .and_then(|(e, _)| match e {
                    Element::Vertex(v) => Some(v.0),
                    _ => None,
                })
        };
        let (nv, ne, nf, nh) = (
            input.num_vertices(),
            input.num_edges(),
            input.num_faces(),
            input.num_halfedges(),
        );
        if let (Some(b), Some(c), Some(d), true) = (of("b"), of("c"), of("d"), rv.len() > nv) {
            let m = nv as u32;
            after.push((Element::Vertex(VertexId(m)), "m"));
            let ends = |h: usize| -> Option<(u32, u32)> {
                let r = rh.get(h)?;
                Some((r.vertex.0, rh.get(r.twin.index())?.vertex.0))
            };
            for h in nh..rh.len() {
                let name = match ends(h) {
                    Some((x, y)) if x == m && y == b => "hb",
                    Some((x, y)) if x == b && y == m => "tb",
                    Some((x, y)) if x == m && y == c => "hc",
                    Some((x, y)) if x == c && y == m => "tc",
                    Some((x, y)) if x == m && y == d => "hd",
                    Some((x, y)) if x == d && y == m => "td",
                    _ => continue,
                };
                after.push((Element::Halfedge(HalfedgeId(h as u32)), name));
            }
            for (k, edge) in re.iter().enumerate().skip(ne) {
                let Some((x, y)) = ends(edge.halfedge.index()) else {
                    continue;
                };
                let other = if x == m {
                    y
                } else if y == m {
                    x
                } else {
                    continue;
                };
                let name = match other {
                    o if o == b => "eb",
                    o if o == c => "ec",
                    o if o == d => "ed",
                    _ => continue,
                };
                after.push((Element::Edge(EdgeId(k as u32)), name));
            }
            for (k, face) in rf.iter().enumerate().skip(nf) {
                // The face's corners, as far as a bounded walk goes.
                let mut corners = Vec::new();
                let start = face.halfedge.index();
                let mut h = start;
                while let Some(r) = rh.get(h) {
                    if corners.len() >= 8 {
                        break;
                    }
                    corners.push(r.vertex.0);
                    h = r.next.index();
                    if h == start {
                        break;
                    }
                }
                let name = if corners.contains(&b) && corners.contains(&c) {
                    "f2"
                } else if corners.contains(&b) && corners.contains(&d) {
                    "f3"
                } else {
                    continue;
                };
                after.push((Element::Face(FaceId(k as u32)), name));
            }
        }
    }
    (names, after)
}

pub(super) fn names_json(out: &mut String, names: &[(Element, &'static str)]) {
    list(out, names.iter(), |o, (e, n)| {
        o.push('[');
        element(o, *e);
        let _ = write!(o, ",\"{n}\"]");
    });
}

/// Each element of `sent` (a relabelled input) by its id in `case` (the
/// fixture's numbering), from the vertex correspondence `case_of`: a
/// halfedge by its two ends, an edge and a face by their halfedges.
/// `None` when the two numberings are the same.
pub(super) fn case_numbering(
    sent: &Mesh,
    case: &Mesh,
    case_of: &[Option<usize>],
) -> Option<[Vec<i64>; 4]> {
    let (sv, se, sf, sh) = sent.records();
    let (cv, _, _, ch) = case.records();
    if sv.len() != cv.len() || sh.len() != ch.len() {
        return None;
    }
    let mut by_ends = std::collections::HashMap::new();
    for (i, h) in ch.iter().enumerate() {
        let to = ch.get(h.twin.index()).map(|t| t.vertex.index());
        by_ends.insert((h.vertex.index(), to), i);
    }
    let hmap: Vec<i64> = sh
        .iter()
        .map(|h| {
            let from = case_of.get(h.vertex.index()).copied().flatten();
            let to = sh
                .get(h.twin.index())
                .and_then(|t| case_of.get(t.vertex.index()).copied().flatten());
            match (from, to) {
                (Some(a), Some(b)) => by_ends.get(&(a, Some(b))).map_or(-1, |&i| i as i64),
                _ => -1,
            }
        })
        .collect();
    let via = |h: usize, pick: fn(&halfedge::Halfedge) -> usize| -> i64 {
        match hmap.get(h) {
            Some(&c) if c >= 0 => ch.get(c as usize).map_or(-1, |r| pick(r) as i64),
            _ => -1,
        }
    };
    let vmap: Vec<i64> = (0..sv.len())
        .map(|i| case_of.get(i).copied().flatten().map_or(-1, |c| c as i64))
        .collect();
    let emap: Vec<i64> = se
        .iter()
        .map(|e| via(e.halfedge.index(), |r| r.edge.index()))
        .collect();
    let fmap: Vec<i64> = sf
        .iter()
        .map(|f| via(f.halfedge.index(), |r| r.face.index()))
        .collect();
    let identity = |m: &[i64]| m.iter().enumerate().all(|(i, &c)| c == i as i64);
    if identity(&vmap) && identity(&hmap) && identity(&emap) && identity(&fmap) {
        return None;
    }
    Some([vmap, emap, fmap, hmap])
}

/// What changed in a mesh's arrays (as [`mesh_json`] writes them) since
/// the frame before: per array that changed, its new length then
/// index, value pairs (`null` for an array the mesh no longer has). A
/// split changes a dozen records, so the frames of a subdivision cost
/// little more than one mesh.
fn mesh_delta(out: &mut String, before: &serde_json::Value, after: &serde_json::Value) {
    use serde_json::Value;
    let (Some(b), Some(a)) = (before.as_object(), after.as_object()) else {
        out.push_str("{}");
        return;
    };
    let empty = Vec::new();
    let mut first = true;
    out.push('{');
    let keys: std::collections::BTreeSet<&String> = b.keys().chain(a.keys()).collect();
    for key in keys {
        let old = b.get(key).and_then(Value::as_array);
        let Some(new) = a.get(key).and_then(Value::as_array) else {
            if old.is_some() {
                out.push_str(if first { "" } else { "," });
                first = false;
                string(out, key);
                out.push_str(":null");
            }
            continue;
        };
        let old = old.unwrap_or(&empty);
        let changed: Vec<usize> = (0..new.len())
            .filter(|&i| old.get(i) != Some(&new[i]))
            .collect();
        if changed.is_empty() && old.len() == new.len() {
            continue;
        }
        out.push_str(if first { "" } else { "," });
        first = false;
        string(out, key);
        let _ = write!(out, ":[{}", new.len());
        for i in changed {
            let _ = write!(out, ",{i},{}", new[i]);
        }
        out.push(']');
    }
    out.push('}');
}

/// Frames as JSON: `{"list":[{"label":..,"mesh":..},{"label":..,"delta":..},..],
/// "firstBroken":k, "cut":..}`: the first frame whole, each later one as
/// its [`mesh_delta`] from the one before; at most [`FRAME_LIMIT`] frames
/// and [`FRAME_BYTES`] bytes.
pub(super) fn frames_json(out: &mut String, frames: &Frames) {
    let start = out.len();
    out.push_str("{\"list\":[");
    let mut written = 0;
    let mut previous: Option<serde_json::Value> = None;
    for (label, mesh) in frames.meshes.iter().take(FRAME_LIMIT) {
        let mut whole = String::new();
        mesh_json(&mut whole, mesh);
        let value: serde_json::Value =
            serde_json::from_str(&whole).unwrap_or(serde_json::Value::Null);
        let mut one = String::from("{\"label\":");
        string(&mut one, label);
        match &previous {
            Some(before) => {
                one.push_str(",\"delta\":");
                mesh_delta(&mut one, before, &value);
            }
            None => {
                one.push_str(",\"mesh\":");
                one.push_str(&whole);
            }
        }
        previous = Some(value);
        one.push('}');
        if written > 0 && out.len() - start + one.len() > FRAME_BYTES {
            break;
        }
        if written > 0 {
            out.push(',');
        }
        out.push_str(&one);
        written += 1;
    }
    out.push_str("],\"firstBroken\":");
    match frames.first_broken.filter(|&k| k < written) {
        Some(k) => {
            let _ = write!(out, "{k}");
        }
        None => out.push_str("null"),
    }
    out.push_str(",\"cut\":");
    let total = frames.meshes.len();
    let mut cut: Vec<String> = frames.cut.iter().cloned().collect();
    if written < total {
        cut.push(format!(
            "the page shows the first {written} of {total} frames"
        ));
    }
    if cut.is_empty() {
        out.push_str("null");
    } else {
        string(out, &cut.join("; "));
    }
    out.push('}');
}
