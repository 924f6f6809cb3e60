"""The figures of a DFP / SFP run (and the ones a bidirectional run shares
with it; matplotlib, imported only when plots are asked for).

Each figure is built by a function of the run's columns and its scene that
returns a ``matplotlib.figure.Figure`` (outputs/figures.py: which device
draws which); ``fpd run`` saves them in plots/ (``make_plots``) and ``Result.plot()`` hands them
to the caller. The figures are drawn on matplotlib's Agg canvas without
pyplot (nothing registered, nothing to close), with fixed margins in inches
(no layout pass that draws the figure twice), and each line is drawn through
at most a few points per pixel column (``thin``: per bin of consecutive rows
the first, last, smallest and largest value of every drawn column, so the
drawn envelope is the one of every row).
"""
from __future__ import annotations

import math

import numpy as np

from .drawing import BINS, DEG, DPI, XY_BINS, _same, new_figure, save, thin, thin_xy  # noqa: F401

def plate_quantity(scene, side: str) -> str:
    """What a plate model's temperature column (T1_C / T2_C) is, in words."""
    from .hottest import quantity_of
    t = scene.thermal(side)
    return quantity_of(t["model"], t.get("source", "follow-pad"), t.get("radius_m", 0.0))


def sides(scene) -> tuple[str, ...]:
    """The sliding interfaces of the device: an SFP has only the lower one
    (its articulation carries no friction and heats nothing)."""
    return ("lower",) if scene["device"]["kind"] == "SFP" else ("lower", "upper")


def _machine(scene) -> bool:
    return scene["loading"]["kind"] == "displacement"


def cycle_of(t, scene):
    """The programme's cycle (1, 2, ...) of each time of a test-machine run."""
    import numpy as np
    ld = scene["loading"]
    # a row at the end of a cycle closes it (the next cycle's line starts from it)
    from fpd.outputs.cycles import hold_of
    k = np.ceil((np.asarray(t) - hold_of(scene)) * ld["frequency_Hz"] * (1.0 - 1e-12)).astype(int)
    return np.clip(k, 1, int(np.ceil(ld["cycles"] - 1e-9)))


def hysteresis(result, scene):
    """F against u. On the test machine each cycle in its own colour."""
    import numpy as np
    u, F, t = 1e3 * result["u_m"], 1e-3 * result["F_N"], result["t_s"]
    fig, (ax,) = new_figure()
    if _machine(scene):
        k = cycle_of(t, scene)
        colours = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown", "tab:pink",
                   "tab:olive", "tab:cyan", "tab:gray")
        for c in np.unique(k):
            rows = np.flatnonzero(k == c)
            rows = np.append(rows, rows[-1] + 1) if rows[-1] + 1 < len(u) else rows   # joined to the next
            s = rows[thin_xy(len(rows), u[rows], F[rows])]
            ax.plot(u[s], F[s], lw=0.8, color=colours[(c - 1) % len(colours)], label=f"cycle {c}")
        ax.legend(loc="upper left", fontsize=8, ncols=2 if len(np.unique(k)) > 5 else 1)
    else:
        s = thin_xy(len(u), u, F)
        ax.plot(u[s], F[s], lw=0.8)
    ax.set_xlabel("relative displacement u (mm)")
    ax.set_ylabel("horizontal force F (kN)")
    ax.set_title(f"{scene.name}: hysteresis")
    ax.grid(alpha=0.3)
    return fig


