"""The acceptance measurement of the FEMA P695 far-field set (44 components) on the
default scene (two-phase + fe1d, dt = 1 ms) as an ``fpd sweep``.

Measures, each the best of --repeat runs of the whole command in a fresh
process (wall clock, the LocalCluster's start included):
- 2 local workers: target <= 40 s;
- 1 worker: the speed-up 1 -> 2 workers, target >= 1.6;
- a rerun with nothing new to do: target <= 5 s.

    python benchmarks/sweep_p695.py [--repeat 3] [--out /tmp/p695-bench]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SWEEP = """name = "p695-far-field-default"
description = "FEMA P695 far-field set (44 components, normalised) on the default scene"
scene = "default"
[axes]
"loading.record_set" = ["p695-far-field"]
"""


def timed(args, env) -> float:
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "fpd", *args], env=env, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if r.returncode != 0:
        sys.exit(f"fpd {' '.join(args)} failed ({r.returncode}): {r.stderr}")
    return dt


def _burn(n: int) -> float:
    t = time.perf_counter()
    x = 0
    for i in range(n):
        x += i * i
    return time.perf_counter() - t


def machine_scaling(n: int = 10_000_000) -> float:
    """Throughput of 2 plain processes over 1 on this machine, now (a shared
    machine may not have a second core to give): the ceiling any 2-worker
    speed-up measured at the same time can reach."""
    import multiprocessing as mp
    with mp.get_context("spawn").Pool(2) as pool:
        pool.map(_burn, [10, 10])
        one = min(_burn(n) for _ in range(2))
        t0 = time.perf_counter()
        pool.map(_burn, [n, n])
        two = time.perf_counter() - t0
    return 2 * one / two


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    work = Path(a.out or tempfile.mkdtemp(prefix="fpd-p695-bench-"))
    work.mkdir(parents=True, exist_ok=True)
    sweep = work / "p695.toml"
    sweep.write_text(SWEEP)
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    base = ["sweep", str(sweep), "--quiet", "--force"]
    # warm numba's on-disk cache and the OS file cache once (not timed)
    timed(base + ["--out", str(work / "warm"), "--workers", "2"], env)
    # 2 and 1 workers interleaved, so that both see the same background load
    # (on a shared machine the load drifts over minutes); each pair gives a ratio
    scaling = [machine_scaling()]
    times = {2: [], 1: []}
    load = []
    for _ in range(a.repeat):
        for n in (2, 1):
            load.append(os.getloadavg()[0])
            times[n].append(timed(base + ["--out", str(work / f"w{n}"), "--workers", str(n)], env))
    res = {n: min(t) for n, t in times.items()}
    pairs = [t1 / t2 for t2, t1 in zip(times[2], times[1])]
    scaling.append(machine_scaling())
    rerun = min(timed(["sweep", str(sweep), "--quiet", "--out", str(work / "w2")], env) for _ in range(a.repeat))
    print(f"P695 far-field, 44 members, default scene; best of {a.repeat}; load average "
          f"{min(load):.1f}-{max(load):.1f} on {os.cpu_count()} cores during the runs")
    print(f"2 workers: {res[2]:.1f} s (target <= 40 s); all: {', '.join(f'{t:.1f}' for t in times[2])}")
    print(f"1 worker:  {res[1]:.1f} s; all: {', '.join(f'{t:.1f}' for t in times[1])}")
    print(f"speed-up, best against best: {res[1] / res[2]:.2f}; pair by pair: "
          f"{', '.join(f'{r:.2f}' for r in pairs)} (target >= 1.6)")
    print(f"the machine itself: 2 plain processes give {scaling[0]:.2f}x (before) and {scaling[1]:.2f}x (after) "
          "the throughput of 1 (the ceiling for the speed-up above)")
    print(f"rerun, nothing new: {rerun:.2f} s (target <= 5 s)")
    print(f"tables in {work / 'w2'}")


if __name__ == "__main__":
    main()
