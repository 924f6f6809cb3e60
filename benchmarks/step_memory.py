"""Memory per step of a long run beyond its history: where it goes.

Runs the default scene (El Centro, two-phase stepper) with lumped plates (or
no heat, --thermal none) for N steps (solver.duration = N dt, the record
ending early and the ground at rest after it) with output.csv_every = 1000,
each N in a fresh process, and prints the peak resident memory (ru_maxrss)
and its growth per step between the two sizes. With --trace, one process
runs under tracemalloc and prints the allocation sites alive just before the
stepping starts and at the end of the run (the loading's arrays, the
stepper's copies), by bytes per step.

    python benchmarks/step_memory.py [--steps 1000000 4000000] [--thermal lumped] [--trace 1000000]
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def one(steps: int, thermal: str, trace: bool) -> dict:
    import resource
    import tracemalloc

    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate

    dt = 1e-3
    over = [f"thermal.model={json.dumps(thermal)}", f"solver.duration={steps * dt!r}", "output.csv_every=1000",
            "output.plots=false"]
    sc = scn.load("default", over)
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    if trace:
        tracemalloc.start(8)
    sim = build(sc)
    out = {"steps": sim.n_steps, "rss_before_build": base}
    if trace:
        snap_built = tracemalloc.take_snapshot()
        out["traced_after_build"] = tracemalloc.get_traced_memory()[0]
    res = simulate(sim, every=1000)
    out["status"] = res.status
    out["rss_peak"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    if trace:
        cur, peak = tracemalloc.get_traced_memory()
        out["traced_end"], out["traced_peak"] = cur, peak
        snap_end = tracemalloc.take_snapshot()
        n = sim.n_steps

        def top(snap, k=12):
            stats = snap.statistics("traceback")
            rows = []
            for st in stats[:k]:
                frames = [f"{Path(f.filename).name}:{f.lineno}" for f in st.traceback[-4:]]
                rows.append((st.size / n, " <- ".join(reversed(frames))))
            return rows
        out["sites_after_build"] = top(snap_built)
        out["sites_end"] = top(snap_end)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, nargs=2, default=[1_000_000, 4_000_000])
    ap.add_argument("--thermal", default="lumped")
    ap.add_argument("--trace", type=int, default=0, help="also one traced run of this many steps")
    ap.add_argument("--child", type=int, default=0, help=argparse.SUPPRESS)
    ap.add_argument("--child-trace", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        print(json.dumps(one(a.child, a.thermal, a.child_trace)))
        return
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")

    def child(n, trace=False):
        args = [sys.executable, __file__, "--child", str(n), "--thermal", a.thermal] + (["--child-trace"] if trace else [])
        r = subprocess.run(args, env=env, capture_output=True, text=True)
        if r.returncode:
            sys.exit(r.stderr)
        return json.loads(r.stdout.strip().splitlines()[-1])

    runs = [child(n) for n in a.steps]
    for r in runs:
        print(f"{r['steps']:>10} steps ({r['status']}): peak RSS {r['rss_peak'] / 1e6:.0f} MB "
              f"({r['rss_before_build'] / 1e6:.0f} MB before the build)")
    per = (runs[1]["rss_peak"] - runs[0]["rss_peak"]) / (runs[1]["steps"] - runs[0]["steps"])
    print(f"growth: {per:.1f} bytes per step (thermal.model = {a.thermal}, csv_every = 1000)")
    if a.trace:
        t = child(a.trace, True)
        n = t["steps"]
        print(f"\ntracemalloc, {n} steps: {t['traced_after_build'] / n:.1f} B/step alive after the build, "
              f"{t['traced_end'] / n:.1f} at the end, peak {t['traced_peak'] / n:.1f}")
        for title, key in (("alive after the build", "sites_after_build"), ("alive at the end", "sites_end")):
            print(f"  {title}:")
            for b, where in t[key]:
                if b >= 0.5:
                    print(f"    {b:6.1f} B/step  {where}")


if __name__ == "__main__":
    main()
