"""numba plate steps for the compiled coupling loop (coupling/_loop_jit.py):
the lumped plate (thermal/lumped.py) and the whole fe1d column step with
its start-up (thermal/fe1d.py, ColumnIntegrator.step_surface on the kernel
path: BDF2 without a Dirichlet node, Rannacher start-up after t = 0 and
after every load jump). Same operations in the same order as the Python
classes, and the same BLAS/LAPACK routines (thermal/_column_jit.py), so the
numbers are identical bit for bit.

Each plate's scalars live in one float64 row P (layout below) that
coupling/fast_loop.py fills from the Python object and writes back; the fe1d
arrays are the integrator's own (K, W, I: u and du stay views of W), plus X:
[BE factor d (n) | BE factor e (n) | u before a start-up step (n) | a copy of W
(3n + N_SCALARS), the state before the step in progress].
"""
from __future__ import annotations

from numba import njit

from fpd.thermal._column_jit import N_SCALARS, _dpttrs, _dsbmv, _ddot, bdf2_column

KIND_NONE, KIND_LUMPED, KIND_FE1D = 0, 1, 2

# -- P: one row per plate ------------------------------------------------------------
P_KIND, P_FIXED, P_R0, P_AC, P_TAIR = 0, 1, 2, 3, 4
# fe1d (ColumnIntegrator attributes)
P_C23, P_C23V, P_Q, P_LS, P_JR, P_SL, P_STEPS, P_LP = 5, 6, 7, 8, 9, 10, 11, 12
P_HIN, P_HLOST, P_HALF, P_SOK, P_H, P_CB, P_M, P_E0 = 13, 14, 15, 16, 17, 18, 19, 20
# lumped (LumpedPlate attributes)
P_LH, P_LT0, P_RISE, P_LIN, P_LLOST, P_DECAY, P_LC, P_LDT = 21, 22, 23, 24, 25, 26, 27, 28
P_START = 29                # thermal.stepping.START_STEPS["bdf2"] (at run time, as all settings)
N_P = 32


@njit(cache=True, nogil=True, error_model="numpy")
def lumped_step(P, power_W):
    """LumpedPlate.step."""
    if P[P_LH] > 0.0:
        rise_eq = P[P_TAIR] - P[P_LT0] + power_W / P[P_LH]
        dT = (rise_eq - P[P_RISE]) * P[P_DECAY]
    else:
        dT = power_W * P[P_LDT] / P[P_LC]
    q = power_W * P[P_LDT]
    P[P_LIN] += q
    P[P_LLOST] += q - P[P_LC] * dT
    P[P_RISE] += dT
    return P[P_LT0] + P[P_RISE]


@njit(cache=True, nogil=True, error_model="numpy")
def _be1(K, W, I, X, P, h, q):
    """ColumnIntegrator._be1 with nf == n: one backward-Euler substep."""
    n = I[0]
    u = W[0:n]
    du = W[n:2 * n]
    rhs = W[2 * n:3 * n]
    sc = W[3 * n:]
    Ab = K[2 * n:4 * n]
    for i in range(n):
        rhs[i] = 0.0
    sc[0] = -h
    sc[1] = 0.0
    _dsbmv(I[6:].ctypes, I[0:].ctypes, I[1:].ctypes, sc[0:].ctypes, Ab.ctypes, I[2:].ctypes,
           u.ctypes, I[3:].ctypes, sc[1:].ctypes, rhs.ctypes, I[3:].ctypes)
    rhs[0] += h * q
    _dpttrs(I[0:].ctypes, I[4:].ctypes, X[0:n].ctypes, X[n:2 * n].ctypes, rhs.ctypes,
            I[0:].ctypes, I[5:].ctypes)
    for i in range(n):
        u[i] += rhs[i]
        du[i] = rhs[i]
    s = h * P[P_CB] * u[n - 1]
    P[P_HIN] += h * q
    P[P_HLOST] += s
    return s


@njit(cache=True, nogil=True, error_model="numpy")
def _jump(P, q):
    """ColumnIntegrator._jump."""
    if abs(q) > P[P_LS]:
        P[P_LS] = abs(q)
    return abs(q - P[P_Q]) > P[P_JR] * P[P_LS]


