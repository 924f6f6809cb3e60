"""The rigid TFP in both horizontal directions (mechanics/tfp3d.py) as the
coupled engine sees it: the device interface of mechanics/dev_two_phase.py,
four interfaces S1..S4 (lower plate, lower slider plate, upper slider plate,
upper plate), footprint centres in 2D.

L = (ax, ay, az, xg, yg, sc, ux, uy, udx, udy, mach): the ground (a test
machine: the lower plate's) acceleration per step (x, y, vertical), its
position per row (x, y), the rows' scratch, the machine's programme u, u'
per grid point (zeros for a ground motion) and mach[0] = 1 for the machine;
X = (out, sc): the step's output and scratch (the stepper's own arrays).
"""
from fpd.mechanics import tfp3d_kernel as k3
from fpd.mechanics import tfp_kernel as tk

__kernel__ = True


def normal(C, S, i):
    return S[k3.S_N + i]


def slip(C, S, i):
    return S[k3.S_SV + i]


def centre(C, S, i):
    """Footprint centre (x, y) on part i (TFP3DStepper.footprints)."""
    if i == 0:
        return C[tk.I_R1] * S[0], C[tk.I_R1] * S[1]
    if i == 1:
        return C[tk.I_R2] * S[2], C[tk.I_R2] * S[3]
    if i == 2:
        return -C[tk.I_R3] * S[2], -C[tk.I_R3] * S[3]
    return -C[tk.I_R4] * S[0], -C[tk.I_R4] * S[1]


def step(C, S, L, X, n, dt, mu, dW):
    if C[tk.I_VERT] == 1.0:
        # a vertical ground motion: the step may lift the stack off and land it
        fail = k3.advance_vertical(C, S, dt, L[0][n - 1], L[1][n - 1], L[2][n - 1], mu[0], mu[1], mu[2], mu[3],
                                   int(L[10][0]), L[6][n], L[7][n], L[8][n], L[9][n], X[0], X[1])
    else:
        fail = k3.advance(C, S, dt, L[0][n - 1], L[1][n - 1], L[2][n - 1], mu[0], mu[1], mu[2], mu[3],
                          int(L[10][0]), L[6][n], L[7][n], L[8][n], L[9][n], X[0], X[1])
    for i in range(4):
        dW[i] = S[k3.S_DW + i]
    return fail


def ok(C, S):
    return True


def values(C, S, L, n, dt, row):
    k3.row_values(C, S, n * dt, L[3][n], L[4][n], row, L[5])
    k3.vertical_row(C, S, L[2][n - 1] if n > 0 else 0.0, row, L[5])
