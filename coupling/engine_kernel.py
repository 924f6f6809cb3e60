"""The coupled engine: the staggered thermo-mechanical step over a range of
steps, for every device, written once (kernel module, fpd/kernels.py).

Per step (model.md section 5), over the device's N interfaces (SFP/DFP/flat
2, TFP 4): mu_i(T_i^n, p_i, v_i) -> the device's step -> the friction work
of each interface and its footprint centre -> each plate's step ->
T_i^{n+1}; a row of the history every ``every`` steps. The device is the
module ``dev`` (the interface in mechanics/dev_two_phase.py): the source
below names the planar two-phase DFP, and ``fpd.kernels.compiled(...,
bind={"dev": ...})`` loads this same file once per device with ``dev`` bound
to that device's module (each compiled and cached on its own, only when a
scene uses it). Every piece of physics is the models' own kernel
(friction_kernel, the device's, lumped_kernel, column_kernel), so the
compiled run and the Python loop (coupling/run.py) compute the same numbers;
coupling/fast_loop.py drives it between simulate()'s events.

Where the Python loop would raise (a device flag, a non-finite temperature,
friction coefficient or state), the step is not taken: the state is put back
as it was before it and the Python loop replays it from there, raising
exactly what it raises. A non-finite row is the one failure reported from
here.
"""
from __future__ import annotations

import math

from fpd.mechanics import dev_two_phase as dev     # rebound per device (fpd.kernels.compiled(bind=))
from fpd.tribology.friction_kernel import law_mu, wear_step
from fpd.thermal import column_kernel as ck
from fpd.thermal import lumped_kernel as lk

__kernel__ = True
# compiled: the plate dispatchers inline into run_chunk (no call passing the plates' arrays per step)
__jit_options__ = {"inline": "always"}

KIND_NONE, KIND_LUMPED, KIND_FE1D = 0, 1, 2
# ctl (int64)
C_NDONE, C_NEND, C_K, C_NROWS, C_EVERY, C_LAST, C_STATUS, C_N, C_HEAT, C_NVAL, C_2D, C_TRACK, C_HOT = range(13)
C_WEAR = 13             # 1: the wear columns (path_i, then wear_i) end the row
N_CTL = 14
# ctl[C_STATUS]
RUNNING, DONE, REPLAY, ROW_FAILED, FULL, LOOK = 0, 1, 2, 3, 4, 5


# The plates' arrays come as tuples over the interfaces (Mbs .. Ps). Taking
# an array out of a tuple at a run-time index, or handing a tuple on,
# counts references to its arrays (atomic operations, the engine's most
# frequent ones): each step takes out only the arrays its plate's kind
# reads, and no tuple of plates is handed to a function.
def fe1d_centre(P, cx, cy, two_d):
    """The centre the fe1d column's step takes for a footprint centre (cx,
    cy): cx on a 1D path (planar runs), else the column's own rule for a 2D
    centre (column_kernel.centre_2d)."""
    if two_d == 0:
        return cx
    return ck.centre_2d(P, cx, cy)


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


def hotter(T, hot):
    """Is some interface's temperature T[i] above hot[i], its highest at the
    earlier looks at the plate fields? (hot[i] raised to it.) A look at the
    fields (outputs/hottest.py) is taken only then: with lumped and fe1d
    plates, heated at the sliding face, no field is hotter than the face
    has been (the maximum principle), so a look while every face is cooler
    than at an earlier look cannot find a hotter field."""
    up = False
    for i in range(len(T)):
        if T[i] > hot[i]:
            hot[i] = T[i]
            up = True
    return up


def end_chunk(ctl, status, n, n_end, k, last_row):
    """The counters after a chunk that ended with status at step n: the
    steps done (n_end when DONE, n when FULL or LOOK, else n - 1: step n is
    the Python loop's or failed), rows kept, the last row's step, the status."""
    if status == DONE:
        ctl[C_NDONE] = n_end
    elif status == FULL or status == LOOK:
        ctl[C_NDONE] = n
    else:
        ctl[C_NDONE] = n - 1
    ctl[C_K], ctl[C_LAST], ctl[C_STATUS] = k, last_row, status


def track_row(row, n_track, SX, SN, LI, SL):
    """Every step's extremes of the row's first n_track values (the stepper's,
    mu_i, T_i) into SX, SN, and the energy ledger's worst residual and input
    into SL (LI: the input's column, then every term it goes into; empty
    without a ledger): the summary reads every step, not only the rows kept."""
    for j in range(n_track):
        x = row[j]
        if x > SX[j]:
            SX[j] = x
        if x < SN[j]:
            SN[j] = x
    if LI.shape[0] > 0:
        s = 0.0
        for k in range(1, LI.shape[0]):
            s += row[LI[k]]
        r = abs(row[LI[0]] - s)
        if r > SL[0]:
            SL[0] = r
        e = abs(row[LI[0]])
        if e > SL[1]:
            SL[1] = e


