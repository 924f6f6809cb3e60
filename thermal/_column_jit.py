"""Optional numba kernel for the fe1d column (issue 7).

Imported only by thermal/fe1d.py, and only when numba is installed and the
environment variable FPD_NO_JIT is not set. The kernel makes the same BLAS
and LAPACK calls as the pure path (dsbmv, dpttrs and ddot of the very
library scipy uses, through scipy.linalg.cython_blas / cython_lapack), in
the same order, with the same scalar arithmetic: the numbers are
bit-for-bit those of the pure path (tests/test_fe1d_jit.py); what it saves
is the Python and f2py overhead around the ~1 us of arithmetic.
A lumped or mechanics-only scene never imports this module (start-up time).

Layout (one float array K of constants, one float array W of state, one
int32 array I), so that a call passes three arrays (numba's dispatch costs
~0.1 us per array argument):

- K: [Mb (2n, Fortran band) | Ab (2n) | df (n) | ef (n) | m1 (n)]
- W: [u (n) | du (n) | rhs (n) | alpha, beta, loss source, m1.u, ...]
- I: [n, k=1, lda=2, inc=1, nrhs=1, info, ord('U')]
"""
from __future__ import annotations

import llvmlite.binding as _ll
from numba import njit, types
from numba.extending import get_cython_function_address


def _extern(module: str, name: str, restype, nargs: int):
    """The scipy BLAS/LAPACK routine as a symbol the compiled code links by
    name (unlike a ctypes pointer, this lets numba cache the kernel)."""
    sym = f"fpd_{name}"
    _ll.add_symbol(sym, get_cython_function_address(f"scipy.linalg.{module}", name))
    return types.ExternalFunction(sym, restype(*([types.voidptr] * nargs)))


_dsbmv = _extern("cython_blas", "dsbmv", types.void, 11)
_ddot = _extern("cython_blas", "ddot", types.float64, 5)
_dpttrs = _extern("cython_lapack", "dpttrs", types.void, 7)

N_SCALARS = 8


@njit(cache=True, nogil=True)
def bdf2_column(K, W, I, c23, g, hcb):
    """One BDF2 step of a column without a Dirichlet node, in place; the
    pure path is ColumnIntegrator._bdf21 (nf == n):

        rhs = -c23 A u + (1/3) M du;  rhs[0] += c23 g;
        du = (M + c23 A)^-1 rhs;  u += du

    g = 3/2 q - 1/2 q_prev. Sets W[3n + 2] = hcb u[n-1] (the loss source)
    and W[3n + 3] = m1 . u; returns u[0]."""
    n = I[0]
    u = W[0:n]
    du = W[n:2 * n]
    rhs = W[2 * n:3 * n]
    sc = W[3 * n:]
    Mb = K[0:2 * n]
    Ab = K[2 * n:4 * n]
    df = K[4 * n:5 * n]
    ef = K[5 * n:6 * n]
    m1 = K[6 * n:7 * n]
    for i in range(n):
        rhs[i] = 0.0
    sc[0] = -c23
    sc[1] = 0.0
    _dsbmv(I[6:].ctypes, I[0:].ctypes, I[1:].ctypes, sc[0:].ctypes, Ab.ctypes, I[2:].ctypes,
           u.ctypes, I[3:].ctypes, sc[1:].ctypes, rhs.ctypes, I[3:].ctypes)
    sc[0] = 1.0 / 3.0
    sc[1] = 1.0
    _dsbmv(I[6:].ctypes, I[0:].ctypes, I[1:].ctypes, sc[0:].ctypes, Mb.ctypes, I[2:].ctypes,
           du.ctypes, I[3:].ctypes, sc[1:].ctypes, rhs.ctypes, I[3:].ctypes)
    rhs[0] += c23 * g
    _dpttrs(I[0:].ctypes, I[4:].ctypes, df.ctypes, ef.ctypes, rhs.ctypes, I[0:].ctypes, I[5:].ctypes)
    for i in range(n):
        u[i] = u[i] + rhs[i]
        du[i] = rhs[i]
    sc[2] = hcb * u[n - 1]
    sc[3] = _ddot(I[0:].ctypes, m1.ctypes, I[3:].ctypes, u.ctypes, I[3:].ctypes)
    return u[0]


def warm_up() -> None:
    """Load (or compile) the kernel now, at build time, rather than inside
    the time loop on its first call: a two-node identity column."""
    import numpy as np
    n = 2
    K = np.zeros(7 * n)
    K[2:4] = (0.0, 1.0)              # Mb diagonal
    K[4 * n:5 * n] = 1.0             # df
    W = np.zeros(3 * n + N_SCALARS)
    bdf2_column(K, W, np.array([n, 1, 2, 1, 1, 0, ord("U")], dtype=np.int32), 0.0, 0.0, 0.0)
