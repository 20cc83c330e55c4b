//! Exporting the student workspace: the lab without the solution.
//!
//! Everything under the lab's root is copied except what only TAs may see
//! (this crate, hidden fixtures, the TA guide, CI) and build or version
//! control output. The root manifest and lock file lose the `reference` package and the
//! README becomes the student README kept in `reference/handout/`.

use std::path::{Path, PathBuf};

/// Paths (relative to the root, `/`-separated) never copied.
pub const EXCLUDED: [&str; 6] = [
    ".git",
    "target",
    "reference",
    "fixtures/hidden",
    "docs/ta-guide.md",
    ".ci",
];

/// What a copy of the lab is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Purpose {
    /// The student workspace: no solution, no hidden cases, student README.
    Handout,
    /// A scratch workspace to grade submissions in: no solution, but the
    /// hidden cases.
    Grading,
}

/// What an export wrote.
#[derive(Debug, Default)]
pub struct Exported {
    pub files: usize,
}

fn excluded(rel: &str, purpose: Purpose) -> bool {
    let kept_for_grading = purpose == Purpose::Grading && rel == "fixtures/hidden";
    (EXCLUDED.contains(&rel) && !kept_for_grading) || rel.ends_with(".snap.new")
}

/// The manifest without the `reference` member.
fn student_manifest(text: &str) -> Result<String, String> {
    let member = "\"reference\"";
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("members") && l.contains(member))
        .ok_or("Cargo.toml: no `members = [...]` line naming \"reference\"")?;
    let fixed = line
        .replace(&format!("{member}, "), "")
        .replace(&format!(", {member}"), "");
    Ok(text.replace(line, &fixed))
}

/// The lock file without the `reference` package (cargo drops the
/// dependencies only it used on the first build).
fn student_lock(text: &str) -> String {
    text.split("\n\n")
        .filter(|block| !block.contains("\nname = \"reference\"\n"))
        .collect::<Vec<_>>()
        .join("\n\n")
}

fn copy_tree(
    root: &Path,
    rel: &Path,
    dest: &Path,
    purpose: Purpose,
    out: &mut Exported,
) -> Result<(), String> {
    let dir = root.join(rel);
    let mut entries: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_name().expect("a directory entry has a name");
        let rel_path = rel.join(name);
        let rel_str = rel_path.to_string_lossy().replace('\\', "/");
        if excluded(&rel_str, purpose) {
            continue;
        }
        let target = dest.join(&rel_path);
        if path.is_dir() {
            std::fs::create_dir_all(&target).map_err(|e| format!("{}: {e}", target.display()))?;
            copy_tree(root, &rel_path, dest, purpose, out)?;
        } else {
            let write = |bytes: &[u8]| {
                std::fs::write(&target, bytes).map_err(|e| format!("{}: {e}", target.display()))
            };
            match rel_str.as_str() {
                "Cargo.toml" => {
                    let text = std::fs::read_to_string(&path).map_err(|e| e.to_string())?;
                    write(student_manifest(&text)?.as_bytes())?;
                }
                "Cargo.lock" => {
                    let text = std::fs::read_to_string(&path).map_err(|e| e.to_string())?;
                    write(student_lock(&text).as_bytes())?;
                }
                "README.md" if purpose == Purpose::Handout => {
                    write(include_str!("../handout/README.md").as_bytes())?
                }
                _ => {
                    std::fs::copy(&path, &target)
                        .map_err(|e| format!("{}: {e}", path.display()))?;
                }
            }
            out.files += 1;
        }
    }
    Ok(())
}

/// Writes the student workspace for the lab at `root` into `dest`, which
/// must not exist yet or be empty, and must not lie inside the lab.
pub fn export(root: &Path, dest: &Path) -> Result<Exported, String> {
    copy_lab(root, dest, Purpose::Handout)
}

/// Copies the lab at `root` into `dest` (new or empty, outside the lab).
pub fn copy_lab(root: &Path, dest: &Path, purpose: Purpose) -> Result<Exported, String> {
    let root = root
        .canonicalize()
        .map_err(|e| format!("{}: {e}", root.display()))?;
    if !root.join("Cargo.toml").is_file() || !root.join("crates/meshedit").is_dir() {
        return Err(format!("{} is not the lab's folder", root.display()));
    }
    if dest.exists() {
        let empty = std::fs::read_dir(dest)
            .map_err(|e| format!("{}: {e}", dest.display()))?
            .next()
            .is_none();
        if !empty {
            return Err(format!(
                "{} exists and is not empty: choose a new folder",
                dest.display()
            ));
        }
    }
    std::fs::create_dir_all(dest).map_err(|e| format!("{}: {e}", dest.display()))?;
    let dest = dest
        .canonicalize()
        .map_err(|e| format!("{}: {e}", dest.display()))?;
    if dest.starts_with(&root) {
        return Err(format!(
            "{} is inside the lab: choose a folder outside it",
            dest.display()
        ));
    }
    let mut out = Exported::default();
    copy_tree(&root, Path::new(""), &dest, purpose, &mut out)?;
    Ok(out)
}

/// Writes a Gradescope autograder into `dest` (new or empty): its two
/// scripts, and the lab for grading (hidden cases in, solution out) as
/// `source/`, where Gradescope puts it.
pub fn gradescope(root: &Path, dest: &Path) -> Result<(), String> {
    copy_lab(root, &dest.join("source"), Purpose::Grading)?;
    for (name, text) in [
        ("setup.sh", include_str!("../gradescope/setup.sh")),
        (
            "run_autograder",
            include_str!("../gradescope/run_autograder"),
        ),
    ] {
        let path = dest.join(name);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
        make_executable(&path)?;
    }
    Ok(())
}

#[cfg(unix)]
fn make_executable(path: &Path) -> Result<(), String> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755))
        .map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(not(unix))]
fn make_executable(_: &Path) -> Result<(), String> {
    Ok(())
}
