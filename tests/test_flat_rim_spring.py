"""The flat bearing's rim of finite stiffness (docs/model.md 7): a spring k
on each slip beyond its capacity and its dashpot 2 zeta sqrt(k m_eff), the
DFP's law (tribology/rim_law.py), against the closed forms of a mass on a
linear spring (and dashpot) while in contact."""
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.loading.ground_motion import harmonic_ground_motion
from fpd.mechanics import flat_kernel as K
from fpd.tribology import rim_law as rl
from fpd.mechanics.flat import FlatGeometry, FlatStepper
from fpd.schema import scene as scn

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_flat_rims import FLAT as RIGID, _scene as rigid_scene  # noqa: E402

GEOM = FlatGeometry(pad_height=0.10, pad_diameter=0.25, pad_mass=400.0, mass=1.0e4)
V0, D1, D2, KRIM = 0.4, 0.05, 0.2, 1.0e7
DTS = (2e-4, 1e-4, 5e-5)          # 99, 199 and 397 steps over the pad's contact pi sqrt(m / k)


def _lifting(gx):
    """A vertical ground falling at 2 g on the grid of gx: the assembly flies
    from the first step (g + a_z = -g) and never lands."""
    from fpd.loading.ground_motion import GroundMotion
    a = np.full(len(gx.t), -2.0 * 9.81)
    return GroundMotion("falling ground", gx.dt, gx.t, 0.5 * a * gx.t ** 2, a * gx.t, a, a[:-1].copy())


def _impact(dt, zeta, upper, fly=False):
    """Frictionless faces, the ground at rest. Lower rim (upper False): pad and
    superstructure launched together at V0, the pad meets the lower rim's
    spring alone (the superstructure slides on over it): the mass it sees is
    m. Upper rim: the superstructure launched over the pad at rest, the
    spring between them: the reduced mass m M / (m + M). Returns (mass,
    contact time (crossings interpolated), rebound rate / V0, peak spring
    force k o, peak |F_N|, rim loss, kinetic energy lost, worst |E_kin +
    E_pot + E_rim - K0| / K0 over the run, contacts counted, peak |J_rim_Ns|).
    fly: the same with the assembly in the air throughout (``_lifting``):
    the energies are then the horizontal ones (the motion's and the rim
    springs'), the flight's own rise apart."""
    m, M = GEOM.pad_mass, GEOM.mass
    gx = harmonic_ground_motion(0.0, 1.0, 1, dt)
    s = FlatStepper(GEOM, gx, gz=_lifting(gx) if fly else None, rim=(D1, D2, 0.0, KRIM, zeta))
    iq, iv, cap, mass = (K.S_Q2, K.S_V2, D2, m * M / (m + M)) if upper else (K.S_Q1, K.S_V1, D1, m)
    s.S[iv] = V0
    s.S[iq] = cap - 0.01
    def horizontal():
        """The horizontal kinetic energy and the springs' (in the air E_kin
        and E_pot also hold the flight's vertical energies)."""
        return K.kinetic(s.C, s.S[K.S_V1], s.S[K.S_V2]), sum(
            rl.spring_energy(KRIM, rl.overlap(abs(s.S[i]) - c)) for i, c in ((K.S_Q1, D1), (K.S_Q2, D2)))

    K0 = horizontal()[0]
    s.E_in = K0
    t_in = t_out = None
    o_pk = F_pk = worst = J_pk = 0.0
    q0 = s.S[iq]
    while t_out is None:
        s.step(0.0, 0.0)
        if fly:
            assert s.S[K.S_FLY] == 1.0 and s.S[K.S_N1] == 0.0 and s.S[K.S_N2] == 0.0
        q = s.S[iq]
        if t_in is None and q > cap:
            t_in = s.t - s.dt * (q - cap) / (q - q0)
        if t_in is not None and q <= cap:
            t_out = s.t - s.dt * (q - cap) / (q - q0)
        q0 = q
        o_pk, F_pk, J_pk = max(o_pk, q - cap), max(F_pk, abs(s.F)), max(J_pk, s.S[K.S_JRIM])
        Ek, Ep = horizontal()
        worst = max(worst, abs(Ek + Ep + s.E_rim - K0) / K0, abs(s.ledger_residual()) / max(K0, abs(s.E_in)))
    Ek, Ep = horizontal()
    return (mass, t_out - t_in, -s.S[iv] / V0, KRIM * o_pk, F_pk, s.E_rim, K0 - Ek - Ep, worst,
            s.S[K.S_NRIM2 if upper else K.S_NRIM1], J_pk)


