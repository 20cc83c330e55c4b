//! The child process: runs one case's student function on its input mesh
//! and writes what happened as JSON for the parent to judge. All judging is
//! done in the parent, so nothing the student's code prints or does here can
//! pass for a verdict.

use std::cell::RefCell;
use std::panic::{self, AssertUnwindSafe};
use std::path::Path;

use halfedge::{EdgeId, Mesh, VertexId};
use serde::{Deserialize, Serialize};

use crate::fixture::{Fixture, Operation};
use crate::Implementation;

/// Element counts: vertices, edges, faces (with holes), halfedges.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counts {
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    pub halfedges: usize,
}

impl Counts {
    pub fn of(mesh: &Mesh) -> Counts {
        Counts {
            vertices: mesh.num_vertices(),
            edges: mesh.num_edges(),
            faces: mesh.num_faces(),
            halfedges: mesh.num_halfedges(),
        }
    }
}

/// What a student function returned.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Returned {
    /// `loop_subdivide` returns nothing.
    Unit,
    Nothing,
    Edge {
        given: u32,
        got: u32,
    },
    Vertex {
        id: u32,
        /// Missing when the id names no vertex.
        position: Option<[f64; 3]>,
    },
}

/// The mesh after the operation, read only when it validated.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshResult {
    pub positions: Vec<[f64; 3]>,
    pub edges: Vec<[usize; 2]>,
    /// For a returned edge: the vertices it joins.
    pub returned_edge_ends: Option<[usize; 2]>,
    /// For a returned vertex: where its halfedge leads.
    pub returned_vertex_leads_to: Option<usize>,
}

/// Everything the parent needs to judge the case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Outcome {
    /// The student function returned.
    Finished {
        returned: Returned,
        before: Counts,
        after: Counts,
        /// `validate()`'s complaint, as "message (element)".
        invalid: Option<String>,
        mesh: Option<MeshResult>,
    },
    /// It panicked (a `todo!()` included).
    Panicked {
        message: String,
        location: Option<String>,
    },
    /// The fixture's input could not be set up: not the student's fault.
    Setup { message: String },
}

thread_local! {
    static LAST_PANIC: RefCell<Option<(String, Option<String>)>> = const { RefCell::new(None) };
}

fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "(a panic with a non-text payload)".to_string()
    }
}

/// Runs `f`, turning a panic into its message and location. The default
/// panic hook is silenced so no backtrace reaches the student's screen.
fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, (String, Option<String>)> {
    panic::set_hook(Box::new(|info| {
        let location = info
            .location()
            .map(|l| format!("{}:{}:{}", l.file(), l.line(), l.column()));
        LAST_PANIC.with(|p| *p.borrow_mut() = Some((panic_text(info.payload()), location)));
    }));
    let result = panic::catch_unwind(AssertUnwindSafe(f));
    let _ = panic::take_hook();
    result.map_err(|payload| {
        LAST_PANIC
            .with(|p| p.borrow_mut().take())
            .unwrap_or_else(|| (panic_text(payload.as_ref()), None))
    })
}

/// How many elements the mesh may grow to: generous for any correct answer,
/// small enough to stop runaway splitting in well under a second.
fn budget(fixture: &Fixture) -> usize {
    let e = &fixture.expected;
    // V + E + F + H of the expected result, bounded by 2E for faces and halfedges.
    let expected = e.positions.len() + e.edges.len() * 5;
    (expected * 16).max(10_000)
}

fn edge_of(mesh: &Mesh, [a, b]: [usize; 2]) -> Result<EdgeId, String> {
    mesh.edge_between(a, b)
        .ok_or_else(|| format!("the input has no edge between vertices {a} and {b}"))
}

/// Runs the case and returns what happened.
pub fn run_case(fixture: &Fixture, imp: &Implementation) -> Outcome {
    let mut mesh = match fixture.input.to_mesh() {
        Ok(m) => m,
        Err(e) => {
            return Outcome::Setup {
                message: format!("input mesh: {e}"),
            }
        }
    };
    let target = match fixture.operation {
        Operation::Flip { edge } | Operation::Split { edge } => match edge_of(&mesh, edge) {
            Ok(e) => Some(e),
            Err(message) => return Outcome::Setup { message },
        },
        Operation::Subdivide { .. } => None,
    };
    let before = Counts::of(&mesh);
    mesh.set_element_budget(Some(budget(fixture)));

    let ran = guarded(|| match fixture.operation {
        Operation::Flip { .. } => {
            let given = target.expect("flip has an edge");
            match (imp.flip_edge)(&mut mesh, given) {
                None => Returned::Nothing,
                Some(got) => Returned::Edge {
                    given: given.0,
                    got: got.0,
                },
            }
        }
        Operation::Split { .. } => {
            match (imp.split_edge)(&mut mesh, target.expect("split has an edge")) {
                None => Returned::Nothing,
                Some(v) => Returned::Vertex {
                    id: v.0,
                    position: None,
                },
            }
        }
        Operation::Subdivide { rounds } => {
            for _ in 0..rounds {
                (imp.loop_subdivide)(&mut mesh);
            }
            Returned::Unit
        }
    });
    let mut returned = match ran {
        Ok(r) => r,
        Err((message, location)) => return Outcome::Panicked { message, location },
    };
    mesh.set_element_budget(None);
    if let Returned::Vertex { id, position } = &mut returned {
        if (*id as usize) < mesh.num_vertices() {
            *position = Some(mesh[VertexId(*id)].pos.to_array());
        }
    }

    let after = Counts::of(&mesh);
    let invalid = mesh.validate().err().map(|e| e.to_string());
    let result = if invalid.is_none() {
        // A valid mesh can be read without panicking; guard all the same.
        guarded(|| read_result(&mesh, &returned)).ok()
    } else {
        None
    };
    Outcome::Finished {
        returned,
        before,
        after,
        invalid,
        mesh: result,
    }
}

fn read_result(mesh: &Mesh, returned: &Returned) -> MeshResult {
    let mut result = MeshResult {
        positions: mesh.positions().iter().map(|p| p.to_array()).collect(),
        edges: mesh.edge_list(),
        returned_edge_ends: None,
        returned_vertex_leads_to: None,
    };
    match *returned {
        Returned::Edge { got, .. } if (got as usize) < mesh.num_edges() => {
            let (a, b) = mesh.edge_vertices(EdgeId(got));
            result.returned_edge_ends = Some([a.index(), b.index()]);
        }
        Returned::Vertex { id, .. } if (id as usize) < mesh.num_vertices() => {
            let h = mesh[VertexId(id)].halfedge;
            result.returned_vertex_leads_to = Some(mesh.halfedge_dst(h).index());
        }
        _ => {}
    }
    result
}

/// The child's whole job: read the fixture, run, write the outcome.
pub fn child_main(fixture_path: &Path, result_path: &Path, imp: &Implementation) -> i32 {
    // The student's log lines show up in the captured output.
    halfedge::logging::init(halfedge::logging::Color::Never);
    let outcome = match crate::fixture::load(fixture_path) {
        Ok(fixture) => run_case(&fixture, imp),
        Err(e) => Outcome::Setup {
            message: e.to_string(),
        },
    };
    let text = serde_json::to_string(&outcome).expect("outcomes serialize");
    match std::fs::write(result_path, text) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("grader child: cannot write {}: {e}", result_path.display());
            3
        }
    }
}
