//! Isolating the child: everything between "run this case" and the bytes
//! the student's code sent back. Nothing here judges an answer.
//!
//! - [`sandbox`]: the launcher that locks the child in, putting together
//!   [`sys`] (limits, users, capabilities, sessions), [`namespace`] (the
//!   PID namespace and the empty root), [`landlock_rules`] and
//!   [`seccomp`] (its system-call filter); [`protections`]: what it put in
//!   force, as facts.
//! - [`runner`]: starting, timing and killing the child ([`spawn`]: how
//!   the launcher starts, in a session of its own; `streams`: the threads
//!   reading its frames and its output; [`process`]: the
//!   grading process, process groups, the sweep of orphans, the child's
//!   CPU clock); [`end`]: how a case ended, the one type the judge and the
//!   reports read.
//! - [`wire`]: what crosses the pipes, in both directions.
//! - [`child`]: the child's side ([`child::serve`]); [`analyze`]: the
//!   parent's reading of its result; [`guard`]: panics caught without a
//!   word on the screen, on both sides.
//!
//! The same lock-in for a student's build (class grading, the platforms)
//! is the TAs' side's: `autograde::build`, built on [`sys`],
//! [`namespace`], [`landlock_rules`] and [`process`].

pub mod analyze;
pub mod child;
pub mod end;
pub mod guard;
pub mod landlock_rules;
pub mod namespace;
pub mod process;
pub mod protections;
pub mod runner;
pub mod sandbox;
pub mod seccomp;
#[cfg(target_os = "linux")]
pub mod spawn;
mod streams;
pub mod sys;
pub mod wire;
