"""Vertical ground motion (docs/model.md 10): three-component records (CSMIP V2,
loading.file_z), the field g + a_z in the one DFP/SFP stepper, its work in the
ledger, and an independent check against a scipy ODE of the seated pendulum."""
import math
from pathlib import Path

import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.mechanics.bidirectional import BidirectionalStepper
from fpd.mechanics.geometry import G_ACC, DeviceGeometry
from fpd.mechanics.ground_motion import RecordError, harmonic_ground_motion, read_v2
from fpd.schema import scene as scn

ROOT = Path(__file__).resolve().parents[1]
V2 = ROOT / "scenes" / "records" / "FERNDALE2022_CE89486.v2"


def _zero_like(gm):
    import copy
    z = copy.copy(gm)
    z.a_step = np.zeros_like(np.asarray(gm.a_step, dtype=float))
    return z


def _ledger(r):
    res = r["E_input_J"] - (r["E_kin_J"] + r["E_pot_J"] + r["W1_J"] + r["W2_J"] + r["E_rim_J"]
                            + (r["E_reseat_J"] if "E_reseat_J" in r.columns else 0.0))
    return np.max(np.abs(res)) / np.max(np.abs(r["E_input_J"]))


# -- the record ------------------------------------------------------------------------

def test_v2_reader_reads_the_three_ferndale_channels():
    """The packaged CSMIP V2 file: three channels of 10100 points at 0.01 s, in g, with
    the peaks its headers state (-388.166, 261.8, 108.9 cm/s2 at 35.02, 35.95, 32.82 s)."""
    ch = read_v2(V2)
    assert [(n, lab) for n, lab, _ in ch] == [(1, "180 Deg"), (2, "90 Deg"), (3, "Up")]
    for (_n, _lab, rec), pga, t_pk in zip(ch, (0.3958, 0.2670, 0.1110), (35.02, 35.95, 32.82)):
        assert len(rec.t) == 10100 and rec.dt == pytest.approx(0.01)
        assert rec.pga_g == pytest.approx(pga, abs=5e-5)
        assert rec.t[np.argmax(np.abs(rec.a_g))] == pytest.approx(t_pk)
    assert ch[0][2].a_g.min() * 100 * G_ACC == pytest.approx(-388.16556, abs=1e-9)


def _edited_v2(tmp_path, name, edit):
    p = tmp_path / name
    p.write_text(edit(V2.read_text()))
    return p


def test_v2_without_three_channels_or_with_unknown_names_is_refused(tmp_path):
    text = V2.read_text()
    two = _edited_v2(tmp_path, "two.v2", lambda s: s[:s.index("/&  ----------  End of data for channel  2")])
    with pytest.raises(RecordError, match=r"three channels .*found 2: 1: '180 Deg', 2: '90 Deg'"):
        read_v2(two)
    odd = _edited_v2(tmp_path, "odd.v2", lambda s: s.replace("Chan  3:  Up  ", "Chan  3:  Sky "))
    with pytest.raises(RecordError, match=r"not known: 3: 'Sky'"):
        read_v2(odd)
    assert "Chan  3:  Up  " in text
    # through a scene: one line naming the key and what was found
    for f, what in ((two, "found 2"), (odd, "'Sky'")):
        with pytest.raises(scn.SceneError, match=what) as e:
            scn.load("ferndale-3c", [f'loading.file="{f}"'])
        assert "\n" not in str(e.value)


def test_channels_choose_the_components_and_default_to_all_three():
    ld = scn.load("ferndale-3c")["loading"]
    assert ld["channels"] == [1, 2, 3] and ld["path_y"] and ld["path_z"]
    ld = scn.load("ferndale-3c", ["loading.channels=[2, 3]"])["loading"]
    assert ld["channels"] == [2, 0, 3] and "path_y" not in ld and ld["path_z"]
    ld = scn.load("ferndale-3c", ["loading.channels=[2, 1]"])["loading"]
    assert ld["channels"] == [2, 1, 0] and ld["path_y"] and "path_z" not in ld
    for bad, msg in (("[3]", "horizontal channel"), ("[1, 4]", "channel numbers of the record"),
                     ("[1, 1]", "distinct")):
        with pytest.raises(scn.SceneError, match=msg):
            scn.load("ferndale-3c", [f"loading.channels={bad}"])
    with pytest.raises(scn.SceneError, match="CSMIP V2 record only"):
        scn.load("northridge-dfp", ["loading.channels=[1]"])


