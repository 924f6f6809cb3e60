"""fe1d plate model: convergence against closed forms, ledger, sources, state."""
import math

import numpy as np
import pytest
import scipy.linalg as sl

from fpd.thermal import exact
from fpd.thermal.fe1d import FE1DPlate
from fpd.thermal.params import PlateParams

Q = 1.0e6


def power_of(p):
    return Q * p.contact_area


def semidiscrete(model, power, t):
    """The FE system integrated exactly in time (eigenvectors of A v = l M v),
    so that space and time errors can be measured separately."""
    dM, eM, dA, eA = model._tri
    M = np.diag(dM) + np.diag(eM, 1) + np.diag(eM, -1)
    A = np.diag(dA) + np.diag(eA, 1) + np.diag(eA, -1)
    lam, V = sl.eigh(A, M)
    b = np.zeros(len(dM))
    b[0] = power
    growth = np.where(lam > 1e-12 * lam.max(), -np.expm1(-lam * t) / np.where(lam > 0, lam, 1), t)
    return V @ ((V.T @ M @ model.integ.u) * np.exp(-lam * t) + (V.T @ b) * growth)


def rate(h, err):
    return np.polyfit(np.log(h), np.log(err), 1)[0]


def test_space_order_halfspace():
    """P1 through the thickness, uniform mesh, exact time integration: the
    surface error against the half-space solution at t = 10 s is O(h^2)."""
    errs, hs = [], []
    for n in (25, 50, 100, 200):
        p = PlateParams(model="fe1d", n_elements=n, grading=1.0, back="adiabatic")
        m = FE1DPlate(p, 1.0)
        u = semidiscrete(m, power_of(p), 10.0)
        errs.append(abs(u[0] - exact.halfspace_flux_surface(10.0, Q, p.k, p.diffusivity)))
        hs.append(p.plate_thickness / n)
    assert abs(rate(hs, errs) - 2.0) < 0.1
    assert errs[-1] < 0.02


@pytest.mark.parametrize("scheme,order,bound", [("bdf2", 2.0, 2e-3), ("cn", 2.0, 5e-4), ("be", 1.0, 0.3)])
def test_time_order_halfspace(scheme, order, bound):
    """Time error at t = 10 s against the exact-in-time solution of the same
    mesh (space error removed), plus the total error against the closed form."""
    errs, dts, total = [], [0.4, 0.2, 0.1, 0.05], []
    for dt in dts:
        p = PlateParams(model="fe1d", n_elements=100, back="adiabatic", scheme=scheme)
        m = FE1DPlate(p, dt)
        ref = semidiscrete(m, power_of(p), 10.0)
        for _ in range(int(round(10.0 / dt))):
            m.step(power_of(p), 0.0)
        errs.append(abs(m.integ.u[0] - ref[0]))
        total.append(abs(m.surface_temperature() - p.T0_C
                         - exact.halfspace_flux_surface(10.0, Q, p.k, p.diffusivity)))
    assert abs(rate(dts, errs) - order) < 0.1
    assert errs[-1] < bound
    assert total[-1] < bound + 0.03   # + the default mesh's space error


@pytest.mark.parametrize("scheme", ["bdf2", "cn"])
def test_defaults_meet_0p1K_halfspace(scheme):
    """Default mesh, dt = 1 ms, 1 MW/m2 for 10 s: surface within 0.1 K of the
    half-space solution at every step, the first included (the start-up
    substeps resolve the sqrt(t) onset)."""
    p = PlateParams(model="fe1d", scheme=scheme)
    dt = 1e-3
    m = FE1DPlate(p, dt)
    T = np.array([m.step(power_of(p), 0.0) for _ in range(10000)])
    ex = exact.halfspace_flux_surface(dt * np.arange(1, 10001), Q, p.k, p.diffusivity)
    assert np.max(np.abs(T - p.T0_C - ex)) < 0.1
    assert abs(T[-1] - p.T0_C - ex[-1]) < 0.03


@pytest.mark.parametrize("scheme", ["bdf2", "cn"])
def test_defaults_meet_0p1K_slab(scheme):
    """A 10 mm plate with an adiabatic back (kappa t / H^2 = 0.41 at 10 s):
    surface against the series solution at every step, mean rise exactly
    q t/(rho c H)."""
    H = 0.01
    p = PlateParams(model="fe1d", plate_thickness=H, back="adiabatic", scheme=scheme)
    dt = 1e-3
    m = FE1DPlate(p, dt)
    T = np.array([m.step(power_of(p), 0.0) for _ in range(10000)])
    pick = np.concatenate((np.arange(0, 100), np.arange(100, 10000, 50), [9999]))
    ex = np.array([exact.slab_flux(0.0, dt * (i + 1), Q, p.k, p.diffusivity, H)[0] for i in pick])
    assert np.max(np.abs(T[pick] - p.T0_C - ex)) < 0.1
    mean_rise = m.stored_heat() / (p.rho * p.c * p.contact_area * H)
    assert abs(mean_rise - exact.slab_flux_mean(10.0, Q, p.rho, p.c, H)) < 1e-9 * mean_rise


