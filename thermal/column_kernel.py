"""The fe1d column step, written once (kernel module, fpd/kernels.py).

One step of M u' + A u = b on the through-thickness column (thermal/fe1d.py),
the load q (W) on the surface node, convection and the optional fixed
temperature on the back node (the Dirichlet node, dofs [nf:]): the schemes,
the start-up after t = 0 and after every load jump (Rannacher), the jump
test and the heat ledger of thermal/stepping.py, specialised to a column.
The linear-algebra and vector calls are thermal/column_blas.py's primitives (the
compiled path swaps in their numba backend); everything around them is here.

Arrays (numpy on both paths): Mb, Ab (2, n) upper band storage of M and A;
FAC (6, n) dpttrf factors of M + gamma A for gamma = h / m (start-up
substeps), the scheme's gamma (h, h / 2, 2 h / 3) and h (BDF2's first step
without the start-up); V (6, n) rows u, du, rhs, u before a start-up step,
m1 = M 1, scratch; I (int32) the BLAS arguments. Reads of single
entries go through float() (a Python float on the pure path: faster). P: the scalars below (a
Python list on the pure path, float64 on the compiled one).
"""
from __future__ import annotations

import math

from .column_blas import accept, band_mv, copy, difference, dot, pt_solve

__kernel__ = True
# compiled: inline these small functions into their callers (a call passing
# the tuples of arrays costs ~1 us per step, more than the arithmetic)
__jit_options__ = {"inline": "always"}
# ... but not the steps that run rarely under the default scheme (BDF2): the
# backward-Euler step (the start-up substeps, BDF2's first step; inlined it
# was typed at four sites) and Crank-Nicolson's: 26 -> 20 s of CPU for the
# default scene's first compile, the same loop time
__jit_no_inline__ = ("be_step", "cn_step", "start_step")

BE, CN, BDF2 = 0, 1, 2
F_SUB, F_MAIN, F_H = 0, 2, 4             # rows of FAC (d, then e)
V_U, V_DU, V_RHS, V_UB, V_M1, V_SC = 0, 1, 2, 3, 4, 5

# P: settings and constants
P_SCHEME, P_RANN, P_M, P_START, P_H, P_CB, P_JR, P_NF = 0, 1, 2, 3, 4, 5, 6, 7
P_MD1, P_AD0, P_AD1, P_E0, P_TAIR, P_FIXED, P_R0, P_AC = 8, 9, 10, 11, 12, 13, 14, 15
# P: state
P_Q, P_LS, P_SL, P_STEPS, P_LP, P_HIN, P_HLOST, P_HALF = 16, 17, 18, 19, 20, 21, 22, 23
N_P = 24
STATE = (P_Q, P_LS, P_SL, P_STEPS, P_LP, P_HIN, P_HLOST, P_HALF)


def reaction(P, Mdu_last, h, uth_2, uth_1):
    """1_D^T of the scheme's residual on the back (Dirichlet) node: the heat
    the fixed temperature supplies over the step (J); no load there."""
    return P[P_MD1] * Mdu_last + h * (P[P_AD0] * uth_2 + P[P_AD1] * uth_1)


def jump(P, q):
    """A change of the load larger than jump_rtol times the largest load seen
    so far (relative to the running maximum, so that a smooth ramp up from
    zero is not a jump, while a switch-on after a stick phase is)."""
    if abs(q) > P[P_LS]:
        P[P_LS] = abs(q)
    return abs(q - P[P_Q]) > P[P_JR] * P[P_LS]


def be_step(Mb, Ab, FAC, V, I, P, h, q, f):
    """Backward Euler over h with the factor row f of FAC; returns the
    step's loss (J)."""
    nf = int(P[P_NF])
    n = V[V_U].shape[0]
    u, du, rhs = V[V_U], V[V_DU], V[V_RHS]
    band_mv(I, V[V_SC], -h, Ab, u, 0.0, rhs)
    rhs[0] += h * q
    pt_solve(I, FAC[f], FAC[f + 1], rhs, nf)
    accept(u, du, rhs, nf)
    s = h * P[P_CB] * float(u[n - 1])
    if nf < n:
        s -= reaction(P, float(rhs[nf - 1]), h, float(u[n - 2]), float(u[n - 1]))
    P[P_HIN] += h * q
    P[P_HLOST] += s
    return s


