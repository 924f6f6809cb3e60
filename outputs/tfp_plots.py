"""Plots of a TFP run: the hysteresis loop with each branch coloured by the
regime it slides in (docs/model.md section 6), temperatures and friction of
the four surfaces, response and energy. Surfaces whose curves coincide (a
symmetric TFP: S1 with S4, S2 with S3) are drawn dashed over solid and named
in a note, so that no curve hides under another unsaid."""
from __future__ import annotations

import numpy as np

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


def hysteresis(result, scene):
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


def response(result, scene):
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


def temperature(result, scene):
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


def friction(result, scene):
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
