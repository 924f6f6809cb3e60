"""Tribology: the Constantinou velocity law, breakaway (static) friction, the
compliant test-machine link (stick-slip), Archard wear and the liner presets,
each against a closed form or the run's own numbers."""
from __future__ import annotations

import math

import numpy as np
import pytest

import fpd
from fpd.tribology import friction_kernel as fk
from fpd.tribology.friction import Constantinou1990, make_law
from fpd.schema.scene import SceneError

G = 9.80665

# a DFP in the test machine, constant friction, lumped plates (quick)
LAB = {
    "name": "trib",
    "device": {"kind": "DFP", "R1": 2.2, "R2": 2.2, "pad_height": 0.10, "pad_diameter": 0.25, "pad_mass": 30.0},
    "superstructure": {"mass": 1.0e5},
    "friction": {"law": "constant", "mu": 0.05},
    "loading": {"kind": "displacement", "amplitude_m": 0.05, "frequency_Hz": 0.5, "cycles": 1},
    "mechanics": {"model": "seated"},
    "thermal": {"model": "lumped"},
    "solver": {"dt": 1.0e-3},
    "output": {"plots": False},
}


def lab(**over):
    import copy
    raw = copy.deepcopy(LAB)
    for key, value in over.items():
        table, name = key.split(".", 1) if "." in key else (key, None)
        if name is None:
            raw[table] = value
        else:
            raw.setdefault(table, {})[name] = value
    return raw


# -- the Constantinou velocity law -----------------------------------------------------------
def test_constantinou_law_closed_form():
    law = Constantinou1990(mu_slow=0.04, mu_fast=0.10, a_s_per_m=25.0)
    assert law(20.0, 0.0, 0.0) == 0.04
    assert law(20.0, 0.0, 10.0) == pytest.approx(0.10, abs=1e-12)
    for v in (-0.3, 0.001, 0.02, 0.04, 0.5):
        ref = 0.10 - (0.10 - 0.04) * math.exp(-25.0 * abs(v))
        assert law(80.0, 3e7, v) == pytest.approx(ref, rel=1e-15)
    # 1 - 1/e of the way at |v| = 1/a
    assert (law(20.0, 0.0, 1 / 25.0) - 0.04) / 0.06 == pytest.approx(1 - math.exp(-1), rel=1e-14)


def test_constantinou_law_from_a_scene():
    sc = fpd.load_scene(lab(friction={"law": "constantinou", "mu_slow": 0.03, "mu_fast": 0.09}))
    f = sc.friction("lower")
    assert (f["law"], f["mu_slow"], f["mu_fast"], f["a_s_per_m"]) == ("constantinou", 0.03, 0.09, 100.0)
    law = make_law(f)
    assert law(20.0, 0.0, 0.01) == pytest.approx(0.09 - 0.06 * math.exp(-1.0), rel=1e-15)
    with pytest.raises(SceneError, match="friction.mu_fast"):
        fpd.load_scene(lab(friction={"law": "constantinou", "mu_slow": 0.03, "mu_fast": 1.5}))
    with pytest.raises(SceneError, match="friction.a_s_per_m"):
        fpd.load_scene(lab(friction={"law": "constantinou", "mu_slow": 0.03, "mu_fast": 0.09,
                                     "a_s_per_m": -1.0}))


# -- breakaway (static) friction ------------------------------------------------------------
def _run(raw):
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate
    sc = fpd.load_scene(raw)
    res = simulate(build(sc))
    assert res.status == "ok", res.message
    return sc, res


def _caps(sc, mu):
    """The DFP's statics at u = 0: the friction part of the restraint force,
    mu (N1 R1 + N2 R2) / L (not mu N), the machine holding the load at M g."""
    from fpd.coupling.build import geometry_of
    g = geometry_of(sc)
    N2 = g.mass * g.g
    N1 = N2 + g.pad_mass * g.g
    return mu * (N1 * g.R1 + N2 * g.friction_radius2) / g.L, g


@pytest.mark.parametrize("direction", [0.0, 30.0])     # the planar machine; the orbit machine
def test_breakaway_force_on_the_test_machine(direction):
    """A slow sine from rest, mu_s = 0.08 > mu_k = 0.05: the first step's force is
    the statics with mu_s, the force at the return through u = 0 the statics
    with mu_k (both within 0.5 %; measured 1e-9 and 6e-6)."""
    sc, res = _run(lab(friction={"law": "constant", "mu": 0.05, "mu_static": 0.08},
                       loading={"kind": "displacement", "amplitude_m": 0.05, "frequency_Hz": 0.05, "cycles": 1,
                                "direction_deg": direction}))
    F = res["F_N"]
    u = res["u_m"]
    Fs, _ = _caps(sc, 0.08)
    Fk, _ = _caps(sc, 0.05)
    assert F[1] == pytest.approx(Fs, rel=5e-3)
    assert F[1] == pytest.approx(Fs, rel=1e-4)            # what it measures
    half = len(u) // 2                                    # back through u = 0, sliding towards -u
    assert abs(u[half]) < 1e-12
    assert abs(F[half]) == pytest.approx(Fk, rel=5e-3)
    assert F[2] == pytest.approx(Fk, rel=5e-3)            # sliding right after the breakaway
    # without mu_static the first step carries the sliding force
    _, res0 = _run(lab(friction={"law": "constant", "mu": 0.05},
                       loading={"kind": "displacement", "amplitude_m": 0.05, "frequency_Hz": 0.05, "cycles": 1,
                                "direction_deg": direction}))
    assert res0["F_N"][1] == pytest.approx(Fk, rel=5e-3)
    np.testing.assert_array_equal(res0["F_N"][2:], F[2:])


