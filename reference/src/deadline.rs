//! `class --before DATE`: where submissions are git repositories (a
//! Classroom 50 or GitHub Actions course clones one per student), grade
//! what each student had handed in by the deadline, not whatever was pushed
//! after.
//!
//! When it was handed in comes from a clock the student does not hold
//! where the TA has one ([`read_records`], `--pushes`): GitHub's record of
//! the pushes (its events or activity API, one JSON file per student), a
//! CSV of pushes the TA made from any platform's log, or Classroom 50's
//! `scores.json` (when its runner graded each submission). The commit
//! graded is the one the last push before the deadline left at the head of
//! the repository's branch. Without a record, the last commit (first
//! parents from `HEAD`) whose committer date is before the deadline is
//! graded, and [`Clock::CommitDate`] says that date is the student's own: a
//! commit made after the deadline can carry any date.
//!
//! The repository is the student's, and so is its `.git/config`: git
//! starts programs it names (`gpg.program` when `log.showSignature` shows
//! a signature, pagers, filters, `core.fsmonitor`, hooks, diff and merge
//! drivers), and reads files it names (`include.path`, alternates,
//! `commondir`). So git never opens the student's git folder as a
//! repository: it runs on an empty one of ours, with no system or global
//! configuration and with the student's object database as its objects
//! (`GIT_OBJECT_DIRECTORY`), on commits this module resolved from the
//! student's `HEAD` and ref files itself. Only plumbing reads objects
//! (`rev-list`, `ls-tree`, `cat-file`): nothing is checked out, so no
//! filter or attribute applies. A repository whose objects are borrowed
//! from elsewhere (alternates) or whose object folder is a link is refused,
//! and symbolic links in the tree are skipped like links in any upload.

use std::path::{Component, Path, PathBuf};
use std::process::{Command, Stdio};

use autograde::clock::{iso8601, parse_instant};

/// Where the time a repository's graded commit was handed in comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clock {
    /// A record of the pushes (GitHub's events or activity, or the TA's
    /// CSV): when the platform received the commit.
    Pushes,
    /// Classroom 50's `scores.json`: when its runner graded the submission
    /// (`graded_at`, a minute or more after the push).
    Classroom50,
    /// The commit's committer date, which the student sets.
    CommitDate,
}

impl Clock {
    /// Its name in `commits.csv` and the summary.
    pub fn label(self) -> &'static str {
        match self {
            Clock::Pushes => "push log",
            Clock::Classroom50 => "Classroom 50 graded_at",
            Clock::CommitDate => "commit date (the student's own)",
        }
    }

    /// Whether the student could have set it.
    pub fn is_students(self) -> bool {
        self == Clock::CommitDate
    }

    fn from_label(label: &str) -> Option<Clock> {
        [Clock::Pushes, Clock::Classroom50, Clock::CommitDate]
            .into_iter()
            .find(|c| c.label() == label)
    }
}

/// What the TA reads beside a row judged by commit dates.
pub const COMMIT_DATE_WARNING: &str = "judged by commit dates, which the student sets: a \
     commit made after the deadline can carry an earlier date (give --pushes with a record of \
     the pushes to judge by a clock the student does not hold)";

/// The commit graded for one repository.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Snapshot {
    /// Its full hash.
    pub commit: String,
    /// When it was handed in, by `clock` (UTC ISO 8601).
    pub date: String,
    pub clock: Clock,
    /// Its committer date (UTC ISO 8601), whatever the clock.
    pub committer_date: String,
    /// Rust files copied out of it.
    pub files: usize,
}

/// A row's commit and when it was handed in (the summary's columns).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HandedIn {
    pub commit: String,
    pub at: String,
    pub clock: Clock,
}

impl HandedIn {
    pub fn to_json(&self) -> serde_json::Value {
        let mut v = serde_json::json!({
            "commit": self.commit, "at": self.at, "clock": self.clock.label(),
        });
        if self.clock.is_students() {
            v["warning"] = COMMIT_DATE_WARNING.into();
        }
        v
    }

    pub fn from_json(v: &serde_json::Value) -> Option<HandedIn> {
        Some(HandedIn {
            commit: v["commit"].as_str()?.to_string(),
            at: v["at"].as_str()?.to_string(),
            clock: Clock::from_label(v["clock"].as_str()?)?,
        })
    }
}

/// Whether `dir` is a git repository's work tree (a `.git` folder in it).
pub fn is_repository(dir: &Path) -> bool {
    let git = dir.join(".git");
    git.is_dir() && !git.is_symlink()
}

/// The deadline as Unix seconds: a date and time with its zone
/// (`2026-12-01 23:59 +0100`, `2026-12-01T22:59:00Z`).
pub fn parse_deadline(text: &str) -> Result<i64, String> {
    parse_instant(text).ok_or(format!(
        "--before {text:?}: give the deadline as a date and time with its zone, e.g. \
         \"2026-12-01 23:59 +0100\" or \"2026-12-01T22:59:00Z\" (without a zone it would be a \
         different instant on each machine)"
    ))
}

/// One push (or graded submission) a platform recorded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Record {
    /// The commit at the branch's head after it (full hash, lower case).
    pub commit: String,
    /// When (Unix seconds, the platform's clock).
    pub at: i64,
    /// The branch pushed to, when the record says (`main`).
    pub branch: Option<String>,
}

/// Every record of a `--pushes` file or folder, by the names of the
/// submissions they belong to.
#[derive(Clone, Debug)]
pub struct Records {
    pub clock: Clock,
    /// The names (lower case) a record may be filed under, and the record.
    entries: Vec<(Vec<String>, Record)>,
}

impl Records {
    /// The records of the submission named `name` (case ignored).
    pub fn of(&self, name: &str) -> Vec<&Record> {
        let name = name.to_lowercase();
        self.entries
            .iter()
            .filter(|(names, _)| names.contains(&name))
            .map(|(_, r)| r)
            .collect()
    }

