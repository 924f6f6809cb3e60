"""One DFP/SFP stepper: a planar ground motion runs the 3D stepper
(mechanics/bidirectional.py) with the y component absent, its midpoint
scheme the default, the planar columns signed."""
from pathlib import Path

import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.schema import scene as scn

NEAR_FAULT = """
name = "near-fault-constant"
[device]
kind = "DFP"
R1 = 2.2
R2 = 2.2
pad_height = 0.10
pad_diameter = 0.25
pad_mass = 30.0
[superstructure]
mass = 1.0e5
[friction]
law = "constant"
mu = 0.06
[loading]
kind = "record"
record = "northridge-1994"
[mechanics]
model = "seated"
[thermal]
model = "none"
"""

PULSE = Path(__file__).resolve().parent / "data" / "pulse_z.txt"   # -1.5 g from 1.001 to 1.2 s
V2 = Path(__file__).resolve().parents[1] / "scenes" / "records" / "FERNDALE2022_CE89486.v2"


def _compiled():
    """Load numba (when there) so that mechanics-only runs take the compiled engine."""
    try:
        import numba  # noqa: F401
    except ImportError:
        pass


def test_planar_scenes_run_the_3d_stepper_midpoint_by_default():
    for name in ("default", "sfp-harmonic", "northridge-dfp"):
        s = scn.load(name, ["solver.duration=0.5"])
        assert s["mechanics"]["normal_force"] == "midpoint", name
        mech = build(s).mechanics
        assert type(mech).__name__ == "BidirectionalStepper" and not mech.two_d, name


def test_friction_work_converges_at_second_order(tmp_path):
    """Friction work of a seated DFP (constant mu) under a near-fault record
    (Northridge 1994, 12 s), dt = 4, 2, 1, 0.5 ms against dt = 1/16 ms: the
    observed order (least squares over the four) is >= 1.8 and the error at
    1 ms below 5e-5 of the work (measured: 1.96, 1.8e-5)."""
    _compiled()
    path = tmp_path / "nf.toml"
    path.write_text(NEAR_FAULT)

    def work(dt):
        r = simulate(build(scn.load(str(path), [f"solver.dt={dt}", "solver.duration=12"])))
        assert r.status == "ok", r.message
        return r["W1_J"][-1] + r["W2_J"][-1]

    ref = work(0.0625e-3)
    dts = np.array([4e-3, 2e-3, 1e-3, 0.5e-3])
    err = np.array([abs(work(dt) - ref) for dt in dts])
    order = np.polyfit(np.log(dts), np.log(err), 1)[0]
    assert order >= 1.8, (order, err)
    assert err[2] / ref < 5e-5, err / ref


@pytest.mark.parametrize("model", ["two-phase", "seated"])
def test_zero_y_component_is_the_planar_run(tmp_path, model):
    """A bidirectional scene whose y record is zero gives the planar run's
    history: ux = u_m, Fx = F_N, W, N, z to 1e-12 relative (the same stepper)."""
    from fpd.loading.ground_motion import read_record
    rec = read_record(Path(scn.__file__).resolve().parent.parent / "scenes" / "records" / "IELC180.AT2")
    zero = tmp_path / "zero.txt"
    np.savetxt(zero, np.column_stack([rec.t, np.zeros_like(rec.t)]))
    over = ["solver.duration=6", "thermal.model=\"lumped\"", f"mechanics.model=\"{model}\""]
    planar = simulate(build(scn.load("default", over)))
    both = simulate(build(scn.load("default", over + [f"loading.file_y=\"{zero}\"", "loading.units=\"g\""])))
    assert planar.status == both.status == "ok"
    for p, b in (("u_m", "ux_m"), ("F_N", "Fx_N"), ("v_mps", "vx_mps"), ("W1_J", "W1_J"), ("W2_J", "W2_J"),
                 ("N1_N", "N1_N"), ("z_m", "z_m"), ("T1_C", "T1_C")):
        ref = planar[p]
        assert np.max(np.abs(both[b] - ref)) <= 1e-12 * np.max(np.abs(ref)), p
    assert np.all(both["uy_m"] == 0.0)