def cn_step(Mb, Ab, FAC, V, I, P, h, q):
    """Crank-Nicolson over h (trapezoidal loss)."""
    nf = int(P[P_NF])
    n = V[V_U].shape[0]
    u, du, rhs = V[V_U], V[V_DU], V[V_RHS]
    band_mv(I, V[V_SC], -h, Ab, u, 0.0, rhs)
    rhs[0] += h * q
    u2, u1 = float(u[n - 2]), float(u[n - 1])
    pt_solve(I, FAC[F_MAIN], FAC[F_MAIN + 1], rhs, nf)
    accept(u, du, rhs, nf)
    s = 0.5 * h * P[P_CB] * (u1 + float(u[n - 1]))
    if nf < n:
        s -= reaction(P, float(rhs[nf - 1]), h, 0.5 * (u2 + float(u[n - 2])), float(u[n - 1]))
    P[P_HIN] += h * q
    P[P_HLOST] += s


def bdf2_step(Mb, Ab, FAC, V, I, P, h, q):
    """BDF2: (M + 2h/3 A) du = 2h/3 (G - A u) + 1/3 M du_prev with
    G = 3/2 q - 1/2 q_prev (the scheme delivers exactly q h per step); the
    loss source passes through the same filter, l_n = 2/3 (s_n + l_{n-1}/2)."""
    nf = int(P[P_NF])
    n = V[V_U].shape[0]
    u, du, rhs = V[V_U], V[V_DU], V[V_RHS]
    c23 = 2.0 * h / 3.0
    band_mv(I, V[V_SC], -c23, Ab, u, 0.0, rhs)
    band_mv(I, V[V_SC], 1.0 / 3.0, Mb, du, 1.0, rhs)
    rhs[0] += c23 * (1.5 * q - 0.5 * P[P_Q])
    pt_solve(I, FAC[F_MAIN], FAC[F_MAIN + 1], rhs, nf)
    last_prev = float(du[nf - 1])
    accept(u, du, rhs, nf)
    if nf == n:
        s = h * P[P_CB] * float(u[n - 1])
    else:
        s = h * P[P_CB] * float(u[n - 1]) - reaction(P, 1.5 * float(rhs[nf - 1]) - 0.5 * last_prev, h,
                                                     float(u[n - 2]), float(u[n - 1]))
    loss = (2.0 / 3.0) * (s + 0.5 * P[P_LP])
    P[P_LP] = loss
    P[P_HIN] += h * q
    P[P_HLOST] += loss


def start_step(Mb, Ab, FAC, V, I, P, h, q):
    """One step as m backward-Euler substeps (start-up); du is the whole
    step's increment (BDF2 history), the loss their sum."""
    nf = int(P[P_NF])
    u, du, ub = V[V_U], V[V_DU], V[V_UB]
    copy(ub, u, nf)
    m = int(P[P_M])
    loss = 0.0
    for _ in range(m):
        loss += be_step(Mb, Ab, FAC, V, I, P, h / m, q, F_SUB)
    difference(du, u, ub, nf)
    P[P_LP] = loss
    P[P_HALF] += m


def step(Mb, Ab, FAC, V, I, P, q):
    """Advance dt with the power q (W) into the surface node."""
    h = P[P_H]
    sch = int(P[P_SCHEME])
    if sch == BE:
        be_step(Mb, Ab, FAC, V, I, P, h, q, F_MAIN)
    elif P[P_RANN] != 0.0 and (P[P_SL] > 0.0 or P[P_STEPS] == 0.0 or jump(P, q)):
        if P[P_STEPS] == 0.0 or jump(P, q):
            P[P_SL] = P[P_START]
        P[P_SL] -= 1.0
        start_step(Mb, Ab, FAC, V, I, P, h, q)
    elif sch == CN:
        cn_step(Mb, Ab, FAC, V, I, P, h, q)
    elif P[P_STEPS] == 0.0:
        P[P_LP] = be_step(Mb, Ab, FAC, V, I, P, h, q, F_H)
    else:
        bdf2_step(Mb, Ab, FAC, V, I, P, h, q)
    P[P_Q] = q
    P[P_STEPS] += 1.0


def plate_step(Mb, Ab, FAC, V, I, P, power_W, centre_m):
    """FE1DPlate.step: the power reaches a fixed-point column only while the
    footprint covers it; returns the surface temperature (degC)."""
    if P[P_FIXED] != 0.0 and not abs(centre_m - P[P_R0]) <= P[P_AC]:
        power_W = 0.0
    step(Mb, Ab, FAC, V, I, P, power_W)
    return float(V[V_U][0]) + float(P[P_TAIR])


def centre_2d(P, cx, cy):
    """The centre plate_step tests for a 2D footprint centre (cx, cy)
    (bidirectional runs): a fixed-point column at (r0, 0) is covered when it
    lies within a of it (FE1DPlate.covered): r0 itself then, else a point
    out of reach."""
    r0, a = P[P_R0], P[P_AC]
    if math.hypot(cx - r0, cy) <= a:
        return r0
    return r0 + 2.0 * a + 1.0


def stored(V, I, P):
    """1^T M (u - u_0) (J)."""
    return dot(I, V[V_M1], V[V_U]) - P[P_E0]
