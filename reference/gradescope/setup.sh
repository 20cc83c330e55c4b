#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder image.
# Written by `cargo run -p reference -- gradescope`, which fills in the Rust
# version the TA built and tested the bundle with.
set -euo pipefail
RUST_VERSION="@RUST_VERSION@"
apt-get update
apt-get install -y --no-install-recommends ca-certificates curl build-essential python3
curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs |
  sh -s -- -y --profile minimal --default-toolchain "$RUST_VERSION"
. "$HOME/.cargo/env"
cd /autograder/source
# The lab's rust-toolchain.toml names a channel; grade with exactly the
# version the bundle was made with (a directory override wins over the file).
rustup override set "$RUST_VERSION"
# Only root may read the hidden cases: the grader's child process, which runs
# the student's code, drops to an unprivileged user.
chown -R root:root fixtures/hidden
chmod -R go-rwx fixtures/hidden
# Fetch and build everything once now, so each submission compiles only the
# student's crate and needs no network.
cargo fetch
cargo build -p grader
