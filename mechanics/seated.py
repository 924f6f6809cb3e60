"""The seated reference model (model.md section 2): one DOF theta.

    I theta'' + S a_g cos(theta) + S g sin(theta) = -(mu1 N1 R1 + mu2 N2 R2) sgn(theta')
    N2 = M (g cos(theta) - a_g sin(theta) + L theta'^2)
    N1 = N2 + m (g cos(theta) - a_g sin(theta) + rho theta'^2)

with I = M L^2 + m rho^2 + J and S = M L + m rho (mechanics.geometry).

Time stepping (docs/model.md, "Seated model: discretisation"): a Moreau-type
scheme. Friction enters as an impulse with lambda in Sgn(theta'_{n+1}), so a
step either sticks exactly (theta' = 0, no chatter, no regularisation) or
slides with the full cap; positions advance with the trapezoidal rule and
gravity is evaluated by the discrete gradient sin(theta_m) sinc(dtheta / 2),
so that the potential energy change of a step is exact. Second order while
sliding, first order at stick-slip transitions.

The step of SeatedStepper is mechanics/seated_kernel.py (kernel module,
written once); SeatedTestMachine's imposed-displacement step is below.

Energies are those of the ground frame (relative energy formulation):
E_input is the work of the ground acceleration's d'Alembert forces through
the relative motion, E_kin = I theta'^2 / 2, E_pot = S g (1 - cos theta).
"""
from __future__ import annotations

import math

from .geometry import DeviceGeometry
from . import seated_kernel as K
from .ground_motion import float_array

from .protocol import TwoInterfaces
from .phases import PHASES, SLIP, STICK, TILT, MechanicsFailure  # noqa: F401

SEATED_COLUMNS = ("t_s", "xg_m", "u_m", "v_mps", "F_N", "z_m", "theta_rad",
                  "s1_m", "s2_m", "N1_N", "N2_N", "W1_J", "W2_J", "phase",
                  "E_input_J", "E_kin_J", "E_pot_J")


class _SeatedBase(TwoInterfaces):
    columns = SEATED_COLUMNS

    def __init__(self, geom: DeviceGeometry, dt: float, n_steps: int):
        self.geom = geom
        self.dt = dt
        self.n_steps = n_steps
        self.n = 0
        self.t = 0.0
        self.theta = 0.0
        self.theta_dot = 0.0
        self.F = 0.0
        self.N1 = self.N2 = geom.mass * geom.g
        self.N1 += geom.pad_mass * geom.g
        self.W1 = self.W2 = 0.0
        self.E_input = 0.0
        self.mode = STICK
        self.slip_v1 = self.slip_v2 = 0.0
        # constants as plain floats for the hot loop
        self._I, self._S = geom.I, geom.S
        self._L, self._M, self._m = geom.L, geom.mass, geom.pad_mass
        self._rho, self._g = geom.rho, geom.g
        self._R1, self._R2 = geom.R1, geom.friction_radius2

    # -- derived outputs ---------------------------------------------------
    @property
    def s1(self) -> float:
        """Arc position of the footprint on the lower plate, R1 theta (m)."""
        return self._R1 * self.theta

    @property
    def s2(self) -> float:
        """Arc slid on the upper plate, R2 theta (m) (0 for the SFP)."""
        return self._R2 * self.theta

    @property
    def u(self) -> float:
        return self._L * math.sin(self.theta)

    @property
    def E_kin(self) -> float:
        return 0.5 * self._I * self.theta_dot ** 2

    @property
    def E_pot(self) -> float:
        return self._S * self._g * (1.0 - math.cos(self.theta))

    def kinetic_energy(self) -> float:
        return self.E_kin

    def potential_energy(self) -> float:
        return self.E_pot

    def energy_residual(self) -> float:
        """E_input - (E_kin + E_pot + W1 + W2) (J): the ledger."""
        return self.E_input - (self.E_kin + self.E_pot + self.W1 + self.W2)

    # former names (before both steppers shared one set): kept for callers
    ledger_residual = energy_residual
    thetad = property(lambda self: self.theta_dot, lambda self, v: setattr(self, "theta_dot", v))
    E_in = property(lambda self: self.E_input, lambda self, v: setattr(self, "E_input", v))
    phase = property(lambda self: self.mode, lambda self, v: setattr(self, "mode", v))

    def save(self):
        return (self.n, self.t, self.theta, self.theta_dot, self.F, self.N1, self.N2,
                self.W1, self.W2, self.E_input, self.mode, self.slip_v1, self.slip_v2)

    def restore(self, snap) -> None:
        (self.n, self.t, self.theta, self.theta_dot, self.F, self.N1, self.N2,
         self.W1, self.W2, self.E_input, self.mode, self.slip_v1, self.slip_v2) = snap

    def values(self) -> tuple:
        th, L = self.theta, self._L
        return (self.t, self.xg(), L * math.sin(th), L * math.cos(th) * self.theta_dot,
                self.F, L * (1.0 - math.cos(th)), th, self._R1 * th, self._R2 * th,
                self.N1, self.N2, self.W1, self.W2, self.mode, self.E_input,
                0.5 * self._I * self.theta_dot ** 2,
                self._S * self._g * (1.0 - math.cos(th)))


