"""Speed of the TFP's compiled loop: `python benchmarks/tfp_speed.py [--repeat N]`.

The packaged tfp-elcentro scene (the two-phase TFP, or ``--model seated``, fe1d on all four heated
parts, El Centro x 2) at dt = 1 ms: the time-stepping loop's own time
(Result.runtime_s: stepping only, not imports, compilation or storing), best
of N runs in one process (the machine may be shared: the best run is the
least disturbed one), and the Python loop once for comparison.
Target: <= 1 s compiled.
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
    ap.add_argument("--python", action="store_true", help="also time the Python loop once")
    ap.add_argument("--model", choices=("seated", "two-phase"), default=None,
                    help="mechanics.model of the run (default: the packaged scene's, two-phase)")
    args = ap.parse_args(argv)
    times = []

    def scene():
        sc = scn.load("tfp-elcentro")
        if args.model:
            sc.data["mechanics"]["model"] = args.model
        return sc

    for i in range(args.repeat):
        sim = build(scene())
        t0 = time.perf_counter()
        r = simulate(sim)
        wall = time.perf_counter() - t0
        assert r.status == "ok", r.message
        times.append(r.runtime_s)
        print(f"run {i + 1}: {sim.n_steps} steps, loop {r.runtime_s:.3f} s "
              f"({1e6 * r.runtime_s / sim.n_steps:.1f} us/step), simulate() {wall:.2f} s", flush=True)
    print(f"best loop time: {min(times):.3f} s for {sim.n_steps} steps (target <= 1 s)")
    if args.python:
        os.environ["FPD_NO_JIT"] = "1"
        sim = build(scene())
        r = simulate(sim)
        print(f"Python loop: {r.runtime_s:.2f} s ({1e6 * r.runtime_s / sim.n_steps:.0f} us/step)")


if __name__ == "__main__":
    main()
