#!/usr/bin/python3
"""Load benchmark of meshio's readers, the counterpart of bench/io_load.c (run by bench/run.sh).

    /usr/bin/python3 bench/io_meshio.py [directory] [runs]

Times meshio.read on the files bench/io_load.c wrote (default directory build/bench; OBJ and
binary little-endian PLY), wall clock, file reading included, median of RUNS runs (default 3),
and prints one line per format on stdout: format,triangles,reader,median_s,runs,median_cpu_s
(reader is "meshio X.Y.Z"; median_cpu_s the median of the process CPU time of the same runs).
The individual runs go to stderr.
"""
import os
import statistics
import sys
import time

import meshio

FILES = [("obj", "io_load.obj"), ("ply_binary_le", "io_load_le.ply")]


def main(argv):
    directory = argv[1] if len(argv) > 1 else "build/bench"
    runs = int(argv[2]) if len(argv) > 2 else 3
    for name, fname in FILES:
        path = os.path.join(directory, fname)
        times = []
        cpu_times = []
        triangles = None
        for k in range(runs):
            c0, t0 = time.process_time(), time.perf_counter()
            mesh = meshio.read(path)
            t1, c1 = time.perf_counter(), time.process_time()
            times.append(t1 - t0)
            cpu_times.append(c1 - c0)
            n = sum(len(c.data) for c in mesh.cells if c.type == "triangle")
            if triangles is not None and n != triangles:
                raise SystemExit("io_meshio: %s gave %d then %d triangles" % (path, triangles, n))
            triangles = n
            del mesh
            print("io_meshio: meshio %s run %d: %.4f s (cpu %.4f s)" % (name, k + 1, times[-1], cpu_times[-1]),
                  file=sys.stderr)
        print("%s,%d,meshio %s,%.6f,%d,%.6f" % (name, triangles, meshio.__version__, statistics.median(times), runs,
                                               statistics.median(cpu_times)))
        sys.stdout.flush()


if __name__ == "__main__":
    main(sys.argv)