@pytest.mark.parametrize("model", ["seated", "two-phase"])
def test_breakaway_threshold_under_a_ground_motion(model):
    """From rest the pad holds while the ground's drive S a_g stays inside the
    static cap mu_s (N1 R1 + N2 R2): a harmonic ground motion whose peak
    acceleration is 1 % below that threshold leaves it stuck (it slides with
    the sliding mu alone), 1 % above breaks it away."""
    sc0 = fpd.load_scene(lab())
    Fs, g = _caps(sc0, 0.08)
    a_break = Fs * g.L / g.S
    peaks = {}
    for fac in (0.99, 1.01):
        A = fac * a_break / (2 * math.pi) ** 2
        for mus in (0.08, None):
            fr = {"law": "constant", "mu": 0.05}
            if mus:
                fr["mu_static"] = mus
            _, res = _run(lab(friction=fr, mechanics={"model": model},
                              loading={"kind": "harmonic", "amplitude_m": A, "frequency_Hz": 1.0, "cycles": 2}))
            peaks[fac, mus] = float(np.max(np.abs(res["u_m"])))
    assert peaks[0.99, 0.08] == 0.0
    assert peaks[0.99, None] > 1e-3
    assert peaks[1.01, 0.08] > 1e-3


def test_mu_static_refused_below_the_sliding_mu_on_every_device():
    with pytest.raises(SceneError, match=r"friction.mu_static = 0.04: must be >= the sliding mu \(0.05"):
        fpd.load_scene(lab(friction={"law": "constant", "mu": 0.05, "mu_static": 0.04}))
    with pytest.raises(SceneError, match=r"friction.lower.mu_static = 0.02: must be >= the sliding mu \(0.03"):
        fpd.load_scene(lab(friction={"law": "constantinou", "mu_slow": 0.03, "mu_fast": 0.09,
                                     "lower": {"mu_static": 0.02}}))
    fpd.load_scene(lab(friction={"law": "constantinou", "mu_slow": 0.03, "mu_fast": 0.09, "mu_static": 0.05}))
    fpd.load_scene("tfp-elcentro", **{"friction.mu_static": 0.5})
    with pytest.raises(SceneError, match=r"friction.S2.mu_static = 0.01: must be >= the sliding mu \(0.02"):
        fpd.load_scene("tfp-lab", **{"friction.S2.mu_static": 0.01})


# -- dwell: the static coefficient grows with the time stuck --------------------------------
def kato(t, mu0, mu_inf, tau, m=1.0):
    """Kato, Sato and Matsubayashi (1972): mu_s(t) = mu_inf - (mu_inf - mu0) exp(-(t / tau)^m)."""
    return mu_inf - (mu_inf - mu0) * math.exp(-((t / tau) ** m))


@pytest.mark.parametrize("hold,m,direction", [(0.0, 1.0, 0.0), (0.5, 1.0, 0.0), (2.0, 1.0, 0.0), (6.0, 1.0, 0.0),
                                              (3.0, 0.5, 0.0), (0.0, 1.0, 30.0), (2.0, 1.0, 30.0),
                                              (3.0, 0.5, 30.0)])
def test_breakaway_after_a_hold_follows_the_dwell_law(hold, m, direction):
    """The machine (planar, or the orbit machine along a turned sine) holds the
    bearing at rest under its load for `hold` s, then drives a slow sine: the
    breakaway force is the statics with mu_s(hold) = mu_inf - (mu_inf - mu_s)
    exp(-(hold / tau)^m) in place of the sliding mu (within 0.5 %; measured
    4e-10 planar, 6e-6 on the orbit machine), the force while held zero, the
    sliding force afterwards the statics with the sliding mu, the ledger closed
    (the restart's launch is input)."""
    dt = LAB["solver"]["dt"]
    ld = {"kind": "displacement", "amplitude_m": 0.05, "frequency_Hz": 0.05, "cycles": 0.25,
          "direction_deg": direction}
    if hold:
        ld["hold_s"] = hold
    fr = {"law": "constant", "mu": 0.05, "mu_static": 0.06, "mu_static_inf": 0.09, "dwell_time_s": 2.0,
          "dwell_exponent": m}
    sc, res = _run(lab(friction=fr, loading=ld))
    F, u = res["F_N"], res["u_m"]
    nh = int(round(hold / dt))
    assert np.all(u[:nh + 1] == 0.0) and np.all(F[:nh + 1] == 0.0) and u[nh + 1] > 0.0
    Fs, _ = _caps(sc, kato(hold, 0.06, 0.09, 2.0, m))
    assert F[nh + 1] == pytest.approx(Fs, rel=5e-3)
    assert F[nh + 1] == pytest.approx(Fs, rel=1e-8 if direction == 0.0 else 1e-5)     # what it measures
    Fk, _ = _caps(sc, 0.05)
    assert F[nh + 2] == pytest.approx(Fk, rel=5e-3)
    ledger = res["E_input_J"] - (res["E_kin_J"] + res["E_pot_J"] + res["W1_J"] + res["W2_J"])
    assert np.max(np.abs(ledger)) < 1e-6 * float(res["W1_J"][-1] + res["W2_J"][-1])


