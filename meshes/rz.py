"""Axisymmetric r-z meshes of a plate section, built or read from a file.

Coordinates: r in [0, R], depth z in [-t, 0], sliding face at z = 0 (with the
face at z = 0 scikit-fem's FacetBasis stays well conditioned on the thin
quads of a graded mesh). Boundaries: ``top`` (z = 0, the sliding face),
``bottom`` (z = -t), ``outer`` (r = R), ``axis`` (r = 0).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from fpd.meshes.line import graded_nodes

BOUNDARIES = ("top", "bottom", "outer", "axis")
REQUIRED = ("top", "bottom", "outer")     # the axis carries no condition (r = 0)


def radial_nodes(R: float, nr: int, band_r: float | None = None,
                 band_fraction: float = 0.75) -> np.ndarray:
    """Radii 0..R: uniform over the band [0, band_r] the footprint sweeps
    (``band_fraction`` of the elements), then growing geometrically to R with
    the first outer element as large as a band element."""
    if nr < 1:
        raise ValueError(f"nr must be >= 1, got {nr}")
    if band_r is None or band_r >= R or nr < 4:
        return np.linspace(0.0, R, nr + 1)
    n_in = max(1, min(nr - 1, int(round(band_fraction * nr))))
    n_out = nr - n_in
    h = band_r / n_in
    rest = R - band_r
    if rest <= n_out * h:            # the band spacing already suffices
        return np.concatenate((np.linspace(0, band_r, n_in + 1),
                               np.linspace(band_r, R, n_out + 1)[1:]))
    lo, hi = 1.0, 2.0
    total = lambda g: h * sum(g ** i for i in range(1, n_out + 1))
    while total(hi) < rest:
        hi *= 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if total(mid) < rest else (lo, mid)
    g = 0.5 * (lo + hi)
    out = band_r + h * np.cumsum(g ** np.arange(1, n_out + 1))
    out[-1] = R
    return np.concatenate((np.linspace(0, band_r, n_in + 1), out))


def footprint_radial_nodes(R: float, a: float, per_radius: int, sweep: float = -1.0) -> np.ndarray:
    """The automatic radial mesh (thermal.nr = 0): elements of a / per_radius
    over the band [0, sweep + a] the footprint covers (the whole radius when
    sweep < 0: it may go anywhere), then growing by 10 % per element to R."""
    from fpd.meshes.box import banded_nodes

    band = R if sweep < 0 else min(R, sweep + a)
    return banded_nodes(R, band, a / per_radius)


def elements_per_radius(R: float, a: float, nr: int) -> float:
    """Elements per footprint radius of the uniform mesh of nr elements."""
    return nr * a / R


def depth_nodes(thickness: float, nz: int, grading: float) -> np.ndarray:
    """z from -t to 0, graded toward the sliding face (as meshes.line)."""
    return -graded_nodes(thickness, nz, grading)[::-1].copy()


def _named(mesh, tol: float):
    r, z = mesh.p
    R, zmin = r.max(), z.min()
    return mesh.with_boundaries({
        "top": lambda x: np.abs(x[1]) < tol,
        "bottom": lambda x: np.abs(x[1] - zmin) < tol,
        "outer": lambda x: np.abs(x[0] - R) < tol,
        "axis": lambda x: np.abs(x[0]) < tol,
    })


def rz_mesh(R: float, thickness: float, nr: int, nz: int, grading: float = 1.0,
            band_r: float | None = None, band_fraction: float = 0.75, triangles: bool = False,
            r_nodes: np.ndarray | None = None):
    """Structured quad (or triangle) mesh of the section, named boundaries.
    ``r_nodes``: the radii to use (0..R) instead of radial_nodes(R, nr, ...).

    Nodes are numbered through the thickness first, so the matrix bandwidth
    is nz + 2 and a sparse LU has little fill."""
    from skfem import MeshQuad, MeshTri

    r = radial_nodes(R, nr, band_r, band_fraction) if r_nodes is None else np.asarray(r_nodes, dtype=float)
    z = depth_nodes(thickness, nz, grading)
    mesh = (MeshTri if triangles else MeshQuad).init_tensor(r, z)
    return _named(mesh, 1e-9 * max(R, thickness))


def _boundary_cells(m, name: str) -> list[np.ndarray]:
    """Line cells (node pairs) of the set ``name`` in a meshio mesh, from
    cell_sets, gmsh:physical tags with field_data names, or meshio's VTU
    encoding of cell sets."""
    pairs = []
    if name in m.cell_sets:
        for block, idx in zip(m.cells, m.cell_sets[name]):
            if block.type == "line" and idx is not None and len(idx):
                pairs.append(block.data[np.asarray(idx)])
    if not pairs and name in m.field_data:
        tag = int(np.atleast_1d(m.field_data[name])[0])
        phys = m.cell_data.get("gmsh:physical")
        if phys is not None:
            for block, tags in zip(m.cells, phys):
                if block.type == "line":
                    sel = np.asarray(tags) == tag
                    if sel.any():
                        pairs.append(block.data[sel])
    if not pairs:
        # meshio writes cell_sets to VTU as one integer cell_data array named
        # "top-bottom-..." whose value is the index of the set's name
        for key, data in m.cell_data.items():
            names = key.split("-")
            if name in names and key != "gmsh:physical":
                tag = names.index(name)
                for block, tags in zip(m.cells, data):
                    if block.type == "line":
                        sel = np.asarray(tags).ravel() == tag
                        if sel.any():
                            pairs.append(block.data[sel])
    return pairs


def read_rz_mesh(path):
    """Read a user's r-z plate mesh from any file meshio reads.

    The 2D cells (triangles or quads, first coordinate r, second z, the
    sliding face at the top) become a scikit-fem mesh; the boundaries are the
    line cells of the sets named top, bottom, outer (required) and axis
    (optional). Raises ValueError with one line naming the file and what is
    missing.
    """
    import meshio
    from skfem import MeshQuad, MeshTri

    path = Path(path)
    try:
        m = meshio.read(path)
    except Exception as exc:  # meshio raises many types for unreadable files
        raise ValueError(f"{path}: cannot read mesh ({exc})") from None
    kinds = [b.type for b in m.cells]
    if "quad" in kinds:
        kind, cls = "quad", MeshQuad
    elif "triangle" in kinds:
        kind, cls = "triangle", MeshTri
    else:
        raise ValueError(f"{path}: no triangle or quad cells (found {sorted(set(kinds))})")
    t = np.concatenate([b.data for b in m.cells if b.type == kind])
    used = np.unique(t)
    renum = np.full(len(m.points), -1)
    renum[used] = np.arange(len(used))
    pts = np.asarray(m.points)[used, :2]
    if pts[:, 0].min() < -1e-12 * max(1.0, np.ptp(pts[:, 0])):
        raise ValueError(f"{path}: negative radius (first coordinate must be r >= 0)")
    t = renum[t]
    # counter-clockwise cells (shoelace sign), whatever the writer's convention
    x, y = pts[t, 0], pts[t, 1]
    area2 = np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)
    t[area2 < 0] = t[area2 < 0, ::-1]
    mesh = cls(pts.T.copy(), t.T.copy())
    facet_of = {tuple(sorted(f)): i for i, f in enumerate(mesh.facets.T)}
    boundaries, missing = {}, []
    for name in BOUNDARIES:
        pairs = _boundary_cells(m, name)
        if not pairs:
            if name in REQUIRED:
                missing.append(name)
            continue
        idx = []
        for a, b in renum[np.concatenate(pairs)]:
            f = facet_of.get((min(a, b), max(a, b)))
            if f is None:
                raise ValueError(f"{path}: boundary '{name}' has a line cell that is not a facet of the 2D cells")
            idx.append(f)
        boundaries[name] = np.unique(np.array(idx, dtype=np.int64))
    if missing:
        raise ValueError(f"{path}: missing boundary line cell set(s) {', '.join(missing)} "
                         f"(name them top, bottom, outer, axis)")
    return cls(mesh.p, mesh.t, _boundaries=boundaries)
