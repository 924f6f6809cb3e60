"""What each device's VTK series draws (outputs/vtk_output.py writes them):
the bodies of one frame and where each interface's plate field goes.

A stepper names its drawing (``stepper.drawing``, a key of ``DRAWINGS``;
a simulation without mechanics is drawn as the planar DFP) and
``drawing_of(sim)`` makes it. A drawing declares:

- ``series``: the name of the device's series (``<series>.pvd``);
- ``parts``: per interface, the name of its plate series
  (``<part>_plate.pvd``), the hottest-field picture's side
  (outputs/hottest.py); ``place`` None when plate fields are not drawn;
- ``bodies(vals)``: the device's parts at the frame whose CSV values are
  ``vals`` (outputs/vtk_budget.py's parts: ``[(part name or None, points,
  cells, point_data, cell_data)]``);
- ``place(i, fld, vals)``: interface i's field (``PlateModel.field()``,
  plate-local) in the device's coordinates (outputs/placement.py).

The drawings:

- ``"planar"`` (DFP, SFP, their test machines, in the x-z plane):
  ``device.pvd``, the device as moving polygons at y = 0: the lower plate
  (a band of the plate's thickness under its concave arc, moving with the
  ground), the pad section (its two arcs between the four corners), the
  upper plate (a band over its arc; for the SFP, a flat housing on the
  pivot) and the superstructure block on top. Two parts per time (one file
  each, listed with part="0" name="plates" and part="1" name="bodies";
  ParaView and pyvista read a multiblock), so that a body without a
  temperature carries no such field: ``plates`` (lower, upper plate) with
  cell data ``body`` (0, 2), ``T_C`` (T1, T2: what the plate model's column
  T1_C / T2_C is, e.g. the footprint mean) and ``mu`` (mu1, mu2);
  ``bodies`` (pad, superstructure) with ``body`` (1, 3) only. Plate series
  ``lower_plate.pvd`` / ``upper_plate.pvd`` (``placement.place_field``:
  wrapped onto the plate's concave surface, the column or section under the
  footprint, moving with the ground or the superstructure).
- ``"spatial"`` (the DFP / SFP in both directions): ``device3d.pvd``, per
  frame the lower plate (its concave spherical cap of radius R1 over the
  plate's radius, moving with the ground (x_g, y_g)), the pad (a cylinder of
  radius a and height h, its axis along the pad axis -n, bottom apex at
  C1 + R1 n), the upper plate (its concave cap of radius R2, centred on the
  superstructure's apex) and the superstructure (a box on top); x, y
  horizontal, z up; the caps triangles, the pad's side quads and its faces
  polygons. Cell data ``body`` (0 lower plate, 1 pad, 2 upper plate, 3
  superstructure), ``T_C`` and ``mu`` (NaN on the pad and the
  superstructure). Plate fields are not drawn.
- ``"tfp"``: ``device.pvd``, the five bodies and the superstructure block
  as moving polygons at y = 0, each frame at the pose of the exact rigid
  model (mechanics/tfp.py): lower plate (band under S1, moving with the
  ground), lower slider plate (convex R1 below, concave S2 above), pad
  (convex R2 and R3), upper slider plate (concave S3 below, convex R4
  above), upper plate (band over S4), superstructure. Cell data per polygon:
  ``body`` (0..5 in that order), ``T_C`` (T1 on the lower plate, T2 on the
  lower slider, T3 on the upper slider, T4 on the upper plate, NaN on the
  pad and the superstructure) and ``mu`` (the friction of the surface that
  heats that part). Plate series ``<part>_plate.pvd`` for the four parts
  (``placement.place_part_field``: each part's field wrapped onto its own
  sliding surface, at that body's pose).

T_C and mu are the values of timeseries.csv at the frame's step.
"""
from __future__ import annotations

import math

import numpy as np

from fpd.schema.scene import TFP_PARTS
from .placement import _e, place_field, place_part_field, surface_centres

N_ARC = 32          # points per arc of the planar polygons
TILT = 2            # phase code of a rocking pad (machines.seated.PHASES)
N_RING, N_SECTOR = 8, 48     # rings and sectors of a 3D cap


def _in_plane(polys):
    """Points (y = 0) and polygon cells of (k, 2) arrays of (x, z) vertices."""
    cells, start = [], 0
    for poly in polys:
        cells.append(("polygon", np.arange(start, start + len(poly))[None, :]))
        start += len(poly)
    xz = np.vstack(polys)
    return np.column_stack((xz[:, 0], np.zeros(start), xz[:, 1])), cells


