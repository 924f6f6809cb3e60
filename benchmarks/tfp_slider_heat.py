"""Where is the paper's lumped Eq. (9) closest to FE on the TFP's slider plates?

`python benchmarks/tfp_slider_heat.py [--quick]`: the packaged tfp-elcentro
scene (El Centro x 2, then at rest) with the slider plates (S2, S3: small
steel parts, 0.30 m x 0.11 m) as lumped, fe1d, axisym and fe3d; the outer
plates fe1d throughout. Prints the slider plate's temperature T2 (lumped: the
body temperature; FE: the footprint-mean surface temperature) at a few times
and the lumped error against each FE model. ``--models`` picks a subset
(lumped is always run: it is the reference of the differences).
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def main(argv=None):
    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate

    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--models", default="fe1d,axisym,fe3d", help="FE models of the slider plates (comma-separated)")
    args = ap.parse_args(argv)
    fe = [m for m in args.models.split(",") if m and m != "lumped"]
    dt, duration = (1e-2, 120.0) if args.quick else (5e-3, 600.0)
    times = [t for t in (5.0, 10.0, 20.0, 40.0, 60.0, 120.0, 300.0, 600.0) if t <= duration]
    out = {}
    for model in ["lumped"] + fe:
        sets = [f"solver.dt={dt}", f"solver.duration={duration}",
                f"thermal.slider_lower.model={model}", f"thermal.slider_upper.model={model}"]
        if model == "axisym":
            sets += ["thermal.slider_lower.nr=30", "thermal.slider_lower.nz=40"]
        sim = build(scn.load("tfp-elcentro", sets))
        r = simulate(sim)
        t = r["t_s"]
        out[model] = [float(np.interp(ti, t, r["T2_C"])) for ti in times]
        print(f"{model}: {r.status}, W2 = {r['W2_J'][-1]:.0f} J, peak T2 = {r['T2_C'].max():.2f} C, "
              f"loop {r.runtime_s:.1f} s", flush=True)
    print("\n| t (s) | lumped T2 (C) | " + " | ".join(f"{m} T2 (C)" for m in fe) + " | "
          + " | ".join(f"lumped - {m} (K)" for m in fe) + " |")
    print("|---" * (1 + 2 * len(fe) + 1) + "|")
    for i, ti in enumerate(times):
        L = out["lumped"][i]
        print(f"| {ti:g} | {L:.2f} | " + " | ".join(f"{out[m][i]:.2f}" for m in fe) + " | "
              + " | ".join(f"{L - out[m][i]:+.2f}" for m in fe) + " |")


if __name__ == "__main__":
    main()
