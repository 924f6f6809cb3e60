"""The run's VTK series (docs/reference.md, outputs: ``vtk/``).

- ``device.pvd``: the device as moving polygons in the x-z plane (y = 0):
  the lower plate (a band of the plate's thickness under its concave arc,
  moving with the ground), the pad section (its two arcs between the four
  corners), the upper plate (a band over its arc; for the SFP, a flat
  housing on the pivot) and the superstructure block on top. Two parts per
  time (one file each, listed with part="0" name="plates" and part="1"
  name="bodies"; ParaView and pyvista read a multiblock), so that a body
  without a temperature carries no such field: ``plates`` (lower, upper
  plate) with cell data ``body`` (0, 2), ``T_C`` (T1, T2: what the plate
  model's column T1_C / T2_C is, e.g. the footprint mean) and ``mu`` (mu1,
  mu2), the values of timeseries.csv at the frame's step; ``bodies`` (pad,
  superstructure) with ``body`` (1, 3) only.
- ``lower_plate.pvd`` / ``upper_plate.pvd``: each plate model's temperature
  field (``PlateModel.field()``: points, meshio-style cells, nodal T_C)
  placed in the device's coordinates (outputs/placement.py: wrapped onto
  the plate's concave surface, the column or section under the footprint,
  moving with the ground or the superstructure), so it overlays device.pvd,
  with point data ``depth_m`` (below the sliding face: the heated layer);
  an fe3d plate on the grid of ``output.vtk_fe3d`` (outputs/vtk_budget.py),
  in float32; no series for plates without a field (lumped, none).

Every frame is written when ``simulate`` calls ``VTKSeries.frame`` (every
``output.vtk_every`` steps); frame 0 is the initial state. Frame 0 is built
first in memory and the whole series bounded from it: over
``output.vtk_max_GB`` the run is refused before any file exists. The files
are written by meshes/vtk.py (zlib-compressed VTU, no meshio); matplotlib is
imported only by ``hottest_pictures``.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .hottest import HottestFields
from .placement import place_field
from .vtk_budget import FieldView, check_budget, depth_of, put

BODIES = ("lower_plate", "pad", "upper_plate", "superstructure")
N_ARC = 32          # points per arc of the device polygons
TILT = 2            # phase code of a rocking pad (mechanics.seated.PHASES)


# -- geometry of the drawing ----------------------------------------------------
def _arc(centre, radius, phi, down: bool) -> np.ndarray:
    """Points centre + radius (sin phi, -+cos phi) (down: the lower half)."""
    sgn = -1.0 if down else 1.0
    return np.column_stack((centre[0] + radius * np.sin(phi), centre[1] + sgn * radius * np.cos(phi)))


def _half_width(plate_radius: float, R: float, a: float) -> float:
    """Half-width drawn for a plate: its radius, at least a bit wider than the
    pad, and short of a half circle."""
    return min(max(plate_radius, 1.2 * a), 0.95 * R)


def pad_outline_body(geom, n: int = N_ARC) -> np.ndarray:
    """The pad section in its body frame (xi, eta): bottom arc A -> B, top arc
    C -> D (closed implicitly D -> A), the radii of ``pad_corners_body``."""
    a, h, R1 = geom.a, geom.pad_height, geom.R1
    Rt = geom.R2 if geom.kind == "DFP" else geom.R1
    xi = np.linspace(-a, a, n)
    bottom = np.column_stack((xi, R1 - np.sqrt(R1 ** 2 - xi ** 2)))
    top = np.column_stack((xi[::-1], h - Rt + np.sqrt(Rt ** 2 - xi[::-1] ** 2)))
    return np.vstack((bottom, top))


def _to_world(O, angle: float, body: np.ndarray) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.column_stack((O[0] + c * body[:, 0] - s * body[:, 1], O[1] + s * body[:, 0] + c * body[:, 1]))


def pad_pose(geom, mech, theta: float, xg: float):
    """(O, angle): world position of the pad's bottom apex and its rotation.

    Seated: from ``geom.seated(theta, xg)``. A stepper may describe the pad
    itself: ``pad_pose()`` -> (O_x relative to the ground, O_z, angle);
    otherwise ``pad_angle`` overrides the seated rotation, and a stepper in
    the tilt phase (``mode``/``phase`` == 2) with a rocking angle ``beta``
    has the seated pad rotated by beta about its pivot corner (A, or B when
    ``diagonal`` == 1), as in the two-phase stepper's chain.
    """
    pose = getattr(mech, "pad_pose", None)
    if callable(pose):
        ox, oz, ang = pose()
        return np.array([xg + ox, oz]), float(ang)
    s = geom.seated(theta, xg)
    O = np.asarray(s["O"], dtype=float)
    angle = float(getattr(mech, "pad_angle", s["pad_angle"]))
    mode = getattr(mech, "mode", getattr(mech, "phase", 0))
    beta = getattr(mech, "beta", 0.0)
    if mode == TILT and isinstance(beta, (int, float)) and beta != 0.0:
        corner = geom.pad_corners_body()["B" if getattr(mech, "diagonal", 0) == 1 else "A"]
        P = geom.to_world(O, angle, *corner)
        c, sn = math.cos(beta), math.sin(beta)
        d = O - P
        O = P + np.array([c * d[0] - sn * d[1], sn * d[0] + c * d[1]])
        angle += beta
    return O, angle


def device_polygons(geom, plate_params, xg: float, u: float, z: float, O, angle: float,
                    n: int = N_ARC) -> list[np.ndarray]:
    """The four polygons (lower plate, pad, upper plate, superstructure),
    each a (k, 2) array of (x, z) vertices, counter-clockwise or clockwise.

    xg: ground position; u, z: the superstructure's displacement and uplift
    relative to the ground (its upper-surface apex is at (xg + u, h + z));
    O, angle: the pad pose (``pad_pose``).
    """
    R1, R2, a, h = geom.R1, geom.R2, geom.a, geom.pad_height
    p1, p2 = plate_params
    # lower plate: concave arc of radius R1 about C1 = (xg, R1), band below it
    w1 = _half_width(p1.plate_radius, R1, a)
    phi1 = np.linspace(-math.asin(w1 / R1), math.asin(w1 / R1), n)
    C1 = (xg, R1)
    lower = np.vstack((_arc(C1, R1, phi1, True), _arc(C1, R1 + p1.plate_thickness, phi1[::-1], True)))
    pad = _to_world(O, angle, pad_outline_body(geom, n))
    apex = (xg + u, h + z)
    t2 = p2.plate_thickness
    if geom.kind == "DFP":
        w2 = _half_width(p2.plate_radius, R2, a)
        phi2 = np.linspace(-math.asin(w2 / R2), math.asin(w2 / R2), n)
        C2 = (apex[0], apex[1] - R2)
        upper = np.vstack((_arc(C2, R2, phi2, False), _arc(C2, R2 + t2, phi2[::-1], False)))
    else:   # SFP: flat housing resting on the slider's pivot
        w2 = max(p2.plate_radius, 1.2 * a)
        x0, x1 = apex[0] - w2, apex[0] + w2
        upper = np.array([[x0, apex[1]], [x1, apex[1]], [x1, apex[1] + t2], [x0, apex[1] + t2]])
    ws = 1.25 * max(w1, w2)
    hs = 0.4 * ws
    zb = apex[1] + t2
    block = np.array([[apex[0] - ws, zb], [apex[0] + ws, zb], [apex[0] + ws, zb + hs], [apex[0] - ws, zb + hs]])
    return [lower, pad, upper, block]


# -- the series -------------------------------------------------------------------
class VTKSeries:
    """Writes the device and plate series of one run into ``folder``.

    ``frame(n, sim)`` is ``simulate``'s on_frame hook; it reads the values of
    the step's CSV row from ``sim.frame_values`` (set by ``simulate`` just
    before the call) and falls back to the models' current state.
    """

    def __init__(self, folder, sim):
        from fpd.meshes.vtk import PVDWriter

        self.folder = Path(folder)
        self.sim = sim
        self.geom = sim.geometry
        self.hottest = HottestFields()   # side -> (Tmax, time, points, cells, T)
        self._shapes = None
        mode = sim.scene["output"]["vtk_fe3d"]
        self.plates = []              # (side, plate, its output grid)
        for side, plate, pp in zip(("lower", "upper"), sim.plates, sim.plate_params):
            if plate is None or not callable(getattr(plate, "field", None)):
                continue
            if plate.field() is None:
                continue
            self.plates.append((side, plate, FieldView(plate, pp.model, mode)))
        # frame 0 built in memory and the whole series bounded before any file exists
        vals = self._initial_values()
        t, entries, fields = self._entries(0, vals)
        single = {f"{side}_plate": view.single for side, _, view in self.plates}
        self.estimate_bytes = check_budget(sim, entries, single, any(v.mode != "slice" and v.single for _, _, v in self.plates))
        self.writers = {"device": PVDWriter(self.folder, "device")}
        for side, _, view in self.plates:
            self.writers[f"{side}_plate"] = PVDWriter(self.folder, f"{side}_plate", single=view.single)
        self.device = self.writers["device"]
        self._put(t, entries, fields, vals)

    # values of the CSV row ----------------------------------------------------
    def _initial_values(self) -> dict:
        """Row 0 as ``simulate`` records it: mechanics values, mu at the initial
        temperatures with zero sliding speed, the plates' surface temperatures."""
        sim = self.sim
        mech = sim.mechanics
        vals = {}
        T = [p.surface_temperature() if p is not None else pp.T0_C for p, pp in zip(sim.plates, sim.plate_params)]
        if mech is not None:
            vals.update(zip(mech.columns, mech.values()))
            area = self.geom.contact_area
            vals["mu1"] = sim.laws[0](T[0], mech.N1 / area, 0.0)
            vals["mu2"] = sim.laws[1](T[1], mech.N2 / area, 0.0)
        else:
            vals["t_s"] = 0.0
        vals["T1_C"], vals["T2_C"] = T
        return vals

    def _current_values(self, n: int) -> dict:
        sim = self.sim
        vals = getattr(sim, "frame_values", None)
        if vals is not None:
            return dict(vals)
        mech = sim.mechanics
        vals = dict(zip(mech.columns, mech.values())) if mech is not None else {"t_s": n * sim.dt}
        for i, (p, pp) in enumerate(zip(sim.plates, sim.plate_params), start=1):
            vals.setdefault(f"T{i}_C", p.surface_temperature() if p is not None else pp.T0_C)
        return vals

    # hooks ------------------------------------------------------------------
    def frame(self, n: int, sim=None) -> None:
        self._write(n, self._current_values(n))

    def _write(self, n: int, vals: dict) -> None:
        self._put(*self._entries(n, vals), vals)

    def _put(self, t, entries, fields, vals) -> None:
        put(self.writers, t, entries)
        # the hottest field of each plate (plots/): a plate whose field is dear to
        # build (fe3d) offers its temperature and state only (outputs/hottest.py),
        # the others their field as written (``fields``)
        self.hottest.update([p if hasattr(p, "field_state") else None for p in self.sim.plates], t)
        for side, fld in fields:
            i = 0 if side == "lower" else 1
            self.hottest.consider(side, t, *fld, surface=vals.get(f"T{i + 1}_C"), params=self.sim.plate_params[i])

    def _entries(self, n: int, vals: dict):
        """(time, the frame's files as outputs/vtk_budget entries, [(side,
        the plate's own field)] for the hottest-field pictures)."""
        sim, geom = self.sim, self.geom
        mech = sim.mechanics
        t = float(vals.get("t_s", n * sim.dt))
        theta = float(vals.get("theta_rad", getattr(mech, "theta", 0.0)))
        xg = float(vals.get("xg_m", 0.0))
        u = float(vals.get("u_m", geom.L * math.sin(theta)))
        z = float(vals.get("z_m", geom.L * (1.0 - math.cos(theta))))
        O, angle = pad_pose(geom, mech, theta, xg)
        polys = self._polygons(xg, u, z, O, angle)
        # two parts per time, so that each body carries only the fields it
        # has (no NaN cells): the plates (T_C, mu: the CSV's T1/T2, mu1/mu2)
        # and the bodies without a sliding surface of their own (pad, superstructure)
        nan = float("nan")
        plates = [(0, polys[0], vals.get("T1_C", nan), vals.get("mu1", nan)),
                  (2, polys[2], vals.get("T2_C", nan), vals.get("mu2", nan))]
        parts = [("plates", [(b, poly) for b, poly, _, _ in plates],
                  {"T_C": [np.array([float(T)]) for _, _, T, _ in plates],
                   "mu": [np.array([float(m)]) for _, _, _, m in plates]}),
                 ("bodies", [(1, polys[1]), (3, polys[3])], {})]
        out = []
        for name, bodies, cdata in parts:
            pts, cells, start = [], [], 0
            for _, poly in bodies:
                pts.append(poly)
                cells.append(("polygon", np.arange(start, start + len(poly))[None, :]))
                start += len(poly)
            xz = np.vstack(pts)
            points = np.column_stack((xz[:, 0], np.zeros(start), xz[:, 1]))
            cdata = dict(cdata, body=[np.array([b], dtype=np.int32) for b, _ in bodies])
            out.append((name, points, cells, None, cdata))
        entries, fields = [("device", out)], []
        for side, plate, view in self.plates:
            fld = view.field(plate)
            if fld is None:
                continue
            p, c, Tf = fld
            Tf = np.asarray(Tf, dtype=float)
            p = np.asarray(p, dtype=float)
            # placed in the device's coordinates, so it overlays device.pvd (outputs/placement.py)
            pw, cw, Tw = place_field(side, (p, c, Tf), geom, sim.plate_params[0 if side == "lower" else 1], vals)
            depth = depth_of(p, len(pw))            # below the sliding face: the heated layer in ParaView, fpd render
            if len(Tw) == len(pw):
                entries.append((f"{side}_plate", [(None, pw, cw, {"T_C": Tw, "depth_m": depth}, None)]))
            else:
                entries.append((f"{side}_plate", [(None, pw, cw, {"depth_m": depth}, {"T_C": [Tw]})]))
            if not hasattr(plate, "field_state"):
                fields.append((side, (np.asarray(p, dtype=float), c, np.asarray(Tf, dtype=float))))
        return t, entries, fields

    def _polygons(self, xg, u, z, O, angle):
        """device_polygons, by translating shapes computed once: the lower
        plate moves with x_g, the upper plate and the superstructure with the
        apex (x_g + u, h + z), the pad is its body outline moved to its pose
        (the same points, ~10x cheaper per frame: vtk_every = 1 is affordable)."""
        if self._shapes is None:
            ref = device_polygons(self.geom, self.sim.plate_params, 0.0, 0.0, 0.0, np.zeros(2), 0.0)
            apex0 = np.array([0.0, self.geom.pad_height])
            self._shapes = (ref[0], ref[2] - apex0, ref[3] - apex0, pad_outline_body(self.geom))
        lower, upper, block, pad = self._shapes
        apex = np.array([xg + u, self.geom.pad_height + z])
        return [lower + np.array([xg, 0.0]), _to_world(O, angle, pad), upper + apex, block + apex]

    def close(self) -> None:
        for w in self.writers.values():
            w.close()

    # pictures -----------------------------------------------------------------
    def hottest_pictures(self, plots_dir) -> list[Path]:
        """One PNG per plate with a field: its temperature field at the frame
        with the highest maximum temperature (matplotlib, no OpenGL)."""
        return self.hottest.pictures(plots_dir)


def series_class(scene, sim):
    """The VTK series that draws this simulation's device: the TFP's
    (outputs/tfp_vtk.py), a bidirectional run's in 3D
    (outputs/vtk_bidirectional.py) or the planar DFP / SFP above (one
    choice for ``fpd run`` and ``fpd.run``)."""
    if scene["device"]["kind"] == "TFP":
        from .tfp_vtk import TFPVTKSeries
        return TFPVTKSeries
    if getattr(sim.mechanics, "two_d", False):
        from .vtk_bidirectional import VTKSeries3D
        return VTKSeries3D
    return VTKSeries
