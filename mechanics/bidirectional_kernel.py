"""Bidirectional DFP steppers, one source for the pure and the compiled path (model.md 8).

Kernel module (fpd/kernels.py): plain functions over floats and float64
arrays (or lists on the pure path); ``fpd.kernels.compiled(__name__)`` gives
the same functions compiled by numba. Errors are returned as flags.

State: the unit vector n from the centre C1 of the lower sphere to the centre
C2 of the upper one (the pad axis, pointing down), n = (sin th cos phi,
sin th sin phi, -cos th), and its rate w = dn/dt (tangent to the unit
sphere). The superstructure's displacement relative to the ground is
u = L (n_x, n_y); its uplift L (1 + n_z). Everything is written in Cartesian
components, so nothing is singular at theta = 0 (the planar model is the
special case n_y = w_y = 0, with n_x = sin(theta), w = theta' (cos, 0, sin)).

A step of either scheme (``C[C_MID]``):

- stick trial: Moreau step on the sphere. The d'Alembert and gravity terms
  are the discrete gradient of the potential V(n) = f . n, f = S (a_x, a_y, g),
  along the great circle of the step's increment (exact work along it); the
  friction impulse is capped by the disk of radius h (mu1 N1 R1 + mu2 N2 R2)/I
  (radial return of the free trial velocity onto that disk);
- when the trial fails the device slides in the plane pi through C1, C2 and
  the increment: phase 1 moves the superstructure by L |d| along the tangent,
  the pad pivots on its trailing rim point by beta1 (the planar
  corner_pivot_rotation, made in pi); phase 2 re-seats in pi, so the axis
  turns by atan(|d|) about the normal of pi;
- an arrest inside the step (the velocity brought to zero by friction) splits
  the step there, as the planar stepper does, when the motion stays on a line
  (in 2D the velocity turns instead: the radial return takes the step).

"start" (the paper's section 3, C[C_MID] = 0): N frozen at t_n, friction along
the end velocity (radial return), the velocity projected onto the seated
tangent after every slip step (the kinetic energy removed is E_reseat). With a
zero y component it is the planar TwoPhaseStepper, to round-off.

"midpoint" (C[C_MID] = 1): N at the step midpoint (position and velocity),
friction along the mid-step velocity (the increment), no projection: the
velocity is carried along the great circle (the perpendicular component
unchanged). Second order in smooth sliding (with sub-steps at events where
the velocity passes near zero). Projections are kept for real landings from
rocking: a stuck pad that tips (Eq. 7) rocks in the plane of the trial on
its trailing rim point, and its landing is an impact (both schemes).

Lift-off (model.md 10): when the step's g + a_z < 0 the moving unit
(superstructure, upper plate and pad) leaves the lower plate and flies
ballistically relative to the ground (-(a_x, a_y, g + a_z), exact per step),
the take-off configuration held as its reference; it lands on the seat under
its flown position with a plastic impact (E_land; past the rim on the rim,
E_rim) and the rest of the step is seated.
docs/bidirectional.md has the derivations and the measured numbers.
"""
import math

from fpd.tribology import rim_law as rl
from fpd.tribology.friction_kernel import dwell_advance, holding_mu_dwell
from .two_phase_kernel import _sinc as sinc, pivot_angle, rocking_increment   # the planar stepper's, one source

__kernel__ = True

# -- constants array C ---------------------------------------------------------
C_L, C_RHO, C_I, C_S, C_M, C_MP, C_J, C_G, C_R1, C_R2 = 0, 1, 2, 3, 4, 5, 6, 7, 8, 9
C_A, C_EB, C_ET, C_H, C_ITRANS, C_MID, C_XB, C_ZB = 10, 11, 12, 13, 14, 15, 16, 17
C_SEATED = 18           # 1: the seated model (no phase 2: the axis moves along the arc by |d|)
# the rocking chain of Eq. (7) (pivot A, top corner C) in the pad frame (xi along e, eta up):
# inertia about the pivot, arms of the pad centroid and of the top corner, contact normals
C_IP, C_RGX, C_RGZ, C_RQX, C_RQZ = 19, 20, 21, 22, 23
C_N1X, C_N1Z, C_N2X, C_N2Z = 24, 25, 26, 27
# the columns written by values(): PLANAR_NONE the bidirectional ones (COLUMNS), a motion
# in the x-z plane (y absent): PLANAR_TWO_PHASE / PLANAR_SEATED the planar steppers' ones
C_PLANAR = 28
# the rim (docs/model.md 9): the axis's largest tilt, min(d1 / R1, d2 / R2) (0: no rim), the
# restitution of an impact, and which surfaces bound it (1.0 each: the limiting one, or both)
C_THMAX, C_REST, C_RIM1, C_RIM2 = 29, 30, 31, 32
# 1: the loading has a vertical component (the column az_mps2 follows the others)
C_VERT = 33
# the orbit machine's vertical actuator in force control (1.0; 0: the superstructure rides on
# the bearing): the load N(t) per grid point over M in the programme's GV, the superstructure
# without inertia (C_I without M L^2), the moving parts' inertial first moment S - M L
C_AXIAL, C_SIN = 34, 35
# the static (breakaway) coefficients of the lower and upper surface (0: none): a stuck
# pad holds until its drive exceeds the cap with them (friction_kernel.holding_mu)
C_MUS1, C_MUS2 = 36, 37
# the static coefficients as ratios to the sliding mu at rest (0: none)
C_MUR1, C_MUR2 = 38, 39
# a rim of finite stiffness (docs/model.md 9): k sum R_i^2 over the surfaces that bound the tilt
# (N m / rad^2), the axis's moment k R_i^2 (theta - thmax) beyond it; 0: the rigid rim
C_KRIM = 40
# the dwell law of the static coefficients (friction_kernel.dwell_mu): mu_s after a long dwell,
# the time constant (0: none), the exponent, lower and upper; the orbit machine's programme step
C_MUI1, C_MUI2, C_TAU1, C_TAU2, C_EXP1, C_EXP2, C_DT = 41, 42, 43, 44, 45, 46, 47
# the orbit machine's compliant link (docs/model.md 11.3): the spring (0: a rigid machine),
# the plate's mass, sub-steps per step
C_LINK, C_MPL, C_NSUB = 48, 49, 50
# the rim's dashpot (docs/model.md 9): 2 zeta sqrt(C_KRIM I), the generalised damping
# (N m s / rad^2) opposing the tilt's rate while the axis is beyond the capacity; 0: none
C_CRIM = 51
N_C = 52
PLANAR_NONE, PLANAR_TWO_PHASE, PLANAR_SEATED = 0.0, 1.0, 2.0

# -- state array S -------------------------------------------------------------
S_NX, S_NY, S_NZ, S_WX, S_WY, S_WZ = 0, 1, 2, 3, 4, 5
S_W1, S_W2, S_EIN, S_ERES, S_N1, S_N2 = 6, 7, 8, 9, 10, 11
S_FX, S_FY, S_FF1, S_FF2, S_SLIP1, S_SLIP2 = 12, 13, 14, 15, 16, 17
S_DS1, S_DS2, S_BETA1, S_BETA2, S_TILT, S_MODE = 18, 19, 20, 21, 22, 23
S_SV1, S_SV2, S_DPHI = 24, 25, 26
# rocking: flag, angle and rate about the pivot, the plane's tangent e; within a step:
# no rocking after a landing, the landing flag and the phase-1 angle at the landing
S_ROCK, S_BETA, S_BETAD, S_EX, S_EY, S_EZ, S_NOROCK, S_LANDED, S_BLAND = 27, 28, 29, 30, 31, 32, 33, 34, 35
S_DIRX = 36            # x component of the direction of the last slide (the planar columns' sign)
# the rim: kinetic and potential energy taken by impacts and contact (J), the impulse of
# the step's impact (N s), the impacts' count, at the rim at the end of the last step
S_ERIM, S_JRIM, S_NRIM, S_ATRIM = 37, 38, 39, 40
S_AZ = 41              # the vertical ground acceleration of the last step (m/s2, up)
# lift-off (model.md 10): in flight (1.0), the moving assembly's height above its seated
# position and its rate (relative to the ground), the landings' loss (J), the lift-offs'
# count, the time spent in flight (s)
S_FLY, S_ZF, S_ZFD, S_ELAND, S_NLIFT, S_TFLY = 42, 43, 44, 45, 46, 47
# in flight: the flying unit's horizontal displacement since take-off and its horizontal
# velocity (relative to the ground; S_ZF, S_ZFD its vertical ones)
S_XF, S_YF, S_VXF, S_VYF = 48, 49, 50, 51
# the lower and upper surface's dwell time (s stuck; friction_kernel.dwell_advance)
S_DW1, S_DW2 = 52, 53
N_S = 54

STICK, SLIP, TILT = 0, 1, 2
FLAG_OK, FLAG_ROCKING, FLAG_OVERTURN = 0, 1, 2

FIXED_POINT_TOL = 1e-15
FIXED_POINT_ITERS = 50
# a landing this close to the step's end (relative to h) ends the step: no seated remainder
FLIGHT_REST = 1e-12
# flights (take-off, landing, take-off ...) at most within one step; then the rest is seated
FLIGHTS_MAX = 4




def hypot(x, y):
    """sqrt(x^2 + y^2), the same bits on both paths (CPython's math.hypot and
    the C library's, which numba calls, may differ in the last bit)."""
    return math.sqrt(x * x + y * y)


def corner_pivot_rotation(a, eta_bottom, eta_top, h, R2, shift):
    """Phase-1 rotation of the pad about its trailing rim point, in the plane
    pi, for a shift L |d| >= 0 of C2 along the tangent (the planar formula of
    mechanics.two_phase.corner_pivot_rotation, which docs/two_phase.md derives)."""
    e = abs(shift)
    px, pz = -a - e, eta_bottom - h + R2
    rx, rz = 2.0 * a, eta_top - eta_bottom
    return pivot_angle(px, pz, rx, rz, a * e - 0.5 * e * e)


def tangent_basis(nx, ny, nz):
    """Orthonormal tangent vectors (t1, t2) at n: the horizontal unit vectors
    x, y turned by the rotation taking the centred axis (0, 0, -1) onto n
    (regular for every n with n_z < 1, i.e. all seated states)."""
    k = 1.0 / (1.0 - nz)
    return (1.0 - nx * nx * k, -nx * ny * k, nx), (-nx * ny * k, 1.0 - ny * ny * k, ny)