def _polygon_part(name, bodies, cell_data):
    """A part of polygons in the x-z plane: ``bodies`` [(body id, polygon)],
    its cell data ``cell_data`` and then ``body``."""
    points, cells = _in_plane([poly for _, poly in bodies])
    return (name, points, cells, None, dict(cell_data, body=[np.array([b], dtype=np.int32) for b, _ in bodies]))


# -- the planar DFP / SFP ------------------------------------------------------------
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


class PlanarDrawing:
    """The DFP / SFP in the x-z plane (the module's text)."""

    series = "device"
    parts = ("lower", "upper")
    BODIES = ("lower_plate", "pad", "upper_plate", "superstructure")

    def __init__(self, sim):
        self.sim, self.geom = sim, sim.geometry
        self._shapes = None

    def bodies(self, vals: dict) -> list:
        geom, mech = self.geom, self.sim.mechanics
        theta = float(vals.get("theta_rad", getattr(mech, "theta", 0.0)))
        xg = float(vals.get("xg_m", 0.0))
        u = float(vals.get("u_m", geom.L * math.sin(theta)))
        z = float(vals.get("z_m", geom.L * (1.0 - math.cos(theta))))
        O, angle = pad_pose(geom, mech, theta, xg)
        polys = self._polygons(xg, u, z, O, angle)
        # two parts, so that each body carries only the fields it has (no NaN
        # cells): the plates (T_C, mu: the CSV's T1/T2, mu1/mu2) and the
        # bodies without a sliding surface of their own (pad, superstructure)
        nan = float("nan")
        T = (vals.get("T1_C", nan), vals.get("T2_C", nan))
        mu = (vals.get("mu1", nan), vals.get("mu2", nan))
        return [_polygon_part("plates", [(0, polys[0]), (2, polys[2])],
                              {"T_C": [np.array([float(x)]) for x in T], "mu": [np.array([float(x)]) for x in mu]}),
                _polygon_part("bodies", [(1, polys[1]), (3, polys[3])], {})]

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

    def place(self, i: int, fld, vals: dict):
        return place_field(self.parts[i], fld, self.geom, self.sim.plate_params[i], vals)


# -- the DFP / SFP in both directions --------------------------------------------------
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


class SpatialDrawing:
    """The DFP / SFP in both directions, in 3D (the module's text)."""

    series = "device3d"
    parts = ("lower", "upper")
    place = None                 # plate fields are not drawn in 3D

    def __init__(self, sim):
        self.sim, self.geom = sim, sim.geometry

    def bodies(self, vals: dict) -> list:
        L = self.geom.L
        ux, uy = float(vals["ux_m"]), float(vals["uy_m"])
        nx, ny = ux / L, uy / L
        axis = (nx, ny, -math.sqrt(max(1.0 - nx * nx - ny * ny, 0.0)))
        pts, blocks, bodies = device_3d(self.geom, self.sim.plate_params, float(vals["xg_m"]), float(vals["yg_m"]),
                                        ux, uy, axis)
        nan = float("nan")
        T = {0: vals.get("T1_C", nan), 2: vals.get("T2_C", nan)}
        mu = {0: vals.get("mu1", nan), 2: vals.get("mu2", nan)}
        return [(None, pts, blocks, None, {
            "body": [np.full(len(c), b, dtype=np.int32) for (_, c), b in zip(blocks, bodies)],
            "T_C": [np.full(len(c), float(T.get(b, nan))) for (_, c), b in zip(blocks, bodies)],
            "mu": [np.full(len(c), float(mu.get(b, nan))) for (_, c), b in zip(blocks, bodies)],
        })]


