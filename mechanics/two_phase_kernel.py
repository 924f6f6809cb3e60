"""The paper's two-phase step for the planar DFP, written once (kernel module).

mechanics/two_phase.py (TwoPhaseStepper) holds the state vector S and the
constants C of these functions and calls ``step``/``values``; the compiled
engine (coupling/engine_kernel.py) calls their numba copy (fpd/kernels.py) on a
float64 copy of the same S. The derivation is in mechanics/two_phase.py's
docstring and docs/two_phase.md; this file is the arithmetic.

Rules that keep the compiled and the pure run identical bit for bit:

- ``x ** 2`` in Python is libm ``pow(x, 2.0)``; numba turns a literal
  exponent into a product, so the kernels raise to C[TWO] (a run-time 2.0).
- math.sin/cos/atan/exp/sqrt and float ** float go to the same libm; no
  fastmath, so no reassociation or FMA contraction.
- Where the step cannot go on (a division by zero, the pad overturning) it
  sets S[ERR] and returns without taking the step; the Python class raises
  from the flag. Python's max/min are _pmax/_pmin (the same -0.0 and NaN).
"""
from __future__ import annotations

import math

from .phases import DIAGONAL_AC, DIAGONAL_BD, SLIP, STICK, TILT

__kernel__ = True

FIXED_POINT_TOL = 1e-15    # rad, on the step increment
FIXED_POINT_ITERS = 50

# -- state S (n, mode, diagonal, rocking stored as floats) -------------------------------
SN, TH, THD, MODE, DIAG, ROCK, BETA, BETAD = 0, 1, 2, 3, 4, 5, 6, 7
CH = 8                    # the rocking chain: I_P, X0, Z0, rGx, rGz, rQx, rQz, sign (8 slots)
W1, W2, EIN, ERS = 16, 17, 18, 19
B1, B2, PTILT, DS1, DS2, SL1, SL2 = 20, 21, 22, 23, 24, 25, 26
FF1, FF2, FF, N1, N2, SV1, SV2 = 27, 28, 29, 30, 31, 32, 33
ERR, ERRV = 34, 35        # error flag (below) and its value (beta at an overturn)
N_STATE = 36
ERR_NONE, ERR_DIVISION, ERR_OVERTURNED = 0.0, 1.0, 2.0

# -- constants C -------------------------------------------------------------------------
CL, CRHO, CI, CS, CM, Cm, CJ, CG, CR1, CR2 = 0, 1, 2, 3, 4, 5, 6, 7, 8, 9
CA, CEB, CET, CPH, CR2C = 10, 11, 12, 13, 14     # the corner (a, eta_b, eta_t, h, R2)
CHC, CIT, CDT, TWO, CGA = 15, 16, 17, 18, 19     # h', I_trans, dt, 2.0, geom.a
CBC = 20                                         # body chains A-C, B-D: 2 x 7
N_CONST = 34

N_VALUES = 31             # len(two_phase.COLUMNS)


def rocking_acceleration(I_P, X, Z, a_g, g):
    """Eq. (7) specialised to the phase-1 chain: beta'' about the pivot.

    Moments about the pivot (counter-clockwise), ground acceleration a_g:
    I_P beta'' = Z a_g - X g, with X, Z the horizontal and vertical first
    moments sum m_i r_i of the pad and of RB3+4 at its corner. No beta'^2
    term: |r_i| is fixed, so the centripetal forces pass through the pivot.
    """
    return (Z * a_g - X * g) / I_P


def _pmax(a, b):
    """Python's max(a, b) for floats (a unless b > a: the same -0.0 and NaN)."""
    return b if b > a else a


def _pmin(a, b):
    """Python's min(a, b) for floats."""
    return b if b < a else a


def _sinc(x):
    if abs(x) < 1e-4:
        return 1.0 - x * x / 6.0
    return math.sin(x) / x


