"""The flat double friction bearing (mechanics/flat.py) as the coupled engine
sees it: the device interface of mechanics/dev_two_phase.py, two interfaces
(the pad's lower face on the lower plate, its upper face under the
superstructure).

L = (a, u, ud, xg, az): the ground acceleration per step, the machine's
programme (u, u' per grid point; one zero for a ground motion), the ground
position per grid point (one zero in the machine), the vertical ground
acceleration per step (one zero without a vertical record); X = (out, w):
flat_kernel.step's scratch. Everything is the stepper's own kernel
(flat_kernel.advance, values).
"""
from fpd.mechanics import flat_kernel as fk

__kernel__ = True


def normal(C, S, i):
    if i == 0:
        return S[fk.S_N1]
    return S[fk.S_N2]


def slip(C, S, i):
    if i == 0:
        return S[fk.S_SV1]
    return S[fk.S_SV2]


def centre(C, S, i):
    """Footprint centres (FlatStepper.footprints): the lower plate at +q1, the upper at -q2."""
    if i == 0:
        return S[fk.S_Q1], 0.0
    return -S[fk.S_Q2], 0.0


def step(C, S, L, X, n, dt, mu, dW):
    flag = fk.advance(C, S, L[0], L[4], L[1], L[2], mu[0], mu[1], X[0], X[1])
    out = X[0]
    dW[0] = out[fk.O_W1]
    dW[1] = out[fk.O_W2]
    return flag


def ok(C, S):
    """No error flag (the pad tips: the Python stepper raises PadTipped), every value finite."""
    if S[fk.S_ERR] != 0.0:
        return False
    s = 0.0
    for i in range(S.shape[0]):
        s += S[i] * 0.0
    return s == 0.0


def values(C, S, L, n, dt, row):
    fk.values(C, S, fk.ground(C, L[1], L[3], n), row)
