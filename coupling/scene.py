"""Scene files (TOML): loading, defaults, validation, ``--set`` overrides.

Every problem is reported once, at load, as a ``SceneError`` whose text is one
line naming the file, the dotted key, the value and what is allowed
(interface.md). Nothing downstream re-validates input.
"""
from __future__ import annotations

import copy
import difflib
import json
import math
import os
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

SCENES_DIR = Path(__file__).resolve().parent.parent / "scenes"
RECORDS = {
    "elcentro-1940": "IELC180.AT2",
    "northridge-1994": "Northridge_CDMG24278_090.dat",
}


class SceneError(ValueError):
    """Bad input: the message is the one line shown to the user."""

    def __init__(self, message: str = ""):
        # one line whatever the user typed: control characters shown escaped
        super().__init__("".join(c if c.isprintable() else repr(c)[1:-1] for c in str(message)))


# -- schema -------------------------------------------------------------------
# Each key: (kind, default, check). kind: "float", "int", "bool", "str",
# "floats" (list of numbers) or a tuple of allowed strings. default REQUIRED
# means the key must be given; None means optional with no value.
REQUIRED = object()
# beyond these, squares and products overflow (floats) or nothing fits in memory (ints, steps)
MAX_MAGNITUDE, MAX_INT, MAX_STEPS = 1e100, 10**9, 2 * 10**7


def _pos(x):
    return None if x > 0 else "must be > 0"


def _nonneg(x):
    return None if x >= 0 else "must be >= 0"


def _mu(x):
    return None if 0 <= x < 1 else "must be in [0, 1)"


def _share(x):
    return None if 0 <= x <= 1 else "must be in [0, 1]"


def _atleast(n):
    return lambda x: None if x >= n else f"must be >= {n}"


def _temp(x):
    return None if -273.15 < x < 5000 else "must be a temperature in degC above -273.15"


def _law_keys(law: str, checks: dict, required=()) -> dict:
    """A law's keys with the defaults of its class in mechanics.friction
    (one source of truth; a field without a default, or named in
    ``required`` (a scene must state it), is REQUIRED)."""
    from dataclasses import MISSING, fields

    from fpd.mechanics.friction import LAWS

    out = {}
    for f in fields(LAWS[law]):
        kind, check = checks[f.name]
        out[f.name] = (kind, REQUIRED if f.default is MISSING or f.name in required else f.default, check)
    return out


FRICTION_KEYS = {
    "constant": _law_keys("constant", {"mu": ("float", _mu)}),
    "linear": _law_keys("linear", {"mu0": ("float", _mu), "T0_C": ("float", _temp),
                                   "slope_per_C": ("float", None), "mu_min": ("float", _mu)},
                        required=("slope_per_C",)),
    "kumar2015": _law_keys("kumar2015", {"mu_ref": ("float", _mu), "p_ref_MPa": ("float", _pos),
                                         "a_s_per_m": ("float", _pos), "use_pressure": ("bool", None),
                                         "use_temperature": ("bool", None), "use_velocity": ("bool", None)}),
    "table": _law_keys("table", {"T_C": ("floats", None), "mu": ("floats", None)}),
}

def _plate_default(name):
    """Defaults of the [thermal] keys are PlateParams' (one source of truth)."""
    from fpd.thermal.params import PlateParams
    return PlateParams.__dataclass_fields__[name].default


THERMAL_KEYS = {name: (kind, _plate_default(name), check) for name, kind, check in (
    ("model", ("none", "lumped", "fe1d", "axisym"), None),
    ("source", ("follow-pad", "fixed-point"), None),
    ("radius_m", "float", _nonneg),
    ("T0_C", "float", _temp),
    ("T_air_C", "float", _temp),
    ("heat_share", "float", _share),
    ("plate_thickness", "float", _pos),
    ("plate_radius", "float", _pos),
    ("k", "float", _pos),
    ("rho", "float", _pos),
    ("c", "float", _pos),
    ("h_conv", "float", _nonneg),
    ("back", ("convection", "adiabatic", "fixed"), None),
    ("T_back_C", "float", _temp),
    ("exchange_area_m2", "float", _nonneg),
    ("n_elements", "int", _atleast(2)),
    ("grading", "float", _atleast(1.0)),
    ("nr", "int", _atleast(2)),
    ("nz", "int", _atleast(2)),
    ("scheme", ("bdf2", "cn", "be"), None),
    ("mesh_file", "str", None),
)}

