"""Per-step physics of the rigid triple friction pendulum in both horizontal
directions, one source (kernel module, fpd/kernels.py).

The planar model (mechanics/tfp_kernel.py, docs/model.md section 6) with
its two rotations made 2D vectors (docs/model.md section 6.8): q = (phi,
alpha), four coordinates, phi = (phi_x, phi_y) the stack's tilt (both slider
plates about C1), alpha the pad's tilt relative to them, psi = phi + alpha
the pad's tilt. A tilt vector v points the body's axis along

    e(v) = (-s(t) v_x, -s(t) v_y, c(t)),   t = |v|^2, s(t) = sin|v| / |v|, c(t) = cos|v|

(a tilt |v| towards the azimuth of v; e((x, 0)) = (-sin x, 0, cos x), the
planar e(x)). Body k sits at r_k = -a_k e(phi) - b_k e(psi) from C1, so

    2T = (Aa + Jphi) |X|^2 + (B + Jpsi) |Y|^2 + 2 K X . Y,   X = De(phi)[phi'], Y = De(psi)[psi'],
    V = g [P1 (1 - c(|phi|^2)) + P2 (1 - c(|psi|^2))],   b = P1 s(|phi|^2) phi + P2 s(|psi|^2) psi,

b the horizontal first moment through which the ground acceleration works.
Friction: the slide of S1 (S4) is R1 (R4) times the arc the stack's axis
turns through, |De(phi) dphi| = |L(phi) dphi|, L(v) = s I + (1 - s) v v^T / t
(radial unchanged, azimuthal sin|v| / |v|); S2 and S3 slide R2, R3 times
|L(alpha) dalpha|. A step's increment solves

    min 1/2 dq^T H dq - r^T dq + c_o |L(phi0) dphi| + c_i |L(alpha0) dalpha|

(H = 2 M(q1) / dt^2, r = 2 p0 / dt + G, G minus the discrete gradient of
V + ag . b + az b_z + T(., p0), blockwise: phi then alpha, each block's
gradient averaged along the segment by 4-point Gauss-Legendre, so G . dq is
the change of that sum to round-off): a second-order cone program solved
exactly by its active set (``socp``) inside the same fixed point on q1 as
the planar scheme.
"""
import math

from . import tfp_kernel as tk

__kernel__ = True

# -- state vector ----------------------------------------------------------------------
# 0..7: phi_x, phi_y, alpha_x, alpha_y, and their rates
S_F, S_W, S_EIN, S_ERIM, S_PHASE, S_REG, S_SLIDE, S_SV, S_DW, S_N = 8, 10, 14, 15, 16, 17, 18, 22, 26, 30
S_ITER, S_KKT, S_EPS = 34, 35, 36          # fixed-point iterations, the step's KKT residual, its scale
# lift-off (docs/model.md 10): in flight (1.0); the flying unit's displacement since take-off
# (x, y, up) and its velocity relative to the ground; the landings' loss (J), the lift-offs'
# count, the time spent in flight (s)
S_FLY, S_XF, S_YF, S_ZF, S_VXF, S_VYF, S_VZF, S_ELAND, S_NLIFT, S_TFLY = 40, 41, 42, 43, 44, 45, 46, 47, 48, 49
S_J, S_NHIT = 50, 52    # the step's rim impulse on the superstructure (x, y, N s); rim impacts of S1..S4 so far
N_S = 56

# -- step output -------------------------------------------------------------------------
O_EIN, O_WO, O_WI, O_ITER, O_FAIL, O_ARR_O, O_ARR_I, O_KKT = 0, 1, 2, 3, 4, 5, 6, 7
O_DQ = 8            # 8..11: the increment
O_FX, O_FY = 12, 13  # the step's mean horizontal force of the bearing (machine: its force)
O_RIM, O_DXR, O_HIT_O, O_HIT_I, O_ARRIVE = 16, 17, 19, 20, 21   # rim loss, u' jump at the rims (x, y), arrivals
N_OUT = 24

FAIL_NONE, FAIL_FIXED_POINT, FAIL_RIM, FAIL_CAPACITY = 0, 2, 4, 1
FAIL_LAND = 5           # a flight would land beyond the outer surfaces' reach (not modelled)
FLIGHT_SEATED, FLIGHT_LANDED, FLIGHT_AIR = 10, 11, 12     # flights(): how the step goes on

FIXED_POINT_TOL = 1e-15
FIXED_POINT_ITERS = 60
N_SC = 684              # scratch length (the rims' from RB = 420 on: N_SC_RIM; the rim springs' from 616)

# Gauss-Legendre, 4 points on [0, 1]
GL_X0, GL_X1 = 0.5 - 0.5 * 0.8611363115940526, 0.5 - 0.5 * 0.3399810435848563
GL_W0, GL_W1 = 0.5 * 0.3478548451374538, 0.5 * 0.6521451548625461

N_ROW = 69          # len(mechanics.tfp3d.COLUMNS)


# -- series in t = |v|^2 (every TFP tilt is well below 1 rad; exact to round-off for t < 4) --
def _coefs(kind):
    """The power series' coefficients in t (index: the power), each the
    correctly rounded value of its exact rational: kind 0 s(t) = sum (-t)^n /
    (2n+1)!, 1 its derivative, 2 its second derivative, 3 (1 - cos sqrt t) / t,
    4 (1 - s(t)) / t. (Import time only.)"""
    from fractions import Fraction
    from math import factorial
    c = []
    for n in range(20):
        if kind == 0:
            c.append(Fraction((-1) ** n, factorial(2 * n + 1)))
        elif kind == 1:
            c.append(Fraction((n + 1) * (-1) ** (n + 1), factorial(2 * n + 3)))
        elif kind == 2:
            c.append(Fraction((n + 2) * (n + 1) * (-1) ** n, factorial(2 * n + 5)))
        elif kind == 3:
            c.append(Fraction((-1) ** n, factorial(2 * n + 2)))
        else:
            c.append(Fraction((-1) ** n, factorial(2 * n + 3)))
    return tuple(float(x) for x in c)


# Horner's rule on these: 14 terms (the last below 1e-20 of the first for t < 4)
C_S, C_SD, C_SDD, C_OMC, C_L = _coefs(0), _coefs(1), _coefs(2), _coefs(3), _coefs(4)
N_TERMS = 14


def _horner(c, t):
    r = c[N_TERMS - 1]
    for n in range(N_TERMS - 2, -1, -1):
        r = r * t + c[n]
    return r


def sfun(t):
    """s(t) = sin(sqrt t) / sqrt t."""
    return _horner(C_S, t)


def _sder(t):
    """s'(t)."""
    return _horner(C_SD, t)


def sder2(t):
    """s''(t) = sum_{n>=2} n (n-1) (-1)^n t^(n-2) / (2n+1)!."""
    return _horner(C_SDD, t)


def omc(t):
    """1 - cos(sqrt t), without cancellation."""
    return t * _omc_tail(t)


def _omc_tail(t):
    """(1 - cos sqrt t) / t = sum_{n>=1} (-t)^(n-1) / (2n)!."""
    return _horner(C_OMC, t)


def lfun(t):
    """(1 - s(t)) / t = sum_{n>=1} (-1)^(n+1) t^(n-1) / (2n+1)!."""
    return _horner(C_L, t)


# -- kinematics of one tilt vector v = (vx, vy) ------------------------------------------
def de(vx, vy, wx, wy, o, k):
    """De(v)[w] into o[k:k+3]."""
    t = vx * vx + vy * vy
    de_s(vx, vy, wx, wy, sfun(t), _sder(t), o, k)


def de_s(vx, vy, wx, wy, s, sd, o, k):
    """``de`` with s(|v|^2), s'(|v|^2) given."""
    vw = vx * wx + vy * wy
    o[k] = -s * wx - 2.0 * sd * vw * vx
    o[k + 1] = -s * wy - 2.0 * sd * vw * vy
    o[k + 2] = -s * vw


def d2e(vx, vy, wx, wy, ux, uy, o, k):
    """D^2 e(v)[w, u] into o[k:k+3]."""
    t = vx * vx + vy * vy
    d2e_s(vx, vy, wx, wy, ux, uy, sfun(t), _sder(t), sder2(t), o, k)


def d2e_s(vx, vy, wx, wy, ux, uy, s, sd, sdd, o, k):
    """``d2e`` with s, s', s'' at |v|^2 given."""
    vw = vx * wx + vy * wy
    vu = vx * ux + vy * uy
    wu = wx * ux + wy * uy
    o[k] = -2.0 * sd * (vu * wx + wu * vx + vw * ux) - 4.0 * sdd * vu * vw * vx
    o[k + 1] = -2.0 * sd * (vu * wy + wu * vy + vw * uy) - 4.0 * sdd * vu * vw * vy
    o[k + 2] = -s * wu - 2.0 * sd * vw * vu


# -- mass matrix (4x4, row-major into M[0:16]) -----------------------------------------
def _ecols(vx, vy):
    """The columns of E(v) = De(v): De(v)[e_x], De(v)[e_y] (3 components each)."""
    t = vx * vx + vy * vy
    return _ecols_s(vx, vy, sfun(t), _sder(t))


def _ecols_s(vx, vy, s, sd):
    """``_ecols`` with s, s' at |v|^2 given."""
    a = 2.0 * sd
    return (-s - a * vx * vx, -a * vx * vy, -s * vx,
            -a * vy * vx, -s - a * vy * vy, -s * vy)


def _cross(px, py, sx, sy, o):
    """C = E(phi)^T E(psi) (C_ij = De(phi)[e_i] . De(psi)[e_j]) into o[0:4] = (C_xx, C_xy, C_yx, C_yy)."""
    tp = px * px + py * py
    ts = sx * sx + sy * sy
    _cross_s(px, py, sx, sy, sfun(tp), _sder(tp), sfun(ts), _sder(ts), o)


def _cross_s(px, py, sx, sy, sp, dp, ss, ds, o):
    """``_cross`` with s, s' of phi and psi given."""
    a0, a1, a2, b0, b1, b2 = _ecols_s(px, py, sp, dp)
    c0, c1, c2, d0, d1, d2 = _ecols_s(sx, sy, ss, ds)
    o[0] = a0 * c0 + a1 * c1 + a2 * c2
    o[1] = a0 * d0 + a1 * d1 + a2 * d2
    o[2] = b0 * c0 + b1 * c1 + b2 * c2
    o[3] = b0 * d0 + b1 * d1 + b2 * d2


def mass_matrix(par, q, M, sc):
    """M(q), q = (phi_x, phi_y, alpha_x, alpha_y). sc: scratch >= 8.

    The Gram matrices E^T E = I - k m m^T (k = (1 - s^2) / t, m = (-v_y, v_x):
    radial unit length, azimuthal s) in closed form; the cross one C =
    E(phi)^T E(psi) from the columns, its xx entry as cos(alpha_x), its value
    at the tilts' x components (phi and psi on the x axis: the angle between
    the axes is alpha_x), plus its change from there, C_xx(q) - C_xx(x
    components) (0 on the axis). The terms are summed in the planar TFP's
    order (Aa, B, K, Jphi, Jpsi): on the axis M's x entries are its
    mass_matrix to the last bit."""
    px, py = q[0], q[1]
    sx, sy = q[0] + q[2], q[1] + q[3]
    tp = px * px + py * py
    ts = sx * sx + sy * sy
    mass_matrix_s(par, q, M, sc, sfun(tp), _sder(tp), lfun(tp), sfun(ts), _sder(ts), lfun(ts))


def mass_matrix_s(par, q, M, sc, sp, dp, lp, ss, ds, ls):
    """``mass_matrix`` with s, s' and l = (1 - s) / t of phi (sp, dp, lp) and psi (ss, ds, ls) given."""
    Aa, B, K, Jphi, Jpsi = par[tk.I_AA], par[tk.I_B], par[tk.I_K], par[tk.I_JPHI], par[tk.I_JPSI]
    px, py = q[0], q[1]
    sx, sy = q[0] + q[2], q[1] + q[3]
    kp = lp * (1.0 + sp)
    ks = ls * (1.0 + ss)
    _cross(px, 0.0, sx, 0.0, sc)
    c_ax = sc[0]
    _cross_s(px, py, sx, sy, sp, dp, ss, ds, sc)
    sc[0] = math.cos(q[2]) + (sc[0] - c_ax)
    for i in range(2):
        for j in range(2):
            if i == j:
                gp = 1.0 - kp * (py * py if i == 0 else px * px)
                gs = 1.0 - ks * (sy * sy if i == 0 else sx * sx)
            else:
                gp = kp * px * py
                gs = ks * sx * sy
            cij = sc[2 * i + j]
            cji = sc[2 * j + i]
            M[4 * i + j] = Aa * gp + B * gs + K * (cij + cji) + Jphi * gp + Jpsi * gs
            M[4 * i + 2 + j] = B * gs + K * cij + Jpsi * gs
            M[4 * (2 + j) + i] = M[4 * i + 2 + j]
            M[4 * (2 + i) + 2 + j] = B * gs + Jpsi * gs


def chol_solve(A, b, x, L):
    """x = A^-1 b for the symmetric positive definite 4x4 A (row-major); L: scratch 16.
    Returns 1 (x not set) if A is not positive definite to round-off, else 0."""
    n = 4
    for i in range(n):
        for j in range(i + 1):
            s = A[4 * i + j]
            for k in range(j):
                s -= L[4 * i + k] * L[4 * j + k]
            if i == j:
                if not s > 0.0:
                    return 1
                L[4 * i + i] = math.sqrt(s)
            else:
                L[4 * i + j] = s / L[4 * j + j]
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= L[4 * i + k] * x[k]
        x[i] = s / L[4 * i + i]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for k in range(i + 1, n):
            s -= L[4 * k + i] * x[k]
        x[i] = s / L[4 * i + i]
    return 0


def solve4(A, b, x):
    """x = A^-1 b for the symmetric positive definite 4x4 A (row-major) by
    blocks of the x components (0, 2) and the y components (1, 3): the y
    part from the Schur complement S = A_yy - A_yx A_xx^-1 A_xy, then
    x_x = A_xx^-1 (b_x - A_xy x_y), each 2x2 solve by Cramer's rule. With no
    coupling of the x and y components and no y load, x_y = 0 and x_x is
    the 2x2 solve of the planar TFP (tfp_kernel.solve2) to the last bit."""
    a11, a12, a22 = A[0], A[2], A[10]
    det = a11 * a22 - a12 * a12
    # A_xx^-1 b_x and A_xx^-1 A_xy (the columns y0 = 1, y1 = 3)
    u0 = (a22 * b[0] - a12 * b[2]) / det
    u1 = (a11 * b[2] - a12 * b[0]) / det
    z00 = (a22 * A[1] - a12 * A[9]) / det
    z10 = (a11 * A[9] - a12 * A[1]) / det
    z01 = (a22 * A[3] - a12 * A[11]) / det
    z11 = (a11 * A[11] - a12 * A[3]) / det
    s11 = A[5] - (A[4] * z00 + A[6] * z10)
    s12 = A[7] - (A[4] * z01 + A[6] * z11)
    s22 = A[15] - (A[12] * z01 + A[14] * z11)
    c0 = b[1] - (A[4] * u0 + A[6] * u1)
    c1 = b[3] - (A[12] * u0 + A[14] * u1)
    ds = s11 * s22 - s12 * s12
    x[1] = (s22 * c0 - s12 * c1) / ds
    x[3] = (s11 * c1 - s12 * c0) / ds
    e0 = b[0] - (A[1] * x[1] + A[3] * x[3])
    e1 = b[2] - (A[9] * x[1] + A[11] * x[3])
    x[0] = (a22 * e0 - a12 * e1) / det
    x[2] = (a11 * e1 - a12 * e0) / det


def kinetic(par, q, v, sc):
    """T(q, v). sc: scratch >= 12."""
    aa = par[tk.I_AA] + par[tk.I_JPHI]
    bb = par[tk.I_B] + par[tk.I_JPSI]
    de(q[0], q[1], v[0], v[1], sc, 0)
    de(q[0] + q[2], q[1] + q[3], v[0] + v[2], v[1] + v[3], sc, 3)
    X2 = sc[0] * sc[0] + sc[1] * sc[1] + sc[2] * sc[2]
    Y2 = sc[3] * sc[3] + sc[4] * sc[4] + sc[5] * sc[5]
    XY = sc[0] * sc[3] + sc[1] * sc[4] + sc[2] * sc[5]
    return 0.5 * (aa * X2 + bb * Y2 + 2.0 * par[tk.I_K] * XY)


def potential(par, q):
    tp = q[0] * q[0] + q[1] * q[1]
    sx, sy = q[0] + q[2], q[1] + q[3]
    ts = sx * sx + sy * sy
    return par[tk.I_G] * (par[tk.I_P1] * omc(tp) + par[tk.I_P2] * omc(ts))


def moments(par, q, o):
    """The horizontal first moment b(q) (o[0:2]) and the vertical one above the
    seated position, b_z = P1 (1 - cos|phi|) + P2 (1 - cos|psi|) (o[2])."""
    tp = q[0] * q[0] + q[1] * q[1]
    sx, sy = q[0] + q[2], q[1] + q[3]
    ts = sx * sx + sy * sy
    P1, P2 = par[tk.I_P1], par[tk.I_P2]
    a = P1 * sfun(tp)
    b = P2 * sfun(ts)
    o[0] = a * q[0] + b * sx
    o[1] = a * q[1] + b * sy
    o[2] = P1 * omc(tp) + P2 * omc(ts)


def u_rel(par, q, o):
    """The superstructure's horizontal displacement relative to the ground (o[0:2])
    and its uplift (o[2])."""
    A, Li = par[tk.I_A], par[tk.I_LI]
    tp = q[0] * q[0] + q[1] * q[1]
    sx, sy = q[0] + q[2], q[1] + q[3]
    ts = sx * sx + sy * sy
    a = A * sfun(tp)
    b = Li * sfun(ts)
    o[0] = a * q[0] + b * sx
    o[1] = a * q[1] + b * sy
    o[2] = A * omc(tp) + Li * omc(ts)


