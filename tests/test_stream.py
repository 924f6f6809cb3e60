"""Issue 7 (memory): `fpd run` streams the history to disk in blocks.

The streamed path writes the bytes and the summary the in-memory path writes
(several blocks, failures and interruptions in the middle of a block
included), its plots keep the peaks, and its memory does not grow with the
number of steps.
"""
from __future__ import annotations

import json
import os
import signal
import tracemalloc

import numpy as np
import pytest

from fpd.outputs import output

from fpd.schema import scene as scn
from fpd.coupling.build import build
from fpd.coupling.recording import Stats
from fpd.outputs.history import PlotSampler, StreamHistory
from fpd.coupling.run import simulate


def _summary(sc, res, sim):
    s = output.summary(sc, res, sim)
    s.pop("runtime_s")
    return json.loads(json.dumps(s))      # as summary.json has it


def in_memory(tmp_path, name, over, **kw):
    sc = scn.load(name, over)
    sim = build(sc)
    res = simulate(sim, **kw)
    path = tmp_path / "memory.csv"
    output.write_csv(path, res)
    return res, path.read_bytes(), _summary(sc, res, sim)


def streamed(tmp_path, name, over, chunk, spill=False, **kw):
    sc = scn.load(name, over)
    sim = build(sc)
    path = tmp_path / "streamed.csv"
    hist = StreamHistory(path, spill_path=tmp_path / "spill.f64" if spill else None, chunk_rows=chunk)
    res = simulate(sim, history=hist, **kw)
    assert res.streamed and res.data is None
    return res, path.read_bytes(), _summary(sc, res, sim)


CASES = {
    "default": ("default", ["solver.duration=3"], 700),
    "default-csv-every": ("default", ["solver.duration=3", "output.csv_every=7"], 50),
    "lab-sine": ("lab-sine", ["solver.duration=2"], 333),
    "sfp-harmonic": ("sfp-harmonic", ["solver.duration=4"], 1024),
    "heat-halfspace": ("heat-halfspace", ["solver.duration=2"], 128),
}


@pytest.mark.parametrize("case", list(CASES))
def test_streamed_csv_and_summary_identical_to_in_memory(tmp_path, case):
    name, over, chunk = CASES[case]
    every = scn.load(name, over)["output"]["csv_every"]
    mem, mem_csv, mem_s = in_memory(tmp_path, name, over, every=every)
    st, st_csv, st_s = streamed(tmp_path, name, over, chunk, spill=output.needs_rows(scn.load(name, over)),
                                every=every)
    assert mem.n_rows > 3 * chunk                       # several blocks, the last one partial
    assert mem.n_rows % chunk
    assert st.n_rows == mem.n_rows and st.steps == mem.steps
    assert st_csv == mem_csv
    assert st_s == mem_s
    if name.startswith("heat"):
        assert "reference" in st_s                      # read back from the spill
    # the plots' copy of a short run is the whole history
    assert np.array_equal(st.plot_view().data, mem.data)


def test_fpd_run_writes_the_in_memory_bytes(tmp_path, monkeypatch, restore_sigterm):
    """The command line streams; its folder holds what the in-memory path writes."""
    from fpd.frontends import cli
    from fpd.outputs import history
    monkeypatch.setattr(history, "CHUNK_ROWS", 500)
    over = ["solver.duration=2", "output.plots=false", "output.vtk_every=0"]
    assert cli.main(["run", "heat-halfspace", "--out", str(tmp_path / "o"), "--quiet",
                     *[a for o in over for a in ("--set", o)]]) == 0
    _, mem_csv, mem_s = in_memory(tmp_path, "heat-halfspace", over)
    assert (tmp_path / "o" / "timeseries.csv").read_bytes() == mem_csv
    assert mem_csv.count(b"\n") > 3 * 500                  # several blocks
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    s.pop("runtime_s")
    assert s == mem_s
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == ["scene.toml", "summary.json", "timeseries.csv"]


