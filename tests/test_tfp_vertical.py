"""The planar TFP under vertical ground motion (docs/model.md 10): the field
g + a_z in its normal forces, friction caps, rocking checks and ledger; a zero
vertical record changes nothing; an independent check of regime I against a
scipy ODE of the equivalent pendulum; lift-off of the two-phase model
through the CLI."""
import math
from pathlib import Path

import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.mechanics import tfp_kernel as K
from fpd.mechanics.geometry import G_ACC
from fpd.loading.ground_motion import harmonic_ground_motion
from fpd.mechanics.tfp import TFPGeometry, TFPStepper
from fpd.schema import scene as scn

ROOT = Path(__file__).resolve().parents[1]
V2 = ROOT / "scenes" / "records" / "FERNDALE2022_CE89486.v2"


def tfp(**kw) -> TFPGeometry:
    p = dict(R1=2.235, R2=0.405, R3=0.405, R4=2.235, pad_height=0.076, pad_diameter=0.10,
             slider_height_lower=0.11, slider_height_upper=0.11, slider_diameter=0.30,
             d1=0.20, d2=0.05, d3=0.05, d4=0.20, pad_mass=20.0, slider_mass=80.0, mass=4.0e4)
    p.update(kw)
    return TFPGeometry(**p)


def _ledger(r):
    res = r["E_input_J"] - (r["E_kin_J"] + r["E_pot_J"] + r["W1_J"] + r["W2_J"] + r["W3_J"] + r["W4_J"]
                            + r["E_rim_J"] + (r["E_reseat_J"] if "E_reseat_J" in r.columns else 0.0))
    return np.max(np.abs(res)) / np.max(np.abs(r["E_input_J"]))


@pytest.mark.parametrize("model", ["seated", "two-phase"])
def test_a_zero_vertical_record_reproduces_the_tfp_run_bit_for_bit(tmp_path, model):
    """file_z of zeros on another time grid: the same rows bit for bit, one more
    column (az_mps2, all 0)."""
    zero_vertical_is_the_run(tmp_path, ["solver.duration=4", f"mechanics.model={model}", "thermal.model=lumped"],
                             2000)


def zero_vertical_is_the_run(tmp_path, over, n):
    """tfp-elcentro with ``over`` and a file_z of n zero samples 4 ms apart
    (another time grid): the rows of the run without it bit for bit, then the
    vertical columns, all 0."""
    z = tmp_path / "zero.txt"
    z.write_text("# [g]\n" + "".join(f"{0.004 * k:.3f} 0.0\n" for k in range(n)))
    a = simulate(build(scn.load("tfp-elcentro", over)))
    b = simulate(build(scn.load("tfp-elcentro", over + [f'loading.file_z="{z}"'])))
    assert a.status == b.status == "ok"
    assert list(b.columns) == list(a.columns) + ["az_mps2", "lift_m", "n_lift", "t_flight_s", "E_land_J"]
    np.testing.assert_array_equal(b.data[:, :len(a.columns)], a.data)
    assert np.all(b.data[:, len(a.columns):] == 0.0)


@pytest.mark.parametrize("model", ["seated", "two-phase"])
def test_the_tfp_ledger_closes_with_the_vertical_ground_work(model):
    """El Centro x 2 with Ferndale's vertical channel x 2 (a_z up to 0.22 g, past
    the rims): E_input (horizontal and vertical ground work) = E_kin + E_pot + W
    + E_rim (+ E_reseat) over the whole history to round-off (measured 8e-13
    seated, 3.1e-12 two-phase); the vertical motion changes the run."""
    over = ["solver.duration=40", f"mechanics.model={model}", "thermal.model=lumped", "loading.scale=2"]
    a = simulate(build(scn.load("tfp-elcentro", over)))
    r = simulate(build(scn.load("tfp-elcentro", over + [f'loading.file_z="{V2}"'])))
    assert a.status == r.status == "ok"
    assert np.abs(r["az_mps2"]).max() > 0.2 * G_ACC
    assert _ledger(r) < 1e-11
    assert r["W1_J"][-1] != a["W1_J"][-1]
    # the top normal force follows M (g + a_z) where the stack is nearly upright and slow
    k = np.argmax(np.abs(r["az_mps2"]))
    M = scn.load("tfp-elcentro")["superstructure"]["mass"]
    assert r["N4_N"][k] == pytest.approx(M * (G_ACC + r["az_mps2"][k]), rel=0.03)


