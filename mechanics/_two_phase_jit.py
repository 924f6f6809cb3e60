"""numba translation of the two-phase stepper (mechanics/two_phase.py) and
of the friction laws (mechanics/friction.py), for the compiled coupling loop
(coupling/_loop_jit.py, issue 7).

The reference is the pure-Python TwoPhaseStepper: these functions do the
same floating-point operations in the same order on a float64 state array,
so that the histories agree bit for bit (tests/test_loop_jit.py). Notes on
keeping it so:

- ``x ** 2`` in Python is libm ``pow(x, 2.0)``, which is not always x * x;
  numba turns a literal exponent into a product, so the kernels raise to
  C[TWO] (a run-time 2.0: numba then calls libm's pow like CPython).
- math.sin/cos/atan/exp/sqrt and float ** float go to the same libm.
- No fastmath, so no reassociation or FMA contraction.
- Where Python would raise (division by zero, the pad overturning), the
  kernel sets S[ERR] and the caller replays the step in Python, which raises
  the same exception with the same message. error_model="numpy": a division
  the Python code does not guard gives inf/NaN here instead of a numba
  exception, and the caller replays a step that leaves a non-finite state.

Only numba is imported here (no scipy): the layouts below are filled by
``pack_constants``/``pack_state`` and read back by ``unpack_state``.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import two_phase as _tp
from .phases import DIAGONAL_AC, DIAGONAL_BD, SLIP, STICK, TILT

# -- state S (float64; n, mode, diagonal, rocking stored as exact floats) -------
SN, TH, THD, MODE, DIAG, ROCK, BETA, BETAD = 0, 1, 2, 3, 4, 5, 6, 7
CH = 8                    # the rocking chain: I_P, X0, Z0, rGx, rGz, rQx, rQz, sign (8 slots)
W1, W2, EIN, ERS = 16, 17, 18, 19
B1, B2, PTILT, DS1, DS2, SL1, SL2 = 20, 21, 22, 23, 24, 25, 26
FF1, FF2, FF, N1, N2, SV1, SV2 = 27, 28, 29, 30, 31, 32, 33
ERR = 34                  # 0 ok, 1 a division by zero, 2 the pad overturned
N_STATE = 36

# TwoPhaseStepper._STATE -> slot (the chain is handled apart)
_SLOTS = {"n": SN, "theta": TH, "theta_dot": THD, "mode": MODE, "diagonal": DIAG,
          "rocking": ROCK, "beta": BETA, "beta_dot": BETAD, "W1": W1, "W2": W2,
          "E_input": EIN, "E_reseat": ERS, "beta1": B1, "beta2": B2, "pad_tilt": PTILT,
          "ds1": DS1, "ds2": DS2, "slip1": SL1, "slip2": SL2, "Ff1": FF1, "Ff2": FF2,
          "F": FF, "N1": N1, "N2": N2, "slip_v1": SV1, "slip_v2": SV2}
_INTS = ("n", "mode", "diagonal")

# -- constants C ------------------------------------------------------------------
CL, CRHO, CI, CS, CM, Cm, CJ, CG, CR1, CR2 = 0, 1, 2, 3, 4, 5, 6, 7, 8, 9
CA, CEB, CET, CPH, CR2C = 10, 11, 12, 13, 14     # the corner tuple (a, eta_b, eta_t, h, R2)
CHC, CIT, CDT, TWO, CGA = 15, 16, 17, 18, 19     # h', I_trans, dt, 2.0, geom.a
CBC = 20                                         # body chains A-C, B-D: 2 x 7
CITER, CTOL = 34, 35     # two_phase._FIXED_POINT_ITERS, _TOL (read at run time: a cached kernel
N_CONST = 36             # keeps the globals it was compiled with)

N_VALUES = 31             # len(two_phase.COLUMNS)


def pack_constants(st) -> np.ndarray:
    """The stepper's per-step constants, as the kernels read them."""
    C = np.zeros(N_CONST)
    C[CL], C[CRHO], C[CI], C[CS] = st._L, st._rho, st._I, st._S
    C[CM], C[Cm], C[CJ], C[CG] = st._M, st._m, st._J, st._g
    C[CR1], C[CR2] = st._R1, st._R2
    C[CA:CR2C + 1] = st._corner
    C[CHC], C[CIT], C[CDT], C[TWO], C[CGA] = st._corner_height, st._I_trans, st.dt, 2.0, st.geom.a
    C[CBC:CBC + 7] = st._body_chains[DIAGONAL_AC]
    C[CBC + 7:CBC + 14] = st._body_chains[DIAGONAL_BD]
    C[CITER], C[CTOL] = _tp._FIXED_POINT_ITERS, _tp._FIXED_POINT_TOL
    return C


