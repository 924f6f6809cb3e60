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

Both steps are machines/seated_kernel.py (kernel module, written once):
SeatedStepper's ``step``, SeatedTestMachine's imposed-displacement
``machine_step`` (the one the compiled engine calls,
machines/dev_seated_machine.py).

Energies are those of the ground frame (relative energy formulation):
E_input is the work of the ground acceleration's d'Alembert forces through
the relative motion, E_kin = I theta'^2 / 2, E_pot = S g (1 - cos theta).
"""
from __future__ import annotations

import math

import numpy as np

from fpd.mechanics.geometry import DeviceGeometry
from . import link_kernel as LK
from . import seated_kernel as K
from fpd.loading.ground_motion import as_float64, float_array

from fpd.mechanics.protocol import TwoInterfaces
from fpd.mechanics.phases import PHASES, SEATED_COLUMNS, SLIP, STICK, TILT, MechanicsFailure  # noqa: F401



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


def _slot(i: int, kind=float):
    """A SeatedStepper attribute that is slot i of its state vector S."""
    if kind is float:
        return property(lambda self: self.S[i], lambda self, v: self.S.__setitem__(i, v))
    return property(lambda self: kind(self.S[i]), lambda self, v: self.S.__setitem__(i, kind(v)))


class _SeatedState(_SeatedBase):
    """A seated stepper whose state is the list ``S`` of machines/seated_kernel.py
    (the attributes are views of its slots) and whose constants are the list ``C``."""

    n, t, theta, theta_dot = _slot(K.SN, int), _slot(K.ST), _slot(K.TH), _slot(K.THD)
    F, N1, N2, W1, W2 = _slot(K.SF), _slot(K.N1), _slot(K.N2), _slot(K.W1), _slot(K.W2)
    E_input, mode = _slot(K.EIN), _slot(K.MODE, int)
    slip_v1, slip_v2 = _slot(K.SV1), _slot(K.SV2)

    def __init__(self, geom: DeviceGeometry, dt: float, n_steps: int):
        self.S = [0.0] * K.N_STATE
        super().__init__(geom, dt, n_steps)
        self._row = [0.0] * K.N_VALUES

    def constants(self, iterations: int = 0) -> list:
        """The kernel's constants C (a list) from the stepper's floats."""
        C = [0.0] * K.N_CONST
        C[K.CDT], C[K.CI], C[K.CS], C[K.CL] = self.dt, self._I, self._S, self._L
        C[K.CM], C[K.Cm], C[K.CRHO], C[K.CG] = self._M, self._m, self._rho, self._g
        C[K.CR1], C[K.CR2], C[K.CITER], C[K.TWO] = self._R1, self._R2, iterations, 2.0
        return C

    def values(self) -> tuple:
        out = self._row
        K.values(self.C, self.S, self.xg(), out)
        out[13] = int(out[13])
        return tuple(out)

    def save(self):
        S = self.S
        return (int(S[0]),) + tuple(S[1:K.MODE]) + (int(S[K.MODE]),) + tuple(S[K.MODE + 1:])

    def restore(self, snap) -> None:
        self.S[:] = snap


class SeatedStepper(_SeatedState):
    """Seated DFP/SFP under an imposed ground motion (loading.ground_motion.GroundMotion).

    The step is machines/seated_kernel.py (written once); the state is the
    list ``S`` it reads and writes, the attributes are views of its slots."""

    def __init__(self, geom: DeviceGeometry, ground, iterations: int = 3):
        super().__init__(geom, ground.dt, ground.n_steps)
        self.ground = ground
        self._a_step = float_array(ground.a_step)  # plain floats, 8 bytes each
        self._xg = ground.d
        self._iters = iterations
        self.C = self.constants(iterations)

    def xg(self) -> float:
        return float(self._xg[self.n])

    def step(self, mu1: float, mu2: float) -> tuple[float, float]:
        return K.step(self.C, self.S, self._a_step, mu1, mu2)


class SeatedTestMachine(_SeatedState):
    """Seated DFP/SFP in a bearing-test machine: the relative displacement
    u(t) is imposed (loading.ground_motion.DisplacementProgramme), the
    superstructure is held horizontally and rides up and down under its
    weight. F_N is the horizontal force of the restraint, from

        F L cos(theta) = I theta'' - S u'' cos(theta) + S g sin(theta) + cap sgn(theta')

    with the normal forces increased by the restraint's axial share F sin(theta).

    ``vertical``: "constant" (default) - the machine's actuator holds the
    vertical load at M g (force control, as a real rig): the riding mass has
    no inertia, only its weight, so I and the inertial S lose M L^2 and M L and
    N2 = M g cos(theta) + F sin(theta); "riding-mass" - the superstructure mass
    M rides up and down under its weight (its vertical inertia adds to the
    normal forces: M (g cos + u'' sin + L theta'^2)); "sine", "series" - an
    axial-load programme N(t) held in force control (``axial``, a
    loading.axial.AxialProgramme): as "constant" with M g replaced by N(t)
    in the normal forces and the restoring moment N L sin(theta); the
    vertical actuator's work beyond the weight's is input to the ledger.
    """

    VERTICAL = ("constant", "riding-mass", "sine", "series")

    def __init__(self, geom: DeviceGeometry, programme, vertical: str = "constant", axial=None):
        super().__init__(geom, programme.dt, programme.n_steps)
        if vertical not in self.VERTICAL:
            raise ValueError(f"vertical must be one of {self.VERTICAL}, got {vertical!r}")
        if (vertical in ("sine", "series")) != (axial is not None and axial.varying):
            raise ValueError(f"vertical = {vertical!r} needs its axial-load programme (and only it)")
        self.vertical = vertical
        self.axial = axial
        self._Sin, self._Mv = self._S, 1.0           # inertial S and the riding mass's inertia factor
        if vertical != "riding-mass":
            self._I = self._I - self._M * self._L ** 2
            self._Sin, self._Mv = self._S - self._M * self._L, 0.0
        self.prog = programme
        self._u = float_array(programme.u)
        self._ud = float_array(programme.ud)
        self._udd = float_array(programme.udd)
        # grid points where the machine has stopped the bearing (SM[i] = 1, the
        # programme's smooth branch there in UDS, UDDS): the step that reaches the
        # first of them ends with the stopping impulse (seated_kernel.machine_step)
        uds = programme.ud if programme.ud_smooth is None else programme.ud_smooth
        udds = programme.udd if programme.udd_smooth is None else programme.udd_smooth
        self._sm = float_array((np.asarray(uds, dtype=float) != np.asarray(programme.ud, dtype=float))
                               | (np.asarray(udds, dtype=float) != np.asarray(programme.udd, dtype=float)))
        self._uds, self._udds = float_array(uds), float_array(udds)
        # the axial-load programme per grid point over M (g throughout when held at M g)
        if axial is not None and axial.varying:
            self._gv = float_array(axial.at(np.asarray(programme.t, dtype=float)) / self._M)
        else:
            self._gv = float_array(np.full(len(programme.t), self._g))
        self.N2 = self._M * self._gv[0]
        self.N1 = self.N2 + self._m * self._g
        self.C = C = self.constants()
        C[K.CSIN], C[K.CMV] = self._Sin, self._Mv
        self.theta = math.asin(self._u[0] / self._L)
        self.theta_dot = self._ud[0] / (self._L * math.cos(self.theta))
        # the machine launches the programme with u'(0) != 0: that energy is input
        self.E_input = self.E_kin + self.E_pot

    def xg(self) -> float:
        return -self._u[self.n]

    LINK_STEP = 0.02      # omega h per sub-step of the compliant link (velocity Verlet: phase error ~ (omega h)^2 / 24)

    def set_link(self, stiffness: float, plate_mass: float) -> None:
        """Drive the plate through a compliant link (link_kernel.seated_link_step):
        a spring of ``stiffness`` (N/m) between the machine and the plate of
        mass ``plate_mass`` (kg); the bearing starts at rest at the programme's
        start. Sub-steps keep omega h <= LINK_STEP, omega the link's frequency
        with the bearing's restoring stiffness and inertia at u = 0."""
        C = self.C
        C[K.CLINK], C[K.CMPL] = float(stiffness), float(plate_mass)
        gv = float(self._gv[0])
        B = K.machine_point(C, 0.0, 0.0, 1.0, gv, 0.0, 0.0, 0.0)[3]
        Kb = K.machine_point(C, 1e-6 * self._L, 0.0, 0.0, gv, 0.0, 0.0, 0.0)[3] / (1e-6 * self._L)
        m = plate_mass + B
        if not m > 0.0:
            raise ValueError(f"the plate's mass with the bearing's ({m:g} kg) must be > 0")
        omega = math.sqrt((stiffness + Kb) / m)
        C[K.CNSUB] = float(max(1, math.ceil(self.dt * omega / self.LINK_STEP)))
        self.theta_dot = 0.0
        self.E_input = self.E_kin + self.E_pot

    def set_static(self, mu_s1: float, mu_s2: float, ratio1: float = 0.0, ratio2: float = 0.0) -> None:
        """The static (breakaway) coefficients of the lower and upper interface,
        and as ratios to the sliding mu at rest (0: none; seated_kernel CMUS1,
        CMUS2, CMUR1, CMUR2)."""
        self.C[K.CMUS1], self.C[K.CMUS2] = float(mu_s1), float(mu_s2)
        self.C[K.CMUR1], self.C[K.CMUR2] = float(ratio1), float(ratio2)

    def set_dwell(self, lower: tuple, upper: tuple) -> None:
        """The static coefficients' growth with the time stuck, per interface
        (mu_s after a long dwell, time constant tau in s, exponent; tau = 0:
        none): seated_kernel CMUI1.., friction_kernel.dwell_mu."""
        C = self.C
        C[K.CMUI1], C[K.CTAU1], C[K.CEXP1] = (float(x) for x in lower)
        C[K.CMUI2], C[K.CTAU2], C[K.CEXP2] = (float(x) for x in upper)

    def step(self, mu1: float, mu2: float) -> tuple[float, float]:
        return LK.seated_machine_step(self.C, self.S, self._u, self._ud, self._udd, self._sm, self._uds,
                                      self._udds, self._gv, mu1, mu2)

    # -- the compiled engine (coupling/engine_kernel.py) ----------------------------
    engine_device = "fpd.machines.dev_seated_machine"

    def engine_state(self):
        """(C, S, L, X) as the engine reads them: float64 copies of the
        constants and state, the programme (u, u', u'', the stop marks and
        the smooth branch's u', u'' per grid point, the axial load over M), no scratch."""
        f = (lambda x: np.asarray(x, dtype=float))
        L = tuple(as_float64(x) for x in (self._u, self._ud, self._udd, self._sm, self._uds, self._udds,
                                          self._gv))
        return f(self.C), f(self.S), L, (np.zeros(1),)

    def engine_pull(self, S) -> None:
        """The state into the engine's copy (before a chunk)."""
        S[:] = self.S

    def engine_push(self, S, n: int) -> None:
        """The engine's copy back (after a chunk; the step count is in S)."""
        self.S[:] = S.tolist()
