//! Helpers shared by the reference's integration tests: running the
//! reference binary, scratch folders and headless Chromium. (Each test file uses some of them.)
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How a run of the reference binary ended.
pub struct Ran {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// Runs the reference binary with `args`, in `dir` if given.
pub fn run_in(dir: Option<&Path>, args: &[&str]) -> Ran {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_reference"));
    cmd.args(args);
    if let Some(d) = dir {
        cmd.current_dir(d);
    }
    let out = cmd.output().expect("the reference binary runs");
    Ran {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Runs the reference binary with `args`.
pub fn run(args: &[&str]) -> Ran {
    run_in(None, args)
}

/// The lab's root folder (the workspace).
pub fn lab_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("reference sits in the lab")
        .to_path_buf()
}

/// A JSON file, read and parsed (a failure names the file).
pub fn json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}\n{text}", path.display()))
}

/// The cases (`*.json`, not `SHA256SUMS`) of one group of the lab's
/// fixtures, sorted.
pub fn case_files(group: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(lab_root().join("fixtures").join(group))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    files
}

/// The counted (lab + hidden) cases of one operation kind (`flip`,
/// `split`, `subdivide`), by name in the order the grader runs them.
pub fn counted_cases(kind: &str) -> Vec<String> {
    ["lab", "hidden"]
        .iter()
        .flat_map(|g| case_files(g))
        .map(|p| json(&p))
        .filter(|f| f["operation"]["kind"] == kind)
        .map(|f| f["name"].as_str().expect("a case has a name").to_string())
        .collect()
}

/// How many counted cases of one operation kind the lab has.
pub fn counted(kind: &str) -> usize {
    counted_cases(kind).len()
}

/// A fresh, empty temporary folder for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("reference-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Whether every test must run its check here: under CI (`CI=true`) and
/// in the full tier (`cargo xtask test` sets `MESHLAB_FULL_TESTS=1`).
pub fn must_run_everything() -> bool {
    let set =
        |name: &str| std::env::var(name).is_ok_and(|v| !v.is_empty() && v != "0" && v != "false");
    set("CI") || set("MESHLAB_FULL_TESTS")
}

/// A check that cannot run on this machine: outside CI it says so loudly
/// and the caller returns (the test passes having checked nothing); under
/// CI or the full tier a skip is a failure.
pub fn skip(reason: &str) {
    assert!(
        !must_run_everything(),
        "this check cannot run here, and under CI or `cargo xtask test` a skip is a failure: {reason}"
    );
    eprintln!("SKIPPED (not under CI): {reason}");
}

/// Whether the tests run as root.
pub fn is_root() -> bool {
    // SAFETY: geteuid only reads.
    unsafe { libc::geteuid() == 0 }
}

/// How `reference grade` ended.
pub struct Graded {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
    pub took: Duration,
}

/// Runs `cmd` (the reference binary, maybe set up further) as `grade
/// --implementation NAME --no-color ARGS`, in its own process group: an
/// attack that reached the grader's group would otherwise reach the test
/// too. Backtraces are asked for: none may reach the student.
pub fn grade_with(cmd: &mut Command, implementation: &str, args: &[&str]) -> Graded {
    use std::os::unix::process::CommandExt;
    let start = Instant::now();
    let out = cmd
        .process_group(0)
        .args(["grade", "--implementation", implementation, "--no-color"])
        .args(args)
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("the reference binary runs");
    Graded {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        took: start.elapsed(),
    }
}

/// `reference grade --implementation NAME ARGS`.
pub fn grade(implementation: &str, args: &[&str]) -> Graded {
    grade_with(
        &mut Command::new(env!("CARGO_BIN_EXE_reference")),
        implementation,
        args,
    )
}

/// The folder class grading builds in for the tests (its `target/` and
/// `vendor/`): outside the lab, as class grading requires, and at a fixed
/// path for this checkout, so that the dependencies compile only once.
pub fn class_build_dir() -> PathBuf {
    use std::hash::{DefaultHasher, Hash, Hasher};
    let mut hasher = DefaultHasher::new();
    reference::lab_root().hash(&mut hasher);
    std::env::temp_dir()
        .join(format!("meshlab-ta-tests-{:016x}", hasher.finish()))
        .join("class-build")
}

