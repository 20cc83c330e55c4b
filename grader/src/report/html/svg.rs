//! The static pictures: orthographic projections drawn as inline SVG,
//! faces filled with flat shading by normal and painted far to near, marks
//! on top. They are what a page without script (or Gradescope's HTML)
//! shows; the inspector draws the same marks in 3D.

use std::collections::HashSet;
use std::fmt::Write as _;

use super::escape;
use super::marks::{Marks, Named, LABEL_LIMIT};
use super::view::{Camera, Prepared, Screen, SIZE};

/// Vertex dots are drawn on meshes up to this many vertices (beyond, they
/// would hide the faces).
pub(super) const DOT_LIMIT: usize = 400;

/// A position in a picture in tenths of a pixel (pictures use one
/// decimal: finer is invisible, coarser makes dense meshes jagged).
pub(super) fn tenths(x: f64) -> i64 {
    (x.clamp(0.0, SIZE) * 10.0).round() as i64
}

/// A number of tenths as SVG writes it: `12.3`, `-0.4`, `7`.
pub(super) fn put(out: &mut String, t: i64) {
    if t < 0 {
        out.push('-');
    }
    let t = t.abs();
    if t % 10 == 0 {
        let _ = write!(out, "{}", t / 10);
    } else {
        let _ = write!(out, "{}.{}", t / 10, t % 10);
    }
}

pub(super) fn coord(out: &mut String, x: f64) {
    put(out, tenths(x));
}

/// Path data: `M` to the first point, then relative moves (shorter than
/// absolute ones, and exact since both ends are rounded first).
pub(super) fn polyline(out: &mut String, pts: &[Screen], close: bool) {
    let mut last = (0, 0);
    for (k, s) in pts.iter().enumerate() {
        let t = (tenths(s.x), tenths(s.y));
        if k == 0 {
            out.push('M');
            put(out, t.0);
            out.push(' ');
            put(out, t.1);
            out.push('l');
        } else {
            // A minus sign separates numbers as well as a space does.
            let (dx, dy) = (t.0 - last.0, t.1 - last.1);
            if k > 1 && dx >= 0 {
                out.push(' ');
            }
            put(out, dx);
            if dy >= 0 {
                out.push(' ');
            }
            put(out, dy);
        }
        last = t;
    }
    if pts.len() == 1 {
        out.push_str("0 0");
    }
    if close {
        out.push('z');
    }
}

/// Projected faces bucketed in a coarse screen grid, to tell whether a
/// point is behind the surface.
pub(super) struct Occluder {
    pub(super) triangles: Vec<[Screen; 3]>,
    pub(super) cells: Vec<Vec<u32>>,
}

pub(super) const CELLS: usize = 24;

impl Occluder {
    pub(super) fn new(triangles: Vec<[Screen; 3]>) -> Occluder {
        let mut cells = vec![Vec::new(); CELLS * CELLS];
        let cell = |v: f64| ((v / SIZE * CELLS as f64) as usize).min(CELLS - 1);
        for (i, t) in triangles.iter().enumerate() {
            let (x0, x1) = (
                t.iter().map(|s| s.x).fold(f64::MAX, f64::min),
                t.iter().map(|s| s.x).fold(f64::MIN, f64::max),
            );
            let (y0, y1) = (
                t.iter().map(|s| s.y).fold(f64::MAX, f64::min),
                t.iter().map(|s| s.y).fold(f64::MIN, f64::max),
            );
            for cy in cell(y0)..=cell(y1) {
                for cx in cell(x0)..=cell(x1) {
                    cells[cy * CELLS + cx].push(i as u32);
                }
            }
        }
        Occluder { triangles, cells }
    }

    /// Whether some face lies in front of `s` (by more than a pixel).
    pub(super) fn hides(&self, s: Screen) -> bool {
        let cell = |v: f64| ((v / SIZE * CELLS as f64) as usize).min(CELLS - 1);
        self.cells[cell(s.y) * CELLS + cell(s.x)].iter().any(|&i| {
            let [a, b, c] = self.triangles[i as usize];
            let d = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
            if d.abs() < 1e-9 {
                return false;
            }
            let l1 = ((b.y - c.y) * (s.x - c.x) + (c.x - b.x) * (s.y - c.y)) / d;
            let l2 = ((c.y - a.y) * (s.x - c.x) + (a.x - c.x) * (s.y - c.y)) / d;
            let l3 = 1.0 - l1 - l2;
            let inside = l1 >= -1e-6 && l2 >= -1e-6 && l3 >= -1e-6;
            inside && l1 * a.depth + l2 * b.depth + l3 * c.depth > s.depth + 1.0
        })
    }
}

