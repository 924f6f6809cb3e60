"""The figures of a run, whatever its device: the TFP's (outputs/tfp_plots.py)
or the two-interface devices' (outputs/plots.py), and writing them."""
from __future__ import annotations

import time
from pathlib import Path

from . import drawing, plots


def figures(result, scene) -> dict:
    """name (the PNG's stem) -> a function of no arguments that builds that
    figure of this run, in the order ``fpd run`` writes them."""
    if "W4_J" in result:                     # the TFP: four surfaces, regimes
        from . import tfp_plots
        return tfp_plots.figures(result, scene)
    return plots.figures(result, scene)


def make_plots(folder: Path, result, scene, timings: list | None = None) -> list[str]:
    """Write every figure of the run into ``folder`` (PNG); the names written.
    ``timings``: a list to append (name, process seconds) to per figure."""
    made = []
    t0 = time.process_time()
    for name, build in figures(result, scene).items():
        fig = build()
        drawing.save(fig, Path(folder) / f"{name}.png")
        made.append(f"{name}.png")
        if timings is not None:
            t1 = time.process_time()
            timings.append((f"{name}.png", t1 - t0))
            t0 = t1
    return made
