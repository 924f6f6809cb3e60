"""The rigid TFP in both horizontal directions (mechanics/tfp3d.py,
mechanics/tfp3d_kernel.py, docs/model.md section 6.8): the step's cone
program against its optimality conditions and an independent minimiser, the
planar TFP reproduced with no y component, a turned record, the ledger,
convergence, scenes."""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fpd import kernels
from fpd.mechanics import tfp3d_kernel as K
from fpd.loading.ground_motion import GroundMotion, pulse_ground_motion
from fpd.mechanics.tfp3d import TFP3DStepper

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_tfp import MUS, tfp  # noqa: E402
from tfp3d_helpers import run_planar, stepped  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


def _kernel():
    return kernels.compiled("fpd.mechanics.tfp3d_kernel") if kernels.available() else None


def run3d(g, gx, gy=None, mus=MUS, kernel="auto"):
    s = TFP3DStepper(g, gx, gy, kernel=_kernel() if kernel == "auto" else kernel)
    return (s,) + stepped(s, gx.n_steps, mus)


def turned(gm, ang):
    c, s = math.cos(ang), math.sin(ang)
    f = ("d", "v", "a", "a_step")
    gx = GroundMotion(gm.name, gm.dt, gm.t, *(c * getattr(gm, k) for k in f))
    gy = GroundMotion(gm.name, gm.dt, gm.t, *(s * getattr(gm, k) for k in f))
    return gx, gy


WIDE = tfp(d2=0.09, d3=0.09)      # inner capacity for a pair that engages S1 and S4 before the rims


def pair(dt, duration=3.0):
    """A two-component ground motion: two pulses of different periods and times."""
    gx = pulse_ground_motion("cosine", 0.35, 1.2, 0.4, duration, dt)
    gy = pulse_ground_motion("cosine", 0.25, 0.8, 0.9, duration, dt)
    return gx, gy


# -- the cone program ------------------------------------------------------------------
def test_socp_is_the_minimiser_against_an_independent_solver():
    """Random strictly convex instances in every active set: the step's
    solution satisfies the optimality conditions to round-off and no point
    found by scipy's minimiser (from the solution and from 0) is lower."""
    from scipy.optimize import minimize
    rng = np.random.default_rng(3)
    sc = np.zeros(K.N_SC)
    sets = set()
    for _ in range(120):
        A = rng.normal(size=(4, 4))
        H = A @ A.T + 0.2 * np.eye(4)
        r = rng.normal(size=4) * 2.0
        c1, c2 = rng.uniform(0.0, 3.0, 2)
        y = np.zeros(4)
        K.socp(H.ravel(), r, c1, c2, y, sc)
        assert K.kkt_residual(H.ravel(), r, c1, c2, y) <= 1e-12

        def f(x):
            return 0.5 * x @ H @ x - r @ x + c1 * np.hypot(x[0], x[1]) + c2 * np.hypot(x[2], x[3])
        for x0 in (y + 1e-2 * rng.normal(size=4), np.full(4, 1e-3)):
            other = minimize(f, x0, method="Powell", options={"xtol": 1e-10, "ftol": 1e-14})
            assert f(y) <= other.fun + 1e-12 * (1.0 + abs(other.fun))
        sets.add((np.hypot(y[0], y[1]) > 0, np.hypot(y[2], y[3]) > 0))
    assert sets == {(False, False), (True, False), (False, True), (True, True)}


