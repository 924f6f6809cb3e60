"""The planar test machine's axial-load programme (loading.vertical = "sine" or
"series", loading/axial.py, docs/test_machine.md): the energy per cycle
against the closed form of the imposed programmes (numpy, independently of
the run's columns), the ledger, the per-cycle mean load, and bad input
refused in one line with nothing written."""
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

from fpd.frontends import api
from fpd.mechanics.geometry import G_ACC

ROOT = Path(__file__).resolve().parents[1]
MU = 0.05
A, F = 0.25, 0.4                    # lab-sine's programme: 0.25 m at 0.4 Hz


def _run(out, vertical: dict, cycles=2):
    r = api.run("lab-sine", out, loading={"cycles": cycles, **vertical},
                friction={"mu_ref": MU, "use_temperature": False}, thermal={"model": "none"},
                output={"plots": False})
    assert r.ok, r.summary.get("message")
    return r, list(csv.DictReader(open(out / "cycles.csv")))


def _closed_form(scene, N_of_t):
    """One cycle's dissipated energy of the imposed programmes, quasi-static:
    the friction work mu N |ds| on each surface (ds = R dtheta; the lower
    one carries the pad's weight too) plus the work of the load's variation
    through the pendulum's rise, the closed integral of (N - W) L sin(theta)
    dtheta (zero when N(t) and u(t) u'(t) are orthogonal over the cycle)."""
    dev = scene["device"]
    L = dev["R1"] + dev["R2"] - dev["pad_height"]
    W = scene["superstructure"]["mass"] * G_ACC
    mg = dev["pad_mass"] * G_ACC
    t = np.linspace(0.0, 1.0 / F, 400001)
    th = np.arcsin(A * np.sin(2 * math.pi * F * t) / L)
    N = N_of_t(t)
    dth, Nm, thm = np.diff(th), 0.5 * (N[1:] + N[:-1]), 0.5 * (th[1:] + th[:-1])
    friction = np.sum(MU * ((Nm + mg) * dev["R1"] + Nm * dev["R2"]) * np.abs(dth))
    pendulum = np.sum((Nm - W) * L * np.sin(thm) * dth)
    return friction, pendulum, W, 4 * MU * W * A * (dev["R1"] + dev["R2"]) / L


@pytest.mark.parametrize("phase, pendulum_work", [(90.0, False), (0.0, True)])
def test_sine_axial_load_dissipates_the_closed_form(tmp_path, phase, pendulum_work):
    """N(t) = W (1 + 0.4 sin(2 pi 2f t + phase)), constant mu = 0.05: each
    cycle's EDC equals the closed form of the imposed programmes within
    0.5 % (measured: 0.05 % and 0.09 %). At phase 90 deg the load peaks at the
    reversals and at the centre and the pendulum term vanishes: EDC is the
    friction integral of mu N(t) |ds| alone, 13 % above the constant load's;
    at phase 0 the load's variation also does work through the rise (+18 %)."""
    W0 = None

    def N_of_t(t):
        return W0 * (1.0 + 0.4 * np.sin(2 * math.pi * 2 * F * t + math.radians(phase)))

    r, rows = _run(tmp_path / "o", {"vertical": "sine", "vertical_amplitude_ratio": 0.4,
                                     "vertical_frequency_Hz": 2 * F, "vertical_phase_deg": phase})
    W0 = r.scene["superstructure"]["mass"] * G_ACC
    friction, pendulum, W, constant = _closed_form(r.scene, N_of_t)
    assert (abs(pendulum) > 0.1 * friction) == pendulum_work
    assert abs(friction / constant - 1) > 0.1 or pendulum_work     # the test tells the programme from W
    assert len(rows) == 2
    for c in rows:
        assert abs(float(c["EDC_J"]) / (friction + pendulum) - 1) < 5e-3, (c["EDC_J"], friction, pendulum)
        assert float(c["N_mean_N"]) == pytest.approx(W, rel=1e-9)       # a whole number of load periods
        assert float(c["mu_eff"]) == pytest.approx(float(c["EDC_J"]) / (4 * W * float(c["d_max_m"])), rel=1e-12)
    # the ledger closes with the vertical actuator's work in the input
    h = r.history
    res = h["E_input_J"] - (h["E_kin_J"] + h["E_pot_J"] + h["W1_J"] + h["W2_J"])
    assert np.max(np.abs(res)) < 1e-6 * (h["W1_J"][-1] + h["W2_J"][-1])
    # the normal forces follow N(t): N2 = N cos(theta) + F sin(theta)
    th = h["theta_rad"]
    N2 = N_of_t(h["t_s"]) * np.cos(th) + h["F_N"] * np.sin(th)
    assert np.max(np.abs(h["N2_N"] - N2)) < 1e-9 * W


def test_series_axial_load(tmp_path):
    """A (t, N) file: the sine of the test above sampled every 10 ms gives
    the sine's EDC within 0.1 %; a ramp 5.5 -> 7.1 MN over the run gives each
    cycle's N_mean the ramp's mean over the cycle, and the EDC its closed form."""
    r0, rows0 = _run(tmp_path / "sine", {"vertical": "sine", "vertical_amplitude_ratio": 0.4,
                                         "vertical_frequency_Hz": 2 * F, "vertical_phase_deg": 90.0})
    W = r0.scene["superstructure"]["mass"] * G_ACC
    t = np.arange(0.0, 5.0 + 1e-9, 0.01)
    f = tmp_path / "sine.txt"
    np.savetxt(f, np.column_stack([t, W * (1 + 0.4 * np.sin(2 * math.pi * 2 * F * t + math.pi / 2))]),
               header="time s, load N")
    r1, rows1 = _run(tmp_path / "series", {"vertical": "series", "vertical_file": str(f)})
    for a, b in zip(rows0, rows1):
        assert float(b["EDC_J"]) == pytest.approx(float(a["EDC_J"]), rel=1e-3)
    g = tmp_path / "ramp.csv"
    g.write_text("# t, N\n0, 5.5e6\n5.0, 7.1e6\n")
    r2, rows2 = _run(tmp_path / "ramp", {"vertical": "series", "vertical_file": str(g)})

    def ramp(t):
        return 5.5e6 + 1.6e6 * t / 5.0
    for k, c in enumerate(rows2):
        assert float(c["N_mean_N"]) == pytest.approx(ramp((k + 0.5) / F), rel=1e-9)
        friction, pendulum, _, _ = _closed_form(r2.scene, lambda t: ramp(t + k / F))
        assert abs(float(c["EDC_J"]) / (friction + pendulum) - 1) < 5e-3
    s = r2.summary["test_machine"]
    assert s["axial_programme"] == {"kind": "series", "file": str(g)}


