"""A rim of finite stiffness on the TFP in both directions
(mechanics/tfp3d_kernel.py ``rim_spring_*``, docs/model.md 6.12): no circle
bounds the tilts; the springs k o_i^2 / 2 on each surface's slide beyond its
capacity, o_i = (R_i |v| - d_i)_+ (v = phi for S1, S4; alpha for S2, S3),
and their dashpots, in the seated and the two-phase models.

The closed forms are those of the rim alone (no gravity, no friction: the
TFPGeometry's g = 0, every mu 0), a block launched into its rim circle. While
it overlaps, the rest is free, so the radial slide is a linear oscillator of
the generalised inertia m_n = 1 / (n^T M^-1 n) (n the block's radial unit
vector) on the spring K = k sum R_i^2 over the block's two surfaces: contact
time pi sqrt(m_n / K), radial rate after it minus the rate before, or
exp(-zeta pi / sqrt(1 - zeta^2)) of it with the dashpot; the tangential
motion goes on."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from fpd import kernels
from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.loading import ground_motion as gmod
from fpd.mechanics import tfp3d_kernel as K
from fpd.mechanics.tfp3d import TFP3DStepper
from fpd.mechanics.tfp3d_two_phase import TFP3DTwoPhaseStepper
from fpd.schema import scene as scn
from tests.test_tfp import tfp
from tests.test_tfp_rim_spring import bounce, crossing_times, frictionless_states
from helpers import refusal

DTS = (1e-3, 5e-4, 2.5e-4)
MUS = (0.08, 0.02, 0.02, 0.08)
STEPPERS = {"seated": TFP3DStepper, "two-phase": TFP3DTwoPhaseStepper}
KERNELS = {"seated": "fpd.mechanics.tfp3d_kernel", "two-phase": "fpd.mechanics.tfp3d_two_phase_kernel"}


def launch(dt, block, k, vn, vt=0.0, ang=0.0, zeta=0.0, model="seated", duration=0.05):
    """The rim alone in both directions: block (0: phi, 1: alpha) started on
    the ray at ang (rad) 2.37 ms of its normal rate vn before its rim circle,
    with the rate vn along the ray and vt across it. Returns the stepper, the
    states (q, rates) at every step, the ledger's residuals, the launch energy."""
    g = dataclasses.replace(tfp(g=0.0), rim_stiffness=k, rim_damping=zeta)
    n = int(round(duration / dt))
    gm = gmod.pulse_ground_motion("cosine", 0.0, 1.0, 0.0, n * dt, dt)
    # (the compiled kernel where there is one: it equals the pure one bit for bit,
    # test_the_compiled_engine_equals_the_pure_path_with_rim_springs)
    kernel = kernels.compiled(KERNELS[model]) if kernels.available() else None
    s = STEPPERS[model](g, gm, gm, kernel=kernel)
    c, sn = math.cos(ang), math.sin(ang)
    b = 2 * block
    r0 = g.qmax[block] - 2.37e-3 * vn
    s.S[b], s.S[b + 1] = r0 * c, r0 * sn
    s.S[4 + b], s.S[5 + b] = vn * c - vt * sn, vn * sn + vt * c
    s.S[K.S_EIN] = E0 = s.E_kin() + s.E_pot()
    states, res = frictionless_states(s, n, 8)
    return s, states, res, E0


def radial(st, block):
    """The block's tilt |v|, its radial rate n . v' and its tangential rate t . v' at every state."""
    b = 2 * block
    rho = np.hypot(st[:, b], st[:, b + 1])
    nx, ny = st[:, b] / rho, st[:, b + 1] / rho
    return rho, nx * st[:, 4 + b] + ny * st[:, 5 + b], -ny * st[:, 4 + b] + nx * st[:, 5 + b]


