//! What crosses the pipes between the grader and a case's child process.
//!
//! The parent sends a [`Request`]: the input mesh (every record, exactly as
//! labelled), the operation and the growth budget. The child sends back
//! frames: [`Frame::Sandbox`] (written by the launcher before the student's
//! program starts), [`Frame::Ready`] (the child program is up and waits for
//! its first request), [`Frame::Started`] (just before the student's
//! function is called: the time limit starts there), then one
//! [`Frame::Result`]; a child serves several requests in turn, each sent
//! length-first ([`framed_request`]), each answered by its own started and
//! result frames (the result length-first, see [`frame_at`]). A launcher
//! whose `exec` of the child program failed sends [`Frame::LaunchFailed`]
//! instead, with the nonce the grader gave it (which no student code ever
//! holds). No frame carries a time: the child's clock is the student's to
//! replace (an interposed `clock_gettime`), so the grader reads the child's
//! CPU time from the kernel itself (`runner`).
//! A request may ask the child to record a subdivision (see
//! `halfedge::recording`): the frames then come back inside the result.
//!
//! The encoding is plain little-endian binary, floats as their bits, so a
//! NaN or a negative zero comes back exactly as the student left it. The
//! decoder checks every length against the bytes present: a corrupted or
//! forged stream is an error, never a panic or a huge allocation.

use serde::{Deserialize, Serialize};

use halfedge::{DVec3, Edge, EdgeId, Face, FaceId, Halfedge, HalfedgeId, Mesh, Vertex, VertexId};

/// The descriptor the child reads its request on. Its standard input is
/// `/dev/null`: never a terminal, whatever started the grader.
pub const REQUEST_FD: i32 = 3;

/// The operation a child runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Flip(EdgeId),
    Split(EdgeId),
    Subdivide {
        rounds: u32,
    },
    /// The request's `steps`, in order.
    Sequence,
}

/// One flip or split of a sequence, on the edge between two vertices: a
/// vertex id of the mesh sent when below its vertex count `n`, else `n + k`
/// for the vertex the k-th split returned (the child resolves it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WireStep {
    pub split: bool,
    pub ends: [u32; 2],
}

/// What one step of a sequence did, as the child saw it. Vertices are
/// named as in [`WireStep`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepRan {
    /// The edge joining the step's two vertices, if one did.
    pub edge: Option<u32>,
    pub answer: StepAnswer,
    /// Vertices, edges, faces, halfedges after the step.
    pub counts: [u32; 4],
    /// `validate()` passed after the step (the child stops when not).
    pub valid: bool,
}

/// A step's return, read back in the step's names (read only on a mesh
/// that validated, else `None` inside).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum StepAnswer {
    Nothing,
    Edge {
        id: u32,
        ends: Option<[u32; 2]>,
    },
    Vertex {
        /// The vertex's name: `n + k` for the k-th split's new vertex.
        name: Option<u32>,
        position: Option<[f64; 3]>,
    },
}

/// Everything a child gets: nothing about the expected result.
#[derive(Clone, Debug)]
pub struct Request {
    pub op: Op,
    /// For [`Op::Sequence`]: the steps.
    pub steps: Vec<WireStep>,
    /// The most elements the mesh may grow to (see `halfedge`'s growth budget).
    pub budget: u64,
    pub mesh: Mesh,
}

/// What a student function returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Answer {
    /// `loop_subdivide` returns nothing.
    Unit,
    /// `None`.
    Nothing,
    Edge(EdgeId),
    Vertex(VertexId),
}

/// What a recording kept (see `halfedge::recording`): the mesh before each
/// vertex the student's code created, and the bound that cut it, if any.
#[derive(Clone, Debug, Default)]
pub struct Recorded {
    pub frames: Vec<Mesh>,
    pub cut: Option<halfedge::recording::Cut>,
}

/// How the student's function ended, as the child saw it.
#[derive(Clone, Debug)]
pub enum Ran {
    Returned {
        answer: Answer,
        mesh: Mesh,
        /// When the request asked for one.
        recorded: Option<Recorded>,
    },
    Panicked {
        message: String,
        location: Option<String>,
        /// The growth budget the mesh library hit, when its panic is the
        /// one (`halfedge::mesh::element_budget_hit`).
        grew_past: Option<u64>,
        /// When the request asked for one: the frames up to the panic.
        recorded: Option<Recorded>,
    },
    /// A sequence: each step that ran, the mesh as the last left it, and
    /// the panic that ended it early, if one did.
    Sequence {
        steps: Vec<StepRan>,
        mesh: Mesh,
        panic: Option<(String, Option<String>)>,
    },
}

