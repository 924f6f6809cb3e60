"""The flat double bearing (mechanics/flat.py) under vertical ground motion
(docs/model.md 10): every normal force, friction cap and the tipping check see
g + a_z, the vertical ground work is input, g + a_z < 0 lifts the assembly off
(ballistic flight, plastic landing), checked against closed forms."""
import copy
import math
from pathlib import Path

import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.mechanics import flat_kernel as K
from fpd.mechanics.flat import FlatGeometry, FlatStepper
from fpd.mechanics.geometry import G_ACC
from fpd.loading.ground_motion import harmonic_ground_motion
from fpd.schema import scene as scn

PULSE = Path(__file__).resolve().parent / "data" / "pulse_z.txt"   # -1.5 g from 1.001 to 1.2 s
GEOM = FlatGeometry(pad_height=0.10, pad_diameter=0.25, pad_mass=40.0, mass=1.0e5)
VERTICAL = ("az_mps2", "lift_m", "n_lift", "t_flight_s", "E_land_J")


def _with_az(gm, az):
    z = copy.copy(gm)
    z.a_step = np.asarray(az, dtype=float)
    return z


def _harmonic_means(A, f, n, dt):
    """Exact step means of a_z = A sin(2 pi f t) on the grid."""
    w = 2 * math.pi * f
    t = np.arange(n + 1) * dt
    return A * (np.cos(w * t[:-1]) - np.cos(w * t[1:])) / (w * dt)


def test_a_zero_vertical_record_reproduces_the_run_without_one_bit_for_bit():
    gx = harmonic_ground_motion(0.1, 1.0, 3, 1e-3)
    a = FlatStepper(GEOM, gx)
    b = FlatStepper(GEOM, gx, gz=_with_az(gx, np.zeros(gx.n_steps)))
    assert b.columns == a.columns + VERTICAL
    for _ in range(gx.n_steps):
        a.step(0.10, 0.06)
        b.step(0.10, 0.06)
        va, vb = a.values(), b.values()
        assert va == vb[:-5] and vb[-5:] == (0.0,) * 5


def test_a_block_decelerating_under_a_harmonic_az_stops_where_the_closed_form_says():
    """The superstructure launched at v0 on the pad (the pad held by the lower
    face): v' = -mu (g + A sin wt), so v(t) = v0 - mu (g t + A (1 - cos wt) / w)
    and x(t) = v0 t - mu (g t^2 / 2 + A (t / w - sin(wt) / w^2)). The stop time
    t* (v = 0) and the distance x(t*) within 1e-4; the friction work on the way
    mu M int (g + a_z) |du| (recomputed from the closed form) equals it, and the
    kinetic energy M v0^2 / 2, to 1e-4."""
    dt, mu, v0, A, f = 1e-3, 0.1, 1.0, 0.6 * G_ACC, 2.0
    w = 2 * math.pi * f
    gx = harmonic_ground_motion(0.0, 1.0, 3, dt)          # the ground at rest horizontally
    n = gx.n_steps
    assert not np.any(gx.a_step)
    s = FlatStepper(GEOM, gx, gz=_with_az(gx, _harmonic_means(A, f, n, dt)))
    s.S[K.S_V2] = v0
    for _ in range(n):
        s.step(0.9, mu)
        if s.S[K.S_V2] == 0.0:
            break

    def v(t):
        return v0 - mu * (G_ACC * t + A * (1 - math.cos(w * t)) / w)

    from scipy.optimize import brentq
    ts = brentq(v, 0.0, 2.0, xtol=1e-14)
    xs = v0 * ts - mu * (0.5 * G_ACC * ts ** 2 + A * (ts / w - math.sin(w * ts) / w ** 2))
    from scipy.integrate import quad
    W = quad(lambda t: mu * GEOM.mass * (G_ACC + A * math.sin(w * t)) * v(t), 0.0, ts, epsabs=0, epsrel=1e-13)[0]
    assert abs(s.t - ts) <= 1.5 * dt
    assert s.s2 == pytest.approx(xs, rel=1e-4)
    assert s.s1 == 0.0 and abs(s.W1) <= 1e-12 * s.W2       # the pad held (its arrests: round-off)
    assert W == pytest.approx(0.5 * GEOM.mass * v0 ** 2, rel=1e-10)
    assert s.W2 == pytest.approx(W, rel=1e-4)
    # without a_z the block stops elsewhere (the check has teeth)
    assert abs(v0 ** 2 / (2 * mu * G_ACC) - xs) > 100 * 1e-4 * xs


