"""The seated reference step (model.md section 2), written once (kernel
module, fpd/kernels.py): a Moreau-type scheme on the one DOF theta; the
derivation is in machines/seated.py's docstring. SeatedStepper holds the
state vector S and the constants C these functions read; SeatedTestMachine
the same, stepped by ``machine_step`` (the imposed displacement), which the
compiled engine calls too (machines/dev_seated_machine.py).
"""
from __future__ import annotations

import math

from fpd.tribology.friction_kernel import dwell_advance, holding_mu_dwell
from fpd.mechanics.phases import SLIP, STICK

__kernel__ = True

# S: the state, in SeatedStepper.save()'s order
SN, ST, TH, THD, SF, N1, N2, W1, W2, EIN, MODE, SV1, SV2 = range(13)
# the lower and upper surface's dwell time (s stuck; friction_kernel.dwell_advance)
SDW1, SDW2 = 13, 14
N_STATE = 15
# C: constants
CDT, CI, CS, CL, CM, Cm, CRHO, CG, CR1, CR2, CITER, TWO = range(12)
# the test machine's: the inertial S (S less M L with the vertical load held) and the riding mass's factor
CSIN, CMV = 12, 13
# the static (breakaway) coefficients of the lower and upper interface (0: none)
CMUS1, CMUS2 = 14, 15
# the compliant link (docs/model.md, "Stick-slip"): the spring's stiffness (0: a rigid
# machine), the plate's mass, sub-steps per step
CLINK, CMPL, CNSUB = 16, 17, 18
# the static coefficients as ratios to the sliding mu at rest (0: none)
CMUR1, CMUR2 = 19, 20
# the dwell law of the static coefficients (friction_kernel.dwell_mu): mu_s after a long
# dwell, the time constant (0: none) and the exponent, lower and upper
CMUI1, CMUI2, CTAU1, CTAU2, CEXP1, CEXP2 = 21, 22, 23, 24, 25, 26
N_CONST = 27
N_VALUES = 17             # len(seated.SEATED_COLUMNS)


def step(C, S, A, mu1, mu2):
    """One step with mu1, mu2 held (A: the ground acceleration per step);
    returns the friction work (J) of the lower and upper interface.

    Friction enters as an impulse with lambda in Sgn(theta'_{n+1}): the step
    sticks exactly or slides with the full cap; positions advance with the
    trapezoidal rule, gravity by the discrete gradient sin(theta_m) sinc(dtheta/2)."""
    dt, I, S_, g = C[CDT], C[CI], C[CS], C[CG]
    L, M, m, rho, R1, R2 = C[CL], C[CM], C[Cm], C[CRHO], C[CR1], C[CR2]
    n = int(S[SN])
    a = A[n]
    th0, v0 = S[TH], S[THD]
    half = 0.5 * dt * v0            # predictor of dtheta / 2
    v1 = v0
    N1_, N2_ = S[N1], S[N2]
    for _ in range(int(C[CITER])):
        thm = th0 + half
        c, s = math.cos(thm), math.sin(thm)
        vm = 0.5 * (v0 + v1)
        N2_ = M * (g * c - a * s + L * vm * vm)
        N1_ = N2_ + m * (g * c - a * s + rho * vm * vm)
        cap = mu1 * N1_ * R1 + mu2 * N2_ * R2
        sinc = math.sin(half) / half if abs(half) > 1e-7 else 1.0 - half * half / 6.0
        drive = -S_ * (a * c + g * s * sinc)
        v_free = v0 + dt * drive / I
        imp = dt * cap / I
        if abs(v_free) <= imp:
            v1 = 0.0
        else:
            v1 = v_free - math.copysign(imp, v_free)
        half = 0.25 * dt * (v0 + v1)
    dth = 2.0 * half
    thm = th0 + half
    c, s = math.cos(thm), math.sin(thm)
    thdd = (v1 - v0) / dt
    # horizontal force of the bearing on the superstructure, against u
    S[SF] = -M * (a + L * (c * thdd - s * (0.5 * (v0 + v1)) ** C[TWO]))
    S[TH] = th0 + dth
    S[THD] = v1
    S[N1], S[N2] = N1_, N2_
    adth = abs(dth)
    dW1 = mu1 * N1_ * R1 * adth
    dW2 = mu2 * N2_ * R2 * adth
    S[W1] += dW1
    S[W2] += dW2
    S[EIN] -= S_ * a * c * dth
    S[MODE] = SLIP if dth != 0.0 else STICK
    S[SV1] = R1 * adth / dt
    S[SV2] = R2 * adth / dt
    S[SN] = n + 1
    S[ST] = (n + 1) * dt
    return dW1, dW2