/// One message from the child process.
#[derive(Clone, Debug)]
pub enum Frame {
    /// The launcher's report of the protections it put in place.
    Sandbox(crate::isolate::protections::Protections),
    /// The child program runs and waits for its first request (sent once,
    /// by `serve`): a timed call's request is sent only then, so that the
    /// CPU time the grader counts is the call's, not the program's start.
    Ready,
    /// The student's function is about to be called.
    Started,
    Result(Ran),
    /// The launcher could not `exec` the child program (after its report):
    /// the nonce the grader sent it first on its stdin, and why.
    LaunchFailed {
        nonce: [u8; NONCE_LEN],
        why: String,
    },
}

/// The length of the nonce a grader sends its launcher (see
/// [`Frame::LaunchFailed`]).
pub const NONCE_LEN: usize = 16;

const REQUEST_MAGIC: &[u8; 4] = b"MLQ1";
const TAG_SANDBOX: u8 = b'L';
const TAG_STARTED: u8 = b'S';
const TAG_RESULT: u8 = b'R';
const TAG_READY: u8 = b'Y';
const TAG_LAUNCH_FAILED: u8 = b'F';

/// Why bytes could not be decoded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WireError(pub String);

impl std::fmt::Display for WireError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

fn put_u32(out: &mut Vec<u8>, x: u32) {
    out.extend_from_slice(&x.to_le_bytes());
}
fn put_u64(out: &mut Vec<u8>, x: u64) {
    out.extend_from_slice(&x.to_le_bytes());
}
fn put_vec3(out: &mut Vec<u8>, v: DVec3) {
    for x in v.to_array() {
        put_u64(out, x.to_bits());
    }
}
fn put_str(out: &mut Vec<u8>, s: &str) {
    put_u32(out, s.len().min(u32::MAX as usize) as u32);
    out.extend_from_slice(&s.as_bytes()[..s.len().min(u32::MAX as usize)]);
}

fn put_mesh(out: &mut Vec<u8>, mesh: &Mesh) {
    let (vs, es, fs, hs) = mesh.records();
    for n in [vs.len(), es.len(), fs.len(), hs.len()] {
        put_u32(out, n as u32);
    }
    for v in vs {
        put_vec3(out, v.pos);
        put_vec3(out, v.new_pos);
        out.push(v.is_new as u8);
        put_u32(out, v.halfedge.0);
    }
    for e in es {
        put_u32(out, e.halfedge.0);
        put_vec3(out, e.new_pos);
        out.push(e.is_new as u8);
    }
    for f in fs {
        put_u32(out, f.halfedge.0);
        out.push(f.is_boundary as u8);
    }
    for h in hs {
        for x in [h.twin.0, h.next.0, h.vertex.0, h.edge.0, h.face.0] {
            put_u32(out, x);
        }
    }
}

/// Bytes per record, to check a count against what is left before
/// allocating for it.
const VERTEX_BYTES: usize = 24 + 24 + 1 + 4;
const EDGE_BYTES: usize = 4 + 24 + 1;
const FACE_BYTES: usize = 4 + 1;
const HALFEDGE_BYTES: usize = 20;

struct Reader<'a> {
    bytes: &'a [u8],
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], WireError> {
        if self.bytes.len() < n {
            return Err(WireError(format!(
                "cut short: {n} more bytes expected, {} left",
                self.bytes.len()
            )));
        }
        let (head, rest) = self.bytes.split_at(n);
        self.bytes = rest;
        Ok(head)
    }
    fn u8(&mut self) -> Result<u8, WireError> {
        Ok(self.take(1)?[0])
    }
    fn bool(&mut self) -> Result<bool, WireError> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            x => Err(WireError(format!("{x} is not a boolean"))),
        }
    }
    fn u32(&mut self) -> Result<u32, WireError> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().expect("4 bytes"),
        ))
    }
    fn u64(&mut self) -> Result<u64, WireError> {
        Ok(u64::from_le_bytes(
            self.take(8)?.try_into().expect("8 bytes"),
        ))
    }
    fn vec3(&mut self) -> Result<DVec3, WireError> {
        Ok(DVec3::new(
            f64::from_bits(self.u64()?),
            f64::from_bits(self.u64()?),
            f64::from_bits(self.u64()?),
        ))
    }
    fn str(&mut self) -> Result<String, WireError> {
        let n = self.u32()? as usize;
        Ok(String::from_utf8_lossy(self.take(n)?).into_owned())
    }
    fn count(&mut self, record_bytes: usize) -> Result<usize, WireError> {
        let n = self.u32()? as usize;
        // Counts are checked against the bytes present before allocating.
        if n.saturating_mul(record_bytes) > self.bytes.len() {
            return Err(WireError(format!(
                "claims {n} records but only {} bytes follow",
                self.bytes.len()
            )));
        }
        Ok(n)
    }
    fn mesh(&mut self) -> Result<Mesh, WireError> {
        let nv = self.count(VERTEX_BYTES)?;
        let ne = self.count(EDGE_BYTES)?;
        let nf = self.count(FACE_BYTES)?;
        let nh = self.count(HALFEDGE_BYTES)?;
        let needed = nv * VERTEX_BYTES + ne * EDGE_BYTES + nf * FACE_BYTES + nh * HALFEDGE_BYTES;
        if needed > self.bytes.len() {
            return Err(WireError("the mesh is cut short".into()));
        }
        let mut vertices = Vec::with_capacity(nv);
        for _ in 0..nv {
            vertices.push(Vertex {
                pos: self.vec3()?,
                new_pos: self.vec3()?,
                is_new: self.bool()?,
                halfedge: HalfedgeId(self.u32()?),
            });
        }
        let mut edges = Vec::with_capacity(ne);
        for _ in 0..ne {
            edges.push(Edge {
                halfedge: HalfedgeId(self.u32()?),
                new_pos: self.vec3()?,
                is_new: self.bool()?,
            });
        }
        let mut faces = Vec::with_capacity(nf);
        for _ in 0..nf {
            faces.push(Face {
                halfedge: HalfedgeId(self.u32()?),
                is_boundary: self.bool()?,
            });
        }
        let mut halfedges = Vec::with_capacity(nh);
        for _ in 0..nh {
            halfedges.push(Halfedge {
                twin: HalfedgeId(self.u32()?),
                next: HalfedgeId(self.u32()?),
                vertex: VertexId(self.u32()?),
                edge: EdgeId(self.u32()?),
                face: FaceId(self.u32()?),
            });
        }
        Ok(Mesh::from_records(vertices, edges, faces, halfedges))
    }
    fn end(&self) -> Result<(), WireError> {
        if self.bytes.is_empty() {
            Ok(())
        } else {
            Err(WireError(format!(
                "{} unexpected bytes at the end",
                self.bytes.len()
            )))
        }
    }
}

