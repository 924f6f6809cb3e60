"""A first compile on two cores. The coupled engine (coupling/engine_kernel.py)
calls the device's step, which takes about half of a first compile; while a
second process compiles that step, from the same source into the same numba
cache, this process compiles what the engine reaches after it (the fe1d
column's separately compiled steps, thermal/column_kernel.py, and the
device's row, its ``values``), then waits for the second process, and the
engine's own compile loads the step from the cache. Had the second process
failed, the engine compiles the step itself, as it would alone. The compiled
code is the same, and so is every number. Only when numba has no cache for
them yet; never on one core.

``python -m fpd.coupling.compile_aside FILE``: the second process (FILE: the
pickled arguments, removed when read).
"""
from __future__ import annotations

import os
import pickle
import subprocess
import sys
import tempfile

WAIT_S = 120.0          # the longest this process waits for the second one


def share(sim, C, S, L, X, dt, mu, dW, row, plates, kinds) -> None:
    """Before the engine's first call: the device's step compiled in a
    second process, the column's steps and the row here. ``plates``:
    fast_loop.plate_arrays' list, ``kinds`` the plates' kinds; C .. row the
    engine's own arguments."""
    from fpd import jitcache

    if (os.cpu_count() or 1) < 2 or os.environ.get("FPD_JIT_NO_CACHE") or os.environ.get("FPD_NO_JIT"):
        return
    dev = sim.mechanics.engine_device
    if not jitcache.uncached_at_load([dev]):
        return
    column = jitcache.uncached_at_load(["fpd.thermal.column_kernel"])
    # once per process: whatever happens below, the engine's first call compiles (or loads) them
    jitcache.compiled_now([dev, "fpd.thermal.column_kernel"])
    proc = None
    try:
        fd, path = tempfile.mkstemp(prefix="fpd-compile-", suffix=".pickle")
        with os.fdopen(fd, "wb") as fh:
            pickle.dump({"step": (dev, C, S, L, X, dt, mu, dW)}, fh, protocol=pickle.HIGHEST_PROTOCOL)
        import fpd
        root = os.path.dirname(os.path.dirname(os.path.abspath(fpd.__file__)))   # this process's fpd
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, (root, os.environ.get("PYTHONPATH")))))
        proc = subprocess.Popen([sys.executable, "-m", "fpd.coupling.compile_aside", path], env=env,
                                stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except (OSError, pickle.PicklingError):
        return
    try:
        here = {"values": (dev, C, S, L, dt, row)}
        fe1d = [arr for (arr, _), k in zip(plates, kinds) if k == "fe1d"]
        if fe1d and column:
            here["column"] = fe1d[0]
        compile_jobs(here)
        proc.wait(timeout=WAIT_S)
    except subprocess.TimeoutExpired:
        pass
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.wait()


def compile_jobs(jobs: dict) -> None:
    """Compile by calling, on copies of the arguments (one step, one row)."""
    import copy

    import numpy as np

    from fpd import kernels
    if "column" in jobs:
        Mb, Ab, FAC, V, I, P = copy.deepcopy(jobs["column"])
        kernels.compiled("fpd.thermal.column_kernel").plate_step(Mb, Ab, FAC, V, I, P, 0.0, 0.0)
    if "values" in jobs:
        dev, C, S, L, dt, row = jobs["values"]
        kernels.compiled(dev).values(C.copy(), S.copy(), L, np.int64(0), float(dt), row.copy())
    if "step" in jobs:
        dev, C, S, L, X, dt, mu, dW = jobs["step"]
        kernels.compiled(dev).step(C, S, L, X, np.int64(1), float(dt), mu, dW)


def main(path: str) -> int:
    with open(path, "rb") as fh:
        jobs = pickle.load(fh)
    os.unlink(path)
    compile_jobs(jobs)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
