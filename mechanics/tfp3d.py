"""The rigid triple friction pendulum in both horizontal directions: the
stepper around mechanics/tfp3d_kernel.py (docs/model.md section 6.8).

The planar TFP's bodies and geometry (mechanics/tfp.py's TFPGeometry), its
two rotations made tilt vectors: phi = (phi_x, phi_y) the stack's (S1 and S4
slide together, R1 : R4), alpha = (alpha_x, alpha_y) the pad's relative to
the slider plates (S2 and S3, R2 : R3). Friction on each surface is a vector
opposing its slip, bounded by a disk; a step's increment is the minimiser of
a small second-order cone program (tfp3d_kernel.socp). A run whose record has
no y component is the planar TFP's to round-off; a record turned by an angle
is the planar run turned. Under a vertical ground motion (az) every normal
force, cap, the drive and the ledger see g + a_z, and when g + a_z < 0 the
stack and the superstructure lift off, fly and land (docs/model.md 10).
"""
from __future__ import annotations

import numpy as np

from . import tfp3d_kernel as K
from . import tfp_kernel as tk
from fpd.loading.ground_motion import float_array
from .phases import MechanicsFailure
from .tfp import TFPGeometry, TFPState, TFPStepper

COLUMNS = (
    "t_s", "xg_m", "yg_m", "ux_m", "uy_m", "u_m", "vx_mps", "vy_mps", "v_mps", "Fx_N", "Fy_N", "F_N", "z_m",
    "theta_rad", "phix_rad", "phiy_rad", "phi_rad", "alphax_rad", "alphay_rad", "alpha_rad",
    "s1x_m", "s1y_m", "s1_m", "s2x_m", "s2y_m", "s2_m", "s3x_m", "s3y_m", "s3_m", "s4x_m", "s4y_m", "s4_m",
    "N1_N", "N2_N", "N3_N", "N4_N", "W1_J", "W2_J", "W3_J", "W4_J", "phase",
    "E_input_J", "E_kin_J", "E_pot_J", "E_rim_J", "regime", "slide1", "slide2", "slide3", "slide4",
    "rim1", "rim2", "rim3", "rim4", "J_rim_Ns", "n_rim1", "n_rim2", "n_rim3", "n_rim4",
    "c1x_m", "c1y_m", "c2x_m", "c2y_m", "c3x_m", "c3y_m", "c4x_m", "c4y_m",
    "fp_iterations", "kkt_rel",
)
assert len(COLUMNS) == K.N_ROW
# a loading with a vertical component (docs/model.md 10): the step's vertical ground acceleration, last
VERTICAL_COLUMNS = ("az_mps2", "lift_m", "n_lift", "t_flight_s", "E_land_J")


class TFP3DFailure(MechanicsFailure):
    pass


