"""The paper's two-phase model of the TFP in both horizontal directions, one
source (kernel module, fpd/kernels.py): docs/model.md section 6.9.

The planar two-phase model (mechanics/tfp_kernel.py with I_TWO, docs/model.md
6.6) on the four coordinates of the seated 3D TFP (mechanics/tfp3d_kernel.py,
6.8): in phase 1 every part moves along its seated tangent at t_n, so the
kinetic metric is M(q_n), frozen over the step, and there is no
velocity-dependent force; gravity and the ground work through the discrete
gradients of the seated 3D step; the increment is the minimiser of the same
second-order cone program with H = 2 M(q_n) / dt^2. A block that stuck is set
to rest in the phase-1 field; phases 2 and 3 re-seat the parts at q_n+1, the
M-orthogonal projection of the phase-1 velocity field (bodies and spins) onto
the seated tangent space there, whose loss is E_reseat. The pivots of phase 1
lie in the plane of each pair's step (the pad's: the plane of its axis and
its slide; the slider plates': the plane of theirs): the planar TFP's
``pad_pivot`` and ``stack_pivot`` there, written as tilt vectors along the
step. The rocking check from rest is the planar one in the vertical plane of
the ground acceleration.

Every physical function is the planar TFP's or the seated 3D TFP's; this
module only orders them into the two-phase step.
"""
import math

from . import tfp3d_kernel as k3
from . import tfp_kernel as tk

__kernel__ = True

# -- state: the seated 3D TFP's (tfp3d_kernel.S_*), then the two-phase model's ------------------
S_ERS = k3.N_S           # the re-seating loss so far (J)
S_B1 = k3.N_S + 1        # the pad's phase-1 pivot as a tilt vector (x, y), rad
S_B2 = k3.N_S + 3        # its re-seating rotation (x, y)
S_G1 = k3.N_S + 5        # the slider plates' phase-1 pivot (x, y)
S_G2 = k3.N_S + 7        # their re-seating rotation (x, y)
S_NPH = k3.N_S + 9       # phases of the step: 0 stick, 2 one pair, 3 both; -1 rocking from rest
N_S = k3.N_S + 10

N_ROW_TWO = 10           # len(mechanics.tfp3d_two_phase.TWO_PHASE_COLUMNS)
N_ROW = k3.N_ROW + N_ROW_TWO

O_RESEAT = k3.N_OUT      # the step's re-seating loss, after the seated 3D step's outputs
N_OUT = k3.N_OUT + 1
FAIL_ROCKING = tk.FAIL_ROCKING


def axis(vx, vy, o, k):
    """e(v), the unit axis of the tilt vector v (tfp3d_kernel's), into o[k:k+3]."""
    t = vx * vx + vy * vy
    s = k3.sfun(t)
    o[k] = -s * vx
    o[k + 1] = -s * vy
    o[k + 2] = 1.0 - k3.omc(t)


def cross(o, a, b, c):
    """o[c:c+3] = o[a:a+3] x o[b:b+3]."""
    o[c] = o[a + 1] * o[b + 2] - o[a + 2] * o[b + 1]
    o[c + 1] = o[a + 2] * o[b] - o[a] * o[b + 2]
    o[c + 2] = o[a] * o[b + 1] - o[a + 1] * o[b]


def _dot(o, a, b):
    return o[a] * o[b] + o[a + 1] * o[b + 1] + o[a + 2] * o[b + 2]


def linv(Lm, blk, a0, a1):
    """L^-1 (a0, a1) for the block blk of the arc metric Lm (tfp3d_kernel.metric_root)."""
    k = 4 * blk
    return (Lm[k + 2] * a0 - Lm[k + 1] * a1) / Lm[k + 3], (Lm[k] * a1 - Lm[k + 1] * a0) / Lm[k + 3]


def matvec(A, x, o):
    """o = A x, A 4x4 row-major."""
    for i in range(4):
        o[i] = A[4 * i] * x[0] + A[4 * i + 1] * x[1] + A[4 * i + 2] * x[2] + A[4 * i + 3] * x[3]


