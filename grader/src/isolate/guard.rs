//! Running code that may panic without a word reaching the screen: the
//! student's functions in the child, and the parent's checks and judge,
//! which walk data the student's code made. [`guarded`] turns a panic into
//! its message and location; a panic outside it is said in one line, as
//! the grader's own error.

use std::cell::RefCell;
use std::panic::{self, AssertUnwindSafe};

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