def test_planar_columns_are_signed():
    """The default scene (lumped plates) ends 11.1 mm on the negative side (the
    3D stepper's resultant would read +11.1 mm), and u_m, F_N, theta change
    sign (peaks -54.4 and +18.9 mm)."""
    r = simulate(build(scn.load("default", ["thermal.model=\"lumped\""])))
    u = r["u_m"]
    assert u.min() < -0.05 and u.max() > 0.015
    assert -0.0116 < u[-1] < -0.0106
    assert r["F_N"].min() < -5e4 and r["F_N"].max() > 5e4
    assert np.all(np.sign(r["theta_rad"]) == np.sign(u))


@pytest.mark.parametrize("scene, over", [
    ("default", ["solver.duration=4"]),
    ("default", ["solver.duration=4", "mechanics.model=seated", "thermal.model=lumped"]),
    ("default", ["solver.duration=4", "mechanics.normal_force=start"]),
    ("sfp-harmonic", ["solver.duration=3"]),
    ("impvall-bidirectional", ["solver.duration=4"]),
    ("ferndale-3c", ["solver.duration=36"]),
    ("ferndale-3c", ["solver.duration=36", "loading.channels=[1, 3]", "mechanics.model=seated"]),
    # a vertical pulse below -g: lift-off, flight and landing
    ("ferndale-3c", ["solver.duration=3", "loading.channels=[1, 2]", "loading.baseline=false",
                     f'loading.file_z="{PULSE}"']),
    # the TFP's rims with a restitution (six arrivals on S2 / S3)
    ("tfp-elcentro", ["solver.duration=12", "loading.scale=4", "device.rim_restitution=0.5",
                      "thermal.model=lumped", "mechanics.model=seated"]),
    # a rim of finite stiffness
    ("sfp-harmonic", ["solver.duration=6", "device.d1=0.15", "device.rim_stiffness_N_per_m=1e9"]),
    ("impvall-bidirectional", ["solver.duration=8", "device.d1=0.04", "device.d2=0.04",
                               "device.rim_stiffness_N_per_m=1e9"]),
    # the planar TFP's rim springs and dashpots (all four rims passed), two-phase, lumped heat
    ("tfp-elcentro", ["solver.duration=8", "loading.scale=6", "device.rim_stiffness_N_per_m=1e8",
                      "device.rim_damping_ratio=0.2", "thermal.model=lumped"]),
    # and its dashpot (planar seated, and the two-phase DFP in both directions)
    ("sfp-harmonic", ["solver.duration=6", "device.d1=0.15", "device.rim_stiffness_N_per_m=1e9",
                      "device.rim_damping_ratio=0.2"]),
    ("impvall-bidirectional", ["solver.duration=8", "device.d1=0.04", "device.d2=0.04",
                               "device.rim_stiffness_N_per_m=1e9", "device.rim_damping_ratio=0.3"]),
    # the flight planar and seated
    ("ferndale-3c", ["solver.duration=3", "loading.channels=[1]", "loading.baseline=false",
                     f'loading.file_z="{PULSE}"', "mechanics.model=seated"]),
    ("tfp-elcentro", ["solver.duration=3", "thermal.model=fe1d"]),
    # the TFP in both directions: a record pair, fe1d on the four parts along 2D footprint paths
    ("tfp-elcentro", ['loading.record="impvall-1979-e11"', 'mechanics.model="seated"', "solver.duration=6",
                      "solver.dt=2e-3"]),
    # its two-phase model (the scene's), all four surfaces sliding
    ("tfp-elcentro", ['loading.record="impvall-1979-e11"', "solver.duration=6", "solver.dt=2e-3",
                      "friction.mu_ref=0.04"]),
    # and on the test machine along a circle
    ("tfp-lab", ['loading.waveform="circle"', "loading.amplitude_m=0.04", "loading.cycles=1",
                 'mechanics.model="two-phase"', 'thermal.model="lumped"']),
    # the TFP under a vertical record (Ferndale's vertical channel x 3 at El Centro's first 35 s)
    ("tfp-elcentro", ["solver.duration=35", "thermal.model=lumped", "mechanics.model=two-phase",
                      f'loading.file_z="{V2}"', "loading.scale=3"]),
    # the planar TFP flies and lands under a vertical pulse below -g (seated; two-phase with fe1d)
    ("tfp-elcentro", ["solver.duration=3", "mechanics.model=seated", f'loading.file_z="{PULSE}"',
                      "loading.baseline=false", "loading.scale=1"]),
    ("tfp-elcentro", ["solver.duration=3", f'loading.file_z="{PULSE}"', "loading.baseline=false",
                      "loading.scale=1"]),
    # the TFP in both directions flies and lands under the pulse (the Imperial Valley pair)
    ("tfp-elcentro", ['loading.record="impvall-1979-e11"', 'mechanics.model="seated"', "solver.duration=3",
                      "solver.dt=2e-3", "loading.scale=1", f'loading.file_z="{PULSE}"', "loading.baseline=false",
                      "thermal.model=lumped"]),
    # its two-phase model flies and lands under the pulse, and takes 0.6 of the pair's x component as vertical
    ("tfp-elcentro", ['loading.record="impvall-1979-e11"', "solver.duration=3", "solver.dt=2e-3",
                      "loading.scale=1", f'loading.file_z="{PULSE}"', "loading.baseline=false",
                      "thermal.model=lumped"]),
    ("tfp-elcentro", ['loading.record="impvall-1979-e11"', "solver.duration=6", "solver.dt=2e-3",
                      "friction.mu_ref=0.04", "loading.vertical_scale=0.6"]),
    # the TFP in both directions under a vertical ground motion (0.6 of the pair's x component), fe1d
    ("tfp-elcentro", ['loading.record="impvall-1979-e11"', 'mechanics.model="seated"', "solver.duration=6",
                      "solver.dt=2e-3", "loading.vertical_scale=0.6"]),
    ("flat-lab", []),
    ("flat-lab", ["thermal.model=lumped"]),
    ("lab-sine", []),
    # the machine stops the bearing between two grid points (the stopping impulse), the riding mass
    ("lab-sine", ["loading.cycles=2.9", "solver.duration=8", 'loading.vertical="riding-mass"',
                  "thermal.model=lumped"]),
    ("lab-sine", ['loading.waveform="circle"']),
    ("lab-sine", ['loading.waveform="figure-eight"', "thermal.model=lumped", "solver.duration=4"]),
    # the axial-load programme: a sine about W, and a (t, N) series with the stopping impulse
    ("lab-sine", ['loading.vertical="sine"', "loading.vertical_amplitude_ratio=0.4",
                  "loading.vertical_frequency_Hz=0.8", "loading.vertical_phase_deg=30"]),
    ("lab-sine", ['loading.vertical="series"', 'loading.vertical_file="axial.txt"', "loading.cycles=2.9",
                  "solver.duration=8", "thermal.model=lumped"]),
    # tribology: breakaway and wear (a table in T) under a record, on the machine, and the
    # machine's compliant link (stick-slip); wear on the flat bearing and the TFP
    ("default", ["solver.duration=4", "friction.mu_static=0.07", "friction.static_ratio=1.5",
                 "friction.wear_T_C=[0.0, 200.0]",
                 "friction.wear_k_T_mm3_per_Nm=[1e-6, 4e-6]"]),
    ("lab-sine", ["friction.mu_static=0.09", "friction.wear_k_mm3_per_Nm=2e-6", "thermal.model=lumped"]),
    ("lab-sine", ["friction.mu_static=0.09", 'loading.waveform="triangle"', "loading.link_stiffness_N_per_m=5e7",
                  "loading.link_mass_kg=3000", "loading.amplitude_m=0.02", "solver.duration=2",
                  "thermal.model=lumped"]),
    ("flat-lab", ["friction.wear_k_mm3_per_Nm=2e-6"]),
    ("tfp-elcentro", ["solver.duration=3", "friction.wear_k_mm3_per_Nm=2e-6"]),
    # the TFP's machine under an axial-load programme; breakaway on the TFP (machine, two-phase;
    # a record, the static ratio) and on the flat bearing
    ("tfp-lab", ['loading.vertical="sine"', "loading.vertical_amplitude_ratio=0.4", "loading.vertical_frequency_Hz=0.23",
                 "loading.cycles=1", "thermal.model=lumped"]),
    ("tfp-lab", ['mechanics.model="two-phase"', "friction.S1.mu_static=0.11", "friction.S4.mu_static=0.11",
                 "friction.S2.mu_static=0.03", "friction.S3.mu_static=0.03", 'loading.vertical="sine"',
                 "loading.vertical_amplitude_ratio=0.3", "loading.vertical_frequency_Hz=0.3", "loading.cycles=1",
                 "thermal.model=lumped"]),
    ("tfp-elcentro", ["solver.duration=3", "friction.static_ratio=1.3", "thermal.model=lumped"]),
    ("flat-lab", ["friction.upper.mu_static=0.6", "thermal.model=lumped"]),
])
def test_compiled_engine_equals_the_pure_path_bit_for_bit(monkeypatch, tmp_path, scene, over):
    """The compiled engine (numba) and the pure path (FPD_NO_JIT: the Python
    loop calling the same kernel modules unchanged) write the same history,
    bit for bit, for every device the engine runs."""
    pytest.importorskip("numba")
    # the axial-load series of a case (6.3 MN +- 30 %, 8 s), found from the working folder
    t = np.linspace(0.0, 8.0, 41)
    np.savetxt(tmp_path / "axial.txt", np.column_stack([t, 6.3e6 * (1 + 0.3 * np.sin(1.7 * t) * np.cos(0.4 * t))]))
    monkeypatch.chdir(tmp_path)
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    from fpd.coupling import fast_loop
    sim = build(scn.load(scene, over))
    assert fast_loop.compiled_loop(sim, 1, 2, fast_loop.loop_columns(sim)) is not None
    a = simulate(sim)
    monkeypatch.setenv("FPD_NO_JIT", "1")
    b = simulate(build(scn.load(scene, over)))
    assert a.status == b.status == "ok" and a.columns == b.columns
    np.testing.assert_array_equal(a.data, b.data)