impl Request {
    /// The request, asking for no recording.
    pub fn encode(&self) -> Vec<u8> {
        self.encode_asking(false)
    }

    /// The request; `record` asks the child to record the function's
    /// splits (a byte after the mesh).
    pub fn encode_asking(&self, record: bool) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(REQUEST_MAGIC);
        match self.op {
            Op::Flip(e) => {
                out.push(0);
                put_u32(&mut out, e.0);
            }
            Op::Split(e) => {
                out.push(1);
                put_u32(&mut out, e.0);
            }
            Op::Subdivide { rounds } => {
                out.push(2);
                put_u32(&mut out, rounds);
            }
            Op::Sequence => {
                out.push(3);
                put_u32(&mut out, 0);
            }
        }
        put_u32(&mut out, self.steps.len() as u32);
        for s in &self.steps {
            out.push(s.split as u8);
            put_u32(&mut out, s.ends[0]);
            put_u32(&mut out, s.ends[1]);
        }
        put_u64(&mut out, self.budget);
        put_mesh(&mut out, &self.mesh);
        out.push(record as u8);
        out
    }

    pub fn decode(bytes: &[u8]) -> Result<Request, WireError> {
        Request::decode_asking(bytes).map(|(r, _)| r)
    }

    /// The request and whether it asks for a recording.
    pub fn decode_asking(bytes: &[u8]) -> Result<(Request, bool), WireError> {
        let mut r = Reader { bytes };
        if r.take(4)? != REQUEST_MAGIC {
            return Err(WireError("not a grading request".into()));
        }
        let op = match (r.u8()?, r.u32()?) {
            (0, e) => Op::Flip(EdgeId(e)),
            (1, e) => Op::Split(EdgeId(e)),
            (2, rounds) => Op::Subdivide { rounds },
            (3, _) => Op::Sequence,
            (x, _) => return Err(WireError(format!("unknown operation {x}"))),
        };
        let n = r.count(9)?;
        let mut steps = Vec::with_capacity(n);
        for _ in 0..n {
            steps.push(WireStep {
                split: r.bool()?,
                ends: [r.u32()?, r.u32()?],
            });
        }
        let budget = r.u64()?;
        let mesh = r.mesh()?;
        let record = r.bool()?;
        r.end()?;
        Ok((
            Request {
                op,
                steps,
                budget,
                mesh,
            },
            record,
        ))
    }
}

/// The launcher's frame: what protections are in force.
pub fn sandbox_frame(p: &crate::isolate::protections::Protections) -> Vec<u8> {
    let mut out = vec![TAG_SANDBOX];
    out.extend_from_slice(&p.to_bytes());
    out
}

/// The frame that starts the clock.
pub fn started_frame() -> Vec<u8> {
    vec![TAG_STARTED]
}

/// The frame the child program sends once, when it waits for its first
/// request.
pub fn ready_frame() -> Vec<u8> {
    vec![TAG_READY]
}