    /// How many records there are.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

/// A full object name (SHA-1 or SHA-256), lower case: a prefix could be
/// matched by a commit made to match it.
fn object_name(text: &str) -> Option<String> {
    let t = text.trim().to_ascii_lowercase();
    (matches!(t.len(), 40 | 64) && t.bytes().all(|b| b.is_ascii_hexdigit())).then_some(t)
}

fn branch_of(git_ref: &str) -> Option<String> {
    git_ref.strip_prefix("refs/heads/").map(str::to_string)
}

/// Reads `--pushes`: a CSV file (`student,commit,pushed_at`, optionally
/// `branch`), Classroom 50's `scores.json`, or a folder of `NAME.json`, the
/// JSON GitHub's API gives for the repository of submission NAME (its
/// events, `repos/OWNER/REPO/events`, or its activity,
/// `repos/OWNER/REPO/activity`; several pages one after the other as `gh
/// api --paginate` writes them). An error names the file and what in it is
/// wrong.
pub fn read_records(path: &Path) -> Result<Records, String> {
    if path.is_dir() {
        return read_github_folder(path);
    }
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if text.trim_start().starts_with('{') {
        read_classroom50(path, &text)
    } else {
        read_csv(path, &text)
    }
}

fn read_csv(path: &Path, text: &str) -> Result<Records, String> {
    let rows = crate::roster::parse_csv(text).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut rows = rows.into_iter().enumerate();
    let (_, header) = rows.next().ok_or(format!(
        "{}: empty (a header row is needed)",
        path.display()
    ))?;
    let column = |name: &str| {
        header
            .iter()
            .position(|h| h.trim().eq_ignore_ascii_case(name))
    };
    let need = |name: &str| {
        column(name).ok_or(format!(
            "{}: no {name} column (the header needs student, commit and pushed_at)",
            path.display()
        ))
    };
    let (student, commit, pushed) = (need("student")?, need("commit")?, need("pushed_at")?);
    let branch = column("branch");
    let mut entries = Vec::new();
    for (i, row) in rows {
        let line = i + 1;
        if row.iter().all(|f| f.trim().is_empty()) {
            continue;
        }
        let field = |k: usize| row.get(k).map(|f| f.trim()).unwrap_or("");
        // Rows counted as a spreadsheet shows them, the header first.
        let at = |what: &str| format!("{} row {line}: {what}", path.display());
        let name = field(student);
        if name.is_empty() {
            return Err(at("no student"));
        }
        let hash = object_name(field(commit)).ok_or(at(&format!(
            "commit {:?} is not a full commit hash (40 or 64 hexadecimal digits)",
            field(commit)
        )))?;
        let when = parse_instant(field(pushed)).ok_or(at(&format!(
            "pushed_at {:?} is not a date and time with its zone (2026-12-01T22:59:00Z)",
            field(pushed)
        )))?;
        let branch = branch
            .map(field)
            .filter(|b| !b.is_empty())
            .map(|b| branch_of(b).unwrap_or(b.to_string()));
        entries.push((
            vec![name.to_lowercase()],
            Record {
                commit: hash,
                at: when,
                branch,
            },
        ));
    }
    Ok(Records {
        clock: Clock::Pushes,
        entries,
    })
}

/// GitHub's records of one repository: PushEvents of its events API,
/// pushes of its activity API; other kinds are left out.
fn github_records(path: &Path, text: &str) -> Result<Vec<Record>, String> {
    let mut items = Vec::new();
    for value in serde_json::Deserializer::from_str(text).into_iter::<serde_json::Value>() {
        let value = value.map_err(|e| format!("{}: not JSON: {e}", path.display()))?;
        match value {
            serde_json::Value::Array(list) => {
                for item in list {
                    // `gh api --paginate --slurp`: a list of pages.
                    match item {
                        serde_json::Value::Array(page) => items.extend(page),
                        other => items.push(other),
                    }
                }
            }
            other => {
                let said = other["message"].as_str().unwrap_or("no list");
                return Err(format!(
                    "{}: not GitHub's list of events or activity (GitHub said: {said})",
                    path.display()
                ));
            }
        }
    }
    let mut out = Vec::new();
    for (i, item) in items.iter().enumerate() {
        let bad = |what: &str| format!("{} item {}: {what}", path.display(), i + 1);
        // (commit, time, ref) by the API's names.
        let fields = if item["type"] == "PushEvent" {
            Some((
                &item["payload"]["head"],
                &item["created_at"],
                &item["payload"]["ref"],
            ))
        } else if let Some(kind) = item["activity_type"].as_str() {
            (kind != "branch_deletion").then_some((
                &item["after"],
                &item["timestamp"],
                &item["ref"],
            ))
        } else {
            None
        };
        let Some((head, when, git_ref)) = fields else {
            continue;
        };
        let commit = head
            .as_str()
            .and_then(object_name)
            .ok_or(bad(&format!("{head} is not a full commit hash")))?;
        if commit.bytes().all(|b| b == b'0') {
            continue;
        }
        let at = when
            .as_str()
            .and_then(parse_instant)
            .ok_or(bad(&format!("{when} is not a date and time")))?;
        out.push(Record {
            commit,
            at,
            branch: git_ref.as_str().and_then(branch_of),
        });
    }
    Ok(out)
}

fn read_github_folder(dir: &Path) -> Result<Records, String> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    paths.sort();
    let mut entries = Vec::new();
    for path in paths {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        if name.starts_with('.') {
            continue;
        }
        let Some(stem) = name.strip_suffix(".json") else {
            return Err(format!(
                "{}: the --pushes folder holds one NAME.json per submission (GitHub's events \
                 or activity of its repository), nothing else",
                path.display()
            ));
        };
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        for record in github_records(&path, &text)? {
            entries.push((vec![stem.to_lowercase()], record));
        }
    }
    Ok(Records {
        clock: Clock::Pushes,
        entries,
    })
}

/// Classroom 50's `scores.json` (`classroom50/scores/v1`): each
/// submission's commit (from its runner) and `graded_at` (the runner's
/// clock when it graded). A submission is filed under its repository's
/// name, `CLASSROOM-ASSIGNMENT-OWNER`, and under `OWNER` too when the file
/// holds one assignment.
fn read_classroom50(path: &Path, text: &str) -> Result<Records, String> {
    let v: serde_json::Value =
        serde_json::from_str(text).map_err(|e| format!("{}: not JSON: {e}", path.display()))?;
    if v["schema"] != "classroom50/scores/v1" {
        return Err(format!(
            "{}: not Classroom 50's scores.json (schema classroom50/scores/v1); GitHub's events \
             go in a folder, one NAME.json per submission, and a push log in a CSV file",
            path.display()
        ));
    }
    let assignments = v["assignments"]
        .as_object()
        .ok_or(format!("{}: no assignments", path.display()))?;
    let mut entries = Vec::new();
    for (slug, bucket) in assignments {
        for entry in bucket["entries"].as_array().into_iter().flatten() {
            let Some(owner) = entry["owner"].as_str() else {
                continue;
            };
            for sub in entry["submissions"].as_array().into_iter().flatten() {
                // Results written before the runner stamped graded_at.
                let Some(at) = sub["graded_at"].as_str().and_then(parse_instant) else {
                    continue;
                };
                let Some(commit) = sub["commit"]
                    .as_str()
                    .and_then(|url| url.rsplit('/').next())
                    .and_then(object_name)
                else {
                    continue;
                };
                let classroom = sub["classroom"].as_str().unwrap_or_default();
                let mut names = vec![format!("{classroom}-{slug}-{owner}").to_lowercase()];
                if assignments.len() == 1 {
                    names.push(owner.to_lowercase());
                }
                entries.push((
                    names,
                    Record {
                        commit,
                        at,
                        branch: None,
                    },
                ));
            }
        }
    }
    Ok(Records {
        clock: Clock::Classroom50,
        entries,
    })
}

