"""Lift-off and landing of the planar TFP (docs/model.md 10): under a
vertical pulse below -g the stack and the superstructure leave the lower
plate, fly ballistically (no contact, no friction, no heat) and land with a
plastic impact booked in E_land; checked against an independent
integration of the flight, the ledger, and through a scene."""
from __future__ import annotations

import dataclasses
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from fpd.loading.ground_motion import GroundMotion, harmonic_ground_motion
from fpd.mechanics.geometry import G_ACC
from fpd.mechanics.tfp import TFPStepper

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_tfp import MUS, tfp  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PULSE = ROOT / "tests" / "data" / "pulse_z.txt"      # -1.5 g from 1.001 to 1.2 s


def _vertical(a_step, dt, t):
    """A vertical ground motion whose step means are a_step (exact integration)."""
    v = np.concatenate([[0.0], np.cumsum(a_step) * dt])
    d = np.concatenate([[0.0], np.cumsum(0.5 * (v[:-1] + v[1:]) * dt)])
    return GroundMotion("pulse", dt, t, d, v, np.concatenate([a_step, [0.0]]), a_step)


def _run(g, gx, gz, kernel=None):
    s = TFPStepper(g, gx, gz=gz, kernel=kernel)
    rows, res, states = [s.values()], [s.ledger_residual()], [s.S.copy()]
    for _ in range(gx.n_steps):
        s.step(*MUS)
        rows.append(s.values())
        res.append(s.ledger_residual())
        states.append(s.S.copy())
    d = np.array(rows)
    return {c: d[:, i] for i, c in enumerate(s.columns)}, np.array(res), states


def _take_off(g, S0):
    """(the unit's mass, the pad's tilt, the superstructure's position x, z
    and velocity vx, vz) at take-off from the state S0: the velocity from the
    bodies' momentum (geom.bodies)."""
    phi, al, w1, w2 = S0[0], S0[1], S0[2], S0[3]
    ps = phi + al
    bodies = g.bodies()
    mt = sum(b[0] for b in bodies)
    px = sum(m * (a * w1 * math.cos(phi) + b * (w1 + w2) * math.cos(ps)) for m, a, b, _, _ in bodies)
    pz = sum(m * (a * w1 * math.sin(phi) + b * (w1 + w2) * math.sin(ps)) for m, a, b, _, _ in bodies)
    return (mt, al, g.A * math.sin(phi) + g.Li * math.sin(ps), g.A * (1 - math.cos(phi)) + g.Li * (1 - math.cos(ps)),
            px / mt, pz / mt)


def _independent_flight(g, S0, ax, az, k0, dt):
    """The flight from the state S0 at the start of step k0, integrated apart
    from the kernel: the unit's velocity from the bodies' momentum (geom.bodies),
    its superstructure's path piecewise quadratic per step under the step means
    (ax, g + az), the seat under it with the pad's tilt held (scipy brentq on
    A sin phi + L_i sin(phi + alpha) = u), the landing the first root of the
    height above the seat (brentq). Returns (flight time, peak height above the
    seat, the superstructure's horizontal position at landing)."""
    mt, al, x, z, vx, vz = _take_off(g, S0)

    def seat(u):
        f = brentq(lambda p: g.A * math.sin(p) + g.Li * math.sin(p + al) - u, -0.5, 0.5, xtol=1e-15, rtol=1e-15)
        return g.A * (1 - math.cos(f)) + g.Li * (1 - math.cos(f + al))

    t, peak = 0.0, 0.0
    for k in range(k0, len(ax)):
        a, b = ax[k], g.g + az[k]

        def lift(s):
            return z + vz * s - 0.5 * b * s * s - seat(x + vx * s - 0.5 * a * s * s)
        if k > k0 and lift(dt) <= 0.0:
            s = brentq(lift, 0.0, dt, xtol=1e-15, rtol=1e-15)
            return t + s, peak, x + vx * s - 0.5 * a * s * s
        for s in np.linspace(0.0, dt, 5)[1:]:
            peak = max(peak, lift(s))
        x, z = x + vx * dt - 0.5 * a * dt * dt, z + vz * dt - 0.5 * b * dt * dt
        vx, vz = vx - a * dt, vz - b * dt
        t += dt
    raise AssertionError("no landing")