@pytest.fixture
def restore_sigterm():
    old = signal.getsignal(signal.SIGTERM)
    yield
    signal.signal(signal.SIGTERM, old)


def _prefix_lines(data: bytes, n: int) -> bytes:
    return b"".join(data.splitlines(keepends=True)[:n])


def test_failure_mid_block_keeps_complete_rows(tmp_path):
    over = ["solver.duration=1", "mechanics.model=seated", "thermal.model=lumped"]
    full, full_csv, _ = in_memory(tmp_path, "default", over)
    mem, mem_csv, mem_s = in_memory(tmp_path, "default", over, inject_failure_at=437)
    st, st_csv, st_s = streamed(tmp_path, "default", over, 100, inject_failure_at=437)
    assert st.status == mem.status == "failed" and "step 437" in st.message
    assert st.steps == 436 and st.n_rows == 437
    assert st_csv == mem_csv == _prefix_lines(full_csv, 1 + 437)
    assert st_csv.endswith(b"\n")
    assert st_s == mem_s and st_s["status"] == "failed"


def _interrupting(stepper, at):
    real = stepper.step

    def step(mu1, mu2):
        if stepper.n == at - 1:
            raise KeyboardInterrupt
        return real(mu1, mu2)
    return step


def test_interrupt_mid_block_keeps_complete_rows(tmp_path, monkeypatch):
    over = ["solver.duration=1", "mechanics.model=seated", "thermal.model=lumped"]
    _, full_csv, _ = in_memory(tmp_path, "default", over)
    sc = scn.load("default", over)
    sim = build(sc)
    monkeypatch.setattr(sim.mechanics, "step", _interrupting(sim.mechanics, 251))
    path = tmp_path / "s.csv"
    res = simulate(sim, history=StreamHistory(path, chunk_rows=64))
    assert res.status == "interrupted" and "step 251" in res.message
    assert res.steps == 250 and res.n_rows == 251
    assert path.read_bytes() == _prefix_lines(full_csv, 1 + 251)
    assert res.stats.final("t_s") == pytest.approx(0.25)


def test_interrupt_while_a_block_is_formatted_loses_no_row(tmp_path, monkeypatch):
    """Ctrl-C in the slow (formatting) part of taking a block: the block is
    taken again at the end, once."""
    over = ["solver.duration=1", "mechanics.model=seated", "thermal.model=lumped"]
    _, full_csv, _ = in_memory(tmp_path, "default", over)
    sim = build(scn.load("default", over))
    path = tmp_path / "s.csv"
    hist = StreamHistory(path, chunk_rows=64)
    real, calls = hist.prepare, []

    def prepare(block):
        calls.append(len(block))
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(block)
    hist.prepare = prepare
    res = simulate(sim, history=hist)
    assert res.status == "interrupted"
    assert res.n_rows == 3 * 64 == res.steps + 1
    assert path.read_bytes() == _prefix_lines(full_csv, 1 + 3 * 64)


def test_signal_while_a_block_is_committed_waits_for_it(tmp_path):
    """SIGINT arriving while a block is appended is held until the block is
    whole and the buffer emptied: no row lost, none written twice."""
    over = ["solver.duration=1", "mechanics.model=seated", "thermal.model=lumped"]
    _, full_csv, _ = in_memory(tmp_path, "default", over)
    sim = build(scn.load("default", over))
    path = tmp_path / "s.csv"
    hist = StreamHistory(path, chunk_rows=64)
    real, calls = hist.commit, []

    def commit(prepared):
        calls.append(1)
        if len(calls) == 2:
            os.kill(os.getpid(), signal.SIGINT)     # held: delivered when the commit is done
        real(prepared)
    hist.commit = commit
    res = simulate(sim, history=hist)
    assert res.status == "interrupted"
    assert res.n_rows == 2 * 64 == res.steps + 1
    assert path.read_bytes() == _prefix_lines(full_csv, 1 + 2 * 64)


