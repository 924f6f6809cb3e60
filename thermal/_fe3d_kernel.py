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
(thermal/_fe3d_jit.py); the numpy path (FPD_NO_JIT, or no numba) runs the same
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


def warm_up():
    v = np.zeros(8)
    o = np.ones(2)
    proj = np.zeros((4, 2))
    exp_step(v, o, o, o, o, o, o, np.ones(8), np.ones(8), np.ones(4), np.ones(4), o, 1.0, proj)
    project(v, o, o, 4, proj)
