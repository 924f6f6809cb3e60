"""Closed forms of model.md section 7 against independent evaluations."""
import math

import numpy as np
import pytest
from scipy import integrate, special

from fpd.thermal import exact

K, KAPPA, RHO, C = 16.0, 16.0 / (7850 * 500), 7850.0, 500.0
Q = 1.0e6


def test_halfspace_surface_is_profile_at_zero():
    t = np.array([0.1, 1.0, 10.0])
    assert np.allclose(exact.halfspace_flux(0.0, t, Q, K, KAPPA),
                       exact.halfspace_flux_surface(t, Q, K, KAPPA), rtol=1e-14)


def test_halfspace_profile_satisfies_flux_and_heat_balance():
    t, z = 5.0, np.linspace(0, 0.05, 20001)
    T = exact.halfspace_flux(z, t, Q, K, KAPPA)
    assert abs(integrate.trapezoid(T, z) * RHO * C - Q * t) < 1e-6 * Q * t
    dz = 1e-7
    grad = (exact.halfspace_flux(dz, t, Q, K, KAPPA) - exact.halfspace_flux(0, t, Q, K, KAPPA)) / dz
    assert abs(-K * grad - Q) < 1e-3 * Q


@pytest.mark.parametrize("t", [0.05, 1.0, 10.0, 100.0])
def test_slab_profile_mean_and_short_time(t):
    H = 0.01
    z = np.linspace(0, H, 4001)
    T = exact.slab_flux(z, t, Q, K, KAPPA, H)
    mean = integrate.simpson(T, x=z) / H
    assert abs(mean - exact.slab_flux_mean(t, Q, RHO, C, H)) < 1e-8 * mean
    if t <= 1.0:   # back face not reached yet: the half-space solution
        assert abs(T[0] - exact.halfspace_flux_surface(t, Q, K, KAPPA)) < 1e-6 * T[0]


def test_slab_profile_adiabatic_back_and_flux_in():
    H, t = 0.01, 3.0
    dz = 1e-7
    g0 = (exact.slab_flux(dz, t, Q, K, KAPPA, H) - exact.slab_flux(0, t, Q, K, KAPPA, H))[0] / dz
    gH = (exact.slab_flux(H, t, Q, K, KAPPA, H) - exact.slab_flux(H - dz, t, Q, K, KAPPA, H))[0] / dz
    assert abs(-K * g0 - Q) < 1e-3 * Q
    assert abs(K * gH) < 1e-3 * Q


@pytest.mark.parametrize("t", [0.3, 3.0, 30.0])
def test_disk_forms_match_hankel_integrals(t):
    """Centre: C&J 10.5 closed form vs (q a/k) int J1(x) erf(sx)/x dx;
    mean: our reduction vs (2 q a/k) int J1(x)^2 erf(sx)/x^2 dx, both by
    brute-force quadrature over 4000 half-periods plus the asymptotic tail."""
    a = 0.01
    s = math.sqrt(KAPPA * t) / a
    X = 4000 * math.pi
    fc = lambda x: special.j1(x) * special.erf(s * x) / x
    fm = lambda x: special.j1(x) ** 2 * special.erf(s * x) / x ** 2
    vc = sum(integrate.quad(fc, i * math.pi, (i + 1) * math.pi)[0] for i in range(4000))
    vm = sum(integrate.quad(fm, i * math.pi, (i + 1) * math.pi)[0] for i in range(4000))
    vm += 1 / (2 * math.pi * X ** 2)
    assert abs(exact.disk_centre(t, Q, a, K, KAPPA) - Q * a / K * vc) < 2e-6 * Q * a / K
    assert abs(exact.disk_mean(t, Q, a, K, KAPPA) - 2 * Q * a / K * vm) < 1e-9 * Q * a / K


def test_disk_limits():
    a = 0.01
    assert abs(exact.disk_centre(1e9, Q, a, K, KAPPA) - Q * a / K) < 1e-3 * Q * a / K
    steady = 8 * Q * a / (3 * math.pi * K)
    assert abs(exact.disk_mean(1e9, Q, a, K, KAPPA) - steady) < 1e-3 * steady
    t = 1e-4   # penetration << a: the 1D half-space value, less the rim's share
    one_d = exact.halfspace_flux_surface(t, Q, K, KAPPA)
    assert abs(exact.disk_centre(t, Q, a, K, KAPPA) - one_d) < 1e-12 * one_d
    assert 0 < one_d - exact.disk_mean(t, Q, a, K, KAPPA) < 2e-3 * one_d


def test_lumped_newton():
    P, H, Cap = 100.0, 2.0, 5000.0
    t = np.array([0.0, 1e3, 1e6])
    T = exact.lumped_newton(t, P, H, Cap, 20.0, 20.0)
    assert T[0] == 20.0 and abs(T[-1] - (20.0 + P / H)) < 1e-9
    dTdt = (exact.lumped_newton(1e3 + 1e-3, P, H, Cap, 20, 20) - T[1]) / 1e-3
    assert abs(Cap * dTdt - (P - H * (T[1] - 20))) < 1e-4


def test_halfspace_surface_alias():
    assert exact.halfspace_surface(Q, 10.0, K, RHO, C) == pytest.approx(
        exact.halfspace_flux_surface(10.0, Q, K, KAPPA), rel=1e-14)


def test_moving_disk_closed_forms_limits():
    """Jaeger's moving disk: at V = 0 the stationary disk's steady centre q a/k
    and mean 8 q a/(3 pi k); the switched-on solution at V = 0 is the
    stationary disk's (C&J 10.5 and the footprint mean) to 1e-12; moving, it
    tends to the quasi-steady values once the disk has travelled far (the
    tail behind it is the slow part at small Peclet numbers)."""
    from fpd.thermal import exact
    q, a, k, kap = 1e6, 0.01, 16.0, 4e-6
    assert abs(exact.moving_disk_centre(q, a, k, kap, 0.0) / (q * a / k) - 1) < 1e-13
    assert abs(exact.moving_disk_mean(q, a, k, kap, 0.0) / (8 * q * a / (3 * math.pi * k)) - 1) < 1e-12
    for t in (0.3, 10.0):
        assert abs(exact.moving_disk_transient(t, q, a, k, kap, 0.0, mean=False)
                   / exact.disk_centre(t, q, a, k, kap) - 1) < 1e-12
        assert abs(exact.moving_disk_transient(t, q, a, k, kap, 0.0, mean=True)
                   / exact.disk_mean(t, q, a, k, kap) - 1) < 1e-12
    for Pe in (0.1, 1.0, 10.0):
        V = 2 * kap * Pe / a
        t = 200 * a / V
        assert abs(exact.moving_disk_transient(t, q, a, k, kap, V, mean=True)
                   / exact.moving_disk_mean(q, a, k, kap, V) - 1) < 1e-4
        assert abs(exact.moving_disk_transient(t, q, a, k, kap, V, mean=False)
                   / exact.moving_disk_centre(q, a, k, kap, V) - 1) < 1e-4
    # faster than the disk's own diffusion the mean tends to the 1D column's value
    V = 2 * kap * 200 / a
    ratio = exact.moving_disk_mean(q, a, k, kap, V) / (8 * q * a / (3 * math.pi * k))
    assert ratio < 0.2