def test_a_hold_shifts_the_programme_and_its_cycles():
    """A hold of 1.5 s before the programme: the run after it is the run without
    it, shifted (no static coefficient: nothing depends on the time at rest;
    lumped plates at their initial temperature meanwhile), and the per-cycle
    test quantities count the cycles from the programme's start."""
    base = {"kind": "displacement", "amplitude_m": 0.05, "frequency_Hz": 0.5, "cycles": 2}
    a = fpd.run(lab(loading=base), output={"plots": False})
    b = fpd.run(lab(loading=dict(base, hold_s=1.5)), output={"plots": False})
    n = 1500
    assert np.all(b.history["u_m"][:n + 1] == 0.0) and np.all(b.history["F_N"][:n + 1] == 0.0)
    for col in ("u_m", "F_N", "W1_J", "T1_C"):
        np.testing.assert_allclose(b.history[col][n:], a.history[col], rtol=1e-12, atol=1e-9)
    ca, cb = a.summary["test_machine"]["cycles"], b.summary["test_machine"]["cycles"]
    assert len(ca) == len(cb) == 2
    for x, y in zip(ca, cb):
        assert y["t_start_s"] == pytest.approx(x["t_start_s"] + 1.5, abs=1e-12)
        assert y["EDC_J"] == pytest.approx(x["EDC_J"], rel=1e-12)


def test_dwell_grows_the_threshold_under_a_compliant_link():
    """Through the compliant link from zero force, the plate stuck from the
    start (or after a hold): the first breakaway comes when the link's force
    k V (t - hold) reaches the statics with mu_s(t), the static coefficient
    grown by the time stuck (the root of that equation; within 0.5 %, measured
    2e-4: the sub-step's start dwell)."""
    from scipy.optimize import brentq
    k, mp, V = 2e6, 2000.0, 0.01
    for hold in (0.0, 3.0):
        ld = {"kind": "displacement", "waveform": "triangle", "amplitude_m": 0.15, "frequency_Hz": V / 0.6,
              "cycles": 0.25, "link_stiffness_N_per_m": k, "link_mass_kg": mp}
        if hold:
            ld["hold_s"] = hold
        sc, res = _run(lab(friction={"law": "constant", "mu": 0.05, "mu_static": 0.06, "mu_static_inf": 0.10,
                                     "dwell_time_s": 4.0}, loading=ld))
        ts = brentq(lambda t: k * V * (t - hold) - _caps(sc, kato(t, 0.06, 0.10, 4.0))[0], hold, hold + 100.0)
        t, F, ph = res["t_s"], res["F_N"], np.asarray(res["phase"])
        first = np.where((ph[1:] != 0) & (ph[:-1] == 0))[0][0] + 1
        assert t[first] == pytest.approx(ts, abs=2e-3)
        assert F[first - 1] == pytest.approx(_caps(sc, kato(ts, 0.06, 0.10, 4.0))[0], rel=5e-3)


@pytest.mark.parametrize("model", ["seated", "two-phase"])
def test_dwell_raises_the_threshold_under_a_ground_motion(model):
    """The ground at rest for t0 = 10 s, then a cosine velocity pulse whose
    acceleration peaks at t0 + Tp / 4: the pad, stuck from the start, holds
    while S a_g stays inside the static cap with mu_s(t), the coefficient
    grown by the time stuck (tau = 10 s: mu_s 0.060 -> 0.079 at the peak).
    A peak 1 % below the threshold with mu_s(t0 + Tp / 4) leaves it stuck,
    1 % above breaks it away; without the dwell law the lower pulse slides."""
    t0, Tp, tau = 10.0, 0.5, 10.0
    sc0 = fpd.load_scene(lab())
    Fs, g = _caps(sc0, kato(t0 + 0.25 * Tp, 0.06, 0.09, tau))
    a_break = Fs * g.L / g.S
    peaks = {}
    for fac in (0.99, 1.01):
        for dwell in (True, False):
            fr = {"law": "constant", "mu": 0.05, "mu_static": 0.06}
            if dwell:
                fr.update(mu_static_inf=0.09, dwell_time_s=tau)
            _, res = _run(lab(friction=fr, mechanics={"model": model},
                              loading={"kind": "pulse", "shape": "cosine", "velocity_mps": fac * a_break * Tp / math.pi,
                                       "period_s": Tp, "t0_s": t0, "duration_s": t0 + Tp + 0.5}))
            peaks[fac, dwell] = float(np.max(np.abs(res["u_m"])))
    assert peaks[0.99, True] == 0.0
    assert peaks[1.01, True] > 1e-3
    assert peaks[0.99, False] > 1e-3


