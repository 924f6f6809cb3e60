"""The flat bearing's rims (docs/model.md 7): capacities d1 (the pad on the
lower plate) and d2 (on the upper plate), a rigid unilateral stop with Newton
restitution, the loss booked in E_rim_J, and the capacity summary."""
import json
import math

import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.mechanics import flat_kernel as K
from fpd.mechanics.flat import FlatGeometry, FlatStepper
from fpd.loading.ground_motion import harmonic_ground_motion
from fpd.schema import scene as scn

GEOM = FlatGeometry(pad_height=0.10, pad_diameter=0.25, pad_mass=400.0, mass=1.0e4)


@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_a_frictionless_block_loses_one_minus_e_squared_of_its_normal_kinetic_energy(e):
    """Pad and superstructure launched together at v0 on frictionless faces,
    the ground at rest: the pad meets the lower rim (d1 = 0.05 m) and loses
    (1 - e^2) m v0^2 / 2 (the rim's impulse (1 + e) m v0 keeps the
    superstructure's momentum: the mass it sees is m); the superstructure
    then slides on the rebounding pad at (1 + e) v0 until the upper rim
    (d2 = 0.03 m), which takes (1 - e^2) mu ((1 + e) v0)^2 / 2 with the
    reduced mass mu = m M / (m + M); inelastic (e = 0), the pad still rests
    on its lower rim and the two rims stop the superstructure together (all
    of M v0^2 / 2, the impulse M v0). No face ever past its capacity; the
    ledger E_kin + E_rim = the launch energy to round-off."""
    dt, v0, d1, d2 = 1e-3, 0.4, 0.05, 0.03
    m, M = GEOM.pad_mass, GEOM.mass
    gx = harmonic_ground_motion(0.0, 1.0, 1, dt)
    s = FlatStepper(GEOM, gx, rim=(d1, d2, e))
    s.S[K.S_V1] = v0
    K0 = s.E_kin
    first = second = None
    for _ in range(gx.n_steps):
        s.step(0.0, 0.0)
        assert abs(s.s1) <= d1 and abs(s.s2) <= d2
        assert abs(s.E_kin + s.E_rim - K0) <= 1e-12 * K0
        if s.S[K.S_NRIM1] == 1 and first is None:
            first = (s.E_rim, s.S[K.S_JRIM], s.S[K.S_V1], s.S[K.S_V2])
        if s.S[K.S_NRIM2] == 1 and second is None:
            second = (s.E_rim - first[0], s.S[K.S_JRIM])
            break
    mu = m * M / (m + M)
    assert first[0] == pytest.approx((1 - e * e) * 0.5 * m * v0 ** 2, rel=1e-12, abs=1e-14 * K0)
    assert first[1] == pytest.approx((1 + e) * m * v0, rel=1e-12)
    assert first[2] == pytest.approx(-e * v0, abs=1e-15)                 # the pad rebounds at e v0
    assert first[2] + first[3] == pytest.approx(v0, rel=1e-14)          # the superstructure goes on
    vr = (1 + e) * v0
    if e == 0.0:
        # the pad rests on its lower rim: the upper rim pushes it into it, both stop (the full lock)
        assert second[0] == pytest.approx(0.5 * M * v0 ** 2, rel=1e-12) and s.E_kin <= 1e-12 * K0
        assert second[1] == pytest.approx(M * v0, rel=1e-12)
    else:
        assert second[0] == pytest.approx((1 - e * e) * 0.5 * mu * vr ** 2, rel=1e-12, abs=1e-14 * K0)
        assert second[1] == pytest.approx((1 + e) * mu * vr, rel=1e-12)


