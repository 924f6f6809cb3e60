"""Plots of a bidirectional run (model.md 8): the x and y hysteresis loops,
the displacement orbit, the force orbit and the friction heat along the
footprint path on each plate."""
from __future__ import annotations

import math
import numpy as np


def _orbit(x, y, xlabel, ylabel, title, circle=None):
    from .drawing import new_figure, thin_xy
    fig, (ax,) = new_figure(figsize=(5.6, 5.2), left=0.85, bottom=0.55, top=0.4)
    s = thin_xy(len(x), x, y)
    ax.plot(x[s], y[s], lw=0.7)
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
    return fig


def loops(result, scene):
    """The x and the y hysteresis loops, F_x against u_x and F_y against u_y
    (signed: each loop's enclosed area is the work the bearing's force does
    in that direction, their sum the friction and rim work of the run)."""
    from .drawing import new_figure, thin_xy
    fig, ax = new_figure(1, 2, figsize=(10.5, 4.2), left=0.8, wgap=0.8, top=0.6)
    for a, d in zip(ax, "xy"):
        u, F = result[f"u{d}_m"], result[f"F{d}_N"]
        work = float(np.sum(0.5 * (F[1:] + F[:-1]) * np.diff(u)))
        s = thin_xy(len(u), u, F)
        a.plot(1e3 * u[s], 1e-3 * F[s], lw=0.7, color="tab:blue" if d == "x" else "tab:green")
        a.set_xlabel(f"relative displacement u_{d} (mm)")
        a.set_ylabel(f"force F_{d} (kN)")
        a.set_title(f"{d}: integral of F_{d} du_{d} = {1e-3 * work:.3g} kJ", fontsize=10)
        a.grid(alpha=0.3)
    fig.suptitle(f"{scene.name}: hysteresis in x and in y")
    return fig


def orbit(result, scene):
    """The displacement orbit u_y against u_x, with the peak resultant's circle."""
    ux, uy = 1e3 * result["ux_m"], 1e3 * result["uy_m"]
    return _orbit(ux, uy, "u_x (mm)", "u_y (mm)", f"{scene.name}: displacement orbit",
                  circle=float(np.max(np.hypot(ux, uy))))


def force_orbit(result, scene):
    """The force orbit F_y against F_x, with the peak resultant's circle."""
    Fx, Fy = 1e-3 * result["Fx_N"], 1e-3 * result["Fy_N"]
    return _orbit(Fx, Fy, "F_x (kN)", "F_y (kN)", f"{scene.name}: force orbit",
                  circle=float(np.max(np.hypot(Fx, Fy))))


def _top_per_cell(x, y, q, cell: float):
    """Indices of the points to draw, hottest last: in each cell of side
    ``cell`` (about half a pixel) only the point of largest q, the one a
    drawing of every point in increasing q shows there."""
    order = np.argsort(q, kind="stable")
    if cell <= 0 or len(q) < 4000:
        return order
    ix = np.round(x[order] / cell).astype(np.int64)
    iy = np.round(y[order] / cell).astype(np.int64)
    key = (ix - ix.min()) * (int(iy.max() - iy.min()) + 1) + (iy - iy.min())
    # the last (hottest) point of each cell, kept in increasing q
    _, last = np.unique(key[::-1], return_index=True)
    return order[np.sort(len(key) - 1 - last)]


def heat_path(result, scene):
    """The footprint centre's path on each plate, coloured by the friction
    heat flux delivered there (W/m2, friction power of the interface over the
    contact area, between consecutive recorded rows)."""
    from .drawing import new_figure, thin_xy
    title = scene.name
    a = 0.5 * scene["device"]["pad_diameter"]
    area = math.pi * a * a
    t = result["t_s"]
    fig, axes = new_figure(1, 2, figsize=(10.5, 5.0), left=0.8, right=0.45, wgap=1.25, top=0.7, bottom=0.55)
    for ax, (i, side) in zip(axes, ((1, "lower"), (2, "upper"))):
        cx, cy = 1e3 * result[f"c{i}x_m"], 1e3 * result[f"c{i}y_m"]
        W = result[f"W{i}_J"]
        dt = np.diff(t)
        q = np.where(dt > 0, np.diff(W) / np.where(dt > 0, dt, 1.0), 0.0) / area
        xm, ym = 0.5 * (cx[1:] + cx[:-1]), 0.5 * (cy[1:] + cy[:-1])
        order = _top_per_cell(xm, ym, q, max(float(np.ptp(cx)), float(np.ptp(cy)), 2e3 * a) / 800.0)
        sc = ax.scatter(xm[order], ym[order], c=1e-6 * q[order], s=3, cmap="inferno_r",
                        vmin=1e-6 * float(q.min()), vmax=1e-6 * float(q.max()))     # the scale of every point
        s = thin_xy(len(cx), cx, cy)
        ax.plot(cx[s], cy[s], lw=0.3, color="0.6", zorder=0)
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
    return fig
