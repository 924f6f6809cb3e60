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
    k = np.ceil(np.asarray(t) * ld["frequency_Hz"] * (1.0 - 1e-12)).astype(int)
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