def rocking_increment(b0, w0, h, I_P, X, Z, fe, fu):
    """Eq. (7) over a (part-)step h: the rocking angle's increment db and end
    rate w1 of the rigid chain about the pivot (inertia I_P about it, mass
    centre at (X, Z) in the pad frame) under the constant in-plane specific
    forces (fe along the plane, fu upward: fe = -a_ground, fu = -g on a
    planar device), by the discrete-gradient midpoint rule (the step's work
    equals the potential's change), a fixed point on db. The one rocking
    integrator of both the planar and the bidirectional steppers."""
    db = h * w0
    w1 = w0
    for _ in range(FIXED_POINT_ITERS):
        mid = b0 + 0.5 * db
        c, s = math.cos(mid), math.sin(mid)
        torque = _sinc(0.5 * db) * (-fe * (s * X + c * Z) + fu * (c * X - s * Z))
        w1 = w0 + h * torque / I_P
        db_new = 0.5 * h * (w0 + w1)
        if abs(db_new - db) <= FIXED_POINT_TOL:
            db = db_new
            break
        db = db_new
    return db, w1


def pivot_angle(px, pz, rx, rz, D):
    """The rotation beta about a pivot that keeps a corner on a moved circle.

    p = pivot - (moved centre), r = corner - pivot, D = (R^2 - |corner -
    moved centre|^2) / 2: P (cos beta - 1) + Q sin beta = D with P = p . r,
    Q = p_z r_x - p_x r_z, solved in tan(beta / 2) by the root that vanishes
    with D (no cancellation for tiny steps; docs/two_phase.md section 3).
    NaN where the corner cannot reach the circle (the caller flags it)."""
    P = px * rx + pz * rz
    Q = pz * rx - px * rz
    disc = Q * Q - D * (2.0 * P + D)
    den = Q + math.sqrt(disc if disc > 0.0 else 0.0)
    if den == 0.0:
        return math.nan
    tau = D / den
    return 2.0 * math.atan(tau)


def corner_pivot_rotation(S, a, eta_bottom, eta_top, h, R2, shift):
    e = abs(shift)
    px, pz = -a - e, eta_bottom - h + R2
    rx, rz = 2.0 * a, eta_top - eta_bottom
    D = a * e - 0.5 * e * e
    beta = pivot_angle(px, pz, rx, rz, D)
    if beta != beta:
        S[ERR] = ERR_DIVISION
        return 0.0
    return beta if shift >= 0.0 else -beta


def _smallest_positive_root(c2, c1, c0, default):
    if c2 == 0.0:
        return -c0 / c1 if c1 != 0.0 and -c0 / c1 > 0.0 else default
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return default
    q = -0.5 * (c1 + math.copysign(math.sqrt(disc), c1))
    r1 = q / c2
    r2 = c0 / q if q != 0.0 else -1.0
    if r1 > 0.0:
        if r2 > 0.0 and r2 < r1:
            return r2
        return r1
    if r2 > 0.0:
        return r2
    return default


def horizontal_momentum(C, S):
    if S[ROCK] != 0.0:
        X0, Z0 = S[CH + 1], S[CH + 2]
        b = S[BETA]
        return -S[BETAD] * (math.sin(b) * X0 + math.cos(b) * Z0)
    return C[CS] * math.cos(S[TH]) * S[THD]


def _moreau_trial(C, th0, v0, a, h, cap):
    S_, g = C[CS], C[CG]
    hI = h / C[CI]
    dth = h * v0
    v1, lam = v0, 0.0
    tol = FIXED_POINT_TOL
    for _ in range(FIXED_POINT_ITERS):
        mid = th0 + 0.5 * dth
        drive = -S_ * _sinc(0.5 * dth) * (a * math.cos(mid) + g * math.sin(mid))
        v_free = v0 + hI * drive
        if abs(v_free) <= hI * cap:
            v1, lam = 0.0, (v_free / (hI * cap) if cap > 0.0 else 0.0)
        else:
            lam = 1.0 if v_free > 0.0 else -1.0
            v1 = v_free - hI * cap * lam
        dth_new = 0.5 * h * (v0 + v1)
        if abs(dth_new - dth) <= tol:
            return v1, dth_new, lam
        dth = dth_new
    return v1, dth, lam


def _arrest(C, th0, v0, a, h, cap):
    S_, g, I = C[CS], C[CG], C[CI]
    sign = 1.0 if v0 > 0.0 else -1.0
    tau = h
    for _ in range(FIXED_POINT_ITERS):
        dth = 0.5 * tau * v0
        mid = th0 + 0.5 * dth
        drive = -S_ * _sinc(0.5 * dth) * (a * math.cos(mid) + g * math.sin(mid))
        decel = drive - cap * sign
        tau_new = -v0 * I / decel if decel * sign < 0.0 else h
        tau_new = _pmin(_pmax(tau_new, 0.0), h)
        if abs(tau_new - tau) <= 1e-15 * h:
            tau = tau_new
            break
        tau = tau_new
    return tau, 0.5 * tau * v0


