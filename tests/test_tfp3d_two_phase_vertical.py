"""The two-phase TFP in both horizontal directions under vertical ground
motion (mechanics/tfp3d_two_phase.py, docs/model.md 10): g + a_z in its
normal forces, caps, heat, re-seating and ledger, the seated 3D TFP's flight
and landing around its step; a zero vertical record changes nothing; a
record turned in the plane with a vertical one is the planar two-phase TFP's
run with it, lift-off and landing included; the ledger closes every step."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from fpd import kernels
from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.loading.ground_motion import harmonic_ground_motion, pulse_ground_motion
from fpd.mechanics.geometry import G_ACC
from fpd.mechanics.tfp import TFPStepper
from fpd.mechanics.tfp3d_two_phase import TFP3DTwoPhaseStepper
from fpd.schema import scene as scn

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_tfp import tfp  # noqa: E402
from tfp3d_helpers import flies_as_planar, stepped, turned_as_planar  # noqa: E402
from test_tfp3d import turned  # noqa: E402
from test_tfp3d_vertical import _pulse, flies_through_the_pulse  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
V2 = ROOT / "scenes" / "records" / "FERNDALE2022_CE89486.v2"
PAIR = ['loading.record="impvall-1979-e11"', 'mechanics.model="two-phase"', 'thermal.model="lumped"']
VERTICAL = ["az_mps2", "lift_m", "n_lift", "t_flight_s", "E_land_J"]


def _kernel():
    return kernels.compiled("fpd.mechanics.tfp3d_two_phase_kernel") if kernels.available() else None


def _closes(d, res, tol=1e-9):
    e_in = np.maximum.accumulate(np.abs(d["E_input_J"]))
    return np.all(np.abs(res) <= tol * np.maximum(e_in, 1e-300))


def test_a_zero_vertical_record_reproduces_the_run_bit_for_bit(tmp_path):
    """The Imperial Valley pair with file_z of zeros on another time grid: the
    two-phase run's rows bit for bit, plus the vertical columns (all 0)."""
    z = tmp_path / "zero.txt"
    z.write_text("# [g]\n" + "".join(f"{0.004 * k:.3f} 0.0\n" for k in range(1500)))
    over = PAIR + ["solver.duration=3", "solver.dt=2e-3", "loading.scale=1", "friction.mu_ref=0.04"]
    a = simulate(build(scn.load("tfp-elcentro", over)))
    b = simulate(build(scn.load("tfp-elcentro", over + [f'loading.file_z="{z}"'])))
    assert a.status == b.status == "ok"
    assert "E_reseat_J" in a.columns and list(b.columns) == list(a.columns) + VERTICAL
    assert np.abs(a["E_reseat_J"]).max() > 0.0
    np.testing.assert_array_equal(b.data[:, :len(a.columns)], a.data)
    assert np.all(b.data[:, len(a.columns):] == 0.0)


@pytest.mark.parametrize("deg", [30.0, -120.0])
def test_a_turned_record_with_a_vertical_one_is_the_planar_two_phase_tfp_with_it(deg):
    """A record turned by an angle in the plane with a vertical harmonic (0.5 g
    at 1.3 Hz): the resultant history (|u|, |F|, the normal forces, the
    friction work of each surface, the input, kinetic and potential energy,
    the re-seating loss, the phases) is the planar two-phase TFP's under the
    same two components to 1e-9; the vertical motion changes the run far more
    than that; the ledger (with the vertical ground's work as input) closes
    every step to 1e-9 of the input."""
    g = tfp()
    dt = 1e-3
    gm = pulse_ground_motion("cosine", 0.35, 1.5, 0.5, 3.0, dt)
    gz = harmonic_ground_motion(0.5 * G_ACC / (2 * math.pi * 1.3) ** 2, 1.3, 10, dt, duration=3.0)
    p, _ = stepped(TFPStepper(g, gm, model="two-phase", gz=gz), gm.n_steps)
    p0, _ = stepped(TFPStepper(g, gm, model="two-phase"), gm.n_steps)
    ang = math.radians(deg)
    s = TFP3DTwoPhaseStepper(g, *turned(gm, ang), kernel=_kernel(), az=gz.a_step)
    d, res = stepped(s, gm.n_steps)
    assert list(s.columns[-5:]) == VERTICAL and np.array_equal(d["az_mps2"], p["az_mps2"])
    wt = turned_as_planar(d, p, ang, ("E_input_J", "E_kin_J", "E_pot_J", "E_reseat_J"))
    assert p["E_reseat_J"][-1] > 0.0
    assert np.array_equal(d["phases"], p["phases"])
    # the vertical record matters: the friction work and the normal forces change by much more than 1e-9
    assert abs(sum(p0[f"W{i}_J"][-1] for i in range(1, 5)) / wt - 1) > 1e-3
    assert np.max(np.abs(p["N1_N"] - p0["N1_N"])) > 0.3 * g.weight
    assert _closes(d, res)


