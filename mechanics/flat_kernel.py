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

``advance`` is the whole step of the stepper (mechanics/flat.py FlatStepper
and the coupled engine, mechanics/dev_flat.py): ``step`` and then the
bookkeeping (friction work, input work, phase, slip speeds, the force, the
tipping check as a flag), on the state vector S.
"""
from . import bidirectional_kernel as bk
from fpd.tribology import rim_law as rl
from . import tfp_kernel as tk
from fpd.tribology.friction_kernel import holding_mu
from .phases import SLIP, STICK

__kernel__ = True

# C: the constants (``par`` of step(): its first two slots); I_VERT: 1 with a vertical
# ground record (the field g + a_z, model.md 10; the columns VERTICAL_COLUMNS follow),
# 2 with the test machine's axial-load programme (AZ: the load N per step, force control)
I_MPAD, I_MSUP, I_H, I_D, I_G, I_DT, I_MACH, I_VERT = 0, 1, 2, 3, 4, 5, 6, 7
# the rims (model.md 7, 9): the capacities |q1| <= d1, |q2| <= d2 (0: no rim; the columns
# RIM_COLUMNS follow the others when there are rims) and the restitution of an impact
I_CAP1, I_CAP2, I_REST = 8, 9, 10
# breakaway (friction_kernel.holding_mu): the faces' static coefficients and static ratios (0: none)
I_MUS1, I_MUS2, I_MUR1, I_MUR2 = 11, 12, 13, 14
# a rim of finite stiffness (model.md 7; 0: the rigid rim): the spring k (N/m) on each slip beyond
# its capacity, the dashpots 2 zeta sqrt(k m_eff) on q1 (m_eff = m) and q2 (m M / (m + M))
I_KRIM, I_CRIM1, I_CRIM2 = 15, 16, 17
N_PAR = 18
RIM_ITERS = 40            # Newton's iterations on the increment with rim springs (2 off the rims, a few on them)

# S: the state; step()'s st = S[0:4] = (q1, q2, q1', q2')
S_Q1, S_Q2, S_V1, S_V2 = 0, 1, 2, 3
S_N, S_T, S_F, S_N1, S_N2, S_W1, S_W2, S_EIN = 4, 5, 6, 7, 8, 9, 10, 11
S_PHASE, S_TIP, S_SV1, S_SV2, S_DEM, S_ERR = 12, 13, 14, 15, 16, 17
# the vertical ground acceleration of the last step (up); lift-off (model.md 10): in flight
# (1.0), the assembly's height above its seat and its rate (relative to the ground), the
# landings' loss (J), the lift-offs' count, the time spent in flight (s)
S_AZ, S_FLY, S_ZF, S_ZFD, S_ELAND, S_NLIFT, S_TFLY = 18, 19, 20, 21, 22, 23, 24
# the rims: their loss (J), the step's impact impulse (N s), the impacts per rim, on the rim
S_ERIM, S_JRIM, S_NRIM1, S_NRIM2, S_AT1, S_AT2 = 25, 26, 27, 28, 29, 30
N_S = 31
ERR_TIPPED = 1.0          # S[S_ERR]: the friction couple exceeded the resisting moment (the pad tips)
ERR_RIM = 2.0             # the test machine drove a face past its rim (the programme exceeds the capacity)

N_VALUES = 16             # len(mechanics.flat.COLUMNS)
N_RIM = 4                 # then, with rims: E_rim_J, J_rim_Ns, n_rim1, n_rim2
N_VERTICAL = 5            # then, with a vertical record: az_mps2, lift_m, n_lift, t_flight_s, E_land_J
# a landing this close to the step's end (relative to dt) ends the step: no seated remainder
FLIGHT_REST = 1e-12

O_DQ1, O_DQ2, O_F, O_EIN, O_W1, O_W2, O_FTOP, O_APAD, O_RLOSS = 0, 1, 2, 3, 4, 5, 6, 7, 8
N_OUT = 9


def kinetic(par, v1, v2):
    m, M = par[I_MPAD], par[I_MSUP]
    return 0.5 * ((m + M) * v1 * v1 + 2.0 * M * v1 * v2 + M * v2 * v2)


def step(par, st, dt, ag, c1, c2, machine, u1, ud1, out, w, lo1, hi1, lo2, hi2):
    """st = [q1, q2, v1, v2] (updated); c1 = mu1 N1 (lower face), c2 = mu2 N2
    (upper face); machine = 1 imposes u = q1 + q2 = u1 and u' = ud1 at t_n+1;
    lo, hi: bounds of the increments (a coordinate resting on its rim may
    not move into it: 0 on that side; else -big, big).
    out: increments, machine force F, input work, friction work per face (the
    arrests included), the horizontal force of the superstructure on the
    pad's top face, the pad's absolute acceleration, the rim dashpots' loss.
    With rim springs (par[I_KRIM]) their force (rim_law.slide) joins the
    step's: Newton's iteration on the increment, each solve the exact QP."""
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
    elif par[I_KRIM] == 0.0:
        tk.qp_box(h11, h12, h22, r1, r2, c1, c2, lo1, hi1, lo2, hi2, w)
    else:
        x1 = x2 = 0.0
        k, cap1, cap2 = par[I_KRIM], par[I_CAP1], par[I_CAP2]
        for _ in range(RIM_ITERS):
            f1, j1, _l1 = rl.slide(k, par[I_CRIM1], cap1, st[0], x1, dt)
            f2, j2, _l2 = rl.slide(k, par[I_CRIM2], cap2, st[1], x2, dt)
            tk.qp_box(h11 + j1, h12, h22 + j2, r1 - f1 + j1 * x1, r2 - f2 + j2 * x2, c1, c2, lo1, hi1, lo2, hi2, w)
            dx = abs(w[0] - x1) + abs(w[1] - x2)
            x1, x2 = w[0], w[1]
            if dx <= 1e-12 * (abs(x1) + abs(x2)):     # quadratic: the iterate then to round-off
                break
        out[O_RLOSS] = (rl.slide(k, par[I_CRIM1], cap1, st[0], x1, dt)[2]
                        + rl.slide(k, par[I_CRIM2], cap2, st[1], x2, dt)[2])
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


def resisting_moment(C, N_top, gv):
    """N D + m gv D / 2 about the trailing bottom corner (N m), in the field gv = g + a_z."""
    return N_top * C[I_D] + C[I_MPAD] * gv * C[I_D] / 2.0


def ground(C, U, XG, n):
    """The ground (lower plate) position at step n: -u in the machine, else the record's."""
    if C[I_MACH] != 0.0:
        return -U[n]
    return XG[n]


