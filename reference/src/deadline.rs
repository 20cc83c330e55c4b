//! `class --before DATE`: where submissions are git repositories (a
//! Classroom 50 or GitHub Actions course clones one per student), grade the
//! last commit made before the deadline, not whatever was pushed after.
//!
//! The repository is the student's: its `.git/config` and `.gitattributes`
//! are theirs too, and git runs commands they name (`core.fsmonitor` on
//! anything that reads the index, smudge filters on checkout and archive,
//! hooks). So nothing is checked out: the commit is found with `rev-list`,
//! its file list read with `ls-tree`, and each Rust file's bytes copied out
//! with `cat-file`, none of which touch the index, a filter or a hook; the
//! system and global configuration are left out, `core.fsmonitor` and
//! `core.hooksPath` are overridden anyway, and symbolic links in the tree
//! are skipped like links in any upload.

use std::path::{Component, Path, PathBuf};
use std::process::{Command, Stdio};

/// The commit graded for one repository.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Snapshot {
    /// Its full hash.
    pub commit: String,
    /// Its committer date, as git prints it in ISO 8601.
    pub date: String,
    /// Rust files copied out of it.
    pub files: usize,
}

/// Whether `dir` is a git repository's work tree (a `.git` folder in it).
pub fn is_repository(dir: &Path) -> bool {
    let git = dir.join(".git");
    git.is_dir() && !git.is_symlink()
}

/// git on `repo`'s database, with none of the configuration that could run
/// a program.
fn git(repo: &Path) -> Command {
    let mut cmd = Command::new("git");
    cmd.arg("--git-dir")
        .arg(repo.join(".git"))
        .args([
            "--no-pager",
            "-c",
            "core.fsmonitor=false",
            "-c",
            "core.hooksPath=/dev/null",
            "-c",
            "safe.directory=*",
        ])
        .env("GIT_CONFIG_NOSYSTEM", "1")
        .env("GIT_CONFIG_GLOBAL", "/dev/null")
        .env("GIT_TERMINAL_PROMPT", "0")
        .env_remove("GIT_DIR")
        .env_remove("GIT_WORK_TREE")
        .stdin(Stdio::null());
    cmd
}

fn output(mut cmd: Command, what: &str) -> Result<Vec<u8>, String> {
    let out = cmd
        .output()
        .map_err(|e| format!("cannot run git ({what}): {e}"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!("git {what} failed: {}", err.trim()));
    }
    Ok(out.stdout)
}

/// Writes what `cat` (a `git cat-file blob`) prints into `target`, to one
/// byte past the cap on a student's file
/// ([`autograde::upload::MAX_SOURCE_BYTES`]): a larger blob is then
/// refused by its size when it is read, as any file is, and costs neither
/// memory nor disk on the way.
fn copy_blob(mut cat: Command, target: &Path) -> Result<(), String> {
    use std::io::Read as _;
    let cap = autograde::upload::MAX_SOURCE_BYTES + 1;
    let mut child = cat
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run git (cat-file): {e}"))?;
    let mut file =
        std::fs::File::create(target).map_err(|e| format!("{}: {e}", target.display()))?;
    let mut stdout = child.stdout.take().expect("piped").take(cap);
    let copied = std::io::copy(&mut stdout, &mut file);
    drop(stdout);
    let whole = copied.as_ref().is_ok_and(|&n| n < cap);
    if !whole {
        let _ = child.kill();
    }
    let out = child
        .wait_with_output()
        .map_err(|e| format!("cannot run git (cat-file): {e}"))?;
    let copied = copied.map_err(|e| format!("{}: {e}", target.display()))?;
    if copied < cap && !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!("git cat-file failed: {}", err.trim()));
    }
    Ok(())
}

/// A tree path that stays inside the folder it is written to.
fn safe_relative(path: &str) -> Option<PathBuf> {
    let p = Path::new(path);
    p.components()
        .all(|c| matches!(c, Component::Normal(_)))
        .then(|| p.to_path_buf())
}

