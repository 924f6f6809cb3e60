"""Issue 8: the catalogue of bad inputs.

Every item runs ``fpd run`` and must give exit status 2, one line on stderr
naming the file, the key (dotted path) or line number, the value and what is
allowed, no traceback, and no results folder: nothing at all may appear in
the (empty) folder that holds --out, which is also the working directory of
the run. The catalogue calls ``coupling.cli.main`` in-process (any exception
but the handled input errors fails the test, as a traceback would), and a
sample of it runs again as real ``fpd`` subprocesses.
"""
from __future__ import annotations

import copy
import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from helpers import refusal

ROOT = Path(__file__).resolve().parent.parent

BASE = {
    "name": "bad",
    "device": {"kind": "DFP", "R1": 2.2, "R2": 2.2, "pad_height": 0.10, "pad_diameter": 0.25,
               "pad_mass": 30.0},
    "superstructure": {"mass": 1.0e5},
    "friction": {"law": "constant", "mu": 0.05},
    "loading": {"kind": "harmonic", "amplitude_m": 0.05, "frequency_Hz": 1.0, "cycles": 1},
    "mechanics": {"model": "seated"},
    "thermal": {"model": "lumped"},
    "solver": {"dt": 1.0e-3},
    "output": {"plots": False},
}
DELETE = object()


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return repr(v)


def dump_toml(d: dict, prefix: str = "") -> str:
    """A small TOML writer for the scenes of these tests."""
    lines = [f"{k} = {_value(v)}" for k, v in d.items() if not isinstance(v, dict)]
    for k, v in d.items():
        if isinstance(v, dict):
            name = f"{prefix}{k}"
            lines.append(f"\n[{name}]")
            lines.append(dump_toml(v, name + "."))
    return "\n".join(lines) + "\n"


def scene_with(changes: dict) -> dict:
    """BASE with dotted keys replaced (a dict replaces a whole table) or deleted."""
    d = copy.deepcopy(BASE)
    for key, value in changes.items():
        *tables, last = key.split(".")
        node = d
        for t in tables:
            node = node.setdefault(t, {})
        if value is DELETE:
            node.pop(last, None)
        else:
            node[last] = value
    return d


def fpd(args, cwd, env_extra=None, timeout=60):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.update(env_extra or {})
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


@pytest.fixture
def fpd_inproc(capsys, monkeypatch):
    """``fpd`` called in-process: (args, cwd) -> an object like CompletedProcess."""
    from fpd.frontends import cli

    def call(args, cwd):
        monkeypatch.chdir(cwd)
        capsys.readouterr()
        sigterm = signal.getsignal(signal.SIGTERM)     # main() installs its own
        try:
            rc = cli.main(list(args))
        except SystemExit as exc:          # argparse errors
            rc = exc.code
        finally:
            monkeypatch.undo()
            signal.signal(signal.SIGTERM, sigterm)
        outerr = capsys.readouterr()
        return subprocess.CompletedProcess(args, rc, outerr.out, outerr.err)
    return call


@pytest.fixture
def dirs(tmp_path):
    """(folder for inputs, empty folder that will hold --out and is the cwd)."""
    inp, runs = tmp_path / "in", tmp_path / "runs"
    inp.mkdir()
    runs.mkdir()
    return inp, runs


def assert_input_error(proc, runs: Path, *tokens):
    err = proc.stderr
    assert proc.returncode == 2, (proc.returncode, err)
    assert "Traceback" not in err, err
    lines = err.splitlines()
    assert len(lines) == 1 and err.endswith("\n"), err
    for tok in tokens:
        assert tok in err, f"{tok!r} not in {err!r}"
    assert list(runs.iterdir()) == [], f"left on disk: {list(runs.iterdir())}"
    assert proc.stdout == ""


def run_scene(dirs, changes, extra=(), runner=None):
    inp, runs = dirs
    path = inp / "scene.toml"
    path.write_text(dump_toml(scene_with(changes)))
    return (runner or fpd)(["run", str(path), "--out", str(runs / "res"), *extra], cwd=runs), path


