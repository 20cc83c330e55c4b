//! The lab's log format: `file.rs:LINE [info] message`.
//!
//! Call [`init`] once at the start of a program; then `log::info!` and
//! `log::warn!` print like the original lab's `info()` and `warn()`. Warnings
//! are red only when printing to a terminal, and never when `NO_COLOR` is set.

use std::io::Write;

use env_logger::fmt::style::{AnsiColor, Style};
use env_logger::fmt::WriteStyle;
use log::Level;

/// Whether to colour `[warn]` lines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Color {
    /// Red on a terminal, plain when piped or when `NO_COLOR` is set.
    Auto,
    Never,
}

/// The level word the lab prints between brackets.
pub fn level_word(level: Level) -> &'static str {
    match level {
        Level::Error => "error",
        Level::Warn => "warn",
        Level::Info => "info",
        Level::Debug => "debug",
        Level::Trace => "trace",
    }
}

/// The file name alone, as the lab prints it (`main.rs`, not `src/main.rs`).
pub fn short_file(path: &str) -> &str {
    path.rsplit(['/', '\\']).next().unwrap_or(path)
}

/// Sets up `log` to print to standard output in the lab's format. Messages
/// at `info` and above are shown; `RUST_LOG` can change that. Calling it a
/// second time does nothing.
pub fn init(color: Color) {
    let mut builder = builder();
    builder.write_style(match color {
        Color::Auto => WriteStyle::Auto,
        Color::Never => WriteStyle::Never,
    });
    // A second init (e.g. in tests) keeps the first logger: not an error.
    let _ = builder.try_init();
}

/// The logger [`init`] installs, before its colour choice: to standard
/// output, `info` and above (or as `RUST_LOG` says), in the lab's format.
pub fn builder() -> env_logger::Builder {
    let mut builder = env_logger::Builder::new();
    builder
        .filter_level(log::LevelFilter::Info)
        .parse_default_env()
        .target(env_logger::Target::Stdout)
        .format(|buf, record| {
            let file = short_file(record.file().unwrap_or("?"));
            let line = record.line().unwrap_or(0);
            let word = level_word(record.level());
            let style = if record.level() <= Level::Warn {
                Style::new().fg_color(Some(AnsiColor::Red.into()))
            } else {
                Style::new()
            };
            writeln!(
                buf,
                "{file}:{line} {style}[{word}] {}{style:#}",
                record.args()
            )
        });
    builder
}
