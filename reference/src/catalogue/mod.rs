//! The catalogue of implementations the grader is tested with: each entry
//! is the three functions a student writes, with a name and what it does.
//!
//! ```text
//!   alternatives  correct answers that differ from the model (must pass)
//!        ^
//!   mistakes      the stubs and one per common mistake (must fail, named)
//!        ^
//!   attacks       hostile code (must be stopped); lookup: the visible
//!                 cases' lookup table
//! ```
//!
//! Each arrow is "used by": attacks build on mistakes (most end with the
//! no-flip mistake), mistakes on the alternatives' steps, never the reverse.
//! [`entry`] holds the entry type and its builder.

pub mod alternatives;
pub mod attacks;
pub mod entry;
pub mod lookup;
pub mod mistakes;

pub use entry::{model, Build, Entry};
pub use mistakes::{subdivision_mistakes, KnownMistake};

use grader::Implementation;

/// The model solution.
pub fn reference() -> Implementation {
    model().done()
}

/// Every implementation: correct ones first, then the mistakes, then the
/// attacks.
pub fn catalogue() -> Vec<Entry> {
    let mut all = alternatives::entries();
    all.extend(mistakes::entries());
    all.extend(attacks::entries());
    all
}

/// The catalogue entry named `name`.
pub fn find(name: &str) -> Option<Entry> {
    catalogue().into_iter().find(|e| e.name == name)
}
