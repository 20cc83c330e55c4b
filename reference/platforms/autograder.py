#!/usr/bin/env python3
"""Classroom 50's autograder for the mesh lab.

Classroom 50's runner runs this once per submission, in the student's
checkout, with the bundle's other files beside it (Path(__file__).parent):
lab/, the lab with its visible fixtures and the `autograde` crate, and
lab.sha256, the list of lab/'s files with their SHA-256, both written by
`cargo run -p reference -- classroom50 DIR`.

Nothing trusted runs inside the checkout, wherever the bundle was unpacked
(the runner puts it in $RUNNER_TEMP; a copy inside the checkout must be as
safe). Cargo reads `.cargo/config.toml` in its working folder and every
folder above it: a student's `build.rustc-wrapper` there would run as the
runner. So the listed files of lab/ (and only those: a student's file
planted beside them is left behind) are copied to a new private folder
outside the checkout, checked against their SHA-256; the autograde program
is built there, offline from crates vendored there, with a CARGO_HOME of
its own and none of the caller's cargo or rustc settings. It then takes the
student's crates/meshedit/src/lib.rs from the checkout, builds it locked in
(in that same private lab), grades it and writes ./result.json
(classroom50/result/v1) with one test per function worth its cases; its
`datetime` is the runner's clock when grading ran.

Exit 0 whenever a result was written, whatever the score; non-zero only
when the autograder itself could not run (the runner then records an
error). For tests, MESHLAB_AUTOGRADE_TARGET is the autograde program's
target folder and MESHLAB_VENDOR the vendored crates.
"""

import hashlib
import json
import os
import shutil
import stat
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
LAB = HERE / "lab"
MANIFEST = HERE / "lab.sha256"
CHECKOUT = Path.cwd().resolve()
CARGO_CONFIGS = ("config.toml", "config")


def fail(message):
    print(f"::error::{message}", file=sys.stderr)
    sys.exit(1)


def inside(path, folder):
    return path == folder or folder in path.parents


def cargo_config_above(folder):
    """A `.cargo` config cargo would read from `folder` or a folder above it."""
    for parent in [folder, *folder.parents]:
        for name in CARGO_CONFIGS:
            config = parent / ".cargo" / name
            if os.path.lexists(config):
                return config
    return None


def private_folder():
    """A new folder only this user may enter, outside the checkout, under
    which no `.cargo` config of anyone's is read: `meshlab-autograder` in
    the runner's own temporary folder (the same path each run, so a kept
    target folder finds its build there), else a new one in TMPDIR."""
    runner_temp = os.environ.get("RUNNER_TEMP")
    if runner_temp:
        work = Path(runner_temp).resolve() / "meshlab-autograder"
        if work.is_symlink() or work.is_file():
            work.unlink()
        elif work.exists():
            shutil.rmtree(work)
        work.mkdir(mode=0o700)
    else:
        work = Path(tempfile.mkdtemp(prefix="meshlab-autograder-")).resolve()
    if inside(work, CHECKOUT):
        shutil.rmtree(work, ignore_errors=True)
        fail(f"the temporary folder {work} is inside the checkout {CHECKOUT}: set RUNNER_TEMP "
             "(or TMPDIR) to a folder outside it")
    config = cargo_config_above(work)
    if config is not None:
        shutil.rmtree(work, ignore_errors=True)
        fail(f"{config} would configure the autograder's build: remove it, or set RUNNER_TEMP "
             "(or TMPDIR) to a folder without one above it")
    return work


def copy_lab(to):
    """lab/'s listed files into `to`, each a regular file (never a link)
    with the SHA-256 the bundle lists."""
    try:
        lines = MANIFEST.read_text(encoding="utf-8").splitlines()
    except OSError as e:
        fail(f"{MANIFEST}: {e} (write the bundle again with `reference classroom50`)")
    for line in lines:
        digest, _, rel = line.partition("  ")
        parts = Path(rel).parts
        if len(digest) != 64 or not parts or any(p in ("", ".", "..") for p in parts) \
                or Path(rel).is_absolute():
            fail(f"{MANIFEST}: not a line of the bundle's list: {line!r}")
        source = LAB / rel
        try:
            fd = os.open(source, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
        except OSError as e:
            fail(f"{source}: {e}")
        with os.fdopen(fd, "rb") as f:
            info = os.fstat(f.fileno())
            if not stat.S_ISREG(info.st_mode):
                fail(f"{source} is not a regular file")
            data = f.read()
        if hashlib.sha256(data).hexdigest() != digest:
            fail(f"{source} is not the bundle's file (its SHA-256 differs from lab.sha256)")
        for parent in source.relative_to(LAB).parents:
            if (LAB / parent).is_symlink():
                fail(f"{LAB / parent} is a link: the bundle has none")
        target = to / rel
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(data)
        os.chmod(target, info.st_mode & 0o755)
        # The bundle's times: a kept target folder rebuilds nothing.
        os.utime(target, ns=(info.st_atime_ns, info.st_mtime_ns))


def cargo_env(cargo_home=None):
    """The caller's environment without its cargo and rustc settings (a
    wrapper, flags, a linker, another target folder), rustup's kept."""
    env = {k: v for k, v in os.environ.items()
           if not (k.startswith("CARGO") or k.startswith("RUSTC") or k.startswith("RUSTDOC")
                   or k in ("RUSTFLAGS", "RUST_LOG"))}
    if cargo_home is not None:
        env["CARGO_HOME"] = str(cargo_home)
    else:
        # The runner's own (the registry's cache for `cargo vendor`).
        home = os.environ.get("CARGO_HOME")
        if home:
            env["CARGO_HOME"] = home
    return env


def run(args, what, cwd, env):
    done = subprocess.run([str(a) for a in args], cwd=cwd, env=env, stdin=subprocess.DEVNULL)
    if done.returncode != 0:
        fail(f"{what} failed (exit {done.returncode})")


def main():
    work = private_folder()
    try:
        lab = work / "lab"
        copy_lab(lab)
        vendor = Path(os.environ.get("MESHLAB_VENDOR") or work / "vendor")
        target = Path(os.environ.get("MESHLAB_AUTOGRADE_TARGET") or work / "target")
        # The dependencies' sources, for the locked-in build (which has no
        # network), from the runner's registry or crates.io.
        if not vendor.is_dir():
            run(["cargo", "vendor", "--locked", "--quiet", vendor], "cargo vendor", lab,
                cargo_env())
        # The autograder's cargo reads this config and the lab's folders
        # only: checked above, none of them is the student's.
        home = work / "cargo-home"
        home.mkdir()
        (home / "config.toml").write_text(
            "[source.crates-io]\nreplace-with = \"meshlab-vendored\"\n"
            f"[source.meshlab-vendored]\ndirectory = {json.dumps(str(vendor))}\n"
            "[net]\noffline = true\n")
        run(["cargo", "build", "--locked", "--offline", "--quiet", "-p", "autograde",
             "--target-dir", target], "building the autograder", lab, cargo_env(home))
        autograde = target / "debug" / "autograde"
        env = cargo_env()
        env["MESHLAB_VENDOR"] = str(vendor)
        done = subprocess.run([str(autograde), "classroom50", "--lab", str(lab)], env=env,
                              stdin=subprocess.DEVNULL)
        return done.returncode
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