def u_dot(par, q, v, o, k):
    """The superstructure's horizontal velocity relative to the ground into o[k:k+2]
    (scratch o[k:k+6])."""
    A, Li = par[tk.I_A], par[tk.I_LI]
    de(q[0], q[1], v[0], v[1], o, k)
    x0, x1 = o[k], o[k + 1]
    de(q[0] + q[2], q[1] + q[3], v[0] + v[2], v[1] + v[3], o, k)
    o[k] = -(A * x0 + Li * o[k])
    o[k + 1] = -(A * x1 + Li * o[k + 1])


def grad_f(par, q, p, agx, agy, az, blk, g, sc):
    """The gradient of f = V + ag . b + az b_z + T(., p) (p fixed) in the block
    blk (0: phi with alpha fixed, psi moving with it; 1: alpha) into g[0:2].
    sc: scratch >= 60 (M at sc[0:16], w at sc[16:20], L at sc[20:36])."""
    aa = par[tk.I_AA] + par[tk.I_JPHI]
    bb = par[tk.I_B] + par[tk.I_JPSI]
    K = par[tk.I_K]
    px, py = q[0], q[1]
    sx, sy = q[0] + q[2], q[1] + q[3]
    tp = px * px + py * py
    ts = sx * sx + sy * sy
    P1, P2, gz = par[tk.I_P1], par[tk.I_P2], par[tk.I_G] + az
    # each series once per tilt
    s_p, s_s = sfun(tp), sfun(ts)
    d_p, d_s = _sder(tp), _sder(ts)
    moving = p[0] != 0.0 or p[1] != 0.0 or p[2] != 0.0 or p[3] != 0.0   # (p = 0: the two-phase model's)
    dd_p = 0.0
    dd_s = 0.0
    wpx, wpy, wsx, wsy = 0.0, 0.0, 0.0, 0.0
    if moving:
        mass_matrix_s(par, q, sc, sc[40:52], s_p, d_p, lfun(tp), s_s, d_s, lfun(ts))
        chol_solve(sc, p, sc[16:20], sc[20:36])
        wpx, wpy = sc[16], sc[17]
        wsx, wsy = sc[16] + sc[18], sc[17] + sc[19]
        de_s(px, py, wpx, wpy, s_p, d_p, sc, 36)        # X
        de_s(sx, sy, wsx, wsy, s_s, d_s, sc, 39)        # Y
        dd_p, dd_s = sder2(tp), sder2(ts)
    for j in range(2):
        ux = 1.0 if j == 0 else 0.0
        uy = 1.0 - ux
        # V, b, b_z of psi
        us = sx * ux + sy * uy
        gv = P2 * (gz * s_s * us + s_s * (agx * ux + agy * uy) + 2.0 * d_s * (sx * agx + sy * agy) * us)
        if blk == 0:
            up = px * ux + py * uy
            gv += P1 * (gz * s_p * up + s_p * (agx * ux + agy * uy) + 2.0 * d_p * (px * agx + py * agy) * up)
        if moving:
            # -1/2 dQ: dX, dY along u (0 without momentum)
            d2e_s(sx, sy, wsx, wsy, ux, uy, s_s, d_s, dd_s, sc, 45)
            dQ = 2.0 * bb * (sc[39] * sc[45] + sc[40] * sc[46] + sc[41] * sc[47]) \
                + 2.0 * K * (sc[36] * sc[45] + sc[37] * sc[46] + sc[38] * sc[47])
            if blk == 0:
                d2e_s(px, py, wpx, wpy, ux, uy, s_p, d_p, dd_p, sc, 48)
                dQ += 2.0 * aa * (sc[36] * sc[48] + sc[37] * sc[49] + sc[38] * sc[50]) \
                    + 2.0 * K * (sc[48] * sc[39] + sc[49] * sc[40] + sc[50] * sc[41])
            gv = gv - 0.5 * dQ
        g[j] = gv


def dgrad(par, q0, q1, p, agx, agy, az, G, sc):
    """Minus the discrete gradient of f (grad_f) from q0 to q1 into G[0:4]:
    phi first (alpha at alpha0), then alpha (phi at phi1), so that
    G . (q1 - q0) = -(f(q1) - f(q0)) to round-off. Each block's gradient
    averaged over its segment (``dgrad_gl``), with its part on the x axis in
    closed form: the same average for the x components alone (q, p and ag
    with their y components 0: the planar problem along x) is replaced by
    the planar TFP's closed form of it (Itoh-Abe: cos a - cos b as a
    product, the kinetic energy's change as -1/2 w1^T dM w0), exact in
    exact arithmetic, so G = closed form + (average - its value on the axis);
    on the axis that is the planar TFP's discrete gradient to the last bit.
    sc: scratch >= 100 (sc[60:70] the averages', sc[70:100] the axis')."""
    dgrad_gl(par, q0, q1, p, agx, agy, az, G, sc)
    for i in range(4):
        sc[70 + i] = q0[i] if i % 2 == 0 else 0.0
        sc[74 + i] = q1[i] if i % 2 == 0 else 0.0
        sc[78 + i] = p[i] if i % 2 == 0 else 0.0
    dgrad_gl(par, sc[70:74], sc[74:78], sc[78:82], agx, 0.0, az, sc[82:86], sc)
    for i in range(4):
        G[i] -= sc[82 + i]
    # the closed form on the axis (tfp_kernel.substep's G1, G2)
    P1, P2, gz = par[tk.I_P1], par[tk.I_P2], par[tk.I_G] + az
    ph0, al0, ph1, al1 = q0[0], q0[2], q1[0], q1[2]
    dTa = 0.0
    if p[0] != 0.0 or p[2] != 0.0:
        # -1/2 w1^T dM w0 / dalpha, dM = K (cos al1 - cos al0) [[2, 1], [1, 0]]
        tk.mass_matrix(par, al1, sc[86:89])
        tk.solve2(sc[86], sc[87], sc[88], p[0], p[2], sc[89:91])
        w11, w12 = sc[89], sc[90]
        tk.mass_matrix(par, al0, sc[86:89])
        tk.solve2(sc[86], sc[87], sc[88], p[0], p[2], sc[89:91])
        w01, w02 = sc[89], sc[90]
        K = par[tk.I_K]
        dTa = 0.5 * (2.0 * K * w11 * w01 + K * (w11 * w02 + w12 * w01)) * math.sin(0.5 * (al0 + al1)) \
            * tk.sinc(0.5 * (al1 - al0))
    tk.dgrad_cos_sin(gz * P1, gz * P2, ph0, al0, ph1, al1, sc[91:93], 0)
    g1 = -sc[91]
    g2 = -dTa - sc[92]
    tk.dgrad_cos_sin(P1, P2, ph0, al0, ph1, al1, sc[91:93], 1)
    g1 -= agx * sc[91]
    g2 -= agx * sc[92]
    G[0] = g1 + G[0]
    G[2] = g2 + G[2]


def dgrad_gl(par, q0, q1, p, agx, agy, az, G, sc):
    """Minus the discrete gradient of f (grad_f) from q0 to q1 into G[0:4]:
    phi first (alpha at alpha0), then alpha (phi at phi1), each block's
    gradient averaged over its segment (4-point Gauss-Legendre), so that
    G . (q1 - q0) = -(f(q1) - f(q0)) to round-off.
    sc: scratch >= 70 (sc[60:64] the node, sc[64:66] the block gradient)."""
    for blk in range(2):
        G[2 * blk] = 0.0
        G[2 * blk + 1] = 0.0
        for k in range(4):
            if k == 0:
                x, w = GL_X0, GL_W0
            elif k == 1:
                x, w = GL_X1, GL_W1
            elif k == 2:
                x, w = 1.0 - GL_X1, GL_W1
            else:
                x, w = 1.0 - GL_X0, GL_W0
            if blk == 0:
                sc[60] = q0[0] + x * (q1[0] - q0[0])
                sc[61] = q0[1] + x * (q1[1] - q0[1])
                sc[62] = q0[2]
                sc[63] = q0[3]
            else:
                sc[60] = q1[0]
                sc[61] = q1[1]
                sc[62] = q0[2] + x * (q1[2] - q0[2])
                sc[63] = q0[3] + x * (q1[3] - q0[3])
            grad_f(par, sc[60:64], p, agx, agy, az, blk, sc[64:66], sc)
            G[2 * blk] -= w * sc[64]
            G[2 * blk + 1] -= w * sc[65]


# -- the second-order cone program ---------------------------------------------------------
def metric_root(vx, vy, o, k):
    """L(v) = s I + (1 - s) v v^T / |v|^2 (the arc metric's square root, symmetric)
    into o[k:k+4] = (L11, L12, L22, det)."""
    # L = I - l (t I - v v^T), l = (1 - s) / t: exactly the identity along v
    t = vx * vx + vy * vy
    l = lfun(t)
    o[k] = 1.0 - l * vy * vy
    o[k + 1] = l * vx * vy
    o[k + 2] = 1.0 - l * vx * vx
    o[k + 3] = o[k] * o[k + 2] - o[k + 1] * o[k + 1]


def block_min(a11, a12, a22, b1, b2, c, y):
    """The minimiser of 1/2 y^T A y - b^T y + c |y| (A 2x2 SPD) into y[0:2],
    for |b| > c (else it is 0): y = (A + mu I)^-1 b with mu |y| = c; mu by a
    safeguarded Newton on 1/|y(mu)| - mu / c (linear in mu when b is along an
    eigenvector of A) in the eigenbasis of A, to round-off."""
    if a12 == 0.0:
        cs, sn = 1.0, 0.0
        l1, l2 = a11, a22
    else:
        th = (a22 - a11) / (2.0 * a12)
        tn = (1.0 if th >= 0.0 else -1.0) / (abs(th) + math.sqrt(1.0 + th * th))
        cs = 1.0 / math.sqrt(1.0 + tn * tn)
        sn = tn * cs
        l1 = a11 - tn * a12
        l2 = a22 + tn * a12
    # eigenvectors u1 = (cs, -sn), u2 = (sn, cs)
    be1 = cs * b1 - sn * b2
    be2 = sn * b1 + cs * b2
    nb = math.sqrt(be1 * be1 + be2 * be2)
    lmin = l1 if l1 < l2 else l2
    lmax = l2 if l1 < l2 else l1
    lo = c * lmin / (nb - c)
    hi = c * lmax / (nb - c)
    mu = 0.5 * (lo + hi)
    on_axis = False
    if be2 == 0.0 and be1 != 0.0:
        mu = c * l1 / (nb - c)
        lo = hi = mu
        on_axis = True
    elif be1 == 0.0 and be2 != 0.0:
        mu = c * l2 / (nb - c)
        lo = hi = mu
        on_axis = True
    if on_axis:
        # b along an eigenvector: y there is (b - c b / |b|) / lambda, the
        # planar TFP's candidate (tfp_kernel._qp_cands) to the last bit
        y1 = 0.0
        y2 = 0.0
        if be2 == 0.0:
            y1 = (be1 - (c if be1 > 0.0 else -c)) / l1
        else:
            y2 = (be2 - (c if be2 > 0.0 else -c)) / l2
        y[0] = cs * y1 + sn * y2
        y[1] = -sn * y1 + cs * y2
        return
    for it in range(100):
        if lo == hi:
            break
        d1 = l1 + mu
        d2 = l2 + mu
        y1 = be1 / d1
        y2 = be2 / d2
        ny = math.sqrt(y1 * y1 + y2 * y2)
        h = 1.0 / ny - mu / c
        if h == 0.0:
            break
        if h < 0.0:
            hi = mu
        else:
            lo = mu
        # d(1/|y|)/dmu = (y1^2 / d1 + y2^2 / d2) / |y|^3
        dh = (y1 * y1 / d1 + y2 * y2 / d2) / (ny * ny * ny) - 1.0 / c
        nm = mu - h / dh
        if not (lo < nm < hi):
            nm = 0.5 * (lo + hi)
        if abs(nm - mu) <= 4e-16 * mu:
            mu = nm
            break
        mu = nm
    y1 = be1 / (l1 + mu)
    y2 = be2 / (l2 + mu)
    y[0] = cs * y1 + sn * y2
    y[1] = -sn * y1 + cs * y2


def socp(H, r, c1, c2, y, sc):
    """The minimiser of f(y) = 1/2 y^T H y - r^T y + c1 |y_a| + c2 |y_b| (H 4x4
    SPD row-major, blocks a = y[0:2], b = y[2:4]) into y, exactly: f is
    strictly convex, its minimiser the one point where 0 is in the
    subdifferential, found among the four active sets in turn (docs/model.md
    6.8): both blocks stuck (|r_a| <= c1, |r_b| <= c2), one stuck (the other
    block's 2D problem, block_min, then the stuck block's cap checked), both
    sliding (damped Newton on the smooth stationarity from y's start).
    Returns the number of Newton iterations (0 for the first three).
    sc: scratch >= 60."""
    ra = math.sqrt(r[0] * r[0] + r[1] * r[1])
    rb = math.sqrt(r[2] * r[2] + r[3] * r[3])
    if ra <= c1 and rb <= c2:
        for i in range(4):
            y[i] = 0.0
        return 0
    if rb > c2:
        block_min(H[10], H[11], H[15], r[2], r[3], c2, sc[0:2])
        gx = r[0] - H[2] * sc[0] - H[3] * sc[1]
        gy = r[1] - H[6] * sc[0] - H[7] * sc[1]
        if gx * gx + gy * gy <= c1 * c1:
            y[0] = 0.0
            y[1] = 0.0
            y[2] = sc[0]
            y[3] = sc[1]
            return 0
    if ra > c1:
        block_min(H[0], H[1], H[5], r[0], r[1], c1, sc[0:2])
        gx = r[2] - H[8] * sc[0] - H[9] * sc[1]
        gy = r[3] - H[12] * sc[0] - H[13] * sc[1]
        if gx * gx + gy * gy <= c2 * c2:
            y[0] = sc[0]
            y[1] = sc[1]
            y[2] = 0.0
            y[3] = 0.0
            return 0
    # both slide: start from y if both its blocks are nonzero (the fixed
    # point's previous iterate), else from a few exact block sweeps
    na = math.sqrt(y[0] * y[0] + y[1] * y[1])
    nb = math.sqrt(y[2] * y[2] + y[3] * y[3])
    if na == 0.0 or nb == 0.0:
        for i in range(4):
            y[i] = 0.0
        _sweeps(H, r, c1, c2, y, sc, 4, 0.0)
    its = 0
    ok = False
    low = 1.0
    fy = socp_f(H, r, c1, c2, y)
    for it in range(60):
        its = it + 1
        na = math.sqrt(y[0] * y[0] + y[1] * y[1])
        nb = math.sqrt(y[2] * y[2] + y[3] * y[3])
        if na == 0.0 or nb == 0.0:
            break
        # gradient and Hessian of the smooth objective
        for i in range(4):
            s = -r[i]
            for j in range(4):
                s += H[4 * i + j] * y[j]
            sc[4 + i] = s
        sc[4] += c1 * y[0] / na
        sc[5] += c1 * y[1] / na
        sc[6] += c2 * y[2] / nb
        sc[7] += c2 * y[3] / nb
        for i in range(16):
            sc[40 + i] = H[i]
        ka = c1 / (na * na * na)
        kb = c2 / (nb * nb * nb)
        sc[40] += ka * y[1] * y[1]
        sc[41] -= ka * y[0] * y[1]
        sc[44] -= ka * y[0] * y[1]
        sc[45] += ka * y[0] * y[0]
        sc[50] += kb * y[3] * y[3]
        sc[51] -= kb * y[2] * y[3]
        sc[54] -= kb * y[2] * y[3]
        sc[55] += kb * y[2] * y[2]
        if chol_solve(sc[40:56], sc[4:8], sc[8:12], sc[20:36]) != 0:
            break
        nd = 0.0
        ny = 0.0
        for i in range(4):
            nd += sc[8 + i] * sc[8 + i]
            ny += y[i] * y[i]
        na2 = sc[8] * sc[8] + sc[9] * sc[9]
        nb2 = sc[10] * sc[10] + sc[11] * sc[11]
        # near the solution (the step small against each block) Newton's full
        # step, to round-off; else damped: f may not rise and no block may
        # lose more than half its length (the kink at 0 is not the model's)
        lam = 1.0
        if na2 > 1e-12 * na * na or nb2 > 1e-12 * nb * nb:
            for ls in range(60):
                for i in range(4):
                    sc[12 + i] = y[i] - lam * sc[8 + i]
                fn = socp_f(H, r, c1, c2, sc[12:16])
                ta = sc[12] * sc[12] + sc[13] * sc[13]
                tb = sc[14] * sc[14] + sc[15] * sc[15]
                if fn <= fy and ta >= 0.25 * na * na and tb >= 0.25 * nb * nb:
                    break
                lam *= 0.5
        for i in range(4):
            y[i] -= lam * sc[8 + i]
        fy = socp_f(H, r, c1, c2, y)
        if nd <= 1e-30 * ny:
            ok = True
            break
        if lam == 1.0:
            low = min(low, nd / ny)
    if not ok and low > 1e-26:      # full steps below 1e-13 of y: at round-off (6.8)
        # Newton did not settle: exact block sweeps (each block's 2D problem
        # with the other held) converge for any strictly convex H, slowly
        _sweeps(H, r, c1, c2, y, sc, 200000, 1e-32)
        its += 1000
    _polish(H, r, c1, c2, y, sc)
    return its