def contact(dt, block, k, vn, vt, zeta=0.0, model="seated", ang=0.7):
    """An oblique arrival: the contact time, the radial rates before and after
    it (at the steps just outside), the tangential rates there, the kinetic
    energy at the launch and after, the closed-form oscillator (m_n, K) at
    the deepest overlap, the worst ledger residual over the launch energy."""
    s, st, res, E0 = launch(dt, block, k, vn, vt, ang, zeta, model)
    t = np.arange(len(st)) * dt
    rho, rd, td = radial(st, block)
    qm = s.geom.qmax[block]
    tin, tout = crossing_times(t, rho, rd, qm)
    before, after = int(math.floor(tin / dt)), int(math.ceil(tout / dt)) + 1
    deep = int(np.argmax(rho))
    M = np.zeros(16)
    K.mass_matrix(s.par, st[deep, 0:4], M, np.zeros(12))
    nvec = np.zeros(4)
    nvec[2 * block:2 * block + 2] = st[deep, 2 * block:2 * block + 2] / rho[deep]
    mn = 1.0 / (nvec @ np.linalg.solve(M.reshape(4, 4), nvec))
    g = s.geom
    Rs = (g.R1, g.R4) if block == 0 else (g.R2, g.R3)
    T = [K.kinetic(s.par, st[i, 0:4], st[i, 4:8], np.zeros(12)) for i in (0, after)]
    return dict(tc=tout - tin, rd=(rd[before], rd[after]), td=(td[before], td[after]), T0=T[0], T1=T[1],
                mn=mn, K=k * sum(R * R for R in Rs), res=np.max(np.abs(res)) / E0, s=s)


def test_the_scratch_holds_the_springs():
    assert K.N_SC >= K.N_SC_SPRING and K.SP_F >= K.N_SC_RIM


# -- (a) the rim alone along x is the planar TFP's; turned, its resultant ------------------------

@pytest.mark.parametrize("model", ["seated", "two-phase"])
@pytest.mark.parametrize("block, k, zeta", [(0, 1e6, 0.0), (1, 1e7, 0.2)], ids=["outer", "inner-damped"])
def test_the_rim_alone_is_the_planar_tfps_along_x_and_turned(block, k, zeta, model):
    """The rim alone, launched along x: the tilts and rates are the planar
    TFP's rim-spring history (tests/test_tfp_rim_spring.py ``bounce``) to 1e-9
    of their peaks (measured: the tilt 3e-15, the rate <= 3.6e-10), the y
    components exactly 0; launched along a ray at 40 deg, the radial history
    is the same to 1e-9 (measured <= 2.4e-10) and nothing leaves the ray
    (measured <= 7e-12); the dashpot's loss (to 4e-12 of the launch energy)
    and the contacts the planar model's."""
    dt, v = 2.5e-4, 5e-5
    p, ref, _, _ = bounce(dt, block, k, v, zeta, model)
    A = np.column_stack([ref[:, block], ref[:, 2 + block]])      # the planar coordinate and its rate
    scale = np.max(np.abs(A), axis=0)
    for ang in (0.0, math.radians(40.0)):
        s, st, res, E0 = launch(dt, block, k, v, ang=ang, zeta=zeta, model=model)
        c, sn = math.cos(ang), math.sin(ang)
        b = 2 * block
        B = np.column_stack([c * st[:, b] + sn * st[:, b + 1], c * st[:, 4 + b] + sn * st[:, 5 + b]])
        across = np.column_stack([-sn * st[:, b] + c * st[:, b + 1], -sn * st[:, 4 + b] + c * st[:, 5 + b]])
        assert np.all(np.max(np.abs(B - A), axis=0) <= 1e-9 * scale), (ang, np.max(np.abs(B - A), axis=0) / scale)
        assert np.all(np.max(np.abs(across), axis=0) <= 1e-9 * scale)
        if ang == 0.0:
            assert np.all(st[:, [1, 3, 5, 7]] == 0.0)
        assert list(s.S[K.S_NHIT:K.S_NHIT + 4]) == list(p.S[K.tk.S_NHIT:K.tk.S_NHIT + 4])
        assert abs(s.E_rim - p.E_rim) <= 1e-9 * E0
        assert np.max(np.abs(res)) <= 1e-10 * E0


# -- (b) an oblique arrival, undamped -------------------------------------------------------------

