"""The staggered thermo-mechanical step over a range of steps, written once
(kernel module, fpd/kernels.py): simulate()'s common case (staggered, one
thermal step per step, the two-phase stepper, lumped / fe1d / no plates).

Per step (model.md section 5): mu_i(T_i^n, p_i, v_i) -> two-phase step ->
friction work of each interface and footprint position -> plate steps ->
T_i^{n+1}; a row of the history every ``every`` steps. Every piece of
physics it calls is the models' own kernel (friction_kernel,
two_phase_kernel, lumped_kernel, column_kernel), so the compiled run and the
Python loop in coupling/run.py compute the same numbers; coupling/fast_loop.py
drives it between simulate()'s events. The per-interface pieces below
(interface_heat, plate_step/stored/lost, two_plate_row, keep_row, end_chunk)
and the ctl / F layout are also the bidirectional and TFP loops' own
(coupling/bidirectional_loop_kernel.py, coupling/tfp_loop_kernel.py).

Where the Python loop would raise (division by zero, an overturned pad, an
overflow in a power, a non-finite temperature or friction coefficient), the
step is not taken: the state is put back as it was before it and the Python
loop replays it from there, raising exactly what it raises. A non-finite row
is the one failure reported from here.
"""
from __future__ import annotations

import math

from fpd.mechanics import two_phase_kernel as tp
from fpd.mechanics.friction_kernel import law_mu
from fpd.thermal import column_kernel as ck
from fpd.thermal import lumped_kernel as lk

__kernel__ = True
# compiled: the plate dispatchers inline into run_chunk (no call passing the plates' arrays per step)
__jit_options__ = {"inline": "always"}

KIND_NONE, KIND_LUMPED, KIND_FE1D = 0, 1, 2
# ctl (int64)
C_NDONE, C_NEND, C_K, C_NROWS, C_EVERY, C_LAST, C_STATUS, C_N, C_HEAT, C_KIND1, C_KIND2 = range(11)
N_CTL = 12
# ctl[C_STATUS]
RUNNING, DONE, REPLAY, ROW_FAILED, FULL = 0, 1, 2, 3, 4
# F (float64): coupling constants, then the loop's floats
F_AREA, F_ETA1, F_ETA2, F_DT, F_T1, F_T2, F_MU1, F_MU2 = range(8)
N_F = 8


def mech_ok(C, S):
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


def plate_step(kind, Mb, Ab, FAC, V, I, P, power_W, centre_m):
    if kind == KIND_FE1D:
        return ck.plate_step(Mb, Ab, FAC, V, I, P, power_W, centre_m)
    return lk.step(P, power_W)


def plate_stored(kind, V, I, P):
    if kind == KIND_FE1D:
        return ck.stored(V, I, P)
    if kind == KIND_LUMPED:
        return lk.stored(P)
    return 0.0


def plate_lost(kind, P):
    if kind == KIND_FE1D:
        return P[ck.P_HLOST]
    if kind == KIND_LUMPED:
        return P[lk.P_LOST]
    return 0.0


# -- the pieces of a staggered step every compiled loop shares (this DFP loop, the
# -- bidirectional one, coupling/bidirectional_loop_kernel.py, and the TFP's,
# -- coupling/tfp_loop_kernel.py)

def plate_centre_2d(kind, P, cx, cy):
    """The centre plate_step takes for a 2D footprint centre (cx, cy)
    (bidirectional runs; the fe1d column's own rule, column_kernel.centre_2d)."""
    if kind == KIND_FE1D:
        return ck.centre_2d(P, cx, cy)
    return 0.0


def interface_heat(kind, Mb, Ab, FAC, V, I, P, eta, dW, dt, centre_m, T):
    """The temperature of an interface's plate after the step: the share eta
    of the friction work dW over the step (eta dW / dt, W) into the plate at
    the footprint centre_m; T unchanged without a plate."""
    q = eta * dW / dt
    if kind == KIND_NONE:
        return T
    return plate_step(kind, Mb, Ab, FAC, V, I, P, q, centre_m)


def two_plate_row(row, j, heat, mu1, mu2, T1, T2, kind1, V1, I1, P1, kind2, V2, I2, P2):
    """The loop's columns after the stepper's j values: mu1, mu2 and, with
    plates, T1_C, T2_C, E_stored_J, E_air_J."""
    row[j] = mu1
    row[j + 1] = mu2
    if heat:
        row[j + 2] = T1
        row[j + 3] = T2
        row[j + 4] = plate_stored(kind1, V1, I1, P1) + plate_stored(kind2, V2, I2, P2)
        row[j + 5] = plate_lost(kind1, P1) + plate_lost(kind2, P2)


