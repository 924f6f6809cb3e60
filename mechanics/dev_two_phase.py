"""The planar two-phase DFP/SFP stepper as the coupled engine sees it
(kernel module, fpd/kernels.py): the device interface every ``dev_*``
module writes (docs/architecture.md, "How to add a device").

    normal(C, S, i), slip(C, S, i)         interface i's normal force (N) and sliding speed (m/s)
    centre(C, S, i) -> (x, y)              its footprint centre on its plate (m)
    step(C, S, L, X, n, dt, mu, dW) -> int one step with the friction coefficients mu[i];
                                           the friction work of each interface into dW;
                                           non-zero (or ok() False): the Python loop replays it
    ok(C, S)                               the state after a step is one the Python loop reaches too
    values(C, S, L, n, dt, row)            the stepper's output columns into row[:n_values]

C, S: the stepper's constants and state (float64 arrays); L: its loading, a
tuple of float64 arrays (here a_step, t, d: TwoPhaseStepper's); X: a tuple
of scratch arrays (unused here). Everything is the stepper's own kernel
(two_phase_kernel): the Python loop and the compiled engine compute the same
numbers.
"""
from fpd.mechanics import two_phase_kernel as tp

__kernel__ = True


def normal(C, S, i):
    if i == 0:
        return S[tp.N1]
    return S[tp.N2]


def slip(C, S, i):
    if i == 0:
        return S[tp.SV1]
    return S[tp.SV2]


def centre(C, S, i):
    """Footprint centres (mech.s1, -mech.s2): the lower plate at +R1 theta, the upper at -R2 theta."""
    th = S[tp.TH]
    if i == 0:
        return C[tp.CR1] * th, 0.0
    return -(C[tp.CR2] * th), 0.0


def step(C, S, L, X, n, dt, mu, dW):
    d1, d2 = tp.step(C, S, L[0], mu[0], mu[1])
    dW[0] = d1
    dW[1] = d2
    return 0


def ok(C, S):
    """No error flag, every value finite, and values() can neither overflow
    (theta'^2 and beta'^2 are Python powers, which raise) nor divide by zero
    (the tipping ratio)."""
    if S[tp.ERR] != 0.0:
        return False
    s = 0.0
    for i in range(tp.N_STATE):
        s += S[i] * 0.0
    if s != 0.0:                        # NaN for any non-finite value
        return False
    if abs(S[tp.THD]) > 1e150 or abs(S[tp.BETAD]) > 1e150:
        return False
    if S[tp.N2] > 0.0 and S[tp.N2] * 2.0 * C[tp.CGA] == 0.0:
        return False
    return True


def values(C, S, L, n, dt, row):
    tp.values(C, S, L[1], L[2], row)