@pytest.mark.parametrize("block, k", [(0, 1e6), (1, 1e7)], ids=["outer", "inner"])
def test_an_oblique_arrival_on_an_undamped_rim(block, k):
    """The rim alone, the block arriving obliquely (normal rate 5e-5 rad/s,
    tangential 3e-5 rad/s, along a ray at 40 deg): the energy (kinetic +
    spring) is constant every step to 1e-10 of the launch energy (measured
    <= 4e-12); the radial rate after the contact is minus the rate before
    to 1e-6 (measured 2.0e-7 .. 1.1e-7 outer, 3.6e-7 .. 1.1e-7 inner, at
    the steps just outside the contact) and the tangential motion goes on
    (its rate within 1e-4 of the rate before, measured <= 6e-6: the free
    motion of the rest bends the metric); the contact time converges at
    second order to pi sqrt(m_n / K) (errors at dt = 1, 0.5, 0.25 ms each
    >= 3 times the next, the last < 1.5e-4 of it: measured 1.09e-3,
    2.7e-4, 6.9e-5 outer, 1.10e-3, 2.7e-4, 6.7e-5 inner). No impulse, no
    rim loss, a contact on each of the block's surfaces."""
    errs = []
    for dt in DTS:
        c = contact(dt, block, k, 5e-5, 3e-5)
        assert c["res"] <= 1e-10
        assert abs(c["rd"][1] / c["rd"][0] + 1.0) <= 1e-6, c["rd"]
        assert abs(c["td"][1] / c["td"][0] - 1.0) <= 1e-4, c["td"]
        errs.append(abs(c["tc"] / (math.pi * math.sqrt(c["mn"] / c["K"])) - 1.0))
        s = c["s"]
        assert list(s.S[K.S_NHIT:K.S_NHIT + 4]) == ([1.0, 0.0, 0.0, 1.0] if block == 0 else [0.0, 1.0, 1.0, 0.0])
        assert s.E_rim == 0.0 and np.all(s.S[K.S_J:K.S_J + 2] == 0.0)
    assert errs[0] >= 3.0 * errs[1] and errs[1] >= 3.0 * errs[2] and errs[2] <= 1.5e-4, errs


def test_the_springs_discrete_gradient_is_exact_over_any_increment():
    """``rim_spring_force`` over random increments from random tilts inside,
    across and beyond the capacities (undamped): its work over the increment
    is the springs' energy change to 1e-12 of the energies involved, and it
    points along (v0 + v1) of each block."""
    g = dataclasses.replace(tfp(), rim_stiffness=1e9)
    par = g.pack()
    sc = np.zeros(K.N_SC)
    rng = np.random.default_rng(3)
    qm = np.repeat(g.qmax, 2)
    for _ in range(400):
        q0 = qm * rng.uniform(0.9, 1.1, 4) * rng.choice([-1.0, 1.0], 4)
        x = qm * rng.uniform(-0.1, 0.1, 4) * rng.choice([1.0, 1e-4, 1e-9])
        K.rim_spring_force(par, q0, x, 1e-3, sc)
        f = sc[K.SP_F:K.SP_F + 4]
        e0, e1 = K.rim_spring_energy(par, q0), K.rim_spring_energy(par, q0 + x)
        assert abs(f @ x - (e1 - e0)) <= 1e-12 * max(e0, e1, 1e-300) + 1e-300
        for b in range(2):
            w = q0[2 * b:2 * b + 2] * 2.0 + x[2 * b:2 * b + 2]
            assert abs(f[2 * b] * w[1] - f[2 * b + 1] * w[0]) <= 1e-12 * np.hypot(*f[2 * b:2 * b + 2]) * np.hypot(*w)


# -- (c) damped --------------------------------------------------------------------------------

@pytest.mark.parametrize("model", ["seated", "two-phase"])
@pytest.mark.parametrize("block, k, zeta", [(0, 1e6, 0.2), (1, 1e7, 0.1)], ids=["outer", "inner"])
def test_a_damped_oblique_arrival_hands_back_the_oscillators_restitution(block, k, zeta, model):
    """The dashpot 2 zeta sqrt(k m_eff) on each overlapping slide, m_eff =
    m_n / sum R_i^2: the block leaves its rim at exp(-zeta pi / sqrt(1 -
    zeta^2)) of its arrival's radial rate within 1e-3 (dt = 0.25 ms, an
    oblique arrival; measured 4.5e-5 outer, 3.2e-5 inner, both models), and
    E_rim_J (the dashpot's loss) is the kinetic energy lost to 1e-10 of the
    launch energy (with the two-phase model's re-seating; measured <=
    4.3e-12); the ledger closes every step."""
    c = contact(2.5e-4, block, k, 5e-5, 3e-5, zeta, model)
    e = math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta * zeta))
    assert -c["rd"][1] / c["rd"][0] == pytest.approx(e, abs=1e-3)
    s = c["s"]
    reseat = s.E_reseat if model == "two-phase" else 0.0
    assert s.E_rim > 0.0
    assert abs(s.E_rim + reseat - (c["T0"] - c["T1"])) <= 1e-10 * c["T0"]
    assert c["res"] <= 1e-10


# -- (d) a record pair through all four rims ------------------------------------------------------

def _kernel(model):
    if not kernels.available():
        pytest.skip("numba not available")
    return kernels.compiled(KERNELS[model])


