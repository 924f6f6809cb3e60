"""Plots of a TFP run: the hysteresis loop with each branch coloured by the
regime it slides in (docs/model.md section 6), temperatures and friction of
the four surfaces, response and energy."""
from __future__ import annotations

from pathlib import Path

import numpy as np

REGIME_STYLE = {0: ("stick", "0.6"), 1: ("I: S2+S3", "tab:blue"), 3: ("III: S1+S4", "tab:red"),
                5: ("V: S2+S3, outer rims", "tab:purple"), 6: ("I+III: all four", "tab:orange")}


def make_tfp_plots(folder: Path, result, scene) -> list[str]:
    from .plots import _fig

    made = []
    title = scene.name
    u, F, t = 1e3 * result["u_m"], 1e-3 * result["F_N"], result["t_s"]
    reg = np.nan_to_num(result["regime"]).astype(int)
    plt, fig, (ax,) = _fig()
    ax.plot(u, F, lw=0.4, color="0.8", zorder=1)
    for code, (label, colour) in REGIME_STYLE.items():
        sel = reg == code
        if sel.any():
            ax.plot(u[sel], F[sel], ".", ms=1.5, color=colour, label=f"regime {label}", zorder=2)
    ax.set_xlabel("relative displacement u (mm)")
    ax.set_ylabel("horizontal force F (kN)")
    ax.set_title(f"{title}: hysteresis by regime")
    ax.legend(loc="upper left", fontsize=7, markerscale=5)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(folder / "hysteresis.png", dpi=110)
    plt.close(fig)
    made.append("hysteresis.png")

    plt, fig, ax = _fig(2)
    ax[0].plot(t, u, lw=0.8, label="u")
    for i in range(1, 5):
        ax[0].plot(t, 1e3 * result[f"s{i}_m"], lw=0.6, label=f"slide S{i}")
    ax[0].set_ylabel("displacement (mm)")
    ax[0].legend(loc="upper right", fontsize=7)
    for i in range(1, 5):
        ax[1].plot(t, 1e-3 * result[f"W{i}_J"], label=f"friction work S{i}")
    ax[1].plot(t, 1e-3 * result["E_input_J"], "--", label="input work")
    ax[1].plot(t, 1e-3 * result["E_rim_J"], label="rim impact loss")
    if "E_reseat_J" in result:
        ax[1].plot(t, 1e-3 * result["E_reseat_J"], label="re-seating loss (two-phase)")
    ax[1].set_ylabel("energy (kJ)")
    ax[1].set_xlabel("t (s)")
    ax[1].legend(loc="upper left", fontsize=7)
    for a in ax:
        a.grid(alpha=0.3)
    ax[0].set_title(f"{title}: response and energy")
    fig.tight_layout()
    fig.savefig(folder / "response.png", dpi=110)
    plt.close(fig)
    made.append("response.png")
    parts = list(scene.data["thermal"])
    if "T1_C" in result:
        plt, fig, (ax,) = _fig()
        for i, part in enumerate(parts, start=1):
            ax.plot(t, result[f"T{i}_C"], label=f"S{i} into {part.replace('_', ' ')} ({scene.data['thermal'][part]['model']})")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("surface temperature under the footprint (C)")
        ax.set_title(f"{title}: temperature")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(folder / "temperature.png", dpi=110)
        plt.close(fig)
        made.append("temperature.png")
    plt, fig, (ax,) = _fig()
    for i in range(1, 5):
        ax.plot(t, result[f"mu{i}"], label=f"S{i} mu{i}")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("friction coefficient")
    ax.set_title(f"{title}: friction")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(folder / "friction.png", dpi=110)
    plt.close(fig)
    made.append("friction.png")
    return made