LOADING_KEYS = {
    "record": {"record": ("str", None, None), "file": ("str", None, None),
               "scale": ("float", 1.0, lambda x: None if x != 0 and math.isfinite(x) else "must be a non-zero number"),
               "units": (("g", "m/s2"), None, None), "baseline": ("bool", True, None)},
    "harmonic": {"amplitude_m": ("float", REQUIRED, _pos), "frequency_Hz": ("float", REQUIRED, _pos),
                 "cycles": ("float", REQUIRED, _pos)},
    "displacement": {"waveform": (("sine",), "sine", None), "amplitude_m": ("float", REQUIRED, _pos),
                     "frequency_Hz": ("float", REQUIRED, _pos), "cycles": ("float", REQUIRED, _pos)},
    "pulse": {"shape": (("step", "cosine", "sine"), "cosine", None),
              "velocity_mps": ("float", REQUIRED, lambda x: None if x != 0 else "must be non-zero"),
              "period_s": ("float", 1.0, _pos), "t0_s": ("float", 0.5, _nonneg),
              "duration_s": ("float", None, _pos)},
    "heat": {"flux_W_m2": ("float", REQUIRED, _nonneg), "duration_s": ("float", REQUIRED, _pos),
             "plate": (("lower", "upper", "both"), "lower", None),
             "reference": (("none", "halfspace", "slab", "disk"), "none", None)},
}

TABLES = {
    "device": {
        "kind": (("DFP", "SFP"), "DFP", None),
        "R1": ("float", REQUIRED, _pos),
        "R2": ("float", None, _pos),
        "pad_height": ("float", REQUIRED, _pos),
        "pad_diameter": ("float", REQUIRED, _pos),
        "pad_mass": ("float", None, _pos),
    },
    "superstructure": {"mass": ("float", REQUIRED, _pos)},
    "mechanics": {"model": (("two-phase", "seated"), "two-phase", None)},
    "coupling": {"scheme": (("staggered", "iterated"), "staggered", None),
                 "tol_K": ("float", 1e-3, _pos), "max_iter": ("int", 20, _atleast(1)),
                 "substeps": ("int", 1, _atleast(1))},
    "solver": {"dt": ("float", 1e-3, _pos), "duration": ("float", None, _pos)},
    "output": {"vtk_every": ("int", 0, _nonneg), "plots": ("bool", True, None),
               "csv_every": ("int", 1, _atleast(1))},
}
TOP_KEYS = {"name": "str", "description": "str"}
ALL_TABLES = set(TABLES) | {"friction", "loading", "thermal"}


@dataclass
class Scene:
    """A validated scene: ``data`` is the fully resolved nested dict."""

    path: str
    data: dict

    @property
    def name(self) -> str:
        return self.data["name"]

    def __getitem__(self, key):
        return self.data[key]

    def thermal(self, plate: str) -> dict:
        """Resolved [thermal] keys of one plate ('lower' or 'upper')."""
        return self.data["thermal"][plate]

    def friction(self, interface: str) -> dict:
        return self.data["friction"][interface]

    def needs_heat(self) -> bool:
        return any(self.thermal(p)["model"] != "none" for p in ("lower", "upper"))


# -- errors -------------------------------------------------------------------
def _fmt(v) -> str:
    if isinstance(v, str):
        return repr(v)
    if isinstance(v, float):
        return f"{v:g}"
    if isinstance(v, dict):
        return "(a table)"
    s = repr(v)
    return s if len(s) < 60 else s[:57] + "..."


class _Ctx:
    def __init__(self, path: str):
        self.path = path

    def fail(self, key: str, value, allowed: str):
        raise SceneError(f"{self.path}: {key} = {_fmt(value)}: {allowed}")

    def missing(self, key: str, what: str):
        raise SceneError(f"{self.path}: {key} is missing: {what}")

    def unknown(self, key: str, value, valid):
        near = difflib.get_close_matches(key.rsplit(".", 1)[-1], list(valid), n=1, cutoff=0.5)
        prefix = key.rsplit(".", 1)[0] + "." if "." in key else ""
        hint = f"; did you mean {prefix}{near[0]}?" if near else \
            f"; valid keys here: {', '.join(sorted(valid))}"
        raise SceneError(f"{self.path}: {key} = {_fmt(value)}: unknown key{hint}")


