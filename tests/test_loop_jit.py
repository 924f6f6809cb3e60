"""The compiled engine (coupling/engine_kernel.py) and the compiled
kernels give the Python loop's and the pure kernels' numbers bit for bit: the two-phase
step (seated, arrest, rocking, landing, overturning), the friction laws,
whole coupled runs (fe1d, lumped, no heat, mixed plates, fixed-point source,
csv_every), the state left in the Python objects, failures, frames and the
hottest-field tracker."""
import math

import numpy as np
import pytest

from fpd.coupling import fast_loop
from fpd.schema import scene as scn
from fpd.coupling.build import build
from fpd.coupling.run import simulate

from fpd import kernels

pytestmark = pytest.mark.skipif(not kernels.available(), reason="numba not installed (or FPD_NO_JIT)")

from fpd.mechanics import two_phase_kernel as K  # noqa: E402
from fpd.tribology.friction import Constant, Kumar2015, Linear, Table  # noqa: E402
from fpd.mechanics.geometry import DeviceGeometry, G_ACC  # noqa: E402
from fpd.mechanics.two_phase import PadOverturned, TwoPhaseStepper  # noqa: E402
from tests.records_helper import elcentro, pulse  # noqa: E402

DEVICE = DeviceGeometry("DFP", R1=2.2, R2=2.2, pad_height=0.10, pad_diameter=0.25, pad_mass=30.0, mass=1.0e5)
TALL_PAD = DeviceGeometry("DFP", R1=2.2, R2=2.2, pad_height=0.50, pad_diameter=0.10, pad_mass=30.0, mass=1.0e5)


# -- the two-phase step ------------------------------------------------------------------
def _compiled():
    return kernels.compiled("fpd.mechanics.two_phase_kernel")


def _kernel_vs_python(geom, ground, mu1, mu2):
    """The compiled kernel on float64 arrays against the stepper (the pure
    kernel on its list)."""
    st = TwoPhaseStepper(geom, ground)
    C, S = np.array(st.C), np.array(st.S, dtype=float)
    A, T, D = (np.asarray(x, dtype=float) for x in (st._a_step, st._t, st._d))
    rows = np.zeros((st.n_steps, K.N_VALUES))
    m = _compiled().run_steps(C, S, A, T, D, mu1, mu2, st.n_steps, rows)
    ref, failure = [], None
    try:
        for _ in range(st.n_steps):
            st.step(mu1, mu2)
            ref.append(st.values())
    except PadOverturned as exc:
        failure = exc
    ref = np.array(ref, dtype=float)
    assert len(ref) == m
    np.testing.assert_array_equal(rows[:m], ref)
    if failure is None:
        np.testing.assert_array_equal(S, np.array(st.S, dtype=float))
    return ref, S, failure


@pytest.mark.parametrize("scale,mu1,mu2", [(1.0, 0.05, 0.05), (2.0, 0.03, 0.07), (0.1, 0.05, 0.05)])
def test_step_kernel_matches_python_on_elcentro(scale, mu1, mu2):
    ref, S, _ = _kernel_vs_python(DEVICE, elcentro(1e-3, scale, duration=15.0), mu1, mu2)
    assert S[K.ERR] == 0.0
    if scale > 0.5:
        assert {0, 1} <= set(ref[:, 14].astype(int))      # stick and slip


@pytest.mark.parametrize("dt", [1e-3, 2.5e-4])
def test_step_kernel_matches_python_through_rocking_and_landing(dt):
    ref, S, _ = _kernel_vs_python(TALL_PAD, pulse(dt, 0.3 * G_ACC, 0.3, 1.5), 0.6, 0.6)
    assert (ref[:, 14] == 2).any() and S[K.ROCK] == 0.0     # it rocked, and landed


