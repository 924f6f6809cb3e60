"""The paper's lumped plate, Eq. (9)-(10): c T' = P - H (T - T_air).

c = c_s M_i (steel specific heat times the plate mass, the paper's choice of
M_i as the whole plate), H = h_s A_i (A_i: ``exchange_area_m2``, by default
the plate's top face). With the power P held over a step the ODE is solved
exactly: T_{n+1} = T_eq + (T_n - T_eq) exp(-H dt / c), T_eq = T_air + P / H.
"""
from __future__ import annotations

import math

from .params import PlateParams


class LumpedPlate:
    """One plate as a single temperature (implements the PlateModel interface)."""

    def __init__(self, params: PlateParams, dt: float):
        self.params = params
        self.dt = dt
        self.C = params.c * params.mass                   # J/K, c_i
        area = params.exchange_area_m2 or math.pi * params.plate_radius ** 2
        self.H = params.h_conv * area                      # W/K, H_i
        self.T_air = params.T_air_C
        self.T0 = params.T0_C
        self.rise = 0.0          # T - T0: kept as a rise so round-off scales with it, not with T
        self._in = 0.0
        self._lost = 0.0
        x = self.H * dt / self.C
        self._decay = -math.expm1(-x)                      # 1 - exp(-H dt / c), exact for small x

    def step(self, power_W: float, centre_m: float = 0.0) -> float:
        """Advance dt with power P (W); exact exponential update. Returns T (degC)."""
        if self.H > 0.0:
            rise_eq = self.T_air - self.T0 + power_W / self.H
            dT = (rise_eq - self.rise) * self._decay
        else:
            dT = power_W * self.dt / self.C
        q = power_W * self.dt
        self._in += q
        self._lost += q - self.C * dT
        self.rise += dT
        return self.T0 + self.rise

    @property
    def T(self) -> float:
        return self.T0 + self.rise

    def surface_temperature(self) -> float:
        return self.T0 + self.rise

    def stored_heat(self) -> float:
        return self.C * self.rise

    def heat_lost(self) -> float:
        return self._lost

    def heat_in(self) -> float:
        return self._in

    def save(self):
        return (self.rise, self._in, self._lost)

    def restore(self, snap) -> None:
        self.rise, self._in, self._lost = snap

    def field(self):
        return None