@pytest.mark.parametrize("deg", [30.0, 135.0])
def test_a_turned_record_flies_and_lands_as_the_planar_two_phase_tfp(deg):
    """x_g = 0.10 sin(pi t) turned by an angle and a_z = -1.5 g for 0.1 s while
    the TFP slides: one lift-off, and the flight (its time, the height above
    the seat, the landing loss) and the whole history around it are the
    planar two-phase TFP's under the same two components to 1e-9; in the air
    no normal force, no force, no phases; the ledger closes every step with
    E_reseat and E_land; no NaN."""
    g, dt = tfp(), 1e-3
    gx = harmonic_ground_motion(0.10, 0.5, 10, dt, duration=2.4)
    gz = _pulse(dt, gx.t, 1000, gx.n_steps)
    p, _ = stepped(TFPStepper(g, gx, model="two-phase", gz=gz), gx.n_steps)
    ang = math.radians(deg)
    s = TFP3DTwoPhaseStepper(g, *turned(gx, ang), kernel=_kernel(), az=gz.a_step)
    d, res = stepped(s, gx.n_steps)
    air = flies_as_planar(d, p, ("W1_J", "W2_J", "W3_J", "W4_J", "E_input_J", "E_kin_J", "E_pot_J", "E_land_J",
                                 "E_reseat_J"))
    assert d["E_land_J"][-1] > 0.0
    assert np.all(d["phases"][air] == 0.0)
    assert _closes(d, res)


def test_a_pair_with_a_vertical_pulse_flies_through_a_scene():
    """The Imperial Valley pair with a_z = -1.5 g from 1.001 to 1.2 s, the
    two-phase model: one lift-off, the flight time within 1 % of z'' = -(g +
    a_z) from rest on a flat seat, the ledger closes with E_reseat and
    E_land, no NaN, summary's lift_off."""
    r = flies_through_the_pulse(PAIR)
    res = r["E_input_J"] - (r["E_kin_J"] + r["E_pot_J"] + r["W1_J"] + r["W2_J"] + r["W3_J"] + r["W4_J"]
                            + r["E_land_J"] + r["E_reseat_J"])
    assert np.max(np.abs(res)) <= 1e-10 * np.max(np.abs(r["E_input_J"]))


@pytest.mark.parametrize("sets", [
    [f'loading.file_z="{V2}"'],
    ["loading.vertical_scale=0.5"],
    ['loading.record="ferndale-2022"'],
])
def test_the_two_phase_tfp_in_both_directions_takes_a_vertical(sets):
    """file_z, vertical_scale and a V2 record's vertical channel are taken by the
    two-phase model in both directions: the run carries the vertical columns."""
    base = ['loading.record="impvall-1979-e11"', 'mechanics.model="two-phase"', 'thermal.model="none"',
            "solver.duration=0.1", "solver.dt=2e-3"]
    sim = build(scn.load("tfp-elcentro", base + sets))
    assert list(sim.mechanics.columns[-5:]) == VERTICAL and "E_reseat_J" in sim.mechanics.columns