def _polish(H, r, c1, c2, y, sc):
    """Both blocks sliding: the stationarity H y = r - c1 d_a - c2 d_b solved
    once more with the directions d_k = y_k / |y_k| of the solution (its
    fixed point there, a change of round-off; kept only if it leaves each
    block's direction). On an axis it is the planar TFP's candidate of two
    free coordinates to the last bit. sc: scratch (sc[12:20])."""
    na = math.sqrt(y[0] * y[0] + y[1] * y[1])
    nb = math.sqrt(y[2] * y[2] + y[3] * y[3])
    if na == 0.0 or nb == 0.0:
        return
    sc[12] = r[0] - c1 * (y[0] / na)
    sc[13] = r[1] - c1 * (y[1] / na)
    sc[14] = r[2] - c2 * (y[2] / nb)
    sc[15] = r[3] - c2 * (y[3] / nb)
    solve4(H, sc[12:16], sc[16:20])
    if sc[16] * y[0] + sc[17] * y[1] > 0.0 and sc[18] * y[2] + sc[19] * y[3] > 0.0:
        for i in range(4):
            y[i] = sc[16 + i]


def _sweeps(H, r, c1, c2, y, sc, n, tol):
    """Block coordinate descent: each block the exact minimiser (block_min)
    with the other held; n sweeps at most, until the squared change is below
    tol |y|^2."""
    for k in range(n):
        ch = 0.0
        for blk in range(2):
            i0 = 2 * blk
            o0 = 2 - i0
            c = c1 if blk == 0 else c2
            b0 = r[i0] - H[4 * i0 + o0] * y[o0] - H[4 * i0 + o0 + 1] * y[o0 + 1]
            b1 = r[i0 + 1] - H[4 * (i0 + 1) + o0] * y[o0] - H[4 * (i0 + 1) + o0 + 1] * y[o0 + 1]
            if b0 * b0 + b1 * b1 <= c * c:
                sc[0] = 0.0
                sc[1] = 0.0
            else:
                block_min(H[4 * i0 + i0], H[4 * i0 + i0 + 1], H[4 * (i0 + 1) + i0 + 1], b0, b1, c, sc[0:2])
            ch += (sc[0] - y[i0]) * (sc[0] - y[i0]) + (sc[1] - y[i0 + 1]) * (sc[1] - y[i0 + 1])
            y[i0] = sc[0]
            y[i0 + 1] = sc[1]
        ny = y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]
        if ch <= tol * ny:
            break


def socp_f(H, r, c1, c2, y):
    f = 0.0
    for i in range(4):
        s = 0.0
        for j in range(4):
            s += H[4 * i + j] * y[j]
        f += y[i] * (0.5 * s - r[i])
    return f + c1 * math.sqrt(y[0] * y[0] + y[1] * y[1]) + c2 * math.sqrt(y[2] * y[2] + y[3] * y[3])


def kkt_residual(H, r, c1, c2, y):
    """The optimality conditions of ``socp`` at y: g = r - H y must equal
    c1 y_a / |y_a| on a sliding block a (|g_a| <= c1 on a stuck one), the
    same for b. Returns the largest violation relative to max(c1, c2, |r|)."""
    sc0 = 0.0
    for i in range(4):
        sc0 += r[i] * r[i]
    scale = max(max(c1, c2), math.sqrt(sc0))
    if scale == 0.0:
        return 0.0
    worst = 0.0
    for blk in range(2):
        c = c1 if blk == 0 else c2
        i0 = 2 * blk
        g0 = r[i0]
        g1 = r[i0 + 1]
        for j in range(4):
            g0 -= H[4 * i0 + j] * y[j]
            g1 -= H[4 * (i0 + 1) + j] * y[j]
        n = math.sqrt(y[i0] * y[i0] + y[i0 + 1] * y[i0 + 1])
        if n > 0.0:
            e0 = g0 - c * y[i0] / n
            e1 = g1 - c * y[i0 + 1] / n
            v = math.sqrt(e0 * e0 + e1 * e1)
        else:
            v = math.sqrt(g0 * g0 + g1 * g1) - c
            if v < 0.0:
                v = 0.0
        if v > worst:
            worst = v
    return worst / scale


# -- normal forces -------------------------------------------------------------------------
def normal_forces(par, q, v, agx, agy, az, Fx, Fy, N, sc):
    """N1..N4 along the axes of the surfaces' centres (S1, S4: e(phi); S2, S3:
    e(psi)) from the bodies' accelerations at the rates v (centripetal terms,
    generalised accelerations left out as in the planar model), the ground's
    d'Alembert force, gravity g + az and the machine's force (Fx, Fy) on the
    superstructure; top down, clipped at 0. sc: scratch >= 12."""
    gz = par[tk.I_G] + az
    px, py = q[0], q[1]
    sx, sy = q[0] + q[2], q[1] + q[3]
    vpx, vpy = v[0], v[1]
    vsx, vsy = v[0] + v[2], v[1] + v[3]
    # -D^2 e[v, v]: the acceleration of -e along the axis' turning
    d2e(px, py, vpx, vpy, vpx, vpy, sc, 0)
    d2e(sx, sy, vsx, vsy, vsx, vsy, sc, 3)
    tp = px * px + py * py
    ts = sx * sx + sy * sy
    s_p, s_s = sfun(tp), sfun(ts)
    ep0, ep1, ep2 = -s_p * px, -s_p * py, 1.0 - omc(tp)
    es0, es1, es2 = -s_s * sx, -s_s * sy, 1.0 - omc(ts)
    A, Li, Ms = par[tk.I_A], par[tk.I_LI], par[tk.I_MSUP]
    # r = -a e(phi) - b e(psi): r'' = -a D2e(phi)[.] - b D2e(psi)[.]
    bx = Ms * (agx - A * sc[0] - Li * sc[3]) - Fx
    by = Ms * (agy - A * sc[1] - Li * sc[4]) - Fy
    bz = Ms * (gz - A * sc[2] - Li * sc[5])
    N[3] = bx * ep0 + by * ep1 + bz * ep2
    a, b, m = par[tk.I_A_SU], Li, par[tk.I_MS_UP]
    bx += m * (agx - a * sc[0] - b * sc[3])
    by += m * (agy - a * sc[1] - b * sc[4])
    bz += m * (gz - a * sc[2] - b * sc[5])
    N[2] = bx * es0 + by * es1 + bz * es2
    a, b, m = par[tk.I_A_PAD], par[tk.I_B_PAD], par[tk.I_MPAD]
    bx += m * (agx - a * sc[0] - b * sc[3])
    by += m * (agy - a * sc[1] - b * sc[4])
    bz += m * (gz - a * sc[2] - b * sc[5])
    N[1] = bx * es0 + by * es1 + bz * es2
    a, m = par[tk.I_A_SL], par[tk.I_MS_LO]
    bx += m * (agx - a * sc[0])
    by += m * (agy - a * sc[1])
    bz += m * (gz - a * sc[2])
    N[0] = bx * ep0 + by * ep1 + bz * ep2
    for i in range(4):
        if N[i] < 0.0:
            N[i] = 0.0


# -- the step -----------------------------------------------------------------------------
def step(par, st, dt, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc, nobounds):
    """One step of the 3D rigid TFP. st = [phi(2), alpha(2), rates(4)] (updated).
    agx, agy: mean ground acceleration over the step; az: vertical ground
    acceleration (gravity g + az); c_o = mu1 N1 R1 + mu4 N4 R4, c_i = mu2 N2
    R2 + mu3 N3 R3. machine = 1: the superstructure's displacement relative
    to the lower plate is imposed, u(t_n+1) = (u1x, u1y), u'(t_n+1) = (ud1x,
    ud1y) (the test machine; its force, the constraint's multiplier, is
    found by Newton on the cone program's dual, ``machine_force``; its
    start is sc[256:258]). out[O_*]: increment, input work, friction work per
    coordinate (arrests included), iterations, KKT residual, the machine's
    force, failure flag. sc: scratch of length N_SC. nobounds = 0: the rim
    circles bound the end tilts (``rim_constrain``; not under the machine),
    1: unbounded (the increment ``step_rims`` splits a step with)."""
    for i in range(N_OUT):
        out[i] = 0.0
    q0, q1, p0, x, G, H, r, Hy, ry, y, Lm, tmp, D, Dy, Fm = step_scratch(sc)
    for i in range(4):
        q0[i] = st[i]
    rb = 1 if (nobounds != 0 or machine == 1) else 0
    rim_start(par, st, rb, sc)
    # p0 = M(q0) v0
    mass_matrix(par, q0, H, tmp)
    for i in range(4):
        s = 0.0
        for j in range(4):
            s += H[4 * i + j] * st[4 + j]
        p0[i] = s
    # rims of finite stiffness (docs/model.md 6.12): no bound (nobounds = 1), their
    # force linearised in the step's problem, Newton's iteration on the increment
    springs = par[tk.I_KRIM] != 0.0
    if springs:
        rim_spring_mass(par, q0, H, sc)
    # the arc metric of each block at the start of the step, and its inverse
    metric_root(q0[0], q0[1], Lm, 0)
    metric_root(q0[2], q0[3], Lm, 4)
    for i in range(4):
        x[i] = dt * st[4 + i]
        y[i] = 0.0
    ex, ey = machine_gap(par, q0, machine, u1x, u1y, tmp)
    mfail = False
    it = 0
    converged = False
    nit = 0
    ch = 0.0
    while it < FIXED_POINT_ITERS:
        it += 1
        for i in range(4):
            q1[i] = q0[i] + x[i]
        dgrad(par, q0, q1, p0, agx, agy, az, G, sc)
        mass_matrix(par, q1, H, tmp)
        for i in range(16):
            H[i] = 2.0 * H[i] / (dt * dt)
        for i in range(4):
            r[i] = 2.0 * p0[i] / dt + G[i]
        if springs:
            sc[SP_LOSS] = rim_spring_linearise(par, q0, x, dt, G, r, H, H, r, sc)
        # in y = L dq: H' = L^-1 H L^-1, r' = L^-1 r (L block-diagonal, symmetric)
        _to_metric(H, r, Lm, Hy, ry, tmp)
        if machine == 1:
            # D: the discrete gradient of u (D^T dq = u(q1) - u(q0)); in y, L^-1 D
            dgrad_u(par, q0, q1, D, sc)
            to_y(Lm, D, Dy)
            if machine_force(Hy, ry, Dy, c_o, c_i, ex, ey, y, Fm, sc) != 0:
                mfail = True
        else:
            nit += socp(Hy, ry, c_o, c_i, y, sc)
            if rb == 0:
                nit += rim_constrain(par, q0, x, Lm, Hy, ry, c_o, c_i, y, rb, sc)
        # dq = L^-1 y
        for blk in range(2):
            tmp[2 * blk], tmp[2 * blk + 1] = linv(Lm, blk, y[2 * blk], y[2 * blk + 1])
        if rb == 0 and it > 6 and rim_involved(sc):
            rim_relax(x, tmp, sc, 0.0)
        if springs and it > 6:
            # (a block held by its springs, the other fast: the iteration may alternate,
            # or creep at a ratio near 0.65 deep past a rim at a large step)
            rim_relax(x, tmp, sc, 0.9)
        ch = 0.0
        for i in range(4):
            ch += abs(tmp[i] - x[i])
            x[i] = tmp[i]
        if ch <= FIXED_POINT_TOL:
            converged = True
            break
        if springs and rim_spring_settled(ch, x):
            converged = True
            break
    fixed_point_end(converged, ch, x, mfail, out)
    if rb == 0:
        rim_snap(par, q0, x, y, ry, Lm, rb, sc)
    machine_kkt(Hy, ry, Dy, Fm, c_o, c_i, y, machine, out)
    # the generalised force of friction Phi = r - H dq; p1 = p0 + dt (G - Phi)
    for i in range(4):
        s = 0.0
        for j in range(4):
            s += H[4 * i + j] * x[j]
        s = r[i] - s
        tmp[i] = p0[i] + dt * (G[i] - s)          # p1
        sc[R_PHI + i] = s
    # the rates in the metric the last iterate's program was built with (q1
    # still holds that iterate's end, within the fixed point's tolerance of
    # the final one: the planar TFP's order of operations)
    mass_matrix(par, q1, H, tmp[8:20])
    for i in range(4):
        q1[i] = q0[i] + x[i]
    solve4(H, tmp[0:4], tmp[4:8])
    for i in range(4):
        st[4 + i] = tmp[4 + i]
    for i in range(4):
        st[i] = q1[i]
    wo, wi, ein = step_work(par, q0, q1, x, y, D, Fm, agx, agy, az, c_o, c_i, machine, out, tmp)
    # a block that stuck ends at rest: an impulse on it alone (the other keeps its momentum)
    z1 = x[0] == 0.0 and x[1] == 0.0
    z2 = x[2] == 0.0 and x[3] == 0.0
    arr_o = 0.0
    arr_i = 0.0
    if rb == 0 and rim_involved(sc):
        rim_velocities(par, q0, q1, x, st, H, dt, c_o, c_i, y, Lm, par[tk.I_REST], sc)
        arr_o = sc[R_OUT + 1]
        arr_i = sc[R_OUT + 2]
        out[O_RIM] = sc[R_OUT]
        out[O_DXR] = sc[R_OUT + 3]
        out[O_DXR + 1] = sc[R_OUT + 4]
        out[O_HIT_O] = sc[R_OUT + 5]
        out[O_HIT_I] = sc[R_OUT + 6]
        if sc[R_OUT + 5] != 0.0 or sc[R_OUT + 6] != 0.0:
            out[O_ARRIVE] = 1.0
    elif z1 or z2:
        # p = M(q1) v
        for i in range(4):
            s = 0.0
            for j in range(4):
                s += H[4 * i + j] * st[4 + j]
            tmp[i] = s
        arr_o, arr_i = arrest(par, q1, H, st[4:8], z1, z2, tmp)
    if machine == 1:
        # the machine imposes u'(t_n+1) through the blocks still sliding: the
        # kinetic-metric projection (an impulse along C^T), its energy input
        ein += machine_velocity(par, st, H, z1, z2, ud1x, ud1y, sc)
    step_out(out, x, ein, wo, wi, arr_o, arr_i, it)
    if springs:
        out[O_RIM] = sc[SP_LOSS]
    # the test machine runs without rims: one reached stops it
    if machine == 1 and past_rims(par, st):
        out[O_FAIL] = FAIL_RIM


def step_scratch(sc):
    """The step's arrays in its scratch sc: q0, q1, p0, the increment x, G, H,
    r, Hy, ry, y, the arc metric Lm, tmp and the machine's D, Dy, F."""
    return (sc[100:104], sc[104:108], sc[108:112], sc[112:116], sc[116:120], sc[120:136], sc[136:140],
            sc[140:156], sc[156:160], sc[160:164], sc[164:172], sc[180:200], sc[240:248], sc[248:256],
            sc[256:258])


def machine_gap(par, q0, machine, u1x, u1y, tmp):
    """What the test machine (machine = 1) still imposes on u over the step,
    u(t_n+1) - u(q0) (0, 0 without it). tmp: scratch >= 3."""
    if machine != 1:
        return 0.0, 0.0
    u_rel(par, q0, tmp)
    return u1x - tmp[0], u1y - tmp[1]


def linv(Lm, blk, a0, a1):
    """L^-1 (a0, a1) for the block blk of the arc metric Lm (``metric_root``),
    through L^-1's entries (as ``_to_metric``): along a tilt on an axis the
    entry along it is 1 exactly and the cross entry 0, so that component is
    its a to the last bit (the planar TFP's increment)."""
    k = 4 * blk
    det = Lm[k + 3]
    i11 = Lm[k + 2] / det
    i12 = -Lm[k + 1] / det
    i22 = Lm[k] / det
    return i11 * a0 + i12 * a1, i12 * a0 + i22 * a1


def to_y(Lm, D, Dy):
    """Dy = L^-1 D, the machine's discrete gradient D (4 x 2, row-major) in y = L dq."""
    for blk in range(2):
        i0 = 2 * blk
        for c in range(2):
            Dy[2 * i0 + c], Dy[2 * i0 + 2 + c] = linv(Lm, blk, D[2 * i0 + c], D[2 * i0 + 2 + c])


def fixed_point_end(converged, ch, x, mfail, out):
    """The fixed point's failure flags: not converged beyond round-off, the machine's force not found."""
    if not converged and ch > 1e-12 * (1.0 + abs(x[0]) + abs(x[1]) + abs(x[2]) + abs(x[3])):
        out[O_FAIL] = FAIL_FIXED_POINT
    if mfail:
        out[O_FAIL] = FAIL_CAPACITY


def machine_kkt(Hy, ry, Dy, Fm, c_o, c_i, y, machine, out):
    """The step's KKT residual into out; under the machine, of the cone program
    its force makes (r' + Dy F: Phi = r - H dq is then friction less the
    machine's force)."""
    if machine == 1:
        for i in range(4):
            ry[i] += Dy[2 * i] * Fm[0] + Dy[2 * i + 1] * Fm[1]
    out[O_KKT] = kkt_residual(Hy, ry, c_o, c_i, y)


def step_work(par, q0, q1, x, y, D, Fm, agx, agy, az, c_o, c_i, machine, out, tmp):
    """The step's friction work on each pair of surfaces before the arrests
    (c |L dq|) and its input: the ground's (horizontal and vertical) work on
    the relative motion and the machine's, F . (D^T dq) (its force into out).
    Returns (wo, wi, ein). tmp: scratch >= 3."""
    wo = c_o * math.sqrt(y[0] * y[0] + y[1] * y[1])
    wi = c_i * math.sqrt(y[2] * y[2] + y[3] * y[3])
    moments(par, q0, tmp)
    b0x, b0y, b0z = tmp[0], tmp[1], tmp[2]
    moments(par, q1, tmp)
    ein = -agx * (tmp[0] - b0x) - agy * (tmp[1] - b0y) - az * (tmp[2] - b0z)
    if machine == 1:
        for i in range(4):
            ein += (D[2 * i] * Fm[0] + D[2 * i + 1] * Fm[1]) * x[i]
        out[O_FX] = Fm[0]
        out[O_FY] = Fm[1]
    return wo, wi, ein


def stop_block(M, v, blk, p):
    """An impulse on block blk alone brings it to rest: the other block keeps
    its momentum p = M v (given), its rates M_oo^-1 p_o."""
    o = 2 - 2 * blk
    m11, m12, m22 = M[5 * o], M[5 * o + 1], M[5 * o + 5]
    v[2 * blk] = 0.0
    v[2 * blk + 1] = 0.0
    # by elimination (the second component first): with m12 = 0 each rate is
    # its momentum over its mass, the planar TFP's arrest to the last bit
    k = m12 / m11
    v[o + 1] = (p[o + 1] - k * p[o]) / (m22 - k * m12)
    v[o] = (p[o] - m12 * v[o + 1]) / m11


