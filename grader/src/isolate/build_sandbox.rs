//! Locking a student's build in: compiling is running student code too.
//!
//! `include_str!`, `include_bytes!`, `#[path]`, `env!` and `global_asm!`'s
//! `.incbin` let a `lib.rs` read any file or variable the compiler can, and
//! embed it in the program it then runs: a hidden case's expected answer, a
//! file of the TA's, the TA's environment. So every grader that compiles a
//! student's crate (class grading, Gradescope's `run_autograder`) starts
//! cargo through this launcher, a mode of a trusted program (the grader, or
//! the grading tool) started with [`BUILD_LAUNCH_ARG`]. It forks; the child
//! locks itself in and `exec`s cargo; the launcher waits, enforces the time
//! limit, kills what is left and writes how the build ended to a status
//! file (never to cargo's output, which the student's code can fill).
//!
//! The child, before cargo runs:
//! - its own session (`setsid`), killed with everything in it afterwards;
//!   killed if the launcher dies;
//! - its own network namespace where it can have one (root, or an
//!   unprivileged user namespace), cargo `--offline` from vendored sources,
//!   and Landlock's TCP rules: no network;
//! - `RLIMIT_AS` (the memory cap, per compiler process), `RLIMIT_FSIZE`,
//!   no core files;
//! - as root, user `nobody` when asked (Gradescope);
//! - Landlock (best ABI up to 6): read and execute only the toolchain, the
//!   system's programs and libraries (`/usr`, `/lib`...), the vendored
//!   crates and its copy of the lab; write only its target folder; no
//!   signals or abstract sockets out. Not `fixtures/hidden`, not the TA's
//!   home, not `/proc` (so not `/proc/self/environ`), not other submissions;
//! - an environment of exactly [`ENV_NAMES`], every value under the target
//!   folder or the toolchain: nothing of the TA's.
//!
//! The memory cap is told from how a compiler process ended (a wrapper
//! around rustc notes a `SIGABRT` or `SIGKILL`), never from its output.

use std::ffi::{CString, OsStr, OsString};
use std::io::Read;
use std::os::unix::ffi::OsStrExt;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The first argument that turns a program into the build launcher.
pub const BUILD_LAUNCH_ARG: &str = "--meshlab-build-launch";

/// The launcher's exit status when the lock-in itself failed.
pub const BUILD_LAUNCH_FAILED: i32 = 97;

/// The memory cap of each compiler process by default. `RLIMIT_AS` counts
/// address space, not resident memory: rustc and the linker reserve far
/// more than they touch, and this lab's build peaks near 1 GiB resident.
pub const DEFAULT_MEMORY: u64 = 4 << 30;

/// The only variables the build's environment holds.
pub const ENV_NAMES: [&str; 7] = [
    "PATH",
    "HOME",
    "CARGO_HOME",
    "CARGO_TARGET_DIR",
    "RUSTC",
    "TMPDIR",
    "LANG",
];

/// One locked-in build of the lab's grader (and the student's crate in it).
#[derive(Clone, Debug, PartialEq)]
pub struct Build {
    /// The copy of the lab to build (read only).
    pub lab: PathBuf,
    /// The dependencies' sources, as `cargo vendor` wrote them (read only).
    pub vendor: PathBuf,
    /// The toolchain's root (`rustc --print sysroot`; read only).
    pub sysroot: PathBuf,
    /// The target folder: the only place the build may write.
    pub target: PathBuf,
    /// The address-space cap of each process, in bytes.
    pub memory: u64,
    /// Seconds the whole build may take.
    pub seconds: f64,
    /// Where the launcher writes how the build ended.
    pub status: PathBuf,
    /// As root, build as user `nobody`.
    pub drop_user: bool,
    /// Apply Landlock (off only to test what a kernel without it leaves).
    pub landlock: bool,
    /// Give the build a root of its own holding only what it needs (off
    /// only to test what a machine without mount namespaces leaves).
    pub empty_root: bool,
}

impl Build {
    /// The launcher's arguments after [`BUILD_LAUNCH_ARG`].
    pub fn args(&self) -> Vec<OsString> {
        let mut args: Vec<OsString> = vec![BUILD_LAUNCH_ARG.into()];
        for (key, value) in [
            ("--lab", self.lab.as_os_str()),
            ("--vendor", self.vendor.as_os_str()),
            ("--sysroot", self.sysroot.as_os_str()),
            ("--target", self.target.as_os_str()),
            ("--status", self.status.as_os_str()),
        ] {
            args.push(key.into());
            args.push(value.to_owned());
        }
        args.extend([
            "--memory".into(),
            self.memory.to_string().into(),
            "--seconds".into(),
            self.seconds.to_string().into(),
            "--user".into(),
            if self.drop_user { "nobody" } else { "same" }.into(),
            "--landlock".into(),
            if self.landlock { "on" } else { "off" }.into(),
            "--root".into(),
            if self.empty_root { "empty" } else { "host" }.into(),
        ]);
        args
    }

    fn parse(args: &[OsString]) -> Result<Build, String> {
        let mut build = Build {
            lab: PathBuf::new(),
            vendor: PathBuf::new(),
            sysroot: PathBuf::new(),
            target: PathBuf::new(),
            memory: DEFAULT_MEMORY,
            seconds: 600.0,
            status: PathBuf::new(),
            drop_user: false,
            landlock: true,
            empty_root: true,
        };
        let mut it = args.iter();
        while let Some(key) = it.next() {
            let value = it
                .next()
                .ok_or_else(|| format!("{} needs a value", key.to_string_lossy()))?;
            let text = value.to_string_lossy();
            let number = |what: &str| format!("{what}: not a number: {text}");
            match key.to_str().unwrap_or("") {
                "--lab" => build.lab = value.into(),
                "--vendor" => build.vendor = value.into(),
                "--sysroot" => build.sysroot = value.into(),
                "--target" => build.target = value.into(),
                "--status" => build.status = value.into(),
                "--memory" => build.memory = text.parse().map_err(|_| number("--memory"))?,
                "--seconds" => build.seconds = text.parse().map_err(|_| number("--seconds"))?,
                "--user" => build.drop_user = text == "nobody",
                "--landlock" => build.landlock = text != "off",
                "--root" => build.empty_root = text != "host",
                other => return Err(format!("unknown option {other}")),
            }
        }
        for (name, path) in [
            ("--lab", &build.lab),
            ("--vendor", &build.vendor),
            ("--sysroot", &build.sysroot),
            ("--target", &build.target),
            ("--status", &build.status),
        ] {
            if !path.is_absolute() {
                return Err(format!("{name} must be an absolute path"));
            }
        }
        Ok(build)
    }