def _check_value(ctx: _Ctx, key: str, value, spec):
    kind, _default, check = spec
    if isinstance(kind, tuple):
        if not isinstance(value, str) or value not in kind:
            ctx.fail(key, value, "must be one of " + ", ".join(f'"{k}"' for k in kind))
        return value
    if kind == "float":
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            ctx.fail(key, value, "must be a number")
        if not (isinstance(value, float) and not math.isfinite(value)) and not abs(value) <= MAX_MAGNITUDE:
            ctx.fail(key, value, f"is out of range: |value| must be <= {MAX_MAGNITUDE:g}")
        value = float(value)
        if not math.isfinite(value):
            ctx.fail(key, value, "must be finite")
    elif kind == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            if isinstance(value, float) and value.is_integer():
                value = int(value)
            else:
                ctx.fail(key, value, "must be a whole number")
        if abs(value) > MAX_INT:
            ctx.fail(key, value, f"is out of range: must be <= {MAX_INT:g}")
    elif kind == "bool":
        if not isinstance(value, bool):
            ctx.fail(key, value, "must be true or false")
    elif kind == "str":
        if not isinstance(value, str):
            ctx.fail(key, value, "must be a string")
    elif kind == "floats":
        if not isinstance(value, list) or not value or not all(
                isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in value):
            ctx.fail(key, value, "must be a non-empty list of finite numbers")
        value = [float(x) for x in value]
    if check is not None:
        msg = check(value)
        if msg:
            ctx.fail(key, value, msg)
    return value


def _table(ctx: _Ctx, name: str, given, schema: dict, extra_ok=()) -> dict:
    if given is None:
        given = {}
    if not isinstance(given, dict):
        ctx.fail(name, given, "must be a table")
    out = {}
    for key, value in given.items():
        if key in extra_ok:
            continue
        if key not in schema:
            ctx.unknown(f"{name}.{key}", value, list(schema) + list(extra_ok))
        out[key] = _check_value(ctx, f"{name}.{key}", value, schema[key])
    for key, spec in schema.items():
        if key not in out:
            if spec[1] is REQUIRED:
                ctx.missing(f"{name}.{key}", _describe(spec))
            if spec[1] is not None:
                out[key] = copy.copy(spec[1])
    return out


def _describe(spec) -> str:
    kind = spec[0]
    if isinstance(kind, tuple):
        return "give one of " + ", ".join(f'"{k}"' for k in kind)
    return {"float": "give a number", "int": "give a whole number", "bool": "give true or false",
            "str": "give a string", "floats": "give a list of numbers"}[kind]


# -- the sections with structure -------------------------------------------------
def _friction(ctx: _Ctx, given) -> dict:
    if given is None:
        ctx.missing("friction", "the scene needs a [friction] table (law and its keys)")
    if not isinstance(given, dict):
        ctx.fail("friction", given, "must be a table")
    base = {k: v for k, v in given.items() if k not in ("lower", "upper")}
    out = {}
    for side in ("lower", "upper"):
        over = given.get(side, {})
        if not isinstance(over, dict):
            ctx.fail(f"friction.{side}", over, "must be a table")
        merged = dict(base)
        merged.update(over)
        where = f"friction.{side}" if over else "friction"
        law = merged.get("law", "constant")
        if not isinstance(law, str) or law not in FRICTION_KEYS:
            ctx.fail(f"{where}.law", law, "must be one of " + ", ".join(f'"{k}"' for k in FRICTION_KEYS))
        schema = FRICTION_KEYS[law]
        # a key of the base table that belongs to another law is an error
        # only if the override does not replace the law
        for key, value in merged.items():
            if key != "law" and key not in schema:
                owner = "friction" if key in base and key not in over else where
                other = [n for n, s in FRICTION_KEYS.items() if key in s]
                if other:
                    ctx.fail(f"{owner}.{key}", value, f'belongs to law "{other[0]}", not "{law}"')
                ctx.unknown(f"{owner}.{key}", value, list(schema) + ["law", "lower", "upper"])
        res = _table(ctx, where, {k: v for k, v in merged.items() if k != "law"}, schema)
        if law == "table":
            T, mu = res["T_C"], res["mu"]
            if len(T) != len(mu):
                ctx.fail(f"{where}.mu", mu, f"must have as many entries as T_C ({len(T)})")
            if any(b <= a for a, b in zip(T, T[1:])):
                ctx.fail(f"{where}.T_C", T, "must increase strictly")
            for m in mu:
                if not 0 <= m < 1:
                    ctx.fail(f"{where}.mu", mu, "every entry must be in [0, 1)")
        res["law"] = law
        out[side] = res
    return out


