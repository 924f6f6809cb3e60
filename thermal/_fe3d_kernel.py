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
load part is p (w0 . mfv0 + w1 . mfv1) with mfv0, mfv1 precomputed.
Written with numpy array operations that numba also compiles: the pure path
is vectorised, the compiled one fuses the loops.
"""
__kernel__ = True

import numpy as np


def exp_step(v, E, Fa, Fb, mloss, w0, w1, vt, p, mfv0, mfv1):
    """One exact step of all modes (v: flat, surface-major, depth-minor; w0, w1:
    the modal footprint weights of the surface at the step's start and end, vt:
    the depth modes at the sliding face, p the power). Updates v in place;
    returns the heat lost over the step (J)."""
    loss = np.dot(mloss, v) + p * (np.dot(w0, mfv0) + np.dot(w1, mfv1))
    v *= E
    v += Fa * np.outer(w0 * p, vt).ravel()
    v += Fb * np.outer(w1 * p, vt).ravel()
    return loss


def surface_modes(v, vt2, nxy, out):
    """out[ij, :] = sum_k v[ij, k] vt2[k, :]: with vt2 = (the depth modes at
    the sliding face, the depth heat-capacity functional), the sliding face in
    the surface modal basis (for the footprint mean and the surface field) and
    the depth-integrated heat, in one pass over v."""
    nz = vt2.shape[0]
    out[:, :] = np.dot(v.reshape(nxy, nz), vt2)
    return out


def warm_up():
    v = np.zeros(6)
    exp_step(v, np.ones(6), np.ones(6), np.ones(6), np.ones(6), np.ones(2), np.ones(2), np.ones(3), 1.0,
             np.ones(2), np.ones(2))
    surface_modes(v, np.ones((3, 2)), 2, np.zeros((2, 2)))
