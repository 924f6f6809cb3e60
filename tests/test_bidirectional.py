"""Bidirectional DFP steppers (mechanics/bidirectional*.py, model.md section 8).

Fast versions of every check run by default; the long studies are slow.
"""
from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest

from fpd import kernels
from fpd.mechanics.bidirectional import BidirectionalStepper, COLUMNS
from fpd.mechanics.geometry import G_ACC, DeviceGeometry
from fpd.loading.ground_motion import GroundMotion, harmonic_ground_motion
from fpd.mechanics.two_phase import TwoPhaseStepper
from tests.records_helper import elcentro, pulse

DEVICE = DeviceGeometry("DFP", R1=2.2, R2=2.2, pad_height=0.10, pad_diameter=0.25,
                        pad_mass=30.0, mass=1.0e5)
HARSH = DeviceGeometry("DFP", R1=1.0, R2=1.0, pad_height=0.10, pad_diameter=0.25,
                       pad_mass=30.0, mass=1.0e5)
TALL_PAD = DeviceGeometry("DFP", R1=2.2, R2=2.2, pad_height=0.50, pad_diameter=0.10,
                          pad_mass=30.0, mass=1.0e5)
COL = {c: i for i, c in enumerate(COLUMNS)}
JIT = kernels.available()


def zero_like(g: GroundMotion) -> GroundMotion:
    z = np.zeros_like(g.t)
    return GroundMotion("zero", g.dt, g.t, z, z.copy(), z.copy(), np.zeros_like(g.a_step))


def rotated(g: GroundMotion, angle: float):
    """The x component g turned by angle: (cos, sin) times it."""
    c, s = math.cos(angle), math.sin(angle)
    mk = lambda f: GroundMotion(g.name, g.dt, g.t, f * g.d, f * g.v, f * g.a, f * g.a_step)  # noqa: E731
    return mk(c), mk(s)


def harsh(dt: float, cycles: float = 3.0) -> GroundMotion:
    """The harsh harmonic: 0.6 g peak ground acceleration at 0.5 Hz (R = 1 m device)."""
    w = 2.0 * math.pi * 0.5
    return harmonic_ground_motion(0.6 * G_ACC / w ** 2, 0.5, cycles, dt)


def history(geom, gx, gy=None, mu=0.05, normal_force="midpoint", jit=False):
    st = BidirectionalStepper(geom, gx, gy, normal_force=normal_force, jit=jit)
    rows = [st.values()]
    for _ in range(st.n_steps):
        st.step(mu, mu)
        rows.append(st.values())
    return np.array(rows), st


def planar_history(geom, g, mu=0.05):
    st = TwoPhaseStepper(geom, g)
    rows = [st.values()]
    for _ in range(st.n_steps):
        st.step(mu, mu)
        rows.append(st.values())
    cols = {c: i for i, c in enumerate(st.columns)}
    return np.array(rows), cols, st


# -- the planar model is the special case --------------------------------------------

@pytest.mark.parametrize("ground", ["elcentro", "harsh"])
def test_zero_y_start_scheme_reproduces_planar_stepper(ground):
    """'start' with a zero y component is today's planar TwoPhaseStepper to
    1e-12 relative (each series against its own peak; the re-seating loss,
    a difference of squares, against the input work)."""
    g = elcentro(1e-3, duration=8.0) if ground == "elcentro" else harsh(2e-3, cycles=1.0)
    geom = DEVICE if ground == "elcentro" else HARSH
    P, pc, ps = planar_history(geom, g)
    B, bs = history(geom, g, zero_like(g), normal_force="start")
    assert np.all(B[:, COL["uy_m"]] == 0.0) and np.all(B[:, COL["Fy_N"]] == 0.0)
    pairs = [("u_m", "ux_m"), ("v_mps", "vx_mps"), ("F_N", "Fx_N"), ("N1_N", "N1_N"), ("N2_N", "N2_N"),
             ("W1_J", "W1_J"), ("W2_J", "W2_J"), ("E_input_J", "E_input_J"), ("z_m", "z_m"),
             ("E_kin_J", "E_kin_J"), ("E_pot_J", "E_pot_J")]
    for pcol, bcol in pairs:
        ref = P[:, pc[pcol]]
        err = np.max(np.abs(B[:, COL[bcol]] - ref)) / np.max(np.abs(ref))
        assert err <= 1e-12, (pcol, err)
    scale = np.max(np.abs(P[:, pc["E_input_J"]]))
    assert np.max(np.abs(B[:, COL["E_reseat_J"]] - P[:, pc["E_reseat_J"]])) <= 1e-12 * scale
    np.testing.assert_array_equal(B[:, COL["phase"]], P[:, pc["phase"]])
    assert np.max(np.abs(np.abs(B[:, COL["theta_rad"]]) - np.abs(P[:, pc["theta_rad"]]))) <= 1e-12


