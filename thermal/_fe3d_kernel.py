"""fe3d's per-step physics (a kernel module, fpd/kernels.py): the exact
exponential step of every mode of the plate (thermal/fe3d.py).

In the eigenbasis the semi-discrete system rho c v' = -lam v + b(t) is
diagonal. Over a thermal step h the load is taken linear in time from b0 (the
footprint where the step starts) to b1 (where it ends), and each mode is
integrated exactly for that load (exponential time differencing, ETD2):

    v <- E v + Fa b0 + Fb b1,   E = exp(-x),  x = lam h / (rho c),
    Fa = (phi1 - phi2) / (rho c),  Fb = phi2 / (rho c),
    phi1 = h (1 - E) / x,  phi2 = h (E - 1 + x) / x^2,

so the stiff (surface) modes see the footprint where it is at the step's end.
The heat lost through the boundary over the step (convection, fixed back)
is the exact integral of the boundary flux, lam m / (rho c) . int v dt:

    loss = sum m (1 - E) v_old + sum m (h (b0 + b1) / (2 rho c) - Fa b0 - Fb b1).

The loads are rank one in the (surface, depth) split, b = p w (x) vt, so the
load part is p (w0 . mfv0 + w1 . mfv1) with mfv0, mfv1 precomputed. E and the
heat capacities m are separable (products of per-direction factors), so the
step reads only v, Fa and Fb: one fused pass that also projects the new state
on the sliding face and on the heat-capacity functional (the footprint mean
and the stored heat need nothing more). Plain loops: fast compiled by numba
(fpd.kernels.compiled); the numpy path (FPD_NO_JIT, or no numba) runs the same
loops in Python, correct but ~100 times slower.
"""
__kernel__ = True

import numpy as np


def exp_step(v, ex, ey, ez, mx, my, mz, Fa, Fb, w0, w1, vt, p, proj):
    """One exact step of all modes. v: flat state, index (i ny + j) nz + k;
    E = ex[i] ey[j] ez[k]; m = mx[i] my[j] mz[k] (rho c included in mx); w0, w1:
    the modal footprint weights (nx ny) at the step's start and end, vt the
    depth modes at the sliding face, p the power (W). Updates v in place and
    proj[ij] = (sum_k v vt, sum_k v mz); returns sum m (1 - E) v_old (J), the
    state part of the heat lost over the step."""
    nx, ny, nz = ex.shape[0], ey.shape[0], ez.shape[0]
    loss = 0.0
    for i in range(nx):
        for j in range(ny):
            ij = i * ny + j
            exy = ex[i] * ey[j]
            a0 = p * w0[ij]
            a1 = p * w1[ij]
            base = ij * nz
            s = 0.0
            top = 0.0
            heat = 0.0
            for k in range(nz):
                n = base + k
                e = exy * ez[k]
                y = v[n]
                s += mz[k] * (1.0 - e) * y
                y = e * y + (Fa[n] * a0 + Fb[n] * a1) * vt[k]
                v[n] = y
                top += y * vt[k]
                heat += y * mz[k]
            loss += mx[i] * my[j] * s
            proj[ij, 0] = top
            proj[ij, 1] = heat
    return loss


def project(v, vt, mz, nxy, proj):
    """proj[ij] = (sum_k v vt, sum_k v mz) without stepping (the initial state)."""
    nz = vt.shape[0]
    for ij in range(nxy):
        top = 0.0
        heat = 0.0
        for k in range(nz):
            top += v[ij * nz + k] * vt[k]
            heat += v[ij * nz + k] * mz[k]
        proj[ij, 0] = top
        proj[ij, 1] = heat
    return proj


def _hat_cum(nodes, j, y):
    """int_{-inf}^{y} phi_j: the hat function of node j (y clipped to the nodes)."""
    n = nodes.shape[0]
    hl = nodes[j] - nodes[j - 1] if j > 0 else 0.0
    hr = nodes[j + 1] - nodes[j] if j < n - 1 else 0.0
    if j > 0 and y <= nodes[j - 1]:
        return 0.0
    if j == 0 and y <= nodes[0]:
        return 0.0
    if y <= nodes[j]:
        d = y - nodes[j - 1]
        return 0.5 * d * d / hl
    if j == n - 1 or y >= nodes[j + 1]:
        return 0.5 * (hl + hr)
    d = nodes[j + 1] - y
    return 0.5 * hl + 0.5 * hr - 0.5 * d * d / hr


