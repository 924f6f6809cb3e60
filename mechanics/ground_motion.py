"""Loadings on the solver's time grid: ground motion and the test machine."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class GroundMotion:
    """Horizontal ground (lower plate) motion sampled on the solver grid.

    ``t``, ``d``, ``v``, ``a`` have n_steps + 1 entries (t_n = n dt);
    ``a_step[n] = (v[n+1] - v[n]) / dt`` is the exact mean acceleration over
    step n of the piecewise-linear acceleration history (what the steppers
    use, so that any dt sees the same ground velocity at the grid points).
    """

    name: str
    dt: float
    t: np.ndarray
    d: np.ndarray
    v: np.ndarray
    a: np.ndarray
    a_step: np.ndarray

    @property
    def n_steps(self) -> int:
        return len(self.t) - 1
