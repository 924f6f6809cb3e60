"""Per-step physics of the rigid triple friction pendulum (TFP), one source.

Kernel module (fpd/kernels.py): plain functions over floats and float64
arrays, no classes, dicts or exceptions; the pure path imports it, the
compiled path loads this same file through ``fpd.kernels.compiled``.

The rigid, non-articulated model (docs/model.md section 6). Two generalised
coordinates q = (phi, alpha):

- phi: the rotation of BOTH slider plates about the centres of the outer
  surfaces (the whole stack turning about C1; S1 slides R1 phi, S4 R4 phi);
- alpha: the pad's rotation relative to the slider plates (the inner DFP of
  S2 and S3, L_i = R2 + R3 - pad_height; S2 slides R2 alpha, S3 R3 alpha);
  the pad's absolute angle is psi = phi + alpha.

Every body k sits at r_k = -a_k e(phi) - b_k e(psi) from C1 (e(x) = (-sin x,
cos x)), so the kinetic energy is (1/2) q'^T M(alpha) q' with

    M11 = Aa + B + 2 K cos(alpha) + Jphi + Jpsi,  M12 = B + K cos(alpha) + Jpsi,
    M22 = B + Jpsi,   Aa = sum m a^2, B = sum m b^2, K = sum m a b,

the potential g [P1 (1 - cos phi) + P2 (1 - cos psi)] (P1 = sum m a, P2 =
sum m b) and the horizontal first moment b(q) = P1 sin phi + P2 sin psi,
through which the ground acceleration works (d'Alembert, relative frame).

Time stepping: an energy-consistent (discrete-gradient) Moreau scheme.
Friction is an impulse with lambda in Sgn(dq) (so the work it does in a step
is exactly cap |dq|), the rims are bounds |q_j| <= qmax_j, and the step's
increment solves the strictly convex problem

    min 1/2 dq^T H dq - r^T dq + c_o |dphi| + c_i |dalpha|   (bounds; machine: d^T dq = e)

with H = 2 M(q1) / dt^2, r = 2 p0 / dt + G(q0, q1), G the discrete gradients
(Itoh-Abe, evaluated in closed form without cancellation) of the kinetic,
potential and ground-forcing terms. The minimiser is found exactly among a
handful of candidates (2 coordinates); a fixed point handles q1 in H and G.

A rim of finite stiffness (par[I_KRIM], docs/model.md 6.7) replaces the
bounds by the springs (1/2) k (R_i |q_i| - d_i)_+^2 of S1..S4 (and their
dashpots): their exact secant joins G, and the fixed point becomes Newton's
iteration on the increment (``rim_coordinate``: rim_law.slide in each
coordinate), each iterate the exact box problem.
"""
import math

from fpd.tribology.friction_kernel import holding_mu
from fpd.tribology import rim_law as rl
from .two_phase_kernel import _sinc as sinc, pivot_angle   # the planar stepper's, one source

__kernel__ = True

# -- parameter vector (pack_params in mechanics/tfp.py) ---------------------------
I_AA, I_B, I_K, I_JPHI, I_JPSI, I_P1, I_P2 = 0, 1, 2, 3, 4, 5, 6
I_A, I_LI, I_G, I_MSUP = 7, 8, 9, 10
I_R1, I_R2, I_R3, I_R4 = 11, 12, 13, 14
I_QMAX_PHI, I_QMAX_ALPHA = 15, 16
I_MS_LO, I_MS_UP, I_MPAD = 17, 18, 19
I_A_SL, I_A_PAD, I_B_PAD, I_A_SU = 20, 21, 22, 23   # a_k, b_k of the lower slider, pad, upper slider
I_TWO = 24                          # 1.0: the paper's two-phase model (docs/model.md 6.6), 0.0: seated
I_AP, I_AS, I_HP, I_TL, I_TU = 25, 26, 27, 28, 29   # pad and slider half-diameters, heights
I_EPB, I_EPT, I_ESB, I_SQ4, I_L4 = 30, 31, 32, 33, 34   # corner heights (below), sqrt(R4^2 - a_s^2), l4
I_D1, I_D2, I_D3, I_D4 = 35, 36, 37, 38   # slide capacities of S1..S4 (arc, m)
I_VERT = 39                         # 1.0: a vertical ground motion (the az_mps2 column), 2.0: the test
                                    # machine's axial-load programme (az carries the held load N), 0.0: none
I_REST = 40                         # Newton's restitution of a rim arrival (0: inelastic)
I_MUS = 41                          # 41..44: static coefficients of S1..S4 (0: none; friction_kernel.holding_mu)
I_MUR = 45                          # 45..48: their static ratios to the sliding law (0: none)
# a rim of finite stiffness (docs/model.md 6.7; 0: the rigid rims): the spring k (N/m) on each
# surface's slide beyond its capacity, the dashpots' damping ratio zeta, and for each of S1..S4
# the sum of R_i^2 over its coordinate's surfaces that reach their rims with it (the same d_i / R_i)
I_KRIM, I_ZRIM, I_SR = 49, 50, 51     # 51..54
N_PAR = 55

# -- step output vector ----------------------------------------------------------
O_DPHI, O_DALPHA, O_F, O_EIN, O_WO, O_WI, O_RIM, O_ITER, O_FAIL = 0, 1, 2, 3, 4, 5, 6, 7, 8
O_ARREST_O, O_ARREST_I, O_MACH_K, O_NU_PHI, O_NU_ALPHA, O_ARRIVE = 9, 10, 11, 12, 13, 14
O_RESEAT = 15
O_DX_RIM, O_HIT_O, O_HIT_I = 16, 17, 18   # the superstructure's velocity jump at rim impacts; impacts per coordinate
N_OUT = 19

FAIL_NONE, FAIL_CAPACITY, FAIL_FIXED_POINT, FAIL_ROCKING = 0, 1, 2, 3
FAIL_LAND = 5           # a flight would land beyond the outer surfaces' reach (not modelled)
# a landing this close to the step's end (relative to dt) ends the step: no seated remainder
FLIGHT_REST = 1e-12
# flights (take-off, landing, take-off ...) at most within one step; then the rest is seated
FLIGHTS_MAX = 4

FIXED_POINT_TOL = 1e-15
FIXED_POINT_ITERS = 60
# with rim springs: the mass matrix M(q1) of a large increment deep past a rim can slow the
# fixed point on the pad's light mode to a ratio near 0.65 (Newton takes the springs' part)
RIM_ITERS = 200




def mass_matrix(par, alpha, M):
    """M(alpha) into M = [M11, M12, M22]."""
    c = math.cos(alpha)
    B, K, Jpsi = par[I_B], par[I_K], par[I_JPSI]
    M[0] = par[I_AA] + B + 2.0 * K * c + par[I_JPHI] + Jpsi
    M[1] = B + K * c + Jpsi
    M[2] = B + Jpsi


def solve2(m11, m12, m22, b1, b2, out):
    """x = M^-1 b for the symmetric 2x2 M; out[0], out[1]."""
    det = m11 * m22 - m12 * m12
    out[0] = (m22 * b1 - m12 * b2) / det
    out[1] = (m11 * b2 - m12 * b1) / det


def kinetic(par, alpha, v1, v2):
    c = math.cos(alpha)
    B, K, Jpsi = par[I_B], par[I_K], par[I_JPSI]
    m11 = par[I_AA] + B + 2.0 * K * c + par[I_JPHI] + Jpsi
    m12 = B + K * c + Jpsi
    m22 = B + Jpsi
    return 0.5 * (m11 * v1 * v1 + 2.0 * m12 * v1 * v2 + m22 * v2 * v2)


def potential(par, phi, alpha):
    return par[I_G] * (par[I_P1] * (1.0 - math.cos(phi)) + par[I_P2] * (1.0 - math.cos(phi + alpha)))


def moment_x(par, phi, alpha):
    """b(q): horizontal first moment sum m_k x_k relative to the ground (kg m)."""
    return par[I_P1] * math.sin(phi) + par[I_P2] * math.sin(phi + alpha)


def u_dot(par, phi, alpha, v1, v2):
    """The superstructure's velocity relative to the ground, u'."""
    c = par[I_LI] * math.cos(phi + alpha)
    return (par[I_A] * math.cos(phi) + c) * v1 + c * v2


def u_rel(par, phi, alpha):
    """Superstructure displacement relative to the ground, u = A sin phi + L_i sin psi."""
    return par[I_A] * math.sin(phi) + par[I_LI] * math.sin(phi + alpha)


def rise(par, phi0, al0, phi1, al1):
    """sum m z(q1) - sum m z(q0): the change of the first moment of the
    heights, potential / g, without cancellation (cos a - cos b as a product)."""
    return rise_of(par[I_P1], par[I_P2], phi0, al0, phi1, al1)


def rise_of(p1, p2, phi0, al0, phi1, al1):
    """f(q1) - f(q0) of f = p1 (1 - cos phi) + p2 (1 - cos psi), without cancellation
    (p1 = A, p2 = L_i: the superstructure's rise, ``uplift``)."""
    hf = 0.5 * (phi1 - phi0)
    hp = 0.5 * (phi1 + al1 - phi0 - al0)
    return 2.0 * (p1 * math.sin(0.5 * (phi0 + phi1)) * math.sin(hf)
                  + p2 * math.sin(0.5 * (phi0 + al0 + phi1 + al1)) * math.sin(hp))


def uplift(par, phi, alpha):
    return par[I_A] * (1.0 - math.cos(phi)) + par[I_LI] * (1.0 - math.cos(phi + alpha))


def rim_coordinate(par, j, q, x, h, mq):
    """The rims of finite stiffness on one coordinate (j = 0: phi, surfaces S1
    and S4; j = 1: alpha, S2 and S3) over the increment x from q in the time h
    (docs/model.md 6.7): (force, dforce/dx, loss) summed over its two
    surfaces, each rim_law.slide in the coordinate (surface i: the spring
    k R_i^2 beyond the capacity d_i / R_i, the dashpot c_i R_i^2 with c_i =
    2 zeta sqrt(k m_eff_i), m_eff_i = mq / par[I_SR + i], mq the coordinate's
    generalised inertia with the other coordinate free). The TFP in both
    directions calls it on each block's radius (tfp3d_kernel.rim_spring_force)."""
    k = par[I_KRIM]
    f = 0.0
    dj = 0.0
    loss = 0.0
    for n in range(2):
        i = 3 * n if j == 0 else 1 + n       # phi: S1, S4; alpha: S2, S3
        R = par[I_R1 + i]
        cap = par[I_D1 + i] / R
        if abs(q) <= cap and abs(q + x) <= cap:
            continue                         # inside the rim over the whole increment: no force
        c = 0.0
        if par[I_ZRIM] != 0.0:
            c = rl.dashpot_coefficient(par[I_ZRIM], k, mq / par[I_SR + i]) * R * R
        a, b, l = rl.slide(k * R * R, c, cap, q, x, h)
        f += a
        dj += b
        loss += l
    return f, dj, loss


