"""The two-phase TFP in both horizontal directions
(mechanics/tfp3d_two_phase.py) as the coupled engine sees it: the device
interface of mechanics/dev_two_phase.py, four interfaces S1..S4 with 2D
footprint centres, the loading and scratch of mechanics/dev_tfp3d.py.
"""
from fpd.mechanics import tfp3d_kernel as k3
from fpd.mechanics import tfp3d_two_phase_kernel as k2
from fpd.mechanics.dev_tfp3d import centre, normal, ok, slip  # noqa: F401 (the seated 3D TFP's)

__kernel__ = True


def step(C, S, L, X, n, dt, mu, dW):
    fail = k2.advance(C, S, dt, L[0][n - 1], L[1][n - 1], L[2][n - 1], mu[0], mu[1], mu[2], mu[3],
                      int(L[10][0]), L[6][n], L[7][n], L[8][n], L[9][n], X[0], X[1])
    for i in range(4):
        dW[i] = S[k3.S_DW + i]
    return fail


def values(C, S, L, n, dt, row):
    k2.row_values(C, S, n * dt, L[3][n], L[4][n], row, L[5])