def test_rotating_the_ground_rotates_the_response():
    """Isotropy: the x record turned by 37 degrees gives the x response turned
    by 37 degrees (same work, same resultants), to round-off."""
    g = elcentro(2e-3, duration=6.0)
    A, _ = history(DEVICE, g, zero_like(g))
    gx, gy = rotated(g, math.radians(37.0))
    B, _ = history(DEVICE, gx, gy)
    c, s = math.cos(math.radians(37.0)), math.sin(math.radians(37.0))
    peak = np.max(np.abs(A[:, COL["ux_m"]]))
    assert np.max(np.abs(B[:, COL["ux_m"]] - c * A[:, COL["ux_m"]])) <= 1e-10 * peak
    assert np.max(np.abs(B[:, COL["uy_m"]] - s * A[:, COL["ux_m"]])) <= 1e-10 * peak
    for col in ("W1_J", "W2_J", "F_N", "N1_N"):
        ref = A[:, COL[col]]
        assert np.max(np.abs(B[:, COL[col]] - ref)) <= 1e-9 * np.max(np.abs(ref)), col


@pytest.mark.skipif(not JIT, reason="numba not installed")
def test_compiled_kernel_matches_pure_path():
    """One source: the compiled kernel gives the pure path's numbers."""
    gx, gy = rotated(elcentro(2e-3, duration=5.0), 0.4)
    A, _ = history(DEVICE, gx, gy, jit=False)
    B, _ = history(DEVICE, gx, gy, jit=True)
    assert np.max(np.abs(A - B) / (1.0 + np.max(np.abs(A), axis=0))) <= 1e-12


def test_ledger_closes_to_the_scheme_order():
    """Energy ledger of the midpoint scheme on a two-component input: the
    residual over the whole history is small (it closes up to the
    d - atan(d) of the re-seating), and shrinks with dt."""
    worst = []
    for dt in (2e-3, 1e-3):
        gx, gy = rotated(elcentro(dt, duration=6.0), 0.7)
        H, st = history(DEVICE, gx, gy)
        res = H[:, COL["E_input_J"]] - (H[:, COL["E_kin_J"]] + H[:, COL["E_pot_J"]] + H[:, COL["W1_J"]]
                                         + H[:, COL["W2_J"]] + H[:, COL["E_reseat_J"]])
        worst.append(np.max(np.abs(res)) / np.max(H[:, COL["E_input_J"]]))
    assert worst[0] < 1e-5 and worst[1] < worst[0]


@pytest.mark.parametrize("amp, mu", [(0.3, 0.6), (0.35, 0.3)])
def test_zero_y_start_scheme_reproduces_planar_rocking(amp, mu):
    """The tall pad rocks on its corner and lands (Eq. 7 chain, made in the
    plane of the trial): 'start' with a zero y component reproduces the
    planar stepper's rocking, landing impact and re-seating to 1e-12."""
    g = pulse(1e-3, amp * G_ACC, 0.3, 1.5)
    P, pc, ps = planar_history(TALL_PAD, g, mu=mu)
    B, bs = history(TALL_PAD, g, zero_like(g), mu=mu, normal_force="start")
    assert (P[:, pc["phase"]] == 2).sum() > 20       # it really rocks
    np.testing.assert_array_equal(B[:, COL["phase"]], P[:, pc["phase"]])
    for pcol, bcol in [("u_m", "ux_m"), ("v_mps", "vx_mps"), ("F_N", "Fx_N"), ("z_m", "z_m"), ("N1_N", "N1_N"),
                       ("N2_N", "N2_N"), ("W1_J", "W1_J"), ("E_input_J", "E_input_J"), ("E_kin_J", "E_kin_J"),
                       ("E_pot_J", "E_pot_J")]:
        ref = P[:, pc[pcol]]
        err = np.max(np.abs(B[:, COL[bcol]] - ref)) / np.max(np.abs(ref))
        assert err <= 1e-12, (pcol, err)
    scale = np.max(np.abs(P[:, pc["E_input_J"]]))
    assert np.max(np.abs(B[:, COL["E_reseat_J"]] - P[:, pc["E_reseat_J"]])) <= 1e-12 * scale
    assert np.max(np.abs(np.abs(B[:, COL["beta_rad"]]) - np.abs(P[:, pc["beta_rad"]]))) <= 1e-12


