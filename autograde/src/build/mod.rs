//! Locking a student's build in: compiling is running student code too.
//! The TAs' side only (class grading and the platforms' autograder): no
//! student compiles it.
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

use std::ffi::OsString;
use std::path::{Path, PathBuf};

mod lockin;
mod root;
mod supervise;

use supervise::{supervise, WRAPPER};

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
                grader::text::format_bytes(self.memory)
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
            grader::text::format_bytes(self.memory),
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