def test_dwell_keys_refused():
    base = {"law": "constant", "mu": 0.05}
    with pytest.raises(SceneError, match=r"friction.dwell_time_s = -1: must be > 0"):
        fpd.load_scene(lab(friction=dict(base, mu_static_inf=0.08, dwell_time_s=-1.0)))
    with pytest.raises(SceneError, match=r"friction.dwell_exponent = 0: must be > 0"):
        fpd.load_scene(lab(friction=dict(base, mu_static_inf=0.08, dwell_time_s=1.0, dwell_exponent=0.0)))
    with pytest.raises(SceneError, match=r"friction.mu_static_inf = 0.08: needs dwell_time_s too"):
        fpd.load_scene(lab(friction=dict(base, mu_static_inf=0.08)))
    with pytest.raises(SceneError, match=r"friction.dwell_time_s = 1: needs mu_static_inf too"):
        fpd.load_scene(lab(friction=dict(base, dwell_time_s=1.0)))
    with pytest.raises(SceneError, match=r"friction.dwell_exponent = 0.5: needs mu_static_inf and dwell_time_s"):
        fpd.load_scene(lab(friction=dict(base, dwell_exponent=0.5)))
    with pytest.raises(SceneError, match=r"friction.lower.mu_static_inf = 0.07: must be >= the static coefficient "
                                         r"at zero dwell \(0.075"):
        fpd.load_scene(lab(friction=dict(base, mu_static=0.075, lower={"mu_static_inf": 0.07, "dwell_time_s": 1.0})))
    with pytest.raises(SceneError, match=r"friction.mu_static_inf = 0.07: must be >= the static coefficient "
                                         r"at zero dwell \(0.08"):
        fpd.load_scene(lab(friction=dict(base, static_ratio=1.6, mu_static_inf=0.07, dwell_time_s=1.0)))
    with pytest.raises(SceneError, match=r"loading.hold_s = -2: must be >= 0"):
        fpd.load_scene(lab(loading=dict(LAB["loading"], hold_s=-2.0)))
    # the DFP and the SFP only: the TFP and the flat bearing refuse it in one line
    dwell = dict(base, mu_static_inf=0.08, dwell_time_s=1.0)
    with pytest.raises(SceneError, match=r"friction.S1.mu_static_inf = 0.9: the static coefficient's growth with "
                                         r"dwell is modelled for the DFP and the SFP only, not the TFP"):
        fpd.load_scene("tfp-lab", **{"friction.S1.mu_static_inf": 0.9, "friction.S1.dwell_time_s": 1.0})
    with pytest.raises(SceneError, match=r"friction.mu_static_inf = 0.95: .*DFP and the SFP only, not the flat"):
        fpd.load_scene("flat-lab", **{"friction.mu_static_inf": 0.95, "friction.dwell_time_s": 1.0})
    fpd.load_scene(lab(friction=dwell, loading={"kind": "harmonic", "amplitude_m": 0.01, "frequency_Hz": 1.0,
                                               "cycles": 1}))
    with pytest.raises(SceneError, match=r"loading.hold_s = 1: the hold is the DFP / SFP test machines'"):
        fpd.load_scene("tfp-lab", **{"loading.hold_s": 1.0})
    fpd.load_scene(lab(friction=dwell, loading=dict(LAB["loading"], direction_deg=30.0, hold_s=1.0)))


def test_orbit_link_compiled_equals_pure(monkeypatch):
    """The link on the orbit machine in the compiled engine: the same history bit for bit."""
    pytest.importorskip("numba")
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    raw = lab(friction={"law": "constant", "mu": 0.05, "mu_static": 0.08, "mu_static_inf": 0.09, "dwell_time_s": 2.0},
              loading={"kind": "displacement", "waveform": "triangle", "amplitude_m": 0.15, "frequency_Hz": 0.05,
                       "cycles": 0.25, "direction_deg": 30.0, "link_stiffness_N_per_m": 2e6, "link_mass_kg": 2000.0})
    _, a = _run(raw)
    monkeypatch.setenv("FPD_NO_JIT", "1")
    _, b = _run(raw)
    assert a.columns == b.columns
    np.testing.assert_array_equal(a.data, b.data)
    assert np.count_nonzero(np.diff(np.asarray(a["phase"])) > 0) >= 2     # it stuck and slipped


@pytest.mark.parametrize("direction", [0.0, 30.0, None])    # the planar machine; the orbit machine; a ground motion
def test_dwell_compiled_equals_pure(monkeypatch, direction):
    """The dwell law and the hold in the compiled engine: the same history bit for bit."""
    pytest.importorskip("numba")
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    fr = {"law": "constant", "mu": 0.05, "mu_static": 0.06, "mu_static_inf": 0.09, "dwell_time_s": 2.0,
          "dwell_exponent": 0.7}
    if direction is None:
        raw = lab(friction=fr, loading={"kind": "pulse", "shape": "cosine", "velocity_mps": 0.3, "period_s": 0.5,
                                        "t0_s": 1.5, "duration_s": 3.0})
        _, a = _run(raw)
        monkeypatch.setenv("FPD_NO_JIT", "1")
        _, b = _run(raw)
        assert a.columns == b.columns
        np.testing.assert_array_equal(a.data, b.data)
        assert np.max(np.abs(a["u_m"])) > 1e-3
        return
    raw = lab(friction=fr, loading={"kind": "displacement", "amplitude_m": 0.05, "frequency_Hz": 0.5, "cycles": 1,
                                    "hold_s": 1.5, "direction_deg": direction})
    _, a = _run(raw)
    monkeypatch.setenv("FPD_NO_JIT", "1")
    _, b = _run(raw)
    assert a.columns == b.columns
    np.testing.assert_array_equal(a.data, b.data)
    assert a["F_N"][1501] > 1.3 * a["F_N"][1502]             # the breakaway after the hold