def ground_arrays(st) -> np.ndarray:
    """(3, len) float64: t, d (both read by values() at step n) and the step
    accelerations a_step (padded)."""
    n = len(st._t)
    G = np.zeros((3, max(n, len(st._a_step))))
    G[0, :n], G[1, :len(st._d)] = st._t, st._d
    G[2, :len(st._a_step)] = st._a_step
    return G


def pack_state(st, S: np.ndarray) -> None:
    for k, i in _SLOTS.items():
        S[i] = float(getattr(st, k))
    S[CH:CH + 8] = st._chain if st._chain is not None else 0.0
    S[ERR] = 0.0


def unpack_state(st, S: np.ndarray) -> None:
    vals = S.tolist()
    for k, i in _SLOTS.items():
        setattr(st, k, int(vals[i]) if k in _INTS else vals[i])
    st.rocking = bool(vals[ROCK])
    st._chain = tuple(vals[CH:CH + 8]) if st.rocking else None


# -- the step ---------------------------------------------------------------------------
@njit(cache=True, nogil=True, error_model="numpy")
def _pmax(a, b):
    """Python's max(a, b) for floats (a unless b > a: the same -0.0 and NaN)."""
    return b if b > a else a


@njit(cache=True, nogil=True, error_model="numpy")
def _pmin(a, b):
    """Python's min(a, b) for floats."""
    return b if b < a else a


@njit(cache=True, nogil=True, error_model="numpy")
def _sinc(x):
    if abs(x) < 1e-4:
        return 1.0 - x * x / 6.0
    return math.sin(x) / x


@njit(cache=True, nogil=True, error_model="numpy")
def _corner_pivot_rotation(S, a, eta_bottom, eta_top, h, R2, shift):
    e = abs(shift)
    px, pz = -a - e, eta_bottom - h + R2
    rx, rz = 2.0 * a, eta_top - eta_bottom
    P = px * rx + pz * rz
    Q = pz * rx - px * rz
    D = a * e - 0.5 * e * e
    disc = Q * Q - D * (2.0 * P + D)
    den = Q + math.sqrt(disc if disc > 0.0 else 0.0)
    if den == 0.0:
        S[ERR] = 1.0
        return 0.0
    tau = D / den
    beta = 2.0 * math.atan(tau)
    return beta if shift >= 0.0 else -beta


@njit(cache=True, nogil=True, error_model="numpy")
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


@njit(cache=True, nogil=True, error_model="numpy")
def horizontal_momentum(C, S):
    if S[ROCK] != 0.0:
        X0, Z0 = S[CH + 1], S[CH + 2]
        b = S[BETA]
        return -S[BETAD] * (math.sin(b) * X0 + math.cos(b) * Z0)
    return C[CS] * math.cos(S[TH]) * S[THD]


@njit(cache=True, nogil=True, error_model="numpy")
def _moreau_trial(C, th0, v0, a, h, cap):
    S_, g = C[CS], C[CG]
    hI = h / C[CI]
    dth = h * v0
    v1, lam = v0, 0.0
    tol = C[CTOL]
    for _ in range(int(C[CITER])):
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


@njit(cache=True, nogil=True, error_model="numpy")
def _arrest(C, th0, v0, a, h, cap):
    S_, g, I = C[CS], C[CG], C[CI]
    sign = 1.0 if v0 > 0.0 else -1.0
    tau = h
    for _ in range(int(C[CITER])):
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


@njit(cache=True, nogil=True, error_model="numpy")
def _two_phase_update(C, S, th0, dth, v1, a, f1, f2):
    I, S_ = C[CI], C[CS]
    S[B1] = _corner_pivot_rotation(S, C[CA], C[CEB], C[CET], C[CPH], C[CR2C], C[CL] * dth)
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


