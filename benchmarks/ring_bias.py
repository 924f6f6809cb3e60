"""The axisym ring-average bias (docs/thermal.md section 8).

A stationary disk of radius a, uniform flux q, on a thick plate: on a
half-space its footprint mean does not depend on where it sits (the closed
form exact.disk_mean). axisym averages a footprint centred at distance c from
its axis into a ring, so off centre it spreads the heat over a wider area and
its footprint mean runs low; fe3d places the disk as it is. Prints both
against the closed form at offsets c / a = 0, 0.1, 0.25, 0.5, 1 and two times.

    OPENBLAS_NUM_THREADS=1 python3 benchmarks/ring_bias.py
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from fpd.meshes.box import symmetric_nodes          # noqa: E402
from fpd.meshes.line import graded_nodes             # noqa: E402
from fpd.thermal import exact                         # noqa: E402
from fpd.thermal.axisym import AxisymPlate            # noqa: E402
from fpd.thermal.fe3d import FE3DPlate                # noqa: E402
from fpd.thermal.params import PlateParams            # noqa: E402

A, K, RHO, C, Q = 0.01, 16.0, 7850.0, 500.0, 1.0e6
KAPPA = K / (RHO * C)


def main():
    offsets = (0.0, 0.1, 0.25, 0.5, 1.0)
    print("| sqrt(kappa t)/a | offset c/a | closed form (K) | axisym | fe3d |")
    print("|---|---|---|---|---|")
    for s in (0.1, 0.5, 2.0):
        t = (s * A) ** 2 / KAPPA
        dl = math.sqrt(KAPPA * t)
        depth = 6 * dl + 3 * A
        ref = exact.disk_mean(t, Q, A, K, KAPPA)
        for off in offsets:
            c = off * A
            R = c + A + 6 * dl
            pa = PlateParams(model="axisym", plate_radius=R, plate_thickness=depth, a_contact_m=A, k=K, rho=RHO,
                             c=C, h_conv=0.0, back="adiabatic", nz=60, grading=1.05, per_radius=40,
                             sweep_m=c)
            ax = AxisymPlate(pa, t / 20)
            L = c + 1.5 * A + 6 * dl
            x = symmetric_nodes(L, c + 1.5 * A, A / 20)
            y = symmetric_nodes(L, 1.5 * A, A / 20)
            z = graded_nodes(depth, 30, 1.15)
            p3 = PlateParams(model="fe3d", plate_radius=1.0, plate_thickness=depth, a_contact_m=A, k=K, rho=RHO,
                             c=C, h_conv=0.0, back="adiabatic", step_multiple=1)
            f3 = FE3DPlate(p3, t / 20, nodes=(x, y, z))
            P = Q * math.pi * A * A
            for _ in range(20):
                Ta = ax.step(P, c)
                T3 = f3.step(P, c)
            print(f"| {s:g} | {off:g} | {ref:.4g} | {100 * ((Ta - 20) / ref - 1):+.2f} % | "
                  f"{100 * ((T3 - 20) / ref - 1):+.2f} % |")


if __name__ == "__main__":
    t0 = time.time()
    main()
    print(f"({time.time() - t0:.1f} s)")
