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
"""
from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from scipy.linalg import eigh, lapack
from scipy.sparse.linalg import splu

from fpd.meshes.line import graded_nodes
from fpd.meshes.rz import read_rz_mesh, rz_mesh
from fpd.thermal.params import PlateParams
from fpd.thermal.stepping import Integrator

NG_FACET = 8          # Gauss points per top facet in the fixed operator
NG_PIECE = 20         # Gauss points per piece of a partly covered facet
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


class _Line:
    """One direction of a tensor-product Q1 mesh: the 1D P1 forms on nodes x
    (exact integrals), weighted by 2 pi x (r) or not (z), kept per element:

        mass       sum_e  m0_e w_a^2 + 2 m1_e w_a w_b + m2_e w_b^2
        stiffness  sum_e  s_e (w_b - w_a)^2  +  sum_b beta_b w_b^2   (k and boundary h)

    so that Rayleigh quotients can be summed from squares (no cancellation)."""

    def __init__(self, x: np.ndarray, weighted: bool, k: float):
        h = np.diff(x)
        if weighted:
            x0, x1, w = x[:-1], x[1:], 2 * np.pi
            self.m0, self.m1, self.m2 = w * h * (3 * x0 + x1) / 12, w * h * (x0 + x1) / 12, w * h * (x0 + 3 * x1) / 12
            self.s = k * w * (x0 + x1) / (2 * h)
        else:
            self.m0 = self.m2 = h / 3
            self.m1 = h / 6
            self.s = k / h
        self.beta = np.zeros(len(x))      # boundary (convective) terms on the diagonal

    def matrices(self, keep=None):
        """(diag, off) of mass and of stiffness + boundary terms, restricted to
        the nodes ``keep`` (the free ones) when given."""
        n = len(self.beta)
        dm, dk = np.zeros(n), self.beta.copy()
        dm[:-1] += self.m0
        dm[1:] += self.m2
        dk[:-1] += self.s
        dk[1:] += self.s
        em, ek = self.m1.copy(), -self.s
        if keep is None:
            return (dm, em), (dk, ek)
        adj = np.diff(keep) == 1            # neighbours among the kept nodes
        return (dm[keep], em[keep[:-1]] * adj), (dk[keep], ek[keep[:-1]] * adj)

    def rayleigh(self, X: np.ndarray) -> np.ndarray:
        """Rayleigh quotients of the columns of X (one value per node; zero on
        removed nodes), from sums of squares: accurate to round-off relative
        to each quotient, also for the smallest ones, which a dense
        eigensolver only gets to round-off relative to the largest."""
        a, b = X[:-1], X[1:]
        num = self.s @ (b - a) ** 2 + self.beta @ X ** 2
        den = self.m0 @ a ** 2 + 2 * self.m1 @ (a * b) + self.m2 @ b ** 2
        return num / den


def _tridiag(d, e):
    return sp.diags([e, d, e], [-1, 0, 1], format="csr")


class TensorModes:
    """Eigenbasis of the plate's matrices on a tensor-product Q1 mesh
    (docs/thermal.md, section 2).

    With the r-weighted Q1 forms on nodes r_i x z_j every matrix is a
    Kronecker product of 1D P1 matrices (r-weighted in r, plain in z):

        M = rho c Mr (x) Mz,   A = Ar (x) Mz + Mr (x) Az,
        Ar = k Kr + h 2 pi R e_R e_R^T,   Az = k Kz + h (e_top e_top^T [+ e_bot e_bot^T])

    (convection on the outer face in Ar, on the top and bottom faces in Az;
    fixed dofs are whole z-layers and drop out of the z factor). With the
    generalised eigenvectors Ar W = Mr W diag(theta), W^T Mr W = I, and
    Az V = Mz V diag(phi), V^T Mz V = I, the change of variables
    u_free = (W (x) V) y makes M and A diagonal on the free dofs:

        (W (x) V)^T M (W (x) V) = rho c I,   (W (x) V)^T A (W (x) V) = diag(theta_i + phi_j),

    so every scheme's solve is a division (ModalIntegrator). Vectors are
    (nr1, nzf) grids, row-major, in both bases.

    ``build`` returns None when the mesh is not such a tensor product, when
    the fixed dofs are not whole z-layers not containing the sliding face,
    when a direction has more than MAX_NODES nodes (dense eigenvectors), or
    when the Kronecker matrices differ from the assembled ones by more than
    round-off: the caller keeps the sparse LU then.
    """

    RTOL = 1e-13         # Kronecker vs assembled matrices, relative to the largest entry
    MAX_NODES = 2000     # per direction: W is dense (nr1^2), its setup O(nr1^3)

    def __init__(self, ru, zu, jf, rline: _Line, zline: _Line, idx):
        self.ru, self.zu, self.jf = ru, zu, jf
        (Mr, Ar), (Mz, Az) = rline.matrices(), zline.matrices(jf)
        Mr, Ar, Mz, Az = (_tridiag(*m).toarray() for m in (Mr, Ar, Mz, Az))
        self.theta, self.W = self._eig(Ar, Mr)
        self.phi, self.V = self._eig(Az, Mz)
        # eigenvalues as Rayleigh quotients summed from squares: the small ones
        # (the slow modes that hold most of the heat) to round-off relative to
        # themselves; with eigh's they carry ~1e-11 relative error, a spurious
        # loss of heat that shows in the ledger at ~1e-13
        self.theta = rline.rayleigh(self.W)
        Vfull = np.zeros((len(zu), len(jf)))
        Vfull[jf] = self.V
        self.phi = zline.rayleigh(Vfull)
        self.Wi = self.W.T @ Mr               # W^-1
        self.Vi = self.V.T @ Mz               # V^-1
        self.nr1, self.nzf = idx.shape
        self.lam = np.add.outer(self.theta, self.phi).ravel()
        # idx[i, j]: free-dof index of node (r_i, z_jf[j]); None when that is
        # the row-major order already (a reshape is then a view, no gather)
        self.idx = None if np.array_equal(idx.ravel(), np.arange(idx.size)) else idx

    @staticmethod
    def _eig(A, M):
        """eigh(A, M), M = LL^T, on the diagonally scaled pair: the r weight makes
        Mr's diagonal span ~nr^2 near the axis, and the error of W W^T = Mr^-1
        (the heat a load delivers in the modal basis) grows with cond(M)."""
        d = 1.0 / np.sqrt(np.diag(M))
        lam, X = eigh(d[:, None] * A * d, d[:, None] * M * d)
        return lam, d[:, None] * X

    @classmethod
    def build(cls, mesh, M, A, perm, nf, rho_c, k, h, convective, z_top):
        from skfem import MeshQuad

        if not isinstance(mesh, MeshQuad):
            return None
        r, z = mesh.p
        ru, zu = np.unique(r), np.unique(z)
        n = mesh.p.shape[1]
        if (len(ru) < 2 or len(zu) < 2 or len(ru) * len(zu) != n
                or max(len(ru), len(zu)) > cls.MAX_NODES):
            return None
        i, j = np.searchsorted(ru, r), np.searchsorted(zu, z)
        grid = np.full((len(ru), len(zu)), -1)
        grid[i, j] = np.arange(n)
        if (grid < 0).any():
            return None
        # every cell one tensor cell [i, i+1] x [j, j+1]
        ti, tj = i[mesh.t], j[mesh.t]
        i0, j0 = ti.min(axis=0), tj.min(axis=0)
        if (len(i0) != (len(ru) - 1) * (len(zu) - 1) or np.ptp(ti, axis=0).max() != 1
                or np.ptp(tj, axis=0).max() != 1
                or len(np.unique(i0 * len(zu) + j0)) != len(i0)):
            return None
        # fixed dofs: whole z-layers, the sliding face free
        inv = np.empty(n, dtype=np.int64)
        inv[perm] = np.arange(n)
        free_node = inv < nf
        free_z = free_node[grid[0]]
        jt = np.searchsorted(zu, z_top)
        if (not np.array_equal(free_node[grid], np.broadcast_to(free_z, grid.shape))
                or jt >= len(zu) or zu[jt] != z_top or not free_z[jt]):
            return None
        rline, zline = _Line(ru, True, k), _Line(zu, False, k)
        if h > 0:
            if "outer" in convective:
                rline.beta[-1] = h * 2 * np.pi * ru[-1]
            if "top" in convective:
                zline.beta[-1] += h
            if "bottom" in convective:
                zline.beta[0] += h
        # the Kronecker matrices, in the internal (permuted) numbering, against the assembled ones
        (Mr, Ar), (Mz, Az) = ((_tridiag(*m) for m in line.matrices()) for line in (rline, zline))
        P = grid.ravel()                                   # row-major grid -> mesh node
        Pi = np.empty(n, dtype=np.int64)
        Pi[P] = np.arange(n)
        to_grid = Pi[perm]                                 # internal dof -> row-major grid
        Mk = (rho_c * sp.kron(Mr, Mz)).tocsr()[to_grid][:, to_grid]
        Ak = (sp.kron(Ar, Mz) + sp.kron(Mr, Az)).tocsr()[to_grid][:, to_grid]
        for want, got in ((M.copy(), Mk), (A.copy(), Ak)):     # copies: a sparse binop sorts indices in place
            if abs(want - got).max() > cls.RTOL * abs(want).max():
                return None
        fz = np.flatnonzero(free_z)
        modes = cls(ru, zu, fz, rline, zline, inv[grid[:, fz]])
        modes.jt = int(np.searchsorted(fz, jt))            # the sliding face's row in the free z-layers
        return modes

    # -- changes of basis on the free dofs (internal numbering <-> modal) -----------
    def _grid(self, x):
        return x.reshape(self.nr1, self.nzf) if self.idx is None else x[self.idx]

    def _vector(self, X):
        if self.idx is None:
            return X.ravel()
        out = np.empty(X.size)
        out[self.idx] = X
        return out

    def adjoint(self, x):
        """(W (x) V)^T x: loads and row vectors (conv, 1^T M) to the modal basis."""
        return (self.W.T @ self._grid(x) @ self.V).ravel()

    def to_modal(self, u):
        """(W (x) V)^-1 u: a state to the modal basis."""
        return (self.Wi @ self._grid(u) @ self.Vi.T).ravel()

    def to_nodal(self, y):
        """(W (x) V) y: a modal state back to the free dofs."""
        return self._vector(self.W @ y.reshape(self.nr1, self.nzf) @ self.V.T)


class ModalIntegrator(Integrator):
    """stepping.Integrator in the basis of TensorModes, where M = rho c I and
    A = diag(lam) on the free dofs: each scheme's solve is a division and its
    right-hand side a few elementwise operations on preallocated arrays.

    The same schemes, start-up and ledger as Integrator (step, _starting,
    _substeps, stored, _be, _cn and their ledgers are inherited; _increment
    and _bdf2 are the same formulas with M, A diagonal). State: u = (modal free dofs, nodal Dirichlet dofs),
    likewise du and b. ``mass``/``stiff`` stay the nodal products (for
    callers that ask for nodal capacities). Jumps are judged on the nodal
    top-face load (``top``, set before each step), as in Integrator.
    """

    def __init__(self, modes: TensorModes, rho_c: float, fD: np.ndarray, n_top: int,
                 mass, stiff, conv, nf, mD, aD, u0, dt, scheme, jump_rtol, rannacher):
        super().__init__(mass, stiff, self._modal_factor, conv, nf, mD, aD, u0, dt, scheme,
                         jump_rtol, rannacher)
        self.modes, self.rho_c = modes, rho_c
        self.lam = modes.lam
        tm = lambda v: np.concatenate((modes.adjoint(v[:nf]), v[nf:]))
        self.conv, self.mD, self.aD = tm(conv), tm(mD), tm(aD)
        self._m1 = tm(self._m1)
        self.u[:nf] = modes.to_modal(self.u[:nf])
        self._e0 = float(self._m1 @ self.u)
        self.fD = modes.adjoint(fD) if self.has_dirichlet else None     # A_fD u_D, constant
        self.top = np.zeros(n_top)          # nodal top-face load of the step being taken
        self.top_prev = np.zeros(n_top)
        self._t = np.empty(nf)

    def _modal_factor(self, gamma: float) -> np.ndarray:
        return 1.0 / (self.rho_c + gamma * self.lam)

    def _au(self, out):
        """A u on the free dofs, into out."""
        np.multiply(self.lam, self.u[:self.nf], out=out)
        if self.fD is not None:
            out += self.fD
        return out

    def is_jump(self, b) -> bool:
        top = self.top
        size = np.abs(top).sum()
        if size > self.load_scale:
            self.load_scale = size
        return np.abs(top - self.top_prev).sum() > self.jump_rtol * self.load_scale

    def step(self, b, power) -> None:
        super().step(b, power)
        self.top_prev[:] = self.top

    def _increment(self, h, b, gamma):
        nf = self.nf
        du = self._au(self._t)
        np.subtract(b[:nf], du, out=du)
        du *= h
        du *= self.solver(gamma)
        self.u[:nf] += du
        self.du[:nf] = du
        return du

    def _bdf2(self, h, b, power):
        nf = self.nf
        dprev = self.du[:nf]
        du_prev_f = dprev.copy() if self.has_dirichlet else None
        du = self._au(self._t)                         # A u
        g = 1.5 * b[:nf]
        g -= 0.5 * self.b[:nf]                         # G
        g -= du
        g *= (2.0 / 3.0) * h
        np.multiply(dprev, self.rho_c / 3.0, out=du)   # 1/3 M du_prev
        du += g
        du *= self.solver(2.0 * h / 3.0)
        self.u[:nf] += du
        dprev[:] = du
        s = h * (self.conv @ self.u)
        if self.has_dirichlet:
            Mdu = self.mD[:nf] @ (1.5 * du - 0.5 * du_prev_f)
            G_D = (1.5 * b[nf:] - 0.5 * self.b[nf:]).sum()
            s -= self._dirichlet_reaction(Mdu, self.aD @ self.u, h, G_D)
        loss = (2.0 / 3.0) * (s + 0.5 * self.loss_prev)
        self.loss_prev = loss
        self.heat_in += h * power
        self.heat_lost += loss

    def save(self):
        return super().save() + (self.top_prev.copy(),)

    def restore(self, snap) -> None:
        super().restore(snap[:-1])
        self.top_prev[:] = snap[-1]

    def nodal(self) -> np.ndarray:
        """u in the internal (nodal) numbering."""
        nf = self.nf
        return np.concatenate((self.modes.to_nodal(self.u[:nf]), self.u[nf:]))


class TopLoad:
    """Footprint load on the top face: whole facets where f is 0 or 1 from
    precomputed facet loads, the partly covered facets (the band) integrated
    apart. Nodes are local top-node indices."""

    def __init__(self, r_nodes: np.ndarray, facet_nodes: np.ndarray):
        ra, rb = r_nodes[facet_nodes[:, 0]], r_nodes[facet_nodes[:, 1]]
        swap = ra > rb
        facet_nodes = np.where(swap[:, None], facet_nodes[:, ::-1], facet_nodes)
        order = np.argsort(np.minimum(ra, rb))
        self.fn = facet_nodes[order]
        self.fn0, self.fn1 = self.fn[:, 0].copy(), self.fn[:, 1].copy()
        self.r0 = r_nodes[self.fn0]
        self.r1 = r_nodes[self.fn1]
        self.n_nodes = len(r_nodes)
        x, w = _GL_FACET
        xi = 0.5 * (x + 1.0)                       # on [0, 1]
        L = (self.r1 - self.r0)[:, None]
        r_qp = self.r0[:, None] + L * xi           # (n_facets, NG)
        wr = 2 * np.pi * r_qp * L * 0.5 * w        # 2 pi r dr weights
        # int phi_i 2 pi r dr over each whole facet, to its first and second node
        # (Gauss-Legendre, exact for this cubic): the load of a covered facet
        self.full0 = np.sum(wr * (1 - xi), axis=1)
        self.full1 = np.sum(wr * xi, axis=1)
        self.L = self.r1 - self.r0
        self.inv_L = 1.0 / self.L
        # facets in order along r without overlaps (any line mesh of the top face):
        # the covered facets are a prefix, the band a contiguous range
        self._sorted = bool(np.all(self.r1[:-1] <= self.r0[1:]))
        x, w = _GL_PIECE
        self._X = 0.5 * (x + 1.0)
        self._w_half = 0.5 * w
        self._cut_steps = 4.0 ** np.arange(40)

    def _range(self, lo: float, hi: float, strict_lo: bool) -> np.ndarray:
        """Facets with r1 > lo (r1 >= lo when not strict_lo... see callers) and r0 < hi."""
        if self._sorted:
            i0 = np.searchsorted(self.r1, lo, side="right" if strict_lo else "left")
            i1 = np.searchsorted(self.r0, hi, side="left")
            return np.arange(i0, max(i0, i1))
        sel = (self.r1 > lo) if strict_lo else (self.r1 >= lo)
        return np.flatnonzero(sel & (self.r0 < hi))

    def _band_loads(self, idx: np.ndarray, c: float, a: float, loads: np.ndarray) -> None:
        """Add the nodal loads of the facets idx that the footprint partly
        covers, each split at the breakpoints lo_b = |c - a|, hi_b = c + a.
        Below lo_b f is 1 (c < a, or the centred step r <= a) or 0, above
        hi_b it is 0: constant, Gauss-Legendre in r is exact there (and the
        zero pieces are left out). Inside the band the piece is integrated
        in the angle psi around the footprint centre,
        r^2 = c^2 + a^2 + 2 a c cos(psi): dr/dpsi vanishes at both
        breakpoints, which removes the square-root behaviour of f there, so
        Gauss-Legendre converges to round-off. All pieces in one batch."""
        r0, r1 = self.r0[idx], self.r1[idx]
        X, wh = self._X, self._w_half
        centred = c <= 1e-12 * a
        if centred:                 # f is the step r <= a
            lo_b = hi_b = a
        else:
            lo_b, hi_b = abs(c - a), c + a
        fis, rs, gs = [], [], []
        if centred or c < a:
            # the covered piece [r0, min(r1, lo_b)] (f = 1)
            p1 = np.minimum(r1, lo_b)
            keep = p1 > r0
            if keep.any():
                q0, q1 = r0[keep, None], p1[keep, None]
                r = q0 + (q1 - q0) * X
                fis.append(idx[keep])
                rs.append(r)
                gs.append(2 * np.pi * r * (q1 - q0) * wh)
        if hi_b > lo_b:
            q0 = np.maximum(r0, lo_b)
            q1 = np.minimum(r1, hi_b)
            # psi(r) = 2 atan(sqrt((hi_b^2 - r^2) / (r^2 - lo_b^2))), written without
            # the cancellation of arccos near the breakpoints (c ~ a puts lo_b ~ 0);
            # both ends of every piece in one call
            q = np.concatenate((q0, q1))
            psi = 2 * np.arctan2(np.sqrt(np.maximum((hi_b - q) * (hi_b + q), 0.0)),
                                 np.sqrt(np.maximum((q - lo_b) * (q + lo_b), 0.0)))
            m = len(idx)
            s0, s1 = psi[:m], psi[m:]              # s0 >= s1
            fi = idx
            if lo_b < a:
                # axis close to the footprint's rim (c ~ a): f has a feature of
                # width sqrt(lo_b / a) near psi = pi; split geometrically toward it
                s0, s1, fi = self._graded_split(s0, s1, idx, lo_b / a)
            else:
                s0, s1 = s0[:, None], s1[:, None]
            s = s1 + (s0 - s1) * X
            half_cos = np.cos(0.5 * s)
            hc2 = half_cos * half_cos
            sin_s = np.sin(s)
            r = np.sqrt((a - c) * (a - c) + (4 * a * c) * hc2)
            # f = (polar angle of the footprint's rim point seen from the axis) / pi,
            # and 2 pi r dr = 2 pi a c sin(psi) dpsi
            f_band = np.arctan2(a * sin_s, (c - a) + (2 * a) * hc2)
            fis.append(fi)
            rs.append(r)
            gs.append(f_band * ((2 * a * c) * sin_s * (s0 - s1) * wh))
        if not fis:
            return
        if len(fis) > 1:
            fi, r, g = np.concatenate(fis), np.concatenate(rs), np.concatenate(gs)
        else:
            fi, r, g = fis[0], rs[0], gs[0]
        gx = np.sum(g * (r - self.r0[fi][:, None]), axis=1) * self.inv_L[fi]
        n = self.n_nodes
        loads += np.bincount(self.fn0[fi], np.sum(g, axis=1) - gx, n)
        loads += np.bincount(self.fn1[fi], gx, n)

    def _graded_split(self, s0, s1, idx, ratio):
        """Cut the psi intervals [s1, s0] at pi - w 4^k, w = sqrt(ratio)
        (vectorised: every interval against the global partition)."""
        w = max(math.sqrt(ratio), 1e-8)
        cuts = w * self._cut_steps
        cuts = cuts[cuts < math.pi]
        part = np.concatenate(([0.0], math.pi - cuts[::-1], [math.pi]))
        lo = np.maximum(s1[:, None], part[None, :-1])
        hi = np.minimum(s0[:, None], part[None, 1:])
        keep = hi > lo
        fi = np.broadcast_to(idx[:, None], keep.shape)[keep]
        return hi[keep][:, None], lo[keep][:, None], fi

    def pattern(self, c: float, a: float) -> np.ndarray:
        """Nodal loads (W per unit flux, on top nodes) of the ring-averaged
        footprint: int f(r) phi_i 2 pi r dr. Facets fully covered add their
        precomputed loads (f = 1 there; uncovered ones nothing), the partly
        covered ones come from _band_loads."""
        loads = np.zeros(self.n_nodes)
        if c <= 1e-12 * a:
            full_below, band = a, self._range(a, a, strict_lo=True)    # r0 < a < r1
        else:
            lo_b, hi_b = abs(c - a), c + a
            full_below = lo_b if c < a else 0.0
            band = self._range(lo_b, hi_b, strict_lo=True)             # r1 > lo_b, r0 < hi_b
        if full_below > 0.0:
            full = np.flatnonzero(self.r1 <= full_below) if not self._sorted else \
                np.arange(np.searchsorted(self.r1, full_below, side="right"))
            if len(full):
                loads += np.bincount(self.fn0[full], self.full0[full], self.n_nodes)
                loads += np.bincount(self.fn1[full], self.full1[full], self.n_nodes)
        if len(band):
            self._band_loads(band, c, a, loads)
        return loads


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
