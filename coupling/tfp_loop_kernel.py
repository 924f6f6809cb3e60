"""The TFP's staggered step over a range of steps, written once (kernel
module, fpd/kernels.py): the common case of coupling/tfp_loop.py (staggered,
one thermal step per step, plates none / lumped / fe1d, friction laws of
mechanics/friction.py); coupling/tfp_fast.py drives it.

Per step, as the Python loop: mu_i(T_i, p_i, v_i) of the four surfaces ->
tfp_kernel.advance -> each part's plate heated by its share of the surface's
friction work at its footprint centre -> a row every ``every`` steps. The
mechanics is mechanics/tfp_kernel.py, the laws friction_kernel.law_mu, the
plate step and the row bookkeeping coupling/loop_kernel.py's (the DFP loop's
own pieces and ctl layout). Where the Python loop would raise (the
capacity, the fixed point) the step is not taken: the state goes back to
before it and the Python loop replays it.

Plates: tuples (one entry per part, lower plate .. upper plate) of the
arrays of loop_kernel.plate_step, and their kind codes KINDS.
"""
from __future__ import annotations

from fpd.coupling import loop_kernel as lk
from fpd.mechanics import tfp_kernel as tk
from fpd.mechanics.friction_kernel import law_mu

__kernel__ = True


def footprint(par, S, i):
    """Footprint centre on part i (lower plate, lower slider, upper slider,
    upper plate): +s on the lower parts, -s on the upper (TFPStepper.footprints)."""
    if i == 0:
        return par[tk.I_R1] * S[0]
    if i == 1:
        return par[tk.I_R2] * S[1]
    if i == 2:
        return -par[tk.I_R3] * S[1]
    return -par[tk.I_R4] * S[0]


def run_chunk(par, S, S0, A, U, UD, XG, machine, dt, LW, areas, eta, dd, KINDS,
              Mbs, Abs, FACs, Vs, Is, Ps, T, mu, buf, row, ctl, out, M, w, tmp, sc):
    """Steps ctl[C_NDONE] + 1 .. ctl[C_NEND] (ctl and the status as
    loop_kernel.run_chunk); par, S the stepper's constants and state, A its
    ground acceleration per step, U, UD the machine's programme, XG the
    ground displacement per row; LW the four laws, T and mu the loop's
    temperatures and friction coefficients (updated in place); out .. sc the
    stepper's scratch."""
    n0, n_end = ctl[lk.C_NDONE], ctl[lk.C_NEND]
    k, n_rows, every, last_row, N = ctl[lk.C_K], ctl[lk.C_NROWS], ctl[lk.C_EVERY], ctl[lk.C_LAST], ctl[lk.C_N]
    heat = ctl[lk.C_HEAT] != 0
    nr = tk.n_row(par)                   # the stepper's columns come first
    status = lk.DONE
    n = n0
    for n in range(n0 + 1, n_end + 1):
        for i in range(4):
            mu[i] = law_mu(LW[i], T[i], S[tk.S_N + i] / areas[i], S[tk.S_SV + i])
        for i in range(S.shape[0]):
            S0[i] = S[i]
        fail = tk.advance(par, S, dt, A[n - 1], mu[0], mu[1], mu[2], mu[3], machine, U[n], UD[n],
                          out, M, w, tmp, sc)
        if fail != 0:                    # capacity, or the fixed point: Python replays and raises
            for i in range(S.shape[0]):
                S[i] = S0[i]
            status = lk.REPLAY
            break
        if heat:
            for i in range(4):
                T[i] = lk.interface_heat(KINDS[i], Mbs[i], Abs[i], FACs[i], Vs[i], Is[i], Ps[i], eta[i],
                                         S[tk.S_DW + i], dt, footprint(par, S, i), T[i])
        if n % every == 0 or n == N:
            tk.row_values(par, S, n * dt, XG[n], dd[0], dd[1], dd[2], dd[3], row)
            for i in range(4):
                row[nr + i] = mu[i]
            if heat:
                st = 0.0
                lo = 0.0
                for i in range(4):
                    row[nr + 4 + i] = T[i]
                    st += lk.plate_stored(KINDS[i], Vs[i], Is[i], Ps[i])
                    lo += lk.plate_lost(KINDS[i], Ps[i])
                row[nr + 8] = st
                row[nr + 9] = lo
            kept, k, last_row = lk.keep_row(buf, row, k, n_rows, n, last_row)
            if kept != lk.RUNNING:
                status = kept
                break
    lk.end_chunk(ctl, status, n, n_end, k, last_row)
    return status
