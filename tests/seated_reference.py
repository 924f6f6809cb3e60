"""A tiny seated reference (the brief's discretisation) until mechanics.seated lands.

I theta'' + S a_g cos(theta) + S g sin(theta) = -(mu1 N1 R1 + mu2 N2 R2) sgn(theta'),
Moreau step, midpoint position update, gravity by the discrete gradient,
E_input by -S a cos(theta_mid) dtheta.
"""
from __future__ import annotations

import math


class SeatedReference:
    def __init__(self, geom, ground, theta0=0.0, theta_dot0=0.0):
        self.g = geom
        self.dt = ground.dt
        self.n_steps = ground.n_steps
        self.a_step = [float(x) for x in ground.a_step]
        self.n = 0
        self.theta, self.v = theta0, theta_dot0
        self.W = 0.0
        self.E_input = 0.0

    def step(self, mu1, mu2):
        g, h = self.g, self.dt
        I, S, G = g.I, g.S, g.g
        a = self.a_step[self.n]
        th0, v0 = self.theta, self.v
        c, s = math.cos(th0), math.sin(th0)
        N2 = g.mass * (G * c - a * s + g.L * v0 * v0)
        N1 = N2 + g.pad_mass * (G * c - a * s + g.rho * v0 * v0)
        cap = mu1 * N1 * g.R1 + mu2 * N2 * g.R2
        dth = h * v0
        for _ in range(50):
            mid = th0 + 0.5 * dth
            x = 0.5 * dth
            sinc = 1.0 - x * x / 6.0 if abs(x) < 1e-4 else math.sin(x) / x
            drive = -S * a * math.cos(mid) - S * G * math.sin(mid) * sinc
            vf = v0 + h / I * drive
            if abs(vf) <= h * cap / I:
                v1 = 0.0
            else:
                v1 = vf - math.copysign(h * cap / I, vf)
            new = 0.5 * h * (v0 + v1)
            if abs(new - dth) <= 1e-15:
                dth = new
                break
            dth = new
        mid = th0 + 0.5 * dth
        self.E_input += -S * a * math.cos(mid) * dth
        dW = cap * abs(dth)
        self.W += dW
        self.theta, self.v = th0 + dth, v1
        self.n += 1
        return dW

    @property
    def u(self):
        return self.g.L * math.sin(self.theta)