@pytest.mark.parametrize("upper", [False, True])
def test_an_elastic_rim_hands_back_the_speed_in_the_closed_form_time_and_force(upper):
    """No damping: the slip rebounds at V0 (energy conserved: E_kin + the
    spring's energy = the launch energy at every step to 1e-11), the contact
    lasts pi sqrt(m_eff / k) and the peak rim force is V0 sqrt(k m_eff), both
    converging as dt shrinks. Measured at dt = 2e-4 / 1e-4 / 5e-5 s, the
    contact time's error: lower rim 8.3e-5 / 2.1e-5 / 5.2e-6, upper 8.6e-5 /
    2.2e-5 / 5.4e-6 (second order); the peak force k o's: 5.2e-5 / 1.5e-5 /
    2.9e-6 and 4.3e-5 / 2.3e-5 / 8.9e-7 (the step's sample of an exact turn);
    on the upper rim the force column F_N is the rim's force itself, its peak
    1.5e-4 / 3.3e-5 / 1.2e-5 off. An impact counted, no impulse."""
    err_t, err_f, err_col = [], [], []
    for dt in DTS:
        mass, T, ratio, F, Fcol, Erim, lost, worst, n, J = _impact(dt, 0.0, upper)
        assert abs(ratio - 1.0) <= 1e-10 and worst <= 1e-11 and Erim == 0.0 and n == 1 and J == 0.0
        err_t.append(abs(T / (math.pi * math.sqrt(mass / KRIM)) - 1.0))
        err_f.append(abs(F / (V0 * math.sqrt(KRIM * mass)) - 1.0))
        err_col.append(abs(Fcol / (V0 * math.sqrt(KRIM * mass)) - 1.0))
        # the energy is conserved, so the peak overlap is exact at the turn: a step's sample
        # of it is off by at most (omega dt / 2)^2 / 2
        assert err_f[-1] <= (math.sqrt(KRIM / mass) * dt) ** 2 / 8.0, err_f
    print("contact time", err_t, "peak force", err_f, "F_N", err_col)
    assert err_t[-1] < 2e-5 and err_f[-1] < 1e-5, (err_t, err_f)
    assert all(a > 2.5 * b for a, b in zip(err_t, err_t[1:])), err_t
    if upper:
        assert err_col[-1] < 1e-3 and all(a > b for a, b in zip(err_col, err_col[1:])), err_col
    else:
        assert all(abs(e - 1.0) < 1e-9 for e in err_col)    # frictionless top face: F_N stays 0


@pytest.mark.parametrize("zeta", [0.1, 0.3])
@pytest.mark.parametrize("upper", [False, True])
def test_a_damped_rim_returns_the_kelvin_voigt_rebound_and_books_the_loss(zeta, upper):
    """With the dashpot (acting while the slip is beyond its capacity, as the
    DFP's) the rebound rate over the arrival rate is exp(-zeta pi / sqrt(1 -
    zeta^2)) within 2e-5 at dt = 5e-5 s, converging at second order
    (measured, lower rim: zeta 0.1 5.2e-5 / 1.3e-5 / 3.3e-6, zeta 0.3 1.6e-4
    / 4.1e-5 / 1.0e-5 at dt = 2e-4 / 1e-4 / 5e-5 s; the upper rim's within
    4 % of these); the dashpot's loss in
    E_rim_J equals the kinetic energy lost to 1e-10 of the launch energy, and
    the ledger closes at every step."""
    closed = math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta * zeta))
    errs = []
    for dt in DTS:
        mass, T, ratio, F, Fcol, Erim, lost, worst, n, J = _impact(dt, zeta, upper)
        errs.append(abs(ratio / closed - 1.0))
        K0 = 0.5 * mass * V0 ** 2
        assert abs(Erim - lost) <= 1e-10 * K0 and worst <= 1e-11 and Erim > 0.0
        assert Erim == pytest.approx((1.0 - closed ** 2) * K0, rel=1e-3)
    print("zeta", zeta, "upper", upper, "rebound ratio errors", errs)
    assert errs[-1] < 2e-5 and all(a > 3.0 * b for a, b in zip(errs, errs[1:])), errs