def test_pad_overturns_as_in_the_planar_stepper():
    from fpd.mechanics.bidirectional import PadOverturned
    from fpd.mechanics.two_phase import PadOverturned as PlanarOverturned
    g = pulse(1e-3, 0.5 * G_ACC, 1.0, 2.0)
    st = BidirectionalStepper(TALL_PAD, g, None, normal_force="start", jit=False)
    with pytest.raises(PadOverturned, match="overturned"):
        for _ in range(st.n_steps):
            st.step(0.6, 0.6)
    n_bi = st.n
    pl = TwoPhaseStepper(TALL_PAD, g)
    with pytest.raises(PlanarOverturned):
        for _ in range(pl.n_steps):
            pl.step(0.6, 0.6)
    assert n_bi == pl.n


def test_rocking_in_a_turned_plane_is_the_planar_rocking_turned():
    """The rocking pulse along 50 degrees: the same rocking, turned."""
    g = pulse(1e-3, 0.3 * G_ACC, 0.3, 1.5)
    A, _ = history(TALL_PAD, g, zero_like(g), mu=0.6)
    gx, gy = rotated(g, math.radians(50.0))
    B, _ = history(TALL_PAD, gx, gy, mu=0.6)
    c, s = math.cos(math.radians(50.0)), math.sin(math.radians(50.0))
    np.testing.assert_array_equal(A[:, COL["phase"]], B[:, COL["phase"]])
    peak = np.max(np.abs(A[:, COL["ux_m"]]))
    assert np.max(np.abs(B[:, COL["ux_m"]] - c * A[:, COL["ux_m"]])) <= 1e-9 * peak
    assert np.max(np.abs(B[:, COL["uy_m"]] - s * A[:, COL["ux_m"]])) <= 1e-9 * peak
    assert np.max(np.abs(B[:, COL["E_reseat_J"]] - A[:, COL["E_reseat_J"]])) <= 1e-9 * np.max(A[:, COL["E_input_J"]])


# -- order ----------------------------------------------------------------------------

def _slope(dts, errs):
    return float(np.polyfit(np.log(dts), np.log(errs), 1)[0])


def _errors(geom, mk, dts, ref_dt, normal_force, mu=0.06):
    def run(dt):
        g = mk(dt)
        st = BidirectionalStepper(geom, g, zero_like(g), normal_force=normal_force, jit=JIT)
        return st.run(mu, mu)
    ref = run(ref_dt)
    eW, eU = [], []
    for dt in dts:
        o = run(dt)
        k = int(round(dt / ref_dt))
        eW.append(abs(o[-1, 2] - ref[-1, 2]) / ref[-1, 2])
        eU.append(np.max(np.abs(o[:, 0] - ref[k - 1::k, 0])))
    return np.array(eW), np.array(eU)