def test_flight_under_a_vertical_pulse_against_an_independent_integration():
    """A seated TFP sliding under x_g = 0.15 sin(pi t) takes a_z = -1.5 g for
    0.1 s: one lift-off at the pulse's first step; the flight time agrees with
    the independent integration to 1e-9 relative (the acceptance asks 1 %),
    and is within 3 % of the flat-seat closed form T + (v + sqrt(v^2 + 2 g z))
    / g, v = 0.5 g T, z = 0.25 g T^2; the landing position and the peak height
    likewise; in the air no normal force, friction, heat or force; the
    ledger closes every step (1e-11 of the input) with E_land, no NaN."""
    g, dt, T = tfp(), 1e-3, 3.0
    gx = harmonic_ground_motion(0.15, 0.5, 10, dt, duration=T)
    az = np.zeros(gx.n_steps)
    k0 = 1000
    az[k0:k0 + 100] = -1.5 * G_ACC
    d, res, states = _run(g, gx, _vertical(az, dt, gx.t))
    assert not any(np.isnan(v).any() for v in d.values())
    assert d["n_lift"][-1] == 1.0 and d["n_lift"][k0] == 0.0 and d["n_lift"][k0 + 1] == 1.0
    assert np.max(np.abs(res)) <= 1e-11 * np.max(np.abs(d["E_input_J"]))
    tf, peak, u_land = _independent_flight(g, states[k0], gx.a_step, az, k0, dt)
    assert d["t_flight_s"][-1] == pytest.approx(tf, rel=1e-9)
    flat = 0.1 + (0.05 * G_ACC + math.sqrt((0.05 * G_ACC) ** 2 + 2 * G_ACC * 0.0025 * G_ACC)) / G_ACC
    assert d["t_flight_s"][-1] == pytest.approx(flat, rel=0.03)
    assert np.max(d["lift_m"]) == pytest.approx(peak, rel=1e-3)       # the independent peak is sampled
    kl = k0 + int(tf / dt)                                               # the landing's step
    air = slice(k0 + 1, kl + 1)
    assert np.all(d["lift_m"][air] > 0.0) and d["lift_m"][kl + 1] == 0.0
    for c in ("N1_N", "N2_N", "N3_N", "N4_N", "F_N"):
        assert np.all(d[c][air] == 0.0), c
    for i in range(1, 5):
        assert np.all(np.diff(d[f"W{i}_J"][air]) == 0.0)
    # the landing: the seat under the flown position, the loss booked (>= 0)
    e0, e1 = d["E_land_J"][kl], d["E_land_J"][kl + 1]
    assert e1 > e0 >= 0.0
    assert d["u_m"][kl + 1] != 0.0 and abs(u_land - d["u_m"][kl]) < 0.05
    # the take-off loss: the bodies' motion relative to the unit's, of order m / M of the kinetic energy
    assert 0.0 <= d["E_land_J"][k0 + 1] <= 1e-2 * d["E_kin_J"][k0]


