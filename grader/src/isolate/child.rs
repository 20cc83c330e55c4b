//! Both ends of a case's child process.
//!
//! [`serve`] is the child: it reads [`Request`]s (the input mesh and the
//! operation, never the expected result) on [`crate::isolate::sandbox::REQUEST_FD`]
//! (its stdin is `/dev/null`), one after another, calls the student's
//! function for each under `catch_unwind` with a silent panic hook, and
//! sends back the mesh as the function left it. It judges nothing and
//! reads no file.
//!
//! [`analyze`] is the parent's reading of what came back: counts, the first
//! broken link, the result as positions and edges. All of it runs in the
//! parent, on data only, so nothing the student's code does can pass for a
//! verdict.

use std::cell::RefCell;
use std::io::{Read, Write};
use std::panic::{self, AssertUnwindSafe};

use halfedge::{EdgeId, Mesh, VertexId};
use serde::{Deserialize, Serialize};

use crate::isolate::end::CaseEnd;
use crate::isolate::wire::{self, Answer, Op, Ran, Request, StepAnswer, StepRan, WireStep};
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
    /// After a split that returned a new vertex, what the contract pins
    /// down besides the shape: see [`SplitIds`].
    pub split: Option<SplitIds>,
}

/// The ids a split must keep sensible, read in the labelling that was sent.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SplitIds {
    /// The new vertex's `is_new` and `new_pos`: a split leaves them at their
    /// defaults (`false`, zero); subdivision sets them after the call.
    pub is_new: bool,
    pub new_pos: [f64; 3],
    /// The split edge's id, and the vertices it joins now: the new vertex
    /// and an end of the old edge.
    pub edge: usize,
    pub edge_ends: [usize; 2],
    /// The old faces beside the edge that no longer have the new vertex as
    /// a corner (each must become one of the triangles around it).
    pub faces_away: Vec<usize>,
}

/// A function that returned, as the parent read its result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Finished {
    pub returned: Returned,
    pub before: Counts,
    pub after: Counts,
    /// The first thing wrong with the result's links or positions.
    pub invalid: Option<Problem>,
    pub mesh: Option<Box<MeshResult>>,
    /// Every record, positions to the bit, is as it was sent.
    #[serde(default)]
    pub unchanged: bool,
}

/// A sequence: what each step that ran did (the child stops at the first
/// step that leaves an invalid mesh, panics or names two vertices no edge
/// joins), and the mesh the last one left, read as for one operation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SequenceRan {
    pub steps: Vec<StepRan>,
    pub panic: Option<(String, Option<String>)>,
    pub before: Counts,
    pub after: Counts,
    pub invalid: Option<Problem>,
    pub mesh: Option<Box<MeshResult>>,
}

/// The first thing wrong with a result's links or positions, as data
/// (its message is [`Problem`]'s `Display`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Problem {
    /// `validate()` failed: the check, the element and its message (the
    /// message as the parent read it, see [`crate::judge::grade::words`]).
    Invalid {
        #[serde(skip)]
        invalid: Option<halfedge::Invalid>,
        message: String,
    },
    /// A vertex whose position is not a finite number.
    NotFinite { vertex: u32, position: [f64; 3] },
    /// Walking the mesh panicked (the library's message).
    Unwalkable { message: String },
}

impl Problem {
    /// `validate()`'s finding, its message as the grader says it.
    pub fn of(invalid: halfedge::Invalid) -> Problem {
        let mut invalid = invalid;
        invalid.message = crate::judge::grade::words(invalid.message);
        Problem::Invalid {
            message: invalid.to_string(),
            invalid: Some(invalid),
        }
    }

    /// The check of `validate()` that failed, if it was one.
    pub fn check(&self) -> Option<halfedge::Check> {
        match self {
            Problem::Invalid { invalid, .. } => invalid.as_ref().map(|i| i.check),
            _ => None,
        }
    }

    /// The element at fault, in the numbering of the mesh checked.
    pub fn element(&self) -> Option<halfedge::Element> {
        match self {
            Problem::Invalid { invalid, .. } => invalid.as_ref().map(|i| i.element),
            Problem::NotFinite { vertex, .. } => Some(VertexId(*vertex).into()),
            Problem::Unwalkable { .. } => None,
        }
    }

    /// The first problem with `mesh`: a non-finite position, else
    /// `validate()`'s. Guard the call: it walks what the student made.
    fn find(mesh: &Mesh) -> Option<Problem> {
        non_finite(mesh).or_else(|| mesh.validate().err().map(Problem::of))
    }
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Problem::Invalid { message, .. } => f.write_str(message),
            Problem::NotFinite {
                vertex,
                position: p,
            } => write!(
                f,
                "vertex v{vertex} is at ({}, {}, {}): a position must be a finite number",
                p[0], p[1], p[2]
            ),
            Problem::Unwalkable { message } => {
                write!(f, "the mesh could not be walked: {message}")
            }
        }
    }
}

thread_local! {
    static LAST_PANIC: RefCell<Option<(String, Option<String>)>> = const { RefCell::new(None) };
    /// Whether this thread is inside [`guarded`].
    static GUARDED: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
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

/// Installs, once per process, the panic hook [`guarded`] relies on: inside
/// it a panic is only recorded (no backtrace reaches the student's screen);
/// elsewhere it is said in one line. Installed once and never removed, so
/// threads judging side by side do not race to set and take it.
fn install_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        panic::set_hook(Box::new(|info| {
            let location = info
                .location()
                .map(|l| format!("{}:{}:{}", l.file(), l.line(), l.column()));
            let text = panic_text(info.payload());
            if GUARDED.with(|g| g.get()) {
                LAST_PANIC.with(|p| *p.borrow_mut() = Some((text, location)));
            } else {
                eprintln!(
                    "grader: internal error: {text} ({}): please tell a TA",
                    location.as_deref().unwrap_or("unknown place")
                );
            }
        }));
    });
}

/// Runs `f`, turning a panic into its message and location, silently.
pub fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, (String, Option<String>)> {
    install_hook();
    let outer = GUARDED.with(|g| g.replace(true));
    let result = panic::catch_unwind(AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(outer));
    result.map_err(|payload| {
        LAST_PANIC
            .with(|p| p.borrow_mut().take())
            .unwrap_or_else(|| (panic_text(payload.as_ref()), None))
    })
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
    if unsafe { libc::fcntl(crate::isolate::sandbox::REQUEST_FD, libc::F_GETFD) } < 0 {
        eprintln!("grader child: no request: this program is started by the grader");
        std::process::exit(3);
    }
    // SAFETY: the descriptor is open and this is its only owner.
    let mut requests = unsafe {
        <std::fs::File as std::os::fd::FromRawFd>::from_raw_fd(crate::isolate::sandbox::REQUEST_FD)
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

/// The first vertex whose position is not a finite number ("vertex v7 is
/// at (NaN, 0, 1)").
fn non_finite(mesh: &Mesh) -> Option<Problem> {
    let (vertices, ..) = mesh.records();
    let (i, v) = vertices
        .iter()
        .enumerate()
        .find(|(_, v)| !v.pos.is_finite())?;
    Some(Problem::NotFinite {
        vertex: i as u32,
        position: v.pos.to_array(),
    })
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