def run_chunk(C, S, S0, L, X, dt, LW, areas, eta, kinds, Mbs, Abs, FACs, Vs, Is, Ps, T, hot, mu, mun, dW,
              buf, row, ctl, SX, SN, LI, SL, WL, PW):
    """Steps ctl[C_NDONE] + 1 .. ctl[C_NEND]; ctl[C_STATUS] says how it ended
    (DONE; REPLAY: step ctl[C_NDONE] + 1 is for the Python loop, the state is
    as before it; ROW_FAILED: that step's row, in ``row``, is not finite;
    FULL: buf has no room left after step ctl[C_NDONE]: the caller empties it;
    LOOK: the caller looks at the plate fields after step ctl[C_NDONE], a
    multiple of ctl[C_HOT] (0: no looks) where ``hotter(T, hot)``).

    C, S: the device's constants and state (S0: room for a copy), L, X its
    loading and scratch (tuples of arrays); per interface i: LW[i] its
    friction law (friction_kernel.law_mu's row), areas[i] the contact area
    (m^2), eta[i] the plate's heat share, kinds[i] the plate kind and its
    arrays (Mbs[i] .. Ps[i]: the fe1d column, or the lumped row Ps[i]), T[i],
    mu[i] the loop's temperature and friction coefficient (updated in place);
    mun, dW: room for N floats. The row: the device's ctl[C_NVAL] values,
    then mu_i, and with plates T_i, E_stored_J, E_air_J. With ctl[C_TRACK]
    (rows kept less often than every step) every step's row goes through
    track_row (SX, SN, LI, SL). With ctl[C_WEAR]: WL[i] the wear coefficient's
    row, PW the paths then the depths (friction_kernel.wear_step, at the
    temperature the step's mu was evaluated at), the row's last 2 N values."""
    n0, n_end = ctl[C_NDONE], ctl[C_NEND]
    k, n_rows, every, last_row, N = ctl[C_K], ctl[C_NROWS], ctl[C_EVERY], ctl[C_LAST], ctl[C_N]
    heat = ctl[C_HEAT] != 0
    wear = ctl[C_WEAR] != 0
    nv, two_d, track = ctl[C_NVAL], ctl[C_2D], ctl[C_TRACK] != 0
    hot_every = ctl[C_HOT]
    ni = T.shape[0]
    n_track = nv + ni
    if heat:
        n_track += ni
    status = DONE
    n = n0
    for n in range(n0 + 1, n_end + 1):
        bad = False
        for i in range(ni):
            if not math.isfinite(T[i]):
                bad = True
                break
            m = law_mu(LW[i], T[i], dev.normal(C, S, i) / areas[i], dev.slip(C, S, i))
            if not math.isfinite(m):
                bad = True
                break
            mun[i] = m
        if bad:
            status = REPLAY
            break
        for j in range(S.shape[0]):
            S0[j] = S[j]
        flag = dev.step(C, S, L, X, n, dt, mun, dW)
        if flag != 0 or not dev.ok(C, S):
            for j in range(S.shape[0]):
                S[j] = S0[j]
            status = REPLAY
            break
        for i in range(ni):
            mu[i] = mun[i]
        if wear:
            for i in range(ni):
                wear_step(WL[i], T[i], dW[i], mu[i], dev.normal(C, S, i), areas[i], PW, i, ni)
        if heat:
            # each plate takes the share eta_i of its interface's friction work over the
            # step (eta_i dW_i / dt, W) at the footprint centre; T_i stays without a plate
            for i in range(ni):
                kind = kinds[i]
                if kind == KIND_FE1D:
                    cx, cy = dev.centre(C, S, i)
                    P = Ps[i]
                    T[i] = ck.plate_step(Mbs[i], Abs[i], FACs[i], Vs[i], Is[i], P, eta[i] * dW[i] / dt,
                                         fe1d_centre(P, cx, cy, two_d))
                elif kind == KIND_LUMPED:
                    T[i] = lk.step(Ps[i], eta[i] * dW[i] / dt)
        kept_step = n % every == 0 or n == N
        if track or kept_step:
            dev.values(C, S, L, n, dt, row)
            for i in range(ni):
                row[nv + i] = mu[i]
            if heat:
                for i in range(ni):
                    row[nv + ni + i] = T[i]
            if wear:
                nw = nv + ni
                if heat:
                    nw += ni + 2
                for j in range(2 * ni):
                    row[nw + j] = PW[j]
            if track:
                track_row(row, n_track, SX, SN, LI, SL)
        if kept_step:
            if heat:
                st = 0.0
                lo = 0.0
                for i in range(ni):
                    kind = kinds[i]
                    if kind == KIND_FE1D:
                        P = Ps[i]
                        st += ck.stored(Vs[i], Is[i], P)
                        lo += P[ck.P_HLOST]
                    elif kind == KIND_LUMPED:
                        P = Ps[i]
                        st += lk.stored(P)
                        lo += P[lk.P_LOST]
                row[nv + 2 * ni] = st
                row[nv + 2 * ni + 1] = lo
            kept, k, last_row = keep_row(buf, row, k, n_rows, n, last_row)
            if kept != RUNNING:
                status = kept
                break
        if hot_every > 0 and n % hot_every == 0 and hotter(T, hot):
            status = LOOK
            break
    end_chunk(ctl, status, n, n_end, k, last_row)
    return status
