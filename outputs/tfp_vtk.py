"""VTK of the TFP: ``vtk/device.pvd``, the five bodies (and the superstructure
block) as moving polygons in the x-z plane (y = 0), each frame at the pose of
the exact rigid model (mechanics/tfp.py): lower plate (band under S1, moving
with the ground), lower slider plate (convex R1 below, concave S2 above),
pad (convex R2 and R3), upper slider plate (concave S3 below, convex R4
above), upper plate (band over S4), superstructure. Cell data per polygon:
``body`` (0..5 in that order), ``T_C`` (T1 on the lower plate, T2 on the lower
slider, T3 on the upper slider, T4 on the upper plate) and ``mu`` (the friction
of the surface that heats that part), the values of timeseries.csv at the
frame's step. Plate temperature fields: ``<part>_plate.pvd`` for the parts
whose model has one (fe1d, axisym, fe3d), placed in the device's coordinates
so that they overlay device.pvd (``place_part_field``: each part's field
wrapped onto its own sliding surface, at that body's pose), with point data
``depth_m`` (below the sliding face); fe3d parts on the grid of
``output.vtk_fe3d``. The series is bounded before it is written
(outputs/vtk_budget.py).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .hottest import TFP_SIDES, HottestFields
from .placement import local_points, mirror_section
from fpd.schema.scene import TFP_PARTS
from .vtk_budget import FieldView, check_budget, depth_of, put

BODIES = ("lower_plate", "lower_slider", "pad", "upper_slider", "upper_plate", "superstructure")
N_ARC = 32


def _e(x):
    return np.array([-math.sin(x), math.cos(x)])


def _world(O, angle, body):
    c, s = math.cos(angle), math.sin(angle)
    return np.column_stack((O[0] + c * body[:, 0] - s * body[:, 1], O[1] + s * body[:, 0] + c * body[:, 1]))


def _band(C, R, half_width, thickness, below: bool, n=N_ARC):
    """A plate: a band of ``thickness`` behind the arc of radius R about C
    (below: a concave-up face, the band under it; else a concave-down face)."""
    w = min(half_width, 0.95 * R)
    phi = np.linspace(-math.asin(w / R), math.asin(w / R), n)
    sg = -1.0 if below else 1.0
    inner = np.column_stack((C[0] + R * np.sin(phi), C[1] + sg * R * np.cos(phi)))
    outer = np.column_stack((C[0] + (R + thickness) * np.sin(phi[::-1]), C[1] + sg * (R + thickness) * np.cos(phi[::-1])))
    return np.vstack((inner, outer))


def surface_centres(g, xg: float, phi: float, alpha: float):
    """Centres (x, z) of S1..S4 at the pose (xg, phi, alpha)."""
    C1 = np.array([xg, g.R1])
    C2 = C1 - g.l1 * _e(phi)
    C3 = C2 - g.Li * _e(phi + alpha)
    C4 = C3 - g.l4 * _e(phi)
    return C1, C2, C3, C4


def tfp_polygons(g, plate_params, xg: float, phi: float, alpha: float, n: int = N_ARC) -> list:
    """The six polygons (BODIES order), each a (k, 2) array of (x, z)."""
    psi = phi + alpha
    C1, C2, C3, C4 = surface_centres(g, xg, phi, alpha)
    rs, rp = 0.5 * g.slider_diameter, 0.5 * g.pad_diameter
    tl, tu, hp = g.slider_height_lower, g.slider_height_upper, g.pad_height
    xs = np.linspace(-rs, rs, n)
    xp = np.linspace(-rp, rp, n)
    lower = _band(C1, g.R1, max(plate_params[0].plate_radius, 1.2 * rs), plate_params[0].plate_thickness, True, n)
    # lower slider in its frame: convex R1 below (centre (0, R1)), concave S2 above (centre (0, tl + R2))
    sl = np.vstack((np.column_stack((xs, g.R1 - np.sqrt(g.R1 ** 2 - xs ** 2))),
                    np.column_stack((xs[::-1], tl + g.R2 - np.sqrt(g.R2 ** 2 - xs[::-1] ** 2)))))
    slider_lo = _world(C1 - g.R1 * _e(phi), phi, sl)
    pad = np.vstack((np.column_stack((xp, g.R2 - np.sqrt(g.R2 ** 2 - xp ** 2))),
                     np.column_stack((xp[::-1], hp - g.R3 + np.sqrt(g.R3 ** 2 - xp[::-1] ** 2)))))
    pad = _world(C2 - g.R2 * _e(psi), psi, pad)
    # upper slider: origin at its lower apex (C3 + R3 e), concave S3 below, convex R4 above (centre C4)
    su = np.vstack((np.column_stack((xs, -g.R3 + np.sqrt(g.R3 ** 2 - xs ** 2))),
                    np.column_stack((xs[::-1], tu - g.R4 + np.sqrt(g.R4 ** 2 - xs[::-1] ** 2)))))
    slider_up = _world(C3 + g.R3 * _e(phi), phi, su)
    upper = _band(C4, g.R4, max(plate_params[3].plate_radius, 1.2 * rs), plate_params[3].plate_thickness, False, n)
    top = C4[1] + g.R4 + plate_params[3].plate_thickness
    ws = 1.25 * max(plate_params[3].plate_radius, 1.2 * rs)
    block = np.array([[C4[0] - ws, top], [C4[0] + ws, top], [C4[0] + ws, top + 0.4 * ws], [C4[0] - ws, top + 0.4 * ws]])
    return [lower, slider_lo, pad, slider_up, upper, block]


def place_part_field(i: int, fld, g, params, vals: dict):
    """(points, cells, T) of part i's field (0..3: lower plate, lower slider,
    upper slider, upper plate; plate-local coordinates, outputs/placement.py)
    in the device's coordinates at the frame whose CSV values are ``vals``.

    Part i carries surface S(i+1), a sphere of radius R about the centre C
    of surface_centres; the part's body turns by phi (the slider plates) or
    not (the outer plates). A plate-local point at arc (x, y) from the
    part's apex and depth d goes, in the body's frame, to C + (R + d) n, n at
    polar angle hypot(x, y) / R from the apex direction (down from C for the
    concave-up S1 and S2, the steel below; up for S3 and S4, the steel
    above), then turns with the body: the footprint the loop gives the
    thermal model (+s1, +s2 on the lower parts, -s3, -s4 on the upper ones)
    lands where the pad or the slider touches that surface."""
    points, cells, T = fld
    T = np.asarray(T, dtype=float)
    k = i + 1
    if params.source == "fixed-point":
        cx = params.radius_m
    else:
        cx = vals.get(f"s{k}_m", 0.0) * (1.0 if i < 2 else -1.0)
    q = local_points(points, cx)
    if params.model == "axisym":
        q, cells = mirror_section(q, cells)
        T = np.concatenate((T, T))
    phi, alpha = float(vals.get("phi_rad", 0.0)), float(vals.get("alpha_rad", 0.0))
    C = surface_centres(g, float(vals.get("xg_m", 0.0)), phi, alpha)[i]
    R = (g.R1, g.R2, g.R3, g.R4)[i]
    turn = phi if i in (1, 2) else 0.0
    x, y, d = q[:, 0], q[:, 1], q[:, 2]
    rho = np.hypot(x, y)
    ang = rho / R
    with np.errstate(invalid="ignore", divide="ignore"):
        ux = np.where(rho > 0, x / rho, 0.0)
        uy = np.where(rho > 0, y / rho, 0.0)
    r = R + d
    bx = r * np.sin(ang) * ux
    bz = (-1.0 if i < 2 else 1.0) * r * np.cos(ang)
    c, s = math.cos(turn), math.sin(turn)
    world = np.column_stack((C[0] + c * bx - s * bz, r * np.sin(ang) * uy, C[1] + s * bx + c * bz))
    return world, cells, T


class TFPVTKSeries:
    """The TFP's VTK series (same hooks as coupling/vtk_output.VTKSeries)."""

    def __init__(self, folder, sim):
        from fpd.meshes.vtk import PVDWriter

        self.folder = Path(folder)
        self.sim = sim
        self.hottest = HottestFields(TFP_SIDES)     # the four parts' fields at their hottest (plots/)
        mode = sim.scene["output"]["vtk_fe3d"]
        self.plates = []              # (part, plate, its output grid)
        for part, plate, pp in zip(TFP_PARTS, sim.plates, sim.plate_params):
            if plate is None or not callable(getattr(plate, "field", None)) or plate.field() is None:
                continue
            self.plates.append((part, plate, FieldView(plate, pp.model, mode)))
        mech = sim.mechanics
        vals = dict(zip(mech.columns, mech.values()))
        for i, (p, pp) in enumerate(zip(sim.plates, sim.plate_params), start=1):
            vals[f"T{i}_C"] = p.surface_temperature() if p is not None else pp.T0_C
        # row 0's mu1..mu4 as simulate_tfp records them: at the initial temperatures, zero speed
        for i, law in enumerate(sim.laws, start=1):
            vals.setdefault(f"mu{i}", law(vals[f"T{i}_C"], mech.N[i - 1] / sim.geometry.areas[i - 1], 0.0))
        # frame 0 built in memory and the whole series bounded before any file exists
        t, entries, fields = self._entries(0, vals)
        single = {f"{part}_plate": view.single for part, _, view in self.plates}
        self.estimate_bytes = check_budget(sim, entries, single, any(v.mode != "slice" and v.single for _, _, v in self.plates))
        self.writers = {"device": PVDWriter(self.folder, "device")}
        for part, _, view in self.plates:
            self.writers[f"{part}_plate"] = PVDWriter(self.folder, f"{part}_plate", single=view.single)
        self.device = self.writers["device"]
        self._put(t, entries, fields, vals)

    def frame(self, n: int, sim=None) -> None:
        vals = getattr(self.sim, "frame_values", None)
        if vals is None:
            mech = self.sim.mechanics
            vals = dict(zip(mech.columns, mech.values()))
        vals = dict(vals)
        self._put(*self._entries(n, vals), vals)

    def _put(self, t, entries, fields, vals) -> None:
        put(self.writers, t, entries)
        # the hottest fields (plots/): fe3d parts offer their state (outputs/hottest.py), the others
        # the frame's field in the part's own coordinates, as the DFP's series offers it
        self.hottest.update([p if hasattr(p, "field_state") else None for p in self.sim.plates], t)
        for part, fld in fields:
            i = TFP_PARTS.index(part)
            self.hottest.consider(part, t, *fld, surface=vals.get(f"T{i + 1}_C"), params=self.sim.plate_params[i])

    def _entries(self, n: int, vals: dict):
        """(time, the frame's files as outputs/vtk_budget entries, [(part,
        its own field)] for the hottest-field pictures)."""
        sim = self.sim
        g = sim.geometry
        t = float(vals.get("t_s", n * sim.dt))
        polys = tfp_polygons(g, sim.plate_params, float(vals["xg_m"]), float(vals["phi_rad"]), float(vals["alpha_rad"]))
        nan = float("nan")
        T = (vals.get("T1_C", nan), vals.get("T2_C", nan), nan, vals.get("T3_C", nan), vals.get("T4_C", nan), nan)
        mu = (vals.get("mu1", nan), vals.get("mu2", nan), nan, vals.get("mu3", nan), vals.get("mu4", nan), nan)
        pts, cells, start = [], [], 0
        for poly in polys:
            pts.append(poly)
            cells.append(("polygon", np.arange(start, start + len(poly))[None, :]))
            start += len(poly)
        allp = np.vstack(pts)
        points = np.column_stack((allp[:, 0], np.zeros(start), allp[:, 1]))
        entries = [("device", [(None, points, cells, None, {
            "body": [np.array([i], dtype=np.int32) for i in range(len(BODIES))],
            "T_C": [np.array([float(x)]) for x in T],
            "mu": [np.array([float(x)]) for x in mu],
        })])]
        fields = []
        for part, plate, view in self.plates:
            fld = view.field(plate)
            if fld is None:
                continue
            # placed in the device's coordinates, so it overlays device.pvd
            i = TFP_PARTS.index(part)
            p, c, Tf = place_part_field(i, fld, g, sim.plate_params[i], vals)
            depth = depth_of(fld[0], len(p))        # below the sliding face: the heated layer
            if len(Tf) == len(p):
                entries.append((f"{part}_plate", [(None, p, c, {"T_C": Tf, "depth_m": depth}, None)]))
            else:
                entries.append((f"{part}_plate", [(None, p, c, {"depth_m": depth}, {"T_C": [Tf]})]))
            if not hasattr(plate, "field_state"):
                fields.append((part, fld))
        return t, entries, fields

    def close(self) -> None:
        for w in self.writers.values():
            w.close()

    def hottest_pictures(self, plots_dir) -> list:
        """One PNG per heated part with a field (outputs/hottest.py)."""
        return self.hottest.pictures(plots_dir)
