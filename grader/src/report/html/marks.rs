//! What is wrong, as marks: the student's result compared with the
//! expected one (matched, missing, extra), the elements the messages are
//! about, the case's edge, and where the pictures look from.

use halfedge::{DVec3, Element, Mesh};

use super::faces::{Shape, MAX_DEGREE};
use super::view::{views, Problems, View};
use super::{fmt_d, fmt_p, pair};
use crate::judge::fixture::{Fixture, Operation, Returns};
use crate::judge::matching;
use crate::judge::verdict::{CaseReport, Comparison, Entry, Level};

/// Meshes with fewer vertices get their ids written beside the vertices.
pub(super) const LABEL_LIMIT: usize = 60;

/// What is marked on one picture.
#[derive(Clone, Debug, Default)]
pub(super) struct Marks {
    /// Vertices drawn red, with their tooltip.
    pub(super) wrong_points: Vec<(usize, String)>,
    /// Edges drawn red.
    pub(super) wrong_edges: Vec<[usize; 2]>,
    /// Where an expected vertex nobody matched is: a hollow red ring.
    pub(super) ghost_points: Vec<(DVec3, String)>,
    /// Expected edges the student lacks, at the expected positions: dashed red.
    pub(super) ghost_edges: Vec<[DVec3; 2]>,
    /// From a vertex of yours to where it should be: dashed red.
    pub(super) moves: Vec<[DVec3; 2]>,
    /// The case's edge or new vertex, orange.
    pub(super) focus_edges: Vec<[usize; 2]>,
    pub(super) focus_points: Vec<usize>,
    /// Elements the messages name (`v7`, `e229`, `h40`, `f3`), purple.
    pub(super) named: Vec<Named>,
    /// A vertex's label (the student's id), for small meshes.
    pub(super) labels: Vec<Option<String>>,
    /// The `data-kind` of this picture's red markers: `yours`, `expected`.
    pub(super) side: &'static str,
}

/// An element a message names, found in the mesh it names it in.
#[derive(Clone, Debug)]
pub(super) enum Named {
    Vertex(usize, String),
    /// An edge or a halfedge: its two ends.
    Edge([usize; 2], String),
    /// A face: its corners, as far as its `next` walk goes.
    Face(Vec<usize>, String),
}

/// The most named elements drawn per case.
pub(super) const NAMED_LIMIT: usize = 12;

/// The elements a case's messages are about, in order, each once, in the
/// numbering of the mesh drawn (the labelling's, when the case failed on a
/// relabelled input: the pictures show the mesh as sent). The entries
/// carry them as data (`Entry::elements`): no message text is read.
pub(super) fn named_elements(entries: &[Entry]) -> Vec<Element> {
    let mut found = Vec::new();
    for named in entries
        .iter()
        .filter(|e| e.level != Level::Info)
        .flat_map(|e| &e.elements)
    {
        let element = named.labelled.unwrap_or(named.element);
        if !found.contains(&element) {
            found.push(element);
        }
    }
    found
}

/// Finds named elements in `mesh`, every id bounds-checked.
pub(super) fn resolve_names(mesh: &Mesh, names: &[Element]) -> Vec<Named> {
    let (vertices, edges, faces, halfedges) = mesh.records();
    let nv = vertices.len();
    let ends = |h: usize| -> Option<[usize; 2]> {
        let record = halfedges.get(h)?;
        let to = halfedges
            .get(record.twin.index())
            .or_else(|| halfedges.get(record.next.index()))?;
        let (a, b) = (record.vertex.index(), to.vertex.index());
        (a < nv && b < nv && a != b).then_some([a, b])
    };
    names
        .iter()
        .filter_map(|&element| {
            let name = element.to_string();
            match element {
                Element::Vertex(v) if v.index() < nv => Some(Named::Vertex(v.index(), name)),
                Element::Vertex(_) => None,
                Element::Edge(e) => Some(Named::Edge(
                    ends(edges.get(e.index())?.halfedge.index())?,
                    name,
                )),
                Element::Halfedge(h) => Some(Named::Edge(ends(h.index())?, name)),
                Element::Face(n) => {
                    let n = n.index();
                    let start = faces.get(n)?.halfedge.index();
                    let mut corners = Vec::new();
                    let mut h = start;
                    while let Some(record) = halfedges.get(h) {
                        if record.vertex.index() >= nv || corners.len() >= MAX_DEGREE {
                            break;
                        }
                        corners.push(record.vertex.index());
                        h = record.next.index();
                        if h == start {
                            break;
                        }
                    }
                    (corners.len() >= 2).then_some(Named::Face(corners, name))
                }
            }
        })
        .take(NAMED_LIMIT)
        .collect()
}

