"""What a rim impact costs the seated TFP in both directions:
`python benchmarks/tfp3d_rims_speed.py [--repeat N]`.

A record pair that drives all four surfaces of a TFP (R1 = R4 = 2.235 m,
R2 = R3 = 0.405 m, capacities 0.20 / 0.05 m, 40 t, mu 0.08 / 0.02) onto their
rims: a sine velocity pulse of 1.5 m/s and 1.5 s on x, 1.0 m/s and 1.1 s on y
(starting 0.2 s and 0.4 s in), 1.6 s at dt = 2 ms (tests/test_tfp3d_rims.py
checks this pair compiled against pure). The compiled kernel stepped from
Python, each step timed: the whole run, the median step, and the dearest
steps with the rim counters that changed there (the impacts: Newton's
method on the rims' dual inside the step's fixed point, the nested
bracketed search where it does not settle; docs/model.md 6.11). Best of N runs per step. `--rim-stiffness K`
gives the rims a finite stiffness K (N/m; docs/model.md 6.12): no impact
steps, the springs in every step.
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

MUS = (0.08, 0.02, 0.02, 0.08)


def main(argv=None) -> int:
    from fpd import kernels
    from fpd.loading.ground_motion import pulse_ground_motion
    from fpd.mechanics import tfp3d
    from fpd.mechanics.tfp import TFPGeometry

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--top", type=int, default=5, help="the dearest steps listed")
    ap.add_argument("--rim-stiffness", type=float, default=0.0, help="N/m: rims of finite stiffness (0: rigid)")
    args = ap.parse_args(argv)
    if not kernels.available():
        print("numba is not installed: this measures the compiled kernel")
        return 1
    k = kernels.compiled("fpd.mechanics.tfp3d_kernel")
    g = TFPGeometry(R1=2.235, R2=0.405, R3=0.405, R4=2.235, pad_height=0.076, pad_diameter=0.10,
                    slider_height_lower=0.11, slider_height_upper=0.11, slider_diameter=0.30,
                    d1=0.20, d2=0.05, d3=0.05, d4=0.20, pad_mass=20.0, slider_mass=80.0, mass=4.0e4,
                    rim_stiffness=args.rim_stiffness)
    gx = pulse_ground_motion("sine", 1.5, 1.5, 0.2, 1.6, 2e-3)
    gy = pulse_ground_motion("sine", 1.0, 1.1, 0.4, 1.6, 2e-3)
    cols = list(tfp3d.COLUMNS)
    hits = [cols.index(f"n_rim{i}") for i in range(1, 5)]
    best, rows = None, None
    for _ in range(args.repeat + 1):            # the first run loads the cached kernel
        s = tfp3d.TFP3DStepper(g, gx, gy, kernel=k)
        ts, rr = [], [s.values()]
        for _n in range(gx.n_steps):
            t0 = time.perf_counter()
            s.step(*MUS)
            ts.append(time.perf_counter() - t0)
            rr.append(s.values())
        ts = np.array(ts)
        best = ts if best is None else np.minimum(best, ts)
        rows = np.array(rr)
    print(f"{gx.n_steps} steps: {best.sum():.3f} s in all, median step {1e3 * np.median(best):.3f} ms "
          f"(best of {args.repeat} per step)")
    for n in np.argsort(best)[::-1][:args.top]:
        new = [i + 1 for i, j in enumerate(hits) if rows[n + 1, j] > rows[n, j]]
        what = f"impacts on rims {', '.join(map(str, new))}" if new else "no new impact"
        print(f"  step {n:4d} (t = {(n + 1) * gx.dt:.3f} s): {best[n]:.3f} s, {what}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