def normal_forces(C, nx, ny, nz, wx, wy, wz, ax, ay, gv):
    """Seated normal forces (N1, N2) at axis n, axis rate w, ground acceleration
    (ax, ay) and vertical field gv = g + a_z: model.md 2 with the axial
    component of gravity and of the d'Alembert force, g_axis = -(a . n_h +
    gv n_z), and the centripetal terms
    of the superstructure (radius L) and pad centroid (radius rho). Clipped at
    zero (no tension across a contact)."""
    g_axis = -(ax * nx + ay * ny + gv * nz)
    w2 = wx * wx + wy * wy + wz * wz
    N2 = C[C_M] * (g_axis + C[C_L] * w2)
    N1 = N2 + C[C_MP] * (g_axis + C[C_RHO] * w2)
    if N2 < 0.0:
        N2 = 0.0
        if N1 < 0.0:
            N1 = 0.0
    elif N1 < 0.0:
        N1 = 0.0
    return N1, N2


def drive_along(C, nx, ny, nz, ex, ey, ez, d, ax, ay, gv):
    """Tangential driving force (generalised, per unit I times I) of gravity
    and the ground's d'Alembert force for an increment of angle d along the
    unit tangent e: the discrete gradient of V = f . n, f = S (ax, ay, gv), on
    the great circle through n along e (its work over the increment is exactly
    V(start) - V(end)); the component normal to the plane pi is the exact
    -f . b (constant along the arc). Returns the 3-vector."""
    S = C[C_S]
    fx, fy, fz = S * ax, S * ay, S * gv
    bx, by, bz = ny * ez - nz * ey, nz * ex - nx * ez, nx * ey - ny * ex
    fn = fx * nx + fy * ny + fz * nz
    fe = fx * ex + fy * ey + fz * ez
    fb = fx * bx + fy * by + fz * bz
    half = 0.5 * d
    De = sinc(half) * (fn * math.sin(half) - fe * math.cos(half))
    if C[C_KRIM] != 0.0:
        # the rim's spring beyond the capacity: along e its discrete gradient on the
        # arc (work exactly V_rim(start) - V_rim(end)), across it the gradient at mid-arc
        ke, kb = _rim_spring_drive(C, nx, ny, nz, ex, ey, ez, bx, by, bz, d)
        De += ke
        fb -= kb
    return De * ex - fb * bx, De * ey - fb * by, De * ez - fb * bz


def rim_overlap(C, nx, ny, nz):
    """The axis's tilt beyond the rim, (theta - thmax)_+ (rad)."""
    return rl.overlap(math.atan2(hypot(nx, ny), -nz) - C[C_THMAX])


def rim_spring_energy(C, nx, ny, nz):
    """Energy stored in the rim of finite stiffness, C_KRIM (theta - thmax)_+^2 / 2."""
    return rl.spring_energy(C[C_KRIM], rim_overlap(C, nx, ny, nz))


def _rim_spring_drive(C, nx, ny, nz, ex, ey, ez, bx, by, bz, d):
    """The rim spring's generalised force along e (the discrete gradient over
    the arc of angle d from n, -(V(end) - V(start)) / d; the derivative when
    d = 0) and across it (its component on b at mid-arc, the exact moment
    -k o m . b with m the outward meridian)."""
    k = C[C_KRIM]
    if abs(d) > 1e-12:
        c, s = math.cos(d), math.sin(d)
        v0 = rim_spring_energy(C, nx, ny, nz)
        v1 = rim_spring_energy(C, c * nx + s * ex, c * ny + s * ey, c * nz + s * ez)
        ke = rl.secant(v0, v1, d)
    else:
        o = rim_overlap(C, nx, ny, nz)
        ke = 0.0
        if o > 0.0:
            r = hypot(nx, ny)
            ke = -k * o * ((ex * nx + ey * ny) * (-nz) / r + ez * r)
    q = 0.5 * d
    c, s = math.cos(q), math.sin(q)
    mx, my, mz = c * nx + s * ex, c * ny + s * ey, c * nz + s * ez
    o = rim_overlap(C, mx, my, mz)
    kb = 0.0
    if o > 0.0:
        r = hypot(mx, my)
        kb = -k * o * ((bx * mx + by * my) * (-mz) / r + bz * r)
    return ke, kb


def _tilt_beyond(C, nx, ny, nz):
    """The axis's tilt minus the rim's, theta - thmax (rad, signed)."""
    return math.atan2(hypot(nx, ny), -nz) - C[C_THMAX]


def rim_damper(C, nx, ny, nz, ex, ey, ez, d, h):
    """The rim's dashpot over an increment of angle d >= 0 along the unit
    tangent e from n, travelled in the time h: the generalised force
    -c f r m, with c = C[C_CRIM], r = (m . t) d / h the tilt's rate at
    mid-arc (m the outward meridian there, t the arc's tangent), and f the
    share of the arc beyond the capacity (the tilt taken linear along it).
    Returns (qx, qy, qz, loss): the force as a vector at n (its component
    along e the work-conjugate one, -c f (m . t)^2 d / h; across, on b =
    n x e, constant along the arc, -c f (m . t)(m . b) d / h) and the energy
    it takes over the increment, c f (m . t)^2 d^2 / h >= 0."""
    if not (d > 0.0 and h > 0.0):
        return 0.0, 0.0, 0.0, 0.0
    c1, s1 = math.cos(d), math.sin(d)
    t0 = _tilt_beyond(C, nx, ny, nz)
    t1 = _tilt_beyond(C, c1 * nx + s1 * ex, c1 * ny + s1 * ey, c1 * nz + s1 * ez)
    f = rl.share_beyond(t0, t1)
    if f == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    q = 0.5 * d
    c, s = math.cos(q), math.sin(q)
    px, py, pz = c * nx + s * ex, c * ny + s * ey, c * nz + s * ez
    tx, ty, tz = -s * nx + c * ex, -s * ny + c * ey, -s * nz + c * ez
    r = hypot(px, py)
    if r == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    mx, my, mz = -pz * px / r, -pz * py / r, r
    bx, by, bz = ny * ez - nz * ey, nz * ex - nx * ez, nx * ey - ny * ex
    me = mx * tx + my * ty + mz * tz
    mb = mx * bx + my * by + mz * bz
    k = C[C_CRIM] * f * me * d / h
    fe, fb = -k * me, -k * mb
    return fe * ex + fb * bx, fe * ey + fb * by, fe * ez + fb * bz, -fe * d


def _free_direction(C, nx, ny, nz, ax, ay, gv):
    """Unit direction of the tangential drive at n (from rest), or (0, 0, 0)."""
    S = C[C_S]
    fx, fy, fz = S * ax, S * ay, S * gv
    fn = fx * nx + fy * ny + fz * nz
    dx, dy, dz = -(fx - fn * nx), -(fy - fn * ny), -(fz - fn * nz)
    m = math.sqrt(dx * dx + dy * dy + dz * dz)
    if m == 0.0:
        return 0.0, 0.0, 0.0
    return dx / m, dy / m, dz / m


def rocking_starts(C, nx, ny, nz, ex, ey, ez, ax, ay, gv):
    """Rocking check of Eq. (7) in the plane pi through the axis and the unit
    tangent e: does the stuck pad, pivoting on its rim point trailing e (the
    planar A-C chain in pi), get a rotation acceleration opening the gap?
    Moments about the pivot of the field per unit mass F = -(ax, ay, gv) on the
    chain's first moments (Xb along e, Zb along the axis, up): Xb F_up - Zb F_e.
    Checked for e and -e (the B-D chain)."""
    F_e = -(ax * ex + ay * ey + gv * ez)
    F_up = ax * nx + ay * ny + gv * nz      # F . (-n)
    Xb, Zb = C[C_XB], C[C_ZB]
    return Xb * F_up - Zb * F_e > 0.0 or Xb * F_up + Zb * F_e > 0.0


def _arrest(C, nx, ny, nz, wx, wy, wz, ax, ay, gv, h, cap0, mu1, mu2):
    """Time tau in (0, h] at which friction at the cap, opposing the velocity
    w0 along its own direction, brings the rate to zero; the cap is frozen
    ("start") or at the sub-step's midpoint ("midpoint"). Returns
    (tau, d, ex, ey, ez, N1, N2, plane): d the angle travelled along e = w0 / |w0|;
    ``plane``: the drive has no component across the line of w0 (to 1e-9 of the
    forces at play), so the motion stays on that line and really passes through
    rest (the planar case; in 2D the velocity turns instead)."""
    I = C[C_I]
    w = math.sqrt(wx * wx + wy * wy + wz * wz)
    ex, ey, ez = wx / w, wy / w, wz / w
    mid = C[C_MID] != 0.0
    cap = cap0
    N1 = N2 = 0.0
    tau = h
    plane = True
    for _ in range(FIXED_POINT_ITERS):
        d = 0.5 * tau * w
        if mid:
            q = 0.5 * d
            c, s = math.cos(q), math.sin(q)
            N1, N2 = normal_forces(C, c * nx + s * ex, c * ny + s * ey, c * nz + s * ez,
                                   0.5 * wx, 0.5 * wy, 0.5 * wz, ax, ay, gv)
            cap = mu1 * N1 * C[C_R1] + mu2 * N2 * C[C_R2]
        dx, dy, dz = drive_along(C, nx, ny, nz, ex, ey, ez, d, ax, ay, gv)
        if C[C_CRIM] != 0.0:
            qx, qy, qz, _loss = rim_damper(C, nx, ny, nz, ex, ey, ez, d, tau)
            dx, dy, dz = dx + qx, dy + qy, dz + qz
        De = dx * ex + dy * ey + dz * ez
        px, py, pz = dx - De * ex, dy - De * ey, dz - De * ez
        plane = math.sqrt(px * px + py * py + pz * pz) <= 1e-9 * (cap + abs(De))
        decel = De - cap
        tau_new = w * I / -decel if decel < 0.0 else h
        tau_new = min(max(tau_new, 0.0), h)
        if abs(tau_new - tau) <= 1e-15 * h:
            tau = tau_new
            break
        tau = tau_new
    return tau, 0.5 * tau * w, ex, ey, ez, N1, N2, plane


