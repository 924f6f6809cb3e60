"""Node sets that resolve the pad's footprint: uniform over the band the
footprint sweeps, graded beyond it (axisym r, fe3d x and y), and the
tensor-product box of the fe3d plate.

fe3d plate-local coordinates (docs/thermal.md, section 8): origin at the
plate centre on the sliding face, x along the path (arc position), y across
it in the face, z the depth into the steel (positive into the plate).
"""
from __future__ import annotations

import math

import numpy as np

from fpd.meshes.line import graded_nodes

GROWTH = 1.1          # size ratio of neighbouring elements beyond the band


def banded_nodes(length: float, band: float, h: float, growth: float = GROWTH) -> np.ndarray:
    """Nodes 0..length: uniform of size <= h over [0, band], then elements
    growing by ``growth`` (the first one of size h) up to ``length``; the last
    graded element is stretched or merged so the nodes end at ``length``."""
    if not (length > 0 and h > 0):
        raise ValueError(f"length and h must be > 0, got {length}, {h}")
    band = min(max(band, 0.0), length)
    n_in = max(1, math.ceil(band / h - 1e-9)) if band > 0 else 0
    inner = np.linspace(0.0, band, n_in + 1) if n_in else np.zeros(1)
    out = [band]
    step = h
    while out[-1] < length - 1e-12 * length:
        step *= growth
        out.append(out[-1] + step)
    out = np.array(out[1:])
    if len(out):
        out[-1] = length
        if len(out) > 1 and (out[-1] - out[-2]) < 0.5 * (out[-2] - (out[-3] if len(out) > 2 else band)):
            out = np.delete(out, -2)                 # a sliver at the end: merge it
    nodes = np.concatenate((inner, out))
    nodes[-1] = length
    return nodes


def symmetric_nodes(half: float, band: float, h: float, growth: float = GROWTH) -> np.ndarray:
    """Nodes -half..half, symmetric about 0: banded_nodes mirrored."""
    right = banded_nodes(half, band, h, growth)
    return np.concatenate((-right[:0:-1], right))


def box_side(plate_radius: float) -> float:
    """Side of the square with the disk plate's area (sqrt(pi) R): the fe3d box
    keeps the plate's mass and exposed face area (its curvature and round rim
    are neglected)."""
    return math.sqrt(math.pi) * plate_radius


def box_nodes(plate_radius: float, thickness: float, a: float, per_radius: int, nz: int, grading: float,
              band_y: float | None = None):
    """x, y, z nodes of the fe3d box.

    x (along the path): uniform at a / per_radius over the whole side (the
    footprint may reach any arc position). y: uniform over |y| <= band_y
    (default a, a planar path; a bidirectional path passes its reach + a),
    graded beyond. z: depth 0..thickness graded toward the sliding face as
    the fe1d column (meshes/line.py)."""
    half = 0.5 * box_side(plate_radius)
    h = a / per_radius
    n = max(2, math.ceil(2 * half / h - 1e-9))
    x = np.linspace(-half, half, n + 1)
    y = symmetric_nodes(half, min(half, band_y if band_y else a), h)
    z = graded_nodes(thickness, nz, grading)
    return x, y, z


def hex_mesh(x: np.ndarray, y: np.ndarray, z: np.ndarray):
    """(points (n, 3), hexahedra (m, 8)) of the tensor grid, node (i, j, k) at
    index (i * ny + j) * nz + k (the fe3d state's order), VTK hexahedron
    corner order."""
    nx, ny, nz = len(x), len(y), len(z)
    X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
    pts = np.column_stack((X.ravel(), Y.ravel(), Z.ravel()))
    idx = np.arange(nx * ny * nz).reshape(nx, ny, nz)
    c = [idx[:-1, :-1, :-1], idx[1:, :-1, :-1], idx[1:, 1:, :-1], idx[:-1, 1:, :-1],
         idx[:-1, :-1, 1:], idx[1:, :-1, 1:], idx[1:, 1:, 1:], idx[:-1, 1:, 1:]]
    cells = np.stack([ci.ravel() for ci in c], axis=1)
    return pts, cells
