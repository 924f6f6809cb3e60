"""The rigid triple friction pendulum (mechanics/tfp.py) as the coupled engine
sees it: the device interface of mechanics/dev_two_phase.py, four interfaces
S1..S4 (lower plate, lower slider plate, upper slider plate, upper plate).

L = (a, u, ud, xg, dd, az): the ground acceleration per step, the machine's
programme (u, u' per step; zeros for a ground motion), the ground position
per row, dd = (d1, d2, d3, d4, machine), the vertical ground acceleration
per step (read only when C[I_VERT] is set); X = (out, M, w, tmp, sc): the
stepper's scratch.
"""
from fpd.mechanics import tfp_kernel as tk

__kernel__ = True


def normal(C, S, i):
    return S[tk.S_N + i]


def slip(C, S, i):
    return S[tk.S_SV + i]


def centre(C, S, i):
    """Footprint centre on part i: +s on the lower parts, -s on the upper (TFPStepper.footprints)."""
    if i == 0:
        return C[tk.I_R1] * S[0], 0.0
    if i == 1:
        return C[tk.I_R2] * S[1], 0.0
    if i == 2:
        return -C[tk.I_R3] * S[1], 0.0
    return -C[tk.I_R4] * S[0], 0.0


def step(C, S, L, X, n, dt, mu, dW):
    machine = int(L[4][4])
    az = 0.0
    if C[tk.I_VERT] != 0.0:
        az = L[5][n - 1]
    if C[tk.I_VERT] == 1.0:
        # a vertical ground motion: the step may lift the stack off and land it
        fail = tk.advance_vertical(C, S, dt, L[0][n - 1], az, mu[0], mu[1], mu[2], mu[3], machine, L[1][n],
                                   L[2][n], X[0], X[1], X[2], X[3], X[4])
    else:
        fail = tk.advance(C, S, dt, L[0][n - 1], az, mu[0], mu[1], mu[2], mu[3], machine, L[1][n], L[2][n],
                          X[0], X[1], X[2], X[3], X[4])
    for i in range(4):
        dW[i] = S[tk.S_DW + i]
    return fail


def ok(C, S):
    return True


def values(C, S, L, n, dt, row):
    dd = L[4]
    tk.row_values(C, S, n * dt, L[3][n], dd[0], dd[1], dd[2], dd[3], row)
