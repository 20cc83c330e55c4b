//! The parent's reading of what a child sent back, as how the case ended
//! ([`CaseEnd`]): the counts, the first broken link, the result as
//! positions and edges, what the contract pins besides the shape. All of
//! it runs in the parent, on data only, so nothing the student's code does
//! can pass for a verdict.

use halfedge::{EdgeId, Mesh, VertexId};

use crate::isolate::end::{
    CaseEnd, Counts, Finished, MeshResult, Problem, Returned, SequenceRan, SplitIds,
};
use crate::isolate::guard::guarded;
use crate::isolate::wire::{Answer, Op, Ran};

/// The parent's reading of what the child sent back, converted into how
/// the case ended: counts, validation, the result as positions and edges.
/// `input` is the mesh that was sent, `op` the operation as sent (in the
/// mesh's own ids).
pub fn analyze(op: Op, input: &Mesh, ran: Ran) -> CaseEnd {
    let (answer, mesh) = match ran {
        Ran::Panicked {
            message,
            location,
            grew_past,
            ..
        } => {
            return CaseEnd::Panicked {
                message,
                location,
                grew_past,
            }
        }
        Ran::Returned { answer, mesh, .. } => (answer, mesh),
        Ran::Sequence { steps, mesh, panic } => {
            let checked = guarded(|| {
                let invalid = Problem::find(&mesh);
                let result = invalid.is_none().then(|| MeshResult {
                    positions: mesh.positions().iter().map(|p| p.to_array()).collect(),
                    edges: mesh.edge_list(),
                    returned_edge_ends: None,
                    returned_vertex_leads_to: None,
                    split: None,
                });
                (invalid, result)
            });
            let (invalid, result) = checked
                .unwrap_or_else(|(message, _)| (Some(Problem::Unwalkable { message }), None));
            return CaseEnd::Sequence(Box::new(SequenceRan {
                steps,
                panic,
                before: Counts::of(input),
                after: Counts::of(&mesh),
                invalid,
                mesh: result.map(Box::new),
            }));
        }
    };
    let returned = match (answer, op) {
        (Answer::Unit, _) => Returned::Unit,
        (Answer::Nothing, _) => Returned::Nothing,
        (Answer::Edge(got), Op::Flip(given) | Op::Split(given)) => Returned::Edge {
            given: given.0,
            got: got.0,
        },
        (Answer::Edge(got), _) => Returned::Edge {
            given: got.0,
            got: got.0,
        },
        (Answer::Vertex(v), _) => Returned::Vertex {
            id: v.0,
            position: (v.index() < mesh.num_vertices()).then(|| mesh[v].pos.to_array()),
        },
    };
    let unchanged = same_records(input, &mesh);
    // The checks walk a mesh the student's code built: guard them all the same.
    let checked = guarded(|| {
        let invalid = Problem::find(&mesh);
        let result = invalid
            .is_none()
            .then(|| read_result(op, input, &mesh, &returned));
        (invalid, result)
    });
    let (invalid, result) =
        checked.unwrap_or_else(|(message, _)| (Some(Problem::Unwalkable { message }), None));
    CaseEnd::Returned(Box::new(Finished {
        returned,
        before: Counts::of(input),
        after: Counts::of(&mesh),
        invalid,
        mesh: result.map(Box::new),
        unchanged,
    }))
}

/// What a split left on the ids it was given (`e` and its faces in the
/// input), for a mesh that validated.
fn split_ids(input: &Mesh, mesh: &Mesh, e: EdgeId, m: VertexId) -> Option<SplitIds> {
    if e.index() >= input.num_edges() || e.index() >= mesh.num_edges() {
        return None;
    }
    let h = input[e].halfedge;
    let faces_away = [h, input[h].twin]
        .into_iter()
        .map(|h| input[h].face)
        .filter(|&f| !input[f].is_boundary && f.index() < mesh.num_faces())
        .filter(|&f| !mesh.face_vertices(f).contains(&m))
        .map(|f| f.index())
        .collect();
    let (a, b) = mesh.edge_vertices(e);
    Some(SplitIds {
        is_new: mesh[m].is_new,
        new_pos: mesh[m].new_pos.to_array(),
        edge: e.index(),
        edge_ends: [a.index(), b.index()],
        faces_away,
    })
}

fn read_result(op: Op, input: &Mesh, mesh: &Mesh, returned: &Returned) -> MeshResult {
    let mut result = MeshResult {
        positions: mesh.positions().iter().map(|p| p.to_array()).collect(),
        edges: mesh.edge_list(),
        returned_edge_ends: None,
        returned_vertex_leads_to: None,
        split: None,
    };
    if let (Op::Split(e), Returned::Vertex { id, .. }) = (op, returned) {
        if (*id as usize) < mesh.num_vertices() {
            result.split = split_ids(input, mesh, e, VertexId(*id));
        }
    }
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

fn same_records(a: &Mesh, b: &Mesh) -> bool {
    let (av, ae, af, ah) = a.records();
    let (bv, be, bf, bh) = b.records();
    let bits = |v: &[halfedge::Vertex]| -> Vec<[u64; 3]> {
        v.iter()
            .map(|v| v.pos.to_array().map(f64::to_bits))
            .collect()
    };
    let links = |v: &[halfedge::Vertex]| -> Vec<_> { v.iter().map(|v| v.halfedge).collect() };
    bits(av) == bits(bv)
        && links(av) == links(bv)
        && ae
            .iter()
            .map(|e| e.halfedge)
            .eq(be.iter().map(|e| e.halfedge))
        && af == bf
        && ah == bh
}
