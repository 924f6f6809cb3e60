"""``fpd stability``: the packaged catalogue of stiff and extreme scenes.

Every scene of ``scenes/stability/*.toml`` runs at a coarse dt (the scene's
``solver.dt``) and a fine dt (coarse / 4; ``--fast``: coarse / 2 and
durations capped at FAST_DURATION s, except where the length is the case).
A case passes when, at both dt:

- every recorded value is finite and the run finished (status ok; an
  iterated coupling that does not converge is a failed run);
- the ledgers close: mechanical |E_input - (E_kin + E_pot + W + E_reseat)|
  relative to the input (or friction) work <= MECH_TOL (the steppers are first
  order, not round-off), and per plate heat_in = stored + lost and friction
  heat = heat delivered to <= HEAT_TOL (round-off);
- each plate's temperatures stay within [coolest boundary or initial
  temperature, its own upper bound] (``plate_bound``: a lumped plate's heat /
  c M; an FE plate's surface rise under the run's peak friction heat flux on
  its whole face all run long, the slab solution); the final through-thickness
  field too, where a model has one;

and the coarse and fine runs tell the same story: peak displacement, friction
work and peak temperature rise agree within STORY_RTOL (relative) or the
absolute floors STORY_ATOL, and both runs slide, or both stay stuck.
"""
from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np

from fpd.schema import scene as scn
from fpd.outputs.output import ResultsFolder
from .study_runner import (EXIT_FAILED, EXIT_OK, _plt, _say, fmt, md_table, min_heat_capacity, out_dir, run_case,
                           write_rows)

CATALOGUE = scn.SCENES_DIR / "stability"
MECH_TOL = 2e-2
HEAT_TOL = 1e-9
STORY_RTOL = 0.15
UNDERSHOOT_REL = 1e-4      # of the temperature rise (see check_run)
STORY_ATOL = {"peak_u_m": 2e-3, "friction_work_J": 50.0, "rise_K": 1.0}
FAST_DURATION = 12.0
KEEP_LENGTH = ("long-record",)     # the length is what these cases test


def catalogue() -> list[Path]:
    return sorted(CATALOGUE.glob("*.toml"))


def _fast_overrides(path: Path) -> list[str]:
    if path.stem in KEEP_LENGTH:
        return []
    sc = scn.load(str(path))
    length = sc["solver"].get("duration") or scn.loading_length(sc["loading"])
    if length is None or length > FAST_DURATION:
        return [f"solver.duration={FAST_DURATION!r}"]
    return []


def slab_surface_rise(q: float, t: float, h: float, k: float, rho_c: float) -> float:
    """Surface temperature rise (K) of a slab of thickness h, insulated at the
    back, under a uniform flux q (W/m2) over its face for a time t: the
    halfspace's 2 q sqrt(kappa t / pi) / k with its images at depths 2 n h
    (Carslaw and Jaeger 2.9): (2 q sqrt(kappa t) / k) (ierfc 0 + 2 sum ierfc(n h / sqrt(kappa t)))."""
    from scipy.special import erfc
    if q <= 0 or t <= 0:
        return 0.0
    kappa = k / rho_c
    s = math.sqrt(kappa * t)

    def ierfc(x):
        return math.exp(-x * x) / math.sqrt(math.pi) - x * float(erfc(x))
    total, n = ierfc(0.0), 1
    while True:
        term = 2.0 * ierfc(n * h / s)
        total += term
        if term < 1e-15 * total or n > 100000:
            break
        n += 1
    return 2.0 * q * s / k * total


def plate_bound(params, plate, t, W, T_start: float) -> float:
    """The hottest a plate may get (degC) with the heat it received.

    - lumped: T_start + its friction heat (share of W) / its heat capacity c M;
    - FE models: T_start + the surface rise of the slab of the plate's
      thickness, insulated at the back, under the run's peak friction heat
      flux q_max = max (share dW/dt) / (pi a^2) over its whole face for the
      whole run (slab_surface_rise). The plate receives at most q_max, on the
      footprint only and part of the time, loses heat to the air and the
      sides, and the heat equation keeps a larger input's temperatures
      larger: a bound a sound model stays under, some tens of percent above
      the peak it reaches (all the heat in the smallest nodal capacity
      would allow 10^5 K)."""
    t = np.asarray(t, float)
    W = np.asarray(W, float)
    share = params.heat_share
    if params.model == "lumped":
        C = min_heat_capacity(plate)
        return T_start + share * float(np.nanmax(W)) / C if C > 0 else math.inf
    dt = np.diff(t)
    ok = dt > 0
    if not ok.any():
        return T_start
    q = share * np.max(np.diff(W)[ok] / dt[ok]) / params.contact_area
    return T_start + slab_surface_rise(float(q), float(t[-1] - t[0]), params.plate_thickness, params.k,
                                       params.rho * params.c)


