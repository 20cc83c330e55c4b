//! The lab's log format, checked on the exact bytes written.

use std::io::Write;
use std::sync::{Arc, Mutex};

use env_logger::fmt::WriteStyle;
use halfedge::logging;
use log::{Level, Log, Record};

#[derive(Clone, Default)]
struct Buffer(Arc<Mutex<Vec<u8>>>);

impl Write for Buffer {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.0.lock().unwrap().extend_from_slice(bytes);
        Ok(bytes.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

fn logged(style: WriteStyle, level: Level, file: &str, line: u32, text: &str) -> String {
    let buffer = Buffer::default();
    let logger = logging::builder()
        .write_style(style)
        .target(env_logger::Target::Pipe(Box::new(buffer.clone())))
        .build();
    logger.log(
        &Record::builder()
            .level(level)
            .file(Some(file))
            .line(Some(line))
            .args(format_args!("{text}"))
            .build(),
    );
    logger.flush();
    let bytes = buffer.0.lock().unwrap().clone();
    String::from_utf8(bytes).unwrap()
}

#[test]
fn lines_look_like_the_lab() {
    assert_eq!(
        logged(
            WriteStyle::Never,
            Level::Info,
            "crates/meshedit/src/lib.rs",
            42,
            "split e3"
        ),
        "lib.rs:42 [info] split e3\n"
    );
    assert_eq!(
        logged(WriteStyle::Never, Level::Warn, "src\\main.rs", 7, "careful"),
        "main.rs:7 [warn] careful\n"
    );
}

#[test]
fn warnings_are_red_only_when_colour_is_on() {
    let red = logged(WriteStyle::Always, Level::Warn, "a.rs", 1, "x");
    assert_eq!(red, "a.rs:1 \u{1b}[31m[warn] x\u{1b}[0m\n");
    let info = logged(WriteStyle::Always, Level::Info, "a.rs", 1, "x");
    assert_eq!(info, "a.rs:1 [info] x\n", "info is never coloured");
}

#[test]
fn file_names_and_level_words() {
    assert_eq!(logging::short_file("a/b/c.rs"), "c.rs");
    assert_eq!(logging::short_file("c.rs"), "c.rs");
    assert_eq!(logging::level_word(Level::Warn), "warn");
    assert_eq!(logging::level_word(Level::Info), "info");
}