@njit(cache=True, nogil=True, error_model="numpy")
def _start_rocking(C, S, a):
    c, s = math.cos(S[TH]), math.sin(S[TH])
    g = C[CG]
    for diagonal in range(2):
        sign = 1.0 if diagonal == DIAGONAL_AC else -1.0
        o = CBC + 7 * diagonal
        I_P, Xb, Zb = C[o], C[o + 1], C[o + 2]
        rGx, rGz, rQx, rQz = C[o + 3], C[o + 4], C[o + 5], C[o + 6]
        X0, Z0 = c * Xb - s * Zb, s * Xb + c * Zb
        if sign * ((Z0 * a - X0 * g) / I_P) > 0.0:
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


@njit(cache=True, nogil=True, error_model="numpy")
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


@njit(cache=True, nogil=True, error_model="numpy")
def _chain_normal_forces(C, S, a):
    I_P, X0, Z0 = S[CH], S[CH + 1], S[CH + 2]
    rGx0, rGz0, rQx0, rQz0, sign = S[CH + 3], S[CH + 4], S[CH + 5], S[CH + 6], S[CH + 7]
    b, w, g = S[BETA], S[BETAD], C[CG]
    c, s = math.cos(b), math.sin(b)
    alpha = ((s * X0 + c * Z0) * a - (c * X0 - s * Z0) * g) / I_P
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


@njit(cache=True, nogil=True, error_model="numpy")
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


@njit(cache=True, nogil=True, error_model="numpy")
def _tilt(C, S, a, h, mu1, mu2):
    I_P, X0, Z0 = S[CH], S[CH + 1], S[CH + 2]
    sign = S[CH + 7]
    g = C[CG]
    b0, w0 = S[BETA], S[BETAD]
    db = h * w0
    w1 = w0
    tol = C[CTOL]
    for _ in range(int(C[CITER])):
        mid = b0 + 0.5 * db
        c, s = math.cos(mid), math.sin(mid)
        torque = _sinc(0.5 * db) * (a * (s * X0 + c * Z0) - g * (c * X0 - s * Z0))
        w1 = w0 + h * torque / I_P
        db_new = 0.5 * h * (w0 + w1)
        if abs(db_new - db) <= tol:
            db = db_new
            break
        db = db_new
    b1 = b0 + db
    S[MODE] = TILT
    S[B2] = 0.0
    S[DS1] = S[DS2] = 0.0
    S[SV1] = S[SV2] = 0.0
    if sign * b1 > 0.0:
        if sign * (math.cos(b1) * X0 - math.sin(b1) * Z0) <= 0.0:
            S[ERR] = 2.0                 # PadOverturned: the caller replays the step in Python
            return
        S[EIN] -= a * ((math.cos(b1) - math.cos(b0)) * X0
                       - (math.sin(b1) - math.sin(b0)) * Z0)
        S[BETA], S[BETAD] = b1, w1
        S[B1] = b1
        S[PTILT] = b1
        _chain_normal_forces(C, S, a)
        return
    _land(C, S, a, h, b0, w0, mu1, mu2)


@njit(cache=True, nogil=True, error_model="numpy")
def step(C, S, G, mu1, mu2):
    """TwoPhaseStepper.step: one step with mu1, mu2 held; returns the
    friction work (J) of the lower and upper interface. S[ERR] != 0 after
    the call: the step must be replayed in Python (S is then garbage)."""
    n = int(S[SN])
    a = G[2, n]
    dt = C[CDT]
    vx0 = horizontal_momentum(C, S)
    W1_0, W2_0 = S[W1], S[W2]
    if S[ROCK] != 0.0:
        _tilt(C, S, a, dt, mu1, mu2)
    else:
        h = _seated(C, S, a, dt, mu1, mu2, True)
        if h >= 0.0:
            _tilt(C, S, a, h, mu1, mu2)
    S[FF] = -((C[CM] + C[Cm]) * a + (horizontal_momentum(C, S) - vx0) / dt)
    S[SN] = n + 1
    return S[W1] - W1_0, S[W2] - W2_0