def test_file_z_is_refused_where_it_cannot_be_taken(tmp_path):
    z = tmp_path / "z.txt"
    z.write_text("# [g]\n0 0.0\n0.01 0.1\n0.02 0.0\n")
    with pytest.raises(scn.SceneError, match=r"loading.file_z.*not yet for this device.*TFP"):
        scn.load("tfp-elcentro", [f'loading.file_z="{z}"'])
    with pytest.raises(scn.SceneError, match=r"loading.channels.*not yet for this device"):
        scn.load("tfp-elcentro", ['loading.record="ferndale-2022"'])
    with pytest.raises(scn.SceneError, match=r"loading.file_z.*vertical one"):
        scn.load("ferndale-3c", [f'loading.file_z="{z}"'])
    with pytest.raises(scn.SceneError, match=r"loading.file_z"):       # a key of records only
        scn.load("sfp-harmonic", [f'loading.file_z="{z}"'])


def test_cli_refuses_a_two_channel_v2_in_one_line_and_writes_nothing(tmp_path):
    import subprocess
    import sys
    two = _edited_v2(tmp_path, "two.v2", lambda s: s[:s.index("/&  ----------  End of data for channel  2")])
    out = tmp_path / "out"
    p = subprocess.run([sys.executable, "-m", "fpd", "run", "ferndale-3c", "--set", f'loading.file="{two}"',
                        "--out", str(out)], capture_output=True, text=True, cwd=ROOT)
    assert p.returncode != 0 and "Traceback" not in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1 and "found 2" in p.stderr
    assert not out.exists()


# -- the stepper: a zero vertical record, the ledger, compiled = pure ------------------

GEOM = DeviceGeometry("DFP", 2.2, 2.2, 0.10, 0.25, 30.0, 1.0e5)


@pytest.mark.parametrize("planar", [True, False])
@pytest.mark.parametrize("normal_force", ["midpoint", "start"])
def test_a_zero_vertical_record_reproduces_the_run_without_one_bit_for_bit(planar, normal_force):
    gx = harmonic_ground_motion(0.12, 0.7, 2, 2e-3)
    a = BidirectionalStepper(GEOM, gx, planar=planar, normal_force=normal_force, jit=False)
    b = BidirectionalStepper(GEOM, gx, planar=planar, normal_force=normal_force, jit=False, gz=_zero_like(gx))
    assert b.columns == a.columns + ("az_mps2",)
    for _ in range(gx.n_steps):
        a.step(0.05, 0.05)
        b.step(0.05, 0.05)
        va, vb = a.values(), b.values()
        assert va == vb[:-1] and vb[-1] == 0.0


def test_zero_file_z_reproduces_the_scene_without_it(tmp_path):
    """Through the scene and the compiled engine when numba is there: file_z of zeros
    on another time grid gives the same rows, bit for bit."""
    z = tmp_path / "zero.txt"
    z.write_text("# [g]\n" + "".join(f"{0.004 * k:.3f} 0.0\n" for k in range(2000)))
    over = ["solver.duration=6", "loading.channels=[1, 2]"]
    a = simulate(build(scn.load("ferndale-3c", over)))
    b = simulate(build(scn.load("ferndale-3c", over + [f'loading.file_z="{z}"'])))
    assert a.status == b.status == "ok"
    cols = [c for c in b.columns if c != "az_mps2"]
    np.testing.assert_array_equal(b.data[:, [b.columns.index(c) for c in cols]],
                                  a.data[:, [a.columns.index(c) for c in cols]])
    assert np.all(b["az_mps2"] == 0.0)