def flight(C, S, ag, gv, h, out, w):
    """Free flight of the moving assembly (pad and superstructure) over at most
    h (model.md 10): no contact with the faces, so no friction, no heat, no
    normal force. Relative to the ground both bodies feel -ag horizontally
    (q1'' = -ag, q2'' = 0: exact for the step's constant ag; the d'Alembert
    force's work is input) and -gv vertically: the height z above the seat
    obeys z'' = -gv, its work -(M + m)(gv - g) dz is input and (M + m) g z
    potential. Takes off (z = z' = 0) when not flying; lands when z returns
    to 0 inside h, with a plastic vertical impact ((M + m) z'^2 / 2 into
    E_land; the horizontal motion goes on). Rims of finite stiffness act in
    the air as on the seat (the lift is far below a rim's height): the
    horizontal motion is then ``step`` without friction over the time
    flown, their springs' force and dashpots in it (out[O_FTOP]: the upper
    rim's force on the superstructure). Returns the time flown (h, or the
    landing time)."""
    m, M = C[I_MPAD], C[I_MSUP]
    Mt = m + M
    for i in range(N_OUT):
        out[i] = 0.0
    if S[S_FLY] == 0.0:
        S[S_FLY] = 1.0
        S[S_NLIFT] += 1.0
        S[S_ZF] = 0.0
        S[S_ZFD] = 0.0
    z0, v0 = S[S_ZF], S[S_ZFD]
    tau = bk.smallest_positive_root(-0.5 * gv, v0, z0, 2.0 * h)
    landed = tau <= h
    if not landed:
        tau = h
    z1 = z0 + tau * (v0 - 0.5 * gv * tau)
    vz1 = v0 - gv * tau
    if landed:
        z1 = 0.0
    S[S_EIN] -= Mt * (gv - C[I_G]) * (z1 - z0)
    if C[I_KRIM] != 0.0:
        big = 1e30
        step(C, S, tau, ag, 0.0, 0.0, 0, 0.0, 0.0, out, w, -big, big, -big, big)
        S[S_EIN] += out[O_EIN]
        S[S_ERIM] += out[O_RLOSS]
        S[S_W1] += out[O_W1]        # (0 without friction: an arrest needs a cap)
        S[S_W2] += out[O_W2]
    else:
        v1, v2 = S[S_V1], S[S_V2]
        dq1 = tau * (v1 - 0.5 * ag * tau)
        dq2 = tau * v2
        S[S_Q1] += dq1
        S[S_Q2] += dq2
        S[S_V1] = v1 - ag * tau
        S[S_EIN] += -ag * (Mt * dq1 + M * dq2)
        out[O_DQ1] = dq1
        out[O_DQ2] = dq2
        out[O_APAD] = 0.0
    S[S_TFLY] += tau
    S[S_ZF] = z1
    S[S_ZFD] = vz1
    S[S_N1] = 0.0
    S[S_N2] = 0.0
    if landed:
        S[S_ELAND] += 0.5 * Mt * vz1 * vz1
        S[S_ZFD] = 0.0
        S[S_FLY] = 0.0
        S[S_N2] = M * gv
        S[S_N1] = M * gv + m * gv
    return tau