def machine_point(C, u, ud, udd, gv, mu1, mu2, sgn):
    """The test machine's state at a grid point of the programme (u, u', u''),
    slip sense sgn: theta, theta', theta'', the restraint's force F and the
    normal forces (its axial share F sin(theta) included), cos(theta).
    gv = N / M: the axial load the machine holds there over the superstructure
    mass (g with the load held at M g or riding).

        F L cos(theta) = I theta'' - S_in u'' cos(theta) + S g sin(theta)
                         + M L (gv - g) sin(theta) + cap sgn(theta')
    """
    L, I, S_, g, M, m, rho = C[CL], C[CI], C[CS], C[CG], C[CM], C[Cm], C[CRHO]
    th = math.asin(u / L)
    c, s = math.cos(th), math.sin(th)
    thd = ud / (L * c)
    thdd = (udd + L * s * thd * thd) / (L * c)
    N2_0 = M * (gv * c + C[CMV] * (udd * s + L * thd * thd))
    N1_0 = N2_0 + m * (g * c + udd * s + rho * thd * thd)
    cap0 = mu1 * N1_0 * C[CR1] + mu2 * N2_0 * C[CR2]
    k = mu1 * C[CR1] + mu2 * C[CR2]
    A = I * thdd - C[CSIN] * udd * c + S_ * g * s + M * L * (gv - g) * s
    F = (A + sgn * cap0) / (L * c - sgn * s * k)
    return th, thd, thdd, F, N1_0 + F * s, N2_0 + F * s, c