# -- stick-slip through a compliant link ----------------------------------------------------
def spring_block(k, m, Kb, Fs, Fk, V):
    """The spring-block with static and kinetic friction, driven at speed V
    through a spring k, with the bearing's restoring stiffness Kb
    (docs/model.md, "Stick-slip"): (slip time, stick time, period, drop of the
    link's force over a slip)."""
    K = k + Kb
    w = math.sqrt(K / m)
    D = Fs - Fk
    c = k * V / (D * w)
    phi = 2.0 * math.pi - 2.0 * math.atan(1.0 / c)
    y0, yd0 = -D / K, -k * V / K
    y1 = y0 * math.cos(phi) + yd0 / w * math.sin(phi)
    t_slip = phi / w
    t_stick = (D + K * y1) / (k * V)
    dx = k * V * t_slip / K + y1 - y0
    drop = D + K * y1 - Kb * dx                     # (Fs + Kb x0) - (Fk - K y1 + Kb x1)
    return t_slip, t_stick, t_slip + t_stick, drop


def test_stick_slip_saw_tooth_matches_the_spring_block():
    """A slow triangle drive (10 mm/s) through a 2 MN/m link onto a 2 t plate,
    mu_s = 0.08, mu_k = 0.05: the saw-tooth's period and force drop are the
    spring-block's with the bearing's restoring stiffness S g / L^2 and its
    inertia added to the plate's (within 1 %; measured 3e-4 and 2e-4); the
    first breakaway comes when the link carries the static cap."""
    k, mp, V = 2e6, 2000.0, 0.01
    sc, res = _run(lab(friction={"law": "constant", "mu": 0.05, "mu_static": 0.08},
                       loading={"kind": "displacement", "waveform": "triangle", "amplitude_m": 0.15,
                                "frequency_Hz": V / 0.6, "cycles": 0.25,
                                "link_stiffness_N_per_m": k, "link_mass_kg": mp}))
    Fs, g = _caps(sc, 0.08)
    Fk, _ = _caps(sc, 0.05)
    Ip, Sin = g.I - g.mass * g.L ** 2, g.S - g.mass * g.L      # the machine holds the load (seated.py)
    m = mp + Ip / g.L ** 2 - Sin / g.L
    Kb = g.S * g.g / g.L ** 2
    t_slip, t_stick, T, drop = spring_block(k, m, Kb, Fs, Fk, V)
    t, F, ph = res["t_s"], res["F_N"], np.asarray(res["phase"])
    starts = np.where((ph[1:] != 0) & (ph[:-1] == 0))[0] + 1
    assert len(starts) >= 4
    assert t[starts[0]] == pytest.approx(Fs / (k * V), abs=2e-3)   # the first breakaway, from zero force
    assert F[starts[0] - 1] == pytest.approx(Fs, rel=5e-3)
    periods = np.diff(t[starts])
    assert periods[0] == pytest.approx(T, rel=1e-2)
    assert periods[0] == pytest.approx(T, rel=1e-3)                # what it measures
    for a, b in zip(starts[:2], starts[1:3]):
        stops = a + np.where(ph[a:b] == 0)[0][0]                    # the first stuck row after the slip
        seg = F[a - 1:stops + 1]
        assert seg.max() - seg.min() == pytest.approx(drop, rel=1e-2)
    # the slip lasts the closed form's time (to the rows' resolution)
    first_stop = starts[0] + np.where(ph[starts[0]:] == 0)[0][0]
    assert t[first_stop] - t[starts[0]] == pytest.approx(t_slip, abs=2.5e-3)


