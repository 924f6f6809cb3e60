"""Set-up cost, cost per step and error against a closed form of the FE
plate models. Run from the repository root:

    OPENBLAS_NUM_THREADS=1 python benchmarks/thermal_fe.py [--quick]

fe1d: 1 MW/m2 into a 50 mm plate for 10 s at dt = 1 ms against the half-space
surface temperature. axisym: a 5 mm disk source on a 30 x 30 mm section for
5 s at dt = 10 ms, against the centre and footprint-mean closed forms.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fpd.thermal import exact  # noqa: E402
from fpd.thermal.params import PlateParams  # noqa: E402

Q = 1.0e6


WARM = 3   # the start-up substeps and BDF2's own factorisation happen in the first 3 steps


def bench_fe1d(n: int, steps: int = 10000, dt: float = 1e-3, scheme: str = "bdf2"):
    """(set-up s incl. the first WARM steps, s per later step, surface error K)."""
    from fpd.thermal.fe1d import FE1DPlate

    grading = 1.05 ** (100 / n)          # the default mesh family, nested
    p = PlateParams(model="fe1d", n_elements=n, grading=grading, scheme=scheme)
    P = Q * p.contact_area
    t0 = time.perf_counter()
    m = FE1DPlate(p, dt)
    for _ in range(WARM):
        m.step(P, 0.0)
    setup = time.perf_counter() - t0
    t0 = time.perf_counter()
    for _ in range(steps - WARM):
        Ts = m.step(P, 0.0)
    per = (time.perf_counter() - t0) / (steps - WARM)
    err = Ts - p.T0_C - exact.halfspace_flux_surface(steps * dt, Q, p.k, p.diffusivity)
    return setup, per, err


def bench_axisym(nr: int, nz: int, steps: int = 500, dt: float = 1e-2, scheme: str = "bdf2"):
    """(nodes, set-up s incl. mesh, assembly and the first WARM steps,
    s per later step, relative centre and footprint-mean errors)."""
    import numpy as np

    from fpd.meshes.rz import rz_mesh
    from fpd.thermal.axisym import AxisymPlate

    a, R, H = 0.005, 0.03, 0.03
    p = PlateParams(model="axisym", plate_radius=R, plate_thickness=H, a_contact_m=a,
                    h_conv=0.0, back="adiabatic", scheme=scheme)
    P = Q * p.contact_area
    t0 = time.perf_counter()
    mesh = rz_mesh(R, H, nr, nz, 1.2 ** (10 / nz), band_r=2 * a)
    m = AxisymPlate(p, dt, mesh=mesh)
    for _ in range(WARM):
        m.step(P, 0.0)
    setup = time.perf_counter() - t0
    t0 = time.perf_counter()
    for _ in range(steps - WARM):
        Tm = m.step(P, 0.0)
    per = (time.perf_counter() - t0) / (steps - WARM)
    T = m.temperature()
    centre = T[np.isclose(mesh.p[0], 0) & np.isclose(mesh.p[1], 0)][0] - p.T0_C
    ec = exact.disk_centre(steps * dt, Q, a, p.k, p.diffusivity)
    em = exact.disk_mean(steps * dt, Q, a, p.k, p.diffusivity)
    return mesh.p.shape[1], setup, per, (centre - ec) / ec, (Tm - p.T0_C - em) / em


def main(quick: bool = False) -> None:
    print("fe1d (BDF2, dt = 1 ms, 1 MW/m2, surface error vs half-space at t_end)")
    print(f"{'elements':>9} {'setup ms':>9} {'us/step':>8} {'steps':>6} {'error K':>10}"
          f"   (set-up includes the first {WARM} steps: start-up substeps, factorisations)")
    for n in (50, 200, 1000):
        steps = 2000 if quick else 10000
        setup, per, err = bench_fe1d(n, steps)
        print(f"{n:9d} {setup * 1e3:9.2f} {per * 1e6:8.2f} {steps:6d} {err:10.2e}")
    print("axisym (BDF2, dt = 10 ms, disk a = 5 mm, 5 s; relative errors vs closed forms)")
    print(f"{'nodes':>7} {'setup s':>8} {'ms/step':>8} {'centre':>10} {'mean':>10}")
    sizes = ((40, 40), (100, 100), (220, 220))
    for nr, nz in sizes[:2] if quick else sizes:
        n, setup, per, ec, em = bench_axisym(nr, nz, steps=100 if quick else 500)
        print(f"{n:7d} {setup:8.3f} {per * 1e3:8.3f} {ec:10.2e} {em:10.2e}")


if __name__ == "__main__":
    main("--quick" in sys.argv)