def arrest(par, q, M, v, z1, z2, tmp):
    """The blocks that stuck (z1: phi's, z2: alpha's) end at rest in the
    metric M at q: an impulse on one alone, the other keeping its momentum
    (tmp[0:4] = M v, given); both: all of it. Returns the kinetic energy
    taken from each, (arr_o, arr_i). tmp: scratch >= 20."""
    K0 = kinetic(par, q, v, tmp[8:20])
    stop_block(M, v, 0 if z1 else 1, tmp)
    Ka = kinetic(par, q, v, tmp[8:20])
    if not z1:
        return 0.0, K0 - Ka
    if z2:
        v[2] = 0.0
        v[3] = 0.0
        return K0 - Ka, Ka
    return K0 - Ka, 0.0


def step_out(out, x, ein, wo, wi, arr_o, arr_i, it):
    """The step's increment, input, friction work (arrests included) and iterations into out."""
    for i in range(4):
        out[O_DQ + i] = x[i]
    out[O_EIN] = ein
    out[O_WO] = wo + arr_o
    out[O_WI] = wi + arr_i
    out[O_ARR_O] = arr_o
    out[O_ARR_I] = arr_i
    out[O_ITER] = it


def past_rims(par, st):
    """The end tilts past a rim circle: |phi| > qmax_phi or |alpha| > qmax_alpha."""
    if par[tk.I_KRIM] != 0.0:
        return False            # (rims of finite stiffness: a tilt may pass them)
    tp = st[0] * st[0] + st[1] * st[1]
    ta = st[2] * st[2] + st[3] * st[3]
    qm, qa = par[tk.I_QMAX_PHI], par[tk.I_QMAX_ALPHA]
    return tp > qm * qm or ta > qa * qa


def grad_u(par, q, o):
    """The Jacobian of u(q) (the superstructure's horizontal displacement):
    o[2 i + k] = du_k / dq_i."""
    A, Li = par[tk.I_A], par[tk.I_LI]
    px, py = q[0], q[1]
    sx, sy = q[0] + q[2], q[1] + q[3]
    tp = px * px + py * py
    ts = sx * sx + sy * sy
    s_p, s_s = sfun(tp), sfun(ts)
    d_p, d_s = _sder(tp), _sder(ts)
    # Dh(v)[w] = s w + 2 s' (v . w) v
    for j in range(2):
        wx = 1.0 if j == 0 else 0.0
        wy = 1.0 - wx
        vs = sx * wx + sy * wy
        vp = px * wx + py * wy
        hsx = s_s * wx + 2.0 * d_s * vs * sx
        hsy = s_s * wy + 2.0 * d_s * vs * sy
        o[2 * j] = A * (s_p * wx + 2.0 * d_p * vp * px) + Li * hsx
        o[2 * j + 1] = A * (s_p * wy + 2.0 * d_p * vp * py) + Li * hsy
        o[2 * (2 + j)] = Li * hsx
        o[2 * (2 + j) + 1] = Li * hsy


def dgrad_u(par, q0, q1, D, sc):
    """The discrete gradient of u from q0 to q1 (blockwise, Gauss-Legendre,
    as ``dgrad``) into D (4x2): D^T (q1 - q0) = u(q1) - u(q0) to round-off.
    sc: scratch (uses sc[60:64], sc[66:74])."""
    for i in range(8):
        D[i] = 0.0
    for blk in range(2):
        for k in range(4):
            if k == 0:
                x, w = GL_X0, GL_W0
            elif k == 1:
                x, w = GL_X1, GL_W1
            elif k == 2:
                x, w = 1.0 - GL_X1, GL_W1
            else:
                x, w = 1.0 - GL_X0, GL_W0
            if blk == 0:
                sc[60] = q0[0] + x * (q1[0] - q0[0])
                sc[61] = q0[1] + x * (q1[1] - q0[1])
                sc[62] = q0[2]
                sc[63] = q0[3]
            else:
                sc[60] = q1[0]
                sc[61] = q1[1]
                sc[62] = q0[2] + x * (q1[2] - q0[2])
                sc[63] = q0[3] + x * (q1[3] - q0[3])
            grad_u(par, sc[60:64], sc[66:74])
            for i in range(2):
                for c in range(2):
                    D[2 * (2 * blk + i) + c] += w * sc[66 + 2 * (2 * blk + i) + c]


def _jac(H, y, c1, c2, Dy, J, sc):
    """J = Dy_S^T (H + K_f)_SS^-1 Dy_S over the sliding blocks S of y (K_f the
    friction's curvature c / |y_k| (I - y_k y_k^T / |y_k|^2)); with no block
    sliding, the frictionless Dy^T H^-1 Dy. J = (J11, J12, J22)."""
    na = math.sqrt(y[0] * y[0] + y[1] * y[1])
    nb = math.sqrt(y[2] * y[2] + y[3] * y[3])
    for i in range(16):
        sc[300 + i] = H[i]
    if na > 0.0:
        ka = c1 / (na * na * na)
        sc[300] += ka * y[1] * y[1]
        sc[301] -= ka * y[0] * y[1]
        sc[304] -= ka * y[0] * y[1]
        sc[305] += ka * y[0] * y[0]
    if nb > 0.0:
        kb = c2 / (nb * nb * nb)
        sc[310] += kb * y[3] * y[3]
        sc[311] -= kb * y[2] * y[3]
        sc[314] -= kb * y[2] * y[3]
        sc[315] += kb * y[2] * y[2]
    if (na == 0.0) != (nb == 0.0):
        # one block: its 2x2 part alone
        i0 = 0 if na > 0.0 else 2
        m11 = sc[300 + 4 * i0 + i0]
        m12 = sc[300 + 4 * i0 + i0 + 1]
        m22 = sc[300 + 4 * (i0 + 1) + i0 + 1]
        det = m11 * m22 - m12 * m12
        for c in range(2):
            a0 = Dy[2 * i0 + c]
            a1 = Dy[2 * (i0 + 1) + c]
            sc[320 + 4 * i0 + 2 * c] = (m22 * a0 - m12 * a1) / det
            sc[320 + 4 * i0 + 2 * c + 1] = (m11 * a1 - m12 * a0) / det
        J[0] = Dy[2 * i0] * sc[320 + 4 * i0] + Dy[2 * (i0 + 1)] * sc[320 + 4 * i0 + 1]
        J[1] = Dy[2 * i0] * sc[320 + 4 * i0 + 2] + Dy[2 * (i0 + 1)] * sc[320 + 4 * i0 + 3]
        J[2] = Dy[2 * i0 + 1] * sc[320 + 4 * i0 + 2] + Dy[2 * (i0 + 1) + 1] * sc[320 + 4 * i0 + 3]
        return
    for c in range(2):
        for i in range(4):
            sc[330 + i] = Dy[2 * i + c]
        chol_solve(sc[300:316], sc[330:334], sc[334 + 4 * c:338 + 4 * c], sc[342:358])
    J[0] = 0.0
    J[1] = 0.0
    J[2] = 0.0
    for i in range(4):
        J[0] += Dy[2 * i] * sc[334 + i]
        J[1] += Dy[2 * i] * sc[338 + i]
        J[2] += Dy[2 * i + 1] * sc[338 + i]


def _force_trial(Hy, ry, Dy, c1, c2, ex, ey, F0, F1, y, sc):
    """The machine's residual |Dy^T y(F) - e|^2 at the force (F0, F1), y(F)
    the cone program's minimiser with r' + Dy F (into sc[368:372], started
    from y), and whether the bearing is stuck there (y(F) = 0)."""
    for i in range(4):
        sc[360 + i] = ry[i] + Dy[2 * i] * F0 + Dy[2 * i + 1] * F1
        sc[368 + i] = y[i]
    socp(Hy, sc[360:364], c1, c2, sc[368:372], sc)
    S0 = -ex
    S1 = -ey
    for i in range(4):
        S0 += Dy[2 * i] * sc[368 + i]
        S1 += Dy[2 * i + 1] * sc[368 + i]
    stuck = sc[368] == 0.0 and sc[369] == 0.0 and sc[370] == 0.0 and sc[371] == 0.0
    return S0 * S0 + S1 * S1, stuck


def machine_force(Hy, ry, Dy, c1, c2, ex, ey, y, F, sc):
    """The test machine's force F (the multiplier of Dy^T y = e): Newton on
    R(F) = Dy^T y(F) - e, y(F) the cone program's minimiser with r' + Dy F
    (R is minus the gradient of the concave dual, its Jacobian J of ``_jac``
    positive definite), halving the step until |R| falls. F: start in, the
    force out; y: the minimiser. Returns 0, or 1 if R did not vanish."""
    rn = 0.0
    tol = 1e-13 * math.sqrt(ex * ex + ey * ey) + 1e-300
    for it in range(80):
        for i in range(4):
            sc[360 + i] = ry[i] + Dy[2 * i] * F[0] + Dy[2 * i + 1] * F[1]
        socp(Hy, sc[360:364], c1, c2, y, sc)
        R0 = -ex
        R1 = -ey
        for i in range(4):
            R0 += Dy[2 * i] * y[i]
            R1 += Dy[2 * i + 1] * y[i]
        rn = math.sqrt(R0 * R0 + R1 * R1)
        if rn <= tol:
            return 0
        _jac(Hy, y, c1, c2, Dy, sc[364:367], sc)
        j11, j12, j22 = sc[364], sc[365], sc[366]
        det = j11 * j22 - j12 * j12
        d0 = (j22 * R0 - j12 * R1) / det
        d1 = (j11 * R1 - j12 * R0) / det
        f0, f1 = F[0], F[1]
        lam = 1.0
        if y[0] == 0.0 and y[1] == 0.0 and y[2] == 0.0 and y[3] == 0.0:
            # stuck at F (a reversal of the programme): R = -e on the whole stuck
            # region, which the Newton step (the frictionless Jacobian's) does not
            # leave; the step is stretched until it leaves it, then bisected to a
            # force with a smaller residual (a stuck trial: further; past: nearer)
            lo, hi = 0.0, 1.0
            found = False
            for k in range(64):
                S2, st = _force_trial(Hy, ry, Dy, c1, c2, ex, ey, f0 - hi * d0, f1 - hi * d1, y, sc)
                if S2 < rn * rn:
                    found = True
                    break
                if not st:
                    break
                lo = hi
                hi *= 2.0
            if not found:
                for k in range(200):
                    mid = 0.5 * (lo + hi)
                    S2, st = _force_trial(Hy, ry, Dy, c1, c2, ex, ey, f0 - mid * d0, f1 - mid * d1, y, sc)
                    if S2 < rn * rn:
                        hi = mid
                        break
                    if st:
                        lo = mid
                    else:
                        hi = mid
            lam = hi
        for ls in range(40):
            F[0] = f0 - lam * d0
            F[1] = f1 - lam * d1
            S2, st = _force_trial(Hy, ry, Dy, c1, c2, ex, ey, F[0], F[1], y, sc)
            if S2 < rn * rn:
                break
            lam *= 0.5
        if abs(lam * d0) + abs(lam * d1) <= 1e-16 * (abs(f0) + abs(f1)):
            break
    # the last F: its minimiser
    for i in range(4):
        sc[360 + i] = ry[i] + Dy[2 * i] * F[0] + Dy[2 * i + 1] * F[1]
    socp(Hy, sc[360:364], c1, c2, y, sc)
    R0 = -ex
    R1 = -ey
    for i in range(4):
        R0 += Dy[2 * i] * y[i]
        R1 += Dy[2 * i + 1] * y[i]
    if math.sqrt(R0 * R0 + R1 * R1) <= 1e-9 * math.sqrt(ex * ex + ey * ey) + 1e-300:
        return 0
    return 1


def machine_velocity(par, st, M, z1, z2, udx, udy, sc):
    """The machine imposes u'(t_n+1) = (udx, udy): the rates of the sliding
    blocks change by M_SS^-1 C_S^T lam with C = du/dq at q1 so that C v =
    u'. Returns the kinetic energy it adds (input). M: M(q1)."""
    if z1 and z2:
        return 0.0
    K0 = kinetic(par, st[0:4], st[4:8], sc[380:392])
    grad_u(par, st[0:4], sc[280:288])
    C = sc[280:288]
    rx = udx
    ry_ = udy
    for i in range(4):
        rx -= C[2 * i] * st[4 + i]
        ry_ -= C[2 * i + 1] * st[4 + i]
    # W = M_SS^-1 C_S^T (columns) for the sliding blocks
    for i in range(8):
        sc[288 + i] = 0.0
    if not z1 and not z2:
        for c in range(2):
            for i in range(4):
                sc[392 + i] = C[2 * i + c]
            chol_solve(M, sc[392:396], sc[396:400], sc[300:316])
            for i in range(4):
                sc[288 + 2 * i + c] = sc[396 + i]
    else:
        i0 = 2 if z1 else 0
        m11 = M[4 * i0 + i0]
        m12 = M[4 * i0 + i0 + 1]
        m22 = M[4 * (i0 + 1) + i0 + 1]
        det = m11 * m22 - m12 * m12
        for c in range(2):
            a0 = C[2 * i0 + c]
            a1 = C[2 * (i0 + 1) + c]
            sc[288 + 2 * i0 + c] = (m22 * a0 - m12 * a1) / det
            sc[288 + 2 * (i0 + 1) + c] = (m11 * a1 - m12 * a0) / det
    # (C W) lam = residual
    a11 = 0.0
    a12 = 0.0
    a21 = 0.0
    a22 = 0.0
    for i in range(4):
        a11 += C[2 * i] * sc[288 + 2 * i]
        a12 += C[2 * i] * sc[288 + 2 * i + 1]
        a21 += C[2 * i + 1] * sc[288 + 2 * i]
        a22 += C[2 * i + 1] * sc[288 + 2 * i + 1]
    det = a11 * a22 - a12 * a21
    if det == 0.0:
        return 0.0
    l0 = (a22 * rx - a12 * ry_) / det
    l1 = (a11 * ry_ - a21 * rx) / det
    for i in range(4):
        st[4 + i] += sc[288 + 2 * i] * l0 + sc[288 + 2 * i + 1] * l1
    return kinetic(par, st[0:4], st[4:8], sc[380:392]) - K0


def _to_metric(H, r, Lm, Hy, ry, tmp):
    """Hy = Li H Li, ry = Li r with Li = L^-1 (block-diagonal 2x2 blocks of Lm)."""
    # Li as a dense 4x4 into tmp[0:16]
    for i in range(16):
        tmp[i] = 0.0
    for blk in range(2):
        k0 = 4 * blk
        l11, l12, l22, det = Lm[k0], Lm[k0 + 1], Lm[k0 + 2], Lm[k0 + 3]
        i0 = 2 * blk
        tmp[4 * i0 + i0] = l22 / det
        tmp[4 * i0 + i0 + 1] = -l12 / det
        tmp[4 * (i0 + 1) + i0] = -l12 / det
        tmp[4 * (i0 + 1) + i0 + 1] = l11 / det
    for i in range(4):
        s = 0.0
        for j in range(4):
            s += tmp[4 * i + j] * r[j]
        ry[i] = s
    for i in range(4):
        for j in range(4):
            s = 0.0
            for a in range(4):
                la = tmp[4 * i + a]
                if la == 0.0:
                    continue
                for b in range(4):
                    lb = tmp[4 * b + j]
                    if lb == 0.0:
                        continue
                    s += la * H[4 * a + b] * lb
            Hy[4 * i + j] = s


# -- the rims (docs/model.md section 6.11) -----------------------------------------------------
# scratch of the rims in sc[RB:RB + 100]
RB = 420
R_M, R_H, R_N, R_NU, R_ACT, R_RS, R_ON0, R_V0 = 420, 424, 426, 430, 432, 434, 438, 440
R_PHI = 444          # the step's generalised force of friction and rims, r - H dq (q-space)
R_MR, R_VR, R_WR, R_PR, R_LL, R_B, R_X = 448, 464, 468, 472, 476, 492, 496
R_C, R_ROT, R_OUT, R_Q = 500, 508, 516, 524   # R_OUT: rim loss, arr_o, arr_i, dxr (2), hits (2)
R_SAVE, R_ACC = 532, 540                      # the part's start state (8), the parts' outputs (N_OUT)
R_SV = R_ACC + N_OUT                          # the rim point (8)
R_UD = R_SV + 8                               # u' scratch (6), u'(start), u'(part start), u'(free) (2 each)
R_MM, R_VF = R_UD + 12, R_UD + 28            # a mass matrix (16), the free rates (4)
R_DXP, R_OM = R_VF + 4, R_VF + 8             # the fixed point's last change (4) and relaxation
R_NW = R_OM + 1                              # the last multipliers (2): Newton's start
N_SC_RIM = R_NW + 2
R_DM, R_JN, R_YS = 404, 412, 416             # Newton's m (8), J (3), y's start (4)
RIM_STALL, RIM_NOISE = 1e-9, 1e-12           # Newton's stalled steps against nu (one rim, both)


def rim_qmax(par, k, nobounds):
    if nobounds != 0:
        return 1e30
    return par[tk.I_QMAX_PHI] if k == 0 else par[tk.I_QMAX_ALPHA]


def rim_start(par, st, nobounds, sc):
    """Before a step: which blocks start on their rims (|q0_k| within 1e-13 of
    qmax_k, or past it by round-off), and the start rates."""
    for k in range(2):
        qm = rim_qmax(par, k, nobounds)
        nq = math.sqrt(st[2 * k] * st[2 * k] + st[2 * k + 1] * st[2 * k + 1])
        sc[R_ON0 + k] = 1.0 if nq >= qm * (1.0 - 1e-13) else 0.0
        sc[R_ACT + k] = 0.0
        sc[R_NU + k] = 0.0
        sc[R_NW + k] = 0.0
    for i in range(4):
        sc[R_V0 + i] = st[4 + i]
        sc[R_DXP + i] = 0.0
    sc[R_OM] = 1.0