def test_base_scene_is_valid(dirs):
    """The catalogue's starting point runs: each error below is the change's."""
    proc, _ = run_scene(dirs, {})
    assert proc.returncode == 0, proc.stderr
    assert (dirs[1] / "res" / "summary.json").is_file()
    assert [p.name for p in dirs[1].iterdir()] == ["res"]


# (id, changes, extra args, tokens that the one line must hold besides the scene file)
CATALOGUE = [
    # unknown keys, with the nearest valid key suggested
    ("unknown-key", {"solver.dtt": 1e-3}, (), ["solver.dtt", "0.001", "unknown key", "did you mean solver.dt?"]),
    ("unknown-table", {"devcie": {"R1": 2.0}}, (), ["devcie", "unknown key", "did you mean device?"]),
    ("unknown-thermal-key", {"thermal.rh0": 7850.0}, (), ["thermal.rh0", "7850", "did you mean thermal.rho?"]),
    ("unknown-top-key", {"nmae": "x"}, (), ["nmae", "'x'", "did you mean name?"]),
    ("key-of-other-law", {"friction.mu_ref": 0.06}, (), ["friction.mu_ref", "0.06", 'belongs to law "kumar2015"']),
    # wrong types
    ("string-for-number", {"device.R1": "big"}, (), ["device.R1", "'big'", "must be a number"]),
    ("bool-for-number", {"superstructure.mass": True}, (), ["superstructure.mass", "True", "must be a number"]),
    ("number-for-bool", {"output.plots": 1}, (), ["output.plots", "1", "must be true or false"]),
    ("fraction-for-int", {"thermal.n_elements": 2.5}, (), ["thermal.n_elements", "2.5", "whole number"]),
    ("scalar-for-table", {"solver": 3}, (), ["solver", "3", "must be a table"]),
    ("number-for-name", {"name": 5}, (), ["name", "5", "must be a string"]),
    ("list-for-number", {"friction.mu": [0.05]}, (), ["friction.mu", "[0.05]", "must be a number"]),
    # missing required keys
    ("missing-R1", {"device.R1": DELETE}, (), ["device.R1", "missing", "give a number"]),
    ("missing-R2-DFP", {"device.R2": DELETE}, (), ["device.R2", "missing"]),
    ("missing-mass", {"superstructure.mass": DELETE}, (), ["superstructure.mass", "missing"]),
    ("missing-mu", {"friction.mu": DELETE}, (), ["friction.mu", "missing"]),
    ("missing-loading", {"loading": DELETE}, (), ["loading", "missing"]),
    ("missing-loading-kind", {"loading.kind": DELETE}, (), ["loading.kind", "missing", '"harmonic"']),
    ("missing-amplitude", {"loading.amplitude_m": DELETE}, (), ["loading.amplitude_m", "missing"]),
    # negative or zero radii, masses, dt, duration
    ("R1-negative", {"device.R1": -2.2}, (), ["device.R1", "-2.2", "must be > 0"]),
    ("R2-zero", {"device.R2": 0.0}, (), ["device.R2", "0", "must be > 0"]),
    ("mass-zero", {"superstructure.mass": 0}, (), ["superstructure.mass", "0", "must be > 0"]),
    ("pad-mass-negative", {"device.pad_mass": -30.0}, (), ["device.pad_mass", "-30", "must be > 0"]),
    ("dt-zero", {"solver.dt": 0.0}, (), ["solver.dt", "0", "must be > 0"]),
    ("dt-negative", {"solver.dt": -1e-3}, (), ["solver.dt", "-0.001", "must be > 0"]),
    ("duration-zero", {"solver.duration": 0.0}, (), ["solver.duration", "0", "must be > 0"]),
    ("duration-negative", {"solver.duration": -5.0}, (), ["solver.duration", "-5", "must be > 0"]),
    ("dt-nan", {"solver.dt": float("nan")}, (), ["solver.dt", "nan", "must be finite"]),
    # dt larger than the duration (given, or the loading's own length)
    ("dt-above-duration", {"solver.dt": 0.5, "solver.duration": 0.1}, (),
     ["solver.dt", "0.5", "must not exceed solver.duration = 0.1"]),
    ("dt-above-loading", {"solver.dt": 2.0}, (), ["solver.dt", "2", "must not exceed the loading's length 1 s"]),
    # pads that do not fit
    ("pad-taller-than-R1+R2", {"device.pad_height": 5.0}, (), ["device.pad_height", "5", "R1 + R2"]),
    ("pad-wider-than-surface", {"device.pad_diameter": 4.5}, (), ["device.pad_diameter", "4.5", "min(R1, R2)"]),
    ("sfp-pad-wider", {"device.kind": "SFP", "device.R2": DELETE, "device.pad_diameter": 4.5}, (),
     ["device.pad_diameter", "4.5", "2 R1"]),
    ("sfp-pivot-above-centre", {"device.kind": "SFP", "device.R2": DELETE, "device.pad_height": 2.5}, (),
     ["device.pad_height", "2.5", "R1"]),
    # friction coefficients outside [0, 1)
    ("mu-one", {"friction.mu": 1.0}, (), ["friction.mu", "1", "[0, 1)"]),
    ("mu-negative", {"friction.mu": -0.1}, (), ["friction.mu", "-0.1", "[0, 1)"]),
    ("mu-upper-override", {"friction.upper": {"mu": 1.5}}, (), ["friction.upper.mu", "1.5", "[0, 1)"]),
    ("linear-mu0", {"friction": {"law": "linear", "mu0": 2.0, "slope_per_C": -1e-4}}, (),
     ["friction.mu0", "2", "[0, 1)"]),
    # table law
    ("table-unsorted", {"friction": {"law": "table", "T_C": [20.0, 10.0, 30.0], "mu": [0.05, 0.04, 0.03]}}, (),
     ["friction.T_C", "[20.0, 10.0, 30.0]", "must increase strictly"]),
    ("table-mismatched", {"friction": {"law": "table", "T_C": [20.0, 100.0], "mu": [0.05]}}, (),
     ["friction.mu", "[0.05]", "as many entries as T_C (2)"]),
    ("table-mu-out-of-range", {"friction": {"law": "table", "T_C": [20.0, 100.0], "mu": [0.05, 1.2]}}, (),
     ["friction.mu", "[0.05, 1.2]", "[0, 1)"]),
    ("table-empty", {"friction": {"law": "table", "T_C": [], "mu": []}}, (),
     ["friction.T_C", "[]", "non-empty list"]),
    # thermal properties <= 0
    ("k-zero", {"thermal.k": 0.0}, (), ["thermal.k", "0", "must be > 0"]),
    ("rho-negative", {"thermal.rho": -7850.0}, (), ["thermal.rho", "-7850", "must be > 0"]),
    ("c-zero", {"thermal.c": 0}, (), ["thermal.c", "0", "must be > 0"]),
    ("k-lower-plate", {"thermal.lower": {"k": -1.0}}, (), ["thermal.lower.k", "-1", "must be > 0"]),
    # meshes with fewer than two elements
    ("fe1d-one-element", {"thermal.model": "fe1d", "thermal.n_elements": 1}, (), ["thermal.n_elements", "1", ">= 2"]),
    ("axisym-nr", {"thermal.model": "axisym", "thermal.nr": 1}, (), ["thermal.nr", "1", ">= 2"]),
    ("axisym-nz", {"thermal.model": "axisym", "thermal.nz": 0}, (), ["thermal.nz", "0", ">= 2"]),
    # unknown model and scheme names
    ("mechanics-model", {"mechanics.model": "three-phase"}, (), ["mechanics.model", "'three-phase'", '"seated"']),
    ("thermal-model", {"thermal.model": "fem"}, (), ["thermal.model", "'fem'", '"fe1d"']),
    ("coupling-scheme", {"coupling": {"scheme": "implicit"}}, (), ["coupling.scheme", "'implicit'", '"iterated"']),
    ("thermal-scheme", {"thermal.scheme": "rk4"}, (), ["thermal.scheme", "'rk4'", '"bdf2"']),
    ("friction-law", {"friction.law": "coulomb"}, (), ["friction.law", "'coulomb'", '"kumar2015"']),
    ("friction-law-list", {"friction.law": ["constant"]}, (), ["friction.law", "['constant']", '"constant"']),
    ("loading-kind", {"loading.kind": "quake"}, (), ["loading.kind", "'quake'", '"record"']),
    ("loading-kind-number", {"loading.kind": 3}, (), ["loading.kind", "3", '"record"']),
    ("device-kind", {"device.kind": "QFP"}, (), ["device.kind", "'QFP'", '"DFP"', '"TFP"']),
    ("packaged-record", {"loading": {"kind": "record", "record": "kobe"}}, (),
     ["loading.record", "'kobe'", '"elcentro-1940"']),
    # --set overrides that are malformed, or whose value the scene refuses
    ("set-bad-number", {}, ("--set", "solver.dt=1e-3e"), ["--set", "solver.dt", "1e-3e", "not a TOML value"]),
    ("set-no-equals", {}, ("--set", "solver.dt"), ["--set", "solver.dt", "KEY=VALUE"]),
    ("set-empty-value", {}, ("--set", "solver.dt="), ["--set", "solver.dt", "not a TOML value"]),
    ("set-bad-key", {}, ("--set", "solver..dt=1"), ["--set", "solver..dt", "not a dotted key"]),
    ("set-open-list", {}, ("--set", "friction.mu=[1,"), ["--set", "friction.mu", "[1,", "not a TOML value"]),
    ("set-into-scalar", {}, ("--set", "device.R1.x=2"), ["--set", "device.R1.x", "'R1' is not a table"]),
    ("set-word-for-number", {}, ("--set", "solver.dt=fast"), ["solver.dt", "'fast'", "must be a number"]),
    ("set-unknown-key", {}, ("--set", "friction.muu=0.1"), ["friction.muu", "0.1", "did you mean friction.mu?"]),
    ("set-inf", {}, ("--set", "solver.dt=inf"), ["solver.dt", "inf", "must be finite"]),
    # keys that would be ignored: an SFP's second radius, units that no record file reads
    ("sfp-R2-not-R1", {"device.kind": "SFP", "device.R2": 3.0}, (),
     ["device.R2", "3", "one concave surface", "R1 = 2.2", "leave R2 out"]),
    ("units-of-an-AT2", {"loading": {"kind": "record", "record": "elcentro-1940", "units": "m/s2"}}, (),
     ["loading.units", "'m/s2'", "is not read", "remove loading.units"]),
    # programmes the steps cannot sample or hold
    ("frequency-above-two-steps", {"loading.frequency_Hz": 600.0}, (),
     ["loading.frequency_Hz", "600", "shorter than two steps", "at most 500 Hz"]),
    ("pulse-period-below-two-steps", {"loading": {"kind": "pulse", "velocity_mps": 0.5, "period_s": 1e-3}}, (),
     ["loading.period_s", "0.001", "shorter than two steps", "at least 0.002 s"]),
    ("axial-frequency-above-two-steps", {"loading": {"kind": "displacement", "amplitude_m": 0.05, "frequency_Hz": 1.0,
                                                     "cycles": 1, "vertical": "sine", "vertical_amplitude_ratio": 0.1,
                                                     "vertical_frequency_Hz": 1000.0}}, (),
     ["loading.vertical_frequency_Hz", "1000", "shorter than two steps"]),
    ("machine-cycles-beyond-steps", {"loading": {"kind": "displacement", "amplitude_m": 0.05, "frequency_Hz": 1.0,
                                                 "cycles": 1e50}, "solver.duration": 1.0}, (),
     ["loading.cycles", "1e+50", "steps of solver.dt", "at most 2e+07", "not its programme"]),
    ("machine-hold-beyond-steps", {"loading": {"kind": "displacement", "amplitude_m": 0.05, "frequency_Hz": 1.0,
                                               "cycles": 1, "hold_s": 1e50}, "solver.duration": 1.0}, (),
     ["loading.hold_s", "1e+50", "at most 2e+07"]),
    # a user mesh on a plate that does not read it
    ("mesh-file-not-axisym", {"thermal.mesh_file": "m.msh"}, (),
     ["thermal.mesh_file", "'m.msh'", 'is for model = "axisym"', '"lumped"', "leave mesh_file out"]),
    # a liner preset's breakaway below the law the scene gives: named as the preset's
    ("liner-mu-static-below-law", {"friction": {"liner": "ptfe", "law": "constant", "mu": 0.2}}, (),
     ["friction.liner", "'ptfe'", "the preset's friction.mu_static = 0.1: must be >=", "0.2 at rest",
      "give friction.mu_static"]),
]


