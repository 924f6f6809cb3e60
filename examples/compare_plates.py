"""The same scene with the paper's lumped plate and with conduction through the
plate (fe1d): the sliding surface heats far more under conduction.

    python examples/compare_plates.py [DURATION_S]

(`fpd compare SCENE`, or `fpd.compare(...)`, runs the full study with axisym too.)
"""
import sys

import fpd

duration = float(sys.argv[1]) if len(sys.argv) > 1 else 5.0
print(f"{'thermal model':14s} {'peak T1 (C)':>12s} {'min mu1':>9s} {'peak u (mm)':>12s}")
for model in ("lumped", "fe1d"):
    r = fpd.run("default", solver={"duration": duration}, thermal={"model": model})
    s = r.summary
    print(f"{model:14s} {s['peak_T1_C']:12.2f} {s['min_mu1']:9.4f} {1e3 * s['peak_u_m']:12.1f}")
