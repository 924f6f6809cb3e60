"""fe3d's per-step physics (a kernel module, fpd/kernels.py): the exact
exponential step of every mode of the plate (thermal/fe3d.py).

In the eigenbasis the semi-discrete system rho c v' = -lam v + b is diagonal;
with the load held over the thermal step h each mode is integrated exactly:

    v <- E v + F b,          E = exp(-lam h / (rho c)),  F = (1 - E) / lam,

and the heat lost through the boundary over the step (convection, fixed back)
is the exact integral of the boundary flux, lam m / (rho c) . int v dt:

    loss = sum m (1 - E) v_old + sum m (h / (rho c) - F) b.

The load is rank one in the (surface, depth) split, b = p w (x) vt, so
sum m (h/rho c - F) b = p w . mfv with mfv precomputed.
Written with numpy array operations that numba also compiles: the pure path
is vectorised, the compiled one fuses the loops.
"""
__kernel__ = True

import numpy as np


def exp_step(v, E, F, mloss, w, vt, p, mfv):
    """One exact step of all modes (v: flat, surface-major, depth-minor; w: the
    modal footprint weights of the surface, vt: the depth modes at the
    sliding face). Updates v in place; returns the heat lost over the step (J)."""
    loss = np.dot(mloss, v) + p * np.dot(w, mfv)
    b = np.outer(w * p, vt).ravel()
    v *= E
    v += F * b
    return loss


def surface_modes(v, vt, nxy, out):
    """out[ij] = sum_k v[ij, k] vt[k]: the sliding face in the surface modal
    basis (what the footprint mean and the surface field need)."""
    nz = vt.shape[0]
    out[:] = np.dot(v.reshape(nxy, nz), vt)
    return out


def warm_up():
    v = np.zeros(6)
    exp_step(v, np.ones(6), np.ones(6), np.ones(6), np.ones(2), np.ones(3), 1.0, np.ones(2))
    surface_modes(v, np.ones(3), 2, np.zeros(2))
