"""The cost of the vertical component: `python benchmarks/vertical_speed.py [--repeat N]`.

Each case runs a scene with two components (or one, planar) and the same
scene with the vertical one added, alternately, in one process (the
compiled engine; the machine may be shared: the best of N runs is the least
disturbed one), and prints the time-stepping loop's own time
(Result.runtime_s: stepping only, not imports, compilation or storing) and
the ratio. Target: a three-component run costs no more than 10 % over two.

Cases (the packaged scenes, their thermal models):
- tfp-planar: tfp-elcentro seated (El Centro x 2), + Ferndale 2022's vertical channel (x 2, 0.22 g);
- tfp-both: tfp-elcentro seated with the Imperial Valley pair x 0.5, + the same vertical channel;
- dfp-both: ferndale-3c (the DFP, two-phase) channels [1, 2], + channel 3.
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
V2 = ROOT / "scenes" / "records" / "FERNDALE2022_CE89486.v2"

CASES = {
    "tfp-planar": ("tfp-elcentro", ['mechanics.model="seated"', "solver.duration=30"],
                   [f'loading.file_z="{V2}"']),
    "tfp-both": ("tfp-elcentro", ['mechanics.model="seated"', 'loading.record="impvall-1979-e11"',
                                  "loading.scale=0.5", "solver.duration=30", "solver.dt=2e-3"],
                 [f'loading.file_z="{V2}"']),
    "dfp-both": ("ferndale-3c", ["loading.channels=[1, 2]"], ["loading.channels=[1, 2, 3]"]),
}


def main(argv=None):
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate
    from fpd.schema import scene as scn

    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--case", choices=tuple(CASES), action="append")
    args = ap.parse_args(argv)
    for name in args.case or CASES:
        scene, base, vert = CASES[name]
        over_v = [o for o in base if not o.startswith("loading.channels")] + vert
        best = {}
        for i in range(args.repeat):
            for label, over in (("2", base), ("3", over_v)):
                sim = build(scn.load(scene, over))
                r = simulate(sim)
                assert r.status == "ok", r.message
                assert ("az_mps2" in r.columns) == (label == "3")
                best[label] = min(best.get(label, float("inf")), r.runtime_s)
                print(f"{name} run {i + 1} ({'with' if label == '3' else 'without'} vertical): {sim.n_steps} "
                      f"steps, loop {r.runtime_s:.3f} s ({1e6 * r.runtime_s / sim.n_steps:.1f} us/step)",
                      flush=True)
        print(f"{name}: best loop {best['2']:.3f} s without the vertical, {best['3']:.3f} s with it: "
              f"x {best['3'] / best['2']:.3f} (target <= 1.10)", flush=True)


if __name__ == "__main__":
    main()