    /// The build's whole environment: cargo's folders under the target
    /// folder, the toolchain first on the path, nothing of the caller's.
    pub fn env(&self) -> Vec<(&'static str, OsString)> {
        let bin = self.sysroot.join("bin");
        let mut path = bin.clone().into_os_string();
        path.push(":/usr/bin:/bin");
        let under = |name: &str| self.target.join(name).into_os_string();
        vec![
            ("PATH", path),
            ("HOME", under("home")),
            ("CARGO_HOME", under("home/cargo")),
            ("CARGO_TARGET_DIR", self.target.clone().into_os_string()),
            ("RUSTC", bin.join("rustc").into_os_string()),
            ("TMPDIR", under("tmp")),
            ("LANG", "C.UTF-8".into()),
        ]
    }

    /// Cargo's command line: the grader and its child program (with the
    /// student's crate), from the vendored sources, without the network or
    /// a new lock file.
    pub fn cargo_args(&self) -> Vec<OsString> {
        // A JSON string is a valid TOML basic string.
        let vendor = serde_json::to_string(&self.vendor.to_string_lossy()).expect("JSON");
        let wrapper =
            serde_json::to_string(&self.target.join(WRAPPER).to_string_lossy()).expect("JSON");
        [
            "build",
            "--offline",
            "--locked",
            "--color",
            "never",
            "-p",
            "grader",
            "-p",
            "grader-child",
            "--config",
            "source.crates-io.replace-with=\"meshlab-vendored\"",
            "--config",
        ]
        .iter()
        .map(OsString::from)
        .chain([
            OsString::from(format!("source.meshlab-vendored.directory={vendor}")),
            "--config".into(),
            format!("build.rustc-wrapper={wrapper}").into(),
        ])
        .collect()
    }
}

/// How a build ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Cargo succeeded.
    Built,
    /// Cargo failed (a compile error, most often).
    Failed,
    /// A compiler process reached the memory cap.
    OutOfMemory,
    /// Stopped at the time limit.
    OutOfTime,
    /// The build could not be locked in: the grader's problem.
    NotLockedIn,
}

impl Outcome {
    fn word(self) -> &'static str {
        match self {
            Outcome::Built => "built",
            Outcome::Failed => "failed",
            Outcome::OutOfMemory => "memory",
            Outcome::OutOfTime => "time",
            Outcome::NotLockedIn => "not-locked-in",
        }
    }
}

/// What the launcher's status file says.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    pub outcome: Outcome,
    /// Cargo's exit status, when it ended by itself.
    pub exit: Option<i32>,
    /// The Landlock ABI in force (0: none).
    pub landlock: i32,
    /// `namespace` (own network namespace) or `landlock` (TCP only).
    pub network: String,
    /// `nobody` or the caller's user.
    pub user: String,
    /// `empty` (the build's own root: nothing else even seen to exist) or
    /// `host` (the machine's tree, Landlock's rules alone).
    pub root: String,
    pub memory: u64,
    pub seconds: f64,
    /// The largest resident size of any process of the build, in KiB.
    pub peak_kib: u64,
    /// Why the build could not be locked in.
    pub error: String,
}

impl Report {
    /// Reads a status file the launcher wrote.
    pub fn read(path: &Path) -> Result<Report, String> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            format!(
                "the build launcher left no status ({}): {e}",
                path.display()
            )
        })?;
        let field = |key: &str| {
            text.lines()
                .find_map(|l| l.strip_prefix(key)?.strip_prefix('='))
                .unwrap_or("")
                .to_string()
        };
        let outcome = match field("outcome").as_str() {
            "built" => Outcome::Built,
            "failed" => Outcome::Failed,
            "memory" => Outcome::OutOfMemory,
            "time" => Outcome::OutOfTime,
            _ => Outcome::NotLockedIn,
        };
        Ok(Report {
            outcome,
            exit: field("exit").parse().ok(),
            landlock: field("landlock").parse().unwrap_or(0),
            network: field("network"),
            user: field("user"),
            root: field("root"),
            memory: field("memory").parse().unwrap_or(0),
            seconds: field("seconds").parse().unwrap_or(0.0),
            peak_kib: field("peak_kib").parse().unwrap_or(0),
            error: field("error"),
        })
    }

    fn write(&self, path: &Path) -> std::io::Result<()> {
        let text = format!(
            "outcome={}\nexit={}\nlandlock={}\nnetwork={}\nuser={}\nroot={}\nmemory={}\n\
             seconds={}\npeak_kib={}\nerror={}\nmessage={}\nprotections={}\n",
            self.outcome.word(),
            self.exit.map(|c| c.to_string()).unwrap_or_default(),
            self.landlock,
            self.network,
            self.user,
            self.root,
            self.memory,
            self.seconds,
            self.peak_kib,
            self.error.replace('\n', " "),
            self.failure().unwrap_or_default().replace('\n', " "),
            self.protections(),
        );
        std::fs::write(path, text)
    }

    /// Why a build that did not succeed is not the student's compile
    /// error, in the lab's words; `None` for a build or a compile error.
    pub fn failure(&self) -> Option<String> {
        match self.outcome {
            Outcome::Built | Outcome::Failed => None,
            Outcome::OutOfMemory => Some(format!(
                "the build used more than {} (the memory cap of each compiler process): \
                 does the code embed or compute something huge at compile time?",
                crate::text::format_bytes(self.memory)
            )),
            Outcome::OutOfTime => Some(format!(
                "the build did not finish within {} s",
                self.seconds
            )),
            Outcome::NotLockedIn => {
                Some(format!("the build could not be locked in: {}", self.error))
            }
        }
    }

    /// The build's protections line.
    pub fn protections(&self) -> String {
        let files = if self.landlock > 0 {
            format!(
                "Landlock ABI {} (reads only the toolchain, the vendored crates and its \
                 copy of the lab; writes only its target folder)",
                self.landlock
            )
        } else {
            format!(
                "Landlock off (the kernel has none: the build can read every file user {} can)",
                if self.user.is_empty() {
                    "?"
                } else {
                    &self.user
                }
            )
        };
        let network = match self.network.as_str() {
            "namespace" => "no network (own network namespace, offline)",
            "landlock" => "no network (Landlock TCP rules, offline)",
            _ => "offline (cargo --offline only: no network lock)",
        };
        let user = if self.user == "nobody" {
            ", user nobody"
        } else {
            ""
        };
        let root = match self.root.as_str() {
            "empty" => "empty root (no other file even seen to exist)",
            _ => "machine's files seen to exist (no mount namespace here)",
        };
        format!(
            "build protections: {files}, {network}, {root}, memory cap {} per process, time \
             limit {} s, own session, environment {}{user}",
            crate::text::format_bytes(self.memory),
            self.seconds,
            ENV_NAMES.join(" ")
        )
    }
}

