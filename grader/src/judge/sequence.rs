//! A sequence of flips and splits, judged step by step: each step's
//! return and element counts and the mesh's validity after it, then the
//! shape the last step left.

use crate::isolate::end::{Counts, MeshResult, Problem};
use crate::isolate::wire::{StepAnswer, StepRan};
use crate::judge::compare::{compare_edges, compare_vertices};
use crate::judge::fixture::{Fixture, Operation, Returns};
use crate::judge::log::{fmt_p, quote, say, Log};
use crate::judge::matching;

/// A sequence, step by step: each step's return and element counts and
/// the mesh's validity after it, then the shape the last step left. The
/// first step that goes wrong is named with everything needed to find it:
/// how many steps went before, the seed, the function and the edge.
pub(super) fn judge_sequence(
    f: &Fixture,
    steps: &[StepRan],
    panic: Option<&(String, Option<String>)>,
    (before, after): (Counts, Counts),
    invalid: Option<&Problem>,
    mesh: Option<&MeshResult>,
    log: &mut Log,
) {
    let Operation::Sequence { seed } = f.operation else {
        return;
    };
    let n = f.input.positions.len();
    let mut counts = [
        before.vertices,
        before.edges,
        before.faces,
        before.halfedges,
    ];
    let mut made = 0;
    say!(
        log,
        Info,
        "run {} flips and splits, validating after each...",
        f.steps.len()
    );
    for (i, (step, want)) in f.steps.iter().zip(&f.expected.steps).enumerate() {
        let function = step.function();
        let [a, b] = step.edge();
        let done = format!(
            "after {i} operation{} (seed {seed})",
            if i == 1 { "" } else { "s" }
        );
        let at = format!("{done}, {function} on edge {a}-{b}");
        let Some(got) = steps.get(i) else {
            if let Some((message, location)) = panic {
                // Worded as for one operation, so that a panic every case
                // shares is one line in the summary; where it came follows.
                quote!(log, Warn, message.as_str(), "{function} panicked:");
                if let Some(loc) = location {
                    quote!(log, Detail, loc.as_str(), "at");
                }
                say!(log, Detail, "{at} (step {} of {})", i + 1, f.steps.len());
                if message.starts_with("not yet implemented") {
                    say!(log, Detail, "the function is still a todo!() stub: write it in crates/meshedit/src/lib.rs");
                } else {
                    say!(log, Detail, "the same call works on the mesh as built? Then an earlier operation left a pointer that this one follows");
                }
            } else {
                say!(log, Warn, "{at} never ran: the sequence stopped early");
            }
            return;
        };
        if got.edge.is_none() {
            say!(
                log,
                Warn,
                "{done}, vertices {a} and {b} are not joined by an edge, but they must be: an earlier operation relinked the wrong vertices"
            );
            return;
        }
        let mut expected_counts = counts;
        let ok = match (want, &got.answer) {
            (Returns::Refused, StepAnswer::Nothing) => true,
            (Returns::Refused, _) => {
                say!(log, Warn, "{at} must return None (its flip would join two vertices already joined by an edge), but it did not");
                false
            }
            (_, StepAnswer::Nothing) => {
                say!(
                    log,
                    Warn,
                    "{at} returned None, but the edge lies between two triangles: it must {}",
                    if step.is_split() {
                        "split it"
                    } else {
                        "flip it"
                    }
                );
                false
            }
            (Returns::Edge { ends }, StepAnswer::Edge { id, ends: got_ends }) => {
                let same = |x: &[u32; 2]| {
                    let x = [x[0] as usize, x[1] as usize];
                    x == *ends || [x[1], x[0]] == *ends
                };
                if Some(*id) != got.edge {
                    say!(
                        log,
                        Warn,
                        "{at} returned Some(e{id}), but it must return the edge it was given (e{})",
                        got.edge.unwrap_or_default()
                    );
                    false
                } else if got.valid && !got_ends.as_ref().is_some_and(same) {
                    say!(log, Warn, "{at} left the edge joining the wrong vertices: it must join {} and {} after the flip", ends[0], ends[1]);
                    false
                } else {
                    true
                }
            }
            (
                Returns::Vertex { position },
                StepAnswer::Vertex {
                    name,
                    position: got_p,
                },
            ) => {
                let new_name = (n + made) as u32;
                made += 1;
                expected_counts[0] += 1;
                // A split between two triangles adds an edge for the other
                // half and one across each, and a face and two halfedges per triangle.
                expected_counts[1] += 3;
                expected_counts[2] += 2;
                expected_counts[3] += 6;
                let off = got_p.map_or(f64::INFINITY, |p| {
                    matching::nearest(&[p], *position).map_or(f64::INFINITY, |n| n.1)
                });
                if *name != Some(new_name) {
                    say!(log, Warn, "{at} did not return the new vertex");
                    false
                } else if off.is_nan() || off > f.tolerance {
                    say!(
                        log,
                        Warn,
                        "{at} put the new vertex away from the midpoint {} of the edge",
                        fmt_p(*position)
                    );
                    false
                } else {
                    true
                }
            }
            _ => {
                say!(log, Warn, "{at} returned the wrong kind of value");
                false
            }
        };
        if !ok {
            return;
        }
        if !got.valid {
            say!(
                log,
                Warn,
                "{at} left an invalid mesh: {}",
                invalid.map_or("validate() failed".to_string(), Problem::to_string)
            );
            if let Some(problem) = invalid {
                log.invalid_found(problem);
            }
            say!(log, Detail, "it passes alone? Then it relies on something the earlier operations changed: a vertex, edge or face pointing at a halfedge that moved");
            return;
        }
        let got_counts = got.counts.map(|c| c as usize);
        if got_counts != expected_counts {
            let c = |c: [usize; 4]| {
                format!(
                    "{} vertices, {} edges, {} faces, {} halfedges",
                    c[0], c[1], c[2], c[3]
                )
            };
            say!(log, Warn, "{at} added or removed the wrong elements");
            say!(log, Detail, "before: {}", c(counts));
            say!(log, Detail, "after:  {}", c(got_counts));
            say!(log, Detail, "should: {}", c(expected_counts));
            return;
        }
        counts = expected_counts;
    }
    if let Some((message, _)) = panic {
        quote!(
            log,
            Warn,
            message.as_str(),
            "the sequence panicked after its last step:"
        );
        return;
    }
    if steps.len() != f.steps.len() {
        say!(
            log,
            Warn,
            "the sequence ran {} steps, not {}",
            steps.len(),
            f.steps.len()
        );
        return;
    }
    say!(log, Info, "passed");
    let Some(mesh) = mesh else {
        say!(
            log,
            Warn,
            "the mesh validated after every step but could not be read back"
        );
        return;
    };
    let _ = after;
    let Some(matched) = compare_vertices(f, mesh, before, log) else {
        return;
    };
    compare_edges(f, mesh, before, &matched, log);
}
