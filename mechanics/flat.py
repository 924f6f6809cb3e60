"""The flat double friction bearing of the paper's Fig. 2 (the "inspiring
physical observation"): a rigid cylinder of diameter D and height H between
two flat plates, the superstructure on top, no restoring force.

Sliding mobilises the friction force f at the faces (the weaker face slides:
f = min(mu2 N, mu1 (N + m g)) quasi-statically), whose couple f H about the
trailing bottom corner is resisted by the load N on the diagonally opposite top
corner (arm D) and the pad's own weight (arm D/2); docs/model.md section 7:

    the pad tips when  f H > N D + m g D / 2,  i.e. (top face sliding, f = mu N)
    mu > mu_tip = (D / H) (1 + m g / (2 N)).

Below that the normal forces shift towards the corners and the pad slides
without turning (the paper's Fig. 2e); above it the overturning moment only
grows with the tilt, so the run stops with a MechanicsFailure naming the
couple and the resisting moment. Each step checks the dynamic version (the
pad's d'Alembert force m a at H/2 included): tip_ratio = |f_top H - m a H/2| /
(N D + m g D/2) > 1.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import flat_kernel as K
from .geometry import G_ACC
from .ground_motion import float_array
from .protocol import TwoInterfaces
from .seated import SLIP, STICK, MechanicsFailure

COLUMNS = ("t_s", "xg_m", "u_m", "v_mps", "F_N", "s1_m", "s2_m", "N1_N", "N2_N", "W1_J", "W2_J",
           "phase", "E_input_J", "E_kin_J", "E_pot_J", "tip_ratio")


@dataclass(frozen=True)
class FlatGeometry:
    pad_height: float
    pad_diameter: float
    pad_mass: float
    mass: float
    g: float = G_ACC
    kind: str = "flat"

    @property
    def a(self) -> float:
        return 0.5 * self.pad_diameter

    @property
    def contact_area(self) -> float:
        return math.pi * self.a ** 2

    @property
    def weight(self) -> float:
        return self.mass * self.g

    def resisting_moment(self, N_top: float) -> float:
        """N D + m g D / 2 about the trailing bottom corner (N m)."""
        return N_top * self.pad_diameter + self.pad_mass * self.g * self.pad_diameter / 2.0

    def mu_tip(self, mu_lower: float | None = None) -> float:
        """Closed-form tipping threshold of the top face's mu (quasi-static, pad
        moving with the lower plate); inf when the lower face slides first
        (mu_lower (N + m g) < that threshold times N)."""
        N = self.weight
        mu = self.pad_diameter / self.pad_height * (1.0 + self.pad_mass * self.g / (2.0 * N))
        if mu_lower is not None and mu_lower * (N + self.pad_mass * self.g) < mu * N:
            return math.inf
        return mu


class PadTipped(MechanicsFailure):
    pass


class FlatStepper(TwoInterfaces):
    """Flat bearing under a ground motion or in the test machine (two interfaces:
    the coupled loop of coupling/run.py drives it like the DFP steppers)."""

    columns = COLUMNS

    def __init__(self, geom: FlatGeometry, loading):
        self.geom = geom
        self.dt = loading.dt
        self.n_steps = loading.n_steps
        self.machine = hasattr(loading, "u")
        if self.machine:
            self._u, self._ud = float_array(loading.u), float_array(loading.ud)
            self._a = float_array(-np.diff(loading.ud) / loading.dt)
        else:
            self._a, self._xg = float_array(loading.a_step), float_array(loading.d)
        self.par = np.array([geom.pad_mass, geom.mass])
        self.st = np.zeros(4)
        self.out = np.zeros(K.N_OUT)
        self._w = np.zeros(2)
        self.n, self.t, self.F = 0, 0.0, 0.0
        self.N2 = geom.weight
        self.N1 = geom.weight + geom.pad_mass * geom.g
        self.W1 = self.W2 = 0.0
        self.E_in = 0.0
        self.phase = STICK
        self.tip = 0.0
        self.slip_v1 = self.slip_v2 = 0.0
        if self.machine and self._ud[0] != 0.0:
            self.st[3] = self._ud[0]          # launched on the top face; its kinetic energy is input
            self.E_in = self.E_kin

    @property
    def s1(self) -> float:
        return float(self.st[0])

    @property
    def s2(self) -> float:
        return float(self.st[1])

    @property
    def E_kin(self) -> float:
        return K.kinetic(self.par, float(self.st[2]), float(self.st[3]))

    def xg(self) -> float:
        return -self._u[self.n] if self.machine else self._xg[self.n]

    def ledger_residual(self) -> float:
        return self.E_in - (self.E_kin + self.W1 + self.W2)

    def values(self) -> tuple:
        st = self.st
        return (self.t, self.xg(), float(st[0] + st[1]), float(st[2] + st[3]), self.F, float(st[0]), float(st[1]),
                self.N1, self.N2, self.W1, self.W2, self.phase, self.E_in, self.E_kin, 0.0, self.tip)

    def save(self):
        return (self.n, self.t, self.st.copy(), self.F, self.W1, self.W2, self.E_in, self.phase, self.tip,
                self.slip_v1, self.slip_v2)

    def restore(self, snap) -> None:
        (self.n, self.t, st, self.F, self.W1, self.W2, self.E_in, self.phase, self.tip,
         self.slip_v1, self.slip_v2) = snap
        self.st[:] = st

    def step(self, mu1: float, mu2: float) -> tuple:
        g, n, dt = self.geom, self.n, self.dt
        ag = self._a[n]
        o = self.out
        c1, c2 = mu1 * self.N1, mu2 * self.N2
        if self.machine:
            K.step(self.par, self.st, dt, ag, c1, c2, 1, self._u[n + 1], self._ud[n + 1], o, self._w)
            self.F = float(o[K.O_F])
        else:
            K.step(self.par, self.st, dt, ag, c1, c2, 0, 0.0, 0.0, o, self._w)
            # the bearing's force on the superstructure, against u: the top face's friction
            self.F = float(o[K.O_FTOP])
        dW1, dW2 = float(o[K.O_W1]), float(o[K.O_W2])
        self.W1 += dW1
        self.W2 += dW2
        self.E_in += float(o[K.O_EIN])
        H = g.pad_height
        demand = abs(H * float(o[K.O_FTOP]) - 0.5 * H * g.pad_mass * float(o[K.O_APAD]))
        self.tip = demand / g.resisting_moment(self.N2)
        dq1, dq2 = float(o[K.O_DQ1]), float(o[K.O_DQ2])
        self.phase = SLIP if (dq1 != 0.0 or dq2 != 0.0) else STICK
        self.slip_v1, self.slip_v2 = abs(dq1) / dt, abs(dq2) / dt
        self.n = n + 1
        self.t = self.n * dt
        if self.tip > 1.0:
            raise PadTipped(f"the pad tips: friction couple {demand:.4g} N m > N D + m g D/2 = "
                            f"{g.resisting_moment(self.N2):.4g} N m (closed form: mu > {g.mu_tip():.4g})")
        return dW1, dW2
