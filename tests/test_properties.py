"""Issue 8: property-based tests of the record readers and the scene loader.

Whatever bytes a record file holds, the readers either return a finite,
increasing record or raise RecordError (one line); whatever TOML tree a scene
holds, the loader either returns a scene or raises SceneError (one line).
Never another exception.
"""
from __future__ import annotations

import copy
import math
import tempfile
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import event as _event
from hypothesis.control import currently_in_test_context
from hypothesis import strategies as st

from fpd.coupling.build import build
from fpd.schema.scene import SceneError, apply_overrides, load, loading_length, to_toml, validate
from fpd.loading.ground_motion import RecordError, parse_at2, parse_two_column, read_record

SETTINGS = settings(max_examples=200, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

# -- record readers -------------------------------------------------------------------
NUMBER_TOKENS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(min_value=-10**30, max_value=10**30).map(str),
    st.sampled_from(["nan", "inf", "-inf", "1e999", "-1e999", ".", "-", "1e", "0x10", "1_0", "E", "1,5",
                     ".01000", "-.6403182E-02", "0", "-0.0", "1e-320", "NPTS", "DT", "SEC", "="]),
)
HEADERS = st.one_of(
    st.builds(lambda n, d: f"NPTS= {n}, DT= {d} SEC", NUMBER_TOKENS, NUMBER_TOKENS),
    st.builds(lambda n, d: f"{n} {d} NPTS, DT", NUMBER_TOKENS, NUMBER_TOKENS),
    st.builds(lambda n, d: f"NPTS = {n} , DT = {d} ,", NUMBER_TOKENS, NUMBER_TOKENS),
    st.text(max_size=40),
)
LINES = st.lists(NUMBER_TOKENS, max_size=6).map(" ".join) | st.lists(NUMBER_TOKENS, max_size=3).map(",".join)
AT2_TEXT = st.builds(lambda pre, head, body: "\n".join(pre + [head] + body),
                     st.lists(st.text(max_size=30), max_size=4), HEADERS, st.lists(LINES, max_size=12))
TWO_COL_TEXT = st.lists(LINES | st.text(max_size=20), max_size=15).map("\n".join)
RECORD_BYTES = st.one_of(
    st.binary(max_size=300),
    AT2_TEXT.map(lambda s: s.encode("utf-8", "surrogatepass")),
    TWO_COL_TEXT.map(lambda s: s.encode("utf-8", "surrogatepass")),
    st.text(max_size=200).map(lambda s: s.encode("utf-8", "surrogatepass")),
)


@pytest.fixture(scope="module")
def workdir():
    with tempfile.TemporaryDirectory() as d:
        yield Path(d)


def event(text: str) -> None:
    """Statistics of what the examples reached (pytest --hypothesis-show-statistics)."""
    if currently_in_test_context():
        _event(text)


def _check_record(rec):
    assert len(rec.t) == len(rec.a_g) >= 2
    assert np.all(np.isfinite(rec.t)) and np.all(np.isfinite(rec.a_g))
    assert rec.t[0] == 0.0 and np.all(np.diff(rec.t) > 0)


def _one_line(exc):
    msg = str(exc)
    assert msg and "\n" not in msg and "\r" not in msg, repr(msg)


@SETTINGS
@given(data=RECORD_BYTES, units=st.sampled_from([None, "g", "m/s2"]))
def test_read_record_bytes(workdir, data, units):
    f = workdir / "rec.AT2"
    f.write_bytes(data)
    try:
        rec = read_record(f, units)
    except RecordError as exc:
        _one_line(exc)
        assert str(exc).startswith(str(f))
    else:
        _check_record(rec)


@SETTINGS
@given(text=st.one_of(AT2_TEXT, st.text(max_size=300)))
def test_parse_at2_text(text):
    try:
        rec = parse_at2(text, "x.AT2")
    except RecordError as exc:
        _one_line(exc)
    else:
        _check_record(rec)


