//! The child: [`serve`] reads [`Request`]s (the input mesh and the
//! operation, never the expected result) on
//! [`crate::isolate::wire::REQUEST_FD`] (its stdin is `/dev/null`), one
//! after another, calls the student's function for each under
//! `catch_unwind` with a silent panic hook ([`guarded`]), and sends back
//! the mesh as the function left it. It judges nothing and reads no file;
//! the parent's reading of what it sent is [`crate::isolate::analyze`].

use std::io::{Read, Write};

use halfedge::{EdgeId, Mesh, VertexId};

use crate::isolate::end::{non_finite, Counts};
use crate::isolate::guard::guarded;
use crate::isolate::wire::{self, Answer, Op, Ran, Request, StepAnswer, StepRan, WireStep};

/// The three functions being graded.
#[derive(Clone, Copy)]
pub struct Implementation {
    pub flip_edge: fn(&mut Mesh, EdgeId) -> Option<EdgeId>,
    pub split_edge: fn(&mut Mesh, EdgeId) -> Option<VertexId>,
    pub loop_subdivide: fn(&mut Mesh),
}

/// Runs a sequence's steps on `mesh`, checking it after each (vertices in
/// the answers named as in [`WireStep`]: the parent maps them back to the
/// fixture's names): a broken
/// mesh ends the sequence there, as the next step would only walk the
/// broken links and panic far from the mistake.
fn run_sequence(
    mesh: &mut Mesh,
    steps: &[WireStep],
    imp: &Implementation,
) -> (Vec<StepRan>, Option<(String, Option<String>)>) {
    let n = mesh.num_vertices() as u32;
    // made[k]: the vertex the k-th split returned.
    let mut made: Vec<VertexId> = Vec::new();
    let mut out = Vec::new();
    let name_of = |v: VertexId, made: &[VertexId]| -> Option<u32> {
        if v.0 < n {
            return Some(v.0);
        }
        made.iter().position(|&m| m == v).map(|k| n + k as u32)
    };
    let counts = |m: &Mesh| {
        let c = Counts::of(m);
        [c.vertices, c.edges, c.faces, c.halfedges].map(|x| x as u32)
    };
    for step in steps {
        let resolve = |x: u32| {
            if x < n {
                Some(VertexId(x))
            } else {
                made.get((x - n) as usize).copied()
            }
        };
        let edge = match (resolve(step.ends[0]), resolve(step.ends[1])) {
            (Some(a), Some(b))
                if a.index() < mesh.num_vertices() && b.index() < mesh.num_vertices() =>
            {
                mesh.edge_between(a.index(), b.index())
            }
            _ => None,
        };
        let Some(e) = edge else {
            out.push(StepRan {
                edge: None,
                answer: StepAnswer::Nothing,
                counts: counts(mesh),
                valid: true,
            });
            break;
        };
        let vertices_before = mesh.num_vertices();
        let ran = guarded(|| {
            if step.split {
                (imp.split_edge)(mesh, e).map(Answer::Vertex)
            } else {
                (imp.flip_edge)(mesh, e).map(Answer::Edge)
            }
        });
        let answer = match ran {
            Ok(a) => a,
            Err(panic) => return (out, Some(panic)),
        };
        // The checks walk what the student's code left: a panic in them is
        // a broken mesh, not the student's panic.
        let valid =
            guarded(|| non_finite(mesh).is_none() && mesh.validate().is_ok()).unwrap_or(false);
        let answer = match answer {
            None => StepAnswer::Nothing,
            Some(Answer::Edge(got)) => StepAnswer::Edge {
                id: got.0,
                ends: (valid && got.index() < mesh.num_edges())
                    .then(|| {
                        let (a, b) = mesh.edge_vertices(got);
                        Some([name_of(a, &made)?, name_of(b, &made)?])
                    })
                    .flatten(),
            },
            Some(Answer::Vertex(v)) => {
                let known = v.index() < mesh.num_vertices();
                // A vertex made by this split takes the next name.
                let name = name_of(v, &made).or_else(|| {
                    (known && v.index() >= vertices_before).then_some(n + made.len() as u32)
                });
                made.push(v);
                StepAnswer::Vertex {
                    name: if known { name } else { None },
                    position: known.then(|| mesh[v].pos.to_array()),
                }
            }
            Some(_) => StepAnswer::Nothing,
        };
        out.push(StepRan {
            edge: Some(e.0),
            answer,
            counts: counts(mesh),
            valid,
        });
        if !valid {
            break;
        }
    }
    (out, None)
}

