"""The figures of a run, whatever its device, and writing them.

``FIGURE_SETS`` is the one registry: each device declares its set of
figures as data, the columns that mark its runs (its stepper's own
columns: ``W4_J`` the TFP's fourth surface, ``uy_m`` a motion in both
directions; the first set that matches is taken, the DFP / SFP's matches
every run) and its figures in the order ``fpd run`` writes them, each
(name: the PNG's stem, when: the columns it needs or a test of the
history, builder: a function of (result, scene) returning a Figure). A
device that adds a figure set adds a line here; its figures live in a
module of its own (outputs/tfp_plots.py, plots_bidirectional.py) or are
shared (outputs/plots.py).
"""
from __future__ import annotations

import time
from pathlib import Path

from . import drawing, plots, plots_bidirectional as bd, tfp_plots


def _path_rows(result) -> bool:
    """The heat along the footprint path needs its centres and more than two rows."""
    return "c1x_m" in result and len(result["t_s"]) > 2


FIGURE_SETS = (
    ("TFP", ("W4_J",), (
        ("hysteresis", (), tfp_plots.hysteresis),       # each branch coloured by its regime
        ("response", (), tfp_plots.response),
        ("temperature", ("T1_C",), tfp_plots.temperature),
        ("friction", (), tfp_plots.friction),
    )),
    ("DFP / SFP in both directions", ("uy_m",), (
        ("hysteresis", ("u_m",), bd.loops),             # the x and the y loops
        ("response", ("u_m",), plots.response),
        ("orbit", (), bd.orbit),
        ("force_orbit", (), bd.force_orbit),
        ("heat_path", _path_rows, bd.heat_path),
        ("temperature", ("T1_C",), plots.temperature),
        ("friction", ("mu1",), plots.friction),
    )),
    ("DFP / SFP, flat bearing, heat only", (), (
        ("hysteresis", ("u_m",), plots.hysteresis),
        ("response", ("u_m",), plots.response),
        ("temperature", ("T1_C",), plots.temperature),
        ("friction", ("mu1",), plots.friction),
    )),
)


def figure_set(result) -> tuple:
    """The figures of the first set whose marking columns the run has."""
    return next(figs for _, marks, figs in FIGURE_SETS if all(c in result for c in marks))


def figures(result, scene) -> dict:
    """name (the PNG's stem) -> a function of no arguments that builds that
    figure of this run, in the order ``fpd run`` writes them."""
    out = {}
    for name, when, build in figure_set(result):
        if when(result) if callable(when) else all(c in result for c in when):
            out[name] = (lambda b=build: b(result, scene))
    return out


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