@pytest.mark.parametrize("changes,extra,tokens", [c[1:] for c in CATALOGUE], ids=[c[0] for c in CATALOGUE])
def test_catalogue(dirs, fpd_inproc, changes, extra, tokens):
    proc, path = run_scene(dirs, changes, extra, fpd_inproc)
    assert_input_error(proc, dirs[1], str(path), *tokens)


SAMPLE = ("unknown-key", "string-for-number", "missing-R1", "dt-above-duration", "pad-taller-than-R1+R2",
          "table-unsorted", "set-bad-number", "friction-law-list")


@pytest.mark.parametrize("changes,extra,tokens", [c[1:] for c in CATALOGUE if c[0] in SAMPLE], ids=SAMPLE)
def test_catalogue_subprocess(dirs, changes, extra, tokens):
    """The same, as the real command: exit status, stderr and no traceback."""
    proc, path = run_scene(dirs, changes, extra)
    assert_input_error(proc, dirs[1], str(path), *tokens)


# -- record files ---------------------------------------------------------------
GOOD_AT2 = "TITLE\nLINE 2\nUNITS OF G\nNPTS=  8, DT= .01000 SEC\n 0.01 0.02 0.03 0.04\n 0.03 0.02 0.01 0.00\n"

RECORD_CASES = [
    # (id, file name, content (None: no file), units, tokens)
    ("missing", "nope.AT2", None, None, ["loading.file", "'nope.AT2'", "file not found"]),
    ("empty", "empty.AT2", b"", None, ["empty.AT2", "loading.file", "empty"]),
    ("blank", "blank.txt", b"  \n\n \t\n", "g", ["blank.txt", "loading.file", "empty"]),
    ("binary", "bin.AT2", bytes(range(256)) * 4, None, ["bin.AT2", "loading.file", "binary"]),
    ("directory", "adir", "DIR", None, ["adir", "loading.file", "directory"]),
    ("header-unreadable", "h.AT2", b"T\nT\nT\nNPTS= many, DT= .01 SEC\n 0.1 0.2\n", None,
     ["h.AT2", "line 4", "NPTS= many", "cannot read NPTS and DT"]),
    ("header-npts-mismatch", "n.AT2", GOOD_AT2.replace("NPTS=  8", "NPTS=  10").encode(), None,
     ["n.AT2", "loading.file", "NPTS = 10", "8 values follow"]),
    ("header-npts-fraction", "f.AT2", GOOD_AT2.replace("NPTS=  8", "NPTS=  8.5").encode(), None,
     ["f.AT2", "line 4", "NPTS = 8.5", "whole number"]),
    ("header-dt-zero", "z.AT2", GOOD_AT2.replace("DT= .01000", "DT= 0.0").encode(), None,
     ["z.AT2", "line 4", "DT = 0", "finite number > 0"]),
    ("at2-bad-value", "v.AT2", GOOD_AT2.replace("0.03 0.02 0.01", "0.03 0.0x2 0.01").encode(), None,
     ["v.AT2", "line 6", "'0.0x2'", "not a number"]),
    ("at2-nan", "nan.AT2", GOOD_AT2.replace("0.03 0.02 0.01", "0.03 NaN 0.01").encode(), None,
     ["nan.AT2", "line 6", "non-finite"]),
    ("at2-inf", "inf.AT2", GOOD_AT2.replace("0.01 0.02", "inf 0.02").encode(), None,
     ["inf.AT2", "line 5", "non-finite"]),
    ("two-col-nan", "nan.txt", b"time accel\n0.0 0.0\n0.01 nan\n0.02 0.1\n", "g",
     ["nan.txt", "line 3", "non-finite", "nan"]),
    ("two-col-times-decrease", "t.txt", b"0.0 0.0\n0.01 0.1\n0.005 0.2\n0.03 0.0\n", "g",
     ["t.txt", "line 3", "time 0.005", "does not increase"]),
    ("two-col-times-repeat", "r.txt", b"0.0 0.0\n0.01 0.1\n0.01 0.2\n0.03 0.0\n", "g",
     ["r.txt", "line 3", "time 0.01", "does not increase"]),
    ("two-col-three-columns", "c.txt", b"0.0 0.0 1\n0.01 0.1 2\n", "g", ["c.txt", "line 1", "found 3"]),
    ("two-col-one-row", "o.txt", b"Time[s] Accel[g]\n0.0 0.0\n", None, ["o.txt", "loading.file", "fewer than two"]),
    ("two-col-no-units", "u.txt", b"0.0 0.0\n0.01 0.1\n0.02 0.0\n", None, ["u.txt", "loading.units", '"m/s2"']),
    ("two-col-garbage-line", "g.txt", b"0.0 0.0\n0.01 0.1\n0.02 zero\n", "g", ["g.txt", "line 3", "0.02 zero"]),
]