@pytest.mark.skipif(not JIT, reason="numba not installed (the pure path is too slow for this study)")
def test_midpoint_second_order_harsh_harmonic_start_first_order():
    """Friction work on the harsh harmonic (0.6 g, 0.5 Hz, R = 1 m): the
    'midpoint' scheme converges at order >= 1.8, the paper's 'start' scheme
    (N frozen, projection every step) at order ~1."""
    dts = np.array([4e-3, 2e-3, 1e-3])
    eW, eU = _errors(HARSH, lambda dt: harsh(dt, 2.0), dts, 2.5e-4, "midpoint")
    assert _slope(dts, eW) >= 1.8 and eW[-1] < 2e-5
    assert _slope(dts, eU) >= 1.8 and eU[-1] < 2e-4
    eWs, _ = _errors(HARSH, lambda dt: harsh(dt, 2.0), dts, 2.5e-4, "start")
    assert 0.8 < _slope(dts, eWs) < 1.3 and eWs[-1] > 10 * eW[-1]


@pytest.mark.skipif(not JIT, reason="numba not installed (the pure path is too slow for this study)")
def test_midpoint_second_order_el_centro():
    """Friction work on El Centro (first 10 s) converges at order >= 1.8
    (least-squares slope over dt = 4..0.5 ms against 0.0625 ms)."""
    dts = np.array([4e-3, 2e-3, 1e-3, 5e-4])
    eW, eU = _errors(DEVICE, lambda dt: elcentro(dt, duration=10.0), dts, 6.25e-5, "midpoint")
    assert _slope(dts, eW) >= 1.8 and eW[-1] < 2e-5
    assert eU[-1] < 1e-6          # m


def test_summary_energy_residual_is_the_largest_over_the_history():
    """A ledger that is off in the middle and closes at the end is reported
    by its worst row (coupling/history.Stats, summary.json)."""
    from fpd.coupling.recording import Stats
    cols = ["t_s", "E_input_J", "E_kin_J", "E_pot_J", "W1_J", "W2_J", "E_reseat_J"]
    st = Stats(cols)
    st.add(np.array([[0.0, 0, 0, 0, 0, 0, 0], [1.0, 10, 5, 0, 0, 0, 0]]))
    st.add(np.array([[2.0, 10, 0, 0, 6, 4, 0]]))
    assert st.ledger_worst == 5.0 and st.input_worst == 10.0
    assert st.final("E_input_J") - (st.final("W1_J") + st.final("W2_J")) == 0.0


def _pair(dt, duration):
    from fpd.coupling import build
    from fpd.schema import scene
    over = [f"solver.dt={dt}"] + ([f"solver.duration={duration}"] if duration is not None else [])
    s = scene.load("impvall-bidirectional", over)
    return build.bidirectional_loading_of(s, dt)


def test_bearing_force_stays_within_friction_disk_plus_restoring_force():
    """On the two-component record, every step's transmitted force (from the
    momentum balance) is the restoring force plus a friction force inside the
    disk of radius (mu1 N1 R1 + mu2 N2 R2) / L: no impulse is dropped at the
    events where the velocity turns or stops (2D)."""
    gx, gy = _pair(1e-3, 12.0)
    H, st = history(DEVICE, gx, gy, mu=0.06)
    L, W = DEVICE.L, (DEVICE.mass + DEVICE.pad_mass) * G_ACC
    Fr = np.hypot(H[:, COL["Fx_N"]] - W * H[:, COL["ux_m"]] / L, H[:, COL["Fy_N"]] - W * H[:, COL["uy_m"]] / L)
    cap = 0.06 * (H[:, COL["N1_N"]] * DEVICE.R1 + H[:, COL["N2_N"]] * DEVICE.R2) / L
    assert np.all(Fr[1:] <= 1.03 * cap[1:]), float(np.max(Fr[1:] / cap[1:]))


# -- independent model: regularised-friction ODE, scipy Radau ------------------------

def _pair_window(dt, t_start, duration):
    """The packaged pair from t_start on (the bearing is still at rest at
    t_start = 4.5 s: its motion before is < 1e-7 m)."""
    from fpd.loading.ground_motion import ground_motion_from_samples, read_record
    from tests.records_helper import RECORDS
    out = []
    for name in ("IMPVALL_H-E11140.txt", "IMPVALL_H-E11230.txt"):
        rec = read_record(RECORDS / name)
        k0 = int(round(t_start / rec.dt))
        out.append(ground_motion_from_samples(name, rec.t[k0:] - rec.t[k0], rec.a_g[k0:] * G_ACC, dt, duration))
    return out