def test_the_ledger_closes_under_three_components():
    """E_input (the work of the horizontal and vertical d'Alembert forces) =
    E_kin + E_pot + W + E_reseat + E_rim to round-off per step, the record at
    4x its scale (a_z up to 0.44 g): the normal forces swing with it. Seated:
    to 1e-11 of the input (measured 5.7e-12); two-phase: no worse than without
    the vertical component (8.2e-9 against 8.3e-9: the two-phase scheme's own
    closure, docs/bidirectional.md)."""
    over = ["solver.duration=40", "loading.scale=4"]
    seated = simulate(build(scn.load("ferndale-3c", over + ["mechanics.model=seated"])))
    assert seated.status == "ok" and _ledger(seated) < 1e-11
    r = simulate(build(scn.load("ferndale-3c", over)))
    r2 = simulate(build(scn.load("ferndale-3c", over + ["loading.channels=[1, 2]"])))
    assert r.status == r2.status == "ok"
    assert _ledger(r) < 1.1 * _ledger(r2) + 1e-12
    W = GEOM.mass * G_ACC
    az = r["az_mps2"]
    assert np.abs(az).max() > 0.4 * G_ACC
    # the upper normal force follows M (g + a_z) (seated, small angles): at the largest a_z
    k = np.argmax(np.abs(az))
    assert r["N2_N"][k] == pytest.approx(W * (1 + az[k] / G_ACC), rel=0.02)
    assert abs(r["N2_N"][k] / r2["N2_N"][k] - 1) > 0.3


# -- independent check: a scipy ODE of the seated SFP ------------------------------------

def _sfp_ode(geom, mu, ax, az, t_end, eps=1e-6):
    """The seated SFP written out from its Lagrangian in the frame of the ground
    (a uniform field -(a_x, g + a_z) per unit mass): theta the tilt of the arm
    C1 -> slider pivot (length L), the slider's centroid on the same arm at rho,
    its spin theta' (inertia J). T = (M L^2 + m rho^2 + J) theta'^2 / 2,
    V = (M L + m rho) [(g + a_z)(1 - cos theta) + a_x sin theta];
    the friction at the surface (lever R about C1) with the normal force from
    each body's radial balance, N = sum m_k ((g + a_z) cos theta - a_x sin theta
    + r_k theta'^2), regularised sgn -> tanh(theta' / eps). Integrated with
    scipy's Radau at tight tolerance; W the friction work."""
    from scipy.integrate import solve_ivp
    M, m = geom.mass, geom.pad_mass
    L, rho = geom.R1 - geom.pad_height, geom.R1 - 0.5 * geom.pad_height
    J = m * (3 * (0.5 * geom.pad_diameter) ** 2 + geom.pad_height ** 2) / 12
    I, S, R, g = M * L * L + m * rho * rho + J, M * L + m * rho, geom.R1, G_ACC

    def rhs(t, y):
        th, w, _W = y
        gv, a = g + az(t), ax(t)
        N = M * (gv * math.cos(th) - a * math.sin(th) + L * w * w) + m * (gv * math.cos(th) - a * math.sin(th)
                                                                          + rho * w * w)
        f = mu * N * R * math.tanh(w / eps)
        return [w, (-S * (a * math.cos(th) + gv * math.sin(th)) - f) / I, f * w]

    sol = solve_ivp(rhs, (0.0, t_end), [0.0, 0.0, 0.0], method="Radau", rtol=1e-10, atol=[1e-13, 1e-11, 1e-6],
                    dense_output=True, max_step=2e-3)
    assert sol.success
    tt = np.linspace(0.0, t_end, 200001)
    th = sol.sol(tt)[0]
    return L * np.max(np.abs(np.sin(th))), sol.y[2, -1]


