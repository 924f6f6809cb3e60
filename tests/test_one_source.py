"""One source for each piece of physics (issue 12): the pure and the compiled
run execute the same kernel modules, so a physics constant changed in its
single place changes both runs, identically; and no hand-written twin of a
kernel is left in the package."""
import ast
from pathlib import Path

import numpy as np
import pytest

from fpd import kernels
from fpd.coupling import fast_loop
from fpd.coupling import scene as scn
from fpd.coupling.build import build
from fpd.coupling.run import simulate
from fpd.mechanics import friction_kernel

ROOT = Path(__file__).resolve().parent.parent
OVER = ["solver.duration=3"]


def _run(monkeypatch, compiled: bool):
    with monkeypatch.context() as m:
        if not compiled:
            m.setenv("FPD_NO_JIT", "1")
        sim = build(scn.load("default", OVER))
        if compiled:
            assert fast_loop.compiled_loop(sim, 1, sim.n_steps + 1, _cols(sim)) is not None
        res = simulate(sim)
    assert res.status == "ok", res.message
    return res


def _cols(sim):
    from fpd.coupling.run import _columns
    return _columns(sim)[0]


@pytest.mark.skipif(not kernels.available(), reason="numba not installed (or FPD_NO_JIT)")
def test_a_constant_changed_in_its_one_place_changes_both_paths_identically(monkeypatch):
    """The Kumar temperature coefficient 0.79 -> 0.70 (friction_kernel only):
    the compiled and the pure default run both move, to the same history."""
    base = _run(monkeypatch, compiled=False)
    try:
        monkeypatch.setenv("FPD_JIT_NO_CACHE", "1")      # a cached kernel keeps the constants it was built with
        monkeypatch.setattr(friction_kernel, "KUMAR_T_COEF", 0.70)
        kernels.fresh()
        pure = _run(monkeypatch, compiled=False)
        comp = _run(monkeypatch, compiled=True)
    finally:
        monkeypatch.undo()
        kernels.fresh()                                   # later tests: the modules of the real constant
    mu = base.columns.index("mu1")
    assert np.nanmin(pure.data[1:, mu]) < 0.95 * np.nanmin(base.data[1:, mu])   # the law changed (x 0.70/0.79)
    assert pure.columns == comp.columns
    np.testing.assert_array_equal(pure.data, comp.data)


def test_no_numba_twin_of_a_kernel():
    """Only kernel modules hold per-step physics for numba: no module of the
    package imports numba except fpd/kernels.py and the primitive backends
    named by a ``__compiled_backend__`` (the BLAS pointer calls)."""
    backends = set()
    for path in ROOT.rglob("*.py"):
        if "tests" in path.parts or ".git" in path.parts:
            continue
        text = path.read_text()
        if "__compiled_backend__ = " in text:
            name = text.split("__compiled_backend__ = ")[1].split("\n")[0].strip("\"'")
            backends.add(name.rsplit(".", 1)[1] + ".py")
    importers = []
    for path in ROOT.rglob("*.py"):
        if "tests" in path.parts or ".git" in path.parts or "benchmarks" in path.parts:
            continue
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module or ""] if isinstance(node, ast.ImportFrom) else []
            if any(n.split(".")[0] == "numba" for n in names):
                importers.append(path.relative_to(ROOT).as_posix())
    allowed = {"fpd/kernels.py"} | {f"thermal/{b}" for b in backends}
    assert set(importers) <= allowed, sorted(set(importers) - allowed)


def test_the_kernel_modules_are_kernels():
    import importlib
    for name in ("fpd.mechanics.friction_kernel", "fpd.mechanics.two_phase_kernel",
                 "fpd.thermal.lumped_kernel", "fpd.thermal.column_kernel", "fpd.coupling.loop_kernel"):
        assert kernels.is_kernel_module(importlib.import_module(name)), name