def test_stick_slip_along_a_straight_orbit_matches_the_spring_block():
    """The orbit machine (a triangle turned by 30 degrees, the superstructure a
    riding mass) through the same link: the plate stays on the line (the force
    across it below 1e-9 of the along one), and the saw-tooth's period and
    force drop along the line are the spring-block's with the bearing's
    restoring stiffness S g / L^2 and inertia I / L^2 - S / L (the riding
    mass's, whose M L^2 and M L cancel) within 1 % (measured 2.3e-3 and 3e-3:
    the riding mass's vertical inertia varies N slightly); the first
    breakaway when the link carries the static cap."""
    k, mp, V, d = 2e6, 2000.0, 0.01, math.radians(30.0)
    sc, res = _run(lab(friction={"law": "constant", "mu": 0.05, "mu_static": 0.08},
                       loading={"kind": "displacement", "waveform": "triangle", "amplitude_m": 0.15,
                                "frequency_Hz": V / 0.6, "cycles": 0.25, "direction_deg": 30.0,
                                "link_stiffness_N_per_m": k, "link_mass_kg": mp}))
    Fs, g = _caps(sc, 0.08)
    Fk, _ = _caps(sc, 0.05)
    m = mp + g.I / g.L ** 2 - g.S / g.L
    Kb = g.S * g.g / g.L ** 2
    t_slip, t_stick, T, drop = spring_block(k, m, Kb, Fs, Fk, V)
    F = res["Fx_N"] * math.cos(d) + res["Fy_N"] * math.sin(d)
    across = -res["Fx_N"] * math.sin(d) + res["Fy_N"] * math.cos(d)
    assert np.max(np.abs(across)) < 1e-9 * np.max(np.abs(F))
    assert np.max(np.abs(-res["ux_m"] * math.sin(d) + res["uy_m"] * math.cos(d))) < 1e-12
    t, ph = res["t_s"], np.asarray(res["phase"])
    starts = np.where((ph[1:] != 0) & (ph[:-1] == 0))[0] + 1
    assert len(starts) >= 4
    assert t[starts[0]] == pytest.approx(Fs / (k * V), abs=2e-3)
    assert F[starts[0] - 1] == pytest.approx(Fs, rel=5e-3)
    periods = np.diff(t[starts])
    for p in periods[:3]:
        assert p == pytest.approx(T, rel=1e-2)
    for a, b in zip(starts[:2], starts[1:3]):
        stops = a + np.where(ph[a:b] == 0)[0][0]
        seg = F[a - 1:stops + 1]
        assert seg.max() - seg.min() == pytest.approx(drop, rel=1e-2)
    ledger = res["E_input_J"] - (res["E_kin_J"] + res["E_pot_J"] + res["W1_J"] + res["W2_J"])
    assert np.max(np.abs(ledger)) < 1e-3 * float(res["W1_J"][-1] + res["W2_J"][-1])


def test_link_refused_off_a_straight_programme():
    link = {"link_stiffness_N_per_m": 2e6, "link_mass_kg": 2000.0}
    with pytest.raises(SceneError, match=r"loading.link_stiffness_N_per_m = 2e\+06: the compliant link drives a "
                                         r"straight programme only"):
        fpd.load_scene(lab(loading=dict(LAB["loading"], waveform="circle", **link)))
    with pytest.raises(SceneError, match=r"loading.link_stiffness_N_per_m = 2e\+06: the compliant link needs the "
                                         r"machine's default vertical load"):
        fpd.load_scene(lab(loading=dict(LAB["loading"], vertical="riding-mass", **link)))
    with pytest.raises(SceneError, match=r"loading.link_stiffness_N_per_m = 2e\+06: the compliant link needs"):
        fpd.load_scene(lab(loading=dict(LAB["loading"], direction_deg=30.0, vertical="sine",
                                        vertical_amplitude_ratio=0.1, vertical_frequency_Hz=1.0, **link)))
    fpd.load_scene(lab(loading=dict(LAB["loading"], direction_deg=30.0, waveform="triangle", **link)))


# -- wear ------------------------------------------------------------------------------------
def test_archard_wear_equals_the_integral_of_its_own_pressure_and_path():
    """Three cycles of +-0.1 m on the machine, kumar2015 heating, k_w a table in T:
    the depth equals the Archard sum k_w(T) (N / A) d(path) recomputed from the
    run's own columns (k_w at the row before: the temperature the step's mu
    used) within 0.1 % (measured 1e-15), and the path is the arcs slid,
    R_i sum |d theta| (an independent count) within 1e-5 (measured 2e-6: the
    step's work has the mean normal force, the path divides by the end one)."""
    sc, res = _run(lab(friction={"law": "kumar2015", "mu_ref": 0.06, "wear_T_C": [20.0, 20.5],
                                 "wear_k_T_mm3_per_Nm": [1e-6, 5e-6]},
                       loading={"kind": "displacement", "amplitude_m": 0.1, "frequency_Hz": 0.5, "cycles": 3}))
    from fpd.coupling.build import geometry_of
    g = geometry_of(sc)
    A = g.contact_area
    th = res["theta_rad"]
    for i, R in ((1, g.R1), (2, g.friction_radius2)):
        p, w, N, T = res[f"path{i}_m"], res[f"wear{i}_m"], res[f"N{i}_N"], res[f"T{i}_C"]
        k = np.interp(T[:-1], [20.0, 20.5], [1e-15, 5e-15])
        ref = float(np.sum(k * N[1:] / A * np.diff(p)))
        assert w[-1] == pytest.approx(ref, rel=1e-3)
        assert w[-1] == pytest.approx(ref, rel=1e-12)
        assert p[-1] == pytest.approx(R * np.sum(np.abs(np.diff(th))), rel=1e-5)
        assert np.all(np.diff(w) >= 0) and T.max() > 20.2       # k_w rose with the temperature
    s = fpd.run(lab(friction={"law": "constant", "mu": 0.05, "lower": {"wear_k_mm3_per_Nm": 3e-6}},
                    loading={"kind": "displacement", "amplitude_m": 0.1, "frequency_Hz": 0.5, "cycles": 1}),
                output={"plots": False}).summary
    assert set(s["wear"]) == {"lower", "upper"}
    assert s["wear"]["upper"]["depth_m"] == 0.0 and s["wear"]["upper"]["path_m"] > 0.2
    lo = s["wear"]["lower"]
    # a constant k_w and pressure: depth = k_w (N1 / A) path, N1 = (M + m) g held
    assert lo["depth_m"] == pytest.approx(3e-15 * (1e5 + 30.0) * G / A * lo["path_m"], rel=1e-3)