def test_sfp_under_horizontal_and_vertical_harmonics_matches_a_scipy_ode():
    """SFP (R = 4 m, constant mu = 0.05) under x_g = 0.15 sin(2 pi 0.4 t) and a
    vertical harmonic of 0.4 g at 0.8 Hz (twice the horizontal frequency: the normal force is high in one phase of every half cycle): the stepper's peak displacement and
    friction work agree with the ODE within 0.5 % (measured at dt = 0.5 ms:
    150.048 against 150.057 mm, 32 949.1 against 32 950.1 J, i.e. 6e-5 and
    3e-5), and the vertical motion matters: without it the peak is 17 % larger
    (175.5 mm) and the work 4.3 % smaller, far outside the tolerance."""
    geom = DeviceGeometry("SFP", 4.0, 4.0, 0.08, 0.20, 5.0, 5.0e4)
    T, dt, mu = 6.0, 5e-4, 0.05
    Ax, fx, fz = 0.15, 0.4, 0.8
    Az = 0.4 * G_ACC / (2 * math.pi * fz) ** 2
    wx, wz = 2 * math.pi * fx, 2 * math.pi * fz
    gx = harmonic_ground_motion(Ax, fx, 10, dt, duration=T)
    gz = harmonic_ground_motion(Az, fz, 10, dt, duration=T)

    def run(vertical):
        st = BidirectionalStepper(geom, gx, planar=True, model="seated", gz=gz if vertical else None)
        u = 0.0
        for _ in range(st.n_steps):
            st.step(mu, mu)
            u = max(u, abs(st.u[0]))
        assert abs(st.energy_residual()) < 1e-9 * st.S[8]
        return u, float(st.S[6] + st.S[7])

    u, W = run(True)
    u0, W0 = run(False)
    u_ode, W_ode = _sfp_ode(geom, mu, lambda t: -Ax * wx * wx * math.sin(wx * t),
                            lambda t: -Az * wz * wz * math.sin(wz * t), T)
    assert abs(u / u_ode - 1) < 5e-3, (u, u_ode)
    assert abs(W / W_ode - 1) < 5e-3, (W, W_ode)
    assert abs(u0 / u - 1) > 0.1 and abs(W0 / W - 1) > 0.03, (u0, u, W0, W)


def test_lift_off_stops_the_run_in_one_line(tmp_path):
    """A vertical pulse below -g: the seated model cannot hold the superstructure
    down; the run stops at the step where g + a_z <= 0 (status failed, the history
    so far kept, finite), compiled or not, instead of pulling the pendulum up."""
    z = tmp_path / "pulse.txt"
    z.write_text("# [g]\n0 0.0\n1.0 0.0\n1.001 -1.5\n1.2 -1.5\n1.201 0.0\n3.0 0.0\n")
    r = simulate(build(scn.load("ferndale-3c", ["solver.duration=3", "loading.channels=[1, 2]",
                                                f'loading.file_z="{z}"', "loading.baseline=false"])))
    assert r.status != "ok" and "lift-off at t = 1.0" in r.message and "\n" not in r.message
    assert np.all(np.isfinite(r.data)) and 0.99 < r["t_s"][-1] < 1.01


def test_the_pad_rocking_threshold_scales_with_g_plus_az():
    """Eq. (7) with the vertical field: the horizontal ground acceleration at which
    a stuck pad (mu high) starts to rock, found by bisection on one step from
    rest, is (2a/h') (g + a_z)-proportional: a_z = -0.4 g lowers it to 0.6 of
    its value without vertical motion (26.39 m/s2 for this pad)."""
    from fpd.mechanics import bidirectional_kernel as K
    gx = harmonic_ground_motion(0.1, 1.0, 1, 1e-3)

    def rocks(ax, az):
        st = BidirectionalStepper(GEOM, gx, planar=True, jit=False)
        S = list(st.S)
        K.step(st.C, S, ax, 0.0, az, 1e-3, 5.0, 5.0)
        return S[K.S_ROCK] != 0.0

    def threshold(az):
        lo, hi = 0.0, 60.0
        for _ in range(60):
            m = 0.5 * (lo + hi)
            lo, hi = (lo, m) if rocks(m, az) else (m, hi)
        return hi

    c0, c1 = threshold(0.0), threshold(-0.4 * G_ACC)
    assert 20.0 < c0 < 40.0
    assert c1 / c0 == pytest.approx(0.6, rel=1e-9)
