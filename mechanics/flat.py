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

from fpd.tribology import rim_law

from . import flat_kernel as K
from .geometry import G_ACC
from fpd.loading.ground_motion import as_float64, float_array
from .protocol import TwoInterfaces
from .phases import STICK, MechanicsFailure

ENGINE_WORTH_STEPS = 60_000     # from here a mechanics-only run loads numba for the compiled engine
COLUMNS = ("t_s", "xg_m", "u_m", "v_mps", "F_N", "s1_m", "s2_m", "N1_N", "N2_N", "W1_J", "W2_J",
           "phase", "E_input_J", "E_kin_J", "E_pot_J", "tip_ratio")
# with a vertical ground record (model.md 10): as the DFP's (mechanics/bidirectional.py)
VERTICAL_COLUMNS = ("az_mps2", "lift_m", "n_lift", "t_flight_s", "E_land_J")
# with rims (capacities d1, d2: model.md 7), before the vertical ones
RIM_COLUMNS = ("E_rim_J", "J_rim_Ns", "n_rim1", "n_rim2")


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
        """N D + m g D / 2 about the trailing bottom corner (N m): flat_kernel's."""
        C = [0.0] * K.N_PAR
        C[K.I_MPAD], C[K.I_D], C[K.I_G] = self.pad_mass, self.pad_diameter, self.g
        return K.resisting_moment(C, N_top, self.g)

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


class MachinePastRim(MechanicsFailure):
    pass


def _slot(i: int, kind=float):
    """A FlatStepper attribute that is slot i of its state vector S."""
    return property(lambda self: kind(self.S[i]), lambda self, v: self.S.__setitem__(i, kind(v)))