def _two_phase_update(C, S, th0, dth, v1, a, f1, f2):
    I, S_ = C[CI], C[CS]
    S[B1] = corner_pivot_rotation(S, C[CA], C[CEB], C[CET], C[CPH], C[CR2C], C[CL] * dth)
    if dth != 0.0:
        S[DIAG] = DIAGONAL_AC if dth > 0.0 else DIAGONAL_BD
    dphi = math.atan(dth)
    th1 = th0 + dphi
    S[B2] = dphi - S[B1]
    S[PTILT] = -S[B2]
    ads = abs(dphi)
    S[W1] += f1 * ads
    S[W2] += f2 * ads
    S[DS1], S[DS2] = C[CR1] * dphi, C[CR2] * dphi
    S[SL1] += C[CR1] * ads
    S[SL2] += C[CR2] * ads
    v_proj = v1 * (C[CIT] * math.cos(dphi) + C[CJ]) / I
    S[ERS] += 0.5 * I * (v1 * v1 - v_proj * v_proj)
    S[EIN] -= a * S_ * (math.sin(th1) - math.sin(th0))
    S[TH], S[THD] = th1, v_proj
    S[SV1] = C[CR1] * abs(v_proj)
    S[SV2] = C[CR2] * abs(v_proj)


def _start_rocking(C, S, a):
    c, s = math.cos(S[TH]), math.sin(S[TH])
    g = C[CG]
    for diagonal in range(2):
        sign = 1.0 if diagonal == DIAGONAL_AC else -1.0
        o = CBC + 7 * diagonal
        I_P, Xb, Zb = C[o], C[o + 1], C[o + 2]
        rGx, rGz, rQx, rQz = C[o + 3], C[o + 4], C[o + 5], C[o + 6]
        X0, Z0 = c * Xb - s * Zb, s * Xb + c * Zb
        if sign * rocking_acceleration(I_P, X0, Z0, a, g) > 0.0:
            S[CH], S[CH + 1], S[CH + 2] = I_P, X0, Z0
            S[CH + 3], S[CH + 4] = c * rGx - s * rGz, s * rGx + c * rGz
            S[CH + 5], S[CH + 6] = c * rQx - s * rQz, s * rQx + c * rQz
            S[CH + 7] = sign
            S[DIAG] = diagonal
            S[ROCK] = 1.0
            S[BETA] = 0.0
            S[BETAD] = 0.0
            return True
    return False


def _seated(C, S, a, h, mu1, mu2, rocking_allowed):
    """TwoPhaseStepper._seated_step, its recursion after an arrest unrolled.
    Returns -1.0, or the step length left when the pad starts rocking (the
    caller then takes the tilt step)."""
    while True:
        th0, v0 = S[TH], S[THD]
        g_axis = C[CG] * math.cos(th0) - a * math.sin(th0)
        w2 = v0 * v0
        n2 = C[CM] * (g_axis + C[CL] * w2)
        n1 = n2 + C[Cm] * (g_axis + C[CRHO] * w2)
        if n2 < 0.0:
            n1, n2 = _pmax(n1, 0.0), 0.0
        elif n1 < 0.0:
            n1 = 0.0
        S[N1], S[N2] = n1, n2
        f1, f2 = mu1 * n1 * C[CR1], mu2 * n2 * C[CR2]
        cap = f1 + f2

        v1, dth, lam = _moreau_trial(C, th0, v0, a, h, cap)
        if v0 != 0.0 and (v1 == 0.0 or (v1 > 0.0) != (v0 > 0.0)):
            tau, dth = _arrest(C, th0, v0, a, h, cap)
            sign = 1.0 if v0 > 0.0 else -1.0
            S[FF1], S[FF2] = sign * f1 / C[CL], sign * f2 / C[CL]
            _two_phase_update(C, S, th0, dth, 0.0, a, f1, f2)
            S[MODE] = STICK
            if h - tau > 0.0:
                h = h - tau
                continue
            return -1.0
        S[FF1], S[FF2] = lam * f1 / C[CL], lam * f2 / C[CL]

        if v1 == 0.0:
            if rocking_allowed and _start_rocking(C, S, a):
                return h
            S[MODE] = STICK
            S[B1] = S[B2] = S[PTILT] = 0.0
            S[DS1] = S[DS2] = 0.0
            S[SV1] = S[SV2] = 0.0
            return -1.0
        _two_phase_update(C, S, th0, dth, v1, a, f1, f2)
        S[MODE] = SLIP
        return -1.0