def _rim_eval(H, r, c1, c2, y, nua, nub, sc):
    """y = the cone program's minimiser with r less the rims' reactions nu_k m_k."""
    for i in range(2):
        sc[R_RS + i] = r[i] - nua * sc[R_M + i]
        sc[R_RS + 2 + i] = r[2 + i] - nub * sc[R_M + 2 + i]
    return socp(H, sc[R_RS:R_RS + 4], c1, c2, y, sc)


def _rim_gap(k, y, sc):
    """m_k . y_k - h_k: > 0 past the rim's tangent line."""
    return sc[R_M + 2 * k] * y[2 * k] + sc[R_M + 2 * k + 1] * y[2 * k + 1] - sc[R_H + k]


def _rim_scale(H, k, sc):
    """m_k^T H_kk^-1 m_k: the gap's rate of fall with nu_k when block k alone slides."""
    i0 = 2 * k
    a11, a12, a22 = H[4 * i0 + i0], H[4 * i0 + i0 + 1], H[4 * (i0 + 1) + i0 + 1]
    m0, m1 = sc[R_M + i0], sc[R_M + i0 + 1]
    return (a22 * m0 * m0 - 2.0 * a12 * m0 * m1 + a11 * m1 * m1) / (a11 * a22 - a12 * a12)


def _rim_inner(H, r, c1, c2, y, nua, sc):
    """nu_b >= 0 for the given nu_a: 0 if block b's rim does not act (then y
    is the minimiser at (nu_a, 0)), else the root of block b's gap (nonincreasing
    in nu_b: minus the derivative of the concave dual), by regula falsi
    (Illinois) in a bracket grown by fours. y: the minimiser at the result."""
    its = _rim_eval(H, r, c1, c2, y, nua, 0.0, sc)
    if sc[R_ACT + 1] == 0.0:
        return 0.0
    flo = _rim_gap(1, y, sc)
    if flo <= 0.0:
        return 0.0
    lo = 0.0
    hi = 1.5 * flo / _rim_scale(H, 1, sc) + 1e-300
    fhi = 0.0
    for k in range(200):
        its += _rim_eval(H, r, c1, c2, y, nua, hi, sc)
        fhi = _rim_gap(1, y, sc)
        if fhi <= 0.0:
            break
        lo, flo = hi, fhi
        hi *= 4.0
    side = 0
    for k in range(200):
        if _falsi_done(lo, hi, fhi):
            break
        x = _falsi_point(lo, flo, hi, fhi)
        its += _rim_eval(H, r, c1, c2, y, nua, x, sc)
        lo, flo, hi, fhi, side = _falsi(lo, flo, hi, fhi, side, x, _rim_gap(1, y, sc))
    its += _rim_eval(H, r, c1, c2, y, nua, hi, sc)
    return hi


def _falsi_done(lo, hi, fhi):
    """The bracket [lo, hi] has its root: a zero gap at hi, a width of 2e-16
    of hi, or two adjacent floats (just above a power of two their spacing is
    2.2e-16 of the value, so the width alone cannot always be met)."""
    return fhi == 0.0 or hi - lo <= 2e-16 * hi or not lo < 0.5 * (lo + hi) < hi


def _falsi_point(lo, flo, hi, fhi):
    """The regula falsi's next point in [lo, hi] (the gaps flo > 0 >= fhi), its middle past round-off."""
    x = lo + (hi - lo) * flo / (flo - fhi)
    if not (lo < x < hi):
        x = 0.5 * (lo + hi)
    return x


def _falsi(lo, flo, hi, fhi, side, x, fx):
    """The bracket after the gap fx at x (Illinois: the end kept twice in a
    row has its gap halved). Returns (lo, flo, hi, fhi, side)."""
    if fx > 0.0:
        if side == 1:
            fhi *= 0.5
        return x, fx, hi, fhi, 1
    if side == -1:
        flo *= 0.5
    return lo, flo, x, fx, -1


def _rim_nu(sc, nua, nub):
    sc[R_NU] = nua
    sc[R_NU + 1] = nub
    return 0


