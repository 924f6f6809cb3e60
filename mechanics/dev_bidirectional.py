"""The 3D DFP/SFP stepper (both horizontal directions, mechanics/bidirectional.py)
as the coupled engine sees it: the device interface of mechanics/dev_two_phase.py.

L = (ax, ay, xg, yg, az): the ground acceleration per step and the ground
position per step, the vertical ground acceleration per step (read only
when C[C_VERT]: otherwise a stand-in, and the field is g); footprint centres in 2D (bidirectional_kernel.centres).
"""
from fpd.mechanics import bidirectional_kernel as bk

__kernel__ = True


def normal(C, S, i):
    if i == 0:
        return S[bk.S_N1]
    return S[bk.S_N2]


def slip(C, S, i):
    if i == 0:
        return S[bk.S_SV1]
    return S[bk.S_SV2]


def centre(C, S, i):
    c1x, c1y, c2x, c2y = bk.centres(C, S)
    if i == 0:
        return c1x, c1y
    return c2x, c2y


def step(C, S, L, X, n, dt, mu, dW):
    w1, w2 = S[bk.S_W1], S[bk.S_W2]
    ay = 0.0
    if C[bk.C_PLANAR] == bk.PLANAR_NONE:     # a planar run has no y component
        ay = L[1][n - 1]
    az = 0.0
    if C[bk.C_VERT] != 0.0:
        az = L[4][n - 1]
    flag = bk.step(C, S, L[0][n - 1], ay, az, dt, mu[0], mu[1])
    dW[0] = S[bk.S_W1] - w1
    dW[1] = S[bk.S_W2] - w2
    return flag


def ok(C, S):
    """Every value of the state finite."""
    s = 0.0
    for i in range(S.shape[0]):
        s += S[i] * 0.0
    return s == 0.0


def values(C, S, L, n, dt, row):
    bk.values(C, S, n * dt, L[2][n], L[3][n], row)