def _slot(i: int, kind=float):
    """A SeatedStepper attribute that is slot i of its state vector S."""
    if kind is float:
        return property(lambda self: self.S[i], lambda self, v: self.S.__setitem__(i, v))
    return property(lambda self: kind(self.S[i]), lambda self, v: self.S.__setitem__(i, kind(v)))


class SeatedStepper(_SeatedBase):
    """Seated DFP/SFP under an imposed ground motion (mechanics.ground_motion.GroundMotion).

    The step is mechanics/seated_kernel.py (written once); the state is the
    list ``S`` it reads and writes, the attributes are views of its slots."""

    n, t, theta, theta_dot = _slot(K.SN, int), _slot(K.ST), _slot(K.TH), _slot(K.THD)
    F, N1, N2, W1, W2 = _slot(K.SF), _slot(K.N1), _slot(K.N2), _slot(K.W1), _slot(K.W2)
    E_input, mode = _slot(K.EIN), _slot(K.MODE, int)
    slip_v1, slip_v2 = _slot(K.SV1), _slot(K.SV2)

    def __init__(self, geom: DeviceGeometry, ground, iterations: int = 3):
        self.S = [0.0] * K.N_STATE
        super().__init__(geom, ground.dt, ground.n_steps)
        self.ground = ground
        self._a_step = float_array(ground.a_step)  # plain floats, 8 bytes each
        self._xg = ground.d
        self._iters = iterations
        self.C = C = [0.0] * K.N_CONST
        C[K.CDT], C[K.CI], C[K.CS], C[K.CL] = self.dt, self._I, self._S, self._L
        C[K.CM], C[K.Cm], C[K.CRHO], C[K.CG] = self._M, self._m, self._rho, self._g
        C[K.CR1], C[K.CR2], C[K.CITER], C[K.TWO] = self._R1, self._R2, iterations, 2.0
        self._row = [0.0] * K.N_VALUES

    def xg(self) -> float:
        return float(self._xg[self.n])

    def step(self, mu1: float, mu2: float) -> tuple[float, float]:
        return K.step(self.C, self.S, self._a_step, mu1, mu2)

    def values(self) -> tuple:
        out = self._row
        K.values(self.C, self.S, float(self._xg[int(self.S[K.SN])]), out)
        out[13] = int(out[13])
        return tuple(out)

    def save(self):
        S = self.S
        return (int(S[0]),) + tuple(S[1:K.MODE]) + (int(S[K.MODE]),) + tuple(S[K.MODE + 1:])

    def restore(self, snap) -> None:
        self.S[:] = snap