@pytest.mark.parametrize("scheme", ["bdf2", "cn", "be"])
@pytest.mark.parametrize("back", ["convection", "adiabatic", "fixed"])
def test_heat_ledger_closes(scheme, back):
    """heat_in = stored + lost to round-off, with an on/off varying power and
    a strong back-face coefficient so the loss is a large share."""
    p = PlateParams(model="fe1d", plate_thickness=0.01, n_elements=40, back=back,
                    h_conv=5000.0, T_air_C=20.0, T_back_C=20.0, scheme=scheme)
    m = FE1DPlate(p, 0.05)
    for i in range(400):
        m.step(power_of(p) * max(0.0, np.sin(0.05 * i)), 0.0)
    hin, st, lost = m.heat_in(), m.stored_heat(), m.heat_lost()
    assert hin > 0
    if back != "adiabatic":
        assert lost > 0.05 * hin
    assert abs(hin - st - lost) < 1e-9 * hin


def test_fixed_point_receives_flux_only_while_covered():
    p = PlateParams(model="fe1d", source="fixed-point", radius_m=0.1, a_contact_m=0.05,
                    back="adiabatic", n_elements=40)
    dt = 0.01
    m = FE1DPlate(p, dt)
    P = power_of(p)
    expected = 0.0
    for i in range(300):
        centre = 0.15 * np.sin(2 * np.pi * i * dt)
        covered = abs(centre - 0.1) <= 0.05
        before = m.heat_in()
        T_before = m.surface_temperature()
        Ts = m.step(P, centre)
        assert m.heat_in() - before == pytest.approx(P * dt if covered else 0.0, abs=1e-9)
        if covered:
            expected += P * dt
        elif m.integ.steps > 2:
            assert Ts <= T_before + 1e-12 or m.params.scheme == "bdf2"
    assert expected > 0 and abs(m.heat_in() - expected) < 1e-12 * expected
    assert abs(m.heat_in() - m.stored_heat()) < 1e-9 * expected
    # follow-pad receives everything
    q = FE1DPlate(PlateParams(model="fe1d", a_contact_m=0.05, back="adiabatic", n_elements=40), dt)
    for i in range(300):
        q.step(P, 0.15 * np.sin(2 * np.pi * i * dt))
    assert abs(q.heat_in() - 300 * P * dt) < 1e-9 * q.heat_in()


@pytest.mark.parametrize("scheme", ["bdf2", "cn", "be"])
def test_save_restore_is_bit_identical(scheme):
    p = PlateParams(model="fe1d", scheme=scheme, back="fixed", n_elements=30)
    m = FE1DPlate(p, 0.01)
    for i in range(5):
        m.step(1000.0 * (i % 2), 0.0)
    snap = m.save()
    T1 = m.step(3000.0, 0.0)
    state1 = (m.integ.u.copy(), m.heat_in(), m.heat_lost(), m.stored_heat())
    m.restore(snap)
    T2 = m.step(3000.0, 0.0)
    assert T1 == T2
    assert np.array_equal(state1[0], m.integ.u)
    assert state1[1:] == (m.heat_in(), m.heat_lost(), m.stored_heat())


def test_field_for_vtk():
    m = FE1DPlate(PlateParams(model="fe1d", n_elements=10), 0.01)
    m.step(100.0, 0.0)
    pts, cells, T = m.field()
    assert pts.shape == (11, 3) and cells[0][0] == "line" and cells[0][1].shape == (10, 2)
    assert pts[0, 2] == 0.0 and pts[-1, 2] < 0 and T[0] > T[-1]


def test_plain_cn_rings_rannacher_restores_second_order():
    """Flux switched on at t = 0: plain CN is first order at the surface (the
    stiff modes it excites alternate in sign and hardly decay); the start-up
    backward-Euler substeps at the jump restore second order."""
    dts = [0.4, 0.2, 0.1, 0.05]
    errs = {True: [], False: []}
    for ran in (True, False):
        for dt in dts:
            p = PlateParams(model="fe1d", n_elements=100, back="adiabatic", scheme="cn")
            m = FE1DPlate(p, dt, rannacher=ran)
            ref = semidiscrete(m, power_of(p), 10.0)
            for _ in range(int(round(10.0 / dt))):
                m.step(power_of(p), 0.0)
            errs[ran].append(abs(m.integ.u[0] - ref[0]))
    assert abs(rate(dts, errs[False]) - 1.0) < 0.15 and errs[False][-1] > 0.3
    assert abs(rate(dts, errs[True]) - 2.0) < 0.1 and errs[True][-1] < 5e-4


