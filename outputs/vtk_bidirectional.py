"""VTK of a bidirectional run (model.md 8): the device in 3D for ParaView.

``device3d.pvd``: per frame, the lower plate (its concave spherical cap of
radius R1 over the plate's radius, moving with the ground (x_g, y_g)), the
pad (a cylinder of radius a and height h, its axis along the pad axis -n,
bottom apex at C1 + R1 n), the upper plate (its concave cap of radius R2,
centred on the superstructure's apex) and the superstructure (a box on
top). World axes x, y horizontal, z up; the plates' caps are triangles, the
pad's side quads and its faces polygons. Cell data: ``body`` (0 lower
plate, 1 pad, 2 upper plate, 3 superstructure), ``T_C`` and ``mu`` (the
plate's surface temperature and friction coefficient of timeseries.csv at
that step, NaN on the pad and the superstructure). Plate fields (fe1d has
none in 3D) are not drawn here.

The same hooks as coupling/vtk_output.VTKSeries (``frame(n, sim)``,
``close()``, ``hottest``), so ``fpd run`` uses it for bidirectional scenes.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .hottest import HottestFields
from .vtk_budget import check_budget, put

BODIES = ("lower_plate", "pad", "upper_plate", "superstructure")
N_RING, N_SECTOR = 8, 48


def _cap(centre, R, radius, down: bool, n_ring=N_RING, n_sector=N_SECTOR):
    """Triangulated spherical cap of radius R about ``centre``: the lower
    (down) or upper half, out to horizontal radius ``radius``. Returns
    (points (k, 3), triangles (m, 3))."""
    cx, cy, cz = centre
    sgn = -1.0 if down else 1.0
    pts = [(cx, cy, cz + sgn * R)]
    phis = np.linspace(0.0, 2.0 * math.pi, n_sector, endpoint=False)
    for i in range(1, n_ring + 1):
        r = radius * i / n_ring
        zz = cz + sgn * math.sqrt(max(R * R - r * r, 0.0))
        pts += [(cx + r * math.cos(p), cy + r * math.sin(p), zz) for p in phis]
    tris = []
    for j in range(n_sector):
        tris.append((0, 1 + j, 1 + (j + 1) % n_sector))
    for i in range(1, n_ring):
        b0, b1 = 1 + (i - 1) * n_sector, 1 + i * n_sector
        for j in range(n_sector):
            j1 = (j + 1) % n_sector
            tris.append((b0 + j, b1 + j, b1 + j1))
            tris.append((b0 + j, b1 + j1, b0 + j1))
    return np.array(pts), np.array(tris, dtype=np.int64)


def _frame_axes(axis):
    """Two unit vectors perpendicular to the unit ``axis`` (regular for an axis near vertical)."""
    ax, ay, az = axis
    k = 1.0 / (1.0 + az)
    e1 = np.array([1.0 - ax * ax * k, -ax * ay * k, -ax])
    e2 = np.array([-ax * ay * k, 1.0 - ay * ay * k, -ay])
    return e1, e2


def _cylinder(base, axis, a, h, n=N_SECTOR):
    """Cylinder of radius a, height h from ``base`` along the unit ``axis``:
    points, side quads, and the two end polygons."""
    e1, e2 = _frame_axes(axis)
    phis = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    ring = np.array([a * (math.cos(p) * e1 + math.sin(p) * e2) for p in phis])
    bottom = base + ring
    top = base + h * np.asarray(axis) + ring
    pts = np.vstack((bottom, top))
    quads = np.array([(j, (j + 1) % n, n + (j + 1) % n, n + j) for j in range(n)], dtype=np.int64)
    ends = [np.arange(n - 1, -1, -1, dtype=np.int64), np.arange(n, 2 * n, dtype=np.int64)]
    return pts, quads, ends


def _box(centre_bottom, half, height):
    x, y, z = centre_bottom
    pts = np.array([(x + sx * half, y + sy * half, z + sz * height)
                    for sz in (0, 1) for sy in (-1, 1) for sx in (-1, 1)])
    return pts, np.array([[0, 1, 3, 2, 4, 5, 7, 6]], dtype=np.int64)


def device_3d(geom, plate_params, xg, yg, ux, uy, n):
    """Meshio blocks of the device at ground (xg, yg), relative displacement
    (ux, uy) and unit axis n (C1 -> C2): (points, [(type, conn)...], body id per block)."""
    R1, R2, a, h = geom.R1, geom.R2, geom.a, geom.pad_height
    p1, p2 = plate_params
    n = np.asarray(n, dtype=float)
    C1 = np.array([xg, yg, R1])
    blocks, bodies, pts, off = [], [], [], 0

    def add(p, kind, conn, body):
        nonlocal off
        pts.append(p)
        blocks.append((kind, conn + off))
        bodies.append(body)
        off += len(p)

    r1 = min(max(p1.plate_radius, 1.2 * a), 0.95 * R1)
    p, t = _cap(C1, R1, r1, down=True)
    add(p, "triangle", t, 0)
    O = C1 + R1 * n                      # the pad's bottom apex
    cp, quads, ends = _cylinder(O, -n, a, h)
    add(cp, "quad", quads, 1)
    for e in ends:
        pts_e = cp[e]
        add(pts_e, "polygon", np.arange(len(e), dtype=np.int64)[None, :], 1)
    z = geom.L * (n[0] ** 2 + n[1] ** 2) / (1.0 - n[2])        # uplift L (1 - cos theta)
    apex = np.array([xg + ux, yg + uy, h + z])
    if geom.kind == "DFP":
        r2 = min(max(p2.plate_radius, 1.2 * a), 0.95 * R2)
        p, t = _cap(apex - np.array([0.0, 0.0, R2]), R2, r2, down=False)
        add(p, "triangle", t, 2)
        top = apex[2] + p2.plate_thickness
        half = 1.25 * max(r1, r2)
    else:
        half = 1.25 * max(r1, p2.plate_radius)
        top = apex[2] + p2.plate_thickness
    bp, hexa = _box((apex[0], apex[1], top), half, 0.4 * half)
    add(bp, "hexahedron", hexa, 3)
    return np.vstack(pts), blocks, bodies


class VTKSeries3D:
    """The bidirectional run's ``vtk/device3d.pvd`` (hooks as VTKSeries)."""

    def __init__(self, folder, sim):
        from fpd.meshes.vtk import PVDWriter

        self.folder = Path(folder)
        self.sim = sim
        self.geom = sim.geometry
        self.hottest = HottestFields()
        mech = sim.mechanics
        vals = dict(zip(mech.columns, mech.values()))
        T = [p.surface_temperature() if p is not None else pp.T0_C for p, pp in zip(sim.plates, sim.plate_params)]
        vals["T1_C"], vals["T2_C"] = T
        # row 0's mu1, mu2 as the run records them: at the initial temperatures, zero speed
        area = self.geom.contact_area
        vals.setdefault("mu1", sim.laws[0](T[0], mech.N1 / area, 0.0))
        vals.setdefault("mu2", sim.laws[1](T[1], mech.N2 / area, 0.0))
        # frame 0 built in memory and the whole series bounded before any file exists
        t, entries = self._entries(0, vals)
        self.estimate_bytes = check_budget(sim, entries, {}, False)
        self.writers = {"device3d": PVDWriter(self.folder, "device3d")}
        self.device = self.writers["device3d"]
        put(self.writers, t, entries)

    def frame(self, n: int, sim=None) -> None:
        vals = getattr(self.sim, "frame_values", None)
        if vals is None:
            mech = self.sim.mechanics
            vals = dict(zip(mech.columns, mech.values()))
        put(self.writers, *self._entries(n, dict(vals)))

    def _entries(self, n, vals):
        """(time, the frame's file as outputs/vtk_budget entries)."""
        geom = self.geom
        L = geom.L
        ux, uy = float(vals["ux_m"]), float(vals["uy_m"])
        nx, ny = ux / L, uy / L
        axis = (nx, ny, -math.sqrt(max(1.0 - nx * nx - ny * ny, 0.0)))
        pts, blocks, bodies = device_3d(geom, self.sim.plate_params, float(vals["xg_m"]), float(vals["yg_m"]),
                                        ux, uy, axis)
        nan = float("nan")
        T = {0: vals.get("T1_C", nan), 2: vals.get("T2_C", nan)}
        mu = {0: vals.get("mu1", nan), 2: vals.get("mu2", nan)}
        return float(vals.get("t_s", n * self.sim.dt)), [("device3d", [(None, pts, blocks, None, {
            "body": [np.full(len(c), b, dtype=np.int32) for (_, c), b in zip(blocks, bodies)],
            "T_C": [np.full(len(c), float(T.get(b, nan))) for (_, c), b in zip(blocks, bodies)],
            "mu": [np.full(len(c), float(mu.get(b, nan))) for (_, c), b in zip(blocks, bodies)],
        })])]

    def close(self) -> None:
        self.device.close()

    def hottest_pictures(self, plots_dir) -> list:
        return self.hottest.pictures(plots_dir)
