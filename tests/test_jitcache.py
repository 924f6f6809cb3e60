"""The first-compile notice and a progress bar whose ETA leaves the compile out."""
from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from fpd import jitcache

ROOT = Path(__file__).resolve().parent.parent


def _module(tmp_path, name="kmod"):
    pkg = tmp_path / "kpkg"
    pkg.mkdir(exist_ok=True)
    (pkg / "__init__.py").write_text("")
    (pkg / f"{name}.py").write_text("def f(x):\n    return x\n")
    return pkg / f"{name}.py"


def test_needs_compile_follows_numbas_index_files(tmp_path, monkeypatch):
    src = _module(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    assert jitcache.needs_compile(["kpkg.kmod"])                 # no index at all
    cache = src.parent / "__pycache__"
    cache.mkdir()
    idx = cache / "kmod.f-1.py311.nbi"
    idx.write_bytes(b"")
    t = src.stat().st_mtime
    os.utime(idx, (t + 10, t + 10))
    assert not jitcache.needs_compile(["kpkg.kmod"])             # an index newer than the source
    os.utime(src, (t + 20, t + 20))
    assert jitcache.needs_compile(["kpkg.kmod"])                 # the source edited since
    elsewhere = tmp_path / "numba-cache" / "deep"
    elsewhere.mkdir(parents=True)
    idx.unlink()
    (elsewhere / "kmod.f-1.py311.nbi").write_bytes(b"")
    os.utime(elsewhere / "kmod.f-1.py311.nbi", (t + 30, t + 30))
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "numba-cache"))
    assert not jitcache.needs_compile(["kpkg.kmod"])
    assert not jitcache.needs_compile(["kpkg.no_such_module"])   # nothing to compile


def test_announce_once_and_only_when_enabled(tmp_path, monkeypatch):
    _module(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delenv("FPD_NO_JIT", raising=False)
    monkeypatch.setitem(sys.modules, "numba", sys.modules.get("numba") or object())
    monkeypatch.setattr(jitcache, "_done", False)
    lines = []
    monkeypatch.setattr(jitcache, "_write", None)
    jitcache.announce(["kpkg.kmod"])
    assert lines == []                                            # library use: silent
    jitcache.enable(lines.append)
    jitcache.announce(["kpkg.kmod"])
    jitcache.announce(["kpkg.kmod"])
    assert lines == [jitcache.NOTICE] and "compiling kernels once, about 15 s" in lines[0]
    jitcache.disable()


_PROBE = """
import sys
from fpd import jitcache
jitcache.needs_compile = lambda names: True       # as on the first run after an install
from fpd.frontends.cli import main
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.skipif(os.environ.get("FPD_NO_JIT") is not None, reason="kernels disabled")
@pytest.mark.parametrize("quiet", [False, True])
def test_cli_prints_the_notice_unless_quiet(tmp_path, quiet):
    pytest.importorskip("numba")
    args = ["run", "default", "--out", str(tmp_path / "o"), "--set", "solver.duration=0.2",
            "--set", "output.plots=false"] + (["--quiet"] if quiet else [])
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    r = subprocess.run([sys.executable, "-c", _PROBE, *args], cwd=tmp_path, env=env, capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert r.stderr.count("compiling kernels once") == (0 if quiet else 1), r.stderr


def test_progress_clock_starts_after_the_kernels_load(monkeypatch):
    """A slow kernel load (a compile) before the loop must not enter the bar's ETA."""
    from fpd.coupling import run as runmod
    from fpd.schema import scene as scn
    from fpd.coupling.build import build

    sim = build(scn.load("sfp-harmonic", ["solver.duration=0.05"]))
    seen = {}

    def slow_compile(*a, **k):
        time.sleep(0.3)
        seen["compiled"] = time.perf_counter()
        return None

    class Bar(runmod._Progress):
        def __init__(self, *a, **k):
            super().__init__(*a, **k)
            seen["bar_t0"] = self.t0

    monkeypatch.setattr(runmod, "compiled_loop", slow_compile)
    monkeypatch.setattr(runmod, "_Progress", Bar)
    sim.scene["coupling"]["scheme"] = "staggered"
    res = runmod.simulate(sim, progress=False)
    assert res.status == "ok"
    assert "compiled" in seen, "compiled_loop was not called on the fast path"
    assert seen["bar_t0"] >= seen["compiled"]


@pytest.mark.skipif(not __import__("fpd.kernels").kernels.available() or (os.cpu_count() or 1) < 2,
                    reason="numba and two cores needed")
def test_first_compile_shares_the_devices_step_with_a_second_process(tmp_path):
    """With an empty cache (a fresh NUMBA_CACHE_DIR), the engine's first
    compile loads the device's step from the cache the second process
    (coupling/compile_aside.py) wrote: a cache hit, not a compile; the
    second process is started once per process (a later build of the same
    device finds it compiled), never with a full cache; and the run equals
    a run with the cache already full, bit for bit."""
    code = (
        "import numpy as np\n"
        "from fpd import kernels\n"
        "from fpd.schema import scene as scn\n"
        "from fpd.coupling.build import build\n"
        "from fpd.coupling.run import simulate\n"
        "import fpd.coupling.compile_aside as ca\n"
        "spawned = []\n"
        "popen = ca.subprocess.Popen\n"
        "ca.subprocess.Popen = lambda *a, **k: spawned.append(1) or popen(*a, **k)\n"
        "sim = build(scn.load('lab-sine', ['solver.duration=0.5']))\n"
        "build(scn.load('lab-sine', ['solver.duration=0.5']))   # compiled already: no second process\n"
        "d = kernels.compiled(sim.mechanics.engine_device)\n"
        "print(sum(d.step.stats.cache_hits.values()), sum(d.step.stats.cache_misses.values()), len(spawned))\n"
        "r = simulate(sim)\n"
        "np.save(%r, np.column_stack([r[c] for c in r.columns]))\n")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    runs = []
    for k in range(2):                      # an empty cache, then the full one
        out = tmp_path / f"run{k}.npy"
        p = subprocess.run([sys.executable, "-c", code % str(out)], env=env, capture_output=True, text=True,
                           cwd=tmp_path, timeout=600)
        assert p.returncode == 0, p.stderr[-2000:]
        runs.append((p.stdout.split(), out))
    # first compile: the step came from the second process, spawned once per process
    assert runs[0][0] == ["1", "0", "1"], runs[0][0]
    assert runs[1][0][2] == "0", runs[1][0]           # a full cache: none
    import numpy as np
    assert np.array_equal(np.load(runs[0][1]), np.load(runs[1][1]))
