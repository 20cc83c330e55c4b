//! Readying a machine to grade on, once, before any student's code is
//! compiled: the hidden cases moved out of the lab's reach, the
//! dependencies vendored, a toolchain and a target folder the build user
//! (`nobody`, when run as root) can use, and the first locked-in build.
//! Gradescope's `run_autograder --setup` builds this program and runs
//! [`gradescope`] (`autograde gradescope-setup`); [`reachable_toolchain`]
//! and [`chown_tree`] are what any caller building as `nobody` needs.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::gradescope::{self, Places};
use crate::process;

/// The user the student's code is compiled as when this runs as root.
pub const BUILD_USER: &str = "nobody";
/// The fixture groups graded against; `hidden` is moved, the others copied.
const GROUPS: [&str; 3] = ["lab", "bonus", "hidden"];

fn io<T>(result: std::io::Result<T>, path: &Path) -> Result<T, String> {
    result.map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(unix)]
fn chmod(path: &Path, mode: u32) -> Result<(), String> {
    use std::os::unix::fs::PermissionsExt;
    io(
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)),
        path,
    )
}

#[cfg(unix)]
fn mode_of(path: &Path) -> Result<u32, String> {
    use std::os::unix::fs::PermissionsExt;
    Ok(io(std::fs::metadata(path), path)?.permissions().mode())
}

/// Whether user `ids` (uid, gid) can run `root/bin/cargo` (every folder
/// above it searchable, the files readable), from `/` with an empty
/// environment.
pub fn can_run_cargo(root: &Path, ids: (u32, u32)) -> bool {
    use std::os::unix::process::CommandExt;
    Command::new(root.join("bin/cargo"))
        .arg("-V")
        .current_dir("/")
        .env_clear()
        .env("PATH", "/usr/bin:/bin")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .uid(ids.0)
        .gid(ids.1)
        .status()
        .is_ok_and(|s| s.success())
}

/// A toolchain user `ids` can run: `sysroot` itself when it can, else a
/// copy of it in `copy` made of hard links where the file system allows
/// (the files stay the owner's and read-only to the user), plain copies
/// where it does not. Returns the toolchain's root and whether it is the
/// copy.
pub fn reachable_toolchain(
    sysroot: &Path,
    copy: &Path,
    ids: (u32, u32),
) -> Result<(PathBuf, bool), String> {
    if can_run_cargo(sysroot, ids) {
        return Ok((sysroot.to_path_buf(), false));
    }
    let _ = std::fs::remove_dir_all(copy);
    io(std::fs::create_dir_all(copy), copy)?;
    chmod(copy, 0o755)?;
    for part in ["bin", "lib", "libexec", "etc"] {
        let from = sysroot.join(part);
        if !from.is_dir() {
            continue;
        }
        let cp = |args: &[&str]| {
            Command::new("cp")
                .args(args)
                .arg(&from)
                .arg(copy.join(part))
                .stderr(Stdio::null())
                .status()
                .is_ok_and(|s| s.success())
        };
        if !cp(&["-a", "-l"]) {
            let _ = std::fs::remove_dir_all(copy.join(part));
            if !cp(&["-a"]) {
                return Err(format!(
                    "cannot copy {} for user {BUILD_USER}",
                    from.display()
                ));
            }
        }
    }
    if !can_run_cargo(copy, ids) {
        return Err(format!(
            "user {BUILD_USER} cannot run {}/bin/cargo, even from {}",
            sysroot.display(),
            copy.display()
        ));
    }
    Ok((copy.to_path_buf(), true))
}

/// Gives `path` and everything under it to user `ids`, links themselves
/// rather than what they point at.
pub fn chown_tree(path: &Path, ids: (u32, u32)) -> Result<(), String> {
    io(
        std::os::unix::fs::lchown(path, Some(ids.0), Some(ids.1)),
        path,
    )?;
    let meta = io(std::fs::symlink_metadata(path), path)?;
    if meta.is_dir() {
        for entry in io(std::fs::read_dir(path), path)? {
            chown_tree(&io(entry, path)?.path(), ids)?;
        }
    }
    Ok(())
}

/// (uid, gid) of [`BUILD_USER`], `nobody` (the grader's one reading of
/// it, `grader::isolate::sys::nobody`).
pub fn build_user_ids() -> Option<(u32, u32)> {
    Some(grader::isolate::sys::nobody())
}

/// Moves `from` to `to`: a rename, or a copy and a removal across file
/// systems.
fn move_tree(from: &Path, to: &Path) -> Result<(), String> {
    if std::fs::rename(from, to).is_ok() {
        return Ok(());
    }
    crate::copy_tree(from, to)?;
    io(std::fs::remove_dir_all(from), from)
}

