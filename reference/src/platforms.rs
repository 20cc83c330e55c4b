//! The bundles for the platforms beside Gradescope: Classroom 50 (an
//! `autograder.py`, the lab it grades with and the list of the lab's
//! files) and PrairieLearn (an external grader's entrypoint, the lab and
//! the fixtures). Both run the `autograde` program built from the bundle's
//! lab, outside any folder of the student's; neither holds the solution.

use std::path::Path;

use crate::handout::{self, Purpose};

const AUTOGRADER_PY: &str = include_str!("../platforms/autograder.py");
const RUN_SH: &str = include_str!("../platforms/run.sh");

fn write_executable(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755))
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

/// Pins the bundle's lab to the toolchain the TA runs (`rustc -V` here):
/// rustup reads `rust-toolchain.toml` wherever cargo runs in the lab, as
/// the Gradescope setup and the grading workflow install that version.
/// Returns the version.
fn pin_toolchain(root: &Path, lab: &Path) -> Result<String, String> {
    let version = handout::rust_version(root)?;
    let path = lab.join("rust-toolchain.toml");
    let text = format!(
        "# The toolchain this bundle was made and tested with: grading uses exactly\n\
         # this version (rustup installs it from this file).\n\
         [toolchain]\nchannel = \"{version}\"\n"
    );
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(version)
}

/// Classroom 50's per-assignment autograder folder (its files go to
/// `CLASSROOM/autograders/ASSIGNMENT/` in the config repository): the
/// script, `lab/` with the visible cases only, and `lab.sha256`, the lab's
/// files with their SHA-256: the script copies exactly those out of the
/// student's reach before building anything, so a file planted beside them
/// (the bundle unpacked inside a checkout) is never read. Classroom 50
/// publishes an autograder's files on GitHub Pages, so the hidden cases
/// stay out. Returns the toolchain version the lab is pinned to.
pub fn classroom50(root: &Path, dest: &Path) -> Result<String, String> {
    let lab = dest.join("lab");
    handout::copy_lab(root, &lab, Purpose::Grading)?;
    let version = pin_toolchain(root, &lab)?;
    let hidden = lab.join("fixtures/hidden");
    std::fs::remove_dir_all(&hidden).map_err(|e| format!("{}: {e}", hidden.display()))?;
    let mut files = Vec::new();
    list_files(&lab, "", &mut files)?;
    let mut manifest = String::new();
    for rel in files {
        let path = lab.join(&rel);
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        manifest.push_str(&format!("{}  {rel}\n", sha256::sha256_hex(&bytes)));
    }
    let list = dest.join("lab.sha256");
    std::fs::write(&list, manifest).map_err(|e| format!("{}: {e}", list.display()))?;
    write_executable(&dest.join("autograder.py"), AUTOGRADER_PY)?;
    Ok(version)
}

/// Every file under `dir/rel`, `/`-separated and sorted; a link or a name
/// that is not UTF-8 is refused (the lab has neither).
fn list_files(dir: &Path, rel: &str, out: &mut Vec<String>) -> Result<(), String> {
    let here = dir.join(rel);
    let mut entries: Vec<_> = std::fs::read_dir(&here)
        .map_err(|e| format!("{}: {e}", here.display()))?
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{}: {e}", here.display()))?;
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let name = entry.file_name();
        let name = name
            .to_str()
            .ok_or(format!("{}: a name that is not UTF-8", here.display()))?;
        let child = if rel.is_empty() {
            name.to_string()
        } else {
            format!("{rel}/{name}")
        };
        let kind = entry.file_type().map_err(|e| e.to_string())?;
        if kind.is_dir() {
            list_files(dir, &child, out)?;
        } else if kind.is_file() {
            out.push(child);
        } else {
            return Err(format!(
                "{}: not a file or a folder",
                dir.join(child).display()
            ));
        }
    }
    Ok(())
}

/// PrairieLearn's `serverFilesCourse/meshlab/`: `run.sh` (the question's
/// entrypoint), `lab/` (without the hidden cases, which the build may not
/// read) and `fixtures/` (every case, outside the lab).
pub fn prairielearn(root: &Path, dest: &Path) -> Result<String, String> {
    let lab = dest.join("lab");
    handout::copy_lab(root, &lab, Purpose::Grading)?;
    let version = pin_toolchain(root, &lab)?;
    let from = lab.join("fixtures");
    let to = dest.join("fixtures");
    std::fs::rename(&from, &to).map_err(|e| format!("{}: {e}", from.display()))?;
    // The grader finds the lab by its fixtures folder: the visible cases
    // stay in it too (the student has them anyway).
    autograde::copy_tree(&to.join("lab"), &from.join("lab"))?;
    write_executable(&dest.join("run.sh"), RUN_SH)?;
    Ok(version)
}
