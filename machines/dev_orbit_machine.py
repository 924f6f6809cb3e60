"""The bearing-test machine along a planar orbit (mechanics/bidirectional.py
BidirectionalTestMachine: a seated DFP/SFP driven along u(t) = (ux, uy)) as
the coupled engine sees it: the device interface of
mechanics/dev_two_phase.py.

L = (U, UD, UDD, GV): the programme's u, u', u'' per grid point ((n + 1, 2)
arrays; the lower plate moves by -u) and the axial load over M per grid
point (one g when the superstructure rides); X unused; footprint centres in 2D
(bidirectional_kernel.centres). Everything is the stepper's own kernel
(link_kernel.orbit_machine_step: bidirectional_kernel.machine_step or the
compliant link's step; bidirectional_kernel.values).
"""
from fpd.machines import link_kernel as lk
from fpd.mechanics import bidirectional_kernel as bk
# the 3D stepper's state, so its interfaces and its state check are that device's own
from fpd.mechanics.dev_bidirectional import centre, normal, ok, slip  # noqa: F401

__kernel__ = True


def step(C, S, L, X, n, dt, mu, dW):
    w1, w2 = S[bk.S_W1], S[bk.S_W2]
    flag = lk.orbit_machine_step(C, S, L[0], L[1], L[2], L[3], n - 1, mu[0], mu[1])
    dW[0] = S[bk.S_W1] - w1
    dW[1] = S[bk.S_W2] - w2
    return flag


def values(C, S, L, n, dt, row):
    U = L[0]
    bk.values(C, S, n * dt, -U[n, 0], -U[n, 1], row)
