"""The bearing-test machine along a planar orbit (mechanics/bidirectional.py
BidirectionalTestMachine: a seated DFP/SFP driven along u(t) = (ux, uy)) as
the coupled engine sees it: the device interface of
mechanics/dev_two_phase.py.

L = (U, UD, UDD): the programme's u, u', u'' per grid point ((n + 1, 2)
arrays; the lower plate moves by -u); X unused; footprint centres in 2D
(bidirectional_kernel.centres). Everything is the stepper's own kernel
(bidirectional_kernel.machine_step, values).
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
    flag = bk.machine_step(C, S, L[0], L[1], L[2], n - 1, mu[0], mu[1])
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
    U = L[0]
    bk.values(C, S, n * dt, -U[n, 0], -U[n, 1], row)
