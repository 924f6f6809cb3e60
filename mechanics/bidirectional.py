"""Bidirectional DFP steppers (model.md section 8): thin classes over the
kernel mechanics/bidirectional_kernel.py (the per-step physics, written once).

BidirectionalStepper: ground motion with two horizontal components (the
two-phase stepper in the paper's plane pi; ``normal_force`` = "midpoint"
(second order, default) or "start" (the paper's section 3 scheme, which with
a zero y component is today's planar TwoPhaseStepper to round-off)).

BidirectionalTestMachine: the bearing-test machine with a prescribed orbit
u(t) = (ux, uy) (circle, figure-eight, sine in a direction), seated model.

Both follow the Stepper protocol of docs/architecture.md; the footprint
centres are 2D: ``centre1`` (lower plate, R1 theta (cos phi, sin phi)) and
``centre2`` (upper plate, -R2 theta (cos phi, sin phi)); ``s1``, ``s2`` are
their distances from the plate centres.
"""
from __future__ import annotations

import math
import sys

import numpy as np

from fpd.tribology import rim_law

from . import bidirectional_kernel as _pure
from .geometry import DeviceGeometry
from fpd.loading.ground_motion import as_float64, float_array
from .phases import DIAGONAL_AC, MechanicsFailure
from .protocol import TwoInterfaces
from .phases import SEATED_COLUMNS
from .two_phase import COLUMNS as PLANAR_COLUMNS, pivot_chain

K = _pure
# the rim (docs/model.md 9): its loss, the impacts' impulse, their count per surface
RIM_COLUMNS = ("E_rim_J", "J_rim_Ns", "n_rim1", "n_rim2")
COLUMNS = (
    "t_s", "xg_m", "yg_m", "ux_m", "uy_m", "u_m", "vx_mps", "vy_mps", "v_mps",
    "Fx_N", "Fy_N", "F_N", "z_m", "theta_rad", "phi_rad", "beta_rad",
    "s1_m", "s2_m", "N1_N", "N2_N", "W1_J", "W2_J", "phase",
    "E_input_J", "E_kin_J", "E_pot_J", "E_reseat_J",
    "beta1_rad", "beta2_rad", "pad_tilt_rad", "ds1_m", "ds2_m", "Ff1_N", "Ff2_N",
    "slip1_m", "slip2_m", "c1x_m", "c1y_m", "c2x_m", "c2y_m",
) + RIM_COLUMNS
NORMAL_FORCE = ("midpoint", "start")
# a loading with a vertical component (model.md 10): the step's vertical ground acceleration,
# the flight above the seated position, the lift-offs so far, the time in flight, the landings' loss
VERTICAL_COLUMNS = ("az_mps2", "lift_m", "n_lift", "t_flight_s", "E_land_J")
PLANAR_COLUMNS = PLANAR_COLUMNS + RIM_COLUMNS
SEATED_COLUMNS = SEATED_COLUMNS + RIM_COLUMNS


class PadRocks(MechanicsFailure):
    """The stuck pad would rock (Eq. 7) where the stepper does not model it."""


class PadOverturned(MechanicsFailure):
    """The rocking pad passed the angle where gravity stops restoring it."""


def _failure(flag, t):
    if flag == K.FLAG_OVERTURN:
        return PadOverturned(f"pad overturned at t = {t:.6g} s (rocking in the plane of the trial)")
    return PadRocks(f"the stuck pad rocks on its rim at t = {t:.6g} s (Eq. 7)")


def kernel(jit: bool | None = None):
    """The kernel module: compiled when ``jit`` (or, for None, when numba is
    already loaded and allowed), else the pure one."""
    from fpd import kernels
    if jit is None:
        jit = "numba" in sys.modules and kernels.available()
    if jit and kernels.available():
        return kernels.compiled("fpd.mechanics.bidirectional_kernel")
    return _pure


