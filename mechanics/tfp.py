"""The triple friction pendulum (TFP) of the paper's Figs. 3, 6, 7: geometry,
the rigid model's steppers (state holders around mechanics/tfp_kernel.py)
and its closed-form regime backbone.

Bodies bottom to top: lower plate (concave S1, radius R1, centre C1 on the
ground), lower slider plate (convex R1 on S1, concave S2 of radius R2 towards
the pad), pad (convex R2 and R3), upper slider plate (concave S3 of radius R3,
convex R4 on S4), upper plate with the superstructure (concave S4, R4).
Heights are apex to apex along each part's axis. Seated and at rest the
stack height is H = t_lower + pad_height + t_upper.

Rigid, non-articulated model (docs/model.md section 6): the pad's axis lies
on C2C3 (S2 and S3 slide together, R2 : R3), both slider plates stay seated
on their outer surfaces and turn together about the outer centres (S1 and S4
slide together, R1 : R4). Two coordinates: phi (the stack, outer) and alpha
(the pad relative to the sliders, inner). Rims: |R1 phi| <= d1, |R4 phi| <= d4,
|R2 alpha| <= d2, |R3 alpha| <= d3 (unilateral, inelastic).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from . import tfp_kernel as K
from .geometry import G_ACC
from fpd.loading.ground_motion import float_array
from .phases import BOTH, INNER, OUTER, PHASES, TFP_PHASES, MechanicsFailure  # noqa: F401

# regime codes (Fenz-Constantinou numbering where it applies; docs/model.md 6.4)
REGIMES = {0: "stick", 1: "I (S2+S3)", 3: "III (S1+S4)", 5: "V (S2+S3, outer rims)", 6: "I+III (all four)"}

STEEL = 7850.0

COLUMNS = ("t_s", "xg_m", "u_m", "v_mps", "F_N", "z_m", "theta_rad",
           "s1_m", "s2_m", "s3_m", "s4_m", "N1_N", "N2_N", "N3_N", "N4_N",
           "W1_J", "W2_J", "W3_J", "W4_J", "phase",
           "E_input_J", "E_kin_J", "E_pot_J", "E_rim_J",
           "phi_rad", "alpha_rad", "regime", "slide1", "slide2", "slide3", "slide4",
           "rim1", "rim2", "rim3", "rim4", "J_rim_Ns", "n_rim1", "n_rim2", "n_rim3", "n_rim4")
# the two-phase model's own columns (docs/model.md 6.6), after COLUMNS
TWO_PHASE_COLUMNS = ("E_reseat_J", "beta1_rad", "beta2_rad", "gamma1_rad", "gamma2_rad",
                     "diagonal", "diagonal_plates", "phases")
# a loading with a vertical component (docs/model.md 10): the step's vertical ground acceleration, last
VERTICAL_COLUMNS = ("az_mps2", "lift_m", "n_lift", "t_flight_s", "E_land_J")


@dataclass(frozen=True)
class TFPGeometry:
    R1: float
    R2: float
    R3: float
    R4: float
    pad_height: float
    pad_diameter: float
    slider_height_lower: float
    slider_height_upper: float
    slider_diameter: float
    d1: float
    d2: float
    d3: float
    d4: float
    pad_mass: float
    slider_mass: float
    mass: float                    # superstructure M (kg)
    g: float = G_ACC
    kind: str = "TFP"
    rim_restitution: float = 0.0   # Newton's e of a rim arrival (0: the inelastic stop)
    rim_stiffness: float = 0.0     # k (N/m) of a rim of finite stiffness on each surface (0: rigid rims)
    rim_damping: float = 0.0       # its dashpots' damping ratio zeta (docs/model.md 6.7)

    # -- lengths ---------------------------------------------------------------
    @property
    def l1(self) -> float:
        """|C1 C2|: the lower slider plate's outer centre to its inner centre."""
        return self.R1 - self.slider_height_lower - self.R2

    @property
    def l4(self) -> float:
        return self.R4 - self.slider_height_upper - self.R3

    @property
    def Li(self) -> float:
        """Inner DFP length |C2 C3| = R2 + R3 - pad_height."""
        return self.R2 + self.R3 - self.pad_height

    @property
    def A(self) -> float:
        """Outer lever l1 + l4; A + Li = R1 + R4 - H."""
        return self.l1 + self.l4

    @property
    def H(self) -> float:
        return self.slider_height_lower + self.pad_height + self.slider_height_upper

    @property
    def L(self) -> float:
        """Length of the whole stack, A + Li = R1 + R4 - H (outer sliding)."""
        return self.A + self.Li

    @property
    def a(self) -> float:
        return 0.5 * self.pad_diameter

    @property
    def contact_area(self) -> float:
        """Pad footprint (S2, S3)."""
        return math.pi * self.a ** 2

    @property
    def slider_area(self) -> float:
        """Slider plate footprint (S1, S4)."""
        return math.pi * (0.5 * self.slider_diameter) ** 2

    @property
    def areas(self) -> tuple:
        return (self.slider_area, self.contact_area, self.contact_area, self.slider_area)

    @property
    def radii(self) -> tuple:
        return (self.R1, self.R2, self.R3, self.R4)

    @property
    def weight(self) -> float:
        return self.mass * self.g

    @property
    def qmax(self) -> tuple:
        """Rim stops of the coordinates: (phi_max, alpha_max) (rad)."""
        return (min(self.d1 / self.R1, self.d4 / self.R4), min(self.d2 / self.R2, self.d3 / self.R3))

    @property
    def capacity(self) -> float:
        """Largest relative displacement: both coordinates at their rims (m)."""
        pm, am = self.qmax
        return self.A * math.sin(pm) + self.Li * math.sin(pm + am)

    def bodies(self) -> list:
        """(mass, a, b, J, rotates_with) of each moving body: r = -a e(phi) - b e(psi) from C1."""
        ms, mp = self.slider_mass, self.pad_mass
        rs, rp = 0.5 * self.slider_diameter, 0.5 * self.pad_diameter
        tl, tu, hp = self.slider_height_lower, self.slider_height_upper, self.pad_height
        return [
            (ms, self.R1 - 0.5 * tl, 0.0, ms * (3 * rs ** 2 + tl ** 2) / 12.0, "phi"),
            (mp, self.l1, self.R2 - 0.5 * hp, mp * (3 * rp ** 2 + hp ** 2) / 12.0, "psi"),
            (ms, self.A - (self.R4 - 0.5 * tu), self.Li, ms * (3 * rs ** 2 + tu ** 2) / 12.0, "phi"),
            (self.mass, self.A, self.Li, 0.0, "none"),
        ]

    def pack(self, two_phase: bool = False):
        """The kernel's parameter vector (tfp_kernel.I_*)."""
        import numpy as np
        p = np.zeros(K.N_PAR)
        b = self.bodies()
        p[K.I_AA] = sum(m * a * a for m, a, _, _, _ in b)
        p[K.I_B] = sum(m * bb * bb for m, _, bb, _, _ in b)
        p[K.I_K] = sum(m * a * bb for m, a, bb, _, _ in b)
        p[K.I_JPHI] = sum(J for _, _, _, J, w in b if w == "phi")
        p[K.I_JPSI] = sum(J for _, _, _, J, w in b if w == "psi")
        p[K.I_P1] = sum(m * a for m, a, _, _, _ in b)
        p[K.I_P2] = sum(m * bb for m, _, bb, _, _ in b)
        p[K.I_A], p[K.I_LI], p[K.I_G], p[K.I_MSUP] = self.A, self.Li, self.g, self.mass
        p[K.I_R1], p[K.I_R2], p[K.I_R3], p[K.I_R4] = self.R1, self.R2, self.R3, self.R4
        p[K.I_QMAX_PHI], p[K.I_QMAX_ALPHA] = self.qmax
        p[K.I_D1], p[K.I_D2], p[K.I_D3], p[K.I_D4] = self.d1, self.d2, self.d3, self.d4
        p[K.I_REST] = self.rim_restitution
        p[K.I_KRIM], p[K.I_ZRIM] = self.rim_stiffness, self.rim_damping
        # per surface: sum R_i^2 over its coordinate's surfaces that reach their rims with it
        # (the dashpot's m_eff = generalised inertia / that sum, docs/model.md 6.7)
        R, d = self.radii, (self.d1, self.d2, self.d3, self.d4)
        for i, pair in ((0, (0, 3)), (3, (0, 3)), (1, (1, 2)), (2, (1, 2))):
            p[K.I_SR + i] = sum(R[j] ** 2 for j in pair if abs(d[j] / R[j] - d[i] / R[i]) <= 1e-12 * d[i] / R[i])
        p[K.I_MS_LO] = p[K.I_MS_UP] = self.slider_mass
        p[K.I_MPAD] = self.pad_mass
        p[K.I_A_SL], p[K.I_A_PAD], p[K.I_B_PAD], p[K.I_A_SU] = b[0][1], b[1][1], b[1][2], b[2][1]
        # the two-phase model's corners (docs/model.md 6.6)
        ap, as_ = 0.5 * self.pad_diameter, 0.5 * self.slider_diameter
        p[K.I_TWO] = 1.0 if two_phase else 0.0
        p[K.I_AP], p[K.I_AS], p[K.I_HP] = ap, as_, self.pad_height
        p[K.I_TL], p[K.I_TU], p[K.I_L4] = self.slider_height_lower, self.slider_height_upper, self.l4
        p[K.I_EPB] = self.R2 - math.sqrt(self.R2 ** 2 - ap ** 2)
        p[K.I_EPT] = self.pad_height - self.R3 + math.sqrt(self.R3 ** 2 - ap ** 2)
        p[K.I_ESB] = self.R1 - math.sqrt(self.R1 ** 2 - as_ ** 2)
        p[K.I_SQ4] = math.sqrt(self.R4 ** 2 - as_ ** 2)
        return p

    def static_weights(self) -> tuple:
        """Vertical load carried by S1..S4 at rest (N)."""
        g, M, ms, mp = self.g, self.mass, self.slider_mass, self.pad_mass
        return ((M + 2 * ms + mp) * g, (M + ms + mp) * g, (M + ms) * g, M * g)