class TFP3DStepper(TFPState):
    """The rigid TFP under a two-component ground motion (gx, gy: GroundMotion
    on the same grid; gy None: the y component absent; az: the vertical ground
    acceleration per step, up, or None). ``step(mu1..mu4)``
    advances one step and returns the friction work of S1..S4 in it; the
    state is one float64 vector (tfp3d_kernel.S_*)."""

    state_layout = K
    n_interfaces = 4
    two_d = True
    drawing = "tfp3d"         # the VTK drawing (outputs/device_drawings.py)
    columns = COLUMNS
    model = "seated"

    def __init__(self, geom: TFPGeometry, gx, gy=None, kernel=None, az=None):
        self.geom = geom
        self.k = kernel if kernel is not None else K
        self.dt = gx.dt
        self.n_steps = gx.n_steps
        # the test machine (an OrbitProgramme: u, u' per grid point, (n + 1, 2)):
        # the lower plate moves by -u, the superstructure is held
        self.machine = np.ndim(getattr(gx, "u", None)) == 2
        if self.machine:
            U, UD = np.asarray(gx.u, dtype=float), np.asarray(gx.ud, dtype=float)
            self._ux, self._uy = float_array(U[:, 0]), float_array(U[:, 1])
            self._udx, self._udy = float_array(UD[:, 0]), float_array(UD[:, 1])
            self._ax = float_array(-np.diff(UD[:, 0]) / gx.dt)
            self._ay = float_array(-np.diff(UD[:, 1]) / gx.dt)
            self._xg, self._yg = float_array(-U[:, 0]), float_array(-U[:, 1])
        else:
            self._ax = float_array(gx.a_step)
            self._xg = float_array(gx.d)
            if gy is not None:
                self._ay = float_array(gy.a_step)
                self._yg = float_array(gy.d)
            else:
                self._ay = np.zeros_like(self._ax)
                self._yg = np.zeros_like(self._xg)
            self._ux = self._uy = self._udx = self._udy = np.zeros_like(self._xg)
        self.par = geom.pack()
        if geom.rim_stiffness and self.machine:
            raise ValueError("a rim of finite stiffness is for a ground motion: the test machine's orbit "
                             "stays within the capacity")
        if geom.rim_stiffness and az is not None:
            raise ValueError("a rim of finite stiffness of the TFP is not yet with a vertical ground motion")
        self._ev = np.zeros(2)
        if az is None:
            self._az = np.zeros_like(self._ax)
        else:
            # every normal force, cap, the heat, the drive and the ledger see g + a_z (docs/model.md 10)
            if self.machine:
                raise ValueError("the test machine takes no vertical ground motion")
            self._az = float_array(az)
            if len(self._az) != len(self._ax):
                raise ValueError("the vertical ground motion must share the horizontal one's time grid")
            self.par[tk.I_VERT] = 1.0
            self.columns = COLUMNS + VERTICAL_COLUMNS
        self.S = np.zeros(K.N_S)
        self.N = self.S[K.S_N:K.S_N + 4]
        self.out = np.zeros(K.N_OUT)
        self._sc = np.zeros(K.N_SC)
        self._row = np.zeros(len(self.columns))
        self.n = 0
        self.t = 0.0
        if self.machine:
            self._place(float(self._ux[0]), float(self._uy[0]), float(self._udx[0]), float(self._udy[0]))
        K.normal_forces(self.par, self.S[0:4], self.S[4:8], 0.0, 0.0, 0.0, 0.0, 0.0, self.N, self._sc)

    def _place(self, ux, uy, vx, vy) -> None:
        """The machine places the bearing at u(0) and launches it at u'(0) on
        the inner surfaces (the stack seated, phi = 0: the pad's tilt with
        L_i sin|alpha| = |u|); the potential and kinetic energy it gives are input."""
        um = float(np.hypot(ux, uy))
        if um >= self.geom.Li:
            raise TFP3DFailure(f"the machine's start |u(0)| = {um:g} m is beyond the inner surfaces' reach")
        if um > 0.0:
            a = float(np.arcsin(um / self.geom.Li))
            self.S[2], self.S[3] = a * ux / um, a * uy / um
        C = np.zeros(8)
        K.grad_u(self.par, self.S[0:4], C)
        Ca = np.array([[C[4], C[6]], [C[5], C[7]]])        # du / dalpha
        self.S[6:8] = np.linalg.solve(Ca, [vx, vy])
        self.S[K.S_EIN] = self.E_kin() + self.E_pot()

    # -- accessors the loop and outputs use (and TFPState's) -------------------------------
    @property
    def q(self) -> np.ndarray:
        """(phi_x, phi_y, alpha_x, alpha_y)."""
        return self.S[0:4].copy()

    def footprints(self) -> tuple:
        """Footprint centres (x, y) on the lower plate, lower slider plate,
        upper slider plate and upper plate: +R phi / +R alpha on the lower
        parts, minus on the upper (the planar TFP's, per component)."""
        g, q = self.geom, self.S
        return ((g.R1 * q[0], g.R1 * q[1]), (g.R2 * q[2], g.R2 * q[3]),
                (-g.R3 * q[2], -g.R3 * q[3]), (-g.R4 * q[0], -g.R4 * q[1]))

    def E_kin(self) -> float:
        if self.par[tk.I_VERT] == 1.0:           # in flight too (docs/model.md 10)
            K.energies_vertical(self.par, self.S, self._ev, self._sc)
            return float(self._ev[0])
        return K.kinetic(self.par, self.S[0:4], self.S[4:8], self._sc)

    def E_pot(self) -> float:
        if self.par[tk.I_VERT] == 1.0:
            K.energies_vertical(self.par, self.S, self._ev, self._sc)
            return float(self._ev[1])
        return K.potential(self.par, self.S[0:4]) + K.rim_spring_energy(self.par, self.S[0:4])

    def ledger_residual(self) -> float:
        return self.E_in - (self.E_kin() + self.E_pot() + sum(self.W) + self.E_rim + self.E_land)

    def values(self) -> tuple:
        n = self.n
        K.row_values(self.par, self.S, self.t, self._xg[n], self._yg[n], self._row, self._sc)
        K.vertical_row(self.par, self.S, self._az[n - 1] if n > 0 else 0.0, self._row, self._sc)
        return tuple(self._row.tolist())

    # -- the compiled engine (coupling/engine_kernel.py with mechanics/dev_tfp3d.py) ----------
    engine_device = "fpd.mechanics.dev_tfp3d"

    @staticmethod
    def engine_worth_loading(n_steps: int) -> bool:
        """Loading numba and the cached engine pays for itself past a few
        thousand steps (the step with the compiled kernel from Python costs
        ~0.3 ms, in the engine ~0.07 ms)."""
        return n_steps >= 3000

    def engine_state(self):
        """(C, S, L, X) as the engine reads them: the stepper's own parameter
        and state vectors, the loading (ground acceleration per step, x, y,
        vertical; ground position per row, x, y; the rows' scratch), the
        step's output and scratch."""
        from fpd.loading.ground_motion import as_float64
        L = (as_float64(self._ax), as_float64(self._ay), as_float64(self._az), as_float64(self._xg),
             as_float64(self._yg), np.zeros(K.N_SC), as_float64(self._ux), as_float64(self._uy),
             as_float64(self._udx), as_float64(self._udy), np.array([1.0 if self.machine else 0.0]))
        return (self.par, self.S, L, (self.out, self._sc))

    def engine_pull(self, S) -> None:
        """Nothing to copy: the engine steps the stepper's own state."""

    def engine_push(self, S, n: int) -> None:
        self.n, self.t = n, n * self.dt

    # a rim reached under a ground motion: the seated model takes the impact (docs/model.md 6.11)
    RIM_MESSAGE = "a surface reached its rim"

    def set_static(self, mu_s, ratio) -> None:
        """The breakaway of S1..S4, as the planar TFP's (TFPStepper.set_static:
        the same slots of the same constants, read by tfp_kernel.holding_caps)."""
        TFPStepper.set_static(self, mu_s, ratio)

    # -- the step ---------------------------------------------------------------------------
    def step(self, mu1: float, mu2: float, mu3: float, mu4: float) -> tuple:
        n = self.n
        # a vertical ground motion: the step may lift the stack off and land it
        adv = self.k.advance_vertical if self.par[tk.I_VERT] == 1.0 else self.k.advance
        fail = adv(self.par, self.S, self.dt, self._ax[n], self._ay[n], self._az[n],
                   mu1, mu2, mu3, mu4, 1 if self.machine else 0, self._ux[n + 1], self._uy[n + 1],
                   self._udx[n + 1], self._udy[n + 1], self.out, self._sc)
        if fail == K.FAIL_CAPACITY:
            raise TFP3DFailure("the test machine's force did not make the bearing follow the orbit "
                               "(Newton on the machine's force did not converge; lower solver.dt)")
        if fail == K.FAIL_RIM:
            raise TFP3DFailure(self.RIM_MESSAGE if not self.machine else
                               "a surface reached its rim under the test machine: the TFP's machine in both "
                               "directions runs without rims (a smaller orbit)")
        if fail == K.FAIL_LAND:
            raise TFP3DFailure("the TFP would land from its flight beyond the outer surfaces' reach: a landing "
                               "on the rims is not modelled (docs/model.md 10)")
        if fail == K.FAIL_FIXED_POINT:
            raise TFP3DFailure(f"the step's fixed point on q(t_n+1) did not converge in {K.FIXED_POINT_ITERS} "
                               "iterations (lower solver.dt)")
        self.n = n + 1
        self.t = self.n * self.dt
        return tuple(float(x) for x in self.S[K.S_DW:K.S_DW + 4])
