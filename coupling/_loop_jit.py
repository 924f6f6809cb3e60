"""The compiled staggered loop (issue 7): simulate()'s fast branch (staggered,
one thermal step per step, the two-phase stepper, lumped/fe1d/no plates) as
one numba function over a range of steps. coupling/fast_loop.py packs the
models into arrays, calls ``run_chunk`` between its events (progress, VTK
frames, the hottest-field tracker, Ctrl-C) and writes the state back.

Same operations in the same order as the Python loop in coupling/run.py
(the kernels it calls are bit-for-bit translations), so the history is
identical. Where the Python loop could raise (division by zero, an
overturned pad, an overflow in a power, a non-finite temperature or friction
coefficient), the step is not taken here: the state is put back as it was
before it and the Python loop replays it from there, raising exactly what
it raises. A non-finite row is the one failure reported from here.
"""
from __future__ import annotations

import math

from numba import njit

from fpd.mechanics import _two_phase_jit as tp
from fpd.thermal import _plate_jit as pj

# ctl (int64)
C_NDONE, C_NEND, C_K, C_NROWS, C_EVERY, C_LAST, C_STATUS, C_N, C_HEAT = range(9)
N_CTL = 12
# ctl[C_STATUS]
RUNNING, DONE, REPLAY, ROW_FAILED, FULL = 0, 1, 2, 3, 4
# F (float64): coupling constants, then the loop's floats
F_AREA, F_ETA1, F_ETA2, F_DT, F_T1, F_T2, F_MU1, F_MU2 = range(8)
N_F = 8


@njit(cache=True, nogil=True, error_model="numpy")
def _mech_ok(C, S):
    """The state after a step is one the Python loop would also have reached
    and can print: no error flag, every value finite, and values() cannot
    overflow (theta'^2 and beta'^2 are Python powers, which raise) nor divide
    by zero (the tipping ratio)."""
    if S[tp.ERR] != 0.0:
        return False
    s = 0.0
    for i in range(tp.N_STATE):
        s += S[i] * 0.0
    if s != 0.0:                        # NaN for any non-finite value
        return False
    if abs(S[tp.THD]) > 1e150 or abs(S[tp.BETAD]) > 1e150:
        return False
    if S[tp.N2] > 0.0 and S[tp.N2] * 2.0 * C[tp.CGA] == 0.0:
        return False
    return True


@njit(cache=True, nogil=True, error_model="numpy")
def run_chunk(MC, MS, MSAVE, G, LW1, LW2, F, PP,
              K1, W1, I1, X1, K2, W2, I2, X2, buf, row, ctl):
    """Steps ctl[C_NDONE] + 1 .. ctl[C_NEND]; ctl[C_STATUS] says how it ended
    (DONE; REPLAY: step ctl[C_NDONE] + 1 is for the Python loop, the state is
    as before it; ROW_FAILED: that step's row, in ``row``, is not finite;
    FULL: buf has no room left after step ctl[C_NDONE]: the caller empties it)."""
    n0, n_end = ctl[C_NDONE], ctl[C_NEND]
    k, n_rows, every, last_row, N = ctl[C_K], ctl[C_NROWS], ctl[C_EVERY], ctl[C_LAST], ctl[C_N]
    heat = ctl[C_HEAT] != 0
    area, eta1, eta2, dt = F[F_AREA], F[F_ETA1], F[F_ETA2], F[F_DT]
    T1, T2 = F[F_T1], F[F_T2]
    mu1, mu2 = F[F_MU1], F[F_MU2]
    P1, P2 = PP[0], PP[1]
    kind1, kind2 = int(P1[pj.P_KIND]), int(P2[pj.P_KIND])
    ncol = row.shape[0]
    status = DONE
    n = n0
    for n in range(n0 + 1, n_end + 1):
        if not (math.isfinite(T1) and math.isfinite(T2)):
            status = REPLAY
            break
        m1 = tp.law_mu(LW1, T1, MS[tp.N1] / area, MS[tp.SV1])
        m2 = tp.law_mu(LW2, T2, MS[tp.N2] / area, MS[tp.SV2])
        if not (math.isfinite(m1) and math.isfinite(m2)):
            status = REPLAY
            break
        for i in range(tp.N_STATE):
            MSAVE[i] = MS[i]
        dW1, dW2 = tp.step(MC, MS, G, m1, m2)
        if not _mech_ok(MC, MS):
            for i in range(tp.N_STATE):
                MS[i] = MSAVE[i]
            status = REPLAY
            break
        mu1, mu2 = m1, m2
        if heat:
            th = MS[tp.TH]
            c1, c2 = MC[tp.CR1] * th, -(MC[tp.CR2] * th)
            q1, q2 = eta1 * dW1 / dt, eta2 * dW2 / dt
            if kind1 != pj.KIND_NONE:
                T1 = pj.plate_step(kind1, K1, W1, I1, X1, P1, q1, c1)
            if kind2 != pj.KIND_NONE:
                T2 = pj.plate_step(kind2, K2, W2, I2, X2, P2, q2, c2)
        if n % every == 0 or n == N:
            tp.values(MC, MS, G, row)
            j = tp.N_VALUES
            row[j] = mu1
            row[j + 1] = mu2
            if heat:
                row[j + 2] = T1
                row[j + 3] = T2
                row[j + 4] = pj.plate_stored(kind1, K1, W1, I1, P1) + pj.plate_stored(kind2, K2, W2, I2, P2)
                row[j + 5] = pj.plate_lost(kind1, P1) + pj.plate_lost(kind2, P2)
            s = 0.0
            for i in range(ncol):
                s += row[i]
            if not math.isfinite(s):
                status = ROW_FAILED
                break
            if k < n_rows:
                for i in range(ncol):
                    buf[k, i] = row[i]
                k += 1
                last_row = n
                if k == n_rows:
                    status = FULL
                    break
    if status == DONE:
        ctl[C_NDONE] = n_end
    elif status == FULL:
        ctl[C_NDONE] = n
    else:
        ctl[C_NDONE] = n - 1
    ctl[C_K], ctl[C_LAST], ctl[C_STATUS] = k, last_row, status
    F[F_T1], F[F_T2], F[F_MU1], F[F_MU2] = T1, T2, mu1, mu2
    return status


def _refresh_stale_caches() -> None:
    """numba keys a cached function on the source of its own file only, yet
    run_chunk and the plate kernels carry compiled copies of the kernels they
    call from other files: after an edit there, they would run the old code.
    So the kernel files are hashed together, and when the hash changes the
    caches of the callers are dropped (compiled afresh on first use)."""
    import hashlib
    import os

    from fpd.thermal import _column_jit

    files = [m.__file__ for m in (_column_jit, pj, tp)] + [__file__]
    h = hashlib.sha256()
    for f in files:
        with open(f, "rb") as fh:
            h.update(fh.read())
    digest = h.hexdigest()
    try:
        stamp = os.path.join(run_chunk._cache.cache_path, "fpd_kernels.sha256")
        with open(stamp) as fh:
            if fh.read() == digest:
                return
    except (OSError, AttributeError):
        pass
    try:
        for obj in vars(pj).values():    # (tp calls nothing from another file: its caches stand)
            if hasattr(obj, "_cache") and hasattr(obj, "py_func") and obj.py_func.__module__ == pj.__name__:
                obj._cache.flush()
        for obj in (_mech_ok, run_chunk):
            obj._cache.flush()
        with open(stamp, "w") as fh:
            fh.write(digest)
    except (OSError, AttributeError, NameError):
        pass        # an unwritable cache: numba compiles in memory anyway


_refresh_stale_caches()