def _ode_check(duration, dt=1e-3, t_start=4.5):
    from tests.bidirectional_reference import solve_seated
    gx, gy = _pair_window(dt, t_start, duration)
    _, ux, uy, W = solve_seated(DEVICE, gx.t, gx.a, gy.a, 0.06, eps=1e-7)
    st = BidirectionalStepper(DEVICE, gx, gy, jit=JIT)      # two-phase, midpoint: the scene default
    o = st.run(0.06, 0.06)
    peak_s, peak_r = np.max(np.hypot(o[:, 0], o[:, 1])), np.max(np.hypot(ux, uy))
    return peak_s / peak_r - 1.0, o[-1, 2] / W[-1] - 1.0, peak_r


@pytest.mark.filterwarnings("ignore::RuntimeWarning")    # scipy's numerical Jacobian on the stiff friction
def test_two_component_record_against_independent_ode():
    """Imperial Valley pair, 4.5 s to 9.5 s, dt = 1 ms: peak resultant displacement
    within 1 % and friction work within 0.5 % of the regularised-friction ODE
    (measured: ~1e-4 and ~1e-4; the ODE's creep at eps = 1e-7 rad/s is below that)."""
    dpeak, dW, peak = _ode_check(5.0)
    assert peak > 0.01
    assert abs(dpeak) < 1e-2 and abs(dW) < 5e-3
    assert abs(dpeak) < 1e-3 and abs(dW) < 1e-3      # what it really does


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_two_component_record_against_independent_ode_long():
    """The same over 25 s of the pair (through its peak)."""
    dpeak, dW, peak = _ode_check(25.0, t_start=0.0)
    assert peak > 0.1
    assert abs(dpeak) < 1e-2 and abs(dW) < 5e-3


# -- the test machine: circular orbit ---------------------------------------------------

def _circle_work(geom, A=0.2, f=0.5, dt=1e-3, mu=0.05, jit=False):
    from fpd.machines.orbit import BidirectionalTestMachine
    from fpd.loading.orbits import orbit_programme
    prog = orbit_programme("circle", A, f, 3, dt)
    st = BidirectionalTestMachine(geom, prog, jit=jit)
    W = [0.0]
    for _ in range(st.n_steps):
        st.step(mu, mu)
        W.append(st.S[6] + st.S[7])
    per = int(round(1.0 / f / dt))
    return W[2 * per] - W[per], st


def test_circular_orbit_dissipation_closed_form():
    """Energy dissipated per revolution of a circular orbit of radius A at
    constant speed (test machine, seated model): the small-angle closed form
    2 pi A W (mu1 R1 + mu2 R2) / L to 0.5 %, and the exact seated form with
    N_i = W_i / cos(theta) (docs/model.md) to 1e-5."""
    A, mu = 0.2, 0.05
    E, st = _circle_work(DEVICE, A=A, mu=mu)
    L, g = DEVICE.L, G_ACC
    W2, W1 = DEVICE.mass * g, (DEVICE.mass + DEVICE.pad_mass) * g
    small = 2.0 * math.pi * A * (mu * W1 * DEVICE.R1 + mu * W2 * DEVICE.R2) / L
    assert abs(E / small - 1.0) < 5e-3
    cos_t = math.sqrt(1.0 - (A / L) ** 2)
    # massless pad: N_i = W_i / cos(theta) exactly; the pad's mass adds terms O(m/M (A/L)^2)
    assert abs(E / (small / cos_t) - 1.0) < 1e-5
    assert abs(st.N2 * cos_t / W2 - 1.0) < 1e-5
    # the N != W correction is what the closed form misses: 1/cos(theta) - 1 = 0.11 % here
    assert abs(E / small - 1.0) > 0.5 * (1.0 / cos_t - 1.0)
    assert abs(st.energy_residual()) < 1e-5 * E


