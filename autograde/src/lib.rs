//! One autograder behind every platform: what grading one submission
//! takes, with no solution in it (it ships in the Gradescope bundle, never
//! to students). [`upload`] finds the student's `lib.rs` in any upload
//! layout; [`grade`] builds it locked in (the grader's build launcher) and
//! grades it one stage at a time within a budget; [`platform`] turns the
//! outcome into Gradescope's, Classroom 50's or PrairieLearn's result file;
//! [`clock`] reads and writes the instants those files and records hold;
//! [`process`] runs commands with deadlines and sweeps what a submission
//! left behind; [`setup`] readies a grading machine once (Gradescope's
//! setup, the build user's toolchain). `reference class` (the TAs' tool)
//! and the `autograde` program (Gradescope, Classroom 50, PrairieLearn)
//! both call it.

pub mod build;
pub mod clock;
pub mod grade;
pub mod gradescope;
pub mod local;
pub mod platform;
pub mod process;
pub mod setup;
pub mod upload;

use std::path::Path;

use grader::report::quoted::{self, Quoted};

/// A new temporary folder only this user may enter (0700), under a name
/// nobody can guess, removed when dropped. (`tempfile` alone makes it as
/// the umask says: 0755 by default.)
pub fn private_temp_dir(prefix: &str) -> Result<tempfile::TempDir, String> {
    use std::os::unix::fs::PermissionsExt;
    tempfile::Builder::new()
        .prefix(prefix)
        .permissions(std::fs::Permissions::from_mode(0o700))
        .tempdir()
        .map_err(|e| {
            format!(
                "cannot make a temporary folder in {}: {e}",
                std::env::temp_dir().display()
            )
        })
}

/// A new folder only this user may enter (it fails if the name is taken:
/// nobody else's folder or link is ever used).
pub fn private_dir(path: &Path) -> Result<(), String> {
    let mut builder = std::fs::DirBuilder::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::DirBuilderExt;
        builder.mode(0o700);
    }
    builder
        .create(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Copies the folder `from` into `to` (made if missing), files and folders.
pub fn copy_tree(from: &Path, to: &Path) -> Result<(), String> {
    std::fs::create_dir_all(to).map_err(|e| format!("{}: {e}", to.display()))?;
    for entry in std::fs::read_dir(from).map_err(|e| format!("{}: {e}", from.display()))? {
        let path = entry.map_err(|e| e.to_string())?.path();
        let target = to.join(path.file_name().expect("a name"));
        if path.is_dir() {
            copy_tree(&path, &target)?;
        } else {
            std::fs::copy(&path, &target).map_err(|e| format!("{}: {e}", path.display()))?;
        }
    }
    Ok(())
}

/// Text of the student's making (a compiler's errors quote their code, a
/// reason may name their files) as shown in results: its first line on
/// one line, the rest under `| `, control characters escaped.
pub fn shown(why: &str) -> String {
    match why.split_once('\n') {
        Some((head, rest)) => format!(
            "{}\n{}",
            quoted::one_line(head),
            Quoted::new(rest.trim_start_matches('\n')).block("")
        ),
        None => quoted::one_line(why),
    }
}

/// "Your code does not compile: ...", with the compiler's words quoted as
/// student text, for a failed build (`limit`: the limit it hit, if any).
pub fn does_not_compile(limit: Option<&str>, compiler: &str) -> String {
    let head = match limit {
        Some(limit) => format!("Your code does not compile: {limit}."),
        None => "Your code does not compile:".to_string(),
    };
    if compiler.trim().is_empty() {
        head
    } else {
        format!("{head}\n\n{}", Quoted::new(compiler).block(""))
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_compiler_s_words_are_quoted_and_cannot_forge_a_line() {
        let text = super::does_not_compile(None, "error: x\nall tests passed\u{1b}[2J");
        assert!(
            text.starts_with("Your code does not compile:\n\n"),
            "{text}"
        );
        assert!(
            text.contains("| error: x\n| all tests passed\\u{1b}[2J"),
            "{text}"
        );
        assert!(
            !text.lines().any(|l| l.starts_with("all tests passed")),
            "{text}"
        );
    }
}
