"""Per-cycle bearing-test quantities of a test-machine run (outputs/cycles.py,
docs/test_machine.md) against the run's own timeseries.csv, computed here
independently with numpy."""
from __future__ import annotations

import csv
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fpd.mechanics.geometry import G_ACC

ROOT = Path(__file__).resolve().parents[1]


def fpd(*args, cwd):
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    d = tmp_path_factory.mktemp("lab")
    r = fpd("run", "lab-sine", "--out", str(d / "lab"), "--quiet", cwd=d)
    assert r.returncode == 0, r.stderr
    return d / "lab"


def _csv(path):
    with open(path) as fh:
        rows = list(csv.reader(fh))
    head = rows[0]
    cols = {h: np.array([float(r[j]) for r in rows[1:]]) for j, h in enumerate(head) if h != "phase"}
    return cols


def test_lab_sine_cycles_match_its_timeseries(lab):
    s = json.loads((lab / "summary.json").read_text())
    tm = s["test_machine"]
    ts = _csv(lab / "timeseries.csv")
    t, u, F = ts["t_s"], ts["u_m"], ts["F_N"]
    T = 1.0 / 0.4
    W = 642420.0 * G_ACC
    assert tm["vertical_load_N"] == pytest.approx(W, rel=1e-12)
    assert len(tm["cycles"]) == 3
    for k, c in enumerate(tm["cycles"]):
        sel = (t >= k * T - 1e-9) & (t <= (k + 1) * T + 1e-9)      # both boundary rows: a closed loop
        uu, FF = u[sel], F[sel]
        edc = float(np.sum(0.5 * (FF[1:] + FF[:-1]) * np.diff(uu)))
        ip, im = np.argmax(uu), np.argmin(uu)
        keff = (FF[ip] - FF[im]) / (uu[ip] - uu[im])
        dmax = 0.5 * (uu[ip] - uu[im])
        mu = edc / (4 * W * dmax)
        for key, ref in (("EDC_J", edc), ("K_eff_N_m", keff), ("mu_eff", mu), ("Q_d_N", edc / (4 * dmax))):
            assert c[key] == pytest.approx(ref, rel=1e-3), (k, key)
        assert c["v_peak_mps"] == pytest.approx(np.max(np.abs(ts["v_mps"][sel])), rel=1e-6)
    # the headline of README: friction falls as the surface heats, and the
    # changes are against the first cycle
    mus = [c["mu_eff"] for c in tm["cycles"]]
    assert mus[0] > mus[1] > mus[2]
    assert tm["cycles"][2]["mu_eff_change_rel"] == pytest.approx(mus[2] / mus[0] - 1, rel=1e-12)
    # the machine's work (sum of the loop areas) is the friction work of a
    # closed programme (the pad's inertia gives nothing back over whole cycles)
    W12 = s["friction_work_J"]["lower"] + s["friction_work_J"]["upper"]
    assert tm["machine_work_J"] == pytest.approx(W12, rel=2e-3)
    assert tm["peak_velocity_mps"] == pytest.approx(2 * math.pi * 0.4 * 0.25, rel=1e-9)


def test_lab_sine_cycles_csv_and_plot(lab):
    with open(lab / "cycles.csv") as fh:
        rows = list(csv.DictReader(fh))
    s = json.loads((lab / "summary.json").read_text())
    assert len(rows) == 3
    for r, c in zip(rows, s["test_machine"]["cycles"]):
        assert float(r["EDC_J"]) == c["EDC_J"] and float(r["mu_eff"]) == c["mu_eff"]
    assert (lab / "plots" / "cycles.png").is_file()
    assert "cycles.png" in s["plots"]