/// The launcher's frame when the child program could not be started: the
/// grader's nonce, then why (as [`sandbox_frame`] sends its text).
pub fn launch_failed_frame(nonce: &[u8; NONCE_LEN], why: &str) -> Vec<u8> {
    let mut out = vec![TAG_LAUNCH_FAILED];
    put_str(&mut out, why);
    out.extend_from_slice(nonce);
    out
}

/// A call's last frame: the tag, the payload's length (so a reader of the
/// stream knows when it is whole, and can refuse one too large before
/// reading it), the payload.
pub fn result_frame(ran: &Ran) -> Vec<u8> {
    let mut out = vec![TAG_RESULT];
    // The length, written once the payload is (a result can be hundreds of
    // MiB: it is built once, never copied).
    put_u64(&mut out, 0);
    put_result(&mut out, ran);
    let len = (out.len() - 9) as u64;
    out[1..9].copy_from_slice(&len.to_le_bytes());
    out
}

fn put_result(out: &mut Vec<u8>, ran: &Ran) {
    match ran {
        Ran::Returned {
            answer,
            mesh,
            recorded,
        } => {
            out.push(0);
            match *answer {
                Answer::Unit => out.push(0),
                Answer::Nothing => out.push(1),
                Answer::Edge(e) => {
                    out.push(2);
                    put_u32(out, e.0);
                }
                Answer::Vertex(v) => {
                    out.push(3);
                    put_u32(out, v.0);
                }
            }
            put_mesh(out, mesh);
            put_recorded(out, recorded.as_ref());
        }
        Ran::Panicked {
            message,
            location,
            grew_past,
            recorded,
        } => {
            out.push(1);
            put_str(out, message);
            put_str(out, location.as_deref().unwrap_or(""));
            put_u64(out, grew_past.unwrap_or(0));
            put_recorded(out, recorded.as_ref());
        }
        Ran::Sequence { steps, mesh, panic } => {
            out.push(2);
            put_u32(out, steps.len() as u32);
            for s in steps {
                put_step(out, s);
            }
            match panic {
                None => out.push(0),
                Some((message, location)) => {
                    out.push(1);
                    put_str(out, message);
                    put_str(out, location.as_deref().unwrap_or(""));
                }
            }
            put_mesh(out, mesh);
        }
    }
}

fn put_recorded(out: &mut Vec<u8>, recorded: Option<&Recorded>) {
    use halfedge::recording::Cut;
    let Some(r) = recorded else {
        out.push(0);
        return;
    };
    out.push(1);
    put_u32(out, r.frames.len() as u32);
    for m in &r.frames {
        put_mesh(out, m);
    }
    match r.cut {
        None => out.push(0),
        Some(Cut::Frames(n)) => {
            out.push(1);
            put_u64(out, n as u64);
        }
        Some(Cut::Bytes(n)) => {
            out.push(2);
            put_u64(out, n as u64);
        }
    }
}

fn put_opt_u32(out: &mut Vec<u8>, x: Option<u32>) {
    match x {
        None => out.push(0),
        Some(x) => {
            out.push(1);
            put_u32(out, x);
        }
    }
}

fn put_step(out: &mut Vec<u8>, s: &StepRan) {
    put_opt_u32(out, s.edge);
    match &s.answer {
        StepAnswer::Nothing => out.push(0),
        StepAnswer::Edge { id, ends } => {
            out.push(1);
            put_u32(out, *id);
            put_opt_u32(out, ends.map(|e| e[0]));
            put_opt_u32(out, ends.map(|e| e[1]));
        }
        StepAnswer::Vertex { name, position } => {
            out.push(2);
            put_opt_u32(out, *name);
            match position {
                None => out.push(0),
                Some(p) => {
                    out.push(1);
                    put_vec3(out, DVec3::from_array(*p));
                }
            }
        }
    }
    for c in s.counts {
        put_u32(out, c);
    }
    out.push(s.valid as u8);
}

