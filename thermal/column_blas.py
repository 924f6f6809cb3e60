"""The linear-algebra and vector primitives of the fe1d column step, pure backend.

thermal/column_kernel.py (the scheme, start-up, jump test and ledger,
written once) calls these (numpy's whole-array operations here, loops in
the compiled twin, where an array expression would cost more than the loop); the compiled path swaps this module for
thermal/column_blas_numba.py (``__compiled_backend__``, fpd/kernels.py),
which calls the same LAPACK/BLAS routines of scipy's library (dpttrs,
ddot) through pointers and writes the band product as the same sequence
of roundings, so both paths give the same numbers bit for bit. The arguments
``I`` (int32: n, k=1, lda=2, inc=1, nrhs=1, info, ord('U'), nf; the routines read n, inc, nrhs, info and nf) and ``sc``
(float scratch) are what the pointer calls need; here they are unused.
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import lapack

__compiled_backend__ = "fpd.thermal.column_blas_numba"

_dpttrs = lapack.dpttrs     # the f2py wrapper, called with positional arguments (faster)


def band_mv(I, sc, alpha, band, x, beta, y):
    """y = alpha B x (beta == 0) or y += alpha B x (beta == 1), B tridiagonal
    symmetric in upper band storage (2, n): per row (B_ii x_i + B_i,i+1
    x_i+1 + B_i-1,i x_i-1) alpha, in that order, as the compiled twin's
    loop. Not BLAS dsbmv: with one off-diagonal it makes two calls per row
    (the fe1d step spent more time in them than in the rest of the step),
    and its rounding depends on the machine's BLAS kernel."""
    t = np.multiply(band[0, 1:], x[1:])
    out = np.multiply(band[1], x, out=y if beta == 0.0 else None)     # y is not x
    out[:-1] += t
    np.multiply(band[0, 1:], x[:-1], out=t)
    out[1:] += t
    out *= alpha
    if beta != 0.0:
        y += out


def pt_solve(I, d, e, rhs, nf):
    """rhs[:nf] = (L D L^T)^-1 rhs[:nf] in place, (d, e) the factor of dpttrf
    (lengths nf, nf - 1)."""
    _dpttrs(d, e, rhs if nf == rhs.shape[0] else rhs[:nf], 1)     # overwrite_b


def dot(I, x, y):
    """x . y (the BLAS ddot the compiled backend calls)."""
    return float(x @ y)


def accept(u, du, x, nf):
    """u[:nf] += x[:nf]; du[:nf] = x[:nf] (the increment taken)."""
    u[:nf] += x[:nf]
    du[:nf] = x[:nf]


def copy(dst, src, nf):
    """dst[:nf] = src[:nf]."""
    dst[:nf] = src[:nf]


def difference(dst, a, b, nf):
    """dst[:nf] = a[:nf] - b[:nf]."""
    dst[:nf] = a[:nf] - b[:nf]