def rim_energy(par, phi, alpha):
    """The rim springs' energy, sum over S1..S4 of k o_i^2 / 2, o_i = (R_i |q_i| - d_i)_+ (0: rigid rims);
    the TFP in both directions gives its tilts' norms."""
    k = par[I_KRIM]
    if k == 0.0:
        return 0.0
    e = 0.0
    for i in range(4):
        q = phi if (i == 0 or i == 3) else alpha
        e += rl.spring_energy(k, rl.overlap(par[I_R1 + i] * abs(q) - par[I_D1 + i]))
    return e


def rim_passes(par, hits, phi0, al0, phi1, al1):
    """The contacts of rims of finite stiffness over a step from (phi0, al0)
    to (phi1, al1) (the TFP in both directions: the tilts' norms): each
    surface whose slide R_i |q| passes its capacity d_i, counted in hits[i]."""
    for i in range(4):
        q0 = phi0 if (i == 0 or i == 3) else al0
        q1 = phi1 if (i == 0 or i == 3) else al1
        R = par[I_R1 + i]
        if R * abs(q0) <= par[I_D1 + i] and R * abs(q1) > par[I_D1 + i]:
            hits[i] += 1.0


def dgrad_cos_sin(p1, p2, phi0, a0, phi1, a1, out, use_sin):
    """Itoh-Abe discrete gradient of f = p1 (1 - cos phi) + p2 (1 - cos(phi + alpha))
    (use_sin = 0) or f = p1 sin phi + p2 sin(phi + alpha) (use_sin = 1), phi first,
    then alpha, so that out . (q1 - q0) = f(q1) - f(q0) exactly."""
    hp = 0.5 * (phi1 - phi0)
    ha = 0.5 * (a1 - a0)
    pm = 0.5 * (phi0 + phi1)
    am = 0.5 * (a0 + a1)
    sp, sa = sinc(hp), sinc(ha)
    if use_sin == 0:
        out[0] = (p1 * math.sin(pm) + p2 * math.sin(pm + a0)) * sp
        out[1] = p2 * math.sin(phi1 + am) * sa
    else:
        out[0] = (p1 * math.cos(pm) + p2 * math.cos(pm + a0)) * sp
        out[1] = p2 * math.cos(phi1 + am) * sa


def qp_box(h11, h12, h22, r1, r2, c1, c2, lo1, hi1, lo2, hi2, x):
    """Minimise f = 1/2 x^T H x - r^T x + c1|x1| + c2|x2| on the box; the
    minimiser is one of the candidates (each coordinate at lo, 0, hi, or free
    on one side of its kink), so the feasible candidate of least f is exact.
    The minimiser without the box comes first (9 candidates): when it lies in
    the box it is the answer (convexity), which is the common case."""
    _qp_cands(h11, h12, h22, r1, r2, c1, c2, -1e300, 1e300, -1e300, 1e300, x, 1)
    if lo1 <= x[0] <= hi1 and lo2 <= x[1] <= hi2:
        return 0.0
    return _qp_cands(h11, h12, h22, r1, r2, c1, c2, lo1, hi1, lo2, hi2, x, 0)


def _off_side(y, g, c):
    """A free candidate on the side g of the kink must lie strictly on it;
    without friction (c = 0, no kink) 0 is on either side."""
    return y * g < 0.0 or (y * g == 0.0 and c != 0.0)


def _qp_cands(h11, h12, h22, r1, r2, c1, c2, lo1, hi1, lo2, hi2, x, free_only):
    best = 1e300
    x[0] = 0.0
    x[1] = 0.0
    det = h11 * h22 - h12 * h12
    # f is compared as 1/2 (y - yu)^T H (y - yu) + c1 |y1| + c2 |y2| (yu = H^-1 r,
    # the same f less a constant): -r^T y and 1/2 y^T H y nearly cancel, and
    # candidates whose f differ by less than their round-off would tie, so the
    # choice, and with it the step's fixed point, could flip between them
    yu1 = (h22 * r1 - h12 * r2) / det
    yu2 = (h11 * r2 - h12 * r1) / det
    for s1 in range(5):
        for s2 in range(5):
            if free_only == 1 and (s1 == 0 or s1 == 2 or s2 == 0 or s2 == 2):
                continue
            # without friction a coordinate has no kink at 0: its free candidates
            # (either sign, 0 included) cover it; a separate "at 0" candidate
            # would tie with them to round-off and the fixed point could cycle
            if (s1 == 1 and c1 == 0.0) or (s2 == 1 and c2 == 0.0):
                continue
            # states: 0 lo, 1 zero, 2 hi, 3 free negative, 4 free positive
            f1 = s1 < 3
            f2 = s2 < 3
            y1 = 0.0
            y2 = 0.0
            if f1:
                y1 = lo1 if s1 == 0 else (0.0 if s1 == 1 else hi1)
            if f2:
                y2 = lo2 if s2 == 0 else (0.0 if s2 == 1 else hi2)
            g1 = 1.0 if s1 == 4 else -1.0
            g2 = 1.0 if s2 == 4 else -1.0
            if not f1 and not f2:
                b1 = r1 - c1 * g1
                b2 = r2 - c2 * g2
                y1 = (h22 * b1 - h12 * b2) / det
                y2 = (h11 * b2 - h12 * b1) / det
                if _off_side(y1, g1, c1) or _off_side(y2, g2, c2):
                    continue
            elif not f1:
                y1 = (r1 - c1 * g1 - h12 * y2) / h11
                if _off_side(y1, g1, c1):
                    continue
            elif not f2:
                y2 = (r2 - c2 * g2 - h12 * y1) / h22
                if _off_side(y2, g2, c2):
                    continue
            if y1 < lo1 or y1 > hi1 or y2 < lo2 or y2 > hi2:
                continue
            e1 = y1 - yu1
            e2 = y2 - yu2
            f = 0.5 * (h11 * e1 * e1 + 2.0 * h12 * e1 * e2 + h22 * e2 * e2) + c1 * abs(y1) + c2 * abs(y2)
            if f < best:
                best = f
                x[0] = y1
                x[1] = y2
    return best


def qp_line(h11, h12, h22, r1, r2, c1, c2, lo1, hi1, lo2, hi2, d1, d2, e, x):
    """The same minimisation on the line d1 x1 + d2 x2 = e (test machine).
    Returns 0, or 1 when the line misses the box (capacity exhausted)."""
    # parametrise by the coordinate with the larger coefficient eliminated
    swap = abs(d2) > abs(d1)
    if swap:
        h11, h22 = h22, h11
        r1, r2 = r2, r1
        c1, c2 = c2, c1
        lo1, lo2 = lo2, lo1
        hi1, hi2 = hi2, hi1
        d1, d2 = d2, d1
    # x1 = (e - d2 t) / d1, x2 = t
    k0 = e / d1
    k1 = -d2 / d1
    # t range from both boxes
    tlo, thi = lo2, hi2
    # which bound of x1 (if any) makes each end of the t range: snapped to exactly at the end
    ylo, yhi = 0.0, 0.0
    flo, fhi = False, False
    if k1 != 0.0:
        ta = (lo1 - k0) / k1
        tb = (hi1 - k0) / k1
        if k1 > 0.0:
            if ta > tlo:
                tlo, ylo, flo = ta, lo1, True
            if tb < thi:
                thi, yhi, fhi = tb, hi1, True
        else:
            if tb > tlo:
                tlo, ylo, flo = tb, hi1, True
            if ta < thi:
                thi, yhi, fhi = ta, lo1, True
    elif k0 < lo1 or k0 > hi1:
        return 1
    if tlo > thi:
        # allow round-off at the capacity
        if tlo - thi > 1e-12 * (1.0 + abs(tlo)):
            return 1
        thi = tlo
    # f(t) = 1/2 A t^2 + Bq t + const + c1 |k0 + k1 t| + c2 |t|
    A = h11 * k1 * k1 + 2.0 * h12 * k1 + h22
    Bq = h11 * k0 * k1 + h12 * k0 - r1 * k1 - r2
    best = 1e300
    bt = tlo
    bj = 0
    # candidates: ends, kinks, stationary points of the four smooth pieces
    for j in range(8):
        if j == 0:
            t = tlo
        elif j == 1:
            t = thi
        elif j == 2:
            if c2 == 0.0:           # no kink without friction (see _qp_cands)
                continue
            t = 0.0
        elif j == 3:
            if k1 == 0.0 or c1 == 0.0:
                continue
            t = -k0 / k1
        else:
            s1 = 1.0 if (j - 4) // 2 == 0 else -1.0
            s2 = 1.0 if (j - 4) % 2 == 0 else -1.0
            if A <= 0.0:
                continue
            t = -(Bq + c1 * s1 * k1 + c2 * s2) / A
        if t < tlo or t > thi:
            continue
        y1 = k0 + k1 * t
        f = 0.5 * A * t * t + Bq * t + c1 * abs(y1) + c2 * abs(t)
        if f < best:
            best = f
            bt = t
            bj = j
    y1 = k0 + k1 * bt
    if bj == 0 and flo:
        y1 = ylo
    elif bj == 1 and fhi:
        y1 = yhi
    if bj == 3:
        y1 = 0.0            # the kink of the eliminated coordinate: it sticks exactly
    if swap:
        x[0] = bt
        x[1] = y1
    else:
        x[0] = y1
        x[1] = bt
    return 0