def test_wear_keys_refused():
    with pytest.raises(SceneError, match="friction.wear_k_mm3_per_Nm = -1: must be >= 0"):
        fpd.load_scene(lab(friction={"law": "constant", "mu": 0.05, "wear_k_mm3_per_Nm": -1.0}))
    with pytest.raises(SceneError, match="friction.wear_k_T_mm3_per_Nm = .*every entry must be >= 0"):
        fpd.load_scene(lab(friction={"law": "constant", "mu": 0.05, "wear_T_C": [0.0, 50.0],
                                     "wear_k_T_mm3_per_Nm": [1e-6, -1e-6]}))
    with pytest.raises(SceneError, match="wear_T_C and wear_k_T_mm3_per_Nm together"):
        fpd.load_scene(lab(friction={"law": "constant", "mu": 0.05, "wear_T_C": [0.0, 50.0]}))


def test_constantinou_compiled_equals_pure(monkeypatch):
    """The law in the compiled engine: the same history bit for bit."""
    pytest.importorskip("numba")
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    raw = lab(friction={"law": "constantinou", "mu_slow": 0.03, "mu_fast": 0.09, "a_s_per_m": 30.0,
                        "mu_static": 0.05})
    _, a = _run(raw)
    monkeypatch.setenv("FPD_NO_JIT", "1")
    _, b = _run(raw)
    assert a.columns == b.columns
    np.testing.assert_array_equal(a.data, b.data)
    assert a["mu1"].min() < 0.04 < a["mu1"].max()          # the speed moved mu


# -- liner presets ---------------------------------------------------------------------------
def test_liner_presets_apply_and_override_key_by_key():
    from fpd.tribology.friction import LINERS
    from pathlib import Path
    doc = (Path(__file__).resolve().parents[1] / "docs" / "liners.md").read_text()
    for name, preset in LINERS.items():
        # every value has its source entry (test_every_liner_value_cites_its_source), and the docs list it
        assert set(preset["sources"]) == set(preset["values"]), name
        assert f"| `{name}` |" in doc, name
        f = fpd.load_scene(lab(friction={"liner": name})).friction("lower")
        assert f["liner"] == name
        for key, value in preset["values"].items():
            assert f[key] == value, (name, key)
    # key by key: the scene's mu_fast wins, the rest stays the preset's; per surface
    sc = fpd.load_scene(lab(friction={"liner": "ptfe", "mu_fast": 0.12, "upper": {"liner": "ptfe-composite"}}))
    lo, up = sc.friction("lower"), sc.friction("upper")
    assert (lo["mu_fast"], lo["mu_slow"], lo["wear_k_mm3_per_Nm"]) == (0.12, 0.04, 3e-4)
    assert (up["mu_fast"], up["mu_slow"], up["wear_k_mm3_per_Nm"]) == (0.12, 0.03, 1e-6)   # the base key: both
    # a law of its own replaces the preset's law and coefficients, keeps mu_static and the wear
    f = fpd.load_scene(lab(friction={"liner": "ptfe", "law": "constant", "mu": 0.05})).friction("lower")
    assert (f["law"], f["mu"], f["mu_static"], f["wear_k_mm3_per_Nm"]) == ("constant", 0.05, 0.10, 3e-4)
    assert "mu_slow" not in f
    with pytest.raises(SceneError, match=r'friction.liner = \'teflon\': must be one of "ptfe", '
                                         r'"ptfe-lubricated", "ptfe-composite"$'):
        fpd.load_scene(lab(friction={"liner": "teflon"}))
    # a liner with no published friction to preset says so, and what to give instead
    with pytest.raises(SceneError) as e:
        fpd.load_scene(lab(friction={"liner": "ptfe", "upper": {"liner": "UHMWPE"}}))
    msg = str(e.value)
    assert "\n" not in msg and "friction.upper.liner = 'UHMWPE': no preset: no published friction" in msg
    assert 'give its law and coefficients' in msg and msg.endswith('"ptfe-composite"')
    # the TFP models breakaway as the DFP does: a preset's mu_static applies there, and
    # is checked against the scene's own law at rest (kumar2015, mu_ref 0.10: 0.100096 > 0.10)
    f = fpd.load_scene("tfp-elcentro", friction={"liner": "ptfe", "mu_ref": 0.09}).friction("S1")
    assert f["mu_static"] == 0.10 and f["wear_k_mm3_per_Nm"] == 3e-4 and f["law"] == "kumar2015"
    with pytest.raises(SceneError, match=r"friction.mu_static = 0.1: must be >= the sliding mu \(0.100096"):
        fpd.load_scene("tfp-elcentro", friction={"liner": "ptfe"})


