#!/usr/bin/env python3
"""Classroom 50's autograder for the mesh lab.

Classroom 50's runner runs this once per submission, in the student's
checkout, with the bundle's other files beside it (Path(__file__).parent):
lab/, the lab with its visible fixtures and the `autograde` crate, written
by `cargo run -p reference -- classroom50 DIR`. It builds the autograde
program from that lab (never the student's copy of the grader or the
fixtures), which takes the student's crates/meshedit/src/lib.rs from the
checkout, builds it locked in, grades it and writes ./result.json
(classroom50/result/v1) with one test per function worth its cases.

Exit 0 whenever a result was written, whatever the score; non-zero only
when the autograder itself could not run (the runner then records an
error). For tests, MESHLAB_AUTOGRADE_TARGET is the autograde program's
target folder and MESHLAB_VENDOR the vendored crates.
"""

import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
LAB = HERE / "lab"
VENDOR = Path(os.environ.get("MESHLAB_VENDOR") or HERE / "vendor")
TARGET = Path(os.environ.get("MESHLAB_AUTOGRADE_TARGET") or HERE / "target")


def run(args, what):
    done = subprocess.run([str(a) for a in args], cwd=LAB)
    if done.returncode != 0:
        print(f"::error::{what} failed (exit {done.returncode})", file=sys.stderr)
        sys.exit(1)


# The dependencies' sources, for the locked-in build (which has no network).
if not VENDOR.is_dir():
    run(["cargo", "vendor", "--locked", "--quiet", VENDOR], "cargo vendor")
run(["cargo", "build", "--locked", "--quiet", "-p", "autograde", "--target-dir", TARGET],
    "building the autograder")
autograde = TARGET / "debug" / "autograde"
os.execv(autograde, [str(autograde), "classroom50", "--lab", str(LAB)])