@njit(cache=True, nogil=True, error_model="numpy")
def values(C, S, G, out):
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
    out[0], out[1], out[2], out[3], out[4], out[5] = G[0, n], G[1, n], u, v, S[FF], z
    out[6], out[7], out[8], out[9] = th, S[B1], C[CR1] * th, C[CR2] * th
    out[10], out[11], out[12], out[13], out[14] = S[N1], S[N2], S[W1], S[W2], S[MODE]
    out[15], out[16], out[17], out[18] = S[EIN], ekin, epot, S[ERS]
    out[19], out[20], out[21], out[22], out[23], out[24] = S[B1], S[B2], S[PTILT], S[DIAG], S[DS1], S[DS2]
    out[25], out[26], out[27], out[28], out[29], out[30] = S[FF1], S[FF2], S[THD], S[SL1], S[SL2], tip


@njit(cache=True, nogil=True, error_model="numpy")
def run_steps(C, S, G, mu1, mu2, count, rows):
    """count steps with mu1, mu2 held, values() after each into rows[i]
    (tests and benchmarks/two_phase_step.py). Returns the steps taken: fewer
    when S[ERR] is set (that step is not taken)."""
    for i in range(count):
        step(C, S, G, mu1, mu2)
        if S[ERR] != 0.0:
            return i
        values(C, S, G, rows[i])
    return count


# -- friction laws (mechanics.friction) ---------------------------------------------------
LAW_CONSTANT, LAW_LINEAR, LAW_KUMAR, LAW_TABLE = 0, 1, 2, 3
N_LAW = 8                 # slots before a table's points


def pack_law(law) -> np.ndarray | None:
    """The law as a float64 row (kind, parameters), None for an unknown law."""
    from .friction import Constant, Kumar2015, Linear, Table
    t = type(law)
    if t is Constant:
        return np.array([LAW_CONSTANT, law.mu], dtype=float)
    if t is Linear:
        return np.array([LAW_LINEAR, law.mu0, law.T0_C, law.slope_per_C, law.mu_min], dtype=float)
    if t is Kumar2015:
        return np.array([LAW_KUMAR, law.mu_ref, law.p_ref_MPa, law.a_s_per_m, bool(law.use_pressure),
                         bool(law.use_temperature), bool(law.use_velocity)], dtype=float)
    if t is Table:
        n = len(law.T_C)
        if n < 1 or len(law.mu) != n:
            return None
        out = np.zeros(N_LAW + 2 * n)
        out[0], out[1] = LAW_TABLE, n
        out[N_LAW:N_LAW + n] = law.T_C
        out[N_LAW + n:] = law.mu
        return out
    return None


@njit(cache=True, nogil=True, error_model="numpy")
def law_mu(P, T_C, p_Pa, v_mps):
    """mu of the law packed in P (pack_law); NaN where Python would raise
    (a table asked at a NaN temperature): the caller then replays in Python."""
    kind = int(P[0])
    if kind == LAW_CONSTANT:
        return P[1]
    if kind == LAW_LINEAR:
        x = P[1] + P[3] * (T_C - P[2])
        return x if x > P[4] else P[4]          # Python's max(mu_min, x)
    if kind == LAW_KUMAR:
        mu = P[1]
        if P[4] != 0.0:
            mu *= 0.70 ** ((p_Pa * 1e-6 - P[2]) / 50.0)
        if P[5] != 0.0:
            mu *= 0.79 * (0.70 ** (T_C / 50.0) + 0.40)
        if P[6] != 0.0:
            mu *= 1.0 - 0.5 * math.exp(-P[3] * abs(v_mps))
        return mu
    n = int(P[1])
    T0 = N_LAW
    M0 = N_LAW + n
    if T_C <= P[T0]:
        return P[M0]
    if T_C >= P[T0 + n - 1]:
        return P[M0 + n - 1]
    # bisect.bisect_right(T, T_C) - 1
    lo, hi = 0, n
    while lo < hi:
        mid = (lo + hi) // 2
        if T_C < P[T0 + mid]:
            hi = mid
        else:
            lo = mid + 1
    i = lo - 1
    if i + 1 >= n:                               # only for a NaN temperature: Python raises
        return np.nan
    w = (T_C - P[T0 + i]) / (P[T0 + i + 1] - P[T0 + i])
    return P[M0 + i] + w * (P[M0 + i + 1] - P[M0 + i])