/// A student's file of at most `cap` bytes, read as every student file is
/// (`autograde::upload::read_capped`: a regular file, never through a
/// link, never blocking, so a FIFO planted as `HEAD` is refused, not read).
fn read_small(path: &Path, cap: u64) -> Result<Vec<u8>, String> {
    use autograde::upload::Unfit;
    autograde::upload::read_capped(path, cap).map_err(|why| match why {
        Unfit::NotRegular(kind) => format!(
            "{} is not a regular file ({})",
            path.display(),
            kind.words()
        ),
        Unfit::TooLarge(bytes) => format!("{} is over {cap} bytes ({bytes})", path.display()),
        Unfit::Unreadable(e) => format!("{}: {e}", path.display()),
    })
}

/// `git/rel`, when every folder on the way is a folder (not a link).
fn inside(git: &Path, rel: &str) -> Option<PathBuf> {
    let relative = safe_relative(rel)?;
    let mut here = git.to_path_buf();
    let mut parts = relative.components().peekable();
    while let Some(part) = parts.next() {
        here.push(part);
        if parts.peek().is_some() {
            let meta = std::fs::symlink_metadata(&here).ok()?;
            if !meta.is_dir() {
                return None;
            }
        }
    }
    Some(here)
}

/// A student's repository, read through an empty git folder of ours.
struct Repository {
    /// The repository the TA named (for messages).
    shown: PathBuf,
    /// Ours: no configuration but what this module writes.
    own: tempfile::TempDir,
    /// The student's object database.
    objects: PathBuf,
    /// How long one git command may take ([`GIT_LIMIT`]).
    limit: std::time::Duration,
    /// The commit `HEAD` names, and its branch (`main`) if it names one.
    head: String,
    branch: Option<String>,
}

const REF_FILE_CAP: u64 = 4096;
const PACKED_REFS_CAP: u64 = 64 << 20;
/// A Rust file of the lab is a few hundred kilobytes at most.
const BLOB_CAP: u64 = 16 << 20;

/// How long one git command may take: reading a commit, a tree or a blob
/// takes milliseconds.
const GIT_LIMIT: std::time::Duration = std::time::Duration::from_secs(60);

/// Most of what one git command's output is read (a tree's listing).
const GIT_OUTPUT_CAP: u64 = 64 << 20;

impl Repository {
    fn open(repo: &Path) -> Result<Repository, String> {
        let shown = repo.to_path_buf();
        let refuse = |why: String| format!("{}: {why}", shown.display());
        let git = repo.join(".git");
        if !is_repository(repo) {
            return Err(refuse("no .git folder".into()));
        }
        let objects = git.join("objects");
        let meta = std::fs::symlink_metadata(&objects)
            .map_err(|e| refuse(format!(".git/objects: {e}")))?;
        if !meta.is_dir() {
            return Err(refuse(
                ".git/objects is not a folder of the repository (a link?)".into(),
            ));
        }
        for borrowed in ["info/alternates", "info/http-alternates"] {
            if std::fs::symlink_metadata(objects.join(borrowed)).is_ok() {
                return Err(refuse(format!(
                    "the repository borrows objects from elsewhere (.git/objects/{borrowed}): \
                     clone it again without --shared or --reference"
                )));
            }
        }
        if git.join("reftable").exists() {
            return Err(refuse(
                "its refs are in git's reftable format, which --before does not read: clone it \
                 with the default ref format"
                    .into(),
            ));
        }
        let (head, branch) = resolve_head(&git).map_err(refuse)?;
        let own = tempfile::Builder::new()
            .prefix("meshlab-git-")
            .tempdir()
            .map_err(|e| format!("cannot make a temporary folder: {e}"))?;
        let config = if head.len() == 64 {
            "[core]\n\trepositoryformatversion = 1\n\tbare = true\n[extensions]\n\tobjectFormat = sha256\n"
        } else {
            "[core]\n\trepositoryformatversion = 0\n\tbare = true\n"
        };
        let write = |rel: &str, text: &str| {
            let path = own.path().join(rel);
            std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
        };
        for dir in ["objects", "refs"] {
            std::fs::create_dir(own.path().join(dir)).map_err(|e| e.to_string())?;
        }
        write("HEAD", "ref: refs/heads/meshlab-none\n")?;
        write("config", config)?;
        // A shallow clone's boundary, checked to be object names only.
        if let Ok(bytes) = read_small(&git.join("shallow"), PACKED_REFS_CAP) {
            let text = String::from_utf8_lossy(&bytes);
            let names: Option<Vec<String>> = text.lines().map(object_name).collect();
            if let Some(names) = names {
                write("shallow", &(names.join("\n") + "\n"))?;
            }
        }
        Ok(Repository {
            shown,
            own,
            objects,
            limit: GIT_LIMIT,
            head,
            branch,
        })
    }

    /// git on our folder, the student's objects as its objects, nothing
    /// of the caller's environment but `PATH`.
    fn git(&self) -> Command {
        let mut cmd = Command::new("git");
        cmd.env_clear()
            .env(
                "PATH",
                std::env::var_os("PATH").unwrap_or_else(|| "/usr/bin:/bin".into()),
            )
            .env("LC_ALL", "C")
            .env("HOME", self.own.path())
            .env("GIT_CONFIG_NOSYSTEM", "1")
            .env("GIT_CONFIG_GLOBAL", "/dev/null")
            .env("GIT_OBJECT_DIRECTORY", &self.objects)
            .env("GIT_NO_REPLACE_OBJECTS", "1")
            .env("GIT_TERMINAL_PROMPT", "0")
            .arg("--git-dir")
            .arg(self.own.path())
            // None of these can be set where git looks (it reads no file of
            // the student's); named anyway, so no later change of git's
            // defaults starts a program.
            .args([
                "--no-pager",
                "-c",
                "core.fsmonitor=false",
                "-c",
                "core.hooksPath=/dev/null",
                "-c",
                "log.showSignature=false",
                "-c",
                "gpg.program=/dev/null/none",
                "-c",
                "core.pager=cat",
            ])
            .stdin(Stdio::null());
        cmd
    }

    /// Runs git with `args`, what it prints into the file `stdout`, within
    /// [`GIT_LIMIT`] (a named pipe planted among the objects would block
    /// it for ever); `what` names the command in an error.
    fn run_into(&self, args: &[&str], what: &str, stdout: &Path) -> Result<(), String> {
        let mut cmd = self.git();
        cmd.args(args);
        let stderr = self.own.path().join("git-stderr");
        let ended = autograde::process::run_limited(cmd, stdout, &stderr, self.limit)?;
        match ended {
            Some(0) => Ok(()),
            Some(_) => {
                let err = std::fs::read(&stderr).unwrap_or_default();
                let err = String::from_utf8_lossy(&err[..err.len().min(4096)]).into_owned();
                Err(format!(
                    "{}: git {what} failed: {}",
                    self.shown.display(),
                    grader::report::quoted::one_line(err.trim())
                ))
            }
            None => Err(format!(
                "{}: git {what} did not finish within {} s: is one of its objects a named pipe \
                 or a device?",
                self.shown.display(),
                self.limit.as_secs_f64()
            )),
        }
    }

