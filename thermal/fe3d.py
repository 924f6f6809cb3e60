"""Transient conduction in the 3D plate under the travelling footprint
(model.md section 10, fe3d; docs/thermal.md section 8).

The plate is a box: a square of the disk plate's area (side sqrt(pi) R, so
the mass and the exposed face are the plate's), thickness t; the concave
face's curvature is neglected (R1, R2 >> the footprint and the depth heat
reaches). Plate-local coordinates: origin at the plate centre on the sliding
face, x along the path (the arc position s the stepper reports: s1 on the
lower plate, -s2 on the upper), y across it in the face, z the depth into
the steel (positive into the plate).

Weak form, trilinear hexahedra (Q1) on the tensor grid x_i y_j z_k:

    int rho c u_t v + int k grad u . grad v + int_{exposed} h u v = int_top q chi v,

u = T - T_air, exposed = the sliding face (the pad's cover neglected, as in
axisym), the four sides, and the back face when params.back is "convection"
("fixed" holds it at T_back_C, "adiabatic" leaves it free); chi is the
footprint disk of radius a centred on the path point, q = P / (pi a^2).

Fast stepping. On the tensor grid every matrix is a Kronecker product of 1D
P1 matrices: M = rho c Mx (x) My (x) Mz, A = Ax (x) My (x) Mz + Mx (x) Ay (x) Mz
+ Mx (x) My (x) Az (A_d = k K_d + h on the convective end nodes). With the
generalised eigenvectors of each pair (A_d, M_d) the change of variables
u = (Wx (x) Wy (x) V) y makes M = rho c I and A = diag(theta_i + theta_j +
theta_k): each mode is integrated exactly over a thermal step
(thermal/_fe3d_kernel.py), the load and the footprint mean are small dense
products (Wx^T P Wy for the footprint weights P on the surface nodes). The
Kronecker structure is checked against scikit-fem's hexahedral assembly in
tests/test_fe3d.py.

Thermal step. One thermal step of h = step_multiple x dt: the friction heat of
those mechanical steps, at their power-weighted mean footprint position, held
over the step (exact in time for that load). Between thermal steps step()
returns the footprint mean of the last thermal step (friction sees the
temperature with a lag of at most h; docs/thermal.md gives the measured error).
Heat received in a thermal step not yet taken is counted in heat_in and
stored_heat (it is in the plate, not yet conducted), so the ledger closes at
every mechanical step.
"""
from __future__ import annotations


import numpy as np
from scipy.linalg import eigh

from fpd.meshes.box import box_nodes, hex_mesh
from fpd.thermal.params import PlateParams

NG = 6                                   # Gauss points per footprint quadrature interval
_GL = np.polynomial.legendre.leggauss(NG)


_WARM = set()


def kernels(jit: bool | None = None):
    """The fe3d kernel module: its numba copy (fpd/kernels.py: the same
    source) when ``jit`` is True, or None and numba is available
    (FPD_NO_JIT unset); else the pure module. ``jit=True`` without numba
    raises ImportError."""
    from fpd import kernels as kern
    from fpd.thermal import _fe3d_kernel

    if jit or (jit is None and kern.available()):
        try:
            k = kern.compiled("fpd.thermal._fe3d_kernel")
        except ImportError:
            if jit:
                raise ImportError("fe3d: jit=True needs numba") from None
        else:
            if id(k) not in _WARM:      # compile (or load) before the time loop, not on its first step
                k.warm_up()
                _WARM.add(id(k))
            return k
    return _fe3d_kernel


# -- 1D factors ---------------------------------------------------------------------
def line_matrices(x: np.ndarray):
    """Exact P1 mass and stiffness of the nodes x (tridiagonal, dense)."""
    h = np.diff(x)
    n = len(x)
    M = np.zeros((n, n))
    K = np.zeros((n, n))
    i = np.arange(n - 1)
    M[i, i] += h / 3
    M[i + 1, i + 1] += h / 3
    M[i, i + 1] = M[i + 1, i] = h / 6
    K[i, i] += 1 / h
    K[i + 1, i + 1] += 1 / h
    K[i, i + 1] = K[i + 1, i] = -1 / h
    return M, K


