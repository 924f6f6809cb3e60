"""The orbit test machine (machines/orbit.py BidirectionalTestMachine)
under an axial-load programme (loading.vertical = "sine" | "series" held in
force control): a turned sine is the planar machine's test, cycle for cycle,
and its EDC the closed form of the imposed programmes; on a circle the normal
forces follow N(t) and each cycle reports the programme's mean load."""
from __future__ import annotations

import math

import numpy as np
import pytest

from fpd.mechanics.geometry import G_ACC

# the planar machine's run and closed form of the imposed programmes, reused as they are
from tests.test_axial_machine import A, F, MU, _closed_form, _run


@pytest.mark.parametrize("phase", [90.0, 0.0])
def test_a_turned_sine_under_a_sine_load_is_the_planar_test(tmp_path, phase):
    """direction_deg = 30 runs the orbit machine: each cycle's EDC equals the
    planar machine's (direction 0, machines/seated_kernel.py: another
    kernel) within 1e-9 and the closed form within 0.5 % (measured 0.05 %
    at 90 deg), N_mean_N the programme's mean; the ledger closes."""
    vert = {"vertical": "sine", "vertical_amplitude_ratio": 0.4, "vertical_frequency_Hz": 2 * F,
            "vertical_phase_deg": phase}
    r, rows = _run(tmp_path / "orbit", {"direction_deg": 30.0, **vert})
    _, flat = _run(tmp_path / "plane", vert)
    assert "ux_m" in r.history.columns and r.scene["loading"]["vertical"] == "sine"
    W = r.scene["superstructure"]["mass"] * G_ACC

    def N_of_t(t):
        return W * (1.0 + 0.4 * np.sin(2 * math.pi * 2 * F * t + math.radians(phase)))

    friction, pendulum, *_ = _closed_form(r.scene, N_of_t)
    edc = friction + pendulum
    assert len(rows) == 2
    for c, p in zip(rows, flat):
        assert float(c["EDC_J"]) == pytest.approx(float(p["EDC_J"]), rel=1e-9)
        assert abs(float(c["EDC_J"]) / edc - 1) < 5e-3, (c["EDC_J"], edc)
        assert float(c["N_mean_N"]) == pytest.approx(W, rel=1e-9)
    assert r.summary["energy_residual_rel"] < 1e-6


def test_a_circle_under_an_axial_load_follows_it(tmp_path):
    """A circle at 0.4 Hz with N = W (1 + 0.3 sin(2 pi 0.13 t)): the normal
    force on the upper surface is N(t) (-n_z) plus the restraint's axial share
    F . n_h to round-off; each cycle's N_mean_N is the programme's time mean
    over it (closed form) within 1e-6; the ledger closes as the riding mass's
    does; EDC per cycle is mu R-weighted friction of the arc: within 0.5 % of
    mu ((N_mean c + F.n_h) (R1 + R2) + m g c R1) alpha_cycle."""
    fv = 0.13
    r, rows = _run(tmp_path / "c", {"waveform": "circle", "vertical": "sine", "vertical_amplitude_ratio": 0.3,
                                    "vertical_frequency_Hz": fv})
    h = r.history
    W = r.scene["superstructure"]["mass"] * G_ACC
    dev = r.scene["device"]
    L = dev["R1"] + dev["R2"] - dev["pad_height"]
    N = W * (1 + 0.3 * np.sin(2 * math.pi * fv * h["t_s"]))
    nz = -np.cos(h["theta_rad"])
    share = (h["Fx_N"] * h["ux_m"] + h["Fy_N"] * h["uy_m"]) / L
    np.testing.assert_allclose(h["N2_N"][1:], (N * -nz + share)[1:], rtol=1e-12, atol=1e-9 * W)
    T = 1.0 / F
    for k, c in enumerate(rows):
        t = np.linspace(k * T, (k + 1) * T, 200001)
        nm = np.mean(W * (1 + 0.3 * np.sin(2 * math.pi * fv * t)))
        assert float(c["N_mean_N"]) == pytest.approx(nm, rel=1e-6)
        th = math.asin(A / L)
        alpha = 2 * math.pi * math.sin(th)                       # the axis' arc per cycle on the unit sphere
        sh = float(np.median(share))
        edc = MU * ((nm * math.cos(th) + sh) * (dev["R1"] + dev["R2"])
                    + dev["pad_mass"] * G_ACC * math.cos(th) * dev["R1"]) * alpha
        assert abs(float(c["EDC_J"]) / edc - 1) < 5e-3, (c["EDC_J"], edc)
    assert r.summary["energy_residual_rel"] < 2e-6


@pytest.mark.parametrize("over", [
    ['loading.waveform="circle"', 'loading.vertical="sine"', "loading.vertical_amplitude_ratio=0.3",
     "loading.vertical_frequency_Hz=0.13", "thermal.model=lumped"],
    ['loading.waveform="figure-eight"', 'loading.vertical="series"', 'loading.vertical_file="axial.txt"',
     "solver.duration=4"],
])
def test_compiled_orbit_machine_with_an_axial_load_equals_the_pure_path(monkeypatch, tmp_path, over):
    pytest.importorskip("numba")
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    from fpd.coupling import fast_loop
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate
    from fpd.schema import scene as scn
    t = np.linspace(0.0, 8.0, 41)
    np.savetxt(tmp_path / "axial.txt", np.column_stack([t, 6.3e6 * (1 + 0.3 * np.sin(1.7 * t))]))
    monkeypatch.chdir(tmp_path)
    sim = build(scn.load("lab-sine", over))
    assert fast_loop.compiled_loop(sim, 1, 2, fast_loop.loop_columns(sim)) is not None
    a = simulate(sim)
    monkeypatch.setenv("FPD_NO_JIT", "1")
    b = simulate(build(scn.load("lab-sine", over)))
    assert a.status == b.status == "ok" and a.columns == b.columns
    np.testing.assert_array_equal(a.data, b.data)