def _rim_side(q, cap):
    """+1 / -1 when q is at or past its rim (cap > 0), else 0."""
    if cap <= 0.0 or abs(q) < cap * (1.0 - 1e-12):
        return 0.0
    if q > 0.0:
        return 1.0
    return -1.0


def _touch(S, q, cap, i_at, i_n):
    """A contact of a rim of finite stiffness: counted as the slip passes the capacity."""
    if abs(q) > cap:
        if S[i_at] == 0.0:
            S[i_n] += 1.0
        S[i_at] = 1.0
    else:
        S[i_at] = 0.0


def rim(C, S, w):
    """The rims after a (part-)step (model.md 7): a coordinate past its rim
    is put back on it, and the velocities get the impulses of a rigid,
    frictionless unilateral stop on each coordinate at its rim: the linear
    complementarity problem of Newton's impact law (outward rate after <=
    -e times before, impulses >= 0 and only where that holds with equality),
    solved exactly by enumeration (the 2x2 matrix o_j o_k M^-1_jk is
    positive definite). An impulse on q1 is the lower rim's on the pad (it
    keeps the superstructure's momentum: the mass it sees is m); on q2 the
    upper rim's between pad and superstructure (mass m M / (m + M)). Each
    takes (1 - e^2) of the kinetic energy normal to it, booked with the
    rest of the change in E_rim. A coordinate arriving at its rim is an
    impact (counted, its impulse in S_JRIM, N s); one resting on it at the
    step's start was held by the step's bound (the rim's reaction is part
    of the step's forces). A rim of finite stiffness acts in the step (no
    impulse): here only its contacts are counted, as a face passes its capacity."""
    S[S_JRIM] = 0.0
    if C[I_KRIM] != 0.0:
        _touch(S, S[S_Q1], C[I_CAP1], S_AT1, S_NRIM1)
        _touch(S, S[S_Q2], C[I_CAP2], S_AT2, S_NRIM2)
        return
    o1 = _rim_side(S[S_Q1], C[I_CAP1])
    o2 = _rim_side(S[S_Q2], C[I_CAP2])
    if o1 == 0.0:
        S[S_AT1] = 0.0
    if o2 == 0.0:
        S[S_AT2] = 0.0
    if o1 == 0.0 and o2 == 0.0:
        return
    if o1 != 0.0:
        S[S_Q1] = o1 * C[I_CAP1]
    if o2 != 0.0:
        S[S_Q2] = o2 * C[I_CAP2]
    m, M = C[I_MPAD], C[I_MSUP]
    v1, v2 = S[S_V1], S[S_V2]
    e = C[I_REST]
    took = rl.impact_set(m + M, M, M, v1, v2, o1, o2, e)
    S[S_ERIM] += rl.impact(m + M, M, M, v1, v2, o1, o2, e, took, w)
    S[S_V1], S[S_V2] = w[0], w[1]
    # the impulses (each >= 0 away from its rim): M times the velocity change, on the
    # coordinates that took one
    l1 = 0.0
    l2 = 0.0
    if took == 1 or took == 3:
        l1 = -o1 * ((m + M) * (w[0] - v1) + M * (w[1] - v2))
    if took == 2 or took == 3:
        l2 = -o2 * (M * (w[0] - v1) + M * (w[1] - v2))
    if o1 != 0.0:
        if l1 > 0.0 and S[S_AT1] == 0.0:
            S[S_NRIM1] += 1.0
            S[S_JRIM] += l1
        S[S_AT1] = 1.0
    if o2 != 0.0:
        if l2 > 0.0 and S[S_AT2] == 0.0:
            S[S_NRIM2] += 1.0
            S[S_JRIM] += l2
        S[S_AT2] = 1.0