def tfp_geometry_errors(g: TFPGeometry) -> list:
    """Reasons the stack does not fit, as (key, value, what is allowed)."""
    out = []
    rs, rp = 0.5 * g.slider_diameter, 0.5 * g.pad_diameter
    for key, R in (("R1", g.R1), ("R4", g.R4)):
        if rs >= R:
            out.append(("device.slider_diameter", g.slider_diameter, f"< 2 {key} = {2 * R:g}"))
    for key, R in (("R2", g.R2), ("R3", g.R3)):
        if rp >= R:
            out.append(("device.pad_diameter", g.pad_diameter, f"< 2 {key} = {2 * R:g}"))
    if rp >= rs:
        out.append(("device.pad_diameter", g.pad_diameter, f"< slider_diameter = {g.slider_diameter:g}"))
    if g.Li <= 0:
        out.append(("device.pad_height", g.pad_height, f"< R2 + R3 = {g.R2 + g.R3:g}"))
    if g.l1 <= 0:
        out.append(("device.slider_height_lower", g.slider_height_lower, f"< R1 - R2 = {g.R1 - g.R2:g}"))
    if g.l4 <= 0:
        out.append(("device.slider_height_upper", g.slider_height_upper, f"< R4 - R3 = {g.R4 - g.R3:g}"))
    for i, (d, R) in enumerate(((g.d1, g.R1), (g.d2, g.R2), (g.d3, g.R3), (g.d4, g.R4)), start=1):
        if d >= 0.5 * math.pi * R:
            out.append((f"device.d{i}", d, f"< pi R{i} / 2 = {0.5 * math.pi * R:.4g} (a quarter circle)"))
    return out