def line_modes(M: np.ndarray, A: np.ndarray):
    """Generalised eigenpairs A W = M W diag(theta), W^T M W = I, on the
    diagonally scaled pencil; theta recomputed as Rayleigh quotients (the small
    eigenvalues, which carry the heat, to round-off relative to themselves)."""
    d = 1.0 / np.sqrt(np.diag(M))
    _, X = eigh(d[:, None] * A * d, d[:, None] * M * d)
    W = d[:, None] * X
    theta = np.einsum("ij,ij->j", W, A @ W) / np.einsum("ij,ij->j", W, M @ W)
    theta = np.maximum(theta, 0.0)
    return theta, W


# -- the footprint -------------------------------------------------------------------
def footprint_loads(xn: np.ndarray, yn: np.ndarray, cx: float, cy: float, a: float, jit: bool | None = None):
    """int chi phi_i(x) phi_j(y) dx dy over the sliding face for the disk chi of
    radius a centred at (cx, cy), on the nodes of the window it touches:
    (i0, j0, P) with P[i - i0, j - j0] the load of node (i, j) per unit flux
    (m2); P.sum() is the disk's area on the plate (thermal/_fe3d_kernel.py)."""
    P = np.zeros((len(xn), len(yn)))
    win = np.zeros(4, dtype=np.int64)
    kernels(jit).footprint_loads(np.asarray(xn, float), np.asarray(yn, float), cx, cy, a, _GL[0], _GL[1], P, win)
    i0, j0, ni, nj = (int(v) for v in win)
    return i0, j0, P[:ni, :nj].copy() if ni else np.zeros((0, 0))


def _centre_xy(centre):
    """A float (arc position along x, planar runs) or a pair (x, y)."""
    if isinstance(centre, (tuple, list, np.ndarray)):
        return float(centre[0]), float(centre[1])
    return float(centre), 0.0