# -- the planar TFP reproduced --------------------------------------------------------------
def test_no_y_component_reproduces_the_planar_tfp():
    """A record without y: the 3D stepper's x columns are the planar TFP's to
    1e-12 (of the peak displacement, the peak tilts, the total work), both
    sliding regimes and sticking visited; y stays 0. On the axis the step
    does the planar TFP's floating-point operations (mass matrix, discrete
    gradient, the cone program's candidates, the rates' solve), so phi and
    alpha are the planar ones bit for bit (measured: u to 3.1e-16, the
    energies to 1.1e-14). For scale, the planar model itself moves 5.8e-12
    of the peak over these 3000 steps when its record is changed by one ulp."""
    g = tfp()
    gm = pulse_ground_motion("cosine", 0.5, 1.5, 0.5, 3.0, 1e-3)
    p = run_planar(g, gm)
    _, d, _ = run3d(g, gm)
    assert set(p["regime"]) >= {0.0, 1.0, 6.0}
    assert np.max(np.abs(d["uy_m"])) == 0.0 and np.max(np.abs(d["phiy_rad"])) == 0.0
    tol = 1e-12
    um = np.max(np.abs(p["u_m"]))
    assert np.max(np.abs(d["ux_m"] - p["u_m"])) <= tol * um
    assert np.max(np.abs(d["phix_rad"] - p["phi_rad"])) <= tol * np.max(np.abs(p["phi_rad"]))
    assert np.max(np.abs(d["alphax_rad"] - p["alpha_rad"])) <= tol * np.max(np.abs(p["alpha_rad"]))
    wt = sum(p[f"W{i}_J"][-1] for i in range(1, 5))
    for c in ("W1_J", "W2_J", "W3_J", "W4_J", "E_input_J", "E_kin_J", "E_pot_J"):
        assert np.max(np.abs(d[c] - p[c])) <= tol * wt, c
    Fm = np.max(np.abs(p["F_N"]))
    assert np.max(np.abs(d["Fx_N"] - p["F_N"])) <= 1e-9 * Fm
    assert np.array_equal(d["regime"], p["regime"])


@pytest.mark.parametrize("deg", [30.0, 135.0, -71.0])
def test_a_turned_record_is_the_planar_run_turned(deg):
    """One record turned by an angle: the resultant history (|u|, |F|, the
    slides, the friction work, the energies) is the run along x, to 1e-9;
    u points along the record's direction."""
    g = tfp()
    gm = pulse_ground_motion("cosine", 0.5, 1.5, 0.5, 3.0, 1e-3)
    _, d0, _ = run3d(g, gm)
    ang = math.radians(deg)
    _, d, _ = run3d(g, *turned(gm, ang))
    um = np.max(d0["u_m"])
    assert np.max(np.abs(d["u_m"] - d0["u_m"])) <= 1e-9 * um
    assert np.max(np.abs(d["uy_m"] * math.cos(ang) - d["ux_m"] * math.sin(ang))) <= 1e-9 * um
    assert np.max(np.abs(d["F_N"] - d0["F_N"])) <= 1e-9 * np.max(d0["F_N"])
    wt = sum(d0[f"W{i}_J"][-1] for i in range(1, 5))
    for c in ("W1_J", "W2_J", "W3_J", "W4_J", "E_input_J", "E_kin_J", "E_pot_J", "s1_m", "s2_m"):
        scale = wt if c.endswith("_J") else np.max(d0[c]) + 1e-300
        assert np.max(np.abs(d[c] - d0[c])) <= 1e-9 * scale, c


# -- the ledger, the optimality conditions, convergence ----------------------------------------
def test_ledger_and_optimality_every_step_under_a_pair():
    """Two components: every step the input equals kinetic + potential +
    friction work to 1e-9 of the input, the step's increment satisfies the
    cone program's optimality conditions to 1e-10, and all four coordinates
    and the four surfaces slide in turn."""
    g = WIDE
    gx, gy = pair(1e-3)
    s, d, res = run3d(g, gx, gy)
    e_in = np.maximum.accumulate(np.abs(d["E_input_J"]))
    assert np.all(np.abs(res) <= 1e-9 * np.maximum(e_in, 1e-300))
    assert np.max(d["kkt_rel"]) <= 1e-10
    assert set(d["regime"]) >= {0.0, 1.0, 6.0}
    assert np.max(np.abs(d["uy_m"])) > 0.2 * np.max(np.abs(d["ux_m"]))
    assert all(d[f"W{i}_J"][-1] > 0 for i in range(1, 5))