def pulse_pair(dt, k, zeta=0.0, model="seated", kernel=None):
    """The record pair of tests/test_tfp3d_rims.py (sine velocity pulses of
    1.5 m/s over 1.5 s on x and 1.0 m/s over 1.1 s on y, 1.6 s) on the TFP of
    tests/test_tfp.py with rim springs k: the stepper, the peak |F|, the
    worst ledger residual over the input and the largest overlap."""
    g = dataclasses.replace(tfp(), rim_stiffness=k, rim_damping=zeta)
    gx = gmod.pulse_ground_motion("sine", 1.5, 1.5, 0.2, 1.6, dt)
    gy = gmod.pulse_ground_motion("sine", 1.0, 1.1, 0.4, 1.6, dt)
    s = STEPPERS[model](g, gx, gy, kernel=kernel)
    peak = worst = over = 0.0
    for _ in range(s.n_steps):
        s.step(*MUS)
        worst = max(worst, abs(s.ledger_residual()))
        Fx, Fy = s.S[K.S_F], s.S[K.S_F + 1]
        peak = max(peak, math.hypot(Fx, Fy))
        over = max(over, g.R1 * math.hypot(s.S[0], s.S[1]) - g.d1, g.R2 * math.hypot(s.S[2], s.S[3]) - g.d2)
    return s, peak, worst / s.E_in, over


@pytest.mark.parametrize("model, k, zeta", [("seated", 1e8, 0.0), ("seated", 1e9, 0.0), ("two-phase", 1e9, 0.2)])
def test_a_pair_through_all_four_rims_converges_in_dt(model, k, zeta):
    """The pair drives all four surfaces past their capacities (by 44 mm at
    k = 1e8 N/m, 12 mm at 1e9), each pass counted; the ledger closes to
    1e-9 of the input every step (measured <= 1e-13); the springs transmit
    a force and no impulse; the peak |F| agrees within 2 % across dt = 1,
    0.5, 0.25 ms (measured 5.060, 5.071, 5.070 MN at 1e8; 14.06, 14.06,
    14.10 MN at 1e9; 11.68, 11.68, 11.68 MN two-phase with zeta = 0.2,
    whose dashpots' loss is E_rim_J)."""
    kern = _kernel(model)
    peaks = []
    for dt in DTS:
        s, peak, worst, over = pulse_pair(dt, k, zeta, model, kern)
        assert worst <= 1e-9
        assert all(s.S[K.S_NHIT + i] >= 1 for i in range(4)), s.S[K.S_NHIT:K.S_NHIT + 4]
        assert over > 5e-3
        assert s.S[K.S_J] == 0.0 and s.S[K.S_J + 1] == 0.0
        assert (s.E_rim > 0.0) == (zeta > 0.0)
        peaks.append(peak)
    assert (max(peaks) - min(peaks)) / min(peaks) <= 0.02, peaks


@pytest.mark.slow
@pytest.mark.parametrize("model, zeta", [("seated", 0.1), ("two-phase", 0.0)])
def test_the_compiled_kernel_equals_the_pure_one_through_the_pair(model, zeta):
    """The pair at dt = 2 ms, k = 1e9 N/m: every column of every row of the
    compiled kernel's history equals the pure kernel's bit for bit (slow: the
    compiled engine's test below runs the same pair through both paths, both
    models, in the default run)."""
    kern = _kernel(model)
    rows = []
    for kernel in (None, kern):
        g = dataclasses.replace(tfp(), rim_stiffness=1e9, rim_damping=zeta)
        gx = gmod.pulse_ground_motion("sine", 1.5, 1.5, 0.2, 1.6, 2e-3)
        gy = gmod.pulse_ground_motion("sine", 1.0, 1.1, 0.4, 1.6, 2e-3)
        s = STEPPERS[model](g, gx, gy, kernel=kernel)
        r = [s.values()]
        for _ in range(s.n_steps):
            s.step(*MUS)
            r.append(s.values())
        rows.append(np.array(r))
    cols = list(s.columns)
    assert all(rows[0][-1, cols.index(f"n_rim{i}")] >= 1 for i in range(1, 5))
    np.testing.assert_array_equal(rows[0], rows[1])


# -- the one compiled engine, through a scene ------------------------------------------------------