def _slide(C, S, d, ex, ey, ez, v1x, v1y, v1z, ax, ay, gv, f1, f2):
    """Phases 1 and 2 of a sliding (part-)step in the plane pi: C2 moved by
    L d along the unit tangent e at n_n with rate v1 (tangent at n_n) at the
    end; re-seat by the rotation atan(d) about the normal of pi; friction work
    f_i atan(d) per interface (the net slip, counted once); the velocity
    projected ("start") or carried along ("midpoint")."""
    nx, ny, nz = S[S_NX], S[S_NY], S[S_NZ]
    I = C[C_I]
    seated = C[C_SEATED] != 0.0
    if seated:
        S[S_BETA1] = 0.0
        dphi = d
    else:
        S[S_BETA1] = corner_pivot_rotation(C[C_A], C[C_EB], C[C_ET], C[C_H], C[C_R2], C[C_L] * d)
        dphi = math.atan(d)
    c, s = math.cos(dphi), math.sin(dphi)
    sh = math.sin(0.5 * dphi)
    k = -2.0 * sh * sh                       # cos(dphi) - 1, without cancellation
    dnx, dny, dnz = k * nx + s * ex, k * ny + s * ey, k * nz + s * ez
    n1x, n1y, n1z = nx + dnx, ny + dny, nz + dnz
    r = 1.0 / math.sqrt(n1x * n1x + n1y * n1y + n1z * n1z)
    n1x, n1y, n1z = n1x * r, n1y * r, n1z * r
    # the tangent e carried to n_n+1, and the normal b of pi (tangent at both ends)
    e1x, e1y, e1z = -s * nx + c * ex, -s * ny + c * ey, -s * nz + c * ez
    bx, by, bz = ny * ez - nz * ey, nz * ex - nx * ez, nx * ey - ny * ex
    ve = v1x * ex + v1y * ey + v1z * ez
    vb = v1x * bx + v1y * by + v1z * bz
    S[S_BETA2] = dphi - S[S_BETA1]
    S[S_TILT] = -S[S_BETA2]
    S[S_DPHI] += dphi
    if ex != 0.0:
        S[S_DIRX] = ex
    S[S_W1] += f1 * dphi
    S[S_W2] += f2 * dphi
    S[S_DS1] += C[C_R1] * dphi
    S[S_DS2] += C[C_R2] * dphi
    S[S_SLIP1] += C[C_R1] * dphi
    S[S_SLIP2] += C[C_R2] * dphi
    if C[C_MID] == 0.0 and not seated:
        # kinetic-energy metric: translations lose their component along C1C2
        # at n_n+1 (in pi), the pad spin is kept; the normal component is
        # tangent at both ends and is kept whole
        vp = ve * (C[C_ITRANS] * c + C[C_J]) / I
        S[S_ERES] += 0.5 * I * (ve * ve - vp * vp)
        ve = vp
    S[S_EIN] -= C[C_S] * (ax * dnx + ay * dny + (gv - C[C_G]) * dnz)
    S[S_NX], S[S_NY], S[S_NZ] = n1x, n1y, n1z
    wx, wy, wz = ve * e1x + vb * bx, ve * e1y + vb * by, ve * e1z + vb * bz
    # keep w tangent to round-off at the new axis
    wn = wx * n1x + wy * n1y + wz * n1z
    S[S_WX], S[S_WY], S[S_WZ] = wx - wn * n1x, wy - wn * n1y, wz - wn * n1z


def _trial(C, nx, ny, nz, w0x, w0y, w0z, ax, ay, gv, h, mu1, mu2, middir):
    """The stick trial's fixed point on the step increment D (a tangent
    vector at n): returns (v1, D, lam, N1, N2, cap, arrest, q), q the rim
    dashpot's force the last velocity took (its work q . D is the loss booked:
    exact whatever the fixed point's last change). ``middir``: friction
    along the mid-step velocity (the midpoint scheme while moving), else along
    the end velocity (radial return of the free trial velocity)."""
    I, R1, R2 = C[C_I], C[C_R1], C[C_R2]
    mid = C[C_MID] != 0.0
    N1, N2 = normal_forces(C, nx, ny, nz, w0x, w0y, w0z, ax, ay, gv)
    cap = mu1 * N1 * R1 + mu2 * N2 * R2
    hI = h / I
    Dx, Dy, Dz = h * w0x, h * w0y, h * w0z
    v1x, v1y, v1z = w0x, w0y, w0z
    lam = 0.0
    arrest = False
    qx = qy = qz = 0.0
    fx0, fy0, fz0 = _free_direction(C, nx, ny, nz, ax, ay, gv)
    for _ in range(FIXED_POINT_ITERS):
        d = math.sqrt(Dx * Dx + Dy * Dy + Dz * Dz)
        if d > 0.0:
            ex, ey, ez = Dx / d, Dy / d, Dz / d
        else:
            ex, ey, ez = fx0, fy0, fz0
            if ex == 0.0 and ey == 0.0 and ez == 0.0:
                t1, _t2 = tangent_basis(nx, ny, nz)
                ex, ey, ez = t1
        if mid:
            q = 0.5 * d
            c, s = math.cos(q), math.sin(q)
            N1, N2 = normal_forces(C, c * nx + s * ex, c * ny + s * ey, c * nz + s * ez,
                                   0.5 * (w0x + v1x), 0.5 * (w0y + v1y), 0.5 * (w0z + v1z), ax, ay, gv)
            cap = mu1 * N1 * R1 + mu2 * N2 * R2
        gx, gy, gz = drive_along(C, nx, ny, nz, ex, ey, ez, d, ax, ay, gv)
        if C[C_CRIM] != 0.0:
            qx, qy, qz, _loss = rim_damper(C, nx, ny, nz, ex, ey, ez, d, h)
            gx, gy, gz = gx + qx, gy + qy, gz + qz
        vfx, vfy, vfz = w0x + hI * gx, w0y + hI * gy, w0z + hI * gz
        if middir:
            # friction along the mid-step velocity x = w0 + v1: x + h cap x/|x| / I
            # = w0 + v_free, so x is the radial return of w0 + v_free onto the
            # disk (closed form, well posed whatever the angle between w0 and
            # the drive); |w0 + v_free| inside the disk: the velocity passes
            # through zero in the step (arrest)
            yx, yy, yz = w0x + vfx, w0y + vfy, w0z + vfz
            y = math.sqrt(yx * yx + yy * yy + yz * yz)
            if y <= hI * cap:
                arrest = True
                break
            r = 1.0 - hI * cap / y
            v1x, v1y, v1z = yx * r - w0x, yy * r - w0y, yz * r - w0z
            lam = 1.0
        else:
            # radial return of the free trial velocity onto the friction disk
            vf = math.sqrt(vfx * vfx + vfy * vfy + vfz * vfz)
            if vf <= hI * cap:
                v1x = v1y = v1z = 0.0
                lam = vf / (hI * cap) if cap > 0.0 else 0.0
            else:
                r = 1.0 - hI * cap / vf
                v1x, v1y, v1z = vfx * r, vfy * r, vfz * r
                lam = 1.0
        Nx, Ny, Nz = 0.5 * h * (w0x + v1x), 0.5 * h * (w0y + v1y), 0.5 * h * (w0z + v1z)
        if middir and Nx * w0x + Ny * w0y + Nz * w0z <= 0.0:
            arrest = True
            break
        ddx, ddy, ddz = Nx - Dx, Ny - Dy, Nz - Dz
        Dx, Dy, Dz = Nx, Ny, Nz
        if math.sqrt(ddx * ddx + ddy * ddy + ddz * ddz) <= FIXED_POINT_TOL:
            break
    return v1x, v1y, v1z, Dx, Dy, Dz, lam, N1, N2, cap, arrest, qx, qy, qz


def smallest_positive_root(c2, c1, c0, default):
    """Smallest positive root of c2 x^2 + c1 x + c0 (stable form), else default."""
    if c2 == 0.0:
        if c1 != 0.0 and -c0 / c1 > 0.0:
            return -c0 / c1
        return default
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return default
    q = -0.5 * (c1 + math.copysign(math.sqrt(disc), c1))
    r1 = q / c2
    r2 = c0 / q if q != 0.0 else -1.0
    best = default
    found = False
    for r in (r1, r2):
        if r > 0.0 and (not found or r < best):
            best = r
            found = True
    return best


def _plane_fields(C, S, ax, ay, gv):
    """Field per unit mass in the rocking plane (components along e and along
    the pad axis up, -n): the whole (gravity and ground, gv = g + a_z) and the
    ground's part (its work is input; gravity's is the potential)."""
    g = C[C_G]
    az = gv - g
    ex, ey, ez = S[S_EX], S[S_EY], S[S_EZ]
    nx, ny, nz = S[S_NX], S[S_NY], S[S_NZ]
    ge, gu = -(ax * ex + ay * ey + az * ez), ax * nx + ay * ny + az * nz
    return ge - g * ez, gu + g * nz, ge, gu


def _chain_forces(C, S, ax, ay, gv):
    """Normal forces of the rocking chain at the pivot (N1) and at the top
    corner (N2) from the accelerations of Eq. (7) and each body's momentum
    balance, in the plane (the planar _chain_normal_forces); Ff1, Ff2 the
    tangential forces the pinned joints carry. The field's component across
    the plane is taken by the pivot."""
    Fe, Fu, _ge, _gu = _plane_fields(C, S, ax, ay, gv)
    b, w = S[S_BETA], S[S_BETAD]
    c, s = math.cos(b), math.sin(b)
    Xr, Zr = c * C[C_XB] - s * C[C_ZB], s * C[C_XB] + c * C[C_ZB]
    alpha = (Xr * Fu - Zr * Fe) / C[C_IP]
    rGe, rGu = c * C[C_RGX] - s * C[C_RGZ], s * C[C_RGX] + c * C[C_RGZ]
    rQe, rQu = c * C[C_RQX] - s * C[C_RQZ], s * C[C_RQX] + c * C[C_RQZ]
    w2 = w * w
    M, m = C[C_M], C[C_MP]
    FMe = M * (-Fe - alpha * rQu - w2 * rQe)
    FMu = M * (-Fu + alpha * rQe - w2 * rQu)
    FPe = FMe + m * (-Fe - alpha * rGu - w2 * rGe)
    FPu = FMu + m * (-Fu + alpha * rGe - w2 * rGu)
    S[S_N1] = FPe * C[C_N1X] + FPu * C[C_N1Z]
    S[S_N2] = FMe * C[C_N2X] + FMu * C[C_N2Z]
    S[S_FF1] = FPe * C[C_N1Z] - FPu * C[C_N1X]
    S[S_FF2] = FMe * C[C_N2Z] - FMu * C[C_N2X]


