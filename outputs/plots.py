"""PNG plots of a run (matplotlib, imported only when plots are asked for)."""
from __future__ import annotations

from pathlib import Path


def _same(a, b, rel: float = 0.003) -> bool:
    """Would two curves hide each other (within rel of their range)?"""
    import numpy as np
    span = max(float(np.ptp(a)), float(np.ptp(b)), 1e-12 * max(1.0, float(np.max(np.abs(a)))))
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) <= rel * span


def _fig(nrows=1):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(nrows, 1, figsize=(7, 3.2 * nrows), squeeze=False)
    return plt, fig, ax[:, 0]


DEG = "\N{DEGREE SIGN}C"     # the one spelling of the unit in every figure


def plate_quantity(scene, side: str) -> str:
    """What a plate model's temperature column (T1_C / T2_C) is, in words."""
    from .hottest import quantity_of
    t = scene.thermal(side)
    return quantity_of(t["model"], t.get("source", "follow-pad"), t.get("radius_m", 0.0))


def sides(scene) -> tuple[str, ...]:
    """The sliding interfaces of the device: an SFP has only the lower one
    (its articulation carries no friction and heats nothing)."""
    return ("lower",) if scene["device"]["kind"] == "SFP" else ("lower", "upper")


def make_plots(folder: Path, result, scene) -> list[str]:
    made = []
    title = scene.name
    machine = scene["loading"]["kind"] == "displacement"
    parts = sides(scene)
    if "u_m" in result:
        plt, fig, (ax,) = _fig()
        ax.plot(1e3 * result["u_m"], 1e-3 * result["F_N"], lw=0.8)
        ax.set_xlabel("relative displacement u (mm)")
        ax.set_ylabel("horizontal force F (kN)")
        ax.set_title(f"{title}: hysteresis")
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(folder / "hysteresis.png", dpi=110)
        plt.close(fig)
        made.append("hysteresis.png")

        plt, fig, ax = _fig(2)
        t = result["t_s"]
        ax[0].plot(t, 1e3 * result["u_m"], lw=0.8, label="u (superstructure relative to the lower plate)")
        if machine:     # the machine drives the lower plate; there is no ground
            ax[0].plot(t, 1e3 * result["xg_m"], "--", lw=0.8, label="lower plate (machine) x_p = -u")
        else:
            ax[0].plot(t, 1e3 * result["xg_m"], lw=0.6, alpha=0.6, label="ground x_g")
        ax[0].set_ylabel("displacement (mm)")
        ax[0].legend(loc="upper right", fontsize=8)
        ax[1].plot(t, 1e-3 * (result["W1_J"] + result["W2_J"]), label="friction work W1 + W2")
        if machine:
            # the machine's work through the bearing, the running loop area: the
            # E_input_J column is the ledger in the lower plate's frame, where the
            # programme's launch at u'(0) = 2 pi f A is kinetic energy put in before t = 0
            import numpy as np
            u, F = result["u_m"], result["F_N"]
            Wm = np.concatenate(([0.0], np.cumsum(0.5 * (F[1:] + F[:-1]) * np.diff(u))))
            ax[1].plot(t, 1e-3 * Wm, "--", label="machine work, integral of F du")
        else:
            ax[1].plot(t, 1e-3 * result["E_input_J"], "--", label="input work")
        if "E_reseat_J" in result:
            ax[1].plot(t, 1e-3 * result["E_reseat_J"], label="re-seating loss")
        ax[1].set_ylabel("energy (kJ)")
        ax[1].set_xlabel("t (s)")
        ax[1].legend(loc="upper left")
        for a in ax:
            a.grid(alpha=0.3)
        head = f"{title}: response and energy"
        if machine:     # the test's conditions: vertical load, amplitude, frequency, peak velocity
            import math
            from .cycles import vertical_load
            ld = scene["loading"]
            head += (f"\nW = {vertical_load(scene) / 1e6:.2f} MN, +-{1e3 * ld['amplitude_m']:g} mm at "
                     f"{ld['frequency_Hz']:g} Hz, peak v = {2 * math.pi * ld['frequency_Hz'] * ld['amplitude_m']:.3f} m/s")
        ax[0].set_title(head, fontsize=10)
        fig.tight_layout()
        fig.savefig(folder / "response.png", dpi=110)
        plt.close(fig)
        made.append("response.png")
    if "uy_m" in result:                  # bidirectional runs (model.md 8)
        from .plots_bidirectional import make_bidirectional_plots
        made += make_bidirectional_plots(folder, result, scene)
    if "T1_C" in result:
        plt, fig, (ax,) = _fig()
        t = result["t_s"]
        styles = {"lower": dict(ls="-", lw=1.6, color="tab:red"),
                  "upper": dict(ls="--", lw=1.2, color="tab:blue")}
        for side in parts:
            i = 1 if side == "lower" else 2
            ax.plot(t, result[f"T{i}_C"], label=f"T{i}, {side} plate: {plate_quantity(scene, side)}",
                    **styles[side])
        if len(parts) == 2 and _same(result["T1_C"], result["T2_C"]):
            ax.text(0.99, 0.02, "the two curves coincide (same plates, near-equal loads)", ha="right",
                    transform=ax.transAxes, fontsize=8, color="0.3")
        ax.set_xlabel("t (s)")
        ax.set_ylabel(f"temperature ({DEG})")
        ax.set_title(f"{title}: plate temperature")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(folder / "temperature.png", dpi=110)
        plt.close(fig)
        made.append("temperature.png")
    if "mu1" in result:
        plt, fig, (ax,) = _fig()
        t = result["t_s"]
        ax.plot(t, result["mu1"], lw=1.6, color="tab:red", label="lower interface mu1")
        if "upper" in parts:
            ax.plot(t, result["mu2"], "--", lw=1.2, color="tab:blue", label="upper interface mu2")
            if _same(result["mu1"], result["mu2"]):
                ax.text(0.99, 0.02, "the two curves coincide", ha="right", transform=ax.transAxes,
                        fontsize=8, color="0.3")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("friction coefficient")
        ax.set_title(f"{title}: friction")
        ax.legend()
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(folder / "friction.png", dpi=110)
        plt.close(fig)
        made.append("friction.png")
    return made
