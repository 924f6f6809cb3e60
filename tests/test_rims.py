"""Rims of the DFP and the SFP (docs/model.md 9): the slide capacity of each
surface, the stop at the rim (inelastic, or with a restitution), its loss in
the ledger (E_rim_J), impacts reported as impulses (N s), never as forces."""
import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.schema import scene as scn
from fpd.schema.scene import SceneError
from helpers import refusal


def _run(scene, over):
    try:
        import numba  # noqa: F401   (mechanics-only and lumped runs: the compiled engine)
    except ImportError:
        pass
    r = simulate(build(scn.load(scene, over)))
    assert r.status == "ok", r.message
    return r


FREE_SFP = """
name = "free-sfp"
[device]
kind = "SFP"
R1 = 2.0
pad_height = 0.08
pad_diameter = 0.20
d1 = 0.10
[superstructure]
mass = 5.0e4
[friction]
law = "constant"
mu = 0.0
[loading]
kind = "pulse"
shape = "step"
velocity_mps = 0.4
period_s = 0.2
t0_s = 0.05
duration_s = 3.0
[mechanics]
model = "seated"
[thermal]
model = "none"
"""


@pytest.mark.parametrize("e", [0.0, 0.5])
def test_frictionless_sfp_loses_the_kinetic_energy_normal_to_the_rim(tmp_path, e):
    """A frictionless SFP set swinging by a short ground pulse reaches its rim
    (d1 = 0.10 m) after the pulse: the first impact takes (1 - e^2) of the
    kinetic energy it arrives with, E_input - E_pot(at the rim), to 1e-9."""
    path = tmp_path / "free.toml"
    path.write_text(FREE_SFP)
    r = _run(str(path), [f"device.rim_restitution={e}", "solver.dt=1e-3"])
    n = r["n_rim1"]
    i = int(np.argmax(n > 0))                   # the row of the first impact
    assert n[i] == 1 and r["t_s"][i] > 0.05 + 0.2 + 0.01       # after the pulse: the input is constant
    assert r["E_input_J"][i] == r["E_input_J"][i - 1]
    ek_rim = r["E_input_J"][i] - r["E_pot_J"][i] - r["E_rim_J"][i - 1]
    assert ek_rim > 100.0
    assert abs(r["E_rim_J"][i] - r["E_rim_J"][i - 1] - (1 - e * e) * ek_rim) <= 1e-9 * ek_rim
    assert abs(r["E_kin_J"][i] - e * e * ek_rim) <= 1e-9 * ek_rim
    assert np.max(np.abs(r["s1_m"])) <= 0.10 * (1 + 1e-12)


CASES = [
    ("DFP two-phase, El Centro", "default", ["solver.duration=12", "thermal.model=lumped", "device.d1=0.02",
                                             "device.d2=0.03"]),
    ("SFP, harmonic", "sfp-harmonic", ["device.d1=0.15"]),
    ("DFP in both directions, Imperial Valley", "impvall-bidirectional",
     ["solver.duration=12", "thermal.model=lumped", "device.d1=0.04", "device.d2=0.04"]),
]


@pytest.mark.parametrize("name, scene, over", CASES, ids=[c[0] for c in CASES])
def test_rim_impacts_converge_and_the_ledger_closes(name, scene, over):
    """dt = 1, 0.5, 0.25 ms: peak displacement and dissipation (friction +
    rim) within 1 %, peak force within 5 %, the ledger within 1e-8 of the
    input over the whole history, no footprint past its capacity (measured:
    dissipation within 0.05 %, peak force within 1 %, ledger <= 3e-10)."""
    out = []
    for dt in (1e-3, 0.5e-3, 0.25e-3):
        r = _run(scene, over + [f"solver.dt={dt}"])
        two_d = "ux_m" in r
        u = np.hypot(r["ux_m"], r["uy_m"]) if two_d else np.abs(r["u_m"])
        F = np.hypot(r["Fx_N"], r["Fy_N"]) if two_d else np.abs(r["F_N"])
        diss = r["W1_J"][-1] + r["W2_J"][-1] + r["E_rim_J"][-1]
        ledger = r["E_input_J"] - (r["E_kin_J"] + r["E_pot_J"] + r["W1_J"] + r["W2_J"] + r["E_rim_J"]
                                   + (r["E_reseat_J"] if "E_reseat_J" in r else 0.0))
        assert np.max(np.abs(ledger)) <= 1e-8 * np.max(np.abs(r["E_input_J"]))
        s = build(scn.load(scene, over)).scene["device"]
        assert np.max(np.abs(r["s1_m"])) <= s["d1"] * (1 + 1e-12)
        if s["kind"] == "DFP":
            assert np.max(np.abs(r["s2_m"])) <= s["d2"] * (1 + 1e-12)
        assert r["n_rim1"][-1] + r["n_rim2"][-1] >= 1 and r["E_rim_J"][-1] > 0.0      # the rim is reached
        out.append((u.max(), diss, F.max()))
    out = np.array(out)
    spread = (out.max(axis=0) - out.min(axis=0)) / out.min(axis=0)
    assert spread[0] <= 0.01 and spread[1] <= 0.01 and spread[2] <= 0.05, spread