def test_sine_test_machine_in_a_direction_is_the_planar_one_turned():
    """A sine orbit along 30 degrees gives the x-direction sine's work and
    forces turned by 30 degrees."""
    from fpd.machines.orbit import BidirectionalTestMachine
    from fpd.loading.orbits import orbit_programme
    out = []
    for d in (0.0, 30.0):
        st = BidirectionalTestMachine(DEVICE, orbit_programme("sine", 0.15, 0.5, 2, 2e-3, direction_deg=d))
        for _ in range(st.n_steps):
            st.step(0.05, 0.05)
        out.append((st.S[6] + st.S[7], st.S[12], st.S[13]))
    (W0, Fx0, _), (W1, Fx1, Fy1) = out
    assert abs(W1 / W0 - 1.0) < 1e-12
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    assert abs(Fx1 - c * Fx0) < 1e-9 * abs(Fx0) and abs(Fy1 - s * Fx0) < 1e-9 * abs(Fx0)


def test_vtk_device_3d_pad_sits_on_both_spheres():
    """The 3D device drawing: the pad cylinder's bottom face centre is on the
    lower sphere (C1 + R1 n), its top face centre on the upper one (|p - C2| = R2)."""
    from fpd.outputs.device_drawings import device_3d
    from fpd.thermal.params import PlateParams
    pp = PlateParams(a_contact_m=DEVICE.a)
    L = DEVICE.L
    ux, uy = 0.08, -0.05
    nx, ny = ux / L, uy / L
    n = np.array([nx, ny, -math.sqrt(1 - nx * nx - ny * ny)])
    pts, blocks, bodies = device_3d(DEVICE, (pp, pp), 0.3, 0.1, ux, uy, n)
    assert np.all(np.isfinite(pts)) and bodies == [0, 1, 1, 1, 2, 3]
    C1 = np.array([0.3, 0.1, DEVICE.R1])
    C2 = C1 + L * n
    faces = [pts[c[0]] for kind, c in blocks if kind == "polygon"]
    bottom, top = faces[0].mean(axis=0), faces[1].mean(axis=0)
    assert np.allclose(bottom, C1 + DEVICE.R1 * n, atol=1e-12)
    assert abs(np.linalg.norm(top - C2) - DEVICE.R2) < 1e-12
    # the upper cap's lowest point is the superstructure's apex, over the ground by u
    cap2 = pts[blocks[4][1]].reshape(-1, 3)
    assert np.isclose(cap2[:, 0].mean(), 0.3 + ux) and np.isclose(cap2[:, 1].mean(), 0.1 + uy)


def test_ledger_passes_a_consistent_physics_error(monkeypatch):
    """What the energy ledger cannot see: with N = M g cos(theta) everywhere
    (the d'Alembert and centripetal terms dropped, in the impulse and in the
    work alike) the ledger closes as well as with the right normal forces,
    while the friction work is visibly different. Accuracy is shown by
    convergence and independent models, not by the ledger."""
    import fpd.mechanics.bidirectional_kernel as K

    gx, gy = rotated(harsh(2e-3, cycles=1.0), 0.5)
    right, _ = history(HARSH, gx, gy, mu=0.06)

    def wrong(C, nx, ny, nz, wx, wy, wz, ax, ay, gv):
        N2 = C[K.C_M] * C[K.C_G] * -nz
        return N2 + C[K.C_MP] * C[K.C_G] * -nz, N2

    monkeypatch.setattr(K, "normal_forces", wrong)
    bad, _ = history(HARSH, gx, gy, mu=0.06)

    def worst(H):
        res = H[:, COL["E_input_J"]] - (H[:, COL["E_kin_J"]] + H[:, COL["E_pot_J"]] + H[:, COL["W1_J"]]
                                         + H[:, COL["W2_J"]] + H[:, COL["E_reseat_J"]])
        return np.max(np.abs(res)) / np.max(np.abs(H[:, COL["E_input_J"]]))

    W_right = right[-1, COL["W1_J"]] + right[-1, COL["W2_J"]]
    W_bad = bad[-1, COL["W1_J"]] + bad[-1, COL["W2_J"]]
    # both ~2.5e-6 (the d - atan(d) of the re-seating at dt = 2 ms); the work differs by ~35 %
    assert worst(bad) < 1e-5 and worst(right) < 1e-5 and worst(bad) < 2.0 * worst(right)
    assert abs(W_bad / W_right - 1.0) > 0.1


