"""The staggered step of the bidirectional stepper over a range of steps,
written once (kernel module, fpd/kernels.py): simulate()'s fast branch for
it (staggered, one thermal step per step, lumped / fe1d / no plates, a law
of mechanics.friction); coupling/bidirectional_loop.py drives it.

It is coupling/loop_kernel.run_chunk with the bidirectional kernel
(mechanics/bidirectional_kernel.py) as the stepper and 2D footprint centres
(loop_kernel.plate_centre_2d); every other piece is loop_kernel's (the
friction laws, the plates, the row and its bookkeeping, the ctl and F
layouts), so the rows are those of coupling/run.py's Python loop. Where the
Python loop would stop (the stepper's flag, a non-finite state, temperature
or friction coefficient) the step is not taken: the state goes back to
before it and the Python loop replays it.
"""
from __future__ import annotations

import math

from fpd.coupling import loop_kernel as lk
from fpd.mechanics import bidirectional_kernel as bk
from fpd.mechanics.friction_kernel import law_mu

__kernel__ = True


def state_ok(S):
    """Every value of the state finite."""
    s = 0.0
    for i in range(S.shape[0]):
        s += S[i] * 0.0
    return s == 0.0


def run_chunk(MC, MS, MSAVE, AX, AY, XG, YG, LW1, LW2, F,
              Mb1, Ab1, FAC1, V1, I1, P1, Mb2, Ab2, FAC2, V2, I2, P2, buf, row, ctl):
    """Steps ctl[C_NDONE] + 1 .. ctl[C_NEND] (ctl, F and the status as
    loop_kernel.run_chunk); MC, MS the stepper's constants and state, AX, AY
    its accelerations per step, XG, YG the ground displacement per row."""
    n0, n_end = ctl[lk.C_NDONE], ctl[lk.C_NEND]
    k, n_rows, every, last_row, N = ctl[lk.C_K], ctl[lk.C_NROWS], ctl[lk.C_EVERY], ctl[lk.C_LAST], ctl[lk.C_N]
    heat = ctl[lk.C_HEAT] != 0
    kind1, kind2 = ctl[lk.C_KIND1], ctl[lk.C_KIND2]
    area, eta1, eta2, dt = F[lk.F_AREA], F[lk.F_ETA1], F[lk.F_ETA2], F[lk.F_DT]
    T1, T2 = F[lk.F_T1], F[lk.F_T2]
    mu1, mu2 = F[lk.F_MU1], F[lk.F_MU2]
    status = lk.DONE
    n = n0
    for n in range(n0 + 1, n_end + 1):
        if not (math.isfinite(T1) and math.isfinite(T2)):
            status = lk.REPLAY
            break
        m1 = law_mu(LW1, T1, MS[bk.S_N1] / area, MS[bk.S_SV1])
        m2 = law_mu(LW2, T2, MS[bk.S_N2] / area, MS[bk.S_SV2])
        if not (math.isfinite(m1) and math.isfinite(m2)):
            status = lk.REPLAY
            break
        for i in range(bk.N_S):
            MSAVE[i] = MS[i]
        flag = bk.step(MC, MS, AX[n - 1], AY[n - 1], dt, m1, m2)
        if flag != 0 or not state_ok(MS):
            for i in range(bk.N_S):
                MS[i] = MSAVE[i]
            status = lk.REPLAY
            break
        dW1, dW2 = MS[bk.S_W1] - MSAVE[bk.S_W1], MS[bk.S_W2] - MSAVE[bk.S_W2]
        mu1, mu2 = m1, m2
        if heat:
            c1x, c1y, c2x, c2y = bk.centres(MC, MS)
            T1 = lk.interface_heat(kind1, Mb1, Ab1, FAC1, V1, I1, P1, eta1, dW1, dt,
                                   lk.plate_centre_2d(kind1, P1, c1x, c1y), T1)
            T2 = lk.interface_heat(kind2, Mb2, Ab2, FAC2, V2, I2, P2, eta2, dW2, dt,
                                   lk.plate_centre_2d(kind2, P2, c2x, c2y), T2)
        if n % every == 0 or n == N:
            bk.values(MC, MS, n * dt, XG[n], YG[n], row)
            lk.two_plate_row(row, bk.N_VALUES, heat, mu1, mu2, T1, T2, kind1, V1, I1, P1, kind2, V2, I2, P2)
            kept, k, last_row = lk.keep_row(buf, row, k, n_rows, n, last_row)
            if kept != lk.RUNNING:
                status = kept
                break
    lk.end_chunk(ctl, status, n, n_end, k, last_row)
    F[lk.F_T1], F[lk.F_T2], F[lk.F_MU1], F[lk.F_MU2] = T1, T2, mu1, mu2
    return status
