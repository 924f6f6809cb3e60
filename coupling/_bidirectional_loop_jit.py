"""The compiled staggered loop for the bidirectional stepper: simulate()'s
fast branch (staggered, one thermal step per step, lumped/fe1d/no plates, a
law of mechanics.friction) as one numba function over a range of steps.

It calls the bidirectional kernel compiled from its one source
(fpd.kernels.compiled("fpd.mechanics.bidirectional_kernel")), the plate
kernels (thermal/_plate_jit.py) and the friction laws
(mechanics/_two_phase_jit.law_mu), in the order of coupling/run.py's loop,
so the rows are those of the Python loop. Where the Python loop would stop
(the rocking flag, a non-finite state, temperature or friction coefficient)
the step is not taken here: the state goes back to before it and the Python
loop replays it. coupling/bidirectional_loop.py drives it.
"""
from __future__ import annotations

import math

from numba import njit

from fpd import kernels
from fpd.mechanics import _two_phase_jit as tp
from fpd.thermal import _plate_jit as pj

BK = kernels.compiled("fpd.mechanics.bidirectional_kernel")
bk_step, bk_values, bk_centres = BK.step, BK.values, BK.centres
N_S, N_VALUES, S_N1, S_N2, S_SV1, S_SV2, S_W1, S_W2 = (BK.N_S, BK.N_VALUES, BK.S_N1, BK.S_N2, BK.S_SV1,
                                                       BK.S_SV2, BK.S_W1, BK.S_W2)

# ctl (int64)
C_NDONE, C_NEND, C_K, C_NROWS, C_EVERY, C_LAST, C_STATUS, C_N, C_HEAT = range(9)
N_CTL = 12
RUNNING, DONE, REPLAY, ROW_FAILED, FULL = 0, 1, 2, 3, 4
# F (float64)
F_AREA, F_ETA1, F_ETA2, F_DT, F_T1, F_T2, F_MU1, F_MU2 = range(8)
N_F = 8


@njit(cache=True, nogil=True, error_model="numpy")
def _finite(S):
    s = 0.0
    for i in range(S.shape[0]):
        s += S[i] * 0.0
    return s == 0.0


@njit(cache=True, nogil=True, error_model="numpy")
def _plate_centre(P, cx, cy):
    """The scalar centre the plate kernel expects for a 2D footprint centre:
    a fixed-point column at (r0, 0) is covered when the 2D distance is at
    most a (fe1d.FE1DPlate.covered): r0 itself then, else a point out of reach."""
    if P[pj.P_KIND] == pj.KIND_FE1D and P[pj.P_FIXED] != 0.0:
        r0, a = P[pj.P_R0], P[pj.P_AC]
        if math.hypot(cx - r0, cy) <= a:
            return r0
        return r0 + 2.0 * a + 1.0
    return 0.0


@njit(cache=True, nogil=True, error_model="numpy")
def run_chunk(MC, MS, MSAVE, AX, AY, XG, YG, LW1, LW2, F, PP,
              K1, W1, I1, X1, K2, W2, I2, X2, buf, row, ctl):
    """Steps ctl[C_NDONE] + 1 .. ctl[C_NEND]; ctl[C_STATUS] as coupling/_loop_jit.run_chunk."""
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
        m1 = tp.law_mu(LW1, T1, MS[S_N1] / area, MS[S_SV1])
        m2 = tp.law_mu(LW2, T2, MS[S_N2] / area, MS[S_SV2])
        if not (math.isfinite(m1) and math.isfinite(m2)):
            status = REPLAY
            break
        for i in range(N_S):
            MSAVE[i] = MS[i]
        flag = bk_step(MC, MS, AX[n - 1], AY[n - 1], dt, m1, m2)
        if flag != 0 or not _finite(MS):
            for i in range(N_S):
                MS[i] = MSAVE[i]
            status = REPLAY
            break
        dW1, dW2 = MS[S_W1] - MSAVE[S_W1], MS[S_W2] - MSAVE[S_W2]
        mu1, mu2 = m1, m2
        if heat:
            c1x, c1y, c2x, c2y = bk_centres(MC, MS)
            q1, q2 = eta1 * dW1 / dt, eta2 * dW2 / dt
            if kind1 != pj.KIND_NONE:
                T1 = pj.plate_step(kind1, K1, W1, I1, X1, P1, q1, _plate_centre(P1, c1x, c1y))
            if kind2 != pj.KIND_NONE:
                T2 = pj.plate_step(kind2, K2, W2, I2, X2, P2, q2, _plate_centre(P2, c2x, c2y))
        if n % every == 0 or n == N:
            bk_values(MC, MS, n * dt, XG[n], YG[n], row)
            j = N_VALUES
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
    """numba keys a cached function on its own file only; run_chunk carries
    compiled copies of the kernels it calls from other files. Hash them all
    and drop this module's caches when the hash changes (as coupling/_loop_jit.py)."""
    import hashlib
    import os

    from fpd.mechanics import bidirectional_kernel
    from fpd.thermal import _column_jit

    h = hashlib.sha256()
    for f in [m.__file__ for m in (_column_jit, pj, tp, bidirectional_kernel)] + [__file__]:
        with open(f, "rb") as fh:
            h.update(fh.read())
    digest = h.hexdigest()
    try:
        stamp = os.path.join(run_chunk._cache.cache_path, "fpd_bidirectional.sha256")
        with open(stamp) as fh:
            if fh.read() == digest:
                return
    except (OSError, AttributeError):
        pass
    try:
        for obj in (_finite, _plate_centre, run_chunk):
            obj._cache.flush()
        with open(stamp, "w") as fh:
            fh.write(digest)
    except (OSError, AttributeError, NameError):
        pass


_refresh_stale_caches()