def check_run(case) -> dict:
    """Pass/fail of one run with the numbers behind it."""
    m, sc, r = case.m, case.scene, case.result
    why = []
    if r.status != "ok":
        why.append(f"run {r.status}: {r.message}")
    if not m["finite"]:
        why.append("non-finite values")
    mech = m["energy_residual_rel"]
    if math.isfinite(mech) and mech > MECH_TOL:
        why.append(f"mechanical ledger {mech:.2e} > {MECH_TOL:g}")
    heat = max(m["heat_residual_rel"], m["work_vs_heat_rel"])
    if heat > HEAT_TOL:
        why.append(f"heat ledger {heat:.2e} > {HEAT_TOL:g}")
    # temperature bounds
    lo_b, hi_b, t_lo, t_hi = math.nan, math.nan, math.nan, math.nan
    plates = [(i, p) for i, p in enumerate(r.plates) if p is not None]
    if plates and r.n_rows:
        temps = []
        for i, p in plates:
            t = sc.thermal(("lower", "upper")[i])
            temps += [t["T0_C"], t["T_air_C"]] + ([t["T_back_C"]] if t["back"] == "fixed" else [])
        lo_b = min(temps)
        los, his = [], []
        hi_b = -math.inf
        for i, p in plates:
            bound = plate_bound(case.sim.plate_params[i], p, r["t_s"], r[f"W{i + 1}_J"], max(temps))
            vals = np.asarray(r[f"T{i + 1}_C"], float)
            if hasattr(p, "temperature"):
                vals = np.concatenate([vals, np.asarray(p.temperature(), float).ravel()])
            lo, hi = float(np.min(vals)), float(np.max(vals))
            los.append(lo)
            his.append((hi, bound, ("lower", "upper")[i]))
            hi_b = max(hi_b, bound)
        t_lo, t_hi = min(los), max(h for h, _, _ in his)
        # consistent-mass Galerkin has no discrete maximum principle: ahead of
        # a heat front a node may dip below T0 by a tiny fraction of the rise
        # (first-cell: 8.3e-4 K under a 56 K rise, the same at every dt, at a
        # node 28 mm deep in 5 mm elements: a mesh effect, not a time-step one)
        slack = UNDERSHOOT_REL * max(t_hi - lo_b, 0.0) + 1e-12
        if t_lo < lo_b - slack:
            why.append(f"temperature {t_lo:.6g} \N{DEGREE SIGN}C below the coolest boundary {lo_b:g} \N{DEGREE SIGN}C")
        for hi, bound, side in his:
            if hi > bound + slack:
                why.append(f"{side} plate temperature {hi:.6g} \N{DEGREE SIGN}C above its bound {bound:.6g} "
                           f"\N{DEGREE SIGN}C")
    under = max(0.0, lo_b - t_lo) if math.isfinite(t_lo) else math.nan
    return {"pass": not why, "why": "; ".join(why), "undershoot_K": under, "ledger": max(mech if math.isfinite(mech) else 0.0, heat),
            "mech_ledger": mech, "heat_ledger": heat, "T_min_C": t_lo, "T_max_C": t_hi,
            "T_bound_lo_C": lo_b, "T_bound_hi_C": hi_b}


def same_story(coarse, fine) -> tuple[bool, str]:
    a, b = coarse.m, fine.m
    why = []
    T0 = coarse.scene.thermal("lower")["T0_C"]
    pairs = [("peak_u_m", a["peak_u_m"], b["peak_u_m"], STORY_ATOL["peak_u_m"]),
             ("friction_work_J", a["friction_work_J"], b["friction_work_J"], STORY_ATOL["friction_work_J"]),
             ("peak rise", a["peak_T1_C"] - T0, b["peak_T1_C"] - T0, STORY_ATOL["rise_K"])]
    for name, x, y, atol in pairs:
        if not (math.isfinite(x) and math.isfinite(y)):
            continue
        if abs(x - y) > STORY_RTOL * max(abs(x), abs(y)) + atol:
            why.append(f"{name} {x:.4g} (coarse) vs {y:.4g} (fine)")
    moved = [v > 1e-3 for v in (a["peak_u_m"], b["peak_u_m"]) if math.isfinite(v)]
    if len(moved) == 2 and moved[0] != moved[1]:
        why.append("one dt slides, the other sticks")
    return not why, "; ".join(why)


