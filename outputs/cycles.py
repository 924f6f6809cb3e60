"""Bearing-test quantities per cycle of a test-machine run (docs/test_machine.md).

A prototype or production test of a sliding isolator is judged cycle by
cycle on the loop of horizontal force F against displacement d (EN 15129,
AASHTO Guide Specifications for Seismic Isolation Design). For each cycle k
of the imposed sine (t in [t0 + k T, t0 + (k+1) T], T = 1 / frequency, t0
the programme's start: loading.hold_s, 0 without a hold):

- ``EDC_J``: energy dissipated per cycle, the loop area, the closed integral
  of F du (trapezoidal over the recorded rows);
- ``d_pos_m``, ``d_neg_m``: the largest and smallest displacement of the
  cycle, ``F_pos_N``, ``F_neg_N``: the force at those rows;
- ``K_eff_N_m`` = (F+ - F-) / (d+ - d-): the effective (secant) stiffness,
  the AASHTO form (|F+| + |F-|) / (|d+| + |d-|) when the signs alternate;
- ``d_max_m`` = (d+ - d-) / 2: the cycle's displacement amplitude;
- ``N_mean_N``: the cycle's mean axial load, the time mean of the machine's
  axial-load programme N(t) over the cycle (loading/axial.py; W = M g when
  the load is held constant);
- ``mu_eff`` = EDC / (4 N_mean d_max): the friction coefficient of the
  rigid-plastic loop of the same area under the vertical load N_mean (a loop of
  height mu W and half-width d_max has area 4 mu W d_max);
- ``Q_d_N`` = EDC / (4 d_max): the characteristic strength of the bilinear
  loop of the same area with zero yield displacement (AASHTO:
  EDC = 4 Q_d (d_max - d_y); a slider has d_y ~ 0), = mu_eff W;
- ``xi_eff`` = EDC / (2 pi K_eff d_max^2): the effective damping ratio;
- ``v_peak_mps``: the largest |relative velocity| of the cycle;
- each with its change against the first cycle (``*_change_rel`` =
  x_k / x_1 - 1);
- ``T<i>_peak_C``, ``T<i>_mean_C``: per sliding interface i (the run's
  T1_C, T2_C, ... columns: what each plate model calls its surface
  temperature), the largest and the mean recorded value over the cycle's
  rows: how far each cycle heats the surfaces, beside the loop quantities
  that the heating changes.

An orbit of the bidirectional test machine (circle, figure-eight, a sine
in a direction) is measured in the plane: ``EDC_J`` is the closed integral
of F . du = F_x du_x + F_y du_y; ``d_pos_m`` is the largest |u| of the cycle
and ``F_pos_N`` the |F| there (``d_neg_m``, ``F_neg_N`` their opposites, so
K_eff = |F| / |u| at the orbit's widest point); ``mu_eff`` and ``Q_d_N``
divide EDC by the path slid in the cycle, sum of |du| (a sine's path is
4 d_max: the formulas above), W times it and itself.

``CycleMeter`` takes the rows block by block (the streamed history of ``fpd
run`` hands it every block it writes), so the numbers are those of every
recorded row whatever the length of the run, and equal those computed from
the written timeseries.csv (the rows are the same floats; the CSV keeps 10
significant digits).
"""
from __future__ import annotations

import csv
import math

import numpy as np

KEYS = ("EDC_J", "K_eff_N_m", "mu_eff", "Q_d_N", "xi_eff")
CSV_COLUMNS = ("cycle", "t_start_s", "t_end_s", "d_pos_m", "d_neg_m", "F_pos_N", "F_neg_N", "d_max_m",
               "v_peak_mps", "N_mean_N", "EDC_J", "K_eff_N_m", "mu_eff", "Q_d_N", "xi_eff",
               "EDC_change_rel", "K_eff_change_rel", "mu_eff_change_rel", "Q_d_change_rel",
               "xi_eff_change_rel")


