"""The interleaved comparison of the reference's `loop_subdivide` with its
peers (run by run.sh, which builds and installs everything first).

Each trial runs, for 1 and then 2 rounds, every driver once in its own fresh
process on the same OBJ file, in an order that rotates from trial to trial
(so no library always runs right after another or first on a quiet core).
Each driver times only the subdivision call and prints
`wall_ms=... cpu_ms=... faces=... maxrss_kb=...`. The table gives each
trial's figures and ratios reference/peer, then min, median and max.
CPU time is the process's own (every thread): on a shared machine the wall
clock also counts waiting for a core, so ratios are taken on CPU time, and
the wall-clock ratios are printed beside them.

With --prefault-shim two more drivers run: `ref-4k`, the reference without
its prefault (`bench --no-prefault`), and `OM+prefault`, OpenMesh's driver
with the same advice given by an LD_PRELOAD shim: reference/ref-4k is what
the prefault is worth, reference/OM+prefault the ratio with it for both.
"""

import argparse
import os
import platform
import statistics
import subprocess
import sys


def run(cmd, env):
    env = None if env is None else {**os.environ, **env}
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, env=env).stdout
    line = [l for l in out.splitlines() if l.startswith("wall_ms=")][-1]
    return {k: float(v) for k, v in (kv.split("=") for kv in line.split())}


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def spread(xs):
    return f"{min(xs):.3f} / {statistics.median(xs):.3f} / {max(xs):.3f}"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--obj", required=True)
    p.add_argument("--trials", type=int, default=7)
    p.add_argument("--rounds", default="1,2")
    p.add_argument("--reference", required=True, help="the release `reference` binary")
    p.add_argument("--openmesh", required=True, help="the built om_loop")
    p.add_argument("--libigl", help="igl_loop.py (left out if not given)")
    p.add_argument("--flags", action="append", default=[], help="NAME: how it was built")
    p.add_argument("--prefault-shim", help="prefault_shim.so: add ref-4k and OM+prefault")
    a = p.parse_args()

    # (name, command without the rounds, environment added or None)
    drivers = [
        ("reference", [a.reference, "bench", "--peers", "--peer-obj", a.obj, "--rounds"], None),
        ("OpenMesh", [a.openmesh, a.obj], None),
    ]
    if a.libigl:
        drivers.append(("libigl", [sys.executable, a.libigl, a.obj], None))
    if a.prefault_shim:
        drivers.append(("ref-4k", [a.reference, "bench", "--peers", "--no-prefault",
                                   "--peer-obj", a.obj, "--rounds"], None))
        drivers.append(("OM+prefault", [a.openmesh, a.obj],
                        {"LD_PRELOAD": os.path.abspath(a.prefault_shim)}))
    peers = [name for name, _, _ in drivers[1:]]

    print(f"machine: {cpu_model()}, {os.cpu_count()} logical cores, {platform.system()} "
          f"{platform.machine()}, kernel {platform.release()}")
    print(f"input: {a.obj}; {a.trials} trials, each driver once per trial and round count, "
          f"order rotating; only the subdivision call timed")
    for f in a.flags:
        print(f"build: {f}")
    print(f"load average at start: {load()}")

    for rounds in [int(r) for r in a.rounds.split(",")]:
        print()
        print(f"== {rounds} round{'s' if rounds > 1 else ''} ==")
        head = ["trial"] + [f"{n} cpu ms" for n, _, _ in drivers] + [f"ref/{n} cpu" for n in peers] \
            + [f"ref/{n} wall" for n in peers]
        print(" | ".join(head))
        rows = []
        for trial in range(a.trials):
            order = drivers[trial % len(drivers):] + drivers[:trial % len(drivers)]
            got = {}
            for name, cmd, env in order:
                got[name] = run(cmd + [str(rounds)], env)
            faces = {int(g["faces"]) for g in got.values()}
            if len(faces) != 1:
                sys.exit(f"the drivers disagree on the output's face count: {got}")
            rows.append(got)
            ref = got["reference"]
            cells = [str(trial + 1)] + [f"{got[n]['cpu_ms']:.1f}" for n, _, _ in drivers] \
                + [f"{ref['cpu_ms'] / got[n]['cpu_ms']:.3f}" for n in peers] \
                + [f"{ref['wall_ms'] / got[n]['wall_ms']:.3f}" for n in peers]
            print(" | ".join(cells), flush=True)
        print(f"output faces: {int(rows[0]['reference']['faces'])}; "
              f"load average now: {load()}")
        print("min / median / max:")
        for name, _, _ in drivers:
            cpu = [r[name]["cpu_ms"] for r in rows]
            wall = [r[name]["wall_ms"] for r in rows]
            rss = [r[name]["maxrss_kb"] / 1024 for r in rows]
            print(f"  {name:<11} cpu ms {spread(cpu)}; wall ms {spread(wall)}; "
                  f"peak RSS MB {statistics.median(rss):.0f}")
        heap = [r["reference"]["heap_b_per_face"] for r in rows]
        print(f"  reference peak heap per output face: {max(heap):.0f} B")
        for n in peers:
            cpu = [r["reference"]["cpu_ms"] / r[n]["cpu_ms"] for r in rows]
            wall = [r["reference"]["wall_ms"] / r[n]["wall_ms"] for r in rows]
            print(f"  reference/{n:<11} cpu {spread(cpu)}; wall {spread(wall)}")


if __name__ == "__main__":
    main()