def _tilt(C, S, ax, ay, gv, h):
    """The rocking chain of Eq. (7) in its plane over a (part-)step of length
    h (the planar _tilt_step: discrete gradient, so the step's work equals the
    potential's change); on landing (beta back to 0) the impact projects the
    chain's velocity onto the seated tangent e (kinetic-energy metric, the
    loss in E_reseat) and the rest of the step is seated, without rocking.
    Returns (time used, flag)."""
    Fe, Fu, ge, gu = _plane_fields(C, S, ax, ay, gv)
    IP, Xb, Zb = C[C_IP], C[C_XB], C[C_ZB]
    b0, w0 = S[S_BETA], S[S_BETAD]
    db, w1 = rocking_increment(b0, w0, h, IP, Xb, Zb, Fe, Fu)
    b1 = b0 + db
    S[S_MODE] = TILT
    S[S_BETA2] = 0.0
    S[S_SV1] = S[S_SV2] = 0.0
    if b1 > 0.0:
        c1, s1 = math.cos(b1), math.sin(b1)
        g = C[C_G]
        # gravity's moment about the pivot no longer restoring: overturned
        if (c1 * Xb - s1 * Zb) * (g * S[S_NZ]) + (s1 * Xb + c1 * Zb) * (g * S[S_EZ]) >= 0.0:
            return h, FLAG_OVERTURN
        c0, s0 = math.cos(b0), math.sin(b0)
        S[S_EIN] += ge * ((c1 - c0) * Xb - (s1 - s0) * Zb) + gu * ((s1 - s0) * Xb + (c1 - c0) * Zb)
        S[S_BETA], S[S_BETAD] = b1, w1
        S[S_BETA1] = b1
        S[S_TILT] = b1
        _chain_forces(C, S, ax, ay, gv)
        return h, FLAG_OK
    # landing inside the step: the time from the same discrete gradient (end point 0 known)
    mid = 0.5 * b0
    c, s = math.cos(mid), math.sin(mid)
    torque = sinc(mid) * (-Fe * (s * Xb + c * Zb) + Fu * (c * Xb - s * Zb))
    tau = smallest_positive_root(0.5 * torque / IP, w0, b0, h)
    tau = min(max(tau, 0.0), h)
    w_land = w0 + tau * torque / IP
    c0, s0 = math.cos(b0), math.sin(b0)
    S[S_EIN] += ge * ((1.0 - c0) * Xb + s0 * Zb) + gu * (-s0 * Xb + (1.0 - c0) * Zb)
    # impact: the chain's velocities (pad spin, centroid, RB3+4 at the corner)
    # projected onto the seated tangent field (L e, rho e, spin 1)
    p = w_land * (C[C_M] * C[C_L] * -C[C_RQZ] + C[C_MP] * C[C_RHO] * -C[C_RGZ] + C[C_J])
    v_seat = p / C[C_I]
    S[S_ERES] += 0.5 * IP * w_land * w_land - 0.5 * C[C_I] * v_seat * v_seat
    S[S_ROCK], S[S_BETA], S[S_BETAD] = 0.0, 0.0, 0.0
    S[S_WX], S[S_WY], S[S_WZ] = v_seat * S[S_EX], v_seat * S[S_EY], v_seat * S[S_EZ]
    S[S_NOROCK] = 1.0
    S[S_LANDED] = 1.0
    S[S_BLAND] = S[S_BETA1]
    return tau, FLAG_OK


def momentum(C, S):
    """Horizontal momentum (M v_s + m v_G relative to the ground): S w_h seated;
    the chain's first moment turning about the pivot while rocking."""
    if S[S_ROCK] != 0.0:
        b, w = S[S_BETA], S[S_BETAD]
        c, s = math.cos(b), math.sin(b)
        Xr, Zr = c * C[C_XB] - s * C[C_ZB], s * C[C_XB] + c * C[C_ZB]
        return w * (-Zr * S[S_EX] - Xr * S[S_NX]), w * (-Zr * S[S_EY] - Xr * S[S_NY])
    return C[C_S] * S[S_WX], C[C_S] * S[S_WY]


def _part(C, S, ax, ay, gv, h, mu1, mu2):
    """One seated (part-)step of length h: stick trial, then slide or stick.
    Returns (time used, flag): less than h at an arrest inside the step."""
    if S[S_ROCK] != 0.0:
        return _tilt(C, S, ax, ay, gv, h)
    R1, R2 = C[C_R1], C[C_R2]
    mid = C[C_MID] != 0.0
    nx, ny, nz = S[S_NX], S[S_NY], S[S_NZ]
    w0x, w0y, w0z = S[S_WX], S[S_WY], S[S_WZ]
    moving = w0x != 0.0 or w0y != 0.0 or w0z != 0.0
    # the static caps, grown by the time stuck so far (friction_kernel.holding_mu_dwell)
    hm1 = holding_mu_dwell(mu1, C[C_MUS1], C[C_MUR1], C[C_MUI1], C[C_TAU1], C[C_EXP1], S[S_DW1])
    hm2 = holding_mu_dwell(mu2, C[C_MUS2], C[C_MUR2], C[C_MUI2], C[C_TAU2], C[C_EXP2], S[S_DW2])
    if not moving and (hm1 > mu1 or hm2 > mu2):
        # at rest: the stick trial with the static cap; a drive beyond it breaks
        # the pad away and the step slides with the sliding cap
        v1x, v1y, v1z, Dx, Dy, Dz, lam, N1, N2, cap, arrest, qx, qy, qz = _trial(
            C, nx, ny, nz, w0x, w0y, w0z, ax, ay, gv, h, hm1, hm2, False)
        if v1x == 0.0 and v1y == 0.0 and v1z == 0.0:
            mu1, mu2 = hm1, hm2
        else:
            v1x, v1y, v1z, Dx, Dy, Dz, lam, N1, N2, cap, arrest, qx, qy, qz = _trial(
                C, nx, ny, nz, w0x, w0y, w0z, ax, ay, gv, h, mu1, mu2, False)
    else:
        v1x, v1y, v1z, Dx, Dy, Dz, lam, N1, N2, cap, arrest, qx, qy, qz = _trial(
            C, nx, ny, nz, w0x, w0y, w0z, ax, ay, gv, h, mu1, mu2, mid and moving)
    if moving and (arrest or v1x * w0x + v1y * w0y + v1z * w0z <= 0.0):
        tau, d, ex, ey, ez, N1a, N2a, plane = _arrest(C, nx, ny, nz, w0x, w0y, w0z, ax, ay, gv, h, cap, mu1, mu2)
        if not plane or (mid and not tau < h):
            # the velocity turns in the plane (a drive across its line) rather
            # than passing through rest on it: no split (it would drop the
            # cross impulse); friction along the end velocity (radial return,
            # the Moreau step: it sticks exactly if the drive is inside the disk)
            if mid:
                v1x, v1y, v1z, Dx, Dy, Dz, lam, N1, N2, cap, arrest, qx, qy, qz = _trial(
                    C, nx, ny, nz, w0x, w0y, w0z, ax, ay, gv, h, mu1, mu2, False)
        else:
            if mid:
                N1, N2 = N1a, N2a
            S[S_N1], S[S_N2] = N1, N2
            f1, f2 = mu1 * N1 * R1, mu2 * N2 * R2
            S[S_FF1], S[S_FF2] = f1 / C[C_L], f2 / C[C_L]
            if C[C_CRIM] != 0.0:
                S[S_ERIM] += rim_damper(C, nx, ny, nz, ex, ey, ez, d, tau)[3]
            _slide(C, S, d, ex, ey, ez, 0.0, 0.0, 0.0, ax, ay, gv, f1, f2)
            S[S_MODE] = STICK
            S[S_SV1] = S[S_SV2] = 0.0
            S[S_DW1] = S[S_DW2] = 0.0           # arrested at tau: its dwell starts there
            return tau, FLAG_OK
    S[S_N1], S[S_N2] = N1, N2
    f1, f2 = mu1 * N1 * R1, mu2 * N2 * R2
    S[S_FF1], S[S_FF2] = lam * f1 / C[C_L], lam * f2 / C[C_L]
    if v1x == 0.0 and v1y == 0.0 and v1z == 0.0:
        # the joints hold at the end of the (part-)step
        if moving:                 # from a moving state (2D, no split): it slid by D first
            d = math.sqrt(Dx * Dx + Dy * Dy + Dz * Dz)
            if d > 0.0:
                S[S_ERIM] -= qx * Dx + qy * Dy + qz * Dz
                _slide(C, S, d, Dx / d, Dy / d, Dz / d, 0.0, 0.0, 0.0, ax, ay, gv, f1, f2)
            S[S_WX] = S[S_WY] = S[S_WZ] = 0.0
        S[S_MODE] = STICK
        S[S_SV1] = S[S_SV2] = 0.0
        dwell_advance(S, S_DW1, not moving, h)      # at rest all the part-step, or stopped at its end
        dwell_advance(S, S_DW2, not moving, h)
        if not moving:
            S[S_BETA1] = S[S_BETA2] = S[S_TILT] = 0.0
        if not moving and S[S_NOROCK] == 0.0:
            # the stuck pad's rocking check (from rest, as the planar stepper), in
            # the plane of the trial: the chain pivots on the rim point trailing e
            ex, ey, ez = _free_direction(C, nx, ny, nz, ax, ay, gv)
            if ex != 0.0 or ey != 0.0 or ez != 0.0:
                Fe = -(ax * ex + ay * ey + gv * ez)
                Fu = ax * nx + ay * ny + gv * nz
                sgn = 0.0
                if C[C_XB] * Fu - C[C_ZB] * Fe > 0.0:
                    sgn = 1.0
                elif C[C_XB] * Fu + C[C_ZB] * Fe > 0.0:
                    sgn = -1.0
                if sgn != 0.0:
                    S[S_ROCK], S[S_BETA], S[S_BETAD] = 1.0, 0.0, 0.0
                    S[S_EX], S[S_EY], S[S_EZ] = sgn * ex, sgn * ey, sgn * ez
                    return _tilt(C, S, ax, ay, gv, h)
        return h, FLAG_OK
    d = math.sqrt(Dx * Dx + Dy * Dy + Dz * Dz)
    # the rim dashpot's work over the increment (the force the trial's velocity took)
    S[S_ERIM] -= qx * Dx + qy * Dy + qz * Dz
    _slide(C, S, d, Dx / d, Dy / d, Dz / d, v1x, v1y, v1z, ax, ay, gv, f1, f2)
    S[S_MODE] = SLIP
    S[S_DW1] = S[S_DW2] = 0.0
    w = math.sqrt(S[S_WX] * S[S_WX] + S[S_WY] * S[S_WY] + S[S_WZ] * S[S_WZ])
    S[S_SV1], S[S_SV2] = R1 * w, R2 * w
    return h, FLAG_OK