RECORD_SAMPLE = ("empty", "binary", "header-npts-mismatch", "at2-nan", "two-col-times-decrease")
RECORD_RUNS = [(c, "inproc") for c in RECORD_CASES] + [(c, "subprocess") for c in RECORD_CASES
                                                       if c[0] in RECORD_SAMPLE]


@pytest.mark.parametrize("name,content,units,tokens,how", [c[1:] + (how,) for c, how in RECORD_RUNS],
                         ids=[f"{c[0]}-{how}" for c, how in RECORD_RUNS])
def test_record_catalogue(dirs, fpd_inproc, how, name, content, units, tokens):
    inp, runs = dirs
    if content == "DIR":
        (inp / name).mkdir()
    elif content is not None:
        (inp / name).write_bytes(content)
    loading = {"kind": "record", "file": name}
    if units:
        loading["units"] = units
    proc, path = run_scene(dirs, {"loading": loading}, (), fpd_inproc if how == "inproc" else None)
    assert_input_error(proc, runs, *tokens)
    if content is None:
        assert str(path) in proc.stderr


def test_record_error_in_check_too(dirs):
    inp, runs = dirs
    (inp / "n.AT2").write_text(GOOD_AT2.replace("NPTS=  8", "NPTS=  9"))
    path = inp / "scene.toml"
    path.write_text(dump_toml(scene_with({"loading": {"kind": "record", "file": "n.AT2"}})))
    proc = fpd(["check", str(path)], cwd=runs)
    assert_input_error(proc, runs, "n.AT2", "NPTS = 9", "8 values follow")