def response(result, scene):
    """Displacements against time; the energy ledger's terms."""
    import numpy as np
    machine = _machine(scene)
    t = result["t_s"]
    W12 = result["W1_J"] + result["W2_J"]
    if machine:
        # the machine's work through the bearing, the running loop area: the
        # E_input_J column is the ledger in the lower plate's frame, where the
        # programme's launch at u'(0) = 2 pi f A is kinetic energy put in before t = 0
        u, F = result["u_m"], result["F_N"]
        work = np.concatenate(([0.0], np.cumsum(0.5 * (F[1:] + F[:-1]) * np.diff(u))))
        wlabel = "machine work, integral of F du"
    else:
        work, wlabel = result["E_input_J"], "input work"
    two_d = "uy_m" in result
    disp = ([result["ux_m"], result["uy_m"], result["xg_m"]] + ([result["yg_m"]] if "yg_m" in result else [])
            if two_d else [result["u_m"], result["xg_m"]])
    s = thin(len(t), *disp, W12, work, *([result["E_reseat_J"]] if "E_reseat_J" in result else []))
    t = t[s]
    fig, ax = new_figure(2, figsize=(7.0, 6.4), top=0.75 if machine else 0.35, sharex=True)
    if two_d:
        ax[0].plot(t, 1e3 * result["ux_m"][s], lw=0.8, label="u_x")
        ax[0].plot(t, 1e3 * result["uy_m"][s], lw=0.8, label="u_y")
        ax[0].plot(t, 1e3 * result["xg_m"][s], lw=0.6, alpha=0.6, label="ground x_g")
        if "yg_m" in result:
            ax[0].plot(t, 1e3 * result["yg_m"][s], lw=0.6, alpha=0.6, label="ground y_g")
    else:
        ax[0].plot(t, 1e3 * result["u_m"][s], lw=0.8, label="u (superstructure relative to the lower plate)")
        if machine:     # the machine drives the lower plate; there is no ground
            ax[0].plot(t, 1e3 * result["xg_m"][s], "--", lw=0.8, label="lower plate (machine) x_p = -u")
        else:
            ax[0].plot(t, 1e3 * result["xg_m"][s], lw=0.6, alpha=0.6, label="ground x_g")
    ax[0].set_ylabel("displacement (mm)")
    ax[0].legend(loc="upper right", fontsize=8, ncols=2 if two_d else 1)
    ax[1].plot(t, 1e-3 * W12[s], label="friction work W1 + W2")
    ax[1].plot(t, 1e-3 * work[s], "--", label=wlabel)
    if "E_reseat_J" in result:
        ax[1].plot(t, 1e-3 * result["E_reseat_J"][s], label="re-seating loss")
    ax[1].set_ylabel("energy (kJ)")
    ax[1].set_xlabel("t (s)")
    ax[1].legend(loc="upper left")
    for a in ax:
        a.grid(alpha=0.3)
    head = f"{scene.name}: response and energy"
    if machine:     # the test's conditions: vertical load, amplitude, frequency, peak velocity
        import math
        from .cycles import vertical_load
        ld = scene["loading"]
        head += (f"\nW = {vertical_load(scene) / 1e6:.2f} MN, +-{1e3 * ld['amplitude_m']:g} mm at "
                 f"{ld['frequency_Hz']:g} Hz, peak v = {2 * math.pi * ld['frequency_Hz'] * ld['amplitude_m']:.3f} m/s")
    ax[0].set_title(head, fontsize=10)
    return fig


def temperature(result, scene):
    """The interfaces' temperature columns against time."""
    parts = sides(scene)
    t = result["t_s"]
    cols = [result[f"T{1 if side == 'lower' else 2}_C"] for side in parts]
    s = thin(len(t), *cols)
    fig, (ax,) = new_figure()
    styles = {"lower": dict(ls="-", lw=1.6, color="tab:red"),
              "upper": dict(ls="--", lw=1.2, color="tab:blue")}
    for side, T in zip(parts, cols):
        i = 1 if side == "lower" else 2
        ax.plot(t[s], T[s], label=f"T{i}, {side} plate: {plate_quantity(scene, side)}", **styles[side])
    if len(parts) == 2 and _same(cols[0], cols[1]):
        ax.text(0.99, 0.02, "the two curves coincide (same plates, near-equal loads)", ha="right",
                transform=ax.transAxes, fontsize=8, color="0.3")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(f"temperature ({DEG})")
    ax.set_title(f"{scene.name}: plate temperature")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def friction(result, scene):
    """The interfaces' friction coefficients against time."""
    parts = sides(scene)
    t = result["t_s"]
    s = thin(len(t), result["mu1"], *([result["mu2"]] if "upper" in parts else []))
    fig, (ax,) = new_figure()
    ax.plot(t[s], result["mu1"][s], lw=1.6, color="tab:red", label="lower interface mu1")
    if "upper" in parts:
        ax.plot(t[s], result["mu2"][s], "--", lw=1.2, color="tab:blue", label="upper interface mu2")
        if _same(result["mu1"], result["mu2"]):
            ax.text(0.99, 0.02, "the two curves coincide", ha="right", transform=ax.transAxes,
                    fontsize=8, color="0.3")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("friction coefficient")
    ax.set_title(f"{scene.name}: friction")
    ax.legend()
    ax.grid(alpha=0.3)
    return fig