/// In a build launcher (started with [`BUILD_LAUNCH_ARG`]), runs the build
/// and exits with cargo's status (or [`BUILD_LAUNCH_FAILED`]); never
/// returns. Elsewhere returns at once. Call it first thing in `main`.
pub fn launch_if_asked() {
    let args: Vec<OsString> = std::env::args_os().collect();
    if args.get(1).map(|a| a.as_os_str()) != Some(BUILD_LAUNCH_ARG.as_ref()) {
        return;
    }
    let build = match Build::parse(&args[2..]) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("grader build sandbox: {e}");
            std::process::exit(BUILD_LAUNCH_FAILED);
        }
    };
    let code = supervise(&build);
    std::process::exit(code);
}

/// The compiler wrapper's name in the target folder (cargo's
/// `build.rustc-wrapper`).
const WRAPPER: &str = "meshlab-rustc-wrapper";

/// Where the wrapper notes each compiler process a signal ended (its shell
/// status, 128 + the signal), one a line.
const SIGNALS: &str = "meshlab-compiler-signals";

/// The wrapper: runs one compiler process and notes whether a signal ended
/// it. A compiler that reaches the memory cap aborts (`SIGABRT`: an
/// allocation failed under `RLIMIT_AS`; rustc's and LLVM's handlers both
/// abort), or the kernel's OOM killer ends it (`SIGKILL`). No student code
/// runs in the build (no build script or macro of its own), and what it
/// makes the compiler print cannot end the compiler by a signal: so unlike
/// the compiler's words ("memory allocation of N bytes failed", which
/// `compile_error!` prints as well), this cannot be forged. rustc itself
/// never exits with a status above 128.
const WRAPPER_SCRIPT: &str = "#!/bin/sh
# Written by the grader's build launcher: runs one compiler process and
# notes, for the launcher, the status of one a signal ended.
\"$@\"
status=$?
if [ \"$status\" -gt 128 ]; then
    echo \"$status\" >> \"${0%/*}/meshlab-compiler-signals\"
fi
exit \"$status\"
";

/// Writes the wrapper into the target folder (executable by the build's
/// user, who may be `nobody`) and clears the notes of an earlier build.
fn install_wrapper(target: &Path) -> Result<(), String> {
    use std::os::unix::fs::PermissionsExt;
    let path = target.join(WRAPPER);
    let fail = |e: std::io::Error| format!("{}: {e}", path.display());
    // Replaced, not rewritten in place: a build never sees half of it.
    let fresh = target.join(format!("{WRAPPER}.new"));
    std::fs::write(&fresh, WRAPPER_SCRIPT).map_err(fail)?;
    std::fs::set_permissions(&fresh, std::fs::Permissions::from_mode(0o755)).map_err(fail)?;
    std::fs::rename(&fresh, &path).map_err(fail)?;
    match std::fs::remove_file(target.join(SIGNALS)) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(fail(e)),
        _ => Ok(()),
    }
}

/// Whether the wrapper saw a compiler process end by `SIGABRT` or
/// `SIGKILL`: the memory cap.
fn compiler_hit_memory_cap(target: &Path) -> bool {
    let notes = std::fs::read_to_string(target.join(SIGNALS)).unwrap_or_default();
    notes.lines().any(|l| {
        l.trim()
            .parse::<i32>()
            .is_ok_and(|s| s == 128 + libc::SIGABRT || s == 128 + libc::SIGKILL)
    })
}

fn last_error() -> String {
    std::io::Error::last_os_error().to_string()
}

