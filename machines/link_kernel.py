"""The compliant link of the test machines (docs/model.md, "Stick-slip"),
written once (kernel module): a spring k = C[link] between the machine and
the plate of mass m_p, the machine's position linear in time between grid
points, in sub-steps. The plate's position u and velocity v are vectors in
the plane; the planar machine (seated_kernel) keeps them on its line (y
zero), the orbit machine (bidirectional_kernel) drives a straight programme
along its own. What is each machine's own is only the bearing's force on the
plate (its statics, ``machine_point``), what a slide books in its state and
where its constants live; the machine's kind (SEATED, ORBIT) picks them.

``seated_machine_step`` and ``orbit_machine_step`` are the machines' steps
(the rigid machine's, or the link's when the machine has one): what the
steppers and the compiled engine call.
"""
from __future__ import annotations

import math

from fpd.machines import seated_kernel as sk
from fpd.mechanics import bidirectional_kernel as bk
from fpd.mechanics.phases import SLIP, STICK
from fpd.tribology.friction_kernel import holding_mu_dwell

__kernel__ = True

SEATED, ORBIT = 0, 1


def _bearing(kind, C, ux, uy, vx, vy, ax, ay, hx, hy, mu1, mu2, gv):
    """The bearing's force on the plate (x, y) and its two normal forces at
    (u, u', u''), friction opposing the direction h (zero: none), and the
    pad's axis n (the orbit machine's; zeros on the planar one). gv: the
    planar machine's axial load over M."""
    if kind == SEATED:
        r = sk.machine_point(C, ux, vx, ax, gv, mu1, mu2, hx)
        return r[3], 0.0, r[4], r[5], 0.0, 0.0, 0.0
    r = bk.link_bearing(C, ux, uy, vx, vy, ax, ay, hx, hy, mu1, mu2)
    return r[0], r[1], r[2], r[3], r[4], r[5], r[6]


def _holding(kind, C, mu1, mu2, tw1, tw2):
    """The coefficients that hold a stuck surface after tw1, tw2 s stuck
    (friction_kernel.holding_mu_dwell), from the machine's constants."""
    if kind == SEATED:
        return (holding_mu_dwell(mu1, C[sk.CMUS1], C[sk.CMUR1], C[sk.CMUI1], C[sk.CTAU1], C[sk.CEXP1], tw1),
                holding_mu_dwell(mu2, C[sk.CMUS2], C[sk.CMUR2], C[sk.CMUI2], C[sk.CTAU2], C[sk.CEXP2], tw2))
    return (holding_mu_dwell(mu1, C[bk.C_MUS1], C[bk.C_MUR1], C[bk.C_MUI1], C[bk.C_TAU1], C[bk.C_EXP1], tw1),
            holding_mu_dwell(mu2, C[bk.C_MUS2], C[bk.C_MUR2], C[bk.C_MUI2], C[bk.C_TAU2], C[bk.C_EXP2], tw2))


def _force(kind, S, fx, fy):
    """The link's force on the plate into the machine's state (its force columns)."""
    if kind == SEATED:
        S[sk.SF] = fx
    else:
        S[bk.S_FX], S[bk.S_FY] = fx, fy


def _book(kind, C, S, ux, u1x, a0x, a0y, a1x, a1y, Fa, Fb, mu1, mu2):
    """A slide's friction work and input (the plate's force on the bearing and
    the moving plate's d'Alembert force, as the machine's rigid step books
    them) and its normal forces at the end, from the bearing's forces Fa, Fb
    at its ends."""
    if kind == SEATED:
        L, Sin, R1, R2 = C[sk.CL], C[sk.CSIN], C[sk.CR1], C[sk.CR2]
        th0, th1 = math.asin(ux / L), math.asin(u1x / L)
        dth = th1 - th0
        adth = abs(dth)
        S[sk.W1] += mu1 * 0.5 * (Fa[2] + Fb[2]) * R1 * adth
        S[sk.W2] += mu2 * 0.5 * (Fa[3] + Fb[3]) * R2 * adth
        S[sk.EIN] += 0.5 * ((Fa[0] * L + Sin * a0x) * math.cos(th0) + (Fb[0] * L + Sin * a1x) * math.cos(th1)) * dth
        S[sk.N1], S[sk.N2] = Fb[2], Fb[3]
        return
    L, R1, R2 = C[bk.C_L], C[bk.C_R1], C[bk.C_R2]
    dx, dy, dz = Fb[4] - Fa[4], Fb[5] - Fa[5], Fb[6] - Fa[6]
    ang = 2.0 * math.asin(0.5 * math.sqrt(dx * dx + dy * dy + dz * dz))
    S[bk.S_W1] += mu1 * 0.5 * (Fa[2] + Fb[2]) * R1 * ang
    S[bk.S_W2] += mu2 * 0.5 * (Fa[3] + Fb[3]) * R2 * ang
    Sin = C[bk.C_S]
    S[bk.S_EIN] += 0.5 * ((L * Fa[0] + Sin * a0x + L * Fb[0] + Sin * a1x) * dx
                          + (L * Fa[1] + Sin * a0y + L * Fb[1] + Sin * a1y) * dy)
    S[bk.S_N1], S[bk.S_N2] = Fb[2], Fb[3]
    S[bk.S_FF1], S[bk.S_FF2] = mu1 * Fb[2], mu2 * Fb[3]
    S[bk.S_SLIP1] += R1 * ang
    S[bk.S_SLIP2] += R2 * ang
    S[bk.S_DS1] += R1 * ang
    S[bk.S_DS2] += R2 * ang
    S[bk.S_DPHI] += ang