class CycleMeter:
    """Per-cycle loop integrals over rows given in blocks (canonical columns).

    period_s, cycles: the programme's cycles (cycle k covers [k T, (k+1) T]);
    vertical_load_N: W of mu_eff; axial: the axial-load programme
    (loading.axial.AxialProgramme) when it varies, its time mean over each
    cycle the cycle's N_mean (and mu_eff's load). A segment between two consecutive rows
    belongs to the cycle of its mid-time (so a row on a cycle boundary closes
    one cycle and opens the next); a row to the cycle of its time."""

    def __init__(self, columns, period_s: float, cycles: int, vertical_load_N: float, axial=None,
                 t0_s: float = 0.0):
        cols = list(columns)
        self.jt, self.ju, self.jF = cols.index("t_s"), cols.index("u_m"), cols.index("F_N")
        # an orbit in the plane (the bidirectional machine): F . du, |u| and the path slid
        self.plane = all(c in cols for c in ("ux_m", "uy_m", "Fx_N", "Fy_N"))
        if self.plane:
            self.jxy = [cols.index(c) for c in ("ux_m", "uy_m", "Fx_N", "Fy_N")]
        self.jv = cols.index("v_mps") if "v_mps" in cols else None
        # the interfaces' temperature columns (T1_C ... T4_C, those the run has)
        self.temps = [(i, cols.index(f"T{i}_C")) for i in range(1, 5) if f"T{i}_C" in cols]
        self.T, self.n, self.W = float(period_s), int(cycles), float(vertical_load_N)
        self.t0 = float(t0_s)                            # the programme's start (after a hold)
        self.edc = np.zeros(self.n)
        self.dpos = np.full(self.n, -np.inf)
        self.dneg = np.full(self.n, np.inf)
        self.Fpos = np.full(self.n, np.nan)
        self.Fneg = np.full(self.n, np.nan)
        self.vpk = np.zeros(self.n)
        self.Tpk = np.full((self.n, len(self.temps)), -np.inf)
        self.Tsum = np.zeros((self.n, len(self.temps)))
        self.rows = np.zeros(self.n, dtype=int)
        self.path = np.zeros(self.n)
        self.axial = axial if axial is not None and axial.varying else None
        self.Nt = np.zeros(self.n)                       # integral of N dt over the cycle's segments
        self.dur = np.zeros(self.n)                      # and their length
        self.seen = np.zeros(self.n, dtype=bool)
        self.closed = np.zeros(self.n, dtype=bool)     # a row at or past the cycle's end was seen
        self.prev = None                                 # the last row of the previous block

    def _cycle(self, t: np.ndarray) -> np.ndarray:
        """Cycle index of times t (-1 outside the programme)."""
        k = np.floor((t - self.t0) / self.T * (1.0 + 1e-12)).astype(int)
        return np.where((t < self.t0) | (k >= self.n), -1, k)

    def add(self, block: np.ndarray) -> None:
        if not len(block):
            return
        rows = block if self.prev is None else np.vstack((self.prev[None, :], block))
        t, u, F = rows[:, self.jt], rows[:, self.ju], rows[:, self.jF]
        if len(rows) > 1:
            seg = self._cycle(0.5 * (t[1:] + t[:-1]))
            if self.plane:
                ux, uy, Fx, Fy = (rows[:, j] for j in self.jxy)
                dx, dy = np.diff(ux), np.diff(uy)
                area = 0.5 * (Fx[1:] + Fx[:-1]) * dx + 0.5 * (Fy[1:] + Fy[:-1]) * dy
                step = np.hypot(dx, dy)
            else:
                area = 0.5 * (F[1:] + F[:-1]) * np.diff(u)
                step = np.abs(np.diff(u))
            ok = seg >= 0
            np.add.at(self.edc, seg[ok], area[ok])
            np.add.at(self.path, seg[ok], step[ok])
            if self.axial is not None:
                N, dt = self.axial.at(t), np.diff(t)
                np.add.at(self.Nt, seg[ok], (0.5 * (N[1:] + N[:-1]) * dt)[ok])
                np.add.at(self.dur, seg[ok], dt[ok])
        new = block
        kt = self._cycle(new[:, self.jt])
        ends = np.floor((new[:, self.jt] - self.t0) / self.T * (1.0 + 1e-12)).astype(int)   # cycles whose end was reached
        for k in range(self.n):
            if np.any(ends > k):
                self.closed[k] = True
            sel = kt == k
            if not sel.any():
                continue
            self.seen[k] = True
            uu = new[sel, self.ju]
            i, j = int(np.argmax(uu)), int(np.argmin(uu))
            if uu[i] > self.dpos[k]:
                self.dpos[k], self.Fpos[k] = uu[i], new[sel, self.jF][i]
                if self.plane:                # the orbit: its widest point, both ways
                    self.dneg[k], self.Fneg[k] = -uu[i], -new[sel, self.jF][i]
            if not self.plane and uu[j] < self.dneg[k]:
                self.dneg[k], self.Fneg[k] = uu[j], new[sel, self.jF][j]
            if self.jv is not None:
                self.vpk[k] = max(self.vpk[k], float(np.max(np.abs(new[sel, self.jv]))))
            if self.temps:
                T = new[sel][:, [j for _, j in self.temps]]
                self.Tpk[k] = np.maximum(self.Tpk[k], T.max(axis=0))
                self.Tsum[k] += T.sum(axis=0)
            self.rows[k] += int(sel.sum())
        self.prev = block[-1].copy()

    def cycles(self) -> list[dict]:
        """One dict per complete cycle (the keys of CSV_COLUMNS)."""
        out = []
        for k in range(self.n):
            if not (self.seen[k] and self.closed[k]):
                break                      # an interrupted run: its complete cycles only
            dmax = 0.5 * (self.dpos[k] - self.dneg[k])
            K = (self.Fpos[k] - self.Fneg[k]) / (self.dpos[k] - self.dneg[k]) if dmax > 0 else math.nan
            edc = float(self.edc[k])
            # the path slid: 4 d_max for a sine (the loop formulas), sum |du| for an orbit
            slid = float(self.path[k]) if self.plane else 4.0 * dmax
            W = float(self.Nt[k] / self.dur[k]) if self.axial is not None and self.dur[k] > 0 else self.W
            c = {"cycle": k + 1, "t_start_s": self.t0 + k * self.T, "t_end_s": self.t0 + (k + 1) * self.T,
                 "d_pos_m": float(self.dpos[k]), "d_neg_m": float(self.dneg[k]),
                 "F_pos_N": float(self.Fpos[k]), "F_neg_N": float(self.Fneg[k]), "d_max_m": float(dmax),
                 "v_peak_mps": float(self.vpk[k]) if self.jv is not None else math.nan,
                 "N_mean_N": W, "EDC_J": edc, "K_eff_N_m": float(K),
                 "mu_eff": edc / (W * slid) if slid > 0 and W > 0 else math.nan,
                 "Q_d_N": edc / slid if slid > 0 else math.nan,
                 "xi_eff": edc / (2.0 * math.pi * K * dmax * dmax) if dmax > 0 and K > 0 else math.nan}
            for m, (i, _) in enumerate(self.temps):
                c[f"T{i}_peak_C"] = float(self.Tpk[k, m])
                c[f"T{i}_mean_C"] = float(self.Tsum[k, m] / self.rows[k])
            out.append(c)
        for c in out:
            for key in KEYS:
                first = out[0][key]
                name = ("Q_d" if key == "Q_d_N" else "K_eff" if key == "K_eff_N_m"
                        else key.removesuffix("_J")) + "_change_rel"
                c[name] = c[key] / first - 1.0 if first and math.isfinite(first) else math.nan
        return out