def test_friction_work_under_harmonic_az_is_the_integral_of_mu_n_du():
    """Driven by a horizontal harmonic with a_z = 0.5 g sin(2 pi 1.7 t): the top
    face's work equals sum mu2 M (g + a_z) |du2| over the steps (the arrests'
    share, kinetic energy of a stopping coordinate, added as the ledger books
    it), with a_z the closed-form step means; the lower face never slides; the
    ledger closes to 1e-10 of the input; the normal force column is M (g + a_z)."""
    dt, mu2 = 1e-3, 0.06
    gx = harmonic_ground_motion(0.1, 1.0, 3, dt)
    az = _harmonic_means(0.5 * G_ACC, 1.7, gx.n_steps, dt)
    s = FlatStepper(GEOM, gx, gz=_with_az(gx, az))
    W, worst, N2 = 0.0, 0.0, []
    for n in range(gx.n_steps):
        q2 = s.s2
        s.step(0.5, mu2)
        W += mu2 * GEOM.mass * (G_ACC + az[n]) * abs(s.s2 - q2)
        worst = max(worst, abs(s.ledger_residual()))
        N2.append(s.N2)
    assert s.s1 == 0.0 and abs(s.W1) <= 1e-12 * s.W2 and s.W2 > 0.0
    assert worst <= 1e-10 * s.E_in
    np.testing.assert_allclose(N2, GEOM.mass * (G_ACC + az), rtol=1e-14)
    # the step's arrests (a stopping superstructure's kinetic energy) are the only difference
    assert abs(s.W2 - W) <= 2e-3 * s.W2
    c = FlatStepper(GEOM, gx)
    for _ in range(gx.n_steps):
        c.step(0.5, mu2)
    assert abs(c.W2 - s.W2) > 0.01 * c.W2              # the vertical motion changes the work


def _ballistic(T, k=1.5):
    v, z = (k - 1) * G_ACC * T, 0.5 * (k - 1) * G_ACC * T * T
    v_land = math.sqrt(v * v + 2 * G_ACC * z)
    return T + (v + v_land) / G_ACC, z + v * v / (2 * G_ACC), v_land


def test_a_pulse_below_minus_g_lifts_the_assembly_off_ballistically():
    """a_z = -1.5 g for 0.1 s while the bearing slides: one lift-off, the flight
    time T + (v + sqrt(v^2 + 2 g z)) / g to round-off (within 1 %), the peak
    height, the landing loss (M + m) v_land^2 / 2; in flight no contact
    (normal forces, friction, force 0) and the horizontal motion ballistic
    relative to the ground (q1'' = -a_g, q2' constant); the ledger with
    E_land_J closes to 1e-10 of the input; nothing non-finite."""
    dt, T = 1e-3, 0.1
    gx = harmonic_ground_motion(0.12, 0.7, 3, dt)
    az = np.zeros(gx.n_steps)
    k0 = int(round(1.0 / dt))
    az[k0:k0 + int(round(T / dt))] = -1.5 * G_ACC
    t_f, z_pk, v_land = _ballistic(T)
    Mt = GEOM.mass + GEOM.pad_mass
    s = FlatStepper(GEOM, gx, gz=_with_az(gx, az))
    rows, worst = [], 0.0
    for n in range(gx.n_steps):
        q1, q2, v1, v2 = s.st
        flying = s.S[K.S_FLY] != 0.0 and s.S[K.S_ZF] > 0.0
        s.step(0.08, 0.05)
        if flying and s.S[K.S_FLY] != 0.0:
            ag = gx.a_step[n]
            assert s.s1 == pytest.approx(q1 + dt * (v1 - 0.5 * ag * dt), abs=1e-15)
            assert s.s2 == pytest.approx(q2 + dt * v2, abs=1e-15)
            assert s.N1 == s.N2 == s.F == 0.0
        rows.append(s.values())
        worst = max(worst, abs(s.ledger_residual()))
    R = np.array(rows)
    c = {name: R[:, j] for j, name in enumerate(s.columns)}
    assert np.all(np.isfinite(R))
    assert c["n_lift"][-1] == 1.0
    assert c["t_flight_s"][-1] == pytest.approx(t_f, rel=1e-12)
    assert c["lift_m"].max() == pytest.approx(z_pk, rel=1e-6)
    assert c["E_land_J"][-1] == pytest.approx(0.5 * Mt * v_land ** 2, rel=1e-9)
    fly = c["lift_m"] > 0.0
    assert np.all(c["W1_J"][fly] == c["W1_J"][np.argmax(fly) - 1])
    assert np.all(c["W2_J"][fly] == c["W2_J"][np.argmax(fly) - 1])
    assert worst <= 1e-10 * s.E_in