def _acc(kind, C, ux, uy, vx, vy, mx, my, hx, hy, mu1, mu2, gv, k, m):
    """The plate's acceleration: m_p u'' + F_b(u, u', u'') = k (u_m - u), F_b
    affine in u'' (machine_point), so u'' = (m_p 1 + B)^-1 (k (u_m - u) - F_b0)."""
    F0 = _bearing(kind, C, ux, uy, vx, vy, 0.0, 0.0, hx, hy, mu1, mu2, gv)
    Fa = _bearing(kind, C, ux, uy, vx, vy, 1.0, 0.0, hx, hy, mu1, mu2, gv)
    Fb = _bearing(kind, C, ux, uy, vx, vy, 0.0, 1.0, hx, hy, mu1, mu2, gv)
    m11, m21 = m + Fa[0] - F0[0], Fa[1] - F0[1]
    m12, m22 = Fb[0] - F0[0], m + Fb[1] - F0[1]
    rx, ry = k * (mx - ux) - F0[0], k * (my - uy) - F0[1]
    det = m11 * m22 - m12 * m21
    return (rx * m22 - m12 * ry) / det, (m11 * ry - m21 * rx) / det


def _slide(kind, C, S, ux, uy, vx, vy, m0x, m0y, m1x, m1y, tau, hx, hy, mu1, mu2, gv, k, m):
    """Slide over tau (velocity Verlet) with the machine from m0 to m1,
    friction opposing the direction h; a stop inside (the velocity's
    component along h through 0) ends the slide there, stuck (cubic in time:
    the acceleration linear between the ends). Books the slide (_book) and
    the link's force; returns (u, v, the time slid)."""
    a0x, a0y = _acc(kind, C, ux, uy, vx, vy, m0x, m0y, hx, hy, mu1, mu2, gv, k, m)
    vhx, vhy = vx + 0.5 * tau * a0x, vy + 0.5 * tau * a0y
    u1x, u1y = ux + tau * vhx, uy + tau * vhy
    a1x, a1y = _acc(kind, C, u1x, u1y, vhx, vhy, m1x, m1y, hx, hy, mu1, mu2, gv, k, m)
    v1x, v1y = vhx + 0.5 * tau * a1x, vhy + 0.5 * tau * a1y
    used = tau
    if v1x * hx + v1y * hy <= 0.0:
        # v(s) . h = v . h + (a0 . h) s + ((a1 - a0) . h) s^2 / (2 tau): its first zero in (0, tau]
        c0 = vx * hx + vy * hy
        c1 = a0x * hx + a0y * hy
        c2 = 0.5 * ((a1x - a0x) * hx + (a1y - a0y) * hy) / tau
        s_ = bk.smallest_positive_root(c2, c1, c0, tau)
        if not s_ <= tau:
            s_ = tau
        used = s_
        f = s_ * s_ * s_ / (6.0 * tau)
        u1x = ux + vx * s_ + 0.5 * a0x * s_ * s_ + (a1x - a0x) * f
        u1y = uy + vy * s_ + 0.5 * a0y * s_ * s_ + (a1y - a0y) * f
        a1x, a1y = a0x + (a1x - a0x) * s_ / tau, a0y + (a1y - a0y) * s_ / tau
        v1x, v1y = 0.0, 0.0
    mx = m0x + (m1x - m0x) * (used / tau)
    my = m0y + (m1y - m0y) * (used / tau)
    Fa = _bearing(kind, C, ux, uy, vx, vy, a0x, a0y, hx, hy, mu1, mu2, gv)
    Fb = _bearing(kind, C, u1x, u1y, v1x, v1y, a1x, a1y, hx, hy, mu1, mu2, gv)
    _book(kind, C, S, ux, u1x, a0x, a0y, a1x, a1y, Fa, Fb, mu1, mu2)
    _force(kind, S, k * (mx - u1x), k * (my - u1y))
    return u1x, u1y, v1x, v1y, used


