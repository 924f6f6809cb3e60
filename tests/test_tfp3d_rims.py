"""The TFP in both horizontal directions at its rims (mechanics/tfp3d_kernel.py,
docs/model.md section 6.11): the planar TFP with its rims reproduced with no y
component and turned, a record pair that engages all four rims converging in
dt with no footprint past its capacity, compiled equal to pure."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from fpd import kernels
from fpd.loading.ground_motion import GroundMotion, pulse_ground_motion
from fpd.mechanics import tfp3d, tfp3d_kernel as K
from fpd.mechanics.tfp3d import TFP3DStepper

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_tfp import tfp  # noqa: E402
from test_tfp3d import _kernel, run3d, run_planar, turned  # noqa: E402
from test_tfp_rims import MUS, elcentro  # noqa: E402


def test_the_scratch_holds_the_rims():
    assert K.N_SC >= K.N_SC_RIM


def test_no_y_component_with_rims_reproduces_the_planar_tfp():
    """El Centro x 4 for 6.5 s (all four rims engaged, the full lock at
    4.9-5.6 s): the 3D stepper's x columns are the planar TFP's with its rims
    to round-off: within twice what the planar model moves when its record
    changes by one ulp, and below 1e-10 (measured 1.3e-11 of the peak
    displacement); rim loss, impacts and regimes the same."""
    g = tfp()
    gm = elcentro(4.0, 1e-3, 6.5)
    p = run_planar(g, gm, MUS)
    ulp = run_planar(g, GroundMotion(gm.name, gm.dt, gm.t, gm.d, gm.v, gm.a, gm.a_step * (1 + 2.2e-16)), MUS)
    _, d, res = run3d(g, gm, mus=MUS)
    assert all(p[f"n_rim{i}"][-1] >= 1 for i in range(1, 5))
    assert np.max(np.abs(d["uy_m"])) == 0.0
    um = np.max(np.abs(p["u_m"]))
    sens = np.max(np.abs(ulp["u_m"] - p["u_m"])) / um
    tol = min(1e-10, 2.0 * max(sens, 1e-13))
    assert np.max(np.abs(d["ux_m"] - p["u_m"])) <= tol * um
    wt = sum(p[f"W{i}_J"][-1] for i in range(1, 5))
    for c in ("W1_J", "W2_J", "W3_J", "W4_J", "E_input_J", "E_kin_J", "E_pot_J", "E_rim_J"):
        assert np.max(np.abs(d[c] - p[c])) <= tol * wt, c
    for i in range(1, 5):
        assert np.array_equal(d[f"n_rim{i}"], p[f"n_rim{i}"])
        assert np.array_equal(d[f"rim{i}"], p[f"rim{i}"])
    assert np.array_equal(d["regime"], p["regime"])
    assert np.max(np.abs(d["J_rim_Ns"] - np.abs(p["J_rim_Ns"]))) <= 1e-6 * np.max(np.abs(p["J_rim_Ns"]))
    assert np.max(np.abs(res)) <= 1e-9 * np.max(np.abs(d["E_input_J"]))


def test_a_turned_record_with_rims_is_the_planar_run_turned():
    """The same record turned by 30 deg: the resultant history (|u|, the slides,
    friction work, rim loss, impacts) is the run along x, to 1e-9; every
    footprint stays on its circle of capacity."""
    g = tfp()
    gm = elcentro(4.0, 1e-3, 6.5)
    _, d0, _ = run3d(g, gm, mus=MUS)
    ang = math.radians(30.0)
    _, d, res = run3d(g, *turned(gm, ang), mus=MUS)
    um = np.max(d0["u_m"])
    assert np.max(np.abs(d["u_m"] - d0["u_m"])) <= 1e-9 * um
    wt = sum(d0[f"W{i}_J"][-1] for i in range(1, 5))
    for c in ("W1_J", "W2_J", "W3_J", "W4_J", "E_rim_J", "E_input_J", "s1_m", "s2_m", "s3_m", "s4_m"):
        scale = wt if c.endswith("_J") else np.max(d0[c])
        assert np.max(np.abs(d[c] - d0[c])) <= 1e-9 * scale, c
    for i in range(1, 5):
        assert np.array_equal(d[f"n_rim{i}"], d0[f"n_rim{i}"])
        cap = getattr(g, f"d{i}")
        assert np.max(d[f"s{i}_m"]) <= cap * (1 + 1e-9)


def _impvall(dt, scale=3.0, duration=15.0):
    from fpd.coupling.build import bidirectional_loading_of
    from fpd.schema import scene as scn
    sc = scn.load("tfp-elcentro", ['loading.record="impvall-1979-e11"', 'mechanics.model="seated"',
                                   f"loading.scale={scale}", f"solver.duration={duration}", f"solver.dt={dt}",
                                   'thermal.model="none"'])
    return scn.tfp_geometry(sc.data), bidirectional_loading_of(sc, dt)


def test_a_pair_engaging_all_four_rims_converges_in_dt():
    """Imperial Valley 1979, both components x 3, 15 s: all four rims reached;
    dissipation (friction + rim loss) within 2 % across dt = 1, 0.5, 0.25 ms
    (measured 144.1, 142.9, 142.8 kJ), no footprint ever past its capacity
    (|s_i| <= d_i (1 + 1e-9)) and the ledger closed to 1e-9 of the input
    every step."""
    D = {}
    for dt in (1e-3, 5e-4, 2.5e-4):
        g, (gx, gy) = _impvall(dt)
        s = TFP3DStepper(g, gx, gy, kernel=_kernel())
        caps = np.array([g.d1, g.d2, g.d3, g.d4])
        R = np.array([g.R1, g.R2, g.R3, g.R4])
        worst = peak = 0.0
        for _ in range(s.n_steps):
            s.step(*MUS)
            q = s.S
            sl = R * np.array([math.hypot(q[0], q[1]), math.hypot(q[2], q[3]),
                               math.hypot(q[2], q[3]), math.hypot(q[0], q[1])])
            peak = max(peak, float(np.max(sl / caps)))
            worst = max(worst, abs(s.ledger_residual()))
        assert peak <= 1.0 + 1e-9
        assert worst <= 1e-9 * s.E_in
        assert all(s.S[K.S_NHIT + i] >= 1 for i in range(4)), s.S[K.S_NHIT:K.S_NHIT + 4]
        D[dt] = sum(s.W) + s.E_rim
    ref = D[2.5e-4]
    assert max(abs(d / ref - 1) for d in D.values()) < 0.02, D


@pytest.mark.slow
def test_compiled_kernel_equals_pure_bit_for_bit_through_a_pair_at_all_four_rims():
    """The record pair through all four rims (its inner rims' impacts cost
    the pure path about a minute a step; the default run checks every rim
    path from set states: test_compiled_kernel_equals_pure_bit_for_bit_at_the_rims)."""
    if not kernels.available():
        pytest.skip("numba not available")
    g = tfp()
    gx = pulse_ground_motion("sine", 1.5, 1.5, 0.2, 1.6, 2e-3)
    gy = pulse_ground_motion("sine", 1.0, 1.1, 0.4, 1.6, 2e-3)
    _, a, _ = run3d(g, gx, gy, mus=MUS, kernel=None)
    _, b, _ = run3d(g, gx, gy, mus=MUS, kernel=_kernel())
    assert all(a[f"n_rim{i}"][-1] >= 1 for i in range(1, 5))
    for c in a:
        assert np.array_equal(a[c], b[c]), c


def _at_the_rims(kernel, stack, pad, steps):
    """A stepper started a hair inside the rims with rates into them: stack
    and pad each given as (angle of the tilt's direction deg or None, normal
    rate, tangential rate); the ground moving under it; its rows over
    ``steps`` steps."""
    g = tfp()
    pm, am = g.qmax
    gx = pulse_ground_motion("sine", 0.8, 0.5, 0.0, steps * 1e-3, 1e-3)
    gy = pulse_ground_motion("sine", -0.5, 0.4, 0.0, steps * 1e-3, 1e-3)
    s = TFP3DStepper(g, gx, gy, kernel=kernel)
    for given, qm, i in ((stack, pm, 0), (pad, am, 2)):
        if given is None:
            continue
        ang, vn, vt = given
        th = math.radians(ang)
        n = np.array([math.cos(th), math.sin(th)])
        t = np.array([-n[1], n[0]])
        s.S[i:i + 2] = (qm - 1e-10) * n
        s.S[4 + i:6 + i] = vn * n + vt * t
    rows = [s.values()]
    for _ in range(steps):
        s.step(*MUS)
        rows.append(s.values())
    return np.array(rows)


@pytest.mark.parametrize("stack,pad,steps,hit", [
    ((20.0, 0.3, 0.1), None, 6, (1, 0, 0, 1)),                # the stack's rims (S1, S4) reached
    (None, (40.0, 0.3, 0.2), 6, (0, 1, 1, 0)),                # the pad's (S2, S3), oblique
    ((20.0, 0.3, 0.1), (-70.0, 0.3, -0.1), 6, (1, 1, 1, 1)),  # both at once, in two directions
    ((200.0, 0.0, 0.0), (200.0, 0.0, 0.0), 2, (1, 1, 1, 1)),  # on all four, pressed by the ground
], ids=["stack", "pad", "both", "resting"])
def test_compiled_kernel_equals_pure_bit_for_bit_at_the_rims(stack, pad, steps, hit):
    """Every rim path of the step (an arrival on the outer rims, on the inner
    ones, on both in two directions, a stack held on both), compiled against
    pure, bit for bit (the record pair through all four rims: the slow test
    below)."""
    if not kernels.available():
        pytest.skip("numba not available")
    a = _at_the_rims(None, stack, pad, steps)
    b = _at_the_rims(_kernel(), stack, pad, steps)
    cols = list(tfp3d.COLUMNS)
    assert tuple(int(a[-1, cols.index(f"n_rim{i}")]) for i in range(1, 5)) == hit
    assert np.array_equal(a, b)


@pytest.mark.parametrize("e", [0.0, 0.5])
def test_an_oblique_impact_takes_the_kinetic_energy_normal_to_the_rim(e):
    """Frictionless, the ground at rest, the pad's tilt a hair inside its rim
    at 40 deg and its rate oblique to the rim (normal and tangential parts):
    the impact takes (1 - e^2) of the kinetic energy normal to the rim, the
    closed form 1/2 (n . v)^2 / (n^T M^-1 n) (n the rim's normal on alpha's
    rates, M the mass matrix there), to 1e-3 (the motion in the 1 us step:
    the frictionless stack under the tilted pad accelerates at ~100 rad/s2),
    leaves the pad on its rim sliding along it (inelastic: no normal
    rate) or leaving it at -e times its normal rate."""
    g = tfp(rim_restitution=e)
    pm, am = g.qmax
    gm = pulse_ground_motion("cosine", 0.0, 1.0, 0.0, 1e-6, 1e-6)
    s = TFP3DStepper(g, gm, kernel=None)
    th = math.radians(40.0)
    n = np.array([math.cos(th), math.sin(th)])
    t = np.array([-n[1], n[0]])
    s.S[2:4] = (am - 1e-10) * n
    s.S[6:8] = 0.3 * n + 0.2 * t
    M = np.zeros(16)
    K.mass_matrix(s.par, s.S[0:4], M, np.zeros(12))
    M = M.reshape(4, 4)
    c = np.array([0.0, 0.0, n[0], n[1]])
    vn = c @ s.S[4:8]
    normal_ke = 0.5 * vn * vn / (c @ np.linalg.solve(M, c))
    res0 = s.ledger_residual()          # minus the energy the state was given
    s.step(0.0, 0.0, 0.0, 0.0)
    assert s.E_rim == pytest.approx((1.0 - e * e) * normal_ke, rel=1e-3)
    assert math.hypot(s.S[2], s.S[3]) <= am * (1 + 1e-12)
    va = s.S[6:8]
    assert va @ n == pytest.approx(-e * vn, abs=2e-3 * abs(vn))
    assert abs(va @ t) > 0.1
    assert abs(s.ledger_residual() - res0) <= 1e-9 * normal_ke


def _impact_programs(steps, every=1):
    """The rims' constrained cone programs (``rim_socp``'s arguments: H, r, the
    friction caps, y's start and the scratch with the rims' lines and
    Newton's start) that the pure kernel meets in ``steps`` of the record pair
    through all four rims (benchmarks/tfp3d_rims_speed.py's; the steps between
    them run compiled when numba is there); every ``every``-th one."""
    g = tfp()
    gx = pulse_ground_motion("sine", 1.5, 1.5, 0.2, 1.6, 2e-3)
    gy = pulse_ground_motion("sine", 1.0, 1.1, 0.4, 1.6, 2e-3)
    kern = _kernel()
    s = TFP3DStepper(g, gx, gy, kernel=kern)
    progs = []
    orig = K.rim_socp

    def spy(H, r, c1, c2, y, sc):
        progs.append((np.array(H), np.array(r), c1, c2, np.array(y), np.array(sc)))
        return orig(H, r, c1, c2, y, sc)

    K.rim_socp = spy
    try:
        for n in range(max(steps) + 1):
            s.k = K if (n in steps or kern is None) else kern
            if n not in steps:
                K.rim_socp = orig
            s.step(*MUS)
            K.rim_socp = spy
    finally:
        K.rim_socp = orig
    return s, progs[::every]


def test_newton_on_the_rims_dual_is_the_bracketed_search_at_the_impacts():
    """Every constrained cone program of the pair's impact steps (the inner
    rims' at 0.698, 0.872, 1.162, 1.556 s, the outer ones' at 1.156, 1.552 s):
    Newton's method on the dual (``rim_newton``) settles on nearly all (239
    of the 240 measured; the bracketed search takes the rest), and the
    solver's multipliers and minimiser (``rim_socp``) are the bracketed
    search's (``rim_search``, the nested regula falsi to 2e-16 of each
    multiplier) to 1e-11 (measured 1.9e-12 in the multipliers, 5e-13 in y,
    104 programs with both rims holding; both are the root to the gaps'
    round-off, the cone program's condition times the unit round-off), the
    same rims holding; the minimiser optimal for the cone program with the
    rims' reactions (KKT to 1e-12, measured 1.8e-13), each held block on its
    line (to 1e-12 of |y| |m_k|) and each free one inside it."""
    steps = (348, 435, 577, 580, 775, 777)
    kern = _kernel()
    s, progs = _impact_programs(steps, every=1 if kern is not None else 8)
    mod = kern if kern is not None else K
    assert len(progs) >= (100 if kern is not None else 12)
    both = 0
    settled = 0
    for H, r, c1, c2, y0, sc in progs:
        ya, sa = y0.copy(), sc.copy()
        settled += int(mod.rim_newton(H.copy(), r.copy(), c1, c2, y0.copy(), sc.copy()) == 0)
        mod.rim_socp(H.copy(), r.copy(), c1, c2, ya, sa)
        yb, sb = y0.copy(), sc.copy()
        mod.rim_search(H.copy(), r.copy(), c1, c2, yb, sb)
        nua, nub = sa[K.R_NU:K.R_NU + 2], sb[K.R_NU:K.R_NU + 2]
        both += int(nub[0] > 0.0 and nub[1] > 0.0)
        assert np.max(np.abs(nua - nub)) <= 1e-11 * max(np.max(nub), 1e-300)
        assert np.max(np.abs(ya - yb)) <= 1e-11 * np.max(np.abs(yb))
        assert np.array_equal(nua > 0.0, nub > 0.0)
        rr = r.copy()
        for k in range(2):
            m = sa[K.R_M + 2 * k:K.R_M + 2 * k + 2]
            rr[2 * k:2 * k + 2] -= nua[k] * m
            if sa[K.R_ACT + k] != 0.0:
                gap = m @ ya[2 * k:2 * k + 2] - sa[K.R_H + k]
                ny = np.linalg.norm(ya) * np.linalg.norm(m)
                if nua[k] > 0.0:
                    assert abs(gap) <= 1e-12 * ny
                else:
                    assert gap <= 0.0
        assert K.kkt_residual(H, rr, c1, c2, ya) <= 1e-12
    assert both >= (50 if kern is not None else 6)
    assert settled >= 0.97 * len(progs), (settled, len(progs))
    assert all(s.S[K.S_NHIT + i] >= 1 for i in range(4))