def normal_forces(par, phi, alpha, v1, v2, a1, a2, ag, gv, F, N):
    """Normal forces N1..N4 (N[0..3]) along the axes through the surface
    centres, from the bodies' accelerations (generalised accelerations a1, a2,
    ground acceleration ag) in the vertical field gv = g + a_z (g without a
    vertical ground motion) top down: the superstructure (minus the machine's
    horizontal force F), the upper slider, the pad, the lower slider.
    No tension across a contact: negative values are clipped to 0."""
    g = gv
    psi = phi + alpha
    vpsi = v1 + v2
    apsi = a1 + a2
    cf, sf = math.cos(phi), math.sin(phi)
    cp, sp = math.cos(psi), math.sin(psi)
    # acceleration of a point r = -a e(phi) - b e(psi): x'' = a(phi'' c - phi'^2 s) + ..., z'' = a(phi'' s + phi'^2 c) + ...
    axf = a1 * cf - v1 * v1 * sf
    azf = a1 * sf + v1 * v1 * cf
    axp = apsi * cp - vpsi * vpsi * sp
    azp = apsi * sp + vpsi * vpsi * cp
    A, Li, Ms = par[I_A], par[I_LI], par[I_MSUP]
    # force of the bearing on the superstructure (upwards through S4)
    bx = Ms * (ag + A * axf + Li * axp) - F
    bz = Ms * (g + A * azf + Li * azp)
    N[3] = -bx * sf + bz * cf
    a_su = par[I_A_SU]
    m = par[I_MS_UP]
    bx += m * (ag + a_su * axf + Li * axp)
    bz += m * (g + a_su * azf + Li * azp)
    N[2] = -bx * sp + bz * cp
    m = par[I_MPAD]
    bx += m * (ag + par[I_A_PAD] * axf + par[I_B_PAD] * axp)
    bz += m * (g + par[I_A_PAD] * azf + par[I_B_PAD] * azp)
    N[1] = -bx * sp + bz * cp
    m = par[I_MS_LO]
    bx += m * (ag + par[I_A_SL] * axf)
    bz += m * (g + par[I_A_SL] * azf)
    N[0] = -bx * sf + bz * cf
    for i in range(4):
        if N[i] < 0.0:
            N[i] = 0.0


def top_load(par, phi, alpha, dn, N):
    """A vertical force dn (N, down) on the superstructure besides its weight
    (the test machine's axial load N(t) - M g) passes down the stack: each
    contact's normal force grows by dn cos(its axis) (S1, S4: phi; S2, S3: psi)."""
    cf = math.cos(phi)
    cp = math.cos(phi + alpha)
    N[0] += dn * cf
    N[1] += dn * cp
    N[2] += dn * cp
    N[3] += dn * cf
    for i in range(4):
        if N[i] < 0.0:
            N[i] = 0.0


def reseat(par, phi0, al0, phi1, al1, v1, v2, M, w):
    """The impulsive re-seating of the two-phase model (docs/model.md 6.6):
    the velocity field of phase 1, every body k moving along its seated
    tangent at q0 (a_k phi' t(phi0) + b_k psi' t(psi0), spins phi', psi'),
    projected in the kinetic-energy metric onto the seated tangent space at
    q1: p = J(q1)^T M_bodies J(q0) v, v+ = M(q1)^-1 p (into w; M <- M(q1)).
    Returns the kinetic energy removed, T(q0, v) - T(q1, v+) >= 0 (the
    projection is M-orthogonal, so it is the energy of the part stopped)."""
    vpsi = v1 + v2
    psi0 = phi0 + al0
    psi1 = phi1 + al1
    c_ff = math.cos(phi1 - phi0)
    c_pp = math.cos(psi1 - psi0)
    c_fp = math.cos(phi1 - psi0)
    c_pf = math.cos(psi1 - phi0)
    Aa, B, K, Jphi, Jpsi = par[I_AA], par[I_B], par[I_K], par[I_JPHI], par[I_JPSI]
    pa = K * v1 * c_pf + B * vpsi * c_pp + Jpsi * vpsi
    pf = Aa * v1 * c_ff + K * vpsi * c_fp + Jphi * v1 + pa
    mass_matrix(par, al1, M)
    solve2(M[0], M[1], M[2], pf, pa, w)
    # the loss as the kinetic energy of the part stopped, 1/2 |J0 v - J1 v+|^2
    # (body by body: a X + b Y, spins), not T0 - T1: no cancellation
    wpsi = w[0] + w[1]
    xx = v1 * math.cos(phi0) - w[0] * math.cos(phi1)
    xz = v1 * math.sin(phi0) - w[0] * math.sin(phi1)
    yx = vpsi * math.cos(psi0) - wpsi * math.cos(psi1)
    yz = vpsi * math.sin(psi0) - wpsi * math.sin(psi1)
    d1 = v1 - w[0]
    d2 = vpsi - wpsi
    return 0.5 * (Aa * (xx * xx + xz * xz) + B * (yx * yx + yz * yz) + 2.0 * K * (xx * yx + xz * yz)
                  + Jphi * d1 * d1 + Jpsi * d2 * d2)


def stuck_then_rim(mss, msr, mrr, vs, vr):
    """A coordinate s stuck by friction while the other, r, is stopped by its
    rim in the same step (mass matrix entries mss, msr, mrr): s's end velocity
    first (its arrest, an impulse on s keeping p_r), then the rim's impulse
    on r alone. A friction force is finite, so it cannot take the impulse: s
    keeps the momentum the impact hands it, p_s = msr v_r, the next step's to
    hold or not. Returns (v_s after, arrest loss, rim loss)."""
    k0 = 0.5 * (mss * vs * vs + 2.0 * msr * vs * vr + mrr * vr * vr)
    vr = (msr * vs + mrr * vr) / mrr
    ka = 0.5 * mrr * vr * vr
    vs = msr * vr / mss
    return vs, k0 - ka, ka - 0.5 * mss * vs * vs


def restitute(e, M, pf1, pf2, v1, v2, w):
    """Newton's restitution e of a rim arrival whose inelastic stop left the
    rates (v1, v2): the free momentum (pf1, pf2) is what the part would carry
    without the rim (its reaction over the part and the stop both act on the
    coordinate at the rim only), v_free = M^-1 pf; the stop's whole jump
    d = v - v_free is taken (1 + e) times: w = v + e d, so the coordinate
    leaves the rim at -e times its free rate. d is M-orthogonal to v (the
    impulse is on the rim's coordinate, whose rate in v is 0), so the energy
    handed back is e^2 (1/2) d^T M d: the impact takes (1 - e^2) of the
    kinetic energy normal to the rim, (1/2) d^T M d. Returns that energy."""
    solve2(M[0], M[1], M[2], pf1, pf2, w)
    d1 = v1 - w[0]
    d2 = v2 - w[1]
    w[0] = v1 + e * d1
    w[1] = v2 + e * d2
    return e * e * 0.5 * (M[0] * d1 * d1 + 2.0 * M[1] * d1 * d2 + M[2] * d2 * d2)


def rim_lock(m11, m12, m22, v1, v2, o1, o2, w):
    """The inelastic rim impact at the end of a step: a coordinate k on its
    rim (o_k = +1 or -1, the side of the rim; 0 off it) may not move into it.
    The velocity after is the kinetic-metric projection of (v1, v2) onto that
    cone (a rigid, inelastic, frictionless impact: an impulse only on the
    coordinates on a rim, each pushing away from its rim, each of them then at
    rest or leaving the rim): into w, by the two-coordinate impact law the
    flat bearing's rims share (rim_law.stop2, restitution 0). Returns the
    kinetic energy removed, the energy of the part stopped, 1/2 dv^T M dv."""
    return rl.stop2(m11, m12, m22, v1, v2, o1, o2, 0.0, w)


def step(par, st, dt, ag, gv, dn, c_o, c_i, machine, u1, ud1, out, M, w, tmp, sc):
    """One step of the rigid TFP (see ``substep``), split at each rim impact.

    A coordinate that reaches its rim inside the step would otherwise be
    stopped by a position clamp whose reaction (and so the momentum it hands
    to the other coordinate, and the loss) depends on where in the step the
    rim was met. Instead the step is split: the first part ends at the rim
    (fraction tau of what is left of the step, from the unclamped increment),
    where the impact is inelastic at velocity level (the kinetic energy of the
    stopped coordinate, exactly, is the rim loss); the rest starts on the rim,
    and is split again if the other coordinate meets its own rim in it.
    out[O_DX_RIM]: the superstructure's velocity change at the impacts, the
    velocity change of each part up to a rim less its share of the free
    flight's (the unbounded step's) smooth change.
    sc: scratch of length >= 4 + 2 N_OUT."""
    for i in range(4):
        sc[i] = st[i]
    substep(par, st, dt, ag, gv, dn, c_o, c_i, machine, u1, ud1, out, M, w, tmp, 0)
    if out[O_FAIL] != FAIL_NONE or out[O_ARRIVE] == 0.0:
        return
    acc = 4
    sv = 4 + N_OUT
    for i in range(N_OUT):
        sc[acc + i] = 0.0
    u0 = 0.0
    if machine == 1:
        u0 = u_rel(par, sc[0], sc[1])
    ud0 = u_dot(par, sc[0], sc[1], sc[2], sc[3])
    t0 = 0.0                    # the fraction of the step done
    F = 0.0
    qm1 = par[I_QMAX_PHI]
    qm2 = par[I_QMAX_ALPHA]
    for k in range(3):
        h = (1.0 - t0) * dt
        # the unclamped increment of what is left decides where the rim is met
        for i in range(4):
            st[i] = sc[i]
        udp = u_dot(par, sc[0], sc[1], sc[2], sc[3])
        substep(par, st, h, ag, gv, dn, c_o, c_i, machine, u1, ud1, out, M, w, tmp, 1)
        udf = u_dot(par, st[0], st[1], st[2], st[3])
        tau = 1.0
        d1 = out[O_DPHI]
        d2 = out[O_DALPHA]
        # (a coordinate already resting on its rim, to the round-off substep
        # treats as on it, does not meet it inside the step: its rim holds it
        # from the start, and the step is split where the other meets its own)
        if d1 != 0.0 and abs(sc[0] + d1) > qm1:
            dist = (qm1 if d1 > 0.0 else -qm1) - sc[0]
            if abs(dist) > 1e-13 * qm1:
                tau = min(tau, dist / d1)
        if d2 != 0.0 and abs(sc[1] + d2) > qm2:
            dist = (qm2 if d2 > 0.0 else -qm2) - sc[1]
            if abs(dist) > 1e-13 * qm2:
                tau = min(tau, dist / d2)
        if tau < 1e-9:
            tau = 1e-9
        if tau > 1.0 - 1e-9:
            tau = 1.0 - 1e-9
        for i in range(4):
            st[i] = sc[i]
        th = t0 + tau * (1.0 - t0)
        substep(par, st, tau * h, ag, gv, dn, c_o, c_i, machine, u0 + th * (u1 - u0), ud0 + th * (ud1 - ud0),
                out, M, w, tmp, 0)
        if out[O_FAIL] != FAIL_NONE:
            return
        if out[O_HIT_O] == 0.0 and out[O_HIT_I] == 0.0:
            # the part ended on a rim only to round-off (the unclamped increment's
            # tau is not exactly where the bounded motion meets it), still moving
            # into it: the impact is here, not spread over the next part's bound
            # reaction (which would reverse the velocity inside it, out of sight
            # of the impulse)
            o1 = 0.0
            o2 = 0.0
            if abs(abs(st[0]) - qm1) <= 1e-13 * qm1 and st[0] * st[2] > 0.0:
                o1 = 1.0 if st[0] > 0.0 else -1.0
                st[0] = o1 * qm1
            if abs(abs(st[1]) - qm2) <= 1e-13 * qm2 and st[1] * st[3] > 0.0:
                o2 = 1.0 if st[1] > 0.0 else -1.0
                st[1] = o2 * qm2
            if o1 != 0.0 or o2 != 0.0:
                mass_matrix(par, st[1], M)
                v1 = st[2]
                v2 = st[3]
                out[O_RIM] += rim_lock(M[0], M[1], M[2], v1, v2, o1, o2, w)
                if par[I_REST] != 0.0:
                    # (no reaction in this part: the free momentum is M v)
                    p1 = M[0] * v1 + M[1] * v2
                    p2 = M[1] * v1 + M[2] * v2
                    out[O_RIM] -= restitute(par[I_REST], M, p1, p2, w[0], w[1], w)
                st[2] = w[0]
                st[3] = w[1]
                if o1 != 0.0:
                    out[O_HIT_O] = 1.0
                if o2 != 0.0:
                    out[O_HIT_I] = 1.0
        out[O_DX_RIM] = u_dot(par, st[0], st[1], st[2], st[3]) - udp - tau * (udf - udp)
        for i in range(N_OUT):
            if i != O_F and i != O_FAIL and i != O_NU_PHI and i != O_NU_ALPHA and i != O_ARRIVE:
                sc[acc + i] += out[i]
        F += tau * (1.0 - t0) * out[O_F]
        t0 = th
        for i in range(4):
            sc[i] = st[i]
        for i in range(4):
            sc[sv + i] = st[i]
        # the rest, from the rim
        substep(par, st, (1.0 - t0) * dt, ag, gv, dn, c_o, c_i, machine, u1, ud1, out, M, w, tmp, 0)
        if out[O_FAIL] != FAIL_NONE or out[O_ARRIVE] == 0.0 or k == 2:
            break
        # the other coordinate meets its rim in the rest: split it too
        for i in range(4):
            st[i] = sc[sv + i]
    for i in range(N_OUT):
        if i != O_F and i != O_FAIL and i != O_NU_PHI and i != O_NU_ALPHA and i != O_ARRIVE:
            out[i] += sc[acc + i]
    # the machine's force over the step: its impulse / dt (a part of a few
    # ulps of dt would otherwise report impulse / (that part), feeding 1e9 N
    # into the next step's normal forces)
    out[O_F] = F + (1.0 - t0) * out[O_F]
    out[O_ARRIVE] = 1.0