class TFPFailure(MechanicsFailure):
    pass


class TFPState:
    """The accessors of a TFP stepper's state vector S that the loop and
    outputs use, at the indices of its kernel module, ``state_layout``
    (tfp_kernel, tfp3d_kernel: S_W, S_EIN, S_ERIM, S_SV, S_ELAND)."""

    state_layout = K

    @property
    def W(self) -> list:
        k = self.state_layout.S_W
        return [float(x) for x in self.S[k:k + 4]]

    @property
    def E_in(self) -> float:
        return float(self.S[self.state_layout.S_EIN])

    @property
    def E_rim(self) -> float:
        """The kinetic energy the rim impacts took (J); with rims of finite stiffness their dashpots' work."""
        return float(self.S[self.state_layout.S_ERIM])

    @property
    def slip_v(self) -> list:
        k = self.state_layout.S_SV
        return [float(x) for x in self.S[k:k + 4]]

    @property
    def E_land(self) -> float:
        """Energy taken by the lift-offs and landings (docs/model.md 10)."""
        return float(self.S[self.state_layout.S_ELAND])

    def save(self):
        return (self.n, self.t, self.S.copy())

    def restore(self, snap) -> None:
        self.n, self.t, S = snap
        self.S[:] = S


class TFPStepper(TFPState):
    """The rigid TFP under a ground motion (GroundMotion) or in the test
    machine (DisplacementProgramme: the superstructure's relative displacement
    imposed, its weight carried). ``step(mu1, mu2, mu3, mu4)`` advances one
    step and returns the friction work of S1..S4 in it. The state is one
    float64 vector (tfp_kernel.S_*), advanced by tfp_kernel.advance, so the
    compiled engine (coupling/engine_kernel.py with mechanics/dev_tfp.py) runs the same source."""

    n_interfaces = 4
    drawing = "tfp"           # the VTK drawing (outputs/device_drawings.py)

    def __init__(self, geom: TFPGeometry, loading, kernel=None, model: str = "seated", gz=None, axial=None):
        """gz: a vertical ground motion on the loading's grid, or None. axial:
        the test machine's axial-load programme (mechanics.axial.AxialProgramme)
        held in force control on the superstructure (the step's mean of N(t)
        at its two grid points; every normal force, cap and the ledger see
        it), or None: the weight M g."""
        import numpy as np
        if model not in ("seated", "two-phase"):
            raise ValueError(f"model must be 'seated' or 'two-phase', not {model!r}")
        self.model = model
        self.columns = COLUMNS + (TWO_PHASE_COLUMNS if model == "two-phase" else ())
        self.ground_z = gz
        self._az = None
        if gz is not None:
            if hasattr(loading, "u"):
                raise ValueError("the test machine takes no vertical ground motion")
            if gz.n_steps != loading.n_steps or gz.dt != loading.dt:
                raise ValueError("the vertical ground motion must share the horizontal one's time grid")
            self._az = float_array(gz.a_step)
            self.columns = self.columns + VERTICAL_COLUMNS
        self.geom = geom
        self.k = kernel if kernel is not None else K
        self._ev = np.zeros(2)
        self.dt = loading.dt
        self.n_steps = loading.n_steps
        self.machine = hasattr(loading, "u")
        if self.machine and geom.rim_stiffness:
            raise ValueError("a rim of finite stiffness is for a ground motion: the test machine's programme "
                             "stays within the capacity")
        if self.machine:
            self._u = float_array(loading.u)
            self._ud = float_array(loading.ud)
            self._a = float_array(-np.diff(loading.ud) / loading.dt)
            self._xg = None
        else:
            self._a = float_array(loading.a_step)
            self._xg = float_array(loading.d)
        self.par = geom.pack(two_phase=model == "two-phase")
        self.par[K.I_VERT] = 1.0 if gz is not None else 0.0
        self.axial = axial if axial is not None and axial.varying else None
        if self.axial is not None:
            if not self.machine:
                raise ValueError("an axial-load programme is the test machine's")
            Nt = self.axial.at(np.asarray(loading.t, dtype=float))
            self._az = float_array(0.5 * (Nt[:-1] + Nt[1:]))
            self.par[K.I_VERT] = 2.0
        self.S = np.zeros(K.N_S)
        self.st = self.S[0:4]                   # a view: phi, alpha and their rates
        self.N = self.S[K.S_N:K.S_N + 4]         # a view: N1..N4
        self.out = np.zeros(K.N_OUT)
        self._row = np.zeros(K.n_row(self.par))
        assert len(self.columns) == len(self._row), "tfp_kernel.N_ROW* and the COLUMNS tuples disagree"
        self._M, self._w, self._tmp = np.zeros(3), np.zeros(2), np.zeros(2)
        self._sc = np.zeros(4 + 2 * K.N_OUT)
        self.n = 0
        self.t = 0.0
        K.normal_forces(self.par, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, geom.g, 0.0, self.N)
        if self.axial is not None:
            K.top_load(self.par, 0.0, 0.0, float(self.axial.at(0.0)) - geom.weight, self.N)
        if self.machine and self._ud[0] != 0.0:
            # the machine launches the programme with u'(0) != 0 on the inner surfaces
            # (they slide first): that kinetic energy is input
            self.S[3] = self._ud[0] / geom.Li
            self.S[K.S_EIN] = self.E_kin()

    def set_static(self, mu_s, ratio) -> None:
        """The breakaway of S1..S4 (friction_kernel.holding_mu): static
        coefficients and static ratios to the sliding law, 0 where none is
        given. A coordinate at rest at a step's start takes its two surfaces'
        caps with the holding coefficient (docs/model.md section 11)."""
        for i in range(4):
            self.par[K.I_MUS + i] = float(mu_s[i])
            self.par[K.I_MUR + i] = float(ratio[i])

    # -- accessors the loop and outputs use -----------------------------------------
    @property
    def phi(self) -> float:
        return float(self.S[0])

    @property
    def alpha(self) -> float:
        return float(self.S[1])

    @property
    def F(self) -> float:
        return float(self.S[K.S_F])

    def slides(self) -> tuple:
        """Arc slid on S1..S4 (signed, m)."""
        g = self.geom
        return (g.R1 * self.phi, g.R2 * self.alpha, g.R3 * self.alpha, g.R4 * self.phi)

    def footprints(self) -> tuple:
        """Footprint centre on each heated part (lower plate, lower slider,
        upper slider, upper plate): +s on the lower parts, -s on the upper."""
        s = self.slides()
        return (s[0], s[1], -s[2], -s[3])

    @property
    def u(self) -> float:
        return K.u_rel(self.par, self.phi, self.alpha)

    def xg(self) -> float:
        if self.machine:
            return -self._u[self.n]
        return self._xg[self.n]

    def E_kin(self) -> float:
        if self.par[K.I_VERT] == 1.0:           # in flight too (docs/model.md 10)
            K.energies_vertical(self.par, self.S, self._ev)
            return float(self._ev[0])
        return K.kinetic(self.par, self.alpha, float(self.S[2]), float(self.S[3]))

    def E_pot(self) -> float:
        if self.par[K.I_VERT] == 1.0:
            K.energies_vertical(self.par, self.S, self._ev)
            return float(self._ev[1])
        return K.potential(self.par, self.phi, self.alpha) + K.rim_energy(self.par, self.phi, self.alpha)

    @property
    def E_reseat(self) -> float:
        """Kinetic energy removed by the re-seating of phases 2 and 3 (two-phase; 0 seated)."""
        return float(self.S[K.S_ERS])

    def ledger_residual(self) -> float:
        return self.E_in - (self.E_kin() + self.E_pot() + sum(self.W) + self.E_rim + self.E_reseat + self.E_land)

    def values(self) -> tuple:
        g = self.geom
        K.row_values(self.par, self.S, self.t, self.xg(), g.d1, g.d2, g.d3, g.d4, self._row)
        return tuple(self._row.tolist())

    # -- the compiled engine (coupling/engine_kernel.py) ---------------------------
    engine_device = "fpd.mechanics.dev_tfp"
    two_d = False

    @staticmethod
    def engine_worth_loading(n_steps: int) -> bool:
        """The TFP's Python step costs ~85 us: past ~5000 steps loading numba
        (and the cached engine) pays for itself even without an fe1d part
        (benchmarks/tfp_speed.py)."""
        return n_steps >= 5000

    def engine_state(self):
        """(C, S, L, X) as the engine reads them: the stepper's own parameter
        and state vectors, the loading (a per step; the machine's u, u' per
        step, zeros for a ground motion; xg per row; d1..d4 and the machine
        flag; a_z per step), the stepper's scratch."""
        import numpy as np
        from fpd.loading.ground_motion import as_float64
        if self.machine:
            U, UD = as_float64(self._u), as_float64(self._ud)
            XG = -U
        else:
            XG = as_float64(self._xg)
            U = UD = XG                 # (read only by the machine)
        g = self.geom
        DD = np.array([g.d1, g.d2, g.d3, g.d4, 1.0 if self.machine else 0.0])
        A = as_float64(self._a)
        AZ = as_float64(self._az) if self._az is not None else A     # (read only with par[I_VERT])
        return (self.par, self.S, (A, U, UD, XG, DD, AZ),
                (self.out, self._M, self._w, self._tmp, self._sc))

    def engine_pull(self, S) -> None:
        """Nothing to copy: the engine steps the stepper's own state."""

    def engine_push(self, S, n: int) -> None:
        self.n, self.t = n, n * self.dt

    # -- the step -----------------------------------------------------------------
    def step(self, mu1: float, mu2: float, mu3: float, mu4: float) -> tuple:
        n = self.n
        az = self._az[n] if self._az is not None else 0.0
        if self.machine:
            fail = self.k.advance(self.par, self.S, self.dt, self._a[n], az, mu1, mu2, mu3, mu4, 1,
                                  self._u[n + 1], self._ud[n + 1], self.out, self._M, self._w, self._tmp, self._sc)
        elif self.par[K.I_VERT] == 1.0:
            # a vertical ground motion: the step may lift the stack off and land it
            fail = self.k.advance_vertical(self.par, self.S, self.dt, self._a[n], az, mu1, mu2, mu3, mu4, 0, 0.0,
                                           0.0, self.out, self._M, self._w, self._tmp, self._sc)
        else:
            fail = self.k.advance(self.par, self.S, self.dt, self._a[n], az, mu1, mu2, mu3, mu4, 0, 0.0, 0.0,
                                  self.out, self._M, self._w, self._tmp, self._sc)
        if fail == K.FAIL_CAPACITY:
            raise TFPFailure(f"the test machine drives the bearing past its displacement capacity "
                             f"{self.geom.capacity:.4g} m (all surfaces at their rims)")
        if fail == K.FAIL_ROCKING:
            gv, dn = self.geom.g + az, 0.0
            if self.axial is not None:
                gv, dn = self.geom.g, az - self.geom.weight
            part = "pad" if K.rocking_loaded(self.par, self.phi, self.alpha, self._a[n], gv, dn) == 1 \
                else "slider plates"
            raise TFPFailure(f"the {part} would start rocking on a corner "
                             f"(ground acceleration {self._a[n] / gv:.3g} (g + a_z) beyond the restoring "
                             "moment of Eq. 7): rocking of the TFP's parts is not modelled (docs/model.md 6.6)")
        if fail == K.FAIL_FIXED_POINT:
            n = K.RIM_ITERS if self.par[K.I_KRIM] != 0.0 else K.FIXED_POINT_ITERS
            raise TFPFailure(f"the step's fixed point on q(t_n+1) did not converge in {n} "
                             "iterations (lower solver.dt)")
        if fail == K.FAIL_LAND:
            raise TFPFailure("the TFP would land from its flight beyond the outer surfaces' reach: a landing on "
                             "the rims is not modelled (docs/model.md 10)")
        self.n = n + 1
        self.t = self.n * self.dt
        return tuple(float(x) for x in self.S[K.S_DW:K.S_DW + 4])
