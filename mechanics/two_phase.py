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
The per-step path uses plain floats and ``math`` only.
"""
from __future__ import annotations

import math

from .geometry import DeviceGeometry
from .ground_motion import GroundMotion, float_array
from .phases import DIAGONAL_AC, DIAGONAL_BD, SLIP, STICK, TILT, MechanicsFailure

COLUMNS = (
    "t_s", "xg_m", "u_m", "v_mps", "F_N", "z_m", "theta_rad", "beta_rad",
    "s1_m", "s2_m", "N1_N", "N2_N", "W1_J", "W2_J", "phase",
    "E_input_J", "E_kin_J", "E_pot_J", "E_reseat_J",
    # diagnostics of the two-phase step
    "beta1_rad", "beta2_rad", "pad_tilt_rad", "diagonal", "ds1_m", "ds2_m",
    "Ff1_N", "Ff2_N", "theta_dot_radps", "slip1_m", "slip2_m", "tip_ratio",
)

_FIXED_POINT_TOL = 1e-15   # rad, on the step increment
_FIXED_POINT_ITERS = 50


def _smallest_positive_root(c2: float, c1: float, c0: float, default: float) -> float:
    """Smallest positive root of c2 x^2 + c1 x + c0 (stable form), else default."""
    if c2 == 0.0:
        return -c0 / c1 if c1 != 0.0 and -c0 / c1 > 0.0 else default
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return default
    q = -0.5 * (c1 + math.copysign(math.sqrt(disc), c1))
    roots = [r for r in (q / c2, c0 / q if q != 0.0 else -1.0) if r > 0.0]
    return min(roots) if roots else default


class PadOverturned(MechanicsFailure):
    """The rocking pad passed the angle where gravity stops restoring it."""


def _sinc(x: float) -> float:
    """sin(x) / x, exact near 0 (used by the discrete gradients)."""
    if abs(x) < 1e-4:
        return 1.0 - x * x / 6.0
    return math.sin(x) / x


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
    e = abs(shift)
    px, pz = -a - e, eta_bottom - h + R2
    rx, rz = 2.0 * a, eta_top - eta_bottom
    P = px * rx + pz * rz
    Q = pz * rx - px * rz
    D = a * e - 0.5 * e * e
    disc = Q * Q - D * (2.0 * P + D)
    tau = D / (Q + math.sqrt(disc if disc > 0.0 else 0.0))
    beta = 2.0 * math.atan(tau)
    return beta if shift >= 0.0 else -beta


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


def rocking_acceleration(I_P: float, X: float, Z: float, a_g: float, g: float) -> float:
    """Eq. (7) specialised to the phase-1 chain: beta'' about the pivot.

    Moments about the pivot (counter-clockwise), ground acceleration a_g:
    I_P beta'' = Z a_g - X g, with X, Z the horizontal and vertical first
    moments sum m_i r_i of the pad and of RB3+4 at its corner. There is no
    beta'^2 term: |r_i| is fixed, so the centripetal forces pass through the
    pivot. The d'Alembert moment -r x (m a_g e_x) = +m r_z a_g overturns, the
    weight's -m r_x g restores.
    """
    return (Z * a_g - X * g) / I_P


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


class TwoPhaseStepper:
    """Paper's two-phase stepper; implements the Stepper protocol (architecture.md).

    ``theta0``/``theta_dot0``: initial seated state (default at rest, centred).
    """

    columns = COLUMNS

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
        # constants of the per-step path, as plain floats
        self._L, self._rho = geom.L, geom.rho
        self._I, self._S = geom.I, geom.S
        self._M, self._m, self._J = geom.mass, geom.pad_mass, geom.pad_inertia
        self._g = geom.g
        self._R1, self._R2 = geom.R1, geom.R2
        c = geom.pad_corners_body()
        self._corner = (geom.a, c["A"][1], c["C"][1], geom.pad_height, geom.R2)
        self._corner_height = c["C"][1] - c["A"][1]  # h' = eta_t - eta_b
        # the phase-1 chains of Eq. (7) in the pad frame, A-C and B-D
        self._body_chains = (pivot_chain(geom, 0.0, DIAGONAL_AC),
                             pivot_chain(geom, 0.0, DIAGONAL_BD))
        # kinetic-energy weight of the translating parts (superstructure, pad centroid)
        self._I_trans = self._M * self._L ** 2 + self._m * self._rho ** 2

        self.n = 0
        self.theta = float(theta0)
        self.theta_dot = float(theta_dot0)
        self.mode = STICK if theta_dot0 == 0.0 else SLIP
        self.diagonal = DIAGONAL_AC if theta_dot0 >= 0.0 else DIAGONAL_BD
        # rocking state: the pad pivots on a bottom corner (Eq. 7 chain)
        self.rocking = False
        self.beta = 0.0
        self.beta_dot = 0.0
        self._chain = None
        # cumulative energies (J)
        self.W1 = self.W2 = 0.0
        self.E_input = 0.0
        self.E_reseat = 0.0
        # last-step diagnostics
        self.beta1 = self.beta2 = self.pad_tilt = 0.0
        self.ds1 = self.ds2 = 0.0
        self.slip1 = self.slip2 = 0.0  # cumulative sliding path per interface (m)
        self.Ff1 = self.Ff2 = 0.0
        self.F = 0.0
        # an initial displacement or velocity is energy put in before t = 0
        self.E_input = self.kinetic_energy() + self.potential_energy()
        a0 = self._a_step[0] if self._a_step else 0.0
        self.N1, self.N2 = seated_normal_forces(geom, self.theta, self.theta_dot, a0)
        self.slip_v1 = self._R1 * abs(self.theta_dot)
        self.slip_v2 = self._R2 * abs(self.theta_dot)

    # ------------------------------------------------------------------
    # protocol
    # ------------------------------------------------------------------
    @property
    def s1(self) -> float:
        """Footprint arc position on the lower plate, R1 theta (m)."""
        return self._R1 * self.theta

    @property
    def s2(self) -> float:
        """Footprint arc position on the upper plate, R2 theta (m)."""
        return self._R2 * self.theta

    def step(self, mu1: float, mu2: float) -> tuple[float, float]:
        """Advance one step with mu1, mu2 held; return the friction work (J)
        of the lower and upper interface in the step."""
        if self.n >= self.n_steps:
            raise IndexError(f"all {self.n_steps} steps of the loading are taken")
        a = self._a_step[self.n]
        vx0 = self._horizontal_momentum()
        W1_0, W2_0 = self.W1, self.W2
        if self.rocking:
            self._tilt_step(a, self.dt, mu1, mu2)
        else:
            self._seated_step(a, self.dt, mu1, mu2, rocking_allowed=True)
        # force the bearing transmits: momentum balance of the moving parts over the step
        self.F = -((self._M + self._m) * a + (self._horizontal_momentum() - vx0) / self.dt)
        self.n += 1
        return self.W1 - W1_0, self.W2 - W2_0

    def values(self) -> tuple:
        """Current values of ``columns`` (phase and diagonal as int codes)."""
        s = self
        u, z, v = s._superstructure_relative()
        return (
            s._t[s.n], s._d[s.n], u, v, s.F, z, s.theta, s.beta1,
            s._R1 * s.theta, s._R2 * s.theta, s.N1, s.N2, s.W1, s.W2, s.mode,
            s.E_input, s.kinetic_energy(), s.potential_energy(), s.E_reseat,
            s.beta1, s.beta2, s.pad_tilt, s.diagonal, s.ds1, s.ds2, s.Ff1, s.Ff2,
            s.theta_dot, s.slip1, s.slip2, s.tip_ratio(),
        )

    def tip_ratio(self) -> float:
        """Forward-tipping ratio of the last step: tangential force carried to
        the superstructure times the corner height h' over N2 2a. Above 1 the
        friction couple would tip the pad on its leading corner, outside what
        this model represents (docs/two_phase.md section 6, item 5)."""
        if self.N2 <= 0.0:
            return 0.0
        F_t = self.Ff2 if self.mode == TILT else self.Ff1 + self.Ff2
        return abs(F_t) * self._corner_height / (self.N2 * 2.0 * self.geom.a)

    @property
    def u(self) -> float:
        """Relative displacement of the superstructure (m)."""
        return self._superstructure_relative()[0]

    _STATE = ("n", "theta", "theta_dot", "mode", "diagonal", "rocking", "beta", "beta_dot",
              "_chain", "W1", "W2", "E_input", "E_reseat", "beta1", "beta2",
              "pad_tilt", "ds1", "ds2", "slip1", "slip2", "Ff1", "Ff2", "F", "N1", "N2",
              "slip_v1", "slip_v2")

    def save(self) -> tuple:
        return tuple(getattr(self, k) for k in self._STATE)

    def restore(self, snap: tuple) -> None:
        for k, v in zip(self._STATE, snap):
            setattr(self, k, v)

    # ------------------------------------------------------------------
    # energies (ground frame) and positions
    # ------------------------------------------------------------------
    def kinetic_energy(self) -> float:
        """Relative kinetic energy: I theta'^2 / 2 seated, I_P beta'^2 / 2 rocking."""
        if self.rocking:
            return 0.5 * self._chain[0] * self.beta_dot ** 2
        return 0.5 * self._I * self.theta_dot ** 2

    def potential_energy(self) -> float:
        """g (M z_s + m z_G) above the centred seated device: S g (1 - cos theta)
        seated, plus the rise of the rocking chain's first moment."""
        E = self._S * self._g * (1.0 - math.cos(self.theta))
        if self.rocking:
            _, X0, Z0 = self._chain[:3]
            b = self.beta
            E += self._g * (math.sin(b) * X0 + (math.cos(b) - 1.0) * Z0)
        return E

    def energy_residual(self) -> float:
        """E_input - (E_kin + E_pot + W1 + W2 + E_reseat) (J): the ledger."""
        return self.E_input - (self.kinetic_energy() + self.potential_energy()
                               + self.W1 + self.W2 + self.E_reseat)

    def _horizontal_momentum(self) -> float:
        """M v_s + m v_G, horizontal, relative to the ground (kg m/s)."""
        if self.rocking:
            _, X0, Z0 = self._chain[:3]
            b = self.beta
            return -self.beta_dot * (math.sin(b) * X0 + math.cos(b) * Z0)
        return self._S * math.cos(self.theta) * self.theta_dot

    def _superstructure_relative(self) -> tuple[float, float, float]:
        """(u, uplift, horizontal velocity) of the superstructure relative to the ground."""
        L, th = self._L, self.theta
        u = L * math.sin(th)
        z = L * (1.0 - math.cos(th))
        v = L * math.cos(th) * self.theta_dot
        if self.rocking:
            rQx, rQz = self._chain[5], self._chain[6]
            c, s = math.cos(self.beta), math.sin(self.beta)
            u += (c - 1.0) * rQx - s * rQz
            z += s * rQx + (c - 1.0) * rQz
            v = -self.beta_dot * (s * rQx + c * rQz)
        return u, z, v

    # ------------------------------------------------------------------
    # the step
    # ------------------------------------------------------------------
    def _seated_step(self, a: float, h: float, mu1: float, mu2: float,
                     rocking_allowed: bool) -> None:
        """One step of length h from a seated state: phase 1 (stick trial,
        rocking check, or slip along the tangent) then phase 2 (re-seat).

        If the relative velocity reaches zero inside the step (arrest or
        reversal), the step is split at that instant: each part is a
        two-phase step with one sign of friction, so the slip of each part is
        its |d theta| and the ledger closes at the event too.
        """
        th0, v0 = self.theta, self.theta_dot
        # seated_normal_forces, inlined with the cached constants (hot path)
        g_axis = self._g * math.cos(th0) - a * math.sin(th0)
        w2 = v0 * v0
        N2 = self._M * (g_axis + self._L * w2)
        N1 = N2 + self._m * (g_axis + self._rho * w2)
        if N2 < 0.0:
            N1, N2 = max(N1, 0.0), 0.0
        elif N1 < 0.0:
            N1 = 0.0
        self.N1, self.N2 = N1, N2
        f1, f2 = mu1 * N1 * self._R1, mu2 * N2 * self._R2  # friction moments about the centres
        cap = f1 + f2  # = F_c L: both interfaces capped together, never one alone

        v1, dth, lam = self._moreau_trial(th0, v0, a, h, cap)
        if v0 != 0.0 and (v1 == 0.0 or (v1 > 0.0) != (v0 > 0.0)):
            tau, dth = self._arrest(th0, v0, a, h, cap)
            sign = 1.0 if v0 > 0.0 else -1.0
            self.Ff1, self.Ff2 = sign * f1 / self._L, sign * f2 / self._L
            self._two_phase_update(th0, dth, 0.0, a, f1, f2)
            self.mode = STICK
            if h - tau > 0.0:  # the rest of the step starts from rest (and labels it)
                self._seated_step(a, h - tau, mu1, mu2, rocking_allowed)
            return
        self.Ff1, self.Ff2 = lam * f1 / self._L, lam * f2 / self._L

        if v1 == 0.0:  # v0 == 0 too: the joints hold over the whole step
            if rocking_allowed and self._start_rocking(a):
                self._tilt_step(a, h, mu1, mu2)
                return
            self.mode = STICK
            self.beta1 = self.beta2 = self.pad_tilt = 0.0
            self.ds1 = self.ds2 = 0.0
            self.slip_v1 = self.slip_v2 = 0.0
            return
        self._two_phase_update(th0, dth, v1, a, f1, f2)
        self.mode = SLIP

    def _moreau_trial(self, th0: float, v0: float, a: float, h: float,
                      cap: float) -> tuple[float, float, float]:
        """Phase 1 stick trial (Moreau) on the seated manifold: returns
        (theta' at the end, d theta, friction multiplier lambda in Sgn).

        The d'Alembert and gravity terms are discrete gradients of their
        potentials S sin(theta), S (1 - cos(theta)) along the arc, so the
        kinetic energy change equals the work along it exactly.
        """
        S, g = self._S, self._g
        hI = h / self._I
        dth = h * v0
        v1, lam = v0, 0.0
        for _ in range(_FIXED_POINT_ITERS):
            mid = th0 + 0.5 * dth
            drive = -S * _sinc(0.5 * dth) * (a * math.cos(mid) + g * math.sin(mid))
            v_free = v0 + hI * drive
            if abs(v_free) <= hI * cap:
                v1, lam = 0.0, (v_free / (hI * cap) if cap > 0.0 else 0.0)
            else:
                lam = 1.0 if v_free > 0.0 else -1.0
                v1 = v_free - hI * cap * lam
            dth_new = 0.5 * h * (v0 + v1)
            if abs(dth_new - dth) <= _FIXED_POINT_TOL:
                return v1, dth_new, lam
            dth = dth_new
        return v1, dth, lam

    def _arrest(self, th0: float, v0: float, a: float, h: float,
                cap: float) -> tuple[float, float]:
        """Time tau in (0, h] at which the sliding motion (friction at the cap,
        opposing v0) brings theta' to zero, and the d theta by then."""
        S, g, I = self._S, self._g, self._I
        sign = 1.0 if v0 > 0.0 else -1.0
        tau = h
        for _ in range(_FIXED_POINT_ITERS):
            dth = 0.5 * tau * v0
            mid = th0 + 0.5 * dth
            drive = -S * _sinc(0.5 * dth) * (a * math.cos(mid) + g * math.sin(mid))
            decel = drive - cap * sign
            tau_new = -v0 * I / decel if decel * sign < 0.0 else h
            tau_new = min(max(tau_new, 0.0), h)
            if abs(tau_new - tau) <= 1e-15 * h:
                tau = tau_new
                break
            tau = tau_new
        return tau, 0.5 * tau * v0

    def _two_phase_update(self, th0: float, dth: float, v1: float, a: float,
                          f1: float, f2: float) -> None:
        """Phases 1 and 2 of a sliding step: the superstructure has moved by
        L dth along the tangent at theta_n with rate v1 at the end."""
        # Phase 1: the trailing corner pivots to keep the opposite top corner
        # on the upper surface; the plates fix C1C2(t_n+1) and theta_n+1.
        I, S = self._I, self._S
        self.beta1 = corner_pivot_rotation(*self._corner, self._L * dth)
        if dth != 0.0:
            self.diagonal = DIAGONAL_AC if dth > 0.0 else DIAGONAL_BD
        dphi = math.atan(dth)
        th1 = th0 + dphi
        # Phase 2: re-seat. Counter-rotation beta2 takes the pad axis onto
        # C1C2(t_n+1); the slip of each interface is its net arc, counted once.
        self.beta2 = dphi - self.beta1
        self.pad_tilt = -self.beta2
        ads = abs(dphi)
        self.W1 += f1 * ads
        self.W2 += f2 * ads
        self.ds1, self.ds2 = self._R1 * dphi, self._R2 * dphi
        self.slip1 += self._R1 * ads
        self.slip2 += self._R2 * ads
        # velocity projection (kinetic-energy metric) onto the tangent at th1:
        # translations lose their component along C1C2, the pad spin is kept
        v_proj = v1 * (self._I_trans * math.cos(dphi) + self._J) / I
        self.E_reseat += 0.5 * I * (v1 * v1 - v_proj * v_proj)
        self.E_input -= a * S * (math.sin(th1) - math.sin(th0))
        self.theta, self.theta_dot = th1, v_proj
        self.slip_v1 = self._R1 * abs(v_proj)
        self.slip_v2 = self._R2 * abs(v_proj)

    def _start_rocking(self, a: float) -> bool:
        """Rocking check (model.md 3, step 2): does Eq. (7) give the pad a
        beta'' opening the gap at beta = 0 about a bottom corner?

        The chains are kept in the pad frame (theta = 0) and turned by theta:
        the first moments and arms rotate rigidly, I_P does not change."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        g = self._g
        for diagonal, sign in ((DIAGONAL_AC, 1.0), (DIAGONAL_BD, -1.0)):
            I_P, Xb, Zb, rGx, rGz, rQx, rQz = self._body_chains[diagonal]
            X0, Z0 = c * Xb - s * Zb, s * Xb + c * Zb
            if sign * rocking_acceleration(I_P, X0, Z0, a, g) > 0.0:
                self._chain = (I_P, X0, Z0, c * rGx - s * rGz, s * rGx + c * rGz,
                               c * rQx - s * rQz, s * rQx + c * rQz, sign)
                self.diagonal = diagonal
                self.rocking = True
                self.beta = self.beta_dot = 0.0
                return True
        return False

    def _tilt_step(self, a: float, h: float, mu1: float, mu2: float) -> None:
        """The rocking chain of Eq. (7) over a step of length h; on landing
        (beta back to 0) the impact re-seats the device and the rest of the
        step is a seated step."""
        I_P, X0, Z0 = self._chain[:3]
        sign = self._chain[7]
        g = self._g
        b0, w0 = self.beta, self.beta_dot
        db = h * w0
        for _ in range(_FIXED_POINT_ITERS):
            mid = b0 + 0.5 * db
            c, s = math.cos(mid), math.sin(mid)
            # discrete gradient of Eq. (7): the first moments at the midpoint
            # times sinc, so the step's work equals the potential's change
            torque = _sinc(0.5 * db) * (a * (s * X0 + c * Z0) - g * (c * X0 - s * Z0))
            w1 = w0 + h * torque / I_P
            db_new = 0.5 * h * (w0 + w1)
            if abs(db_new - db) <= _FIXED_POINT_TOL:
                db = db_new
                break
            db = db_new
        b1 = b0 + db
        self.mode = TILT
        self.beta2 = 0.0
        self.ds1 = self.ds2 = 0.0
        self.slip_v1 = self.slip_v2 = 0.0
        if sign * b1 > 0.0:
            if sign * (math.cos(b1) * X0 - math.sin(b1) * Z0) <= 0.0:
                raise PadOverturned(f"pad overturned at t = {self._t[self.n]:.6g} s "
                                    f"(beta = {b1:.4g} rad)")
            self.E_input -= a * ((math.cos(b1) - math.cos(b0)) * X0
                                 - (math.sin(b1) - math.sin(b0)) * Z0)
            self.beta, self.beta_dot = b1, w1
            self.beta1 = b1
            self.pad_tilt = b1
            self.N1, self.N2 = self._chain_normal_forces(a)
            return
        self._land(a, h, b0, w0, mu1, mu2)

    def _chain_normal_forces(self, a: float) -> tuple[float, float]:
        """Normal forces of the rocking chain at the pivot (N1) and at the top
        corner (N2), from the accelerations of Eq. (7) and each body's
        momentum balance; the normals are those of the plates at the corners
        (the plates do not rotate, so they keep their seated directions).
        Sets Ff1, Ff2: the tangential forces the pinned joints carry (the
        model does not let them slip; a test checks |Ff_i| <= mu_i N_i)."""
        I_P, X0, Z0, rGx0, rGz0, rQx0, rQz0, sign = self._chain
        b, w, g = self.beta, self.beta_dot, self._g
        c, s = math.cos(b), math.sin(b)
        alpha = rocking_acceleration(I_P, c * X0 - s * Z0, s * X0 + c * Z0, a, g)
        rGx, rGz = c * rGx0 - s * rGz0, s * rGx0 + c * rGz0
        rQx, rQz = c * rQx0 - s * rQz0, s * rQx0 + c * rQz0
        w2 = w * w
        M, m = self._M, self._m
        # forces the pad exerts on RB3+4 and the lower plate exerts on the pad
        FMx = M * (a - alpha * rQz - w2 * rQx)
        FMz = M * (g + alpha * rQx - w2 * rQz)
        FPx = FMx + m * (a - alpha * rGz - w2 * rGx)
        FPz = FMz + m * (g + alpha * rGx - w2 * rGz)
        ct, st = math.cos(self.theta), math.sin(self.theta)
        xa, R1, R2 = self.geom.a, self._R1, self._R2
        eta1 = math.sqrt(R1 * R1 - xa * xa)
        eta2 = math.sqrt(R2 * R2 - xa * xa)
        # pad-frame normals: lower plate at the pivot (+-a, eta1)/R1 pointing to
        # C1, upper plate at the top corner (-+a, eta2)/R2 pointing away from C2
        n1x, n1z = sign * xa / R1, eta1 / R1
        n2x, n2z = sign * xa / R2, eta2 / R2
        # world normals, and the tangents (normal turned clockwise, along +x
        # when seated at the centre) for the friction the pinned joints need
        w1x, w1z = ct * n1x - st * n1z, st * n1x + ct * n1z
        w2x, w2z = ct * n2x - st * n2z, st * n2x + ct * n2z
        N1 = FPx * w1x + FPz * w1z
        N2 = FMx * w2x + FMz * w2z
        # friction on the pad at the pivot (from RB1) and on RB3+4 at the corner
        self.Ff1 = FPx * w1z - FPz * w1x
        self.Ff2 = FMx * w2z - FMz * w2x
        return N1, N2

    def _land(self, a: float, h: float, b0: float, w0: float, mu1: float, mu2: float) -> None:
        """The pad lands within the step: find the landing time with the same
        discrete gradient (end point beta = 0 known), project the velocities
        onto the seated tangent (impact loss, E_reseat), finish the step seated."""
        I_P, X0, Z0 = self._chain[:3]
        g = self._g
        mid = 0.5 * b0
        c, s = math.cos(mid), math.sin(mid)
        torque = _sinc(mid) * (a * (s * X0 + c * Z0) - g * (c * X0 - s * Z0))
        # b0 + tau w0 + tau^2 torque / (2 I_P) = 0, smallest root in (0, h]
        tau = _smallest_positive_root(0.5 * torque / I_P, w0, b0, default=h)
        tau = min(max(tau, 0.0), h)
        w_land = w0 + tau * torque / I_P
        self.E_input -= a * ((1.0 - math.cos(b0)) * X0 + math.sin(b0) * Z0)
        # impact: chain velocities (pad spin w, centroid w k x r_G, RB3+4 w k x r_Q)
        # projected in the kinetic-energy metric onto the seated tangent field
        # (L t for RB3+4, rho t for the centroid, spin 1), t = (cos th, sin th)
        _, _, _, rGx, rGz, rQx, rQz, _ = self._chain
        ct, st = math.cos(self.theta), math.sin(self.theta)
        tG = -rGz * ct + rGx * st
        tQ = -rQz * ct + rQx * st
        p = w_land * (self._M * self._L * tQ + self._m * self._rho * tG + self._J)
        v_seat = p / self._I
        self.E_reseat += 0.5 * I_P * w_land * w_land - 0.5 * self._I * v_seat * v_seat
        self.rocking = False
        self.beta = self.beta_dot = 0.0
        self.theta_dot = v_seat
        self._chain = None
        beta_land = self.beta1
        if h - tau > 0.0:
            self._seated_step(a, h - tau, mu1, mu2, rocking_allowed=False)
        self.mode = TILT  # the step is labelled by its rocking part
        self.beta1 = beta_land
