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
