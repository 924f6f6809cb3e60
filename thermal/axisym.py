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
facets -> nodal loads); the at most two facets holding a breakpoint |c - a|,
c + a are integrated apart, split at the breakpoints with a cosine map that
removes the square-root behaviour of f there. The load is then scaled so that
the delivered heat is exactly power dt (the part of a footprint hanging over
the plate's edge is delivered to the plate). The returned surface temperature
is the footprint mean with the same weights, int f T r dr / int f r dr.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from meshes.rz import read_rz_mesh, rz_mesh
from thermal.params import PlateParams
from thermal.stepping import Integrator

BACKS = ("convection", "adiabatic", "fixed")
NG_FACET = 8          # Gauss points per top facet in the fixed operator
NG_PIECE = 20         # Gauss points per piece of a facet split at a breakpoint
_GL_FACET = np.polynomial.legendre.leggauss(NG_FACET)
_GL_PIECE = np.polynomial.legendre.leggauss(NG_PIECE)


def covered_fraction(r, c: float, a: float):
    """Share of the circle of radius r covered by the disk (c, a)."""
    r = np.asarray(r, dtype=float)
    if c <= 1e-12 * a:
        return (r <= a).astype(float)
    x = (r * r + c * c - a * a) / (2.0 * np.maximum(r, 1e-300) * c)
    return np.arccos(np.clip(x, -1.0, 1.0)) / math.pi


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


class TopLoad:
    """Footprint load on the top face: nodal loads = Q f(r_qp), plus the
    breakpoint facets integrated apart. Nodes are local top-node indices."""

    def __init__(self, r_nodes: np.ndarray, facet_nodes: np.ndarray):
        ra, rb = r_nodes[facet_nodes[:, 0]], r_nodes[facet_nodes[:, 1]]
        swap = ra > rb
        facet_nodes = np.where(swap[:, None], facet_nodes[:, ::-1], facet_nodes)
        order = np.argsort(np.minimum(ra, rb))
        self.fn = facet_nodes[order]
        self.r0 = r_nodes[self.fn[:, 0]]
        self.r1 = r_nodes[self.fn[:, 1]]
        self.n_nodes = len(r_nodes)
        x, w = _GL_FACET
        xi = 0.5 * (x + 1.0)                       # on [0, 1]
        L = (self.r1 - self.r0)[:, None]
        self.r_qp = self.r0[:, None] + L * xi      # (n_facets, NG)
        wr = 2 * np.pi * self.r_qp * L * 0.5 * w   # 2 pi r dr weights
        nf = len(self.r0)
        rows = np.concatenate((np.repeat(self.fn[:, 0], NG_FACET), np.repeat(self.fn[:, 1], NG_FACET)))
        cols = np.concatenate((np.arange(nf * NG_FACET), np.arange(nf * NG_FACET)))
        vals = np.concatenate(((wr * (1 - xi)).ravel(), (wr * xi).ravel()))
        self.Q = sp.csr_matrix((vals, (rows, cols)), shape=(self.n_nodes, nf * NG_FACET))
        self.r_flat = self.r_qp.ravel()

    def _special_loads(self, facets, c: float, a: float, breaks) -> np.ndarray:
        """Nodal loads of the facets near the breakpoints, each split at the
        breakpoints inside it, each piece mapped so that the square-root
        behaviour of f at a breakpoint becomes smooth: r = beta +- t^2 toward
        the nearest breakpoint, or a cosine map when both ends are
        breakpoints. Round-off accurate; all pieces evaluated in one batch."""
        pieces = []          # (facet, p0, p1, cosine map?, beta, sign)
        for i in facets:
            lo, hi = self.r0[i], self.r1[i]
            inner = sorted(b for b in breaks if lo < b < hi)
            cuts = [lo] + inner + [hi]
            for p0, p1 in zip(cuts[:-1], cuts[1:]):
                if p1 <= p0:
                    continue
                if p0 in inner and p1 in inner:
                    pieces.append((i, p0, p1, True, 0.0, 1.0))
                    continue
                beta = min(breaks, key=lambda b: min(abs(b - p0), abs(b - p1)))
                pieces.append((i, p0, p1, False, beta, 1.0 if beta <= p0 else -1.0))
        fi, p0, p1, cos_map, beta, sign = (np.array(v) for v in zip(*pieces))
        fi = fi.astype(np.int64)
        x, w = _GL_PIECE
        X = 0.5 * (x + 1.0)
        p0, p1, beta, sign = p0[:, None], p1[:, None], beta[:, None], sign[:, None]
        # cosine map: r = mid - half cos(theta), dr vanishes at both ends
        half = 0.5 * (p1 - p0)
        theta = math.pi * X
        r_cos = 0.5 * (p0 + p1) - half * np.cos(theta)
        j_cos = half * np.sin(theta) * 0.5 * math.pi * w
        # square-root map toward beta: r = beta + sign t^2, t uniform
        t0, t1 = np.sqrt(np.abs(p0 - beta)), np.sqrt(np.abs(p1 - beta))
        t = t0 + (t1 - t0) * X
        r_sq = beta + sign * t * t
        j_sq = sign * 2 * t * (t1 - t0) * 0.5 * w
        cm = cos_map[:, None]
        r = np.where(cm, r_cos, r_sq)
        g = covered_fraction(r, c, a) * 2 * np.pi * r * np.where(cm, j_cos, j_sq)
        lo, hi = self.r0[fi][:, None], self.r1[fi][:, None]
        xi = (r - lo) / (hi - lo)
        gx = np.sum(g * xi, axis=1)
        return (np.bincount(self.fn[fi, 0], np.sum(g, axis=1) - gx, self.n_nodes)
                + np.bincount(self.fn[fi, 1], gx, self.n_nodes))

    def pattern(self, c: float, a: float) -> np.ndarray:
        """Nodal loads (W per unit flux, on top nodes) of the ring-averaged
        footprint: int f(r) phi_i 2 pi r dr."""
        f = covered_fraction(self.r_flat, c, a).reshape(self.r_qp.shape)
        breaks = (abs(c - a), c + a)
        special = set()
        nfac = len(self.r0)
        for b in breaks:
            # the facet holding a breakpoint and its neighbours, where f is
            # too close to a square-root point for the fixed Gauss rule
            i = int(np.searchsorted(self.r0, b, side="right")) - 1
            if 0 <= i < nfac and self.r0[i] <= b <= self.r1[i]:
                special.update(j for j in (i - 1, i, i + 1) if 0 <= j < nfac)
        if not special:
            return self.Q @ f.ravel()
        idx = np.array(sorted(special))
        f[idx] = 0.0
        return self.Q @ f.ravel() + self._special_loads(idx, c, a, breaks)


class AxisymPlate:
    """PlateModel of docs/architecture.md on the plate's r-z section."""

    def __init__(self, params: PlateParams, dt: float, jump_rtol: float = 0.1, mesh=None,
                 band_r: float | None = None, rannacher: bool = True):
        if params.back not in BACKS:
            raise ValueError(f"thermal.back must be one of {BACKS}, got {params.back!r}")
        self.params = p = params
        self.dt = float(dt)
        if mesh is None:
            if p.mesh_file:
                mesh = read_rz_mesh(p.mesh_file)
            else:
                mesh = rz_mesh(p.plate_radius, p.plate_thickness, p.nr, p.nz, p.grading, band_r)
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
        lu = splu(S, permc_spec="MMD_AT_PLUS_A")
        return lu.solve

    def _set_footprint(self, centre_m: float) -> None:
        c = abs(float(centre_m))
        key = c
        if key == self._pattern_key:
            return
        pat = self.top.pattern(c, self.params.a_contact_m)
        total = pat.sum()
        self._weights = pat / total if total > 0 else np.zeros_like(pat)
        self._pattern_key = key

    # -- PlateModel interface -------------------------------------------------------
    def step(self, power_W: float, centre_m: float = 0.0) -> float:
        """Advance dt with power_W over the footprint at centre_m; return the
        footprint-mean surface temperature (degC) at the end of the step."""
        self._set_footprint(centre_m)
        power = float(power_W) if self._weights.any() else 0.0
        self._load[self.top_nodes] = power * self._weights
        self.integ.step(self._load, power)
        return self.surface_temperature()

    def surface_temperature(self) -> float:
        return float(self._weights @ self.integ.u[self.top_nodes] + self.params.T_air_C)

    def temperature(self) -> np.ndarray:
        """Nodal temperatures (degC) in the mesh's node order."""
        return self.integ.u[self.inv] + self.params.T_air_C

    def stored_heat(self) -> float:
        return self.integ.stored()

    def heat_lost(self) -> float:
        return self.integ.heat_lost

    def heat_in(self) -> float:
        return self.integ.heat_in

    def save(self):
        return (self.integ.save(), self._weights.copy(), self._pattern_key)

    def restore(self, snap) -> None:
        s, w, key = snap
        self.integ.restore(s)
        self._weights = w.copy()
        self._pattern_key = key

    def field(self):
        """(points, cells, T): the section with x = r, z = depth coordinate."""
        pts = np.zeros((self.mesh.p.shape[1], 3))
        pts[:, 0] = self.mesh.p[0]
        pts[:, 2] = self.mesh.p[1]
        kind = "quad" if self.mesh.t.shape[0] == 4 else "triangle"
        return pts, [(kind, self.mesh.t.T.copy())], self.temperature()