@pytest.mark.skipif(not JIT, reason="numba not installed")
@pytest.mark.parametrize("thermal", [["thermal.model=fe1d"], ["thermal.model=lumped"],
                                     ["thermal.model=fe1d", "thermal.source=fixed-point", "thermal.radius_m=0.03"]])
def test_compiled_coupled_loop_gives_the_python_loops_rows(monkeypatch, thermal):
    """simulate()'s compiled engine for the bidirectional stepper (coupling/
    engine_kernel.py bound to mechanics/dev_bidirectional.py) writes the rows
    of the Python loop (same kernels, same order), bit for bit."""
    from fpd.coupling import build, run
    from fpd.schema import scene
    from fpd.coupling.run import simulate
    s = scene.load("impvall-bidirectional", ["solver.duration=9.0", "solver.dt=2e-3"] + thermal)
    used = []
    orig = run.compiled_loop

    def spy(*a, **k):
        loop = orig(*a, **k)
        used.append(loop is not None)
        return loop
    monkeypatch.setattr(run, "compiled_loop", spy)
    fast = simulate(build.build(s))
    monkeypatch.setattr(run, "compiled_loop", lambda *a, **k: None)
    slow = simulate(build.build(s))
    assert used == [True] and fast.status == slow.status == "ok"
    np.testing.assert_array_equal(fast.data, slow.data)
    assert np.max(fast["u_m"]) > 0.05


# -- scene keys, the command, outputs ----------------------------------------------------

def _scene(over):
    from fpd.schema import scene
    return scene.load("impvall-bidirectional", over)


@pytest.mark.parametrize("over, needle", [
    (["thermal.model=axisym"], "thermal.model = 'axisym': the axisymmetric plate cannot take the 2D footprint path"),
    (["coupling.substeps=2"], "coupling.substeps = 2: must be 1 for a bidirectional run"),
    (['loading.file_y="nope.AT2"'], "loading.file_y = 'nope.AT2': must not be given with the packaged pair"),
    (['loading.record="impvall"'], "loading.record = 'impvall': must be one of"),
    (['loading.angle_deg="x"'], "loading.angle_deg = 'x': must be a number"),
    (['mechanics.normal_force="end"'], 'mechanics.normal_force = \'end\': must be one of "midpoint", "start"'),
])
def test_bad_bidirectional_keys_are_one_line_errors(over, needle):
    from fpd.schema.scene import SceneError
    with pytest.raises(SceneError) as exc:
        _scene(over)
    msg = str(exc.value)
    assert needle in msg and "\n" not in msg, msg


def test_orbit_longer_than_its_programme_is_refused():
    from fpd.schema import scene
    with pytest.raises(scene.SceneError, match="solver.duration = 10: must not exceed the orbit's length 7.5 s"):
        scene.load("lab-sine", ["loading.waveform=circle", "solver.duration=10"])


def test_scene_defaults_and_kinds(tmp_path):
    from fpd.schema import scene
    s = _scene([])
    assert s["mechanics"]["normal_force"] == "midpoint" and scene.is_bidirectional(s.data)
    d = scene.load("default")
    assert d["mechanics"]["normal_force"] == "midpoint" and not scene.is_bidirectional(d.data)   # every DFP/SFP scene
    assert scene.is_bidirectional(scene.load("default", ["loading.angle_deg=30"]).data)
    lab = scene.load("lab-sine", ["loading.waveform=circle"])
    assert scene.is_bidirectional(lab.data)
    # a file_y next to the scene, relative path
    rec = Path(scene.SCENES_DIR / "records" / "IMPVALL_H-E11230.txt")
    (tmp_path / "y.txt").write_text(rec.read_text())
    (tmp_path / "s.toml").write_text(
        (scene.SCENES_DIR / "impvall-bidirectional.toml").read_text()
        .replace('record = "impvall-1979-e11"', f'file = "{scene.SCENES_DIR / "records" / "IMPVALL_H-E11140.txt"}"'
                 '\nfile_y = "y.txt"'))
    t = scene.load(str(tmp_path / "s.toml"))
    assert t["loading"]["path_y"] == str((tmp_path / "y.txt").resolve())