def _chain_normal_forces(C, S, a):
    I_P, X0, Z0 = S[CH], S[CH + 1], S[CH + 2]
    rGx0, rGz0, rQx0, rQz0, sign = S[CH + 3], S[CH + 4], S[CH + 5], S[CH + 6], S[CH + 7]
    b, w, g = S[BETA], S[BETAD], C[CG]
    c, s = math.cos(b), math.sin(b)
    alpha = rocking_acceleration(I_P, c * X0 - s * Z0, s * X0 + c * Z0, a, g)
    rGx, rGz = c * rGx0 - s * rGz0, s * rGx0 + c * rGz0
    rQx, rQz = c * rQx0 - s * rQz0, s * rQx0 + c * rQz0
    w2 = w * w
    M, m = C[CM], C[Cm]
    FMx = M * (a - alpha * rQz - w2 * rQx)
    FMz = M * (g + alpha * rQx - w2 * rQz)
    FPx = FMx + m * (a - alpha * rGz - w2 * rGx)
    FPz = FMz + m * (g + alpha * rGx - w2 * rGz)
    ct, st = math.cos(S[TH]), math.sin(S[TH])
    xa, R1, R2 = C[CGA], C[CR1], C[CR2]
    eta1 = math.sqrt(R1 * R1 - xa * xa)
    eta2 = math.sqrt(R2 * R2 - xa * xa)
    n1x, n1z = sign * xa / R1, eta1 / R1
    n2x, n2z = sign * xa / R2, eta2 / R2
    w1x, w1z = ct * n1x - st * n1z, st * n1x + ct * n1z
    w2x, w2z = ct * n2x - st * n2z, st * n2x + ct * n2z
    S[N1] = FPx * w1x + FPz * w1z
    S[N2] = FMx * w2x + FMz * w2z
    S[FF1] = FPx * w1z - FPz * w1x
    S[FF2] = FMx * w2z - FMz * w2x


def _land(C, S, a, h, b0, w0, mu1, mu2):
    I_P, X0, Z0 = S[CH], S[CH + 1], S[CH + 2]
    g = C[CG]
    mid = 0.5 * b0
    c, s = math.cos(mid), math.sin(mid)
    torque = _sinc(mid) * (a * (s * X0 + c * Z0) - g * (c * X0 - s * Z0))
    tau = _smallest_positive_root(0.5 * torque / I_P, w0, b0, h)
    tau = _pmin(_pmax(tau, 0.0), h)
    w_land = w0 + tau * torque / I_P
    S[EIN] -= a * ((1.0 - math.cos(b0)) * X0 + math.sin(b0) * Z0)
    rGx, rGz, rQx, rQz = S[CH + 3], S[CH + 4], S[CH + 5], S[CH + 6]
    ct, st = math.cos(S[TH]), math.sin(S[TH])
    tG = -rGz * ct + rGx * st
    tQ = -rQz * ct + rQx * st
    p = w_land * (C[CM] * C[CL] * tQ + C[Cm] * C[CRHO] * tG + C[CJ])
    v_seat = p / C[CI]
    S[ERS] += 0.5 * I_P * w_land * w_land - 0.5 * C[CI] * v_seat * v_seat
    S[ROCK] = 0.0
    S[BETA] = S[BETAD] = 0.0
    S[THD] = v_seat
    for i in range(8):
        S[CH + i] = 0.0
    beta_land = S[B1]
    if h - tau > 0.0:
        _seated(C, S, a, h - tau, mu1, mu2, False)
    S[MODE] = TILT
    S[B1] = beta_land