def vertical_load(scene) -> float:
    """W: the superstructure's weight, the test's vertical load (N)."""
    from fpd.mechanics.geometry import G_ACC
    return scene["superstructure"]["mass"] * G_ACC


def meter_for(scene, columns) -> CycleMeter | None:
    """The meter of a test-machine scene (loading.kind = "displacement"), else None."""
    ld = scene["loading"]
    if ld["kind"] != "displacement" or "F_N" not in columns or "u_m" not in columns:
        return None
    return CycleMeter(columns, 1.0 / ld["frequency_Hz"], int(math.ceil(ld["cycles"] - 1e-9)), vertical_load(scene),
                      axial_of(scene), hold_of(scene))


def hold_of(scene) -> float:
    """The programme's start: loading.hold_s rounded to whole steps (0 without a hold)."""
    dt = scene["solver"]["dt"]
    return round(scene["loading"].get("hold_s", 0.0) / dt) * dt


def axial_of(scene):
    """The planar machine's axial-load programme when it varies (loading/axial.py), else None."""
    ld = scene["loading"]
    if ld.get("vertical") not in ("sine", "series"):
        return None
    from fpd.loading.axial import programme_of
    return programme_of(ld, vertical_load(scene))


def summary_block(meter: CycleMeter, scene) -> dict:
    """summary.json's ``test_machine``: the test's vertical load and programme,
    and the per-cycle list."""
    ld = scene["loading"]
    cyc = meter.cycles()
    A, f = ld["amplitude_m"], ld["frequency_Hz"]
    return {
        "definitions": "EDC = loop area (closed integral of F du); K_eff = (F+ - F-)/(d+ - d-); "
                       "d_max = (d+ - d-)/2; N_mean = the cycle's mean axial load; "
                       "mu_eff = EDC/(4 N_mean d_max); Q_d = EDC/(4 d_max); "
                       "xi_eff = EDC/(2 pi K_eff d_max^2); *_change_rel = value / first cycle's - 1 "
                       "(docs/test_machine.md)",
        "vertical_load_N": vertical_load(scene),
        "axial_programme": _axial_block(ld, vertical_load(scene)),
        "amplitude_m": A, "frequency_Hz": f, "programme_peak_velocity_mps": 2.0 * math.pi * f * A,
        "peak_velocity_mps": max((c["v_peak_mps"] for c in cyc), default=math.nan),
        "machine_work_J": float(meter.edc.sum()),
        "cycles": cyc,
    }