def substep(par, st, dt, ag, gv, dn, c_o, c_i, machine, u1, ud1, out, M, w, tmp, nobounds):
    """One step of the rigid TFP. st = [phi, alpha, v_phi, v_alpha] (updated).

    ag: mean ground acceleration over the step; gv: the vertical field
    g + a_z (the step's mean vertical ground acceleration a_z, up; g without
    one): it drives the discrete gradient of the heights, g of it is the
    potential and a_z of it the vertical ground's input; dn: the test
    machine's axial load less the superstructure's weight, N(t) - M g (0
    without a programme), on the superstructure's height (``uplift``): M g of
    N is in the potential, its work -dn dz is input; c_o = mu1 N1 R1 + mu4 N4 R4,
    c_i = mu2 N2 R2 + mu3 N3 R3 (friction caps of the two coordinates);
    machine = 1: the superstructure's relative displacement is imposed,
    u(t_n+1) = u1, u'(t_n+1) = ud1 (test machine; F is its horizontal force).
    M, w, tmp: scratch arrays of length >= 3, 2, 2.
    out[O_*]: increments, F, input work, friction work per coordinate (the
    arrest losses included), rim loss, iterations, failure flag."""
    for i in range(N_OUT):
        out[i] = 0.0
    q10 = st[0]
    q20 = st[1]
    v10 = st[2]
    v20 = st[3]
    qm1 = par[I_QMAX_PHI]
    qm2 = par[I_QMAX_ALPHA]
    # rims of finite stiffness (docs/model.md 6.7): no bound, their springs (and
    # dashpots) in the step's forces, Newton's iteration on the increment
    springs = par[I_KRIM] != 0.0
    if nobounds == 1 or springs:
        qm1 = 1e30
        qm2 = 1e30
    # momentum p0 = M(q0) v0
    mass_matrix(par, q20, M)
    p1 = M[0] * v10 + M[1] * v20
    p2 = M[1] * v10 + M[2] * v20
    m011, m012, m022 = M[0], M[1], M[2]
    # the generalised inertia of each coordinate with the other free (the dashpots')
    mq1 = (m011 * m022 - m012 * m012) / m022
    mq2 = (m011 * m022 - m012 * m012) / m011
    j1 = 0.0
    j2 = 0.0
    rloss = 0.0
    # box of the increment (a start a hair outside by round-off counts as on the rim)
    lo1 = -qm1 - q10
    hi1 = qm1 - q10
    lo2 = -qm2 - q20
    hi2 = qm2 - q20
    # on a rim to round-off: exactly on it (no spurious slide of an ulp)
    if abs(lo1) <= 1e-13 * qm1:
        lo1 = 0.0
    if abs(hi1) <= 1e-13 * qm1:
        hi1 = 0.0
    if abs(lo2) <= 1e-13 * qm2:
        lo2 = 0.0
    if abs(hi2) <= 1e-13 * qm2:
        hi2 = 0.0
    if lo1 > 0.0:
        lo1 = 0.0
    if hi1 < 0.0:
        hi1 = 0.0
    if lo2 > 0.0:
        lo2 = 0.0
    if hi2 < 0.0:
        hi2 = 0.0
    # predictor
    x1 = dt * v10
    x2 = dt * v20
    if x1 < lo1:
        x1 = lo1
    if x1 > hi1:
        x1 = hi1
    if x2 < lo2:
        x2 = lo2
    if x2 > hi2:
        x2 = hi2
    A, Li, g = par[I_A], par[I_LI], par[I_G]
    e = 0.0
    if machine == 1:
        e = u1 - u_rel(par, q10, q20)
    it = 0
    G1 = 0.0
    G2 = 0.0
    r1 = 0.0
    r2 = 0.0
    h11 = h12 = h22 = 0.0
    dx1 = 0.0
    dx2 = 0.0
    converged = False
    two = par[I_TWO] != 0.0
    iters = RIM_ITERS if springs else FIXED_POINT_ITERS
    y1 = y2 = math.nan          # the iterate before last (springs: a two-cycle of round-off)
    while it < iters:
        it += 1
        phi1 = q10 + x1
        al1 = q20 + x2
        dTa = 0.0
        if not two:
            mass_matrix(par, al1, M)
            # discrete gradient of T(q, p0) in alpha: -1/2 w1^T dM w0 / dalpha
            solve2(M[0], M[1], M[2], p1, p2, w)
            w11, w12 = w[0], w[1]
            solve2(m011, m012, m022, p1, p2, w)
            w01, w02 = w[0], w[1]
            K = par[I_K]
            dTa = 0.5 * (2.0 * K * w11 * w01 + K * (w11 * w02 + w12 * w01)) * math.sin(0.5 * (q20 + al1)) \
                * sinc(0.5 * (al1 - q20))
        # discrete gradients of V and b
        dgrad_cos_sin(gv * par[I_P1] + dn * A, gv * par[I_P2] + dn * Li, q10, q20, phi1, al1, tmp, 0)
        G1 = -tmp[0]
        G2 = -dTa - tmp[1]
        dgrad_cos_sin(par[I_P1], par[I_P2], q10, q20, phi1, al1, tmp, 1)
        G1 -= ag * tmp[0]
        G2 -= ag * tmp[1]
        if springs:
            # the springs' discrete gradient at this iterate and its derivative: the
            # problem linearised in them about x (Newton), friction exact
            f1, j1, l1 = rim_coordinate(par, 0, q10, x1, dt, mq1)
            f2, j2, l2 = rim_coordinate(par, 1, q20, x2, dt, mq2)
            G1 -= f1
            G2 -= f2
            rloss = l1 + l2
        h11 = 2.0 * M[0] / (dt * dt)
        h12 = 2.0 * M[1] / (dt * dt)
        h22 = 2.0 * M[2] / (dt * dt)
        r1 = 2.0 * p1 / dt + G1
        r2 = 2.0 * p2 / dt + G2
        if springs:
            qp_box(h11 + j1, h12, h22 + j2, r1 + j1 * x1, r2 + j2 * x2, c_o, c_i, lo1, hi1, lo2, hi2, w)
        elif machine == 1:
            dgrad_cos_sin(A, Li, q10, q20, phi1, al1, tmp, 1)
            dx1, dx2 = tmp[0], tmp[1]
            if qp_line(h11, h12, h22, r1, r2, c_o, c_i, lo1, hi1, lo2, hi2, dx1, dx2, e, w) != 0:
                out[O_FAIL] = FAIL_CAPACITY
                return
        else:
            qp_box(h11, h12, h22, r1, r2, c_o, c_i, lo1, hi1, lo2, hi2, w)
        n1, n2 = w[0], w[1]
        ch = abs(n1 - x1) + abs(n2 - x2)
        # (with rim springs also to 1e-12 of the increment, or a return to the iterate
        # before last within 1e-10 of it: the box problem is nearly singular along the
        # pad's light mode, and the iterates can settle into a two-cycle of round-off,
        # 2e-13 of the increment apart under El Centro and Northridge x 5-8 at
        # k = 1e7-1e10 and dt = 2 ms, 1e-12 at dt = 5 ms)
        cyc = springs and n1 == y1 and n2 == y2 and ch <= 1e-10 * (abs(n1) + abs(n2))
        y1, y2 = x1, x2
        x1, x2 = n1, n2
        if ch <= FIXED_POINT_TOL or (springs and ch <= 1e-12 * (abs(x1) + abs(x2))) or cyc:
            converged = True
            break
    if not converged:
        out[O_FAIL] = FAIL_FIXED_POINT
    # the generalised force of friction, rims and machine: Phi = r - H dq
    Phi1 = r1 - (h11 * x1 + h12 * x2)
    Phi2 = r2 - (h12 * x1 + h22 * x2)
    # momentum and velocity at t_n+1 (M holds M(q1))
    pn1 = p1 + dt * (G1 - Phi1)
    pn2 = p2 + dt * (G2 - Phi2)
    solve2(M[0], M[1], M[2], pn1, pn2, w)
    v11, v21 = w[0], w[1]
    phi1 = q10 + x1
    al1 = q20 + x2
    if x1 == lo1 and lo1 < 0.0:
        phi1 = -qm1
    elif x1 == hi1 and hi1 > 0.0:
        phi1 = qm1
    if x2 == lo2 and lo2 < 0.0:
        al1 = -qm2
    elif x2 == hi2 and hi2 > 0.0:
        al1 = qm2
    # the split of Phi into friction, rim reaction and machine force
    s1 = 1.0 if x1 > 0.0 else (-1.0 if x1 < 0.0 else 0.0)
    s2 = 1.0 if x2 > 0.0 else (-1.0 if x2 < 0.0 else 0.0)
    at1 = (x1 == lo1 and lo1 < 0.0) or (x1 == hi1 and hi1 > 0.0)
    at2 = (x2 == lo2 and lo2 < 0.0) or (x2 == hi2 and hi2 > 0.0)
    F = 0.0
    if machine == 1:
        # F from a coordinate that slides freely: Phi_k = c_k s_k - F d_k
        if s2 != 0.0 and not at2 and dx2 != 0.0:
            F = (c_i * s2 - Phi2) / dx2
        elif s1 != 0.0 and not at1 and dx1 != 0.0:
            F = (c_o * s1 - Phi1) / dx1
        elif s1 != 0.0 and dx1 != 0.0:
            F = (c_o * s1 - Phi1) / dx1
            at1 = False
        elif s2 != 0.0 and dx2 != 0.0:
            F = (c_i * s2 - Phi2) / dx2
            at2 = False
    wo = c_o * abs(x1)
    wi = c_i * abs(x2)
    rim = rloss
    nu1 = 0.0
    nu2 = 0.0
    if at1:
        nu1 = Phi1 - c_o * s1 + F * dx1
        rim += nu1 * x1
    if at2:
        nu2 = Phi2 - c_i * s2 + F * dx2
        rim += nu2 * x2
    # the superstructure's velocity u' = cx1 phi' + cx2 alpha' at q1: its jumps
    # at the rims are impulses (out[O_DX_RIM]), kept out of the step's force
    cx2 = Li * math.cos(phi1 + al1)
    cx1 = A * math.cos(phi1) + cx2
    dxr = 0.0
    ein = -ag * (moment_x(par, phi1, al1) - moment_x(par, q10, q20)) + F * e
    if gv != g:
        # the vertical ground's d'Alembert force -m a_z on the rise of the first
        # moment of the heights, sum m z = P1 (1 - cos phi) + P2 (1 - cos psi)
        ein -= (gv - g) * rise(par, q10, q20, phi1, al1)
    if dn != 0.0:
        # the machine's axial load beyond M g on the superstructure's rise
        ein -= dn * rise_of(A, Li, q10, q20, phi1, al1)
    # velocity jumps at t_n+1 (impulses at fixed position, each one's kinetic
    # energy change booked where it belongs): a coordinate that stuck (dq = 0)
    # or stopped at its rim ends at rest
    # (two-phase: in the phase-1 field, metric M(q0), before the re-seating)
    ak = q20 if two else al1
    K0 = kinetic(par, ak, v11, v21)
    z1 = s1 == 0.0 or at1
    z2 = s2 == 0.0 or at2
    # a coordinate held on its rim while its start velocity pushed into it
    # (two-phase: the re-seating's share) was stopped by the rim, not by friction
    rim1 = at1 or (s1 == 0.0 and ((lo1 == 0.0 and v10 < 0.0) or (hi1 == 0.0 and v10 > 0.0)))
    rim2 = at2 or (s2 == 0.0 and ((lo2 == 0.0 and v20 < 0.0) or (hi2 == 0.0 and v20 > 0.0)))
    arr_o = 0.0
    arr_i = 0.0
    if z1 and z2 and rim2 and not rim1:
        # phi stuck by friction, alpha stopped by its rim (stuck_then_rim)
        vb = (M[1] * v11 + M[2] * v21) / M[2]
        v11, l_arr, l_rim = stuck_then_rim(M[0], M[1], M[2], v11, v21)
        dxr += cx1 * v11 - cx2 * vb
        v21 = 0.0
        arr_o += l_arr
        rim += l_rim
    elif z1 and z2 and rim1 and not rim2:
        # the same with the roles swapped: alpha stuck by friction, phi on its rim
        va = (M[0] * v11 + M[1] * v21) / M[0]
        v21, l_arr, l_rim = stuck_then_rim(M[2], M[1], M[0], v21, v11)
        dxr += cx2 * v21 - cx1 * va
        v11 = 0.0
        arr_i += l_arr
        rim += l_rim
    elif z1 and z2:
        # stop the coordinate 1 first (impulse along e1), then the rest
        # an impulse on coordinate 1 only keeps p2 = M12 v1 + M22 v2
        va = 0.0
        vb = (M[1] * v11 + M[2] * v21) / M[2]
        Ka = kinetic(par, ak, va, vb)
        l1 = K0 - Ka
        l2 = Ka
        if rim1:
            rim += l1
            dxr += cx2 * vb - (cx1 * v11 + cx2 * v21)
        else:
            arr_o += l1
        if rim2:
            rim += l2
            dxr -= cx2 * vb
        else:
            arr_i += l2
        v11 = 0.0
        v21 = 0.0
    elif z1:
        vb = (M[1] * v11 + M[2] * v21) / M[2]
        if rim1:
            dxr += cx2 * vb - (cx1 * v11 + cx2 * v21)
        v21 = vb
        v11 = 0.0
        l1 = K0 - kinetic(par, ak, v11, v21)
        if rim1:
            rim += l1
        else:
            arr_o += l1
        if at1 and par[I_REST] != 0.0:
            rim -= restitute(par[I_REST], M, pn1 + dt * nu1, pn2, v11, v21, w)
            dxr += cx1 * (w[0] - v11) + cx2 * (w[1] - v21)
            v11, v21 = w[0], w[1]
    elif z2:
        va = (M[0] * v11 + M[1] * v21) / M[0]
        if rim2:
            dxr += cx1 * va - (cx1 * v11 + cx2 * v21)
        v11 = va
        v21 = 0.0
        l2 = K0 - kinetic(par, ak, v11, v21)
        if rim2:
            rim += l2
        else:
            arr_i += l2
        if at2 and par[I_REST] != 0.0:
            rim -= restitute(par[I_REST], M, pn1, pn2 + dt * nu2, v11, v21, w)
            dxr += cx1 * (w[0] - v11) + cx2 * (w[1] - v21)
            v11, v21 = w[0], w[1]
    if two:
        # phases 2 and 3: the phase-1 velocity field (every part along its
        # seated tangent at t_n, rates v1) re-seated at q(t_n+1), an
        # M-orthogonal projection; M becomes M(q1). What it leaves on a
        # coordinate that stuck (the turning tangent's centripetal share) is
        # the next step's to hold or not, against the friction cap.
        out[O_RESEAT] = reseat(par, q10, q20, phi1, al1, v11, v21, M, w)
        v11, v21 = w[0], w[1]
    # a coordinate that ends on its rim cannot move into it: what the impulses
    # above (the stuck-then-rim hand-over, the re-seating) left pushing into a
    # rim is stopped by it, inelastically (the full lock: both at rest)
    o1 = 1.0 if x1 == hi1 else (-1.0 if x1 == lo1 else 0.0)
    o2 = 1.0 if x2 == hi2 else (-1.0 if x2 == lo2 else 0.0)
    rim += rim_lock(M[0], M[1], M[2], v11, v21, o1, o2, w)
    dxr += cx1 * (w[0] - v11) + cx2 * (w[1] - v21)
    v11, v21 = w[0], w[1]
    mk = 0.0
    if machine == 1:
        # the machine imposes u'(t_n+1) through the coordinates still free
        c1 = A * math.cos(phi1) + Li * math.cos(phi1 + al1)
        c2 = Li * math.cos(phi1 + al1)
        Kb = kinetic(par, al1, v11, v21)
        if not z1 and not z2:
            solve2(M[0], M[1], M[2], c1, c2, w)
            den = c1 * w[0] + c2 * w[1]
            P = (ud1 - (c1 * v11 + c2 * v21)) / den
            v11 += P * w[0]
            v21 += P * w[1]
        elif not z1 and c1 != 0.0:
            v11 = (ud1 - c2 * v21) / c1
        elif not z2 and c2 != 0.0:
            v21 = (ud1 - c1 * v11) / c2
        mk = kinetic(par, al1, v11, v21) - Kb
        ein += mk
    st[0] = phi1
    st[1] = al1
    st[2] = v11
    st[3] = v21
    out[O_DPHI] = x1
    out[O_DALPHA] = x2
    out[O_F] = F
    out[O_EIN] = ein
    out[O_WO] = wo + arr_o
    out[O_WI] = wi + arr_i
    out[O_RIM] = rim
    out[O_ITER] = it
    out[O_ARREST_O] = arr_o
    out[O_ARREST_I] = arr_i
    out[O_MACH_K] = mk
    out[O_NU_PHI] = nu1
    out[O_NU_ALPHA] = nu2
    out[O_DX_RIM] = dxr
    # a coordinate that moved onto its rim in this step (not one that stayed on it)
    if at1 and x1 != 0.0:
        out[O_HIT_O] = 1.0
    if at2 and x2 != 0.0:
        out[O_HIT_I] = 1.0
    if (at1 and x1 != 0.0) or (at2 and x2 != 0.0):
        out[O_ARRIVE] = 1.0


