"""One source for each piece of physics (issue 12): the pure and the compiled
run execute the same kernel modules, so a physics constant changed in its
single place changes both runs, identically; and no hand-written twin of a
kernel is left in the package."""
import ast
from pathlib import Path

import numpy as np
import pytest

from fpd import kernels

ROOT = Path(__file__).resolve().parent.parent


# The changed constant is tried in a child process: numba links a compiled
# function by its symbol name, so kernels compiled with the patched constant
# would stay linked into the cached ones loaded later in the same process.
_CHILD = r"""
import json, os, sys
import numpy as np
os.environ["FPD_JIT_NO_CACHE"] = "1"           # a cached kernel keeps the constants it was built with
from fpd import kernels
from fpd.tribology import friction_kernel
coef, what, out = float(sys.argv[1]), sys.argv[2], sys.argv[3]
friction_kernel.KUMAR_T_COEF = coef            # the one place of the Kumar temperature coefficient
if what == "law":
    from fpd.tribology.friction import Kumar2015
    law = Kumar2015(0.06, use_pressure=True, use_velocity=True)
    T = np.linspace(-20.0, 400.0, 57)
    comp = kernels.compiled("fpd.tribology.friction_kernel").law_mu
    P = np.array(law.P)
    np.savez(out, pure=[law(t, 3e7, 0.1) for t in T], comp=[comp(P, t, 3e7, 0.1) for t in T])
else:
    from fpd.coupling import fast_loop
    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate, _columns
    res = {}
    for mode in ("comp", "pure"):
        fast_loop.enabled = mode == "comp"
        if mode == "pure":
            os.environ["FPD_NO_JIT"] = "1"
        sim = build(scn.load("default", ["solver.duration=3"]))
        used = fast_loop.compiled_loop(sim, 1, sim.n_steps + 1, _columns(sim)[0]) is not None
        assert used == (mode == "comp"), mode
        plate = sim.plates[0].integ.compiled
        assert plate == (mode == "comp"), mode
        r = simulate(sim)
        assert r.status == "ok", r.message
        res[mode] = r.data
        res["columns"] = np.array(r.columns)
    np.savez(out, **res)
"""


def _child(tmp_path, coef, what):
    import os
    import subprocess
    import sys
    out = tmp_path / f"{what}-{coef}.npz"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    env.pop("FPD_NO_JIT", None)
    r = subprocess.run([sys.executable, "-c", _CHILD, str(coef), what, str(out)], env=env, cwd=ROOT,
                       capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    return np.load(out)


needs_numba = pytest.mark.skipif(not kernels.available(), reason="numba not installed (or FPD_NO_JIT)")


@needs_numba
def test_a_constant_changed_in_its_one_place_changes_both_laws_identically(tmp_path):
    """Fast version: the Kumar coefficient 0.79 -> 0.70 in friction_kernel
    only moves the pure law and its compiled twin by k_T's ratio, identically."""
    ref, new = _child(tmp_path, 0.79, "law"), _child(tmp_path, 0.70, "law")
    np.testing.assert_array_equal(ref["pure"], ref["comp"])
    np.testing.assert_array_equal(new["pure"], new["comp"])
    np.testing.assert_allclose(new["pure"] / ref["pure"], 0.70 / 0.79, rtol=1e-14)


@needs_numba
@pytest.mark.slow
def test_a_constant_changed_in_its_one_place_changes_both_paths_identically(tmp_path):
    """The acceptance test of issue 12: the Kumar temperature coefficient
    0.79 -> 0.70, changed in friction_kernel only, moves the compiled and the
    pure default run, to the same history bit for bit (compiles the loop
    without the cache: about a minute)."""
    ref, new = _child(tmp_path, 0.79, "scene"), _child(tmp_path, 0.70, "scene")
    np.testing.assert_array_equal(ref["pure"], ref["comp"])
    np.testing.assert_array_equal(new["pure"], new["comp"])
    mu = list(ref["columns"]).index("mu1")
    assert np.nanmin(new["pure"][1:, mu]) < 0.95 * np.nanmin(ref["pure"][1:, mu])   # x 0.70/0.79 on k_T


def _project_sources():
    """The project's own .py files: not those under a hidden folder (.git, or
    the .venv the README's set-up makes inside the checkout)."""
    return (p for p in ROOT.rglob("*.py") if not any(part.startswith(".") for part in p.relative_to(ROOT).parts))


def test_no_numba_twin_of_a_kernel():
    """Only kernel modules hold per-step physics for numba: no module of the
    package imports numba except fpd/kernels.py and the primitive backends
    named by a ``__compiled_backend__`` (the BLAS pointer calls)."""
    backends = set()
    for path in _project_sources():
        if "tests" in path.parts:
            continue
        text = path.read_text()
        if "__compiled_backend__ = " in text:
            name = text.split("__compiled_backend__ = ")[1].split("\n")[0].strip("\"'")
            backends.add(name.rsplit(".", 1)[1] + ".py")
    importers = []
    for path in _project_sources():
        if "tests" in path.parts or "benchmarks" in path.parts:
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
    for name in ("fpd.tribology.friction_kernel", "fpd.mechanics.two_phase_kernel", "fpd.machines.seated_kernel",
                 "fpd.thermal.lumped_kernel", "fpd.thermal.column_kernel", "fpd.coupling.engine_kernel",
                 "fpd.mechanics.dev_two_phase", "fpd.mechanics.dev_bidirectional", "fpd.mechanics.dev_tfp",
                 "fpd.mechanics.flat_kernel", "fpd.mechanics.dev_flat", "fpd.machines.dev_seated_machine",
                 "fpd.machines.dev_orbit_machine", "fpd.machines.link_kernel"):
        assert kernels.is_kernel_module(importlib.import_module(name)), name
