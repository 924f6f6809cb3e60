"""The figures of a run, whatever its device, and writing them.

``FIGURE_SETS`` is the one registry: each device declares its set of
figures as data, the columns that mark its runs (its stepper's own
columns: ``W4_J`` the TFP's fourth surface, ``uy_m`` a motion in both
directions; the first set that matches is taken, the DFP / SFP's matches
every run) and its figures in the order ``fpd run`` writes them, each
(name: the PNG's stem, when: the columns it needs or a test of the
history, builder: a function of (result, scene) returning a Figure). A
device that adds a figure set adds a line here and its builders to
outputs/plots.py (the figure builders of every device, shared or its own).
"""
from __future__ import annotations

import time
from pathlib import Path

from . import drawing, plots


def _path_rows(result) -> bool:
    """The heat along the footprint path needs its centres and more than two rows."""
    return "c1x_m" in result and len(result["t_s"]) > 2


FIGURE_SETS = (
    ("TFP in both directions", ("W4_J", "uy_m"), (
        ("hysteresis", (), plots.loops),                 # the x and the y loops
        ("response", (), plots.response),
        ("orbit", (), plots.orbit),
        ("force_orbit", (), plots.force_orbit),
        ("heat_path", _path_rows, plots.heat_path),
        ("temperature", ("T1_C",), plots.tfp_temperature),
        ("friction", (), plots.tfp_friction),
    )),
    ("TFP", ("W4_J",), (
        ("hysteresis", (), plots.tfp_hysteresis),       # each branch coloured by its regime
        ("response", (), plots.tfp_response),
        ("temperature", ("T1_C",), plots.tfp_temperature),
        ("friction", (), plots.tfp_friction),
    )),
    ("DFP / SFP in both directions", ("uy_m",), (
        ("hysteresis", ("u_m",), plots.loops),             # the x and the y loops
        ("response", ("u_m",), plots.response),
        ("orbit", (), plots.orbit),
        ("force_orbit", (), plots.force_orbit),
        ("heat_path", _path_rows, plots.heat_path),
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