def keep_row(buf, row, k, n_rows, n, last_row):
    """Step n's row into buf[k] -> (status, k, last_row): ROW_FAILED (row not
    finite, nothing kept), FULL (buf has no room left after it) or RUNNING.
    A row finds no room only after FULL was ignored: it is not kept then."""
    ncol = row.shape[0]
    s = 0.0
    for i in range(ncol):
        s += row[i]
    if not math.isfinite(s):
        return ROW_FAILED, k, last_row
    if k < n_rows:
        for i in range(ncol):
            buf[k, i] = row[i]
        k += 1
        last_row = n
        if k == n_rows:
            return FULL, k, last_row
    return RUNNING, k, last_row


def end_chunk(ctl, status, n, n_end, k, last_row):
    """The counters after a chunk that ended with status at step n: the
    steps done (n_end when DONE, n when FULL, else n - 1: step n is the
    Python loop's or failed), rows kept, the last row's step, the status."""
    if status == DONE:
        ctl[C_NDONE] = n_end
    elif status == FULL:
        ctl[C_NDONE] = n
    else:
        ctl[C_NDONE] = n - 1
    ctl[C_K], ctl[C_LAST], ctl[C_STATUS] = k, last_row, status


def run_chunk(MC, MS, MSAVE, A, T, D, LW1, LW2, F,
              Mb1, Ab1, FAC1, V1, I1, P1, Mb2, Ab2, FAC2, V2, I2, P2, buf, row, ctl):
    """Steps ctl[C_NDONE] + 1 .. ctl[C_NEND]; ctl[C_STATUS] says how it ended
    (DONE; REPLAY: step ctl[C_NDONE] + 1 is for the Python loop, the state is
    as before it; ROW_FAILED: that step's row, in ``row``, is not finite;
    FULL: buf has no room left after step ctl[C_NDONE]: the caller empties it).
    MC, MS: the stepper's constants and state, A, T, D its loading (a_step,
    t, d); LW1, LW2 the friction laws; per plate the column arrays (fe1d) and
    its row P (fe1d or lumped)."""
    n0, n_end = ctl[C_NDONE], ctl[C_NEND]
    k, n_rows, every, last_row, N = ctl[C_K], ctl[C_NROWS], ctl[C_EVERY], ctl[C_LAST], ctl[C_N]
    heat = ctl[C_HEAT] != 0
    kind1, kind2 = ctl[C_KIND1], ctl[C_KIND2]
    area, eta1, eta2, dt = F[F_AREA], F[F_ETA1], F[F_ETA2], F[F_DT]
    T1, T2 = F[F_T1], F[F_T2]
    mu1, mu2 = F[F_MU1], F[F_MU2]
    status = DONE
    n = n0
    for n in range(n0 + 1, n_end + 1):
        if not (math.isfinite(T1) and math.isfinite(T2)):
            status = REPLAY
            break
        m1 = law_mu(LW1, T1, MS[tp.N1] / area, MS[tp.SV1])
        m2 = law_mu(LW2, T2, MS[tp.N2] / area, MS[tp.SV2])
        if not (math.isfinite(m1) and math.isfinite(m2)):
            status = REPLAY
            break
        for i in range(tp.N_STATE):
            MSAVE[i] = MS[i]
        dW1, dW2 = tp.step(MC, MS, A, m1, m2)
        if not mech_ok(MC, MS):
            for i in range(tp.N_STATE):
                MS[i] = MSAVE[i]
            status = REPLAY
            break
        mu1, mu2 = m1, m2
        if heat:
            th = MS[tp.TH]
            c1, c2 = MC[tp.CR1] * th, -(MC[tp.CR2] * th)      # footprint centres (mech.s1, -mech.s2)
            T1 = interface_heat(kind1, Mb1, Ab1, FAC1, V1, I1, P1, eta1, dW1, dt, c1, T1)
            T2 = interface_heat(kind2, Mb2, Ab2, FAC2, V2, I2, P2, eta2, dW2, dt, c2, T2)
        if n % every == 0 or n == N:
            tp.values(MC, MS, T, D, row)
            two_plate_row(row, tp.N_VALUES, heat, mu1, mu2, T1, T2, kind1, V1, I1, P1, kind2, V2, I2, P2)
            kept, k, last_row = keep_row(buf, row, k, n_rows, n, last_row)
            if kept != RUNNING:
                status = kept
                break
    end_chunk(ctl, status, n, n_end, k, last_row)
    F[F_T1], F[F_T2], F[F_MU1], F[F_MU2] = T1, T2, mu1, mu2
    return status