def rim_newton(H, r, c1, c2, y, sc):
    """``rim_socp``'s dual by projected Newton from sc[R_NW:R_NW + 2] (docs/model.md
    6.11; the gaps' Jacobian -m^T (H + K_f)_SS^-1 m, ``_jac``): y, sc[R_NU:R_NU + 2]
    and 0, or 1 if it did not settle (the caller's bracketed search)."""
    act0 = sc[R_ACT] != 0.0
    act1 = sc[R_ACT + 1] != 0.0
    nua = sc[R_NW] if act0 else 0.0
    nub = sc[R_NW + 1] if act1 else 0.0
    for i in range(4):          # m as a 4 x 2 (row i, column i // 2)
        sc[R_DM + 2 * i + i // 2] = sc[R_M + i]
        sc[R_DM + 2 * i + 1 - i // 2] = 0.0
    prev = 1.0
    for it in range(40):
        _rim_eval(H, r, c1, c2, y, nua, nub, sc)
        ga = _rim_gap(0, y, sc) if act0 else -1.0
        gb = _rim_gap(1, y, sc) if act1 else -1.0
        wa = act0 and (nua > 0.0 or ga > 0.0)
        wb = act1 and (nub > 0.0 or gb > 0.0)
        if not wa and not wb:
            return _rim_nu(sc, 0.0, 0.0)
        _jac(H, y, c1, c2, sc[R_DM:R_DM + 8], sc[R_JN:R_JN + 3], sc)
        j11, j12, j22 = sc[R_JN], sc[R_JN + 1], sc[R_JN + 2]
        det = j11 * j22 - j12 * j12
        if wa and wb and not (det > 0.0 and j11 > 0.0):
            return 1
        if wa != wb and not (j11 if wa else j22) > 0.0:
            # the held block stuck at y(nu), the dual flat: a zero gap is a root, else below
            if (ga if wa else gb) == 0.0:
                return _rim_nu(sc, nua, nub)
            return _rim_narrow(H, r, c1, c2, y, sc, 0 if wa else 1, nua + nub, 0.25 * (nua + nub), ga if wa else gb)
        if wa and wb:
            da = (j22 * ga - j12 * gb) / det
            db = (j11 * gb - j12 * ga) / det
        else:
            da = ga / j11 if wa else 0.0
            db = gb / j22 if wb else 0.0
        ra = (abs(da) / nua if nua > 0.0 else 1.0) if wa else 0.0
        rb = (abs(db) / nub if nub > 0.0 else 1.0) if wb else 0.0
        if (not wa or ga == 0.0 or ra <= 4e-16) and (not wb or gb == 0.0 or rb <= 4e-16):
            return _rim_nu(sc, nua, nub)
        rel = max(ra, rb)       # steps stalled in the gaps' round-off
        if rel <= RIM_STALL and rel >= 0.5 * prev:
            if wa != wb:
                return _rim_narrow(H, r, c1, c2, y, sc, 0 if wa else 1, nua + nub, da + db, ga if wa else gb)
            if rel <= RIM_NOISE:
                return _rim_nu(sc, nua, nub)
        prev = rel
        nua = max(nua + da, 0.0)
        nub = max(nub + db, 0.0)
    return 1


def _rim_at(H, r, c1, c2, y, sc, k, x):
    """Block k's gap at nu_k = x, the other multiplier 0 (y the minimiser there)."""
    _rim_eval(H, r, c1, c2, y, x if k == 0 else 0.0, x if k == 1 else 0.0, sc)
    return _rim_gap(k, y, sc)


def _rim_narrow(H, r, c1, c2, y, sc, k, x, d, g):
    """Block k's rim alone holding, Newton stalled at x (gap g, last step d): a bracket
    about x grown from 2 |d| by fours (to 0 at most: a gap <= 0 there, no reaction),
    rim_search's regula falsi to 2e-16, y at its upper end. 0, or 1: fall back."""
    w = max(2.0 * abs(d), 4e-16 * x)
    lo, flo, hi, fhi = x, g, x, g
    up = g > 0.0
    for it in range(60):
        z = x + w if up else max(x - w, 0.0)
        fz = _rim_at(H, r, c1, c2, y, sc, k, z)
        if fz > 0.0:
            lo, flo = z, fz
        else:
            hi, fhi = z, fz
        if (fz > 0.0) != up or z == 0.0:
            break
        w *= 4.0
    side = 0
    for it in range(200):
        if flo <= 0.0 or fhi > 0.0 or _falsi_done(lo, hi, fhi):
            break
        xm = _falsi_point(lo, flo, hi, fhi)
        lo, flo, hi, fhi, side = _falsi(lo, flo, hi, fhi, side, xm, _rim_at(H, r, c1, c2, y, sc, k, xm))
    if flo <= 0.0:
        hi = 0.0
    elif fhi > 0.0:
        return 1
    _rim_at(H, r, c1, c2, y, sc, k, hi)
    if sc[R_ACT + 1 - k] != 0.0 and _rim_gap(1 - k, y, sc) > 0.0:
        return 1
    return _rim_nu(sc, hi if k == 0 else 0.0, hi if k == 1 else 0.0)


def rim_socp(H, r, c1, c2, y, sc):
    """``socp`` with the rims' half-planes m_k . y_k <= h_k (blocks flagged at
    sc[R_ACT + k]) on its concave dual over nu >= 0 (its gradient the gaps), by
    Newton, else the bracketed search from the same start. The minimiser into
    y, the multipliers into sc[R_NU:R_NU + 2] and sc[R_NW:R_NW + 2]."""
    sc[R_YS:R_YS + 4] = y[0:4]
    if rim_newton(H, r, c1, c2, y, sc) != 0:
        y[0:4] = sc[R_YS:R_YS + 4]
        rim_search(H, r, c1, c2, y, sc)
    sc[R_NW:R_NW + 2] = sc[R_NU:R_NU + 2]
    return 0


def rim_search(H, r, c1, c2, y, sc):
    """``rim_socp``'s bracketed search: nu_b for each nu_a (``_rim_inner``), nu_a
    by the same regula falsi on a's gap (the dual maximised over nu_b)."""
    its = 0
    nub = _rim_inner(H, r, c1, c2, y, 0.0, sc)
    nua = 0.0
    if sc[R_ACT] != 0.0:
        flo = _rim_gap(0, y, sc)
        if flo > 0.0:
            lo = 0.0
            hi = 1.5 * flo / _rim_scale(H, 0, sc) + 1e-300
            fhi = 0.0
            for k in range(200):
                nub = _rim_inner(H, r, c1, c2, y, hi, sc)
                fhi = _rim_gap(0, y, sc)
                if fhi <= 0.0:
                    break
                lo, flo = hi, fhi
                hi *= 4.0
            side = 0
            for k in range(200):
                if _falsi_done(lo, hi, fhi):
                    break
                x = _falsi_point(lo, flo, hi, fhi)
                nub = _rim_inner(H, r, c1, c2, y, x, sc)
                lo, flo, hi, fhi, side = _falsi(lo, flo, hi, fhi, side, x, _rim_gap(0, y, sc))
            nua = hi
            nub = _rim_inner(H, r, c1, c2, y, nua, sc)
    sc[R_NU] = nua
    sc[R_NU + 1] = nub
    return its


def rim_constrain(par, q0, x, Lm, H, r, c1, c2, y, nobounds, sc):
    """Inside the step's fixed point, after the unconstrained cone program:
    a block whose end tilt q0_k + dq_k (dq_k = L_k^-1 y_k) lies past its rim
    circle |q_k| = qmax_k is held by the rim's tangent line there, n_k . q_k <=
    qmax_k, n_k the outward normal at the previous iterate's end point if that
    was held (or on the rim), else at the unconstrained one: in y, m_k . y_k <= h_k with
    m_k = L_k^-1 n_k, h_k = qmax_k - n_k . q0_k (0 for a block that starts on
    its rim, as the planar box). At the fixed point n_k is the normal at q1_k
    itself, so q1_k lies on the circle. The held blocks' normal components are
    then set on their lines exactly. Returns the Newton iterations.

    A block the previous iterate held (multiplier nu_k) adds the rim's
    curvature to the program first, the Hessian of nu_k (|q_k| - qmax_k) at
    that iterate's point qb_k on the circle, nu_k / qmax_k t t^T (t the
    tangent; the sequential quadratic programming step): 1/2 nu_k / qmax_k
    (t . (q_k - qb_k))^2, which vanishes with its gradient at the fixed point
    (q1_k = qb_k) but keeps the iteration from running along the tangent
    when a light mode is pressed hard into a rim (without it the full lock
    in two directions diverges)."""
    its = 0
    curv = 0
    hp0 = sc[R_ACT] != 0.0 and sc[R_NU] > 0.0
    hp1 = sc[R_ACT + 1] != 0.0 and sc[R_NU + 1] > 0.0
    for k in range(2):
        held = hp0 if k == 0 else hp1
        nu = sc[R_NU + k]
        sc[R_ACT + k] = 0.0
        sc[R_NU + k] = 0.0
        if not held:
            continue
        p0_ = q0[2 * k] + x[2 * k]
        p1_ = q0[2 * k + 1] + x[2 * k + 1]
        npv = math.sqrt(p0_ * p0_ + p1_ * p1_)
        if npv == 0.0:
            continue
        t0 = -p1_ / npv
        t1 = p0_ / npv
        off = -(t0 * q0[2 * k] + t1 * q0[2 * k + 1])      # t . (qb - q0), t . qb = 0
        kap = nu / rim_qmax(par, k, nobounds)
        w0, w1 = linv(Lm, k, t0, t1)
        i0 = 2 * k
        H[4 * i0 + i0] += kap * w0 * w0
        H[4 * i0 + i0 + 1] += kap * w0 * w1
        H[4 * (i0 + 1) + i0] += kap * w1 * w0
        H[4 * (i0 + 1) + i0 + 1] += kap * w1 * w1
        r[i0] += kap * w0 * off
        r[i0 + 1] += kap * w1 * off
        curv = 1
    if curv != 0:
        its += socp(H, r, c1, c2, y, sc)
    for rep in range(3):
        added = 0
        for k in range(2):
            if sc[R_ACT + k] != 0.0:
                continue
            qm = rim_qmax(par, k, nobounds)
            d0, d1 = linv(Lm, k, y[2 * k], y[2 * k + 1])
            e0 = q0[2 * k] + d0
            e1 = q0[2 * k + 1] + d1
            ne = math.sqrt(e0 * e0 + e1 * e1)
            if not ne > qm:
                continue
            # the normal: the previous iterate's end point if on the rim
            p0_ = q0[2 * k] + x[2 * k]
            p1_ = q0[2 * k + 1] + x[2 * k + 1]
            npv = math.sqrt(p0_ * p0_ + p1_ * p1_)
            n0, n1, h, m0, m1 = 0.0, 0.0, 0.0, 0.0, 0.0
            for tr in range(2):
                hp = hp0 if k == 0 else hp1
                if tr == 0 and npv > 0.0 and (hp or npv >= qm * (1.0 - 1e-12)):
                    n0, n1 = p0_ / npv, p1_ / npv
                else:
                    n0, n1 = e0 / ne, e1 / ne
                h = qm - (n0 * q0[2 * k] + n1 * q0[2 * k + 1])
                if sc[R_ON0 + k] != 0.0 and abs(h) <= 1e-13 * qm:
                    h = 0.0
                if h < 0.0:
                    h = 0.0
                m0, m1 = linv(Lm, k, n0, n1)
                if m0 * y[2 * k] + m1 * y[2 * k + 1] > h or tr == 1:
                    break
            sc[R_N + 2 * k] = n0
            sc[R_N + 2 * k + 1] = n1
            sc[R_M + 2 * k] = m0
            sc[R_M + 2 * k + 1] = m1
            sc[R_H + k] = h
            sc[R_ACT + k] = 1.0
            added += 1
        if added == 0:
            break
        its += rim_socp(H, r, c1, c2, y, sc)
    for k in range(2):
        if sc[R_ACT + k] != 0.0 and sc[R_NU + k] > 0.0:
            # on the line exactly
            m0, m1 = sc[R_M + 2 * k], sc[R_M + 2 * k + 1]
            g = (sc[R_H + k] - (m0 * y[2 * k] + m1 * y[2 * k + 1])) / (m0 * m0 + m1 * m1)
            y[2 * k] += g * m0
            y[2 * k + 1] += g * m1
    return its


def rim_snap(par, q0, x, y, ry, Lm, nobounds, sc):
    """After the fixed point: a held block's end tilt is put on its circle
    (q1_k = qmax_k q1_k / |q1_k|, a change of the fixed point's tolerance; in
    one direction q1 = +-qmax exactly, the planar box's), one past it by
    round-off likewise; y_k = L_k dq_k again; ry less the rims' reactions (the
    optimality conditions then hold with them)."""
    for k in range(2):
        qm = rim_qmax(par, k, nobounds)
        e0 = q0[2 * k] + x[2 * k]
        e1 = q0[2 * k + 1] + x[2 * k + 1]
        ne = math.sqrt(e0 * e0 + e1 * e1)
        held = sc[R_ACT + k] != 0.0 and sc[R_NU + k] > 0.0
        if not held:
            sc[R_ACT + k] = 0.0
        if (held or ne > qm) and ne > 0.0:
            x[2 * k] = qm * (e0 / ne) - q0[2 * k]
            x[2 * k + 1] = qm * (e1 / ne) - q0[2 * k + 1]
            if sc[R_ON0 + k] != 0.0 and abs(x[2 * k]) + abs(x[2 * k + 1]) <= 1e-13 * qm:
                # a block that starts on its rim and is held there does not
                # move by the snap's round-off (it stuck; on an axis the snap
                # gives 0 exactly, the planar box's x = hi = 0)
                x[2 * k] = 0.0
                x[2 * k + 1] = 0.0
            k0 = 4 * k
            y[2 * k] = Lm[k0] * x[2 * k] + Lm[k0 + 1] * x[2 * k + 1]
            y[2 * k + 1] = Lm[k0 + 1] * x[2 * k] + Lm[k0 + 2] * x[2 * k + 1]
        if held:
            ry[2 * k] -= sc[R_NU + k] * sc[R_M + 2 * k]
            ry[2 * k + 1] -= sc[R_NU + k] * sc[R_M + 2 * k + 1]


def rim_relax(x, xn, sc, creep):
    """The step's fixed point with a rim in it, past its first iterations: a
    block pressed into its rim along a turning normal can make the plain
    iteration alternate and converge slowly (or not); the new iterate xn is
    relaxed, x + w (xn - x), w = 1 / (1 - lambda) for an alternating factor
    lambda < 0 estimated from the last two changes (Irons and Tuck's secant
    in one dimension; w = 1, the plain iteration, otherwise), and for a
    creeping one, 0 < lambda <= creep (rim springs: 0.9, a large increment
    deep past a rim slows the fixed point on M(q1) to about 0.65, w <= 10;
    rigid rims: 0, none). The fixed point, where xn = x, is the same."""
    dd = 0.0
    dp = 0.0
    for i in range(4):
        d = xn[i] - x[i]
        dd += d * sc[R_DXP + i]
        dp += sc[R_DXP + i] * sc[R_DXP + i]
    om = 1.0
    if dp > 0.0:
        # the raw changes' ratio is the relaxed factor 1 + w0 (lambda - 1)
        lam = 1.0 + (dd / dp - 1.0) / sc[R_OM]
        if lam < 0.0 or (lam > 0.0 and lam <= creep):
            om = 1.0 / (1.0 - lam)
            if om < 0.05:
                om = 0.05
    for i in range(4):
        sc[R_DXP + i] = xn[i] - x[i]
        xn[i] = x[i] + om * (xn[i] - x[i])
    sc[R_OM] = om


def rim_involved(sc):
    return sc[R_ACT] != 0.0 or sc[R_ACT + 1] != 0.0 or sc[R_ON0] != 0.0 or sc[R_ON0 + 1] != 0.0


def _rot_basis(q, k, on, sc):
    """Block k's basis (n, t): n the outward normal of its rim at q_k when on it,
    else (1, 0); t = (-n_y, n_x). Into sc[R_ROT + 4 k: +4] = (nx, ny, tx, ty)."""
    n0, n1 = 1.0, 0.0
    if on:
        nq = math.sqrt(q[2 * k] * q[2 * k] + q[2 * k + 1] * q[2 * k + 1])
        if nq > 0.0:
            n0, n1 = q[2 * k] / nq, q[2 * k + 1] / nq
    sc[R_ROT + 4 * k] = n0
    sc[R_ROT + 4 * k + 1] = n1
    sc[R_ROT + 4 * k + 2] = -n1
    sc[R_ROT + 4 * k + 3] = n0


def _rot_fwd(v, o, sc):
    """o = R^T v (the rates in the blocks' (n, t) bases)."""
    for k in range(2):
        n0, n1 = sc[R_ROT + 4 * k], sc[R_ROT + 4 * k + 1]
        a, b = v[2 * k], v[2 * k + 1]
        o[2 * k] = n0 * a + n1 * b
        o[2 * k + 1] = -n1 * a + n0 * b


def _rot_back(v, o, sc):
    """o = R v."""
    for k in range(2):
        n0, n1 = sc[R_ROT + 4 * k], sc[R_ROT + 4 * k + 1]
        a, b = v[2 * k], v[2 * k + 1]
        o[2 * k] = n0 * a - n1 * b
        o[2 * k + 1] = n1 * a + n0 * b


def _rot_mass(M, sc):
    """sc[R_MR] = R^T M R."""
    for i in range(4):
        for j in range(4):
            s = 0.0
            for a in range(4):
                ka, ia = a // 2, i // 2
                if ka != ia:
                    continue
                # R[a, i]: column i of block ka: (n0, n1) for i even, (-n1, n0) for i odd
                ra = sc[R_ROT + 4 * ka + 2 * (i % 2) + (a % 2)]
                for b in range(4):
                    kb, jb = b // 2, j // 2
                    if kb != jb:
                        continue
                    rb = sc[R_ROT + 4 * kb + 2 * (j % 2) + (b % 2)]
                    s += ra * M[4 * a + b] * rb
            sc[R_MR + 4 * i + j] = s


def _proj_zero(mask, v, w, sc):
    """The kinetic-metric projection of the rates v (rotated) onto {w_i = 0, i
    in mask} (bit i of mask): the momentum of the free coordinates kept,
    w_F = Mr_FF^-1 (Mr v)_F. Returns the kinetic energy removed, 1/2 |v - w|^2_Mr."""
    Mr = sc[R_MR:R_MR + 16]
    nf = 0
    for i in range(4):
        if (mask >> i) & 1 == 0:
            sc[R_X + nf] = float(i)
            nf += 1
    for i in range(4):
        w[i] = 0.0
    if nf > 0:
        # p_F and Mr_FF, Gaussian elimination (SPD, no pivoting)
        for a in range(nf):
            ia = int(sc[R_X + a])
            s = 0.0
            for j in range(4):
                s += Mr[4 * ia + j] * v[j]
            sc[R_B + a] = s
            for b in range(nf):
                sc[R_LL + 4 * a + b] = Mr[4 * ia + int(sc[R_X + b])]
        for c in range(nf):
            piv = sc[R_LL + 4 * c + c]
            for a in range(c + 1, nf):
                f = sc[R_LL + 4 * a + c] / piv
                for b in range(c, nf):
                    sc[R_LL + 4 * a + b] -= f * sc[R_LL + 4 * c + b]
                sc[R_B + a] -= f * sc[R_B + c]
        for a in range(nf - 1, -1, -1):
            s = sc[R_B + a]
            for b in range(a + 1, nf):
                s -= sc[R_LL + 4 * a + b] * w[int(sc[R_X + b])]
            w[int(sc[R_X + a])] = s / sc[R_LL + 4 * a + a]
    e = 0.0
    for i in range(4):
        s = 0.0
        for j in range(4):
            s += Mr[4 * i + j] * (v[j] - w[j])
        e += (v[i] - w[i]) * s
    return 0.5 * e


def _stage(mask, label, sc):
    """A stage of the end-of-step impulses on the rotated rates sc[R_VR]:
    project (``_proj_zero``), book the loss (label 0: S1/S4's arrest, 1:
    S2/S3's, 2: the rim, whose velocity jump of the superstructure is kept)."""
    v = sc[R_VR:R_VR + 4]
    w = sc[R_WR:R_WR + 4]
    e = _proj_zero(mask, v, w, sc)
    if label == 2:
        sc[R_OUT] += e
        _rot_back(v, sc[R_PR:R_PR + 4], sc)
        for i in range(4):
            sc[R_Q + i] = sc[R_PR + i]
        _rot_back(w, sc[R_PR:R_PR + 4], sc)
        for c in range(2):
            s = 0.0
            for i in range(4):
                s += sc[R_C + 2 * i + c] * (sc[R_PR + i] - sc[R_Q + i])
            sc[R_OUT + 3 + c] += s
    else:
        sc[R_OUT + 1 + label] += e
    for i in range(4):
        v[i] = w[i]


def _stages(k, stuck, rimk, base, sc):
    """Block k's stages on top of the mask base: a block that stuck stops whole
    (its normal rate first, the rim's if the rim stopped it, then the rest,
    friction's arrest); one that reached its rim sliding loses its normal rate
    only (the rim's). Returns the mask after them."""
    bn = 1 << (2 * k)
    bt = 1 << (2 * k + 1)
    if stuck:
        if rimk:
            _stage(base | bn, 2, sc)
        _stage(base | bn | bt, k, sc)
        return base | bn | bt
    _stage(base | bn, 2, sc)
    return base | bn


def rim_lock3(o0, o1, sc):
    """The inelastic rim impact on the rotated rates sc[R_VR]: a block k on its
    rim (o_k) may not move into it (its normal rate <= 0). The kinetic-metric
    projection onto that cone (as tfp_kernel.rim_lock, the coordinates being
    the normal rates): one block's normal rate stopped if the other's is then
    not driven into its rim and the impulse pushes off the rim, else both.
    The loss and the superstructure's jump are booked as the rim's."""
    v = sc[R_VR:R_VR + 4]
    w = sc[R_WR:R_WR + 4]
    in0 = o0 and v[0] > 0.0
    in1 = o1 and v[2] > 0.0
    if not in0 and not in1:
        return
    Mr = sc[R_MR:R_MR + 16]
    mask = 5
    for c in range(2):
        if c == 0 and not in0:
            continue
        if c == 1 and not in1:
            continue
        i = 2 * c
        j = 2 - i
        _proj_zero(1 << i, v, w, sc)
        imp = 0.0
        for a in range(4):
            imp += Mr[4 * i + a] * (w[a] - v[a])
        oj = o1 if c == 0 else o0
        if not (oj and w[j] > 0.0) and imp <= 0.0:
            mask = 1 << i
            break
    _stage(mask, 2, sc)


def rim_velocities(par, q0, q1, x, st, M, dt, c_o, c_i, y, Lm, e_rest, sc):
    """The end-of-step velocity jumps of a step with a rim in it (the planar
    TFP's, tfp_kernel.substep, block by block in each block's (normal,
    tangent) basis): a block that stuck stops (friction's arrest; its normal
    rate the rim's if it rests on its rim and pushed into it), one that reached
    its rim loses its normal rate (the rim's); the stuck-then-rim hand-over,
    Newton's restitution e of an arrival, and last the inelastic lock of every
    block that ends on its rim (``rim_lock3``). st[4:8]: the rates, updated;
    M = M(q1). Results at sc[R_OUT:R_OUT + 7]: rim loss, arrests of
    phi and alpha, the superstructure's velocity jump at the rims (x, y), and
    whether phi, alpha arrived at their rims."""
    for i in range(7):
        sc[R_OUT + i] = 0.0
    grad_u(par, q1, sc[R_C:R_C + 8])
    s0, at0, rim0, on0_ = _rim_flags(q0, y, 0, sc)
    s1, at1, rim1, on1_ = _rim_flags(q0, y, 1, sc)
    _rot_basis(q1, 0, on0_, sc)
    _rot_basis(q1, 1, on1_, sc)
    # the rim's work over the increment of a held block (its reaction's, r - H dq less friction's)
    for k in range(2):
        if sc[R_ACT + k] != 0.0:
            c = c_o if k == 0 else c_i
            sc[R_OUT] += sc[R_PHI + 2 * k] * x[2 * k] + sc[R_PHI + 2 * k + 1] * x[2 * k + 1] \
                - c * math.sqrt(y[2 * k] * y[2 * k] + y[2 * k + 1] * y[2 * k + 1])
    _rot_mass(M, sc)
    _rot_fwd(st[4:8], sc[R_VR:R_VR + 4], sc)
    za = (not s0) or at0
    zb = (not s1) or at1
    if za and zb and rim1 and not rim0:
        # phi stuck by friction, alpha stopped by its rim: the arrest, then the
        # rim's impulse on alpha alone (phi keeps the momentum it hands it)
        _stages(0, not s0, False, 0, sc)
        _stages(1, not s1, rim1, 0, sc)
    elif za and zb and rim0 and not rim1:
        _stages(1, not s1, False, 0, sc)
        _stages(0, not s0, rim0, 0, sc)
    elif za and zb:
        mk = _stages(0, not s0, rim0, 0, sc)
        _stages(1, not s1, rim1, mk, sc)
    elif za or zb:
        k = 0 if za else 1
        sk = s0 if za else s1
        atk = at0 if za else at1
        rk = rim0 if za else rim1
        _stages(k, not sk, rk, 0, sc)
        if atk and e_rest != 0.0:
            # Newton's restitution: the free momentum is p1 plus the rim's
            # impulse over the step (its reaction: the force r - H dq less friction's)
            _rot_back(sc[R_VR:R_VR + 4], sc[R_Q:R_Q + 4], sc)
            c = c_o if k == 0 else c_i
            ny = math.sqrt(y[2 * k] * y[2 * k] + y[2 * k + 1] * y[2 * k + 1])
            for i in range(4):
                t = 0.0
                for j in range(4):
                    t += M[4 * i + j] * st[4 + j]
                sc[R_PR + i] = t           # p1, the scheme's end momentum
            k0 = 4 * k
            for j in range(2):
                fr = 0.0
                if ny > 0.0:
                    # L^T y / |y| (L symmetric)
                    fr = c * (Lm[k0 + j] * y[2 * k] + Lm[k0 + j + 1] * y[2 * k + 1]) / ny
                sc[R_PR + 2 * k + j] += dt * (sc[R_PHI + 2 * k + j] - fr)
            chol_solve(M, sc[R_PR:R_PR + 4], sc[R_WR:R_WR + 4], sc[R_LL:R_LL + 16])
            # the stop's jump d = v - v_free taken (1 + e) times
            _rot_fwd(sc[R_WR:R_WR + 4], sc[R_PR:R_PR + 4], sc)
            for i in range(4):
                sc[R_WR + i] = sc[R_VR + i] + e_rest * (sc[R_VR + i] - sc[R_PR + i])
            # the energy handed back, e^2 of the stop's 1/2 d^T M d (d is M-orthogonal
            # to v), booked as the kinetic energy's change itself, 1/2 (w - v)^T M (w + v)
            Mr = sc[R_MR:R_MR + 16]
            ee = 0.0
            for i in range(4):
                t = 0.0
                for j in range(4):
                    t += Mr[4 * i + j] * (sc[R_WR + j] + sc[R_VR + j])
                ee += (sc[R_WR + i] - sc[R_VR + i]) * t
            sc[R_OUT] -= 0.5 * ee
            _rot_back(sc[R_WR:R_WR + 4], sc[R_PR:R_PR + 4], sc)
            for c2 in range(2):
                t = 0.0
                for i in range(4):
                    t += sc[R_C + 2 * i + c2] * (sc[R_PR + i] - sc[R_Q + i])
                sc[R_OUT + 3 + c2] += t
            for i in range(4):
                sc[R_VR + i] = sc[R_WR + i]
    # a block that ends on its rim cannot move into it
    rim_lock3(on0_, on1_, sc)
    _rot_back(sc[R_VR:R_VR + 4], st[4:8], sc)
    # (an arrival that moved)
    sc[R_OUT + 5] = 1.0 if at0 and s0 else 0.0
    sc[R_OUT + 6] = 1.0 if at1 and s1 else 0.0


def _rim_flags(q0, y, k, sc):
    """Block k after the step: whether it slid, arrived at its rim (held by it,
    not on it at the start), was stopped by its rim (arrived, or stuck on it
    while its start rate pushed into it) and ends on it (held, or stuck on it)."""
    sk = y[2 * k] != 0.0 or y[2 * k + 1] != 0.0
    held = sc[R_ACT + k] != 0.0
    on0 = sc[R_ON0 + k] != 0.0
    push = False
    if on0 and not sk:
        # (into the rim beyond round-off: the lock that put it there leaves its
        # normal rate 0 only to round-off of the rates, whose sign is noise;
        # the planar TFP's is 0 exactly)
        nv = 0.0
        for i in range(4):
            nv += sc[R_V0 + i] * sc[R_V0 + i]
        nq = math.sqrt(q0[2 * k] * q0[2 * k] + q0[2 * k + 1] * q0[2 * k + 1])
        push = q0[2 * k] * sc[R_V0 + 2 * k] + q0[2 * k + 1] * sc[R_V0 + 2 * k + 1] > 1e-12 * nq * math.sqrt(nv)
    at = held and not on0
    return sk, at, at or push, held or (on0 and not sk)


def _ud(par, st, sc, o):
    """The superstructure's velocity u' of the state st into sc[o:o+2]."""
    u_dot(par, st[0:4], st[4:8], sc, R_UD)
    sc[o] = sc[R_UD]
    sc[o + 1] = sc[R_UD + 1]


def step_rims(par, st, dt, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc):
    """One step of the 3D TFP (``step``) with its rims, split at each arrival
    as the planar TFP's step (tfp_kernel.step): the first part ends where the
    unclamped increment of what is left of the step meets the rim circle
    (the segment's crossing), the impact there is inelastic at velocity level
    (``rim_velocities``; restitution as an option), the rest starts on the
    rim and is split again if the other block meets its own rim in it.
    out[O_DXR:O_DXR + 2]: the superstructure's velocity change at the
    impacts, each part's change up to its rim less its share of the free
    flight's smooth change. The test machine runs without rims (``step``'s
    capacity check stops it at one)."""
    if par[tk.I_KRIM] != 0.0:
        # rims of finite stiffness: no bound, their springs in the step (docs/model.md 6.12)
        step(par, st, dt, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc, 1)
        return
    for i in range(8):
        sc[R_SAVE + i] = st[i]
    step(par, st, dt, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc, 0)
    if out[O_FAIL] != FAIL_NONE or machine == 1 or out[O_ARRIVE] == 0.0:
        return
    e_rest = par[tk.I_REST]
    for i in range(N_OUT):
        sc[R_ACC + i] = 0.0
    kkt = 0.0
    u_p = R_UD + 8
    u_f = R_UD + 10
    t0 = 0.0
    for part in range(3):
        h = (1.0 - t0) * dt
        # the unclamped increment of what is left decides where the rim is met
        for i in range(8):
            st[i] = sc[R_SAVE + i]
        _ud(par, st, sc, u_p)
        step(par, st, h, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc, 1)
        _ud(par, st, sc, u_f)
        tau = 1.0
        for b in range(2):
            d0 = out[O_DQ + 2 * b]
            d1 = out[O_DQ + 2 * b + 1]
            nd = math.sqrt(d0 * d0 + d1 * d1)
            if nd == 0.0:
                continue
            qm = rim_qmax(par, b, 0)
            a0 = sc[R_SAVE + 2 * b]
            a1 = sc[R_SAVE + 2 * b + 1]
            e0 = a0 + d0
            e1 = a1 + d1
            if not math.sqrt(e0 * e0 + e1 * e1) > qm:
                continue
            # the segment a + s d meets the circle at s = (sqrt(qm^2 - c^2) - a.d^) / |d|,
            # c = a x d^ (in one direction c = 0 and s = (+-qm - a) / d, the planar)
            dx = d0 / nd
            dy = d1 / nd
            ad = a0 * dx + a1 * dy
            cr = a0 * dy - a1 * dx
            disc = qm * qm - cr * cr
            if disc < 0.0:
                disc = 0.0
            dist = math.sqrt(disc) - ad
            # (a block already resting on its rim does not meet it inside the step)
            if abs(dist) > 1e-13 * qm:
                tau = min(tau, dist / nd)
        if tau < 1e-9:
            tau = 1e-9
        if tau > 1.0 - 1e-9:
            tau = 1.0 - 1e-9
        for i in range(8):
            st[i] = sc[R_SAVE + i]
        th = t0 + tau * (1.0 - t0)
        step(par, st, tau * h, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc, 0)
        if out[O_FAIL] != FAIL_NONE:
            return
        if out[O_HIT_O] == 0.0 and out[O_HIT_I] == 0.0:
            # the part ended on a rim only to round-off, still moving into it:
            # the impact is here (tfp_kernel.step)
            o0 = _rim_touch(par, st, 0)
            o1 = _rim_touch(par, st, 1)
            if o0 or o1:
                rim_touch_impact(par, st, o0, o1, e_rest, sc)
                out[O_RIM] += sc[R_OUT]
                if o0:
                    out[O_HIT_O] = 1.0
                if o1:
                    out[O_HIT_I] = 1.0
        _ud(par, st, sc, R_UD)
        for c in range(2):
            out[O_DXR + c] = sc[R_UD + c] - sc[u_p + c] - tau * (sc[u_f + c] - sc[u_p + c])
        for i in range(N_OUT):
            if i != O_FAIL and i != O_KKT and i != O_ARRIVE and i != O_FX and i != O_FY:
                sc[R_ACC + i] += out[i]
        if out[O_KKT] > kkt:
            kkt = out[O_KKT]
        t0 = th
        for i in range(8):
            sc[R_SAVE + i] = st[i]
            sc[R_SV + i] = st[i]
        # the rest, from the rim
        step(par, st, (1.0 - t0) * dt, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc, 0)
        if out[O_FAIL] != FAIL_NONE or out[O_ARRIVE] == 0.0 or part == 2:
            break
        # the other block meets its rim in the rest: split it too
        for i in range(8):
            st[i] = sc[R_SV + i]
    for i in range(N_OUT):
        if i != O_FAIL and i != O_KKT and i != O_ARRIVE and i != O_FX and i != O_FY:
            out[i] += sc[R_ACC + i]
    if kkt > out[O_KKT]:
        out[O_KKT] = kkt
    out[O_ARRIVE] = 1.0


def _rim_touch(par, st, k):
    """Block k on its rim to round-off and moving into it."""
    qm = rim_qmax(par, k, 0)
    a0, a1 = st[2 * k], st[2 * k + 1]
    nq = math.sqrt(a0 * a0 + a1 * a1)
    return abs(nq - qm) <= 1e-13 * qm and a0 * st[4 + 2 * k] + a1 * st[4 + 2 * k + 1] > 0.0


def rim_touch_impact(par, st, o0, o1, e_rest, sc):
    """The inelastic lock (``rim_lock3``) of the blocks o_k put on their rims
    exactly, then Newton's restitution e (no reaction in the part: the free
    rates are the rates before the lock; the lock's jump taken (1 + e) times,
    e^2 of its loss handed back). The rim loss into sc[R_OUT]."""
    for i in range(7):
        sc[R_OUT + i] = 0.0
    for k in range(2):
        if (k == 0 and o0) or (k == 1 and o1):
            qm = rim_qmax(par, k, 0)
            a0, a1 = st[2 * k], st[2 * k + 1]
            nq = math.sqrt(a0 * a0 + a1 * a1)
            st[2 * k] = qm * (a0 / nq)
            st[2 * k + 1] = qm * (a1 / nq)
    M = sc[R_MM:R_MM + 16]
    mass_matrix(par, st[0:4], M, sc[R_LL:R_LL + 12])
    grad_u(par, st[0:4], sc[R_C:R_C + 8])
    _rot_basis(st, 0, o0, sc)
    _rot_basis(st, 1, o1, sc)
    _rot_mass(M, sc)
    _rot_fwd(st[4:8], sc[R_VR:R_VR + 4], sc)
    for i in range(4):
        sc[R_VF + i] = sc[R_VR + i]
    rim_lock3(o0, o1, sc)
    if e_rest != 0.0:
        Mr = sc[R_MR:R_MR + 16]
        ee = 0.0
        for i in range(4):
            sc[R_VF + i] = e_rest * (sc[R_VR + i] - sc[R_VF + i])      # the jump e d
        for i in range(4):
            t = 0.0
            for j in range(4):
                t += Mr[4 * i + j] * (2.0 * sc[R_VR + j] + sc[R_VF + j])
            ee += sc[R_VF + i] * t
        sc[R_OUT] -= 0.5 * ee
        for i in range(4):
            sc[R_VR + i] += sc[R_VF + i]
    _rot_back(sc[R_VR:R_VR + 4], st[4:8], sc)


# -- the whole step of the stepper ---------------------------------------------------------
def advance(par, S, dt, agx, agy, az, mu1, mu2, mu3, mu4, machine, u1x, u1y, ud1x, ud1y, out, sc):
    """One step on the state vector S (layout S_*): ``begin_advance``, the
    step with its rims (``step_rims``), their account, ``finish_advance``.
    Returns the failure flag."""
    a1, a2, c_o, c_i, ux0, uy0 = begin_advance(par, S, agx, agy, az, mu1, mu2, mu3, mu4, machine, sc)
    step_rims(par, S[0:8], dt, agx, agy, az, c_o, c_i, machine, u1x, u1y, ud1x, ud1y, out, sc)
    if par[tk.I_KRIM] != 0.0:
        rim_spring_hits(par, S, sc)
    rim_account(par, S, out)
    return finish_advance(par, S, dt, agx, agy, machine, a1, a2, c_o, c_i, ux0, uy0, 1, out, sc)


def begin_advance(par, S, agx, agy, az, mu1, mu2, mu3, mu4, machine, sc):
    """Before a step on S (this TFP's and the two-phase one's): the normal
    forces at its start, the caps. Returns (a1, a2, c_o, c_i, u'x, u'y at
    the start): a1 = mu1 N1 R1, a2 = mu2 N2 R2, c_o = a1 + mu4 N4 R4, c_i =
    a2 + mu3 N3 R3; sc[256:258] the machine's last force."""
    N = S[S_N:S_N + 4]
    # the machine's force (the last step's) enters the normal forces; a ground motion has none
    fx = S[S_F] if machine == 1 else 0.0
    fy = S[S_F + 1] if machine == 1 else 0.0
    normal_forces(par, S[0:4], S[4:8], agx, agy, az, fx, fy, N, sc[200:220])
    # a coordinate at rest (did not slide in the step before) holds with the static coefficient
    mu1, mu2, mu3, mu4 = tk.holding_caps(par, S[S_SLIDE], S[S_SLIDE + 1], mu1, mu2, mu3, mu4)
    a1 = mu1 * N[0] * par[tk.I_R1]
    a4 = mu4 * N[3] * par[tk.I_R4]
    a2 = mu2 * N[1] * par[tk.I_R2]
    a3 = mu3 * N[2] * par[tk.I_R3]
    # the superstructure's velocity at the start
    u_dot(par, S[0:4], S[4:8], sc, 220)
    sc[256] = S[S_F]            # the machine's force: Newton starts from the last step's
    sc[257] = S[S_F + 1]
    return a1, a2, a1 + a4, a2 + a3, sc[220], sc[221]


def finish_advance(par, S, dt, agx, agy, machine, a1, a2, c_o, c_i, ux0, uy0, rims, out, sc):
    """After a step on S (``begin_advance``'s values): the friction work of
    each surface (a coordinate's shared by its two surfaces as their caps),
    the bearing's force, phase, regime (rims = 1: 5 with the stack on its
    rim), sliding flags and speeds. Returns the step's failure flag."""
    fail = int(out[O_FAIL])
    R1, R2, R3, R4 = par[tk.I_R1], par[tk.I_R2], par[tk.I_R3], par[tk.I_R4]
    S[S_ITER] = out[O_ITER]
    S[S_KKT] = out[O_KKT]
    wo = out[O_WO]
    wi = out[O_WI]
    fo = a1 / c_o if c_o > 0.0 else 0.5
    fi = a2 / c_i if c_i > 0.0 else 0.5
    S[S_DW] = fo * wo
    S[S_DW + 1] = fi * wi
    S[S_DW + 2] = (1.0 - fi) * wi
    S[S_DW + 3] = (1.0 - fo) * wo
    for i in range(4):
        S[S_W + i] += S[S_DW + i]
    S[S_EIN] += out[O_EIN]
    u_dot(par, S[0:4], S[4:8], sc, 220)
    Ms = par[tk.I_MSUP]
    if machine == 1:
        S[S_F] = out[O_FX]
        S[S_F + 1] = out[O_FY]
    else:
        # (the velocity jump at a rim is an impulse, S_J, kept out of the force)
        S[S_F] = -Ms * (agx + (sc[220] - out[O_DXR] - ux0) / dt)
        S[S_F + 1] = -Ms * (agy + (sc[221] - out[O_DXR + 1] - uy0) / dt)
    dp = math.sqrt(out[O_DQ] * out[O_DQ] + out[O_DQ + 1] * out[O_DQ + 1])
    da = math.sqrt(out[O_DQ + 2] * out[O_DQ + 2] + out[O_DQ + 3] * out[O_DQ + 3])
    so = 1.0 if dp != 0.0 else 0.0
    si = 1.0 if da != 0.0 else 0.0
    S[S_SLIDE] = so
    S[S_SLIDE + 1] = si
    S[S_SLIDE + 2] = si
    S[S_SLIDE + 3] = so
    if so != 0.0 and si != 0.0:
        S[S_PHASE] = tk.PHASE_BOTH
        S[S_REG] = 6.0
    elif so != 0.0:
        S[S_PHASE] = tk.PHASE_OUTER
        S[S_REG] = 3.0
    elif si != 0.0:
        S[S_PHASE] = tk.PHASE_INNER
        on_rim = rims == 1 and S[0] * S[0] + S[1] * S[1] >= (par[tk.I_QMAX_PHI] * (1.0 - 1e-12)) ** 2
        S[S_REG] = 5.0 if on_rim else 1.0
    else:
        S[S_PHASE] = tk.PHASE_STICK
        S[S_REG] = 0.0
    # slip speeds: the arcs slid (wo / c_o = |L dphi|)
    lo_ = wo - out[O_ARR_O]
    li_ = wi - out[O_ARR_I]
    ao = lo_ / c_o if c_o > 0.0 else dp
    ai = li_ / c_i if c_i > 0.0 else da
    S[S_SV] = R1 * ao / dt
    S[S_SV + 1] = R2 * ai / dt
    S[S_SV + 2] = R3 * ai / dt
    S[S_SV + 3] = R4 * ao / dt
    return fail


def rim_account(par, S, out):
    """A step's rims in the state: the rim loss, the impulse on the
    superstructure (minus its mass times u's jump at the rims, N s) and the
    impacts, counted on the surfaces whose capacity makes the rim (as
    tfp_kernel.advance)."""
    S[S_ERIM] += out[O_RIM]
    Ms = par[tk.I_MSUP]
    S[S_J] = -Ms * out[O_DXR]
    S[S_J + 1] = -Ms * out[O_DXR + 1]
    tol = 1.0 - 1e-12
    if out[O_HIT_O] != 0.0:
        qm = par[tk.I_QMAX_PHI]
        if par[tk.I_R1] * qm >= par[tk.I_D1] * tol:
            S[S_NHIT] += out[O_HIT_O]
        if par[tk.I_R4] * qm >= par[tk.I_D4] * tol:
            S[S_NHIT + 3] += out[O_HIT_O]
    if out[O_HIT_I] != 0.0:
        qm = par[tk.I_QMAX_ALPHA]
        if par[tk.I_R2] * qm >= par[tk.I_D2] * tol:
            S[S_NHIT + 1] += out[O_HIT_I]
        if par[tk.I_R3] * qm >= par[tk.I_D3] * tol:
            S[S_NHIT + 2] += out[O_HIT_I]


def vertical_row(par, S, az, row, sc):
    """The vertical ground motion's columns (mechanics.tfp3d.VERTICAL_COLUMNS,
    after the stepper's) into row[N_ROW:N_ROW+5]: az, the last step's a_z (0 in
    the first row), the height above the seat, the lift-offs, the time in
    flight, the landings' loss; in flight the superstructure's position,
    velocity, uplift and the energies follow the unit (the tilt, slide and
    footprint columns keep the take-off's). Only with a vertical loading
    (par[I_VERT] = 1). sc: scratch >= 40."""
    if par[tk.I_VERT] != 1.0:
        return
    j = N_ROW
    row[j] = az
    row[j + 1] = 0.0
    if S[S_FLY] != 0.0:
        row[3] += S[S_XF]
        row[4] += S[S_YF]
        row[5] = math.sqrt(row[3] * row[3] + row[4] * row[4])
        row[6] = S[S_VXF]
        row[7] = S[S_VYF]
        row[8] = math.sqrt(row[6] * row[6] + row[7] * row[7])
        row[12] += S[S_ZF]
        mt = tk.moving_mass(par)
        row[42] = 0.5 * mt * (S[S_VXF] * S[S_VXF] + S[S_VYF] * S[S_VYF] + S[S_VZF] * S[S_VZF])
        row[43] += mt * par[tk.I_G] * S[S_ZF]
        row[j + 1] = flight_lift(par, S, S[S_XF], S[S_YF], S[S_ZF], sc)
    row[j + 2] = S[S_NLIFT]
    row[j + 3] = S[S_TFLY]
    row[j + 4] = S[S_ELAND]


def row_values(par, S, t, xg, yg, row, sc):
    """The stepper's columns (mechanics.tfp3d.COLUMNS) into row[0:N_ROW]."""
    q = S[0:4]
    v = S[4:8]
    R1, R2, R3, R4 = par[tk.I_R1], par[tk.I_R2], par[tk.I_R3], par[tk.I_R4]
    u_rel(par, q, sc)
    ux, uy, z = sc[0], sc[1], sc[2]
    u_dot(par, q, v, sc, 10)
    vx, vy = sc[10], sc[11]
    Fx, Fy = S[S_F], S[S_F + 1]
    row[0] = t
    row[1] = xg
    row[2] = yg
    row[3] = ux
    row[4] = uy
    row[5] = math.sqrt(ux * ux + uy * uy)
    row[6] = vx
    row[7] = vy
    row[8] = math.sqrt(vx * vx + vy * vy)
    row[9] = Fx
    row[10] = Fy
    row[11] = math.sqrt(Fx * Fx + Fy * Fy)
    row[12] = z
    phi = math.sqrt(q[0] * q[0] + q[1] * q[1])
    al = math.sqrt(q[2] * q[2] + q[3] * q[3])
    psx, psy = q[0] + q[2], q[1] + q[3]
    row[13] = math.sqrt(psx * psx + psy * psy)
    row[14] = q[0]
    row[15] = q[1]
    row[16] = phi
    row[17] = q[2]
    row[18] = q[3]
    row[19] = al
    # slides (footprint offsets on the lower parts; the upper parts' are their negatives)
    rr = (R1, R2, R3, R4)
    for i in range(4):
        Ri = rr[i]
        if i == 0 or i == 3:
            row[20 + 3 * i] = Ri * q[0]
            row[21 + 3 * i] = Ri * q[1]
            row[22 + 3 * i] = Ri * phi
        else:
            row[20 + 3 * i] = Ri * q[2]
            row[21 + 3 * i] = Ri * q[3]
            row[22 + 3 * i] = Ri * al
    for i in range(4):
        row[32 + i] = S[S_N + i]
        row[36 + i] = S[S_W + i]
    row[40] = S[S_PHASE]
    row[41] = S[S_EIN]
    row[42] = kinetic(par, q, v, sc)
    row[43] = potential(par, q)
    if par[tk.I_KRIM] != 0.0:
        row[43] += rim_spring_energy(par, q)
    row[44] = S[S_ERIM]
    row[45] = S[S_REG]
    for i in range(4):
        row[46 + i] = S[S_SLIDE + i]
    # rim flags: a footprint at its capacity (the planar TFP's)
    tol = 1.0 - 1e-12
    dd = (par[tk.I_D1], par[tk.I_D2], par[tk.I_D3], par[tk.I_D4])
    for i in range(4):
        row[50 + i] = 1.0 if row[22 + 3 * i] >= dd[i] * tol else 0.0
    row[54] = math.sqrt(S[S_J] * S[S_J] + S[S_J + 1] * S[S_J + 1])     # J_rim_Ns: its magnitude
    for i in range(4):
        row[55 + i] = S[S_NHIT + i]
    # footprint centres on the four heated parts
    for i in range(4):
        sg = 1.0 if i < 2 else -1.0
        row[59 + 2 * i] = sg * row[20 + 3 * i]
        row[60 + 2 * i] = sg * row[21 + 3 * i]
    row[67] = S[S_ITER]
    row[68] = S[S_KKT]


# -- lift-off and landing (docs/model.md 10) ---------------------------------------------------
def seat_phi(par, q, ux, uy, o, sc):
    """The stack's tilt (o[0:2]) of the seated configuration with the pad's
    relative tilt alpha = q[2:4] whose superstructure is at (ux, uy): Newton
    on the horizontal displacement from phi = q[0:2]. Returns 0, or 1 if it
    did not converge (beyond the reach). sc: scratch >= 20."""
    sc[0] = q[0]
    sc[1] = q[1]
    sc[2] = q[2]
    sc[3] = q[3]
    for it in range(60):
        u_rel(par, sc[0:4], sc[4:7])
        fx = sc[4] - ux
        fy = sc[5] - uy
        grad_u(par, sc[0:4], sc[8:16])
        a11, a12, a21, a22 = sc[8], sc[10], sc[9], sc[11]      # du_k / dphi_i: o[2 i + k]
        det = a11 * a22 - a12 * a21
        if not det > 0.0:
            return 1
        d0 = (a22 * fx - a12 * fy) / det
        d1 = (a11 * fy - a21 * fx) / det
        sc[0] -= d0
        sc[1] -= d1
        if abs(d0) + abs(d1) <= 1e-16 * (1.0 + abs(sc[0]) + abs(sc[1])):
            o[0] = sc[0]
            o[1] = sc[1]
            return 0
    o[0] = sc[0]
    o[1] = sc[1]
    return 0 if abs(fx) + abs(fy) <= 1e-12 * (1.0 + abs(ux) + abs(uy)) else 1


def flight_lift(par, S, x, y, z, sc):
    """The height of the flying superstructure above the seat under it after a
    flight of (x, y, z) from the take-off configuration held in S (q): the
    seated configuration with the same alpha under the flown position.
    sc: scratch >= 40."""
    u_rel(par, S[0:4], sc[20:23])
    ux, uy, z0 = sc[20] + x, sc[21] + y, sc[22]
    if seat_phi(par, S[0:4], ux, uy, sc[24:26], sc) != 0:
        return z0 + z            # beyond the reach: above the rims' ring, no seat under it
    sc[26] = sc[24]
    sc[27] = sc[25]
    sc[28] = S[2]
    sc[29] = S[3]
    u_rel(par, sc[26:30], sc[30:33])
    return z0 + z - sc[32]


def unit_momentum(par, q, v, o, sc):
    """The moving parts' momentum relative to the ground (o[0:3]): body k at
    -a_k e(phi) - b_k e(psi), so p = -(P1 De(phi)[phi'] + P2 De(psi)[psi'])."""
    P1, P2 = par[tk.I_P1], par[tk.I_P2]
    de(q[0], q[1], v[0], v[1], sc, 0)
    de(q[0] + q[2], q[1] + q[3], v[0] + v[2], v[1] + v[3], sc, 3)
    for i in range(3):
        o[i] = -(P1 * sc[i] + P2 * sc[3 + i])


def _takeoff(par, S, sc):
    """The unit leaves with the moving parts' momentum over their mass; the
    bodies' motion relative to each other is stopped (its energy to E_land)."""
    mt = tk.moving_mass(par)
    unit_momentum(par, S[0:4], S[4:8], sc[40:43], sc)
    vx, vy, vz = sc[40] / mt, sc[41] / mt, sc[42] / mt
    S[S_ELAND] += kinetic(par, S[0:4], S[4:8], sc) - 0.5 * mt * (vx * vx + vy * vy + vz * vz)
    S[4] = S[5] = S[6] = S[7] = S[S_XF] = S[S_YF] = S[S_ZF] = 0.0
    S[S_FLY] = 1.0
    S[S_VXF], S[S_VYF], S[S_VZF] = vx, vy, vz
    S[S_NLIFT] += 1.0


def _land(par, S, sc):
    """The landing: the seated configuration under the unit (alpha kept, phi
    from the flown position) and a plastic impact, the flight velocity V
    projected onto the seated motions in the kinetic-energy metric (M q' = p,
    p_i = sum m_k dr_k/dq_i . V); the energy before minus after to E_land.
    Returns 0, or FAIL_LAND beyond the outer surfaces' reach."""
    mt = tk.moving_mass(par)
    vx, vy, vz = S[S_VXF], S[S_VYF], S[S_VZF]
    u_rel(par, S[0:4], sc[60:63])
    if seat_phi(par, S[0:4], sc[60] + S[S_XF], sc[61] + S[S_YF], sc[64:66], sc) != 0:
        return FAIL_LAND
    if sc[64] * sc[64] + sc[65] * sc[65] > par[tk.I_QMAX_PHI] * par[tk.I_QMAX_PHI]:
        return FAIL_LAND
    e0 = 0.5 * mt * (vx * vx + vy * vy + vz * vz) + potential(par, S[0:4]) + mt * par[tk.I_G] * S[S_ZF]
    S[0] = sc[64]
    S[1] = sc[65]
    P1, P2 = par[tk.I_P1], par[tk.I_P2]
    q = S[0:4]
    sx, sy = q[0] + q[2], q[1] + q[3]
    for j in range(2):
        ex = 1.0 if j == 0 else 0.0
        ey = 1.0 - ex
        de(q[0], q[1], ex, ey, sc, 0)
        de(sx, sy, ex, ey, sc, 3)
        ps = -(sc[3] * vx + sc[4] * vy + sc[5] * vz) * P2
        sc[70 + j] = -(sc[0] * vx + sc[1] * vy + sc[2] * vz) * P1 + ps
        sc[72 + j] = ps
    mass_matrix(par, q, sc[80:96], sc)
    chol_solve(sc[80:96], sc[70:74], sc[74:78], sc[96:112])
    for i in range(4):
        S[4 + i] = sc[74 + i]
    S[S_ELAND] += e0 - (kinetic(par, S[0:4], S[4:8], sc) + potential(par, S[0:4]))
    for i in range(S_FLY, S_VZF + 1):
        S[i] = 0.0
    return FAIL_NONE


def _flight(par, S, agx, agy, gv, h, sc):
    """Ballistic flight of the unit for at most h (x'' = -agx, y'' = -agy,
    z'' = -gv relative to the ground, exact for the step-constant field), the
    ground's d'Alembert work through its displacement input. Takes off first
    when seated (only when the path stays above the seat to h: else returns
    -1, nothing changed). Lands at the first time the height meets the seat
    (bisection to round-off). Returns the time flown (h, or the landing
    time; -2 - fail when the landing is not modelled)."""
    az = gv - par[tk.I_G]
    if S[S_FLY] == 0.0:
        mt = tk.moving_mass(par)
        unit_momentum(par, S[0:4], S[4:8], sc[40:43], sc)
        vx, vy, vz = sc[40] / mt, sc[41] / mt, sc[42] / mt
        if not flight_lift(par, S, vx * h - 0.5 * agx * h * h, vy * h - 0.5 * agy * h * h,
                           vz * h - 0.5 * gv * h * h, sc) > 0.0:
            return -1.0
        _takeoff(par, S, sc)
    x0, y0, z0 = S[S_XF], S[S_YF], S[S_ZF]
    vx, vy, vz = S[S_VXF], S[S_VYF], S[S_VZF]
    tau = h
    landed = False
    if not flight_lift(par, S, x0 + vx * h - 0.5 * agx * h * h, y0 + vy * h - 0.5 * agy * h * h,
                       z0 + vz * h - 0.5 * gv * h * h, sc) > 0.0:
        lo, hi = 0.0, h
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if not (lo < mid < hi):
                break
            if flight_lift(par, S, x0 + vx * mid - 0.5 * agx * mid * mid, y0 + vy * mid - 0.5 * agy * mid * mid,
                           z0 + vz * mid - 0.5 * gv * mid * mid, sc) > 0.0:
                lo = mid
            else:
                hi = mid
        tau = hi
        landed = True
    dx = vx * tau - 0.5 * agx * tau * tau
    dy = vy * tau - 0.5 * agy * tau * tau
    dz = vz * tau - 0.5 * gv * tau * tau
    S[S_XF] = x0 + dx
    S[S_YF] = y0 + dy
    S[S_ZF] = z0 + dz
    S[S_VXF] = vx - agx * tau
    S[S_VYF] = vy - agy * tau
    S[S_VZF] = vz - gv * tau
    S[S_EIN] += -tk.moving_mass(par) * (agx * dx + agy * dy + az * dz)
    S[S_TFLY] += tau
    if landed:
        fail = _land(par, S, sc)
        if fail != FAIL_NONE:
            return -2.0 - fail
    return tau


def advance_vertical(par, S, dt, agx, agy, az, mu1, mu2, mu3, mu4, machine, u1x, u1y, ud1x, ud1y, out, sc):
    """``advance`` under a vertical ground motion that may lift the TFP off
    (docs/model.md 10): while g + az >= 0 and the unit is seated, ``advance``
    itself. When the step's g + az < 0 the stack and the superstructure leave
    the lower plate and fly (``flights``) until they land; a step that lands
    finishes seated (``advance`` over the rest, its force spread over dt).
    In the air: no contact, no friction, no heat, no force on the ground."""
    rem, how = flights(par, S, dt, par[tk.I_G] + az, agx, agy, sc)
    if how != FLIGHT_SEATED and how != FLIGHT_LANDED:
        return FAIL_NONE if how == FLIGHT_AIR else how
    fail = advance(par, S, rem, agx, agy, az, mu1, mu2, mu3, mu4, machine, u1x, u1y, ud1x, ud1y, out, sc)
    if how == FLIGHT_LANDED:
        landed_share(S, rem, dt)
    return fail


def flights(par, S, dt, gv, agx, agy, sc):
    """The flights (``_flight``) in a step of dt under gv = g + az, in the air
    or seated with gv < 0 (this TFP's and the two-phase one's). Returns (what
    is left of the step, how it goes on): FLIGHT_SEATED (it never left
    the seat, or g + az >= 0 seated: seated over all of it), FLIGHT_LANDED (landed with time
    left: seated over that, then ``landed_share``), FLIGHT_AIR (in the
    air at its end, or landed with nothing left: the contact columns
    cleared), or a landing's failure flag."""
    rem = dt
    flown = False
    for _ in range(tk.FLIGHTS_MAX):
        if S[S_FLY] == 0.0 and not gv < 0.0:
            break
        tau = _flight(par, S, agx, agy, gv, rem, sc)
        if tau <= -2.0:
            return rem, int(-2.0 - tau)
        if tau < 0.0:              # the seat's curvature keeps it down over the step: seated
            break
        flown = True
        rem = rem - tau
        if S[S_FLY] != 0.0 or not rem > tk.FLIGHT_REST * dt:
            break
    if not flown:
        return dt, FLIGHT_SEATED
    if S[S_FLY] == 0.0 and rem > tk.FLIGHT_REST * dt:
        return rem, FLIGHT_LANDED
    for i in range(4):
        S[S_N + i] = S[S_SV + i] = S[S_DW + i] = S[S_SLIDE + i] = 0.0
    S[S_F] = S[S_F + 1] = S[S_REG] = S[S_ITER] = S[S_KKT] = 0.0
    S[S_PHASE] = tk.PHASE_STICK
    return rem, FLIGHT_AIR


def landed_share(S, rem, dt):
    """A step that landed with rem of dt left: its force and slip speeds over
    the whole step (the bearing carries nothing in the air)."""
    S[S_F] = S[S_F] * (rem / dt)
    S[S_F + 1] = S[S_F + 1] * (rem / dt)
    for i in range(4):
        S[S_SV + i] = S[S_SV + i] * (rem / dt)


def energies_vertical(par, S, o, sc):
    """(E_kin, E_pot) into o[0:2], in flight too: the unit's (M + m) |V|^2 / 2
    and the take-off configuration's potential + (M + m) g z_f."""
    if S[S_FLY] != 0.0:
        mt = tk.moving_mass(par)
        o[0] = 0.5 * mt * (S[S_VXF] * S[S_VXF] + S[S_VYF] * S[S_VYF] + S[S_VZF] * S[S_VZF])
        o[1] = potential(par, S[0:4]) + mt * par[tk.I_G] * S[S_ZF]
    else:
        o[0] = kinetic(par, S[0:4], S[4:8], sc)
        o[1] = potential(par, S[0:4])


# -- rims of finite stiffness (docs/model.md 6.12) -------------------------------------------------
# With par[I_KRIM] = k != 0 no circle bounds the tilts: each surface's slide beyond its capacity,
# R_i |v| - d_i (v = phi for S1, S4; alpha for S2, S3: the slide's arc R_i |v|, the measure of the
# footprint's distance from the centre, s1_m..s4_m), is a spring k and a dashpot (tribology/rim_law.py).
# Their scratch: the force (4), its Jacobian (16), each block's radial inertia (2), the dashpots'
# loss, a solve's vectors (8) and factor (16), and the two-phase step's H + J (16) and r + J x (4).
SP_F, SP_J, SP_M, SP_LOSS, SP_V, SP_LL, SP_H, SP_R = 616, 620, 636, 638, 640, 648, 664, 680
N_SC_SPRING = 684


def rim_spring_mass(par, q, M, sc):
    """Each block's generalised inertia along its radial direction n (the
    tilt's unit vector at q; x at q = 0) with every other direction free,
    m_n = 1 / (n^T M^-1 n), M = M(q) given: the mass a rigid rim's impulse
    along n sees (on the x axis the planar TFP's det M / M_jj), into
    sc[SP_M:SP_M + 2]."""
    for b in range(2):
        vx, vy = q[2 * b], q[2 * b + 1]
        rho = math.sqrt(vx * vx + vy * vy)
        nx, ny = 1.0, 0.0
        if rho > 0.0:
            nx, ny = vx / rho, vy / rho
        for i in range(4):
            sc[SP_V + i] = 0.0
        sc[SP_V + 2 * b] = nx
        sc[SP_V + 2 * b + 1] = ny
        chol_solve(M, sc[SP_V:SP_V + 4], sc[SP_V + 4:SP_V + 8], sc[SP_LL:SP_LL + 16])
        sc[SP_M + b] = 1.0 / (nx * sc[SP_V + 4 + 2 * b] + ny * sc[SP_V + 5 + 2 * b])


def rim_spring_force(par, q0, x, h, sc):
    """The rims' generalised force over the increment x from q0 in the time h
    into sc[SP_F:SP_F + 4], its Jacobian in x (symmetric, positive
    semi-definite) into sc[SP_J:SP_J + 16]; returns the dashpots' loss.
    Per block, from v0 to v1 = v0 + x: the radial law of its two surfaces,
    the planar TFP's rim_coordinate on rho = |v| from |v0| to |v1|
    (rim_law.slide per surface: the spring k R^2 beyond d / R and its
    secant, the dashpot c R^2, c = 2 zeta sqrt(k m_eff), m_eff = m_n / sum
    R^2, ``rim_spring_mass``), their sum f along
    u = (v0 + v1) / (|v0| + |v1|). u . x = |v1| - |v0|, so the force's work
    over x is the springs' energy change plus the loss: the discrete
    gradient of the central potential (exact for any increment), on the x
    axis the planar TFP's rim_coordinate. Jacobian: j u u^T + (f / (|v0| +
    |v1|))_+ (I - u u^T) (j = df / d|v1|), the derivative's symmetric part
    at a short increment."""
    loss = 0.0
    for i in range(20):
        sc[SP_F + i] = 0.0
    for b in range(2):
        ax, ay = q0[2 * b], q0[2 * b + 1]
        bx, by = ax + x[2 * b], ay + x[2 * b + 1]
        r0 = math.sqrt(ax * ax + ay * ay)
        r1 = math.sqrt(bx * bx + by * by)
        f, j, l = tk.rim_coordinate(par, b, r0, r1 - r0, h, sc[SP_M + b])
        loss += l
        if f == 0.0 and j == 0.0:
            continue
        s = r0 + r1
        ux, uy = (ax + bx) / s, (ay + by) / s
        sc[SP_F + 2 * b] = f * ux
        sc[SP_F + 2 * b + 1] = f * uy
        ft = f / s if f > 0.0 else 0.0
        i0 = SP_J + 10 * b        # the block's diagonal 2x2 of the row-major 4x4
        sc[i0] = j * ux * ux + ft * (1.0 - ux * ux)
        sc[i0 + 1] = (j - ft) * ux * uy
        sc[i0 + 4] = (j - ft) * ux * uy
        sc[i0 + 5] = j * uy * uy + ft * (1.0 - uy * uy)
    return loss


def rim_spring_linearise(par, q0, x, h, G, r, H, Hn, rn, sc):
    """The step's problem with the rims' force linearised about the iterate x
    (Newton's iteration on the increment; at its fixed point the force is
    exact): G and r less the force, Hn = H + J, rn = r + J x (Hn, rn may
    be H, r). Returns the dashpots' loss over x."""
    loss = rim_spring_force(par, q0, x, h, sc)
    for i in range(4):
        G[i] -= sc[SP_F + i]
        r[i] -= sc[SP_F + i]
    for i in range(4):
        s = 0.0
        for j in range(4):
            Hn[4 * i + j] = H[4 * i + j] + sc[SP_J + 4 * i + j]
            s += sc[SP_J + 4 * i + j] * x[j]
        rn[i] = r[i] + s
    return loss


def rim_spring_settled(ch, x):
    """Newton's iteration on the increment has settled to round-off of it (the
    springs' force, large on a light block, leaves its last ulps to the iteration)."""
    return ch <= 1e-13 * (abs(x[0]) + abs(x[1]) + abs(x[2]) + abs(x[3]))


def rim_spring_energy(par, q):
    """The rim springs' energy, sum over S1..S4 of k o_i^2 / 2, o_i = (R_i |v_i| - d_i)_+
    (v_i = phi for S1, S4, alpha for S2, S3; 0: rigid rims): the planar TFP's on the tilts' norms."""
    return tk.rim_energy(par, math.sqrt(q[0] * q[0] + q[1] * q[1]), math.sqrt(q[2] * q[2] + q[3] * q[3]))


def rim_spring_hits(par, S, sc):
    """A step's contacts with rims of finite stiffness: a surface's slide
    passing its capacity from the step's start (step_scratch's q0) to S
    (the planar TFP's count on the tilts' norms)."""
    tk.rim_passes(par, S[S_NHIT:S_NHIT + 4], math.sqrt(sc[100] * sc[100] + sc[101] * sc[101]),
                  math.sqrt(sc[102] * sc[102] + sc[103] * sc[103]), math.sqrt(S[0] * S[0] + S[1] * S[1]),
                  math.sqrt(S[2] * S[2] + S[3] * S[3]))
