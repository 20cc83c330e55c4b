//! How a call that did not return a mesh to judge ended, in the lab's
//! words: out of time, stuck before the call, a stack overflow, out of
//! memory, a signal, an exit, a garbled or runaway result, a panic (the
//! stubs' `todo!()`, or the one panic the contract asks for), the grader's
//! own failure.

use crate::isolate::end::CaseEnd;
use crate::judge::fixture::{Fixture, Returns};
use crate::judge::log::{hint, quote, say, Log};
use crate::judge::verdict::{GraderHint, Hint};

/// Says how the call ended when it did not end with a mesh to judge:
/// every end but a sequence that ran and a mesh returned as asked.
pub(super) fn say_how(f: &Fixture, end: &CaseEnd, failed: Option<&str>, log: &mut Log) {
    let function = f.operation.stage().function();
    let must_panic = f.expected.returns == Some(Returns::Panic);
    match end {
        CaseEnd::TimedOut { limit } => {
            say!(
                log,
                Warn,
                "{function} did not finish within {} s",
                limit.as_secs_f64()
            );
            say!(log, Detail, "an endless loop? a walk around a face or vertex that never gets back to its start?");
        }
        CaseEnd::StuckBeforeCall { limit } => {
            say!(
                log,
                Warn,
                "{function} was never reached: the program was still starting after {} s",
                limit.as_secs_f64()
            );
            say!(
                log,
                Detail,
                "does your crate run code before main (a static initialiser) that never ends?"
            );
        }
        CaseEnd::StackOverflow => {
            say!(log, Warn, "{function} overflowed the stack");
            say!(log, Detail, "a function that calls itself without end?");
        }
        CaseEnd::OutOfMemory { cap } => {
            say!(
                log,
                Warn,
                "{function} used more than {} of memory",
                crate::text::format_bytes(*cap)
            );
            say!(log, Detail, "a loop that never stops adding elements or growing a Vec? (--memory changes the cap)");
        }
        CaseEnd::Signal { signal: sig } => {
            say!(log, Warn, "{function} crashed: {}", signal_name(*sig));
        }
        CaseEnd::Exited { code } => {
            let code = code.map_or("unknown".to_string(), |c| c.to_string());
            say!(
                log,
                Warn,
                "{function} ended the program (exit status {code}) before returning"
            );
            say!(log, Detail, "does your code call std::process::exit?");
        }
        CaseEnd::Garbled { why } => {
            say!(
                log,
                Warn,
                "{function}'s result could not be read: the grader's channel was written to ({why})"
            );
            say!(
                log,
                Detail,
                "does your code write to file descriptors it did not open?"
            );
        }
        CaseEnd::TooLarge { bytes } => {
            say!(
                log,
                Warn,
                "{function} returned a mesh far larger than any right answer ({} MiB of data)",
                bytes >> 20
            );
            hint!(log, f, Hint::Grader(GraderHint::RunawayResult));
        }
        // A sandbox that failed stops grading before any judging (`lib.rs`):
        // here only for completeness, said as the grader's problem.
        CaseEnd::JudgeFailed | CaseEnd::SandboxFailed { .. } => {
            let why = match end {
                CaseEnd::SandboxFailed { why } => why.as_str(),
                _ => failed.unwrap_or_default(),
            };
            quote!(
                log,
                Warn,
                why,
                "the grader could not judge this result: tell a TA, with your code; the grader's message:"
            );
        }
        CaseEnd::Panicked {
            message,
            location,
            grew_past,
        } if must_panic => {
            if is_stub(message) {
                quote!(log, Warn, message.as_str(), "{function} panicked:");
                say!(
                    log,
                    Detail,
                    "the function is still a todo!() stub: write it in crates/meshedit/src/lib.rs"
                );
            } else if grew_past.is_none() && names_a_non_triangle(message) {
                quote!(
                    log,
                    Info,
                    message.as_str(),
                    "{function} panicked, as it must:"
                );
            } else {
                quote!(
                    log,
                    Warn,
                    message.as_str(),
                    "{function} panicked, but its message does not say a face is not a triangle:"
                );
                if let Some(loc) = location {
                    quote!(log, Detail, loc.as_str(), "at");
                }
                say!(log, Detail, "check first: mesh.first_non_triangle() finds such a face; name it in the panic message");
            }
        }
        CaseEnd::Panicked {
            message,
            location,
            grew_past,
        } => {
            quote!(log, Warn, message.as_str(), "{function} panicked:");
            if let Some(loc) = location {
                quote!(log, Detail, loc.as_str(), "at");
            }
            if grew_past.is_some() {
                hint!(log, f, Hint::Grader(GraderHint::GrewPast));
            } else if is_stub(message) {
                say!(
                    log,
                    Detail,
                    "the function is still a todo!() stub: write it in crates/meshedit/src/lib.rs"
                );
            }
        }
        CaseEnd::Returned(_) if must_panic => {
            say!(log, Warn, "{function} returned, but the mesh has a face that is not a triangle: it must panic with a message that says so");
        }
        CaseEnd::Sequence(_) | CaseEnd::Returned(_) => {}
    }
}

/// Whether a panic is `todo!()`'s: std's own words for the stubs, the
/// one panic the grader tells by its message (std gives no other sign).
fn is_stub(message: &str) -> bool {
    message.starts_with("not yet implemented")
}

/// Whether the student's panic message says a face is not a triangle, as
/// the contract asks of `loop_subdivide` on a mesh with another face: the
/// student's words are what is judged here (like a position), never a
/// message of the grader or the mesh library.
fn names_a_non_triangle(student_message: &str) -> bool {
    student_message.to_lowercase().contains("triangle")
}

fn signal_name(sig: i32) -> String {
    let name = match sig {
        6 => "SIGABRT: the program aborted",
        9 => "SIGKILL: killed, perhaps for using too much memory",
        11 => "SIGSEGV: invalid memory access",
        4 => "SIGILL: illegal instruction",
        8 => "SIGFPE: arithmetic error",
        _ => "",
    };
    if name.is_empty() {
        format!("signal {sig}")
    } else {
        format!("signal {sig} ({name})")
    }
}
