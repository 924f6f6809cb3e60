"""Stepping shared by the tests of the TFP (tests/test_tfp3d*.py): a stepper
run step by step under its record, its columns and ledger residual per row."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from fpd.mechanics.tfp import TFPStepper

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_tfp import MUS  # noqa: E402


def stepped(s, n_steps, mus=MUS):
    """Step s n_steps times with the coefficients mus: its columns (one array
    each, the initial row first) and the ledger residual of every row."""
    rows = [s.values()]
    res = [s.ledger_residual()]
    for _ in range(n_steps):
        s.step(*mus)
        rows.append(s.values())
        res.append(s.ledger_residual())
    d = np.array(rows)
    return {c: d[:, i] for i, c in enumerate(s.columns)}, np.array(res)


def run_planar(g, gm, mus=MUS, model="seated"):
    """The planar TFP (model: "seated" or "two-phase") under a ground motion: its columns."""
    return stepped(TFPStepper(g, gm, model=model), gm.n_steps, mus)[0]


def flies_as_planar(d, p, energies, tol=1e-9):
    """The TFP in both directions (columns d) under a turned record and a
    vertical pulse against the planar TFP's (p) under its two components:
    no NaN; one lift-off; the flight's time, height above the seat, |u|, z
    and the columns ``energies`` within tol (the work's scale for these);
    in the air no normal force and no force (at least 200 rows of it).
    Returns the rows in the air."""
    assert not any(np.isnan(v).any() for v in d.values())
    assert d["n_lift"][-1] == p["n_lift"][-1] == 1.0
    assert abs(d["t_flight_s"][-1] / p["t_flight_s"][-1] - 1.0) <= tol
    assert np.max(np.abs(d["lift_m"] - p["lift_m"])) <= tol * np.max(p["lift_m"])
    um = np.max(np.abs(p["u_m"]))
    assert np.max(np.abs(d["u_m"] - np.abs(p["u_m"]))) <= tol * um
    assert np.max(np.abs(d["z_m"] - p["z_m"])) <= tol * np.max(p["z_m"])
    wt = sum(p[f"W{i}_J"][-1] for i in range(1, 5))
    for c in energies:
        assert np.max(np.abs(d[c] - p[c])) <= tol * wt, c
    air = d["lift_m"] > 0.0
    assert air.sum() > 200 and np.all(d["N1_N"][air] == 0.0) and np.all(d["F_N"][air] == 0.0)
    return air


def turned_as_planar(d, p, ang, energies, tol=1e-9):
    """The TFP in both directions (columns d) under a record turned by ang
    (rad) against the planar TFP's (p) under it along x: |u| and F, the
    motion along the record's line, the normal forces, W1..W4 and the
    columns ``energies`` within tol (of the peak, the peak N1, the total
    work). Returns the total work, the scale of the energies."""
    um = np.max(np.abs(p["u_m"]))
    assert np.max(np.abs(d["u_m"] - np.abs(p["u_m"]))) <= tol * um
    assert np.max(np.abs(d["uy_m"] * np.cos(ang) - d["ux_m"] * np.sin(ang))) <= tol * um
    assert np.max(np.abs(d["F_N"] - np.abs(p["F_N"]))) <= tol * np.max(np.abs(p["F_N"]))
    nm = np.max(p["N1_N"])
    wt = sum(p[f"W{i}_J"][-1] for i in range(1, 5))
    for i in range(1, 5):
        assert np.max(np.abs(d[f"N{i}_N"] - p[f"N{i}_N"])) <= tol * nm
        assert np.max(np.abs(d[f"W{i}_J"] - p[f"W{i}_J"])) <= tol * wt
    for c in energies:
        assert np.max(np.abs(d[c] - p[c])) <= tol * wt, c
    return wt