def test_summary_reports_capacity_and_impacts(tmp_path):
    """summary.json: per surface the capacity, the peak slide, their ratio and
    the impacts counted; the rim's loss and impulse; the largest ratio (sweep
    tables). The default capacity is what the plate allows: plate_radius - a."""
    from fpd.frontends import api
    r = api.run("default", solver={"duration": 12.0}, thermal={"model": "lumped"}, device={"d1": 0.02},
                output={"plots": False})
    s = r.summary
    assert s["capacity"]["lower"]["capacity_m"] == 0.02
    assert s["capacity"]["upper"]["capacity_m"] == pytest.approx(0.40 - 0.125)        # the default
    assert s["capacity"]["lower"]["ratio"] == pytest.approx(1.0, abs=1e-12) == s["capacity_ratio"]
    assert s["capacity"]["lower"]["impacts"] >= 1 and s["rim_impacts"]["lower"] == s["capacity"]["lower"]["impacts"]
    assert s["rim_loss_J"] > 0 and s["rim_impulse_Ns"] > 0
    # an impulse is not a force: the peak force stays the sliding response's
    assert s["peak_F_N"] < 1.2 * api.run("default", solver={"duration": 12.0}, thermal={"model": "lumped"},
                                         output={"plots": False}).summary["peak_F_N"]


@pytest.mark.parametrize("over, needle", [
    (["device.d1=0.3"], "device.d1 = 0.3: the footprint (radius 0.125 m) would pass the plate's edge"),
    (["thermal.upper.plate_radius=0.1"], "plate_radius = 0.1: must be >= the pad radius 0.125 m"),
    (["device.rim_restitution=1.5"], "device.rim_restitution = 1.5: must be in [0, 1]"),
])
def test_bad_capacities_are_one_line(over, needle):
    assert needle in refusal("default", over)


def test_sfp_has_no_d2_and_the_machine_stays_inside_its_capacity():
    with pytest.raises(SceneError, match="device.d2 = 0.1: the SFP has one sliding surface"):
        scn.load("sfp-harmonic", ["device.d2=0.1"])
    with pytest.raises(SceneError, match="loading.amplitude_m = 0.25: drives the bearing past its capacity"):
        scn.load("lab-sine", ["device.d1=0.05"])


# -- a rim of finite stiffness (device.rim_stiffness_N_per_m) -----------------------------

def _dissipation(r):
    return r["W1_J"][-1] + r["W2_J"][-1] + r["E_rim_J"][-1]


def _ledger_worst(r):
    res = r["E_input_J"] - (r["E_kin_J"] + r["E_pot_J"] + r["W1_J"] + r["W2_J"] + r["E_rim_J"]
                            + (r["E_reseat_J"] if "E_reseat_J" in r else 0.0))
    return np.max(np.abs(res))