def _impvall(dt, duration=10.0):
    """The packaged Imperial Valley pair at half scale on the grid dt, and the scene's TFP."""
    from fpd.coupling.build import bidirectional_loading_of
    from fpd.schema import scene as scn
    sc = scn.load("tfp-elcentro", ['loading.record="impvall-1979-e11"', 'mechanics.model="seated"',
                                   "loading.scale=0.5", f"solver.duration={duration}", f"solver.dt={dt}",
                                   'thermal.model="none"'])
    return scn.tfp_geometry(sc.data), bidirectional_loading_of(sc, dt)


def test_friction_work_converges_at_first_order_or_better():
    """Total friction work under a two-component record (Imperial Valley 1979,
    both components, half scale, 10 s) at dt = 4, 2, 1, 0.5, 0.25 ms: the
    observed order from successive differences, log2 |W(dt) - W(dt/2)| /
    |W(dt/2) - W(dt/4)|, is >= 1 each time (measured 1.8, 3.3, 2.9)."""
    W = []
    for dt in (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4):
        g, (gx, gy) = _impvall(dt)
        s = TFP3DStepper(g, gx, gy, kernel=_kernel())
        for _ in range(s.n_steps):
            s.step(*MUS)
        W.append(sum(s.W))
    d = [abs(W[i] - W[i + 1]) for i in range(len(W) - 1)]
    orders = [math.log2(d[i] / d[i + 1]) for i in range(len(d) - 1)]
    assert min(orders) >= 1.0, (W, orders)
    assert d[-1] <= 1e-5 * W[-1]


def test_compiled_kernel_equals_pure_bit_for_bit():
    if not kernels.available():
        pytest.skip("numba not available")
    g = tfp()
    gx, gy = pair(2e-3, 1.2)
    _, a, _ = run3d(g, gx, gy, kernel=None)
    _, b, _ = run3d(g, gx, gy, kernel=_kernel())
    for c in a:
        assert np.array_equal(a[c], b[c]), c


# -- scenes ----------------------------------------------------------------------------
def _cli(args, tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=ROOT, env=env, capture_output=True, text=True)


def test_a_record_pair_runs_with_heat_on_four_parts(tmp_path):
    out = tmp_path / "run"
    r = _cli(["run", "tfp-elcentro", "--out", str(out), "--quiet", "--set", 'loading.record="impvall-1979-e11"',
              "--set", 'mechanics.model="seated"', "--set", "solver.duration=4.0", "--set", 'thermal.model="lumped"',
              "--set", "loading.scale=0.5"], tmp_path)
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "ok" and s["energy_residual_rel"] <= 1e-9 and s["heat_residual_rel"] <= 1e-9
    head = (out / "timeseries.csv").read_text().split("\n", 1)[0].split(",")
    for c in ("ux_m", "uy_m", "Fx_N", "Fy_N", "phix_rad", "phiy_rad", "alphax_rad", "alphay_rad",
              "s1x_m", "s4y_m", "c2x_m", "c3y_m", "W4_J", "T4_C"):
        assert c in head, c
    # the figures of a run in both directions: x and y loops, orbits, the four parts' heat paths
    for name in ("hysteresis", "response", "orbit", "force_orbit", "heat_path", "temperature", "friction"):
        assert (out / "plots" / f"{name}.png").is_file(), name


def test_vtk_of_the_five_bodies_in_3d(tmp_path):
    """output.vtk_every on an orbit: device3d frames of the six bodies (two
    plates, two slider plates, the pad, the superstructure's block); the
    block sits over the superstructure, (xg + ux, yg + uy) (held at the
    origin by the machine), the pad halfway between the plates' centres."""
    import csv

    import meshio
    out = tmp_path / "vtk"
    r = _cli(["run", "tfp-lab", "--out", str(out), "--quiet", "--set", 'loading.waveform="circle"',
              "--set", "loading.amplitude_m=0.04", "--set", "loading.cycles=0.5", "--set", 'thermal.model="lumped"',
              "--set", "output.vtk_every=500"], tmp_path)
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader((out / "timeseries.csv").open()))
    frames = sorted((out / "vtk").glob("device3d_*.vtu"))
    assert len(frames) >= 3 and (out / "vtk" / "device3d.pvd").is_file()
    for k, f in enumerate(frames):
        row = rows[500 * k]
        m = meshio.read(f)
        assert {int(b[0]) for b in m.cell_data["body"]} == set(range(6))
        for cb, b in zip(m.cells, m.cell_data["body"]):
            if cb.type == "hexahedron":
                c = m.points[cb.data[0]][:, :2].mean(axis=0)
                assert abs(c[0] - (float(row["xg_m"]) + float(row["ux_m"]))) <= 1e-9
                assert abs(c[1] - (float(row["yg_m"]) + float(row["uy_m"]))) <= 1e-9


