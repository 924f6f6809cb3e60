"""Time stepping shared by the FE plate models, with an exact heat ledger.

The semi-discrete system (model.md section 4) is

    M u' + A u = b(t),      u = T - T_air,  A = K + C,

with M the (rho c weighted) mass matrix, K the conduction matrix, C the
convective boundary mass (h on the exposed faces) and b the friction load
(W), held constant over a step. Dofs are ordered free first, then the
Dirichlet (fixed-temperature) dofs, which never change; the integrator
solves for the increment du = u^{n+1} - u^n on the free dofs only, so the
Dirichlet columns drop out exactly.

Schemes (all use a matrix M + gamma A, factorised once per gamma):

- ``be``:   (M + dt A) du = dt (b - A u)
- ``cn``:   (M + dt/2 A) du = dt (b - A u).
- ``bdf2``: (M + 2 dt/3 A) du = 2 dt/3 (G - A u) + 1/3 M du_prev.
  G = 3/2 b^{n+1} - 1/2 b^n is the BDF2 derivative of the
  cumulative heat input, so the scheme delivers exactly sum(b) dt per step
  (and G is a second-order value of the load at t_{n+1} when the step loads
  sample a smooth flux at mid-step).
- start-up (cn, bdf2): at t = 0 and after every jump of the load (a change
  larger than jump_rtol), the next step (cn) or two steps (bdf2) are each
  taken as START_SUBSTEPS backward-Euler substeps (Rannacher's remedy,
  with more, smaller substeps: they also resolve the sqrt(t) onset of the
  surface temperature). ``rannacher=False`` turns it off (plain CN rings;
  BDF2 then starts with one backward-Euler step).

Ledger: heat_in += dt sum(b). The loss is computed from the boundary fluxes
with the scheme's own time rule, never as a difference: the convective part
c . u (c = C 1) and the Dirichlet reaction 1_D^T (residual of the scheme on
the Dirichlet rows); for BDF2 the per-step loss source s_n is passed through
the same filter as the energy, l_n = 2/3 (s_n + l_{n-1}/2). Then
sum 1^T M du = heat_in - heat_lost holds to round-off for every scheme.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

SCHEMES = ("bdf2", "cn", "be")
# Start-up after t = 0 and after every jump of the load (Rannacher-type): the
# first START_STEPS[scheme] steps are each taken as START_SUBSTEPS backward-Euler
# substeps. It damps the stiff modes a jump excites (CN would ring) and resolves
# the sqrt(t) onset of the surface temperature (docs/thermal.md, section 2).
START_SUBSTEPS = 8
START_STEPS = {"cn": 1, "bdf2": 2}


class Integrator:
    """Steps M u' + A u = b on free dofs [:nf] with Dirichlet dofs [nf:].

    mass(x), stiff(x): full-length products M x, A x (new arrays or views
    that the caller does not keep). factor(gamma): returns solve(rhs_free)
    for the free block of M + gamma A. conv: c = C 1 (W/K per dof).
    mD, aD: 1_D^T M and 1_D^T A (rows summed over the Dirichlet dofs).
    """

    def __init__(self, mass: Callable, stiff: Callable, factor: Callable,
                 conv: np.ndarray, nf: int, mD: np.ndarray, aD: np.ndarray,
                 u0: np.ndarray, dt: float, scheme: str, jump_rtol: float = 0.1,
                 rannacher: bool = True, start_substeps: int = START_SUBSTEPS):
        if scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {SCHEMES}, got {scheme!r}")
        if not dt > 0:
            raise ValueError(f"dt must be > 0, got {dt}")
        self.mass, self.stiff, self._factor = mass, stiff, factor
        self.conv, self.nf, self.mD, self.aD = conv, nf, mD, aD
        self.has_dirichlet = nf < len(u0)
        self.dt, self.scheme, self.jump_rtol = float(dt), scheme, jump_rtol
        self.rannacher = rannacher     # False: plain CN / plain BDF2 start (for tests)
        self.start_substeps = int(start_substeps)
        self._start_left = 0           # steps of the current start-up still to take
        self._solvers: dict[float, Callable] = {}
        n = len(u0)
        self.u = np.array(u0, dtype=float)
        self._m1 = np.array(mass(np.ones(len(u0))), dtype=float)   # M 1 = M^T 1
        self._e0 = float(self._m1 @ self.u)
        self.du = np.zeros(n)          # last increment (BDF2 history)
        self.b = np.zeros(n)           # last load
        self.heat_in = 0.0
        self.heat_lost = 0.0
        self.loss_prev = 0.0           # BDF2 filtered loss of the last step
        self.steps = 0
        self.load_scale = 0.0          # largest load 1-norm seen (jump detection)
        self.half_steps = 0            # start-up BE substeps taken (diagnostic)

    # -- factorisations, one per gamma ------------------------------------
    def solver(self, gamma: float) -> Callable:
        s = self._solvers.get(gamma)
        if s is None:
            s = self._solvers[gamma] = self._factor(gamma)
        return s

    # -- state ----------------------------------------------------------------
    def save(self):
        return (self.u.copy(), self.du.copy(), self.b.copy(), self.heat_in,
                self.heat_lost, self.loss_prev, self.steps, self.half_steps, self._start_left,
                self.load_scale)

    def restore(self, snap) -> None:
        (u, du, b, self.heat_in, self.heat_lost, self.loss_prev, self.steps, self.half_steps,
         self._start_left, self.load_scale) = snap
        self.u[:] = u
        self.du[:] = du
        self.b[:] = b

    # -- stepping -------------------------------------------------------------
    def _dirichlet_reaction(self, Mdu: float, Au: float, h: float, load_D: float) -> float:
        """1_D^T of the scheme's residual on the Dirichlet rows (heat supplied
        by the fixed-temperature boundary over the step, J)."""
        return Mdu + h * Au - h * load_D

    def _increment(self, h: float, b: np.ndarray, gamma: float) -> np.ndarray:
        """du = (M + gamma A)^-1 h (b - A u) on the free dofs, added to u and
        kept in self.du (backward Euler: gamma = h, CN: h / 2)."""
        nf = self.nf
        rhs = h * (b - self.stiff(self.u))
        du = self.solver(gamma)(rhs[:nf])
        self.u[:nf] += du
        self.du[:nf] = du
        return du

    def _be(self, h: float, b: np.ndarray, power: float) -> float:
        nf = self.nf
        du = self._increment(h, b, h)
        s = h * (self.conv @ self.u)
        if self.has_dirichlet:
            s -= self._dirichlet_reaction(self.mD[:nf] @ du, self.aD @ self.u, h, b[nf:].sum())
        self.heat_in += h * power
        self.heat_lost += s
        return s

    def _cn(self, h: float, b: np.ndarray, power: float) -> None:
        nf = self.nf
        cu = self.conv @ self.u
        aDu = self.aD @ self.u if self.has_dirichlet else 0.0
        du = self._increment(h, b, 0.5 * h)
        s = 0.5 * h * (cu + self.conv @ self.u)
        if self.has_dirichlet:
            aDu = 0.5 * (aDu + self.aD @ self.u)
            s -= self._dirichlet_reaction(self.mD[:nf] @ du, aDu, h, b[nf:].sum())
        self.heat_in += h * power
        self.heat_lost += s

    def _bdf2(self, h: float, b: np.ndarray, power: float) -> None:
        nf = self.nf
        G = 1.5 * b - 0.5 * self.b
        rhs = (2.0 / 3.0) * h * (G - self.stiff(self.u)) + (1.0 / 3.0) * self.mass(self.du)
        du = self.solver(2.0 * h / 3.0)(rhs[:nf])
        du_prev_f = self.du[:nf].copy() if self.has_dirichlet else None
        self.u[:nf] += du
        self.du[:nf] = du
        s = h * (self.conv @ self.u)
        if self.has_dirichlet:
            Mdu = self.mD[:nf] @ (1.5 * du - 0.5 * du_prev_f)
            s -= self._dirichlet_reaction(Mdu, self.aD @ self.u, h, G[nf:].sum())
        loss = (2.0 / 3.0) * (s + 0.5 * self.loss_prev)
        self.loss_prev = loss
        self.heat_in += h * power
        self.heat_lost += loss

    def is_jump(self, b: np.ndarray) -> bool:
        """A change of the load (pattern or magnitude, 1-norm) larger than
        jump_rtol times the largest load seen so far: the non-smooth data
        that makes plain CN ring. Relative to the running maximum, not to the
        current load, so that a smooth ramp up from zero (a sliding speed
        through a reversal) is not taken for a jump, while a switch-on after
        a stick phase is."""
        size = np.abs(b).sum()
        if size > self.load_scale:
            self.load_scale = size
        return np.abs(b - self.b).sum() > self.jump_rtol * self.load_scale

    def _starting(self, jump: bool) -> bool:
        """Whether this step belongs to a start-up (after t = 0 or a jump)."""
        if not self.rannacher or self.scheme == "be":
            return False
        if self.steps == 0 or jump:
            self._start_left = START_STEPS[self.scheme]
        if self._start_left > 0:
            self._start_left -= 1
            return True
        return False

    def _substeps(self, h: float, b: np.ndarray, power: float) -> float:
        """One step of length h as start_substeps backward-Euler substeps;
        du is the whole step's increment (BDF2 history), the loss their sum."""
        nf = self.nf
        u_before = self.u[:nf].copy()
        m = self.start_substeps
        loss = sum(self._be(h / m, b, power) for _ in range(m))
        self.du[:nf] = self.u[:nf] - u_before
        self.half_steps += m
        return loss

    def step(self, b: np.ndarray, power: float) -> None:
        """Advance one step dt with the load vector b (W), sum(b) = power."""
        h = self.dt
        if self.scheme == "be":
            self._be(h, b, power)
        elif self._starting(self.steps > 0 and self.is_jump(b)):
            self.loss_prev = self._substeps(h, b, power)
        elif self.scheme == "cn":
            self._cn(h, b, power)
        else:
            if self.steps == 0:
                self.loss_prev = self._be(h, b, power)
            else:
                self._bdf2(h, b, power)
        self.b[:] = b
        self.steps += 1

    def stored(self) -> float:
        """1^T M (u - u_0) (J): the rho c integral of the temperature rise."""
        return float(self._m1 @ self.u - self._e0)