def _independent_spring_flight(g, S0, ax, az, k0, dt):
    """The flight from the state S0 at the start of step k0 with rims of
    finite stiffness g.rim_stiffness, apart from the kernel: the unit's
    horizontal path M x'' = -M a_x - E'(x) per step (scipy DOP853, rtol
    1e-12), E(x) the springs of S1 and S4 at the tilt of the seat under the
    unit (brentq on A sin phi + L_i sin(phi + alpha) = u, the pad's tilt
    held), E' by central differences; z ballistic; the landing the first root
    of the height above the seat (the solver's event). Returns the flight
    time."""
    mt, al, x, z, vx, vz = _take_off(g, S0)

    def seat_tilt(u):
        return brentq(lambda p: g.A * math.sin(p) + g.Li * math.sin(p + al) - u, -0.6, 0.6, xtol=1e-16, rtol=1e-15)

    def seat(u):
        f = seat_tilt(u)
        return g.A * (1 - math.cos(f)) + g.Li * (1 - math.cos(f + al))

    def energy(u):
        f = seat_tilt(u)
        return sum(0.5 * g.rim_stiffness * max(R * abs(f) - d, 0.0) ** 2 for R, d in ((g.R1, g.d1), (g.R4, g.d4)))

    t = 0.0
    for n in range(k0, len(ax)):
        a, b = ax[n], g.g + az[n]

        def height(s, y, z=z, vz=vz, b=b):
            return z + vz * s - 0.5 * b * s * s - seat(y[0])
        height.terminal, height.direction = True, -1
        sol = solve_ivp(lambda s, y, a=a: [y[1], -a - (energy(y[0] + 1e-7) - energy(y[0] - 1e-7)) / 2e-7 / mt],
                        (0.0, dt), [x, vx], method="DOP853", rtol=1e-12, atol=1e-14,
                        events=height if n > k0 else None)
        if n > k0 and sol.t_events[0].size:
            return t + sol.t_events[0][0]
        x, vx = sol.y[0, -1], sol.y[1, -1]
        z, vz = z + vz * dt - 0.5 * b * dt * dt, vz - b * dt
        t += dt
    raise AssertionError("no landing")


def test_rim_springs_push_the_flying_unit():
    """Rims of finite stiffness (k = 1e8 N/m) under a lift-off that starts
    with S1 and S4 past their capacity (a_z = -1.5 g for 0.1 s at t = 0.64 s
    under x_g = 0.6 sin(pi t)): in the air the springs push the unit, with
    the energy of the seat under it (docs/model.md 10), so that the springs
    hold the same energy at the take-off and the landing. The flight time
    agrees with an independent integration of that force to 1e-6 (measured
    5.4e-7 at dt = 1 ms, 1.3e-7 at 0.5 ms: second order, the discrete
    gradient's), the ledger closes every step to 1e-11 of the input
    (measured 1.1e-12), and neither the take-off nor the landing books a
    negative loss (a jump of the springs' energy would)."""
    from fpd import kernels
    kern = kernels.compiled("fpd.mechanics.tfp_kernel") if kernels.available() else None
    errs = []
    for dt in (1e-3, 5e-4):
        g = dataclasses.replace(tfp(), rim_stiffness=1e8)
        gx = harmonic_ground_motion(0.6, 0.5, 10, dt, duration=1.2)
        az = np.zeros(gx.n_steps)
        n0 = int(round(0.64 / dt))
        az[n0:n0 + int(round(0.1 / dt))] = -1.5 * G_ACC
        d, res, states = _run(g, gx, _vertical(az, dt, gx.t), kernel=kern)
        assert d["n_lift"][-1] == 1.0
        k0 = int(np.flatnonzero(np.diff(d["n_lift"]))[0])
        assert g.R1 * abs(d["phi_rad"][k0]) > g.d1 + 0.01          # S1 and S4 pressed into their rims
        assert np.max(np.abs(res)) <= 1e-11 * np.max(np.abs(d["E_input_J"]))
        assert np.all(np.diff(d["E_land_J"]) >= 0.0)
        tf = _independent_spring_flight(g, states[k0], gx.a_step, az, k0, dt)
        errs.append(abs(d["t_flight_s"][-1] / tf - 1.0))
    assert errs[0] <= 1e-6 and math.log2(errs[0] / errs[1]) >= 1.8, errs