def test_fe3d_on_the_four_parts_along_the_2d_paths(tmp_path):
    """The 3D plates take the footprint paths in x and y: the heat ledger closes."""
    out = tmp_path / "fe3d"
    r = _cli(["run", "tfp-elcentro", "--out", str(out), "--quiet", "--set", 'loading.record="impvall-1979-e11"',
              "--set", 'mechanics.model="seated"', "--set", "solver.duration=6.0", "--set", "solver.dt=2e-3",
              "--set", 'thermal.model="fe3d"'], tmp_path)
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "ok" and s["heat_residual_rel"] <= 1e-9 and s["peak_T2_C"] > 25.0


@pytest.mark.parametrize("sets,key", [
    # both models take a vertical ground motion (tests/test_tfp3d_vertical.py, test_tfp3d_two_phase_vertical.py)
    (['thermal.model="axisym"'], "thermal.lower.model"),
    (["coupling.substeps=2"], "coupling.substeps"),
])
def test_what_the_tfp_in_both_directions_does_not_do_yet_is_refused_in_one_line(sets, key):
    from fpd.schema import scene as scn
    base = ['loading.record="impvall-1979-e11"', 'mechanics.model="seated"', 'thermal.model="lumped"']
    with pytest.raises(scn.SceneError) as err:
        scn.load("tfp-elcentro", base + sets)
    msg = str(err.value)
    assert key in msg and "\n" not in msg


# -- the test machine ------------------------------------------------------------------------
def orbit(g, A, f=0.1, cycles=2.0, dt=5e-3, mus=MUS, waveform="circle", direction_deg=0.0):
    from fpd.loading.orbits import orbit_programme
    prog = orbit_programme(waveform, A, f, cycles, dt, direction_deg=direction_deg)
    s = TFP3DStepper(g, prog, kernel=_kernel())
    rows = [s.values()]
    res = [s.ledger_residual()]
    for _ in range(prog.n_steps):
        s.step(*mus)
        rows.append(s.values())
        res.append(s.ledger_residual())
    d = np.array(rows)
    return prog, {c: d[:, i] for i, c in enumerate(s.columns)}, np.array(res)


def test_circle_orbit_in_regime_one_dissipates_two_pi_a_f_i():
    """A circle of radius A = 40 mm at 0.1 Hz: only S2 and S3 slide (the
    stack stays seated), the bearing follows the orbit exactly, and the
    second revolution dissipates 2 pi A F_i within 0.5 % (F_i = (mu2 R2 +
    mu3 R3) W_i / L_i, W_i the weight S2 and S3 carry: the superstructure,
    the upper slider plate and half the pad; measured +0.15 %, the normal
    forces' W / cos(psi) on the tilted pad)."""
    g = tfp()
    A = 0.04
    prog, d, res = orbit(g, A)
    assert set(d["regime"]) <= {0.0, 1.0} and np.max(d["phi_rad"]) == 0.0
    assert np.max(np.abs(d["ux_m"] + d["xg_m"])) <= 1e-12 and np.max(np.abs(d["uy_m"] + d["yg_m"])) <= 1e-12
    assert np.max(np.abs(res)) <= 1e-12 * np.max(np.abs(d["E_input_J"]))
    assert np.max(d["kkt_rel"]) <= 1e-10
    W = sum(d[f"W{i}_J"] for i in range(1, 5))
    n1 = prog.n_steps // 2
    Wi = (g.mass + g.slider_mass + 0.5 * g.pad_mass) * g.g
    Fi = (MUS[1] * g.R2 + MUS[2] * g.R3) * Wi / g.Li
    assert abs((W[-1] - W[n1]) / (2 * math.pi * A * Fi) - 1.0) <= 5e-3