def _tilt(C, S, a, h, mu1, mu2):
    I_P, X0, Z0 = S[CH], S[CH + 1], S[CH + 2]
    sign = S[CH + 7]
    g = C[CG]
    b0, w0 = S[BETA], S[BETAD]
    db, w1 = rocking_increment(b0, w0, h, I_P, X0, Z0, -a, -g)
    b1 = b0 + db
    S[MODE] = TILT
    S[B2] = 0.0
    S[DS1] = S[DS2] = 0.0
    S[SV1] = S[SV2] = 0.0
    if sign * b1 > 0.0:
        if sign * (math.cos(b1) * X0 - math.sin(b1) * Z0) <= 0.0:
            S[ERR] = ERR_OVERTURNED
            S[ERRV] = b1
            return
        S[EIN] -= a * ((math.cos(b1) - math.cos(b0)) * X0
                       - (math.sin(b1) - math.sin(b0)) * Z0)
        S[BETA], S[BETAD] = b1, w1
        S[B1] = b1
        S[PTILT] = b1
        _chain_normal_forces(C, S, a)
        return
    _land(C, S, a, h, b0, w0, mu1, mu2)


def step(C, S, A, mu1, mu2):
    """TwoPhaseStepper.step: one step with mu1, mu2 held; returns the
    friction work (J) of the lower and upper interface. S[ERR] != 0 after
    the call: the step must be replayed in Python (S is then garbage)."""
    n = int(S[SN])
    a = A[n]
    dt = C[CDT]
    vx0 = horizontal_momentum(C, S)
    W1_0, W2_0 = S[W1], S[W2]
    if S[ROCK] != 0.0:
        _tilt(C, S, a, dt, mu1, mu2)
    else:
        h = _seated(C, S, a, dt, mu1, mu2, True)
        if h >= 0.0:
            _tilt(C, S, a, h, mu1, mu2)
    if S[ERR] != 0.0:                  # the step is not taken (the caller raises)
        return 0.0, 0.0
    S[FF] = -((C[CM] + C[Cm]) * a + (horizontal_momentum(C, S) - vx0) / dt)
    S[SN] = n + 1
    return S[W1] - W1_0, S[W2] - W2_0


def values(C, S, T, D, out):
    """TwoPhaseStepper.values() written into out[:N_VALUES]."""
    n = int(S[SN])
    L, th = C[CL], S[TH]
    u = L * math.sin(th)
    z = L * (1.0 - math.cos(th))
    v = L * math.cos(th) * S[THD]
    rocking = S[ROCK] != 0.0
    if rocking:
        rQx, rQz = S[CH + 5], S[CH + 6]
        c, s = math.cos(S[BETA]), math.sin(S[BETA])
        u += (c - 1.0) * rQx - s * rQz
        z += s * rQx + (c - 1.0) * rQz
        v = -S[BETAD] * (s * rQx + c * rQz)
    if rocking:
        ekin = 0.5 * S[CH] * S[BETAD] ** C[TWO]
    else:
        ekin = 0.5 * C[CI] * S[THD] ** C[TWO]
    epot = C[CS] * C[CG] * (1.0 - math.cos(th))
    if rocking:
        b = S[BETA]
        epot += C[CG] * (math.sin(b) * S[CH + 1] + (math.cos(b) - 1.0) * S[CH + 2])
    if S[N2] <= 0.0:
        tip = 0.0
    else:
        F_t = S[FF2] if S[MODE] == TILT else S[FF1] + S[FF2]
        tip = abs(F_t) * C[CHC] / (S[N2] * 2.0 * C[CGA])
    out[0], out[1], out[2], out[3], out[4], out[5] = T[n], D[n], u, v, S[FF], z
    out[6], out[7], out[8], out[9] = th, S[B1], C[CR1] * th, C[CR2] * th
    out[10], out[11], out[12], out[13], out[14] = S[N1], S[N2], S[W1], S[W2], S[MODE]
    out[15], out[16], out[17], out[18] = S[EIN], ekin, epot, S[ERS]
    out[19], out[20], out[21], out[22], out[23], out[24] = S[B1], S[B2], S[PTILT], S[DIAG], S[DS1], S[DS2]
    out[25], out[26], out[27], out[28], out[29], out[30] = S[FF1], S[FF2], S[THD], S[SL1], S[SL2], tip


def run_steps(C, S, A, T, D, mu1, mu2, count, rows):
    """count steps with mu1, mu2 held, values() after each into rows[i]
    (tests and benchmarks/two_phase_step.py). Returns the steps taken: fewer
    when S[ERR] is set (that step is not taken)."""
    for i in range(count):
        step(C, S, A, mu1, mu2)
        if S[ERR] != 0.0:
            return i
        values(C, S, T, D, rows[i])
    return count