def _steps(kind, C, S, U0x, U0y, U1x, U1y, ux, uy, vx, vy, gv, mu1, mu2, k, m, ns, tw1, tw2, dt):
    """One grid step of the machine (its position from U0 to U1) driving the
    plate (u, v) through the link, in ns sub-steps. Stuck (u' = 0): the
    bearing holds while the link's demand k (u_m - u) - F_b(u, 0, 0; no
    friction) stays inside the static cap along it (friction_kernel.
    holding_mu_dwell: grown by the time stuck so far, tw1, tw2, that of the
    sub-step's start), the breakaway located inside the sub-step (the demand
    linear in time); sliding: _slide, friction opposing the velocity. A
    straight programme keeps the plate on its line. Returns (u, v, the times
    stuck, whether it moved)."""
    h = dt / ns
    moved = False
    for j in range(ns):
        m0x = U0x + (U1x - U0x) * (j / ns)
        m0y = U0y + (U1y - U0y) * (j / ns)
        m1x = U0x + (U1x - U0x) * ((j + 1) / ns)
        m1y = U0y + (U1y - U0y) * ((j + 1) / ns)
        t0, rem = 0.0, h
        for _ in range(4):
            if not rem > 1e-12 * h:
                break
            max_ = m0x + (m1x - m0x) * (t0 / h)
            may = m0y + (m1y - m0y) * (t0 / h)
            if vx == 0.0 and vy == 0.0:
                hm1, hm2 = _holding(kind, C, mu1, mu2, tw1, tw2)
                F0 = _bearing(kind, C, ux, uy, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, gv)
                d1x, d1y = k * (m1x - ux) - F0[0], k * (m1y - uy) - F0[1]
                _force(kind, S, k * (m1x - ux), k * (m1y - uy))
                dm = math.sqrt(d1x * d1x + d1y * d1y)
                cap = 0.0
                if dm > 0.0:
                    Fc = _bearing(kind, C, ux, uy, 0.0, 0.0, 0.0, 0.0, d1x / dm, d1y / dm, hm1, hm2, gv)
                    cap = ((Fc[0] - F0[0]) * d1x + (Fc[1] - F0[1]) * d1y) / dm
                if dm <= cap:
                    tw1 += rem                  # stuck to the sub-step's end
                    tw2 += rem
                    break
                # the demand, linear in time from t0 to the sub-step's end, reaches the cap
                d0x, d0y = k * (max_ - ux) - F0[0], k * (may - uy) - F0[1]
                ex, ey = d1x - d0x, d1y - d0y
                qa = ex * ex + ey * ey
                qb = d0x * ex + d0y * ey
                qc = d0x * d0x + d0y * d0y - cap * cap
                x = 0.0
                if qa > 0.0 and qc < 0.0:
                    x = (-qb + math.sqrt(qb * qb - qa * qc)) / qa
                if x > 1.0:
                    x = 1.0
                t0 = t0 + x * rem
                rem = h - t0
                max_ = m0x + (m1x - m0x) * (t0 / h)
                may = m0y + (m1y - m0y) * (t0 / h)
                hx, hy = d1x / dm, d1y / dm
            else:
                vm = math.sqrt(vx * vx + vy * vy)
                hx, hy = vx / vm, vy / vm
            ux, uy, vx, vy, used = _slide(kind, C, S, ux, uy, vx, vy, max_, may, m1x, m1y, rem, hx, hy,
                                          mu1, mu2, gv, k, m)
            moved = True
            tw1, tw2 = 0.0, 0.0                 # slid: a stop from here dwells anew
            t0 = t0 + used
            rem = h - t0
    return ux, uy, vx, vy, tw1, tw2, moved