def stop_block(M, v, blk, p):
    """An impulse on block blk alone brings it to rest: the other block keeps
    its momentum p = M v (into p), its rates M_oo^-1 p_o."""
    matvec(M, v, p)
    o = 2 - 2 * blk
    m11, m12, m22 = M[5 * o], M[5 * o + 1], M[5 * o + 5]
    det = m11 * m22 - m12 * m12
    v[2 * blk] = 0.0
    v[2 * blk + 1] = 0.0
    v[o] = (m22 * p[o] - m12 * p[o + 1]) / det
    v[o + 1] = (m11 * p[o + 1] - m12 * p[o]) / det


def reseat(par, q0, q1, v, w, sc):
    """Phases 2 and 3 (docs/model.md 6.9): the phase-1 velocity field, every body
    k moving with -a_k X0 - b_k Y0 (X0 = De(phi0)[phi'], Y0 = De(psi0)[psi'])
    and turning with e(phi0) x X0, e(psi0) x Y0, projected in the kinetic-energy
    metric onto the seated tangent space at q1: p = J(q1)^T M_bodies J(q0) v,
    w = M(q1)^-1 p. Returns the kinetic energy removed, the energy of the part
    stopped, 1/2 |J(q0) v - J(q1) w|^2 in the bodies' masses (body by body, no
    cancellation). With y = 0 it is tfp_kernel.reseat. sc: scratch >= 100."""
    Aa, B, K = par[tk.I_AA], par[tk.I_B], par[tk.I_K]
    Jphi, Jpsi = par[tk.I_JPHI], par[tk.I_JPSI]
    p0x, p0y = q0[0], q0[1]
    s0x, s0y = q0[0] + q0[2], q0[1] + q0[3]
    p1x, p1y = q1[0], q1[1]
    s1x, s1y = q1[0] + q1[2], q1[1] + q1[3]
    # the phase-1 field: X0, Y0 and the spins e0 x X0, e0 x Y0
    k3.de(p0x, p0y, v[0], v[1], sc, 0)                  # X0
    k3.de(s0x, s0y, v[0] + v[2], v[1] + v[3], sc, 3)    # Y0
    axis(p0x, p0y, sc, 6)
    axis(s0x, s0y, sc, 9)
    cross(sc, 6, 0, 12)                                 # the stack's spin
    cross(sc, 9, 3, 15)                                 # the pad's spin
    axis(p1x, p1y, sc, 18)
    axis(s1x, s1y, sc, 21)
    # p_j = E1_j . (bodies' momenta) + spins' (e1 x E1_j) . (J omega0)
    for j in range(2):
        ux = 1.0 if j == 0 else 0.0
        uy = 1.0 - ux
        k3.de(p1x, p1y, ux, uy, sc, 24)                 # De(phi1)[u]
        k3.de(s1x, s1y, ux, uy, sc, 27)                 # De(psi1)[u]
        cross(sc, 18, 24, 30)
        cross(sc, 21, 27, 33)
        pa = K * _dot(sc, 27, 0) + B * _dot(sc, 27, 3) + Jpsi * _dot(sc, 33, 15)
        sc[40 + j] = Aa * _dot(sc, 24, 0) + K * _dot(sc, 24, 3) + Jphi * _dot(sc, 30, 12) + pa
        sc[42 + j] = pa
    k3.mass_matrix(par, q1, sc[44:60], sc[60:72])
    k3.chol_solve(sc[44:60], sc[40:44], w, sc[72:88])
    # the loss: the part stopped, body by body
    k3.de(p1x, p1y, w[0], w[1], sc, 24)                 # X1
    k3.de(s1x, s1y, w[0] + w[2], w[1] + w[3], sc, 27)   # Y1
    cross(sc, 18, 24, 30)
    cross(sc, 21, 27, 33)
    for i in range(3):
        sc[i] -= sc[24 + i]          # dX
        sc[3 + i] -= sc[27 + i]      # dY
        sc[12 + i] -= sc[30 + i]     # the stack's spin change
        sc[15 + i] -= sc[33 + i]     # the pad's
    return 0.5 * (Aa * _dot(sc, 0, 0) + B * _dot(sc, 3, 3) + 2.0 * K * _dot(sc, 0, 3)
                  + Jphi * _dot(sc, 12, 12) + Jpsi * _dot(sc, 15, 15))


