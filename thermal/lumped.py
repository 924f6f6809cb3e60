"""The paper's lumped plate, Eq. (9)-(10): c T' = P - H (T - T_air).

c = c_s M_i (steel specific heat times the plate mass, the paper's choice of
M_i as the whole plate), H = h_s A_i (A_i: ``exchange_area_m2``, by default
the plate's top face). The step (exact for the power held over a step) is
thermal/lumped_kernel.py; this class holds its row ``P``.
"""
from __future__ import annotations

import math

from . import lumped_kernel as K
from .params import PlateParams


def _slot(i, doc):
    return property(lambda self: self.P[i], lambda self, v: self.P.__setitem__(i, v), doc=doc)


class LumpedPlate:
    """One plate as a single temperature (implements the PlateModel interface)."""

    C = _slot(K.P_C, "heat capacity c_i (J/K)")
    H = _slot(K.P_H, "exchange conductance H_i (W/K)")
    T_air = _slot(K.P_TAIR, "air temperature (degC)")
    T0 = _slot(K.P_T0, "initial temperature (degC)")
    rise = _slot(K.P_RISE, "T - T0 (K)")

    def __init__(self, params: PlateParams, dt: float):
        self.params = params
        self.dt = dt
        self.P = P = [0.0] * K.N_P
        P[K.P_C] = params.c * params.mass                    # J/K, c_i
        area = params.exchange_area_m2 or math.pi * params.plate_radius ** 2
        P[K.P_H] = params.h_conv * area                      # W/K, H_i
        P[K.P_TAIR] = params.T_air_C
        P[K.P_T0] = params.T0_C
        P[K.P_DT] = dt
        x = P[K.P_H] * dt / P[K.P_C]
        P[K.P_DECAY] = -math.expm1(-x)                       # 1 - exp(-H dt / c), exact for small x

    def step(self, power_W: float, centre_m: float = 0.0) -> float:
        """Advance dt with power P (W); exact exponential update. Returns T (degC)."""
        return K.step(self.P, power_W)

    @property
    def T(self) -> float:
        return self.P[K.P_T0] + self.P[K.P_RISE]

    def surface_temperature(self) -> float:
        return self.P[K.P_T0] + self.P[K.P_RISE]

    def stored_heat(self) -> float:
        return K.stored(self.P)

    def heat_lost(self) -> float:
        return self.P[K.P_LOST]

    def heat_in(self) -> float:
        return self.P[K.P_IN]

    def save(self):
        P = self.P
        return (P[K.P_RISE], P[K.P_IN], P[K.P_LOST])

    def restore(self, snap) -> None:
        self.P[K.P_RISE], self.P[K.P_IN], self.P[K.P_LOST] = snap

    def field(self):
        return None
