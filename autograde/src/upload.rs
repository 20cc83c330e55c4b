//! Finding the student's `lib.rs` in whatever they uploaded: the file
//! alone, the workspace, the workspace inside one folder (a zip of the
//! folder), with other crates' `lib.rs` around. One table of layouts is
//! tested here; every platform goes through [`find_lib_rs`].
//!
//! And reading it: whatever a student hands in may be a named pipe, a
//! device or a link (a tarball unpacked by root recreates them all), or a
//! file of gigabytes. [`read_source`] is the one way every path (class
//! grading, the Gradescope upload, Classroom 50, PrairieLearn, the
//! similarity hints) reads a student's file: regular files only, opened
//! without following a link and without blocking, checked again on the
//! opened descriptor, at most [`MAX_SOURCE_BYTES`] read.

use std::io::Read as _;
use std::path::{Path, PathBuf};

/// Folders of an upload that never hold the student's file.
const SKIP_DIRS: [&str; 4] = ["target", ".git", "__MACOSX", "node_modules"];
/// Crates of the lab other than the student's: their `lib.rs` is never taken.
const OTHER_CRATES: [&str; 5] = ["halfedge", "grader", "reference", "autograde", "crates"];

/// Why no file was taken from an upload (facts; [`NotFound::message`]
/// words them for the student).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NotFound {
    /// Several `meshedit/src/lib.rs` at the same depth.
    SeveralMeshedit(Vec<String>),
    /// Several loose `lib.rs` outside the lab's other crates.
    SeveralLib(Vec<String>),
    /// The file that would be taken is a symbolic link (never followed: it
    /// could name a hidden case, which the compiler would quote back).
    Link(String),
    /// The file that would be taken cannot be taken as it is (see
    /// [`read_source`]).
    Unfit(String, Unfit),
    /// Nothing fits; up to 10 of the Rust files seen.
    Nothing(Vec<String>),
}

impl NotFound {
    /// What the student reads.
    pub fn message(&self) -> String {
        match self {
            NotFound::SeveralMeshedit(list) => format!(
                "Your upload holds several copies of meshedit/src/lib.rs ({}): upload only one.",
                list.join(", ")
            ),
            NotFound::SeveralLib(list) => format!(
                "Your upload holds several lib.rs files ({}): upload only crates/meshedit/src/lib.rs.",
                list.join(", ")
            ),
            NotFound::Link(path) => {
                format!("{path} is a symbolic link: upload the file itself.")
            }
            NotFound::Unfit(path, why) => why.message(path),
            NotFound::Nothing(seen) => format!(
                "No crates/meshedit/src/lib.rs in your upload (found: {}). Upload the file \
                 crates/meshedit/src/lib.rs alone, or the whole lab folder.",
                if seen.is_empty() {
                    "no .rs file at all".to_string()
                } else {
                    seen.join(", ")
                }
            ),
        }
    }
}

/// The most bytes a student's source file may hold. The lab's `lib.rs` is
/// 10 KiB as handed out and 20-40 KiB solved; a file past this is no
/// hand-written answer, and reading it whole would cost memory for nothing
/// (a 60 MB one held the similarity hints in 4 GB).
pub const MAX_SOURCE_BYTES: u64 = 1 << 20;

/// What a path that is not a regular file is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Link,
    Folder,
    NamedPipe,
    CharDevice,
    BlockDevice,
    Socket,
    Unknown,
}

impl Kind {
    /// `None` for a regular file.
    fn of(file_type: std::fs::FileType) -> Option<Kind> {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_file() {
            return None;
        }
        Some(if file_type.is_symlink() {
            Kind::Link
        } else if file_type.is_dir() {
            Kind::Folder
        } else if file_type.is_fifo() {
            Kind::NamedPipe
        } else if file_type.is_char_device() {
            Kind::CharDevice
        } else if file_type.is_block_device() {
            Kind::BlockDevice
        } else if file_type.is_socket() {
            Kind::Socket
        } else {
            Kind::Unknown
        })
    }

    pub fn words(self) -> &'static str {
        match self {
            Kind::Link => "a symbolic link",
            Kind::Folder => "a folder",
            Kind::NamedPipe => "a named pipe",
            Kind::CharDevice => "a character device",
            Kind::BlockDevice => "a block device",
            Kind::Socket => "a socket",
            Kind::Unknown => "of an unknown type",
        }
    }
}

/// Why a student's file was not read (facts; [`Unfit::message`] words
/// them).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Unfit {
    /// Not a regular file (never opened, or closed unread).
    NotRegular(Kind),
    /// More than [`MAX_SOURCE_BYTES`]: its size.
    TooLarge(u64),
    /// The system refused (its words).
    Unreadable(String),
}