def _axial_block(ld: dict, W: float) -> dict:
    """summary.json's test_machine.axial_programme: the axial load's programme."""
    kind = ld.get("vertical", "constant")
    out = {"kind": kind}
    if kind == "sine":
        from fpd.loading.axial import amplitude_of
        out.update(mean_N=W, amplitude_N=amplitude_of(ld, W), frequency_Hz=ld["vertical_frequency_Hz"],
                   phase_deg=ld.get("vertical_phase_deg") or 0.0)
    elif kind == "series":
        out["file"] = ld["path_vertical"]
    return out


# the per-interface temperature columns a cycle may have (those of the run's T<i>_C)
TEMP_COLUMNS = tuple(f"T{i}_{what}_C" for i in range(1, 5) for what in ("peak", "mean"))


def columns_of(cycles: list[dict]) -> tuple[str, ...]:
    """cycles.csv's columns: CSV_COLUMNS, then the temperature columns present."""
    return CSV_COLUMNS + tuple(k for k in TEMP_COLUMNS if cycles and k in cycles[0])


def doc_table(cycles: list[dict]) -> str:
    """The per-cycle table of docs/test_machine.md (a test checks the page
    against a run of lab-sine)."""
    lines = ["| cycle | EDC (kJ) | K_eff (kN/m) | mu_eff | change of EDC | peak T1 (\N{DEGREE SIGN}C) |",
             "|---|---|---|---|---|---|"]
    for c in cycles:
        lines.append(f"| {c['cycle']} | {c['EDC_J'] / 1e3:.1f} | {c['K_eff_N_m'] / 1e3:.0f} | {c['mu_eff']:.4f} | "
                     f"{100 * c['EDC_change_rel']:+.1f} % | {c.get('T1_peak_C', math.nan):.1f} |")
    return "\n".join(lines)