/// Copies the Rust files of `repo`'s last commit (on its checked-out
/// branch, `HEAD`) made before `before` into `into`, which must not exist
/// yet. `before` is anything `git rev-list --before` accepts (`2026-12-01
/// 23:59 +0100`); an error names the repository when it has no commit
/// before then.
pub fn snapshot_before(repo: &Path, before: &str, into: &Path) -> Result<Snapshot, String> {
    let mut find = git(repo);
    find.args(["rev-list", "-1", "--first-parent"])
        .arg(format!("--before={before}"))
        .arg("HEAD");
    let commit = String::from_utf8_lossy(&output(find, "rev-list")?)
        .trim()
        .to_string();
    if commit.is_empty() {
        return Err(format!(
            "{}: no commit before {before} (the repository's first commit is later)",
            repo.display()
        ));
    }
    let mut show = git(repo);
    show.args(["show", "-s", "--format=%cI"]).arg(&commit);
    let date = String::from_utf8_lossy(&output(show, "show")?)
        .trim()
        .to_string();
    let mut list = git(repo);
    list.args(["ls-tree", "-r", "-z", "--full-tree"])
        .arg(&commit);
    let listing = output(list, "ls-tree")?;
    std::fs::create_dir(into).map_err(|e| format!("{}: {e}", into.display()))?;
    let mut files = 0;
    for entry in listing.split(|&b| b == 0).filter(|e| !e.is_empty()) {
        // "<mode> <type> <hash>\t<path>"
        let entry = String::from_utf8_lossy(entry);
        let Some((meta, path)) = entry.split_once('\t') else {
            continue;
        };
        let mut meta = meta.split(' ');
        let (mode, kind, hash) = (meta.next(), meta.next(), meta.next());
        // Regular files only: 120000 is a link, 160000 a submodule.
        if kind != Some("blob") || !matches!(mode, Some("100644" | "100755")) {
            continue;
        }
        if !path.ends_with(".rs") {
            continue;
        }
        let Some(relative) = safe_relative(path) else {
            continue;
        };
        let target = into.join(&relative);
        if let Some(parent) = target.parent() {
            std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
        }
        let mut cat = git(repo);
        cat.args(["cat-file", "blob"]).arg(hash.unwrap_or_default());
        copy_blob(cat, &target)?;
        files += 1;
    }
    Ok(Snapshot {
        commit,
        date,
        files,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn have_git() -> bool {
        Command::new("git")
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    }

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("meshlab-deadline-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A git command in `dir` as a student would run it, at a fixed date.
    fn student_git(dir: &Path, date: &str, args: &[&str]) {
        let ok = Command::new("git")
            .args(args)
            .current_dir(dir)
            .env("GIT_CONFIG_NOSYSTEM", "1")
            .env("GIT_CONFIG_GLOBAL", "/dev/null")
            .env("GIT_AUTHOR_NAME", "s")
            .env("GIT_AUTHOR_EMAIL", "s@example.org")
            .env("GIT_COMMITTER_NAME", "s")
            .env("GIT_COMMITTER_EMAIL", "s@example.org")
            .env("GIT_AUTHOR_DATE", date)
            .env("GIT_COMMITTER_DATE", date)
            .output()
            .unwrap();
        assert!(ok.status.success(), "{args:?}: {ok:?}");
    }

    fn commit_lib(repo: &Path, text: &str, date: &str) {
        let lib = repo.join("crates/meshedit/src/lib.rs");
        std::fs::create_dir_all(lib.parent().unwrap()).unwrap();
        std::fs::write(&lib, text).unwrap();
        student_git(repo, date, &["add", "-A"]);
        student_git(repo, date, &["commit", "-q", "-m", "work"]);
    }

    #[test]
    fn the_last_commit_before_the_deadline_is_taken_and_nothing_runs() {
        if !have_git() {
            // git is on every machine this lab supports (it is how the lab is
            // cloned): a missing one is a broken machine, not a skip.
            panic!("git is needed for --before and is not on the PATH");
        }
        let root = scratch("before");
        let repo = root.join("alice");
        std::fs::create_dir_all(&repo).unwrap();
        student_git(&repo, "2026-11-01T10:00:00Z", &["init", "-q"]);
        commit_lib(&repo, "// on time\n", "2026-11-30T10:00:00Z");
        // A hostile repository: a filter and an fsmonitor that would write
        // a file if git ran them, and a link to a file outside.
        let marker = root.join("ran");
        let hook = format!("touch {}", marker.display());
        std::fs::write(repo.join(".gitattributes"), "*.rs filter=evil\n").unwrap();
        student_git(
            &repo,
            "2026-11-30T11:00:00Z",
            &["config", "filter.evil.smudge", &hook],
        );
        student_git(
            &repo,
            "2026-11-30T11:00:00Z",
            &["config", "core.fsmonitor", &hook],
        );
        std::os::unix::fs::symlink("/etc/passwd", repo.join("crates/meshedit/src/leak.rs"))
            .unwrap();
        student_git(&repo, "2026-11-30T12:00:00Z", &["add", "-A"]);
        student_git(
            &repo,
            "2026-11-30T12:00:00Z",
            &["commit", "-q", "-m", "attrs"],
        );
        commit_lib(&repo, "// late\n", "2026-12-02T09:00:00Z");
        // The student's own git commands above ran their fsmonitor.
        let _ = std::fs::remove_file(&marker);

        let into = root.join("graded");
        let snap = snapshot_before(&repo, "2026-12-01T23:59:00Z", &into).unwrap();
        assert!(snap.date.starts_with("2026-11-30T12:00:00"), "{snap:?}");
        let lib = std::fs::read_to_string(into.join("crates/meshedit/src/lib.rs")).unwrap();
        assert_eq!(lib, "// on time\n", "the late commit is not graded");
        assert_eq!(snap.files, 1, "the link is skipped: {snap:?}");
        assert!(!into.join("crates/meshedit/src/leak.rs").exists());
        assert!(
            !marker.exists(),
            "no filter or fsmonitor of the student's ran"
        );

        let early = snapshot_before(&repo, "2026-10-01", &root.join("early"));
        let err = early.unwrap_err();
        assert!(err.contains("no commit before 2026-10-01"), "{err}");
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn a_blob_past_the_cap_is_cut_one_byte_past_it_and_refused_when_read() {
        let root = scratch("large");
        let repo = root.join("mallory");
        std::fs::create_dir_all(&repo).unwrap();
        student_git(&repo, "2026-11-01T10:00:00Z", &["init", "-q"]);
        let cap = autograde::upload::MAX_SOURCE_BYTES as usize;
        commit_lib(&repo, &"x".repeat(3 * cap), "2026-11-30T10:00:00Z");
        let into = root.join("graded");
        snapshot_before(&repo, "2026-12-01", &into).unwrap();
        let lib = into.join("crates/meshedit/src/lib.rs");
        assert_eq!(std::fs::metadata(&lib).unwrap().len() as usize, cap + 1);
        let why = autograde::upload::take_lib_rs(&into).unwrap_err().message();
        assert!(
            why.starts_with("crates/meshedit/src/lib.rs is larger than 1 MiB"),
            "{why}"
        );
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn paths_leaving_the_folder_are_refused() {
        assert!(safe_relative("../x.rs").is_none());
        assert!(safe_relative("/etc/x.rs").is_none());
        assert_eq!(safe_relative("a/b.rs"), Some(PathBuf::from("a/b.rs")));
    }
}
