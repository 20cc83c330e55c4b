//! Recording a mesh's history, for the grader's step-through of a
//! student's `loop_subdivide`.
//!
//! A process-wide switch, like the growth budget, off unless the grader's
//! child turns it on. While it is on, every [`Mesh::new_vertex`] first
//! keeps a copy of the mesh as it is at that moment: the mesh before the
//! split that makes that vertex, when the split makes its vertex before
//! changing anything (as the handout's picture does: `m` first). The
//! student calls their own `split_edge`, so the library, which every
//! split goes through to create its vertex, is the one place that sees
//! each split begin. Flips create nothing and take no frame.
//!
//! The recording is bounded (frames and bytes, [`Limits`]); the first frame
//! over either bound is not kept, and the recording says so ([`Cut`]).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

use crate::mesh::Mesh;

/// Whether a recording is running (read on every vertex creation).
static ON: AtomicBool = AtomicBool::new(false);

/// The recording so far.
static STATE: Mutex<Option<State>> = Mutex::new(None);

/// How much a recording may keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    pub frames: usize,
    pub bytes: usize,
}

impl Default for Limits {
    /// The grader's: 200 frames, 32 MiB.
    fn default() -> Limits {
        Limits {
            frames: 200,
            bytes: 32 << 20,
        }
    }
}

/// Which bound stopped a recording.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cut {
    /// The most frames were kept.
    Frames(usize),
    /// The next frame would have passed this many bytes.
    Bytes(usize),
}

/// What a recording kept: the mesh before each vertex the code created,
/// in order, and the bound that stopped it, if one did.
#[derive(Clone, Debug, Default)]
pub struct Recording {
    pub frames: Vec<Mesh>,
    pub cut: Option<Cut>,
}

struct State {
    limits: Limits,
    bytes: usize,
    kept: Recording,
}

/// Bytes a mesh's records take (what a frame costs to keep and to send).
pub fn record_bytes(mesh: &Mesh) -> usize {
    let (v, e, f, h) = mesh.records();
    std::mem::size_of_val(v)
        + std::mem::size_of_val(e)
        + std::mem::size_of_val(f)
        + std::mem::size_of_val(h)
}

/// Starts a recording in this process (any earlier one is dropped).
pub fn start(limits: Limits) {
    *STATE.lock().unwrap_or_else(|e| e.into_inner()) = Some(State {
        limits,
        bytes: 0,
        kept: Recording::default(),
    });
    ON.store(true, Ordering::SeqCst);
}

/// Stops the recording and returns what it kept (nothing if none ran).
pub fn stop() -> Recording {
    ON.store(false, Ordering::SeqCst);
    STATE
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .take()
        .map(|s| s.kept)
        .unwrap_or_default()
}

/// Called by [`Mesh::new_vertex`] before it adds the vertex.
#[inline]
pub(crate) fn before_vertex(mesh: &Mesh) {
    if ON.load(Ordering::Relaxed) {
        keep(mesh);
    }
}

#[cold]
#[inline(never)]
fn keep(mesh: &Mesh) {
    let mut guard = STATE.lock().unwrap_or_else(|e| e.into_inner());
    let Some(state) = guard.as_mut() else {
        return;
    };
    if state.kept.cut.is_some() {
        return;
    }
    let bytes = record_bytes(mesh);
    if state.kept.frames.len() >= state.limits.frames {
        state.kept.cut = Some(Cut::Frames(state.limits.frames));
    } else if state.bytes + bytes > state.limits.bytes {
        state.kept.cut = Some(Cut::Bytes(state.limits.bytes));
    } else {
        state.bytes += bytes;
        let mut copy = mesh.clone();
        // The copy is not charged against any budget.
        copy.set_element_budget(None);
        state.kept.frames.push(copy);
    }
}
