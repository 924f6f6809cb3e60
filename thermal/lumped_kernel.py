"""The paper's lumped plate step, Eq. (9)-(10), written once (kernel module).

c T' = P - H (T - T_air) with the power P held over the step, solved
exactly: T_{n+1} = T_eq + (T_n - T_eq) exp(-H dt / c), T_eq = T_air + P / H.
thermal/lumped.py (LumpedPlate) holds the row ``P`` these functions read and
write; the compiled loop calls the numba copy on a float64 copy of it.
"""
from __future__ import annotations

__kernel__ = True
# compiled: inlined into the loop
__jit_options__ = {"inline": "always"}

# P: constants, then state
P_H, P_C, P_DT, P_T0, P_TAIR, P_DECAY = 0, 1, 2, 3, 4, 5
P_RISE, P_IN, P_LOST = 6, 7, 8           # T - T0 (round-off scales with the rise), heat in, heat lost
N_P = 9


def step(P, power_W):
    """Advance dt with power P (W); returns T (degC). The heat lost is what
    the exact update does not store: in - C dT, per step."""
    if P[P_H] > 0.0:
        rise_eq = P[P_TAIR] - P[P_T0] + power_W / P[P_H]
        dT = (rise_eq - P[P_RISE]) * P[P_DECAY]
    else:
        dT = power_W * P[P_DT] / P[P_C]
    q = power_W * P[P_DT]
    P[P_IN] += q
    P[P_LOST] += q - P[P_C] * dT
    P[P_RISE] += dT
    return P[P_T0] + P[P_RISE]


def stored(P):
    """C (T - T0) (J)."""
    return P[P_C] * P[P_RISE]