# -- files and options ------------------------------------------------------------
def test_scene_file_not_toml(dirs):
    inp, runs = dirs
    path = inp / "broken.toml"
    path.write_text("[device]\nR1 = = 2\n")
    proc = fpd(["run", str(path), "--out", str(runs / "res")], cwd=runs)
    assert_input_error(proc, runs, str(path), "invalid TOML", "line 2")


def test_scene_file_binary(dirs):
    inp, runs = dirs
    path = inp / "bin.toml"
    path.write_bytes(b"\xff\xfe\x00\x01" * 10)
    proc = fpd(["run", str(path), "--out", str(runs / "res")], cwd=runs)
    assert_input_error(proc, runs, str(path), "UTF-8")


def test_unknown_scene_name_suggests(dirs):
    proc = fpd(["run", "defualt", "--out", str(dirs[1] / "res")], cwd=dirs[1])
    assert_input_error(proc, dirs[1], "defualt", "did you mean default?")


def test_unknown_option(dirs):
    proc = fpd(["run", "--bogus", "--out", str(dirs[1] / "res")], cwd=dirs[1])
    assert_input_error(proc, dirs[1], "--bogus")


def test_out_is_a_file(dirs):
    inp, runs = dirs
    target = runs / "res"
    target.write_text("keep me")
    proc, _ = run_scene(dirs, {}, ("--force",))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert len(proc.stderr.splitlines()) == 1 and str(target) in proc.stderr
    assert sorted(p.name for p in runs.iterdir()) == ["res"] and target.read_text() == "keep me"