# -- the whole step of the stepper (mechanics/tfp.py's TFPStepper and the compiled loop) --------
S_F, S_W, S_EIN, S_ERIM, S_PHASE, S_REG, S_SLIDE, S_SV, S_DW, S_N = 4, 5, 9, 10, 11, 12, 13, 17, 21, 25
S_ERS, S_B1, S_B2, S_G1, S_G2, S_DP, S_DS, S_NPH = 29, 30, 31, 32, 33, 34, 35, 36   # two-phase
S_J, S_NHIT = 37, 38   # the step's rim impulse on the superstructure (N s); rim impacts of S1..S4 so far
S_AZ = 42              # the step's vertical ground acceleration (m/s2, up)
# lift-off (docs/model.md 10): in flight (1.0); the flying unit's displacement since take-off
# (horizontal, up) and its velocity relative to the ground; the landings' loss (J), the
# lift-offs' count, the time spent in flight (s)
S_FLY, S_XF, S_ZF, S_VXF, S_VZF, S_ELAND, S_NLIFT, S_TFLY = 43, 44, 45, 46, 47, 48, 49, 50
N_S = 51
PHASE_STICK, PHASE_INNER, PHASE_OUTER, PHASE_BOTH = 0, 3, 4, 5
N_ROW = 40          # len(mechanics.tfp.COLUMNS)
N_ROW_TWO = 8       # len(mechanics.tfp.TWO_PHASE_COLUMNS)
N_ROW_VERT = 5      # len(mechanics.tfp.VERTICAL_COLUMNS)


