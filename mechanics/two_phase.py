"""The paper's two-phase rigid-body stepper for the planar DFP (model.md section 3).

Every step t_n -> t_n+1 starts and ends seated (geometrically compatible) and
is split as in the paper's Fig. 8:

- phase 1 (first ASRB): stick trial against the combined friction cap, then
  either the rocking check of Eq. (7) about the trailing bottom corner (stick),
  or slip: the superstructure moves along the seated tangent at theta_n under
  its own equation of motion with the capped friction; the pad pivots on the
  trailing bottom corner (A, or B on reversal) by beta1, the rotation that keeps
  the opposite top corner (C, or D) on the upper surface; the plates then fix
  C1C2(t_n+1) and so theta_n+1;
- phase 2 (second ASRB): the pad re-seats (centroid along C1C2, counter-rotation
  beta2), RB3+4 closes |C1C2| to L, the interfaces slide by R_i |d theta| (the
  friction work, counted once) and the velocities are projected, mass-weighted,
  onto the seated tangent at theta_n+1 (the kinetic energy removed is E_reseat).

A pad that tips (tilt) rocks on its corner by Eq. (7), the superstructure riding
on the opposite top corner, until it lands; the landing is the phase-2 impact.

Energies are relative to the ground (the ground acceleration enters as the
d'Alembert force -m a_g on every moving mass); docs/two_phase.md has the
derivations, the choices the paper leaves open and the measured numbers.
The step itself is mechanics/two_phase_kernel.py, written once for the
pure and the compiled path; the class holds its state vector.
"""
from __future__ import annotations

import math

from .geometry import DeviceGeometry
from fpd.loading.ground_motion import GroundMotion, as_float64, float_array
from . import two_phase_kernel as K
from .protocol import TwoInterfaces
from .phases import DIAGONAL_AC, DIAGONAL_BD, SLIP, STICK, PadOverturned  # noqa: F401
from .two_phase_kernel import rocking_acceleration  # noqa: F401  (Eq. 7, used by the tests)

COLUMNS = (
    "t_s", "xg_m", "u_m", "v_mps", "F_N", "z_m", "theta_rad", "beta_rad",
    "s1_m", "s2_m", "N1_N", "N2_N", "W1_J", "W2_J", "phase",
    "E_input_J", "E_kin_J", "E_pot_J", "E_reseat_J",
    # diagnostics of the two-phase step
    "beta1_rad", "beta2_rad", "pad_tilt_rad", "diagonal", "ds1_m", "ds2_m",
    "Ff1_N", "Ff2_N", "theta_dot_radps", "slip1_m", "slip2_m", "tip_ratio",
)

def seated_normal_forces(geom: DeviceGeometry, theta: float, theta_dot: float,
                         a_g: float) -> tuple[float, float]:
    """Normal forces N1 (lower) and N2 (upper) of the seated device (model.md 2).

    Both act along the pad axis through the centres C1, C2; the centripetal
    terms are those of the superstructure (radius L) and pad centroid (rho).
    A negative value (lift-off) is clipped to 0: no tension across a contact.
    """
    c, s = math.cos(theta), math.sin(theta)
    g_axis = geom.g * c - a_g * s
    w2 = theta_dot * theta_dot
    N2 = geom.mass * (g_axis + geom.L * w2)
    N1 = N2 + geom.pad_mass * (g_axis + geom.rho * w2)
    return max(N1, 0.0), max(N2, 0.0)


def corner_pivot_rotation(a: float, eta_bottom: float, eta_top: float, h: float,
                          R2: float, shift: float) -> float:
    """Phase-1 rotation beta1 of the pad about its trailing bottom corner.

    Pad frame at theta_n (origin at the bottom apex, axis up): pivot A at
    (-a, eta_bottom), top corner C at (+a, eta_top), upper-surface centre
    C2 = (0, h - R2) moved by ``shift`` = L * dtheta along the seated tangent
    (+x here). beta1 (counter-clockwise) brings C back onto the upper surface
    |C - C2'| = R2: with p = A - C2', r = C - A the condition reads
    P (cos b - 1) + Q sin b = D, P = p.r, Q = p x r, D = a shift - shift^2/2,
    solved in tan(b/2) by the root that vanishes with the shift (no
    cancellation for tiny steps). Reversal (shift < 0) mirrors to B-D.
    """
    S = [0.0] * K.N_STATE
    beta = K.corner_pivot_rotation(S, a, eta_bottom, eta_top, h, R2, shift)
    if S[K.ERR] != 0.0:
        raise ZeroDivisionError("float division by zero")
    return beta