def test_out_under_a_file(dirs):
    inp, runs = dirs
    (runs / "afile").write_text("keep me")
    proc, _ = run_scene(dirs, {}, ("--out", str(runs / "afile" / "res")))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    assert len(proc.stderr.splitlines()) == 1 and "afile" in proc.stderr and "--out" in proc.stderr
    assert [p.name for p in runs.iterdir()] == ["afile"] and (runs / "afile").read_text() == "keep me"


def test_grading_that_makes_the_first_element_vanish(tmp_path):
    from fpd.schema.scene import SceneError, load
    with pytest.raises(SceneError, match=r"default.toml: thermal.n_elements = 1000: with grading = 1.05"):
        load("default", ["thermal.n_elements=1000", "thermal.grading=1.05"])


# -- packaged scenes with overrides: refused at validation (schema.load), one line -----------
OVERRIDE_CASES = [
    # (id, scene, overrides, tokens)
    ("tfp-circle-start-past-inner-rims", "tfp-lab", ['loading.waveform="circle"'],
     ["loading.amplitude_m = 0.455", "inner surfaces", "at most 0.09039 m", "without rims"]),
    ("tfp-liner-below-law", "tfp-elcentro", ['friction.liner="ptfe"'],
     ["friction.liner = 'ptfe'", "the preset's friction.mu_static = 0.1", "0.100096", "give friction.mu_static"]),
    ("units-of-a-v2", "ferndale-3c", ['loading.units="g"'], ["loading.units = 'g'", "is not read"]),
    ("units-of-an-AT2-pair-member", "default", ['loading.file_z="records/IELC180.AT2"', 'loading.units="g"'],
     ["loading.units = 'g'", "is not read"]),
    ("flat-planar-names-the-tfp", "flat-lab", ['loading.direction_deg=30'],
     ["loading.direction_deg = 30", "a DFP, an SFP or a TFP"]),
    ("sfp-R2-packaged", "sfp-harmonic", ["device.R2=2.5"], ["device.R2 = 2.5", "R1 = 2 m"]),
    ("machine-frequency-above-two-steps", "tfp-lab", ["loading.frequency_Hz=1e9", "solver.duration=1"],
     ["loading.frequency_Hz = 1e+09", "at most 250 Hz"]),
]