impl Unfit {
    /// What the student reads, `path` being the file as they know it.
    pub fn message(&self, path: &str) -> String {
        match self {
            Unfit::NotRegular(kind) => format!(
                "{path} is not a regular file ({}): upload the file itself.",
                kind.words()
            ),
            Unfit::TooLarge(bytes) => format!(
                "{path} is larger than {} MiB ({bytes} bytes): the lab's lib.rs is far \
                 smaller; upload crates/meshedit/src/lib.rs alone.",
                MAX_SOURCE_BYTES >> 20
            ),
            Unfit::Unreadable(error) => format!("{path} cannot be read: {error}."),
        }
    }
}

/// The bytes of a student's source file ([`read_capped`] at
/// [`MAX_SOURCE_BYTES`]).
pub fn read_source(path: &Path) -> Result<Vec<u8>, Unfit> {
    read_capped(path, MAX_SOURCE_BYTES)
}

/// The bytes of a student's file, if it is a regular file of at most
/// `cap` bytes. Anything else is never opened (opening a device
/// runs its driver's code; a named pipe blocks until someone writes), and
/// the file opened is checked again on its descriptor (`fstat`): opened
/// without following a link (`O_NOFOLLOW`) and without blocking
/// (`O_NONBLOCK`), never as a terminal (`O_NOCTTY`), the same file
/// (device and inode) as the one looked at, and read to the cap and one
/// byte more, however large it has grown since.
pub fn read_capped(path: &Path, cap: u64) -> Result<Vec<u8>, Unfit> {
    use std::os::unix::fs::{MetadataExt, OpenOptionsExt};
    let io = |e: std::io::Error| Unfit::Unreadable(e.to_string());
    let seen = std::fs::symlink_metadata(path).map_err(io)?;
    if let Some(kind) = Kind::of(seen.file_type()) {
        return Err(Unfit::NotRegular(kind));
    }
    if seen.len() > cap {
        return Err(Unfit::TooLarge(seen.len()));
    }
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK | libc::O_NOCTTY)
        .open(path)
        .map_err(|e| match e.raw_os_error() {
            // Made a link since it was looked at.
            Some(libc::ELOOP) => Unfit::NotRegular(Kind::Link),
            _ => io(e),
        })?;
    let opened = file.metadata().map_err(io)?;
    if let Some(kind) = Kind::of(opened.file_type()) {
        return Err(Unfit::NotRegular(kind));
    }
    if (opened.dev(), opened.ino()) != (seen.dev(), seen.ino()) {
        return Err(Unfit::Unreadable(
            "it was replaced while it was being read".into(),
        ));
    }
    if opened.len() > cap {
        return Err(Unfit::TooLarge(opened.len()));
    }
    let mut bytes = Vec::with_capacity(opened.len() as usize);
    (&file).take(cap + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > cap {
        // It grew while it was read.
        let now = file.metadata().map_or(bytes.len() as u64, |m| m.len());
        return Err(Unfit::TooLarge(now));
    }
    Ok(bytes)
}

/// The student's `lib.rs` inside an uploaded folder ([`find_lib_rs`]) and
/// its bytes ([`read_source`]): what every platform grades.
pub fn take_lib_rs(dir: &Path) -> Result<(PathBuf, Vec<u8>), NotFound> {
    let path = find_lib_rs(dir)?;
    match read_source(&path) {
        Ok(bytes) => Ok((path, bytes)),
        Err(why) => {
            let shown = path
                .strip_prefix(dir)
                .unwrap_or(&path)
                .display()
                .to_string();
            Err(NotFound::Unfit(shown, why))
        }
    }
}

/// Whether `path` is a symbolic link.
pub fn is_link(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
}

/// Every `.rs` file under `dir` (links included, to be refused by name),
/// relative, in sorted walk order; linked folders are never entered.
fn rust_files(dir: &Path, rel: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir.join(rel)) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for path in paths {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let rel_path = rel.join(&*name);
        if !is_link(&path) && path.is_dir() {
            if !name.starts_with('.') && !SKIP_DIRS.contains(&&*name) {
                rust_files(dir, &rel_path, out);
            }
        } else if name.ends_with(".rs") {
            out.push(rel_path);
        }
    }
}

fn parts(p: &Path) -> Vec<String> {
    p.components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect()
}

fn shown(list: &[&PathBuf]) -> Vec<String> {
    list.iter().map(|p| p.display().to_string()).collect()
}