def advance(C, S, A, AZ, U, UD, mu1, mu2, out, w):
    """Step S[S_N] -> S[S_N] + 1 with mu1 (lower face), mu2 (upper face): A
    the ground acceleration per step, AZ the vertical one (up; read only with
    C[I_VERT]); U, UD the machine's programme per grid point (read only in
    the machine; with C[I_VERT] == 2 the machine's axial load N per step in
    AZ). out, w: step()'s scratch (out holds the step's increments
    after it: the friction work of the faces out[O_W1], out[O_W2]). Every
    normal force and friction cap sees gv = g + a_z; when gv < 0 the
    assembly lifts off (``flight``) and a step that lands finishes seated.
    Returns ERR_TIPPED when the dynamic tipping ratio |f_top H - m a H / 2|
    / (N D + m gv D / 2) exceeds 1 (also in S[S_ERR]; the state is the
    step's), else 0."""
    n = int(S[S_N])
    dt = C[I_DT]
    ag = A[n]
    az = 0.0
    if C[I_VERT] == 1.0:
        az = AZ[n]
        S[S_AZ] = az
    gv = C[I_G] + az
    h = dt
    seated = True
    f_air = 0.0                 # the upper rim spring's force on the superstructure in the air, x its share of dt
    if C[I_VERT] == 2.0:
        # the machine's vertical actuator holds N on the superstructure; the pad keeps its weight
        S[S_N2] = AZ[n]
        S[S_N1] = AZ[n] + C[I_MPAD] * C[I_G]
    if C[I_VERT] == 1.0:
        if S[S_FLY] == 0.0 and not gv < 0.0:
            S[S_N2] = C[I_MSUP] * gv
            S[S_N1] = C[I_MSUP] * gv + C[I_MPAD] * gv
        else:
            tf = flight(C, S, ag, gv, dt, out, w)
            f_air = out[O_FTOP] * (tf / dt)
            h = dt - tf
            if S[S_FLY] != 0.0 or not h > FLIGHT_REST * dt:
                seated = False
            elif gv < 0.0:             # landed while the field still lifts: off again
                f_air += out[O_FTOP] * (flight(C, S, ag, gv, h, out, w) / dt)
                seated = False
    if seated:
        # a face at rest at the step's start holds with the holding coefficient (the
        # TFP's rule: its cap in the convex step, docs/model.md section 11)
        # (the run's first step starts from rest: the machine's launch speed u'(0)
        # is given to a bearing that was at rest, which breaks away)
        if S[S_V1] == 0.0 or n == 0:
            mu1 = holding_mu(mu1, C[I_MUS1], C[I_MUR1])
        if S[S_V2] == 0.0 or n == 0:
            mu2 = holding_mu(mu2, C[I_MUS2], C[I_MUR2])
        c1 = mu1 * S[S_N1]
        c2 = mu2 * S[S_N2]
        big = 1e30
        if C[I_MACH] != 0.0:
            step(C, S, h, ag, c1, c2, 1, U[n + 1], UD[n + 1], out, w, -big, big, -big, big)
            S[S_F] = out[O_F]
        else:
            # a coordinate resting on its rim is held by it (the rim's reaction is then in
            # the step's forces; an arrival is an impact: ``rim`` after the step)
            lo1, hi1, lo2, hi2 = -big, big, -big, big
            if S[S_AT1] != 0.0 and C[I_KRIM] == 0.0:
                if S[S_Q1] > 0.0:
                    hi1 = 0.0
                else:
                    lo1 = 0.0
            if S[S_AT2] != 0.0 and C[I_KRIM] == 0.0:
                if S[S_Q2] > 0.0:
                    hi2 = 0.0
                else:
                    lo2 = 0.0
            step(C, S, h, ag, c1, c2, 0, 0.0, 0.0, out, w, lo1, hi1, lo2, hi2)
            # the bearing's force on the superstructure, against u: the top face's friction
            S[S_F] = out[O_FTOP]
            if h != dt:                # landed: the bearing carried nothing before (but a rim spring)
                S[S_F] = out[O_FTOP] * (h / dt)
                if C[I_KRIM] != 0.0:
                    S[S_F] += f_air
        S[S_W1] += out[O_W1]
        S[S_W2] += out[O_W2]
        S[S_EIN] += out[O_EIN]
        S[S_ERIM] += out[O_RLOSS]
        H = C[I_H]
        demand = abs(H * out[O_FTOP] - 0.5 * H * C[I_MPAD] * out[O_APAD])
        S[S_TIP] = demand / resisting_moment(C, S[S_N2], gv)
        S[S_DEM] = demand
    else:
        S[S_F] = f_air
        S[S_TIP] = 0.0
        S[S_DEM] = 0.0
    if C[I_MACH] == 0.0 and (C[I_CAP1] > 0.0 or C[I_CAP2] > 0.0):
        rim(C, S, w)
    dq1, dq2 = out[O_DQ1], out[O_DQ2]
    S[S_PHASE] = SLIP if (dq1 != 0.0 or dq2 != 0.0) else STICK
    S[S_SV1] = 0.0
    S[S_SV2] = 0.0
    if seated:
        S[S_SV1] = abs(dq1) / dt
        S[S_SV2] = abs(dq2) / dt
    S[S_N] = n + 1
    S[S_T] = (n + 1) * dt
    if S[S_TIP] > 1.0:
        S[S_ERR] = ERR_TIPPED
        return ERR_TIPPED
    if C[I_MACH] != 0.0 and (_past(S[S_Q1], C[I_CAP1]) or _past(S[S_Q2], C[I_CAP2])):
        S[S_ERR] = ERR_RIM
        return ERR_RIM
    return 0.0


