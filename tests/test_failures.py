"""Issue 8: failures and interruptions never lose the history computed, and
the results folder is only ever replaced by a complete one.

Also the command-line basics of issue 1: ``fpd check``, ``fpd scenes``,
``--set`` typed as TOML, and no overwrite of a results folder without --force.
"""
from __future__ import annotations

import csv
import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from fpd.frontends import cli
from fpd.outputs import output as out_mod
from fpd.schema.scene import SceneError, load, parse_override

ROOT = Path(__file__).resolve().parent.parent
SCENE = """
name = "short"
[device]
kind = "DFP"
R1 = 2.2
R2 = 2.2
pad_height = 0.10
pad_diameter = 0.25
pad_mass = 30.0
[superstructure]
mass = 1.0e5
[friction]
law = "constant"
mu = 0.05
[loading]
kind = "harmonic"
amplitude_m = 0.05
frequency_Hz = 1.0
cycles = 1
[mechanics]
model = "seated"
[thermal]
model = "lumped"
[solver]
dt = 1.0e-3
[output]
plots = false
"""


def _env(extra=None):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.update(extra or {})
    return env


def fpd(args, cwd, env_extra=None, timeout=120):
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=cwd, env=_env(env_extra),
                          capture_output=True, text=True, timeout=timeout)


@pytest.fixture
def scene_file(tmp_path):
    p = tmp_path / "short.toml"
    p.write_text(SCENE)
    return p


def read_rows(path: Path):
    """timeseries.csv as (header, rows); every line complete and newline-ended."""
    text = path.read_text()
    assert text.endswith("\n"), "last line truncated"
    rows = list(csv.reader(text.splitlines()))
    header, body = rows[0], rows[1:]
    for r in body:
        assert len(r) == len(header), r
        for name, x in zip(header, r):
            if name != "phase":
                assert math.isfinite(float(x)), (name, x)
    return header, body


def snapshot(folder: Path) -> dict:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def no_leftovers(parent: Path, keep: set):
    names = {p.name for p in parent.iterdir()}
    assert names == keep, names


# -- a step that fails -----------------------------------------------------------
def test_injected_nan_keeps_history(tmp_path, scene_file):
    out = tmp_path / "runs" / "res"
    proc = fpd(["run", str(scene_file), "--out", str(out)], cwd=tmp_path,
               env_extra={"FPD_INJECT_NAN_AT_STEP": "250"})
    assert proc.returncode == 1, proc.stderr
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.splitlines()) == 1, proc.stderr
    assert "step 250" in proc.stderr and "t = 0.25 s" in proc.stderr and str(out) in proc.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "failed"
    assert "step 250" in s["message"] and "t = 0.25 s" in s["message"] and "non-finite" in s["message"]
    assert s["steps"] == 249
    header, rows = read_rows(out / "timeseries.csv")
    assert len(rows) == 250                                     # steps 0 .. 249, all complete
    t = [float(r[header.index("t_s")]) for r in rows]
    assert t[0] == 0.0 and t[-1] == pytest.approx(0.249)
    assert (out / "scene.toml").is_file()
    no_leftovers(out.parent, {"res"})


def test_injected_nan_with_csv_every(tmp_path, scene_file):
    out = tmp_path / "res"
    proc = fpd(["run", str(scene_file), "--out", str(out), "--set", "output.csv_every=10", "--quiet"],
               cwd=tmp_path, env_extra={"FPD_INJECT_NAN_AT_STEP": "105"})
    assert proc.returncode == 1 and "step 105" in proc.stderr and "t = 0.105 s" in proc.stderr
    header, rows = read_rows(out / "timeseries.csv")
    assert [float(r[0]) for r in rows] == pytest.approx([0.01 * i for i in range(11)])
    assert json.loads((out / "summary.json").read_text())["status"] == "failed"


def test_step_raising_arithmetic_error_keeps_history(tmp_path, scene_file, monkeypatch):
    """Any arithmetic error inside a step is a numerical failure at that step,
    not a traceback that throws the history away."""
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate

    sim = build(load(str(scene_file)))
    real = sim.mechanics.step

    def step(mu1, mu2):
        if sim.mechanics.n == 99:
            raise ZeroDivisionError("float division by zero")
        return real(mu1, mu2)

    monkeypatch.setattr(sim.mechanics, "step", step)
    res = simulate(sim)
    assert res.status == "failed"
    assert "step 100" in res.message and "t = 0.1 s" in res.message and "division by zero" in res.message
    assert res.n_rows == 100 and res.steps == 99
    assert math.isfinite(res.data.sum())