def test_turned_pair_is_the_pair_turned():
    """angle_deg turns both components of the ground motion (x towards y)."""
    from fpd.coupling import build
    s0, s1 = _scene(["solver.duration=3"]), _scene(["solver.duration=3", "loading.angle_deg=90"])
    (x0, y0), (x1, y1) = build.bidirectional_loading_of(s0, 1e-3), build.bidirectional_loading_of(s1, 1e-3)
    np.testing.assert_allclose(x1.a_step, -y0.a_step, atol=1e-12)
    np.testing.assert_allclose(y1.a_step, x0.a_step, atol=1e-12)


def test_fpd_run_writes_bidirectional_outputs(tmp_path):
    import json
    import subprocess
    import sys
    out = tmp_path / "r"
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[1]))
    p = subprocess.run([sys.executable, "-m", "fpd", "run", "impvall-bidirectional", "--out", str(out), "--quiet",
                        "--set", "solver.duration=9", "--set", "solver.dt=2e-3", "--set", "thermal.model=lumped",
                        "--set", "output.vtk_every=1000"],
                       capture_output=True, text=True, env=env, timeout=300)
    assert p.returncode == 0, p.stderr
    s = json.loads((out / "summary.json").read_text())
    header = (out / "timeseries.csv").open().readline().strip().split(",")
    for c in ("ux_m", "uy_m", "vx_mps", "vy_mps", "Fx_N", "Fy_N", "xg_m", "yg_m", "u_m", "F_N"):
        assert c in header
    import csv
    rows = list(csv.DictReader((out / "timeseries.csv").open()))
    peak = max(math.hypot(float(r["ux_m"]), float(r["uy_m"])) for r in rows)
    assert abs(s["peak_u_m"] - peak) <= 1e-9 * peak
    for png in ("orbit.png", "force_orbit.png", "heat_path.png"):
        assert (out / "plots" / png).stat().st_size > 1000
    assert (out / "vtk" / "device3d.pvd").exists() and len(list((out / "vtk").glob("device3d_*.vtu"))) >= 4
    assert s["energy_residual_rel"] < 1e-6


def test_target_pga_scales_the_pair_as_one():
    """loading.target_pga_g brings the x record's PGA to the target and the y
    record by the same factor: the pair keeps its proportions."""
    from fpd.schema import scene as scn
    from fpd.coupling.build import build

    sim = build(scn.load("impvall-bidirectional", ["solver.duration=0.5", "loading.target_pga_g=0.5",
                                                   'thermal.model="none"']))
    rx, ry = sim.info["record"], sim.info["record_y"]
    assert abs(rx["scaled_pga_g"] - 0.5) < 1e-12
    assert abs(ry["scaled_pga_g"] / rx["scaled_pga_g"] - ry["pga_g"] / rx["pga_g"]) < 1e-12
    # the ground motion itself: both components by the x record's factor
    base = build(scn.load("impvall-bidirectional", ["solver.duration=0.5", 'thermal.model="none"']))
    f = 0.5 / rx["pga_g"]
    for comp in ("ground", "ground_y"):
        a, a0 = getattr(sim.mechanics, comp).a, getattr(base.mechanics, comp).a
        np.testing.assert_allclose(a, f * a0, rtol=1e-9, atol=1e-12 * np.abs(a0).max())


def test_frictionless_swing_through_the_centre_without_ground_motion():
    """mu = 0 and no ground acceleration: nothing turns the velocity, so the
    midpoint scheme's sub-step rule has no event to resolve (it divided by
    zero at the centre); the swing conserves its energy."""
    from fpd.mechanics import bidirectional_kernel as K
    g = zero_like(harsh(1e-3, cycles=0.5))
    st = BidirectionalStepper(DEVICE, g, None, normal_force="midpoint", jit=False)
    st.S[K.S_WX] = 0.05                     # rad/s: swinging out of the centre
    e0 = st.values()[COL["E_kin_J"]] + st.values()[COL["E_pot_J"]]
    for _ in range(st.n_steps):
        st.step(0.0, 0.0)
    r = st.values()
    assert np.all(np.isfinite(r)) and r[COL["ux_m"]] > 0.1
    assert abs(r[COL["E_kin_J"]] + r[COL["E_pot_J"]] - e0) < 1e-8 * e0