def write_cycles_csv(path, cycles: list[dict]) -> None:
    cols = columns_of(cycles)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(cols)
        for c in cycles:
            w.writerow([c["cycle"]] + [repr(float(c[k])) for k in cols[1:]])


def cycles_figure(cycles: list[dict], title: str):
    """EDC, K_eff, mu_eff (and Q_d on mu_eff's axis, as mu_eff W) per cycle,
    and each interface's peak and mean surface temperature per cycle."""
    from .drawing import DEG, new_figure

    k = [c["cycle"] for c in cycles]
    temps = sorted({int(key[1]) for key in (cycles[0] if cycles else {}) if key.endswith("_peak_C")})
    n = 4 if temps else 3
    fig, ax = new_figure(n, figsize=(7.0, 2.3 * n + 0.5), left=0.9, right=0.9, top=0.35, bottom=0.5,
                         hgap=0.15, sharex=True)
    panels = (("EDC_J", 1e-3, "EDC (kJ)", "EDC_change_rel"),
              ("K_eff_N_m", 1e-3, "K_eff (kN/m)", "K_eff_change_rel"),
              ("mu_eff", 1.0, "mu_eff = EDC / (4 N_mean d_max)", "mu_eff_change_rel"))
    for a, (key, s, label, ch) in zip(ax, panels):
        y = [s * c[key] for c in cycles]
        a.plot(k, y, "o-", color="tab:blue")
        for kk, yy, c in zip(k, y, cycles):
            if kk > 1:
                a.annotate(f"{100 * c[ch]:+.1f} %", (kk, yy), textcoords="offset points", xytext=(6, 6),
                           fontsize=8)
        a.set_ylabel(label)
        a.grid(alpha=0.3)
    if cycles:
        W = cycles[0]["Q_d_N"] / cycles[0]["mu_eff"] if cycles[0]["mu_eff"] else None
        if W:
            sec = ax[2].secondary_yaxis("right", functions=(lambda m: m * W * 1e-3, lambda q: q / (W * 1e-3)))
            sec.set_ylabel("Q_d = EDC / (4 d_max) (kN)")
    if temps:
        a = ax[3]
        styles = ("-", "--", "-.", ":")
        for m, i in enumerate(temps):
            peak = [c[f"T{i}_peak_C"] for c in cycles]
            mean = [c[f"T{i}_mean_C"] for c in cycles]
            a.plot(k, peak, "o" + styles[m % 4], color="tab:red", ms=5 - m, label=f"T{i} peak")
            a.plot(k, mean, "s" + styles[m % 4], color="tab:blue", ms=5 - m, label=f"T{i} mean")
        same = [i for i in temps[1:] if all(abs(c[f"T{i}_peak_C"] - c[f"T{temps[0]}_peak_C"]) <= 0.003 * max(
            1.0, abs(c[f"T{temps[0]}_peak_C"])) for c in cycles)]
        if same:
            a.text(0.99, 0.04, "T" + ", T".join(map(str, [temps[0], *same])) + " coincide",
                   ha="right", transform=a.transAxes, fontsize=8, color="0.3")
        a.set_ylabel(f"surface T per cycle ({DEG})")
        a.legend(fontsize=7, ncols=len(temps), loc="upper left")
        a.grid(alpha=0.3)
    ax[-1].set_xlabel("cycle (change against cycle 1 marked)")
    ax[-1].set_xticks(k)
    if k:
        ax[-1].set_xlim(k[0] - 0.3, k[-1] + 0.3)      # room for the last cycle's mark (shared by every panel)
    ax[0].set_title(f"{title}: per-cycle test quantities")
    return fig


def plot_cycles(path, cycles: list[dict], title: str) -> None:
    """plots/cycles.png (cycles_figure)."""
    from .drawing import save
    save(cycles_figure(cycles, title), path)
