"""The friction laws mu(T, p, v), written once (kernel module, fpd/kernels.py).

A law is a row of floats ``P`` (kind, parameters; a table's points after
N_HEAD slots), built by tribology.friction from the ``[friction]`` table.
``law_mu(P, T_C, p_Pa, v_mps)`` is the one evaluation: the pure path calls it
through the law objects of tribology/friction.py (P a Python list), the
compiled loop calls its numba copy (P a float64 array).

Kumar, Whittaker and Constantinou (2015): mu = mu_ref k_p k_T k_v with
k_p = 0.70^((p - p_ref) / 50 MPa), k_T = 0.79 (0.70^(T / 50 C) + 0.40),
k_v = 1 - 0.5 exp(-a v); the constants below are the only copy.

Constantinou, Mokha and Reinhorn (1990): mu = mu_fast - (mu_fast - mu_slow)
exp(-a |v|), the velocity law bearing tests are fitted with.

Breakaway (``holding_mu``): a stuck surface holds while the force it must
carry stays within mu_s N, mu_s the static coefficient (never below the
sliding mu); every stepper's stick test takes its cap from it.

Dwell (``dwell_mu``, ``holding_mu_dwell``, ``dwell_advance``): the static
coefficient grows with the time t the surface has been stuck, in the
empirical form of Kato, Sato and Matsubayashi (1972),
mu_s(t) = mu_s_inf - (mu_s_inf - mu_s0) exp(-(t / tau)^m), mu_s0 the
holding coefficient at zero dwell; the dwell time is per surface state the
stepper keeps (advanced by ``dwell_advance``).
"""
from __future__ import annotations

import math

__kernel__ = True

LAW_CONSTANT, LAW_LINEAR, LAW_KUMAR, LAW_TABLE, LAW_CONSTANTINOU = 0, 1, 2, 3, 4
N_HEAD = 8                 # slots before a table's points: kind, n, ...

# Kumar et al. (2015), Eqs. for k_p, k_T, k_v
KUMAR_P_BASE = 0.70        # k_p = KUMAR_P_BASE^((p - p_ref) / KUMAR_P_SCALE_MPA)
KUMAR_P_SCALE_MPA = 50.0
KUMAR_T_COEF = 0.79        # k_T = KUMAR_T_COEF (KUMAR_T_BASE^(T / KUMAR_T_SCALE_C) + KUMAR_T_OFFSET)
KUMAR_T_BASE = 0.70
KUMAR_T_SCALE_C = 50.0
KUMAR_T_OFFSET = 0.40
KUMAR_V_DROP = 0.5         # k_v = 1 - KUMAR_V_DROP exp(-a |v|)


def law_mu(P, T_C, p_Pa, v_mps):
    """mu of the law P at temperature T_C (degC), pressure p_Pa, slip speed v_mps.
    NaN for a table asked at a NaN temperature (no point brackets it)."""
    kind = int(P[0])
    if kind == LAW_KUMAR:                       # mu_ref, p_ref_MPa, a, use_p, use_T, use_v
        mu = P[1]
        if P[4] != 0.0:
            mu *= KUMAR_P_BASE ** ((p_Pa * 1e-6 - P[2]) / KUMAR_P_SCALE_MPA)
        if P[5] != 0.0:
            mu *= KUMAR_T_COEF * (KUMAR_T_BASE ** (T_C / KUMAR_T_SCALE_C) + KUMAR_T_OFFSET)
        if P[6] != 0.0:
            mu *= 1.0 - KUMAR_V_DROP * math.exp(-P[3] * abs(v_mps))
        return mu
    if kind == LAW_CONSTANT:
        return P[1]
    if kind == LAW_CONSTANTINOU:                # mu_slow, mu_fast, a
        return P[2] - (P[2] - P[1]) * math.exp(-P[3] * abs(v_mps))
    if kind == LAW_LINEAR:                      # mu0 + slope (T - T0), never below mu_min
        x = P[1] + P[3] * (T_C - P[2])
        return x if x > P[4] else P[4]
    # table: piecewise linear through (T[i], mu[i]), constant beyond the ends
    n = int(P[1])
    T0 = N_HEAD
    M0 = N_HEAD + n
    if T_C <= P[T0]:
        return P[M0]
    if T_C >= P[T0 + n - 1]:
        return P[M0 + n - 1]
    lo, hi = 0, n                               # bisect_right(T, T_C)
    while lo < hi:
        mid = (lo + hi) // 2
        if T_C < P[T0 + mid]:
            hi = mid
        else:
            lo = mid + 1
    i = lo - 1
    if i + 1 >= n:                              # a NaN temperature
        return math.nan
    w = (T_C - P[T0 + i]) / (P[T0 + i + 1] - P[T0 + i])
    return P[M0 + i] + w * (P[M0 + i + 1] - P[M0 + i])


def holding_mu(mu, mu_s, ratio):
    """The coefficient that caps a stuck surface's friction: the larger of the
    static coefficient mu_s and ratio times the sliding mu (the law at rest,
    at the surface's temperature and pressure: a static coefficient that
    follows them), never below the sliding mu (mu_s = ratio = 0: none given,
    the sliding mu holds it)."""
    h = mu
    if mu_s > h:
        h = mu_s
    r = ratio * mu
    if r > h:
        h = r
    return h


def wear_step(K, T_C, dW, mu, N, area, PW, i, ni):
    """Archard wear of interface i over a step (of ni): the sliding path
    ds = dW / (mu N) (the step's friction work dW at the coefficient mu and
    normal force N) into PW[i], the depth k_w(T) (N / area) ds into
    PW[ni + i]; K: the wear coefficient's row (a law row, m^2/N, in T only).
    A step without friction work adds nothing."""
    if dW > 0.0 and mu > 0.0 and N > 0.0:
        ds = dW / (mu * N)
        PW[i] += ds
        PW[ni + i] += law_mu(K, T_C, 0.0, 0.0) * (N / area) * ds


def dwell_mu(h0, mu_inf, tau, expo, t):
    """The static coefficient after a dwell of t seconds (Kato, Sato and
    Matsubayashi 1972): mu_inf - (mu_inf - h0) exp(-(t / tau)^expo), h0 the
    coefficient at zero dwell; h0 itself without a dwell law (tau = 0), for
    t <= 0, or when mu_inf does not exceed it."""
    if tau > 0.0 and t > 0.0 and mu_inf > h0:
        return mu_inf - (mu_inf - h0) * math.exp(-((t / tau) ** expo))
    return h0


def holding_mu_dwell(mu, mu_s, ratio, mu_inf, tau, expo, t):
    """holding_mu grown by a dwell of t seconds (dwell_mu): the cap of a
    surface stuck for t (tau = 0: holding_mu)."""
    return dwell_mu(holding_mu(mu, mu_s, ratio), mu_inf, tau, expo, t)


def dwell_advance(D, i, stuck, dt):
    """Surface i's dwell time D[i] over a step of dt: grows while stuck,
    back to zero once it slides."""
    if stuck:
        D[i] += dt
    else:
        D[i] = 0.0