def test_the_two_phase_tfp_flies_as_the_seated_one():
    """The two-phase model (docs/model.md 6.6) under the same motion: one
    lift-off, the flight from its own take-off state against the independent
    integration to 1e-9, the ledger (with E_reseat and E_land) every step to
    1e-11 of the input (measured 2.3e-12), no NaN."""
    g, dt = tfp(), 1e-3
    gx = harmonic_ground_motion(0.15, 0.5, 10, dt, duration=3.0)
    az = np.zeros(gx.n_steps)
    k0 = 1000
    az[k0:k0 + 100] = -1.5 * G_ACC
    s = TFPStepper(g, gx, gz=_vertical(az, dt, gx.t), model="two-phase")
    rows, res, states = [s.values()], [], [s.S.copy()]
    for _ in range(gx.n_steps):
        s.step(*MUS)
        rows.append(s.values())
        res.append(s.ledger_residual())
        states.append(s.S.copy())
    d = {c: np.array(rows)[:, i] for i, c in enumerate(s.columns)}
    assert not any(np.isnan(v).any() for v in d.values())
    assert d["n_lift"][-1] == 1.0 and d["E_reseat_J"][-1] > 0.0
    assert np.max(np.abs(res)) <= 1e-11 * np.max(np.abs(d["E_input_J"]))
    tf, _, _ = _independent_flight(g, states[k0], gx.a_step, az, k0, dt)
    assert d["t_flight_s"][-1] == pytest.approx(tf, rel=1e-9)


def test_lift_off_through_a_scene(tmp_path):
    """tfp-elcentro, seated, El Centro x 1 and a vertical pulse of -1.5 g for
    0.2 s (tests/data/pulse_z.txt): one lift-off, summary.json's lift_off
    (count, flight time, peak lift, landing loss) agrees with the columns; the
    energy and heat ledgers close; the flight time within 1 % of an
    independent integration of z'' = -(g + a_z(t)) from rest on a flat seat
    (the bearing slides slowly at the pulse)."""
    out = tmp_path / "run"
    p = subprocess.run([sys.executable, "-m", "fpd", "run", "tfp-elcentro", "--quiet", "--out", str(out),
                        "--set", 'mechanics.model="seated"', "--set", f'loading.file_z="{PULSE}"',
                        "--set", "loading.baseline=false", "--set", "solver.duration=3", "--set", "loading.scale=1",
                        "--set", 'thermal.model="lumped"', "--set", "output.plots=false"],
                       capture_output=True, text=True, cwd=ROOT)
    assert p.returncode == 0, p.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "ok" and s["energy_residual_rel"] <= 1e-9 and s["heat_residual_rel"] <= 1e-9
    lo = s["lift_off"]
    assert lo["count"] == 1 and lo["peak_lift_m"] > 0.0 and lo["landing_loss_J"] > 0.0
    import csv
    rows = list(csv.DictReader((out / "timeseries.csv").open()))
    assert float(rows[-1]["t_flight_s"]) == pytest.approx(lo["flight_time_s"], rel=1e-9)
    # when: the first row that counts the lift-off, the row of the highest lift
    first = next(float(r["t_s"]) for r in rows if float(r["n_lift"]) > 0)
    lift = [float(r["lift_m"]) for r in rows]
    assert lo["first_lift_t_s"] == pytest.approx(first, rel=1e-9) and 0.0 < first < 3.0
    assert lo["peak_lift_t_s"] == pytest.approx(float(rows[int(np.argmax(lift))]["t_s"]), rel=1e-9)
    assert lo["peak_lift_t_s"] > lo["first_lift_t_s"]
    assert max(lift) == pytest.approx(lo["peak_lift_m"], rel=1e-9)
    assert all(math.isfinite(float(v)) for r in rows for k, v in r.items() if k != "phase")
    # z'' = -(g + a_z(t)) from rest at the first step with g + a_z < 0, landing at z = 0
    t, a = np.loadtxt(PULSE, comments="#", unpack=True)
    ts = np.linspace(0.0, 3.0, 300001)
    az = np.interp(ts, t, a * G_ACC)
    acc = -(G_ACC + az)
    k = np.flatnonzero(acc > 0)[0]
    v = np.concatenate([[0.0], np.cumsum(0.5 * (acc[k:-1] + acc[k + 1:]) * np.diff(ts[k:]))])
    z = np.concatenate([[0.0], np.cumsum(0.5 * (v[:-1] + v[1:]) * np.diff(ts[k:]))])
    land = np.flatnonzero(z[1:] <= 0.0)[0] + 1
    assert lo["flight_time_s"] == pytest.approx(ts[k + land] - ts[k], rel=0.01)
