"""output.history = "parquet": timeseries.parquet holds the rows of
timeseries.csv unrounded, the summary is unchanged (issue 18)."""
from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

ROOT = Path(__file__).resolve().parents[1]


def _fpd(*args, cwd):
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=300)


def test_parquet_history_is_the_csv_history(tmp_path):
    common = ["--set", "output.plots=false", "--set", "solver.duration=1.5", "--quiet"]
    r = _fpd("run", "lab-sine", "--out", str(tmp_path / "c"), *common, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    r = _fpd("run", "lab-sine", "--out", str(tmp_path / "p"), "--set", 'output.history="parquet"', *common,
             cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert not (tmp_path / "p" / "timeseries.csv").exists()
    table = pq.read_table(tmp_path / "p" / "timeseries.parquet")
    with open(tmp_path / "c" / "timeseries.csv") as fh:
        rows = list(csv.reader(fh))
    assert table.schema.names == rows[0]
    assert table.num_rows == len(rows) - 1 == 1501
    for j, name in enumerate(rows[0]):
        col = table.column(name)
        if name == "phase":
            assert col.to_pylist() == [r[j] for r in rows[1:]]
        else:
            ref = np.array([float(r[j]) for r in rows[1:]])
            got = col.to_numpy()
            assert got.dtype == np.float64
            np.testing.assert_allclose(got, ref, rtol=1e-9, atol=1e-300)   # the CSV's 10 digits
    sc, sp = (json.loads((tmp_path / d / "summary.json").read_text()) for d in ("c", "p"))
    for s in (sc, sp):
        s.pop("runtime_s")
    assert sc == sp


def test_parquet_without_pyarrow_is_one_clear_line(monkeypatch):
    from fpd.schema import scene as scn
    from fpd.outputs.output import history_format
    from fpd.schema.scene import SceneError

    sc = scn.load("lab-sine", ['output.history="parquet"'])
    monkeypatch.setitem(sys.modules, "pyarrow", None)
    monkeypatch.setitem(sys.modules, "pyarrow.parquet", None)
    with pytest.raises(SceneError, match='output.history = "parquet" needs pyarrow'):
        history_format(sc)


def test_pandas_reads_it(tmp_path):
    pd = pytest.importorskip("pandas")
    r = _fpd("run", "lab-sine", "--out", str(tmp_path / "p"), "--set", 'output.history="parquet"', "--set",
             "output.plots=false", "--set", "solver.duration=0.5", "--quiet", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    df = pd.read_parquet(tmp_path / "p" / "timeseries.parquet")
    assert len(df) == 501 and list(df["phase"].astype(str).unique()) == ["stick", "slip"]
