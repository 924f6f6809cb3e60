"""Transient conduction in the plate's r-z section (model.md section 4, axisym).

Weak form (every integral carries 2 pi r, so matrices are in J/K and W/K):

    int rho c T_t v 2 pi r + int k grad T . grad v 2 pi r
      + int_{exposed} h (T - T_air) v 2 pi r = int_top q f(r) v 2 pi r,

exposed = the whole top face (the pad's cover is neglected there: h dT is
~1e-4 of a friction flux, and it keeps the matrix fixed), the outer face and,
when params.back is "convection", the bottom face; "fixed" holds the bottom
at T_back_C, "adiabatic" leaves it free.

Footprint: a disk of radius a centred at distance c = |centre| from the axis,
averaged around the axis into a ring: f(r) = arccos((r^2 + c^2 - a^2)/(2 r c))/pi
where the circle of radius r is partly covered, 1 or 0 elsewhere. The load
uses a precomputed sparse quadrature operator (fixed Gauss points on the top
facets -> nodal loads) for the facets the footprint covers fully or not at
all; the partly covered facets (the band |c - a| < r < c + a) are split at
the breakpoints and integrated in the angle around the footprint centre,
which removes the square-root behaviour of f at the breakpoints (round-off
accurate; docs/thermal.md). The load is then scaled so that the delivered
heat is exactly power dt (the part of a footprint hanging over the plate's
edge is delivered to the plate). The returned surface temperature is the
footprint mean with the same weights, int f T r dr / int f r dr.

One concept per file: the footprint load is thermal/axisym_load.py, the
eigenbasis and its integrator thermal/axisym_modes.py, the plate (assembly,
stepping, the PlateModel interface) here.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from fpd.meshes.line import graded_nodes
from fpd.meshes.rz import footprint_radial_nodes, read_rz_mesh, rz_mesh
from fpd.thermal.axisym_load import NG_FACET, NG_PIECE, TopLoad, covered_fraction  # noqa: F401
from fpd.thermal.axisym_modes import ModalIntegrator, TensorModes  # noqa: F401
from fpd.thermal.params import PlateParams
from fpd.thermal.stepping import Integrator


def assemble_section(mesh, rho_c: float, k: float, h: float, convective: tuple[str, ...]):
    """Mass, conduction and convective-boundary matrices of the r-z section."""
    from skfem import (Basis, BilinearForm, ElementQuad1, ElementTriP1, FacetBasis,
                       MeshQuad)
    from skfem.helpers import dot, grad

    elem = ElementQuad1() if isinstance(mesh, MeshQuad) else ElementTriP1()

    @BilinearForm
    def mass(u, v, w):
        return rho_c * u * v * 2 * np.pi * w.x[0]

    @BilinearForm
    def conduction(u, v, w):
        return k * dot(grad(u), grad(v)) * 2 * np.pi * w.x[0]

    @BilinearForm
    def convection(u, v, w):
        return h * u * v * 2 * np.pi * w.x[0]

    basis = Basis(mesh, elem, intorder=4)
    M = mass.assemble(basis)
    K = conduction.assemble(basis)
    C = sp.csr_matrix(M.shape)
    for name in convective:
        facets = mesh.boundaries.get(name)
        if facets is not None and len(facets) and h > 0:
            C = C + convection.assemble(FacetBasis(mesh, elem, facets=facets, intorder=4))
    return M.tocsr(), K.tocsr(), C.tocsr()


class AxisymPlate:
    """PlateModel of docs/architecture.md on the plate's r-z section."""

    def __init__(self, params: PlateParams, dt: float, jump_rtol: float = 0.1, mesh=None,
                 band_r: float | None = None, rannacher: bool = True, fast_solver: bool = True,
                 jit: bool | None = None):
        """fast_solver: step in the eigenbasis on a tensor-product quad mesh
        (TensorModes; False: always the nodal stepping with a sparse LU).
        jit: accepted for compatibility; the axisym plate has one path (the
        eigenbasis or sparse-LU stepping in numpy, no compiled kernel)."""
        from fpd.thermal.fe1d import check_params

        check_params(params)
        self.params = p = params
        self.dt = float(dt)
        if mesh is None:
            if p.mesh_file:
                mesh = read_rz_mesh(p.mesh_file)
            else:
                dz = np.diff(graded_nodes(p.plate_thickness, p.nz, p.grading))
                if dz.min() < 1e-9 * p.plate_thickness:
                    raise ValueError(f"thermal: nz={p.nz} with grading={p.grading} gives a first element "
                                     f"of {dz.min():.1e} m (< 1e-9 of the thickness); lower the grading")
                r_nodes = None
                if p.nr == 0 and band_r is None:      # automatic: resolve the footprint (docs/thermal.md, 5)
                    r_nodes = footprint_radial_nodes(p.plate_radius, p.a_contact_m, p.per_radius, p.sweep_m)
                mesh = rz_mesh(p.plate_radius, p.plate_thickness, max(p.nr, 1), p.nz, p.grading, band_r,
                               r_nodes=r_nodes)
        self.mesh = mesh
        conv_faces = ("top", "outer") + (("bottom",) if p.back == "convection" else ())
        M, K, C = assemble_section(mesh, p.rho * p.c, p.k, p.h_conv, conv_faces)
        n = M.shape[0]
        if p.back == "fixed":
            fixed = np.unique(mesh.facets[:, mesh.boundaries["bottom"]])
        else:
            fixed = np.zeros(0, dtype=np.int64)
        free = np.setdiff1d(np.arange(n), fixed)
        self.perm = np.concatenate((free, fixed))           # internal -> mesh node
        self.inv = np.empty(n, dtype=np.int64)
        self.inv[self.perm] = np.arange(n)
        nf = len(free)
        P = self.perm
        self.M = M[P][:, P].tocsr()
        self.A = (K + C)[P][:, P].tocsr()
        conv = np.asarray(C.sum(axis=1)).ravel()[P]
        mD = np.asarray(self.M[nf:].sum(axis=0)).ravel()
        aD = np.asarray(self.A[nf:].sum(axis=0)).ravel()
        self._nf = nf
        # top face: nodes, radii, facets -> the precomputed load operator
        top_facets = mesh.boundaries["top"]
        top_mesh_nodes = np.unique(mesh.facets[:, top_facets])
        z_top = mesh.p[1, top_mesh_nodes]
        if np.ptp(z_top) > 1e-9 * max(p.plate_thickness, 1e-12):
            raise ValueError("axisym: the top (sliding) face of the mesh must be flat (constant z)")
        local = {int(v): i for i, v in enumerate(top_mesh_nodes)}
        fnodes = np.vectorize(local.get)(mesh.facets[:, top_facets].T)
        self.top_nodes = self.inv[top_mesh_nodes]               # internal numbering
        self.top = TopLoad(mesh.p[0, top_mesh_nodes], fnodes)
        u0 = np.full(n, p.T0_C - p.T_air_C)
        u0[nf:] = p.T_back_C - p.T_air_C
        self._load = np.zeros(n)
        self._weights = np.zeros(len(self.top_nodes))
        self._pattern_key = None
        # a tensor-product quad mesh: step in the eigenbasis (TensorModes),
        # otherwise on the nodes with a sparse LU
        self.modes = TensorModes.build(mesh, self.M, self.A, self.perm, nf, p.rho * p.c, p.k, p.h_conv,
                                       conv_faces, float(z_top[0])) if fast_solver else None
        if self.modes is not None:
            m = self.modes
            self._top_i = np.searchsorted(m.ru, mesh.p[0, top_mesh_nodes])   # top node -> r index
            self._vtop = m.V[m.jt].copy()
            self._wgrid = np.zeros(m.nr1)
            self._pat_hat = np.zeros(n)      # modal footprint weights (free dofs; Dirichlet part 0)
            fD = self.A[:nf, nf:] @ u0[nf:]
            self.integ = ModalIntegrator(m, p.rho * p.c, fD, len(self.top_nodes), self._mass, self._stiff,
                                         conv, nf, mD, aD, u0, self.dt, p.scheme, jump_rtol, rannacher)
        else:
            self.integ = Integrator(self._mass, self._stiff, self._factor, conv, nf, mD, aD,
                                    u0, self.dt, p.scheme, jump_rtol, rannacher)
        self._set_footprint(0.0)

    # -- kernels ------------------------------------------------------------------
    def _mass(self, x):
        return self.M @ x

    def _stiff(self, x):
        return self.A @ x

    def _factor(self, gamma: float):
        nf = self._nf
        S = (self.M[:nf, :nf] + gamma * self.A[:nf, :nf]).tocsc()
        # SPD: no pivoting and a symmetric ordering keep the fill at the
        # minimum-degree level (measured ~2x faster solves than the default)
        lu = splu(S, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                  options=dict(SymmetricMode=True))
        return lu.solve

    def _set_footprint(self, centre_m: float) -> None:
        c = abs(float(centre_m))
        key = c
        if key == self._pattern_key:
            return
        pat = self.top.pattern(c, self.params.a_contact_m)
        total = pat.sum()
        # a footprint wholly off the plate delivers nothing; the surface
        # temperature then stays the mean under the last footprint on it
        self._on_plate = total > 0
        if self._on_plate:
            self._weights = pat / total
            if self.modes is not None:
                # (W (x) V)^T of the weights on the sliding face's z-layer jt:
                # (W^T w)_i V[jt, j]; it is also the modal surface-mean functional
                self._wgrid[self._top_i] = self._weights
                self._pat_hat[:self._nf] = np.outer(self.modes.W.T @ self._wgrid, self._vtop).ravel()
        self._pattern_key = key

    # -- PlateModel interface -------------------------------------------------------
    def step(self, power_W: float, centre_m: float = 0.0) -> float:
        """Advance dt with power_W over the footprint at centre_m; return the
        footprint-mean surface temperature (degC) at the end of the step."""
        self._set_footprint(centre_m)
        power = float(power_W) if self._on_plate else 0.0
        if self.modes is not None:
            np.multiply(self._weights, power, out=self.integ.top)    # nodal, for the jump test
            np.multiply(self._pat_hat, power, out=self._load)
        else:
            self._load[self.top_nodes] = power * self._weights
        self.integ.step(self._load, power)
        return self.surface_temperature()

    def surface_temperature(self) -> float:
        if self.modes is not None:
            return float(self._pat_hat @ self.integ.u + self.params.T_air_C)
        return float(self._weights @ self.integ.u[self.top_nodes] + self.params.T_air_C)

    def temperature(self) -> np.ndarray:
        """Nodal temperatures (degC) in the mesh's node order."""
        u = self.integ.nodal() if self.modes is not None else self.integ.u
        return u[self.inv] + self.params.T_air_C

    def stored_heat(self) -> float:
        return self.integ.stored()

    def heat_lost(self) -> float:
        return self.integ.heat_lost

    def heat_in(self) -> float:
        return self.integ.heat_in

    def save(self):
        pat = self._pat_hat.copy() if self.modes is not None else None
        return (self.integ.save(), self._weights.copy(), self._pattern_key, self._on_plate, pat)

    def restore(self, snap) -> None:
        s, w, key, self._on_plate, pat = snap
        self.integ.restore(s)
        self._weights = w.copy()
        self._pattern_key = key
        if pat is not None:
            self._pat_hat[:] = pat

    def field(self):
        """(points, cells, T): the section with x = r, z = depth coordinate."""
        pts = np.zeros((self.mesh.p.shape[1], 3))
        pts[:, 0] = self.mesh.p[0]
        pts[:, 2] = self.mesh.p[1]
        kind = "quad" if self.mesh.t.shape[0] == 4 else "triangle"
        return pts, [(kind, self.mesh.t.T.copy())], self.temperature()