def test_a_turned_line_through_its_reversals_is_the_planar_machine():
    """A straight sine of 120 mm at 0.2 Hz along 30 degrees engages S1 and S4
    and reverses twice: at each reversal the bearing sticks while the
    machine's force crosses from one friction cap to the other (Newton on the
    force alone stalls there: the residual is the same over the whole stuck
    region). The bearing follows the line, the ledger closes, and the
    resultant history is the planar TFP machine's (another kernel) under the
    same programme along x (measured: u 4.6e-16, F 2.1e-11, W 2.2e-15)."""
    from fpd.loading.ground_motion import sine_programme
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from test_tfp import run as run_tfp
    g = tfp()
    ang = math.radians(30.0)
    prog, d, res = orbit(g, 0.12, f=0.2, cycles=1.0, dt=2e-3, waveform="sine", direction_deg=30.0)
    assert {3.0, 6.0} <= set(d["regime"]) and 0.0 in set(d["regime"])
    assert np.max(np.abs(d["ux_m"] + d["xg_m"])) <= 1e-12 and np.max(np.abs(d["uy_m"] + d["yg_m"])) <= 1e-12
    assert np.max(np.abs(res)) <= 1e-9 * np.max(np.abs(d["E_input_J"]))
    _, p, _ = run_tfp(g, sine_programme(0.12, 0.2, 1.0, 2e-3))
    um, Fm = np.max(np.abs(p["u_m"])), np.max(np.abs(p["F_N"]))
    assert np.max(np.abs(d["ux_m"] * math.cos(ang) + d["uy_m"] * math.sin(ang) - p["u_m"])) <= 1e-9 * um
    assert np.max(np.abs(d["Fx_N"] * math.cos(ang) + d["Fy_N"] * math.sin(ang) - p["F_N"])) <= 1e-9 * Fm
    wt = sum(p[f"W{i}_J"][-1] for i in range(1, 5))
    for i in range(1, 5):
        assert np.max(np.abs(d[f"W{i}_J"] - p[f"W{i}_J"])) <= 1e-9 * wt, i


def test_an_orbit_engaging_all_four_surfaces_against_an_independent_ode():
    """A circle of 120 mm at 0.2 Hz engages S1 and S4 (regime I+III): the
    second revolution's dissipation equals that of an independent
    continuous-time computation (tests/tfp3d_reference.py: regularised
    friction, the orbit as a constraint, scipy's LSODA) within 1 %
    (measured -0.07 %; DOP853 at rtol 1e-10 gives the same 20842 J)."""
    from tfp3d_reference import circle_second_revolution
    g = WIDE
    A, f = 0.12, 0.2
    prog, d, res = orbit(g, A, f=f, cycles=2.0, dt=5e-3)
    assert 6.0 in set(d["regime"]) and min(d["W1_J"][-1], d["W4_J"][-1]) > 0.1 * d["W2_J"][-1]
    assert np.max(np.abs(res)) <= 1e-12 * np.max(np.abs(d["E_input_J"]))
    W = sum(d[f"W{i}_J"] for i in range(1, 5))
    n1 = prog.n_steps // 2
    y0 = TFP3DStepper(g, prog).S[0:8].copy()             # the machine's placement at u(0), u'(0)
    Wref = circle_second_revolution(g, MUS, A, f, y0)
    assert abs((W[-1] - W[n1]) / Wref - 1.0) <= 0.01


def test_an_orbit_is_a_scene(tmp_path):
    """loading.waveform = "circle" on the TFP's test machine runs in both
    directions; the ledger closes."""
    out = tmp_path / "orbit"
    r = _cli(["run", "tfp-lab", "--out", str(out), "--quiet", "--set", 'loading.waveform="circle"',
              "--set", "loading.amplitude_m=0.04", "--set", "loading.cycles=1", "--set", 'thermal.model="lumped"'],
             tmp_path)
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "ok" and s["energy_residual_rel"] <= 1e-9