def run_catalogue(fast=False, log=lambda s: None, only=None) -> list[dict]:
    out = []
    for path in catalogue():
        if only and path.stem not in only:
            continue
        raw = scn.read_toml(path)
        base = _fast_overrides(path) if fast else []
        dt = scn.load(str(path))["solver"]["dt"]
        runs = []
        for tag, d in (("coarse", dt), ("fine", dt / (2 if fast else 4))):
            t0 = time.perf_counter()
            c = run_case(str(path), base + [f"solver.dt={d!r}"], tag)
            chk = check_run(c)
            runs.append((tag, c, chk))
            log(f"stability {path.stem} {tag} dt={d:g}: {'pass' if chk['pass'] else 'FAIL ' + chk['why']} "
                f"({time.perf_counter() - t0:.2f} s)")
        story, story_why = same_story(runs[0][1], runs[1][1])
        ok = story and all(chk["pass"] for _, _, chk in runs)
        why = "; ".join([f"{tag}: {chk['why']}" for tag, _, chk in runs if chk["why"]]
                        + ([f"coarse vs fine: {story_why}"] if story_why else []))
        out.append({"case": path.stem, "description": raw.get("description", ""), "pass": ok, "why": why,
                    "story": story, "runs": runs})
    return out


def cmd_stability(args) -> int:
    out = out_dir(args, "stability")
    cases = run_catalogue(args.fast, lambda s: _say(args, s))
    folder = ResultsFolder(out)
    try:
        rows = []
        for c in cases:
            for tag, run, chk in c["runs"]:
                m = run.m
                rows.append({"case": c["case"], "dt_label": tag, "dt_s": m["dt_s"], "steps": m["steps"],
                             "verdict": "pass" if c["pass"] else "FAIL", "run_pass": chk["pass"],
                             "mech_ledger": chk["mech_ledger"], "heat_ledger": chk["heat_ledger"],
                             "worst_ledger": chk["ledger"], "T_min_C": chk["T_min_C"], "T_max_C": chk["T_max_C"],
                             "T_bound_lo_C": chk["T_bound_lo_C"], "undershoot_K": chk["undershoot_K"], "T_bound_hi_C": chk["T_bound_hi_C"],
                             "peak_u_m": m["peak_u_m"], "friction_work_J": m["friction_work_J"],
                             "min_mu1": m["min_mu1"], "iterations": m["iterations"],
                             "max_iterations": m["max_iterations"], "runtime_s": m["runtime_s"],
                             "why": c["why"]})
        write_rows(folder.path("stability.csv"), rows, list(rows[0]) if rows else ["case"])
        plots = stability_plots(folder.subdir("plots"), cases)
        folder.path("stability.md").write_text(stability_report(cases, args.fast, plots))
        folder.path("summary.json").write_text(json.dumps(
            {"study": "stability", "fast": bool(args.fast), "cases": len(cases),
             "passed": sum(c["pass"] for c in cases),
             "failed": [c["case"] for c in cases if not c["pass"]],
             "tolerances": {"mech_ledger": MECH_TOL, "heat_ledger": HEAT_TOL, "story_rtol": STORY_RTOL,
                            "story_atol": STORY_ATOL}}, indent=2) + "\n")
    except BaseException:
        folder.discard()
        raise
    folder.commit()
    failed = [c["case"] for c in cases if not c["pass"]]
    if not args.quiet:
        print(f"stability: {len(cases) - len(failed)}/{len(cases)} cases pass"
              + (f"; failed: {', '.join(failed)}" if failed else "") + f"; results in {out}/")
    return EXIT_FAILED if failed else EXIT_OK