def constants(geom: DeviceGeometry, midpoint: bool, seated: bool = False) -> list:
    """The kernel's constants array C (a list; np.array of it for the compiled path)."""
    C = [0.0] * K.N_C
    C[K.C_L], C[K.C_RHO], C[K.C_I], C[K.C_S] = geom.L, geom.rho, geom.I, geom.S
    C[K.C_M], C[K.C_MP], C[K.C_J], C[K.C_G] = geom.mass, geom.pad_mass, geom.pad_inertia, geom.g
    C[K.C_R1], C[K.C_R2] = geom.R1, geom.friction_radius2
    c = geom.pad_corners_body()
    C[K.C_A], C[K.C_EB], C[K.C_ET], C[K.C_H] = geom.a, c["A"][1], c["C"][1], geom.pad_height
    C[K.C_ITRANS] = geom.mass * geom.L ** 2 + geom.pad_mass * geom.rho ** 2
    C[K.C_MID] = 1.0 if midpoint else 0.0
    C[K.C_SEATED] = 1.0 if seated or geom.kind == "SFP" else 0.0
    if geom.kind == "DFP":
        # the A-C chain of Eq. (7) in the pad frame (mechanics.two_phase.pivot_chain at theta = 0)
        I_P, X0, Z0, rGx, rGz, rQx, rQz = pivot_chain(geom, 0.0, DIAGONAL_AC)
        C[K.C_XB], C[K.C_ZB], C[K.C_IP] = X0, Z0, I_P
        C[K.C_RGX], C[K.C_RGZ], C[K.C_RQX], C[K.C_RQZ] = rGx, rGz, rQx, rQz
        xa, R1, R2 = geom.a, geom.R1, geom.R2
        C[K.C_N1X], C[K.C_N1Z] = xa / R1, math.sqrt(R1 * R1 - xa * xa) / R1
        C[K.C_N2X], C[K.C_N2Z] = xa / R2, math.sqrt(R2 * R2 - xa * xa) / R2
    else:                              # the SFP's articulated slider does not rock
        C[K.C_XB], C[K.C_ZB], C[K.C_IP] = 1.0, 0.0, 1.0
    return C