/// The student's `lib.rs` inside an uploaded folder: `meshedit/src/lib.rs`
/// at any depth (the shallowest), else a single `lib.rs` outside any other
/// crate of the lab, else the folder's only Rust file at its top. Never
/// another crate's `lib.rs`, never a symbolic link.
pub fn find_lib_rs(dir: &Path) -> Result<PathBuf, NotFound> {
    let mut found = Vec::new();
    rust_files(dir, Path::new(""), &mut found);
    let is_lib = |p: &&PathBuf| p.file_name().is_some_and(|n| n == "lib.rs");
    let mut meshedit: Vec<&PathBuf> = found
        .iter()
        .filter(is_lib)
        .filter(|p| parts(p).ends_with(&["meshedit".into(), "src".into(), "lib.rs".into()]))
        .collect();
    meshedit.sort_by_key(|p| (parts(p).len(), p.to_path_buf()));
    let chosen = match meshedit.as_slice() {
        [one] => Some(*one),
        [a, b, ..] if parts(a).len() < parts(b).len() => Some(*a),
        [_, _, ..] => return Err(NotFound::SeveralMeshedit(shown(&meshedit))),
        [] => None,
    };
    let chosen = match chosen {
        Some(p) => p,
        None => {
            let loose: Vec<&PathBuf> = found
                .iter()
                .filter(is_lib)
                .filter(|p| {
                    let ps = parts(p);
                    !ps[..ps.len() - 1]
                        .iter()
                        .any(|c| OTHER_CRATES.contains(&c.as_str()))
                })
                .collect();
            match loose.as_slice() {
                [one] => *one,
                [_, _, ..] => return Err(NotFound::SeveralLib(shown(&loose))),
                [] => match found.as_slice() {
                    [only] if parts(only).len() == 1 => only,
                    _ => {
                        let seen = found.iter().take(10).map(|p| p.display().to_string());
                        return Err(NotFound::Nothing(seen.collect()));
                    }
                },
            }
        }
    };
    let path = dir.join(chosen);
    if is_link(&path) {
        return Err(NotFound::Link(chosen.display().to_string()));
    }
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every upload layout a platform has met: (files, the one taken or
    /// the start of the message).
    const LAYOUTS: &[(&[&str], Result<&str, &str>)] = &[
        (&["lib.rs"], Ok("lib.rs")),
        (&["meshedit.rs"], Ok("meshedit.rs")),
        (
            &["crates/meshedit/src/lib.rs"],
            Ok("crates/meshedit/src/lib.rs"),
        ),
        (
            &[
                "crates/halfedge/src/lib.rs",
                "crates/meshedit/src/lib.rs",
                "grader/src/lib.rs",
                "Cargo.toml",
            ],
            Ok("crates/meshedit/src/lib.rs"),
        ),
        (
            &[
                "lab-2026/crates/halfedge/src/lib.rs",
                "lab-2026/crates/meshedit/src/lib.rs",
                "lab-2026/grader/src/lib.rs",
            ],
            Ok("lab-2026/crates/meshedit/src/lib.rs"),
        ),
        // The shallowest copy wins over one in a backup folder below it.
        (
            &[
                "crates/meshedit/src/lib.rs",
                "old/crates/meshedit/src/lib.rs",
            ],
            Ok("crates/meshedit/src/lib.rs"),
        ),
        (
            &["a/meshedit/src/lib.rs", "b/meshedit/src/lib.rs"],
            Err("Your upload holds several copies"),
        ),
        (&["src/lib.rs"], Ok("src/lib.rs")),
        (
            &["x/lib.rs", "y/lib.rs"],
            Err("Your upload holds several lib.rs"),
        ),
        (
            &["crates/halfedge/src/lib.rs"],
            Err("No crates/meshedit/src/lib.rs in your upload (found: crates/halfedge/src/lib.rs)"),
        ),
        (
            &[],
            Err("No crates/meshedit/src/lib.rs in your upload (found: no .rs file at all)"),
        ),
        (
            &[
                "target/debug/lib.rs",
                "__MACOSX/lib.rs",
                ".git/lib.rs",
                "main.rs",
            ],
            Ok("main.rs"),
        ),
        (
            &["notes/a.rs", "notes/b.rs"],
            Err("No crates/meshedit/src/lib.rs"),
        ),
    ];

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("autograde-upload-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn every_upload_layout_finds_the_student_s_file_or_says_why() {
        for (i, (files, expected)) in LAYOUTS.iter().enumerate() {
            let dir = scratch(&i.to_string());
            for f in *files {
                let path = dir.join(f);
                std::fs::create_dir_all(path.parent().unwrap()).unwrap();
                std::fs::write(&path, "// a file").unwrap();
            }
            let got = find_lib_rs(&dir);
            match (expected, &got) {
                (Ok(want), Ok(path)) => assert_eq!(path, &dir.join(want), "{files:?}"),
                (Err(start), Err(why)) => {
                    assert!(
                        why.message().starts_with(start),
                        "{files:?}: {}",
                        why.message()
                    )
                }
                _ => panic!("{files:?}: expected {expected:?}, got {got:?}"),
            }
            std::fs::remove_dir_all(&dir).unwrap();
        }
    }

    #[test]
    fn a_linked_file_is_refused_by_name_and_a_linked_folder_never_entered() {
        let dir = scratch("links");
        let outside = scratch("outside");
        std::fs::create_dir_all(outside.join("crates/meshedit/src")).unwrap();
        std::fs::write(outside.join("crates/meshedit/src/lib.rs"), "secret").unwrap();
        std::os::unix::fs::symlink(
            outside.join("crates/meshedit/src/lib.rs"),
            dir.join("lib.rs"),
        )
        .unwrap();
        assert_eq!(
            find_lib_rs(&dir).unwrap_err().message(),
            "lib.rs is a symbolic link: upload the file itself."
        );
        std::fs::remove_file(dir.join("lib.rs")).unwrap();
        std::os::unix::fs::symlink(&outside, dir.join("lab")).unwrap();
        assert!(matches!(find_lib_rs(&dir), Err(NotFound::Nothing(_))));
        std::fs::remove_dir_all(&dir).unwrap();
        std::fs::remove_dir_all(&outside).unwrap();
    }

    /// `f` on another thread, failed if it takes over 10 s (a read that
    /// blocks would hang the test run rather than fail it).
    fn within_seconds<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
        let (send, receive) = std::sync::mpsc::channel();
        std::thread::spawn(move || send.send(f()));
        receive
            .recv_timeout(std::time::Duration::from_secs(10))
            .expect("did not return within 10 s: it blocked")
    }

    fn mkfifo(path: &Path) {
        use std::os::unix::ffi::OsStrExt;
        let c = std::ffi::CString::new(path.as_os_str().as_bytes()).unwrap();
        // SAFETY: a valid C string; mkfifo only makes the file.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0, "mkfifo");
    }

    #[test]
    fn only_a_regular_file_within_the_cap_is_read_and_nothing_blocks() {
        let dir = scratch("unfit");
        let file = dir.join("lib.rs");
        std::fs::write(&file, "pub fn f() {}").unwrap();
        assert_eq!(read_source(&file).unwrap(), b"pub fn f() {}");
        // A named pipe with no writer: opening it to read would block.
        let fifo = dir.join("fifo.rs");
        mkfifo(&fifo);
        let got = within_seconds({
            let fifo = fifo.clone();
            move || read_source(&fifo)
        });
        assert_eq!(got, Err(Unfit::NotRegular(Kind::NamedPipe)));
        // Devices are never opened; /dev/zero would never end.
        for (device, kind) in [
            ("/dev/zero", Kind::CharDevice),
            ("/dev/null", Kind::CharDevice),
        ] {
            let got = within_seconds(move || read_source(Path::new(device)));
            assert_eq!(got, Err(Unfit::NotRegular(kind)), "{device}");
        }
        let link = dir.join("zero.rs");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        assert_eq!(read_source(&link), Err(Unfit::NotRegular(Kind::Link)));
        assert_eq!(read_source(&dir), Err(Unfit::NotRegular(Kind::Folder)));
        // The cap, to the byte (sparse files: nothing is written).
        let big = dir.join("big.rs");
        let f = std::fs::File::create(&big).unwrap();
        f.set_len(MAX_SOURCE_BYTES).unwrap();
        assert_eq!(read_source(&big).unwrap().len() as u64, MAX_SOURCE_BYTES);
        f.set_len(MAX_SOURCE_BYTES + 1).unwrap();
        assert_eq!(
            read_source(&big),
            Err(Unfit::TooLarge(MAX_SOURCE_BYTES + 1))
        );
        assert!(matches!(
            read_source(&dir.join("missing.rs")),
            Err(Unfit::Unreadable(_))
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_unfit_lib_rs_in_an_upload_is_named_by_its_path_there() {
        let dir = scratch("unfit-upload");
        std::fs::create_dir_all(dir.join("crates/meshedit/src")).unwrap();
        let lib = dir.join("crates/meshedit/src/lib.rs");
        mkfifo(&lib);
        let got = within_seconds({
            let dir = dir.clone();
            move || take_lib_rs(&dir).map(|(p, _)| p)
        });
        assert_eq!(
            got.unwrap_err().message(),
            "crates/meshedit/src/lib.rs is not a regular file (a named pipe): upload the file \
             itself."
        );
        std::fs::remove_file(&lib).unwrap();
        std::fs::File::create(&lib)
            .unwrap()
            .set_len(60 << 20)
            .unwrap();
        assert_eq!(
            take_lib_rs(&dir).unwrap_err().message(),
            "crates/meshedit/src/lib.rs is larger than 1 MiB (62914560 bytes): the lab's lib.rs \
             is far smaller; upload crates/meshedit/src/lib.rs alone."
        );
        std::fs::write(&lib, "pub fn f() {}").unwrap();
        assert_eq!(take_lib_rs(&dir).unwrap(), (lib, b"pub fn f() {}".to_vec()));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