# -- the triple friction pendulum ----------------------------------------------------
def _band(C, R, half_width, thickness, below: bool, n=N_ARC):
    """A plate: a band of ``thickness`` behind the arc of radius R about C
    (below: a concave-up face, the band under it; else a concave-down face)."""
    w = min(half_width, 0.95 * R)
    phi = np.linspace(-math.asin(w / R), math.asin(w / R), n)
    sg = -1.0 if below else 1.0
    inner = np.column_stack((C[0] + R * np.sin(phi), C[1] + sg * R * np.cos(phi)))
    outer = np.column_stack((C[0] + (R + thickness) * np.sin(phi[::-1]), C[1] + sg * (R + thickness) * np.cos(phi[::-1])))
    return np.vstack((inner, outer))


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
    slider_lo = _to_world(C1 - g.R1 * _e(phi), phi, sl)
    pad = np.vstack((np.column_stack((xp, g.R2 - np.sqrt(g.R2 ** 2 - xp ** 2))),
                     np.column_stack((xp[::-1], hp - g.R3 + np.sqrt(g.R3 ** 2 - xp[::-1] ** 2)))))
    pad = _to_world(C2 - g.R2 * _e(psi), psi, pad)
    # upper slider: origin at its lower apex (C3 + R3 e), concave S3 below, convex R4 above (centre C4)
    su = np.vstack((np.column_stack((xs, -g.R3 + np.sqrt(g.R3 ** 2 - xs ** 2))),
                    np.column_stack((xs[::-1], tu - g.R4 + np.sqrt(g.R4 ** 2 - xs[::-1] ** 2)))))
    slider_up = _to_world(C3 + g.R3 * _e(phi), phi, su)
    upper = _band(C4, g.R4, max(plate_params[3].plate_radius, 1.2 * rs), plate_params[3].plate_thickness, False, n)
    top = C4[1] + g.R4 + plate_params[3].plate_thickness
    ws = 1.25 * max(plate_params[3].plate_radius, 1.2 * rs)
    block = np.array([[C4[0] - ws, top], [C4[0] + ws, top], [C4[0] + ws, top + 0.4 * ws], [C4[0] - ws, top + 0.4 * ws]])
    return [lower, slider_lo, pad, slider_up, upper, block]



class TFPDrawing:
    """The triple friction pendulum in the x-z plane (the module's text)."""

    series = "device"
    parts = TFP_PARTS
    BODIES = ("lower_plate", "lower_slider", "pad", "upper_slider", "upper_plate", "superstructure")

    def __init__(self, sim):
        self.sim, self.geom = sim, sim.geometry

    def bodies(self, vals: dict) -> list:
        phi, alpha = float(vals["phi_rad"]), float(vals["alpha_rad"])
        polys = tfp_polygons(self.geom, self.sim.plate_params, float(vals["xg_m"]), phi, alpha)
        if float(vals.get("lift_m", 0.0)) > 0.0:
            # in flight (docs/model.md 10) all but the lower plate translate with the unit
            g, psi = self.geom, phi + alpha
            d = (float(vals["u_m"]) - g.A * math.sin(phi) - g.Li * math.sin(psi),
                 float(vals["z_m"]) - g.A * (1 - math.cos(phi)) - g.Li * (1 - math.cos(psi)))
            polys = polys[:1] + [p + np.array(d) for p in polys[1:]]
        nan = float("nan")
        T = (vals.get("T1_C", nan), vals.get("T2_C", nan), nan, vals.get("T3_C", nan), vals.get("T4_C", nan), nan)
        mu = (vals.get("mu1", nan), vals.get("mu2", nan), nan, vals.get("mu3", nan), vals.get("mu4", nan), nan)
        points, cells = _in_plane(polys)
        return [(None, points, cells, None, {"body": [np.array([i], dtype=np.int32) for i in range(len(polys))],
                                             "T_C": [np.array([float(x)]) for x in T],
                                             "mu": [np.array([float(x)]) for x in mu]})]

    def place(self, i: int, fld, vals: dict):
        return place_part_field(i, fld, self.geom, self.sim.plate_params[i], vals)


def _axis(vx: float, vy: float) -> np.ndarray:
    """The unit axis e(v) of a tilt vector (mechanics/tfp3d_kernel.py, docs/model.md 6.8)."""
    t = math.hypot(vx, vy)
    s = math.sin(t) / t if t > 0.0 else 1.0
    return np.array([-s * vx, -s * vy, math.cos(t)])