class _Base(TwoInterfaces):
    columns = COLUMNS
    two_d = True

    def footprints(self) -> tuple:
        """Footprint centres (x, y) on the lower and the upper plate (m); a
        planar run's on the x axis (+s1 and -s2, signed)."""
        c = _pure.centres(self.C, self.S)
        if not self.two_d:
            return (float(c[0]), float(c[2]))
        return ((float(c[0]), float(c[1])), (float(c[2]), float(c[3])))

    # the planar run's pad, as the planar stepper names it (outputs/device_drawings.pad_pose)
    @property
    def mode(self) -> int:
        return int(self.S[K.S_MODE])

    @property
    def diagonal(self) -> int:
        return 1 if K.planar_sign(self.S) < 0.0 else 0

    @property
    def beta(self) -> float:
        """The rocking angle about the pivot corner (rad, signed as x; 0 when seated)."""
        return K.planar_sign(self.S) * float(self.S[K.S_BETA]) if self.S[K.S_ROCK] != 0.0 else 0.0

    def _setup(self, geom, dt, n_steps, midpoint, jit, u0=(0.0, 0.0), v0=(0.0, 0.0), seated=False):
        self.geom = geom
        self.dt = float(dt)
        self.n_steps = int(n_steps)
        self.n = 0
        self.midpoint = bool(midpoint)
        self._K = kernel(jit)
        self.compiled = self._K is not _pure
        C = constants(geom, midpoint, seated)
        S = [0.0] * K.N_S
        L = geom.L
        nx, ny = u0[0] / L, u0[1] / L
        nz = -math.sqrt(1.0 - nx * nx - ny * ny)
        S[K.S_NX], S[K.S_NY], S[K.S_NZ] = nx, ny, nz
        # rate of n from the horizontal velocity (tangent: n . w = 0)
        wx, wy = v0[0] / L, v0[1] / L
        S[K.S_WX], S[K.S_WY], S[K.S_WZ] = wx, wy, -(nx * wx + ny * wy) / nz
        S[K.S_MODE] = K.STICK if (v0[0] == 0.0 and v0[1] == 0.0) else K.SLIP
        if self.compiled:
            self.C, self.S = np.array(C), np.array(S)
        else:
            self.C, self.S = C, S
        Ek, Ep = _pure.energies(C, S)
        self.S[K.S_EIN] = Ek + Ep           # an initial state is energy put in before t = 0
        self.S[K.S_N1], self.S[K.S_N2] = _pure.normal_forces(C, nx, ny, nz, S[K.S_WX], S[K.S_WY], S[K.S_WZ],
                                                            0.0, 0.0, C[K.C_G])
        w = math.sqrt(wx * wx + wy * wy + S[K.S_WZ] ** 2)
        self.S[K.S_SV1], self.S[K.S_SV2] = C[K.C_R1] * w, C[K.C_R2] * w

    def set_static(self, mu_s1: float, mu_s2: float, ratio1: float = 0.0, ratio2: float = 0.0) -> None:
        """The static (breakaway) coefficients of the lower and upper surface,
        and as ratios to the sliding mu at rest (0: none; bidirectional_kernel
        C_MUS1, C_MUS2, C_MUR1, C_MUR2)."""
        self.C[K.C_MUS1], self.C[K.C_MUS2] = float(mu_s1), float(mu_s2)
        self.C[K.C_MUR1], self.C[K.C_MUR2] = float(ratio1), float(ratio2)

    def set_dwell(self, lower: tuple, upper: tuple) -> None:
        """The static coefficients' growth with the time stuck, per surface (mu_s
        after a long dwell, time constant tau in s, exponent; tau = 0: none):
        bidirectional_kernel C_MUI1.., friction_kernel.dwell_mu. The time stuck
        starts at zero with the run."""
        C = self.C
        C[K.C_MUI1], C[K.C_TAU1], C[K.C_EXP1] = (float(x) for x in lower)
        C[K.C_MUI2], C[K.C_TAU2], C[K.C_EXP2] = (float(x) for x in upper)

    def set_rim(self, d1: float, d2: float | None = None, restitution: float = 0.0,
                stiffness: float | None = None, damping: float = 0.0) -> None:
        """The slide capacities (arc from each surface's centre, m; the SFP's
        d1 only) and the rim's restitution: the axis's tilt is bounded by
        min(d1 / R1, d2 / R2), the surface (or both) that sets it counts the
        impacts (docs/model.md 9). ``stiffness`` (N/m): a rim of finite
        stiffness instead of the rigid one, a spring on the slide beyond the
        capacity of each surface that sets it (elastic: no loss at the rim);
        ``damping``: its damping ratio zeta in [0, 1), a dashpot on the same
        slide, 2 zeta sqrt(k m_eff) with m_eff = I / sum R_i^2 over those
        surfaces (the pendulum's generalised inertia carried by the slide),
        i.e. 2 zeta sqrt(C_KRIM I) on the tilt (docs/model.md 9)."""
        g = self.geom
        arcs = [d1 / g.R1] + ([d2 / g.R2] if (d2 is not None and g.kind == "DFP") else [])
        th = min(arcs)
        C = self.C
        C[K.C_THMAX], C[K.C_REST] = th, float(restitution)
        C[K.C_RIM1] = 1.0 if arcs[0] <= th * (1 + 1e-12) else 0.0
        C[K.C_RIM2] = 1.0 if len(arcs) > 1 and arcs[1] <= th * (1 + 1e-12) else 0.0
        if stiffness:
            C[K.C_KRIM] = float(stiffness) * (C[K.C_RIM1] * g.R1 ** 2 + C[K.C_RIM2] * g.R2 ** 2)
            C[K.C_CRIM] = rim_law.dashpot_coefficient(float(damping), C[K.C_KRIM], C[K.C_I])
        self.capacity = (d1, d2 if g.kind == "DFP" else None)

    # -- protocol attributes ----------------------------------------------------
    @property
    def N1(self) -> float:
        return float(self.S[K.S_N1])

    @property
    def N2(self) -> float:
        return float(self.S[K.S_N2])

    @property
    def slip_v1(self) -> float:
        return float(self.S[K.S_SV1])

    @property
    def slip_v2(self) -> float:
        return float(self.S[K.S_SV2])

    @property
    def theta(self) -> float:
        """Tilt of the pad axis from vertical (>= 0)."""
        S = self.S
        return math.atan2(math.hypot(S[K.S_NX], S[K.S_NY]), -S[K.S_NZ])

    @property
    def phi(self) -> float:
        """Azimuth of the displacement, atan2(uy, ux)."""
        return math.atan2(self.S[K.S_NY], self.S[K.S_NX])

    @property
    def s1(self) -> float:
        """Distance of the lower footprint from the plate centre, R1 theta (m)."""
        return self.C[K.C_R1] * self.theta

    @property
    def s2(self) -> float:
        return self.C[K.C_R2] * self.theta

    @property
    def centre1(self) -> tuple:
        """Footprint centre on the lower plate, R1 theta (cos phi, sin phi) (m)."""
        c = _pure.centres(self.C, self.S)
        return (float(c[0]), float(c[1]))

    @property
    def centre2(self) -> tuple:
        """Footprint centre on the upper plate, -R2 theta (cos phi, sin phi) (m)."""
        c = _pure.centres(self.C, self.S)
        return (float(c[2]), float(c[3]))

    @property
    def u(self) -> tuple:
        """Relative displacement (ux, uy) of the superstructure (m), rocking included."""
        L = self.geom.L
        dx, dy = _pure.rocking_offsets(self.C, self.S)[:2]
        if self.S[K.S_FLY] != 0.0:
            dx, dy = dx + self.S[K.S_XF], dy + self.S[K.S_YF]
        return (L * float(self.S[K.S_NX]) + float(dx), L * float(self.S[K.S_NY]) + float(dy))

    def kinetic_energy(self) -> float:
        return _pure.energies(self.C, self.S)[0]

    def potential_energy(self) -> float:
        return _pure.energies(self.C, self.S)[1]

    def energy_residual(self) -> float:
        S = self.S
        Ek, Ep = _pure.energies(self.C, S)
        return float(S[K.S_EIN] - (Ek + Ep + S[K.S_W1] + S[K.S_W2] + S[K.S_ERES] + S[K.S_ERIM] + S[K.S_ELAND]))

    def save(self):
        """(n, then every slot of the state as a float)."""
        return (self.n, *(float(x) for x in self.S))

    def restore(self, snap) -> None:
        self.n = snap[0]
        for i, x in enumerate(snap[1:]):
            self.S[i] = x

    def values(self) -> tuple:
        out = [0.0] * max(K.N_VALUES, len(self.columns))
        xg, yg = self.ground_position()
        _pure.values(self.C, [float(x) for x in self.S] if self.compiled else self.S,
                     self.n * self.dt, xg, yg, out)
        out = out[:len(self.columns)]
        if self.C[K.C_PLANAR] != K.PLANAR_NONE:          # the planar columns: phase (and diagonal) as ints
            codes = (13,) if self.C[K.C_PLANAR] == K.PLANAR_SEATED else (14, 22)
            for j in codes:          # a non-finite code stays as it is: the loop reports it
                out[j] = int(out[j]) if math.isfinite(out[j]) else out[j]
        return tuple(out)

    def use_compiled(self) -> None:
        """Hold the state as float64 arrays and step with the compiled kernel."""
        if not self.compiled:
            self._K = kernel(True)
            self.compiled = self._K is not _pure
            if self.compiled:
                self.C, self.S = np.array(self.C), np.array(self.S)