# -- Ctrl-C ------------------------------------------------------------------------
def _start_long_run(tmp_path, extra=()):
    out = tmp_path / "runs" / "long"
    out.parent.mkdir()
    proc = subprocess.Popen([sys.executable, "-m", "fpd", "run", "--out", str(out),
                             "--set", "solver.dt=1e-4", "--set", "output.plots=false", *extra],
                            cwd=tmp_path, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    partial = out.parent / f".long.partial-{proc.pid}"
    t0 = time.monotonic()
    while not partial.exists():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() - t0 < 30, "run did not start"
        time.sleep(0.02)
    time.sleep(0.4)                         # well inside the time loop (about 3 s long)
    assert proc.poll() is None
    return proc, out


def _check_interrupted(proc, out, stdout, stderr):
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "interrupted", s
    assert "interrupted at step" in s["message"]
    header, rows = read_rows(out / "timeseries.csv")
    assert 10 < len(rows) < 399000
    assert len(rows) == s["steps"] + 1
    assert float(rows[-1][0]) == pytest.approx(s["steps"] * 1e-4)
    assert (out / "scene.toml").is_file()
    no_leftovers(out.parent, {"long"})
    return s


def test_sigint_keeps_history(tmp_path):
    proc, out = _start_long_run(tmp_path)
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    s = _check_interrupted(proc, out, stdout, stderr)
    # one line for the interruption (the one-line compile notice may come first, on a cold cache)
    from fpd.jitcache import NOTICE
    lines = [ln for ln in stderr.splitlines() if ln != NOTICE]
    assert "interrupted at step" in stderr and len(lines) == 1


def test_second_sigint_while_writing_keeps_history(tmp_path):
    """A second Ctrl-C (or SIGTERM) while the history is being written does
    not throw it away: the folder is finished first."""
    proc, out = _start_long_run(tmp_path, ("--quiet",))
    proc.send_signal(signal.SIGINT)
    time.sleep(0.3)
    if proc.poll() is None:
        proc.send_signal(signal.SIGTERM)
    stdout, stderr = proc.communicate(timeout=60)
    _check_interrupted(proc, out, stdout, stderr)


# -- the results folder ----------------------------------------------------------------
def test_rerun_refuses_without_force(tmp_path, scene_file):
    out = tmp_path / "runs" / "res"
    assert fpd(["run", str(scene_file), "--out", str(out), "--quiet"], cwd=tmp_path).returncode == 0
    before = snapshot(out)
    proc = fpd(["run", str(scene_file), "--out", str(out)], cwd=tmp_path)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert len(proc.stderr.splitlines()) == 1
    assert str(out) in proc.stderr and "--force" in proc.stderr
    assert snapshot(out) == before
    no_leftovers(out.parent, {"res"})


def test_empty_out_dir_is_used(tmp_path, scene_file):
    out = tmp_path / "res"
    out.mkdir()
    assert fpd(["run", str(scene_file), "--out", str(out), "--quiet"], cwd=tmp_path).returncode == 0
    assert (out / "summary.json").is_file()


def test_force_bad_input_keeps_old_results(tmp_path, scene_file):
    out = tmp_path / "runs" / "res"
    assert fpd(["run", str(scene_file), "--out", str(out), "--quiet"], cwd=tmp_path).returncode == 0
    before = snapshot(out)
    (tmp_path / "empty.AT2").write_text("")
    for extra in (["--set", "solver.dt=-1"], ["--set", "loading.kind=record", "--set", "loading.file=empty.AT2",
                                              "--set", "loading.amplitude_m=0"]):
        proc = fpd(["run", str(scene_file), "--out", str(out), "--force", *extra], cwd=tmp_path)
        assert proc.returncode == 2, proc.stderr
        assert snapshot(out) == before
        no_leftovers(out.parent, {"res"})


def test_force_replaces_when_complete(tmp_path, scene_file):
    out = tmp_path / "runs" / "res"
    assert fpd(["run", str(scene_file), "--out", str(out), "--quiet"], cwd=tmp_path).returncode == 0
    (out / "stale.txt").write_text("from an older run")
    proc = fpd(["run", str(scene_file), "--out", str(out), "--force", "--quiet", "--set", "friction.mu=0.08"],
               cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert not (out / "stale.txt").exists()
    assert "mu = 0.08" in (out / "scene.toml").read_text()
    assert json.loads((out / "summary.json").read_text())["status"] == "ok"
    no_leftovers(out.parent, {"res"})


@pytest.fixture
def keep_sigterm():
    """main() installs its SIGTERM handler: put pytest's back afterwards."""
    old = signal.getsignal(signal.SIGTERM)
    yield
    signal.signal(signal.SIGTERM, old)


def test_force_crash_while_writing_keeps_old_results(tmp_path, scene_file, monkeypatch, capsys, keep_sigterm):
    """Old results stay intact until the new ones are complete: a crash in the
    middle of writing leaves the old folder as it was and no partial folder."""
    out = tmp_path / "runs" / "res"
    assert cli.main(["run", str(scene_file), "--out", str(out), "--quiet"]) == 0
    before = snapshot(out)

    def broken(*a, **k):
        raise OSError(28, "No space left on device")

    # a write failure (issue 19): one line, exit 1, the earlier results kept as they were
    monkeypatch.setattr(out_mod, "summary", broken)
    capsys.readouterr()
    assert cli.main(["run", str(scene_file), "--out", str(out), "--quiet", "--force"]) == 1
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "No space left on device" in err and "1000 steps computed" in err
    assert "still holds the earlier results" in err
    assert snapshot(out) == before
    no_leftovers(out.parent, {"res"})

    # any other crash: raised as it was, the old folder untouched too
    def bug(*a, **k):
        raise RuntimeError("a bug")

    monkeypatch.setattr(out_mod, "summary", bug)
    with pytest.raises(RuntimeError):
        cli.main(["run", str(scene_file), "--out", str(out), "--quiet", "--force"])
    assert snapshot(out) == before
    no_leftovers(out.parent, {"res"})


def test_force_failed_run_replaces_with_its_history(tmp_path, scene_file):
    out = tmp_path / "res"
    assert fpd(["run", str(scene_file), "--out", str(out), "--quiet"], cwd=tmp_path).returncode == 0
    proc = fpd(["run", str(scene_file), "--out", str(out), "--force", "--quiet"], cwd=tmp_path,
               env_extra={"FPD_INJECT_NAN_AT_STEP": "10"})
    assert proc.returncode == 1
    assert json.loads((out / "summary.json").read_text())["status"] == "failed"
    assert len(read_rows(out / "timeseries.csv")[1]) == 10


# -- check, scenes, --set ----------------------------------------------------------
def test_check_prints_resolved_scene(tmp_path, scene_file):
    import tomllib

    proc = fpd(["check", str(scene_file), "--set", "friction.mu=0.07"], cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    resolved = tomllib.loads(proc.stdout)
    assert resolved["friction"]["lower"]["mu"] == 0.07 and resolved["friction"]["upper"]["mu"] == 0.07
    assert resolved["thermal"]["lower"]["k"] == 16.0            # defaults spelled out
    assert list(tmp_path.iterdir()) == [scene_file]             # check writes nothing


def test_check_packaged_default(tmp_path):
    proc = fpd(["check", "default"], cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert 'record = "elcentro-1940"' in proc.stdout


def test_scenes_lists_packaged(tmp_path):
    proc = fpd(["scenes"], cwd=tmp_path)
    assert proc.returncode == 0
    names = [line.split()[0] for line in proc.stdout.splitlines()]
    assert {"default", "lab-sine", "northridge-dfp", "sfp-harmonic"} <= set(names)


@pytest.mark.parametrize("text,value", [
    ("solver.dt=5e-4", 5e-4),
    ("thermal.n_elements=50", 50),
    ("output.plots=false", False),
    ("mechanics.model=seated", "seated"),
    ('name="my-run"', "my-run"),
    ("friction.T_C=[20, 100.5]", [20, 100.5]),
    ("friction.mu = 0.08", 0.08),
    ("thermal.lower.k=20", 20),
])
def test_set_typed_as_toml(text, value):
    keys, parsed = parse_override(text)
    assert keys == text.split("=")[0].strip().split(".")
    assert parsed == value and type(parsed) is type(value)


def test_set_applies_to_scene(scene_file):
    sc = load(str(scene_file), ["solver.dt=5e-4", "thermal.lower.k=20", "output.plots=true"])
    assert sc["solver"]["dt"] == 5e-4
    assert sc.thermal("lower")["k"] == 20.0 and sc.thermal("upper")["k"] == 16.0
    assert sc["output"]["plots"] is True
    with pytest.raises(SceneError, match="solver.dt = 'x'"):
        load(str(scene_file), ["solver.dt=x"])


def test_coupling_not_converged_is_a_failure(tmp_path, scene_file):
    out = tmp_path / "res"
    proc = fpd(["run", str(scene_file), "--out", str(out), "--quiet", "--set", "coupling.scheme=iterated",
                "--set", "coupling.max_iter=1", "--set", "coupling.tol_K=1e-12"], cwd=tmp_path)
    assert proc.returncode == 1, proc.stderr
    assert len(proc.stderr.splitlines()) == 1 and "did not converge" in proc.stderr and "step " in proc.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "failed" and "did not converge" in s["message"]
    header, rows = read_rows(out / "timeseries.csv")
    assert len(rows) == s["steps"] + 1 >= 1
