"""The orbit test machine: a seated DFP/SFP in a bearing-test machine driven
along a planar orbit (loading.orbits.OrbitProgramme), stepped by the stepper
in both directions' kernel (mechanics/bidirectional_kernel.py
``machine_step``; through a compliant link, machines/link_kernel.py); as
the engine sees it:
machines/dev_orbit_machine.py."""
from __future__ import annotations

import math

import numpy as np

from fpd.machines import link_kernel as _link
from fpd.mechanics.bidirectional import K, _Base, _pure
from fpd.mechanics.geometry import DeviceGeometry


class BidirectionalTestMachine(_Base):
    """Seated DFP/SFP in a bearing-test machine driven along a planar orbit
    (loading.orbits.OrbitProgramme). F_N components are the restraint's
    horizontal force; the normal forces include its axial share."""

    def __init__(self, geom: DeviceGeometry, programme, jit: bool | None = None, axial=None):
        """axial: None (the superstructure rides on the bearing with its weight
        and inertia), or an axial-load programme (loading.axial.AxialProgramme:
        "constant" W, "sine", "series") the vertical actuator holds in force
        control: the superstructure has no inertia, N(t) takes the place of
        M g in the normal forces and the restoring moment, and the
        actuator's work beyond the weight's is input."""
        u0, v0 = programme.u[0], programme.ud[0]
        self._setup(geom, programme.dt, programme.n_steps, True, jit,
                    u0=(float(u0[0]), float(u0[1])), v0=(float(v0[0]), float(v0[1])), seated=True)
        self.prog = programme
        self.C[K.C_DT] = self.dt                # the dwell time's step (bidirectional_kernel.machine_step)
        self._U = np.ascontiguousarray(programme.u, dtype=float)
        self._UD = np.ascontiguousarray(programme.ud, dtype=float)
        self._UDD = np.ascontiguousarray(programme.udd, dtype=float)
        self._GV = np.full(1, geom.g)
        self.axial = axial
        if axial is not None:
            self._GV = np.ascontiguousarray(axial.at(np.asarray(programme.t, dtype=float)) / geom.mass, dtype=float)
            C, S = self.C, self.S
            C[K.C_AXIAL] = 1.0
            C[K.C_I] = geom.I - geom.mass * geom.L ** 2
            C[K.C_SIN] = geom.S - geom.mass * geom.L
            Ek, Ep = _pure.energies(C, S)
            S[K.S_EIN] = Ek + Ep        # the launch's kinetic energy without the held superstructure's
            nz = S[K.S_NZ]
            S[K.S_N2] = geom.mass * self._GV[0] * -nz
            S[K.S_N1] = S[K.S_N2] + geom.pad_mass * geom.g * -nz
        self.normal_force = "seated"

    def set_static(self, mu_s1: float, mu_s2: float, ratio1: float = 0.0, ratio2: float = 0.0) -> None:
        """As the stepper's; the bearing starts at rest (stuck) before the
        programme launches it, so its first step breaks it away."""
        super().set_static(mu_s1, mu_s2, ratio1, ratio2)
        self.S[K.S_MODE] = K.STICK

    LINK_STEP = 0.02      # omega h per sub-step of the compliant link (as SeatedTestMachine's)

    def set_link(self, stiffness: float, plate_mass: float) -> None:
        """Drive the plate through a compliant link (link_kernel.orbit_link_step):
        a spring of ``stiffness`` (N/m) between the machine and the plate of mass
        ``plate_mass`` (kg); the bearing starts at rest at the programme's start.
        Sub-steps keep omega h <= LINK_STEP, omega the link's frequency with the
        bearing's restoring stiffness and inertia at u = 0."""
        C, S = self.C, self.S
        C[K.C_LINK], C[K.C_MPL] = float(stiffness), float(plate_mass)
        g = C[K.C_G]
        F0 = _pure.machine_point(C, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, g)[0]
        B = _pure.machine_point(C, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, g)[0] - F0
        du = 1e-6 * C[K.C_L]
        Kb = (_pure.machine_point(C, du, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, g)[0] - F0) / du
        m = plate_mass + B
        if not m > 0.0:
            raise ValueError(f"the plate's mass with the bearing's ({m:g} kg) must be > 0")
        omega = math.sqrt((stiffness + Kb) / m)
        C[K.C_NSUB] = float(max(1, math.ceil(self.dt * omega / self.LINK_STEP)))
        S[K.S_WX] = S[K.S_WY] = S[K.S_WZ] = 0.0
        S[K.S_MODE] = K.STICK
        S[K.S_SV1] = S[K.S_SV2] = 0.0
        Ek, Ep = _pure.energies(C, S)
        S[K.S_EIN] = Ek + Ep

    def set_dwell(self, lower: tuple, upper: tuple) -> None:
        """As the stepper's; the bearing starts at rest before the programme."""
        super().set_dwell(lower, upper)
        self.S[K.S_MODE] = K.STICK

    def ground_position(self):
        # the lower plate moves by -u
        return (-float(self._U[self.n, 0]), -float(self._U[self.n, 1]))

    # -- the compiled engine (coupling/engine_kernel.py) ----------------------------
    engine_device = "fpd.machines.dev_orbit_machine"

    def engine_state(self):
        """(C, S, L, X) as the engine reads them: the stepper's own arrays (it
        steps with the compiled kernel from now on), the programme (u, u',
        u'' per grid point), no scratch. ImportError without numba."""
        self.use_compiled()
        if not self.compiled:
            raise ImportError("numba is not available")
        return self.C, self.S, (self._U, self._UD, self._UDD, self._GV), (np.zeros(1),)

    def engine_pull(self, S) -> None:
        """Nothing to copy: the engine steps the stepper's own state."""

    def engine_push(self, S, n: int) -> None:
        self.n = n

    def _machine(self):
        """The machine's step (machines/link_kernel.py), compiled when the stepper's kernel is."""
        if self.compiled:
            from fpd import kernels
            return kernels.compiled("fpd.machines.link_kernel")
        return _link

    def step(self, mu1: float, mu2: float) -> tuple[float, float]:
        if self.n >= self.n_steps:
            raise IndexError(f"all {self.n_steps} steps of the loading are taken")
        S = self.S
        W1, W2 = S[K.S_W1], S[K.S_W2]
        self._machine().orbit_machine_step(self.C, S, self._U, self._UD, self._UDD, self._GV, self.n, mu1, mu2)
        self.n += 1
        return float(S[K.S_W1] - W1), float(S[K.S_W2] - W2)
