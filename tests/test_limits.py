"""Limits checked before anything runs, each one line naming the key: record
files that are not regular files (a FIFO would block forever), loading.dt
with a file that has a time column, plate meshes larger than the memory
available, the Python API's own argument types (fpd.SceneError)."""
from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import fpd
from fpd.schema import scene as scn
from fpd.loading.ground_motion import RecordError, read_record

ROOT = Path(__file__).resolve().parents[1]


def _fpd(args, cwd, timeout=60):
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout)


def _scene(tmp_path: Path, file: str, extra: str = "") -> Path:
    text = (scn.SCENES_DIR / "default.toml").read_text()
    text = text.replace('record = "elcentro-1940"', f'file = "{file}"\nunits = "g"\n{extra}')
    f = tmp_path / "s.toml"
    f.write_text(text)
    return f


# -- record files -------------------------------------------------------------------------
@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_fifo_record_is_refused_before_it_is_opened(tmp_path):
    """Opening a FIFO for reading blocks until a writer comes: the check
    comes before the open, in the scene (fpd check/run) and in the reader."""
    fifo = tmp_path / "rec.fifo"
    os.mkfifo(fifo)
    with pytest.raises(RecordError, match="is a FIFO \\(named pipe\\), not a regular file"):
        read_record(fifo)
    _scene(tmp_path, "rec.fifo")
    t0 = time.perf_counter()
    for cmd in (["check", "s.toml"], ["run", "s.toml", "--out", "out", "--quiet"]):
        r = _fpd(cmd, tmp_path, timeout=30)
        assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
        assert "loading.file = 'rec.fifo': is a FIFO (named pipe), not a regular file" in r.stderr, r.stderr
    assert time.perf_counter() - t0 < 30 and not (tmp_path / "out").exists()


def _two_column(tmp_path: Path, n=1000, dt=0.01) -> tuple[Path, np.ndarray]:
    t = np.arange(n) * dt
    a = 0.2 * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.2 * t)
    f = tmp_path / "two.txt"
    f.write_text("time (s), acceleration (g)\n" + "".join(f"{x!r} {y!r}\n" for x, y in zip(t.tolist(), a.tolist())))
    return f, a


def test_loading_dt_with_a_time_column_is_refused(tmp_path):
    """The file holds 0.2 g with its times 0..9.99 s: read as samples it would
    report a PGA of 9.99 g. With loading.dt it is refused, naming the key;
    without it, it is read as (time, acceleration), PGA 0.2 g."""
    f, a = _two_column(tmp_path)
    with pytest.raises(RecordError) as exc:
        read_record(f, "g", 0.01)
    msg = str(exc.value)
    assert "\n" not in msg and "remove loading.dt" in msg and "0 to 9.99" in msg, msg
    rec = read_record(f, "g")
    assert rec.pga_g == pytest.approx(np.abs(a).max(), rel=1e-12) and rec.pga_g < 0.21
    _scene(tmp_path, "two.txt", "dt = 0.01\n")
    r = _fpd(["run", "s.toml", "--out", "out", "--quiet"], tmp_path)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "loading.dt" in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()


def test_two_samples_per_line_with_loading_dt_are_still_read(tmp_path):
    """Samples two per line (an accelerogram: the first column does not
    increase on every line) are samples, read in order."""
    rng = np.random.default_rng(3)
    a = 0.1 * rng.standard_normal(400)
    f = tmp_path / "pairs.txt"
    f.write_text("".join(f"{x!r} {y!r}\n" for x, y in a.reshape(-1, 2).tolist()))
    rec = read_record(f, "g", 0.005)
    np.testing.assert_array_equal(rec.a_g, a)
    assert rec.t[-1] == pytest.approx(399 * 0.005)


# -- meshes against memory --------------------------------------------------------------------
@pytest.mark.parametrize("over, key", [
    (["thermal.model='fe3d'", "thermal.nz=200000", "thermal.grading=1.0"], "thermal.nz = 200000"),
    (["thermal.model='axisym'", "thermal.nz=2000000", "thermal.grading=1.0"], "thermal.nz = 2000000"),
    (["thermal.model='fe3d'", "thermal.per_radius=100000"], "thermal.per_radius = 100000"),
    (["thermal.n_elements=500000000", "thermal.grading=1.0"], "thermal.n_elements = 500000000"),
])
def test_a_mesh_larger_than_memory_is_refused_at_once(tmp_path, over, key):
    """Uniform meshes (grading = 1, which the first-element check lets
    through) far beyond any memory: one line naming the key, exit 2, in a
    fraction of the time building them would take."""
    args = ["check", "default"]
    for o in over:
        args += ["--set", o]
    t0 = time.perf_counter()
    r = _fpd(args, tmp_path)
    assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    assert key in r.stderr and "GB of memory available" in r.stderr and "Traceback" not in r.stderr, r.stderr
    assert time.perf_counter() - t0 < 30


def test_the_mesh_estimate_brackets_what_the_build_allocates(monkeypatch):
    """The estimate of the default fe3d plate is within a factor 2 of what
    building it allocates (tracemalloc's peak), and the check compares it
    with the memory available: refused below, accepted above."""
    import tracemalloc

    from fpd.coupling.build import build
    sc = scn.load("default", ["thermal.model='fe3d'", "thermal.upper.model='none'", "solver.duration=0.01"])
    need = scn.mesh_estimate(sc["thermal"]["lower"], 0.125)[0]
    tracemalloc.start()
    try:
        build(sc)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert 0.5 < need / peak < 2.0, (need, peak)
    monkeypatch.setattr(scn, "available_memory", lambda: need)           # 0.8 of it usable: too little
    with pytest.raises(scn.SceneError, match="thermal.lower.per_radius = 20: the fe3d mesh of the lower plate \\(115 x 75 x 61 nodes\\)"):
        scn.load("default", ["thermal.model='fe3d'", "thermal.upper.model='none'"])
    monkeypatch.setattr(scn, "available_memory", lambda: 2 * need)
    scn.load("default", ["thermal.model='fe3d'", "thermal.upper.model='none'"])


# -- the API's own arguments ------------------------------------------------------------------
@pytest.mark.parametrize("kw, needle", [
    ({"out": 123}, "fpd.run(out=123): out must be a folder path (a str or a Path) or None, not int"),
    ({"out": ""}, "out must be a folder path, not an empty string"),
    ({"out": ["a"]}, "not list"),
    ({"force": "yes"}, "fpd.run(force='yes'): force must be True or False, not str"),
    ({"progress": 1}, "progress must be True or False, not int"),
])
def test_api_argument_types_are_scene_errors(tmp_path, kw, needle):
    with pytest.raises(fpd.SceneError) as exc:
        fpd.run("default", **kw)
    assert needle in str(exc.value) and "\n" not in str(exc.value)


def test_study_argument_types_are_scene_errors():
    with pytest.raises(fpd.SceneError, match=r"fpd.compare\(out=1.5\)"):
        fpd.compare("default", out=1.5)
    with pytest.raises(fpd.SceneError, match=r"fpd.converge\(fast='no'\)"):
        fpd.converge("default", fast="no")
