"""Closed-form conduction solutions used to verify the plate models.

These are the references of model.md section 7. All return the temperature
*rise* (K) above the initial temperature; ``q`` is the surface flux (W/m2),
``k`` the conductivity, ``kappa`` the diffusivity k / (rho c), depth ``z``
is measured from the heated face into the solid. Sources: Carslaw & Jaeger,
*Conduction of Heat in Solids* (2nd ed.), sections 2.9, 3.9 and 10.5. The
derivation of the footprint-mean disk temperature is in docs/thermal.md.
"""
from __future__ import annotations

import math

import numpy as np
from scipy import special


def ierfc(x):
    """First repeated integral of erfc: exp(-x^2)/sqrt(pi) - x erfc(x)."""
    x = np.asarray(x, dtype=float)
    return np.exp(-x * x) / math.sqrt(math.pi) - x * special.erfc(x)


def halfspace_flux(z, t, q, k, kappa):
    """Semi-infinite solid, constant flux q into z = 0 from t = 0 (C&J 2.9 (7))."""
    z = np.asarray(z, dtype=float)
    s = np.sqrt(kappa * np.asarray(t, dtype=float))
    return (2.0 * q / k) * (s / math.sqrt(math.pi) * np.exp(-z * z / (4 * s * s))
                            - 0.5 * z * special.erfc(z / (2 * s)))


def halfspace_flux_surface(t, q, k, kappa):
    """Surface rise of the half-space: 2 q sqrt(kappa t / pi) / k."""
    return 2.0 * q * np.sqrt(kappa * np.asarray(t, dtype=float) / math.pi) / k


def slab_flux_mean(t, q, rho, c, H):
    """Slab of thickness H, flux q in one face, other face adiabatic:
    the mean rise is q t / (rho c H) exactly (heat balance)."""
    return q * np.asarray(t, dtype=float) / (rho * c * H)


def slab_flux(z, t, q, k, kappa, H, tol=1e-17):
    """Profile of the same slab (C&J 3.9 (3) with y = H - z measured from the
    adiabatic face):

        T - T0 = q t/(rho c H) + (q H/k) [ (3 y^2 - H^2)/(6 H^2)
                 - (2/pi^2) sum_n (-1)^n/n^2 exp(-kappa n^2 pi^2 t/H^2) cos(n pi y/H) ].

    Terms are summed until the exponential drops below ``tol``.
    """
    z = np.atleast_1d(np.asarray(z, dtype=float))
    t = float(t)
    tau = kappa * t / (H * H)
    n_max = int(math.sqrt(-math.log(tol) / (math.pi ** 2 * max(tau, 1e-300)))) + 2
    n_max = min(max(n_max, 1), 200000)
    n = np.arange(1, n_max + 1, dtype=float)
    y = (H - z) / H
    coef = (-1.0) ** n / n ** 2 * np.exp(-tau * (n * math.pi) ** 2)
    series = np.cos(np.pi * np.outer(y, n)) @ coef
    rise = (q * H / k) * (tau + (3 * y * y - 1) / 6 - 2 / math.pi ** 2 * series)
    return rise


def disk_centre(t, q, a, k, kappa):
    """Uniform flux q on a disk of radius a of a half-space's surface (the rest
    adiabatic): temperature rise at the centre of the disk (C&J 10.5 (7)),

        (2 q sqrt(kappa t)/k) [1/sqrt(pi) - ierfc(a / (2 sqrt(kappa t)))],

    tending to q a / k.
    """
    s = np.sqrt(kappa * np.asarray(t, dtype=float))
    return 2.0 * q * s / k * (1.0 / math.sqrt(math.pi) - ierfc(a / (2 * s)))


_GL40 = np.polynomial.legendre.leggauss(40)


def _gauss(f, lo, hi, panels=8):
    """Composite 40-point Gauss-Legendre rule: smooth integrands to round-off,
    and (unlike adaptive quad) a smooth function of its parameters."""
    x, w = _GL40
    edges = np.linspace(lo, hi, panels + 1)
    total = 0.0
    for a0, a1 in zip(edges[:-1], edges[1:]):
        h = 0.5 * (a1 - a0)
        total += h * np.sum(w * f(a0 + h * (x + 1.0)))
    return total