def machine_step(C, S, U, UD, UDD, SM, UDS, UDDS, GV, mu1, mu2):
    """One step of the test machine (grid point n -> n + 1 of the programme
    U, UD, UDD: u, u', u''); SM[i] != 0 where the machine has stopped the
    bearing, with (UDS[i], UDDS[i]) the programme's smooth branch there: the
    step that reaches the first of them ends with the stopping impulse.
    GV[i] = N / M, the axial-load programme (loading/axial.py) per grid point.
    Returns the friction work (J) of the lower and upper interface, with the
    normal forces averaged over the step.

    The ledger's input is the horizontal restraint's work plus the vertical
    actuator's beyond the weight's, -(N - M g) dz with dz = L sin(theta) dtheta
    (trapezoidal): E_pot keeps the weight's S g (1 - cos theta). With a
    compliant link (C[CLINK] > 0) the machine drives the plate through it
    instead (machines/link_kernel.py)."""
    L, Sin, dt = C[CL], C[CSIN], C[CDT]
    i0 = int(S[SN])
    i1 = i0 + 1
    th0 = S[TH]
    th1 = math.asin(U[i1] / L)
    dth = th1 - th0
    sgn = 1.0 if dth > 0 else (-1.0 if dth < 0 else 0.0)
    _, _, _, Fa, N1a, N2a, ca = machine_point(C, U[i0], UD[i0], UDD[i0], GV[i0], mu1, mu2, sgn)
    th, thd, _, F, N1_, N2_, c = machine_point(C, U[i1], UD[i1], UDD[i1], GV[i1], mu1, mu2, sgn)
    adth = abs(dth)
    dW1 = mu1 * 0.5 * (N1a + N1_) * C[CR1] * adth
    dW2 = mu2 * 0.5 * (N2a + N2_) * C[CR2] * adth
    # ground-frame input: the restraint's generalised force plus the
    # d'Alembert force of the moving lower plate (trapezoidal in theta)
    Q0 = (Fa * L + Sin * UDD[i0]) * ca
    if SM[i1] != 0.0 and SM[i0] == 0.0:
        # the machine stops the bearing inside this step: the smooth branch's
        # input up to the stop, then the stopping impulse, whose work is the
        # kinetic energy it removes (at fixed position)
        _, thd_s, _, F_s, _, _, _ = machine_point(C, U[i1], UDS[i1], UDDS[i1], GV[i1], mu1, mu2, sgn)
        Q1 = (F_s * L + Sin * UDDS[i1]) * c
        S[EIN] += 0.5 * (Q0 + Q1) * dth + 0.5 * C[CI] * (thd * thd - thd_s * thd_s)
    else:
        Q1 = (F * L + Sin * UDD[i1]) * c
        S[EIN] += 0.5 * (Q0 + Q1) * dth
        if dth == 0.0:
            # at rest: a programme that starts again after a hold launches the bearing
            # by an impulse at fixed position, whose work is the kinetic energy it gives
            S[EIN] += 0.5 * C[CI] * (thd * thd - S[THD] * S[THD])
    # the vertical actuator's work beyond the weight's (zero with the load held at M g)
    ML, g = C[CM] * L, C[CG]
    S[EIN] -= 0.5 * (ML * (GV[i0] - g) * math.sin(th0) + ML * (GV[i1] - g) * math.sin(th)) * dth
    hm1 = holding_mu_dwell(mu1, C[CMUS1], C[CMUR1], C[CMUI1], C[CTAU1], C[CEXP1], S[SDW1])
    hm2 = holding_mu_dwell(mu2, C[CMUS2], C[CMUR2], C[CMUI2], C[CTAU2], C[CEXP2], S[SDW2])
    if S[MODE] == STICK and sgn != 0.0 and (hm1 > mu1 or hm2 > mu2):
        # breakaway: the bearing at rest holds until the restraint carries the
        # static cap at the step's start (grown by the time stuck so far); the
        # step's row reports that force, the largest of the step (the sliding
        # law takes over once it moves)
        F = machine_point(C, U[i0], UD[i0], UDD[i0], GV[i0], hm1, hm2, sgn)[3]
    dwell_advance(S, SDW1, dth == 0.0, dt)
    dwell_advance(S, SDW2, dth == 0.0, dt)
    S[TH], S[THD], S[SF], S[N1], S[N2] = th, thd, F, N1_, N2_
    S[W1] += dW1
    S[W2] += dW2
    S[MODE] = SLIP if dth != 0.0 else STICK
    S[SV1] = C[CR1] * adth / dt
    S[SV2] = C[CR2] * adth / dt
    S[SN] = i1
    S[ST] = i1 * dt
    return dW1, dW2


def values(C, S, xg, out):
    """The row of SEATED_COLUMNS into out (xg: the ground displacement now)."""
    th, L = S[TH], C[CL]
    out[0], out[1], out[2] = S[ST], xg, L * math.sin(th)
    out[3], out[4], out[5] = L * math.cos(th) * S[THD], S[SF], L * (1.0 - math.cos(th))
    out[6], out[7], out[8] = th, C[CR1] * th, C[CR2] * th
    out[9], out[10], out[11], out[12], out[13] = S[N1], S[N2], S[W1], S[W2], S[MODE]
    out[14] = S[EIN]
    out[15] = 0.5 * C[CI] * S[THD] ** C[TWO]
    out[16] = C[CS] * C[CG] * (1.0 - math.cos(th))