SUBSTEP_MIN = 1.0 / 256.0     # shortest sub-step near a turning event, in steps
SUBSTEP_TAU = 0.005           # s: turning time scale below which the midpoint scheme sub-steps
                              # (0.02: the default scene took 4.9 part-steps a step against 2.6, for the same errors;
                              # docs/bidirectional.md, section 2)
SUBSTEPS_MAX = 2000


def _event_substep(C, S, ax, ay, gv, h, rem, h_min, mu1, mu2):
    """Length of the next sub-step of the midpoint scheme.

    Near an event where the velocity passes close to zero (a stop, or in 2D
    a fast turn), the friction direction turns at the rate ~ acc / |w|,
    acc = (cap + |f_t|) / I, and a step of length h has a local error
    ~ h^3 cap/I (acc/|w|)^2: summed over the event, h^2 / tau with tau the
    time to the event, which is first order overall. Sub-steps of length
    h tau / SUBSTEP_TAU (tau = |w| / acc < SUBSTEP_TAU), at least h_min,
    make the event's error O(h^2) again, at a cost of
    ~ (SUBSTEP_TAU / h) log(h / h_min) sub-steps per event."""
    wx, wy, wz = S[S_WX], S[S_WY], S[S_WZ]
    w = math.sqrt(wx * wx + wy * wy + wz * wz)
    if w == 0.0:
        return rem
    nx, ny, nz = S[S_NX], S[S_NY], S[S_NZ]
    N1, N2 = normal_forces(C, nx, ny, nz, wx, wy, wz, ax, ay, gv)
    cap = mu1 * N1 * C[C_R1] + mu2 * N2 * C[C_R2]
    Sm = C[C_S]
    fx, fy, fz = Sm * ax, Sm * ay, Sm * gv
    fn = fx * nx + fy * ny + fz * nz
    tx, ty, tz = fx - fn * nx, fy - fn * ny, fz - fn * nz
    acc = (cap + math.sqrt(tx * tx + ty * ty + tz * tz)) / C[C_I]
    if acc <= 0.0:          # nothing turns the velocity (no friction, no tangential force): no event
        return rem
    tau = w / acc
    if tau >= SUBSTEP_TAU:
        return rem
    hs = h * tau / SUBSTEP_TAU
    if hs < h_min:
        hs = h_min
    if rem - hs < h_min:
        hs = rem
    return hs


def rim(C, S, gv):
    """Keep the axis inside the rim's cone (tilt <= C[C_THMAX]) after a
    (part-)step: an axis past it is put back on it along its meridian, and
    the velocity's outward component there is reversed times the restitution
    (0: the inelastic stop). The energy it takes (kinetic and potential, the
    overshoot's included) is booked in S[S_ERIM]. Returns (jx, jy): the
    horizontal momentum an impact took (an arrival at the rim: reported as
    an impulse, not a force), (0, 0) for contact (the axis already on the
    rim when the step began: the rim's reaction, part of the force)."""
    thmax = C[C_THMAX]
    if thmax <= 0.0 or S[S_ROCK] != 0.0:
        return 0.0, 0.0
    if C[C_KRIM] != 0.0:
        # a rim of finite stiffness: a contact force in the drive (its dashpot's loss
        # booked by the part-step, rim_damper), no impulse;
        # an impact is counted when the axis passes the capacity
        if rim_overlap(C, S[S_NX], S[S_NY], S[S_NZ]) > 0.0:
            if S[S_ATRIM] == 0.0:
                S[S_ATRIM] = 1.0
                S[S_NRIM] += 1.0
        else:
            S[S_ATRIM] = 0.0
        return 0.0, 0.0
    nx, ny, nz = S[S_NX], S[S_NY], S[S_NZ]
    r = hypot(nx, ny)
    th = math.atan2(r, -nz)
    if th <= thmax:
        if th < thmax * (1.0 - 1e-9):   # off the rim (an axis left on it stays in contact)
            S[S_ATRIM] = 0.0
        return 0.0, 0.0
    Ek0, Ep0 = energies(C, S)
    px0, py0 = momentum(C, S)
    cx, cy = nx / r, ny / r
    # the velocity in the meridian frame at the overshoot: outward along the meridian,
    # and round the axis (w is tangent: w . n = 0)
    c0, s0 = -nz, r
    wr = S[S_WX] * c0 * cx + S[S_WY] * c0 * cy + S[S_WZ] * s0
    wa = -S[S_WX] * cy + S[S_WY] * cx
    st, ct = math.sin(thmax), math.cos(thmax)
    S[S_NX], S[S_NY], S[S_NZ] = st * cx, st * cy, -ct
    Ep1 = energies(C, S)[1]
    if wr > 0.0:
        # the outward rate at the rim itself: the overshoot turned kinetic energy into
        # potential (Ep0 - Ep1); the rim hands back e of that rate, inwards, so the
        # impact takes (1 - e^2) of the kinetic energy normal to the rim
        I = C[C_I]
        ek = 0.5 * I * wr * wr + (Ep0 - Ep1) * (gv / C[C_G])     # the height in the field g + a_z
        w_rim = 0.0
        if ek > 0.0:
            w_rim = math.sqrt(2.0 * ek / I)
        wr = -C[C_REST] * w_rim
    # carried to the rim along the meridian (the same frame there)
    wx, wy, wz = wr * ct * cx - wa * cy, wr * ct * cy + wa * cx, wr * st
    S[S_WX], S[S_WY], S[S_WZ] = wx, wy, wz
    Ek1, Ep1 = energies(C, S)
    S[S_ERIM] += (Ek0 + Ep0) - (Ek1 + Ep1)
    px1, py1 = momentum(C, S)
    w = math.sqrt(wx * wx + wy * wy + wz * wz)
    S[S_SV1], S[S_SV2] = C[C_R1] * w, C[C_R2] * w
    if S[S_ATRIM] != 0.0:              # resting against the rim: its reaction
        return 0.0, 0.0
    S[S_ATRIM] = 1.0
    S[S_NRIM] += 1.0
    jx, jy = px1 - px0, py1 - py0
    S[S_JRIM] = S[S_JRIM] + hypot(jx, jy)
    return jx, jy


def step(C, S, ax, ay, az, h, mu1, mu2):
    """One step of length h under the step-mean ground acceleration (ax, ay,
    az) (az up, 0 without a vertical record) with mu1, mu2 held: every
    normal force, friction cap, rocking check and drive sees the vertical
    field gv = g + az (model.md 10). Returns a flag (FLAG_OK, FLAG_ROCKING).
    When gv < 0 the moving assembly leaves the lower plate (lift-off) and
    flies until it lands (``_airborne``); a step that lands finishes seated.
    Sets the force the bearing transmits to the ground, from the momentum
    balance of the moving parts over the step: F = -((M + m) a + S (w_h(end)
    - w_h(start)) / h) seated, zero in flight."""
    gv = C[C_G] + az
    S[S_AZ] = az
    if S[S_FLY] == 0.0 and not gv < 0.0:
        return _seated(C, S, ax, ay, gv, h, mu1, mu2)
    return _airborne(C, S, ax, ay, gv, h, mu1, mu2)


def _airborne(C, S, ax, ay, gv, h, mu1, mu2):
    """A step that flies or may take off (model.md 10): flights (``_flight``)
    while the unit is in the air or the field lifts it off, then the rest of
    the step seated (the force on the ground that part's, spread over h)."""
    rem = h
    for _ in range(FLIGHTS_MAX):
        if S[S_FLY] == 0.0 and not gv < 0.0:
            break
        tau = _flight(C, S, ax, ay, gv, rem)
        if tau < 0.0:              # the seat's curvature keeps it down over the step: seated
            break
        rem = rem - tau
        if S[S_FLY] != 0.0 or not rem > FLIGHT_REST * h:
            return FLAG_OK
    flag = _seated(C, S, ax, ay, gv, rem, mu1, mu2)
    if rem != h:
        # the force over the whole step: the bearing carries nothing in the air
        S[S_FX] = S[S_FX] * (rem / h)
        S[S_FY] = S[S_FY] * (rem / h)
    return flag


def _momentum3(C, S):
    """Momentum of the moving parts relative to the ground (3 components): S w
    seated, the rocking chain's first moment turning about its pivot."""
    if S[S_ROCK] != 0.0:
        b, w = S[S_BETA], S[S_BETAD]
        c, s = math.cos(b), math.sin(b)
        Xr, Zr = c * C[C_XB] - s * C[C_ZB], s * C[C_XB] + c * C[C_ZB]
        return (w * (-Zr * S[S_EX] - Xr * S[S_NX]), w * (-Zr * S[S_EY] - Xr * S[S_NY]),
                w * (-Zr * S[S_EZ] - Xr * S[S_NZ]))
    Sm = C[C_S]
    return Sm * S[S_WX], Sm * S[S_WY], Sm * S[S_WZ]


def _base(C, S):
    """The superstructure's position (x, y, z) relative to the ground of the
    (seated or rocking) configuration held in S: L n_h + the rocking offsets,
    L (1 + n_z) + the rocking rise."""
    L = C[C_L]
    dx, dy, dz, _vx, _vy = rocking_offsets(C, S)
    return (L * S[S_NX] + dx, L * S[S_NY] + dy,
            L * uplift_factor(S[S_NX], S[S_NY], S[S_NZ]) + dz)


def _seat_axis(C, ux, uy):
    """The seated axis n whose superstructure is at the horizontal position
    (ux, uy): n_h = u / L, held inside the rim's cone (the whole sphere without
    a rim). Returns (nx, ny, nz, clamped)."""
    L = C[C_L]
    nx, ny = ux / L, uy / L
    r = hypot(nx, ny)
    rmax = 1.0
    if C[C_THMAX] > 0.0:
        rmax = math.sin(C[C_THMAX])
    clamped = r > rmax
    if clamped:
        nx, ny = nx * (rmax / r), ny * (rmax / r)
    q = 1.0 - (nx * nx + ny * ny)
    if q < 0.0:
        q = 0.0
    return nx, ny, -math.sqrt(q), clamped