def test_the_two_phase_tfp_lifts_off_and_lands_through_the_cli(tmp_path):
    """tfp-elcentro (the two-phase model, El Centro x 1) with a_z = -1.5 g from
    1.001 to 1.2 s (tests/data/pulse_z.txt): the run lifts off once and lands
    (docs/model.md 10; tests/test_tfp_liftoff.py checks the flight), summary
    lift_off says so, the ledger closes with E_land and E_reseat."""
    import json
    import subprocess
    import sys
    out = tmp_path / "out"
    p = subprocess.run([sys.executable, "-m", "fpd", "run", "tfp-elcentro", "--quiet", "--out", str(out),
                        "--set", f'loading.file_z="{ROOT / "tests" / "data" / "pulse_z.txt"}"',
                        "--set", "loading.baseline=false", "--set", "loading.scale=1", "--set", "solver.duration=3",
                        "--set", "thermal.model=lumped", "--set", "output.plots=false"],
                       capture_output=True, text=True, cwd=ROOT)
    assert p.returncode == 0, p.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "ok" and s["models"]["mechanics"] == "two-phase"
    assert s["lift_off"]["count"] == 1 and s["lift_off"]["flight_time_s"] > 0.4
    assert s["energy_residual_rel"] <= 1e-9 and s["heat_residual_rel"] <= 1e-9


# -- independent check: regime I as a pendulum -----------------------------------------

def _regime_I_ode(g, mu, ax, az, t_end, eps=1e-6):
    """Regime I of the seated TFP (the stack held by friction on S1 and S4, the
    pad turning by psi between the slider plates) written out from the bodies:
    the superstructure and the upper slider plate (mass M + m_s) translate on a
    circle of radius L_i = R2 + R3 - h_p about C2, the pad (m_p, centroid at
    b_p = R2 - h_p / 2, inertia J_p) turns with psi. In the ground's frame the
    field is -(a_x, g + a_z) per unit mass:
    I psi'' = -P [(g + a_z) sin psi + a_x cos psi] - (mu2 N2 R2 + mu3 N3 R3) sgn psi',
    I = (M + m_s) L_i^2 + m_p b_p^2 + J_p, P = (M + m_s) L_i + m_p b_p,
    N3 = (M + m_s) [(g + a_z) cos psi - a_x sin psi + L_i psi'^2], N2 = N3 + m_p [... b_p ...]
    (sgn -> tanh(psi' / eps)); Radau at tight tolerance. Returns the peak |u| =
    L_i |sin psi| and the friction work of S2 + S3."""
    from scipy.integrate import solve_ivp
    M, ms, mp = g.mass, g.slider_mass, g.pad_mass
    Li = g.R2 + g.R3 - g.pad_height
    bp = g.R2 - 0.5 * g.pad_height
    Jp = mp * (3 * (0.5 * g.pad_diameter) ** 2 + g.pad_height ** 2) / 12
    I, P = (M + ms) * Li ** 2 + mp * bp ** 2 + Jp, (M + ms) * Li + mp * bp

    def rhs(t, y):
        th, w, _W = y
        gv, a = G_ACC + az(t), ax(t)
        n = gv * math.cos(th) - a * math.sin(th)
        N3 = (M + ms) * (n + Li * w * w)
        N2 = N3 + mp * (n + bp * w * w)
        f = (mu * N2 * g.R2 + mu * N3 * g.R3) * math.tanh(w / eps)
        return [w, (-P * (gv * math.sin(th) + a * math.cos(th)) - f) / I, f * w]

    sol = solve_ivp(rhs, (0.0, t_end), [0.0, 0.0, 0.0], method="Radau", rtol=1e-10, atol=[1e-13, 1e-11, 1e-6],
                    dense_output=True, max_step=2e-3)
    assert sol.success
    th = sol.sol(np.linspace(0.0, t_end, 200001))[0]
    return Li * np.max(np.abs(np.sin(th))), sol.y[2, -1]


