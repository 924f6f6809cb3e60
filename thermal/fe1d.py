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
from scipy.linalg import lapack

from fpd.meshes.line import line_mesh
from fpd.thermal import column_kernel as CK
from fpd.thermal.params import PlateParams
from fpd.thermal.stepping import SCHEMES, START_STEPS, START_SUBSTEPS

BACKS = ("convection", "adiabatic", "fixed")
SOURCES = ("follow-pad", "fixed-point")

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


def column_kernels(jit: bool | None = None):
    """The column kernel module: its numba copy (fpd/kernels.py) when ``jit``
    is True, or None and numba is available (FPD_NO_JIT unset); else the pure
    module. ``jit=True`` without numba raises ImportError."""
    from fpd import kernels

    if jit or (jit is None and kernels.available()):
        try:
            return kernels.compiled("fpd.thermal.column_kernel")
        except ImportError:
            if jit:
                raise ImportError("fe1d: jit=True needs numba") from None
    return CK


def _slot(i: int, kind=float):
    return property(lambda self: kind(self.P[i]), lambda self, v: self.P.__setitem__(i, v))


class ColumnIntegrator:
    """The column's state as thermal/column_kernel.py reads it (same schemes,
    start-up and ledger as thermal.stepping.Integrator): arrays Mb, Ab, FAC,
    V (u and du are rows of it), I and the scalars P (a list on the pure
    path, float64 on the compiled one). Stepping is the kernel's."""

    heat_in = _slot(CK.P_HIN)
    heat_lost = _slot(CK.P_HLOST)
    loss_prev = _slot(CK.P_LP)
    load_scale = _slot(CK.P_LS)
    steps = _slot(CK.P_STEPS, int)
    half_steps = _slot(CK.P_HALF, int)
    _start_left = _slot(CK.P_SL, int)

    def __init__(self, tri, conv_back: float, nf: int, u0, dt, scheme, jump_rtol, rannacher=True,
                 jit: bool | None = None):
        if scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {SCHEMES}, got {scheme!r}")
        if not dt > 0:
            raise ValueError(f"dt must be > 0, got {dt}")
        dM, eM, dA, eA = tri
        n = len(dM)
        self._tri, self.nf = tri, nf
        self.dt, self.scheme, self.jump_rtol = float(dt), scheme, jump_rtol
        self.rannacher = rannacher
        self.start_substeps = START_SUBSTEPS
        self.kern = column_kernels(jit)
        self.compiled = self.kern is not CK
        # upper band storage, Fortran order so that BLAS reads it without a copy
        self.Mb = np.zeros((2, n), order="F")
        self.Mb[1], self.Mb[0, 1:] = dM, eM
        self.Ab = np.zeros((2, n), order="F")
        self.Ab[1], self.Ab[0, 1:] = dA, eA
        h = self.dt
        gammas = {"be": h, "cn": 0.5 * h, "bdf2": 2.0 * h / 3.0}
        fac = [None] * 6
        for row, gamma in ((CK.F_SUB, h / self.start_substeps), (CK.F_MAIN, gammas[scheme]), (CK.F_H, h)):
            fac[row], fac[row + 1] = (np.ascontiguousarray(x, dtype=float) for x in self._factor(gamma))
        self.FAC = tuple(fac)
        self.I = np.array([n, 1, 2, 1, 1, 0, ord("U"), nf], dtype=np.int32)
        self.V = tuple(np.zeros(n) for _ in range(6))
        self.u, self.du = self.V[CK.V_U], self.V[CK.V_DU]
        self.u[:] = u0
        self.V[CK.V_M1][:] = self.mass(np.ones(n))          # M 1 = M^T 1
        P = [0.0] * CK.N_P
        P[CK.P_SCHEME] = {"be": CK.BE, "cn": CK.CN, "bdf2": CK.BDF2}[scheme]
        P[CK.P_RANN] = 1.0 if rannacher else 0.0
        P[CK.P_M], P[CK.P_START] = self.start_substeps, START_STEPS.get(scheme, 0)
        P[CK.P_H], P[CK.P_CB], P[CK.P_JR], P[CK.P_NF] = h, conv_back, jump_rtol, nf
        if nf < n:
            P[CK.P_MD1], P[CK.P_AD0], P[CK.P_AD1] = eM[-1], eA[-1], dA[-1]
        P[CK.P_E0] = float(self.V[CK.V_M1] @ self.V[CK.V_U])
        self.P = np.array(P) if self.compiled else P

    def _factor(self, gamma: float):
        dM, eM, dA, eA = self._tri
        nf = self.nf
        df, ef, info = lapack.dpttrf(dM[:nf] + gamma * dA[:nf], eM[:nf - 1] + gamma * eA[:nf - 1])
        if info != 0:
            raise np.linalg.LinAlgError(f"dpttrf failed (info={info})")
        return df, ef

    def __getstate__(self):
        state = dict(self.__dict__)
        del state["kern"]                # a module: found again on unpickling
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.kern = column_kernels(True) if self.compiled else CK

    def mass(self, x):
        """M x (full length)."""
        y = np.zeros(len(x))
        CK.band_mv(self.I, self.V[CK.V_SC], 1.0, self.Mb, np.asarray(x, dtype=float), 0.0, y)
        return y

    def step_surface(self, q: float) -> None:
        """Advance dt with the power q (W) into the surface node."""
        self.kern.step(self.Mb, self.Ab, self.FAC, self.V, self.I, self.P, q)

    def save(self):
        return (self.u.copy(), self.du.copy(), tuple(float(self.P[i]) for i in CK.STATE))

    def restore(self, snap) -> None:
        u, du, state = snap
        self.u[:] = u
        self.du[:] = du
        for i, v in zip(CK.STATE, state):
            self.P[i] = v

    def stored(self) -> float:
        """1^T M (u - u_0) (J): the rho c integral of the temperature rise."""
        return float(self.kern.stored(self.V, self.I, self.P))


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
        P = self.integ.P
        P[CK.P_TAIR], P[CK.P_FIXED] = self._T_air, 1.0 if self._fixed_point else 0.0
        P[CK.P_R0], P[CK.P_AC] = p.radius_m, p.a_contact_m

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
        it = self.integ
        if isinstance(centre_m, tuple):     # a 2D footprint path (bidirectional runs): the kernel's scalar
            centre_m = it.kern.centre_2d(it.P, float(centre_m[0]), float(centre_m[1]))
        return it.kern.plate_step(it.Mb, it.Ab, it.FAC, it.V, it.I, it.P, float(power_W), float(centre_m))

    def surface_temperature(self) -> float:
        return float(self.integ.u[0] + self.params.T_air_C)

    def temperature(self) -> np.ndarray:
        """Nodal temperatures (degC) at depths self.z."""
        return self.integ.u + self.params.T_air_C

    def stored_heat(self) -> float:
        return self.integ.stored()

    def heat_lost(self) -> float:
        return float(self.integ.P[CK.P_HLOST])

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