def _ive1(w):
    """exp(-w) I1(w); scipy returns nan beyond ~1e10, where the asymptotic
    series is exact to round-off."""
    w = np.asarray(w, dtype=float)
    big = w > 1e6
    safe = np.where(big, 1.0, w)
    return np.where(big, (1 - 3 / (8 * w)) / np.sqrt(2 * np.pi * np.where(big, w, 1.0)),
                    special.ive(1, safe))


def _g(p):
    """g(p) = int_0^inf J1(x)^2 exp(-p x^2) / x dx
            = int_0^{1/(2p)} exp(-w) I1(w) / (2 w) dw   (see docs/thermal.md),
    vectorised over p. Up to W = 1/(2p) = 20: two 40-point Gauss panels on
    [0, W]; beyond, 1/2 minus the tail, with w = W / s^2 mapping the w^(-3/2)
    tail onto a smooth integrand on (0, 1]."""
    p = np.atleast_1d(np.asarray(p, dtype=float))
    out = np.full(p.shape, 0.5)
    x, wq = _GL40
    X = 0.5 * (x + 1.0)
    pos = p > 0
    W = np.where(pos, 0.5 / np.where(pos, p, 1.0), np.inf)
    near = pos & (W <= 20.0)
    if near.any():
        Wn = W[near][:, None]
        total = 0.0
        for k in range(2):          # panels [0, W/2], [W/2, W]
            w = Wn * 0.5 * (k + X)
            total = total + 0.25 * Wn[:, 0] * np.sum(wq * special.ive(1, w) / (2 * w), axis=1)
        out[near] = total
    far = pos & (W > 20.0)
    if far.any():
        Wf = W[far][:, None]
        out[far] = 0.5 - 0.5 * np.sum(wq * _ive1(Wf / (X * X)) / X, axis=1)
    return out


def _disk_mean_factor(s):
    """I(s) = int_0^inf J1(x)^2 erf(s x) / x^2 dx = (2/sqrt(pi)) int_0^s g(u^2) du."""
    if s <= 0:
        return 0.0
    val = _gauss(lambda u: _g(u * u), 0.0, min(s, 1.0))
    if s > 1.0:
        # u = 1/v: g(1/v^2)/v^2 -> 1/8 as v -> 0, a smooth integrand
        val += _gauss(lambda v: _g(1.0 / (v * v)) / (v * v), 1.0 / s, 1.0)
    return 2.0 / math.sqrt(math.pi) * val


def disk_mean(t, q, a, k, kappa):
    """Same disk source: temperature rise averaged over the footprint (the
    quantity fed back to friction, model.md section 4):

        T_mean = (2 q a / k) int_0^inf J1(x)^2 erf(x sqrt(kappa t)/a) / x^2 dx,

    the disk average 2 J1(x r/a)/(x) ... of the Hankel-transform surface
    solution of C&J 10.5 (5). Evaluated with an exact reduction to a smooth
    double integral (docs/thermal.md); steady value 8 q a / (3 pi k) and
    short-time limit the 1D value 2 q sqrt(kappa t / pi) / k.
    """
    t_arr = np.atleast_1d(np.asarray(t, dtype=float))
    out = np.array([2 * q * a / k * _disk_mean_factor(math.sqrt(kappa * ti) / a) for ti in t_arr])
    return out if np.ndim(t) else float(out[0])


def lumped_newton(t, P, H, C, T0, T_air):
    """Lumped body C T' = P - H (T - T_air), T(0) = T0 (paper Eq. (9)-(10)):
    T = T_air + P/H + (T0 - T_air - P/H) exp(-H t / C)."""
    t = np.asarray(t, dtype=float)
    if H == 0:
        return T0 + P * t / C
    T_inf = T_air + P / H
    return T_inf + (T0 - T_inf) * np.exp(-H * t / C)


def halfspace_surface(q, t, k, rho, c):
    """halfspace_flux_surface with (q, t, k, rho, c) arguments, the spelling
    benchmarks/run.py uses."""
    return halfspace_flux_surface(t, q, k, k / (rho * c))


# -- moving disk source (model.md section 10) ------------------------------------------
def _overlap_theta(n: int = 200):
    """Gauss nodes on th in (0, pi/2) for r = 2a cos(th): the overlap area of
    two disks of radius a at distance r, A(r) = 2a^2 (th - sin th cos th), is
    then smooth (its sqrt at r = 2a is removed)."""
    x, w = np.polynomial.legendre.leggauss(n)
    th = 0.25 * np.pi * (x + 1.0)
    return th, 0.25 * np.pi * w


