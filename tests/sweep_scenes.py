"""The small scenes the sweep tests run (one DFP, a short pulse or a record),
written once for tests/test_sweep.py and tests/test_sweep_cluster.py."""
from __future__ import annotations


def lite(duration_s: float = 1.5) -> str:
    """A DFP under a cosine velocity pulse, lumped plates, no plots."""
    return f"""
name = "lite"
[device]
kind = "DFP"
R1 = 2.2
R2 = 2.2
pad_height = 0.10
pad_diameter = 0.25
[superstructure]
mass = 1.0e5
[friction]
law = "constant"
mu = 0.06
[loading]
kind = "pulse"
shape = "cosine"
velocity_mps = 0.5
period_s = 1.0
t0_s = 0.2
duration_s = {duration_s!r}
[thermal]
model = "lumped"
[solver]
dt = 1e-3
[output]
plots = false
"""


def with_loading(scene: str, loading: str) -> str:
    """The scene with its [loading] table replaced by ``loading`` (its lines)."""
    return scene.split("[loading]")[0] + "[loading]\n" + loading + "[thermal]" + scene.split("[thermal]")[1]
