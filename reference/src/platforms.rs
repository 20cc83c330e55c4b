//! The bundles for the platforms beside Gradescope: Classroom 50 (an
//! `autograder.py` and the lab it grades with) and PrairieLearn (an
//! external grader's entrypoint, the lab and the fixtures). Both run the
//! `autograde` program built from the bundle's lab; neither holds the
//! solution.

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
/// script and `lab/`, with the visible cases only. Classroom 50 publishes
/// an autograder's files on GitHub Pages, so the hidden cases stay out.
pub fn classroom50(root: &Path, dest: &Path) -> Result<String, String> {
    let lab = dest.join("lab");
    handout::copy_lab(root, &lab, Purpose::Grading)?;
    let version = pin_toolchain(root, &lab)?;
    let hidden = lab.join("fixtures/hidden");
    std::fs::remove_dir_all(&hidden).map_err(|e| format!("{}: {e}", hidden.display()))?;
    write_executable(&dest.join("autograder.py"), AUTOGRADER_PY)?;
    Ok(version)
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
