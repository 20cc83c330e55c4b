#!/usr/bin/env bash
# Gradescope runs this once, as root, when it builds the autograder image,
# from /autograder/source (where it unzipped the bundle: this file,
# run_autograder and lab/). Written by `cargo run -p reference -- gradescope`,
# which fills in the Rust version the TA built and tested the bundle with.
set -euo pipefail
RUST_VERSION="@RUST_VERSION@"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
echo "setup.sh: installing Debian's ca-certificates, curl, build-essential and python3"
apt-get update
apt-get install -y --no-install-recommends ca-certificates curl build-essential python3
# The toolchain outside /root, readable by everyone: the student's code is
# compiled as user nobody (see run_autograder), who cannot enter /root.
export RUSTUP_HOME=/usr/local/rustup CARGO_HOME=/usr/local/cargo
echo "setup.sh: installing Rust $RUST_VERSION (minimal profile) with rustup from sh.rustup.rs"
curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs |
  sh -s -- -y --no-modify-path --profile minimal --default-toolchain "$RUST_VERSION"
export PATH="$CARGO_HOME/bin:$PATH"
chmod -R a+rX "$RUSTUP_HOME" "$CARGO_HOME"
cd "$HERE/lab"
# The lab's rust-toolchain.toml names a channel; grade with exactly the
# version the bundle was made with (a directory override wins over the file).
rustup override set "$RUST_VERSION"
# Download the dependencies now: grading needs no network. `cargo fetch`
# without --target takes every platform's crates (the Windows-only ones
# too), which `cargo vendor` below needs; it names each crate it downloads.
echo "setup.sh: downloading the lab's crates from crates.io (Cargo.lock, every platform)"
cargo fetch --locked
# Moves the hidden cases out of the lab into a folder only root may read,
# vendors the dependencies, prepares the build user's folders and builds
# everything once as that user (each submission then compiles only the
# student's crate and the grader).
python3 "$HERE/run_autograder" --setup