def _thermal(ctx: _Ctx, given) -> dict:
    given = {} if given is None else given
    if not isinstance(given, dict):
        ctx.fail("thermal", given, "must be a table")
    base = {k: v for k, v in given.items() if k not in ("lower", "upper")}
    base_res = _table(ctx, "thermal", base, THERMAL_KEYS)
    out = {}
    for side in ("lower", "upper"):
        over = given.get(side, {})
        res = dict(base_res)
        res.update(_table(ctx, f"thermal.{side}", over, {k: (s[0], None, s[2]) for k, s in THERMAL_KEYS.items()}))
        out[side] = res
    for side in ("lower", "upper"):
        t = out[side]
        where = f"thermal.{side}" if "mesh_file" in given.get(side, {}) else "thermal"
        if t["model"] == "axisym" and t["mesh_file"]:
            p = Path(t["mesh_file"])
            if not p.is_absolute():
                p = Path(ctx.path).parent / p
            if not p.is_file():
                ctx.fail(f"{where}.mesh_file", t["mesh_file"], "file not found")
            t["mesh_file"] = str(p)
    return out


def _loading(ctx: _Ctx, given, scene_dir: Path) -> dict:
    if given is None:
        ctx.missing("loading", "the scene needs a [loading] table with kind = "
                    + ", ".join(f'"{k}"' for k in LOADING_KEYS))
    if not isinstance(given, dict):
        ctx.fail("loading", given, "must be a table")
    if "kind" not in given:
        ctx.missing("loading.kind", "give one of " + ", ".join(f'"{k}"' for k in LOADING_KEYS))
    kind = given["kind"]
    if not isinstance(kind, str) or kind not in LOADING_KEYS:
        ctx.fail("loading.kind", kind, "must be one of " + ", ".join(f'"{k}"' for k in LOADING_KEYS))
    res = _table(ctx, "loading", {k: v for k, v in given.items() if k != "kind"}, LOADING_KEYS[kind])
    res["kind"] = kind
    if kind == "record":
        has_r, has_f = "record" in res, "file" in res
        if has_r == has_f:
            ctx.missing("loading.record", 'give exactly one of loading.record (packaged: '
                        + ", ".join(f'"{r}"' for r in RECORDS) + ") or loading.file (a path)")
        if has_r:
            if res["record"] not in RECORDS:
                ctx.fail("loading.record", res["record"], "must be one of "
                         + ", ".join(f'"{r}"' for r in RECORDS) + " (or give loading.file)")
            res["path"] = str(SCENES_DIR / "records" / RECORDS[res["record"]])
        else:
            p = Path(os.path.expanduser(res["file"]))
            if not p.is_absolute():
                cand = scene_dir / p
                p = cand if cand.exists() or not p.exists() else p.resolve()
            if not p.exists():
                ctx.fail("loading.file", res["file"], f"file not found (looked in {p.parent})")
            res["path"] = str(p.resolve())
    return res


def validate(raw: dict, path: str = "<scene>") -> Scene:
    """Validate a parsed TOML tree and fill defaults; raise SceneError."""
    ctx = _Ctx(path)
    if not isinstance(raw, dict):
        raise SceneError(f"{path}: the scene must be a TOML table")
    for key, value in raw.items():
        if key in TOP_KEYS:
            if not isinstance(value, str):
                ctx.fail(key, value, "must be a string")
        elif key not in ALL_TABLES:
            ctx.unknown(key, value, list(ALL_TABLES) + list(TOP_KEYS))
    scene_dir = Path(path).parent if path and not path.startswith("<") else Path.cwd()
    data = {"name": raw.get("name") or Path(path).stem or "scene",
            "description": raw.get("description", "")}
    if not re.fullmatch(r"[A-Za-z0-9_.+-]+", data["name"]):
        ctx.fail("name", data["name"], "must be letters, digits, '_', '-', '.', '+' (it names the results folder)")
    data["loading"] = _loading(ctx, raw.get("loading"), scene_dir)
    heat_only = data["loading"]["kind"] == "heat"
    for table, schema in TABLES.items():
        given = raw.get(table)
        if heat_only and table in ("device", "superstructure") and given is None:
            # the thermal-only loading ignores the device; a nominal DFP fills the tables
            given = ({"R1": 2.2, "R2": 2.2, "pad_height": 0.1, "pad_diameter": 0.25} if table == "device"
                     else {"mass": 1.0})
        data[table] = _table(ctx, table, given, schema)
    dev = data["device"]
    if dev["kind"] == "DFP":
        if "R2" not in dev:
            ctx.missing("device.R2", "a DFP needs the upper radius R2 (m)")
    else:
        dev.setdefault("R2", dev["R1"])
    if "pad_mass" not in dev:
        # a solid steel cylinder of the pad's size
        dev["pad_mass"] = 7850.0 * math.pi * (dev["pad_diameter"] / 2) ** 2 * dev["pad_height"]
    if heat_only and raw.get("friction") is None:
        data["friction"] = _friction(ctx, {"law": "constant", "mu": 0.0})
    else:
        data["friction"] = _friction(ctx, raw.get("friction"))
    data["thermal"] = _thermal(ctx, raw.get("thermal"))
    _cross_checks(ctx, data)
    return Scene(path=path, data=data)