@SETTINGS
@given(text=st.one_of(TWO_COL_TEXT, st.text(max_size=300)), units=st.sampled_from(["g", "m/s2"]))
def test_parse_two_column_text(text, units):
    try:
        rec = parse_two_column(text, "x.txt", units)
    except RecordError as exc:
        _one_line(exc)
    else:
        _check_record(rec)


# -- scene loader ----------------------------------------------------------------------
BASE = {
    "name": "prop",
    "device": {"kind": "DFP", "R1": 2.2, "R2": 2.2, "pad_height": 0.10, "pad_diameter": 0.25, "pad_mass": 30.0},
    "superstructure": {"mass": 1.0e5},
    "friction": {"law": "constant", "mu": 0.05},
    "loading": {"kind": "harmonic", "amplitude_m": 0.05, "frequency_Hz": 1.0, "cycles": 1},
    "mechanics": {"model": "seated"},
    "thermal": {"model": "lumped"},
    "solver": {"dt": 1.0e-3},
    "output": {"plots": False},
}
# names the loader knows, so that the trees reach deep into the validation
KNOWN = sorted({"name", "description", "device", "superstructure", "friction", "loading", "mechanics", "thermal",
                "coupling", "solver", "output", "lower", "upper", "kind", "R1", "R2", "pad_height",
                "pad_diameter", "pad_mass", "mass", "law", "mu", "mu0", "T0_C", "slope_per_C", "mu_min",
                "mu_ref", "p_ref_MPa", "a_s_per_m", "use_pressure", "use_temperature", "use_velocity",
                "T_C", "record", "file", "scale", "units", "baseline", "amplitude_m", "frequency_Hz",
                "cycles", "waveform", "flux_W_m2", "duration_s", "plate", "model", "source", "radius_m",
                "T_air_C", "heat_share", "plate_thickness", "plate_radius", "k", "rho", "c", "h_conv",
                "back", "T_back_C", "exchange_area_m2", "n_elements", "grading", "nr", "nz", "scheme",
                "mesh_file", "tol_K", "max_iter", "substeps", "dt", "duration", "vtk_every", "plots",
                "csv_every"})
WORDS = ["DFP", "SFP", "constant", "linear", "kumar2015", "table", "record", "harmonic", "displacement", "heat",
         "two-phase", "seated", "none", "lumped", "fe1d", "axisym", "follow-pad", "fixed-point", "staggered",
         "iterated", "bdf2", "cn", "be", "g", "m/s2", "elcentro-1940", "northridge-1994", "sine", "lower",
         "upper", "both", "convection", "adiabatic", "fixed", "", ".", "..", "/", "~", "nope.AT2"]
KEYS = st.one_of(st.sampled_from(KNOWN), st.text(max_size=8))
SCALARS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e3, max_value=1e3),
    st.sampled_from([0, 1, 2, -1, 0.0, 1e-300, 5e-324, 1e99, 1e300, 1.7976931348623157e308, 0.5, 0.999999,
                     10**400, -(10**30), 2**63, 1e-7, 1e-9]),
    st.integers(),
    st.integers(min_value=-2**70, max_value=2**70),
    st.booleans(),
    st.sampled_from(WORDS),
    st.text(max_size=12),
    st.sampled_from(["\n", "two\nlines", "\x7f", "\x00", "\r", "tab\there", '"', "\\", "é"]),
)
TREES = st.recursive(SCALARS, lambda kids: st.one_of(st.lists(kids, max_size=4),
                                                     st.dictionaries(KEYS, kids, max_size=4)), max_leaves=8)
OVERLAY = st.dictionaries(KEYS, st.one_of(TREES, st.dictionaries(KEYS, TREES, max_size=4)), max_size=4)
# whole tables replaced (a record loading, another friction law...), keys of their own
TABLES = st.fixed_dictionaries({}, optional={
    "loading": st.fixed_dictionaries({"kind": st.sampled_from(["record", "harmonic", "displacement", "heat"])},
                                     optional={k: SCALARS for k in ("record", "file", "units", "scale",
                                                                    "amplitude_m", "frequency_Hz", "cycles",
                                                                    "flux_W_m2", "duration_s", "plate")}),
    "friction": st.fixed_dictionaries({"law": st.sampled_from(["constant", "linear", "kumar2015", "table"])},
                                      optional={k: TREES for k in ("mu", "mu0", "slope_per_C", "mu_ref", "T_C",
                                                                   "lower", "upper", "use_pressure")}),
})