FLAT_Z = """
name = "flat-z"
[device]
kind = "flat"
pad_height = 0.10
pad_diameter = 0.25
pad_mass = 40.0
[superstructure]
mass = 1.0e5
[friction.lower]
law = "constant"
mu = 0.10
[friction.upper]
law = "constant"
mu = 0.06
[loading]
kind = "record"
record = "northridge-1994"
scale = 1.0
[thermal]
model = "lumped"
[solver]
duration = 3.0
"""


def _scene(tmp_path, over=()):
    p = tmp_path / "flat.toml"
    p.write_text(FLAT_Z)
    return scn.load(str(p), list(over))


def test_zero_file_z_reproduces_the_scene_without_it(tmp_path):
    z = tmp_path / "zero.txt"
    z.write_text("# [g]\n" + "".join(f"{0.004 * k:.3f} 0.0\n" for k in range(2000)))
    a = simulate(build(_scene(tmp_path)))
    b = simulate(build(_scene(tmp_path, [f'loading.file_z="{z}"'])))
    assert a.status == b.status == "ok"
    cols = [c for c in b.columns if c not in VERTICAL]
    np.testing.assert_array_equal(b.data[:, [b.columns.index(c) for c in cols]],
                                  a.data[:, [a.columns.index(c) for c in cols]])
    for c in VERTICAL:
        assert np.all(b[c] == 0.0)


def test_lift_off_through_a_scene_is_summarised_and_the_ledger_closes(tmp_path):
    from fpd.frontends import api
    _scene(tmp_path)                  # writes flat.toml
    r = api.run(str(tmp_path / "flat.toml"), output={"plots": False}, loading={"file_z": str(PULSE)})
    s = r.summary
    assert s["status"] == "ok", s["message"]
    lo = s["lift_off"]
    assert lo["count"] == 1 and lo["flight_time_s"] > 0.2 and lo["peak_lift_m"] > 0.02 and lo["landing_loss_J"] > 0
    n, t, lift = r.history["n_lift"], r.history["t_s"], r.history["lift_m"]
    assert lo["first_lift_t_s"] == float(t[np.flatnonzero(n > 0)[0]])
    assert lo["peak_lift_t_s"] == float(t[int(np.argmax(lift))])
    assert s["energy_residual_rel"] < 1e-10
    assert "record_z" in s


def test_compiled_flat_bearing_with_a_vertical_record_equals_the_pure_path(monkeypatch, tmp_path):
    pytest.importorskip("numba")
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    from fpd.coupling import fast_loop
    over = [f'loading.file_z="{PULSE}"']
    sim = build(_scene(tmp_path, over))
    assert fast_loop.compiled_loop(sim, 1, 2, fast_loop.loop_columns(sim)) is not None
    a = simulate(sim)
    monkeypatch.setenv("FPD_NO_JIT", "1")
    b = simulate(build(_scene(tmp_path, over)))
    assert a.status == b.status == "ok" and a.columns == b.columns
    assert np.max(a["n_lift"]) == 1.0
    np.testing.assert_array_equal(a.data, b.data)
