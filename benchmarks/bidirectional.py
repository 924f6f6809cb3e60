"""Bidirectional DFP (model.md 8): speed, convergence, the independent check,
the planar special case and the unidirectional-superposition comparison.

    python benchmarks/bidirectional.py [--quick]

Timings are best of several runs (the machine may be shared).
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from fpd.coupling import build  # noqa: E402

from fpd.schema import scene
from fpd.mechanics.bidirectional import BidirectionalStepper  # noqa: E402
from tests import test_bidirectional as T  # noqa: E402


def speed(repeat):
    s = scene.load("impvall-bidirectional")
    gx, gy = build.bidirectional_loading_of(s, 1e-3)
    geom = build.geometry_of(s)
    st = BidirectionalStepper(geom, gx, gy, jit=True)
    st.run(0.06, 0.06, 10)                     # compile / load the cache
    best = math.inf
    for _ in range(repeat):
        st = BidirectionalStepper(geom, gx, gy, jit=True)
        t0 = time.perf_counter()
        st.run(0.06, 0.06)
        best = min(best, time.perf_counter() - t0)
    print(f"mechanics only, compiled kernel loop, {gx.n_steps} steps at 1 ms: best {best:.3f} s "
          f"({1e6 * best / gx.n_steps:.2f} us/step)")
    from fpd.coupling.run import simulate
    best = math.inf
    for _ in range(repeat):
        sim = build.build(s)
        r = simulate(sim)
        best = min(best, r.runtime_s)
    from fpd.coupling import fast_loop
    kind = "compiled" if fast_loop.compiled_loop(sim, 1, 2, fast_loop.loop_columns(sim)) else "Python"
    print(f"coupled loop (two-phase midpoint + fe1d both plates, kumar2015, staggered; {kind} loop): "
          f"best {best:.3f} s ({1e6 * best / gx.n_steps:.1f} us/step), status {r.status}")


def orders(quick):
    def study(name, geom, mk, dts, ref_dt, nf):
        eW, eU = T._errors(geom, mk, np.array(dts), ref_dt, nf) if mk is not None else (None, None)
        sW = T._slope(dts, eW)
        sU = T._slope(dts, eU)
        print(f"  {name:38s} {nf:8s} W rel err {' '.join(f'{x:.2e}' for x in eW)}  order {sW:.2f};"
              f"  max|u - u_ref| {' '.join(f'{x:.1e}' for x in eU)} m  order {sU:.2f}")
    dts = [4e-3, 2e-3, 1e-3] if quick else [4e-3, 2e-3, 1e-3, 5e-4]
    print(f"convergence (dt = {dts}, reference 1/16 of the smallest... see code):")
    for nf in ("start", "midpoint"):
        study("harsh harmonic 0.6 g 0.5 Hz R = 1 m", T.HARSH, lambda dt: T.harsh(dt, 2.0), dts, 2.5e-4 if quick else 6.25e-5, nf)
        study("El Centro 1940, 10 s", T.DEVICE, lambda dt: T.elcentro(dt, duration=10.0), dts, 6.25e-5, nf)
    for nf in ("start", "midpoint"):
        def run(dt, nf=nf):
            gx, gy = T._pair(dt, 8.0)
            return BidirectionalStepper(T.DEVICE, gx, gy, normal_force=nf, jit=True).run(0.06, 0.06)
        ref = run(6.25e-5)
        eW, eU = [], []
        for dt in dts:
            o = run(dt)
            k = int(round(dt / 6.25e-5))
            eW.append(abs(o[-1, 2] - ref[-1, 2]) / ref[-1, 2])
            eU.append(np.max(np.hypot(o[:, 0] - ref[k - 1::k, 0], o[:, 1] - ref[k - 1::k, 1])))
        print(f"  {'Imperial Valley pair (2D), 8 s':38s} {nf:8s} W rel err {' '.join(f'{x:.2e}' for x in eW)}  "
              f"order {T._slope(dts, eW):.2f};  max|u - u_ref| {' '.join(f'{x:.1e}' for x in eU)} m  "
              f"order {T._slope(dts, eU):.2f}")


def superposition():
    """Unidirectional runs of each component, superposed, against the true
    bidirectional run (two-phase, midpoint, mu = 0.06, dt = 1 ms)."""
    gx, gy = T._pair(1e-3, None)
    zx, zy = T.zero_like(gx), T.zero_like(gy)
    both, _ = T.history(T.DEVICE, gx, gy, mu=0.06, jit=True)
    onlyx, _ = T.history(T.DEVICE, gx, zy, mu=0.06, jit=True)
    onlyy, _ = T.history(T.DEVICE, zx, gy, mu=0.06, jit=True)
    C = T.COL
    u_b = np.hypot(both[:, C["ux_m"]], both[:, C["uy_m"]])
    F_b = np.hypot(both[:, C["Fx_N"]], both[:, C["Fy_N"]])
    ux, uy = onlyx[:, C["ux_m"]], onlyy[:, C["uy_m"]]
    Fx, Fy = onlyx[:, C["Fx_N"]], onlyy[:, C["Fy_N"]]
    u_s, F_s = np.hypot(ux, uy), np.hypot(Fx, Fy)
    W_b = both[-1, C["W1_J"]] + both[-1, C["W2_J"]]
    W_s = sum(r[-1, C["W1_J"]] + r[-1, C["W2_J"]] for r in (onlyx, onlyy))
    print("unidirectional superposition vs bidirectional (Imperial Valley 1979 E11 pair, mu = 0.06):")
    print(f"  peak |u|: bidirectional {1e3 * u_b.max():.1f} mm; superposed histories {1e3 * u_s.max():.1f} mm "
          f"({100 * (u_s.max() / u_b.max() - 1):+.1f} %); x alone {1e3 * np.abs(ux).max():.1f} mm, "
          f"y alone {1e3 * np.abs(uy).max():.1f} mm")
    print(f"  peak |F|: bidirectional {1e-3 * F_b.max():.1f} kN; superposed {1e-3 * F_s.max():.1f} kN "
          f"({100 * (F_s.max() / F_b.max() - 1):+.1f} %); x alone {1e-3 * np.abs(Fx).max():.1f} kN, "
          f"y alone {1e-3 * np.abs(Fy).max():.1f} kN")
    print(f"  friction work: bidirectional {1e-3 * W_b:.2f} kJ; sum of the two unidirectional runs "
          f"{1e-3 * W_s:.2f} kJ ({100 * (W_s / W_b - 1):+.1f} %)")


def independent(quick):
    for dur, t0 in ((5.0, 4.5),) if quick else ((5.0, 4.5), (25.0, 0.0)):
        dpeak, dW, peak = T._ode_check(dur, t_start=t0)
        print(f"independent ODE (Radau, eps = 1e-7 rad/s), pair {t0:g}..{t0 + dur:g} s, dt = 1 ms: "
              f"peak |u| {1e3 * peak:.2f} mm, stepper - ODE: peak {100 * dpeak:+.4f} %, friction work {100 * dW:+.4f} %")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--speed", action="store_true", help="only the speed measurement")
    a = ap.parse_args()
    speed(3 if a.quick else 7)
    if a.speed:
        return
    superposition()
    E, _ = T._circle_work(T.DEVICE)
    L = T.DEVICE.L
    small = 2 * math.pi * 0.2 * 0.05 * ((T.DEVICE.mass + T.DEVICE.pad_mass) * 2.2 + T.DEVICE.mass * 2.2) * T.G_ACC / L
    print(f"circular orbit A = 0.2 m: dissipated per revolution {E:.1f} J; small-angle closed form "
          f"{small:.1f} J ({100 * (E / small - 1):+.3f} %); with N = W / cos(theta) "
          f"{100 * (E / (small / math.sqrt(1 - (0.2 / L) ** 2)) - 1):+.5f} %")
    independent(a.quick)
    orders(a.quick)


if __name__ == "__main__":
    main()
