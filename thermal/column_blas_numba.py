"""The fe1d column's linear-algebra primitives, compiled backend (numba).

Same contract as thermal/column_blas.py, whose ``__compiled_backend__``
names this module: fpd.kernels.compiled("fpd.thermal.column_kernel") calls
these instead. dpttrs and ddot are the routines of the library scipy uses
(scipy.linalg.cython_blas / cython_lapack), linked by symbol name so that
numba can cache the callers; the band product is numpy's elementwise
sequence, written out. Only numba and scipy are imported.
"""
from __future__ import annotations

import llvmlite.binding as _ll
from numba import njit, types
from numba.extending import get_cython_function_address

_OPTIONS = {"cache": True, "nogil": True, "error_model": "numpy", "inline": "always"}


def _extern(module: str, name: str, restype, nargs: int):
    """The scipy BLAS/LAPACK routine as a symbol the compiled code links by
    name (unlike a ctypes pointer, this lets numba cache the kernel)."""
    sym = f"fpd_{name}"
    _ll.add_symbol(sym, get_cython_function_address(f"scipy.linalg.{module}", name))
    return types.ExternalFunction(sym, restype(*([types.voidptr] * nargs)))


_ddot = _extern("cython_blas", "ddot", types.float64, 5)
_dpttrs = _extern("cython_lapack", "dpttrs", types.void, 7)


@njit(**_OPTIONS)
def band_mv(I, sc, alpha, band, x, beta, y):
    n = x.shape[0]
    for i in range(n):           # column_blas.band_mv's numpy sequence, element by element
        o = band[1, i] * x[i]
        if i < n - 1:
            o += band[0, i + 1] * x[i + 1]
        if i > 0:
            o += band[0, i] * x[i - 1]
        o *= alpha
        if beta == 0.0:
            y[i] = o
        else:
            y[i] += o


@njit(**_OPTIONS)
def pt_solve(I, d, e, rhs, nf):
    I[7] = nf
    _dpttrs(I[7:].ctypes, I[4:].ctypes, d.ctypes, e.ctypes, rhs.ctypes, I[7:].ctypes, I[5:].ctypes)


@njit(**_OPTIONS)
def dot(I, x, y):
    return _ddot(I[0:].ctypes, x.ctypes, I[3:].ctypes, y.ctypes, I[3:].ctypes)


@njit(**_OPTIONS)
def accept(u, du, x, nf):
    for i in range(nf):
        u[i] = u[i] + x[i]
        du[i] = x[i]


@njit(**_OPTIONS)
def copy(dst, src, nf):
    for i in range(nf):
        dst[i] = src[i]


@njit(**_OPTIONS)
def difference(dst, a, b, nf):
    for i in range(nf):
        dst[i] = a[i] - b[i]
