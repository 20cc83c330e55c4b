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
"""

import argparse
import os
import platform
import statistics
import subprocess
import sys


def run(cmd):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
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
    a = p.parse_args()

    drivers = [
        ("reference", [a.reference, "bench", "--peers", "--peer-obj", a.obj, "--rounds"]),
        ("OpenMesh", [a.openmesh, a.obj]),
    ]
    if a.libigl:
        drivers.append(("libigl", [sys.executable, a.libigl, a.obj]))
    peers = [name for name, _ in drivers[1:]]

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
        head = ["trial"] + [f"{n} cpu ms" for n, _ in drivers] + [f"ref/{n} cpu" for n in peers] \
            + [f"ref/{n} wall" for n in peers]
        print(" | ".join(head))
        rows = []
        for trial in range(a.trials):
            order = drivers[trial % len(drivers):] + drivers[:trial % len(drivers)]
            got = {}
            for name, cmd in order:
                got[name] = run(cmd + [str(rounds)])
            faces = {int(g["faces"]) for g in got.values()}
            if len(faces) != 1:
                sys.exit(f"the drivers disagree on the output's face count: {got}")
            rows.append(got)
            ref = got["reference"]
            cells = [str(trial + 1)] + [f"{got[n]['cpu_ms']:.1f}" for n, _ in drivers] \
                + [f"{ref['cpu_ms'] / got[n]['cpu_ms']:.3f}" for n in peers] \
                + [f"{ref['wall_ms'] / got[n]['wall_ms']:.3f}" for n in peers]
            print(" | ".join(cells), flush=True)
        print(f"output faces: {int(rows[0]['reference']['faces'])}; "
              f"load average now: {load()}")
        print("min / median / max:")
        for name, _ in drivers:
            cpu = [r[name]["cpu_ms"] for r in rows]
            wall = [r[name]["wall_ms"] for r in rows]
            rss = [r[name]["maxrss_kb"] / 1024 for r in rows]
            print(f"  {name:<9} cpu ms {spread(cpu)}; wall ms {spread(wall)}; "
                  f"peak RSS MB {statistics.median(rss):.0f}")
        heap = [r["reference"]["heap_b_per_face"] for r in rows]
        print(f"  reference peak heap per output face: {max(heap):.0f} B")
        for n in peers:
            cpu = [r["reference"]["cpu_ms"] / r[n]["cpu_ms"] for r in rows]
            wall = [r["reference"]["wall_ms"] / r[n]["wall_ms"] for r in rows]
            print(f"  reference/{n:<9} cpu {spread(cpu)}; wall {spread(wall)}")


if __name__ == "__main__":
    main()
