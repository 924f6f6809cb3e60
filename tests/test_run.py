"""`fpd run` end to end, as a new user runs it."""
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
REQUIRED = ("t_s", "xg_m", "u_m", "v_mps", "F_N", "z_m", "theta_rad", "s1_m", "s2_m", "N1_N", "N2_N",
            "mu1", "mu2", "T1_C", "T2_C", "W1_J", "W2_J", "phase", "E_input_J", "E_kin_J", "E_pot_J",
            "E_stored_J", "E_air_J")
SUMMARY = ("status", "scene", "models", "steps", "runtime_s", "peak_u_m", "residual_u_m", "peak_F_N",
           "peak_T1_C", "peak_T2_C", "friction_work_J", "energy_residual_rel", "heat_residual_rel", "version")


def fpd(*args, cwd):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


def test_default_scene_runs_and_writes_everything(tmp_path):
    t0 = time.perf_counter()
    r = fpd("run", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert time.perf_counter() - t0 < 60
    out = tmp_path / "results" / "default"
    for f in ("timeseries.csv", "summary.json", "scene.toml", "plots/hysteresis.png",
              "plots/temperature.png", "plots/friction.png"):
        assert (out / f).is_file(), f
    header = (out / "timeseries.csv").read_text().splitlines()[0].split(",")
    for c in REQUIRED:
        assert c in header
    s = json.loads((out / "summary.json").read_text())
    for k in SUMMARY:
        assert k in s, k
    assert s["status"] == "ok"
    assert s["energy_residual_rel"] < 1e-3
    assert s["heat_residual_rel"] < 1e-9
    data = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert len(data) == s["steps"] + 1
    assert np.max(np.abs(data["u_m"])) == pytest.approx(s["peak_u_m"], rel=1e-9)
    assert [p.name for p in tmp_path.joinpath("results").iterdir()] == ["default"]   # no leftovers

    again = fpd("run", cwd=tmp_path)
    assert again.returncode == 2
    assert "--force" in again.stderr and len(again.stderr.strip().splitlines()) == 1
    assert json.loads((out / "summary.json").read_text()) == s            # untouched
    forced = fpd("run", "--force", "--quiet", "--set", "output.plots=false", cwd=tmp_path)
    assert forced.returncode == 0, forced.stderr
    assert not (out / "plots").exists()


def test_resolved_scene_reruns_identically(tmp_path):
    r = fpd("run", "sfp-harmonic", "--out", "a", "--quiet", "--set", "output.plots=false", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    r2 = fpd("run", str(tmp_path / "a" / "scene.toml"), "--out", "b", "--quiet",
             "--set", "output.plots=false", cwd=tmp_path)
    assert r2.returncode == 0, r2.stderr
    assert (tmp_path / "a/timeseries.csv").read_text() == (tmp_path / "b/timeseries.csv").read_text()


def test_every_packaged_scene_checks(tmp_path, capsys):
    # in-process: 21 scenes (stability/* included) in ~1 s instead of 21 interpreters
    from fpd.schema import scene
    from fpd.frontends.cli import main
    names = scene.packaged_scenes()
    assert "stability/tall-pad" in names
    for name in names:
        assert main(["check", name]) == 0, (name, capsys.readouterr().err)


@pytest.mark.parametrize("name,bound_K", [("heat-halfspace", 0.1), ("heat-slab", 0.1), ("heat-disk", None)])
def test_packaged_closed_form_scenes(tmp_path, name, bound_K):
    r = fpd("run", name, "--out", "o", "--quiet", "--set", "output.plots=false", "--set", "output.vtk_every=0",
            cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    ref = s["reference"]
    if bound_K is not None:
        assert abs(ref["error_end_K"]) < bound_K
    else:   # disk source: within 0.5 % of the closed form
        assert abs(ref["error_end_K"]) < 0.005 * (ref["T_exact_end_C"] - 20.0)
    assert s["heat_residual_rel"] < 1e-9


def test_heat_only_scene_needs_no_device(tmp_path):
    """A thermal-only scene has no bearing: [device] and [superstructure] may be left out."""
    text = (ROOT / "scenes" / "heat-halfspace.toml").read_text()
    kept, skip = [], False
    for line in text.splitlines():
        if line.startswith("["):
            skip = line.strip() in ("[device]", "[superstructure]")
        if not skip:
            kept.append(line)
    (tmp_path / "bare.toml").write_text("\n".join(kept).replace('name = "heat-halfspace"', 'name = "bare"'))
    r = fpd("run", "bare.toml", "--quiet", "--set", "output.plots=false", "--set", "output.vtk_every=0",
            "--set", "solver.duration=1", "--set", "loading.duration_s=1", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    s = json.loads((tmp_path / "results" / "bare" / "summary.json").read_text())
    assert s["status"] == "ok" and abs(s["reference"]["error_end_K"]) < 0.1