/// Forks the locked-in cargo, waits for it within the time limit, kills
/// its session and every orphan, writes the status file. Returns the exit
/// status for the launcher.
fn supervise(build: &Build) -> i32 {
    let mut report = Report {
        outcome: Outcome::NotLockedIn,
        exit: None,
        landlock: 0,
        network: String::new(),
        user: String::new(),
        root: String::new(),
        memory: build.memory,
        seconds: build.seconds,
        peak_kib: 0,
        error: String::new(),
    };
    let fail = |mut report: Report, error: String| {
        eprintln!("grader build sandbox: {error}");
        report.error = error;
        let _ = report.write(&build.status);
        BUILD_LAUNCH_FAILED
    };
    for dir in ["home/cargo", "tmp"] {
        if let Err(e) = std::fs::create_dir_all(build.target.join(dir)) {
            return fail(report, format!("{}: {e}", build.target.join(dir).display()));
        }
    }
    if let Err(e) = install_wrapper(&build.target) {
        return fail(report, e);
    }
    // Everything prepared before the fork: the child allocates nothing it
    // can avoid between fork and exec.
    let cargo = build.sysroot.join("bin/cargo");
    let c = |s: &OsStr| CString::new(s.as_bytes()).unwrap_or_default();
    let argv: Vec<CString> = std::iter::once(cargo.clone().into_os_string())
        .chain(build.cargo_args())
        .map(|a| c(&a))
        .collect();
    let envp: Vec<CString> = build
        .env()
        .into_iter()
        .map(|(k, v)| {
            let mut kv = OsString::from(k);
            kv.push("=");
            kv.push(v);
            c(&kv)
        })
        .collect();
    let lab = c(build.lab.as_os_str());
    // The child tells how it locked itself in on `status` (close-on-exec:
    // end of file means cargo started); its standard error comes through
    // `errors`, passed on.
    let (status_r, status_w) = match pipe() {
        Ok(p) => p,
        Err(e) => return fail(report, e),
    };
    let (errors_r, errors_w) = match pipe() {
        Ok(p) => p,
        Err(e) => return fail(report, e),
    };
    // SAFETY: plain system calls; this process has one thread here.
    unsafe {
        // Orphans of the build become ours, to be killed at the end.
        #[cfg(target_os = "linux")]
        libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0);
    }
    let parent = std::process::id() as libc::pid_t;
    // SAFETY: fork in a single-threaded process.
    let pid = unsafe { libc::fork() };
    if pid < 0 {
        return fail(report, format!("fork: {}", last_error()));
    }
    if pid == 0 {
        // SAFETY: our own descriptors.
        unsafe {
            libc::close(status_r);
            libc::close(errors_r);
            libc::dup2(errors_w, 2);
            libc::close(errors_w);
        }
        let message = match lock_in(build, parent, status_w) {
            Ok(line) => line,
            Err(e) => format!("error={e}"),
        };
        write_all(status_w, message.as_bytes());
        if !message.starts_with("error=") {
            let ptrs = |v: &[CString]| -> Vec<*const libc::c_char> {
                v.iter()
                    .map(|s| s.as_ptr())
                    .chain(std::iter::once(std::ptr::null()))
                    .collect()
            };
            let (argv_p, envp_p) = (ptrs(&argv), ptrs(&envp));
            // SAFETY: null-terminated arrays of C strings that outlive the call.
            unsafe {
                libc::chdir(lab.as_ptr());
                libc::execve(argv_p[0], argv_p.as_ptr(), envp_p.as_ptr());
            }
            write_all(
                status_w,
                format!("\nerror=cannot run {}: {}", cargo.display(), last_error()).as_bytes(),
            );
        }
        // SAFETY: ends the child without running the parent's destructors.
        unsafe { libc::_exit(BUILD_LAUNCH_FAILED) };
    }
    // SAFETY: our own descriptors.
    unsafe {
        libc::close(status_w);
        libc::close(errors_w);
    }
    let start = Instant::now();
    let mut locked = String::new();
    // SAFETY: the read end is ours; File takes it over.
    let mut status_file =
        unsafe { <std::fs::File as std::os::fd::FromRawFd>::from_raw_fd(status_r) };
    let _ = status_file.read_to_string(&mut locked);
    // SAFETY: as above.
    let errors_file = unsafe { <std::fs::File as std::os::fd::FromRawFd>::from_raw_fd(errors_r) };
    let reader = std::thread::spawn(move || pass_on(errors_file));

    // Asked to stop (a TA's Ctrl-C, the caller's SIGTERM): the build's
    // session goes too, rather than running on without a supervisor.
    for signal in [libc::SIGTERM, libc::SIGINT, libc::SIGHUP] {
        // SAFETY: the handler only stores to an atomic.
        unsafe { libc::signal(signal, on_stop as *const () as libc::sighandler_t) };
    }
    let limit = Duration::from_secs_f64(build.seconds.max(0.0));
    let mut timed_out = false;
    let mut wait_status = 0;
    loop {
        // SAFETY: waiting for our own child.
        let done = unsafe { libc::waitpid(pid, &mut wait_status, libc::WNOHANG) };
        if done == pid {
            break;
        }
        let stopped = STOP.load(std::sync::atomic::Ordering::Relaxed);
        if stopped || start.elapsed() >= limit {
            timed_out = !stopped;
            // The child's session is its process group.
            crate::isolate::process::kill_group(pid as u32);
            // SAFETY: waits for our own child.
            unsafe {
                libc::waitpid(pid, &mut wait_status, 0);
            }
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    sweep(pid);
    let _ = reader.join();
    let saw_memory = compiler_hit_memory_cap(&build.target);
    // SAFETY: a plain query about our (reaped) children.
    let peak = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage);
        usage.ru_maxrss.max(0) as u64
    };
    report.peak_kib = peak;
    let field = |key: &str| {
        locked
            .lines()
            .find_map(|l| l.strip_prefix(key)?.strip_prefix('='))
            .map(str::to_string)
    };
    if let Some(error) = field("error") {
        return fail(report, error);
    }
    report.landlock = field("landlock").and_then(|v| v.parse().ok()).unwrap_or(0);
    report.network = field("network").unwrap_or_default();
    report.user = field("user").unwrap_or_default();
    report.root = field("root").unwrap_or_default();
    let exit = libc::WIFEXITED(wait_status).then(|| libc::WEXITSTATUS(wait_status));
    report.exit = if timed_out { None } else { exit };
    report.outcome = match (timed_out, exit) {
        (true, _) => Outcome::OutOfTime,
        (false, Some(0)) => Outcome::Built,
        (false, _) if saw_memory => Outcome::OutOfMemory,
        (false, _) => Outcome::Failed,
    };
    if let Some(why) = report.failure() {
        eprintln!("grader build sandbox: {why}");
    }
    if let Err(e) = report.write(&build.status) {
        eprintln!(
            "grader build sandbox: cannot write {}: {e}",
            build.status.display()
        );
        return BUILD_LAUNCH_FAILED;
    }
    match report.outcome {
        Outcome::Built => 0,
        _ => exit.filter(|c| *c != 0).unwrap_or(1),
    }
}

