"""Wall time of `fpd run default --set output.vtk_every=N` (target:
N = 1, i.e. 39 991 frames and 160 000 files, in under 60 s), best of R runs,
with the run's CPU time (user + system: the system part is creating the
files) and the same run without VTK for reference.

    python3 benchmarks/vtk_series.py [N] [R] [OUT_PARENT]
"""
from __future__ import annotations

import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def run(every: int, out: str) -> tuple[float, float]:
    env = dict(os.environ, PYTHONPATH=ROOT, OPENBLAS_NUM_THREADS="1")
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "fpd", "run", "default", "--set", f"output.vtk_every={every}",
                    "--out", out, "--force", "--quiet"], env=env, check=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    shutil.rmtree(out)
    return wall, cpu


def main():
    every = int(sys.argv[1]) if len(sys.argv) > 1 else 1
    reps = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    parent = sys.argv[3] if len(sys.argv) > 3 else None
    with tempfile.TemporaryDirectory(dir=parent) as tmp:
        out = os.path.join(tmp, "run")
        for n in (0, every):
            best = min((run(n, out) for _ in range(reps)), key=lambda x: x[0])
            print(f"vtk_every = {n}: best wall {best[0]:.1f} s (cpu {best[1]:.1f} s) of {reps}")
    print(f"load average now: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
