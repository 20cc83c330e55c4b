//! The grader's words as a switch: every message the judge says, and
//! every `validate()` message the parent reads, passes through [`words`],
//! which the tests can turn into a rewording that no decision survives
//! if it reads words; and how sizes are said ([`format_bytes`]). The
//! bottom of the crate: every layer may use it.

use std::sync::atomic::{AtomicBool, Ordering};

/// Whether every message is rewritten (see [`set_rewording`]).
static REWORDING: AtomicBool = AtomicBool::new(false);

/// For the tests that prove no decision reads a message: from now on, in
/// this process, every line the judge says and every `validate()` message
/// the parent reads is rewritten ([`words`]). Off in normal use.
pub fn set_rewording(on: bool) {
    REWORDING.store(on, Ordering::Relaxed);
}

/// A message as the grader says it: unchanged, or rewritten when
/// [`set_rewording`] is on (upper case behind a marker, so any code that
/// still matched words would stop matching).
pub fn words(text: String) -> String {
    if REWORDING.load(Ordering::Relaxed) {
        format!("REWORDED: {}", text.to_uppercase())
    } else {
        text
    }
}

/// `2 GiB`, `512 MiB`: how messages say a memory size.
pub fn format_bytes(bytes: u64) -> String {
    const GIB: u64 = 1 << 30;
    const MIB: u64 = 1 << 20;
    if bytes % GIB == 0 {
        format!("{} GiB", bytes / GIB)
    } else if bytes >= GIB {
        format!("{:.1} GiB", bytes as f64 / GIB as f64)
    } else {
        format!("{} MiB", bytes.div_ceil(MIB))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_well() {
        assert_eq!(format_bytes(2 << 30), "2 GiB");
        assert_eq!(format_bytes(512 << 20), "512 MiB");
        assert_eq!(format_bytes(3 << 29), "1.5 GiB");
    }
}
