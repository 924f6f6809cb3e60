"""Friction laws mu(T, p, v) per interface (paper Eq. 8: F_mu = mu(T) N).

Each law is a small callable ``law(T_C, p_Pa, v_mps) -> mu`` evaluated once
per step at the surface temperature the thermal model returns.
"""
from __future__ import annotations

import bisect
import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Constant:
    mu: float

    def __call__(self, T_C: float, p_Pa: float = 0.0, v_mps: float = 0.0) -> float:
        return self.mu


@dataclass(frozen=True)
class Linear:
    """mu = mu0 + slope (T - T0), never below mu_min."""

    mu0: float
    T0_C: float = 20.0
    slope_per_C: float = 0.0
    mu_min: float = 0.0

    def __call__(self, T_C: float, p_Pa: float = 0.0, v_mps: float = 0.0) -> float:
        return max(self.mu_min, self.mu0 + self.slope_per_C * (T_C - self.T0_C))


@dataclass(frozen=True)
class Kumar2015:
    """Kumar, Whittaker and Constantinou (2015), mu = mu_ref k_p k_T k_v with
    k_p = 0.70^((p - p_ref) / 50 MPa), k_T = 0.79 (0.70^(T / 50 C) + 0.40),
    k_v = 1 - 0.5 exp(-a v). Each factor can be switched off (then 1).
    k_T is 1.00 at 20 C and falls to 0.70 at 100 C, 0.45 at 250 C."""

    mu_ref: float
    p_ref_MPa: float = 50.0
    a_s_per_m: float = 100.0
    use_pressure: bool = False
    use_temperature: bool = True
    use_velocity: bool = False

    def __call__(self, T_C: float, p_Pa: float = 0.0, v_mps: float = 0.0) -> float:
        mu = self.mu_ref
        if self.use_pressure:
            mu *= 0.70 ** ((p_Pa * 1e-6 - self.p_ref_MPa) / 50.0)
        if self.use_temperature:
            mu *= 0.79 * (0.70 ** (T_C / 50.0) + 0.40)
        if self.use_velocity:
            mu *= 1.0 - 0.5 * math.exp(-self.a_s_per_m * abs(v_mps))
        return mu


@dataclass(frozen=True)
class Table:
    """Piecewise linear in T through (T_C[i], mu[i]), constant beyond the ends."""

    T_C: tuple
    mu: tuple

    def __call__(self, T_C: float, p_Pa: float = 0.0, v_mps: float = 0.0) -> float:
        T, M = self.T_C, self.mu
        if T_C <= T[0]:
            return M[0]
        if T_C >= T[-1]:
            return M[-1]
        i = bisect.bisect_right(T, T_C) - 1
        w = (T_C - T[i]) / (T[i + 1] - T[i])
        return M[i] + w * (M[i + 1] - M[i])


LAWS = {"constant": Constant, "linear": Linear, "kumar2015": Kumar2015, "table": Table}


def make_law(spec: dict):
    """A law from a validated ``[friction]`` table (keys already checked)."""
    kw = {k: v for k, v in spec.items() if k != "law"}
    if spec["law"] == "table":
        kw = {"T_C": tuple(kw["T_C"]), "mu": tuple(kw["mu"])}
    return LAWS[spec["law"]](**kw)