def test_rannacher_restarts_at_every_switch():
    p = PlateParams(model="fe1d", n_elements=20, scheme="cn", source="fixed-point", radius_m=0.2,
                    a_contact_m=0.05)
    m = FE1DPlate(p, 0.01)
    restarts, was_on = 0, None
    for i in range(200):
        centre = 0.25 * math.sin(2 * math.pi * i / 100)
        on = m.covered(centre)
        restarts += (i == 0) or (on != was_on)    # the start, then every on/off switch
        was_on = on
        m.step(5e3, centre)
    from fpd.thermal.stepping import START_SUBSTEPS
    assert restarts >= 5 and m.integ.half_steps == START_SUBSTEPS * restarts


def test_hot_loop_calls_no_scikit_fem(monkeypatch):
    import skfem

    m = FE1DPlate(PlateParams(model="fe1d", scheme="cn"), 1e-3)

    def boom(*a, **k):
        raise AssertionError("scikit-fem called in step()")
    monkeypatch.setattr(skfem.BilinearForm, "assemble", boom)
    for i in range(10):
        m.step(1e3 * (i % 2), 0.0)


@pytest.mark.parametrize("bad", [dict(back="insulated"), dict(source="moving"), dict(scheme="rk4"),
                                 dict(k=0.0), dict(n_elements=0), dict(n_elements=1000, grading=1.05)])
def test_bad_parameters_raise_one_line(bad):
    with pytest.raises(ValueError) as err:
        FE1DPlate(PlateParams(model="fe1d", **bad), 1e-3)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("n", [2, 3, 40, 350])
def test_band_product_is_the_dense_product(n):
    """column_blas.band_mv (and its compiled twin, bit for bit) against the
    dense symmetric tridiagonal matrix's product: y = a B x and y += a B x
    to round-off (each row sums three products)."""
    from fpd import kernels
    from fpd.thermal import column_blas
    rng = np.random.default_rng(n)
    band = rng.standard_normal((2, n))
    band[0, 0] = np.nan                       # not part of B (upper band storage)
    B = np.diag(band[1]) + np.diag(band[0, 1:], 1) + np.diag(band[0, 1:], -1)
    x, y0 = rng.standard_normal(n), rng.standard_normal(n)
    ref = -0.7 * (B @ x)
    scale = 0.7 * (np.abs(B) @ np.abs(x))
    backends = [column_blas]
    if kernels.available():
        from fpd.thermal import column_blas_numba
        backends.append(column_blas_numba)
    got = []
    for mod in backends:
        y = np.zeros(n)
        mod.band_mv(None, None, -0.7, band, x, 0.0, y)
        assert np.all(np.abs(y - ref) <= 1e-15 * scale)
        z = y0.copy()
        mod.band_mv(None, None, -0.7, band, x, 1.0, z)
        assert np.all(np.abs(z - (y0 + ref)) <= 1e-15 * (scale + np.abs(y0)))
        got.append((y, z))
    for y, z in got[1:]:
        assert np.array_equal(y, got[0][0]) and np.array_equal(z, got[0][1])


@pytest.mark.parametrize("scheme,order,bound", [("bdf2", 2.0, 1e-3), ("cn", 2.0, 3e-4), ("be", 1.0, 0.1)])
def test_time_order_through_switch_off(scheme, order, bound):
    """Flux on for 5 s then off: BDF2 with its conservative load
    G = 3/2 b^{n+1} - 1/2 b^n stays second order through the switch (the
    reference is the exact-in-time response, S(10) - S(5) by superposition)."""
    dts, errs = [0.2, 0.1, 0.05, 0.025], []
    for dt in dts:
        p = PlateParams(model="fe1d", n_elements=100, back="adiabatic", scheme=scheme)
        m = FE1DPlate(p, dt)
        P = power_of(p)
        ref = semidiscrete(m, P, 10.0) - semidiscrete(m, P, 5.0)
        n = int(round(10.0 / dt))
        for i in range(n):
            m.step(P if i < n // 2 else 0.0, 0.0)
        errs.append(abs(m.integ.u[0] - ref[0]))
    assert abs(rate(dts, errs) - order) < 0.1
    assert errs[-1] < bound


@pytest.mark.parametrize("scheme", ["cn", "bdf2"])
def test_smooth_reversals_are_not_jumps(scheme):
    """Power ~ |sin|, as at velocity reversals while sliding: once the load
    scale is known (first half cycle), the smooth passages through zero do
    not restart the stepping; a switch-on from zero after a stick does."""
    p = PlateParams(model="fe1d", n_elements=30, scheme=scheme)
    m = FE1DPlate(p, 1e-3)
    P = power_of(p)
    for i in range(200):
        m.step(P * abs(math.sin(2 * math.pi * i / 400)), 0.0)
    after_first = m.integ.half_steps
    for i in range(200, 1400):
        m.step(P * abs(math.sin(2 * math.pi * i / 400)), 0.0)
    assert m.integ.half_steps == after_first
    for _ in range(50):
        m.step(0.0, 0.0)      # stick: the power drops to zero at once -> restart
    m.step(P, 0.0)            # and comes back at once -> restart
    assert m.integ.half_steps > after_first