@njit(cache=True, nogil=True, error_model="numpy")
def _bdf2(K, W, I, P, q):
    h = P[P_H]
    n = I[0]
    bdf2_column(K, W, I, P[P_C23], 1.5 * q - 0.5 * P[P_Q], h * P[P_CB])
    P[P_SOK] = 1.0
    loss = (2.0 / 3.0) * (W[3 * n + 2] + 0.5 * P[P_LP])
    P[P_LP] = loss
    P[P_HIN] += h * q
    P[P_HLOST] += loss


@njit(cache=True, nogil=True, error_model="numpy")
def fe1d_step(K, W, I, X, P, power_W, centre_m):
    """FE1DPlate.step (kernel path, bdf2, nf == n, rannacher): returns the
    surface temperature (degC)."""
    if P[P_FIXED] != 0.0 and not abs(centre_m - P[P_R0]) <= P[P_AC]:
        power_W = 0.0
    q = power_W
    n = I[0]
    if P[P_C23] != 0.0 and P[P_SL] <= 0.0 and P[P_STEPS] > 0.0:
        # ColumnIntegrator.step_surface's inlined BDF2 step
        aq = abs(q)
        if aq > P[P_LS]:
            P[P_LS] = aq
        if not abs(q - P[P_Q]) > P[P_JR] * P[P_LS]:
            _bdf2(K, W, I, P, q)
            P[P_Q] = q
            P[P_STEPS] += 1.0
            return W[0] + P[P_TAIR]
    h = P[P_H]
    P[P_SOK] = 0.0
    if P[P_SL] > 0.0 or P[P_STEPS] == 0.0 or _jump(P, q):
        if P[P_STEPS] == 0.0 or _jump(P, q):
            P[P_SL] = P[P_START]
        P[P_SL] -= 1.0
        ub = X[2 * n:3 * n]
        for i in range(n):
            ub[i] = W[i]
        m = int(P[P_M])
        hs = h / m
        loss = 0.0
        for _ in range(m):
            loss += _be1(K, W, I, X, P, hs, q)
        for i in range(n):
            W[n + i] = W[i] - ub[i]
        P[P_LP] = loss
        P[P_HALF] += m
    else:
        if P[P_C23] == 0.0:              # ColumnIntegrator._bdf2_setup (factor precomputed in K)
            P[P_C23] = P[P_C23V]
        _bdf2(K, W, I, P, q)
    P[P_Q] = q
    P[P_STEPS] += 1.0
    return W[0] + P[P_TAIR]


@njit(cache=True, nogil=True, error_model="numpy")
def fe1d_stored(K, W, I, P):
    """ColumnIntegrator.stored()."""
    n = I[0]
    if P[P_SOK] != 0.0:
        return W[3 * n + 3] - P[P_E0]
    return _ddot(I[0:].ctypes, K[6 * n:].ctypes, I[3:].ctypes, W.ctypes, I[3:].ctypes) - P[P_E0]


@njit(cache=True, nogil=True, error_model="numpy")
def plate_step(kind, K, W, I, X, P, power_W, centre_m):
    if kind == KIND_FE1D:
        return fe1d_step(K, W, I, X, P, power_W, centre_m)
    return lumped_step(P, power_W)


@njit(cache=True, nogil=True, error_model="numpy")
def plate_stored(kind, K, W, I, P):
    if kind == KIND_FE1D:
        return fe1d_stored(K, W, I, P)
    if kind == KIND_LUMPED:
        return P[P_LC] * P[P_RISE]
    return 0.0


@njit(cache=True, nogil=True, error_model="numpy")
def plate_lost(kind, P):
    if kind == KIND_FE1D:
        return P[P_HLOST]
    if kind == KIND_LUMPED:
        return P[P_LLOST]
    return 0.0


@njit(cache=True, nogil=True, error_model="numpy")
def plate_save(kind, W, X, P, Psave):
    """Copy the plate's state (P, and W for fe1d) aside (X's last block)."""
    for i in range(N_P):
        Psave[i] = P[i]
    if kind == KIND_FE1D:
        o = 3 * ((W.shape[0] - N_SCALARS) // 3)
        for i in range(W.shape[0]):
            X[o + i] = W[i]


@njit(cache=True, nogil=True, error_model="numpy")
def plate_restore(kind, W, X, P, Psave):
    for i in range(N_P):
        P[i] = Psave[i]
    if kind == KIND_FE1D:
        o = 3 * ((W.shape[0] - N_SCALARS) // 3)
        for i in range(W.shape[0]):
            W[i] = X[o + i]
