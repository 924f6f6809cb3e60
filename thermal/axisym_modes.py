"""The eigenbasis of the axisym plate on a tensor-product Q1 mesh
(TensorModes) and the time integrator that steps in it (ModalIntegrator:
thermal.stepping's schemes with M, A diagonal); docs/thermal.md, section 2.
Used by thermal/axisym.py when the mesh is a tensor product."""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.linalg import eigh

from fpd.thermal.stepping import Integrator


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