@pytest.mark.parametrize("name, scene, over", [
    ("SFP, harmonic", "sfp-harmonic", ["device.d1=0.15"]),
    ("DFP two-phase, El Centro", "default", ["solver.duration=12", "thermal.model=lumped", "device.d1=0.02",
                                             "device.d2=0.03"]),
    ("DFP in both directions, Imperial Valley", "impvall-bidirectional",
     ["solver.duration=12", "thermal.model=lumped", "device.d1=0.04", "device.d2=0.04"]),
], ids=["sfp", "dfp", "dfp-2d"])
def test_a_finite_rim_stiffness_gives_a_contact_force_that_converges_in_dt(name, scene, over):
    """k = 1e9 N/m: the impact is a contact force (part of F_N, no impulse, no
    rim loss) whose peak converges as dt shrinks: within 1 % across dt = 1, 0.5,
    0.25 ms (measured 0.4 %, 0.2 %, 0.14 %), dissipation within 0.01 %; the
    spring's energy, (1/2) k (slide beyond the capacity)^2, is in E_pot_J and
    the ledger closes (seated to 1e-13 of the input, the two-phase scheme to
    its own closure) while that energy is >= 1e4 times the residual."""
    k = 1e9
    out = []
    for dt in (1e-3, 0.5e-3, 0.25e-3):
        r = _run(scene, over + [f"solver.dt={dt}", f"device.rim_stiffness_N_per_m={k}"])
        two_d = "ux_m" in r
        F = np.hypot(r["Fx_N"], r["Fy_N"]) if two_d else np.abs(r["F_N"])
        s = build(scn.load(scene, over)).scene["device"]
        s1 = np.hypot(r["c1x_m"], r["c1y_m"]) if two_d else np.abs(r["s1_m"])
        over1 = max(np.max(s1) - s["d1"], 0.0)
        assert r["n_rim1"][-1] + r["n_rim2"][-1] >= 1 and over1 > 1e-4          # the rim is reached, and yields
        assert np.all(r["E_rim_J"] == 0.0) and np.all(r["J_rim_Ns"] == 0.0)
        worst = _ledger_worst(r)
        seated = "E_reseat_J" not in r
        assert worst <= (1e-13 if seated else 1e-8) * np.max(np.abs(r["E_input_J"]))
        assert 0.5 * k * over1 ** 2 >= 1e4 * worst
        out.append((F.max(), _dissipation(r)))
    out = np.array(out)
    spread = (out.max(axis=0) - out.min(axis=0)) / out.min(axis=0)
    assert spread[0] <= 0.01 and spread[1] <= 1e-4, spread


def test_a_stiffer_rim_approaches_the_rigid_elastic_rim():
    """The spring stores and returns the impact's energy: as k grows the run
    approaches the rigid rim of restitution 1 (SFP, harmonic, d1 = 0.15 m, dt =
    0.5 ms): dissipation 65 846, 60 861, 56 792, 55 743 J at k = 1e7 .. 1e10
    against 55 215 J, the gap shrinking with k and under 1 % at 1e10; the
    largest slide past the capacity shrinks as 1 / sqrt(k) roughly (41, 13,
    3.8, 1.2 mm)."""
    base = ["device.d1=0.15", "solver.dt=5e-4"]
    rigid = _dissipation(_run("sfp-harmonic", base + ["device.rim_restitution=1"]))
    gaps, past = [], []
    for k in (1e7, 1e8, 1e9, 1e10):
        r = _run("sfp-harmonic", base + [f"device.rim_stiffness_N_per_m={k}"])
        gaps.append(_dissipation(r) / rigid - 1.0)
        past.append(np.max(np.abs(r["s1_m"])) - 0.15)
    assert all(g > 0.0 for g in gaps) and all(a > b for a, b in zip(gaps, gaps[1:])), gaps
    assert gaps[-1] < 0.01, gaps
    assert all(a > 2.5 * b for a, b in zip(past, past[1:])), past


@pytest.mark.parametrize("scene, over, needle", [
    ("tfp-elcentro", ['loading.record="impvall-1979-e11"', "device.rim_restitution=0.5"],
     "device.rim_restitution = 0.5: is a key of the rigid rim"),
    ("tfp-elcentro", ["device.rim_restitution=0.5"], "device.rim_restitution = 0.5: is a key of the rigid rim"),
    ("lab-sine", [], "test machine"),
    ("sfp-harmonic", ["device.rim_restitution=0.5"], "device.rim_restitution = 0.5: is a key of the rigid rim"),
])
def test_rim_stiffness_is_refused_where_it_is_not_modelled(scene, over, needle):
    assert needle in refusal(scene, over + ["device.rim_stiffness_N_per_m=1e9"])