impl Reader<'_> {
    fn recorded(&mut self) -> Result<Option<Recorded>, WireError> {
        use halfedge::recording::Cut;
        if !self.bool()? {
            return Ok(None);
        }
        // The smallest mesh is 16 bytes (four zero counts).
        let n = self.count(16)?;
        let mut frames = Vec::with_capacity(n);
        for _ in 0..n {
            frames.push(self.mesh()?);
        }
        let cut = match self.u8()? {
            0 => None,
            1 => Some(Cut::Frames(self.u64()? as usize)),
            2 => Some(Cut::Bytes(self.u64()? as usize)),
            x => return Err(WireError(format!("unknown recording cut {x}"))),
        };
        Ok(Some(Recorded { frames, cut }))
    }

    fn opt_u32(&mut self) -> Result<Option<u32>, WireError> {
        Ok(if self.bool()? {
            Some(self.u32()?)
        } else {
            None
        })
    }
    fn step(&mut self) -> Result<StepRan, WireError> {
        let edge = self.opt_u32()?;
        let answer = match self.u8()? {
            0 => StepAnswer::Nothing,
            1 => {
                let id = self.u32()?;
                let ends = match (self.opt_u32()?, self.opt_u32()?) {
                    (Some(a), Some(b)) => Some([a, b]),
                    _ => None,
                };
                StepAnswer::Edge { id, ends }
            }
            2 => StepAnswer::Vertex {
                name: self.opt_u32()?,
                position: if self.bool()? {
                    Some(self.vec3()?.to_array())
                } else {
                    None
                },
            },
            x => return Err(WireError(format!("unknown step answer {x}"))),
        };
        let counts = [self.u32()?, self.u32()?, self.u32()?, self.u32()?];
        Ok(StepRan {
            edge,
            answer,
            counts,
            valid: self.bool()?,
        })
    }
}

/// Splits what the child wrote into frames. A stream that ends inside a
/// frame, or holds anything after the result, is an error.
pub fn decode_frames(bytes: &[u8]) -> Result<Vec<Frame>, WireError> {
    let mut r = Reader { bytes };
    let mut frames = Vec::new();
    while !r.bytes.is_empty() {
        match r.u8()? {
            TAG_SANDBOX => {
                let bytes = r.take(crate::isolate::protections::Protections::LEN)?;
                let p = crate::isolate::protections::Protections::from_bytes(bytes)
                    .ok_or_else(|| WireError("a launcher report that does not decode".into()))?;
                frames.push(Frame::Sandbox(p));
            }
            TAG_STARTED => frames.push(Frame::Started),
            TAG_READY => frames.push(Frame::Ready),
            TAG_LAUNCH_FAILED => {
                let why = r.str()?;
                let nonce = r.take(NONCE_LEN)?.try_into().expect("NONCE_LEN bytes");
                frames.push(Frame::LaunchFailed { nonce, why });
            }
            TAG_RESULT => {
                let n = r.u64()?;
                let payload = r.take(usize::try_from(n).unwrap_or(usize::MAX))?;
                let mut r = Reader { bytes: payload };
                let ran = match r.u8()? {
                    0 => {
                        let answer = match r.u8()? {
                            0 => Answer::Unit,
                            1 => Answer::Nothing,
                            2 => Answer::Edge(EdgeId(r.u32()?)),
                            3 => Answer::Vertex(VertexId(r.u32()?)),
                            x => return Err(WireError(format!("unknown answer kind {x}"))),
                        };
                        Ran::Returned {
                            answer,
                            mesh: r.mesh()?,
                            recorded: r.recorded()?,
                        }
                    }
                    1 => {
                        let message = r.str()?;
                        let location = Some(r.str()?).filter(|l| !l.is_empty());
                        let grew_past = Some(r.u64()?).filter(|&n| n > 0);
                        Ran::Panicked {
                            message,
                            location,
                            grew_past,
                            recorded: r.recorded()?,
                        }
                    }
                    2 => {
                        // The smallest step is 19 bytes.
                        let n = r.count(19)?;
                        let mut steps = Vec::with_capacity(n);
                        for _ in 0..n {
                            steps.push(r.step()?);
                        }
                        let panic = if r.bool()? {
                            let message = r.str()?;
                            let location = Some(r.str()?).filter(|l| !l.is_empty());
                            Some((message, location))
                        } else {
                            None
                        };
                        Ran::Sequence {
                            steps,
                            mesh: r.mesh()?,
                            panic,
                        }
                    }
                    x => return Err(WireError(format!("unknown result kind {x}"))),
                };
                r.end()?;
                frames.push(Frame::Result(ran));
            }
            x => return Err(WireError(format!("unknown frame {x}"))),
        }
    }
    Ok(frames)
}

/// How a frame at the start of `bytes` stands, for a reader of the stream
/// as it arrives (see [`frame_at`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pending {
    /// The frame is whole: it is this many bytes.
    Whole(usize),
    /// More bytes are needed; for a result, its length is known once its
    /// header arrived (`Some(total)`).
    Partial(Option<usize>),
}

