"""The coupled loop's own time per device: `python benchmarks/engine_speed.py [--repeat N] [--root DIR]`.

For each case the time-stepping loop's own time (Result.runtime_s: stepping
only, not imports, compilation or storing), best of N runs in one process
(the best run is the least disturbed one on a shared machine). ``--root``
runs another checkout of the project (same cases), so that two versions can
be measured side by side: run both, alternating, on the same machine.
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import importlib  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

CASES = [
    # name, scene, overrides
    ("DFP default (fe1d)", "default", []),
    ("DFP default, lumped", "default", ["thermal.model=lumped"]),
    ("DFP bidirectional (fe1d)", "impvall-bidirectional", []),
    # the vertical component's cost: the same record with two, then three components
    ("DFP Ferndale x, y (lumped)", "ferndale-3c", ["loading.channels=[1, 2]"]),
    ("DFP Ferndale x, y, z (lumped)", "ferndale-3c", []),
    ("TFP two-phase (fe1d)", "tfp-elcentro", ["thermal.model=fe1d"]),
    ("TFP seated, lumped", "tfp-elcentro", ["mechanics.model=seated", "thermal.model=lumped"]),
    ("flat machine (flat-lab)", "flat-lab", []),
    ("flat machine, lumped", "flat-lab", ["thermal.model=lumped"]),
    ("test machine (lab-sine, fe1d)", "lab-sine", []),
    ("test machine, lumped", "lab-sine", ["thermal.model=lumped"]),
    ("orbit machine (circle, fe1d)", "lab-sine", ['loading.waveform="circle"']),
]


def _module(*names):
    for name in names:
        try:
            return importlib.import_module(name)
        except ImportError:
            continue
    raise ImportError(names)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--root", default=str(Path(__file__).resolve().parent.parent))
    args = ap.parse_args(argv)
    sys.path.insert(0, args.root)
    import numba  # noqa: F401  (every case takes the compiled loop)
    # an earlier layout first (--root): its scene module lived in the coupling package
    scn = _module("fpd." + "coupling.scene", "fpd.schema.scene")
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate
    for name, scene, over in CASES:
        best = float("inf")
        try:
            scn.load(scene, over)
        except Exception as exc:                    # a case another checkout does not have
            print(f"{name:28s} n/a ({type(exc).__name__})", flush=True)
            continue
        for _ in range(args.repeat + 1):            # the first run loads (or compiles) the kernels
            r = simulate(build(scn.load(scene, over)))
            assert r.status == "ok", r.message
            best = min(best, r.runtime_s)
        print(f"{name:28s} {r.steps:7d} steps  loop {best:.3f} s  ({1e6 * best / r.steps:.2f} us/step)", flush=True)


if __name__ == "__main__":
    main()