def _cross_checks(ctx: _Ctx, data: dict):
    from fpd.mechanics.geometry import DeviceGeometry, geometry_errors

    dev = data["device"]
    geom = DeviceGeometry(dev["kind"], dev["R1"], dev["R2"], dev["pad_height"], dev["pad_diameter"],
                          dev["pad_mass"], data["superstructure"]["mass"])
    for key, value, allowed in geometry_errors(geom):
        ctx.fail(key, value, "must be " + allowed)
    if dev["kind"] == "SFP" and data["mechanics"]["model"] == "two-phase" and data["loading"]["kind"] != "heat":
        ctx.fail("mechanics.model", "two-phase", 'the SFP has the seated model only: use "seated"')
    ld, sol = data["loading"], data["solver"]
    if ld["kind"] == "displacement":
        if ld["amplitude_m"] >= geom.L:
            ctx.fail("loading.amplitude_m", ld["amplitude_m"], f"must be < L = {geom.L:.4g} m")
        if data["mechanics"]["model"] == "two-phase":
            # the test machine holds the superstructure: the seated model describes it
            data["mechanics"]["model"] = "seated"
    if "duration" in sol and sol["dt"] > sol["duration"]:
        ctx.fail("solver.dt", sol["dt"], f"must not exceed solver.duration = {sol['duration']:g} s")
    length = loading_length(ld)
    if length is not None and "duration" not in sol and sol["dt"] > length:
        ctx.fail("solver.dt", sol["dt"], f"must not exceed the loading's length {length:g} s")
    length = sol.get("duration", length)
    if length is not None:
        check_steps(ctx.path, sol["dt"], length)
    for side in ("lower", "upper"):
        t = data["thermal"][side]
        n_key = {"fe1d": "n_elements", "axisym": "nz"}.get(t["model"])
        if n_key and t["grading"] > 1.0:
            n, g = t[n_key], t["grading"]
            first = (g - 1.0) / (g ** min(n, 10000) - 1.0) if n * math.log(g) < 700 else 0.0
            if first < 1e-9:
                ctx.fail(f"thermal.{n_key}", n, f"with grading = {g:g} the first element is {first:.1e} of the "
                         "thickness (< 1e-9): lower the grading or the element count")
        if t["source"] == "fixed-point" and t["radius_m"] > t["plate_radius"]:
            ctx.fail("thermal.radius_m", t["radius_m"], f"must be <= plate_radius = {t['plate_radius']:g} m")
        if dev["pad_diameter"] / 2 > t["plate_radius"] and t["model"] != "none":
            ctx.fail("thermal.plate_radius", t["plate_radius"],
                     f"must be >= the pad radius {dev['pad_diameter'] / 2:g} m")


def check_steps(path: str, dt: float, length: float) -> None:
    """A dt so small that the run cannot fit in memory is an input error (a typo, most often)."""
    if length / dt > MAX_STEPS:
        raise SceneError(f"{path}: solver.dt = {dt:g}: gives {length / dt:.3g} steps over {length:g} s; "
                         f"at most {MAX_STEPS:.0e} allowed (raise solver.dt or set a shorter solver.duration)")


