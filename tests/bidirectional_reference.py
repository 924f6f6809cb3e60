"""An independent model for the bidirectional steppers' checks: the seated
DFP (spherical pendulum of length L with the pad's mass and inertia) with
regularised Coulomb friction, written as an ODE in Cartesian components and
solved by scipy's Radau at tight tolerance. It shares no code with
mechanics/bidirectional_kernel.py but the device constants.

    n' = w
    w' = [-(f - (f.n) n) - cap(N) w / sqrt(|w|^2 + eps^2)] / I - |w|^2 n
    f = S (a_x(t), a_y(t), g),   cap = mu (N1 R1 + N2 R2)
    N2 = M (g_axis + L |w|^2),  N1 = N2 + m (g_axis + rho |w|^2),  g_axis = -(a . n_h + g n_z)

The regularisation lets the stuck bearing creep at |w| ~ eps (rad/s); the
friction work is integrated as a state.
"""
from __future__ import annotations

import numpy as np


def solve_seated(geom, t, ax, ay, mu, eps=1e-7, rtol=1e-9, atol=1e-12, t_end=None):
    """Returns (t, ux, uy, W) at the grid times t (ground accelerations ax, ay
    there, linear in between)."""
    from scipy.integrate import solve_ivp

    L, S, I, g = geom.L, geom.S, geom.I, geom.g
    M, m, rho, R1, R2 = geom.mass, geom.pad_mass, geom.rho, geom.R1, geom.R2
    t_end = t[-1] if t_end is None else t_end
    h = t[1] - t[0]

    def accel(tt):
        k = min(int(tt / h), len(t) - 2)
        r = (tt - t[k]) / h
        return ax[k] + r * (ax[k + 1] - ax[k]), ay[k] + r * (ay[k + 1] - ay[k])

    def rhs(tt, y):
        n, w = y[0:3], y[3:6]
        a0, a1 = accel(tt)
        f = S * np.array([a0, a1, g])
        w2 = w @ w
        g_axis = -(a0 * n[0] + a1 * n[1] + g * n[2])
        N2 = M * (g_axis + L * w2)
        N1 = N2 + m * (g_axis + rho * w2)
        cap = mu * (N1 * R1 + N2 * R2)
        reg = 1.0 / np.sqrt(w2 + eps * eps)
        ft = f - (f @ n) * n
        dw = (-ft - cap * reg * w) / I - w2 * n
        return np.concatenate([w, dw, [cap * w2 * reg]])

    y0 = np.array([0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0])
    keep = t <= t_end + 1e-12
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="Radau", t_eval=t[keep], rtol=rtol, atol=atol,
                    max_step=5 * h)
    if not sol.success:
        raise RuntimeError(sol.message)
    return sol.t, L * sol.y[0], L * sol.y[1], sol.y[6]