class FlatStepper(TwoInterfaces):
    """Flat bearing under a ground motion or in the test machine (two interfaces:
    the coupled loop of coupling/run.py drives it like the DFP steppers).

    The step is mechanics/flat_kernel.py ``advance`` (written once, the one
    the compiled engine calls through mechanics/dev_flat.py); the state is
    the list ``S`` it reads and writes, the attributes are views of its
    slots, the constants the list ``C``."""

    columns = COLUMNS
    drawing = None            # no VTK drawing (output.vtk_every is refused for the flat bearing)
    n, t, F = _slot(K.S_N, int), _slot(K.S_T), _slot(K.S_F)
    N1, N2, W1, W2, E_in = _slot(K.S_N1), _slot(K.S_N2), _slot(K.S_W1), _slot(K.S_W2), _slot(K.S_EIN)
    phase, tip = _slot(K.S_PHASE, int), _slot(K.S_TIP)
    slip_v1, slip_v2 = _slot(K.S_SV1), _slot(K.S_SV2)

    def __init__(self, geom: FlatGeometry, loading, gz=None, rim: tuple | None = None, axial=None):
        """gz: the vertical ground motion (up) on the loading's grid, or None
        (model.md 10: every normal force, friction cap and the tipping check
        see g + a_z; g + a_z < 0 lifts the assembly off). rim: (d1, d2,
        restitution[, stiffness, damping ratio]), the capacities of the lower
        and the upper face (m, > 0), or None: unbounded plates; a stiffness
        (N/m, None: rigid) makes each rim a spring on the slip beyond its
        capacity with a dashpot 2 zeta sqrt(k m_eff), m_eff the mass a rigid
        rim's impulse sees (m on q1, m M / (m + M) on q2; model.md 7). axial: the test machine's axial-load
        programme (loading.axial.AxialProgramme) held in force control on
        the superstructure (N2 = N(t), N1 = N(t) + m g; the step's mean
        of the programme at its two grid points), or None: the weight M g."""
        self.geom = geom
        self.dt = loading.dt
        self.n_steps = loading.n_steps
        self.machine = hasattr(loading, "u")
        if self.machine:
            self._u, self._ud = float_array(loading.u), float_array(loading.ud)
            self._a = float_array(-np.diff(loading.ud) / loading.dt)
            self._xg = float_array(np.zeros(1))
        else:
            self._a, self._xg = float_array(loading.a_step), float_array(loading.d)
            self._u = self._ud = float_array(np.zeros(1))
        if gz is not None and (self.machine or gz.n_steps != loading.n_steps or gz.dt != loading.dt):
            raise ValueError("the vertical ground motion must be on the horizontal record's grid (no test machine)")
        self.ground_z = gz
        self._az = float_array(gz.a_step) if gz is not None else float_array(np.zeros(1))
        self.axial = axial if axial is not None and axial.varying else None
        if self.axial is not None:
            if not self.machine:
                raise ValueError("an axial-load programme is the test machine's")
            N = self.axial.at(np.asarray(loading.t, dtype=float))
            self._az = float_array(0.5 * (N[:-1] + N[1:]))
        self.columns = COLUMNS + (RIM_COLUMNS if rim is not None else ()) + (
            VERTICAL_COLUMNS if gz is not None else ())
        self.C = C = [0.0] * K.N_PAR
        C[K.I_MPAD], C[K.I_MSUP], C[K.I_H], C[K.I_D] = geom.pad_mass, geom.mass, geom.pad_height, geom.pad_diameter
        C[K.I_G], C[K.I_DT], C[K.I_MACH] = geom.g, self.dt, 1.0 if self.machine else 0.0
        C[K.I_VERT] = 1.0 if gz is not None else (2.0 if self.axial is not None else 0.0)
        if rim is not None:
            if not (rim[0] > 0.0 and rim[1] > 0.0 and 0.0 <= rim[2] <= 1.0):
                raise ValueError(f"rim: capacities must be > 0 and the restitution in [0, 1], not {rim}")
            C[K.I_CAP1], C[K.I_CAP2], C[K.I_REST] = float(rim[0]), float(rim[1]), float(rim[2])
            if len(rim) > 3 and rim[3]:
                if self.machine:
                    raise ValueError("a rim of finite stiffness is for a ground motion, not the test machine")
                m, M, zeta = geom.pad_mass, geom.mass, float(rim[4])
                C[K.I_KRIM] = float(rim[3])
                C[K.I_CRIM1] = rim_law.dashpot_coefficient(zeta, C[K.I_KRIM], m)
                C[K.I_CRIM2] = rim_law.dashpot_coefficient(zeta, C[K.I_KRIM], m * M / (m + M))
        self.S = [0.0] * K.N_S
        self.out = [0.0] * K.N_OUT
        self._w = [0.0] * 2
        self.N2 = geom.weight if self.axial is None else float(self.axial.at(0.0))
        self.N1 = self.N2 + geom.pad_mass * geom.g
        self.phase = STICK
        if self.machine and self._ud[0] != 0.0:
            self.S[K.S_V2] = self._ud[0]          # launched on the top face; its kinetic energy is input
            self.E_in = self.E_kin

    def set_static(self, m1: float, m2: float, r1: float, r2: float) -> None:
        """The faces' breakaway (friction_kernel.holding_mu): static coefficients
        and static ratios of the lower and the upper face, 0 where none is given.
        A face at rest at a step's start takes its cap with the holding coefficient."""
        self.C[K.I_MUS1], self.C[K.I_MUS2] = float(m1), float(m2)
        self.C[K.I_MUR1], self.C[K.I_MUR2] = float(r1), float(r2)

    @property
    def st(self) -> list:
        """(q1, q2, q1', q2'): the pad's slip on the lower plate, the superstructure's on the pad."""
        return self.S[:4]

    @property
    def s1(self) -> float:
        return float(self.S[K.S_Q1])

    @property
    def s2(self) -> float:
        return float(self.S[K.S_Q2])

    @property
    def E_kin(self) -> float:
        return K.energies(self.C, self.S)[0]

    @property
    def E_pot(self) -> float:
        return K.energies(self.C, self.S)[1]

    @property
    def E_land(self) -> float:
        return float(self.S[K.S_ELAND])

    def xg(self) -> float:
        return K.ground(self.C, self._u, self._xg, self.n)

    @property
    def E_rim(self) -> float:
        return float(self.S[K.S_ERIM])

    def ledger_residual(self) -> float:
        return self.E_in - (self.E_kin + self.E_pot + self.W1 + self.W2 + self.E_land + self.E_rim)

    def values(self) -> tuple:
        row = [0.0] * len(self.columns)
        K.values(self.C, self.S, self.xg(), row)
        row[11] = int(row[11])
        return tuple(row)

    def save(self):
        """The state's slots, the step count and the phase as ints."""
        S = self.S
        return tuple(int(x) if i in (K.S_N, K.S_PHASE) else x for i, x in enumerate(S))

    def restore(self, snap) -> None:
        self.S[:] = [float(x) for x in snap]

    def step(self, mu1: float, mu2: float) -> tuple:
        o = self.out
        if K.advance(self.C, self.S, self._a, self._az, self._u, self._ud, mu1, mu2, o, self._w) != 0.0:
            self.raise_error()
        return o[K.O_W1], o[K.O_W2]

    def raise_error(self) -> None:
        """The exception the step's error flag S[S_ERR] stands for."""
        g, S = self.geom, self.S
        if S[K.S_ERR] == K.ERR_RIM:
            raise MachinePastRim(f"the machine drove a face past its rim (s1 = {S[K.S_Q1]:.4g} m, d1 = "
                                 f"{self.C[K.I_CAP1]:.4g} m; s2 = {S[K.S_Q2]:.4g} m, d2 = {self.C[K.I_CAP2]:.4g} m)")
        raise PadTipped(f"the pad tips: friction couple {S[K.S_DEM]:.4g} N m > N D + m g D/2 = "
                        f"{K.resisting_moment(self.C, self.N2, g.g + float(S[K.S_AZ])):.4g} N m "
                        f"(closed form: mu > {g.mu_tip():.4g})")

    # -- the compiled engine (coupling/engine_kernel.py) ----------------------------
    engine_device = "fpd.mechanics.dev_flat"

    def engine_state(self):
        """(C, S, L, X) as the engine reads them: float64 copies of the
        constants and state, the loading (a per step, u, u' per grid point,
        the ground position per grid point, a_z per step) and step()'s
        scratch (out, w)."""
        f = (lambda x: np.asarray(x, dtype=float))
        return (f(self.C), f(self.S), (as_float64(self._a), as_float64(self._u), as_float64(self._ud),
                                       as_float64(self._xg), as_float64(self._az)), (np.zeros(K.N_OUT), np.zeros(2)))

    def engine_pull(self, S) -> None:
        """The state into the engine's copy (before a chunk)."""
        S[:] = self.S

    def engine_push(self, S, n: int) -> None:
        """The engine's copy back (after a chunk; the step count is in S)."""
        self.S[:] = S.tolist()

    @staticmethod
    def engine_worth_loading(n_steps: int) -> bool:
        """Loading numba and the engine (~0.7 s) pays past ~60000 steps (the Python step ~12 us, compiled ~0.5 us)."""
        return n_steps >= ENGINE_WORTH_STEPS