# -- the plots' copy ---------------------------------------------------------------
def test_plot_sampler_keeps_every_peak_and_stays_bounded():
    rng = np.random.default_rng(1)
    cols = ["t_s", "u_m", "F_N", "T1_C", "phase"]
    n = 200_003
    data = np.column_stack([np.arange(n) * 1e-3, np.cumsum(rng.standard_normal(n)), rng.standard_normal(n),
                            20 + np.cumsum(np.abs(rng.standard_normal(n))), rng.integers(0, 3, n)])
    data[123_457, 2] = 50.0                       # a spike one row wide
    ps = PlotSampler(cols, n, full_rows=1000, bins=500)
    b = ps.bin_rows
    chunk = (4096 // b) * b
    for s in range(0, n, chunk):
        ps.add(data[s:s + chunk])
    kept = ps.data()
    assert len(kept) <= 500 * (2 + 2 * 3)
    assert np.all(np.diff(kept[:, 0]) > 0)                  # whole rows, in time order
    rows = {tuple(r) for r in data[[0, n - 1, 123_457]]}
    assert rows <= {tuple(r) for r in kept}                 # first, last, the spike
    for j in (1, 2, 3):
        assert kept[:, j].max() == data[:, j].max() and kept[:, j].min() == data[:, j].min()
    # a short history is kept whole
    small = PlotSampler(cols, 999, full_rows=1000)
    small.add(data[:999])
    assert np.array_equal(small.data(), data[:999])


def test_stats_combine_exactly_across_blocks():
    rng = np.random.default_rng(2)
    data = rng.standard_normal((10_001, 4)) * np.array([1, 1e-3, 1e6, 1])
    one, many = Stats(list("abcd")), Stats(list("abcd"))
    one.add(data)
    for s in range(0, len(data), 333):
        many.add(data[s:s + 333])
    for name in "abcd":
        j = "abcd".index(name)
        assert many.peak(name) == one.peak(name) == data[:, j].max()
        assert many.low(name) == one.low(name) == data[:, j].min()
        assert many.peak_abs(name) == np.max(np.abs(data[:, j]))
        assert many.final(name) == data[-1, j]


# -- memory --------------------------------------------------------------------------
def _peak_streamed(tmp_path, duration):
    sim = build(scn.load("default", [f"solver.duration={duration}", "mechanics.model=seated",
                                     "thermal.model=lumped"]))
    hist = StreamHistory(tmp_path / f"m{duration}.csv", chunk_rows=512, plot_full_rows=2000, plot_bins=200)
    tracemalloc.start()
    try:
        res = simulate(sim, history=hist)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert res.status == "ok"
    return peak, res.n_rows, len(res.columns)


def test_streamed_memory_does_not_grow_with_steps(tmp_path):
    _peak_streamed(tmp_path, 6)                             # one-time allocations out of the way
    p1, n1, ncol = _peak_streamed(tmp_path, 6)
    p4, n4, _ = _peak_streamed(tmp_path, 24)
    assert n4 > 3.9 * n1
    in_memory_history = 8 * ncol * n4
    assert p4 < 1.25 * p1 + 256 * 1024, (p1, p4)           # flat, not 4x
    assert p4 < in_memory_history / 4, (p4, in_memory_history)


def test_a_signal_handed_to_another_thread_waits_for_the_block_too():
    """The system may hand a process's SIGINT to any thread (numba, dask and
    libraries start some): it still waits until the held block is done, then
    interrupts (the full suite once lost a row of a committed block to it)."""
    import threading
    import time

    from fpd.coupling.recording import signals_held
    started, stop = threading.Event(), threading.Event()
    other = threading.Thread(target=lambda: (started.set(), stop.wait(10)))
    other.start()
    started.wait()
    order = []
    try:
        with signals_held():
            signal.pthread_kill(other.ident, signal.SIGINT)
            for _ in range(10_000):
                order.append(1)
            time.sleep(0.05)
            order.append("done")
    except KeyboardInterrupt:
        order.append("interrupted")
    finally:
        stop.set()
        other.join()
    assert order[-2:] == ["done", "interrupted"]