def pivot_chain(geom: DeviceGeometry, theta: float, diagonal: int) -> tuple:
    """The phase-1 chain of Eq. (7) about a bottom corner, seated at theta.

    Pivot A with top corner C (diagonal 0) or B with D (diagonal 1). The pad
    (m, J, centroid G) rotates about the pivot; RB3+4 rides on the top corner
    as a particle of mass M there (model.md: Eq. (7) as printed holds only
    then, since a revolute joint at C cannot supply the couple that stops a
    finite RB3+4 from rotating). Returns (I_P, X0, Z0, rGx, rGz, rQx, rQz):
    the inertia about the pivot and the first moments m r_G + M r_Q (world
    frame, at beta = 0) with the arms r_G = G - P, r_Q = Q - P.
    """
    corners = geom.pad_corners_body()
    if diagonal == DIAGONAL_AC:
        (pxi, peta), (qxi, qeta) = corners["A"], corners["C"]
    else:
        (pxi, peta), (qxi, qeta) = corners["B"], corners["D"]
    gxi, geta = 0.0, geom.pad_centroid_height
    c, s = math.cos(theta), math.sin(theta)

    def arm(xi: float, eta: float) -> tuple[float, float]:
        dxi, deta = xi - pxi, eta - peta
        return c * dxi - s * deta, s * dxi + c * deta

    rGx, rGz = arm(gxi, geta)
    rQx, rQz = arm(qxi, qeta)
    m, M = geom.pad_mass, geom.mass
    I_P = geom.pad_inertia + m * (rGx * rGx + rGz * rGz) + M * (rQx * rQx + rQz * rQz)
    X0 = m * rGx + M * rQx
    Z0 = m * rGz + M * rQz
    return I_P, X0, Z0, rGx, rGz, rQx, rQz


def rocking_threshold(geom: DeviceGeometry, theta: float = 0.0) -> float:
    """Ground acceleration (m/s2) beyond which a stuck pad, seated at theta,
    rocks on its trailing corner A: g X0 / Z0 of Eq. (7), ~ (2a/h) g."""
    _, X0, Z0 = pivot_chain(geom, theta, DIAGONAL_AC)[:3]
    return geom.g * X0 / Z0


def sliding_threshold(geom: DeviceGeometry, mu1: float, mu2: float) -> float:
    """Ground acceleration (m/s2) beyond which the centred device at rest
    slides: S a = mu1 N1 R1 + mu2 N2 R2 (the stick trial's bound)."""
    N1, N2 = seated_normal_forces(geom, 0.0, 0.0, 0.0)
    return (mu1 * N1 * geom.R1 + mu2 * N2 * geom.R2) / geom.S


def leading_corner_tipping_ratio(geom: DeviceGeometry, mu1: float, mu2: float) -> float:
    """Overturning over restoring moment of a sliding pad about its leading
    bottom corner (B for motion to +x): the capped friction F_c at the height
    h' of the top corners against the vertical load over the width 2a,
    F_c h' / (N2 2a). Above 1 the friction couple would tip the sliding pad
    forwards, which this model (pivot on the trailing corner) does not
    represent. It exceeds 1 exactly when a stuck pad can rock at all
    (rocking_threshold < sliding_threshold): docs/two_phase.md section 6."""
    N1, N2 = seated_normal_forces(geom, 0.0, 0.0, 0.0)
    F_c = (mu1 * N1 * geom.R1 + mu2 * N2 * geom.R2) / geom.L
    c = geom.pad_corners_body()
    return F_c * (c["C"][1] - c["A"][1]) / (N2 * 2.0 * geom.a)