/// 32 hex digits from the system's random source: a folder name nobody
/// can guess.
fn unguessable() -> Result<String, String> {
    use std::io::Read;
    let mut bytes = [0u8; 16];
    let random = Path::new("/dev/urandom");
    io(
        std::fs::File::open(random).and_then(|mut f| f.read_exact(&mut bytes)),
        random,
    )?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// Runs a setup command in `dir`, its standard output or its errors.
fn checked(cmd: &mut Command, what: &str) -> Result<String, String> {
    let out = cmd
        .output()
        .map_err(|e| format!("{what}: cannot run {:?}: {e}", cmd.get_program()))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let tail: String = err.trim().chars().rev().take(3000).collect();
        return Err(format!(
            "{what} failed ({}):\n{}",
            out.status,
            tail.chars().rev().collect::<String>()
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The folder the environment variable `key` names, unless it is unset or
/// empty (the tests' way to share folders between runs).
fn folder_from_env(key: &str) -> Option<PathBuf> {
    std::env::var_os(key)
        .filter(|dir| !dir.is_empty())
        .map(PathBuf::from)
}

/// Gradescope's setup, as root once per image (or as a TA trying the
/// bundle): the fixtures graded against in `meshlab/fixtures` (mode 700,
/// the hidden cases moved out of the lab), the bundle's fresh-case sets
/// beside them, the vendored dependencies, the build user's toolchain and
/// target folder (`MESHLAB_BUILD_TARGET`, else a new unguessable one; the
/// vendored crates in `MESHLAB_VENDOR`, else in `meshlab/vendor`: tests share
/// both with class grading's, so that the dependencies compile once),
/// `meshlab/settings.json`, and the first locked-in build. `log` gets
/// each step's line.
pub fn gradescope(places: &Places, log: &dyn Fn(&str)) -> Result<(), String> {
    let lab = places.lab();
    if !lab.join("Cargo.toml").is_file() {
        return Err(format!(
            "{} holds no Cargo.toml: unzip the bundle into {}",
            lab.display(),
            places.root.join("source").display()
        ));
    }
    let ids = if process::is_root() {
        Some(build_user_ids().ok_or(format!(
            "there is no user {BUILD_USER} to build the student's code as"
        ))?)
    } else {
        None
    };
    // The build user must reach the lab (to build it) and the programs
    // graded with (the grader drops the case child only if it can run
    // them): others may pass the folders above, not list them.
    for folder in [places.root.clone(), places.root.join("source")] {
        chmod(&folder, mode_of(&folder)? | 0o011)?;
    }
    let state = places.state();
    io(std::fs::create_dir_all(&state), &state)?;
    chmod(&state, 0o755)?;

    let fixtures = places.fixtures();
    io(std::fs::create_dir_all(&fixtures), &fixtures)?;
    chmod(&fixtures, 0o700)?;
    for group in GROUPS {
        let from = lab.join("fixtures").join(group);
        if !from.is_dir() {
            continue; // hidden/: moved by an earlier setup
        }
        let to = fixtures.join(group);
        let _ = std::fs::remove_dir_all(&to);
        if group == "hidden" {
            move_tree(&from, &to)?;
        } else {
            crate::copy_tree(&from, &to)?;
        }
    }
    if !fixtures.join("lab").is_dir() {
        return Err(format!("no fixtures/lab in {}", lab.display()));
    }
    let bundled = places.root.join("source/fresh");
    let fresh = places.fresh();
    if bundled.is_dir() {
        let _ = std::fs::remove_dir_all(&fresh);
        move_tree(&bundled, &fresh)?;
    }
    if fresh.is_dir() {
        chmod(&fresh, 0o700)?;
    }
    log(&format!(
        "fresh-case sets: {} (one per upload, chosen from its bytes)",
        gradescope::fresh_sets(places).len()
    ));
    log(&format!(
        "fixtures for grading in {} (mode 700); hidden cases: {}",
        fixtures.display(),
        if fixtures.join("hidden").is_dir() {
            "yes"
        } else {
            "none"
        }
    ));

    // The dependencies' sources, readable by the build user (root's cargo
    // home may not be); setup.sh fetched them.
    let vendor = folder_from_env("MESHLAB_VENDOR").unwrap_or_else(|| places.vendor());
    let vendor = io(std::path::absolute(&vendor), &vendor)?;
    let _ = std::fs::remove_dir_all(&vendor);
    checked(
        Command::new("cargo")
            .args(["vendor", "--locked", "--offline", "--quiet"])
            .arg(&vendor)
            .current_dir(&lab)
            .env_remove("CARGO_TARGET_DIR")
            .env_remove("RUSTC_WRAPPER"),
        "cargo vendor",
    )?;
    let sysroot = crate::local::sysroot(&lab)?;
    let toolchain = match ids {
        Some(ids) => {
            let (toolchain, copied) = reachable_toolchain(&sysroot, &state.join("toolchain"), ids)?;
            if copied {
                log(&format!(
                    "{} is out of {BUILD_USER}'s reach: linked into {}",
                    sysroot.display(),
                    toolchain.display()
                ));
            }
            toolchain
        }
        None => sysroot,
    };

    // The build's only writable folder, outside the lab, under a name
    // that leads nowhere (the student's code sees it in CARGO_TARGET_DIR).
    let target = match folder_from_env("MESHLAB_BUILD_TARGET") {
        Some(dir) => dir,
        None => {
            let var_tmp = Path::new("/var/tmp");
            let parent = if var_tmp.is_dir() { var_tmp } else { &state };
            parent.join(format!("meshlab-build-{}", unguessable()?))
        }
    };
    let target = io(std::path::absolute(&target), &target)?;
    for folder in [
        target.clone(),
        target.join("home/cargo"),
        target.join("tmp"),
    ] {
        io(std::fs::create_dir_all(&folder), &folder)?;
    }
    chmod(&target, 0o700)?;
    if let Some(ids) = ids {
        chown_tree(&target, ids)?;
    }
    let settings = serde_json::json!({
        "toolchain": toolchain,
        "target": target,
        "vendor": vendor,
        "user": ids.map(|_| BUILD_USER),
    });
    let path = places.settings();
    let text = serde_json::to_string_pretty(&settings).expect("JSON");
    io(std::fs::write(&path, text), &path)?;
    chmod(&path, 0o644)?;

    // Then the lab once, locked in as every submission's build will be,
    // so that each submission compiles only the student's crate and the
    // grader.
    for line in gradescope::warm(places)?.lines() {
        log(line);
    }
    Ok(())
}