class SeatedTestMachine(_SeatedBase):
    """Seated DFP/SFP in a bearing-test machine: the relative displacement
    u(t) is imposed (mechanics.ground_motion.DisplacementProgramme), the
    superstructure is held horizontally and rides up and down under its
    weight. F_N is the horizontal force of the restraint, from

        F L cos(theta) = I theta'' - S u'' cos(theta) + S g sin(theta) + cap sgn(theta')

    with the normal forces increased by the restraint's axial share F sin(theta).

    ``vertical``: "constant" (default) - the machine's actuator holds the
    vertical load at M g (force control, as a real rig): the riding mass has
    no inertia, only its weight, so I and the inertial S lose M L^2 and M L and
    N2 = M g cos(theta) + F sin(theta); "riding-mass" - the superstructure mass
    M rides up and down under its weight (its vertical inertia adds to the
    normal forces: M (g cos + u'' sin + L theta'^2)).
    """

    VERTICAL = ("constant", "riding-mass")

    def __init__(self, geom: DeviceGeometry, programme, vertical: str = "constant"):
        super().__init__(geom, programme.dt, programme.n_steps)
        if vertical not in self.VERTICAL:
            raise ValueError(f"vertical must be one of {self.VERTICAL}, got {vertical!r}")
        self.vertical = vertical
        self._Sin, self._Mv = self._S, 1.0           # inertial S and the riding mass's inertia factor
        if vertical == "constant":
            self._I = self._I - self._M * self._L ** 2
            self._Sin, self._Mv = self._S - self._M * self._L, 0.0
        self.prog = programme
        self._u = float_array(programme.u)
        self._ud = float_array(programme.ud)
        self._udd = float_array(programme.udd)
        # grid points where the machine has stopped the bearing: the step that
        # reaches the first of them ends with the stopping impulse (below)
        uds = programme.ud if programme.ud_smooth is None else programme.ud_smooth
        udds = programme.udd if programme.udd_smooth is None else programme.udd_smooth
        self._smooth = {i: (float(a), float(b)) for i, (a, b) in
                        enumerate(zip(uds, udds)) if a != programme.ud[i] or b != programme.udd[i]}
        self.theta = math.asin(self._u[0] / self._L)
        self.theta_dot = self._ud[0] / (self._L * math.cos(self.theta))
        # the machine launches the programme with u'(0) != 0: that energy is input
        self.E_input = self.E_kin + self.E_pot

    def xg(self) -> float:
        return -self._u[self.n]

    def _state_at(self, i: int, mu1: float, mu2: float, sgn: float, smooth=None):
        """theta, theta', F, N1, N2 at grid point i (u'' known); ``smooth`` =
        (u', u'') of the programme's smooth branch instead of the grid values."""
        L, I, S, g, M, m, rho = self._L, self._I, self._S, self._g, self._M, self._m, self._rho
        u, ud, udd = self._u[i], self._ud[i], self._udd[i]
        if smooth is not None:
            ud, udd = smooth
        th = math.asin(u / L)
        c, s = math.cos(th), math.sin(th)
        thd = ud / (L * c)
        thdd = (udd + L * s * thd * thd) / (L * c)
        N2_0 = M * (g * c + self._Mv * (udd * s + L * thd * thd))
        N1_0 = N2_0 + m * (g * c + udd * s + rho * thd * thd)
        cap0 = mu1 * N1_0 * self._R1 + mu2 * N2_0 * self._R2
        k = mu1 * self._R1 + mu2 * self._R2
        A = I * thdd - self._Sin * udd * c + S * g * s
        F = (A + sgn * cap0) / (L * c - sgn * s * k)
        return th, thd, thdd, F, N1_0 + F * s, N2_0 + F * s, c

    def step(self, mu1: float, mu2: float) -> tuple[float, float]:
        i0, i1 = self.n, self.n + 1
        th0 = self.theta
        th1 = math.asin(self._u[i1] / self._L)
        dth = th1 - th0
        sgn = 1.0 if dth > 0 else (-1.0 if dth < 0 else 0.0)
        # friction work with the normal forces averaged over the step
        _, _, _, Fa, N1a, N2a, ca = self._state_at(i0, mu1, mu2, sgn)
        th, thd, thdd, F, N1, N2, c = self._state_at(i1, mu1, mu2, sgn)
        adth = abs(dth)
        dW1 = mu1 * 0.5 * (N1a + N1) * self._R1 * adth
        dW2 = mu2 * 0.5 * (N2a + N2) * self._R2 * adth
        # ground-frame input: the restraint's generalised force plus the
        # d'Alembert force of the moving lower plate (trapezoidal in theta)
        Q0 = (Fa * self._L + self._Sin * self._udd[i0]) * ca
        stop = self._smooth.get(i1) if i0 not in self._smooth else None
        if stop is None:
            Q1 = (F * self._L + self._Sin * self._udd[i1]) * c
            self.E_input += 0.5 * (Q0 + Q1) * dth
        else:
            # the machine stops the bearing inside this step: the smooth
            # branch's input up to the stop, then the stopping impulse, whose
            # work is the kinetic energy it removes (at fixed position)
            _, thd_s, _, F_s, _, _, _ = self._state_at(i1, mu1, mu2, sgn, stop)
            Q1 = (F_s * self._L + self._Sin * stop[1]) * c
            self.E_input += 0.5 * (Q0 + Q1) * dth + 0.5 * self._I * (thd * thd - thd_s * thd_s)
        self.theta, self.theta_dot, self.F, self.N1, self.N2 = th, thd, F, N1, N2
        self.W1 += dW1
        self.W2 += dW2
        self.mode = SLIP if dth != 0.0 else STICK
        self.slip_v1 = self._R1 * adth / self.dt
        self.slip_v2 = self._R2 * adth / self.dt
        self.n = i1
        self.t = i1 * self.dt
        return dW1, dW2
