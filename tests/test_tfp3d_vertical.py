"""The TFP in both horizontal directions under vertical ground motion
(mechanics/tfp3d.py, docs/model.md 10): the field g + a_z in its normal
forces, caps, heat, drive and ledger; a zero vertical record changes nothing;
a pair turned by an angle with a vertical record is the planar TFP's run
with it, lift-off and landing included; the vertical as a scale of the
horizontal record (planar and 3D)."""
from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.loading.ground_motion import harmonic_ground_motion, pulse_ground_motion
from fpd.mechanics.geometry import G_ACC
from fpd.mechanics.tfp import TFPStepper
from fpd.mechanics.tfp3d import TFP3DStepper
from fpd.schema import scene as scn

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_tfp import tfp  # noqa: E402
from tfp3d_helpers import flies_as_planar, stepped, turned_as_planar  # noqa: E402
from test_tfp3d import _kernel, turned  # noqa: E402
from test_tfp_vertical import zero_vertical_is_the_run  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
V2 = ROOT / "scenes" / "records" / "FERNDALE2022_CE89486.v2"
PAIR = ['loading.record="impvall-1979-e11"', 'mechanics.model="seated"', 'thermal.model="lumped"']


def _ledger(r):
    res = r["E_input_J"] - (r["E_kin_J"] + r["E_pot_J"] + r["W1_J"] + r["W2_J"] + r["W3_J"] + r["W4_J"]
                            + r["E_rim_J"])
    return np.max(np.abs(res)) / np.max(np.abs(r["E_input_J"]))


def test_a_zero_vertical_record_reproduces_the_run_bit_for_bit(tmp_path):
    """A pair with file_z of zeros on another time grid: the same rows bit for
    bit (the acceptance asks 1e-12 relative), plus the vertical columns (all 0)."""
    zero_vertical_is_the_run(tmp_path, PAIR + ["solver.duration=3", "solver.dt=2e-3", "loading.scale=0.5"], 1500)


@pytest.mark.parametrize("deg", [0.0, 30.0, 135.0])
def test_a_turned_record_with_a_vertical_one_is_the_planar_tfp_with_it(deg):
    """A record turned by an angle in the plane with a vertical harmonic (0.5 g
    at 1.3 Hz): the resultant history (|u|, |F|, the normal forces, the
    friction work of each surface, the input, kinetic and potential energy)
    is the planar TFP's under the same two components to 1e-9; the vertical
    motion changes the run far more than that; the ledger closes every step."""
    g = tfp()
    dt = 1e-3
    gm = pulse_ground_motion("cosine", 0.35, 1.5, 0.5, 3.0, dt)
    gz = harmonic_ground_motion(0.5 * G_ACC / (2 * math.pi * 1.3) ** 2, 1.3, 10, dt, duration=3.0)
    p, _ = stepped(TFPStepper(g, gm, gz=gz), gm.n_steps)
    p0, _ = stepped(TFPStepper(g, gm), gm.n_steps)
    ang = math.radians(deg)
    s = TFP3DStepper(g, *turned(gm, ang), kernel=_kernel(), az=gz.a_step)
    d, res = stepped(s, gm.n_steps)
    assert s.columns[-5] == "az_mps2" and np.array_equal(d["az_mps2"], p["az_mps2"])
    wt = turned_as_planar(d, p, ang, ("E_input_J", "E_kin_J", "E_pot_J"))
    # the vertical record matters: the friction work and the peak change by much more than 1e-9
    assert abs(sum(p0[f"W{i}_J"][-1] for i in range(1, 5)) / wt - 1) > 1e-3
    assert np.max(np.abs(p["N1_N"] - p0["N1_N"])) > 0.3 * g.weight
    e_in = np.maximum.accumulate(np.abs(d["E_input_J"]))
    assert np.all(np.abs(res) <= 1e-9 * np.maximum(e_in, 1e-300))