/// Where the frame at the start of `bytes` ends, without decoding it; an
/// unknown tag is an error (the channel was written to by someone else).
pub fn frame_at(bytes: &[u8]) -> Result<Pending, WireError> {
    let Some(&tag) = bytes.first() else {
        return Ok(Pending::Partial(None));
    };
    let sized = |header: usize, len: Option<u64>| match len {
        None => Pending::Partial(None),
        Some(len) => {
            let total = (header as u64).saturating_add(len);
            let total = usize::try_from(total).unwrap_or(usize::MAX);
            if bytes.len() >= total {
                Pending::Whole(total)
            } else {
                Pending::Partial(Some(total))
            }
        }
    };
    match tag {
        TAG_STARTED | TAG_READY => Ok(Pending::Whole(1)),
        TAG_SANDBOX => Ok(sized(
            1,
            Some(crate::isolate::protections::Protections::LEN as u64),
        )),
        TAG_LAUNCH_FAILED => Ok(sized(
            5 + NONCE_LEN,
            bytes
                .get(1..5)
                .map(|b| u32::from_le_bytes(b.try_into().expect("4 bytes")) as u64),
        )),
        TAG_RESULT => Ok(sized(
            9,
            bytes
                .get(1..9)
                .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes"))),
        )),
        x => Err(WireError(format!("unknown frame {x}"))),
    }
}

/// A request as it goes down the pipe of a child that serves several
/// (see [`crate::isolate::child::serve`]): its length, then its bytes.
pub fn framed_request(request: &Request, record: bool) -> Vec<u8> {
    let body = request.encode_asking(record);
    let mut out = Vec::with_capacity(8 + body.len());
    put_u64(&mut out, body.len() as u64);
    out.extend_from_slice(&body);
    out
}

/// What the child writes on its output (the student's stdout and stderr)
/// after each call, before the call's result: the runner cuts the output
/// there, so each call gets what was printed during it. Its first byte
/// occurs nowhere else in it, so a plain scan finds it. Code that prints
/// it only moves printed text between calls: no verdict reads the output.
pub const CALL_END: &[u8] = b"\x00meshlab: call ended\n";