@pytest.mark.parametrize("scene,overrides,tokens", [c[1:] for c in OVERRIDE_CASES],
                         ids=[c[0] for c in OVERRIDE_CASES])
def test_override_catalogue(scene, overrides, tokens):
    msg = refusal(scene, overrides)
    assert msg.startswith(str(ROOT / "scenes" / f"{scene}.toml")), msg
    for tok in tokens:
        assert tok in msg, f"{tok!r} not in {msg!r}"


def test_what_the_new_checks_let_through():
    """The resolved scene of an SFP repeats R2 = R1 (it must load again); units read by a
    two-column y beside an .AT2 x; a circle orbit within the inner rims; two steps a period."""
    from fpd.schema.scene import load, to_toml, validate
    import tomllib
    sc = load("sfp-harmonic")
    assert validate(tomllib.loads(to_toml(sc)), "again.toml").data["device"]["R2"] == sc["device"]["R1"]
    load("tfp-lab", ['loading.waveform="circle"', "loading.amplitude_m=0.09"])
    load("sfp-harmonic", ["loading.frequency_Hz=500", "loading.cycles=1"])


def test_a_failing_file_y_is_named(dirs, fpd_inproc):
    """A y record that cannot be read beside a packaged x record: the key is loading.file_y."""
    inp, runs = dirs
    (inp / "y.AT2").write_bytes(b"")
    proc, _ = run_scene(dirs, {"loading": {"kind": "record", "record": "elcentro-1940", "file_y": "y.AT2"},
                               "solver.duration": 0.01}, (), fpd_inproc)
    assert_input_error(proc, runs, "y.AT2", "empty", "(loading.file_y)")