def test_the_ledger_closes_under_a_three_component_record():
    """Ferndale 2022, all three channels (x, y and up) x 3, 34 s: a_z up to 0.33 g,
    the bearing slides in both directions; E_input (the horizontal and vertical
    ground's work) = E_kin + E_pot + W1..W4 over the whole history to 1e-10;
    the top normal force is M (g + a_z) where the bearing is nearly upright
    and slow; the vertical channel changes the friction work."""
    over = ['loading.record="ferndale-2022"', 'mechanics.model="seated"', 'thermal.model="none"',
            "solver.duration=34", "solver.dt=2e-3", "loading.scale=3"]
    r = simulate(build(scn.load("tfp-elcentro", over)))
    a = simulate(build(scn.load("tfp-elcentro", over + ["loading.channels=[1, 2]"])))
    assert r.status == a.status == "ok"
    assert np.abs(r["az_mps2"]).max() > 0.3 * G_ACC
    assert np.abs(r["uy_m"]).max() > 0.1 * np.abs(r["ux_m"]).max() > 0.0
    assert _ledger(r) < 1e-10
    W = sum(r[f"W{i}_J"][-1] for i in range(1, 5))
    W0 = sum(a[f"W{i}_J"][-1] for i in range(1, 5))
    assert abs(W / W0 - 1) > 1e-4        # (measured 5.9e-4)
    M = scn.load("tfp-elcentro")["superstructure"]["mass"]
    slow = (np.abs(r["v_mps"]) < 1e-3) & (r["phi_rad"] < 0.01) & (r["alpha_rad"] < 0.02)
    k = np.flatnonzero(slow)[np.argmax(np.abs(r["az_mps2"][slow]))]
    assert r["N4_N"][k] == pytest.approx(M * (G_ACC + r["az_mps2"][k]), rel=0.03)


@pytest.mark.parametrize("both", [False, True])
def test_vertical_scale_is_the_x_record_as_file_z(both):
    """loading.vertical_scale = 1 on the TFP (planar and in both directions) is
    the x record's own file given as file_z, bit for bit; summary record_z
    names the copy."""
    over = ["solver.duration=3", 'thermal.model="none"', 'mechanics.model="seated"']
    if both:
        over += ['loading.record="impvall-1979-e11"', "solver.dt=2e-3"]
        xfile = ROOT / "scenes" / "records" / scn.RECORD_PAIRS["impvall-1979-e11"][0]
    else:
        xfile = Path(scn.load("tfp-elcentro")["loading"]["path"])
    sa = build(scn.load("tfp-elcentro", over + ["loading.vertical_scale=1"]))
    a = simulate(sa)
    b = simulate(build(scn.load("tfp-elcentro", over + [f'loading.file_z="{xfile}"'])))
    assert a.status == b.status == "ok" and a.columns == b.columns and "az_mps2" in a.columns
    np.testing.assert_array_equal(a.data, b.data)
    assert np.abs(a["az_mps2"]).max() > 0.02 * G_ACC
    assert sa.info["record_z"]["vertical_scale"] == 1.0


def _pulse(dt, t, k0, n):
    """a_z = -1.5 g over steps k0 .. k0 + 99 (exactly integrated), 0 elsewhere."""
    from fpd.loading.ground_motion import GroundMotion
    az = np.zeros(n)
    az[k0:k0 + 100] = -1.5 * G_ACC
    v = np.concatenate([[0.0], np.cumsum(az) * dt])
    d = np.concatenate([[0.0], np.cumsum(0.5 * (v[:-1] + v[1:]) * dt)])
    return GroundMotion("pulse", dt, t, d, v, np.concatenate([az, [0.0]]), az)


@pytest.mark.parametrize("deg", [30.0, -120.0])
def test_a_turned_record_flies_and_lands_as_the_planar_tfp(deg):
    """x_g = 0.10 sin(pi t) turned by an angle and a_z = -1.5 g for 0.1 s while
    the TFP slides: one lift-off, and the flight (its time, the height above
    the seat, the superstructure's path, the take-off and landing losses) and
    the whole history around it are the planar seated TFP's under the same
    two components to 1e-9 (measured 1e-12); the ledger closes every step
    with E_land; no NaN. (The planar flight is checked against an independent
    integration in tests/test_tfp_liftoff.py.)"""
    g, dt = tfp(), 1e-3
    gx = harmonic_ground_motion(0.10, 0.5, 10, dt, duration=2.4)
    gz = _pulse(dt, gx.t, 1000, gx.n_steps)
    p, _ = stepped(TFPStepper(g, gx, gz=gz), gx.n_steps)
    ang = math.radians(deg)
    s = TFP3DStepper(g, *turned(gx, ang), kernel=_kernel(), az=gz.a_step)
    d, res = stepped(s, gx.n_steps)
    flies_as_planar(d, p, ("W1_J", "W2_J", "W3_J", "W4_J", "E_input_J", "E_kin_J", "E_pot_J", "E_land_J"))
    e_in = np.maximum.accumulate(np.abs(d["E_input_J"]))
    assert np.all(np.abs(res) <= 1e-9 * np.maximum(e_in, 1e-300))


