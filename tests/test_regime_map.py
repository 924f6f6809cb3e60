"""fpd map (studies/regime_map.py): the measures on synthetic results, and a
tiny map end to end on a 2-worker cluster (the quick map itself is slow)."""
from __future__ import annotations

import argparse
import json
import math

import pytest

pytest.importorskip("dask.distributed")

from fpd.studies import regime_map as rm  # noqa: E402


def _run(**summary):
    return {"status": "ok", "summary": summary}


def test_tilt_share_separates_a_dt_artefact_from_rocking():
    """Richardson on the peak tilt at dt and dt/2: a tilt proportional to dt
    (the splitting artefact) leaves 0, a converged one (rocking) leaves 1."""
    art = {"A": _run(peak_beta_rad=2e-4), "B": _run(peak_beta_rad=1e-4),
           "G": _run(peak_beta_rad=0.31), "H": _run(peak_beta_rad=0.30)}
    m = rm._metrics(art, 20.0)
    assert m["tilt_share_mu006"] == 0.0
    assert m["tilt_share_mu06"] == pytest.approx((2 * 0.30 - 0.31) / 0.30)
    assert math.isnan(m["u_2p_vs_seated"]) and m["failed"] == []


def test_relative_differences_and_error_bars():
    runs = {"A": _run(peak_u_m=0.100, friction_work_total_J=1000.0, peak_T1_C=40.0),
            "B": _run(peak_u_m=0.101, friction_work_total_J=1000.0, peak_T1_C=40.0),
            "C": _run(peak_u_m=0.098, friction_work_total_J=990.0),
            "E": _run(peak_u_m=0.100, friction_work_total_J=1000.0),
            "D": _run(peak_u_m=0.110, peak_T1_C=20.2), "F": _run(peak_u_m=0.111, peak_T1_C=20.2),
            "G": {"status": "failed", "summary": {}}}
    m = rm._metrics(runs, 20.0)
    assert m["u_2p_vs_seated"] == pytest.approx(0.002 / 0.098)
    assert m["u_2p_vs_seated_fine"] == pytest.approx(0.001 / 0.100)
    assert m["W_2p_vs_seated"] == pytest.approx(10 / 990)
    assert m["T_lumped_vs_fe1d"] == pytest.approx((20.0 - 0.2) / 20.0)
    assert m["u_lumped_vs_fe1d"] == pytest.approx(0.010 / 0.100)
    assert m["failed"] == ["G"]


def test_closed_form_rocking_onset_is_about_2a_over_h():
    """g X0/Z0 ~ (2a/h) g for a light pad; tall pads below, squat above."""
    for hD in (0.8, 1.6, 3.2):
        assert rm.rocking_threshold_g(hD) == pytest.approx(1 / hD, rel=0.05)


def test_tiny_map_end_to_end(tmp_path, monkeypatch):
    """2 aspects x 2 pulses x 8 variants on 2 workers: the files, and the
    answers the quick map gives (docs/sweeps.md): at mu_ref = 0.06 the tilt is
    a dt artefact, two-phase and seated agree within 1 %, the lumped plate
    misses > 90 % of the surface temperature rise."""
    monkeypatch.setitem(rm.GRIDS, "quick", {"h_over_D": [0.4, 3.2], "pulse_V": [0.5, 1.0], "pga_g": [],
                                            "components": [], "pulse_s": 2.0, "record_s": None})
    out = tmp_path / "map"
    args = argparse.Namespace(quick=True, out=str(out), workers=2, scheduler=None, force=False, quiet=True)
    assert rm.cmd_map(args) == 0
    for f in ("map.md", "map.json", "map-rocking.png", "map-two-phase-vs-seated.png", "map-lumped-vs-fe1d.png",
              "sweep/sweep.csv"):
        assert (out / f).is_file(), f
    cells = json.loads((out / "map.json").read_text())["pulse"]
    assert len(cells) == 4
    for c in cells.values():
        assert c["tilt_share_mu006"] < 0.01
        assert c["u_2p_vs_seated"] < 0.01 and c["W_2p_vs_seated"] < 0.01
        assert c["T_lumped_vs_fe1d"] > 0.9
    # squat pad at 0.32 g: far below its 2.7 g onset, no rocking even when stuck (mu_ref = 0.6)
    assert cells["(0.4, 1.0)"]["tilt_share_mu06"] < 0.01
    assert "## rocking" in (out / "map.md").read_text()


@pytest.mark.slow
def test_quick_map_under_three_minutes(tmp_path):
    import subprocess
    import sys
    import time
    from pathlib import Path
    root = Path(__file__).resolve().parents[1]
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "fpd", "map", "--quick", "--out", str(tmp_path / "m"), "--quiet"],
                       capture_output=True, text=True, env={**__import__("os").environ, "PYTHONPATH": str(root)})
    assert r.returncode == 0, r.stderr
    assert time.perf_counter() - t0 < 180
