"""Plate temperature fields placed in the device's coordinates (vtk/).

A plate model's ``field()`` gives (points, cells, T) in plate-local
coordinates: origin at the plate centre on the sliding face, x and y in the
face, the third coordinate through the thickness. Two depth conventions
exist and both are taken: fe1d and axisym put the steel at z <= 0 (z = 0 the
sliding face, negative down into the plate), fe3d at z >= 0 (z the depth).
Since the sliding face is z = 0 and the steel lies on one side of it, the
depth into the steel is |z| either way.

The device drawing (``device.pvd``) lives in world coordinates (x, y, z),
x the direction of motion, z up, y = 0 its plane:

- lower plate: its concave sliding surface is the sphere of radius R1 about
  C1 = (x_g, 0, R1) (x_g: where the ground or the machine has moved it); a
  plate-local point at arc coordinates (x, y) on the face and depth d goes
  to C1 + (R1 + d) n, n the unit vector at polar angle rho / R1 (rho =
  hypot(x, y)) from straight down, towards (x, y): the face is wrapped onto
  the sphere by arc length, the depth along the radius (into the steel,
  below the surface);
- upper plate (DFP): the sphere of radius R2 about C2 = apex - (0, 0, R2)
  (apex: the superstructure's upper-surface apex, x_g + u, h + z, so the
  plate moves with the superstructure), n from straight up, the steel above;
  SFP: the flat housing, the point at apex + (x, y, d);
- a field that is a single column (fe1d: every point at x = y = 0) is put
  where the model's column is: under the footprint centre (``source =
  "follow-pad"``: s1 on the lower plate, -s2 on the upper, the positions the
  run gives the thermal models) or at the material point's radius
  (``"fixed-point"``: x = radius_m);
- an axisymmetric section (axisym: x = r >= 0, y = 0) is drawn mirrored to
  -r as well, the full diametral section in the device's plane.

The footprint centre in plate-local x is s1 (lower) and -s2 (upper) in the
run loop (coupling/run.py), with the plates' x along the world x; that is
what makes a placed field's hot spot sit under the pad.

The TFP's four parts (``place_part_field``) are each wrapped onto their own
sliding surface S1..S4 (``surface_centres``), at that body's pose.
"""
from __future__ import annotations

import math

import numpy as np


def _wrap(points: np.ndarray, centre, R: float, up: bool) -> np.ndarray:
    """Plate-local (x, y, depth) -> world on the sphere of radius R about centre."""
    x, y, d = points[:, 0], points[:, 1], points[:, 2]
    rho = np.hypot(x, y)
    ang = rho / R
    s = np.sin(ang)
    with np.errstate(invalid="ignore", divide="ignore"):
        ux = np.where(rho > 0, x / rho, 0.0)
        uy = np.where(rho > 0, y / rho, 0.0)
    r = R + d
    zsign = 1.0 if up else -1.0
    return np.column_stack((centre[0] + r * s * ux, centre[1] + r * s * uy, centre[2] + zsign * r * np.cos(ang)))


def local_points(points, column_x: float = 0.0) -> np.ndarray:
    """A field's points as plate-local (x, y, depth >= 0); a single column
    (every point at x = y = 0) moved to x = column_x."""
    p = np.asarray(points, dtype=float)
    if p.shape[1] == 2:
        p = np.column_stack((p, np.zeros(len(p))))
    q = np.column_stack((p[:, 0], p[:, 1], np.abs(p[:, 2])))
    column = len(q) > 0 and not np.any(q[:, 0]) and not np.any(q[:, 1])
    if column:
        q[:, 0] = column_x
    return q


def mirror_section(points: np.ndarray, cells):
    """An r >= 0 section and its mirror image at -r (one field, twice the cells)."""
    n = len(points)
    mirrored = points.copy()
    mirrored[:, 0] *= -1.0
    pts = np.vstack((points, mirrored))
    out = []
    for kind, conn in cells:
        conn = np.asarray(conn)
        out.append((kind, conn))
        out.append((kind, conn[:, ::-1] + n if kind in ("triangle", "quad", "polygon") else conn + n))
    return pts, out


def place_field(side: str, fld, geom, params, vals: dict):
    """(points, cells, T) of a plate's field in world coordinates at the
    frame whose CSV values are ``vals`` (xg_m, u_m, z_m, s1_m, s2_m)."""
    points, cells, T = fld
    T = np.asarray(T, dtype=float)
    model = params.model
    if getattr(params, "source", "follow-pad") == "fixed-point":
        cx = params.radius_m
    else:
        cx = vals.get("s1_m", 0.0) if side == "lower" else -vals.get("s2_m", 0.0)
    q = local_points(points, cx)
    if model == "axisym":
        q, cells = mirror_section(q, cells)
        T = np.concatenate((T, T))          # nodal or per cell: the mirror repeats both in order
    xg = vals.get("xg_m", 0.0)
    if side == "lower":
        world = _wrap(q, (xg, 0.0, geom.R1), geom.R1, up=False)
    else:
        apex = (xg + vals.get("u_m", 0.0), geom.pad_height + vals.get("z_m", 0.0))
        if geom.kind == "DFP":
            world = _wrap(q, (apex[0], 0.0, apex[1] - geom.R2), geom.R2, up=True)
        else:
            world = np.column_stack((apex[0] + q[:, 0], q[:, 1], apex[1] + q[:, 2]))
    return world, cells, T


# -- the TFP's four parts ------------------------------------------------------------
def _e(x):
    return np.array([-math.sin(x), math.cos(x)])


def surface_centres(g, xg: float, phi: float, alpha: float):
    """Centres (x, z) of S1..S4 at the pose (xg, phi, alpha)."""
    C1 = np.array([xg, g.R1])
    C2 = C1 - g.l1 * _e(phi)
    C3 = C2 - g.Li * _e(phi + alpha)
    C4 = C3 - g.l4 * _e(phi)
    return C1, C2, C3, C4


def place_part_field(i: int, fld, g, params, vals: dict):
    """(points, cells, T) of part i's field (0..3: lower plate, lower slider,
    upper slider, upper plate; plate-local coordinates, as above)
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