def step(par, st, dt, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc):
    """One two-phase step. st = [phi(2), alpha(2), rates(4)] (updated): phase 1
    in the frozen metric M(q0) (the increment the minimiser of tfp3d_kernel's
    cone program with H = 2 M(q0) / dt^2 and the discrete gradients of
    V + ag . b + az b_z, without T's), arrests in the phase-1 field, the
    re-seating at q1. machine = 1: the test machine imposes u(t_n+1) = (u1x,
    u1y) through the constraint of the seated 3D step (its force the
    multiplier, tfp3d_kernel.machine_force, started from sc[256:258]) and,
    after the re-seating, u'(t_n+1) = (ud1x, ud1y) through the sliding blocks
    (tfp3d_kernel.machine_velocity). out: tfp3d_kernel's O_*, and O_RESEAT.
    sc: scratch of length tfp3d_kernel.N_SC."""
    for i in range(N_OUT):
        out[i] = 0.0
    q0 = sc[100:104]
    q1 = sc[104:108]
    p0 = sc[108:112]
    x = sc[112:116]
    G = sc[116:120]
    H = sc[120:136]
    r = sc[136:140]
    Hy = sc[140:156]
    ry = sc[156:160]
    y = sc[160:164]
    Lm = sc[164:172]
    z4 = sc[172:176]
    tmp = sc[180:200]
    M0 = sc[260:276]
    v = sc[276:280]
    w = sc[280:284]
    for i in range(4):
        q0[i] = st[i]
        z4[i] = 0.0
    k3.mass_matrix(par, q0, M0, tmp)
    matvec(M0, st[4:8], p0)
    kk = 2.0 / (dt * dt)
    for i in range(16):
        H[i] = kk * M0[i]
    k3.metric_root(q0[0], q0[1], Lm, 0)
    k3.metric_root(q0[2], q0[3], Lm, 4)
    # the frozen metric: H' once for the step
    for i in range(4):
        r[i] = 0.0
    k3._to_metric(H, r, Lm, Hy, ry, tmp)
    for i in range(4):
        x[i] = dt * st[4 + i]
        y[i] = 0.0
    D = sc[240:248]
    Dy = sc[248:256]
    Fm = sc[256:258]
    ex = 0.0
    ey = 0.0
    mfail = False
    if machine == 1:
        k3.u_rel(par, q0, tmp)
        ex = u1x - tmp[0]
        ey = u1y - tmp[1]
    it = 0
    converged = False
    ch = 0.0
    while it < k3.FIXED_POINT_ITERS:
        it += 1
        for i in range(4):
            q1[i] = q0[i] + x[i]
        k3.dgrad(par, q0, q1, z4, agx, agy, az, G, sc)
        for i in range(4):
            r[i] = 2.0 * p0[i] / dt + G[i]
        for blk in range(2):
            ry[2 * blk], ry[2 * blk + 1] = linv(Lm, blk, r[2 * blk], r[2 * blk + 1])
        if machine == 1:
            # D: the discrete gradient of u (D^T dq = u(q1) - u(q0)); in y, L^-1 D
            k3.dgrad_u(par, q0, q1, D, sc)
            for i0 in range(0, 4, 2):
                for c in range(2):
                    Dy[2 * i0 + c], Dy[2 * i0 + 2 + c] = linv(Lm, i0 // 2, D[2 * i0 + c], D[2 * i0 + 2 + c])
            mfail = k3.machine_force(Hy, ry, Dy, c_o, c_i, ex, ey, y, Fm, sc) != 0
        else:
            k3.socp(Hy, ry, c_o, c_i, y, sc)
        ch = 0.0
        for blk in range(2):
            a0, a1 = linv(Lm, blk, y[2 * blk], y[2 * blk + 1])
            ch += abs(a0 - x[2 * blk]) + abs(a1 - x[2 * blk + 1])
            x[2 * blk] = a0
            x[2 * blk + 1] = a1
        if ch <= k3.FIXED_POINT_TOL:
            converged = True
            break
    if not converged and ch > 1e-12 * (1.0 + abs(x[0]) + abs(x[1]) + abs(x[2]) + abs(x[3])):
        out[k3.O_FAIL] = k3.FAIL_FIXED_POINT
    if mfail:
        out[k3.O_FAIL] = k3.FAIL_CAPACITY
    if machine == 1:
        # the cone program the machine's force makes: r' + Dy F (Phi = r - H dq
        # below is friction less the machine's force: p1 takes both)
        for i in range(4):
            ry[i] += Dy[2 * i] * Fm[0] + Dy[2 * i + 1] * Fm[1]
    out[k3.O_KKT] = k3.kkt_residual(Hy, ry, c_o, c_i, y)
    # Phi = r - H dq; p1 = p0 + dt (G - Phi); the phase-1 rates v = M(q0)^-1 p1
    for i in range(4):
        q1[i] = q0[i] + x[i]
    matvec(H, x, tmp[4:8])
    for i in range(4):
        tmp[i] = p0[i] + dt * (G[i] - (r[i] - tmp[4 + i]))
    k3.chol_solve(M0, tmp[0:4], v, sc[200:216])
    wo = c_o * math.sqrt(y[0] * y[0] + y[1] * y[1])
    wi = c_i * math.sqrt(y[2] * y[2] + y[3] * y[3])
    k3.moments(par, q0, tmp)
    b0x, b0y, b0z = tmp[0], tmp[1], tmp[2]
    k3.moments(par, q1, tmp)
    ein = -agx * (tmp[0] - b0x) - agy * (tmp[1] - b0y) - az * (tmp[2] - b0z)
    if machine == 1:
        # the machine's work: F . (D^T dq)
        for i in range(4):
            ein += (D[2 * i] * Fm[0] + D[2 * i + 1] * Fm[1]) * x[i]
        out[k3.O_FX] = Fm[0]
        out[k3.O_FY] = Fm[1]
    # a block that stuck ends at rest in the phase-1 field (metric M(q0)): an
    # impulse on it alone, the other block keeping its momentum
    z1 = x[0] == 0.0 and x[1] == 0.0
    z2 = x[2] == 0.0 and x[3] == 0.0
    arr_o = 0.0
    arr_i = 0.0
    if z1 or z2:
        K0 = k3.kinetic(par, q0, v, tmp[8:20])
        stop_block(M0, v, 0 if z1 else 1, tmp)
        Ka = k3.kinetic(par, q0, v, tmp[8:20])
        if z1:
            arr_o = K0 - Ka
            if z2:
                v[2] = 0.0
                v[3] = 0.0
                arr_i = Ka
        else:
            arr_i = K0 - Ka
    # phases 2 and 3: re-seated at q1 (what the projection leaves on a block
    # that stuck is the next step's to hold or not, against its cap)
    out[O_RESEAT] = reseat(par, q0, q1, v, w, sc)
    for i in range(4):
        st[i] = q1[i]
        st[4 + i] = w[i]
    if machine == 1:
        # the machine imposes u'(t_n+1) through the blocks still sliding, in M(q1)
        k3.mass_matrix(par, q1, H, tmp)
        ein += k3.machine_velocity(par, st, H, z1, z2, ud1x, ud1y, sc)
    for i in range(4):
        out[k3.O_DQ + i] = x[i]
    out[k3.O_EIN] = ein
    out[k3.O_WO] = wo + arr_o
    out[k3.O_WI] = wi + arr_i
    out[k3.O_ARR_O] = arr_o
    out[k3.O_ARR_I] = arr_i
    out[k3.O_ITER] = it
    tp = st[0] * st[0] + st[1] * st[1]
    ta = st[2] * st[2] + st[3] * st[3]
    qa = par[tk.I_QMAX_ALPHA]
    if tp > par[tk.I_QMAX_PHI] * par[tk.I_QMAX_PHI] or ta > qa * qa:
        out[k3.O_FAIL] = k3.FAIL_RIM


def rocking_from_rest(par, q, agx, agy, gv):
    """Eq. 7 at rest (tfp_kernel.rocking_in_field) in the vertical plane of the
    ground acceleration (of the pad's tilt without one; x without either),
    with the tilts' components in that plane: 1 the pad, 2 the slider plates, 0 neither."""
    ex, ey = agx, agy
    n = math.sqrt(ex * ex + ey * ey)
    if n == 0.0:
        ex, ey = q[0] + q[2], q[1] + q[3]
        n = math.sqrt(ex * ex + ey * ey)
    if n == 0.0:
        ex, ey, n = 1.0, 0.0, 1.0
    ex, ey = ex / n, ey / n
    return tk.rocking_in_field(par, q[0] * ex + q[1] * ey, q[2] * ex + q[3] * ey, agx * ex + agy * ey, gv)


def pivots(par, S, q0, dq, sc):
    """The phase-1 pivots and re-seating rotations of the step dq from q0 into
    S[S_B1:S_B1+8] (docs/model.md 6.9); returns the number of pairs that slid.
    sc: scratch >= 8."""
    n = 0
    for blk in range(2):
        dx = dq[2 * blk]
        dy = dq[2 * blk + 1]
        i0 = S_G1 if blk == 0 else S_B1
        for k in range(4):
            S[i0 + k] = 0.0
        if dx == 0.0 and dy == 0.0:
            continue
        n += 1
        k3.metric_root(q0[2 * blk], q0[2 * blk + 1], sc, 0)
        yx = sc[0] * dx + sc[1] * dy
        yy = sc[1] * dx + sc[2] * dy
        arc = math.sqrt(yx * yx + yy * yy)
        ux, uy = yx / arc, yy / arc
        # the pad's in the plane of its slide; the slider plates' with the pad's tilt in theirs
        b = tk.pad_pivot(par, arc) if blk == 1 else tk.stack_pivot(par, q0[2] * ux + q0[3] * uy, arc)
        S[i0] = b * ux
        S[i0 + 1] = b * uy
        S[i0 + 2] = (arc - b) * ux
        S[i0 + 3] = (arc - b) * uy
    return n


# -- the whole step of the stepper (mechanics/tfp3d_two_phase.py and the compiled loop) ---------
def advance(par, S, dt, agx, agy, az, mu1, mu2, mu3, mu4, machine, u1x, u1y, ud1x, ud1y, out, sc):
    """tfp3d_kernel.advance with the two-phase step (machine = 1: the test
    machine along an orbit, u(t_n+1) = (u1x, u1y), u'(t_n+1) = (ud1x, ud1y),
    its force the last step's in the normal forces): normal forces at the start of the
    step, caps, ``step``, the friction work of each surface, the bearing's
    force, phase, regime, sliding flags and speeds, then the phases and the
    rocking check. Returns the failure flag (tfp3d_kernel.FAIL_*, FAIL_ROCKING)."""
    N = S[k3.S_N:k3.S_N + 4]
    fx = S[k3.S_F] if machine == 1 else 0.0
    fy = S[k3.S_F + 1] if machine == 1 else 0.0
    k3.normal_forces(par, S[0:4], S[4:8], agx, agy, az, fx, fy, N, sc[200:220])
    # a coordinate at rest (did not slide in the step before) holds with the static coefficient
    mu1, mu2, mu3, mu4 = tk.holding_caps(par, S[k3.S_SLIDE], S[k3.S_SLIDE + 1], mu1, mu2, mu3, mu4)
    R1, R2, R3, R4 = par[tk.I_R1], par[tk.I_R2], par[tk.I_R3], par[tk.I_R4]
    a1 = mu1 * N[0] * R1
    a4 = mu4 * N[3] * R4
    a2 = mu2 * N[1] * R2
    a3 = mu3 * N[2] * R3
    c_o = a1 + a4
    c_i = a2 + a3
    k3.u_dot(par, S[0:4], S[4:8], sc, 220)
    ux0, uy0 = sc[220], sc[221]
    for i in range(4):
        sc[228 + i] = S[i]
    rest0 = S[4] == 0.0 and S[5] == 0.0 and S[6] == 0.0 and S[7] == 0.0
    sc[256] = S[k3.S_F]         # the machine's force: Newton starts from the last step's
    sc[257] = S[k3.S_F + 1]
    step(par, S[0:8], dt, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc)
    fail = int(out[k3.O_FAIL])
    S[k3.S_ITER] = out[k3.O_ITER]
    S[k3.S_KKT] = out[k3.O_KKT]
    wo = out[k3.O_WO]
    wi = out[k3.O_WI]
    fo = a1 / c_o if c_o > 0.0 else 0.5
    fi = a2 / c_i if c_i > 0.0 else 0.5
    S[k3.S_DW] = fo * wo
    S[k3.S_DW + 1] = fi * wi
    S[k3.S_DW + 2] = (1.0 - fi) * wi
    S[k3.S_DW + 3] = (1.0 - fo) * wo
    for i in range(4):
        S[k3.S_W + i] += S[k3.S_DW + i]
    S[k3.S_EIN] += out[k3.O_EIN]
    S[S_ERS] += out[O_RESEAT]
    k3.u_dot(par, S[0:4], S[4:8], sc, 220)
    Ms = par[tk.I_MSUP]
    if machine == 1:
        S[k3.S_F] = out[k3.O_FX]
        S[k3.S_F + 1] = out[k3.O_FY]
    else:
        S[k3.S_F] = -Ms * (agx + (sc[220] - ux0) / dt)
        S[k3.S_F + 1] = -Ms * (agy + (sc[221] - uy0) / dt)
    dp = math.sqrt(out[k3.O_DQ] * out[k3.O_DQ] + out[k3.O_DQ + 1] * out[k3.O_DQ + 1])
    da = math.sqrt(out[k3.O_DQ + 2] * out[k3.O_DQ + 2] + out[k3.O_DQ + 3] * out[k3.O_DQ + 3])
    so = 1.0 if dp != 0.0 else 0.0
    si = 1.0 if da != 0.0 else 0.0
    for i in range(4):
        S[k3.S_SLIDE + i] = so if i == 0 or i == 3 else si
    if so != 0.0 and si != 0.0:
        S[k3.S_PHASE] = tk.PHASE_BOTH
        S[k3.S_REG] = 6.0
    elif so != 0.0:
        S[k3.S_PHASE] = tk.PHASE_OUTER
        S[k3.S_REG] = 3.0
    elif si != 0.0:
        S[k3.S_PHASE] = tk.PHASE_INNER
        S[k3.S_REG] = 1.0
    else:
        S[k3.S_PHASE] = tk.PHASE_STICK
        S[k3.S_REG] = 0.0
    ao = (wo - out[k3.O_ARR_O]) / c_o if c_o > 0.0 else dp     # the arcs slid
    ai = (wi - out[k3.O_ARR_I]) / c_i if c_i > 0.0 else da
    S[k3.S_SV] = R1 * ao / dt
    S[k3.S_SV + 1] = R2 * ai / dt
    S[k3.S_SV + 2] = R3 * ai / dt
    S[k3.S_SV + 3] = R4 * ao / dt
    # the phases (Figs. 6-7): 2 with one pair sliding, 3 with both
    n = pivots(par, S, sc[228:232], out[k3.O_DQ:k3.O_DQ + 4], sc[232:240])
    S[S_NPH] = 0.0 if n == 0 else n + 1.0
    if n == 0 and rest0 and rocking_from_rest(par, sc[228:232], agx, agy, par[tk.I_G] + az) != 0:
        S[S_NPH] = -1.0
        if fail == k3.FAIL_NONE:
            fail = FAIL_ROCKING
    return fail


def row_values(par, S, t, xg, yg, row, sc):
    """The stepper's columns (mechanics.tfp3d_two_phase.COLUMNS) into row[0:N_ROW]:
    the seated 3D TFP's, then E_reseat_J, the pivots and re-seating rotations
    (x, y) and the number of phases."""
    k3.row_values(par, S, t, xg, yg, row, sc)
    for i in range(N_ROW_TWO):
        row[k3.N_ROW + i] = S[S_ERS + i]
