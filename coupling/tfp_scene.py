"""Scene validation of the triple friction pendulum (``kind = "TFP"``) and
the flat double bearing (``kind = "flat"``), called from coupling/scene.py.

Same rule as the rest of the scene: every problem is one line naming the file,
the key, the value and what is allowed (SceneError through ``ctx``).
"""
from __future__ import annotations

import math

STEEL = 7850.0
TFP_REQUIRED = ("R1", "R2", "R3", "R4", "slider_diameter", "d1", "d2", "d3", "d4")
PART_SURFACE = {"lower": "S1", "slider_lower": "S2", "slider_upper": "S3", "upper": "S4"}


def tfp_geometry(data):
    from fpd.mechanics.tfp import TFPGeometry
    d = data["device"]
    return TFPGeometry(d["R1"], d["R2"], d["R3"], d["R4"], d["pad_height"], d["pad_diameter"],
                       d["slider_height_lower"], d["slider_height_upper"], d["slider_diameter"],
                       d["d1"], d["d2"], d["d3"], d["d4"], d["pad_mass"], d["slider_mass"],
                       data["superstructure"]["mass"])


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
    from .scene import RECORD_PAIRS

    ld, mech = data["loading"], data["mechanics"]
    why = f"the {device} is planar in this version (bidirectional motion: a DFP or an SFP)"
    if ld["kind"] == "record":
        if ld.get("file_y") is not None:
            ctx.fail("loading.file_y", ld["file_y"], f"is not allowed: {why}")
        if ld.get("component") == "pair":
            ctx.fail("loading.component", "pair", f'must be "a" or "b": {why}')
        if ld.get("record") in RECORD_PAIRS:
            ctx.fail("loading.record", ld["record"], f"must be a single-component record: {why}")
        if ld.get("angle_deg", 0.0) != 0.0:
            ctx.fail("loading.angle_deg", ld["angle_deg"], f"must be 0: {why}")
    if ld["kind"] == "displacement":
        if ld.get("vertical") is not None:
            ctx.fail("loading.vertical", ld["vertical"], f"is a key of the DFP / SFP test machine; the {device}'s "
                     "machine passes the superstructure's weight and inertia down the stack (leave it out)")
        if ld.get("waveform", "sine") != "sine":
            ctx.fail("loading.waveform", ld["waveform"], f'must be "sine": {why}')
        if ld.get("direction_deg", 0.0) != 0.0:
            ctx.fail("loading.direction_deg", ld["direction_deg"], f"must be 0: {why}")
    if mech.get("normal_force") not in (None, "start"):
        ctx.fail("mechanics.normal_force", mech["normal_force"], f'is a key of the DFP steppers: {why}')


def tfp_cross_checks(ctx, data) -> None:
    planar_only(ctx, data, "TFP")
    from fpd.mechanics.tfp import tfp_geometry_errors
    from .scene import check_time_grid

    geom = tfp_geometry(data)
    for key, value, allowed in tfp_geometry_errors(geom):
        ctx.fail(key, value, "must be " + allowed)
    ld, sol = data["loading"], data["solver"]
    if ld["kind"] == "displacement" and ld["amplitude_m"] >= geom.capacity:
        ctx.fail("loading.amplitude_m", ld["amplitude_m"],
                 f"must be < the TFP's displacement capacity {geom.capacity:.4g} m (all four rims)")
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


def flat_cross_checks(ctx, data) -> None:
    planar_only(ctx, data, "flat bearing")
    from .scene import check_time_grid

    ld, sol, dev = data["loading"], data["solver"], data["device"]
    if data["output"]["vtk_every"] > 0:
        ctx.fail("output.vtk_every", data["output"]["vtk_every"], "must be 0 for the flat bearing (no VTK yet)")
    check_time_grid(ctx, ld, sol)
    for side, t in data["thermal"].items():
        if t["model"] != "none" and dev["pad_diameter"] / 2 > t["plate_radius"]:
            ctx.fail("thermal.plate_radius", t["plate_radius"], f"must be >= the pad radius {dev['pad_diameter'] / 2:g} m")
        if t["source"] == "fixed-point" and t["radius_m"] > t["plate_radius"]:
            ctx.fail("thermal.radius_m", t["radius_m"], f"must be <= plate_radius = {t['plate_radius']:g} m")
