"""Packaged scenes whose histories the speed work must reproduce
(tests/test_speed_equivalence.py; fingerprints in tests/data/speed_fingerprints.npz,
regenerated only from pre-optimisation code with `python tests/speed_cases.py`)."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

CASES = {
    "default": ("default", ["solver.duration=6"]),
    "default-iterated": ("default", ["solver.duration=3", "coupling.scheme=iterated"]),
    "default-seated-lumped": ("default", ["solver.duration=6", "mechanics.model=seated", "thermal.model=lumped"]),
    "lab-sine": ("lab-sine", []),
    "sfp-harmonic": ("sfp-harmonic", []),
    "northridge-dfp": ("northridge-dfp", ["solver.duration=5"]),
    "heat-halfspace": ("heat-halfspace", []),
}
EVERY = 25     # rows kept: every 25th plus the last


def run_case(name):
    from coupling import scene as scn
    from coupling.build import build
    from coupling.run import simulate

    scene, over = CASES[name]
    res = simulate(build(scn.load(scene, over)))
    assert res.status == "ok", res.message
    return res


def fingerprint(res):
    rows = np.r_[np.arange(0, res.n_rows, EVERY), res.n_rows - 1]
    return res.data[rows], np.array(res.columns), res.n_rows


if __name__ == "__main__":
    root = Path(__file__).resolve().parent.parent
    sys.path.insert(0, str(root))
    out = {}
    for name in CASES:
        data, cols, n = fingerprint(run_case(name))
        out[f"{name}/data"], out[f"{name}/columns"], out[f"{name}/n_rows"] = data, cols, np.array(n)
        print(name, data.shape, n)
    np.savez_compressed(Path(__file__).parent / "data" / "speed_fingerprints.npz", **out)
