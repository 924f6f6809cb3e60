"""Plots of a bidirectional run (model.md 8): the displacement orbit, the
force orbit and the friction heat along the footprint path on each plate."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _orbit(folder: Path, x, y, xlabel, ylabel, title, name, circle=None) -> str:
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.6, 5.2))
    ax.plot(x, y, lw=0.7)
    ax.plot(x[:1], y[:1], "o", ms=4, color="C2", label="start")
    ax.plot(x[-1:], y[-1:], "s", ms=4, color="C3", label="end")
    if circle is not None:
        t = np.linspace(0.0, 2.0 * math.pi, 200)
        ax.plot(circle * np.cos(t), circle * np.sin(t), "--", lw=0.6, color="0.5", label="peak resultant")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(folder / name, dpi=110)
    plt.close(fig)
    return name


def make_bidirectional_plots(folder: Path, result, scene) -> list[str]:
    title = scene.name
    made = []
    ux, uy = 1e3 * result["ux_m"], 1e3 * result["uy_m"]
    made.append(_orbit(folder, ux, uy, "u_x (mm)", "u_y (mm)", f"{title}: displacement orbit", "orbit.png",
                       circle=float(np.max(np.hypot(ux, uy)))))
    Fx, Fy = 1e-3 * result["Fx_N"], 1e-3 * result["Fy_N"]
    made.append(_orbit(folder, Fx, Fy, "F_x (kN)", "F_y (kN)", f"{title}: force orbit", "force_orbit.png",
                       circle=float(np.max(np.hypot(Fx, Fy)))))
    if "c1x_m" in result and len(result["t_s"]) > 2:
        made.append(_heat_path(folder, result, scene, title))
    return made


def _heat_path(folder: Path, result, scene, title) -> str:
    """The footprint centre's path on each plate, coloured by the friction
    heat flux delivered there (W/m2, friction power of the interface over the
    contact area, between consecutive recorded rows)."""
    plt = _plt()
    a = 0.5 * scene["device"]["pad_diameter"]
    area = math.pi * a * a
    t = result["t_s"]
    fig, axes = plt.subplots(1, 2, figsize=(10.5, 5.0))
    for ax, (i, side) in zip(axes, ((1, "lower"), (2, "upper"))):
        cx, cy = 1e3 * result[f"c{i}x_m"], 1e3 * result[f"c{i}y_m"]
        W = result[f"W{i}_J"]
        dt = np.diff(t)
        q = np.where(dt > 0, np.diff(W) / np.where(dt > 0, dt, 1.0), 0.0) / area
        xm, ym = 0.5 * (cx[1:] + cx[:-1]), 0.5 * (cy[1:] + cy[:-1])
        order = np.argsort(q)              # the hottest points drawn last (on top)
        sc = ax.scatter(xm[order], ym[order], c=1e-6 * q[order], s=3, cmap="inferno_r")
        ax.plot(cx, cy, lw=0.3, color="0.6", zorder=0)
        circ = np.linspace(0.0, 2.0 * math.pi, 100)
        ax.plot(cx[-1] + 1e3 * a * np.cos(circ), cy[-1] + 1e3 * a * np.sin(circ), lw=0.8, color="C0",
                label="pad footprint at the end")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x on the plate (mm)")
        ax.set_ylabel("y on the plate (mm)")
        ax.set_title(f"{side} plate: W{i} = {1e-3 * W[-1]:.3g} kJ")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
        fig.colorbar(sc, ax=ax, label="friction heat flux (MW/m2)", shrink=0.8)
    fig.suptitle(f"{title}: heat along the footprint path")
    fig.tight_layout()
    fig.savefig(folder / "heat_path.png", dpi=110)
    plt.close(fig)
    return "heat_path.png"
