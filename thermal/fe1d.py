"""Transient conduction through the plate thickness (model.md section 4, fe1d).

rho c T_t = k T_zz on 0 < z < H (depth z from the sliding face), P1 elements
on a mesh graded toward the sliding face, flux q = power / A_c in at z = 0,
the back face z = H convective (h_conv to T_air), adiabatic or at T_back_C.
The column has the footprint's cross-section A_c, so every matrix is in W/K
or J/K and the ledger is in J. This is the 1D counterpart of the paper's
lumped Eq. (9): the same heat, but resolved through the thickness.

Source placement (params.source):

- ``follow-pad``: the column under the pad receives the flux at every step,
  wherever the pad is (an upper bound of the surface temperature);
- ``fixed-point``: the column at the material point of arc position r0 =
  params.radius_m receives the flux only while the footprint covers it,
  |centre - r0| <= a; its surface temperature is returned. heat_in counts
  what this column received, not the whole friction work.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.linalg import blas, lapack

from fpd.meshes.line import line_mesh
from fpd.thermal.jit import OptionalKernels
from fpd.thermal.params import PlateParams
from fpd.thermal.stepping import START_STEPS, Integrator

BACKS = ("convection", "adiabatic", "fixed")
SOURCES = ("follow-pad", "fixed-point")

_KERNELS = OptionalKernels("fpd.thermal._column_jit", warm=True)


def jit_kernels():
    """thermal._column_jit if numba is installed and FPD_NO_JIT is unset, else None."""
    k = _KERNELS()
    return k[0] if k else None


def assemble_column(z: np.ndarray, rho_c: float, k: float, area: float):
    """Consistent P1 mass and stiffness of the column as tridiagonals
    (diag, offdiag) for mass (J/K) and conduction (W/K)."""
    from skfem import Basis, BilinearForm, ElementLineP1, MeshLine

    @BilinearForm
    def mass(u, v, w):
        return rho_c * area * u * v

    @BilinearForm
    def conduction(u, v, w):
        return k * area * u.grad[0] * v.grad[0]

    basis = Basis(MeshLine(z), ElementLineP1())
    M = mass.assemble(basis).todia()
    K = conduction.assemble(basis).todia()
    # skfem numbers MeshLine nodes in the order given, so these are tridiagonal
    def diags(A):
        A = A.tocsr()
        return A.diagonal().copy(), A.diagonal(1).copy()
    return diags(M), diags(K)


def check_params(p: PlateParams) -> None:
    """One clear line for a value the FE models cannot use."""
    for name in ("k", "rho", "c", "plate_thickness", "plate_radius", "a_contact_m"):
        if not getattr(p, name) > 0:
            raise ValueError(f"thermal.{name} must be > 0, got {getattr(p, name)!r}")
    if not p.h_conv >= 0:
        raise ValueError(f"thermal.h_conv must be >= 0, got {p.h_conv!r}")
    if p.back not in BACKS:
        raise ValueError(f"thermal.back must be one of {BACKS}, got {p.back!r}")
    if p.source not in SOURCES:
        raise ValueError(f"thermal.source must be one of {SOURCES}, got {p.source!r}")


class ColumnIntegrator(Integrator):
    """The Integrator specialised to the column (same schemes, same ledger):
    the load sits on the surface node, convection and the fixed temperature
    on the back node, so the hot loop is two banded BLAS products, one
    dpttrs and scalar ledger updates; no per-step skfem, no sparse matrices."""

    def __init__(self, tri, conv_back: float, nf: int, u0, dt, scheme, jump_rtol, rannacher=True,
                 jit: bool | None = None):
        dM, eM, dA, eA = tri
        n = len(dM)
        # upper band storage, Fortran order so that f2py passes it without a copy
        self._Mb = np.zeros((2, n), order="F")
        self._Mb[1], self._Mb[0, 1:] = dM, eM
        self._Ab = np.zeros((2, n), order="F")
        self._Ab[1], self._Ab[0, 1:] = dA, eA
        self._tri = tri
        # reference-BLAS dsbmv costs ~25 ns per row; numpy's tridiagonal
        # product wins beyond a few hundred rows (measured, docs/thermal.md)
        self._use_blas = n <= 300
        self._t1 = np.empty(n - 1)
        conv = np.zeros(n)
        conv[-1] = conv_back
        self._cb = conv_back
        mD, aD = np.zeros(n), np.zeros(n)
        if nf < n:
            mD[-2:] = eM[-1], dM[-1]
            aD[-2:] = eA[-1], dA[-1]
        self._mD1 = mD[-2]
        self._aD = (aD[-2], aD[-1])
        super().__init__(self._mass, self._stiff, self._factor, conv, nf, mD, aD,
                         u0, dt, scheme, jump_rtol, rannacher)
        self._q = 0.0
        self._c23 = None
        self._factors = {}
        # the numba path (bdf2 without a Dirichlet node; start-up steps stay
        # pure): constants K and state W packed as _column_jit expects, with
        # u and du views of W so that both paths share the state
        kern = jit_kernels() if jit is None or jit else None
        if jit and kern is None:
            raise ImportError("fe1d: jit=True needs numba")
        # (beyond 300 rows the pure path's products are numpy's, not dsbmv)
        self._kern = kern if (kern is not None and scheme == "bdf2" and nf == n and self._use_blas) else None
        self._stored_ok = False
        if self._kern is not None:
            self._K = np.zeros(7 * n)
            self._K[:2 * n] = self._Mb.ravel(order="F")
            self._K[2 * n:4 * n] = self._Ab.ravel(order="F")
            self._K[6 * n:] = self._m1
            self._W = np.zeros(3 * n + kern.N_SCALARS)
            self._W[:n], self._W[n:2 * n] = self.u, self.du
            self.u, self.du = self._W[:n], self._W[n:2 * n]
            self._I = np.array([n, 1, 2, 1, 1, 0, ord("U")], dtype=np.int32)
            self._sc = 3 * n
            self._bdf2_kernel = kern.bdf2_column

    def _band(self, alpha: float, band: np.ndarray, x: np.ndarray, y=None) -> np.ndarray:
        """alpha B x (+ y, in place, when y is given) for a tridiagonal B in
        upper band storage."""
        if self._use_blas:
            if y is None:
                return blas.dsbmv(1, alpha, band, x)
            return blas.dsbmv(1, alpha, band, x, beta=1.0, y=y, overwrite_y=1)
        t = self._t1
        out = np.multiply(band[1], x)
        np.multiply(band[0, 1:], x[1:], out=t)
        out[:-1] += t
        np.multiply(band[0, 1:], x[:-1], out=t)
        out[1:] += t
        out *= alpha
        if y is None:
            return out
        y += out
        return y

    def _mass(self, x):
        return self._band(1.0, self._Mb, x)

    def _stiff(self, x):
        return self._band(1.0, self._Ab, x)

    def _factor(self, gamma: float):
        dM, eM, dA, eA = self._tri
        nf = self.nf
        df, ef, info = lapack.dpttrf(dM[:nf] + gamma * dA[:nf], eM[:nf - 1] + gamma * eA[:nf - 1])
        if info != 0:
            raise np.linalg.LinAlgError(f"dpttrf failed (info={info})")
        self._factors[gamma] = (df, ef)
        dpttrs = lapack.dpttrs
        return lambda rhs: dpttrs(df, ef, rhs)[0]

    def _reaction(self, Mdu_last: float, h: float, uth_2: float, uth_1: float) -> float:
        # 1_D^T residual on the back node (no load there)
        return self._mD1 * Mdu_last + h * (self._aD[0] * uth_2 + self._aD[1] * uth_1)

    def _be1(self, h: float, q: float) -> float:
        nf, u = self.nf, self.u
        rhs = self._band(-h, self._Ab, u)
        rhs[0] += h * q
        du = self.solver(h)(rhs[:nf])
        u[:nf] += du
        self.du[:nf] = du
        s = h * self._cb * u[-1]
        if nf < len(u):
            s -= self._reaction(du[-1], h, u[-2], u[-1])
        self.heat_in += h * q
        self.heat_lost += s
        return s

    def _cn1(self, h: float, q: float) -> None:
        nf, u = self.nf, self.u
        rhs = self._band(-h, self._Ab, u)
        rhs[0] += h * q
        u2, u1 = u[-2], u[-1]
        du = self.solver(0.5 * h)(rhs[:nf])
        u[:nf] += du
        self.du[:nf] = du
        s = 0.5 * h * self._cb * (u1 + u[-1])
        if nf < len(u):
            s -= self._reaction(du[-1], h, 0.5 * (u2 + u[-2]), u[-1])
        self.heat_in += h * q
        self.heat_lost += s

    def _bdf21(self, h: float, q: float) -> None:
        nf, u = self.nf, self.u
        c23 = self._c23 if self._c23 is not None else self._bdf2_setup(h)
        if self._kern is not None:
            W = self._W
            self._bdf2_kernel(self._K, W, self._I, c23, 1.5 * q - 0.5 * self._q, h * self._cb)
            self._stored_ok = True
            loss = (2.0 / 3.0) * (W[self._sc + 2] + 0.5 * self.loss_prev)
            self.loss_prev = loss
            self.heat_in += h * q
            self.heat_lost += loss
            return
        rhs = self._band(-c23, self._Ab, u)
        rhs = self._band(1.0 / 3.0, self._Mb, self.du, rhs)
        rhs[0] += c23 * (1.5 * q - 0.5 * self._q)
        du = self._bdf2_solve(rhs[:nf])
        u[:nf] += du
        if nf == len(u):
            last_prev = 0.0
            self.du[:] = du
            s = h * self._cb * u[-1]
        else:
            last_prev = self.du[nf - 1]
            self.du[:nf] = du
            s = h * self._cb * u[-1] - self._reaction(1.5 * du[-1] - 0.5 * last_prev, h, u[-2], u[-1])
        loss = (2.0 / 3.0) * (s + 0.5 * self.loss_prev)
        self.loss_prev = loss
        self.heat_in += h * q
        self.heat_lost += loss

    def _bdf2_setup(self, h: float) -> float:
        self._c23 = 2.0 * h / 3.0
        self._bdf2_solve = self.solver(self._c23)
        if self._kern is not None:
            df, ef = self._factors[self._c23]
            n = len(self.u)
            self._K[4 * n:5 * n] = df
            self._K[5 * n:6 * n - 1] = ef
        return self._c23

    def _jump(self, q: float) -> bool:
        """Integrator.is_jump for the scalar surface load."""
        if abs(q) > self.load_scale:
            self.load_scale = abs(q)
        return abs(q - self._q) > self.jump_rtol * self.load_scale

    def step_surface(self, q: float) -> None:
        """Advance dt with the power q (W) into the surface node (schemes and
        start-up as Integrator.step). Returns u[0] on the kernel's fast path,
        else None."""
        if (self._kern is not None and self._c23 is not None and self.rannacher
                and self._start_left <= 0 and self.steps > 0):
            # the common BDF2 step, inlined (same operations as below); a jump
            # falls through to the start-up, whose _jump gives the same answer
            aq = abs(q)
            if aq > self.load_scale:
                self.load_scale = aq
            if not abs(q - self._q) > self.jump_rtol * self.load_scale:
                h = self.dt
                W = self._W
                u0 = self._bdf2_kernel(self._K, W, self._I, self._c23, 1.5 * q - 0.5 * self._q, h * self._cb)
                self._stored_ok = True
                loss = (2.0 / 3.0) * (W[self._sc + 2] + 0.5 * self.loss_prev)
                self.loss_prev = loss
                self.heat_in += h * q
                self.heat_lost += loss
                self._q = q
                self.b[0] = q
                self.steps += 1
                return u0
        h = self.dt
        sch = self.scheme
        self._stored_ok = False
        if sch == "be":
            self._be1(h, q)
        elif self.rannacher and (self._start_left > 0 or self.steps == 0 or self._jump(q)):
            if self.steps == 0 or self._jump(q):
                self._start_left = START_STEPS[sch]
            self._start_left -= 1
            nf = self.nf
            u_before = self.u[:nf].copy()
            m = self.start_substeps
            loss = 0.0
            for _ in range(m):
                loss += self._be1(h / m, q)
            self.du[:nf] = self.u[:nf] - u_before
            self.loss_prev = loss
            self.half_steps += m
        elif sch == "cn":
            self._cn1(h, q)
        elif self.steps == 0:
            self.loss_prev = self._be1(h, q)
        else:
            self._bdf21(h, q)
        self._q = q
        self.b[0] = q
        self.steps += 1

    def restore(self, snap) -> None:
        super().restore(snap)
        self._q = self.b[0]
        self._stored_ok = False

    def stored(self) -> float:
        if self._stored_ok:                 # m1 . u from the kernel's ddot
            return float(self._W[self._sc + 3] - self._e0)
        return super().stored()


class FE1DPlate:
    """PlateModel of docs/architecture.md on a graded through-thickness column."""

    def __init__(self, params: PlateParams, dt: float, jump_rtol: float = 0.1, rannacher: bool = True,
                 jit: bool | None = None):
        """jit: None uses the numba kernel when available (FPD_NO_JIT unset),
        False the pure numpy/LAPACK path, True requires numba."""
        check_params(params)
        self.params = p = params
        self.dt = float(dt)
        self.area = p.contact_area
        self._fixed_point = p.source == "fixed-point"
        self._T_air = float(p.T_air_C)
        self.z = line_mesh(p.plate_thickness, p.n_elements, p.grading).p[0].copy()
        n = len(self.z)
        h_min = np.diff(self.z).min()
        if h_min < 1e-9 * p.plate_thickness:
            raise ValueError(f"thermal: n_elements={p.n_elements} with grading={p.grading} gives a first "
                             f"element of {h_min:.1e} m (< 1e-9 of the thickness); lower the grading")
        (dM, eM), (dK, eK) = assemble_column(self.z, p.rho * p.c, p.k, self.area)
        dA = dK.copy()
        conv_back = p.h_conv * self.area if p.back == "convection" else 0.0
        dA[-1] += conv_back
        nf = n - 1 if p.back == "fixed" else n
        u0 = np.full(n, p.T0_C - p.T_air_C)
        if nf < n:
            u0[-1] = p.T_back_C - p.T_air_C
        self._tri = (dM, eM, dA, eK)
        self.integ = ColumnIntegrator(self._tri, conv_back, nf, u0, self.dt, p.scheme, jump_rtol, rannacher, jit)

    # -- PlateModel interface ---------------------------------------------------
    def covered(self, centre_m: float) -> bool:
        """Whether the footprint centred at centre_m covers this column."""
        if self.params.source == "follow-pad":
            return True
        if isinstance(centre_m, tuple):     # a 2D footprint path (bidirectional runs): point at (r0, 0)
            return math.hypot(centre_m[0] - self.params.radius_m, centre_m[1]) <= self.params.a_contact_m
        return abs(centre_m - self.params.radius_m) <= self.params.a_contact_m

    def step(self, power_W: float, centre_m: float = 0.0) -> float:
        """Advance dt with power_W over the footprint at centre_m; return the
        column's surface temperature (degC) at the end of the step."""
        if self._fixed_point and not self.covered(centre_m):
            power_W = 0.0
        u0 = self.integ.step_surface(float(power_W))
        if u0 is not None:
            return u0 + self._T_air
        return float(self.integ.u[0] + self._T_air)

    def surface_temperature(self) -> float:
        return float(self.integ.u[0] + self.params.T_air_C)

    def temperature(self) -> np.ndarray:
        """Nodal temperatures (degC) at depths self.z."""
        return self.integ.u + self.params.T_air_C

    def stored_heat(self) -> float:
        return self.integ.stored()

    def heat_lost(self) -> float:
        return self.integ.heat_lost

    def heat_in(self) -> float:
        return self.integ.heat_in

    def save(self):
        return self.integ.save()

    def restore(self, snap) -> None:
        self.integ.restore(snap)

    def field(self):
        """(points, cells, T): the column as a VTK line, sliding face at z = 0."""
        n = len(self.z)
        pts = np.zeros((n, 3))
        pts[:, 2] = -self.z
        conn = np.column_stack((np.arange(n - 1), np.arange(1, n)))
        return pts, [("line", conn)], self.temperature().copy()