def n_row(par):
    """Columns of a row: the seated model's, plus the two-phase model's own,
    plus the vertical ground motion's."""
    n = N_ROW + N_ROW_TWO if par[I_TWO] != 0.0 else N_ROW
    if par[I_VERT] == 1.0:
        n += N_ROW_VERT
    return n


def pad_pivot(par, dal):
    """Phase 1 of the inner DFP (Fig. 6a-d): the pad's rotation about its
    trailing corner on S2 (A for dalpha > 0, B for dalpha < 0) that keeps the
    opposite top corner on S3 when the upper slider plate is shifted by
    L_i dalpha along the tangent (docs/two_phase.md section 3 with R2, R3)."""
    a = par[I_AP]
    e = abs(par[I_LI] * dal)
    # pad frame at the bottom apex; S3's centre at (e, h_p - R3) after the shift
    px, pz = -a - e, par[I_EPB] - par[I_HP] + par[I_R3]
    b = pivot_angle(px, pz, 2.0 * a, par[I_EPT] - par[I_EPB], a * e - 0.5 * e * e)
    return b if dal >= 0.0 else -b


def stack_pivot(par, alpha, dphi):
    """Phase 1 of the outer surfaces (Fig. 6e-n, 7b): the slider plates and
    the frozen pad as one body, turning about the lower slider's trailing
    corner on S1 so that the upper slider's opposite top corner stays on S4
    when the upper plate is shifted by (A + L_i cos alpha) dphi along the
    slider plates' tangent. With the pad tilted (alpha != 0) the body is not
    symmetric: the diagonal used forwards is not the one used on reversal."""
    a = par[I_AS]
    sg = 1.0 if dphi >= 0.0 else -1.0
    e = abs((par[I_A] + par[I_LI] * math.cos(alpha)) * dphi)
    # lower slider frame at its bottom apex, mirrored for dphi < 0; C4 at (dl, c4z)
    dl = sg * par[I_LI] * math.sin(alpha)
    c4z = par[I_TL] + par[I_R2] - par[I_LI] * math.cos(alpha) - par[I_L4]
    px, pz = -a - dl - e, par[I_ESB] - c4z
    rx, rz = dl + 2.0 * a, c4z + par[I_SQ4] - par[I_ESB]
    b = pivot_angle(px, pz, rx, rz, a * e - 0.5 * e * e)
    return sg * b


def _moment(c, s, x, z, m, ag, g):
    """Moment about a pivot (counter-clockwise) of the weight and the ground's
    d'Alembert force on a mass m at (x, z) from it in a frame turned by the
    angle (c, s)."""
    return m * ((s * x + c * z) * ag - (c * x - s * z) * g)


def rocking_start(par, phi, alpha, ag):
    """Eq. (7) at rest, the rocking check of the two-phase model: 1 if the
    pad would start to turn about a corner on S2 (its load from above as a
    particle at the opposite top corner, as in the DFP), 2 if the slider
    plates and the pad as one body would about a corner on S1, 0 if neither
    (the restoring moment of the weights holds)."""
    return rocking_in_field(par, phi, alpha, ag, par[I_G])


def rocking_in_field(par, phi, alpha, ag, gv):
    """``rocking_start`` in the vertical field gv = g + a_z: the weights'
    restoring moments scale with gv, so the threshold does."""
    return rocking_loaded(par, phi, alpha, ag, gv, 0.0)


def rocking_loaded(par, phi, alpha, ag, gv, dn):
    """``rocking_in_field`` with a vertical force dn (N, down) on the
    superstructure besides its weight (the test machine's axial load less M g),
    acting where the superstructure's weight does."""
    g = gv
    m_above = par[I_MSUP] + par[I_MS_UP]
    psi = phi + alpha
    c, s = math.cos(psi), math.sin(psi)
    a, ha = par[I_AP], 0.5 * par[I_HP]
    for k in range(2):
        sg = 1.0 - 2.0 * k
        # pad pivot (-sg a, eta_b), top corner (sg a, eta_t), centroid (0, h_p / 2)
        mo = _moment(c, s, sg * a, ha - par[I_EPB], par[I_MPAD], ag, g) \
            + _moment(c, s, 2.0 * sg * a, par[I_EPT] - par[I_EPB], m_above, ag, g) \
            + _moment(c, s, 2.0 * sg * a, par[I_EPT] - par[I_EPB], dn, 0.0, 1.0)
        if sg * mo > 0.0:
            return 1
    c, s = math.cos(phi), math.sin(phi)
    a = par[I_AS]
    dl = par[I_LI] * math.sin(alpha)
    c4z = par[I_TL] + par[I_R2] - par[I_LI] * math.cos(alpha) - par[I_L4]
    zb = par[I_ESB]
    bp = par[I_B_PAD]
    for k in range(2):
        sg = 1.0 - 2.0 * k
        x0 = -sg * a           # the pivot
        mo = _moment(c, s, -x0, 0.5 * par[I_TL] - zb, par[I_MS_LO], ag, g) \
            + _moment(c, s, bp * math.sin(alpha) - x0, par[I_TL] + par[I_R2] - bp * math.cos(alpha) - zb,
                      par[I_MPAD], ag, g) \
            + _moment(c, s, dl - x0, c4z + par[I_R4] - 0.5 * par[I_TU] - zb, par[I_MS_UP], ag, g) \
            + _moment(c, s, dl + sg * a - x0, c4z + par[I_SQ4] - zb, par[I_MSUP], ag, g) \
            + _moment(c, s, dl + sg * a - x0, c4z + par[I_SQ4] - zb, dn, 0.0, 1.0)
        if sg * mo > 0.0:
            return 2
    return 0


def two_phase_kinematics(par, S, ph0, al0, v00, v01, ag, gv, dn, out):
    """The paper's phases of the step just taken (two-phase model): the
    re-seating loss, the phase-1 pivots (pad: beta1, slider plates: gamma1)
    and the re-seating rotations of phases 2 and 3 (beta2 = dalpha - beta1,
    gamma2 = dphi - gamma1), the diagonals (0: the corner behind a positive
    slide, 1: on reversal) and the number of phases (0 stick, 2 one pair of
    surfaces (Fig. 6), 3 both (Fig. 7)); S[S_NPH] = -1 if a step that starts
    and ends at rest would start the pad or the stack rocking (Eq. 7)."""
    S[S_ERS] += out[O_RESEAT]
    dphi = out[O_DPHI]
    dal = out[O_DALPHA]
    b1 = pad_pivot(par, dal) if dal != 0.0 else 0.0
    g1 = stack_pivot(par, al0, dphi) if dphi != 0.0 else 0.0
    S[S_B1], S[S_B2] = b1, dal - b1
    S[S_G1], S[S_G2] = g1, dphi - g1
    if dal != 0.0:
        S[S_DP] = 0.0 if dal > 0.0 else 1.0
    if dphi != 0.0:
        S[S_DS] = 0.0 if dphi > 0.0 else 1.0
    if dal != 0.0 and dphi != 0.0:
        S[S_NPH] = 3.0            # Fig. 7: both pivots, the pad re-seats, then the slider plates
    elif dal != 0.0 or dphi != 0.0:
        S[S_NPH] = 2.0            # Fig. 6: one pivot, one re-seating
    else:
        S[S_NPH] = 0.0
    if S[S_NPH] == 0.0 and v00 == 0.0 and v01 == 0.0 and rocking_loaded(par, ph0, al0, ag, gv, dn) != 0:
        S[S_NPH] = -1.0


def holding_caps(par, slid_outer, slid_inner, mu1, mu2, mu3, mu4):
    """The coefficients of S1..S4's caps for a step: a coordinate that did not
    slide in the step before (slid_outer: the stack's, S1 and S4; slid_inner:
    the pad's, S2 and S3; 0.0 when it did not) holds its two surfaces with
    the holding coefficient (friction_kernel.holding_mu: the static one, par's
    I_MUS and I_MUR, 0 where none is given), a sliding one takes the sliding
    mu. The planar TFP's and the TFP's in both directions (docs/model.md 11)."""
    if slid_outer == 0.0:
        mu1 = holding_mu(mu1, par[I_MUS], par[I_MUR])
        mu4 = holding_mu(mu4, par[I_MUS + 3], par[I_MUR + 3])
    if slid_inner == 0.0:
        mu2 = holding_mu(mu2, par[I_MUS + 1], par[I_MUR + 1])
        mu3 = holding_mu(mu3, par[I_MUS + 2], par[I_MUR + 2])
    return mu1, mu2, mu3, mu4


