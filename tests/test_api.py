"""The Python API (fpd.run, fpd.load_scene, fpd.compare, fpd.converge) and the examples.

The API must give what the command line gives: the same summary fields and
values, the same columns and numbers as timeseries.csv.
"""
from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import fpd
from fpd.frontends.cli import main

ROOT = Path(__file__).resolve().parent.parent
ENV = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")


def test_import_fpd_is_cheap():
    code = ("import sys, fpd; assert fpd.__version__; "
            "bad = [m for m in ('numpy', 'scipy', 'numba', 'skfem', 'matplotlib', 'fpd.coupling') if m in sys.modules]; "
            "assert not bad, bad; fpd.run; assert 'fpd.frontends.api' in sys.modules")
    r = subprocess.run([sys.executable, "-c", code], cwd="/", env=ENV, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert set(fpd.__all__) <= set(dir(fpd))
    with pytest.raises(AttributeError):
        fpd.no_such_name


def _same(a, b, where):
    if isinstance(b, dict):
        assert set(a) == set(b), where
        for k in b:
            _same(a[k], b[k], f"{where}.{k}")
    elif isinstance(b, float):
        assert a == pytest.approx(b, rel=1e-12, abs=1e-300), where
    else:
        assert a == b, where


def test_run_matches_the_command_line(tmp_path):
    """Same scene, same overrides: summary.json and timeseries.csv of `fpd run`
    are the API's summary and history (to the CSV's 10 digits)."""
    out = tmp_path / "cli"
    assert main(["run", "default", "--out", str(out), "--quiet", "--set", "solver.duration=1.5",
                 "--set", "output.plots=false"]) == 0
    r = fpd.run("default", solver={"duration": 1.5}, output={"plots": False})
    disk = json.loads((out / "summary.json").read_text())
    assert set(r.summary) == set(disk)
    for key, value in disk.items():
        if key not in ("runtime_s",):
            _same(r.summary[key], value, key)
    with open(out / "timeseries.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == list(r.history) == r.history.columns
    assert r.history.n_rows == len(rows) - 1
    for j, name in enumerate(rows[0]):
        col = [row[j] for row in rows[1:]]
        if name == "phase":
            assert list(r.history["phase"]) == col
        else:
            np.testing.assert_allclose(r.history[name], np.array(col, float), rtol=1e-9, atol=1e-300)
    assert r.out is None and r.ok and r.scene["solver"]["duration"] == 1.5


def test_scene_forms_and_overrides_agree(tmp_path):
    """A name, a path, a dict and a Scene give the same resolved scene; nested
    and dotted overrides are the same override; --set is the same again."""
    from fpd.schema import scene as scn

    by_name = fpd.load_scene("lab-sine", friction={"mu_ref": 0.07}, solver={"dt": 2e-3})
    by_dots = fpd.load_scene("lab-sine", **{"friction.mu_ref": 0.07, "solver.dt": 2e-3})
    path = scn.SCENES_DIR / "lab-sine.toml"
    by_path = fpd.load_scene(path, friction={"mu_ref": 0.07}, solver={"dt": 2e-3})
    by_dict = fpd.load_scene(dict(scn.read_toml(path), name="lab-sine"), friction={"mu_ref": 0.07},
                             solver={"dt": 2e-3})
    by_set = scn.load("lab-sine", ["friction.mu_ref=0.07", "solver.dt=2e-3"])
    base = fpd.load_scene("lab-sine")
    by_scene = fpd.load_scene(base, friction={"mu_ref": 0.07}, solver={"dt": 2e-3})
    for s in (by_dots, by_path, by_dict, by_set, by_scene):
        assert s.data == by_name.data
    assert by_name.friction("lower")["mu_ref"] == 0.07 != base.friction("lower")["mu_ref"]
    assert fpd.load_scene(None).name == "default"
    assert fpd.load_scene("stability/tall-pad").name == "tall-pad"


def test_bad_input_raises_scene_error_with_the_cli_message():
    with pytest.raises(fpd.SceneError, match=r"friction\.mu_ref = 1\.5: must be in \[0, 1\)"):
        fpd.load_scene("lab-sine", friction={"mu_ref": 1.5})
    with pytest.raises(fpd.SceneError, match="solver.dtt.*did you mean solver.dt"):
        fpd.run("default", **{"solver.dtt": 1e-3})
    with pytest.raises(fpd.SceneError, match="no such scene"):
        fpd.run("no-such-scene")
    with pytest.raises(fpd.SceneError, match="not a table"):
        fpd.load_scene("default", **{"solver.dt": 1e-3, "solver.dt.x": 1})
    with pytest.raises(fpd.SceneError):
        fpd.load_scene(42)


def test_run_with_out_writes_the_results_folder(tmp_path):
    out = tmp_path / "res"
    r = fpd.run("sfp-harmonic", out, solver={"duration": 1.0}, output={"plots": False})
    assert r.out == out
    for f in ("timeseries.csv", "summary.json", "scene.toml"):
        assert (out / f).is_file(), f
    assert json.loads((out / "summary.json").read_text())["steps"] == r.summary["steps"]
    with pytest.raises(fpd.SceneError, match="not empty"):
        fpd.run("sfp-harmonic", out, solver={"duration": 1.0})
    assert fpd.run("sfp-harmonic", out, force=True, solver={"duration": 0.5}, output={"plots": False}).ok


def test_failure_does_not_raise():
    # a numerical failure keeps the history (here: the iterated coupling cannot converge in one iteration)
    r = fpd.run("lab-sine", solver={"duration": 0.5}, coupling={"scheme": "iterated", "max_iter": 1,
                                                                 "tol_K": 1e-12})
    assert r.status == "failed" and not r.ok and "did not converge" in r.summary["message"]
    assert r.history.n_rows >= 1


def test_history_conversions(monkeypatch):
    r = fpd.run("default", solver={"duration": 0.2})
    h = r.history
    assert set(h["phase"]) <= {"stick", "slip", "tilt"}
    assert h["phase_code"].dtype.kind == "i"
    with pytest.raises(KeyError, match="not a column"):
        h["nope"]
    pd = pytest.importorskip("pandas")
    df = h.to_pandas()
    assert list(df.columns) == h.columns and len(df) == h.n_rows
    assert isinstance(df["phase"].dtype, pd.CategoricalDtype)
    xr = pytest.importorskip("xarray")
    ds = h.to_xarray()
    assert isinstance(ds, xr.Dataset) and ds["u_m"].attrs["units"] == "m"
    np.testing.assert_array_equal(ds["t_s"].values, h["t_s"])
    monkeypatch.setitem(sys.modules, "pandas", None)
    monkeypatch.setitem(sys.modules, "xarray", None)
    with pytest.raises(ImportError, match="needs pandas: pip install pandas"):
        h.to_pandas()
    with pytest.raises(ImportError, match="needs xarray: pip install xarray"):
        h.to_xarray()


def test_compare_and_converge(tmp_path):
    c = fpd.compare("default", fast=True, solver={"duration": 2.0})
    models = {row["model"] for row in c.rows}
    assert {"lumped", "fe1d follow-pad"} <= models and c.out is None
    lumped = [row for row in c.rows if row["model"] == "lumped" and row["plate"] == "lower"][0]
    fe1d = [row for row in c.rows if row["model"] == "fe1d follow-pad" and row["plate"] == "lower"][0]
    assert fe1d["peak_T_C"] > lumped["peak_T_C"]        # conduction keeps the heat near the surface
    v = fpd.converge("heat-halfspace", tmp_path / "conv", fast=True, solver={"duration": 2.0})
    assert v.out == tmp_path / "conv" and (v.out / "orders.csv").is_file()
    assert {row["sweep"] for row in v.rows} >= {"dt", "mesh"}
    assert "converge" in v.tables and v.summary["study"] == "converge"


@pytest.mark.parametrize("script,args", [
    ("run_scene.py", ["default", "1.0"]),
    ("compare_plates.py", ["1.0"]),
    ("hysteresis_plot.py", ["{tmp}/h.png"]),
])
def test_examples_run(tmp_path, script, args):
    args = [a.format(tmp=tmp_path) for a in args]
    r = subprocess.run([sys.executable, str(ROOT / "examples" / script), *args], cwd=tmp_path, env=ENV,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip()
    if script == "hysteresis_plot.py":
        assert (tmp_path / "h.png").stat().st_size > 10_000


def test_every_example_is_tested():
    tested = {"run_scene.py", "compare_plates.py", "hysteresis_plot.py"}
    assert {p.name for p in (ROOT / "examples").glob("*.py")} == tested


def test_tfp_phase_names_read_as_the_csv_writes_them(tmp_path):
    """The TFP's phase codes (inner, outer, inner+outer) come after the DFP's
    three: the history names them as timeseries.csv does."""
    import csv

    r = fpd.run("tfp-elcentro", out=tmp_path / "r", solver={"duration": 3.0}, thermal={"model": "lumped"})
    names = list(r.history["phase"])
    with open(tmp_path / "r" / "timeseries.csv") as fh:
        written = [row["phase"] for row in csv.DictReader(fh)]
    assert names == written
    assert {"inner", "outer"} & set(names) and (r.history["phase_code"] >= 3).any()
