"""The rims' laws, written once (docs/model.md 6, 7, 9). The rim of finite
stiffness: a spring k on the slide beyond the capacity and its dashpot 2
zeta sqrt(k m_eff), the law the DFP / SFP kernel (on the tilt) and the flat
bearing's kernel (on each slip coordinate) call. The rigid rim's impact on
two coordinates (``stop2``): the flat bearing's two slips and the planar
TFP's two rotations. Kernel module (fpd/kernels.py)."""
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


def _targets(v1, v2, o1, o2, e):
    """The rates a stopped coordinate leaves with (-e times its rate into its
    rim; 0 for one not moving into it, and for e = 0)."""
    t1 = -e * v1 if o1 * v1 > 0.0 and e != 0.0 else 0.0
    t2 = -e * v2 if o2 * v2 > 0.0 and e != 0.0 else 0.0
    return t1, t2


def impact_set(m11, m12, m22, v1, v2, o1, o2, e):
    """Which coordinates take an impulse in ``stop2``: 0 none, 1 or 2 that one
    alone (the other keeps its momentum), 3 both."""
    in1 = o1 * v1 > 0.0
    in2 = o2 * v2 > 0.0
    if not in1 and not in2:
        return 0
    p1 = m11 * v1 + m12 * v2
    p2 = m12 * v1 + m22 * v2
    t1, t2 = _targets(v1, v2, o1, o2, e)
    # one rim: its coordinate stopped (and sent back), the other keeps its momentum; the
    # solution if the other then does not move into its own rim faster than its law allows
    # (o t: 0, or -e times its rate into it) and the impulse pushes away
    a2 = (p2 - m12 * t1) / m22
    b1 = (p1 - m12 * t2) / m11
    if in1 and (o2 == 0.0 or (not (o2 * a2 > o2 * t2) and o1 * (m11 * t1 + m12 * a2 - p1) <= 0.0)):
        return 1
    if in2 and (o1 == 0.0 or (not (o1 * b1 > o1 * t1) and o2 * (m12 * b1 + m22 * t2 - p2) <= 0.0)):
        return 2
    return 3


def stop2(m11, m12, m22, v1, v2, o1, o2, e, w):
    """Newton's impact law for two coordinates with the kinetic metric M =
    [[m11, m12], [m12, m22]] (positive definite) and rigid, frictionless
    unilateral stops: o_k = +1 or -1 where coordinate k is on its rim (the
    rim's side), 0 where it is free. Impulses act only on coordinates on a
    rim, each pushing away from it; after them a coordinate that was moving
    into its rim leaves it at -e times its rate, one that was not moves not
    into it, and an impulse is zero where its coordinate leaves faster (the
    linear complementarity problem, whose matrix M^-1 is positive definite:
    its one solution, found among the three active sets). An impulse on
    coordinate k alone keeps the other coordinate's momentum p_j = (M v)_j.
    The velocities after go into w (a stopped coordinate exactly -e times
    its rate, 0 inelastic; a coordinate off its rim is never stopped);
    returns the kinetic energy removed, (1/2) dv^T M (v + w) with dv = v -
    w (e = 0: (1/2) dv^T M dv, the energy of the part stopped, the
    projection being M-orthogonal)."""
    return impact(m11, m12, m22, v1, v2, o1, o2, e, impact_set(m11, m12, m22, v1, v2, o1, o2, e), w)


def impact(m11, m12, m22, v1, v2, o1, o2, e, k, w):
    """``stop2`` with its active set k (``impact_set``) given: the rates after
    into w, the kinetic energy removed returned."""
    w[0] = v1
    w[1] = v2
    if k == 0:
        return 0.0
    t1, t2 = _targets(v1, v2, o1, o2, e)
    if k == 1:
        w[0] = t1
        w[1] = (m12 * v1 + m22 * v2 - m12 * t1) / m22
    elif k == 2:
        w[0] = (m11 * v1 + m12 * v2 - m12 * t2) / m11
        w[1] = t2
    else:
        # both on their rims, both stopped (and sent back)
        w[0] = t1
        w[1] = t2
    d1 = v1 - w[0]
    d2 = v2 - w[1]
    if e == 0.0:
        return 0.5 * (m11 * d1 * d1 + 2.0 * m12 * d1 * d2 + m22 * d2 * d2)
    return 0.5 * (m11 * d1 * (v1 + w[0]) + m12 * (d1 * (v2 + w[1]) + d2 * (v1 + w[0])) + m22 * d2 * (v2 + w[1]))