FLAT_RECORD = """
name = "flat-record"
[device]
kind = "flat"
pad_height = 0.10
pad_diameter = 0.08
pad_mass = 500.0
[superstructure]
mass = 1.0e4
[friction.lower]
law = "constant"
mu = 0.95
[friction.upper]
law = "constant"
mu = 0.5
[loading]
kind = "record"
record = "northridge-1994"
scale = 2.5
[thermal]
model = "lumped"
[solver]
duration = 15.0
"""


@pytest.mark.parametrize("mu, status", [(0.5, "ok"), (0.81, "failed")])
def test_compiled_flat_bearing_under_a_record_equals_the_pure_path(monkeypatch, tmp_path, mu, status):
    """The flat bearing under a ground motion, compiled and pure, bit for bit;
    at mu2 = 0.81, below the closed-form threshold 0.82, the pad's inertia
    tips it mid-run (step 6496): the engine hands that step to the Python
    loop, which raises PadTipped with the same message and the same rows."""
    pytest.importorskip("numba")
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    from fpd.coupling import fast_loop
    path = tmp_path / "flat.toml"
    path.write_text(FLAT_RECORD)
    over = [f"friction.upper.mu={mu}"]
    sim = build(scn.load(str(path), over))
    assert fast_loop.compiled_loop(sim, 1, 2, fast_loop.loop_columns(sim)) is not None
    a = simulate(sim)
    monkeypatch.setenv("FPD_NO_JIT", "1")
    b = simulate(build(scn.load(str(path), over)))
    assert a.status == b.status == status and a.message == b.message and a.columns == b.columns
    if status == "failed":
        assert "the pad tips" in a.message and len(a.data) > 6000
    np.testing.assert_array_equal(a.data, b.data)


@pytest.mark.parametrize("scene, over", [
    ("flat-lab", {"thermal": {"model": "lumped"}}),
    ("lab-sine", {}),
    ("lab-sine", {"loading": {"waveform": "circle"}}),
])
def test_compiled_engine_tracks_every_step_as_the_pure_path(monkeypatch, scene, over):
    """With rows kept every 10 steps the summary (every step's peaks and
    ledger: the engine's track_row, the Python loop's StepTracker) is the
    same, value for value, compiled and pure, for the flat bearing and the
    two test machines."""
    pytest.importorskip("numba")
    from fpd import kernels
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    from fpd.frontends import api

    def summary():
        s = api.run(scene, output={"csv_every": 10, "plots": False}, **over).summary
        s.pop("runtime_s", None)
        return s

    a = summary()
    monkeypatch.setenv("FPD_NO_JIT", "1")
    assert a == summary()