def two_phase_validity_errors(geom: DeviceGeometry, mu1: float, mu2: float) -> list:
    """Reasons the two-phase model does not describe this device and friction,
    as (key, value, what is allowed), after geometry_errors()."""
    out = []
    ratio = leading_corner_tipping_ratio(geom, mu1, mu2)
    if ratio >= 1.0:
        out.append(("friction.mu", max(mu1, mu2),
                    f"small enough that the friction couple cannot tip the sliding pad "
                    f"on its leading corner (F_c h' / (N 2a) = {ratio:.3g} >= 1)"))
    return out


_kstep = K.step
assert (K.SN, K.ERR) == (0, 34)


def _slot(i: int, doc: str, kind=float):
    """A stepper attribute that is slot i of the state vector S."""
    if kind is float:
        return property(lambda self: self.S[i], lambda self, v: self.S.__setitem__(i, v), doc=doc)
    return property(lambda self: kind(self.S[i]), lambda self, v: self.S.__setitem__(i, kind(v)), doc=doc)


# TwoPhaseStepper.save(): (name, slot, type); the chain (8 slots) follows "beta_dot"
_SAVED = (("n", K.SN, int), ("theta", K.TH, float), ("theta_dot", K.THD, float), ("mode", K.MODE, int),
          ("diagonal", K.DIAG, int), ("rocking", K.ROCK, bool), ("beta", K.BETA, float),
          ("beta_dot", K.BETAD, float), ("_chain", K.CH, None), ("W1", K.W1, float), ("W2", K.W2, float),
          ("E_input", K.EIN, float), ("E_reseat", K.ERS, float), ("beta1", K.B1, float),
          ("beta2", K.B2, float), ("pad_tilt", K.PTILT, float), ("ds1", K.DS1, float),
          ("ds2", K.DS2, float), ("slip1", K.SL1, float), ("slip2", K.SL2, float), ("Ff1", K.FF1, float),
          ("Ff2", K.FF2, float), ("F", K.FF, float), ("N1", K.N1, float), ("N2", K.N2, float),
          ("slip_v1", K.SV1, float), ("slip_v2", K.SV2, float))