/// Class grading options for the tests: builds locked in by the reference
/// binary, in [`class_build_dir`].
pub fn class_options(timeout: f64, budget: f64) -> reference::class::Options {
    reference::class::Options {
        timeout,
        budget,
        bonus: false,
        build_dir: Some(class_build_dir()),
        launcher: PathBuf::from(env!("CARGO_BIN_EXE_reference")),
        build_memory: autograde::build::DEFAULT_MEMORY,
        build_seconds: None,
        fresh: true,
        progress: false,
        grader_args: Vec::new(),
        landlock: true,
        only: Vec::new(),
        before: None,
        pushes: None,
        jobs: 1,
        regrade: false,
        roster: None,
        assignment: "Mesh lab".into(),
    }
}

/// A student's `lib.rs` whose `loop_subdivide` is the model's, then a scan
/// of every edge for each edge (right results, quadratic time), and which
/// replaces libc's `clock_gettime` in its program with one of its own that
/// says 1 µs passed at each call: a child's own timing of the call would
/// say 0.001 ms and "scales well". It prints what its own clock says one
/// round took, once.
pub fn own_clock_quadratic() -> String {
    let solution = std::fs::read_to_string(lab_root().join("reference/src/solution.rs"))
        .expect("the model solution");
    solution.replace("pub fn loop_subdivide(", "pub fn loop_subdivide_model(")
        + r#"
static TICKS: std::sync::atomic::AtomicI64 = std::sync::atomic::AtomicI64::new(0);

/// Every clock of this program, libc's own replaced: 1 us a call.
#[no_mangle]
pub unsafe extern "C" fn clock_gettime(_clock: i32, now: *mut [i64; 2]) -> i32 {
    let t = TICKS.fetch_add(1000, std::sync::atomic::Ordering::Relaxed);
    if !now.is_null() {
        *now = [t / 1_000_000_000, t % 1_000_000_000];
    }
    0
}

static SAID: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

pub fn loop_subdivide(mesh: &mut Mesh) {
    let begun = std::time::Instant::now();
    loop_subdivide_model(mesh);
    let mut sum = 0u64;
    for e in mesh.edge_ids() {
        for f in mesh.edge_ids() {
            sum = sum.wrapping_add(std::hint::black_box(e.0 ^ f.0) as u64);
        }
    }
    std::hint::black_box(sum);
    if !SAID.swap(true, std::sync::atomic::Ordering::Relaxed) {
        println!("my own clock says one round took {:?}", begun.elapsed());
    }
}
"#
}

/// The browser: `$CHROMIUM`, else `chromium` or `chromium-browser` on the
/// PATH.
pub fn chromium() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .flat_map(|dir| ["chromium", "chromium-browser"].map(|name| dir.join(name)))
        .find(|exe| exe.is_file())
}

/// Whether the browser tests can run here; if not, the skip says how to
/// get Chromium (and fails under CI or `cargo xtask test`).
pub fn have_chromium() -> bool {
    let found = chromium().is_some();
    if !found {
        skip(
            "the browser tests need Chromium and none was found on the PATH: run \
             `cargo xtask test` (installs Debian's `chromium` as root), or install it \
             (`apt-get install chromium`) or set CHROMIUM=/path/to/chrome",
        );
    }
    found
}

/// Runs headless Chromium on `url` with `extra` options and returns its
/// standard output; killed after a minute.
pub fn browse(work: &Path, extra: &[&str], url: &str) -> String {
    let profile = work.join("chromium-profile");
    std::fs::create_dir_all(&profile).unwrap();
    let mut child = Command::new(chromium().expect("checked by have_chromium"))
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(url)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("chromium starts");
    // Read while it runs: a large page's DOM fills the pipe otherwise.
    let drain = |mut pipe: Box<dyn std::io::Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            let _ = pipe.read_to_end(&mut bytes);
            bytes
        })
    };
    let stdout = drain(Box::new(child.stdout.take().unwrap()));
    let stderr = drain(Box::new(child.stderr.take().unwrap()));
    let deadline = Instant::now() + Duration::from_secs(60);
    let status = loop {
        if let Some(status) = child.try_wait().expect("chromium can be waited for") {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish within a minute on {url}");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let stdout = stdout.join().unwrap();
    let stderr = stderr.join().unwrap();
    assert!(
        status.success(),
        "chromium failed on {url}: {}",
        String::from_utf8_lossy(&stderr)
    );
    String::from_utf8_lossy(&stdout).into_owned()
}

/// Makes a named pipe at `path` (no writer: opening it to read blocks).
pub fn mkfifo(path: &Path) {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(path.as_os_str().as_bytes()).unwrap();
    // SAFETY: a valid C string; mkfifo only makes the file.
    let made = unsafe { libc::mkfifo(c.as_ptr(), 0o644) };
    assert_eq!(made, 0, "mkfifo {}", path.display());
}

/// Makes a character device at `path` with the numbers of `/dev/zero`
/// (1, 5: it reads without end), as a tarball unpacked by root does.
/// Only root can: elsewhere this says so and returns false (see [`skip`]).
pub fn mknod_zero(path: &Path) -> bool {
    use std::os::unix::ffi::OsStrExt;
    if !is_root() {
        skip("a character device in a submission needs root to make (mknod)");
        return false;
    }
    let c = std::ffi::CString::new(path.as_os_str().as_bytes()).unwrap();
    // SAFETY: a valid C string; mknod only makes the node.
    let made = unsafe { libc::mknod(c.as_ptr(), libc::S_IFCHR | 0o644, libc::makedev(1, 5)) };
    assert_eq!(made, 0, "mknod {}", path.display());
    true
}

/// A file of `bytes` zero bytes at `path`, sparse (nothing written).
pub fn huge_file(path: &Path, bytes: u64) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::File::create(path).unwrap().set_len(bytes).unwrap();
}