def _pair_scene(tmp_path, over):
    """tfp-elcentro with the pulse pair as its record files (x and y, m/s2)."""
    gx = gmod.pulse_ground_motion("sine", 1.5, 1.5, 0.2, 1.6, 2e-3)
    gy = gmod.pulse_ground_motion("sine", 1.0, 1.1, 0.4, 1.6, 2e-3)
    fx, fy = tmp_path / "x.txt", tmp_path / "y.txt"
    np.savetxt(fx, np.column_stack([gx.t, gx.a]))
    np.savetxt(fy, np.column_stack([gy.t, gy.a]))
    text = (scn.resolve_path("tfp-elcentro")).read_text()
    text = text.replace('record = "elcentro-1940"\nscale = 2.0',
                        f'file = "{fx}"\nfile_y = "{fy}"\nunits = "m/s2"\nbaseline = false')
    path = tmp_path / "pair.toml"
    path.write_text(text)
    return scn.load(str(path), ["thermal.model=lumped", "solver.dt=2e-3", "solver.duration=1.6",
                                "device.rim_stiffness_N_per_m=1e9"] + over)


@pytest.mark.parametrize("over", [["mechanics.model=seated", "device.rim_damping_ratio=0.1"],
                                  ["mechanics.model=two-phase"]], ids=["seated-damped", "two-phase"])
def test_the_compiled_engine_equals_the_pure_path_with_rim_springs(monkeypatch, tmp_path, over):
    """The pair as a scene (lumped heat on the four parts): the compiled
    engine and the pure path write the same history, every column bit for
    bit, through all four rims; the ledger closes to 1e-9 of the input."""
    pytest.importorskip("numba")
    if not kernels.available():
        pytest.skip("FPD_NO_JIT")
    from fpd.coupling import fast_loop
    sim = build(_pair_scene(tmp_path, over))
    assert fast_loop.compiled_loop(sim, 1, 2, fast_loop.loop_columns(sim)) is not None
    a = simulate(sim)
    monkeypatch.setenv("FPD_NO_JIT", "1")
    b = simulate(build(_pair_scene(tmp_path, over)))
    assert a.status == b.status == "ok", (a.message, b.message)
    assert a.columns == b.columns
    np.testing.assert_array_equal(a.data, b.data)
    assert min(b[f"n_rim{i}"][-1] for i in (1, 2, 3, 4)) >= 1
    res = b["E_input_J"] - (b["E_kin_J"] + b["E_pot_J"] + b["W1_J"] + b["W2_J"] + b["W3_J"] + b["W4_J"]
                            + b["E_rim_J"] + (b["E_reseat_J"] if "E_reseat_J" in b else 0.0))
    assert np.max(np.abs(res)) <= 1e-9 * np.max(np.abs(b["E_input_J"]))


# -- the scenes ------------------------------------------------------------------------------------

@pytest.mark.parametrize("model", ["seated", "two-phase"])
def test_a_scene_gives_the_tfp_in_both_directions_its_rim_springs(model):
    s = scn.load("tfp-elcentro", ['loading.record="impvall-1979-e11"', f"mechanics.model={model}",
                                  "device.rim_stiffness_N_per_m=1e9", "device.rim_damping_ratio=0.1"])
    m = build(s).mechanics
    assert isinstance(m, STEPPERS[model])
    assert m.geom.rim_stiffness == 1e9 and m.geom.rim_damping == 0.1
    assert m.par[K.tk.I_KRIM] == 1e9


@pytest.mark.parametrize("over, needle", [
    (["device.rim_damping_ratio=0.1"], "damps a rim of finite stiffness"),
    (["device.rim_stiffness_N_per_m=1e9", "device.rim_restitution=0.5"], "is a key of the rigid rim"),
    (["device.rim_stiffness_N_per_m=1e9", "loading.vertical_scale=0.5"],
     "not yet with a vertical ground motion for the TFP"),
])
def test_what_the_tfp_in_both_directions_still_refuses(over, needle):
    assert needle in refusal("tfp-elcentro", ['loading.record="impvall-1979-e11"', "mechanics.model=seated"] + over)


def test_the_orbit_refuses_the_stiffness():
    assert "test machine" in refusal("tfp-lab", ['loading.waveform="circle"', "loading.amplitude_m=0.04",
                                                 "device.rim_stiffness_N_per_m=1e9"])


def test_the_stepper_refuses_the_machine_and_a_vertical_motion_with_springs():
    g = dataclasses.replace(tfp(), rim_stiffness=1e9)
    gm = gmod.pulse_ground_motion("cosine", 0.0, 1.0, 0.0, 0.01, 1e-3)
    with pytest.raises(ValueError, match="vertical ground motion"):
        TFP3DStepper(g, gm, gm, az=np.zeros(gm.n_steps))