class TwoPhaseStepper(TwoInterfaces):
    """Paper's two-phase stepper; implements the Stepper protocol (architecture.md).

    ``theta0``/``theta_dot0``: initial seated state (default at rest, centred).
    The state is the list ``S`` (layout in two_phase_kernel) that the step
    reads and writes; the attributes below are views of its slots. ``C``
    holds the per-step constants.
    """

    columns = COLUMNS

    n = _slot(K.SN, "steps taken", int)
    theta = _slot(K.TH, "seated angle theta (rad)")
    theta_dot = _slot(K.THD, "theta' (rad/s)")
    mode = _slot(K.MODE, "phase of the last step (STICK, SLIP, TILT)", int)
    diagonal = _slot(K.DIAG, "loaded diagonal (DIAGONAL_AC, DIAGONAL_BD)", int)
    rocking = _slot(K.ROCK, "the pad pivots on a bottom corner", bool)
    beta = _slot(K.BETA, "rocking angle (rad)")
    beta_dot = _slot(K.BETAD, "rocking rate (rad/s)")
    W1 = _slot(K.W1, "friction work, lower interface (J)")
    W2 = _slot(K.W2, "friction work, upper interface (J)")
    E_input = _slot(K.EIN, "energy input (J)")
    E_reseat = _slot(K.ERS, "kinetic energy removed by re-seating and landing (J)")
    beta1 = _slot(K.B1, "phase-1 pivot rotation of the last step (rad)")
    beta2 = _slot(K.B2, "phase-2 counter-rotation of the last step (rad)")
    pad_tilt = _slot(K.PTILT, "pad tilt of the last step (rad)")
    ds1 = _slot(K.DS1, "arc slid on the lower plate in the last step (m)")
    ds2 = _slot(K.DS2, "arc slid on the upper plate in the last step (m)")
    slip1 = _slot(K.SL1, "cumulative sliding path, lower (m)")
    slip2 = _slot(K.SL2, "cumulative sliding path, upper (m)")
    Ff1 = _slot(K.FF1, "friction force, lower interface (N)")
    Ff2 = _slot(K.FF2, "friction force, upper interface (N)")
    F = _slot(K.FF, "horizontal force of the bearing (N)")
    N1 = _slot(K.N1, "normal force, lower interface (N)")
    N2 = _slot(K.N2, "normal force, upper interface (N)")
    slip_v1 = _slot(K.SV1, "slip speed, lower interface (m/s)")
    slip_v2 = _slot(K.SV2, "slip speed, upper interface (m/s)")

    def __init__(self, geom: DeviceGeometry, ground: GroundMotion,
                 theta0: float = 0.0, theta_dot0: float = 0.0):
        if geom.kind != "DFP":
            raise ValueError(f"device.kind = {geom.kind!r}: the two-phase model needs a DFP")
        self.geom = geom
        self.ground = ground
        self.dt = float(ground.dt)
        self.n_steps = int(ground.n_steps)
        self._t = float_array(ground.t)
        self._d = float_array(ground.d)
        self._a_step = float_array(ground.a_step)
        self.C = C = [0.0] * K.N_CONST
        C[K.CL], C[K.CRHO], C[K.CI], C[K.CS] = geom.L, geom.rho, geom.I, geom.S
        C[K.CM], C[K.Cm], C[K.CJ], C[K.CG] = geom.mass, geom.pad_mass, geom.pad_inertia, geom.g
        C[K.CR1], C[K.CR2] = geom.R1, geom.R2
        c = geom.pad_corners_body()
        C[K.CA:K.CR2C + 1] = (geom.a, c["A"][1], c["C"][1], geom.pad_height, geom.R2)
        C[K.CHC] = c["C"][1] - c["A"][1]                  # h' = eta_t - eta_b
        # kinetic-energy weight of the translating parts (superstructure, pad centroid)
        C[K.CIT] = geom.mass * geom.L ** 2 + geom.pad_mass * geom.rho ** 2
        C[K.CDT], C[K.TWO], C[K.CGA] = self.dt, 2.0, geom.a
        # the phase-1 chains of Eq. (7) in the pad frame, A-C and B-D
        C[K.CBC:K.CBC + 7] = pivot_chain(geom, 0.0, DIAGONAL_AC)
        C[K.CBC + 7:K.CBC + 14] = pivot_chain(geom, 0.0, DIAGONAL_BD)

        self.S = S = [0.0] * K.N_STATE
        self._row = [0.0] * K.N_VALUES
        S[K.SN] = 0
        S[K.TH], S[K.THD] = float(theta0), float(theta_dot0)
        S[K.MODE] = STICK if theta_dot0 == 0.0 else SLIP
        S[K.DIAG] = DIAGONAL_AC if theta_dot0 >= 0.0 else DIAGONAL_BD
        # an initial displacement or velocity is energy put in before t = 0
        S[K.EIN] = self.kinetic_energy() + self.potential_energy()
        a0 = self._a_step[0] if self._a_step else 0.0
        S[K.N1], S[K.N2] = seated_normal_forces(geom, self.theta, self.theta_dot, a0)
        S[K.SV1] = geom.R1 * abs(self.theta_dot)
        S[K.SV2] = geom.R2 * abs(self.theta_dot)

    # ------------------------------------------------------------------
    # protocol
    # ------------------------------------------------------------------
    @property
    def s1(self) -> float:
        """Footprint arc position on the lower plate, R1 theta (m)."""
        return self.C[K.CR1] * self.S[K.TH]

    @property
    def s2(self) -> float:
        """Footprint arc position on the upper plate, R2 theta (m)."""
        return self.C[K.CR2] * self.S[K.TH]

    def step(self, mu1: float, mu2: float) -> tuple[float, float]:
        """Advance one step with mu1, mu2 held; return the friction work (J)
        of the lower and upper interface in the step."""
        S = self.S
        if S[0] >= self.n_steps:                     # S[K.SN]
            raise IndexError(f"all {self.n_steps} steps of the loading are taken")
        dW = _kstep(self.C, S, self._a_step, mu1, mu2)
        if S[34] != 0.0:                             # S[K.ERR]
            self.raise_error()
        return dW

    # -- the compiled engine (coupling/engine_kernel.py) ----------------------------
    engine_device = "fpd.mechanics.dev_two_phase"

    def engine_state(self):
        """(C, S, L, X) as the engine reads them: float64 copies of the
        constants and state, the loading (a_step, t, d), no scratch."""
        import numpy as np
        f = (lambda x: np.asarray(x, dtype=float))
        return (f(self.C), f(self.S), (as_float64(self._a_step), as_float64(self._t), as_float64(self._d)),
                (np.zeros(1),))

    def engine_pull(self, S) -> None:
        """The state into the engine's copy (before a chunk)."""
        S[:] = self.S

    def engine_push(self, S, n: int) -> None:
        """The engine's copy back (after a chunk; the step count is in S)."""
        self.S[:] = S.tolist()

    def raise_error(self) -> None:
        """The exception the step's error flag S[ERR] stands for."""
        S = self.S
        if S[K.ERR] == K.ERR_OVERTURNED:
            raise PadOverturned(f"pad overturned at t = {self._t[int(S[K.SN])]:.6g} s "
                                f"(beta = {S[K.ERRV]:.4g} rad)")
        raise ZeroDivisionError("float division by zero")

    def values(self) -> tuple:
        """Current values of ``columns`` (phase and diagonal as int codes)."""
        out = self._row
        K.values(self.C, self.S, self._t, self._d, out)
        out[14], out[22] = int(out[14]), int(out[22])
        return tuple(out)

    def tip_ratio(self) -> float:
        """Forward-tipping ratio of the last step: tangential force carried to
        the superstructure times the corner height h' over N2 2a. Above 1 the
        friction couple would tip the pad on its leading corner, outside what
        this model represents (docs/two_phase.md section 6, item 5)."""
        return self.values()[30]

    @property
    def u(self) -> float:
        """Relative displacement of the superstructure (m)."""
        return self.values()[2]

    @property
    def _chain(self):
        """The rocking chain (I_P, X0, Z0, rGx, rGz, rQx, rQz, sign), None when seated."""
        return tuple(self.S[K.CH:K.CH + 8]) if self.S[K.ROCK] else None

    def save(self) -> tuple:
        S = self.S
        out = []
        for _, i, kind in _SAVED:
            if kind is None:
                out.append(tuple(S[K.CH:K.CH + 8]) if S[K.ROCK] else None)
            else:
                out.append(kind(S[i]))
        return tuple(out)

    def restore(self, snap: tuple) -> None:
        S = self.S
        for (_, i, kind), v in zip(_SAVED, snap):
            if kind is None:
                S[K.CH:K.CH + 8] = v if v is not None else (0.0,) * 8
            else:
                S[i] = v
        S[K.ERR] = S[K.ERRV] = 0.0

    # ------------------------------------------------------------------
    # energies (ground frame)
    # ------------------------------------------------------------------
    def kinetic_energy(self) -> float:
        """Relative kinetic energy: I theta'^2 / 2 seated, I_P beta'^2 / 2 rocking."""
        K.values(self.C, self.S, self._t, self._d, self._row)
        return self._row[16]

    def potential_energy(self) -> float:
        """g (M z_s + m z_G) above the centred seated device: S g (1 - cos theta)
        seated, plus the rise of the rocking chain's first moment."""
        K.values(self.C, self.S, self._t, self._d, self._row)
        return self._row[17]

    def energy_residual(self) -> float:
        """E_input - (E_kin + E_pot + W1 + W2 + E_reseat) (J): the ledger."""
        return self.E_input - (self.kinetic_energy() + self.potential_energy()
                               + self.W1 + self.W2 + self.E_reseat)
