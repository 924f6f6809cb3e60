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


def matvec(A, x, o):
    """o = A x, A 4x4 row-major."""
    for i in range(4):
        o[i] = A[4 * i] * x[0] + A[4 * i + 1] * x[1] + A[4 * i + 2] * x[2] + A[4 * i + 3] * x[3]


def reseat(par, q0, q1, v, w, sc):
    """Phases 2 and 3 (docs/model.md 6.9): the phase-1 velocity field, every body
    k moving with -a_k X0 - b_k Y0 (X0 = De(phi0)[phi'], Y0 = De(psi0)[psi'])
    and turning with e(phi0) x X0, e(psi0) x Y0, projected in the kinetic-energy
    metric onto the seated tangent space at q1: p = J(q1)^T M_bodies J(q0) v,
    w = M(q1)^-1 p. Returns the kinetic energy removed, the energy of the part
    stopped, 1/2 |J(q0) v - J(q1) w|^2 in the bodies' masses (body by body, no
    cancellation). With y = 0 it is tfp_kernel.reseat, whose operations it
    then does (on the x axis the tilts, rates and the field are the planar
    ones: the planar re-seating there to the last bit). sc: scratch >= 100."""
    if q0[1] == 0.0 and q0[3] == 0.0 and q1[1] == 0.0 and q1[3] == 0.0 and v[1] == 0.0 and v[3] == 0.0:
        loss = tk.reseat(par, q0[0], q0[2], q1[0], q1[2], v[0], v[2], sc[44:47], sc[47:49])
        w[0] = sc[47]
        w[1] = 0.0
        w[2] = sc[48]
        w[3] = 0.0
        return loss
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
    q0, q1, p0, x, G, H, r, Hy, ry, y, Lm, tmp, D, Dy, Fm = k3.step_scratch(sc)
    z4 = sc[172:176]
    M0 = sc[260:276]
    v = sc[276:280]
    w = sc[280:284]
    for i in range(4):
        q0[i] = st[i]
        z4[i] = 0.0
    k3.mass_matrix(par, q0, M0, tmp)
    matvec(M0, st[4:8], p0)
    # rims of finite stiffness (docs/model.md 6.12): their force linearised about
    # each iterate into H + J (the frozen H kept) and r + J x, Newton on the increment
    springs = par[tk.I_KRIM] != 0.0
    if springs:
        k3.rim_spring_mass(par, q0, M0, sc)
    for i in range(16):
        H[i] = 2.0 * M0[i] / (dt * dt)
    k3.metric_root(q0[0], q0[1], Lm, 0)
    k3.metric_root(q0[2], q0[3], Lm, 4)
    # the frozen metric: H' once for the step
    for i in range(4):
        r[i] = 0.0
    k3._to_metric(H, r, Lm, Hy, ry, tmp)
    for i in range(4):
        x[i] = dt * st[4 + i]
        y[i] = 0.0
    ex, ey = k3.machine_gap(par, q0, machine, u1x, u1y, tmp)
    mfail = False
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
            ry[2 * blk], ry[2 * blk + 1] = k3.linv(Lm, blk, r[2 * blk], r[2 * blk + 1])
        if springs:
            Hn = sc[k3.SP_H:k3.SP_H + 16]
            rn = sc[k3.SP_R:k3.SP_R + 4]
            sc[k3.SP_LOSS] = k3.rim_spring_linearise(par, q0, x, dt, G, r, H, Hn, rn, sc)
            k3._to_metric(Hn, rn, Lm, Hy, ry, tmp)
        if machine == 1:
            # D: the discrete gradient of u (D^T dq = u(q1) - u(q0)); in y, L^-1 D
            k3.dgrad_u(par, q0, q1, D, sc)
            k3.to_y(Lm, D, Dy)
            mfail = k3.machine_force(Hy, ry, Dy, c_o, c_i, ex, ey, y, Fm, sc) != 0
        else:
            k3.socp(Hy, ry, c_o, c_i, y, sc)
        ch = 0.0
        for blk in range(2):
            a0, a1 = k3.linv(Lm, blk, y[2 * blk], y[2 * blk + 1])
            ch += abs(a0 - x[2 * blk]) + abs(a1 - x[2 * blk + 1])
            x[2 * blk] = a0
            x[2 * blk + 1] = a1
        if ch <= k3.FIXED_POINT_TOL:
            converged = True
            break
        if springs and k3.rim_spring_settled(ch, x):
            converged = True
            break
    k3.fixed_point_end(converged, ch, x, mfail, out)
    k3.machine_kkt(Hy, ry, Dy, Fm, c_o, c_i, y, machine, out)
    # Phi = r - H dq; p1 = p0 + dt (G - Phi); the phase-1 rates v = M(q0)^-1 p1
    for i in range(4):
        q1[i] = q0[i] + x[i]
    matvec(H, x, tmp[4:8])
    for i in range(4):
        tmp[i] = p0[i] + dt * (G[i] - (r[i] - tmp[4 + i]))
    k3.solve4(M0, tmp[0:4], v)
    wo, wi, ein = k3.step_work(par, q0, q1, x, y, D, Fm, agx, agy, az, c_o, c_i, machine, out, tmp)
    # a block that stuck ends at rest in the phase-1 field (metric M(q0)): an
    # impulse on it alone, the other block keeping its momentum
    z1 = x[0] == 0.0 and x[1] == 0.0
    z2 = x[2] == 0.0 and x[3] == 0.0
    arr_o = 0.0
    arr_i = 0.0
    if z1 or z2:
        matvec(M0, v, tmp)
        arr_o, arr_i = k3.arrest(par, q0, M0, v, z1, z2, tmp)
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
    k3.step_out(out, x, ein, wo, wi, arr_o, arr_i, it)
    if springs:
        out[k3.O_RIM] = sc[k3.SP_LOSS]
    if k3.past_rims(par, st):
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
    its force the last step's in the normal forces): tfp3d_kernel.begin_advance
    (normal forces at the start of the step, caps), ``step``,
    tfp3d_kernel.finish_advance without rims (the friction work of each
    surface, the bearing's force, phase, regime, sliding flags and speeds),
    then the re-seating loss, the phases and the rocking check. Returns the failure flag (tfp3d_kernel.FAIL_*, FAIL_ROCKING)."""
    for i in range(4):
        sc[228 + i] = S[i]
    rest0 = S[4] == 0.0 and S[5] == 0.0 and S[6] == 0.0 and S[7] == 0.0
    a1, a2, c_o, c_i, ux0, uy0 = k3.begin_advance(par, S, agx, agy, az, mu1, mu2, mu3, mu4, machine, sc)
    step(par, S[0:8], dt, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc)
    if par[tk.I_KRIM] != 0.0:
        # rims of finite stiffness: the dashpots' loss and the contacts
        S[k3.S_ERIM] += out[k3.O_RIM]
        k3.rim_spring_hits(par, S, sc)
    fail = k3.finish_advance(par, S, dt, agx, agy, machine, a1, a2, c_o, c_i, ux0, uy0, 0, out, sc)
    S[S_ERS] += out[O_RESEAT]
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


def advance_vertical(par, S, dt, agx, agy, az, mu1, mu2, mu3, mu4, machine, u1x, u1y, ud1x, ud1y, out, sc):
    """``advance`` under a vertical ground motion that may lift the TFP off
    (docs/model.md 10): the seated 3D TFP's lift-off (tfp3d_kernel.flights)
    around the two-phase step. While g + az >= 0 and the unit is seated,
    ``advance`` itself; when the step's g + az < 0 the stack and the
    superstructure fly (tfp3d_kernel._flight: take-off, ballistic flight,
    plastic landing) until they land, and a step that lands finishes seated
    with ``advance`` over the rest. In the air: no contact, no friction, no
    heat, no phases."""
    rem, how = k3.flights(par, S, dt, par[tk.I_G] + az, agx, agy, sc)
    if how == k3.FLIGHT_AIR:
        for i in range(9):
            S[S_B1 + i] = 0.0           # the pivots, rotations and phases (S_NPH)
    if how != k3.FLIGHT_SEATED and how != k3.FLIGHT_LANDED:
        return k3.FAIL_NONE if how == k3.FLIGHT_AIR else how
    fail = advance(par, S, rem, agx, agy, az, mu1, mu2, mu3, mu4, machine, u1x, u1y, ud1x, ud1y, out, sc)
    if how == k3.FLIGHT_LANDED:
        k3.landed_share(S, rem, dt)
    return fail


def vertical_row(par, S, az, row, sc):
    """The vertical ground motion's columns (tfp3d_kernel.vertical_row, the
    seated 3D TFP's) after the two-phase model's: row[N_ROW:N_ROW+5]. Only
    with a vertical loading (par[I_VERT] = 1). sc: scratch >= 40."""
    if par[tk.I_VERT] != 1.0:
        return
    k3.vertical_row(par, S, az, row, sc)
    for i in range(5):
        row[N_ROW + i] = row[k3.N_ROW + i]
    for i in range(N_ROW_TWO):
        row[k3.N_ROW + i] = S[S_ERS + i]