def test_regime_I_under_vertical_and_horizontal_harmonics_matches_a_scipy_ode():
    """A seated TFP whose outer surfaces hold (mu1 = mu4 = 0.3) and inner ones
    slide (mu2 = mu3 = 0.04; no rim reached) under x_g = 0.10 sin(2 pi 0.5 t) and a
    vertical harmonic of 0.4 g at 1 Hz: the stepper's peak displacement and the
    friction work of S2 + S3 agree with the pendulum ODE within 0.5 % (dt = 0.5 ms),
    S1 and S4 never slide, and the vertical motion matters (far outside the
    tolerance without it)."""
    g = tfp(d2=0.3, d3=0.3, d1=0.5, d4=0.5)
    T, dt, mu_o, mu_i = 6.0, 5e-4, 0.3, 0.04
    Ax, fx, fz = 0.10, 0.5, 1.0
    Az = 0.4 * G_ACC / (2 * math.pi * fz) ** 2
    wx, wz = 2 * math.pi * fx, 2 * math.pi * fz
    gx = harmonic_ground_motion(Ax, fx, 10, dt, duration=T)
    gz = harmonic_ground_motion(Az, fz, 10, dt, duration=T)

    def run(vertical):
        st = TFPStepper(g, gx, model="seated", gz=gz if vertical else None)
        u, worst = 0.0, 0.0
        for _ in range(st.n_steps):
            st.step(mu_o, mu_i, mu_i, mu_o)
            u = max(u, abs(st.u))
            worst = max(worst, abs(st.ledger_residual()))
            assert st.phi == 0.0
        assert worst < 1e-10 * abs(st.E_in) + 1e-9
        return u, st.W[1] + st.W[2]

    u, W = run(True)
    u0, W0 = run(False)
    u_ode, W_ode = _regime_I_ode(g, mu_i, lambda t: -Ax * wx * wx * math.sin(wx * t),
                                 lambda t: -Az * wz * wz * math.sin(wz * t), T)
    print(u, u_ode, W, W_ode, u0, W0)
    assert abs(u / u_ode - 1) < 5e-3, (u, u_ode)
    assert abs(W / W_ode - 1) < 5e-3, (W, W_ode)
    assert abs(u0 / u - 1) > 0.02 or abs(W0 / W - 1) > 0.02, (u0, u, W0, W)


def test_the_rocking_threshold_scales_with_g_plus_az():
    """Eq. (7) of the two-phase TFP in the field g + a_z: the horizontal ground
    acceleration at which a stack at rest (friction high) starts to rock, found
    by bisection on one step, is proportional to g + a_z: a_z = -0.4 g lowers it
    to 0.6 of its value."""
    g = tfp()
    gx = harmonic_ground_motion(0.1, 1.0, 1, 1e-3)

    def rocks(ax, az):
        st = TFPStepper(g, gx, model="two-phase")
        return K.advance(st.par, st.S, 1e-3, ax, az, 5.0, 5.0, 5.0, 5.0, 0, 0.0, 0.0,
                         st.out, st._M, st._w, st._tmp, st._sc) == K.FAIL_ROCKING

    def threshold(az):
        lo, hi = 0.0, 30.0
        assert rocks(hi, az) and not rocks(lo, az)
        for _ in range(60):
            m = 0.5 * (lo + hi)
            lo, hi = (lo, m) if rocks(m, az) else (m, hi)
        return hi

    c0, c1 = threshold(0.0), threshold(-0.4 * G_ACC)
    assert c1 / c0 == pytest.approx(0.6, rel=1e-9)




