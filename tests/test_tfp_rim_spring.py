"""A rim of finite stiffness on the planar TFP (mechanics/tfp_kernel.py
``rim_coordinate``, docs/model.md 6.7): the springs k o_i^2 / 2 on each
surface's slide beyond its capacity and their dashpots, in the seated and
the two-phase models.

The closed forms are those of the rim alone: no gravity, no friction (the
TFPGeometry's g = 0, every mu 0), a coordinate launched into its rim at a
small rate. While it overlaps, the other coordinate is free, so the
coordinate is a linear oscillator of generalised inertia m_q = det M / M_jj
(the other's diagonal entry) on the generalised spring K = k sum R_i^2 over
its two surfaces (both reach their rims together here): contact time
pi sqrt(m_q / K), deepest overlap of surface i R_i v sqrt(m_q / K) (the
slide's rate R_i v, m_eff = m_q / sum R^2: its peak force R_i v sqrt(k
m_eff)), rate after the contact -v, or -v exp(-zeta pi / sqrt(1 - zeta^2))
with the dashpot."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.loading import ground_motion as gmod
from fpd.mechanics import tfp_kernel as K
from fpd.mechanics.tfp import TFPStepper
from fpd.schema import scene as scn
from fpd.schema.scene import SceneError
from tests.test_tfp import tfp

DTS = (1e-3, 5e-4, 2.5e-4)


def bounce(dt, coord, k, v, zeta=0.0, model="seated", duration=0.05):
    """The rim alone: coordinate ``coord`` (0: phi, S1 and S4; 1: alpha, S2
    and S3) launched at the rate v from 2.37 ms before its rim. Returns the
    stepper, the states (phi, alpha and their rates) at every step, the
    ledger's residuals and the launch energy."""
    g = dataclasses.replace(tfp(g=0.0), rim_stiffness=k, rim_damping=zeta)
    n = int(round(duration / dt))
    s = TFPStepper(g, gmod.pulse_ground_motion("cosine", 0.0, 1.0, 0.0, n * dt, dt), model=model)
    s.S[coord] = g.qmax[coord] - 2.37e-3 * v
    s.S[2 + coord] = v
    s.S[K.S_EIN] = E0 = s.E_kin() + s.E_pot()
    states, res = [s.S[0:4].copy()], [0.0]
    for _ in range(n):
        s.step(0.0, 0.0, 0.0, 0.0)
        states.append(s.S[0:4].copy())
        res.append(s.ledger_residual())
    return s, np.array(states), np.array(res), E0


def crossing_times(t, q, v, level):
    """The times q crosses level, each from the cubic Hermite of the step it is in."""
    out = []
    for i in range(len(t) - 1):
        a, b = q[i] - level, q[i + 1] - level
        if a * b < 0.0:
            h = t[i + 1] - t[i]

            def f(s):
                return ((2 * s ** 3 - 3 * s ** 2 + 1) * a + (s ** 3 - 2 * s ** 2 + s) * h * v[i]
                        + (3 * s ** 2 - 2 * s ** 3) * b + (s ** 3 - s ** 2) * h * v[i + 1])
            lo, hi = 0.0, 1.0
            for _ in range(80):
                mid = 0.5 * (lo + hi)
                lo, hi = (lo, mid) if f(lo) * f(mid) <= 0.0 else (mid, hi)
            out.append(t[i] + 0.5 * (lo + hi) * h)
    return out


def oscillator(s, coord, states):
    """(m_q, K) of the coordinate's linear oscillator at the launch."""
    M = np.zeros(3)
    K.mass_matrix(s.par, states[0, 1], M)
    g = s.geom
    Rs = (g.R1, g.R4) if coord == 0 else (g.R2, g.R3)
    return (M[0] * M[2] - M[1] ** 2) / (M[2] if coord == 0 else M[0]), g.rim_stiffness * sum(R * R for R in Rs)


def contact(dt, coord, k, v, zeta=0.0, model="seated"):
    """Contact time, rate after it over the rate before, the kinetic energy
    after it and at the launch, the deepest overlap of the coordinate, the
    closed-form oscillator (m_q, K), the worst ledger residual over the
    launch energy, the stepper."""
    s, st, res, E0 = bounce(dt, coord, k, v, zeta, model)
    t = np.arange(len(st)) * dt
    qm = s.geom.qmax[coord]
    tin, tout = crossing_times(t, st[:, coord], st[:, 2 + coord], qm)
    after = int(math.ceil(tout / dt)) + 1
    T0 = K.kinetic(s.par, st[0, 1], st[0, 2], st[0, 3])
    T1 = K.kinetic(s.par, st[after, 1], st[after, 2], st[after, 3])
    mq, Kq = oscillator(s, coord, st)
    return dict(tc=tout - tin, ratio=st[after, 2 + coord] / v, T0=T0, T1=T1, over=np.max(st[:, coord]) - qm,
                mq=mq, K=Kq, res=np.max(np.abs(res)) / E0, s=s)