/// The judge's comparison ([`Comparison`], made on the mesh the page
/// draws) as the pictures use it: nothing is matched again here, so a
/// picture marks what the verdict says. Every id is bounds-checked
/// against the shapes drawn.
pub(super) struct Compared {
    /// Your vertices that matched no expected one.
    pub(super) extra_vertices: Vec<usize>,
    /// Expected vertices none of yours matched.
    pub(super) missing_vertices: Vec<usize>,
    /// Expected vertex -> your vertex matched with it (or standing for it,
    /// see `stands_for`).
    pub(super) student_of: Vec<Option<usize>>,
    /// One vertex of yours in the wrong place and the expected vertex it
    /// stands for, when the judge left exactly one of each unmatched: the
    /// pairing is then certain, and a dashed line shows the move.
    pub(super) stands_for: Option<(usize, usize)>,
    /// Expected edges you lack (expected ids), `None` when the judge did
    /// not compare edges.
    pub(super) missing_edges: Option<Vec<[usize; 2]>>,
    /// Your edges the expected result lacks (your ids).
    pub(super) extra_edges: Option<Vec<[usize; 2]>>,
}

pub(super) fn compared(c: &Comparison, yours: &Shape, expected: &Shape) -> Compared {
    let (ny, ne) = (yours.len(), expected.len());
    let mut student_of = vec![None; ne];
    for (s, e) in c.matched.iter().enumerate().take(ny) {
        if let Some(slot) = e.and_then(|e| student_of.get_mut(e)) {
            *slot = Some(s);
        }
    }
    let extra_vertices: Vec<usize> = c
        .extra_vertices
        .iter()
        .copied()
        .filter(|&v| v < ny)
        .collect();
    let missing_vertices: Vec<usize> = c
        .missing_vertices
        .iter()
        .copied()
        .filter(|&v| v < ne)
        .collect();
    let stands_for = match (&extra_vertices[..], &missing_vertices[..]) {
        ([s], [k]) => Some((*s, *k)),
        _ => None,
    };
    if let Some((s, k)) = stands_for {
        student_of[k] = Some(s);
    }
    let edges = |list: &Option<Vec<[usize; 2]>>, n: usize| {
        list.as_ref().map(|l| {
            l.iter()
                .filter(|[a, b]| *a < n && *b < n && a != b)
                .map(|&[a, b]| pair(a, b))
                .collect()
        })
    };
    Compared {
        missing_edges: edges(&c.missing_edges, ne),
        extra_edges: edges(&c.extra_edges, ny),
        extra_vertices,
        missing_vertices,
        student_of,
        stands_for,
    }
}

/// Everything shown for one case, computed before any HTML is written.
pub(super) struct CasePictures {
    pub(super) input: Shape,
    pub(super) expected: Shape,
    pub(super) yours: Option<Shape>,
    pub(super) marks_input: Marks,
    pub(super) marks_expected: Marks,
    pub(super) marks_yours: Marks,
    /// Why a view looks where it does, per view.
    pub(super) cameras: Vec<View>,
    /// Lines said under the pictures (vertices not drawn, and so on).
    pub(super) notes: Vec<String>,
    /// Input vertex as sent -> the fixture's (the case's) vertex.
    pub(super) case_of: Vec<Option<usize>>,
    /// Expected vertex -> the student's vertex matched or paired with it.
    pub(super) student_of_expected: Vec<Option<usize>>,
    /// Expected vertex -> the input vertex (as sent) it is: the expected
    /// result keeps the input's ids and appends new vertices.
    pub(super) input_of_expected: Vec<Option<usize>>,
    /// The case's edge in the input as sent.
    pub(super) case_edge: Option<[usize; 2]>,
    /// The expected result's new vertex (a split's), expected numbering.
    pub(super) new_vertex: Option<usize>,
}

pub(super) fn labels_for(n: usize, name: impl Fn(usize) -> Option<usize>) -> Vec<Option<String>> {
    if n >= LABEL_LIMIT {
        return Vec::new();
    }
    (0..n).map(|i| name(i).map(|v| format!("v{v}"))).collect()
}

