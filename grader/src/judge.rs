//! Judging: from a case and what the child sent back to a verdict, its
//! findings as data and its messages. Nothing here starts a process.
//!
//! - [`fixture`]: the case format, shared with the fixture generator;
//!   [`digest`]: the fixtures' SHA-256 list.
//! - [`relabel`]: the same input with other ids and pointers, so that
//!   order-dependent bugs show.
//! - [`matching`]: order-independent comparison of vertices and edges.
//! - [`grade`]: the verdict and messages for one case, built from the
//!   checks beside it ([`ended`], [`returned`], [`counts`], [`compare`],
//!   [`sequence`]) writing to a [`log`]; [`verdict`]: the verdict and its
//!   findings as data ([`named`]: the elements its lines name); [`frames`]: the step-through of a recorded
//!   subdivision.
//! - [`scaling`]: `loop_subdivide` timed on two sizes, to catch quadratic
//!   code (a warning, not counted).

pub mod compare;
pub mod counts;
pub mod digest;
pub mod ended;
pub mod fixture;
pub mod frames;
pub mod grade;
pub mod log;
pub mod matching;
pub mod named;
pub mod relabel;
pub mod returned;
pub mod scaling;
pub mod sequence;
pub mod verdict;