def advance(par, S, dt, ag, az, mu1, mu2, mu3, mu4, machine, u1, ud1, out, M, w, tmp, sc):
    """One step of the stepper on its state vector S (layout S_*) under the
    step's mean ground accelerations ag (horizontal) and az (vertical, up; 0
    without a vertical record): every normal force, friction cap, rocking
    check and the discrete gradient of the heights see gv = g + az. Normal
    forces at the start of the step (weights, the ground's d'Alembert force,
    centripetal terms, the machine's force; without the generalised
    accelerations, see docs/model.md 6.2), caps, ``step``, the friction work of
    each surface (the arrest loss of a coordinate shared by its two surfaces as
    their caps), the force F, phase, regime, sliding flags and speeds.
    Returns the failure flag (FAIL_*)."""
    N = S[S_N:S_N + 4]
    dn = 0.0
    if par[I_VERT] == 2.0:
        # the test machine's axial-load programme: az carries the step's held load N
        dn = az - par[I_MSUP] * par[I_G]
        az = 0.0
    gv = par[I_G] + az
    S[S_AZ] = az
    normal_forces(par, S[0], S[1], S[2], S[3], 0.0, 0.0, ag, gv, S[S_F] if machine == 1 else 0.0, N)
    if dn != 0.0:
        top_load(par, S[0], S[1], dn, N)
    R1, R2, R3, R4 = par[I_R1], par[I_R2], par[I_R3], par[I_R4]
    # the caps: a coordinate at rest at the step's start, one that did not slide
    # in the step before (stuck or on its rim; the run's first step: the test
    # machine's launch speed u'(0) is given to a bearing at rest, which breaks
    # away), holds its surfaces with the holding coefficient
    # (friction_kernel.holding_mu; the sliding mu without a static one); one
    # that slides takes the sliding mu (docs/model.md section 11)
    mu1, mu2, mu3, mu4 = holding_caps(par, S[S_SLIDE], S[S_SLIDE + 1], mu1, mu2, mu3, mu4)
    a1 = mu1 * N[0] * R1
    a4 = mu4 * N[3] * R4
    a2 = mu2 * N[1] * R2
    a3 = mu3 * N[2] * R3
    c_o = a1 + a4
    c_i = a2 + a3
    ph0, al0, v00, v01 = S[0], S[1], S[2], S[3]
    step(par, S[0:4], dt, ag, gv, dn, c_o, c_i, machine, u1, ud1, out, M, w, tmp, sc)
    fail = int(out[O_FAIL])
    if fail == FAIL_CAPACITY:
        return fail
    if par[I_TWO] != 0.0:
        two_phase_kinematics(par, S, ph0, al0, v00, v01, ag, gv, dn, out)
        if fail == FAIL_NONE and S[S_NPH] < 0.0:
            return FAIL_ROCKING
    dphi = out[O_DPHI]
    dal = out[O_DALPHA]
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
    S[S_ERIM] += out[O_RIM]
    # a rim impact is an impulse: the superstructure's velocity jump there is
    # booked as one (N s) and kept out of the force, which stays the sliding
    # response's (an impulse / dt would grow as 1 / dt)
    S[S_J] = -par[I_MSUP] * out[O_DX_RIM]
    if par[I_KRIM] != 0.0:
        # a contact of a rim of finite stiffness: counted as the slide passes the capacity
        rim_passes(par, S[S_NHIT:S_NHIT + 4], ph0, al0, S[0], S[1])
    if out[O_HIT_O] != 0.0:
        tol = 1.0 - 1e-12
        qm = par[I_QMAX_PHI]
        if R1 * qm >= par[I_D1] * tol:
            S[S_NHIT] += out[O_HIT_O]
        if R4 * qm >= par[I_D4] * tol:
            S[S_NHIT + 3] += out[O_HIT_O]
    if out[O_HIT_I] != 0.0:
        tol = 1.0 - 1e-12
        qm = par[I_QMAX_ALPHA]
        if R2 * qm >= par[I_D2] * tol:
            S[S_NHIT + 1] += out[O_HIT_I]
        if R3 * qm >= par[I_D3] * tol:
            S[S_NHIT + 2] += out[O_HIT_I]
    if machine == 1:
        S[S_F] = out[O_F]
    else:
        # the bearing's horizontal force against u: minus the superstructure's inertia force
        A, Li = par[I_A], par[I_LI]
        x0 = (A * math.cos(ph0) + Li * math.cos(ph0 + al0)) * v00 + Li * math.cos(ph0 + al0) * v01
        x1 = (A * math.cos(S[0]) + Li * math.cos(S[0] + S[1])) * S[2] + Li * math.cos(S[0] + S[1]) * S[3]
        S[S_F] = -par[I_MSUP] * (ag + (x1 - out[O_DX_RIM] - x0) / dt)
    so = 1.0 if dphi != 0.0 else 0.0
    si = 1.0 if dal != 0.0 else 0.0
    S[S_SLIDE] = so
    S[S_SLIDE + 1] = si
    S[S_SLIDE + 2] = si
    S[S_SLIDE + 3] = so
    if so != 0.0 and si != 0.0:
        S[S_PHASE] = PHASE_BOTH
        S[S_REG] = 6.0
    elif so != 0.0:
        S[S_PHASE] = PHASE_OUTER
        S[S_REG] = 3.0
    elif si != 0.0:
        S[S_PHASE] = PHASE_INNER
        S[S_REG] = 5.0 if abs(S[0]) >= par[I_QMAX_PHI] * (1.0 - 1e-12) else 1.0
    else:
        S[S_PHASE] = PHASE_STICK
        S[S_REG] = 0.0
    S[S_SV] = R1 * abs(dphi) / dt
    S[S_SV + 1] = R2 * abs(dal) / dt
    S[S_SV + 2] = R3 * abs(dal) / dt
    S[S_SV + 3] = R4 * abs(dphi) / dt
    return fail


def row_values(par, S, t, xg, d1, d2, d3, d4, row):
    """The stepper's output columns (mechanics.tfp.COLUMNS) into row[0:N_ROW]."""
    phi, al = S[0], S[1]
    v1, v2 = S[2], S[3]
    A, Li = par[I_A], par[I_LI]
    R1, R2, R3, R4 = par[I_R1], par[I_R2], par[I_R3], par[I_R4]
    c = math.cos(phi + al)
    row[0] = t
    row[1] = xg
    row[2] = u_rel(par, phi, al)
    row[3] = (A * math.cos(phi) + Li * c) * v1 + Li * c * v2
    row[4] = S[S_F]
    row[5] = uplift(par, phi, al)
    row[6] = phi + al
    row[7] = R1 * phi
    row[8] = R2 * al
    row[9] = R3 * al
    row[10] = R4 * phi
    for i in range(4):
        row[11 + i] = S[S_N + i]
        row[15 + i] = S[S_W + i]
    row[19] = S[S_PHASE]
    row[20] = S[S_EIN]
    row[21] = kinetic(par, al, v1, v2)
    row[22] = potential(par, phi, al) + rim_energy(par, phi, al)
    row[23] = S[S_ERIM]
    row[24] = phi
    row[25] = al
    row[26] = S[S_REG]
    for i in range(4):
        row[27 + i] = S[S_SLIDE + i]
    tol = 1.0 - 1e-12
    row[31] = 1.0 if abs(R1 * phi) >= d1 * tol else 0.0
    row[32] = 1.0 if abs(R2 * al) >= d2 * tol else 0.0
    row[33] = 1.0 if abs(R3 * al) >= d3 * tol else 0.0
    row[34] = 1.0 if abs(R4 * phi) >= d4 * tol else 0.0
    row[35] = S[S_J]
    for i in range(4):
        row[36 + i] = S[S_NHIT + i]
    if par[I_TWO] != 0.0:
        row[40] = S[S_ERS]
        row[41] = S[S_B1]
        row[42] = S[S_B2]
        row[43] = S[S_G1]
        row[44] = S[S_G2]
        row[45] = S[S_DP]
        row[46] = S[S_DS]
        row[47] = S[S_NPH]
    if par[I_VERT] == 1.0:
        vertical_values(par, S, row, n_row(par) - N_ROW_VERT)


# -- lift-off and landing (docs/model.md 10) ---------------------------------------------------
def moving_mass(par):
    """The flying unit's mass: the superstructure, both slider plates and the pad."""
    return par[I_MSUP] + par[I_MS_LO] + par[I_MS_UP] + par[I_MPAD]


def seat_phi(par, alpha, u, phi):
    """The stack's tilt of the seated configuration with the pad's relative
    tilt alpha whose superstructure is at u (A sin phi + L_i sin(phi + alpha)
    = u; Newton from phi, the map increasing over the stack's reach)."""
    A, Li = par[I_A], par[I_LI]
    for _ in range(60):
        f = A * math.sin(phi) + Li * math.sin(phi + alpha) - u
        d = A * math.cos(phi) + Li * math.cos(phi + alpha)
        dp = f / d
        phi -= dp
        if abs(dp) <= 1e-16 * (1.0 + abs(phi)):
            break
    return phi


def flight_lift(par, S, x, z):
    """The height of the flying superstructure above the seat under it, after a
    flight of (x, z) from the take-off configuration held in S (phi, alpha)."""
    phi, al = S[0], S[1]
    u = u_rel(par, phi, al) + x
    ps = seat_phi(par, al, u, phi)
    return uplift(par, phi, al) + z - uplift(par, ps, al)


def unit_velocity(par, S):
    """The moving parts' momentum over their mass (x, up): body k at
    r_k = -a_k e(phi) - b_k e(psi), p = (P1 phi' cos phi + P2 psi' cos psi,
    P1 phi' sin phi + P2 psi' sin psi)."""
    phi, v1, ps, w = S[0], S[2], S[0] + S[1], S[2] + S[3]
    P1, P2, mt = par[I_P1], par[I_P2], moving_mass(par)
    return ((P1 * v1 * math.cos(phi) + P2 * w * math.cos(ps)) / mt,
            (P1 * v1 * math.sin(phi) + P2 * w * math.sin(ps)) / mt)


def _takeoff(par, S):
    """The unit leaves with the moving parts' momentum over their mass: the
    bodies' motion relative to each other (the rates of phi and alpha, the
    turning) is stopped by an internal plastic impulse, its energy to E_land."""
    vx, vz = unit_velocity(par, S)
    S[S_ELAND] += kinetic(par, S[1], S[2], S[3]) - 0.5 * moving_mass(par) * (vx * vx + vz * vz)
    S[2] = S[3] = S[S_XF] = S[S_ZF] = 0.0
    S[S_FLY] = 1.0
    S[S_VXF], S[S_VZF] = vx, vz
    S[S_NLIFT] += 1.0


def _land(par, S, M):
    """The landing: the seated configuration under the unit (the pad's tilt
    alpha kept, phi from the flown position) and a plastic impact, the flight
    velocity projected onto the seated motions in the kinetic-energy metric
    (M q' = the generalised momentum of the unit's translation). The energy
    before (kinetic and potential) minus the seated state's after goes to
    E_land. Returns 0, or FAIL_LAND past the outer surfaces' reach."""
    phi, al = S[0], S[1]
    mt = moving_mass(par)
    vx, vz = S[S_VXF], S[S_VZF]
    ps = seat_phi(par, al, u_rel(par, phi, al) + S[S_XF], phi)
    if par[I_KRIM] == 0.0 and abs(ps) > par[I_QMAX_PHI]:
        return FAIL_LAND
    e0 = 0.5 * mt * (vx * vx + vz * vz) + potential(par, phi, al) + mt * par[I_G] * S[S_ZF]
    P1, P2 = par[I_P1], par[I_P2]
    sp = ps + al
    pa = P2 * (vx * math.cos(sp) + vz * math.sin(sp))
    pp = P1 * (vx * math.cos(ps) + vz * math.sin(ps)) + pa
    mass_matrix(par, al, M)
    S[0] = ps
    solve2(M[0], M[1], M[2], pp, pa, S[2:4])
    S[S_ELAND] += e0 - (kinetic(par, al, S[2], S[3]) + potential(par, ps, al))
    S[S_FLY] = S[S_XF] = S[S_ZF] = S[S_VXF] = S[S_VZF] = 0.0
    # the stack and the pad land moving: both pairs of surfaces slide at the next step's start
    S[S_SLIDE] = S[S_SLIDE + 3] = 1.0 if S[2] != 0.0 else 0.0
    S[S_SLIDE + 1] = S[S_SLIDE + 2] = 1.0 if S[3] != 0.0 else 0.0
    return FAIL_NONE


