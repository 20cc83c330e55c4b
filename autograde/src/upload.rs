//! Finding the student's `lib.rs` in whatever they uploaded: the file
//! alone, the workspace, the workspace inside one folder (a zip of the
//! folder), with other crates' `lib.rs` around. One table of layouts is
//! tested here; every platform goes through [`find_lib_rs`].

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
}
