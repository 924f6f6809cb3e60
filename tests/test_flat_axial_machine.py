"""The flat bearing's test machine under an axial-load programme
(loading.vertical = "sine" | "series", loading/axial.py): the energy per
cycle and the per-cycle mean load against the closed form of the imposed
programmes, the ledger, bad input in one line."""
from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from fpd.frontends import api
from fpd.mechanics.geometry import G_ACC
from fpd.schema import scene as scn

A, F, MU2 = 0.05, 0.1, 0.5          # flat-lab: 0.05 m at 0.1 Hz, the top face slides at mu 0.5
W = 1.0e4 * G_ACC


def _closed_form(N_of_t, k):
    """Cycle k's EDC = int mu2 N(t) |u'(t)| dt and its mean load (1/T) int N dt."""
    T = 1.0 / F
    t = np.linspace(k * T, (k + 1) * T, 400001)
    du = np.abs(2 * math.pi * F * A * np.cos(2 * math.pi * F * t))
    N = N_of_t(t)
    f = MU2 * N * du
    return np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(t)), np.sum(0.5 * (N[1:] + N[:-1]) * np.diff(t)) / T


def _run(out, vertical: dict):
    r = api.run("flat-lab", out, loading={"cycles": 2, **vertical}, output={"plots": False})
    assert r.ok, r.summary.get("message")
    return r, list(csv.DictReader(open(out / "cycles.csv")))


@pytest.mark.parametrize("fv, phase", [(0.2, 90.0), (0.13, 30.0)])
def test_sine_axial_load_dissipates_the_closed_form(tmp_path, fv, phase):
    """N(t) = W (1 + 0.4 sin(2 pi fv t + phase)): each cycle's EDC equals
    int mu2 N(t) |du| within 0.5 % (measured below 1e-4) and its N_mean_N the
    time mean of N over the cycle within 1e-6; the ledger closes; the column
    N2_N is the programme."""
    vertical = {"vertical": "sine", "vertical_amplitude_ratio": 0.4, "vertical_frequency_Hz": fv,
                "vertical_phase_deg": phase}
    r, rows = _run(tmp_path / "r", vertical)

    def N(t):
        return W * (1 + 0.4 * np.sin(2 * math.pi * fv * t + math.radians(phase)))

    assert len(rows) == 2
    for k, row in enumerate(rows):
        edc, nm = _closed_form(N, k)
        assert float(row["EDC_J"]) == pytest.approx(edc, rel=5e-3)
        assert abs(float(row["EDC_J"]) / edc - 1) < 1e-4
        assert float(row["N_mean_N"]) == pytest.approx(nm, rel=1e-6)
    const = 4 * MU2 * W * A
    assert abs(_closed_form(N, 0)[0] / const - 1) > 0.01        # the programme changes the loop
    s = r.summary
    assert s["energy_residual_rel"] < 1e-10
    assert s["test_machine"]["axial_programme"]["kind"] == "sine"


def test_series_axial_load_is_the_programme(tmp_path):
    t = np.linspace(0.0, 20.0, 81)
    Nf = W * (1 + 0.3 * np.sin(0.7 * t) * np.cos(0.25 * t))
    path = tmp_path / "axial.txt"
    np.savetxt(path, np.column_stack([t, Nf]))
    r, rows = _run(tmp_path / "r", {"vertical": "series", "vertical_file": str(path)})
    for k, row in enumerate(rows):
        edc, nm = _closed_form(lambda x: np.interp(x, t, Nf), k)
        assert abs(float(row["EDC_J"]) / edc - 1) < 1e-3
        assert float(row["N_mean_N"]) == pytest.approx(nm, rel=1e-5)


def test_a_constant_vertical_is_the_run_without_it(tmp_path):
    a = api.run("flat-lab", tmp_path / "a", output={"plots": False})
    b = api.run("flat-lab", tmp_path / "b", loading={"vertical": "constant"}, output={"plots": False})
    for c in ("u_m", "F_N", "N1_N", "N2_N", "W1_J", "W2_J", "E_input_J"):
        np.testing.assert_array_equal(a.history[c], b.history[c])


def test_bad_axial_input_is_refused_in_one_line():
    with pytest.raises(scn.SceneError, match=r"^[^\n]*loading\.vertical[^\n]*flat bearing[^\n]*$"):
        scn.load("flat-lab", ['loading.vertical="riding-mass"'])
    with pytest.raises(scn.SceneError, match=r"^[^\n]*must be below the mean load[^\n]*$"):
        scn.load("flat-lab", ['loading.vertical="sine"', "loading.vertical_amplitude_ratio=1.2",
                              "loading.vertical_frequency_Hz=0.2"])


def test_compiled_flat_machine_with_an_axial_load_equals_the_pure_path(monkeypatch):
    pytest.importorskip("numba")
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    from fpd.coupling import fast_loop
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate
    over = ['loading.vertical="sine"', "loading.vertical_amplitude_ratio=0.4", "loading.vertical_frequency_Hz=0.13",
            "thermal.model=lumped"]
    sim = build(scn.load("flat-lab", over))
    assert fast_loop.compiled_loop(sim, 1, 2, fast_loop.loop_columns(sim)) is not None
    a = simulate(sim)
    monkeypatch.setenv("FPD_NO_JIT", "1")
    b = simulate(build(scn.load("flat-lab", over)))
    assert a.status == b.status == "ok" and a.columns == b.columns
    np.testing.assert_array_equal(a.data, b.data)