def flight_rim_energy(par, S, x):
    """The rim springs' energy in flight after the flown displacement x: that
    of the configuration the unit would seat in under it (the pad's tilt held,
    the stack's from seat_phi), the seated one at the take-off and at the
    landing (docs/model.md 10)."""
    phi, al = S[0], S[1]
    return rim_energy(par, seat_phi(par, al, u_rel(par, phi, al) + x, phi), al)


def flight_springs(par, S, x0, vx, ag, h):
    """The rim springs' energy at x0 when rims of finite stiffness act on the
    flight from x0 over h (their energy non-zero at x0 or at the ballistic
    end), else -1.0 (the flight is ballistic)."""
    if par[I_KRIM] == 0.0:
        return -1.0
    e0 = flight_rim_energy(par, S, x0)
    if e0 > 0.0 or flight_rim_energy(par, S, x0 + vx * h - 0.5 * ag * h * h) > 0.0:
        return e0
    return -1.0


def flight_x(par, S, x0, e0, vx, ag, h):
    """The flown horizontal displacement and velocity after h from (x0, vx)
    under the field -ag and the rim springs, by their discrete gradient:
    M (v1 - v0) = -M ag h - h (E(x1) - E(x0)) / (x1 - x0), x1 - x0 = h (v0 +
    v1) / 2 with E = flight_rim_energy, so that the unit's kinetic energy and
    E change by the ground's work -M ag (x1 - x0) exactly. x1 is the root of
    that residual, increasing in x1 (E convex along the flight), bracketed
    from the ballistic end and bisected to adjacent floats. e0: E(x0)."""
    mt = moving_mass(par)

    def residual(x1):
        d = x1 - x0
        if d == 0.0:
            g = 0.0
        else:
            g = (flight_rim_energy(par, S, x1) - e0) / d
        return mt * (2.0 * d / h - 2.0 * vx) + mt * ag * h + h * g

    xb = x0 + vx * h - 0.5 * ag * h * h
    fb = residual(xb)
    if fb == 0.0:
        return xb, 2.0 * (xb - x0) / h - vx
    step = abs(xb - x0) + 1e-9
    lo = hi = xb
    for _ in range(200):                     # the bracket: grown by twos away from the residual's sign
        if fb > 0.0:
            lo = lo - step
            if residual(lo) <= 0.0:
                break
            hi = lo + step
        else:
            hi = hi + step
            if residual(hi) >= 0.0:
                break
            lo = hi - step
        step *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if not (lo < mid < hi):
            break
        if residual(mid) > 0.0:
            hi = mid
        else:
            lo = mid
    x1 = lo if abs(residual(lo)) <= abs(residual(hi)) else hi
    return x1, 2.0 * (x1 - x0) / h - vx


def _flown(par, S, x0, vx, ag, t, e0):
    """The flown horizontal displacement after t (the ballistic one when the
    springs do not act, e0 < 0; else their energy at x0: flight_springs)."""
    if e0 >= 0.0:
        return flight_x(par, S, x0, e0, vx, ag, t)[0]
    return x0 + vx * t - 0.5 * ag * t * t


def _flight(par, S, ag, gv, h, M):
    """The flight of the unit for at most h under the step's field (x'' =
    -ag, z'' = -gv relative to the ground): ballistic, exact for the
    step-constant field, but for the horizontal push of rims of finite
    stiffness (flight_x); the work of the ground's d'Alembert force through
    the unit's displacement is input. Takes off first when seated (only when
    the path stays above the seat to h: else returns -1, nothing changed).
    Lands at the first time the height meets the seat (bisection to
    round-off). Returns the time flown (h, or the landing time; -2.0 - fail
    when the landing is not modelled)."""
    az = gv - par[I_G]
    if S[S_FLY] == 0.0:
        # the take-off: the path from the seat (x0 = z0 = 0) stays above it to h
        vx, vz = unit_velocity(par, S)
        sp = flight_springs(par, S, 0.0, vx, ag, h)
        if not flight_lift(par, S, _flown(par, S, 0.0, vx, ag, h, sp), vz * h - 0.5 * gv * h * h) > 0.0:
            return -1.0
        _takeoff(par, S)
        aloft = True
    else:
        sp = flight_springs(par, S, S[S_XF], S[S_VXF], ag, h)
        aloft = flight_lift(par, S, _flown(par, S, S[S_XF], S[S_VXF], ag, h, sp),
                            S[S_ZF] + S[S_VZF] * h - 0.5 * gv * h * h) > 0.0
    x0, z0, vx, vz = S[S_XF], S[S_ZF], S[S_VXF], S[S_VZF]
    tau = h
    landed = False
    if not aloft:
        lo, hi = 0.0, h
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if not (lo < mid < hi):
                break
            if flight_lift(par, S, _flown(par, S, x0, vx, ag, mid, sp), z0 + vz * mid - 0.5 * gv * mid * mid) > 0.0:
                lo = mid
            else:
                hi = mid
        tau = hi
        landed = True
    if sp >= 0.0:
        x1, v1 = flight_x(par, S, x0, sp, vx, ag, tau)
        dx = x1 - x0
        S[S_XF] = x1
        S[S_VXF] = v1
    else:
        dx = vx * tau - 0.5 * ag * tau * tau
        S[S_XF] = x0 + dx
        S[S_VXF] = vx - ag * tau
    dz = vz * tau - 0.5 * gv * tau * tau
    S[S_ZF] = z0 + dz
    S[S_VZF] = vz - gv * tau
    S[S_EIN] += -moving_mass(par) * (ag * dx + az * dz)
    S[S_TFLY] += tau
    if landed:
        fail = _land(par, S, M)
        if fail != FAIL_NONE:
            return -2.0 - fail
    return tau


def advance_vertical(par, S, dt, ag, az, mu1, mu2, mu3, mu4, machine, u1, ud1, out, M, w, tmp, sc):
    """``advance`` under a vertical ground motion that may lift the TFP off
    (docs/model.md 10): while g + az >= 0 and the unit is seated, ``advance``
    itself. When the step's g + az < 0 the stack and the superstructure leave
    the lower plate and fly (``_flight``) until they land; a step that lands
    finishes seated (``advance`` over the rest, its force spread over dt).
    In the air: no contact, no friction, no heat, no force on the ground."""
    gv = par[I_G] + az
    if S[S_FLY] == 0.0 and not gv < 0.0:
        return advance(par, S, dt, ag, az, mu1, mu2, mu3, mu4, machine, u1, ud1, out, M, w, tmp, sc)
    S[S_AZ] = az
    rem = dt
    flown = False
    for _ in range(FLIGHTS_MAX):
        if S[S_FLY] == 0.0 and not gv < 0.0:
            break
        tau = _flight(par, S, ag, gv, rem, M)
        if tau <= -2.0:
            return int(-2.0 - tau)
        if tau < 0.0:              # the seat's curvature keeps it down over the step: seated
            break
        flown = True
        rem = rem - tau
        if S[S_FLY] != 0.0 or not rem > FLIGHT_REST * dt:
            break
    if not flown:
        return advance(par, S, dt, ag, az, mu1, mu2, mu3, mu4, machine, u1, ud1, out, M, w, tmp, sc)
    if S[S_FLY] == 0.0 and rem > FLIGHT_REST * dt:
        fail = advance(par, S, rem, ag, az, mu1, mu2, mu3, mu4, machine, u1, ud1, out, M, w, tmp, sc)
        # the force over the whole step: the bearing carries nothing in the air
        S[S_F] = S[S_F] * (rem / dt)
        for i in range(4):
            S[S_SV + i] = S[S_SV + i] * (rem / dt)
        return fail
    for i in range(4):
        S[S_N + i] = S[S_SV + i] = S[S_DW + i] = S[S_SLIDE + i] = 0.0
    S[S_F] = S[S_J] = S[S_REG] = 0.0
    S[S_B1] = S[S_B2] = S[S_G1] = S[S_G2] = S[S_NPH] = 0.0     # two-phase: no phases in the air
    S[S_PHASE] = PHASE_STICK
    return FAIL_NONE


def energies_vertical(par, S, o):
    """(E_kin, E_pot) into o[0:2], in flight too: the unit's (M + m) |V|^2 / 2
    and the take-off configuration's potential + (M + m) g z_f."""
    if S[S_FLY] != 0.0:
        mt = moving_mass(par)
        o[0] = 0.5 * mt * (S[S_VXF] * S[S_VXF] + S[S_VZF] * S[S_VZF])
        o[1] = potential(par, S[0], S[1]) + mt * par[I_G] * S[S_ZF]
        if par[I_KRIM] != 0.0:
            o[1] += flight_rim_energy(par, S, S[S_XF])
    else:
        o[0] = kinetic(par, S[1], S[2], S[3])
        o[1] = potential(par, S[0], S[1])
        o[1] += rim_energy(par, S[0], S[1])


def vertical_values(par, S, row, j):
    """The vertical ground motion's columns (mechanics.tfp.VERTICAL_COLUMNS)
    into row[j:j+5]; in flight the superstructure's position, velocity,
    uplift and the energies follow the unit (the tilt, slide and footprint
    columns keep the take-off's)."""
    row[j] = S[S_AZ]
    row[j + 1] = 0.0
    if S[S_FLY] != 0.0:
        row[2] += S[S_XF]
        row[3] = S[S_VXF]
        row[5] += S[S_ZF]
        energies_vertical(par, S, row[21:23])     # E_kin_J, E_pot_J of the flying unit
        row[j + 1] = flight_lift(par, S, S[S_XF], S[S_ZF])
    row[j + 2] = S[S_NLIFT]
    row[j + 3] = S[S_TFLY]
    row[j + 4] = S[S_ELAND]