@pytest.mark.parametrize("coord, k, v", [(0, 1e6, 5e-5), (1, 1e7, 5e-5)], ids=["outer", "inner"])
def test_an_undamped_rim_spring_is_the_linear_oscillator(coord, k, v):
    """The rim alone (no gravity, no friction), undamped: the energy (kinetic
    + spring) is constant every step to 1e-10 of the launch energy; the
    contact gives back the launch's kinetic energy to 1e-10 (the speed in
    the kinetic metric) and the coordinate's rate reversed to 1e-6 (the
    other coordinate's motion bends the mass matrix: measured 4e-8, 8e-7);
    the contact time converges at second order to pi sqrt(m_q / K) (errors
    at dt = 1, 0.5, 0.25 ms each >= 3 times the next, the last < 1.5e-4 of
    it: measured 1.09e-3, 2.7e-4, 6.9e-5 outer; 1.10e-3, 2.8e-4, 7.2e-5
    inner) and the deepest overlap to v sqrt(m_q / K) within 1e-3: on the
    surface i, a peak force R_i v sqrt(k m_eff). A contact on each of the
    coordinate's surfaces, no impulse, no rim loss."""
    errs = []
    for dt in DTS:
        c = contact(dt, coord, k, v)
        assert c["res"] <= 1e-10
        assert abs(c["T1"] / c["T0"] - 1.0) <= 1e-10
        assert abs(c["ratio"] + 1.0) <= 1e-6
        ref = math.pi * math.sqrt(c["mq"] / c["K"])
        errs.append(abs(c["tc"] / ref - 1.0))
        s = c["s"]
        hits = s.S[K.S_NHIT:K.S_NHIT + 4]
        assert list(hits) == ([1.0, 0.0, 0.0, 1.0] if coord == 0 else [0.0, 1.0, 1.0, 0.0])
        assert s.E_rim == 0.0 and s.S[K.S_J] == 0.0
    assert errs[0] >= 3.0 * errs[1] and errs[1] >= 3.0 * errs[2] and errs[2] <= 1.5e-4, errs
    assert c["over"] == pytest.approx(v * math.sqrt(c["mq"] / c["K"]), rel=1e-3)


@pytest.mark.parametrize("model", ["seated", "two-phase"])
@pytest.mark.parametrize("coord, k, zeta, dt", [(0, 1e6, 0.2, 2.5e-4), (1, 1e7, 0.1, 2.5e-4), (0, 1e9, 0.3, 2.5e-5)],
                         ids=["outer", "inner", "outer-stiff"])
def test_a_damped_rim_hands_back_the_oscillators_restitution(coord, k, zeta, dt, model):
    """The dashpot 2 zeta sqrt(k m_eff) on each overlapping slide, m_eff =
    m_q / sum R_i^2: the coordinate leaves its rim at exp(-zeta pi /
    sqrt(1 - zeta^2)) of its arrival rate within 1e-3 (dt = 0.25 ms; k = 1e9:
    a contact of 0.9 ms, at dt = 25 us; measured 4.6e-5, 3.1e-5, 5.0e-4, both
    models), and E_rim_J (the dashpot's loss) is the kinetic energy lost
    to 1e-10 of the launch energy (with the two-phase model's re-seating),
    (1 - e^2) m_q v^2 / 2 within 1e-3 (measured 6.7e-5, 1.0e-4, 4.3e-4); the
    ledger closes every step."""
    c = contact(dt, coord, k, 5e-5, zeta, model)
    e = math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta * zeta))
    s = c["s"]
    assert -c["ratio"] == pytest.approx(e, abs=1e-3)
    s = c["s"]
    assert abs(s.E_rim + s.E_reseat - (c["T0"] - c["T1"])) <= 1e-10 * c["T0"]
    # the loss of the motion normal to the rim, (1 - e^2) m_q v^2 / 2
    assert s.E_rim == pytest.approx((1.0 - e * e) * 0.5 * c["mq"] * 5e-5 ** 2, rel=1e-3)
    assert c["res"] <= 1e-10