def test_every_liner_value_cites_its_source():
    """Each preset value has a source entry: a reference of LINER_SOURCES (a full
    citation: authors, year, title, where) or none, whether the reference
    states that number (then the note quotes it) or the basis used; every
    reference is cited; docs/liners.md carries the table generated from the
    data, nothing marked a placeholder."""
    import re
    from pathlib import Path
    from fpd.frontends.reference import LINER_BEGIN, LINER_END, liner_markdown
    from fpd.tribology.friction import LINER_SOURCES, LINERS
    cited = set()
    for name, preset in LINERS.items():
        assert set(preset["sources"]) == set(preset["values"]), name
        for key, value in preset["values"].items():
            src = preset["sources"][key]
            assert set(src) == {"ref", "stated", "note"}, (name, key)
            assert len(src["note"]) > 20, (name, key)
            if src["ref"] is None:
                assert not src["stated"] and "no published value" in src["note"], (name, key)
                assert "basis" in src["note"], (name, key)
            else:
                assert src["ref"] in LINER_SOURCES, (name, key)
                cited.add(src["ref"])
            if src["stated"] and isinstance(value, float):
                assert src["ref"] is not None and f"{value:g}" in src["note"], (name, key)
    assert cited == set(LINER_SOURCES)
    for ref, text in LINER_SOURCES.items():
        # a publication by year and title, or a report by its number and where to find it
        assert re.search(r"\((19|20)\d\d\)", text) and '"' in text or "Handbook" in text \
            or re.search(r"Report \w+ \d+.*https://", text), ref
    # EN 1337-2 Eq. (B.1) at >= 30 MPa gives the lubricated preset's 0.03
    assert LINERS["ptfe-lubricated"]["values"]["mu_static"] == pytest.approx(1.2 / (10.0 + 30.0), abs=1e-15)
    doc = (Path(__file__).resolve().parents[1] / "docs" / "liners.md").read_text()
    block = doc[doc.index(LINER_BEGIN) + len(LINER_BEGIN):doc.index(LINER_END)].strip()
    assert block == "\n".join(liner_markdown()).strip(), "docs/liners.md: regenerate its liner table"
    assert "placeholder" not in doc.lower()


def test_compare_liners_tabulates_each_preset(tmp_path):
    """`fpd compare --liners`: one row per preset with the five quantities; on the
    test machine (the displacement imposed) the friction work follows the
    presets' friction (lubricated PTFE least, dry PTFE most), the peak
    displacement is the programme's, and the wear column is the run's own."""
    import csv
    import json
    from fpd.frontends import cli
    from fpd.tribology.friction import LINERS
    out = tmp_path / "cl"
    assert cli.main(["compare", "lab-sine", "--liners", "--fast", "--out", str(out), "--quiet"]) == 0
    with open(out / "liners.csv") as fh:
        rows = {r["liner"]: r for r in csv.DictReader(fh)}
    assert list(rows) == list(LINERS)
    for r in rows.values():
        assert r["status"] == "ok"
        assert float(r["peak_u_m"]) == pytest.approx(0.25, rel=1e-9)
        assert abs(float(r["residual_u_m"])) < 1e-9
        assert float(r["peak_T_C"]) > 20.0
    work = {k: float(r["friction_work_J"]) for k, r in rows.items()}
    assert work["ptfe-lubricated"] < work["ptfe-composite"] < work["ptfe"]
    assert rows["ptfe-lubricated"]["max_wear_m"] in ("", "nan")      # no wear coefficient
    assert float(rows["ptfe"]["max_wear_m"]) > 100 * float(rows["ptfe-composite"]["max_wear_m"]) > 0.0
    s = json.loads((out / "summary.json").read_text())
    assert s["study"] == "compare-liners" and len(s["rows"]) == len(LINERS)
    assert "| ptfe |" in (out / "liners.md").read_text()


def test_static_ratio_follows_the_temperature():
    """static_ratio = 1.6 with a law falling with T, the plates starting at 60 degC:
    the breakaway force is the statics with 1.6 mu(60 degC) = 1.6 x 0.042, the
    sliding force afterwards the statics with the sliding mu (within 0.5 %)."""
    fr = {"law": "linear", "mu0": 0.05, "T0_C": 20.0, "slope_per_C": -2e-4, "static_ratio": 1.6}
    sc, res = _run(lab(friction=fr, thermal={"model": "lumped", "T0_C": 60.0},
                       loading={"kind": "displacement", "amplitude_m": 0.05, "frequency_Hz": 0.05, "cycles": 0.5}))
    Fs, _ = _caps(sc, 1.6 * 0.042)
    assert res["F_N"][1] == pytest.approx(Fs, rel=5e-3)
    Fk, _ = _caps(sc, float(res["mu1"][2]))
    assert res["F_N"][2] == pytest.approx(Fk, rel=5e-3)
    assert res["mu1"][1] == pytest.approx(0.042, rel=1e-9)
    with pytest.raises(SceneError, match="friction.static_ratio = 0.9: must be >= 1"):
        fpd.load_scene(lab(friction=dict(fr, static_ratio=0.9)))


def test_surface_keys_carry_over_a_side_with_its_own_law():
    sc = fpd.load_scene(lab(friction={"law": "constant", "mu": 0.05, "mu_static": 0.08, "wear_k_mm3_per_Nm": 1e-6,
                                      "upper": {"law": "constantinou", "mu_slow": 0.03, "mu_fast": 0.07}}))
    up = sc.friction("upper")
    assert (up["law"], up["mu_static"], up["wear_k_mm3_per_Nm"]) == ("constantinou", 0.08, 1e-6)
    assert "mu" not in up