def test_step_kernel_flags_the_overturn_python_raises():
    ref, S, failure = _kernel_vs_python(TALL_PAD, pulse(1e-3, 0.5 * G_ACC, 1.0, 2.0), 0.6, 0.6)
    assert isinstance(failure, PadOverturned) and S[K.ERR] == 2.0


def test_state_round_trip():
    """The state the compiled loop writes back (floats) is the state: save()
    gives the same snapshot, with the same types."""
    st = TwoPhaseStepper(TALL_PAD, pulse(1e-3, 0.3 * G_ACC, 0.3, 1.5))
    for _ in range(400):                 # inside the rocking
        st.step(0.6, 0.6)
    assert st.rocking
    snap = st.save()
    S = np.array(st.S, dtype=float)
    st2 = TwoPhaseStepper(TALL_PAD, pulse(1e-3, 0.3 * G_ACC, 0.3, 1.5))
    st2.S[:] = S.tolist()
    assert st2.save() == snap
    assert [type(x) for x in st2.save()] == [type(x) for x in snap]


# -- friction laws ---------------------------------------------------------------------------
LAWS = [Constant(0.05), Linear(0.06, 20.0, -2e-4, 0.02), Kumar2015(0.06),
        Kumar2015(0.06, 40.0, 80.0, True, True, True), Kumar2015(0.06, use_temperature=False, use_velocity=True),
        Table((20.0, 100.0, 250.0), (0.06, 0.045, 0.03)), Table((20, 100), (6, 4)), Table((50.0,), (0.07,))]


@pytest.mark.parametrize("law", LAWS, ids=lambda x: type(x).__name__)
def test_friction_law_kernel_matches_python(law):
    P = np.array(law.P)
    law_mu = kernels.compiled("fpd.tribology.friction_kernel").law_mu
    rng = np.random.default_rng(3)
    T = np.r_[rng.uniform(-50, 400, 300), 20.0, 100.0, 250.0, 50.0, -1e3, 1e4]
    p = rng.uniform(0, 80e6, len(T))
    v = rng.uniform(-0.5, 0.5, len(T))
    for Ti, pi, vi in zip(T.tolist(), p.tolist(), v.tolist()):
        assert law_mu(P, Ti, pi, vi) == law(Ti, pi, vi), (Ti, pi, vi)


# -- whole runs ------------------------------------------------------------------------------
def _sim(scene, over, friction=None, tmp=None):
    """Build a packaged scene, with its [friction] table replaced by ``friction``
    (TOML text) when given (a copy in ``tmp``)."""
    if friction is not None:
        import re
        text = scn.resolve_path(scene).read_text()
        text = re.sub(r"\[friction\].*?\n\n", "[friction]\n" + friction.strip() + "\n\n", text, flags=re.S)
        path = tmp / f"{scene}-friction.toml"
        path.write_text(text)
        scene = str(path)
    return build(scn.load(scene, over))


def _python_loop(monkeypatch, sim, **kw):
    with monkeypatch.context() as m:
        m.setattr(fast_loop, "enabled", False)
        return simulate(sim, **kw)


def _assert_same_run(a, b, sim_a, sim_b):
    assert a.columns == b.columns
    assert (a.status, a.message, a.steps, a.iterations, a.max_iterations) == \
           (b.status, b.message, b.steps, b.iterations, b.max_iterations)
    np.testing.assert_array_equal(a.data, b.data)
    # the state left in the Python objects: a restart from it goes on alike
    sa, sb = sim_a.mechanics.save(), sim_b.mechanics.save()
    assert [type(x) for x in sa] == [type(x) for x in sb]
    assert all(x == y or (x != x and y != y) for x, y in zip(sa, sb)), (sa, sb)     # NaN after a failure
    for pa, pb in zip(sim_a.plates, sim_b.plates):
        if pa is None:
            continue
        sa, sb = pa.save(), pb.save()
        for x, y in zip(sa, sb):
            np.testing.assert_array_equal(x, y)
        np.testing.assert_array_equal([pa.stored_heat(), pa.heat_lost(), pa.heat_in(), pa.surface_temperature()],
                                      [pb.stored_heat(), pb.heat_lost(), pb.heat_in(), pb.surface_temperature()])


