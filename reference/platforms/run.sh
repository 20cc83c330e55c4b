#!/bin/sh
# PrairieLearn's external grader for the mesh lab: the question's
# `entrypoint`. The student's file is in /grade/student, this folder
# (serverFilesCourse/meshlab/, written by `cargo run -p reference --
# prairielearn DIR`) holds lab/ (the lab with the autograde crate, without
# the solution or the hidden cases) and fixtures/ (every case, hidden ones
# included, outside the lab the student's build may read). It builds the
# autograde program from that lab, which builds the student's file locked
# in, grades it and writes /grade/results/results.json.
# For tests: MESHLAB_GRADE_ROOT replaces /grade, MESHLAB_AUTOGRADE_TARGET
# is the autograde program's target folder, MESHLAB_VENDOR the vendored
# crates.
set -eu
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="${MESHLAB_GRADE_ROOT:-/grade}"
TARGET="${MESHLAB_AUTOGRADE_TARGET:-$HERE/target}"
VENDOR="${MESHLAB_VENDOR:-$HERE/vendor}"
cd "$HERE/lab"
# The dependencies' sources, for the locked-in build (which has no network).
[ -d "$VENDOR" ] || cargo vendor --locked --quiet "$VENDOR" >/dev/null
cargo build --locked --quiet -p autograde --target-dir "$TARGET"
MESHLAB_VENDOR="$VENDOR" exec "$TARGET/debug/autograde" prairielearn \
  --lab "$HERE/lab" --fixtures "$HERE/fixtures" --root "$ROOT"