def moving_disk_centre(q, a, k, kappa, V):
    """Quasi-steady rise at the centre of a disk of radius a, uniform flux q,
    moving at speed V over a half-space (Jaeger 1942): the moving point source
    P / (2 pi k R) exp(-V (R + xi) / (2 kappa)) integrated over the disk. With
    the angle done analytically (int exp(-b r (1 + cos phi)) dphi =
    2 pi exp(-b r) I0(b r), b = V / (2 kappa)):

        T_c = (q / k) int_0^a exp(-b r) I0(b r) dr,

    q a / k at V = 0 (the stationary disk's steady centre)."""
    b = V / (2.0 * kappa)
    return q / k * _gauss(lambda r: special.ive(0, b * r), 0.0, a)


def moving_disk_mean(q, a, k, kappa, V):
    """Quasi-steady rise averaged over the same moving disk (disk x disk): with
    A(r) the overlap area of two disks of radius a at distance r,

        T_mean = q / (k pi a^2) int_0^2a A(r) exp(-b r) I0(b r) dr,

    8 q a / (3 pi k) at V = 0 (docs/thermal.md, section 8)."""
    b = V / (2.0 * kappa)
    th, w = _overlap_theta()
    r = 2 * a * np.cos(th)
    A = 2 * a * a * (th - np.sin(th) * np.cos(th))
    return q / (k * math.pi * a * a) * float(np.sum(w * A * special.ive(0, b * r) * 2 * a * np.sin(th)))


def moving_disk_transient(t, q, a, k, kappa, V, mean=True, n_tau=400):
    """The same disk switched on at t = 0 and moving at V from then on: the
    rise at time t at its centre (mean=False) or averaged over it (mean=True).
    Superposing instantaneous disk sources on the adiabatic surface of the
    half-space (Green's function 2 / (rho c (4 pi kappa tau)^(3/2)) exp(-d^2 /
    (4 kappa tau))), a source emitted tau ago sits D = V tau behind:

        T = (q / (rho c)) int_0^t dtau / sqrt(pi kappa tau)
            int_0^Rmax w(r) exp(-(r - D)^2 / (4 kappa tau)) ive0(r D / (2 kappa tau)) r dr / (2 kappa tau),

    w(r) = 1 on r < a (centre) or A(r) / (pi a^2) on r < 2a (mean). tau = s^2
    removes the 1/sqrt(tau) singularity; tends to moving_disk_centre /
    moving_disk_mean as t grows (tests)."""
    rho_c = k / kappa
    x, wq = np.polynomial.legendre.leggauss(40)
    if mean:
        th, wt = _overlap_theta(120)
        r = 2 * a * np.cos(th)
        wr = 2 * a * a * (th - np.sin(th) * np.cos(th)) / (math.pi * a * a) * 2 * a * np.sin(th) * wt
    else:
        xr, wr0 = np.polynomial.legendre.leggauss(120)
        r = 0.5 * a * (xr + 1.0)
        wr = 0.5 * a * wr0
    # s = sqrt(tau) on [0, sqrt(t)], panels graded toward s = 0 (the near field)
    S = math.sqrt(t)
    edges = np.concatenate(([0.0], S * np.geomspace(1e-4, 1.0, max(8, n_tau // 40))))
    total = 0.0
    for s0, s1 in zip(edges[:-1], edges[1:]):
        s = s0 + (s1 - s0) * 0.5 * (x + 1.0)
        ws = (s1 - s0) * 0.5 * wq
        tau = s * s
        D = V * tau
        ft = 4 * kappa * tau[:, None]
        arg = r[None, :] * D[:, None] / (0.5 * ft)
        inner = np.sum(wr[None, :] * r[None, :] * np.exp(-(r[None, :] - D[:, None]) ** 2 / ft)
                       * special.ive(0, arg), axis=1) / (0.5 * ft[:, 0])
        # dtau / sqrt(pi kappa tau) = 2 s ds / (sqrt(pi kappa) s) = 2 ds / sqrt(pi kappa)
        total += np.sum(ws * inner) * 2.0 / math.sqrt(math.pi * kappa)
    return q / rho_c * total