pub(super) fn shade(base: [f64; 3], k: f64) -> String {
    let c = base.map(|x| (x * k).round().clamp(0.0, 255.0) as u8);
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The face shades: flat shading by the angle to a light beside the eye.
pub(super) fn shade_css() -> String {
    let mut css = String::new();
    for k in 0..=15 {
        let light = k as f64 / 15.0;
        let _ = write!(
            css,
            ".s{k}{{fill:{}}}",
            shade([150.0, 182.0, 226.0], 0.5 + 0.55 * light)
        );
    }
    for k in 0..=3 {
        let light = k as f64 / 3.0;
        let _ = write!(
            css,
            ".b{k}{{fill:{}}}",
            shade([240.0, 222.0, 190.0], 0.82 + 0.2 * light)
        );
    }
    css
}

/// Red marks drawn one element each (with `data-` attributes and a
/// tooltip) up to this many per kind and picture; beyond, they are drawn
/// as one path, those behind the surface left out, the ghosts in *yours*
/// too (the expected picture shows them).
pub(super) const SINGLE_LIMIT: usize = 40;

/// One picture of one shape as an inline `<svg>`.
pub(super) fn draw(out: &mut String, cam: &Camera, p: &Prepared, marks: &Marks, caption: &str) {
    let shape = p.shape;
    let proj: Vec<Option<Screen>> = shape
        .points
        .iter()
        .map(|q| q.map(|q| cam.project(q)))
        .collect();
    let at = |i: usize| proj.get(i).copied().flatten();
    let _ = write!(
        out,
        "<svg class=\"view\" viewBox=\"0 0 {SIZE} {SIZE}\" width=\"{SIZE}\" height=\"{SIZE}\" role=\"img\" aria-label=\"{}\">",
        escape(caption)
    );
    // Faces, far to near.
    let mut painted: Vec<(f64, String)> = Vec::new();
    let mut triangles = Vec::new();
    for face in &shape.faces {
        let Some(screen) = face.iter().map(|&v| at(v)).collect::<Option<Vec<Screen>>>() else {
            continue;
        };
        let Some(normal) = shape
            .face_normal(face)
            .and_then(|n| (n * p.outward).try_normalize())
        else {
            continue;
        };
        let facing = normal.dot(cam.dir) > 0.0;
        if p.closed && !facing {
            continue;
        }
        // Shades are CSS classes (`s0`..`s15` in front, `b0`..`b3` behind):
        // shorter than a colour per face, and flat shading needs few.
        let light = normal.dot(cam.light).abs();
        let fill = if facing {
            format!("s{}", (light * 15.0).round() as usize)
        } else {
            format!("b{}", (light * 3.0).round() as usize)
        };
        let depth = screen.iter().map(|s| s.depth).sum::<f64>() / screen.len() as f64;
        let mut d = String::from("<path d=\"");
        polyline(&mut d, &screen, true);
        let _ = write!(d, "\" class=\"{fill}\"/>");
        painted.push((depth, d));
        for k in 1..screen.len() - 1 {
            triangles.push([screen[0], screen[k], screen[k + 1]]);
        }
    }
    painted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let _ = write!(
        out,
        "<g class=\"faces\" stroke-width=\"{}\">",
        if painted.len() > 600 { 0.3 } else { 0.6 }
    );
    for (_, path) in &painted {
        out.push_str(path);
    }
    out.push_str("</g>");
    let occluder = Occluder::new(triangles);
    let hidden = |s: Screen| occluder.hides(s);
    let midpoint = |a: Screen, b: Screen| Screen {
        x: (a.x + b.x) / 2.0,
        y: (a.y + b.y) / 2.0,
        depth: (a.depth + b.depth) / 2.0,
        pinned: false,
    };
    // Many segments or dots as one path: `class` styles them.
    let batch = |out: &mut String, class: &str, items: &[Vec<Screen>]| {
        if items.is_empty() {
            return;
        }
        let _ = write!(out, "<path class=\"{class}\" d=\"");
        for item in items {
            polyline(out, item, false);
        }
        out.push_str("\"/>");
    };
    let line = |out: &mut String, a: Screen, b: Screen, attrs: &str| {
        out.push_str("<line x1=\"");
        coord(out, a.x);
        out.push_str("\" y1=\"");
        coord(out, a.y);
        out.push_str("\" x2=\"");
        coord(out, b.x);
        out.push_str("\" y2=\"");
        coord(out, b.y);
        let _ = write!(out, "\"{attrs}/>");
    };
    let circle = |out: &mut String, s: Screen, r: f64, attrs: &str, title: Option<&str>| {
        out.push_str("<circle cx=\"");
        coord(out, s.x);
        out.push_str("\" cy=\"");
        coord(out, s.y);
        let _ = write!(out, "\" r=\"{r}\"{attrs}");
        match title {
            Some(t) => {
                let _ = write!(out, "><title>{}</title></circle>", escape(t));
            }
            None => out.push_str("/>"),
        }
    };
    let behind = |s: Screen| if hidden(s) { " behind" } else { "" };

    // Edges that are no face's side.
    let (mut front, mut back) = (Vec::new(), Vec::new());
    for &[a, b] in &p.loose {
        if let (Some(sa), Some(sb)) = (at(a), at(b)) {
            if hidden(midpoint(sa, sb)) {
                back.push(vec![sa, sb]);
            } else {
                front.push(vec![sa, sb]);
            }
        }
    }
    batch(out, "loose behind", &back);
    batch(out, "loose", &front);
    // Vertex dots, where seen.
    let red: HashSet<usize> = marks.wrong_points.iter().map(|(i, _)| *i).collect();
    if shape.len() <= DOT_LIMIT {
        let dots: Vec<Vec<Screen>> = proj
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.filter(|s| !red.contains(&i) && !hidden(*s)))
            .map(|s| vec![s])
            .collect();
        let class = if shape.len() > 150 {
            "dots small"
        } else {
            "dots"
        };
        batch(out, class, &dots);
    }
    // What the messages name.
    for named in &marks.named {
        let (pts, name, closed): (Vec<Screen>, &str, bool) = match named {
            Named::Vertex(v, name) => (at(*v).into_iter().collect(), name, false),
            Named::Edge([a, b], name) => (at(*a).into_iter().chain(at(*b)).collect(), name, false),
            Named::Face(corners, name) => (
                corners.iter().filter_map(|&v| at(v)).collect(),
                name,
                corners.len() > 2,
            ),
        };
        let Some(&first) = pts.first() else { continue };
        let _ = write!(
            out,
            "<g class=\"named\" data-name=\"{name}\"><title>{name}, named in the messages</title>"
        );
        if pts.len() == 1 {
            circle(out, first, 6.5, "", None);
        } else {
            out.push_str("<path d=\"");
            polyline(out, &pts, closed);
            out.push_str("\"/>");
        }
        let n = pts.len() as f64;
        let mid = Screen {
            x: pts.iter().map(|s| s.x).sum::<f64>() / n,
            y: pts.iter().map(|s| s.y).sum::<f64>() / n,
            ..first
        };
        out.push_str("<text x=\"");
        coord(out, (mid.x + 7.0).min(SIZE - 24.0));
        out.push_str("\" y=\"");
        coord(out, (mid.y + 12.0).min(SIZE - 3.0));
        let _ = write!(out, "\">{name}</text></g>");
    }
    // The case's edge and new vertex.
    for &[a, b] in &marks.focus_edges {
        if let (Some(sa), Some(sb)) = (at(a), at(b)) {
            let class = format!(" class=\"case-edge{}\"", behind(midpoint(sa, sb)));
            line(out, sa, sb, &class);
        }
    }
    for &v in &marks.focus_points {
        if let Some(s) = at(v) {
            circle(
                out,
                s,
                5.0,
                &format!(" class=\"case-vertex{}\"", behind(s)),
                None,
            );
        }
    }
    // Red: edges first, vertices on top.
    let yours = marks.side == "yours";
    let edge_kind = if yours { "extra-edge" } else { "missing-edge" };
    let wrong_edges: Vec<([usize; 2], Screen, Screen)> = marks
        .wrong_edges
        .iter()
        .filter_map(|&[a, b]| Some(([a, b], at(a)?, at(b)?)))
        .collect();
    if wrong_edges.len() <= SINGLE_LIMIT {
        for &([a, b], sa, sb) in &wrong_edges {
            let ends = |v: usize| {
                marks.labels.get(v).cloned().flatten().unwrap_or_else(|| {
                    if yours {
                        format!("v{v}")
                    } else {
                        "?".into()
                    }
                })
            };
            let attrs = format!(
                " class=\"wrong edge {edge_kind}{}\" data-edge=\"{}-{}\"",
                behind(midpoint(sa, sb)),
                ends(a),
                ends(b)
            );
            line(out, sa, sb, &attrs);
        }
    } else {
        let seen: Vec<Vec<Screen>> = wrong_edges
            .iter()
            .filter(|(_, a, b)| !hidden(midpoint(*a, *b)))
            .map(|(_, a, b)| vec![*a, *b])
            .collect();
        batch(out, &format!("wrong edge {edge_kind} many"), &seen);
    }
    if marks.ghost_edges.len() <= SINGLE_LIMIT {
        for &[a, b] in &marks.ghost_edges {
            line(
                out,
                cam.project(a),
                cam.project(b),
                " class=\"wrong edge missing-edge ghost\"",
            );
        }
    }
    if marks.moves.len() <= SINGLE_LIMIT {
        for &[a, b] in &marks.moves {
            line(
                out,
                cam.project(a),
                cam.project(b),
                " class=\"wrong edge move\"",
            );
        }
    }
    if marks.ghost_points.len() <= SINGLE_LIMIT {
        for (q, title) in &marks.ghost_points {
            let attrs = " class=\"wrong vertex missing-vertex ghost\"";
            circle(out, cam.project(*q), 4.0, attrs, Some(title));
        }
    }
    let vertex_kind = if yours {
        "wrong-vertex"
    } else {
        "missing-vertex"
    };
    let wrong_points: Vec<(usize, &str, Screen)> = marks
        .wrong_points
        .iter()
        .filter_map(|(v, title)| Some((*v, title.as_str(), at(*v)?)))
        .collect();
    if wrong_points.len() <= SINGLE_LIMIT {
        for &(v, title, s) in &wrong_points {
            let name = marks.labels.get(v).cloned().flatten();
            let name = match (yours, name) {
                (true, _) => format!("v{v}"),
                (false, Some(n)) => n,
                (false, None) => String::new(),
            };
            let mut title = title.to_string();
            if s.pinned {
                title.push_str(" (outside the picture: pinned to its border)");
            }
            if hidden(s) {
                title.push_str(" (behind the surface in this view)");
            }
            let attrs = format!(
                " class=\"wrong vertex {vertex_kind}{}\" data-vertex=\"{name}\"",
                behind(s)
            );
            circle(out, s, 3.2, &attrs, Some(&title));
        }
    } else {
        let seen: Vec<Vec<Screen>> = wrong_points
            .iter()
            .filter(|(_, _, s)| !hidden(*s))
            .map(|(_, _, s)| vec![*s])
            .collect();
        batch(out, &format!("wrong vertex {vertex_kind} many"), &seen);
    }
    // The student's ids, on small meshes, where seen (red ones always).
    if shape.len() < LABEL_LIMIT {
        out.push_str("<g class=\"labels\">");
        for (i, s) in proj.iter().enumerate() {
            let (Some(s), Some(Some(name))) = (s, marks.labels.get(i)) else {
                continue;
            };
            let is_red = red.contains(&i);
            if hidden(*s) && !is_red {
                continue;
            }
            out.push_str("<text x=\"");
            coord(out, s.x + 3.0);
            out.push_str("\" y=\"");
            coord(out, s.y - 3.0);
            let class = if is_red { " class=\"red\"" } else { "" };
            let _ = write!(out, "\"{class}>{}</text>", escape(name));
        }
        out.push_str("</g>");
    }
    out.push_str("</svg>");
}

