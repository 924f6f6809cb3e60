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

import numpy as np
from scipy.linalg import lapack

from meshes.line import line_mesh
from thermal.params import PlateParams
from thermal.stepping import Integrator

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


class FE1DPlate:
    """PlateModel of docs/architecture.md on a graded through-thickness column."""

    def __init__(self, params: PlateParams, dt: float, jump_rtol: float = 0.1):
        if params.back not in BACKS:
            raise ValueError(f"thermal.back must be one of {BACKS}, got {params.back!r}")
        if params.source not in SOURCES:
            raise ValueError(f"thermal.source must be one of {SOURCES}, got {params.source!r}")
        self.params = p = params
        self.dt = float(dt)
        self.area = p.contact_area
        self.z = line_mesh(p.plate_thickness, p.n_elements, p.grading).p[0].copy()
        n = len(self.z)
        (dM, eM), (dK, eK) = assemble_column(self.z, p.rho * p.c, p.k, self.area)
        dA, eA = dK.copy(), eK.copy()
        conv = np.zeros(n)
        if p.back == "convection":
            conv[-1] = p.h_conv * self.area
            dA[-1] += conv[-1]
        nf = n - 1 if p.back == "fixed" else n
        mD = np.zeros(n)
        aD = np.zeros(n)
        if nf < n:
            mD[-2:] = eM[-1], dM[-1]
            aD[-2:] = eA[-1], dA[-1]
        self._tri = (dM, eM, dA, eA)
        u0 = np.full(n, p.T0_C - p.T_air_C)
        if nf < n:
            u0[-1] = p.T_back_C - p.T_air_C
        self._mw = np.empty(n)
        self._aw = np.empty(n)
        self._load = np.zeros(n)
        self.integ = Integrator(self._mass, self._stiff, self._factor, conv, nf, mD, aD,
                                u0, self.dt, p.scheme, jump_rtol)

    # -- tridiagonal kernels (no skfem in the hot loop) -----------------------
    @staticmethod
    def _tri_mul(d, e, x, out):
        np.multiply(d, x, out=out)
        out[:-1] += e * x[1:]
        out[1:] += e * x[:-1]
        return out

    def _mass(self, x):
        dM, eM, _, _ = self._tri
        return self._tri_mul(dM, eM, x, self._mw)

    def _stiff(self, x):
        _, _, dA, eA = self._tri
        return self._tri_mul(dA, eA, x, self._aw)

    def _factor(self, gamma: float):
        dM, eM, dA, eA = self._tri
        nf = self.integ.nf if hasattr(self, "integ") else None
        nf = nf if nf is not None else len(dM)
        d = dM[:nf] + gamma * dA[:nf]
        e = eM[:nf - 1] + gamma * eA[:nf - 1]
        df, ef, info = lapack.dpttrf(d, e)
        if info != 0:
            raise np.linalg.LinAlgError(f"dpttrf failed (info={info})")
        dpttrs = lapack.dpttrs

        def solve(rhs):
            x, info = dpttrs(df, ef, rhs)
            return x
        return solve

    # -- PlateModel interface ---------------------------------------------------
    def covered(self, centre_m: float) -> bool:
        """Whether the footprint centred at centre_m covers this column."""
        if self.params.source == "follow-pad":
            return True
        return abs(centre_m - self.params.radius_m) <= self.params.a_contact_m

    def step(self, power_W: float, centre_m: float = 0.0) -> float:
        """Advance dt with power_W over the footprint at centre_m; return the
        column's surface temperature (degC) at the end of the step."""
        on = self.covered(centre_m)
        p_in = float(power_W) if on else 0.0
        self._load[0] = p_in
        self.integ.step(self._load, p_in)
        return self.surface_temperature()

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