def _lift_at(C, bx, by, bz, x0, y0, z0, vx, vy, vz, ax, ay, gv, t):
    """The flying unit's height above the seat under it (the lower plate's
    surface height at its horizontal position, L (1 + n_z) of ``_seat_axis``)
    at time t of a flight from (x0, y0, z0) with velocity v under the
    constant field (ax, ay, gv), the configuration's position b added."""
    ux = bx + x0 + t * (vx - 0.5 * ax * t)
    uy = by + y0 + t * (vy - 0.5 * ay * t)
    uz = bz + z0 + t * (vz - 0.5 * gv * t)
    nx, ny, nz, _c = _seat_axis(C, ux, uy)
    return uz - C[C_L] * uplift_factor(nx, ny, nz)


def flight_lift(C, S):
    """The flying unit's height above the seat under it (m; 0 when seated)."""
    if S[S_FLY] == 0.0:
        return 0.0
    bx, by, bz = _base(C, S)
    return _lift_at(C, bx, by, bz, S[S_XF], S[S_YF], S[S_ZF], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def _flight(C, S, ax, ay, gv, h):
    """Ballistic flight of the moving unit (superstructure, upper plate and
    pad, rigidly; model.md 10) over at most h. Relative to the ground it
    translates under the field -(ax, ay, gv) (exact for the step's constant
    field): its displacement since take-off (S_XF, S_YF, S_ZF) and velocity
    (S_VXF, S_VYF, S_ZFD); the configuration at take-off (n, the rocking
    chain) is held as the reference its displacement is added to. Takes off
    (when not flying) with the moving parts' momentum over their mass, the
    kinetic energy of their motion relative to each other into E_land; only
    when the unit is still above its seat at the end of h (else returns -1:
    no take-off, nothing changed). Lands at the first time its height meets
    the seat under it (bisection to round-off), ``_land``. No contact: normal
    forces, friction, slip and the force on the ground zero; the field's
    work beyond gravity's, -(M + m)(ax dx + ay dy + (gv - g) dz), is input.
    Returns the time flown (h, or the landing time)."""
    Mt = C[C_M] + C[C_MP]
    bx, by, bz = _base(C, S)
    takeoff = S[S_FLY] == 0.0
    if takeoff:
        px, py, pz = _momentum3(C, S)
        vx, vy, vz = px / Mt, py / Mt, pz / Mt
        x0 = y0 = z0 = 0.0
        if not _lift_at(C, bx, by, bz, x0, y0, z0, vx, vy, vz, ax, ay, gv, h) > 0.0:
            return -1.0
        Ek0 = energies(C, S)[0]
        S[S_ELAND] += Ek0 - 0.5 * Mt * (vx * vx + vy * vy + vz * vz)
        S[S_FLY] = 1.0
        S[S_NLIFT] += 1.0
        S[S_DW1] = S[S_DW2] = 0.0               # out of contact: a landing dwells anew
        S[S_XF] = S[S_YF] = S[S_ZF] = 0.0
        S[S_VXF], S[S_VYF], S[S_ZFD] = vx, vy, vz
    x0, y0, z0 = S[S_XF], S[S_YF], S[S_ZF]
    vx, vy, vz = S[S_VXF], S[S_VYF], S[S_ZFD]
    S[S_DS1] = S[S_DS2] = S[S_DPHI] = 0.0
    S[S_BETA2] = 0.0
    S[S_NOROCK] = S[S_LANDED] = 0.0
    S[S_JRIM] = 0.0
    S[S_N1] = S[S_N2] = S[S_FF1] = S[S_FF2] = 0.0
    S[S_SV1] = S[S_SV2] = 0.0
    S[S_FX] = S[S_FY] = 0.0
    tau = h
    landed = False
    if not takeoff and not _lift_at(C, bx, by, bz, x0, y0, z0, vx, vy, vz, ax, ay, gv, h) > 0.0:
        # the landing: the first time the height meets the seat (above it at 0, not at h)
        lo, hi = 0.0, h
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if not (lo < mid < hi):
                break
            if _lift_at(C, bx, by, bz, x0, y0, z0, vx, vy, vz, ax, ay, gv, mid) > 0.0:
                lo = mid
            else:
                hi = mid
        tau = hi
        landed = True
    dx = tau * (vx - 0.5 * ax * tau)
    dy = tau * (vy - 0.5 * ay * tau)
    dz = tau * (vz - 0.5 * gv * tau)
    # the d'Alembert forces' work through the unit's displacement (gravity's is the potential)
    S[S_EIN] -= Mt * (ax * dx + ay * dy + (gv - C[C_G]) * dz)
    S[S_TFLY] += tau
    S[S_XF], S[S_YF], S[S_ZF] = x0 + dx, y0 + dy, z0 + dz
    S[S_VXF], S[S_VYF], S[S_ZFD] = vx - ax * tau, vy - ay * tau, vz - gv * tau
    if landed:
        _land(C, S, bx, by)
    return tau


def _land(C, S, bx, by):
    """The landing (model.md 10): the seated configuration under the unit
    (n_h = u / L of the flown horizontal position u; past the rim: on the rim
    along u), the rocking chain let go, and the plastic impact: the unit's
    velocity V projected onto the seated motions at n in the kinetic-energy
    metric, w = (S / I) (V - (V . n) n) (the velocity normal to the seat
    removed, the tangential kept; the pad takes its share). The energy of
    the unit before (kinetic and potential) minus the seated state's after
    into E_land. Past the rim: then the rim's impact (its outward rate
    reversed times the restitution, the loss in E_rim, counted)."""
    Mt = C[C_M] + C[C_MP]
    Ek0, Ep0 = energies(C, S)
    vx, vy, vz = S[S_VXF], S[S_VYF], S[S_ZFD]
    nx, ny, nz, clamped = _seat_axis(C, bx + S[S_XF], by + S[S_YF])
    S[S_ROCK] = S[S_BETA] = S[S_BETAD] = 0.0
    S[S_NX], S[S_NY], S[S_NZ] = nx, ny, nz
    vn = vx * nx + vy * ny + vz * nz
    k = C[C_S] / C[C_I]
    wx, wy, wz = k * (vx - vn * nx), k * (vy - vn * ny), k * (vz - vn * nz)
    S[S_FLY] = 0.0
    S[S_XF] = S[S_YF] = S[S_ZF] = 0.0
    S[S_VXF] = S[S_VYF] = S[S_ZFD] = 0.0
    S[S_WX], S[S_WY], S[S_WZ] = wx, wy, wz
    Ek1, Ep1 = energies(C, S)
    S[S_ELAND] += (Ek0 + Ep0) - (Ek1 + Ep1)
    if clamped and C[C_THMAX] > 0.0:
        r = hypot(nx, ny)
        cx, cy = nx / r, ny / r
        # the outward meridian tangent at n: (-n_z c, r)
        mx, my, mz = -nz * cx, -nz * cy, r
        wr = wx * mx + wy * my + wz * mz
        if wr > 0.0:
            dw = -(1.0 + C[C_REST]) * wr
            S[S_WX], S[S_WY], S[S_WZ] = wx + dw * mx, wy + dw * my, wz + dw * mz
            Ek2 = energies(C, S)[0]
            S[S_ERIM] += Ek1 - Ek2
            S[S_NRIM] += 1.0
            S[S_JRIM] += C[C_S] * abs(dw) * -nz
        S[S_ATRIM] = 1.0
    w = math.sqrt(S[S_WX] * S[S_WX] + S[S_WY] * S[S_WY] + S[S_WZ] * S[S_WZ])
    S[S_SV1], S[S_SV2] = C[C_R1] * w, C[C_R2] * w


def _seated(C, S, ax, ay, gv, h, mu1, mu2):
    """The seated (part-)step of length h (``step``)."""
    px0, py0 = momentum(C, S)
    S[S_DS1] = S[S_DS2] = S[S_DPHI] = 0.0
    S[S_BETA2] = 0.0
    if S[S_ROCK] == 0.0:
        S[S_BETA1] = S[S_TILT] = 0.0
    S[S_NOROCK] = S[S_LANDED] = 0.0
    rem = h
    flag = FLAG_OK
    h_min = h * SUBSTEP_MIN
    jx = jy = 0.0
    S[S_JRIM] = 0.0
    for _ in range(SUBSTEPS_MAX):
        hs = rem
        if C[C_MID] != 0.0:
            hs = _event_substep(C, S, ax, ay, gv, h, rem, h_min, mu1, mu2)
        used, flag = _part(C, S, ax, ay, gv, hs, mu1, mu2)
        if flag != FLAG_OK:
            break
        dx, dy = rim(C, S, gv)
        jx, jy = jx + dx, jy + dy
        rem = rem - used
        if not rem > 0.0:
            break
    if S[S_LANDED] != 0.0:         # the step is labelled by its rocking part
        S[S_MODE] = TILT
        S[S_BETA1] = S[S_BLAND]
    Mt = C[C_M] + C[C_MP]
    px1, py1 = momentum(C, S)
    # an impact's impulse is not a force of the step (it is reported as itself: S_JRIM)
    S[S_FX] = -(Mt * ax + (px1 - px0 - jx) / h)
    S[S_FY] = -(Mt * ay + (py1 - py0 - jy) / h)
    return flag


def uplift_factor(nx, ny, nz):
    """1 + n_z = 1 - cos(theta), without cancellation: |n_h|^2 / (1 - n_z)."""
    return (nx * nx + ny * ny) / (1.0 - nz)


def energies(C, S):
    """(E_kin, E_pot): I |w|^2 / 2 and S g (1 - cos theta) seated; while
    rocking I_P beta'^2 / 2, and the rise of the chain's first moment added;
    in flight (model.md 10) the unit's (M + m) |V|^2 / 2, and (M + m) g z
    (its rise since take-off) added to the take-off configuration's potential."""
    Ek, Ep = _seated_energies(C, S)
    if S[S_FLY] != 0.0:
        Mt = C[C_M] + C[C_MP]
        Ek = 0.5 * Mt * (S[S_VXF] * S[S_VXF] + S[S_VYF] * S[S_VYF] + S[S_ZFD] * S[S_ZFD])
        Ep += Mt * C[C_G] * S[S_ZF]
    return Ek, Ep


def _seated_energies(C, S):
    """energies() of the seated state (the rocking chain's included)."""
    Ep = C[C_S] * C[C_G] * uplift_factor(S[S_NX], S[S_NY], S[S_NZ])
    if S[S_ROCK] != 0.0:
        b = S[S_BETA]
        c, s = math.cos(b), math.sin(b)
        dX = (c - 1.0) * C[C_XB] - s * C[C_ZB]
        dZ = s * C[C_XB] + (c - 1.0) * C[C_ZB]
        # gravity in the plane: (-g e_z, g n_z); its potential -F . dr
        Ep += C[C_G] * (S[S_EZ] * dX - S[S_NZ] * dZ)
        return 0.5 * C[C_IP] * S[S_BETAD] * S[S_BETAD], Ep
    w2 = S[S_WX] * S[S_WX] + S[S_WY] * S[S_WY] + S[S_WZ] * S[S_WZ]
    if C[C_KRIM] != 0.0:
        Ep += rim_spring_energy(C, S[S_NX], S[S_NY], S[S_NZ])
    return 0.5 * C[C_I] * w2, Ep


def rocking_offsets(C, S):
    """Displacement (dx, dy, dz) and velocity (vx, vy) of the superstructure
    (carried by the top corner) added by the rocking chain to the seated values."""
    if S[S_ROCK] == 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    b, w = S[S_BETA], S[S_BETAD]
    c, s = math.cos(b), math.sin(b)
    qe, qu = C[C_RQX], C[C_RQZ]
    re, ru = c * qe - s * qu, s * qe + c * qu
    de, du = re - qe, ru - qu
    ex, ey, ez = S[S_EX], S[S_EY], S[S_EZ]
    nx, ny, nz = S[S_NX], S[S_NY], S[S_NZ]
    # up = -n; the corner's velocity w (-r_up e + r_e up)
    return (de * ex - du * nx, de * ey - du * ny, de * ez - du * nz,
            w * (-ru * ex - re * nx), w * (-ru * ey - re * ny))


def run_steps(C, S, AX, AY, AZ, h, mu1, mu2, n0, n1, out):
    """Steps n0..n1-1 with constant friction (mechanics-only runs, studies,
    benchmarks): out[k] = (ux, uy, W1 + W2) after each step. Returns the
    number of steps done (fewer on a flag)."""
    L = C[C_L]
    for n in range(n0, n1):
        flag = step(C, S, AX[n], AY[n], AZ[n], h, mu1, mu2)
        k = n - n0
        dx, dy, _dz, _vx, _vy = rocking_offsets(C, S)
        if S[S_FLY] != 0.0:
            dx, dy = dx + S[S_XF], dy + S[S_YF]
        out[k, 0] = L * S[S_NX] + dx
        out[k, 1] = L * S[S_NY] + dy
        out[k, 2] = S[S_W1] + S[S_W2]
        if flag != FLAG_OK:
            return n - n0
    return n1 - n0


# -- the bearing-test machine: a prescribed orbit u(t) = (ux, uy) --------------------

def machine_point(C, ux, uy, vx, vy, ax, ay, tx, ty, tz, mu1, mu2, gv):
    """Restraint force (Fx, Fy) and normal forces at one instant of a
    prescribed relative motion u, u', u'' (the lower plate moves by -u, the
    superstructure is held horizontally and rides on its weight), with the
    unit tangent t of the slip (friction opposes it; zero: no friction).

    The seated equation on the sphere (tangent plane at n):
        I (n'')_T + S P_T(a_g, g) + cap t = L P_T(F)
    with a_g = -u'' the lower plate's acceleration and cap = sum mu_i R_i N_i,
    N_i = N_i0 + F . n_h (the restraint's axial share). Linear in F: solved
    in the tangent basis. The planar SeatedTestMachine is the case u_y = 0.
    With C[C_AXIAL] the vertical actuator holds N = M gv in force control
    (gv = g: the weight; docs/test_machine.md "Axial-load programme"): the
    superstructure has no inertia, N2 = N (-n_z) + F . n_h, and its weight
    M g in S g becomes N (S g + M L (gv - g)); gv is read only then.
    Returns (Fx, Fy, N1, N2, nx, ny, nz, wx, wy, wz)."""
    L, I, S, g = C[C_L], C[C_I], C[C_S], C[C_G]
    nx, ny = ux / L, uy / L
    nz = -math.sqrt(1.0 - nx * nx - ny * ny)
    wx, wy = vx / L, vy / L
    wz = -(nx * wx + ny * wy) / nz
    w2 = wx * wx + wy * wy + wz * wz
    qx, qy = ax / L, ay / L
    qz = -(w2 + nx * qx + ny * qy) / nz
    gax, gay = -ax, -ay                       # the lower plate's acceleration
    # the seated normal forces (unclipped: the machine's formula is linear in F)
    g_axis = -(gax * nx + gay * ny + g * nz)
    Sin = S
    Sg = S * g
    if C[C_AXIAL] != 0.0:
        N2_0 = C[C_M] * gv * -nz
        Sin = C[C_SIN]
        Sg = S * g + C[C_M] * L * (gv - g)
    else:
        N2_0 = C[C_M] * (g_axis + L * w2)
    N1_0 = N2_0 + C[C_MP] * (g_axis + C[C_RHO] * w2)
    k = mu1 * C[C_R1] + mu2 * C[C_R2]
    cap0 = mu1 * C[C_R1] * N1_0 + mu2 * C[C_R2] * N2_0
    t1, t2 = tangent_basis(nx, ny, nz)
    # right-hand side, a 3-vector in the tangent plane (normal parts drop in the dots)
    rx = I * qx + Sin * gax + cap0 * tx
    ry = I * qy + Sin * gay + cap0 * ty
    rz = I * qz + Sg + cap0 * tz
    b1 = rx * t1[0] + ry * t1[1] + rz * t1[2]
    b2 = rx * t2[0] + ry * t2[1] + rz * t2[2]
    tt1 = tx * t1[0] + ty * t1[1] + tz * t1[2]
    tt2 = tx * t2[0] + ty * t2[1] + tz * t2[2]
    a11, a12 = L * t1[0] - k * nx * tt1, L * t1[1] - k * ny * tt1
    a21, a22 = L * t2[0] - k * nx * tt2, L * t2[1] - k * ny * tt2
    det = a11 * a22 - a12 * a21
    Fx = (b1 * a22 - a12 * b2) / det
    Fy = (a11 * b2 - a21 * b1) / det
    share = Fx * nx + Fy * ny
    return Fx, Fy, N1_0 + share, N2_0 + share, nx, ny, nz, wx, wy, wz


def _chord_tangent(nx, ny, nz, dx, dy, dz):
    """Unit tangent at n of the chord d (projected), or zeros."""
    p = dx * nx + dy * ny + dz * nz
    tx, ty, tz = dx - p * nx, dy - p * ny, dz - p * nz
    m = math.sqrt(tx * tx + ty * ty + tz * tz)
    if m == 0.0:
        return 0.0, 0.0, 0.0
    return tx / m, ty / m, tz / m


def _slip_tangent(nx, ny, nz, wx, wy, dx, dy, dz):
    """Direction of slip at n for the step with chord d: the velocity's
    direction when it points along the step (exactly tangent), else the
    chord's (a reversal or a stop at this point)."""
    wz = -(nx * wx + ny * wy) / nz
    if wx * dx + wy * dy + wz * dz > 0.0:
        m = math.sqrt(wx * wx + wy * wy + wz * wz)
        return wx / m, wy / m, wz / m
    return _chord_tangent(nx, ny, nz, dx, dy, dz)


def link_bearing(C, ux, uy, vx, vy, ax, ay, hx, hy, mu1, mu2):
    """The bearing's force on the plate and its normal forces at (u, u', u''),
    friction opposing the horizontal direction (hx, hy) (zero: none):
    machine_point with that direction's tangent at n (the compliant link of
    the orbit machine: machines/link_kernel.py)."""
    L = C[C_L]
    nx, ny = ux / L, uy / L
    nz = -math.sqrt(1.0 - nx * nx - ny * ny)
    tx, ty, tz = 0.0, 0.0, 0.0
    if hx != 0.0 or hy != 0.0:
        tx, ty, tz = _chord_tangent(nx, ny, nz, hx, hy, 0.0)
    return machine_point(C, ux, uy, vx, vy, ax, ay, tx, ty, tz, mu1, mu2, C[C_G])


def machine_step(C, S, U, UD, UDD, GV, i, mu1, mu2):
    """Grid point i -> i+1 of the prescribed orbit (U, UD, UDD: (n+1, 2)
    arrays of u, u', u''; GV: the axial load over M per grid point, read
    with C[C_AXIAL] only). Friction work per interface: mu_i R_i times the
    normal force averaged over the step times the angle between the axes
    (the great-circle arc); the input work: the generalised force of the
    restraint and of the moving plate's d'Alembert force, trapezoidal over
    the chord, and in force control the actuator's work beyond the weight's,
    -(N - M g) dz with dz = L dn_z (trapezoidal). Returns the flag.
    With C[C_LINK] the machine drives the plate through the compliant link
    instead (machines/link_kernel.py)."""
    L = C[C_L]
    n0x, n0y = U[i, 0] / L, U[i, 1] / L
    n1x, n1y = U[i + 1, 0] / L, U[i + 1, 1] / L
    n0z = -math.sqrt(1.0 - n0x * n0x - n0y * n0y)
    n1z = -math.sqrt(1.0 - n1x * n1x - n1y * n1y)
    dx, dy, dz = n1x - n0x, n1y - n0y, n1z - n0z
    chord = math.sqrt(dx * dx + dy * dy + dz * dz)
    ang = 2.0 * math.asin(0.5 * chord)
    t0 = _slip_tangent(n0x, n0y, n0z, UD[i, 0] / L, UD[i, 1] / L, dx, dy, dz)
    t1 = _slip_tangent(n1x, n1y, n1z, UD[i + 1, 0] / L, UD[i + 1, 1] / L, dx, dy, dz)
    gva = C[C_G]
    gvb = C[C_G]
    Sin = C[C_S]
    if C[C_AXIAL] != 0.0:
        gva = GV[i]
        gvb = GV[i + 1]
        Sin = C[C_SIN]
    Fa = machine_point(C, U[i, 0], U[i, 1], UD[i, 0], UD[i, 1], UDD[i, 0], UDD[i, 1],
                       t0[0], t0[1], t0[2], mu1, mu2, gva)
    Fb = machine_point(C, U[i + 1, 0], U[i + 1, 1], UD[i + 1, 0], UD[i + 1, 1], UDD[i + 1, 0],
                       UDD[i + 1, 1], t1[0], t1[1], t1[2], mu1, mu2, gvb)
    R1, R2 = C[C_R1], C[C_R2]
    launch = ang == 0.0 and S[S_WX] == 0.0 and S[S_WY] == 0.0 and S[S_WZ] == 0.0
    Ek0 = 0.0
    if launch:
        Ek0 = energies(C, S)[0]
    S[S_W1] += mu1 * 0.5 * (Fa[2] + Fb[2]) * R1 * ang
    S[S_W2] += mu2 * 0.5 * (Fa[3] + Fb[3]) * R2 * ang
    # generalised force Q = L F + S u'' (the plate's d'Alembert force is -S a_g = S u'')
    qa = (L * Fa[0] + Sin * UDD[i, 0], L * Fa[1] + Sin * UDD[i, 1])
    qb = (L * Fb[0] + Sin * UDD[i + 1, 0], L * Fb[1] + Sin * UDD[i + 1, 1])
    S[S_EIN] += 0.5 * ((qa[0] + qb[0]) * dx + (qa[1] + qb[1]) * dy)
    if C[C_AXIAL] != 0.0:
        S[S_EIN] -= 0.5 * C[C_M] * L * ((gva - C[C_G]) + (gvb - C[C_G])) * dz
    S[S_NX], S[S_NY], S[S_NZ] = Fb[4], Fb[5], Fb[6]
    S[S_WX], S[S_WY], S[S_WZ] = Fb[7], Fb[8], Fb[9]
    S[S_FX], S[S_FY], S[S_N1], S[S_N2] = Fb[0], Fb[1], Fb[2], Fb[3]
    S[S_FF1] = mu1 * Fb[2]
    S[S_FF2] = mu2 * Fb[3]
    if launch:
        # at rest: a programme that starts after a hold launches the bearing by an
        # impulse at fixed position, whose work is the kinetic energy it gives
        S[S_EIN] += energies(C, S)[0] - Ek0
    hm1 = holding_mu_dwell(mu1, C[C_MUS1], C[C_MUR1], C[C_MUI1], C[C_TAU1], C[C_EXP1], S[S_DW1])
    hm2 = holding_mu_dwell(mu2, C[C_MUS2], C[C_MUR2], C[C_MUI2], C[C_TAU2], C[C_EXP2], S[S_DW2])
    dwell_advance(S, S_DW1, ang == 0.0, C[C_DT])
    dwell_advance(S, S_DW2, ang == 0.0, C[C_DT])
    if S[S_MODE] == STICK and ang != 0.0 and (hm1 > mu1 or hm2 > mu2):
        # breakaway from rest: the restraint carries the static cap at the step's
        # start (grown by the time stuck so far); the step's row reports that force,
        # the largest of the step
        Fs = machine_point(C, U[i, 0], U[i, 1], UD[i, 0], UD[i, 1], UDD[i, 0], UDD[i, 1],
                           t0[0], t0[1], t0[2], hm1, hm2, gva)
        S[S_FX], S[S_FY] = Fs[0], Fs[1]
        S[S_FF1], S[S_FF2] = hm1 * Fs[2], hm2 * Fs[3]
    S[S_DS1], S[S_DS2], S[S_DPHI] = R1 * ang, R2 * ang, ang
    S[S_SLIP1] += R1 * ang
    S[S_SLIP2] += R2 * ang
    S[S_MODE] = SLIP if ang != 0.0 else STICK
    w = math.sqrt(Fb[7] * Fb[7] + Fb[8] * Fb[8] + Fb[9] * Fb[9])
    S[S_SV1], S[S_SV2] = R1 * w, R2 * w
    return FLAG_OK


# -- outputs (the class's values() and the compiled loop's rows) ----------------------

N_VALUES = 44           # len(mechanics.bidirectional.COLUMNS)
N_PLANAR, N_SEATED = 35, 21   # the planar two-phase and seated columns (rim's included)
N_VERTICAL = 5                # the columns of a vertical loading: az_mps2, lift_m, n_lift, t_flight_s, E_land_J


def rim_values(C, S, out, j):
    """E_rim_J, J_rim_Ns, n_rim1, n_rim2 into out[j:j + 4] (the impacts counted
    on the surface, or both, that bounds the slide)."""
    out[j], out[j + 1] = S[S_ERIM], S[S_JRIM]
    out[j + 2], out[j + 3] = C[C_RIM1] * S[S_NRIM], C[C_RIM2] * S[S_NRIM]


def centres(C, S):
    """Footprint centres (c1x, c1y, c2x, c2y): lower plate R1 theta (cos phi,
    sin phi), upper plate -R2 theta (cos phi, sin phi)."""
    nx, ny, nz = S[S_NX], S[S_NY], S[S_NZ]
    r = hypot(nx, ny)
    th = math.atan2(r, -nz)
    if r > 0.0:
        cx, cy = nx / r, ny / r
    else:
        cx, cy = 0.0, 0.0
    s1, s2 = C[C_R1] * th, C[C_R2] * th
    return s1 * cx, s1 * cy, -(s2 * cx), -(s2 * cy)


def planar_sign(S):
    """+1 when the last slide went towards +x (or none yet), else -1: the sign
    of a planar run's one-sided diagnostics (the loaded diagonal, the arcs and
    friction forces of the step, the rocking angle)."""
    if S[S_DIRX] < 0.0:
        return -1.0
    return 1.0


def values_planar(C, S, t, xg, out):
    """The planar steppers' columns (mechanics.two_phase.COLUMNS; with
    C[C_PLANAR] == PLANAR_SEATED machines.seated.SEATED_COLUMNS) of a
    motion in the x-z plane: the displacement, velocity, force, angle and arcs
    signed as the ground's x axis."""
    L = C[C_L]
    nx, ny, nz = S[S_NX], S[S_NY], S[S_NZ]
    Ek, Ep = energies(C, S)
    th = math.atan2(nx, -nz)
    dx, dy, dz, rvx, rvy = rocking_offsets(C, S)
    u, v = L * nx + dx, L * S[S_WX] + rvx
    z = L * uplift_factor(nx, ny, nz) + dz
    if S[S_FLY] != 0.0:
        u, v, z = u + S[S_XF], S[S_VXF], z + S[S_ZF]
    sg = planar_sign(S)
    R1, R2 = C[C_R1], C[C_R2]
    if C[C_PLANAR] == PLANAR_SEATED:
        out[0], out[1], out[2], out[3], out[4], out[5], out[6] = t, xg, u, v, S[S_FX], z, th
        out[7], out[8], out[9], out[10] = R1 * th, R2 * th, S[S_N1], S[S_N2]
        out[11], out[12], out[13], out[14], out[15], out[16] = S[S_W1], S[S_W2], S[S_MODE], S[S_EIN], Ek, Ep
        rim_values(C, S, out, 17)
        return
    if S[S_N2] <= 0.0:
        tip = 0.0
    else:
        F_t = S[S_FF2] if S[S_MODE] == TILT else S[S_FF1] + S[S_FF2]
        tip = abs(F_t) * (C[C_ET] - C[C_EB]) / (S[S_N2] * 2.0 * C[C_A])
    diag = 0.0
    if sg < 0.0:
        diag = 1.0
    out[0], out[1], out[2], out[3], out[4], out[5] = t, xg, u, v, S[S_FX], z
    out[6], out[7], out[8], out[9] = th, sg * S[S_BETA1], R1 * th, R2 * th
    out[10], out[11], out[12], out[13], out[14] = S[S_N1], S[S_N2], S[S_W1], S[S_W2], S[S_MODE]
    out[15], out[16], out[17], out[18] = S[S_EIN], Ek, Ep, S[S_ERES]
    out[19], out[20], out[21], out[22] = sg * S[S_BETA1], sg * S[S_BETA2], sg * S[S_TILT], diag
    out[23], out[24], out[25], out[26] = sg * S[S_DS1], sg * S[S_DS2], sg * S[S_FF1], sg * S[S_FF2]
    out[27] = S[S_WX] * -nz + S[S_WZ] * nx          # theta' (n = (sin theta, 0, -cos theta))
    out[28], out[29], out[30] = S[S_SLIP1], S[S_SLIP2], tip
    rim_values(C, S, out, 31)


def n_base(C):
    """How many columns precede the vertical loading's."""
    if C[C_PLANAR] == PLANAR_SEATED:
        return N_SEATED
    if C[C_PLANAR] == PLANAR_TWO_PHASE:
        return N_PLANAR
    return N_VALUES


def values(C, S, t, xg, yg, out):
    """The row of mechanics.bidirectional.COLUMNS into out[0:N_VALUES]
    (a planar run's: values_planar), then with a vertical loading
    VERTICAL_COLUMNS."""
    if C[C_VERT] != 0.0:
        j = n_base(C)
        out[j], out[j + 1], out[j + 2], out[j + 3], out[j + 4] = S[S_AZ], flight_lift(C, S), S[S_NLIFT], S[S_TFLY], S[S_ELAND]
    if C[C_PLANAR] != PLANAR_NONE:
        values_planar(C, S, t, xg, out)
        return
    L = C[C_L]
    nx, ny, nz = S[S_NX], S[S_NY], S[S_NZ]
    Ek, Ep = energies(C, S)
    th = math.atan2(hypot(nx, ny), -nz)
    c1x, c1y, c2x, c2y = centres(C, S)
    dx, dy, dz, rvx, rvy = rocking_offsets(C, S)
    ux, uy, vx, vy = L * nx + dx, L * ny + dy, L * S[S_WX] + rvx, L * S[S_WY] + rvy
    if S[S_FLY] != 0.0:
        ux, uy, vx, vy = ux + S[S_XF], uy + S[S_YF], S[S_VXF], S[S_VYF]
    out[0], out[1], out[2], out[3], out[4], out[5] = t, xg, yg, ux, uy, hypot(ux, uy)
    out[6], out[7], out[8] = vx, vy, hypot(vx, vy)
    out[9], out[10], out[11] = S[S_FX], S[S_FY], hypot(S[S_FX], S[S_FY])
    z = L * uplift_factor(nx, ny, nz) + dz
    if S[S_FLY] != 0.0:
        z += S[S_ZF]
    out[12], out[13], out[14], out[15] = z, th, math.atan2(ny, nx), S[S_BETA1]
    out[16], out[17], out[18], out[19] = C[C_R1] * th, C[C_R2] * th, S[S_N1], S[S_N2]
    out[20], out[21], out[22] = S[S_W1], S[S_W2], S[S_MODE]
    out[23], out[24], out[25], out[26] = S[S_EIN], Ek, Ep, S[S_ERES]
    out[27], out[28], out[29], out[30], out[31] = S[S_BETA1], S[S_BETA2], S[S_TILT], S[S_DS1], S[S_DS2]
    out[32], out[33], out[34], out[35] = S[S_FF1], S[S_FF2], S[S_SLIP1], S[S_SLIP2]
    out[36], out[37], out[38], out[39] = c1x, c1y, c2x, c2y
    rim_values(C, S, out, 40)
