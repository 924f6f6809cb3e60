"""Tribology: the Constantinou velocity law, breakaway (static) friction, the
compliant test-machine link (stick-slip), Archard wear and the liner presets,
each against a closed form or the run's own numbers."""
from __future__ import annotations

import math

import numpy as np
import pytest

import fpd
from fpd.mechanics import friction_kernel as fk
from fpd.mechanics.friction import Constantinou1990, make_law
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