EDGES = st.sampled_from([0, 0.0, -1.0, 1e-300, 1e99, 1e300, float("nan"), float("inf"), 10**400, True, "x", [1.0]])


def _value_of(spec):
    """Values for one schema entry: mostly of the right type, sometimes edges."""
    kind = spec[0]
    if isinstance(kind, tuple):
        right = st.sampled_from(kind)
    elif kind == "float":
        right = st.one_of(st.floats(1e-3, 5.0), st.floats(1e-3, 0.9))
    elif kind == "int":
        right = st.integers(1, 50)
    elif kind == "bool":
        right = st.booleans()
    elif kind == "floats":
        right = st.lists(st.floats(-50.0, 500.0), max_size=4)
    else:
        right = st.sampled_from(WORDS)
    # 1 key in 100 gets an edge value: most scenes then reach the cross checks and the build
    return st.tuples(st.sampled_from([False] * 99 + [True]), right, EDGES).map(lambda x: x[2] if x[0] else x[1])


RECORD_FILES = [str(Path(__file__).resolve().parent.parent / "scenes" / "records" / f)
                for f in ("IELC180.AT2", "Northridge_CDMG24278_090.dat")]


def _table_of(schema: dict, fixed=None):
    from fpd.schema.scene import REQUIRED
    need = {k: _value_of(v) for k, v in schema.items() if v[1] is REQUIRED or k == "R2"}
    return st.fixed_dictionaries((fixed or {}) | need,
                                 optional={k: _value_of(v) for k, v in schema.items() if k not in need})


def _plausible():
    from fpd.schema.scene import FRICTION_KEYS, LOADING_KEYS, TABLES as SCHEMA, THERMAL_KEYS
    loading = st.one_of(*[_table_of(keys, {"kind": st.just(kind)}) for kind, keys in LOADING_KEYS.items()
                          if kind != "record"],
                        _table_of({k: v for k, v in LOADING_KEYS["record"].items() if k not in ("record", "file")},
                                  {"kind": st.just("record"),
                                   "file": st.sampled_from(RECORD_FILES + ["nope.AT2", ""])}),
                        _table_of({k: v for k, v in LOADING_KEYS["record"].items() if k not in ("record", "file")},
                                  {"kind": st.just("record"),
                                   "record": st.sampled_from(["elcentro-1940", "northridge-1994", "x"])}))
    friction = st.one_of(*[_table_of(keys, {"law": st.just(law)}) for law, keys in FRICTION_KEYS.items()])
    return st.fixed_dictionaries(
        {"loading": loading, "friction": friction, "device": _table_of(SCHEMA["device"]),
         "superstructure": _table_of(SCHEMA["superstructure"])},
        optional={"thermal": _table_of(THERMAL_KEYS),
                  **{t: _table_of(sch) for t, sch in SCHEMA.items() if t not in ("device", "superstructure")}})


def merge(base: dict, over: dict) -> dict:
    out = copy.deepcopy(base)
    for k, v in over.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = merge(out[k], v)
        else:
            out[k] = v
    return out


def _validate(raw, workdir):
    try:
        scene = validate(raw, str(workdir / "scene.toml"))
    except SceneError as exc:
        _one_line(exc)
        event("refused: " + str(exc).split(": ")[-1][:20])
        return None
    event("valid " + scene.data["loading"]["kind"])
    # the resolved scene written into every results folder reads back to the same scene
    again = validate(tomllib.loads(to_toml(scene)), str(workdir / "scene.toml"))
    assert again.data["solver"] == scene.data["solver"]
    assert again.data["description"] == scene.data["description"]
    # and what the run builds from it raises nothing but the input error either (models of
    # this branch only, and short runs: the property is about input, not run time)
    d = scene.data
    length = d["solver"].get("duration") or loading_length(d["loading"]) or 40.0
    if (length / d["solver"]["dt"] < 2e5
            and (d["mechanics"]["model"] == "seated" or d["loading"]["kind"] in ("heat", "displacement"))
            and all(d["thermal"][p]["model"] in ("none", "lumped") for p in ("lower", "upper"))):
        try:
            build(scene)
            event("built")
        except SceneError as exc:
            _one_line(exc)
    return scene


