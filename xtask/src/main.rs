//! `cargo xtask test`: the full test run of the lab, as on a new machine.
//!
//! Plain `cargo test --workspace` is the fast tier: a test that needs
//! something this machine lacks (Chromium for the report pages, root or
//! Landlock for some attacks) says `SKIPPED` and passes. This runner is the
//! full tier that the README gives and CI runs: it finds or installs what
//! the tests need, then runs `cargo test --workspace` with
//! `MESHLAB_FULL_TESTS=1`, under which every skip is a failure (as under
//! `CI=true`). Crates are fetched by cargo itself, online: nothing relies on
//! a warm cache.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

const USAGE: &str = "usage: cargo xtask test [ARGS FOR cargo test...]

Runs every test of the workspace, with nothing skipped:
  - finds Chromium ($CHROMIUM, else `chromium` or `chromium-browser` on the
    PATH), or installs Debian's `chromium` package with apt-get when run as
    root; otherwise stops and says what to install;
  - runs `cargo test --workspace ARGS` with MESHLAB_FULL_TESTS=1 and
    CHROMIUM set, so that a test that cannot run its check fails.";

fn main() -> ExitCode {
    let args: Vec<OsString> = std::env::args_os().skip(1).collect();
    match args.first().and_then(|a| a.to_str()) {
        Some("test") => match test(&args[1..]) {
            Ok(code) => code,
            Err(message) => {
                eprintln!("xtask: {message}");
                ExitCode::FAILURE
            }
        },
        Some("-h" | "--help" | "help") => {
            println!("{USAGE}");
            ExitCode::SUCCESS
        }
        _ => {
            eprintln!("{USAGE}");
            ExitCode::from(2)
        }
    }
}

fn test(extra: &[OsString]) -> Result<ExitCode, String> {
    let chromium = find_chromium().map_or_else(install_chromium, Ok)?;
    eprintln!(
        "xtask: Chromium for the report tests: {}",
        chromium.display()
    );
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask sits in the workspace");
    eprintln!("xtask: cargo test --workspace (MESHLAB_FULL_TESTS=1: a skipped check fails)");
    let status = Command::new(&cargo)
        .current_dir(root)
        .args(["test", "--workspace"])
        .args(extra)
        .env("MESHLAB_FULL_TESTS", "1")
        .env("CHROMIUM", &chromium)
        .status()
        .map_err(|e| format!("cannot start {}: {e}", cargo.to_string_lossy()))?;
    Ok(match status.code() {
        Some(0) => ExitCode::SUCCESS,
        Some(c) => ExitCode::from(u8::try_from(c).unwrap_or(1)),
        None => ExitCode::FAILURE,
    })
}

/// `$CHROMIUM` if set (it must exist), else the first `chromium` or
/// `chromium-browser` on the PATH.
fn find_chromium() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|dir| ["chromium", "chromium-browser"].map(|name| dir.join(name)))
        .find(|exe| exe.is_file())
}

fn is_root() -> bool {
    // Without a libc binding: the effective uid is in /proc/self/status.
    std::fs::read_to_string("/proc/self/status").is_ok_and(|s| {
        s.lines()
            .find_map(|l| l.strip_prefix("Uid:"))
            .and_then(|ids| ids.split_whitespace().nth(1))
            == Some("0")
    })
}

/// Installs Debian's `chromium` with apt-get, where this runs as root on a
/// machine that has apt-get; elsewhere an error that says what to do.
fn install_chromium() -> Result<PathBuf, String> {
    const HOW: &str = "the report tests load the report page in a real browser and no Chromium \
        was found: install it (Debian/Ubuntu: `apt-get install chromium`, as root) or set \
        CHROMIUM=/path/to/chrome-or-chromium, then run `cargo xtask test` again";
    let apt = Path::new("/usr/bin/apt-get");
    if !is_root() || !apt.is_file() {
        return Err(HOW.to_string());
    }
    eprintln!("xtask: no Chromium found; installing Debian's `chromium` package with apt-get");
    for args in [&["update"][..], &["install", "-y", "chromium"]] {
        let status = Command::new(apt)
            .args(args)
            .env("DEBIAN_FRONTEND", "noninteractive")
            .status()
            .map_err(|e| format!("cannot start apt-get: {e}"))?;
        if !status.success() {
            return Err(format!(
                "`apt-get {}` failed ({status}); {HOW}",
                args.join(" ")
            ));
        }
    }
    find_chromium()
        .ok_or_else(|| format!("apt-get installed chromium, but it is not on the PATH; {HOW}"))
}