/// The tags of the launcher's frame, of the frames that say the child is
/// ready and that starts the clock, and of the result, for a reader that
/// watches the stream as it arrives.
pub const SANDBOX_TAG: u8 = TAG_SANDBOX;
pub const READY_TAG: u8 = TAG_READY;
pub const STARTED_TAG: u8 = TAG_STARTED;
pub const RESULT_TAG: u8 = TAG_RESULT;

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field of every record, floats by their bits.
    fn fields(m: &Mesh) -> Vec<Vec<u64>> {
        let (v, e, f, h) = m.records();
        let bits = |p: halfedge::DVec3| p.to_array().map(f64::to_bits);
        let mut out = Vec::new();
        for v in v {
            let mut r = vec![v.is_new as u64, v.halfedge.0 as u64];
            r.extend(bits(v.pos));
            r.extend(bits(v.new_pos));
            out.push(r);
        }
        for e in e {
            let mut r = vec![e.is_new as u64, e.halfedge.0 as u64];
            r.extend(bits(e.new_pos));
            out.push(r);
        }
        for f in f {
            out.push(vec![f.is_boundary as u64, f.halfedge.0 as u64]);
        }
        for h in h {
            out.push(
                [h.twin.0, h.next.0, h.vertex.0, h.edge.0, h.face.0]
                    .map(u64::from)
                    .to_vec(),
            );
        }
        out
    }

    fn same(a: &Mesh, b: &Mesh) -> bool {
        fields(a) == fields(b)
    }

    /// A mesh with a hole whose every field holds something other than what
    /// building it gives: flags set on some records, `new_pos` everywhere,
    /// vertices and faces pointing at another of their halfedges, a NaN and
    /// a negative zero.
    fn unusual() -> Mesh {
        let grid = halfedge::shapes::grid(2, 3);
        let (vs, es, fs, hs) = grid.records();
        let (mut vs, mut es, mut fs, hs) = (vs.to_vec(), es.to_vec(), fs.to_vec(), hs.to_vec());
        for (i, v) in vs.iter_mut().enumerate() {
            v.is_new = i % 2 == 0;
            v.new_pos = halfedge::DVec3::new(i as f64 + 0.25, -(i as f64), 1e-300);
            // Another halfedge leaving v: the one after the twin of its own.
            v.halfedge = hs[hs[v.halfedge.index()].twin.index()].next;
        }
        for (i, e) in es.iter_mut().enumerate() {
            e.is_new = i % 3 != 0;
            e.new_pos = halfedge::DVec3::new(0.5, i as f64 * 1.5, -2.0);
            e.halfedge = hs[e.halfedge.index()].twin;
        }
        for f in fs.iter_mut() {
            f.halfedge = hs[f.halfedge.index()].next;
        }
        vs[2].pos.x = f64::NAN;
        vs[3].pos.y = -0.0;
        // The wire carries records as they are, valid or not.
        Mesh::from_records(vs, es, fs, hs)
    }

    /// A change made to a mesh's four arenas.
    type Change = dyn Fn(&mut [Vertex], &mut [Edge], &mut [Face], &mut [Halfedge]);

    #[test]
    fn the_comparison_sees_every_field() {
        let m = unusual();
        let (vs, es, fs, hs) = m.records();
        assert!(fs.iter().any(|f| f.is_boundary), "the grid has a hole");
        assert!(vs.iter().any(|v| v.is_new) && es.iter().any(|e| e.is_new));
        let rebuilt = |change: &Change| {
            let (mut v, mut e, mut f, mut h) = (vs.to_vec(), es.to_vec(), fs.to_vec(), hs.to_vec());
            change(&mut v, &mut e, &mut f, &mut h);
            Mesh::from_records(v, e, f, h)
        };
        let changes: [&Change; 13] = [
            &|v, _, _, _| v[1].pos.z += 1.0,
            &|v, _, _, _| v[1].new_pos.y += 1.0,
            &|v, _, _, _| v[1].is_new = !v[1].is_new,
            &|v, _, _, _| v[1].halfedge = HalfedgeId(v[1].halfedge.0 ^ 1),
            &|_, e, _, _| e[1].new_pos.x += 1.0,
            &|_, e, _, _| e[1].is_new = !e[1].is_new,
            &|_, e, _, _| e[1].halfedge = HalfedgeId(e[1].halfedge.0 ^ 1),
            &|_, _, f, _| f[1].halfedge = HalfedgeId(f[1].halfedge.0 ^ 1),
            &|_, _, f, _| f[1].is_boundary = !f[1].is_boundary,
            &|_, _, _, h| h[1].twin = HalfedgeId(h[1].twin.0 ^ 1),
            &|_, _, _, h| h[1].next = HalfedgeId(h[1].next.0 ^ 1),
            &|_, _, _, h| h[1].vertex = VertexId(h[1].vertex.0 ^ 1),
            &|_, _, _, h| h[1].edge = EdgeId(h[1].edge.0 ^ 1),
        ];
        for (i, change) in changes.iter().enumerate() {
            assert!(!same(&m, &rebuilt(change)), "change {i} unseen");
        }
        let face_change = rebuilt(&|_, _, _, h| h[1].face = FaceId(h[1].face.0 ^ 1));
        assert!(!same(&m, &face_change), "a halfedge's face unseen");
    }

    #[test]
    fn a_request_round_trips_exactly() {
        let mesh = unusual();
        let req = Request {
            op: Op::Split(EdgeId(4)),
            steps: Vec::new(),
            budget: 1234,
            mesh,
        };
        let back = Request::decode(&req.encode()).unwrap();
        assert!(!Request::decode_asking(&req.encode()).unwrap().1);
        assert!(Request::decode_asking(&req.encode_asking(true)).unwrap().1);
        assert_eq!(back.op, req.op);
        assert_eq!(back.budget, 1234);
        assert!(same(&back.mesh, &req.mesh));
        assert!(back.mesh[VertexId(2)].pos.x.is_nan());
        for op in [Op::Flip(EdgeId(7)), Op::Subdivide { rounds: 3 }] {
            let req = Request {
                op,
                steps: Vec::new(),
                budget: 1,
                mesh: unusual(),
            };
            assert_eq!(Request::decode(&req.encode()).unwrap().op, op);
        }
        let steps = vec![
            WireStep {
                split: true,
                ends: [0, 5],
            },
            WireStep {
                split: false,
                ends: [12, 3],
            },
        ];
        let req = Request {
            op: Op::Sequence,
            steps: steps.clone(),
            budget: 9,
            mesh: unusual(),
        };
        let back = Request::decode(&req.encode()).unwrap();
        assert_eq!((back.op, back.steps), (Op::Sequence, steps));
    }

    #[test]
    fn a_sequence_result_round_trips() {
        let steps = vec![
            StepRan {
                edge: Some(4),
                answer: StepAnswer::Vertex {
                    name: Some(12),
                    position: Some([0.5, -0.0, f64::MAX]),
                },
                counts: [13, 33, 22, 66],
                valid: true,
            },
            StepRan {
                edge: None,
                answer: StepAnswer::Edge { id: 7, ends: None },
                counts: [13, 33, 22, 66],
                valid: false,
            },
            StepRan {
                edge: Some(1),
                answer: StepAnswer::Nothing,
                counts: [1, 2, 3, 4],
                valid: true,
            },
        ];
        let ran = Ran::Sequence {
            steps: steps.clone(),
            mesh: unusual(),
            panic: Some(("boom".into(), Some("src/lib.rs:3:4".into()))),
        };
        match decode_frames(&result_frame(&ran)).unwrap().pop() {
            Some(Frame::Result(Ran::Sequence {
                steps: back,
                mesh,
                panic,
            })) => {
                assert_eq!(back, steps);
                assert!(same(&mesh, &unusual()));
                assert_eq!(panic, Some(("boom".into(), Some("src/lib.rs:3:4".into()))));
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn frames_round_trip() {
        let mesh = unusual();
        let launched = crate::isolate::protections::Protections {
            landlock: 6,
            pid: 17,
            ..Default::default()
        };
        let mut bytes = sandbox_frame(&launched);
        bytes.extend(ready_frame());
        bytes.extend(started_frame());
        bytes.extend(result_frame(&Ran::Returned {
            answer: Answer::Edge(EdgeId(3)),
            mesh: mesh.clone(),
            recorded: Some(Recorded {
                frames: vec![mesh.clone(), Mesh::new()],
                cut: Some(halfedge::recording::Cut::Bytes(1 << 25)),
            }),
        }));
        let nonce = [7u8; NONCE_LEN];
        bytes.extend(launch_failed_frame(&nonce, "cannot start /child"));
        let frames = decode_frames(&bytes).unwrap();
        assert!(matches!(&frames[0], Frame::Sandbox(p) if *p == launched));
        assert!(matches!(frames[1], Frame::Ready));
        assert!(matches!(frames[2], Frame::Started));
        assert!(
            matches!(&frames[4], Frame::LaunchFailed { nonce: n, why } if *n == nonce && why == "cannot start /child"),
            "{:?}",
            frames[4]
        );
        match &frames[3] {
            Frame::Result(Ran::Returned {
                answer,
                mesh: m,
                recorded: Some(r),
            }) => {
                assert_eq!(*answer, Answer::Edge(EdgeId(3)));
                assert!(same(m, &mesh));
                assert_eq!(r.frames.len(), 2);
                assert!(same(&r.frames[0], &mesh) && same(&r.frames[1], &Mesh::new()));
                assert_eq!(r.cut, Some(halfedge::recording::Cut::Bytes(1 << 25)));
            }
            other => panic!("{other:?}"),
        }
        let panicked = result_frame(&Ran::Panicked {
            message: "boom".into(),
            location: None,
            grew_past: Some(4000),
            recorded: None,
        });
        match &decode_frames(&panicked).unwrap()[0] {
            Frame::Result(Ran::Panicked {
                message,
                location,
                grew_past,
                recorded: None,
            }) => {
                assert_eq!((message.as_str(), location), ("boom", &None));
                assert_eq!(*grew_past, Some(4000));
            }
            other => panic!("{other:?}"),
        }
    }

    /// A reader of the stream learns where each frame ends, and a
    /// result's length from its header alone.
    #[test]
    fn frames_are_found_as_they_arrive() {
        let result = result_frame(&Ran::Returned {
            answer: Answer::Unit,
            mesh: unusual(),
            recorded: None,
        });
        let mut stream = sandbox_frame(&Default::default());
        stream.extend(started_frame());
        stream.extend(result.clone());
        let s = 1 + crate::isolate::protections::Protections::LEN;
        assert_eq!(frame_at(&stream), Ok(Pending::Whole(s)));
        assert_eq!(frame_at(&stream[s..]), Ok(Pending::Whole(1)));
        assert_eq!(frame_at(&stream[s + 1..]), Ok(Pending::Whole(result.len())));
        assert_eq!(frame_at(&ready_frame()), Ok(Pending::Whole(1)));
        let failed = launch_failed_frame(&[1; NONCE_LEN], "why");
        assert_eq!(frame_at(&failed), Ok(Pending::Whole(5 + NONCE_LEN + 3)));
        assert_eq!(
            frame_at(&failed[..6]),
            Ok(Pending::Partial(Some(failed.len())))
        );
        assert_eq!(frame_at(&result[..5]), Ok(Pending::Partial(None)));
        assert_eq!(
            frame_at(&result[..20]),
            Ok(Pending::Partial(Some(result.len())))
        );
        assert!(frame_at(b"Z").is_err());
        let mut request = framed_request(
            &Request {
                op: Op::Flip(EdgeId(1)),
                steps: Vec::new(),
                budget: 5,
                mesh: unusual(),
            },
            true,
        );
        let body = request.split_off(8);
        assert_eq!(
            u64::from_le_bytes(request.try_into().unwrap()),
            body.len() as u64
        );
        assert!(Request::decode_asking(&body).unwrap().1);
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        let mesh = halfedge::shapes::lab_object("cube").unwrap();
        let good = result_frame(&Ran::Returned {
            answer: Answer::Unit,
            mesh,
            recorded: None,
        });
        for cut in [1, 2, 3, 10, good.len() - 1] {
            assert!(decode_frames(&good[..cut]).is_err(), "cut at {cut}");
        }
        let mut extra = good.clone();
        extra.push(0);
        assert!(decode_frames(&extra).is_err());
        // A count far larger than the bytes present is refused before any allocation.
        let mut huge = vec![TAG_RESULT, 0, 0];
        huge.extend_from_slice(&u32::MAX.to_le_bytes());
        assert!(decode_frames(&huge).is_err());
        assert!(decode_frames(b"Zzz").is_err());
        assert!(Request::decode(b"MLQ1").is_err());
    }
}
