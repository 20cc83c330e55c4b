"""Times libigl's Loop subdivision (`igl.loop`, the PyPI wheel `libigl`) on one
OBJ file: one timed call per process, as the interleaved comparison (run.sh,
compare.py) runs it. Reading the file and importing are not timed; the
bindings' copy of the arrays in and out is (a few ms at these sizes).

Run: python3 igl_loop.py MESH.obj ROUNDS
Prints one line: wall_ms=... cpu_ms=... faces=... maxrss_kb=...
"""

import resource
import sys
import time

import igl
import numpy as np


def read_obj(path):
    """The `v` and `f` lines only (the bench's files have nothing else)."""
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                faces.append([int(x.split("/")[0]) - 1 for x in parts[1:]])
    return np.array(vertices, dtype=np.float64), np.array(faces, dtype=np.int64)


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: igl_loop.py MESH.obj ROUNDS")
    v, f = read_obj(sys.argv[1])
    rounds = int(sys.argv[2])
    wall0, cpu0 = time.perf_counter(), time.process_time()
    _, out_f = igl.loop(v, f, rounds)
    cpu = (time.process_time() - cpu0) * 1e3
    wall = (time.perf_counter() - wall0) * 1e3
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(f"wall_ms={wall:.3f} cpu_ms={cpu:.3f} faces={len(out_f)} maxrss_kb={rss}")


if __name__ == "__main__":
    main()
