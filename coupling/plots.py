"""PNG plots of a run (matplotlib, imported only when plots are asked for)."""
from __future__ import annotations

from pathlib import Path


def _fig(nrows=1):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(nrows, 1, figsize=(7, 3.2 * nrows), squeeze=False)
    return plt, fig, ax[:, 0]


def make_plots(folder: Path, result, scene) -> list[str]:
    if "W4_J" in result:                     # the TFP: four surfaces, regimes
        from .tfp_plots import make_tfp_plots
        return make_tfp_plots(folder, result, scene)
    made = []
    title = scene.name
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
        ax[0].plot(t, 1e3 * result["u_m"], lw=0.8, label="u")
        ax[0].plot(t, 1e3 * result["xg_m"], lw=0.6, alpha=0.6, label="ground x_g")
        ax[0].set_ylabel("displacement (mm)")
        ax[0].legend(loc="upper right")
        ax[1].plot(t, 1e-3 * (result["W1_J"] + result["W2_J"]), label="friction work")
        ax[1].plot(t, 1e-3 * result["E_input_J"], "--", label="input work")
        if "E_reseat_J" in result:
            ax[1].plot(t, 1e-3 * result["E_reseat_J"], label="re-seating loss")
        ax[1].set_ylabel("energy (kJ)")
        ax[1].set_xlabel("t (s)")
        ax[1].legend(loc="upper left")
        for a in ax:
            a.grid(alpha=0.3)
        ax[0].set_title(f"{title}: response and energy")
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
        m = scene.data["thermal"]
        ax.plot(t, result["T1_C"], label=f"lower plate ({m['lower']['model']})")
        ax.plot(t, result["T2_C"], label=f"upper plate ({m['upper']['model']})")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("surface temperature under the pad (C)")
        ax.set_title(f"{title}: temperature")
        ax.legend()
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(folder / "temperature.png", dpi=110)
        plt.close(fig)
        made.append("temperature.png")
    if "mu1" in result:
        plt, fig, (ax,) = _fig()
        t = result["t_s"]
        ax.plot(t, result["mu1"], label="lower interface mu1")
        ax.plot(t, result["mu2"], "--", label="upper interface mu2")
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
