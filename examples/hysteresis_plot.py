"""The force-displacement loop of the bearing-test machine scene (lab-sine),
one colour per cycle: the loop narrows as the sliding surface heats.

    python examples/hysteresis_plot.py [OUT.png]
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fpd  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "hysteresis.png"
r = fpd.run("lab-sine", solver={"dt": 2e-3})
h = r.history
period = 1.0 / r.scene["loading"]["frequency_Hz"]
cycle = np.minimum((h["t_s"] / period).astype(int), int(r.scene["loading"]["cycles"]) - 1)
fig, ax = plt.subplots(figsize=(6, 4.5))
for c in np.unique(cycle):
    sel = cycle == c
    ax.plot(1e3 * h["u_m"][sel], 1e-3 * h["F_N"][sel], lw=1, label=f"cycle {c + 1}")
ax.set_xlabel("u (mm)")
ax.set_ylabel("F (kN)")
ax.set_title(f"{r.scene.name}: force against displacement")
ax.legend()
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(out, dpi=110)
print(f"peak F {1e-3 * r.summary['peak_F_N']:.0f} kN, peak T1 {r.summary['peak_T1_C']:.1f} C; wrote {out}")
