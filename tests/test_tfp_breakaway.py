"""Breakaway (static) friction on the TFP and the flat bearing: a surface at
rest holds until the force it must carry exceeds mu_s N (the one rule,
friction_kernel.holding_mu), against the models' own statics with mu_s in
place of the sliding mu; under a ground motion a bracket on the threshold."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.mechanics import tfp as T
from fpd.mechanics import tfp_kernel as K
from fpd.studies import tfp_backbone as B
from fpd.mechanics.geometry import G_ACC
from fpd.schema import scene as scn

KIN = (0.10, 0.02, 0.02, 0.10)          # tfp-lab's sliding mu of S1..S4
STAT = (0.11, 0.03, 0.03, 0.11)         # the static ones the tests give (the outer breaks away before the inner rim)
STATIC_KEYS = [f"friction.S{i}.mu_static={m}" for i, m in zip(range(1, 5), STAT)]


def _sim(scene, over):
    sc = scn.load(scene, over)
    sim = build(sc)
    res = simulate(sim)
    assert res.status == "ok", res.message
    return sim, res


def _raw(scene, **tables):
    raw = scn.read_toml(scn.resolve_path(scene))
    raw = copy.deepcopy(raw)
    raw.update(tables)
    return raw


def _mixed_transition(geom):
    """Where the outer surfaces break away from rest on the inner branch: the
    inner slides with the sliding mu, the outer holds with the static one
    (the root in psi of the outer demand minus its static cap)."""
    def h(psi):
        F = B.branch_force(geom, KIN, 0.0, psi, "alpha", 1.0)
        d, cap = B.demand(geom, STAT, 0.0, psi, F, "phi")
        return d - cap
    lo, hi = 0.0, geom.qmax[1]
    assert h(lo) < 0 < h(hi)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if h(lo) * h(mid) <= 0 else (mid, hi)
    return B.branch_force(geom, KIN, 0.0, 0.5 * (lo + hi), "alpha", 1.0)


@pytest.mark.parametrize("model", ["seated", "two-phase"])
def test_tfp_machine_breaks_away_at_the_static_statics(model):
    """tfp-lab at 0.30 m, 0.02 Hz (quasi-static), mu_s = 0.11 / 0.03 on the
    outer / inner surfaces over mu_k = 0.10 / 0.02. Each force against the
    rigid model's closed-form branch force (mechanics/tfp.py, the step's mean
    of its two ends) within 0.5 %:
    the first step (the inner surfaces break away from rest): mu_s;
    the next steps: mu_k;
    the outer surfaces' first breakaway (I -> III, the largest force before it):
    the inner branch at mu_k against the outer cap at mu_s;
    regime III once the inner surfaces have unloaded (<= 5 steps): the outer
    branch at mu_k;
    the reversal at the peak (the inner surfaces, stuck in III, break away
    backwards): mu_s, the step after: mu_k."""
    over = ["loading.amplitude_m=0.3", "loading.frequency_Hz=0.02", "loading.cycles=0.75",
            'thermal.model="none"', f'mechanics.model="{model}"'] + STATIC_KEYS
    sim, res = _sim("tfp-lab", over)
    g = sim.geometry
    F, phi, al = res["F_N"], res["phi_rad"], res["alpha_rad"]

    def branch(mus, r, coord, s):
        a = B.branch_force(g, mus, phi[r - 1], phi[r - 1] + al[r - 1], coord, s)
        b = B.branch_force(g, mus, phi[r], phi[r] + al[r], coord, s)
        return 0.5 * (a + b)

    errs = {}
    errs["first step, mu_s"] = F[1] / branch(STAT, 1, "alpha", 1.0) - 1
    errs["second step, mu_k"] = F[2] / branch(KIN, 2, "alpha", 1.0) - 1
    errs["tenth step, mu_k"] = F[10] / branch(KIN, 10, "alpha", 1.0) - 1
    i = int(np.argmax(res["slide1"] > 0))
    assert res["regime"][i - 1] == 1 and i > 100
    errs["outer breakaway"] = np.max(F[:i + 1]) / _mixed_transition(g) - 1
    # (the inner surfaces unload in a step or two, both sliding: regime I+III)
    r3 = next(r for r in range(i + 1, i + 20) if res["regime"][r] == 3 and res["regime"][r - 1] == 3)
    assert r3 - i < 6
    errs["regime III, mu_k"] = F[r3] / branch(KIN, r3, "phi", 1.0) - 1
    j = int(np.argmax(res["u_m"]))
    rev = j + int(np.argmax(res["slide2"][j:] > 0))
    assert res["regime"][rev - 1] in (0, 3) and rev - j < 4
    errs["reversal, mu_s"] = F[rev] / branch(STAT, rev, "alpha", -1.0) - 1
    errs["after the reversal, mu_k"] = F[rev + 1] / branch(KIN, rev + 1, "alpha", -1.0) - 1
    bad = {k: v for k, v in errs.items() if abs(v) > 5e-3}
    assert not bad, (bad, errs)
    # the static coefficient is felt: the first step's force is ~ mu_s / mu_k of the sliding one's
    assert F[1] / branch(KIN, 1, "alpha", 1.0) > 1.4
    assert abs(res["E_input_J"][-1] - sum(res[f"W{k}_J"][-1] for k in range(1, 5)) - res["E_kin_J"][-1]
               - res["E_pot_J"][-1] - (res["E_reseat_J"][-1] if "E_reseat_J" in res.columns else 0.0)) \
        < 1e-9 * res["E_input_J"][-1]


def test_tfp_machine_without_static_keys_is_unchanged():
    """mu_s equal to the sliding mu (holding_mu then gives the sliding mu) runs the
    scene without the keys bit for bit."""
    base = ["loading.cycles=0.3", 'thermal.model="lumped"']
    _, a = _sim("tfp-lab", base)
    _, b = _sim("tfp-lab", base + [f"friction.S{i}.mu_static={m}" for i, m in zip(range(1, 5), KIN)])
    np.testing.assert_array_equal(a.data, b.data)


def _tfp_ground(model, A, mus_static):
    fr = {"law": "constant", "mu": KIN[0],
          "S2": {"law": "constant", "mu": KIN[1]}, "S3": {"law": "constant", "mu": KIN[2]}}
    if mus_static:
        for i, m in zip(range(1, 5), STAT):
            fr.setdefault(f"S{i}", {})["mu_static"] = m
    raw = _raw("tfp-lab", friction=fr, mechanics={"model": model}, thermal={"model": "none"},
               loading={"kind": "harmonic", "amplitude_m": A, "frequency_Hz": 1.0, "cycles": 2})
    sc = scn.validate(raw, "tfp-ground")
    res = simulate(build(sc))
    assert res.status == "ok", res.message
    return sc, res


def _tfp_threshold(geom, mus):
    """From rest the step's increment is zero while the ground's drive on each
    coordinate, a_g (P1 + P2) on phi and a_g P2 on alpha, stays inside its cap
    (the convex step's optimality at 0): a* = min(c_o / (P1 + P2), c_i / P2)."""
    p = geom.pack()
    W1, W2, W3, W4 = geom.static_weights()
    c_o = mus[0] * W1 * geom.R1 + mus[3] * W4 * geom.R4
    c_i = mus[1] * W2 * geom.R2 + mus[2] * W3 * geom.R3
    return min(c_o / (p[K.I_P1] + p[K.I_P2]), c_i / p[K.I_P2])


@pytest.mark.parametrize("model", ["seated", "two-phase"])
def test_tfp_breakaway_threshold_under_a_ground_motion(model):
    """A harmonic ground motion from rest whose peak acceleration is 1 % below
    the static threshold leaves the TFP stuck (it slides with the sliding mu
    alone), 1 % above breaks it away."""
    sc0 = scn.load("tfp-lab")
    g = scn.tfp_geometry(sc0.data)
    a_s, a_k = _tfp_threshold(g, STAT), _tfp_threshold(g, KIN)
    assert a_k < 0.9 * a_s
    peaks = {}
    for fac in (0.99, 1.01):
        A = fac * a_s / (2 * math.pi) ** 2
        for mus in (True, False):
            _, res = _tfp_ground(model, A, mus)
            peaks[fac, mus] = float(np.max(np.abs(res["u_m"])))
    assert peaks[0.99, True] == 0.0
    assert peaks[0.99, False] > 1e-4
    assert peaks[1.01, True] > 1e-6


@pytest.mark.parametrize("model", ["seated", "two-phase"])
def test_the_tfp_in_both_directions_breaks_away_as_the_planar_one(model):
    """The TFP in both directions takes the same static coefficients (one rule,
    tfp_kernel.holding_caps, in both kernels): a harmonic ground motion turned
    by 30 degrees whose peak acceleration is 1 % below the static threshold
    leaves it stuck, while with the sliding mu alone it slides; 1 % above, it
    breaks away, and its resultant history is the planar TFP's to 1e-9."""
    import sys
    from pathlib import Path
    from fpd.loading.ground_motion import harmonic_ground_motion
    from fpd.mechanics.tfp3d import TFP3DStepper
    from fpd.mechanics.tfp3d_two_phase import TFP3DTwoPhaseStepper
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from test_tfp3d import turned
    g = scn.tfp_geometry(scn.load("tfp-lab").data)
    a_s = _tfp_threshold(g, STAT)
    ang = math.radians(30.0)
    three = TFP3DTwoPhaseStepper if model == "two-phase" else TFP3DStepper
    peaks = {}
    for fac in (0.99, 1.01):
        gm = harmonic_ground_motion(fac * a_s / (2 * math.pi) ** 2, 1.0, 2, 1e-3)
        for static in (True, False):
            s3 = three(g, *turned(gm, ang))
            sp = T.TFPStepper(g, gm, model=model)
            if static:
                s3.set_static(STAT, (0.0,) * 4)
                sp.set_static(STAT, (0.0,) * 4)
            rows3, rowsp = [s3.values()], [sp.values()]
            for _ in range(gm.n_steps):
                s3.step(*KIN)
                sp.step(*KIN)
                rows3.append(s3.values())
                rowsp.append(sp.values())
            d3 = dict(zip(s3.columns, np.array(rows3).T))
            dp = dict(zip(sp.columns, np.array(rowsp).T))
            peaks[fac, static] = float(np.max(np.abs(d3["u_m"])))
            um = max(float(np.max(np.abs(dp["u_m"]))), 1e-300)
            assert np.max(np.abs(d3["ux_m"] * math.cos(ang) + d3["uy_m"] * math.sin(ang) - dp["u_m"])) <= 1e-9 * um
    assert peaks[0.99, True] == 0.0
    assert peaks[0.99, False] > 1e-4
    assert peaks[1.01, True] > 1e-6


# -- the flat bearing ------------------------------------------------------------------------
def test_flat_machine_breaks_away_at_mu_s_n():
    """flat-lab (the top face slides, mu 0.5) with mu_s = 0.6: the first step's
    force is mu_s N2, then mu_k N2 (within 0.5 %; the machine's launch from
    rest breaks the face away); the ledger closes."""
    sim, res = _sim("flat-lab", ["friction.upper.mu_static=0.6"])
    N2 = 1.0e4 * G_ACC
    F = res["F_N"]
    assert F[1] == pytest.approx(0.6 * N2, rel=5e-3)
    assert F[2] == pytest.approx(0.5 * N2, rel=5e-3)
    assert F[100] == pytest.approx(0.5 * N2, rel=5e-3)
    _, res0 = _sim("flat-lab", [])
    assert res0["F_N"][1] == pytest.approx(0.5 * N2, rel=5e-3)
    np.testing.assert_array_equal(res0["F_N"][2:], F[2:])


def _flat_ground(A, mu_static):
    fr = {"lower": {"law": "constant", "mu": 0.9}, "upper": {"law": "constant", "mu": 0.5}}
    if mu_static:
        fr["upper"]["mu_static"] = 0.6
    raw = _raw("flat-lab", friction=fr,
               loading={"kind": "harmonic", "amplitude_m": A, "frequency_Hz": 1.0, "cycles": 2})
    res = simulate(build(scn.validate(raw, "flat-ground")))
    assert res.status == "ok", res.message
    return res


def test_flat_breakaway_threshold_under_a_ground_motion():
    """From rest the faces hold while |a_g| (M + m) <= mu1 N1 and |a_g| M <= mu2 N2:
    a* = g min(mu1, mu2) = 0.6 g with mu_s = 0.6 on the top face; 1 % below stays
    stuck (the sliding mu alone slides), 1 % above breaks away."""
    a_s = 0.6 * G_ACC
    peaks = {}
    for fac in (0.99, 1.01):
        A = fac * a_s / (2 * math.pi) ** 2
        for mus in (True, False):
            peaks[fac, mus] = float(np.max(np.abs(_flat_ground(A, mus)["u_m"])))
    assert peaks[0.99, True] == 0.0
    assert peaks[0.99, False] > 1e-4
    assert peaks[1.01, True] > 1e-6