RUNS = {
    "fe1d": ("default", ["solver.duration=8"]),
    "lumped": ("default", ["solver.duration=8", "thermal.model=lumped"]),
    "no-heat": ("default", ["solver.duration=8", "thermal.model=none"]),
    "mixed": ("default", ["solver.duration=8", "thermal.upper.model=lumped"]),
    "one-plate": ("default", ["solver.duration=5", "thermal.upper.model=none"]),
    "fixed-point": ("default", ["solver.duration=8", "thermal.source=fixed-point", "thermal.radius_m=0.02"]),
    "table-law": ("default", ["solver.duration=8"],
                  'law = "table"\nT_C = [20.0, 40.0, 200.0]\nmu = [0.06, 0.05, 0.03]'),
    "linear-law": ("default", ["solver.duration=8"],
                   'law = "linear"\nmu0 = 0.06\nslope_per_C = -1e-3\nmu_min = 0.055'),
    "kumar-pv": ("default", ["solver.duration=8", "friction.use_pressure=true", "friction.use_velocity=true"]),
    "strong": ("default", ["solver.duration=10", "loading.scale=2.0", "friction.upper.mu_ref=0.04"]),
    "northridge": ("northridge-dfp", ["solver.duration=5", "mechanics.model=two-phase"]),
    # every fe1d scheme and back face runs compiled (one column kernel)
    "fe1d-cn": ("default", ["solver.duration=5", "thermal.scheme=cn"]),
    "fe1d-fixed-be": ("default", ["solver.duration=5", "thermal.back=fixed", "thermal.scheme=be"]),
    "fe1d-fixed-bdf2": ("default", ["solver.duration=5", "thermal.back=fixed", "thermal.upper.back=adiabatic"]),
}


@pytest.mark.parametrize("name", list(RUNS))
def test_compiled_loop_matches_python_loop(monkeypatch, tmp_path, name):
    scene, over, *fr = RUNS[name]
    fr = fr[0] if fr else None
    sa, sb = _sim(scene, over, fr, tmp_path), _sim(scene, over, fr, tmp_path)
    assert fast_loop.compiled_loop(sa, 1, sa.n_steps + 1, _cols(sa)) is not None
    a = simulate(sa)
    b = _python_loop(monkeypatch, sb)
    assert a.status == "ok", a.message
    _assert_same_run(a, b, sa, sb)


def _cols(sim):
    from fpd.coupling.run import _columns
    return _columns(sim)[0]


def test_csv_every_and_restart_from_the_state_left(monkeypatch):
    over = ["solver.duration=4"]
    sa, sb = _sim("default", over), _sim("default", over)
    a, b = simulate(sa, every=7), _python_loop(monkeypatch, sb, every=7)
    _assert_same_run(a, b, sa, sb)


def test_injected_failure_hands_over_to_the_python_loop(monkeypatch):
    over = ["solver.duration=1"]
    sa, sb = _sim("default", over), _sim("default", over)
    a, b = simulate(sa, inject_failure_at=250), _python_loop(monkeypatch, sb, inject_failure_at=250)
    assert a.status == "failed" and "step 250" in a.message and a.steps == 249
    _assert_same_run(a, b, sa, sb)


def test_a_step_python_would_fail_is_replayed_by_python(monkeypatch):
    """mu rises towards 1e308 once the surface warms: the cap overflows,
    the kernel hands the step back, the Python loop reports the failure."""
    sa, sb = _sim("default", ["solver.duration=6"]), _sim("default", ["solver.duration=6"])
    law = Table((20.0, 20.0001), (0.06, 1e308))      # beyond what a scene accepts
    sa.laws = sb.laws = (law, law)
    a, b = simulate(sa), _python_loop(monkeypatch, sb)
    assert a.status == "failed" and "non-finite" in a.message, a.message
    assert 10 < a.steps < sa.n_steps
    _assert_same_run(a, b, sa, sb)