def footprint_loads(xn, yn, cx, cy, a, gx, gw, P, win):
    """Loads int chi phi_i(x) phi_j(y) dx dy of the disk chi (centre (cx, cy),
    radius a) on the nodes of the window it touches: P[i - i0, j - j0] (P
    zeroed first, at least as large as the window); win = (i0, j0, ni, nj).
    x = cx + a sin(t), the chord |y - cy| <= a cos(t); the chord integral of
    the hats is exact, the t integral Gauss-Legendre (nodes gx, weights gw on
    [-1, 1]) on pieces split wherever x or a chord end crosses a node, each a
    smooth trigonometric polynomial (docs/thermal.md, section 8). Returns the
    covered area (0: nothing on the plate)."""
    nxn, nyn = xn.shape[0], yn.shape[0]
    win[0] = 0
    win[1] = 0
    win[2] = 0
    win[3] = 0
    P[:, :] = 0.0
    t_lo = np.arcsin(min(1.0, max(-1.0, (xn[0] - cx) / a)))
    t_hi = np.arcsin(min(1.0, max(-1.0, (xn[nxn - 1] - cx) / a)))
    i0 = max(0, np.searchsorted(xn, cx - a, side="right") - 1)
    i1 = min(nxn, np.searchsorted(xn, cx + a, side="left") + 1)
    j0 = max(0, np.searchsorted(yn, cy - a, side="right") - 1)
    j1 = min(nyn, np.searchsorted(yn, cy + a, side="left") + 1)
    if t_hi <= t_lo or i1 - i0 < 2 or j1 - j0 < 2 or cy - a >= yn[nyn - 1] or cy + a <= yn[0]:
        return 0.0
    br = np.empty(2 + (i1 - i0) + 2 * (j1 - j0))
    nb = 0
    br[nb] = t_lo
    nb += 1
    br[nb] = t_hi
    nb += 1
    for i in range(i0, i1):
        u = (xn[i] - cx) / a
        if -1.0 < u < 1.0:
            t = np.arcsin(u)
            if t_lo < t < t_hi:
                br[nb] = t
                nb += 1
    for j in range(j0, j1):
        u = abs(yn[j] - cy) / a
        if u < 1.0:
            t = np.arccos(u)
            if t_lo < t < t_hi:
                br[nb] = t
                nb += 1
            if t_lo < -t < t_hi:
                br[nb] = -t
                nb += 1
    br = np.sort(br[:nb])
    total = 0.0
    for q in range(nb - 1):
        lo, hi = br[q], br[q + 1]
        if hi - lo <= 1e-15:
            continue
        for g in range(gx.shape[0]):
            t = lo + (hi - lo) * 0.5 * (gx[g] + 1.0)
            ct = np.cos(t)
            wt = (hi - lo) * 0.5 * gw[g] * a * ct
            X = cx + a * np.sin(t)
            half = a * ct
            e = min(max(np.searchsorted(xn, X, side="right") - 1, 0), nxn - 2)
            xi = min(1.0, max(0.0, (X - xn[e]) / (xn[e + 1] - xn[e])))
            for j in range(j0, j1):
                gj = _hat_cum(yn, j, cy + half) - _hat_cum(yn, j, cy - half)
                if gj != 0.0:
                    P[e - i0, j - j0] += wt * (1.0 - xi) * gj
                    if e + 1 < i1:
                        P[e + 1 - i0, j - j0] += wt * xi * gj
                    total += wt * gj
    win[0] = i0
    win[1] = j0
    win[2] = i1 - i0
    win[3] = j1 - j0
    return total


def warm_up():
    v = np.zeros(8)
    o = np.ones(2)
    proj = np.zeros((4, 2))
    exp_step(v, o, o, o, o, o, o, np.ones(8), np.ones(8), np.ones(4), np.ones(4), o, 1.0, proj)
    project(v, o, o, 4, proj)
    nodes = np.linspace(-1.0, 1.0, 5)
    g = np.array([-0.5, 0.5])
    footprint_loads(nodes, nodes, 0.1, 0.0, 0.7, g, np.ones(2), np.zeros((5, 5)), np.zeros(4, dtype=np.int64))
