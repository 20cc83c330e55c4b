#!/bin/sh
# PrairieLearn's external grader for the mesh lab: the question's
# `entrypoint`. The student's file is in /grade/student, this folder
# (serverFilesCourse/meshlab/, written by `cargo run -p reference --
# prairielearn DIR`) holds lab/ (the lab with the autograde crate, without
# the solution or the hidden cases) and fixtures/ (every case, hidden ones
# included, outside the lab the student's build may read). It builds the
# autograde program from that lab, which builds the student's file locked
# in, grades it and writes /grade/results/results.json.
#
# The autograder's own build reads no configuration but this bundle's:
# cargo reads .cargo/config.toml in the lab and in every folder above it
# (refused: none of them may have one; the upload is not among them) and
# wrappers, flags and linkers from the environment (removed); it builds
# offline from the vendored crates with a CARGO_HOME of its own.
#
# For tests: MESHLAB_GRADE_ROOT replaces /grade, MESHLAB_AUTOGRADE_TARGET
# is the autograde program's target folder, MESHLAB_VENDOR the vendored
# crates.
set -eu
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="${MESHLAB_GRADE_ROOT:-/grade}"
TARGET="${MESHLAB_AUTOGRADE_TARGET:-$HERE/target}"
VENDOR="${MESHLAB_VENDOR:-$HERE/vendor}"
# The image's, for its registry cache (`cargo vendor` below).
REGISTRY_HOME="${CARGO_HOME:-$HOME/.cargo}"
dir="$HERE/lab"
while :; do
  for config in "$dir/.cargo/config.toml" "$dir/.cargo/config"; do
    if [ -e "$config" ] || [ -L "$config" ]; then
      echo "run.sh: $config would configure the autograder's build: remove it" >&2
      exit 1
    fi
  done
  [ "$dir" = / ] && break
  dir="$(dirname "$dir")"
done
for var in $(env | sed -n 's/^\(CARGO[A-Za-z0-9_]*\|RUSTC[A-Za-z0-9_]*\|RUSTDOC[A-Za-z0-9_]*\|RUSTFLAGS\)=.*/\1/p'); do
  unset "$var"
done
OWN_HOME="$(mktemp -d "${TMPDIR:-/tmp}/meshlab-cargo-home-XXXXXX")"
trap 'rm -rf "$OWN_HOME"' EXIT
printf '[source.crates-io]\nreplace-with = "meshlab-vendored"\n[source.meshlab-vendored]\ndirectory = "%s"\n[net]\noffline = true\n' \
  "$VENDOR" > "$OWN_HOME/config.toml"
cd "$HERE/lab"
# The dependencies' sources, for the locked-in build (which has no network).
[ -d "$VENDOR" ] || CARGO_HOME="$REGISTRY_HOME" cargo vendor --locked --quiet "$VENDOR" >/dev/null
CARGO_HOME="$OWN_HOME" cargo build --locked --offline --quiet -p autograde --target-dir "$TARGET"
MESHLAB_VENDOR="$VENDOR" "$TARGET/debug/autograde" prairielearn \
  --lab "$HERE/lab" --fixtures "$HERE/fixtures" --root "$ROOT"