def test_frames_and_hottest_fields_as_the_python_loop(monkeypatch):
    from fpd.outputs.hottest import HottestFields

    def recorder(log):
        def on_frame(n, sim):
            m = sim.mechanics
            log.append((n, dict(sim.frame_values), m.theta, m.mode, m.beta, m.diagonal))
        return on_frame

    over = ["solver.duration=3"]
    runs = []
    for compiled in (True, False):
        sim = _sim("default", over)
        log, hot = [], HottestFields()
        kw = dict(on_frame=recorder(log), frame_every=100, hottest=hot, every=2)
        res = simulate(sim, **kw) if compiled else _python_loop(monkeypatch, sim, **kw)
        runs.append((res, sim, log, hot))
    (a, sa, la, ha), (b, sb, lb, hb) = runs
    _assert_same_run(a, b, sa, sb)
    assert len(la) == 30 and la == lb
    for side in ("lower", "upper"):
        ta, tb = ha[side], hb[side]
        assert ta[:2] == tb[:2]
        np.testing.assert_array_equal(ta[4], tb[4])


def test_ctrl_c_in_a_frame_keeps_the_history(monkeypatch):
    def on_frame(n, sim):
        if n == 1500:
            raise KeyboardInterrupt

    over = ["solver.duration=3"]
    sa, sb = _sim("default", over), _sim("default", over)
    a = simulate(sa, on_frame=on_frame, frame_every=100)
    b = _python_loop(monkeypatch, sb, on_frame=on_frame, frame_every=100)
    assert a.status == "interrupted" and a.steps == 1500 and a.n_rows == 1501
    _assert_same_run(a, b, sa, sb)


def test_not_compiled_where_the_python_loop_is_needed(monkeypatch):
    def cols_ok(sim):
        return fast_loop.compiled_loop(sim, 1, sim.n_steps + 1, _cols(sim)) is not None

    assert cols_ok(_sim("default", ["solver.duration=2"]))
    # the seated model is the same (3D) stepper's: compiled too
    assert cols_ok(_sim("default", ["solver.duration=2", "mechanics.model=seated"]))
    assert not cols_ok(_sim("default", ["solver.duration=2", "coupling.scheme=iterated"]))
    assert not cols_ok(_sim("default", ["solver.duration=2", "thermal.model=axisym", "thermal.nr=40",
                                        "thermal.nz=4"]))
    sim = _sim("default", ["solver.duration=2"])
    monkeypatch.setattr(sim.mechanics, "step", sim.mechanics.step)
    assert not cols_ok(sim)
    # lumped and mechanics-only scenes: only where numba is loaded anyway (it is in this process)
    assert cols_ok(_sim("default", ["solver.duration=2", "thermal.model=lumped"]))
    monkeypatch.setattr(fast_loop, "_numba_loaded", lambda: False)
    assert not cols_ok(_sim("default", ["solver.duration=2", "thermal.model=lumped"]))
    assert not cols_ok(_sim("default", ["solver.duration=2", "thermal.model=none"]))
    assert cols_ok(_sim("default", ["solver.duration=2"]))


def test_default_scene_loop_is_compiled_and_fast():
    sim = _sim("default", [])
    res = simulate(sim)
    assert res.status == "ok"
    assert math.isfinite(res.data.sum())


