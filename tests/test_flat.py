"""The flat double friction bearing of the paper's Fig. 2 (mechanics/flat.py,
docs/model.md section 7): the tipping threshold and the ledger."""
from __future__ import annotations

import numpy as np
import pytest

from fpd.mechanics.flat import FlatGeometry, FlatStepper, PadTipped
from fpd.loading.ground_motion import harmonic_ground_motion, sine_programme


def tips(g, mu_top, loading, mu_bottom=0.95):
    s = FlatStepper(g, loading)
    try:
        for _ in range(loading.n_steps):
            s.step(mu_bottom, mu_top)
    except PadTipped:
        return True, s
    return False, s


@pytest.mark.parametrize("m,M", [(5.0, 1.0e4), (250.0, 1.0e3)])
def test_tipping_threshold_within_1_percent_of_closed_form(m, M):
    """mu_tip = (D/H)(1 + m g / 2N): the heavy pad (m g / 2N = 0.125) shows the
    weight correction, which is larger than the 1 % band."""
    g = FlatGeometry(pad_height=0.10, pad_diameter=0.08, pad_mass=m, mass=M)
    mu = g.mu_tip()
    assert mu == pytest.approx(0.8 * (1 + m / (2 * M)), rel=1e-12)
    prog = sine_programme(0.02, 0.2, 1, 1e-3)
    assert tips(g, 1.01 * mu, prog)[0]
    assert not tips(g, 0.99 * mu, prog)[0]
    if m / M > 0.05:
        assert not tips(g, 1.01 * 0.8, prog)[0]      # the light-pad rule mu H > D would be wrong here


def test_tipping_under_ground_motion_includes_the_pad_inertia():
    """Under a ground motion the pad's d'Alembert force m a at H/2 adds to the
    couple; with a light pad the threshold stays within 1 % of the closed form."""
    g = FlatGeometry(pad_height=0.10, pad_diameter=0.08, pad_mass=5.0, mass=1.0e4)
    gm = harmonic_ground_motion(0.3, 1.0, 2, 1e-3)       # peak 1.2 g: the top face slides
    mu = g.mu_tip()
    assert tips(g, 1.01 * mu, gm)[0]
    assert not tips(g, 0.99 * mu, gm)[0]


def test_flat_ledger_closes_every_step():
    g = FlatGeometry(pad_height=0.10, pad_diameter=0.25, pad_mass=40.0, mass=1.0e5)
    gm = harmonic_ground_motion(0.1, 1.0, 3, 1e-3)
    s = FlatStepper(g, gm)
    res = [0.0]
    for _ in range(gm.n_steps):
        s.step(0.10, 0.06)
        res.append(s.ledger_residual())
    assert np.max(np.abs(np.diff(res))) <= 1e-9 * s.E_in
    assert s.W2 > 0 and s.W1 < 1e-9 * s.W2      # the weaker top face slides, the pad rides the ground


def test_dfp_with_infinite_radii_is_the_flat_bearing(tmp_path):
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path
    root = Path(__file__).resolve().parent.parent
    env = dict(os.environ, PYTHONPATH=str(root))
    out = tmp_path / "r"
    p = subprocess.run([sys.executable, "-m", "fpd", "run", "northridge-dfp", "--out", str(out), "--quiet",
                        "--set", "device.R1=inf", "--set", "device.R2=inf", "--set", "solver.duration=2",
                        "--set", "output.plots=false", "--set", "thermal.model=none"],
                       capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300)
    assert p.returncode == 0, p.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["device"] == "flat" and s["mu_tip_closed_form"] > 1