def seated_link_step(C, S, U, GV, mu1, mu2):
    """The planar machine's step through the link (seated_kernel's state:
    theta, theta'; the machine's position U per grid point, the axial load
    GV). Returns the friction work per interface."""
    L, dt = C[sk.CL], C[sk.CDT]
    i0 = int(S[sk.SN])
    i1 = i0 + 1
    w1, w2 = S[sk.W1], S[sk.W2]
    th = S[sk.TH]
    u = L * math.sin(th)
    v = L * math.cos(th) * S[sk.THD]
    u, _, v, _, tw1, tw2, moved = _steps(SEATED, C, S, U[i0], 0.0, U[i1], 0.0, u, 0.0, v, 0.0, GV[i1], mu1, mu2,
                                         C[sk.CLINK], C[sk.CMPL], int(C[sk.CNSUB]), S[sk.SDW1], S[sk.SDW2], dt)
    S[sk.SDW1], S[sk.SDW2] = tw1, tw2
    th1 = math.asin(u / L)
    S[sk.TH] = th1
    S[sk.THD] = v / (L * math.cos(th1))
    S[sk.MODE] = SLIP if moved else STICK
    S[sk.SV1] = C[sk.CR1] * abs(S[sk.THD])
    S[sk.SV2] = C[sk.CR2] * abs(S[sk.THD])
    S[sk.SN] = i1
    S[sk.ST] = i1 * dt
    return S[sk.W1] - w1, S[sk.W2] - w2


def orbit_link_step(C, S, U, i, mu1, mu2):
    """Grid point i -> i + 1 of the orbit machine through the link
    (bidirectional_kernel's state: the pad axis n and its rate w; U the
    machine's position per grid point, (n + 1, 2)). Returns the flag."""
    L = C[bk.C_L]
    S[bk.S_DS1] = S[bk.S_DS2] = S[bk.S_DPHI] = 0.0
    ux, uy, vx, vy, tw1, tw2, moved = _steps(ORBIT, C, S, U[i, 0], U[i, 1], U[i + 1, 0], U[i + 1, 1],
                                             L * S[bk.S_NX], L * S[bk.S_NY], L * S[bk.S_WX], L * S[bk.S_WY],
                                             C[bk.C_G], mu1, mu2, C[bk.C_LINK], C[bk.C_MPL], int(C[bk.C_NSUB]),
                                             S[bk.S_DW1], S[bk.S_DW2], C[bk.C_DT])
    S[bk.S_DW1], S[bk.S_DW2] = tw1, tw2
    nx, ny = ux / L, uy / L
    nz = -math.sqrt(1.0 - nx * nx - ny * ny)
    wx, wy = vx / L, vy / L
    S[bk.S_NX], S[bk.S_NY], S[bk.S_NZ] = nx, ny, nz
    S[bk.S_WX], S[bk.S_WY], S[bk.S_WZ] = wx, wy, -(nx * wx + ny * wy) / nz
    S[bk.S_MODE] = SLIP if moved else STICK
    if moved and (S[bk.S_DS1] > 0.0):
        S[bk.S_DIRX] = vx if vx != 0.0 else S[bk.S_DIRX]
    w = math.sqrt(S[bk.S_WX] * S[bk.S_WX] + S[bk.S_WY] * S[bk.S_WY] + S[bk.S_WZ] * S[bk.S_WZ])
    S[bk.S_SV1], S[bk.S_SV2] = C[bk.C_R1] * w, C[bk.C_R2] * w
    return bk.FLAG_OK


def seated_machine_step(C, S, U, UD, UDD, SM, UDS, UDDS, GV, mu1, mu2):
    """The planar machine's step (seated_kernel.machine_step), through the
    link when it has one (C[CLINK] > 0). Returns the friction work per interface."""
    if C[sk.CLINK] > 0.0:
        return seated_link_step(C, S, U, GV, mu1, mu2)
    return sk.machine_step(C, S, U, UD, UDD, SM, UDS, UDDS, GV, mu1, mu2)


def orbit_machine_step(C, S, U, UD, UDD, GV, i, mu1, mu2):
    """The orbit machine's step (bidirectional_kernel.machine_step), through
    the link when it has one (C[C_LINK] > 0). Returns the flag."""
    if C[bk.C_LINK] > 0.0:
        return orbit_link_step(C, S, U, i, mu1, mu2)
    return bk.machine_step(C, S, U, UD, UDD, GV, i, mu1, mu2)
