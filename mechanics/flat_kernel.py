"""Per-step physics of the flat double friction bearing (paper, Fig. 2), one source.

Kernel module (fpd/kernels.py). A cylinder (the pad, mass m, diameter D,
height H) between two flat plates; the superstructure (mass M) on top; no
restoring force. Coordinates q = (q1, q2): q1 the pad's slip on the lower
plate, q2 the superstructure's slip on the pad (u = q1 + q2). The kinetic
energy is (1/2) q'^T M q' with the constant M = [[m + M, M], [M, M]]; the
ground acceleration works through b(q) = (m + M) q1 + M q2. Same
energy-consistent Moreau step as the TFP (mechanics/tfp_kernel.py, whose
exact minimisers it reuses): friction impulses in Sgn(dq), trapezoidal
positions, a stuck coordinate ends at rest (its kinetic energy to friction).
"""
from . import tfp_kernel as tk

__kernel__ = True

I_MPAD, I_MSUP = 0, 1
N_PAR = 2

O_DQ1, O_DQ2, O_F, O_EIN, O_W1, O_W2, O_FTOP, O_APAD = 0, 1, 2, 3, 4, 5, 6, 7
N_OUT = 8


def kinetic(par, v1, v2):
    m, M = par[I_MPAD], par[I_MSUP]
    return 0.5 * ((m + M) * v1 * v1 + 2.0 * M * v1 * v2 + M * v2 * v2)


def step(par, st, dt, ag, c1, c2, machine, u1, ud1, out, w):
    """st = [q1, q2, v1, v2] (updated); c1 = mu1 N1 (lower face), c2 = mu2 N2
    (upper face); machine = 1 imposes u = q1 + q2 = u1 and u' = ud1 at t_n+1.
    out: increments, machine force F, input work, friction work per face (the
    arrests included), the horizontal force of the superstructure on the
    pad's top face, the pad's absolute acceleration."""
    m, M = par[I_MPAD], par[I_MSUP]
    for i in range(N_OUT):
        out[i] = 0.0
    v10, v20 = st[2], st[3]
    m11, m12, m22 = m + M, M, M
    p1 = m11 * v10 + m12 * v20
    p2 = m12 * v10 + m22 * v20
    G1 = -ag * (m + M)
    G2 = -ag * M
    h11 = 2.0 * m11 / (dt * dt)
    h12 = 2.0 * m12 / (dt * dt)
    h22 = 2.0 * m22 / (dt * dt)
    r1 = 2.0 * p1 / dt + G1
    r2 = 2.0 * p2 / dt + G2
    big = 1e30
    e = 0.0
    if machine == 1:
        e = u1 - (st[0] + st[1])
        if tk.qp_line(h11, h12, h22, r1, r2, c1, c2, -big, big, -big, big, 1.0, 1.0, e, w) != 0:
            return
    else:
        tk.qp_box(h11, h12, h22, r1, r2, c1, c2, -big, big, -big, big, w)
    x1, x2 = w[0], w[1]
    Phi1 = r1 - (h11 * x1 + h12 * x2)
    Phi2 = r2 - (h12 * x1 + h22 * x2)
    pn1 = p1 + dt * (G1 - Phi1)
    pn2 = p2 + dt * (G2 - Phi2)
    det = m11 * m22 - m12 * m12
    v11 = (m22 * pn1 - m12 * pn2) / det
    v21 = (m11 * pn2 - m12 * pn1) / det
    s1 = 1.0 if x1 > 0.0 else (-1.0 if x1 < 0.0 else 0.0)
    s2 = 1.0 if x2 > 0.0 else (-1.0 if x2 < 0.0 else 0.0)
    F = 0.0
    if machine == 1:
        # Phi_k = c_k s_k - F (grad u = (1, 1)), from a coordinate that slides
        if s2 != 0.0:
            F = c2 * s2 - Phi2
        elif s1 != 0.0:
            F = c1 * s1 - Phi1
    # friction force of the superstructure on the pad's top face (the couple's upper force):
    # minus the top face's generalised friction force on q2 (the machine's share removed)
    f_top = Phi2 + F
    K0 = kinetic(par, v11, v21)
    a1 = 0.0
    a2 = 0.0
    if s1 == 0.0 and s2 == 0.0:
        # split as in the TFP: coordinate 1 first (an impulse on it keeps p2), then the rest
        Ka = kinetic(par, 0.0, (m12 * v11 + m22 * v21) / m22)
        a1 = K0 - Ka
        a2 = Ka
        v11 = 0.0
        v21 = 0.0
    elif s1 == 0.0:
        v21 = (m12 * v11 + m22 * v21) / m22
        v11 = 0.0
        a1 = K0 - kinetic(par, v11, v21)
    elif s2 == 0.0:
        v11 = (m11 * v11 + m12 * v21) / m11
        v21 = 0.0
        a2 = K0 - kinetic(par, v11, v21)
    mk = 0.0
    if machine == 1:
        Kb = kinetic(par, v11, v21)
        if s1 != 0.0 and s2 != 0.0:
            # impulse along grad u = (1, 1): dv = P M^-1 (1, 1)
            w1 = (m22 - m12) / det
            w2 = (m11 - m12) / det
            P = (ud1 - (v11 + v21)) / (w1 + w2)
            v11 += P * w1
            v21 += P * w2
        elif s1 != 0.0:
            v11 = ud1
        elif s2 != 0.0:
            v21 = ud1
        mk = kinetic(par, v11, v21) - Kb
    out[O_APAD] = ag + (v11 - st[2]) / dt
    st[0] += x1
    st[1] += x2
    st[2] = v11
    st[3] = v21
    out[O_DQ1] = x1
    out[O_DQ2] = x2
    out[O_F] = F
    out[O_EIN] = -ag * ((m + M) * x1 + M * x2) + F * e + mk
    out[O_W1] = c1 * abs(x1) + a1
    out[O_W2] = c2 * abs(x2) + a2
    out[O_FTOP] = f_top