def test_rims_under_a_strong_ground_motion_hold_and_converge():
    """A harmonic ground motion that drives the superstructure into the upper
    rim repeatedly (mu 0.05 on top, 0.5 below; d2 = 0.04 m): no face past
    its capacity, every step's ledger closed to 1e-10 of the input, and the
    total dissipation (friction + rim) and the rims' own loss each within 1 %
    across dt = 1, 0.5 and 0.25 ms (a face resting on its rim is held by it,
    so contact costs nothing; measured: 850.5 / 851.7 / 849.9 J); the peak of the force column (the sliding force and the rim's
    contact reaction, never an impact's impulse / dt) within 5 %."""
    out = []
    for dt in (1e-3, 5e-4, 2.5e-4):
        gx = harmonic_ground_motion(0.15, 1.0, 3, dt)
        s = FlatStepper(GEOM, gx, rim=(0.2, 0.04, 0.0))
        worst, Fpk = 0.0, 0.0
        for _ in range(gx.n_steps):
            s.step(0.5, 0.05)
            assert abs(s.s1) <= 0.2 and abs(s.s2) <= 0.04
            worst = max(worst, abs(s.ledger_residual()))
            Fpk = max(Fpk, abs(s.F))
        assert worst <= 1e-10 * s.E_in
        assert s.S[K.S_NRIM2] >= 4
        out.append((s.W1 + s.W2 + s.E_rim, Fpk, s.E_rim))
    D = np.array(out)
    assert np.ptp(D[:, 0]) / D[:, 0].mean() < 0.01, D
    assert np.ptp(D[:, 1]) / D[:, 1].mean() < 0.05, D
    assert np.all(D[:, 2] > 0.0) and np.ptp(D[:, 2]) / D[:, 2].mean() < 0.01, D     # the rims' loss itself


FLAT = """
name = "flat-rim"
[device]
kind = "flat"
pad_height = 0.10
pad_diameter = 0.25
pad_mass = 400.0
d2 = 0.04
[superstructure]
mass = 1.0e4
[friction.lower]
law = "constant"
mu = 0.5
[friction.upper]
law = "constant"
mu = 0.05
[loading]
kind = "record"
record = "northridge-1994"
[thermal]
model = "lumped"
[solver]
duration = 6.0
"""


def _scene(tmp_path, over=(), text=None):
    p = tmp_path / "flat.toml"
    p.write_text(FLAT if text is None else text)
    return scn.load(str(p), list(over))


def test_capacities_default_to_what_the_plate_allows_and_larger_ones_are_refused(tmp_path):
    d = _scene(tmp_path).data["device"]
    assert d["d1"] == pytest.approx(0.40 - 0.125) and d["d2"] == 0.04
    with pytest.raises(scn.SceneError, match=r"^[^\n]*device\.d1[^\n]*plate's edge[^\n]*$"):
        _scene(tmp_path, ["device.d1=0.3"])
    with pytest.raises(scn.SceneError, match=r"loading\.amplitude_m.*capacity"):
        scn.load("flat-lab", ["device.d2=0.03"])


def test_the_scene_reports_the_capacity_and_the_impacts(tmp_path):
    from fpd.frontends import api
    _scene(tmp_path)
    s = api.run(str(tmp_path / "flat.toml"), output={"plots": False}, friction={"upper": {"mu": 0.02}},
                loading={"scale": 3.0}).summary
    assert s["status"] == "ok", s["message"]
    assert s["capacity"]["upper"]["capacity_m"] == 0.04 and s["capacity_ratio"] == pytest.approx(1.0)
    assert s["rim_impacts"]["upper"] >= 1 and s["rim_loss_J"] > 0 and s["rim_impulse_Ns"] > 0
    assert s["energy_residual_rel"] < 1e-10


def test_compiled_flat_bearing_with_rims_equals_the_pure_path(monkeypatch, tmp_path):
    pytest.importorskip("numba")
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    over = ["friction.upper.mu=0.02", "loading.scale=3.0"]
    a = simulate(build(_scene(tmp_path, over)))
    monkeypatch.setenv("FPD_NO_JIT", "1")
    b = simulate(build(_scene(tmp_path, over)))
    assert a.status == b.status == "ok" and a.columns == b.columns
    assert a["n_rim2"][-1] >= 1
    np.testing.assert_array_equal(a.data, b.data)


def test_a_machine_that_drives_a_face_past_its_rim_stops_the_run():
    """The flat bearing's machine cannot push a face through its rim: a
    programme past d2 (built around the scene check) stops with
    MachinePastRim naming the slips and the capacities."""
    from fpd.mechanics.flat import MachinePastRim
    from fpd.loading.ground_motion import sine_programme
    s = FlatStepper(GEOM, sine_programme(0.05, 0.2, 1, 1e-3), rim=(0.2, 0.03, 0.0))
    with pytest.raises(MachinePastRim, match=r"past its rim.*d2 = 0\.03"):
        for _ in range(5000):
            s.step(0.9, 0.3)
