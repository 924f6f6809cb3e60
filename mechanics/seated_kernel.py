"""The seated reference step (model.md section 2), written once (kernel
module, fpd/kernels.py): a Moreau-type scheme on the one DOF theta; the
derivation is in mechanics/seated.py's docstring. SeatedStepper holds the
state vector S and the constants C these functions read.
"""
from __future__ import annotations

import math

from .phases import SLIP, STICK

__kernel__ = True

# S: the state, in SeatedStepper.save()'s order
SN, ST, TH, THD, SF, N1, N2, W1, W2, EIN, MODE, SV1, SV2 = range(13)
N_STATE = 13
# C: constants
CDT, CI, CS, CL, CM, Cm, CRHO, CG, CR1, CR2, CITER, TWO = range(12)
N_CONST = 12
N_VALUES = 17             # len(seated.SEATED_COLUMNS)


def step(C, S, A, mu1, mu2):
    """One step with mu1, mu2 held (A: the ground acceleration per step);
    returns the friction work (J) of the lower and upper interface.

    Friction enters as an impulse with lambda in Sgn(theta'_{n+1}): the step
    sticks exactly or slides with the full cap; positions advance with the
    trapezoidal rule, gravity by the discrete gradient sin(theta_m) sinc(dtheta/2)."""
    dt, I, S_, g = C[CDT], C[CI], C[CS], C[CG]
    L, M, m, rho, R1, R2 = C[CL], C[CM], C[Cm], C[CRHO], C[CR1], C[CR2]
    n = int(S[SN])
    a = A[n]
    th0, v0 = S[TH], S[THD]
    half = 0.5 * dt * v0            # predictor of dtheta / 2
    v1 = v0
    N1_, N2_ = S[N1], S[N2]
    for _ in range(int(C[CITER])):
        thm = th0 + half
        c, s = math.cos(thm), math.sin(thm)
        vm = 0.5 * (v0 + v1)
        N2_ = M * (g * c - a * s + L * vm * vm)
        N1_ = N2_ + m * (g * c - a * s + rho * vm * vm)
        cap = mu1 * N1_ * R1 + mu2 * N2_ * R2
        sinc = math.sin(half) / half if abs(half) > 1e-7 else 1.0 - half * half / 6.0
        drive = -S_ * (a * c + g * s * sinc)
        v_free = v0 + dt * drive / I
        imp = dt * cap / I
        if abs(v_free) <= imp:
            v1 = 0.0
        else:
            v1 = v_free - math.copysign(imp, v_free)
        half = 0.25 * dt * (v0 + v1)
    dth = 2.0 * half
    thm = th0 + half
    c, s = math.cos(thm), math.sin(thm)
    thdd = (v1 - v0) / dt
    # horizontal force of the bearing on the superstructure, against u
    S[SF] = -M * (a + L * (c * thdd - s * (0.5 * (v0 + v1)) ** C[TWO]))
    S[TH] = th0 + dth
    S[THD] = v1
    S[N1], S[N2] = N1_, N2_
    adth = abs(dth)
    dW1 = mu1 * N1_ * R1 * adth
    dW2 = mu2 * N2_ * R2 * adth
    S[W1] += dW1
    S[W2] += dW2
    S[EIN] -= S_ * a * c * dth
    S[MODE] = SLIP if dth != 0.0 else STICK
    S[SV1] = R1 * adth / dt
    S[SV2] = R2 * adth / dt
    S[SN] = n + 1
    S[ST] = (n + 1) * dt
    return dW1, dW2


def values(C, S, xg, out):
    """The row of SEATED_COLUMNS into out (xg: the ground displacement now)."""
    th, L = S[TH], C[CL]
    out[0], out[1], out[2] = S[ST], xg, L * math.sin(th)
    out[3], out[4], out[5] = L * math.cos(th) * S[THD], S[SF], L * (1.0 - math.cos(th))
    out[6], out[7], out[8] = th, C[CR1] * th, C[CR2] * th
    out[9], out[10], out[11], out[12], out[13] = S[N1], S[N2], S[W1], S[W2], S[MODE]
    out[14] = S[EIN]
    out[15] = 0.5 * C[CI] * S[THD] ** C[TWO]
    out[16] = C[CS] * C[CG] * (1.0 - math.cos(th))
