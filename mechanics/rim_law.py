"""The rim of finite stiffness, written once (docs/model.md 7, 9): a spring k
on the slide beyond the capacity and its dashpot 2 zeta sqrt(k m_eff), the law
the DFP / SFP kernel (on the tilt) and the flat bearing's kernel (on each slip
coordinate) call. Kernel module (fpd/kernels.py)."""
import math

__kernel__ = True


def overlap(excess):
    """The slide beyond the capacity, excess_+ (excess: slide minus capacity)."""
    return excess if excess > 0.0 else 0.0


def spring_energy(k, o):
    """The energy k o^2 / 2 the spring stores at the overlap o >= 0."""
    return 0.5 * k * o * o


def secant(v0, v1, d):
    """The spring's discrete gradient over an increment d, -(V1 - V0) / d: the
    constant driving force whose work over d is exactly V0 - V1."""
    return -(v1 - v0) / d


def share_beyond(t0, t1):
    """The share of an increment beyond the capacity, from the signed excess
    at its ends (taken linear along it): 1 inside the contact, 0 outside."""
    if t0 > 0.0 and t1 > 0.0:
        return 1.0
    if t0 > 0.0 or t1 > 0.0:
        return max(t0, t1) / abs(t1 - t0)
    return 0.0


def dashpot_coefficient(zeta, k, m_eff):
    """2 zeta sqrt(k m_eff): the dashpot of damping ratio zeta on the spring k."""
    return 2.0 * zeta * math.sqrt(k * m_eff)


def slide(k, c, cap, q, x, h):
    """The rim of a straight slide coordinate (|q| <= cap on either side) over
    the increment x from q, travelled in the time h: (force, dforce/dx, loss),
    the generalised force resisting the slide (the spring's discrete gradient,
    work over x exactly its energy's change, plus the dashpot c on the share
    of x beyond the capacity at the increment's mean rate), its derivative in
    x (for a Newton iteration on x) and the dashpot's loss c f x^2 / h >= 0."""
    s = 1.0 if q + 0.5 * x >= 0.0 else -1.0
    a = s * q - cap
    b = s * (q + x) - cap
    if a > 0.0 and b > 0.0:
        # both ends beyond: (k b^2 / 2 - k a^2 / 2) / x = s k (a + b) / 2, without the
        # cancellation of the two energies (which a short increment would amplify)
        f = s * 0.5 * k * (a + b)
    elif abs(x) > 1e-12 * cap:
        f = -secant(spring_energy(k, overlap(abs(q) - cap)), spring_energy(k, overlap(abs(q + x) - cap)), x)
    else:
        f = s * k * overlap(a)
    if a >= 0.0 and b >= 0.0:
        j = 0.5 * k
    elif b >= 0.0:
        j = 0.5 * k * b * (b - 2.0 * a) / ((b - a) * (b - a))
    elif a >= 0.0:
        j = 0.5 * k * a * a / ((a - b) * (a - b))
    else:
        j = 0.0
    g = share_beyond(a, b) * c / h
    if b > 0.0:
        j += c / h
    return f + g * x, j, g * x * x