# -- rim restitution (device.rim_restitution) ------------------------------------------

def _first_impact(e, dt, mu=0.0):
    """A seated TFP with the outer rims far (d1 = d4 = 1 m), the inner ones near
    (d2 = d3 = 4 mm), launched at rest with alpha' = 1.5 rad/s: the state, E_rim
    and the worst relative ledger residual after the step of the first impact."""
    g = tfp(d1=1.0, d4=1.0, d2=0.004, d3=0.004, rim_restitution=e)
    gx = harmonic_ground_motion(0.0, 1.0, 1, dt, duration=0.2)
    st = TFPStepper(g, gx, model="seated")
    st.S[3] = 1.5
    st.S[K.S_EIN] = st.E_kin()              # the launch's kinetic energy is the input
    worst = 0.0
    for _ in range(st.n_steps):
        st.step(mu, mu, mu, mu)
        worst = max(worst, abs(st.ledger_residual()) / st.E_in)
        if st.E_rim > 0.0:
            return st, st.E_rim, worst
    raise AssertionError("no impact")


@pytest.mark.parametrize("mu", [0.0, 0.02])
def test_a_rim_arrival_with_restitution_takes_1_minus_e2_of_the_normal_kinetic_energy(mu):
    """Newton's restitution at the pad's rim (frictionless, and with friction on
    all four surfaces): the impact hands back e^2 of the kinetic energy normal to
    the rim, T_n = (1/2) d^T M d (d: the stop's jump from the free rates), the
    same T_n whatever e (the motion up to it is the same), so
    E_rim(0) - E_rim(e) = e^2 (E_rim(0) - E_rim(1)) to round-off; the inelastic
    E_rim is T_n up to the rim reaction's work inside the arrival part, so
    E_rim(e) / E_rim(0) -> 1 - e^2 as dt shrinks (its distance from it 2.2e-3 e^2 (3.1e-3 e^2 with friction)
    at dt = 1 ms, 1.1e-4 e^2 at 0.25 ms, frictionless); the pad leaves the rim; the ledger closes; e = 0
    is the inelastic stop of before, bit for bit (a scene with the key = 0 is the
    scene without it)."""
    for dt, tol in ((1e-3, 4e-3), (2.5e-4, 1.5e-4)):
        st0, E0, w0 = _first_impact(0.0, dt, mu)
        st1, E1, _ = _first_impact(1.0, dt, mu)
        assert E1 < 0.005 * E0
        for e in (0.3, 0.7):
            st, E, w = _first_impact(e, dt, mu)
            assert E0 - E == pytest.approx(e * e * (E0 - E1), rel=1e-9)
            assert abs(E / E0 - (1.0 - e * e)) < tol * e * e, (dt, e, E / E0)
            assert st.S[3] * np.sign(st.alpha) < 0.0          # leaving the rim
            assert max(w0, w) < 1e-9
    a = simulate(build(scn.load("tfp-elcentro", ["solver.duration=6", "thermal.model=lumped"])))
    b = simulate(build(scn.load("tfp-elcentro", ["solver.duration=6", "thermal.model=lumped",
                                                 "device.rim_restitution=0"])))
    np.testing.assert_array_equal(a.data, b.data)


def test_rim_restitution_through_a_scene_closes_the_ledger():
    """El Centro x 4 on the packaged TFP with e = 0.5: rims reached, the ledger
    closes to round-off, less is lost at the rims than inelastically."""
    over = ["solver.duration=12", "thermal.model=lumped", "loading.scale=4"]
    a = simulate(build(scn.load("tfp-elcentro", over)))
    b = simulate(build(scn.load("tfp-elcentro", over + ["device.rim_restitution=0.5"])))
    assert a.status == b.status == "ok"
    assert a["E_rim_J"][-1] > 0.0 and b["E_rim_J"][-1] > 0.0
    assert _ledger(b) < 1e-10
    print(a["E_rim_J"][-1], b["E_rim_J"][-1], _ledger(a), _ledger(b))
