"""1D mesh through a plate's thickness, graded toward the sliding face."""
from __future__ import annotations

import numpy as np


def graded_nodes(thickness: float, n: int, grading: float) -> np.ndarray:
    """Node depths 0 = z_0 < ... < z_n = thickness, element sizes h_i = h_0 g^i.

    Depth 0 is the sliding face, where the friction flux enters and the
    temperature gradient is steepest, so the smallest element sits there.
    ``grading`` = 1 gives a uniform mesh.
    """
    if n < 1:
        raise ValueError(f"n_elements must be >= 1, got {n}")
    if not grading > 0:
        raise ValueError(f"grading must be > 0, got {grading}")
    h = grading ** np.arange(n, dtype=float)
    z = np.concatenate(([0.0], np.cumsum(h)))
    z *= thickness / z[-1]
    z[-1] = thickness
    return z


def line_mesh(thickness: float, n: int, grading: float):
    """The same nodes as a scikit-fem ``MeshLine`` (coordinate = depth)."""
    from skfem import MeshLine

    return MeshLine(graded_nodes(thickness, n, grading))
