"""Speed of the two-phase TFP in both directions in the compiled loop:
`python benchmarks/tfp3d_two_phase_speed.py [--repeat N] [--model seated]`.

The packaged tfp-elcentro scene (the two-phase TFP, fe1d on all four heated
parts along their 2D footprint paths) under the Imperial Valley 1979 pair
(`loading.record = "impvall-1979-e11"`, both components at half scale, inside the rims, 40 s) at
dt = 1 ms:
the time-stepping loop's own time (Result.runtime_s: stepping only, not
imports, compilation or storing), best of N runs in one process, with the
machine's load average before each run and simulate()'s CPU time (the machine
may be shared: the best run is the least disturbed one, and on a loaded
machine the CPU time is what the loop would take on a quiet one). Target: <= 1.5 s compiled on a quiet 2-core
machine.
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def main(argv=None):
    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate

    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--duration", type=float, default=40.0)
    ap.add_argument("--model", choices=("seated", "two-phase"), default="two-phase")
    args = ap.parse_args(argv)
    over = ['loading.record="impvall-1979-e11"', "loading.scale=0.5", f"solver.duration={args.duration}", "solver.dt=1e-3",
            f'mechanics.model="{args.model}"', 'thermal.model="fe1d"']
    times = []
    for i in range(args.repeat):
        sim = build(scn.load("tfp-elcentro", over))
        load = os.getloadavg()[0]
        t0, c0 = time.perf_counter(), time.process_time()
        r = simulate(sim)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        assert r.status == "ok", r.message
        times.append(r.runtime_s)
        print(f"run {i + 1}: {sim.n_steps} steps, loop {r.runtime_s:.3f} s "
              f"({1e6 * r.runtime_s / sim.n_steps:.1f} us/step), simulate() {wall:.2f} s wall, {cpu:.2f} s CPU, "
              f"load average before {load:.2f}", flush=True)
    print(f"best loop time: {min(times):.3f} s for {sim.n_steps} steps ({args.model}; target <= 1.5 s)")


if __name__ == "__main__":
    main()
