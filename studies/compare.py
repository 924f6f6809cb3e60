"""``fpd compare``: the thermal models side by side on one scene (lumped, fe1d
follow-pad and fixed-point, axisym, fe3d), each model's error against the
reference (the first of fe3d, axisym, fe1d follow-pad that ran) and the
lumped model's validity numbers. The shared runner is studies/study_runner.py.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from fpd.schema import scene as scn
from fpd.outputs.output import ResultsFolder
from .study_runner import (EXIT_FAILED, EXIT_OK, Case, _json, _plt, _say, _scene_name, fmt, md_table,
                           model_available, out_dir, run_case, thermal_set, write_rows)


# ======================================================================================
# fpd compare
# ======================================================================================
COMPARE_MODELS = (
    ("lumped", "lumped", {"model": "lumped"}),
    ("fe1d follow-pad", "fe1d", {"model": "fe1d", "source": "follow-pad"}),
    # the material point at the edge of the footprint at rest (r0 = a): heated
    # only while the pad covers it, about half of the time
    ("fe1d fixed-point", "fe1d", {"model": "fe1d", "source": "fixed-point", "radius_m": "a"}),
    ("axisym", "axisym", {"model": "axisym"}),
    # the reference where it runs: the footprint as it is, no ring average
    ("fe3d", "fe3d", {"model": "fe3d"}),
)
FAST_COMPARE = {"duration": 8.0, "n_elements": 40, "nr": 0, "per_radius": 10, "nz": 12}
REFERENCES = ("fe3d", "axisym", "fe1d follow-pad")      # the first that ran is the reference


def compare_cases(scene_arg, fast=False, log=lambda s: None) -> tuple[list[Case], dict]:
    base = scn.load(scene_arg)
    extra = []
    if fast:
        length = base["solver"].get("duration") or scn.loading_length(base["loading"])
        dur = FAST_COMPARE["duration"] if length is None else min(FAST_COMPARE["duration"], length)
        extra = [f"solver.duration={dur!r}"]
    cases, missing = [], {}
    for label, model, keys in COMPARE_MODELS:
        if not model_available(model):
            missing[label] = f"thermal/{model}.py is not in this checkout"
            log(f"compare: {label}: not available")
            continue
        keys = dict(keys)
        if keys.get("radius_m") == "a":
            keys["radius_m"] = 0.5 * base["device"]["pad_diameter"]
        if fast and model == "fe1d":
            keys["n_elements"] = FAST_COMPARE["n_elements"]
        if fast and model in ("axisym", "fe3d"):
            keys["nr"], keys["nz"] = FAST_COMPARE["nr"], FAST_COMPARE["nz"]
            keys["per_radius"] = FAST_COMPARE["per_radius"]
        c = run_case(scene_arg, extra + thermal_set(**keys), label)
        log(f"compare: {label}: {c.m['status']}, {c.runtime_s:.2f} s, peak T {c.m['peak_T1_C']:.2f} \N{DEGREE SIGN}C")
        cases.append(c)
    return cases, missing


def _reference(cases):
    by = {c.label: c for c in cases}
    for label in REFERENCES:
        if label in by and by[label].ok:
            return by[label]
    return None


def lumped_validity(scene) -> dict:
    """When is the lumped plate right?  Closed-form scales of this scene.

    - through the thickness: a plate heated on one face (other face nearly
      adiabatic) has its surface above its mean by q H / (3 k) at long times,
      i.e. a ratio 1 + H^2 / (3 kappa t): within 10 % once t > 10 H^2 / (3 kappa);
    - over the face: the lumped plate spreads the heat over the whole plate
      area A_p, the conduction models over what the pad covers (A_c for the
      column under the pad, the swept ring for axisym); lateral spreading
      takes R^2 / kappa.
    """
    t = scene.thermal("lower")
    H, R, kappa = t["plate_thickness"], t["plate_radius"], t["k"] / (t["rho"] * t["c"])
    a = 0.5 * scene["device"]["pad_diameter"]
    return {"H_m": H, "R_m": R, "kappa_m2_s": kappa, "a_m": a,
            "t_H_s": H * H / kappa, "t_R_s": R * R / kappa,
            "t_10pct_s": 10 * H * H / (3 * kappa),
            "area_ratio": (R / a) ** 2, "biot": t["h_conv"] * H / t["k"]}


def liner_cases(scene_arg, fast=False, log=lambda s: None) -> list[Case]:
    """The scene once per liner preset (tribology.friction.LINERS): its
    [friction] table replaced by the preset on every surface."""
    from fpd.tribology.friction import LINERS

    base = scn.load(scene_arg)
    extra = []
    if fast:
        length = base["solver"].get("duration") or scn.loading_length(base["loading"])
        dur = FAST_COMPARE["duration"] if length is None else min(FAST_COMPARE["duration"], length)
        extra = [f"solver.duration={dur!r}"]
    cases = []
    for liner in LINERS:
        c = run_case(scene_arg, extra + [f'friction={{liner="{liner}"}}'], liner)
        log(f"compare --liners: {liner}: {c.m['status']}, {c.runtime_s:.2f} s")
        cases.append(c)
    return cases


def liner_rows(cases) -> list[dict]:
    """Per preset: peak displacement, peak temperature (hottest surface), friction
    work, residual displacement, and per surface the wear depth (NaN without)."""
    rows = []
    for c in cases:
        r = c.result
        has = r is not None and r.n_rows > 0
        row = {"liner": c.label, "status": c.m["status"], "peak_u_m": c.m["peak_u_m"],
               "friction_work_J": c.m["friction_work_J"], "residual_u_m": c.m["residual_u_m"]}
        temps = [float(np.max(r[f"T{i}_C"])) for i in range(1, 5) if has and f"T{i}_C" in r]
        row["peak_T_C"] = max(temps) if temps else float("nan")
        for i in range(1, 5):
            if has and f"wear{i}_m" in r:
                row[f"wear{i}_m"] = float(r[f"wear{i}_m"][-1])
        wears = [v for k, v in row.items() if k.startswith("wear")]
        row["max_wear_m"] = max(wears) if wears else float("nan")
        rows.append(row)
    return rows


def cmd_compare_liners(args) -> int:
    name = _scene_name(args.scene)
    out = out_dir(args, f"compare-liners-{name}")
    cases = liner_cases(args.scene, args.fast, lambda s: _say(args, s))
    folder = ResultsFolder(out)
    try:
        rows = liner_rows(cases)
        n_wear = max((sum(1 for k in r if k.startswith("wear")) for r in rows), default=0)
        cols = ["liner", "status", "peak_u_m", "peak_T_C", "friction_work_J", "residual_u_m", "max_wear_m"]
        cols += [f"wear{i}_m" for i in range(1, n_wear + 1)]
        write_rows(folder.path("liners.csv"), [{k: r.get(k, float("nan")) for k in cols} for r in rows], cols)
        head = ["liner", "status", "peak u (mm)", "peak T (C)", "friction work (kJ)", "residual u (mm)",
                "max wear (um)"]
        table = [[r["liner"], r["status"], fmt(1e3 * r["peak_u_m"]), fmt(r["peak_T_C"]),
                  fmt(1e-3 * r["friction_work_J"]), fmt(1e3 * r["residual_u_m"]), fmt(1e6 * r["max_wear_m"])]
                 for r in rows]
        text = (f"# Liner presets on {name}\n\n"
                "The scene once per preset of docs/liners.md (its [friction] replaced by the preset on every "
                "surface). Wear: the deepest surface's Archard depth; empty where the preset has no wear "
                "coefficient. The values no source states (marked * there, with the basis used) are not "
                "measured values.\n\n"
                + md_table(head, table))
        folder.path("liners.md").write_text(text)
        folder.path("summary.json").write_text(json.dumps(
            {"study": "compare-liners", "scene": name, "fast": bool(args.fast), "rows": rows},
            indent=2, default=_json) + "\n")
    except BaseException:
        folder.discard()
        raise
    folder.commit()
    if not args.quiet:
        print(f"compare --liners {name}: {len(cases)} presets; results in {out}/")
        for r in rows:
            print(f"  {r['liner']:16s} peak u {1e3 * r['peak_u_m']:8.2f} mm  peak T {r['peak_T_C']:7.2f} C  "
                  f"work {1e-3 * r['friction_work_J']:9.2f} kJ  residual {1e3 * r['residual_u_m']:7.2f} mm  "
                  f"wear {1e6 * r['max_wear_m']:.4g} um")
    return EXIT_OK if all(c.ok for c in cases) else EXIT_FAILED


def cmd_compare(args) -> int:
    if getattr(args, "liners", False):
        return cmd_compare_liners(args)
    name = _scene_name(args.scene)
    out = out_dir(args, f"compare-{name}")
    log = (lambda s: _say(args, s))
    cases, missing = compare_cases(args.scene, args.fast, log)
    folder = ResultsFolder(out)
    try:
        rows = compare_rows(cases)
        cols = ["model", "plate", "status", "peak_T_C", "end_T_C", "min_mu", "friction_work_J", "peak_u_m",
                "residual_u_m", "runtime_s", "mu_at_peak_T", "err_peak_T_K", "err_end_T_K", "err_peak_rise_rel",
                "err_mu_at_peak_T", "err_friction_work_rel", "err_peak_u_m"]
        write_rows(folder.path("compare.csv"), rows, cols)
        plots = compare_plots(folder.subdir("plots"), cases, name)
        ref = _reference(cases)
        text = compare_report(name, cases, rows, missing, ref, lumped_validity(cases[0].scene), args.fast, plots)
        folder.path("compare.md").write_text(text)
        folder.path("summary.json").write_text(json.dumps(
            {"study": "compare", "scene": name, "fast": bool(args.fast),
             "reference": ref.label if ref else None, "missing": missing, "rows": rows},
            indent=2, default=_json) + "\n")
    except BaseException:
        folder.discard()
        raise
    folder.commit()
    if not args.quiet:
        print(f"compare {name}: {len(cases)} models; reference {ref.label if ref else 'none'}; results in {out}/")
        for r in rows:
            if ref is not None and r["model"] != ref.label:
                print(f"  {r['model']:17s} {r['plate']:5s} peak T {r['peak_T_C']:8.3f} C "
                      f"(err {r.get('err_peak_T_K', float('nan')):+.3f} K), mu at peak "
                      f"{r['mu_at_peak_T']:.5f} (err {r.get('err_mu_at_peak_T', float('nan')):+.5f}), "
                      f"work err {100 * r.get('err_friction_work_rel', float('nan')):+.3f} %, "
                      f"peak u err {1e3 * r.get('err_peak_u_m', float('nan')):+.3f} mm")
    return EXIT_OK if all(c.ok for c in cases) else EXIT_FAILED


def compare_rows(cases) -> list[dict]:
    ref = _reference(cases)
    rows = []
    for c in cases:
        for i, plate in ((1, "lower"), (2, "upper")):
            m = c.m
            row = {"model": c.label, "plate": plate, "status": m["status"],
                   "peak_T_C": m[f"peak_T{i}_C"], "end_T_C": m[f"end_T{i}_C"], "min_mu": m[f"min_mu{i}"],
                   "friction_work_J": m[f"W{i}_J"], "peak_u_m": m["peak_u_m"],
                   "residual_u_m": m["residual_u_m"], "runtime_s": c.runtime_s}
            row["mu_at_peak_T"] = _mu_at_peak(c, i)
            if ref is not None and c is not ref:
                r = ref.m
                row["err_mu_at_peak_T"] = row["mu_at_peak_T"] - _mu_at_peak(ref, i)
                T0 = c.scene.thermal(plate)["T0_C"]
                row["err_peak_T_K"] = m[f"peak_T{i}_C"] - r[f"peak_T{i}_C"]
                row["err_end_T_K"] = m[f"end_T{i}_C"] - r[f"end_T{i}_C"]
                rise = r[f"peak_T{i}_C"] - T0
                row["err_peak_rise_rel"] = row["err_peak_T_K"] / rise if rise else float("nan")
                W = r[f"W{i}_J"]
                row["err_friction_work_rel"] = (m[f"W{i}_J"] - W) / W if W else float("nan")
                row["err_peak_u_m"] = m["peak_u_m"] - r["peak_u_m"]
            rows.append(row)
    return rows


def _mu_at_peak(case, i) -> float:
    """mu of interface i at the moment its surface temperature peaks."""
    r = case.result
    if r is None or not r.n_rows or f"T{i}_C" not in r or f"mu{i}" not in r:
        return float("nan")
    return float(r[f"mu{i}"][int(np.argmax(r[f"T{i}_C"]))])



def _time_plot(fig, ax, folder, file: str, title: str, ylabel: str) -> str:
    """Finish a figure of curves against time (labels, grid, legend), write
    it to folder/file and close it; returns file."""
    ax.set_xlabel("t (s)")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(folder / file, dpi=110)
    _plt().close(fig)
    return file


def compare_plots(folder: Path, cases, name) -> list[str]:
    plt = _plt()
    made = []
    styles = {"lumped": "-", "fe1d follow-pad": "-", "fe1d fixed-point": "--", "axisym": "-.", "fe3d": ":"}
    ok = [c for c in cases if c.result is not None and c.result.n_rows > 1]
    fig, ax = plt.subplots(figsize=(7.5, 4))
    for c in ok:
        r = c.result
        if "T1_C" in r:
            from fpd.outputs.hottest import quantity_of
            t = c.scene.thermal("lower")
            what = quantity_of(t["model"], t.get("source", "follow-pad"), t.get("radius_m", 0.0))
            ax.plot(r["t_s"], r["T1_C"], styles.get(c.label, "-"), lw=1, label=f"{c.label}, lower: {what}")
    made.append(_time_plot(fig, ax, folder, "temperature.png", f"{name}: temperature by thermal model",
                           "lower plate T1 (\N{DEGREE SIGN}C), each model's own quantity"))
    if ok and "mu1" in ok[0].result:
        fig, ax = plt.subplots(figsize=(7.5, 4))
        for c in ok:
            ax.plot(c.result["t_s"], c.result["mu1"], styles.get(c.label, "-"), lw=1, label=c.label)
        made.append(_time_plot(fig, ax, folder, "friction.png", f"{name}: friction by thermal model",
                               "friction coefficient mu1 (lower)"))
    if ok and "u_m" in ok[0].result:
        made.append(_loops(folder, ok, name))
    return made


def _loops(folder: Path, cases, name) -> str:
    """The hysteresis loops in small multiples: one panel per thermal model on
    shared axes, the first model's loop drawn faintly behind the others (five
    loops on one axes hide each other)."""
    import math

    from fpd.outputs.drawing import new_figure, save, thin_xy
    n = len(cases)
    ncols = min(3, n)
    nrows = math.ceil(n / ncols)
    fig, axes = new_figure(nrows, ncols, figsize=(3.4 * ncols + 0.9, 2.9 * nrows + 0.8), left=0.8, right=0.15,
                           top=0.6, bottom=0.55, hgap=0.55, wgap=0.2, sharex=True, sharey=True)
    base = cases[0]
    bu, bF = 1e3 * base.result["u_m"], 1e-3 * base.result["F_N"]
    bs = thin_xy(len(bu), bu, bF)
    for k, (ax, c) in enumerate(zip(axes, cases)):
        u, F = 1e3 * c.result["u_m"], 1e-3 * c.result["F_N"]
        if k:
            ax.plot(bu[bs], bF[bs], lw=0.6, color="0.75", label=base.label)
        s = thin_xy(len(u), u, F)
        ax.plot(u[s], F[s], lw=0.7, color=f"C{k}", label=c.label)
        ax.set_title(c.label, fontsize=9)
        ax.grid(alpha=0.3)
        if k:
            ax.legend(fontsize=7, loc="upper left")
        if k % ncols == 0:
            ax.set_ylabel("F (kN)")
        if k >= n - ncols:
            ax.set_xlabel("u (mm)")
            ax.xaxis.set_tick_params(labelbottom=True)
    for ax in axes[n:]:
        ax.set_visible(False)
    fig.suptitle(f"{name}: hysteresis by thermal model ({base.label} in grey behind the others)", fontsize=10)
    save(fig, folder / "hysteresis.png")
    return "hysteresis.png"


def compare_report(name, cases, rows, missing, ref, val, fast, plots) -> str:
    by = {c.label: c for c in cases}
    L = [f"# Thermal models compared: `{name}`\n"]
    if fast:
        L.append("Fast version (shortened duration, coarse meshes): numbers are indicative only.\n")
    L.append(f"Reference: **{ref.label if ref else 'none'}**"
             + ("" if ref is None or ref.label == "fe3d" else
                " (fe3d did not run, so the next model of " + ", ".join(REFERENCES)
                + " stands in for it; axisym averages an off-centre footprint into a ring and "
                "runs low, the fe1d follow-pad column is an upper bound)") + ".\n")
    for lab, why in missing.items():
        L.append(f"- `{lab}`: not run ({why}).")
    if missing:
        L.append("")
    hdr = ["model", "plate", "peak T (\N{DEGREE SIGN}C)", "T end (\N{DEGREE SIGN}C)", "min mu", "friction work (kJ)", "peak u (mm)",
           "residual u (mm)", "run time (s)", "err peak T (K)", "err T end (K)", "err work (%)"]
    body = []
    for r in rows:
        body.append([r["model"], r["plate"], fmt(r["peak_T_C"], ".2f"), fmt(r["end_T_C"], ".2f"),
                     fmt(r["min_mu"], ".4f"), fmt(r["friction_work_J"] / 1e3, ".3f"),
                     fmt(1e3 * r["peak_u_m"], ".2f"), fmt(1e3 * r["residual_u_m"], ".2f"),
                     fmt(r["runtime_s"], ".2f"), fmt(r.get("err_peak_T_K", float("nan")), "+.2f"),
                     fmt(r.get("err_end_T_K", float("nan")), "+.2f"),
                     fmt(100 * r.get("err_friction_work_rel", float("nan")), "+.2f")])
    L.append(md_table(hdr, body))
    L += _errors_vs_reference(rows, ref)
    lump = by.get("lumped")
    fp = by.get("fe1d follow-pad")
    L.append("## How far the paper's lumped plate is from conduction\n")
    T0 = cases[0].scene.thermal("lower")["T0_C"]
    if lump is not None and ref is not None:
        rl, rr = lump.m["peak_T1_C"] - T0, ref.m["peak_T1_C"] - T0
        ratio = rr / rl if rl > 0 else float("inf")
        L.append(f"- Peak surface rise of the lower plate: lumped **{rl:.3g} K**, {ref.label} **{rr:.3g} K**: "
                 f"the lumped plate under-predicts the rise by a factor **{ratio:.3g}** "
                 f"({100 * (rl - rr) / rr if rr else float('nan'):+.1f} %).")
        dmu = lump.m["min_mu1"] - ref.m["min_mu1"]
        L.append(f"- Lowest mu1: lumped {lump.m['min_mu1']:.4f}, {ref.label} {ref.m['min_mu1']:.4f} "
                 f"(difference {dmu:+.4f}); friction work differs by "
                 f"{100 * (lump.m['friction_work_J'] - ref.m['friction_work_J']) / ref.m['friction_work_J']:+.2f} %, "
                 f"peak displacement by {1e3 * (lump.m['peak_u_m'] - ref.m['peak_u_m']):+.2f} mm.")
    if fp is not None and lump is not None:
        L.append(f"- The column under the pad (fe1d follow-pad, an upper bound) peaks at "
                 f"{fp.m['peak_T1_C']:.2f} C against the lumped {lump.m['peak_T1_C']:.2f} C.")
    L.append("")
    L.append("## When the lumped plate is right\n")
    dur = cases[0].sim.n_steps * cases[0].sim.dt
    L.append(
        f"The lumped plate (paper Eq. 9-10) spreads the friction heat at once through the whole plate "
        f"(thickness H = {1e3 * val['H_m']:.0f} mm, radius R = {1e3 * val['R_m']:.0f} mm, "
        f"kappa = {val['kappa_m2_s']:.3g} m2/s). Conduction needs time to do that:\n")
    L.append(f"- **Through the thickness** it takes t_H = H^2/kappa = **{val['t_H_s']:.0f} s**. With one face "
             f"heated, the surface of a slab runs above its mean by q H/(3k), a ratio 1 + H^2/(3 kappa t): the "
             f"lumped mean is within 10 % of the surface only after t > 10 H^2/(3 kappa) = "
             f"**{val['t_10pct_s']:.0f} s** (long times), or, for this run's {dur:.0f} s, on a plate thinner "
             f"than sqrt(0.3 kappa t) = **{1e3 * math.sqrt(0.3 * val['kappa_m2_s'] * dur):.1f} mm** "
             f"(thin plates).")
    L.append(f"- **Over the face** the lumped plate uses the whole area, (R/a)^2 = **{val['area_ratio']:.1f}** "
             f"times the pad's footprint; conduction spreads heat sideways only over R^2/kappa = "
             f"**{val['t_R_s']:.0f} s**. The lumped plate is therefore right only when the pad sweeps most of "
             f"the plate and each passage is slow against the thickness time, i.e. a cycle period well above "
             f"t_H = {val['t_H_s']:.0f} s (slow cycling): then the column under the pad has time to even out "
             f"between passages.")
    try:
        from fpd.thermal import exact
        t = cases[0].scene.thermal("lower")
        ratios = []
        for tt in (dur, val["t_H_s"], val["t_10pct_s"]):
            surf = float(exact.slab_flux(0.0, tt, 1.0, t["k"], val["kappa_m2_s"], val["H_m"])[0])
            ratios.append((tt, surf / float(exact.slab_flux_mean(tt, 1.0, t["rho"], t["c"], val["H_m"]))))
        L.append("- Closed form (slab, flux in one face, other adiabatic): the heated face runs "
                 + ", ".join(f"**{r:.3g}** times the plate mean at t = {tt:.0f} s" for tt, r in ratios) + ".")
    except ImportError:
        pass
    L.append(f"- Biot number h H / k = {val['biot']:.3g} (< 0.1: the plate is isothermal through its thickness "
             f"in the steady state; it says nothing about the transient above).")
    L.append(f"- This scene lasts {dur:.1f} s = {dur / val['t_H_s']:.3g} t_H: "
             + ("far too short for the lumped assumption; expect the conduction models to be hotter."
                if dur < val["t_10pct_s"] else "long enough for the through-thickness part of the assumption."))
    L.append("")
    if plots:
        L.append("## Plots\n")
        L += [f"![{p}](plots/{p})" for p in plots]
        L.append("")
    return "\n".join(L) + "\n"


def _errors_vs_reference(rows, ref) -> list[str]:
    """Each model's error against the reference: peak surface temperature, mu
    at that moment, friction work, peak displacement."""
    if ref is None:
        return []
    L = [f"## Error of each model against {ref.label}\n"]
    hdr = ["model", "plate", "peak T err (K)", "peak rise err (%)", "mu at peak T", "mu err",
           "friction work err (%)", "peak u err (mm)", "run time (s)"]
    body = [[r["model"], r["plate"], fmt(r.get("err_peak_T_K", float("nan")), "+.3f"),
             fmt(100 * r.get("err_peak_rise_rel", float("nan")), "+.2f"), fmt(r["mu_at_peak_T"], ".5f"),
             fmt(r.get("err_mu_at_peak_T", float("nan")), "+.5f"),
             fmt(100 * r.get("err_friction_work_rel", float("nan")), "+.3f"),
             fmt(1e3 * r.get("err_peak_u_m", float("nan")), "+.3f"), fmt(r["runtime_s"], ".2f")]
            for r in rows if r["model"] != ref.label]
    return L + [md_table(hdr, body)]