def loading_length(ld: dict):
    """Natural length of a loading (s), or None when only the record knows it."""
    if ld["kind"] in ("harmonic", "displacement"):
        return ld["cycles"] / ld["frequency_Hz"]
    if ld["kind"] == "heat":
        return ld["duration_s"]
    if ld["kind"] == "pulse":
        return ld.get("duration_s") or ld["t0_s"] + ld["period_s"] + 10.0
    return None


# -- files and overrides ------------------------------------------------------------
def resolve_path(scene: str | None) -> Path:
    """A scene argument: a path to a TOML file, or a packaged scene name."""
    if scene is None:
        return SCENES_DIR / "default.toml"
    p = Path(scene)
    if p.is_file():
        return p
    cand = SCENES_DIR / (scene if scene.endswith(".toml") else scene + ".toml")
    if cand.is_file() and os.sep not in scene:
        return cand
    names = packaged_scenes()
    near = difflib.get_close_matches(scene, names, n=1)
    hint = f"; did you mean {near[0]}?" if near else f"; packaged scenes: {', '.join(names)}"
    raise SceneError(f"{scene}: no such scene file or packaged scene{hint}")


def packaged_scenes() -> list[str]:
    return sorted(p.stem for p in SCENES_DIR.glob("*.toml"))


def parse_override(text: str) -> tuple[list[str], object]:
    """``KEY=VALUE`` from --set: dotted key, TOML-typed value (bare words are strings)."""
    if "=" not in text:
        raise SceneError(f"--set {text}: expected KEY=VALUE (e.g. --set friction.mu=0.08)")
    key, value = text.split("=", 1)
    key = key.strip()
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*", key):
        raise SceneError(f"--set {text}: '{key}' is not a dotted key (e.g. solver.dt)")
    value = value.strip()
    try:
        parsed = tomllib.loads(f"v = {value}")["v"]
    except tomllib.TOMLDecodeError:
        if re.fullmatch(r"[A-Za-z][A-Za-z0-9_+./-]*", value) and not re.search(r"\d", value[:1]):
            parsed = value
        else:
            raise SceneError(f"--set {key}={value}: '{value}' is not a TOML value "
                             "(numbers like 5e-4, true/false, \"strings\", [lists])") from None
    return key.split("."), parsed


def apply_overrides(raw: dict, overrides: list[str]) -> dict:
    raw = copy.deepcopy(raw)
    for text in overrides or []:
        keys, value = parse_override(text)
        node = raw
        for k in keys[:-1]:
            nxt = node.setdefault(k, {})
            if not isinstance(nxt, dict):
                raise SceneError(f"--set {text}: '{k}' is not a table")
            node = nxt
        node[keys[-1]] = value
    return raw


def read_toml(path: Path) -> dict:
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise SceneError(f"{path}: cannot be read ({exc.strerror})") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise SceneError(f"{path}: not a UTF-8 text file (a scene is TOML)") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{path}: invalid TOML: {exc}") from None
    except RecursionError:
        raise SceneError(f"{path}: invalid TOML: arrays or tables nested too deeply") from None


def load(scene: str | None = None, overrides: list[str] | None = None) -> Scene:
    """Resolve, read, override and validate a scene."""
    path = resolve_path(scene)
    raw = read_toml(path)
    try:
        raw = apply_overrides(raw, overrides or [])
    except SceneError as exc:       # name the scene the override was meant for
        raise SceneError(f"{path}: {exc}") from None
    if "name" not in raw:
        raw["name"] = path.stem
    return validate(raw, str(path))


# -- writing the resolved scene -------------------------------------------------------
def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):   # a TOML basic string: JSON's escapes are TOML's, and DEL must be escaped too
        return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(v)


def to_toml(scene: Scene) -> str:
    """The fully resolved scene as TOML (every key explicit, both plates and
    interfaces spelled out), so that a run can be repeated exactly."""
    d = scene.data
    lines = [f"name = {_toml_value(d['name'])}"]
    if d.get("description"):
        lines.append(f"description = {_toml_value(d['description'])}")
    for table in ("device", "superstructure", "friction", "loading", "mechanics", "thermal",
                  "coupling", "solver", "output"):
        body = d[table]
        if table in ("friction", "thermal"):
            for side in ("lower", "upper"):
                lines.append(f"\n[{table}.{side}]")
                lines += [f"{k} = {_toml_value(v)}" for k, v in body[side].items()]
            continue
        lines.append(f"\n[{table}]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in body.items() if k != "path"]
    return "\n".join(lines) + "\n"