pub(super) fn pictures(f: &Fixture, r: &CaseReport) -> CasePictures {
    let fixture_input = Shape::from_faces(&f.input.positions, &f.input.faces);
    let input = r
        .input
        .as_ref()
        .map(Shape::from_mesh)
        .unwrap_or_else(|| fixture_input.clone());
    let expected = Shape::expected(f);
    let yours = r.result.as_ref().map(Shape::from_mesh);
    let tol = f.tolerance.max(1e-300);
    let n_in = fixture_input.len();

    // The input as sent has its ids permuted: find each fixture vertex's id.
    let as_array = |s: &Shape| -> Vec<[f64; 3]> {
        s.points
            .iter()
            .map(|p| p.map_or([f64::NAN; 3], |p| p.to_array()))
            .collect()
    };
    // Where each fixture vertex went in the input as sent: the labelling's
    // permutation when the case failed on a relabelled input (relabel.rs
    // made it), else the identity (the mesh as built from the faces).
    let mut id_of: Vec<Option<usize>> = (0..n_in).map(Some).collect();
    if let Some(l) = &r.labelling {
        for (i, slot) in id_of.iter_mut().enumerate() {
            *slot = l.permutation.vertices.get(i).map(|&v| v as usize);
        }
    }
    let mut case_of = vec![None; input.points.len()];
    for (fixture, sent) in id_of.iter().enumerate() {
        if let Some(slot) = sent.and_then(|s| case_of.get_mut(s)) {
            *slot = Some(fixture);
        }
    }
    let id = |i: usize| id_of.get(i).copied().flatten();

    // The judge's comparison, made on `r.result`, the mesh drawn.
    let cmp = match (&r.comparison, &yours) {
        (Some(c), Some(y)) => Some(compared(c, y, &expected)),
        _ => None,
    };
    let mut notes = Vec::new();

    // Input: the case's edge.
    let case_edge = match f.operation {
        Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] } => {
            id(a).zip(id(b)).map(|(a, b)| pair(a, b))
        }
        Operation::Subdivide { .. } | Operation::Sequence { .. } => None,
    };
    let mut marks_input = Marks {
        focus_edges: case_edge.into_iter().collect(),
        labels: labels_for(input.len(), Some),
        side: "input",
        ..Marks::default()
    };

    // Expected: its labels are the student's ids (matched, else the id the
    // vertex had in the input), its red what nobody matched.
    let student_of = |i: usize| {
        cmp.as_ref()
            .and_then(|c| c.student_of.get(i).copied().flatten())
    };
    let mut marks_expected = Marks {
        labels: labels_for(expected.len(), |i| {
            student_of(i).or_else(|| if i < n_in { id(i) } else { None })
        }),
        side: "expected",
        ..Marks::default()
    };
    let new_vertex = match f.expected.returns {
        Some(Returns::Vertex { position }) => matching::nearest(&as_array(&expected), position)
            .filter(|&(_, d)| d <= tol)
            .map(|(k, _)| k),
        _ => None,
    };
    match (f.expected.returns, f.operation) {
        (Some(Returns::Edge { ends: [c, d] }), _) => marks_expected.focus_edges.push(pair(c, d)),
        (
            Some(Returns::Refused),
            Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] },
        ) => marks_expected.focus_edges.push(pair(a, b)),
        _ => {}
    }
    marks_expected.focus_points.extend(new_vertex);

    let mut marks_yours = Marks {
        side: "yours",
        ..Marks::default()
    };
    if let Some(y) = &yours {
        marks_yours.labels = labels_for(y.len(), Some);
        let not_drawn: Vec<String> = y
            .points
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_none())
            .map(|(i, _)| format!("v{i}"))
            .collect();
        if !not_drawn.is_empty() {
            let more = if not_drawn.len() > 8 {
                format!(" and {} more", not_drawn.len() - 8)
            } else {
                String::new()
            };
            notes.push(format!(
                "not drawn, their position is not a finite number: {}{more}",
                not_drawn[..not_drawn.len().min(8)].join(", ")
            ));
        }
        // The case's element, where the student has it.
        for &[a, b] in &marks_expected.focus_edges {
            if let (Some(a), Some(b)) = (student_of(a), student_of(b)) {
                if y.edges.contains(&pair(a, b)) {
                    marks_yours.focus_edges.push(pair(a, b));
                }
            }
        }
        marks_yours
            .focus_points
            .extend(new_vertex.and_then(student_of));
    }
    // Elements the messages name, where the student's code left them (or
    // in the input, when it left no mesh).
    if !r.passed {
        let names = named_elements(&r.entries);
        match (&r.result, &r.input) {
            (Some(mesh), _) => marks_yours.named = resolve_names(mesh, &names),
            (None, Some(mesh)) => marks_input.named = resolve_names(mesh, &names),
            (None, None) => {}
        }
    }
    // Red only on a failure (a pass may differ within the tolerance).
    if let (Some(c), Some(y), false) = (&cmp, &yours, r.passed) {
        for &s in &c.extra_vertices {
            let Some(p) = y.point(s) else { continue };
            let title = match c.stands_for.and_then(|(_, k)| expected.point(k)) {
                Some(q) if c.stands_for.is_some_and(|(m, _)| m == s) => {
                    marks_yours.moves.push([p, q]);
                    format!(
                        "your v{s} is at {}: it should be at {} ({} away)",
                        fmt_p(p),
                        fmt_p(q),
                        fmt_d(p.distance(q))
                    )
                }
                _ => format!(
                    "your v{s} at {}: no expected vertex is within {} of it",
                    fmt_p(p),
                    f.tolerance
                ),
            };
            marks_yours.wrong_points.push((s, title));
        }
        for &k in &c.missing_vertices {
            let Some(q) = expected.point(k) else { continue };
            let stands = match c.student_of[k] {
                Some(s) => format!("; your v{s} stands for it"),
                None => String::new(),
            };
            let title = format!(
                "expected a vertex at {}: none of yours is within {}{stands}",
                fmt_p(q),
                f.tolerance
            );
            marks_expected.wrong_points.push((k, title.clone()));
            marks_yours.ghost_points.push((q, title));
        }
        let missing = c.missing_edges.clone().unwrap_or_default();
        // A missing edge is drawn between your vertices where you have them.
        let place = |k: usize| {
            c.student_of[k]
                .and_then(|s| y.point(s))
                .or_else(|| expected.point(k))
        };
        marks_yours.ghost_edges = missing
            .iter()
            .filter_map(|&[a, b]| Some([place(a)?, place(b)?]))
            .collect();
        let missing_is_empty = missing.is_empty();
        marks_expected.wrong_edges = missing;
        marks_yours.wrong_edges = c.extra_edges.clone().unwrap_or_default();
        let vertices_right = c.extra_vertices.is_empty() && c.missing_vertices.is_empty();
        let edges_compared = c.missing_edges.is_some() && c.extra_edges.is_some();
        if !edges_compared {
            notes.push(if vertices_right {
                "the edges were not compared (see the messages)".to_string()
            } else {
                "the edges were not compared: the vertices were wrong first".to_string()
            });
        } else if vertices_right && missing_is_empty && c.extra_edges.iter().all(Vec::is_empty) {
            notes.push(
                "your mesh has the expected vertices and edges: what failed is not in its shape (see the messages)"
                    .to_string(),
            );
        }
    } else if yours.is_some() && !r.passed {
        notes.push(if r.invalid.is_some() {
            "nothing is red: your mesh is not valid, so the grader compared none of its positions or edges; purple is what the messages name"
                .to_string()
        } else {
            "nothing is red: the grader did not compare your mesh with the expected one (see the messages)"
                .to_string()
        });
    }

    let cameras = views(
        &input,
        &expected,
        yours.as_ref(),
        case_edge,
        Problems {
            expected_point: marks_expected.wrong_points.first().map(|p| p.0),
            yours_point: marks_yours.wrong_points.first().map(|p| p.0),
            expected_edge: marks_expected.wrong_edges.first().copied(),
        },
    );
    let student_of_expected = (0..expected.len()).map(student_of).collect();
    let input_of_expected = (0..expected.len())
        .map(|i| if i < n_in { id(i) } else { None })
        .collect();
    CasePictures {
        input,
        expected,
        yours,
        marks_input,
        marks_expected,
        marks_yours,
        cameras,
        notes,
        case_of,
        student_of_expected,
        input_of_expected,
        case_edge,
        new_vertex,
    }
}