/// Runs `cmd` to its end and returns what it printed; kills it and fails
/// if it takes longer than `seconds` (a run that hangs fails the test
/// rather than hanging it).
pub fn output_within(cmd: &mut Command, seconds: u64) -> std::process::Output {
    use std::os::unix::process::CommandExt;
    let child = cmd
        .process_group(0)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the command starts");
    let pid = child.id() as i32;
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || send.send(child.wait_with_output()));
    match receive.recv_timeout(Duration::from_secs(seconds)) {
        Ok(out) => out.expect("the command can be waited for"),
        Err(_) => {
            // SAFETY: a signal to the group of our own child.
            unsafe { libc::kill(-pid, libc::SIGKILL) };
            panic!("{cmd:?} did not finish within {seconds} s: it hung");
        }
    }
}

/// Aborts the test binary, saying why, unless dropped within `seconds`:
/// for a call made in this process (class grading) that could hang.
pub struct Watchdog(std::sync::Arc<std::sync::atomic::AtomicBool>);

impl Watchdog {
    pub fn new(seconds: u64, what: &'static str) -> Watchdog {
        let done = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let flag = done.clone();
        std::thread::spawn(move || {
            let deadline = Instant::now() + Duration::from_secs(seconds);
            while Instant::now() < deadline {
                if flag.load(std::sync::atomic::Ordering::SeqCst) {
                    return;
                }
                std::thread::sleep(Duration::from_millis(200));
            }
            eprintln!("{what}: not done within {seconds} s (it hung)");
            std::process::abort();
        });
        Watchdog(done)
    }
}

impl Drop for Watchdog {
    fn drop(&mut self) {
        self.0.store(true, std::sync::atomic::Ordering::SeqCst);
    }
}

/// One file no student's `lib.rs` can be: how to make it at a path, and
/// what its refusal says.
pub struct Unfit {
    pub says: &'static str,
    pub make: Box<dyn Fn(&Path)>,
}

/// Every kind of file a student's `lib.rs` cannot be, as a tarball
/// unpacked by root makes them: a named pipe, `/dev/zero`'s device (as
/// root only; elsewhere a skip), links to `/dev/zero` and to `ta_file`,
/// and 60 MB.
pub fn unfit_files(ta_file: &Path) -> Vec<Unfit> {
    let ta_file = ta_file.to_path_buf();
    let mut all = vec![
        Unfit {
            says: "is not a regular file (a named pipe)",
            make: Box::new(mkfifo),
        },
        Unfit {
            says: "is a symbolic link",
            make: Box::new(|p| std::os::unix::fs::symlink("/dev/zero", p).unwrap()),
        },
        Unfit {
            says: "is a symbolic link",
            make: Box::new(move |p| std::os::unix::fs::symlink(&ta_file, p).unwrap()),
        },
        Unfit {
            says: "is larger than 1 MiB (62914560 bytes)",
            make: Box::new(|p| huge_file(p, 60 << 20)),
        },
    ];
    if is_root() {
        all.push(Unfit {
            says: "is not a regular file (a character device)",
            make: Box::new(|p| assert!(mknod_zero(p))),
        });
    } else {
        skip("a character device in a submission needs root to make (mknod)");
    }
    all
}
