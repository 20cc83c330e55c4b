#!/usr/bin/env bash
# The reference's loop_subdivide against OpenMesh's LoopT and libigl's
# igl::loop, interleaved, in one command (docs/performance.md quotes it).
#
# What it installs (it says so again as it goes; SKIP_INSTALL=1 skips it):
#   - Debian's libopenmesh-dev and g++ (apt-get; as root, or with sudo);
#   - the PyPI wheel libigl (pip install --user when not root), which
#     brings numpy.
# What it builds, in target/peers/ (never part of the cargo workspace):
#   - om_loop from om_loop.cpp with g++ -std=c++17 -O2 -DNDEBUG, the flags of
#     CMake's Release build type (OpenMesh's assertions off);
#   - the reference in cargo's release profile (cargo build --release).
# Then it writes icosphere(6) (81,920 faces) as OBJ with `reference bench
# --peers` and runs compare.py: TRIALS trials (default 7) of 1 and 2 rounds.
#
# Usage: reference/bench/peers/run.sh [TRIALS]   (from anywhere in the lab)
# Environment: LEVEL (default 6), ROUNDS (default 1,2), SKIP_INSTALL=1, NO_LIBIGL=1,
#   PREFAULT_CHECK=1 (also builds prefault_shim.so with gcc and runs the reference
#   without its prefault and OpenMesh with the shim's: see compare.py).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
trials="${1:-7}"
level="${LEVEL:-6}"
rounds="${ROUNDS:-1,2}"
out="$root/target/peers"
mkdir -p "$out"

as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }

if [ "${SKIP_INSTALL:-0}" != 1 ]; then
    if ! dpkg -s libopenmesh-dev >/dev/null 2>&1 || ! command -v g++ >/dev/null; then
        echo "run.sh: installing Debian's libopenmesh-dev and g++ (apt-get)" >&2
        as_root apt-get update -qq
        as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libopenmesh-dev g++ >&2
    fi
    if [ "${NO_LIBIGL:-0}" != 1 ] && ! python3 -c "import igl" 2>/dev/null; then
        echo "run.sh: installing the PyPI wheel libigl (pip install libigl)" >&2
        if [ "$(id -u)" = 0 ]; then pip3 install -q libigl >&2; else pip3 install -q --user libigl >&2; fi
    fi
fi

om_flags="-std=c++17 -O2 -DNDEBUG"
echo "run.sh: building om_loop: g++ $om_flags" >&2
# shellcheck disable=SC2086
g++ $om_flags "$here/om_loop.cpp" -lOpenMeshTools -lOpenMeshCore -o "$out/om_loop"
echo "run.sh: building the reference: cargo build --release -p reference" >&2
(cd "$root" && cargo build --release --quiet -p reference)
ref="$root/target/release/reference"
"$ref" bench --peers --levels "$level" --obj-dir "$out" >/dev/null
obj="$out/icosphere-$level.obj"

om_version="$(dpkg-query -W -f='${Version}' libopenmesh-dev 2>/dev/null || echo unknown)"
gxx_version="$(g++ -dumpfullversion)"
rustc_version="$(cd "$root" && rustc --version)"
args=(--obj "$obj" --trials "$trials" --rounds "$rounds" --reference "$ref" --openmesh "$out/om_loop"
      --flags "reference: $rustc_version, cargo release profile (opt-level 3, fat LTO, codegen-units 1, debug-assertions off)"
      --flags "OpenMesh: libopenmesh-dev $om_version (Debian's build of the libraries), driver g++ $gxx_version $om_flags, TriMesh_ArrayKernelT<>, LoopT attach + operator()(rounds) + detach")
if [ "${NO_LIBIGL:-0}" != 1 ]; then
    igl_version="$(python3 -c 'import importlib.metadata as m; print(m.version("libigl"))')"
    args+=(--libigl "$here/igl_loop.py"
           --flags "libigl: PyPI wheel libigl $igl_version (its own release build of igl::loop), $(python3 --version), float64 V, int64 F, copies in and out included")
fi
if [ "${PREFAULT_CHECK:-0}" = 1 ]; then
    echo "run.sh: building prefault_shim.so: gcc -O2 -shared -fPIC" >&2
    gcc -O2 -shared -fPIC -o "$out/prefault_shim.so" "$here/prefault_shim.c" -ldl
    args+=(--prefault-shim "$out/prefault_shim.so"
           --flags "ref-4k: the same reference binary with bench --no-prefault"
           --flags "OM+prefault: the same om_loop with LD_PRELOAD=prefault_shim.so (gcc $gxx_version -O2)")
fi
exec python3 "$here/compare.py" "${args[@]}"