/// Runs the request's operation on its mesh with `imp`; with `record`, a
/// subdivision is recorded (`halfedge::recording`, bounded by its default
/// limits) and its frames sent back.
pub fn run_request(req: Request, imp: &Implementation, record: bool) -> Ran {
    let mut mesh = req.mesh;
    let record = record && matches!(req.op, Op::Subdivide { .. });
    halfedge::mesh::set_process_element_budget(Some(req.budget as usize));
    if req.op == Op::Sequence {
        let (steps, panic) = run_sequence(&mut mesh, &req.steps, imp);
        halfedge::mesh::set_process_element_budget(None);
        return Ran::Sequence { steps, mesh, panic };
    }
    if record {
        halfedge::recording::start(halfedge::recording::Limits::default());
    }
    let ran = guarded(|| match req.op {
        Op::Flip(e) => match (imp.flip_edge)(&mut mesh, e) {
            None => Answer::Nothing,
            Some(got) => Answer::Edge(got),
        },
        Op::Split(e) => match (imp.split_edge)(&mut mesh, e) {
            None => Answer::Nothing,
            Some(v) => Answer::Vertex(v),
        },
        Op::Sequence => unreachable!("run above"),
        Op::Subdivide { rounds } => {
            for round in 1..=rounds {
                (imp.loop_subdivide)(&mut mesh);
                // A round that broke the mesh ends the case there: the next
                // would only walk the broken links and panic far from the
                // mistake, which the parent can name from this mesh.
                if round < rounds && mesh.validate().is_err() {
                    break;
                }
            }
            Answer::Unit
        }
    });
    let recorded = record.then(|| {
        let r = halfedge::recording::stop();
        wire::Recorded {
            frames: r.frames,
            cut: r.cut,
        }
    });
    // Read before the reset below clears it.
    let grew_past = halfedge::mesh::element_budget_hit().map(|n| n as u64);
    halfedge::mesh::set_process_element_budget(None);
    match ran {
        Ok(answer) => Ran::Returned {
            answer,
            mesh,
            recorded,
        },
        Err((message, location)) => Ran::Panicked {
            message,
            location,
            grew_past,
            recorded,
        },
    }
}

/// The child's whole life: read requests on the request descriptor, one
/// after another, run each, send its frames on the result channel; exit
/// when the grader closes the pipe. Standard output is moved onto
/// standard error first, so the student's prints never mix with frames.
/// The runner sends one child the labellings of one case only, and a
/// call that does not pass in a child that served an earlier one is run
/// again in a fresh child (see `docs/architecture.md`).
pub fn serve(imp: &Implementation) -> ! {
    use std::os::fd::AsFd;
    // The result channel: stdout's pipe, kept on a close-on-exec descriptor.
    let channel = match std::io::stdout().as_fd().try_clone_to_owned() {
        Ok(fd) => fd,
        Err(e) => {
            eprintln!("grader child: no result channel: {e}");
            std::process::exit(3);
        }
    };
    // SAFETY: plain dup2 of our own descriptors.
    unsafe {
        libc::dup2(2, 1);
    }
    let mut channel = std::fs::File::from(channel);
    // The requests come on their own descriptor (stdin is /dev/null).
    // SAFETY: F_GETFD only asks whether the descriptor is open.
    if unsafe { libc::fcntl(crate::isolate::wire::REQUEST_FD, libc::F_GETFD) } < 0 {
        eprintln!("grader child: no request: this program is started by the grader");
        std::process::exit(3);
    }
    // SAFETY: the descriptor is open and this is its only owner.
    let mut requests = unsafe {
        <std::fs::File as std::os::fd::FromRawFd>::from_raw_fd(crate::isolate::wire::REQUEST_FD)
    };
    // The student's log lines show up in the captured output.
    halfedge::logging::init(halfedge::logging::Color::Never);
    // Up and waiting: a timed call's request is sent only now.
    let _ = channel.write_all(&wire::ready_frame());
    let _ = channel.flush();
    loop {
        let mut len = [0u8; 8];
        match requests.read_exact(&mut len) {
            Ok(()) => {}
            // The grader closed the pipe: no more calls.
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => std::process::exit(0),
            Err(e) => {
                eprintln!("grader child: cannot read the request ({e}): this program is started by the grader");
                std::process::exit(3);
            }
        }
        let mut bytes = Vec::new();
        let read = (&mut requests)
            .take(u64::from_le_bytes(len))
            .read_to_end(&mut bytes);
        let decoded = read
            .map_err(|e| e.to_string())
            .and_then(|_| Request::decode_asking(&bytes).map_err(|e| e.to_string()));
        let (req, record) = match decoded {
            Ok(r) => r,
            Err(e) => {
                eprintln!("grader child: bad request: {e}");
                std::process::exit(3);
            }
        };
        drop(bytes);
        let _ = channel.write_all(&wire::started_frame());
        let _ = channel.flush();
        // No clock is read here: this process's clock is the student's to
        // replace. The grader reads its CPU time from the kernel.
        let ran = run_request(req, imp, record);
        // What the call printed, then the mark that ends it, before its
        // result: the runner cuts the output there.
        let _ = std::io::stdout().flush();
        let _ = std::io::stderr().write_all(wire::CALL_END);
        let _ = std::io::stderr().flush();
        let _ = channel.write_all(&wire::result_frame(&ran));
        let _ = channel.flush();
    }
}