/// Set when the launcher is asked to stop.
static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

extern "C" fn on_stop(_: libc::c_int) {
    STOP.store(true, std::sync::atomic::Ordering::Relaxed);
}

/// Copies the build's standard error to ours. (Nothing is decided from
/// it: the student's crate chooses what the compiler prints.)
fn pass_on(mut from: std::fs::File) {
    let _ = std::io::copy(&mut from, &mut std::io::stderr());
}

/// Kills the build's session and every process left to us (orphans come to
/// this launcher, a subreaper), then reaps them all.
fn sweep(session: libc::pid_t) {
    let me = std::process::id().to_string();
    for _ in 0..50 {
        crate::isolate::process::kill_group(session as u32);
        let mut any = false;
        for entry in std::fs::read_dir("/proc").into_iter().flatten().flatten() {
            let Ok(pid) = entry.file_name().to_string_lossy().parse::<libc::pid_t>() else {
                continue;
            };
            let Ok(stat) = std::fs::read_to_string(entry.path().join("stat")) else {
                continue;
            };
            // The fields after the command's closing parenthesis: state, ppid.
            let ppid = stat
                .rsplit_once(')')
                .and_then(|(_, rest)| rest.split_whitespace().nth(1).map(str::to_string));
            if ppid.as_deref() == Some(me.as_str()) {
                any = true;
                // SAFETY: our own child.
                unsafe { libc::kill(pid, libc::SIGKILL) };
            }
        }
        // SAFETY: reaping our own children.
        while unsafe { libc::waitpid(-1, std::ptr::null_mut(), libc::WNOHANG) } > 0 {}
        if !any {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

fn pipe() -> Result<(i32, i32), String> {
    let mut fds = [0; 2];
    // SAFETY: a plain system call filling our array.
    if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) } != 0 {
        return Err(format!("pipe: {}", last_error()));
    }
    Ok((fds[0], fds[1]))
}

fn write_all(fd: i32, mut bytes: &[u8]) {
    while !bytes.is_empty() {
        // SAFETY: writing our own buffer to our own descriptor.
        let n = unsafe { libc::write(fd, bytes.as_ptr().cast(), bytes.len()) };
        if n <= 0 {
            return;
        }
        bytes = &bytes[n as usize..];
    }
}

// Limits are set as the case launcher sets them.
use crate::isolate::sys::set_limit;

/// The child's lock-in, before cargo is `exec`ed: the status line for the
/// launcher (`landlock=6 network=namespace user=nobody root=empty`).
/// `status` is the status pipe, which a process of the lock-in that stays
/// behind (waiting outside a PID namespace) lets go of.
fn lock_in(build: &Build, parent: libc::pid_t, status: i32) -> Result<String, String> {
    // SAFETY: plain system calls on this (single-threaded) process.
    unsafe {
        if libc::setsid() < 0 {
            return Err(format!("setsid: {}", last_error()));
        }
        #[cfg(target_os = "linux")]
        {
            libc::prctl(
                libc::PR_SET_PDEATHSIG,
                libc::SIGKILL as libc::c_ulong,
                0,
                0,
                0,
            );
        }
        if libc::getppid() != parent {
            return Err("the launcher is gone".into());
        }
        let null = c"/dev/null";
        let fd = libc::open(null.as_ptr(), libc::O_RDONLY);
        if fd >= 0 {
            libc::dup2(fd, 0);
            libc::close(fd);
        }
    }
    // Asked before the empty root hides /etc/passwd.
    let caller = user_name();
    let spaces = own_namespaces();
    if spaces.pid {
        // This process waits outside the new PID namespace; its child, the
        // namespace's first process, goes on to lock itself in and run
        // cargo (killed, with all it started, when this one is).
        wait_outside(status)?;
    }
    let rooted = if build.empty_root && spaces.mount && spaces.pid {
        empty_root(build)?
    } else {
        false
    };
    let network = spaces.network;
    set_limit(libc::RLIMIT_AS, build.memory)?;
    // The largest file a build writes is a debug binary of tens of MiB.
    set_limit(libc::RLIMIT_FSIZE, 2 << 30)?;
    set_limit(libc::RLIMIT_CORE, 0)?;
    // SAFETY: plain system calls.
    let root = unsafe { libc::geteuid() } == 0;
    let user = if build.drop_user && root {
        crate::isolate::sys::drop_to_nobody()?;
        // SAFETY: a plain system call.
        unsafe {
            // Dropping the user clears the parent-death signal.
            #[cfg(target_os = "linux")]
            libc::prctl(
                libc::PR_SET_PDEATHSIG,
                libc::SIGKILL as libc::c_ulong,
                0,
                0,
                0,
            );
        }
        "nobody".to_string()
    } else {
        caller
    };
    let abi = if build.landlock { landlock(build)? } else { 0 };
    let network = match network {
        true => "namespace",
        false if abi >= 4 => "landlock",
        false => "none",
    };
    // Descriptors this launcher inherited must not reach the build.
    // SAFETY: a plain system call on our own descriptor table.
    #[cfg(target_os = "linux")]
    unsafe {
        const CLOSE_RANGE_CLOEXEC: u32 = 1 << 2;
        libc::syscall(libc::SYS_close_range, 3u32, u32::MAX, CLOSE_RANGE_CLOEXEC);
    }
    let root = if rooted { "empty" } else { "host" };
    Ok(format!(
        "landlock={abi}\nnetwork={network}\nuser={user}\nroot={root}\n"
    ))
}

/// This process's user's name, for the protections line.
fn user_name() -> String {
    // SAFETY: getpwuid returns a pointer to static storage or null.
    unsafe {
        let uid = libc::geteuid();
        let pw = libc::getpwuid(uid);
        if pw.is_null() || (*pw).pw_name.is_null() {
            return uid.to_string();
        }
        std::ffi::CStr::from_ptr((*pw).pw_name)
            .to_string_lossy()
            .into_owned()
    }
}

/// The namespaces the build got: a network namespace (no interface but a
/// loopback that is down), and mount and PID namespaces for the empty
/// root (a PID namespace for a `/proc` that shows the build's processes
/// only: rustc finds its libraries through `/proc/self/exe`).
#[derive(Clone, Copy, Default)]
struct Spaces {
    network: bool,
    mount: bool,
    pid: bool,
}

/// Namespaces of its own: as root directly, otherwise inside a new user
/// namespace mapping this user to itself (tried first in a throwaway
/// process: where a user namespace can be made but not mapped, this one
/// must not be left in it). The most it can get, down to none.
#[cfg(target_os = "linux")]
fn own_namespaces() -> Spaces {
    let all = libc::CLONE_NEWNET | libc::CLONE_NEWNS | libc::CLONE_NEWPID;
    // SAFETY: plain system calls on this (single-threaded) process.
    unsafe {
        if libc::geteuid() == 0 {
            if libc::unshare(all) == 0 {
                return Spaces {
                    network: true,
                    mount: true,
                    pid: true,
                };
            }
            return Spaces {
                network: libc::unshare(libc::CLONE_NEWNET) == 0,
                ..Spaces::default()
            };
        }
    }
    // SAFETY: plain system calls.
    let (uid, gid) = unsafe { (libc::geteuid(), libc::getegid()) };
    let maps = [
        ("/proc/self/setgroups", "deny".to_string()),
        ("/proc/self/uid_map", format!("{uid} {uid} 1")),
        ("/proc/self/gid_map", format!("{gid} {gid} 1")),
    ];
    let enter = |flags: libc::c_int| {
        // SAFETY: a plain system call.
        (unsafe { libc::unshare(libc::CLONE_NEWUSER | flags) } == 0)
            && maps.iter().all(|(f, t)| std::fs::write(f, t).is_ok())
    };
    let works = |flags: libc::c_int| match crate::isolate::sys::fork() {
        Ok(0) => {
            let ok = enter(flags);
            // SAFETY: ends the throwaway process.
            unsafe { libc::_exit(if ok { 0 } else { 1 }) }
        }
        Ok(probe) => crate::isolate::sys::wait_for(probe) == Some(0),
        Err(_) => false,
    };
    for (flags, got) in [
        (
            all,
            Spaces {
                network: true,
                mount: true,
                pid: true,
            },
        ),
        (
            libc::CLONE_NEWNET,
            Spaces {
                network: true,
                ..Spaces::default()
            },
        ),
    ] {
        if works(flags) {
            return if enter(flags) { got } else { Spaces::default() };
        }
    }
    Spaces::default()
}

#[cfg(not(target_os = "linux"))]
fn own_namespaces() -> Spaces {
    Spaces::default()
}

/// In a new PID namespace: forks its first process, which returns and goes
/// on; this one lets go of the status pipe and its standard streams, waits
/// for it and ends as it ended (the launcher reads cargo's status from
/// this process's).
#[cfg(target_os = "linux")]
fn wait_outside(status: i32) -> Result<(), String> {
    let first = crate::isolate::sys::fork()?;
    if first == 0 {
        // SAFETY: a plain prctl call. Its parent is this process's waiter.
        unsafe {
            libc::prctl(
                libc::PR_SET_PDEATHSIG,
                libc::SIGKILL as libc::c_ulong,
                0,
                0,
                0,
            );
        }
        return Ok(());
    }
    // SAFETY: plain system calls on our own descriptor table.
    unsafe {
        libc::close(status);
        let null = libc::open(c"/dev/null".as_ptr(), libc::O_RDWR);
        for fd in [0, 1, 2] {
            libc::dup2(null, fd);
        }
        if null > 2 {
            libc::close(null);
        }
    }
    let ended = crate::isolate::sys::wait_for(first).unwrap_or(libc::SIGKILL);
    crate::isolate::sys::end_like(ended)
}

#[cfg(not(target_os = "linux"))]
fn wait_outside(_: i32) -> Result<(), String> {
    Ok(())
}

/// How a path the build needs goes into its root.
#[cfg(target_os = "linux")]
enum Place {
    /// A detached copy of its mount (`open_tree`), read-only or not.
    Tree(std::os::fd::OwnedFd, bool, bool),
    /// The same symbolic link (`/bin -> usr/bin`).
    Link(PathBuf),
}

/// Where a path of the new root is inside the folder `new` it is built in.
fn inside(new: &Path, path: &Path) -> PathBuf {
    new.join(path.strip_prefix("/").unwrap_or(path))
}

/// Gives the build (its PID namespace's first process, still privileged
/// there) a mount namespace whose root is a fresh tmpfs holding only what
/// the build needs, each at its own path: the toolchain, the vendored
/// crates, its copy of the lab (read-only), its target folder (the one it
/// may write), the system's programs and libraries (`/usr`, `/lib*`,
/// `/bin`, `/sbin`), the loader's and the alternatives' files in `/etc`,
/// `/dev/null` and a `/proc` of its own PID namespace. Landlock's rules
/// stay as they are; this adds that what the build may not read, it cannot
/// tell from what does not exist (`include_str!` of a hidden case and of a
/// name nobody used fail alike: "No such file or directory").
///
/// Returns whether it did; where the kernel refuses a step before the
/// switch, the machine's tree stays (and the status says so). A failure
/// after the switch is an error: the root would be half made.
#[cfg(target_os = "linux")]
fn empty_root(build: &Build) -> Result<bool, String> {
    use crate::isolate::namespace::{cpath, mount, open_folders, remount_read_only};
    use crate::isolate::sys::os_error;
    use std::os::fd::{AsRawFd, FromRawFd};
    if mount(
        None,
        Path::new("/"),
        None,
        libc::MS_REC | libc::MS_PRIVATE,
        None,
    )
    .is_err()
    {
        return Ok(false);
    }
    // (path, read-only, the build's own): the build's own folders are
    // named to cargo by these paths, so each must be its own path, no link
    // on the way.
    let mut wanted: Vec<(PathBuf, bool, bool)> = vec![
        (build.sysroot.clone(), true, true),
        (build.vendor.clone(), true, true),
        (build.lab.clone(), true, true),
        (build.target.clone(), false, true),
    ];
    for path in SYSTEM_PATHS {
        wanted.push((PathBuf::from(path), true, false));
    }
    wanted.push((PathBuf::from("/dev/null"), false, false));
    for (path, _, own) in &wanted {
        if *own && std::fs::canonicalize(path).ok().as_deref() != Some(path.as_path()) {
            return Ok(false);
        }
    }
    wanted.sort_by(|a, b| a.0.cmp(&b.0));
    let mut places: Vec<(PathBuf, Place)> = Vec::new();
    for (path, read_only, _) in wanted {
        // Inside a folder already bound (a toolchain under /usr): there
        // with it.
        let covered = places.iter().any(|(p, place)| {
            matches!(place, Place::Tree(_, _, true)) && path.starts_with(p) && path != *p
        });
        if covered {
            continue;
        }
        let Ok(meta) = std::fs::symlink_metadata(&path) else {
            continue;
        };
        if meta.file_type().is_symlink() {
            let Ok(to) = std::fs::read_link(&path) else {
                return Ok(false);
            };
            places.push((path, Place::Link(to)));
            continue;
        }
        const OPEN_TREE_CLONE: libc::c_uint = 1;
        const AT_RECURSIVE: libc::c_uint = 0x8000;
        // SAFETY: a plain system call on a C string we own; the descriptor
        // it returns is ours.
        let fd = unsafe {
            libc::syscall(
                libc::SYS_open_tree,
                libc::AT_FDCWD,
                cpath(&path)?.as_ptr(),
                OPEN_TREE_CLONE | AT_RECURSIVE | libc::O_CLOEXEC as libc::c_uint,
            )
        };
        if fd < 0 {
            return Ok(false);
        }
        // SAFETY: the descriptor was just returned to us.
        let tree = unsafe { std::os::fd::OwnedFd::from_raw_fd(fd as i32) };
        places.push((path, Place::Tree(tree, read_only, meta.is_dir())));
    }
    // The fresh root, mounted on the target folder (whose copy is taken
    // above): a folder that exists and that nothing else is under.
    let new = build.target.clone();
    if mount(
        Some(Path::new("tmpfs")),
        &new,
        Some("tmpfs"),
        libc::MS_NOSUID | libc::MS_NODEV,
        Some("size=1m,mode=0755"),
    )
    .is_err()
    {
        return Ok(false);
    }
    let furnish = || -> Result<(), String> {
        for (path, place) in &places {
            let at = inside(&new, path);
            if let Some(parent) = at.parent() {
                open_folders(&new, parent)?;
            }
            match place {
                Place::Link(to) => std::os::unix::fs::symlink(to, &at)
                    .map_err(|e| format!("symlink {}: {e}", at.display()))?,
                Place::Tree(tree, _, is_dir) => {
                    if *is_dir {
                        open_folders(&new, &at)?;
                    } else {
                        std::fs::File::create(&at)
                            .map_err(|e| format!("create {}: {e}", at.display()))?;
                    }
                    const MOVE_MOUNT_F_EMPTY_PATH: libc::c_uint = 0x4;
                    // SAFETY: a plain system call on our descriptor and a C
                    // string we own.
                    if unsafe {
                        libc::syscall(
                            libc::SYS_move_mount,
                            tree.as_raw_fd(),
                            c"".as_ptr(),
                            libc::AT_FDCWD,
                            cpath(&at)?.as_ptr(),
                            MOVE_MOUNT_F_EMPTY_PATH,
                        )
                    } != 0
                    {
                        return Err(os_error(&format!("move_mount {}", at.display())));
                    }
                }
            }
        }
        let proc = new.join("proc");
        open_folders(&new, &proc)?;
        mount(
            Some(Path::new("proc")),
            &proc,
            Some("proc"),
            libc::MS_NOSUID | libc::MS_NODEV | libc::MS_NOEXEC,
            None,
        )
    };
    let dot = c".";
    // SAFETY: plain system calls on C strings we own. `pivot_root(".",
    // ".")` stacks the old root on the new one; detaching it leaves only
    // the new.
    let switched = furnish().is_ok()
        && unsafe {
            libc::chdir(cpath(&new)?.as_ptr()) == 0
                && libc::syscall(libc::SYS_pivot_root, dot.as_ptr(), dot.as_ptr()) == 0
        };
    if !switched {
        // SAFETY: plain system calls: back to the machine's tree, whole.
        unsafe {
            libc::chdir(c"/".as_ptr());
            libc::umount2(cpath(&new)?.as_ptr(), libc::MNT_DETACH);
        }
        return Ok(false);
    }
    // SAFETY: as above.
    unsafe {
        if libc::umount2(dot.as_ptr(), libc::MNT_DETACH) != 0 || libc::chdir(c"/".as_ptr()) != 0 {
            return Err(os_error("cannot let go of the old root"));
        }
    }
    mount(
        None,
        Path::new("/"),
        None,
        libc::MS_BIND | libc::MS_REMOUNT | libc::MS_RDONLY | libc::MS_NOSUID | libc::MS_NODEV,
        None,
    )?;
    for (path, place) in &places {
        if let Place::Tree(_, true, _) = place {
            remount_read_only(path)?;
        }
    }
    Ok(true)
}

#[cfg(not(target_os = "linux"))]
fn empty_root(_: &Build) -> Result<bool, String> {
    Ok(false)
}

/// The system's paths the build reads (Landlock's rules name the same):
/// the compilers, linkers and libraries, the loader's files, and the
/// alternatives the system's `cc` is a link through.
const SYSTEM_PATHS: [&str; 9] = [
    "/usr",
    "/lib",
    "/lib64",
    "/bin",
    "/sbin",
    "/etc/ld.so.cache",
    "/etc/ld.so.conf",
    "/etc/ld.so.conf.d",
    "/etc/alternatives",
];

#[cfg(not(target_os = "linux"))]
fn landlock(_: &Build) -> Result<i32, String> {
    Ok(0)
}

/// Applies the build's Landlock rules; the ABI in force (0: none).
#[cfg(target_os = "linux")]
fn landlock(build: &Build) -> Result<i32, String> {
    use landlock::{
        Access, AccessFs, BitFlags, LandlockStatus, PathBeneath, PathFd, RulesetCreatedAttr,
        RulesetStatus, ABI,
    };
    let abi = ABI::V6;
    let fail = |e: &dyn std::fmt::Display| format!("Landlock: {e}");
    let mut ruleset = crate::isolate::landlock_rules::denying_everything()?;
    let read: BitFlags<AccessFs> = AccessFs::from_read(abi);
    // The toolchain, the system's compilers, linkers and libraries, the
    // dependencies' sources and the copy of the lab: read only.
    let mut rules: Vec<(PathBuf, BitFlags<AccessFs>)> = vec![
        (build.sysroot.clone(), read),
        (build.vendor.clone(), read),
        (build.lab.clone(), read),
        (build.target.clone(), AccessFs::from_all(abi)),
        ("/dev/null".into(), AccessFs::ReadFile | AccessFs::WriteFile),
    ];
    for dir in ["/usr", "/lib", "/lib64", "/bin", "/sbin"] {
        rules.push((dir.into(), read));
    }
    for file in ["/etc/ld.so.cache", "/etc/ld.so.conf"] {
        rules.push((file.into(), AccessFs::ReadFile.into()));
    }
    for dir in ["/etc/ld.so.conf.d", "/etc/alternatives"] {
        rules.push((dir.into(), read));
    }
    for (path, rights) in rules {
        let Ok(fd) = PathFd::new(&path) else {
            continue;
        };
        // A file takes only the rights a file can have.
        let rights = if path.is_dir() {
            rights
        } else {
            rights & AccessFs::from_file(abi)
        };
        ruleset = ruleset
            .add_rule(PathBeneath::new(fd, rights))
            .map_err(|e| fail(&e))?;
    }
    let status = ruleset.restrict_self().map_err(|e| fail(&e))?;
    Ok(match (status.ruleset, status.landlock) {
        (RulesetStatus::NotEnforced, _) => 0,
        (_, LandlockStatus::Available { effective_abi, .. }) => effective_abi as i32,
        _ => 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build() -> Build {
        Build {
            lab: "/tmp/lab".into(),
            vendor: "/tmp/vendor".into(),
            sysroot: "/opt/rust".into(),
            target: "/tmp/t".into(),
            memory: 123,
            seconds: 4.5,
            status: "/tmp/status".into(),
            drop_user: true,
            landlock: false,
            empty_root: false,
        }
    }

    #[test]
    fn arguments_parse_back() {
        let b = build();
        let args = b.args();
        assert_eq!(args[0], BUILD_LAUNCH_ARG);
        assert_eq!(Build::parse(&args[1..]).unwrap(), b);
        assert!(Build::parse(&["--lab".into(), "relative".into()]).is_err());
    }

    #[test]
    fn the_environment_is_the_allow_list_and_names_only_the_build() {
        let b = build();
        let env = b.env();
        let names: Vec<&str> = env.iter().map(|(k, _)| *k).collect();
        assert_eq!(names, ENV_NAMES);
        for (k, v) in &env {
            let v = v.to_string_lossy();
            let ours = v.starts_with("/tmp/t") || v.starts_with("/opt/rust/bin");
            assert!(ours || v == "C.UTF-8", "{k}={v}");
        }
    }

    #[test]
    fn failures_are_named() {
        let mut r = Report {
            outcome: Outcome::OutOfMemory,
            exit: Some(101),
            landlock: 6,
            network: "namespace".into(),
            user: "nobody".into(),
            root: "empty".into(),
            memory: 4 << 30,
            seconds: 60.0,
            peak_kib: 1,
            error: String::new(),
        };
        assert!(r
            .failure()
            .unwrap()
            .starts_with("the build used more than 4 GiB"));
        r.outcome = Outcome::OutOfTime;
        assert_eq!(r.failure().unwrap(), "the build did not finish within 60 s");
        r.outcome = Outcome::Failed;
        assert_eq!(r.failure(), None);
        let line = r.protections();
        assert!(line.contains("Landlock ABI 6") && line.contains("own network namespace"));
        assert!(
            line.contains("empty root (no other file even seen to exist)"),
            "{line}"
        );
        r.root = "host".into();
        assert!(
            r.protections()
                .contains("machine's files seen to exist (no mount namespace here)"),
            "{}",
            r.protections()
        );
        r.landlock = 0;
        assert!(
            r.protections().contains("Landlock off"),
            "{}",
            r.protections()
        );
    }
}