/// The legend, drawn with the pictures' own classes.
pub(super) fn legend() -> String {
    let item = |svg: &str, text: &str| {
        format!(
            "<span><svg class=\"view\" width=\"34\" height=\"16\" viewBox=\"0 0 34 16\" style=\"display:inline;border:0;background:none\">{svg}</svg> {text}</span>"
        )
    };
    [
        item("<circle cx=\"17\" cy=\"8\" r=\"3.2\" class=\"wrong vertex\"/>", "a vertex of yours that no expected vertex matches (in <i>yours</i>), an expected vertex no vertex of yours matches (in <i>expected</i>)"),
        item("<circle cx=\"17\" cy=\"8\" r=\"4\" class=\"wrong vertex ghost\"/>", "where that expected vertex is"),
        item("<line x1=\"3\" y1=\"8\" x2=\"31\" y2=\"8\" class=\"wrong edge\"/>", "an edge of yours that is not expected (in <i>yours</i>), an expected edge you lack (in <i>expected</i>)"),
        item("<line x1=\"3\" y1=\"8\" x2=\"31\" y2=\"8\" class=\"wrong edge ghost\"/>", "where that missing edge should be"),
        item("<line x1=\"3\" y1=\"8\" x2=\"31\" y2=\"8\" class=\"wrong edge move\"/>", "from a vertex of yours to where it should be"),
        item("<line x1=\"3\" y1=\"8\" x2=\"31\" y2=\"8\" class=\"case-edge\"/>", "the case's edge (flipped, split or refused), or its new vertex"),
        item("<g class=\"named\"><path d=\"M3 8h28\"/></g>", "an element the messages name (<code>v7</code>, <code>e229</code>, <code>h40</code>, <code>f3</code>), labelled"),
        item("<rect x=\"4\" y=\"2\" width=\"26\" height=\"12\" fill=\"#f0dfbf\" stroke=\"#2a3a4f\" stroke-opacity=\".55\"/>", "the back of a face (seen through a hole)"),
        "<span>faded: behind the surface in that view. <code>v7</code>: your vertex ids (meshes under 60 vertices); hover a red mark for where it is</span>".to_string(),
    ]
    .join("\n")
}