def test_base_scene_valid(workdir):
    assert _validate(BASE, workdir) is not None


@SETTINGS
@given(over=OVERLAY)
@example(over={"friction": {"law": ["constant"]}})          # once: 'unhashable type' tracebacks
@example(over={"loading": {"kind": ["record"]}})
@example(over={"\r": {}})                                  # once: a message on two lines
@example(over={"description": "two\nlines"})               # once: a scene.toml that did not read back
@example(over={"device": {"R1": 10**400}})                 # once: OverflowError
@example(over={"device": {"R1": 1e300, "R2": 1e300}})      # once: OverflowError in the fit checks
@example(over={"solver": {"dt": 1e-300}})                  # once: 1e300 steps allocated
def test_scene_trees(workdir, over):
    _validate(merge(BASE, over), workdir)


@SETTINGS
@given(tables=TABLES, over=OVERLAY)
def test_scene_tables(workdir, tables, over):
    _validate(merge({k: v for k, v in BASE.items() if k not in tables} | tables, over), workdir)


@SETTINGS
@given(tables=_plausible())
def test_scene_plausible(workdir, tables):
    """Scenes of the right shape with values near and beyond the limits: these
    reach the cross checks and the build."""
    _validate({"name": "p"} | tables, workdir)


@SETTINGS
@given(table=st.sampled_from(["device", "superstructure", "friction", "loading", "thermal", "solver",
                              "coupling", "output", "mechanics"]),
       key=st.sampled_from(KNOWN), value=TREES)
def test_scene_one_key(workdir, table, key, value):
    """One key of one table set to anything: the commonest typo."""
    _validate(merge(BASE, {table: {key: value}}), workdir)


@SETTINGS
@given(tree=TREES)
def test_scene_whole_tree(workdir, tree):
    _validate(tree if isinstance(tree, dict) else {"name": tree}, workdir)


@SETTINGS
@given(key=st.text(max_size=20), value=st.text(max_size=20))
def test_set_overrides(workdir, key, value):
    try:
        raw = apply_overrides(BASE, [f"{key}={value}"])
    except SceneError as exc:
        _one_line(exc)
        return
    _validate(raw, workdir)


TOML_TEXT = st.lists(st.one_of(
    st.builds(lambda k, v: f"{k} = {v}", st.sampled_from(KNOWN), st.sampled_from(
        ["1", "-1", "0.5", "1e999", "nan", "inf", "true", '"x"', "[1, 2]", "[", "{a = 1}", '"""a\nb"""', "'lit'",
         "1979-05-27", "0x1f", "1_000", "[[1], [2]]", "=", ""])),
    st.builds(lambda t: f"[{t}]", st.sampled_from(KNOWN + ["friction.lower", "thermal.upper", "a.b.c", ""])),
    st.text(max_size=20)), max_size=12).map("\n".join)


@SETTINGS
@given(data=st.one_of(st.binary(max_size=200), TOML_TEXT.map(str.encode),
                      st.text(max_size=200).map(lambda s: s.encode("utf-8", "surrogatepass"))))
@example(data=b"a = " + b"[" * 5000)              # once: RecursionError from tomllib
def test_scene_file_bytes(workdir, data):
    """A scene file holding anything: only SceneError, one line, naming the file."""
    f = workdir / "scene.toml"
    f.write_bytes(data)
    try:
        load(str(f))
    except SceneError as exc:
        _one_line(exc)
        assert str(exc).startswith(str(f))
