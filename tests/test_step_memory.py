"""Memory per step of a long run: a record on the solver grid holds 24 bytes
per step (t, d, a_step, shared with the stepper without a copy; v and a are
computed only when asked for), sampled block by block (temporaries bounded
whatever the steps), the same numbers bit for bit as sampling the whole grid
at once. The 10^7-step run under 300 MB is the slow test; benchmarks/step_memory.py
measures the growth per step."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from fpd.loading import ground_motion as gmod

ROOT = Path(__file__).resolve().parents[1]


def _whole_grid(t_rec, a_rec, dt, n):
    """The sampling on the whole grid at once (as it was written before blocks)."""
    v0, _ = gmod._cumulative(t_rec, a_rec)
    b1, b2 = gmod.baseline_fit(t_rec, v0)
    a_rec = a_rec - (b1 + 2.0 * b2 * t_rec)
    v_rec, d_rec = gmod._cumulative(t_rec, a_rec)
    t = np.arange(n + 1) * dt
    k = np.clip(np.searchsorted(t_rec, t, side="right") - 1, 0, len(t_rec) - 2)
    h = t_rec[k + 1] - t_rec[k]
    tau = np.minimum(t - t_rec[k], h)
    slope = (a_rec[k + 1] - a_rec[k]) / h
    a = a_rec[k] + slope * tau
    v = v_rec[k] + a_rec[k] * tau + 0.5 * slope * tau ** 2
    d = d_rec[k] + v_rec[k] * tau + 0.5 * a_rec[k] * tau ** 2 + slope * tau ** 3 / 6.0
    after = t > t_rec[-1]
    a[after] = 0.0
    v[after] = v_rec[-1]
    d[after] = d_rec[-1] + v_rec[-1] * (t[after] - t_rec[-1])
    return {"t": t, "d": d, "v": v, "a": a, "a_step": np.diff(v) / dt}


@pytest.mark.parametrize("chunk", [7, 1000, gmod.CHUNK])
def test_blocks_give_the_whole_grid_bit_for_bit(monkeypatch, chunk):
    rng = np.random.default_rng(5)
    t_rec = np.cumsum(rng.uniform(0.005, 0.02, 300))
    t_rec -= t_rec[0]
    a_rec = rng.standard_normal(300)
    monkeypatch.setattr(gmod, "CHUNK", chunk)
    for dt, duration in ((1e-3, None), (3e-3, 1.5 * t_rec[-1])):      # the record ends early in the second
        n = max(1, int(round((duration or t_rec[-1]) / dt)))
        ref = _whole_grid(t_rec, a_rec, dt, n)
        gm = gmod.ground_motion_from_samples("x", t_rec, a_rec, dt, duration)
        for k, arr in ref.items():
            assert np.array_equal(getattr(gm, k), arr), (k, chunk, dt)


def test_a_record_holds_24_bytes_per_step_shared_with_the_stepper():
    """2e5 steps of the default scene (El Centro, two-phase stepper): what
    the build leaves alive is under 30 bytes per step, the stepper's loading
    is the ground motion's own memory, and the build's temporaries are bounded
    by the block size, not the steps."""
    from fpd.schema import scene as scn
    from fpd.coupling.build import build

    n = 200_000
    sc = scn.load("default", ['thermal.model="lumped"', f"solver.duration={n * 1e-3}", "output.plots=false"])
    tracemalloc.start()
    try:
        sim = build(sc)
        alive, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert sim.n_steps == n
    assert alive / n < 30, alive / n
    assert peak - alive < 40 * gmod.CHUNK * 8, (peak - alive)      # a few dozen block-sized temporaries
    mech, g = sim.mechanics, sim.mechanics.ground
    assert mech._ax is gmod.float_array(g.a_step) and mech._xg is g.d and mech._ay is None   # planar: no y series
    assert g._v is None and g._a is None                             # not computed for the run
    assert np.array_equal(np.diff(g.v) / g.dt, g.a_step) and len(g.a) == n + 1


@pytest.mark.slow
def test_a_ten_million_step_run_stays_under_300_MB():
    r = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "step_memory.py"), "--child", "10000000"],
                       env=dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1"),
                       capture_output=True, text=True, timeout=3600)
    out = json.loads(r.stdout.strip().splitlines()[-1])
    assert out["status"] == "ok" and out["steps"] == 10_000_000
    assert out["rss_peak"] < 300e6, out


def test_analytic_loadings_share_their_arrays_with_the_stepper():
    """Pulses and sines: the same values as computed, in compact arrays the
    stepper uses as they are (float_array returns the same memory)."""
    for gm in (gmod.pulse_ground_motion("cosine", 0.5, 1.0, 0.2, 3.0, 1e-3),
               gmod.harmonic_ground_motion(0.05, 0.5, 2, 1e-3)):
        assert all(gmod.float_array(getattr(gm, k)) is gmod.float_array(getattr(gm, k))
                   for k in ("t", "d", "v", "a", "a_step"))
        assert np.array_equal(gm.a_step, np.diff(gm.v) / gm.dt)
    g = gmod.pulse_ground_motion("cosine", 0.5, 1.0, 0.2, 3.0, 1e-3)
    t = np.arange(3001) * 1e-3
    s = np.clip(t - 0.2, 0.0, 1.0)
    assert np.array_equal(g.v, 0.5 * 0.5 * (1.0 - np.cos(2 * np.pi * s)))