def test_rows_into_a_small_buffer():
    """CompiledLoop.run stops when the row buffer is full and goes on from
    there when called again (simulate() empties the buffer in between, as a
    streamed history does): the rows and the events are those of one run."""
    over = ["solver.duration=3"]
    ref_log = []
    ref = simulate(_sim("default", over), every=3, on_frame=lambda n, sim: ref_log.append(n), frame_every=30)
    sim = _sim("default", over)
    cols = _cols(sim)
    loop = fast_loop.compiled_loop(sim, 3, ref.n_rows, cols)
    buf, got, log = np.full((64, len(cols)), np.nan), [], []
    k = last_row = start = 0
    T, mu = [ref["T1_C"][0], ref["T2_C"][0]], [ref["mu1"][0], ref["mu2"][0]]
    full = False
    while True:
        out = loop.run(buf, k, last_row, T, mu, on_frame=lambda n, sim: log.append(n), frame_every=30,
                       start=start, pending=full)
        assert not out.failure and not out.interrupted
        k, last_row, start, full = out.k, out.last_row, out.steps, out.full
        T, mu = out.T, out.mu
        if not full:
            break
        got.append(buf[:k].copy())
        k = 0
    assert out.steps == sim.n_steps
    got.append(buf[:k].copy())
    rows = np.vstack(got)
    from fpd.coupling.run import _columns
    order = _columns(sim)[1]
    want = ref.data[1:][:, [order.index(c) for c in cols]]
    assert len(got) > 5
    np.testing.assert_array_equal(rows, want)
    assert log == ref_log and len(log) == 100


def test_streamed_history_and_ctrl_c_while_a_block_is_taken(monkeypatch, tmp_path):
    """fpd run's StreamHistory with small blocks: the compiled loop stops at
    every full buffer for simulate() to hand it over; a Ctrl-C while a block
    is formatted ends the run there, as with the Python loop."""
    from fpd.outputs.history import StreamHistory

    over = ["solver.duration=2"]
    for interrupt in (False, True):
        results = []
        for compiled in (True, False):
            sim = _sim("default", over)
            path = tmp_path / f"{compiled}-{interrupt}.csv"
            hist = StreamHistory(path, chunk_rows=64)
            real, calls = hist.prepare, []

            def prepare(block, real=real, calls=calls):
                calls.append(len(block))
                if interrupt and len(calls) == 3:
                    raise KeyboardInterrupt
                return real(block)
            hist.prepare = prepare
            res = simulate(sim, history=hist) if compiled else _python_loop(monkeypatch, sim, history=hist)
            results.append((res, path.read_bytes(), calls))
        (a, csv_a, calls_a), (b, csv_b, calls_b) = results
        assert (a.status, a.message, a.steps, a.n_rows) == (b.status, b.message, b.steps, b.n_rows)
        assert csv_a == csv_b and calls_a == calls_b
        if interrupt:
            assert a.status == "interrupted" and a.n_rows == 3 * 64 == a.steps + 1
        else:
            assert a.status == "ok" and len(calls_a) > 20


@pytest.mark.parametrize("kind,scale", [("DFP", 1.0), ("SFP", 2.5)])
def test_seated_kernel_compiled_matches_the_stepper(kind, scale):
    """machines/seated_kernel.py compiled on float64 arrays against
    SeatedStepper (the same source run as Python on its list)."""
    from fpd.machines.seated import SeatedStepper
    geom = DeviceGeometry(kind, R1=2.2, R2=2.2 if kind == "DFP" else None, pad_height=0.10, pad_diameter=0.25,
                          pad_mass=30.0, mass=1.0e5)
    st = SeatedStepper(geom, elcentro(1e-3, scale, duration=10.0))
    SK = kernels.compiled("fpd.machines.seated_kernel")
    C, S, A = np.array(st.C), np.array(st.S, dtype=float), np.asarray(st._a_step, dtype=float)
    xg = np.asarray(st._xg, dtype=float)
    row = np.zeros(SK.N_VALUES)
    for _ in range(st.n_steps):
        dw = st.step(0.05, 0.04)
        assert SK.step(C, S, A, 0.05, 0.04) == dw
        SK.values(C, S, xg[int(S[SK.SN])], row)
        assert row.tolist() == list(st.values())
    assert S.tolist() == [float(x) for x in st.S]