def test_constant_load_reports_its_weight(tmp_path):
    r, rows = _run(tmp_path / "c", {}, cycles=1)
    W = r.scene["superstructure"]["mass"] * G_ACC
    assert float(rows[0]["N_mean_N"]) == W
    assert r.summary["test_machine"]["axial_programme"] == {"kind": "constant"}


def _fpd(*args, cwd):
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


BAD = [
    (['loading.vertical="sine"', "loading.vertical_amplitude_ratio=1.2", "loading.vertical_frequency_Hz=1"],
     "must be below the mean load"),
    (['loading.vertical="sine"', "loading.vertical_amplitude_N=-1e6", "loading.vertical_frequency_Hz=1"],
     "must be > 0"),
    (['loading.vertical="sine"', "loading.vertical_amplitude_ratio=0.2", "loading.vertical_frequency_Hz=0"],
     "must be > 0"),
    (['loading.vertical="sine"', "loading.vertical_amplitude_ratio=0.2"], "vertical_frequency_Hz is missing"),
    (['loading.vertical="sine"', "loading.vertical_frequency_Hz=1"], "exactly one of"),
    (['loading.vertical="sine"', "loading.vertical_amplitude_ratio=0.2", "loading.vertical_amplitude_N=1e6",
      "loading.vertical_frequency_Hz=1"], "exactly one of"),
    (["loading.vertical_amplitude_ratio=0.2"], 'applies to loading.vertical = "sine" only'),
    (['loading.vertical="series"'], "vertical_file is missing"),
    (['loading.vertical="series"', 'loading.vertical_file="one.txt"'], "found 1 column"),
    (['loading.vertical="series"', 'loading.vertical_file="neg.txt"'], "must be > 0"),
    (['loading.vertical="series"', 'loading.vertical_file="short.txt"'], "must cover the run"),
    (['loading.vertical="series"', 'loading.vertical_file="back.txt"'], "must increase"),
    (['loading.vertical="series"', 'loading.vertical_file="words.txt"'], "is not two numbers"),
    (['loading.vertical="series"', 'loading.vertical_file="none.txt"'], "file not found"),
    (['loading.vertical="sine"', "loading.vertical_amplitude_ratio=1.2", "loading.vertical_frequency_Hz=1",
      'loading.waveform="circle"'], "must be below the mean load"),
    (['loading.vertical="constant"', 'loading.waveform="circle"'], 'must be "riding-mass" (or left out)'),
]


@pytest.mark.parametrize("over, says", BAD)
def test_bad_axial_programme_is_refused_in_one_line(tmp_path, over, says):
    (tmp_path / "one.txt").write_text("0\n1\n")
    (tmp_path / "neg.txt").write_text("0 1e6\n5 -2e6\n10 1e6\n")
    (tmp_path / "short.txt").write_text("0 1e6\n5 1e6\n")
    (tmp_path / "back.txt").write_text("0 1e6\n5 1e6\n4 1e6\n")
    (tmp_path / "words.txt").write_text("0 1e6\nten 1e6\n")
    args = ["run", "lab-sine", "--out", str(tmp_path / "out"), "--quiet"]
    for o in over:
        args += ["--set", o]
    r = _fpd(*args, cwd=tmp_path)
    assert r.returncode != 0
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and says in lines[0], r.stderr
    assert not (tmp_path / "out").exists()


def test_tfp_machine_refuses_a_programme_key_without_its_programme(tmp_path):
    r = _fpd("run", "tfp-lab", "--out", str(tmp_path / "out"), "--set", "loading.vertical_amplitude_ratio=0.2",
             cwd=tmp_path)
    assert r.returncode != 0 and len(r.stderr.strip().splitlines()) == 1
    assert 'applies to loading.vertical = "sine" only (loading.vertical is not given)' in r.stderr
    assert not (tmp_path / "out").exists()


def test_sweep_hashes_the_series_by_content(tmp_path):
    """A sweep member's hash (its cache key) follows the series file's content
    (a member re-run when the file changes); the file is shipped to a worker
    with the scene."""
    from fpd.schema import scene as scn
    from fpd.studies import sweep
    f = tmp_path / "n.txt"
    over = ['loading.vertical="series"', f'loading.vertical_file="{f}"']
    f.write_text("0 6e6\n10 6e6\n")
    h1 = sweep.member_hash(scn.load("lab-sine", over), "all")
    f.write_text("0 7e6\n10 7e6\n")
    h2 = sweep.member_hash(scn.load("lab-sine", over), "all")
    f.write_text("0 6e6\n10 6e6\n")
    assert h1 != h2 and sweep.member_hash(scn.load("lab-sine", over), "all") == h1
    assert sweep._file_roles(scn.load("lab-sine", over).data) == {"loading.path_vertical": str(f)}