    /// What git prints for `args` (at most [`GIT_OUTPUT_CAP`] of it).
    fn output(&self, args: &[&str], what: &str) -> Result<Vec<u8>, String> {
        use std::io::Read as _;
        let path = self.own.path().join("git-stdout");
        self.run_into(args, what, &path)?;
        let mut bytes = Vec::new();
        std::fs::File::open(&path)
            .and_then(|f| f.take(GIT_OUTPUT_CAP).read_to_end(&mut bytes))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(bytes)
    }

    /// Whether `name` is a commit of the student's objects.
    fn has_commit(&self, name: &str) -> bool {
        self.output(&["cat-file", "-t", name], "cat-file")
            .is_ok_and(|out| out == b"commit\n")
    }

    /// Writes the blob `hash` into `target`, cut to one byte past the cap
    /// on a student's file ([`autograde::upload::MAX_SOURCE_BYTES`]): a
    /// larger blob (at most [`BLOB_CAP`], checked from the tree first) is
    /// then refused by its size when it is read, as any file is.
    fn copy_blob(&self, hash: &str, target: &Path) -> Result<(), String> {
        self.run_into(&["cat-file", "blob", hash], "cat-file", target)?;
        let cap = autograde::upload::MAX_SOURCE_BYTES + 1;
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(target)
            .map_err(|e| format!("{}: {e}", target.display()))?;
        let len = file.metadata().map_or(0, |m| m.len());
        if len > cap {
            file.set_len(cap)
                .map_err(|e| format!("{}: {e}", target.display()))?;
        }
        Ok(())
    }

    /// The committer date of `commit`, UTC ISO 8601, read from the object.
    fn committer_date(&self, commit: &str) -> Result<String, String> {
        let raw = self.output(&["cat-file", "commit", commit], "cat-file")?;
        let text = String::from_utf8_lossy(&raw);
        text.lines()
            .take_while(|l| !l.is_empty())
            .find_map(|l| l.strip_prefix("committer "))
            .and_then(|l| {
                let mut words = l.rsplit(' ');
                let _zone = words.next()?;
                words.next()?.parse::<i64>().ok()
            })
            .map(iso8601)
            .ok_or(format!(
                "{}: commit {commit} has no committer date",
                self.shown.display()
            ))
    }
}

/// The commit `HEAD` names (through its branch, loose or packed) and the
/// branch, read from the files themselves.
fn resolve_head(git: &Path) -> Result<(String, Option<String>), String> {
    let head = read_small(&git.join("HEAD"), REF_FILE_CAP)?;
    let mut text = String::from_utf8_lossy(&head).trim().to_string();
    let mut branch = None;
    for _ in 0..5 {
        if let Some(name) = object_name(&text) {
            return Ok((name, branch));
        }
        let Some(target) = text.strip_prefix("ref:").map(str::trim) else {
            return Err("HEAD names no commit and no branch".into());
        };
        if !target.starts_with("refs/") {
            return Err(format!("HEAD names {target:?}, which is not a ref"));
        }
        if branch.is_none() {
            branch = branch_of(target);
        }
        let loose = inside(git, target).ok_or(format!("the ref {target:?} is not a plain name"))?;
        text = match read_small(&loose, REF_FILE_CAP) {
            Ok(bytes) => String::from_utf8_lossy(&bytes).trim().to_string(),
            Err(_) if !loose.exists() && !loose.is_symlink() => packed_ref(git, target)?.ok_or(
                format!("HEAD names {target}, which has no commit (an empty repository?)"),
            )?,
            Err(e) => return Err(e),
        };
    }
    Err("HEAD's refs name each other in a loop".into())
}

/// `name`'s commit in `packed-refs`, if it is there.
fn packed_ref(git: &Path, name: &str) -> Result<Option<String>, String> {
    let path = git.join("packed-refs");
    if !path.exists() && !path.is_symlink() {
        return Ok(None);
    }
    let bytes = read_small(&path, PACKED_REFS_CAP)?;
    Ok(String::from_utf8_lossy(&bytes).lines().find_map(|l| {
        let (hash, r) = l.split_once(' ')?;
        (r.trim() == name).then(|| object_name(hash)).flatten()
    }))
}

/// A tree path that stays inside the folder it is written to.
fn safe_relative(path: &str) -> Option<PathBuf> {
    let p = Path::new(path);
    (!path.is_empty() && p.components().all(|c| matches!(c, Component::Normal(_))))
        .then(|| p.to_path_buf())
}

/// The record the deadline grades: the last push (by its time) at or
/// before `deadline`, to the repository's branch where both say which.
fn last_on_time<'a>(
    records: &[&'a Record],
    deadline: i64,
    branch: Option<&str>,
    clock: Clock,
) -> Result<&'a Record, String> {
    let ours: Vec<&Record> = records
        .iter()
        .copied()
        .filter(|r| match (&r.branch, branch) {
            (Some(pushed), Some(head)) => pushed == head,
            _ => true,
        })
        .collect();
    let on_time = ours
        .iter()
        .copied()
        .filter(|r| r.at <= deadline)
        .max_by_key(|r| r.at);
    match on_time {
        Some(r) => Ok(r),
        None => {
            let to = branch.map_or(String::new(), |b| format!(" to {b}"));
            Err(match ours.iter().map(|r| r.at).min() {
                Some(first) => format!(
                    "no push{to} by the deadline in the {} (the first is at {})",
                    clock.label(),
                    iso8601(first)
                ),
                None => format!("no push{to} in the {} for this repository", clock.label()),
            })
        }
    }
}

/// Copies the Rust files of what `repo` had handed in by `deadline` (Unix
/// seconds) into `into`, which must not exist yet: the commit of the last
/// of `records` at or before it, or, with no records, the last commit
/// before it by committer date on `HEAD`'s first parents. An error names
/// the repository and why nothing can be graded (no commit by then, the
/// commit pushed is not in this clone, a repository this module will not
/// read).
pub fn snapshot(
    repo: &Path,
    deadline: i64,
    records: Option<(&[&Record], Clock)>,
    into: &Path,
) -> Result<Snapshot, String> {
    snapshot_with(Repository::open(repo)?, repo, deadline, records, into)
}