class BidirectionalStepper(_Base):
    """Two-phase DFP stepper in 3D under a two-component ground motion.

    ``gx``, ``gy``: GroundMotion of the x and y components on the same grid
    (gy None: unidirectional along x); ``gz``: the vertical component (up;
    None: none), every normal force sees g + a_z (model.md 10). ``normal_force``: "midpoint" or
    "start". ``model``: "two-phase" or "seated" (the spherical pendulum of
    model.md 2 in 3D: no re-seating phase; the SFP always). ``jit``: use the
    compiled kernel (None: when numba is loaded)."""

    def __init__(self, geom: DeviceGeometry, gx, gy=None, normal_force: str = "midpoint",
                 jit: bool | None = None, model: str = "two-phase", planar: bool = False,
                 rim: tuple | None = None, gz=None):
        if normal_force not in NORMAL_FORCE:
            raise ValueError(f"normal_force = {normal_force!r}: must be one of {NORMAL_FORCE}")
        if gy is not None and (gy.n_steps != gx.n_steps or gy.dt != gx.dt):
            raise ValueError("the two ground-motion components must share the time grid")
        if gz is not None and (gz.n_steps != gx.n_steps or gz.dt != gx.dt):
            raise ValueError("the vertical ground motion must share the horizontal one's time grid")
        if planar and gy is not None:
            raise ValueError("a planar run has no y component")
        self.ground, self.ground_y = gx, gy
        self._setup(geom, gx.dt, gx.n_steps, normal_force == "midpoint", jit, seated=model == "seated")
        self.normal_force = normal_force
        self.model = "seated" if geom.kind == "SFP" else model
        if rim is not None:
            self.set_rim(*rim)
        if planar:
            # the motion in the x-z plane (y absent): the planar steppers' columns, signed
            seated = self.model == "seated"
            self.C[K.C_PLANAR] = K.PLANAR_SEATED if seated else K.PLANAR_TWO_PHASE
            self.columns = SEATED_COLUMNS if seated else PLANAR_COLUMNS
            self.two_d = False
        self._ax = float_array(gx.a_step)
        # a planar run has no y component at all: no series of zeros (8 bytes a step)
        self._ay = float_array(gy.a_step) if gy is not None else (None if planar else float_array(np.zeros(gx.n_steps)))
        self._xg = gx.d
        self._yg = gy.d if gy is not None else None
        self.ground_z = gz
        self._az = None
        if gz is not None:
            self._az = float_array(gz.a_step)
            self.C[K.C_VERT] = 1.0
            self.columns = tuple(self.columns) + VERTICAL_COLUMNS

    def ground_position(self):
        return (float(self._xg[self.n]), float(self._yg[self.n]) if self._yg is not None else 0.0)

    # -- the compiled engine (coupling/engine_kernel.py) ----------------------------
    engine_device = "fpd.mechanics.dev_bidirectional"

    @staticmethod
    def engine_worth_loading(n_steps: int) -> bool:
        """The Python step of the 3D stepper costs ~35 us, the compiled one
        ~1 us: loading numba and the cached engine (~0.6 s) pays past
        ~20 000 steps, with lumped plates or none as with fe1d ones."""
        return n_steps >= 20_000

    def engine_state(self):
        """(C, S, L, X) as the engine reads them: the stepper's own arrays (it
        steps with the compiled kernel from now on), the loading (ax, ay per
        step, xg, yg per row), no scratch. ImportError without numba."""
        self.use_compiled()
        if not self.compiled:
            raise ImportError("numba is not available")
        xg = as_float64(self._xg)
        yg = as_float64(self._yg) if self._yg is not None else xg     # (read only with a y component)
        ax = as_float64(self._ax)
        ay = as_float64(self._ay) if self._ay is not None else ax      # (a planar run reads no ay: dev_bidirectional)
        az = as_float64(self._az) if self._az is not None else ax      # (read only with C_VERT)
        return self.C, self.S, (ax, ay, xg, yg, az), (np.zeros(1),)

    def engine_pull(self, S) -> None:
        """Nothing to copy: the engine steps the stepper's own state."""

    def engine_push(self, S, n: int) -> None:
        self.n = n

    def step(self, mu1: float, mu2: float) -> tuple[float, float]:
        if self.n >= self.n_steps:
            raise IndexError(f"all {self.n_steps} steps of the loading are taken")
        S = self.S
        W1, W2 = S[K.S_W1], S[K.S_W2]
        flag = self._K.step(self.C, S, self._ax[self.n], self._ay[self.n] if self._ay is not None else 0.0,
                            self._az[self.n] if self._az is not None else 0.0, self.dt, mu1, mu2)
        if flag != K.FLAG_OK:
            raise _failure(flag, self.n * self.dt)
        self.n += 1
        return float(S[K.S_W1] - W1), float(S[K.S_W2] - W2)

    def run(self, mu1: float, mu2: float, n_steps: int | None = None) -> np.ndarray:
        """Mechanics only, constant friction: (n, 3) array of ux, uy, W1 + W2
        after each step (the kernel's own loop; compiled when this stepper is)."""
        n1 = self.n_steps if n_steps is None else self.n + n_steps
        out = np.zeros((n1 - self.n, 3))
        AX = np.asarray(self._ax)
        AY = np.asarray(self._ay) if self._ay is not None else np.zeros(len(AX))
        AZ = np.asarray(self._az) if self._az is not None else np.zeros(len(AX))
        done = self._K.run_steps(self.C, self.S, AX, AY, AZ, self.dt, mu1, mu2, self.n, n1, out)
        self.n += done
        if self.n < n1:
            raise _failure(K.FLAG_OVERTURN, self.n * self.dt)
        return out