@pytest.mark.parametrize("zeta", [0.0, 0.3])
@pytest.mark.parametrize("upper", [False, True])
def test_a_rim_spring_acts_in_the_air_with_the_same_closed_forms(zeta, upper):
    """The assembly lifted off by a vertical ground falling at 2 g (in the air
    throughout: no normal force, no friction) meets a rim spring: the
    horizontal contact is the seated frictionless one (model.md 7, 10),
    so the same closed forms hold at dt = 5e-5 s: the contact time pi
    sqrt(m_eff / k), the rebound rate (1 undamped, exp(-zeta pi / sqrt(1 -
    zeta^2)) damped), the dashpot's loss equal to the kinetic energy lost,
    the horizontal energy (motion and springs, with the loss) constant to
    1e-11 of the launch energy and the ledger closed at every step."""
    dt = DTS[-1]
    mass, T, ratio, F, Fcol, Erim, lost, worst, n, J = _impact(dt, zeta, upper, fly=True)
    closed = math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta * zeta))
    K0 = 0.5 * mass * V0 ** 2
    assert abs(ratio / closed - 1.0) < 2e-5 and worst <= 1e-11 and n == 1 and J == 0.0
    assert abs(Erim - lost) <= 1e-10 * K0
    assert abs(T / (math.pi * math.sqrt(mass / KRIM)) - 1.0) < 2e-5 or zeta != 0.0
    if upper:       # the upper rim's spring is the force on the superstructure, in the air too
        assert Fcol == pytest.approx(F, rel=2e-3) or zeta != 0.0
        assert Fcol > 0.0



def _spring(text: str) -> str:
    """The rigid-rim scene of test_flat_rims with a damped rim spring, upper mu 0.02, Northridge x 3."""
    out = text
    for a, b in (('name = "flat-rim"', 'name = "flat-rim-spring"'),
                 ("d2 = 0.04\n", "d2 = 0.04\nrim_stiffness_N_per_m = 1.0e8\nrim_damping_ratio = 0.2\n"),
                 ("mu = 0.05\n", "mu = 0.02\n"),
                 ('record = "northridge-1994"\n', 'record = "northridge-1994"\nscale = 3.0\n')):
        assert out.count(a) == 1, a
        out = out.replace(a, b)
    return out


FLAT = _spring(RIGID)


def _scene(tmp_path, over=()):
    return rigid_scene(tmp_path, over, FLAT)


def test_a_scene_with_a_rim_spring_reports_its_contacts_and_closes_the_ledger(tmp_path):
    """Northridge x 3 drives the superstructure into its upper rim: the
    summary reports the capacity ratio past 1 (the spring compressed), the
    contacts counted, the dashpot's loss, no impulse (the rim's force is in
    F_N), and the ledger closed to 1e-10 of the input."""
    from fpd.frontends import api
    _scene(tmp_path)
    r = api.run(str(tmp_path / "flat.toml"), output={"plots": False})
    s = r.summary
    assert s["status"] == "ok", s["message"]
    assert s["capacity"]["upper"]["ratio"] > 1.0 and s["rim_impacts"]["upper"] >= 1
    assert s["rim_loss_J"] > 0.0 and s["rim_impulse_Ns"] == 0.0
    assert s["energy_residual_rel"] < 1e-10


@pytest.mark.parametrize("over", [(), ("loading.vertical_scale=2.0",)], ids=["horizontal", "vertical"])
def test_compiled_flat_bearing_with_a_rim_spring_equals_the_pure_path(monkeypatch, tmp_path, over):
    """Compiled equals pure bit for bit, with the record's vertical component
    too (twice the record's: the springs act in the step's seated part and
    in the air); the ledger closes to 1e-10 of the input at every row."""
    pytest.importorskip("numba")
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    a = simulate(build(_scene(tmp_path, over)))
    monkeypatch.setenv("FPD_NO_JIT", "1")
    b = simulate(build(_scene(tmp_path, over)))
    assert a.status == b.status == "ok" and a.columns == b.columns
    assert a["n_rim2"][-1] >= 1 and np.max(a["E_pot_J"]) > 0.0
    np.testing.assert_array_equal(a.data, b.data)
    res = a["E_input_J"] - sum(a[c] for c in ("E_kin_J", "E_pot_J", "W1_J", "W2_J", "E_rim_J")) - (
        a["E_land_J"] if over else 0.0)
    assert np.max(np.abs(res)) <= 1e-10 * np.max(np.abs(a["E_input_J"]))
    if over:
        print("lift-offs", a["n_lift"][-1], "time in the air", a["t_flight_s"][-1], "upper contacts",
              a["n_rim2"][-1], "peak |F|", np.max(np.abs(a["F_N"])))


@pytest.mark.parametrize("over, needle", [
    (["device.rim_restitution=0.5"], "device.rim_restitution = 0.5: is a key of the rigid rim"),
])
def test_a_rim_spring_is_refused_in_one_line_where_it_does_not_apply(tmp_path, over, needle):
    with pytest.raises(scn.SceneError) as e:
        _scene(tmp_path, over)
    assert needle in str(e.value) and "\n" not in str(e.value)


def test_the_flat_bearings_test_machine_refuses_a_rim_spring():
    with pytest.raises(scn.SceneError) as e:
        scn.load("flat-lab", ["device.rim_stiffness_N_per_m=1e8"])
    assert "test machine" in str(e.value) and "\n" not in str(e.value)