def _past(q, cap):
    """q beyond its rim (cap > 0)."""
    return cap > 0.0 and abs(q) > cap * (1.0 + 1e-12)


def energies(C, S):
    """(E_kin, E_pot): the horizontal (1/2) q'^T M q', in flight the assembly's
    (M + m) z'^2 / 2 added, and its potential (M + m) g z, with the rim springs'."""
    Ek = kinetic(C, S[S_V1], S[S_V2])
    Ep = 0.0
    if S[S_ZF] != 0.0 or S[S_ZFD] != 0.0:
        Mt = C[I_MPAD] + C[I_MSUP]
        Ek += 0.5 * Mt * S[S_ZFD] * S[S_ZFD]
        Ep = Mt * C[I_G] * S[S_ZF]
    if C[I_KRIM] != 0.0:
        Ep += (rl.spring_energy(C[I_KRIM], rl.overlap(abs(S[S_Q1]) - C[I_CAP1]))
               + rl.spring_energy(C[I_KRIM], rl.overlap(abs(S[S_Q2]) - C[I_CAP2])))
    return Ek, Ep


def values(C, S, xg, row):
    """The row of mechanics.flat.COLUMNS into row (xg: the ground position now),
    then with a vertical record the N_VERTICAL columns."""
    row[0], row[1], row[2], row[3] = S[S_T], xg, S[S_Q1] + S[S_Q2], S[S_V1] + S[S_V2]
    row[4], row[5], row[6], row[7], row[8] = S[S_F], S[S_Q1], S[S_Q2], S[S_N1], S[S_N2]
    row[9], row[10], row[11], row[12] = S[S_W1], S[S_W2], S[S_PHASE], S[S_EIN]
    Ek, Ep = energies(C, S)
    row[13] = Ek
    row[14] = Ep
    row[15] = S[S_TIP]
    j = N_VALUES
    if C[I_CAP1] > 0.0 or C[I_CAP2] > 0.0:
        row[j], row[j + 1], row[j + 2], row[j + 3] = S[S_ERIM], S[S_JRIM], S[S_NRIM1], S[S_NRIM2]
        j += N_RIM
    if C[I_VERT] == 1.0:
        row[j], row[j + 1], row[j + 2], row[j + 3], row[j + 4] = S[S_AZ], S[S_ZF], S[S_NLIFT], S[S_TFLY], S[S_ELAND]
