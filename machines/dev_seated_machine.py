"""The planar bearing-test machine (machines/seated.py SeatedTestMachine: a
seated DFP/SFP driven along an imposed displacement) as the coupled engine
sees it: the device interface of mechanics/dev_two_phase.py.

L = (u, ud, udd, sm, uds, udds, gv): the programme per grid point, the marks
where the machine has stopped the bearing, the programme's smooth branch
there and the axial load over M (seated_kernel.machine_step); X unused. Everything is the stepper's
own kernel (link_kernel.seated_machine_step: seated_kernel.machine_step or the compliant link's step;
seated_kernel.values).
"""
from fpd.machines import link_kernel as lk
from fpd.machines import seated_kernel as sk

__kernel__ = True


def normal(C, S, i):
    if i == 0:
        return S[sk.N1]
    return S[sk.N2]


def slip(C, S, i):
    if i == 0:
        return S[sk.SV1]
    return S[sk.SV2]


def centre(C, S, i):
    """Footprint centres (s1, -s2): the lower plate at +R1 theta, the upper at -R2 theta."""
    th = S[sk.TH]
    if i == 0:
        return C[sk.CR1] * th, 0.0
    return -(C[sk.CR2] * th), 0.0


def step(C, S, L, X, n, dt, mu, dW):
    d1, d2 = lk.seated_machine_step(C, S, L[0], L[1], L[2], L[3], L[4], L[5], L[6], mu[0], mu[1])
    dW[0] = d1
    dW[1] = d2
    return 0


def ok(C, S):
    """Every value finite (where Python's asin or a division would raise,
    the compiled step gives NaN or inf: the Python loop replays the step),
    and values() cannot overflow (theta'^2 is a Python power, which raises)."""
    s = 0.0
    for i in range(sk.N_STATE):
        s += S[i] * 0.0
    if s != 0.0:                        # NaN for any non-finite value
        return False
    return abs(S[sk.THD]) <= 1e150


def values(C, S, L, n, dt, row):
    sk.values(C, S, -L[0][n], row)