# -- the triple friction pendulum: branches by regime, its four surfaces -----------------
# (each branch coloured by the regime it slides in, docs/model.md section 6; surfaces whose
# curves coincide, a symmetric TFP's S1 with S4 and S2 with S3, drawn dashed over solid and
# named in a note, so that no curve hides under another unsaid)

REGIME_STYLE = {0: ("stick", "0.6"), 1: ("I: S2+S3", "tab:blue"), 3: ("III: S1+S4", "tab:red"),
                5: ("V: S2+S3, outer rims", "tab:purple"), 6: ("I+III: all four", "tab:orange")}
SURFACE_COLOUR = ("tab:blue", "tab:orange", "tab:green", "tab:red")


def coinciding(curves, rel: float = 0.01) -> list[tuple[int, int]]:
    """Pairs (i, j), i < j, of curves (0-based) that would hide each other:
    apart by at most rel of their range everywhere (1 %: about two pixels of
    a plot's height, under a 1.8-point line)."""
    from .drawing import _same
    return [(i, j) for i in range(len(curves)) for j in range(i + 1, len(curves))
            if _same(curves[i], curves[j], rel)]


def _four(ax, t, curves, labels):
    """Four surfaces' curves; a curve equal to an earlier one is drawn dashed
    over it and its legend entry says which it coincides with."""
    same = dict((j, i) for i, j in reversed(coinciding(curves)))    # j -> the first i it equals
    for k, (y, label) in enumerate(zip(curves, labels)):
        dashed = k in same
        if dashed:
            label += f" (= S{same[k] + 1} within 1 %, dashed over it)"
        ax.plot(t, y, ls="--" if dashed else "-", lw=1.1 if dashed else 1.8, color=SURFACE_COLOUR[k],
                label=label, zorder=3 if dashed else 2)


def tfp_hysteresis(result, scene):
    from .drawing import new_figure, thin_xy
    u, F = 1e3 * result["u_m"], 1e-3 * result["F_N"]
    reg = np.nan_to_num(result["regime"]).astype(int)
    fig, (ax,) = new_figure()
    s = thin_xy(len(u), u, F)
    ax.plot(u[s], F[s], lw=0.4, color="0.8", zorder=1)
    for code, (label, colour) in REGIME_STYLE.items():
        sel = np.flatnonzero(reg == code)
        if len(sel):
            sel = sel[thin_xy(len(sel), u[sel], F[sel])]
            ax.plot(u[sel], F[sel], ".", ms=1.5, color=colour, label=f"regime {label}", zorder=2)
    ax.set_xlabel("relative displacement u (mm)")
    ax.set_ylabel("horizontal force F (kN)")
    ax.set_title(f"{scene.name}: hysteresis by regime")
    ax.legend(loc="upper left", fontsize=7, markerscale=5)
    ax.grid(alpha=0.3)
    return fig