fn snapshot_with(
    r: Repository,
    repo: &Path,
    deadline: i64,
    records: Option<(&[&Record], Clock)>,
    into: &Path,
) -> Result<Snapshot, String> {
    let (commit, date, clock) = match records {
        Some((records, clock)) => {
            let pushed = last_on_time(records, deadline, r.branch.as_deref(), clock)
                .map_err(|e| format!("{}: {e}", repo.display()))?;
            if !r.has_commit(&pushed.commit) {
                return Err(format!(
                    "{}: commit {}, pushed at {} (the {}), is not in this clone (force-pushed \
                     away?): fetch it (git -C {} fetch origin {}) and grade again",
                    repo.display(),
                    pushed.commit,
                    iso8601(pushed.at),
                    clock.label(),
                    repo.display(),
                    pushed.commit
                ));
            }
            (pushed.commit.clone(), iso8601(pushed.at), clock)
        }
        None => {
            let found = r.output(
                &[
                    "rev-list",
                    "-1",
                    "--first-parent",
                    &format!("--min-age={deadline}"),
                    &r.head,
                ],
                "rev-list",
            )?;
            let commit = String::from_utf8_lossy(&found).trim().to_string();
            if commit.is_empty() {
                return Err(format!(
                    "{}: no commit before {} (the repository's first commit is later)",
                    repo.display(),
                    iso8601(deadline)
                ));
            }
            let date = r.committer_date(&commit)?;
            (commit, date, Clock::CommitDate)
        }
    };
    let committer_date = r.committer_date(&commit)?;
    let listing = r.output(
        &["ls-tree", "-r", "-z", "-l", "--full-tree", &commit],
        "ls-tree",
    )?;
    std::fs::create_dir(into).map_err(|e| format!("{}: {e}", into.display()))?;
    let mut files = 0;
    for entry in listing.split(|&b| b == 0).filter(|e| !e.is_empty()) {
        // "<mode> <type> <hash> <size>\t<path>"
        let entry = String::from_utf8_lossy(entry);
        let Some((meta, path)) = entry.split_once('\t') else {
            continue;
        };
        let mut meta = meta.split_whitespace();
        let (mode, kind, hash, size) = (meta.next(), meta.next(), meta.next(), meta.next());
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
        let Some(hash) = hash.and_then(object_name) else {
            continue;
        };
        let size: u64 = size.and_then(|s| s.parse().ok()).unwrap_or(u64::MAX);
        if size > BLOB_CAP {
            return Err(format!(
                "{}: {path} in commit {commit} is {size} bytes, over the {BLOB_CAP} a Rust file \
                 of this lab may have",
                repo.display()
            ));
        }
        let target = into.join(&relative);
        if let Some(parent) = target.parent() {
            std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
        }
        r.copy_blob(&hash, &target)?;
        files += 1;
    }
    Ok(Snapshot {
        commit,
        date,
        clock,
        committer_date,
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

    fn need_git() {
        if !have_git() {
            // git is on every machine this lab supports (it is how the lab is
            // cloned): a missing one is a broken machine, not a skip.
            panic!("git is needed for --before and is not on the PATH");
        }
    }

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("meshlab-deadline-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A git command in `dir` as a student would run it, at a fixed date.
    fn student_git(dir: &Path, date: &str, args: &[&str]) -> String {
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
            .stdin(Stdio::null())
            .output()
            .unwrap();
        assert!(ok.status.success(), "{args:?}: {ok:?}");
        String::from_utf8_lossy(&ok.stdout).trim().to_string()
    }

    fn commit_lib(repo: &Path, text: &str, date: &str) -> String {
        let lib = repo.join("crates/meshedit/src/lib.rs");
        std::fs::create_dir_all(lib.parent().unwrap()).unwrap();
        std::fs::write(&lib, text).unwrap();
        student_git(repo, date, &["add", "-A"]);
        student_git(repo, date, &["commit", "-q", "-m", "work"]);
        student_git(repo, date, &["rev-parse", "HEAD"])
    }

    fn at(text: &str) -> i64 {
        parse_instant(text).unwrap()
    }

    fn graded_lib(into: &Path) -> String {
        std::fs::read_to_string(into.join("crates/meshedit/src/lib.rs")).unwrap()
    }

    #[test]
    fn the_last_commit_before_the_deadline_is_taken_and_nothing_runs() {
        need_git();
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
        let snap = snapshot(&repo, at("2026-12-01T23:59:00Z"), None, &into).unwrap();
        assert_eq!(snap.date, "2026-11-30T12:00:00Z", "{snap:?}");
        assert_eq!(snap.clock, Clock::CommitDate);
        assert_eq!(
            graded_lib(&into),
            "// on time\n",
            "the late commit is not graded"
        );
        assert_eq!(snap.files, 1, "the link is skipped: {snap:?}");
        assert!(!into.join("crates/meshedit/src/leak.rs").exists());
        assert!(
            !marker.exists(),
            "no filter or fsmonitor of the student's ran"
        );

        let early = snapshot(&repo, at("2026-10-01T00:00:00Z"), None, &root.join("early"));
        let err = early.unwrap_err();
        assert!(
            err.contains("no commit before 2026-10-01T00:00:00Z"),
            "{err}"
        );
        let _ = std::fs::remove_dir_all(&root);
    }

    /// A program for a setting: it leaves `ran-NAME` if anything runs it.
    fn plant(root: &Path, name: &str) -> String {
        use std::os::unix::fs::PermissionsExt;
        let program = root.join(format!("prog-{name}"));
        std::fs::write(
            &program,
            format!(
                "#!/bin/sh\ntouch {}\ncat >/dev/null 2>&1\nexit 0\n",
                root.join(format!("ran-{name}")).display()
            ),
        )
        .unwrap();
        std::fs::set_permissions(&program, std::fs::Permissions::from_mode(0o755)).unwrap();
        program.display().to_string()
    }

    fn ran(root: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(root)
            .unwrap()
            .filter_map(|e| {
                let name = e.ok()?.file_name().to_string_lossy().into_owned();
                name.strip_prefix("ran-").map(str::to_string)
            })
            .collect();
        names.sort();
        names
    }

    fn clear_ran(root: &Path) {
        for name in ran(root) {
            std::fs::remove_file(root.join(format!("ran-{name}"))).unwrap();
        }
    }

    /// Every setting of a repository's configuration that makes git start a
    /// program (or read a file it names), planted in a student's
    /// repository whose commits are signed; the commit before the deadline
    /// is read out and none of them runs.
    #[test]
    fn every_program_starting_setting_is_planted_and_none_runs() {
        need_git();
        let root = scratch("planted");
        let repo = root.join("mallory");
        std::fs::create_dir_all(&repo).unwrap();
        student_git(&repo, "2026-11-01T10:00:00Z", &["init", "-q", "-b", "main"]);
        let on_time = commit_lib(&repo, "// on time\n", "2026-11-30T10:00:00Z");
        // A signed commit on top (a signature git checks when
        // log.showSignature is on), still before the deadline.
        let tree = student_git(&repo, "2026-11-30T11:00:00Z", &["rev-parse", "HEAD^{tree}"]);
        let raw = format!(
            "tree {tree}\nparent {on_time}\nauthor s <s@example.org> 1764500400 +0000\n\
             committer s <s@example.org> 1764500400 +0000\ngpgsig -----BEGIN PGP SIGNATURE-----\n \n \
             iQEzBAABCAAdFiEE\n -----END PGP SIGNATURE-----\n\nsigned\n"
        );
        std::fs::write(root.join("signed.txt"), raw).unwrap();
        let signed = student_git(
            &repo,
            "2026-11-30T11:00:00Z",
            &[
                "hash-object",
                "-t",
                "commit",
                "-w",
                root.join("signed.txt").to_str().unwrap(),
            ],
        );
        student_git(
            &repo,
            "2026-11-30T11:00:00Z",
            &["update-ref", "HEAD", &signed],
        );
        let settings: Vec<(&str, String)> = vec![
            ("log.showSignature", "true".into()),
            ("gpg.program", plant(&root, "gpg")),
            ("gpg.openpgp.program", plant(&root, "gpg-openpgp")),
            ("gpg.x509.program", plant(&root, "gpg-x509")),
            ("gpg.ssh.program", plant(&root, "gpg-ssh")),
            ("core.pager", plant(&root, "core-pager")),
            ("pager.log", plant(&root, "pager-log")),
            ("pager.show", plant(&root, "pager-show")),
            ("pager.rev-list", plant(&root, "pager-rev-list")),
            ("pager.cat-file", plant(&root, "pager-cat-file")),
            ("pager.ls-tree", plant(&root, "pager-ls-tree")),
            ("core.fsmonitor", plant(&root, "fsmonitor")),
            ("core.hooksPath", root.join("hooks").display().to_string()),
            ("core.sshCommand", plant(&root, "ssh-command")),
            ("core.editor", plant(&root, "editor")),
            ("core.askPass", plant(&root, "askpass")),
            ("sequence.editor", plant(&root, "sequence-editor")),
            ("credential.helper", plant(&root, "credential")),
            ("core.alternateRefsCommand", plant(&root, "alternate-refs")),
            ("filter.evil.clean", plant(&root, "clean")),
            ("filter.evil.smudge", plant(&root, "smudge")),
            ("filter.evil.process", plant(&root, "filter-process")),
            ("diff.evil.textconv", plant(&root, "textconv")),
            ("diff.evil.command", plant(&root, "diff-command")),
            ("merge.evil.driver", plant(&root, "merge-driver")),
            ("alias.rev-list", format!("!{}", plant(&root, "alias"))),
            ("safe.directory", "*".into()),
            (
                "core.worktree",
                root.join("elsewhere").display().to_string(),
            ),
            ("include.path", root.join("included").display().to_string()),
            (
                "includeIf.gitdir:/.path",
                root.join("included-if").display().to_string(),
            ),
        ];
        for (key, value) in &settings {
            student_git(&repo, "2026-11-30T11:00:00Z", &["config", key, value]);
        }
        // The included files would set the pager and gpg again.
        for (file, name) in [("included", "include"), ("included-if", "include-if")] {
            std::fs::write(
                root.join(file),
                format!(
                    "[core]\n\tpager = {}\n[gpg]\n\tprogram = {}\n",
                    plant(&root, &format!("{name}-pager")),
                    plant(&root, &format!("{name}-gpg"))
                ),
            )
            .unwrap();
        }
        std::fs::create_dir_all(root.join("hooks")).unwrap();
        for hook in [
            "post-checkout",
            "pre-commit",
            "reference-transaction",
            "post-index-change",
        ] {
            let program = plant(&root, &format!("hook-{hook}"));
            std::fs::copy(&program, root.join("hooks").join(hook)).unwrap();
        }
        std::fs::write(
            repo.join(".git/info/attributes"),
            "* filter=evil diff=evil merge=evil\n",
        )
        .unwrap();
        // The planted settings are live: the student's own git runs them.
        let _ = Command::new("git")
            .args(["show", "-s", "HEAD"])
            .current_dir(&repo)
            .env("GIT_CONFIG_NOSYSTEM", "1")
            .env("GIT_CONFIG_GLOBAL", "/dev/null")
            .stdin(Stdio::null())
            .output()
            .unwrap();
        let live = ran(&root);
        assert!(
            live.iter().any(|n| n.ends_with("gpg")),
            "the plants would run under the student's own git: {live:?}"
        );
        clear_ran(&root);

        let into = root.join("graded");
        let snap = snapshot(&repo, at("2026-12-01T23:59:00Z"), None, &into).unwrap();
        assert_eq!(snap.commit, signed, "{snap:?}");
        assert_eq!(graded_lib(&into), "// on time\n");
        assert_eq!(
            ran(&root),
            Vec::<String>::new(),
            "nothing of the student's ran"
        );
        assert!(!root.join("elsewhere").exists());

        // The same with a record of the pushes.
        let records = [Record {
            commit: on_time.clone(),
            at: at("2026-11-30T10:05:00Z"),
            branch: Some("main".into()),
        }];
        let refs: Vec<&Record> = records.iter().collect();
        let into = root.join("graded-pushed");
        let snap = snapshot(
            &repo,
            at("2026-12-01T23:59:00Z"),
            Some((&refs, Clock::Pushes)),
            &into,
        )
        .unwrap();
        assert_eq!(
            (snap.commit.as_str(), snap.clock),
            (on_time.as_str(), Clock::Pushes)
        );
        assert_eq!(snap.date, "2026-11-30T10:05:00Z");
        assert_eq!(
            ran(&root),
            Vec::<String>::new(),
            "nothing of the student's ran"
        );
        let _ = std::fs::remove_dir_all(&root);
    }

    /// A commit made after the deadline with its date set before it: a
    /// record of the pushes grades what was pushed by then; without one the
    /// backdated commit wins, and the snapshot says whose clock that was.
    #[test]
    fn a_backdated_commit_loses_to_a_record_of_the_pushes() {
        need_git();
        let root = scratch("backdated");
        let repo = root.join("eve");
        std::fs::create_dir_all(&repo).unwrap();
        student_git(&repo, "2026-11-01T10:00:00Z", &["init", "-q", "-b", "main"]);
        let pushed = commit_lib(&repo, "// pushed on time\n", "2026-11-30T10:00:00Z");
        let backdated = commit_lib(&repo, "// made late\n", "2026-11-30T12:00:00Z");
        let deadline = at("2026-12-01T23:59:00Z");
        // GitHub saw the first pushed on time and the second two days late.
        let records = [
            Record {
                commit: pushed.clone(),
                at: at("2026-11-30T10:01:00Z"),
                branch: Some("main".into()),
            },
            Record {
                commit: backdated.clone(),
                at: at("2026-12-03T08:00:00Z"),
                branch: Some("main".into()),
            },
            // Another branch's push is not the submission.
            Record {
                commit: backdated.clone(),
                at: at("2026-11-30T13:00:00Z"),
                branch: Some("scratch".into()),
            },
        ];
        let refs: Vec<&Record> = records.iter().collect();
        let into = root.join("pushed");
        let snap = snapshot(&repo, deadline, Some((&refs, Clock::Pushes)), &into).unwrap();
        assert_eq!(snap.commit, pushed);
        assert_eq!(graded_lib(&into), "// pushed on time\n");
        assert_eq!(snap.date, "2026-11-30T10:01:00Z");
        assert_eq!(snap.committer_date, "2026-11-30T10:00:00Z");

        let into = root.join("dates");
        let snap = snapshot(&repo, deadline, None, &into).unwrap();
        assert_eq!(snap.commit, backdated, "commit dates alone are fooled");
        assert!(snap.clock.is_students());
        assert_eq!(snap.clock.label(), "commit date (the student's own)");

        // Only late pushes: nothing was handed in.
        let late = [&records[1]];
        let err = snapshot(
            &repo,
            deadline,
            Some((&late, Clock::Pushes)),
            &root.join("none"),
        )
        .unwrap_err();
        assert!(
            err.contains(
                "no push to main by the deadline in the push log (the first is at \
                          2026-12-03T08:00:00Z)"
            ),
            "{err}"
        );
        // A push whose commit the clone lacks (force-pushed away).
        let gone = [Record {
            commit: "ab".repeat(20),
            at: at("2026-11-30T09:00:00Z"),
            branch: None,
        }];
        let gone: Vec<&Record> = gone.iter().collect();
        let err = snapshot(
            &repo,
            deadline,
            Some((&gone, Clock::Pushes)),
            &root.join("gone"),
        )
        .unwrap_err();
        assert!(
            err.contains("is not in this clone") && err.contains("fetch origin abab"),
            "{err}"
        );
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn borrowed_objects_linked_folders_and_odd_heads_are_refused() {
        need_git();
        let root = scratch("refused");
        let repo = root.join("trent");
        std::fs::create_dir_all(&repo).unwrap();
        student_git(&repo, "2026-11-01T10:00:00Z", &["init", "-q", "-b", "main"]);
        let first = commit_lib(&repo, "// one\n", "2026-11-30T10:00:00Z");
        let deadline = at("2026-12-01T00:00:00Z");
        // Packed refs only (as after `git gc` or a fresh clone).
        student_git(&repo, "2026-11-30T10:00:00Z", &["pack-refs", "--all"]);
        assert!(!repo.join(".git/refs/heads/main").exists());
        let snap = snapshot(&repo, deadline, None, &root.join("packed")).unwrap();
        assert_eq!(snap.commit, first);

        let alternates = repo.join(".git/objects/info/alternates");
        std::fs::create_dir_all(alternates.parent().unwrap()).unwrap();
        std::fs::write(&alternates, "/somewhere/else/.git/objects\n").unwrap();
        let err = snapshot(&repo, deadline, None, &root.join("a")).unwrap_err();
        assert!(err.contains("borrows objects from elsewhere"), "{err}");
        std::fs::remove_file(&alternates).unwrap();

        // HEAD as a FIFO: refused, not waited on.
        let head = repo.join(".git/HEAD");
        let text = std::fs::read(&head).unwrap();
        std::fs::remove_file(&head).unwrap();
        let c = std::ffi::CString::new(head.to_str().unwrap()).unwrap();
        // SAFETY: mkfifo on a path of this test's.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
        let err = snapshot(&repo, deadline, None, &root.join("fifo")).unwrap_err();
        assert!(err.contains("is not a regular file"), "{err}");
        std::fs::remove_file(&head).unwrap();
        // HEAD naming a file outside the refs.
        std::fs::write(&head, "ref: ../../../etc/passwd\n").unwrap();
        let err = snapshot(&repo, deadline, None, &root.join("outside")).unwrap_err();
        assert!(err.contains("is not a ref"), "{err}");
        std::fs::write(&head, &text).unwrap();

        // The object folder a link to another repository's.
        let objects = repo.join(".git/objects");
        std::fs::rename(&objects, root.join("moved")).unwrap();
        std::os::unix::fs::symlink(root.join("moved"), &objects).unwrap();
        let err = snapshot(&repo, deadline, None, &root.join("linked")).unwrap_err();
        assert!(err.contains("not a folder of the repository"), "{err}");
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn a_sha256_repository_is_read_too() {
        need_git();
        let root = scratch("sha256");
        let repo = root.join("walter");
        std::fs::create_dir_all(&repo).unwrap();
        student_git(
            &repo,
            "2026-11-01T10:00:00Z",
            &["init", "-q", "--object-format=sha256"],
        );
        let commit = commit_lib(&repo, "// long hashes\n", "2026-11-30T10:00:00Z");
        assert_eq!(commit.len(), 64);
        let into = root.join("graded");
        let snap = snapshot(&repo, at("2026-12-01T00:00:00Z"), None, &into).unwrap();
        assert_eq!(snap.commit, commit);
        assert_eq!(graded_lib(&into), "// long hashes\n");
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
        snapshot(&repo, at("2026-12-01T00:00:00Z"), None, &into).unwrap();
        let lib = into.join("crates/meshedit/src/lib.rs");
        assert_eq!(std::fs::metadata(&lib).unwrap().len() as usize, cap + 1);
        let why = autograde::upload::take_lib_rs(&into).unwrap_err().message();
        assert!(
            why.starts_with("crates/meshedit/src/lib.rs is larger than 1 MiB"),
            "{why}"
        );
        let _ = std::fs::remove_dir_all(&root);
    }

    /// A named pipe planted among the objects (as the blob of lib.rs)
    /// would block git for ever: the command is stopped at its limit and
    /// the repository refused with a message, and the run goes on.
    #[test]
    fn a_named_pipe_among_the_objects_is_stopped_at_the_limit() {
        need_git();
        let root = scratch("fifo-object");
        let repo = root.join("oscar");
        std::fs::create_dir_all(&repo).unwrap();
        student_git(&repo, "2026-11-01T10:00:00Z", &["init", "-q"]);
        commit_lib(&repo, "// blocked\n", "2026-11-30T10:00:00Z");
        let blob = student_git(
            &repo,
            "2026-11-30T10:00:00Z",
            &["rev-parse", "HEAD:crates/meshedit/src/lib.rs"],
        );
        let blob = blob.trim();
        let loose = repo.join(".git/objects").join(&blob[..2]).join(&blob[2..]);
        std::fs::remove_file(&loose).unwrap();
        let c = std::ffi::CString::new(loose.as_os_str().as_encoded_bytes()).unwrap();
        // SAFETY: makes a FIFO at a path we own.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
        let mut r = Repository::open(&repo).unwrap();
        r.limit = std::time::Duration::from_secs(2);
        let start = std::time::Instant::now();
        let into = root.join("graded");
        let e = snapshot_with(r, &repo, at("2026-12-01T00:00:00Z"), None, &into).unwrap_err();
        assert!(start.elapsed() < std::time::Duration::from_secs(20), "{e}");
        assert!(e.contains("did not finish within 2 s"), "{e}");
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn paths_leaving_the_folder_are_refused() {
        assert!(safe_relative("../x.rs").is_none());
        assert!(safe_relative("/etc/x.rs").is_none());
        assert!(safe_relative("").is_none());
        assert_eq!(safe_relative("a/b.rs"), Some(PathBuf::from("a/b.rs")));
    }

    #[test]
    fn deadlines_need_their_zone() {
        assert_eq!(
            parse_deadline("2026-12-01 23:59 +0100"),
            Ok(at("2026-12-01T22:59:00Z"))
        );
        let err = parse_deadline("2026-12-01 23:59").unwrap_err();
        assert!(err.contains("with its zone"), "{err}");
    }

    fn records_of(name: &str, text: &str) -> Result<Records, String> {
        let dir = scratch(&format!("records-{name}"));
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let r = read_records(&path);
        let _ = std::fs::remove_dir_all(&dir);
        r
    }

    const A: &str = "1111111111111111111111111111111111111111";
    const B: &str = "2222222222222222222222222222222222222222";

    #[test]
    fn a_csv_push_log_is_read_and_its_mistakes_are_named() {
        let r = records_of(
            "pushes.csv",
            &format!(
                "Student,pushed_at,commit,branch\nalice,2026-11-30T10:00:00Z,{A},main\n\
                 Bob,2026-12-01 23:00 +0100,{},refs/heads/main\n\n",
                B.to_uppercase()
            ),
        )
        .unwrap();
        assert_eq!(r.clock, Clock::Pushes);
        assert_eq!(
            r.of("ALICE"),
            [&Record {
                commit: A.into(),
                at: at("2026-11-30T10:00:00Z"),
                branch: Some("main".into())
            }]
        );
        assert_eq!(r.of("bob")[0].commit, B);
        assert_eq!(r.of("bob")[0].branch.as_deref(), Some("main"));
        assert!(r.of("carol").is_empty());
        for (text, says) in [
            ("student,commit\n", "no pushed_at column"),
            (
                "student,commit,pushed_at\nalice,1111111,2026-11-30T10:00:00Z\n",
                "row 2: commit \"1111111\" is not a full commit hash",
            ),
            (
                &format!("student,commit,pushed_at\nalice,{A},yesterday\n"),
                "row 2: pushed_at \"yesterday\" is not a date and time with its zone",
            ),
            (
                &format!("student,commit,pushed_at\n,{A},2026-11-30T10:00Z\n"),
                "no student",
            ),
        ] {
            let err = records_of("bad.csv", text).unwrap_err();
            assert!(err.contains(says), "{text}: {err}");
        }
    }

    #[test]
    fn github_s_events_and_activity_are_read_per_submission() {
        let dir = scratch("github");
        // Two pages of events as `gh api --paginate` writes them.
        std::fs::write(
            dir.join("alice.json"),
            format!(
                "[{{\"type\":\"PushEvent\",\"created_at\":\"2026-12-02T09:00:00Z\",\
                 \"payload\":{{\"ref\":\"refs/heads/main\",\"head\":\"{B}\",\"before\":\"{A}\"}}}},\
                 {{\"type\":\"WatchEvent\",\"created_at\":\"2026-11-30T09:00:00Z\"}}]\n\
                 [{{\"type\":\"PushEvent\",\"created_at\":\"2026-11-30T10:00:00Z\",\
                 \"payload\":{{\"ref\":\"refs/heads/main\",\"head\":\"{A}\"}}}}]"
            ),
        )
        .unwrap();
        std::fs::write(
            dir.join("bob.json"),
            format!(
                "[{{\"activity_type\":\"push\",\"ref\":\"refs/heads/main\",\"after\":\"{A}\",\
                 \"timestamp\":\"2026-11-29T08:00:00Z\"}},\
                 {{\"activity_type\":\"branch_deletion\",\"ref\":\"refs/heads/x\",\
                 \"after\":\"0000000000000000000000000000000000000000\",\
                 \"timestamp\":\"2026-11-29T09:00:00Z\"}}]"
            ),
        )
        .unwrap();
        let r = read_records(&dir).unwrap();
        assert_eq!(r.len(), 3);
        let alice: Vec<(&str, i64)> = r
            .of("alice")
            .iter()
            .map(|x| (x.commit.as_str(), x.at))
            .collect();
        assert_eq!(
            alice,
            [
                (B, at("2026-12-02T09:00:00Z")),
                (A, at("2026-11-30T10:00:00Z"))
            ]
        );
        assert_eq!(r.of("bob")[0].branch.as_deref(), Some("main"));

        std::fs::write(dir.join("carol.json"), "{\"message\":\"Not Found\"}").unwrap();
        let err = read_records(&dir).unwrap_err();
        assert!(
            err.contains("carol.json") && err.contains("GitHub said: Not Found"),
            "{err}"
        );
        std::fs::remove_file(dir.join("carol.json")).unwrap();
        std::fs::write(dir.join("notes.txt"), "").unwrap();
        let err = read_records(&dir).unwrap_err();
        assert!(err.contains("one NAME.json per submission"), "{err}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn classroom50_s_scores_are_read_by_repository_and_owner() {
        let scores = format!(
            "{{\"schema\":\"classroom50/scores/v1\",\"assignments\":{{\"meshedit\":{{\
             \"type\":\"individual\",\"entries\":[{{\"owner\":\"Alice\",\"submissions\":[\
             {{\"classroom\":\"cg-2026\",\"commit\":\"https://github.com/o/r/commit/{A}\",\
             \"datetime\":\"2020-01-01T00:00:00Z\",\"graded_at\":\"2026-11-30T10:03:00Z\"}},\
             {{\"classroom\":\"cg-2026\",\"commit\":\"https://github.com/o/r/commit/{B}\",\
             \"datetime\":\"2020-01-01T00:00:00Z\"}}]}}]}}}}}}"
        );
        let r = records_of("scores.json", &scores).unwrap();
        assert_eq!(r.clock, Clock::Classroom50);
        // graded_at, never the commit's own datetime; a result without
        // graded_at is no record.
        for name in ["cg-2026-meshedit-alice", "alice"] {
            let of = r.of(name);
            assert_eq!(of.len(), 1, "{name}");
            assert_eq!(
                (of[0].commit.as_str(), of[0].at),
                (A, at("2026-11-30T10:03:00Z"))
            );
        }
        let err = records_of("other.json", "{\"schema\":\"x\"}").unwrap_err();
        assert!(err.contains("not Classroom 50's scores.json"), "{err}");
    }
}