def test_a_pair_with_a_vertical_pulse_flies_through_a_scene():
    """The Imperial Valley pair with a_z = -1.5 g from 1.001 to 1.2 s
    (tests/data/pulse_z.txt): one lift-off, the flight time within 1 % of
    z'' = -(g + a_z) from rest on a flat seat (the bearing nearly at rest at
    the pulse), the ledger closes with E_land, no NaN, summary's lift_off."""
    r = flies_through_the_pulse(PAIR)
    res = r["E_input_J"] - (r["E_kin_J"] + r["E_pot_J"] + r["W1_J"] + r["W2_J"] + r["W3_J"] + r["W4_J"]
                            + r["E_land_J"])
    assert np.max(np.abs(res)) <= 1e-10 * np.max(np.abs(r["E_input_J"]))


def flies_through_the_pulse(pair):
    """tfp-elcentro with the pair's keys and tests/data/pulse_z.txt (a_z = -1.5 g
    from 1.001 to 1.2 s), 3 s at 2 ms: ok, no NaN, one lift-off with a landing
    loss, its flight time within 1 % of z'' = -(g + a_z) from rest on a flat
    seat. Returns the result."""
    from fpd.outputs.output import lift_summary
    pulse = ROOT / "tests" / "data" / "pulse_z.txt"
    r = simulate(build(scn.load("tfp-elcentro", pair + ["solver.duration=3", "solver.dt=2e-3", "loading.scale=1",
                                                        f'loading.file_z="{pulse}"', "loading.baseline=false"])))
    assert r.status == "ok" and not np.isnan(r.data).any()
    lo = lift_summary(r.stats)
    assert lo["count"] == 1 and lo["landing_loss_J"] > 0.0
    v, z = 0.5 * G_ACC * 0.2, 0.25 * G_ACC * 0.2 ** 2
    assert lo["flight_time_s"] == pytest.approx(0.2 + (v + math.sqrt(v * v + 2 * G_ACC * z)) / G_ACC, rel=0.01)
    return r


def test_the_vtk_follows_the_flight(tmp_path):
    """output.vtk_every through a flight in both directions: the superstructure's
    block stays over the superstructure, (xg + ux, yg + uy), in the air too,
    its top rising with z_m; the lower plate stays with the ground."""
    import csv

    import meshio
    pulse = ROOT / "tests" / "data" / "pulse_z.txt"
    out = tmp_path / "vtk"
    p = subprocess.run([sys.executable, "-m", "fpd", "run", "tfp-elcentro", "--quiet", "--out", str(out),
                        "--set", 'loading.record="impvall-1979-e11"', "--set", 'mechanics.model="seated"',
                        "--set", "loading.scale=1", "--set", f'loading.file_z="{pulse}"',
                        "--set", "loading.baseline=false", "--set", "solver.duration=2", "--set", "solver.dt=2e-3",
                        "--set", 'thermal.model="none"', "--set", "output.vtk_every=50",
                        "--set", "output.plots=false"], capture_output=True, text=True, cwd=ROOT)
    assert p.returncode == 0, p.stderr
    rows = list(csv.DictReader((out / "timeseries.csv").open()))
    frames = sorted((out / "vtk").glob("device3d_*.vtu"))
    tops, flying = [], 0
    for k, f in enumerate(frames):
        row = rows[50 * k]
        flying += float(row["lift_m"]) > 0.0
        m = meshio.read(f)
        for cb, b in zip(m.cells, m.cell_data["body"]):
            if cb.type == "hexahedron":
                c = m.points[cb.data[0]]
                assert abs(c[:, 0].mean() - (float(row["xg_m"]) + float(row["ux_m"]))) <= 1e-9
                assert abs(c[:, 1].mean() - (float(row["yg_m"]) + float(row["uy_m"]))) <= 1e-9
                tops.append((c[:, 2].min(), float(row["z_m"])))
    assert flying >= 3
    base = tops[0][0] - tops[0][1]
    assert all(abs(z0 - zm - base) <= 1e-9 for z0, zm in tops)