def test_cycle_meter_is_blocking_invariant():
    """The streamed meter sees the rows in blocks: any chunking gives the same cycles."""
    from fpd.outputs.cycles import CycleMeter

    cols = ["t_s", "u_m", "v_mps", "F_N"]
    t = np.arange(0, 2001) * 1e-3
    w = 2 * np.pi
    u = 0.1 * np.sin(w * t)
    F = 1e3 * u + 50.0 * np.sign(np.cos(w * t))       # a bilinear loop: EDC = 4 Q d = 4 * 50 * 0.1
    data = np.column_stack((t, u, 0.1 * w * np.cos(w * t), F))
    whole = CycleMeter(cols, 1.0, 2, 1000.0)
    whole.add(data)
    parts = CycleMeter(cols, 1.0, 2, 1000.0)
    for s in range(0, len(data), 37):
        parts.add(data[s:s + 37])
    a, b = whole.cycles(), parts.cycles()
    assert len(a) == 2
    for ca, cb in zip(a, b):
        for key in ("EDC_J", "K_eff_N_m", "mu_eff", "v_peak_mps"):
            assert ca[key] == pytest.approx(cb[key], rel=1e-12)
        assert ca["EDC_J"] == pytest.approx(4 * 50 * 0.1, rel=2e-3)       # the closed form
        assert ca["Q_d_N"] == pytest.approx(50.0, rel=2e-3)
        assert ca["mu_eff"] == pytest.approx(50.0 / 1000.0, rel=2e-3)
    # an interrupted run: only complete cycles
    cut = CycleMeter(cols, 1.0, 2, 1000.0)
    cut.add(data[:1500])
    assert len(cut.cycles()) == 1


def test_docs_test_machine_numbers_are_lab_sines(lab):
    """docs/test_machine.md's per-cycle table and machine-work sentence are those
    of the packaged lab-sine as it runs now (they went stale once)."""
    from fpd.outputs.cycles import doc_table
    s = json.loads((lab / "summary.json").read_text())
    text = (ROOT / "docs" / "test_machine.md").read_text()
    assert doc_table(s["test_machine"]["cycles"]) in text
    W12 = sum(s["friction_work_J"].values())
    assert (f"`machine_work_J` = {s['test_machine']['machine_work_J'] / 1e3:.1f} kJ against "
            f"W1 + W2 = {W12 / 1e3:.1f} kJ in lab-sine") in text


def test_reference_states_what_the_runs_do(lab):
    """docs/reference.md's claims checked against runs: on the test machine
    xg_m is the driven lower plate, -u_m at every row; a TFP scene without
    mechanics.model runs the two-phase model (the reference said 'rigid seated')."""
    ts = _csv(lab / "timeseries.csv")
    assert np.array_equal(ts["xg_m"], -ts["u_m"])
    text = (ROOT / "docs" / "reference.md").read_text()
    assert "= -u_m" in text and "the fixed base, 0" not in text
    import tomllib

    import fpd as api
    raw = tomllib.loads((ROOT / "scenes" / "tfp-elcentro.toml").read_text())
    raw.pop("mechanics", None)
    assert api.load_scene(raw)["mechanics"]["model"] == "two-phase"
    assert "TFP\": triple friction pendulum" in text and "two-phase model by default" in text


def test_orbit_cycles_are_measured_in_the_plane(tmp_path):
    """The bidirectional machine's circle (radius 0.25 m, constant mu = 0.05,
    no heat): each revolution's EDC is the closed integral of F . du, equal
    to the closed form (2 pi A / L)(mu W1 R1 + mu W2 R2) / cos(theta) within
    0.1 %; d_max the radius, mu_eff = EDC / (W 2 pi A) and K_eff = |F| / |u|
    finite and positive (they read |u| and |F|: K_eff was 1e19, mu_eff < 0)."""
    import csv
    import math
    from fpd.frontends import api
    from fpd.mechanics.geometry import G_ACC
    out = tmp_path / "o"
    r = api.run("lab-sine", out, loading={"waveform": "circle"}, friction={"mu_ref": 0.05, "use_temperature": False},
                thermal={"model": "none"}, output={"plots": False})
    assert r.ok
    rows = list(csv.DictReader(open(out / "cycles.csv")))
    sc = r.scene
    dev, A = sc["device"], sc["loading"]["amplitude_m"]
    L = dev["R1"] + dev["R2"] - dev["pad_height"]
    W2 = sc["superstructure"]["mass"] * G_ACC
    W1 = W2 + dev["pad_mass"] * G_ACC
    closed = 2 * math.pi * A * 0.05 * (W1 * dev["R1"] + W2 * dev["R2"]) / L / math.sqrt(1 - (A / L) ** 2)
    assert len(rows) == sc["loading"]["cycles"]
    for c in rows:
        edc = float(c["EDC_J"])
        assert abs(edc / closed - 1) < 1e-3, (edc, closed)
        assert float(c["d_max_m"]) == pytest.approx(A, rel=1e-9)
        assert float(c["mu_eff"]) == pytest.approx(edc / (W2 * 2 * math.pi * A), rel=2e-3)
        assert 0 < float(c["K_eff_N_m"]) < 1e8 and 0 < float(c["xi_eff"]) < 1