class FE3DPlate:
    """PlateModel of docs/architecture.md on the 3D box (module docstring)."""

    def __init__(self, params: PlateParams, dt: float, nodes=None, jit: bool | None = None):
        """dt: the mechanical step; the thermal step is params.step_multiple * dt.
        nodes: (x, y, z) to override the default box_nodes (tests).
        jit: None uses the numba kernel when available, False never, True requires it."""
        from fpd.thermal.fe1d import check_params

        check_params(params)
        self.params = p = params
        self.dt = float(dt)
        self.multiple = max(1, int(p.step_multiple))
        self.h = self.dt * self.multiple
        a = p.a_contact_m
        if nodes is None:
            band_y = (p.sweep_y_m + a) if p.sweep_y_m > 0 else None
            nodes = box_nodes(p.plate_radius, p.plate_thickness, a, p.per_radius, p.nz, p.grading, band_y)
        self.x, self.y, self.z = (np.asarray(v, dtype=float) for v in nodes)
        rc, k, hc = p.rho * p.c, p.k, p.h_conv
        self.rho_c = rc
        self._K = kernels(jit)
        # 1D factors: convection on both ends in x and y (the sides), on the
        # sliding face (z = 0) and, with "convection", the back face
        Mx, Kx = line_matrices(self.x)
        My, Ky = line_matrices(self.y)
        Mz, Kz = line_matrices(self.z)
        Ax, Ay, Az = k * Kx, k * Ky, k * Kz
        for A in (Ax, Ay):
            A[0, 0] += hc
            A[-1, -1] += hc
        Az[0, 0] += hc
        if p.back == "convection":
            Az[-1, -1] += hc
        nz = len(self.z)
        self.fixed = p.back == "fixed"
        f = np.arange(nz - 1) if self.fixed else np.arange(nz)
        self.tx, self.Wx = line_modes(Mx, Ax)
        self.ty, self.Wy = line_modes(My, Ay)
        self.tz, self.V = line_modes(Mz[np.ix_(f, f)], Az[np.ix_(f, f)])
        self.Wxi, self.Wyi, self.Vi = self.Wx.T @ Mx, self.Wy.T @ My, self.V.T @ Mz[np.ix_(f, f)]
        self.nx, self.ny, self.nzf = len(self.x), len(self.y), len(f)
        self.nxy = self.nx * self.ny
        lam = (self.tx[:, None, None] + self.ty[None, :, None] + self.tz[None, None, :]).ravel()
        # heat capacity functional m = rho c (Wx^T Mx 1) (x) (Wy^T My 1) (x) (V^T Mz_ff 1)
        mx, my = self.Wx.T @ Mx.sum(axis=1), self.Wy.T @ My.sum(axis=1)
        mz = self.V.T @ Mz[np.ix_(f, f)].sum(axis=1)
        m = rc * (mx[:, None, None] * my[None, :, None] * mz[None, None, :]).ravel()
        x_ = lam * self.h / rc
        h = self.h
        # E = exp(-x) is separable: the kernel multiplies per-direction factors
        self.ex, self.ey, self.ez = (np.exp(-t * h / rc) for t in (self.tx, self.ty, self.tz))
        small = x_ < 1e-3
        xs = np.where(small, 1.0, x_)
        phi1 = np.where(small, h * (1 - x_ / 2 + x_ * x_ / 6 - x_ ** 3 / 24), h * -np.expm1(-xs) / xs)
        phi2 = np.where(small, h * (0.5 - x_ / 6 + x_ * x_ / 24 - x_ ** 3 / 120),
                        h * (np.expm1(-xs) + xs) / (xs * xs))
        self.Fa = (phi1 - phi2) / rc
        self.Fb = phi2 / rc
        self.vt = self.V[0].copy()                         # depth modes at the sliding face
        red = lambda arr: arr.reshape(self.nxy, self.nzf) @ self.vt
        self.mfv0 = red(m * (0.5 * h / rc - self.Fa))
        self.mfv1 = red(m * (0.5 * h / rc - self.Fb))
        del m
        self._mx, self._my, self._mz = rc * mx, my, mz    # m = (rho c mx) (x) my (x) mz
        # the fixed back: steady no-load state ys (A_ff us = -A_fD uD) and the
        # state as a deviation from it (the fixed face then drops out of the ledger)
        self.ys = np.zeros(len(lam))
        if self.fixed:
            d = p.T_back_C - p.T_air_C
            D = nz - 1
            ax, ay = self.Wx.T @ Ax.sum(axis=1), self.Wy.T @ Ay.sum(axis=1)
            mzD, azD = self.V.T @ Mz[f, D], self.V.T @ Az[f, D]
            fhat = d * (np.einsum("i,j,k->ijk", ax, my, mzD) + np.einsum("i,j,k->ijk", mx, ay, mzD)
                        + np.einsum("i,j,k->ijk", mx, my, azD)).ravel()
            self.ys = -fhat / lam
        self.ys_top = self.ys.reshape(self.nxy, self.nzf) @ self.vt
        u0 = np.full((self.nx, self.ny, self.nzf), p.T0_C - p.T_air_C)
        self.v = self.to_modal(u0) - self.ys
        # one pass over v per thermal step gives the sliding face (column 0) and
        # the heat content (column 1: rho c (mx (x) my) . this = m . v)
        self._mxy = rc * np.outer(mx, my).ravel()
        self._proj = np.zeros((self.nxy, 2))
        self._K.project(self.v, self.vt, self._mz, self.nxy, self._proj)
        self.top = self._proj[:, 0].copy()                 # surface modes of v
        self._m_v0 = float(self._mxy @ self._proj[:, 1])
        # the fixed material point: (radius_m, 0) on the sliding face
        self.point_xy = (float(p.radius_m), 0.0)
        self._wpoint = self._point_weights(*self.point_xy)
        self._heat_in = 0.0
        self._lost = 0.0
        self._acc = [0.0, 0.0, 0.0, 0]                     # energy, energy-weighted x, y, steps
        self._zero = np.zeros(self.nxy)
        # the footprint's node window: at most 2 a / (smallest element) + 3 nodes a side
        wmax = lambda nodes: min(len(nodes), int(2 * a / np.diff(nodes).min()) + 4)
        self._Pbuf = np.zeros((wmax(self.x), wmax(self.y)))
        self._win = np.zeros(4, dtype=np.int64)
        self._pattern_key = None
        self._w_start = self._w_end = None                # modal footprint weights (None: off the plate)
        self.steps = 0                                     # thermal steps taken
        self._stored = 0.0                                 # m . (v - v0), set at each thermal step
        self.point_peak = (float(p.T0_C), 0.0)             # the material point's hottest (T degC, t s)
        self._T = float(p.T0_C)
        self._T = self._mean_at(0.0, 0.0)

    # -- changes of basis ------------------------------------------------------------
    def to_modal(self, U: np.ndarray) -> np.ndarray:
        """(Wx (x) Wy (x) V)^-1 of a nodal (nx, ny, nzf) field, flat."""
        T = np.tensordot(self.Wxi, U, axes=(1, 0))
        T = np.einsum("bj,ajk->abk", self.Wyi, T)
        return (T @ self.Vi.T).ravel()

    def to_nodal(self, y: np.ndarray, rows=None) -> np.ndarray:
        """(Wx (x) Wy (x) V) y as a nodal (nx, ny, nzf) field; ``rows``: only
        those y rows (nx, len(rows), nzf), a slice at a fraction of the cost."""
        Y = y.reshape(self.nx, self.ny, self.nzf)
        if rows is not None:
            T = np.einsum("bj,ajk->abk", self.Wy[rows], Y)
            return np.tensordot(self.Wx, T, axes=(1, 0)) @ self.V.T
        T = np.tensordot(self.Wx, Y, axes=(1, 0))
        T = np.einsum("bj,ajk->abk", self.Wy, T)
        return T @ self.V.T

    # -- footprint ----------------------------------------------------------------------
    def footprint_weights(self, cx: float, cy: float):
        """Modal footprint weights (nx*ny,), normalised to 1 (the heat of a
        footprint partly over the edge goes to the plate), or None when the
        footprint is wholly off the plate."""
        tot = self._K.footprint_loads(self.x, self.y, cx, cy, self.params.a_contact_m, _GL[0], _GL[1],
                                      self._Pbuf, self._win)
        if not tot > 0:
            return None
        i0, j0, ni, nj = (int(v) for v in self._win)
        P = self._Pbuf[:ni, :nj] / tot
        Wx = self.Wx[i0:i0 + P.shape[0]]
        Wy = self.Wy[j0:j0 + P.shape[1]]
        return (Wx.T @ P @ Wy).ravel()

    def _point_weights(self, px: float, py: float) -> np.ndarray:
        def hat(nodes, s):
            w = np.zeros(len(nodes))
            e = int(np.clip(np.searchsorted(nodes, s, side="right") - 1, 0, len(nodes) - 2))
            xi = min(1.0, max(0.0, (s - nodes[e]) / (nodes[e + 1] - nodes[e])))
            w[e], w[e + 1] = 1 - xi, xi
            return w
        return np.outer(self.Wx.T @ hat(self.x, px), self.Wy.T @ hat(self.y, py)).ravel()

    def _mean_at(self, cx: float, cy: float) -> float:
        w = self.footprint_weights(cx, cy)
        if w is None:
            return self._T
        return float(w @ (self.top + self.ys_top) + self.params.T_air_C)

    # -- PlateModel interface ----------------------------------------------------------
    def step(self, power_W: float, centre=0.0) -> float:
        """Receive power_W over one mechanical step with the footprint at
        ``centre`` (a float: arc position along x; or a pair (x, y)). Every
        step_multiple calls, one thermal step; returns the footprint-mean
        surface temperature (degC) of the last thermal step."""
        cx, cy = _centre_xy(centre)
        acc = self._acc
        e = float(power_W) * self.dt
        acc[0] += e
        acc[1] += e * cx
        acc[2] += e * cy
        acc[3] += 1
        if acc[3] >= self.multiple:
            self._thermal_step(cx, cy)
        return self._T

    def _thermal_step(self, cx: float, cy: float) -> None:
        """One thermal step: the heat received since the last one, delivered at
        a constant power over the step, its footprint moving linearly from where
        the last step ended to (cx, cy) (ETD2, thermal/_fe3d_kernel.py)."""
        E_in = self._acc[0]
        self._acc = [0.0, 0.0, 0.0, 0]
        key = (cx, cy)
        if key != self._pattern_key:
            self._w_end = self.footprint_weights(cx, cy)
            self._pattern_key = key
        w0, w1 = self._w_start, self._w_end
        if w0 is None:
            w0 = w1
        if w1 is None:
            w1 = w0
        if w0 is None:                                     # wholly off the plate: nothing delivered
            w0 = w1 = self._zero
            E_in = 0.0
        p = E_in / self.h
        K = self._K
        loss = K.exp_step(self.v, self.ex, self.ey, self.ez, self._mx, self._my, self._mz, self.Fa, self.Fb,
                          w0, w1, self.vt, p, self._proj)
        self._lost += loss + p * (w0 @ self.mfv0 + w1 @ self.mfv1)
        self._heat_in += E_in
        self.top[:] = self._proj[:, 0]
        self._stored = float(self._mxy @ self._proj[:, 1]) - self._m_v0
        self.steps += 1
        self._w_start = self._w_end
        Tp = self.point_temperature()
        if Tp > self.point_peak[0]:
            self.point_peak = (Tp, self.steps * self.h)
        if self._w_end is not None:
            self._T = float(self._w_end @ (self.top + self.ys_top) + self.params.T_air_C)

    def surface_temperature(self) -> float:
        return self._T

    def point_temperature(self) -> float:
        """Temperature (degC) of the fixed material point (radius_m, 0) on the
        sliding face, at the last thermal step."""
        return float(self._wpoint @ (self.top + self.ys_top) + self.params.T_air_C)

    def surface_field(self) -> np.ndarray:
        """Nodal temperatures (degC) of the sliding face, (nx, ny)."""
        Y = (self.top + self.ys_top).reshape(self.nx, self.ny)
        return self.Wx @ Y @ self.Wy.T + self.params.T_air_C

    def peak_temperature(self) -> float:
        """Hottest nodal temperature (degC) of the sliding face (the hottest
        point of the plate: heat enters there)."""
        return float(self.surface_field().max())

    def temperature(self, state=None, rows=None) -> np.ndarray:
        """Nodal temperatures (degC), (nx, ny, nz) (the fixed back layer
        included), of the current state or of one kept by field_state();
        ``rows``: only those y rows, (nx, len(rows), nz)."""
        p = self.params
        U = self.to_nodal((self.v if state is None else state) + self.ys, rows) + p.T_air_C
        if self.fixed:
            U = np.concatenate((U, np.full((U.shape[0], U.shape[1], 1), p.T_back_C)), axis=2)
        return U

    def stored_heat(self) -> float:
        """rho c int (T - T_initial) (J), with the heat received in the thermal
        step under way (in the plate, not yet conducted)."""
        return self._stored + self._acc[0]

    def heat_lost(self) -> float:
        return self._lost

    def heat_in(self) -> float:
        return self._heat_in + self._acc[0]

    def save(self):
        # the weight arrays are never modified in place (new arrays per position): kept by reference
        return (self.v.copy(), self.top.copy(), self._w_start, self._w_end, self._pattern_key,
                self._heat_in, self._lost, list(self._acc), self.steps, self._T, self._stored, self.point_peak)

    def restore(self, snap) -> None:
        (v, top, self._w_start, self._w_end, self._pattern_key, self._heat_in, self._lost, acc, self.steps,
         self._T, self._stored, self.point_peak) = snap
        self.v[:] = v
        self.top[:] = top
        self._acc = list(acc)

    def field_state(self):
        """A copy of the state, for field(state) later (the hottest-field
        tracker keeps this instead of building the field at every look)."""
        return self.v.copy()

    def field(self, state=None):
        """(points, cells, T) of the plate in plate-local coordinates: origin at
        the plate centre on the sliding face, x along the path, y across it in
        the face, z the depth into the steel (positive into the plate); cells
        are VTK hexahedra (nodes (i, j, k) of the x, y, z grid at index
        (i ny + j) nz + k); T in degC at the last thermal step (or of a state
        from field_state())."""
        T = self.temperature(state)
        if getattr(self, "_mesh", None) is None:         # the grid never changes: built once
            self._mesh = hex_mesh(self.x, self.y, self.z)
        pts, cells = self._mesh
        return pts, [("hexahedron", cells)], T.ravel()