def tfp_3d(g, plate_params, xg, yg, q):
    """Meshio blocks of the TFP in both directions at ground (xg, yg) and tilts
    q = (phi_x, phi_y, alpha_x, alpha_y): (points, [(type, conn)...], body id
    per block; bodies in TFPDrawing.BODIES order)."""
    ep = _axis(q[0], q[1])
    es = _axis(q[0] + q[2], q[1] + q[3])
    C1 = np.array([xg, yg, g.R1])
    C2 = C1 - g.l1 * ep
    C3 = C2 - g.Li * es
    C4 = C3 - g.l4 * ep
    rs, rp = 0.5 * g.slider_diameter, 0.5 * g.pad_diameter
    blocks, bodies, pts, off = [], [], [], 0

    def add(p, kind, conn, body):
        nonlocal off
        pts.append(p)
        blocks.append((kind, conn + off))
        bodies.append(body)
        off += len(p)

    def cylinder(base, axis, a, h, body):
        cp, quads, ends = _cylinder(base, axis, a, h)
        add(cp, "quad", quads, body)
        for e in ends:
            add(cp[e], "polygon", np.arange(len(e), dtype=np.int64)[None, :], body)

    r1 = min(max(plate_params[0].plate_radius, 1.2 * rs), 0.95 * g.R1)
    p, t = _cap(C1, g.R1, r1, down=True)
    add(p, "triangle", t, 0)
    cylinder(C1 - g.R1 * ep, ep, rs, g.slider_height_lower, 1)          # on S1, along the stack's axis
    cylinder(C2 - g.R2 * es, es, rp, g.pad_height, 2)                    # on S2, along the pad's axis
    cylinder(C3 + g.R3 * ep, ep, rs, g.slider_height_upper, 3)          # under S4
    r4 = min(max(plate_params[3].plate_radius, 1.2 * rs), 0.95 * g.R4)
    p, t = _cap(C4, g.R4, r4, down=False)
    add(p, "triangle", t, 4)
    top = C4[2] + g.R4 + plate_params[3].plate_thickness
    half = 1.25 * max(r1, r4)
    bp, hexa = _box((C4[0], C4[1], top), half, 0.4 * half)
    add(bp, "hexahedron", hexa, 5)
    return np.vstack(pts), blocks, bodies


class TFP3DDrawing:
    """The triple friction pendulum in both directions, in 3D: the lower and
    upper plates' spherical caps, the slider plates and the pad as cylinders
    along their axes e(phi), e(phi + alpha), the superstructure block."""

    series = "device3d"
    parts = TFP_PARTS
    place = None                 # plate fields are not drawn in 3D

    def __init__(self, sim):
        self.sim, self.geom = sim, sim.geometry

    def bodies(self, vals: dict) -> list:
        q = [float(vals[c]) for c in ("phix_rad", "phiy_rad", "alphax_rad", "alphay_rad")]
        pts, blocks, bodies = tfp_3d(self.geom, self.sim.plate_params, float(vals["xg_m"]), float(vals["yg_m"]), q)
        if float(vals.get("lift_m", 0.0)) > 0.0:
            # in flight (docs/model.md 10) all but the lower plate translate with the unit
            g = self.geom
            ep, es = _axis(q[0], q[1]), _axis(q[0] + q[2], q[1] + q[3])
            d = np.array([float(vals["ux_m"]), float(vals["uy_m"]), float(vals["z_m"]) - g.A - g.Li])
            d += g.A * ep + g.Li * es
            first = np.max(blocks[0][1]) + 1          # the lower plate's points come first
            pts = np.vstack((pts[:first], pts[first:] + d))
        nan = float("nan")
        T = (vals.get("T1_C", nan), vals.get("T2_C", nan), nan, vals.get("T3_C", nan), vals.get("T4_C", nan), nan)
        mu = (vals.get("mu1", nan), vals.get("mu2", nan), nan, vals.get("mu3", nan), vals.get("mu4", nan), nan)
        return [(None, pts, blocks, None, {
            "body": [np.full(len(c), b, dtype=np.int32) for (_, c), b in zip(blocks, bodies)],
            "T_C": [np.full(len(c), float(T[b])) for (_, c), b in zip(blocks, bodies)],
            "mu": [np.full(len(c), float(mu[b])) for (_, c), b in zip(blocks, bodies)],
        })]


# what a stepper's ``drawing`` names
DRAWINGS = {"planar": PlanarDrawing, "spatial": SpatialDrawing, "tfp": TFPDrawing, "tfp3d": TFP3DDrawing}


def drawing_of(sim):
    """The drawing of a simulation's device (``sim.mechanics.drawing``; the
    planar one without mechanics)."""
    name = getattr(sim.mechanics, "drawing", "planar") if sim.mechanics is not None else "planar"
    if name not in DRAWINGS:
        raise ValueError(f"no VTK drawing of this device ({name!r})")
    return DRAWINGS[name](sim)