def stability_report(cases, fast, plots) -> str:
    L = ["# Stability catalogue\n"]
    if fast:
        L.append(f"Fast version: fine dt = coarse / 2 and durations capped at {FAST_DURATION:g} s "
                 f"(except {', '.join(KEEP_LENGTH)}).\n")
    n_ok = sum(c["pass"] for c in cases)
    L.append(f"**{n_ok} of {len(cases)} cases pass.** Each case runs at its scene's dt (coarse) and at a "
             f"finer dt. Pass: every value finite and the run finished (iterated coupling converged); "
             f"mechanical ledger <= {MECH_TOL:g} of the input work, heat ledgers <= {HEAT_TOL:g}; "
             f"each plate's temperatures within [coolest boundary, its bound]: a lumped plate its friction heat / "
             f"c M above the hottest start; an FE plate the surface rise of a slab of its thickness, "
             f"insulated at the back, under the run's peak footprint heat flux over its whole face for the whole "
             f"run (it gets that flux only under the footprint, part of the time, and loses heat) "
             f"(an undershoot of {UNDERSHOOT_REL:g} of the rise is allowed: consistent-mass FE has no discrete "
             f"maximum principle ahead of a heat front; the worst is listed below); "
             f"coarse and fine agree on peak u, friction work and peak rise within {100 * STORY_RTOL:.0f} % "
             f"(floors {STORY_ATOL['peak_u_m'] * 1e3:g} mm, {STORY_ATOL['friction_work_J']:g} J, "
             f"{STORY_ATOL['rise_K']:g} K) and both slide or both stick.\n")
    hdr = ["case", "dt (s)", "verdict", "worst ledger", "T range (\N{DEGREE SIGN}C)", "T bound (\N{DEGREE SIGN}C)", "peak u (mm)",
           "iterations (max/step)", "run time (s)"]
    body = []
    for c in cases:
        for tag, run, chk in c["runs"]:
            m = run.m
            body.append([c["case"], f"{m['dt_s']:g} ({tag})", "pass" if c["pass"] else "**FAIL**",
                         fmt(chk["ledger"], ".1e"), f"{fmt(chk['T_min_C'], '.2f')} .. {fmt(chk['T_max_C'], '.2f')}",
                         f"{fmt(chk['T_bound_lo_C'], '.1f')} .. {fmt(chk['T_bound_hi_C'], '.3g')}",
                         fmt(1e3 * m["peak_u_m"], ".1f"), f"{m['iterations']} ({m['max_iterations']})",
                         fmt(m["runtime_s"], ".2f")])
    L.append(md_table(hdr, body))
    worst = max(((chk["undershoot_K"], c["case"], tag) for c in cases for tag, _, chk in c["runs"]
                 if math.isfinite(chk["undershoot_K"])), default=None)
    if worst and worst[0] > 0:
        L.append(f"Worst undershoot below the coolest boundary: {worst[0]:.2g} K ({worst[1]}, {worst[2]} dt), "
                 "inside the plate ahead of the heat front.\n")
    bad = [c for c in cases if not c["pass"]]
    if bad:
        L.append("## Failures\n")
        L += [f"- `{c['case']}`: {c['why']}" for c in bad]
        L.append("")
    L.append("## Cases\n")
    L += [f"- `{c['case']}`: {c['description']}" for c in cases]
    L.append("")
    if plots:
        L.append("## Plots\n")
        L += [f"![{p}](plots/{p})" for p in plots]
    return "\n".join(L) + "\n"


def stability_plots(folder: Path, cases) -> list[str]:
    """One panel per case: lower-plate surface temperature at coarse and fine dt."""
    if not cases:
        return []
    plt = _plt()
    n = len(cases)
    ncol = 4
    nrow = math.ceil(n / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.2 * ncol, 2.4 * nrow), squeeze=False)
    for ax, c in zip(axes.flat, cases):
        for tag, run, _ in c["runs"]:
            r = run.result
            if r.n_rows > 1 and "T1_C" in r:
                ax.plot(r["t_s"], r["T1_C"], "-" if tag == "coarse" else "--", lw=0.9,
                        label=f"dt {run.m['dt_s']:g}")
        ax.set_title(f"{c['case']} ({'pass' if c['pass'] else 'FAIL'})", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.ticklabel_format(axis="y", useOffset=False)     # 20.0005, not "+2e1" and 0.0005
        ax.legend(fontsize=6)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.supxlabel("t (s)", fontsize=8)
    fig.supylabel("lower plate T1 (\N{DEGREE SIGN}C)", fontsize=8)
    fig.tight_layout()
    fig.savefig(folder / "temperatures.png", dpi=100)
    plt.close(fig)
    return ["temperatures.png"]