def tfp_response(result, scene):
    from .drawing import new_figure, thin
    t = result["t_s"]
    cols = ([result["u_m"]] + [result[f"s{i}_m"] for i in range(1, 5)] + [result[f"W{i}_J"] for i in range(1, 5)]
            + [result["E_input_J"], result["E_rim_J"]] + ([result["E_reseat_J"]] if "E_reseat_J" in result else []))
    s = thin(len(t), *cols)
    t = t[s]
    fig, ax = new_figure(2, figsize=(7.0, 6.4), sharex=True)
    _four(ax[0], t, [1e3 * result[f"s{i}_m"][s] for i in range(1, 5)], [f"slide S{i}" for i in range(1, 5)])
    ax[0].plot(t, 1e3 * result["u_m"][s], lw=0.8, color="k", label="u", zorder=4)
    ax[0].set_ylabel("displacement (mm)")
    ax[0].legend(loc="upper right", fontsize=7)
    _four(ax[1], t, [1e-3 * result[f"W{i}_J"][s] for i in range(1, 5)],
          [f"friction work S{i}" for i in range(1, 5)])
    ax[1].plot(t, 1e-3 * result["E_input_J"][s], "--", color="k", lw=0.9, label="input work")
    ax[1].plot(t, 1e-3 * result["E_rim_J"][s], color="tab:purple", label="rim impact loss")
    if "E_reseat_J" in result:
        ax[1].plot(t, 1e-3 * result["E_reseat_J"][s], color="tab:brown", label="re-seating loss (two-phase)")
    ax[1].set_ylabel("energy (kJ)")
    ax[1].set_xlabel("t (s)")
    ax[1].legend(loc="upper left", fontsize=7)
    for a in ax:
        a.grid(alpha=0.3)
    ax[0].set_title(f"{scene.name}: response and energy")
    return fig


def tfp_temperature(result, scene):
    from .drawing import DEG, new_figure, thin
    t = result["t_s"]
    parts = list(scene.data["thermal"])
    curves = [result[f"T{i}_C"] for i in range(1, len(parts) + 1)]
    s = thin(len(t), *curves)
    fig, (ax,) = new_figure()
    _four(ax, t[s], [c[s] for c in curves],
          [f"S{i} into {part.replace('_', ' ')} ({scene.data['thermal'][part]['model']})"
           for i, part in enumerate(parts, start=1)])
    ax.set_xlabel("t (s)")
    ax.set_ylabel(f"surface temperature ({DEG})")
    ax.set_title(f"{scene.name}: temperature under each footprint")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return fig


def tfp_friction(result, scene):
    from .drawing import new_figure, thin
    t = result["t_s"]
    curves = [result[f"mu{i}"] for i in range(1, 5)]
    s = thin(len(t), *curves)
    fig, (ax,) = new_figure()
    _four(ax, t[s], [c[s] for c in curves], [f"S{i} mu{i}" for i in range(1, 5)])
    ax.set_xlabel("t (s)")
    ax.set_ylabel("friction coefficient")
    ax.set_title(f"{scene.name}: friction")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return fig


# -- a motion in both directions (model.md 8): the x and y loops, the orbits, the heat path --

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
    dev = scene["device"]
    t = result["t_s"]
    if "c4x_m" in result:
        # the TFP's four heated parts: the slider plates' footprints on S1 and S4, the pad's on S2 and S3
        rs, rp = 0.5 * dev["slider_diameter"], 0.5 * dev["pad_diameter"]
        panels = ((1, "lower", rs), (2, "lower slider", rp), (3, "upper slider", rp), (4, "upper", rs))
        fig, axes = new_figure(2, 2, figsize=(10.5, 9.6), left=0.8, right=0.45, wgap=1.25, hgap=0.9, top=0.7,
                               bottom=0.55)
    else:
        a = 0.5 * dev["pad_diameter"]
        panels = ((1, "lower", a), (2, "upper", a))
        fig, axes = new_figure(1, 2, figsize=(10.5, 5.0), left=0.8, right=0.45, wgap=1.25, top=0.7, bottom=0.55)
    for ax, (i, side, a) in zip(axes, panels):
        area = math.pi * a * a
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
                label="footprint at the end" if len(panels) == 4 else "pad footprint at the end")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x on the plate (mm)")
        ax.set_ylabel("y on the plate (mm)")
        ax.set_title(f"{side} plate: W{i} = {1e-3 * W[-1]:.3g} kJ")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
        fig.colorbar(sc, ax=ax, label="friction heat flux (MW/m2)", shrink=0.8)
    fig.suptitle(f"{title}: heat along the footprint path")
    return fig
