"""An independent computation of the TFP in both directions on the test
machine (tests/test_tfp3d.py): the four coordinates' equations of motion in
continuous time, friction regularised (c v / sqrt(|v|^2 + eps^2)), the
orbit imposed as a constraint with its multiplier (the machine's force),
integrated by scipy (DOP853) at tight tolerance.

Shared with the stepper is only the model's definition (docs/model.md 6.8:
the bodies at r_k = -a_k e(phi) - b_k e(phi + alpha), the tilting inertia,
each block's slip the speed of its axis, the normal forces passed down the
stack without the generalised accelerations, the machine's force in them);
not its code: the Jacobians here are complex-step derivatives of e(v), the
centripetal terms central differences of them, no discrete gradient, no cone program.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

H_CS = 1e-30


def _e(v):
    """Axis direction of a tilt vector v = (vx, vy) (each component may be an
    array of perturbations), complex-safe: the series in t = |v|^2."""
    t = v[0] * v[0] + v[1] * v[1]
    s = 0.0 * t
    c = 0.0 * t
    a = 1.0 + 0.0 * t        # (-t)^n / (2n)!
    for n in range(14):
        if n > 0:
            a = a * (-t) / ((2 * n - 1) * (2 * n))
        c = c + a
        s = s + a / (2 * n + 1)
    return np.array([-s * v[0], -s * v[1], c])


_PERT = 1j * H_CS * np.eye(4)


def _jac(fun, q):
    """d fun / d q (3 x 4) by complex step (the four perturbations at once)."""
    Q = q[:, None] + _PERT              # column j: q + i h e_j
    return fun(Q).imag / H_CS


def _quad(fun, q, qd, d=1e-5):
    """d^2/de^2 fun(q + e qd) at 0 (the centripetal part of the acceleration):
    central differences of the complex-step directional derivative."""
    Q = np.column_stack([q + d * qd, q - d * qd]) + 1j * H_CS * qd[:, None]
    f = fun(Q).imag / H_CS
    return (f[:, 0] - f[:, 1]) / (2.0 * d)


class Reference:
    def __init__(self, geom, mus, prog_u, prog_ud, prog_udd, eps=1e-3):
        self.g = geom
        self.mus = mus
        self.u, self.ud, self.udd = prog_u, prog_ud, prog_udd
        self.eps = eps
        b = geom.bodies()
        # real masses (m, a, b) bottom to top; the tilting inertia as pseudo-points
        self.pts = [(m, a, bb) for m, a, bb, _, _ in b]
        Jphi = sum(J for _, _, _, J, w in b if w == "phi")
        Jpsi = sum(J for _, _, _, J, w in b if w == "psi")
        self.Aa = sum(m * a * a for m, a, _ in self.pts) + Jphi
        self.B = sum(m * bb * bb for m, _, bb in self.pts) + Jpsi
        self.K = sum(m * a * bb for m, a, bb in self.pts)
        self.P1 = sum(m * a for m, a, _ in self.pts)
        self.P2 = sum(m * bb for m, _, bb in self.pts)
        self.F = np.zeros(2)

    @staticmethod
    def ephi(q):
        return _e(q[0:2])

    @staticmethod
    def epsi(q):
        return _e(q[0:2] + q[2:4])

    def rhs(self, t, y):
        g = self.g
        q, qd = y[0:4], y[4:8]
        Ep, Es = _jac(self.ephi, q), _jac(self.epsi, q)
        cp, cs = _quad(self.ephi, q, qd), _quad(self.epsi, q, qd)
        ep, es = self.ephi(q), self.epsi(q)
        udd = self.udd(t)
        g3 = np.array([-udd[0], -udd[1], g.g])        # gravity and the lower plate's d'Alembert force
        M = self.Aa * Ep.T @ Ep + self.B * Es.T @ Es + self.K * (Ep.T @ Es + Es.T @ Ep)
        quad = self.Aa * Ep.T @ cp + self.B * Es.T @ cs + self.K * (Ep.T @ cs + Es.T @ cp)
        Qg = self.P1 * Ep.T @ g3 + self.P2 * Es.T @ g3
        A, Li = g.A, g.Li
        C = -(A * Ep + Li * Es)[0:2]
        u = -(A * ep + Li * es)[0:2]
        csup = -(A * cp + Li * cs)
        # slips: the speed of each block's axis (alpha's: the axis e(alpha) of the relative tilt)
        Ea = _jac(lambda qq: _e(qq[2:4]), q)
        vo = Ep @ qd
        vi = Ea @ qd
        no = math.sqrt(vo @ vo + self.eps ** 2)
        ni = math.sqrt(vi @ vi + self.eps ** 2)
        ud = self.ud(t)
        up = self.u(t)
        om = 50.0                   # Baumgarte
        rhs_c = udd - csup[0:2] - 2.0 * om * (C @ qd - ud) - om * om * (u - up)
        F = self.F.copy()
        mu1, mu2, mu3, mu4 = self.mus
        for _ in range(40):
            # normal forces down the stack (centripetal terms, no generalised accelerations)
            (ml, al, bl), (mp, ap, bp), (mu_, au, bu), (Ms, _, _) = self.pts
            b = Ms * (g3 + csup) - np.array([F[0], F[1], 0.0])
            N4 = b @ ep
            b = b + mu_ * (g3 - (au * cp + bu * cs))
            N3 = b @ es
            b = b + mp * (g3 - (ap * cp + bp * cs))
            N2 = b @ es
            b = b + ml * (g3 - (al * cp + bl * cs))
            N1 = b @ ep
            N1, N2, N3, N4 = (max(x, 0.0) for x in (N1, N2, N3, N4))
            co = mu1 * N1 * g.R1 + mu4 * N4 * g.R4
            ci = mu2 * N2 * g.R2 + mu3 * N3 * g.R3
            Qf = -co * Ep.T @ vo / no - ci * Ea.T @ vi / ni
            KKT = np.zeros((6, 6))
            KKT[0:4, 0:4] = M
            KKT[0:4, 4:6] = -C.T
            KKT[4:6, 0:4] = C
            sol = np.linalg.solve(KKT, np.concatenate([Qg + Qf - quad, rhs_c]))
            Fn = sol[4:6]
            if np.max(np.abs(Fn - F)) <= 1e-13 * (1.0 + np.max(np.abs(Fn))):
                F = Fn
                break
            F = Fn
        self.F = F
        power = co * (vo @ vo) / no + ci * (vi @ vi) / ni
        return np.concatenate([qd, sol[0:4], [power]])

    def run(self, y0, t_end, **kw):
        opts = dict(method="DOP853", rtol=1e-9, atol=1e-11, dense_output=True)
        opts.update(kw)
        return solve_ivp(self.rhs, (0.0, t_end), np.concatenate([y0, [0.0]]), **opts)


def circle_second_revolution(g, mus, A, f, y0):
    """The reference's dissipation over the second revolution of the test
    machine's circle of radius A at f Hz, from the machine's placement y0
    (the stepper's first 8 state entries at u(0), u'(0)); LSODA at rtol
    1e-9."""
    w = 2.0 * math.pi * f
    ref = Reference(g, mus, lambda t: A * np.array([math.cos(w * t), math.sin(w * t)]),
                    lambda t: A * w * np.array([-math.sin(w * t), math.cos(w * t)]),
                    lambda t: -A * w * w * np.array([math.cos(w * t), math.sin(w * t)]))
    sol = ref.run(y0, 2.0 / f, method="LSODA", rtol=1e-9, atol=1e-11)
    assert sol.status == 0
    return sol.sol(2.0 / f)[8] - sol.sol(1.0 / f)[8]
