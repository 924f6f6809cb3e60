"""The numbers of docs/two_phase.md, section "Measured" (run from the repository root).

    python benchmarks/two_phase_study.py

Same runs as tests/test_two_phase.py (default device, El Centro 1940).
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.test_two_phase import (  # noqa: E402
    COL, DEVICE, DTS, G, MU, _constant_acceleration, _tall_pad_pulse, elcentro_run,
    ledger_residual, observed_order, run, seated_run,
)
from tests.records_helper import elcentro  # noqa: E402


def order_pairs(values):
    return ", ".join(f"{math.log2(a / b):.2f}" for a, b in zip(values, values[1:]))


def main() -> None:
    print("## Ledger, El Centro x1.0: max |residual| over the history / E_input")
    rel = []
    for dt in DTS:
        t0 = time.perf_counter()
        h, st = elcentro_run(dt)
        el = time.perf_counter() - t0
        r = np.abs(ledger_residual(h)).max()
        rel.append(r / st.E_input)
        print(f"dt {dt*1e3:5.2f} ms  E_input {st.E_input:10.3f} J  max|res| {r:.3e} J "
              f" rel {r / st.E_input:.3e}  E_reseat {st.E_reseat:.4e} J  "
              f"peak u {np.abs(h[:, COL['u_m']]).max()*1e3:.4f} mm  run {el:.1f} s")
    print(f"fitted order {observed_order(DTS, rel):.2f}; pairwise {order_pairs(rel)}")

    print("\n## Convergence, El Centro x1.5")
    W, u = [], []
    for dt in DTS:
        h, st = elcentro_run(dt, 1.5)
        W.append(st.W1 + st.W2)
        u.append(h[:, COL["u_m"]])
        print(f"dt {dt*1e3:5.2f} ms  W {W[-1]:.4f} J  peak u {np.abs(u[-1]).max()*1e3:.4f} mm "
              f" E_reseat {st.E_reseat:.4e} J")
    stride = [int(round(dt / DTS[-1])) for dt in DTS]
    du = [np.abs(u[k] - u[-1][::stride[k]][:len(u[k])]).max() for k in range(3)]
    dW = [abs(W[k] - W[-1]) / W[-1] for k in range(3)]
    dWs = [abs(W[k] - W[k + 1]) / W[-1] for k in range(3)]
    print("vs finest: |dW|/W " + ", ".join(f"{x:.3e}" for x in dW)
          + f"  fitted order {observed_order(DTS[:3], dW):.2f}")
    print("successive |dW|/W " + ", ".join(f"{x:.3e}" for x in dWs)
          + f"  pairwise orders {order_pairs(dWs)}")
    print("vs finest: max|du| (m) " + ", ".join(f"{x:.3e}" for x in du)
          + f"  fitted order {observed_order(DTS[:3], du):.2f}")

    print("\n## Against the seated model, El Centro x1.0")
    for dt in DTS[1:]:
        h, st = elcentro_run(dt)
        us, Ws = seated_run(dt)
        uu = h[:, COL["u_m"]]
        print(f"dt {dt*1e3:5.2f} ms  peak {np.abs(uu).max()/np.abs(us).max()-1:+.3e}  "
              f"W {(st.W1+st.W2)/Ws-1:+.3e}  max|du| {np.abs(uu-us).max():.3e} m")

    print("\n## Northridge 1994 (CDMG 24278, 090) x1.0, against the seated model")
    from fpd.mechanics.geometry import G_ACC
    from fpd.loading.ground_motion import ground_motion_from_samples, read_record
    from fpd.machines.seated import SeatedStepper
    rec = read_record(Path(__file__).resolve().parents[1] / "scenes" / "records"
                      / "Northridge_CDMG24278_090.dat")
    for dt in (1e-3, 2.5e-4):
        gm = ground_motion_from_samples("northridge", rec.t, rec.a_g * G_ACC, dt)
        h, st = run(DEVICE, gm)
        se = SeatedStepper(DEVICE, gm)
        us = [se.u]
        for _ in range(se.n_steps):
            se.step(MU, MU)
            us.append(se.u)
        us, uu = np.array(us), h[:, COL["u_m"]]
        W, Ws = st.W1 + st.W2, se.W1 + se.W2
        print(f"dt {dt*1e3:5.2f} ms  peak {np.abs(uu).max()*1e3:.3f} mm (seated "
              f"{np.abs(us).max()*1e3:.3f})  W {W:.1f} J (seated {Ws:.1f})  "
              f"max|du| {np.abs(uu-us).max():.2e} m  ledger "
              f"{np.abs(ledger_residual(h)).max()/st.E_input:.1e}  E_reseat {st.E_reseat:.3g} J")

    print("\n## beta1, squat pad, El Centro 0-6 s")
    peaks = []
    for dt in (2e-3, 1e-3, 5e-4):
        h, _ = run(DEVICE, elcentro(dt, duration=6.0))
        peaks.append(np.abs(h[:, COL["beta1_rad"]]).max())
        print(f"dt {dt*1e3:5.2f} ms  max|beta1| {peaks[-1]:.3e} rad  "
              f"max|pad tilt| {np.abs(h[:, COL['pad_tilt_rad']]).max():.3e} rad")
    print(f"fitted order {observed_order((2e-3, 1e-3, 5e-4), peaks):.3f}")

    print("\n## Tall pad (0.5 m x 0.1 m), mu = 0.6, 0.3 g half-sine of 0.3 s")
    for dt in (1e-3, 5e-4, 2.5e-4):
        h, st = _tall_pad_pulse(dt)
        tilt = h[:, COL["phase"]] == 2
        print(f"dt {dt*1e3:5.2f} ms  max beta1 {np.abs(h[:, COL['beta1_rad']]).max():.5f} rad  "
              f"tilt steps {tilt.sum()}  rocking {h[tilt, 0][0]:.3f}-{h[tilt, 0][-1]:.3f} s  "
              f"max uplift {h[:, COL['z_m']].max()*1e3:.3f} mm  E_reseat {st.E_reseat:.3f} J  "
              f"E_input {st.E_input:.1f} J  max|res| {np.abs(ledger_residual(h)).max():.2e} J")

    print("\n## Frictionless period (theta0 = 0.01 rad), dt = 1 ms")
    T0 = 2 * math.pi * math.sqrt(DEVICE.I / (DEVICE.S * G))
    h, _ = run(DEVICE, _constant_acceleration(0.0, 1e-3, 3.2 * T0), mu1=0.0, mu2=0.0, theta0=0.01)
    t, th = h[:, COL["t_s"]], h[:, COL["theta_rad"]]
    up = np.nonzero((th[:-1] < 0) & (th[1:] >= 0))[0]
    cr = t[up] - th[up] * (t[up + 1] - t[up]) / (th[up + 1] - th[up])
    print(f"T0 {T0:.5f} s; measured " + ", ".join(f"{p:.5f}" for p in np.diff(cr))
          + f"; max rel error {np.abs(np.diff(cr) / T0 - 1).max():.2e}")


if __name__ == "__main__":
    main()
