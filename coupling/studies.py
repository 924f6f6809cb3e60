"""The three studies of issue 6: ``fpd compare``, ``fpd converge``, ``fpd stability``.

Each study runs a scene several times with ``--set``-style overrides (lists of
'key=value' strings applied before validation), measures named outputs, and
writes a folder a person can read: CSV tables, a short markdown report and
PNG plots, written into a temporary folder and moved into place at the end
(coupling.output.ResultsFolder), like ``fpd run``.

The models a study needs but this checkout does not have (thermal/fe1d.py,
thermal/axisym.py) are reported as "not available" rather than failing.
"""
from __future__ import annotations

import csv
import importlib.util
import json
import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import scene as scn
from .claim import hold
from .output import ResultsFolder
from .scene import SceneError

EXIT_OK, EXIT_FAILED = 0, 1


# -- running one case ------------------------------------------------------------------
@dataclass
class Case:
    """One run of a study: its label, the overrides, the measured outputs."""

    label: str
    overrides: list
    scene: object = None
    sim: object = None
    result: object = None
    runtime_s: float = float("nan")
    m: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.result is not None and self.result.status == "ok"


def model_available(model: str) -> bool:
    mod = {"fe1d": "fpd.thermal.fe1d", "axisym": "fpd.thermal.axisym", "fe3d": "fpd.thermal.fe3d",
           "two-phase": "fpd.mechanics.two_phase"}.get(model)
    return mod is None or importlib.util.find_spec(mod) is not None


def thermal_set(**keys) -> list[str]:
    """Overrides setting [thermal] keys on both plates (a scene's per-plate
    tables would otherwise win over the base table)."""
    out = []
    for side in ("lower", "upper"):
        for k, v in keys.items():
            out.append(f"thermal.{side}.{k}={_tomlv(v)}")
    return out


def _tomlv(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    return repr(v)


def min_heat_capacity(plate) -> float:
    """The smallest heat capacity of a plate model (J/K): the lumped plate's
    c M, or the smallest nodal (row-sum) capacity of an FE mesh."""
    if plate is None:
        return math.inf
    if hasattr(plate, "C") and not hasattr(plate, "integ"):
        return float(plate.C)
    integ = getattr(plate, "integ", None)
    if integ is not None:
        n = len(integ.u)
        return float(np.min(np.asarray(integ.mass(np.ones(n)))[: integ.nf]))
    return math.nan


def run_case(scene_arg, overrides, label="", progress=False) -> Case:
    """Load, build and run a scene with overrides; measure its outputs."""
    from .build import build
    from .run import simulate

    case = Case(label, list(overrides))
    case.scene = scn.load(scene_arg, overrides)
    key = (case.scene["mechanics"]["model"], case.scene.thermal("lower")["model"], case.scene.thermal("upper")["model"])
    if key not in _WARM:          # imports, kernel loading and compiling once per model: a few steps first
        simulate(build(scn.load(scene_arg, list(overrides) + [f"solver.duration={5 * case.scene['solver']['dt']!r}"])))
        _WARM.add(key)
    best = float("inf")
    for _ in range(3):            # run time = build + stepping (no storing); best of 3 when it is short
        t0 = time.perf_counter()
        case.sim = build(case.scene)
        build_s = time.perf_counter() - t0
        case.result = simulate(case.sim, progress=progress)
        best = min(best, build_s + case.result.runtime_s)
        if best > 0.2:
            break
    case.runtime_s = best
    case.m = measure(case)
    return case


_WARM: set = set()


def measure(case: Case) -> dict:
    """Named outputs of a run (NaN where a scene does not compute one)."""
    r, sim = case.result, case.sim
    nan = float("nan")
    m = {"status": r.status, "message": r.message, "runtime_s": case.runtime_s, "steps": sim.n_steps,
         "dt_s": sim.dt, "iterations": int(r.iterations), "max_iterations": int(r.max_iterations)}
    has = r.n_rows > 0
    m["finite"] = bool(has and np.all(np.isfinite(r.data)))
    mech = has and "u_m" in r
    m["peak_u_m"] = float(np.max(np.abs(r["u_m"]))) if mech else nan
    m["residual_u_m"] = float(r["u_m"][-1]) if mech else nan
    m["W1_J"] = float(r["W1_J"][-1]) if mech else nan
    m["W2_J"] = float(r["W2_J"][-1]) if mech else nan
    # the TFP's surfaces S3, S4 (mechanics/tfp.py) count in the total
    w34 = sum(float(r[c][-1]) for c in ("W3_J", "W4_J") if mech and c in r)
    m["friction_work_J"] = m["W1_J"] + m["W2_J"] + w34
    if mech:
        # the largest residual over the history, not the last row's (summary.json does the same);
        # the TFP's surfaces S3, S4 and its rim losses count too
        e_in = r["E_input_J"]
        w = r["W1_J"] + r["W2_J"]
        for c in ("W3_J", "W4_J"):
            if c in r:
                w = w + r[c]
        out = r["E_kin_J"] + r["E_pot_J"] + w
        for c in ("E_reseat_J", "E_rim_J"):
            if c in r:
                out = out + r[c]
        scale = max(float(np.max(np.abs(e_in))), abs(float(w[-1])), 1e-300)
        worst = float(np.max(np.abs(e_in - out)))
        m["energy_residual_rel"] = worst / scale if worst else 0.0
    else:
        m["energy_residual_rel"] = nan
    for i in (1, 2):
        col = f"T{i}_C"
        m[f"peak_T{i}_C"] = float(np.max(r[col])) if has and col in r else nan
        m[f"end_T{i}_C"] = float(r[col][-1]) if has and col in r else nan
        m[f"min_T{i}_C"] = float(np.min(r[col])) if has and col in r else nan
        mu = f"mu{i}"
        m[f"min_mu{i}"] = float(np.min(r[mu])) if has and mu in r else nan
        m[f"max_mu{i}"] = float(np.max(r[mu])) if has and mu in r else nan
    m["peak_T_C"], m["end_T_C"] = m["peak_T1_C"], m["end_T1_C"]
    # heat ledgers: per plate heat_in = stored + lost; friction heat = heat in
    worst_plate, worst_work = 0.0, 0.0
    heat_in_total = 0.0
    for i, plate in enumerate(r.plates):
        if plate is None:
            continue
        q_in, st, lo = plate.heat_in(), plate.stored_heat(), plate.heat_lost()
        heat_in_total += q_in
        scale = max(abs(q_in), abs(st), abs(lo))
        worst_plate = max(worst_plate, abs(q_in - st - lo) / scale if scale else 0.0)
        pp = sim.plate_params[i]
        fixed = getattr(pp, "source", "") == "fixed-point" and pp.model in ("fe1d",)
        if mech and r.status == "ok" and not fixed:
            W = r[f"W{i + 1}_J"][-1] * pp.heat_share
            worst_work = max(worst_work, abs(W - q_in) / abs(W) if W else abs(q_in))
    m["heat_residual_rel"] = worst_plate
    m["work_vs_heat_rel"] = worst_work
    m["heat_in_J"] = heat_in_total
    return m


# -- small helpers ------------------------------------------------------------------------
def out_dir(args, default: str) -> Path:
    out = Path(args.out) if args.out else Path("results") / default
    hold(args, out)             # DIR ours until the command returns (coupling/claim.py); checked under the claim
    return out


def write_rows(path: Path, rows: list[dict], columns: list[str]) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(columns)
        for row in rows:
            w.writerow([_cell(row.get(c, "")) for c in columns])


def _cell(v):
    if isinstance(v, float):
        return "" if math.isnan(v) else f"{v:.10g}"
    return v


def fmt(v, spec=".4g") -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return format(v, spec)


def md_table(header: list[str], rows: list[list]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _say(args, text: str) -> None:
    if not getattr(args, "quiet", False):
        sys.stderr.write(text + "\n")
        sys.stderr.flush()


def _scene_name(scene_arg) -> str:
    return scn.load(scene_arg).name


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
    # the reference where it runs: the footprint as it is, no ring average (issue 13)
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


def cmd_compare(args) -> int:
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


def _json(o):
    if isinstance(o, float) and not math.isfinite(o):
        return None
    return str(o)


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


def compare_plots(folder: Path, cases, name) -> list[str]:
    plt = _plt()
    made = []
    styles = {"lumped": "-", "fe1d follow-pad": "-", "fe1d fixed-point": "--", "axisym": "-.", "fe3d": ":"}
    ok = [c for c in cases if c.result is not None and c.result.n_rows > 1]
    fig, ax = plt.subplots(figsize=(7.5, 4))
    for c in ok:
        r = c.result
        if "T1_C" in r:
            from .hottest import quantity_of
            t = c.scene.thermal("lower")
            what = quantity_of(t["model"], t.get("source", "follow-pad"), t.get("radius_m", 0.0))
            ax.plot(r["t_s"], r["T1_C"], styles.get(c.label, "-"), lw=1, label=f"{c.label}, lower: {what}")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("lower plate T1 (\N{DEGREE SIGN}C), each model's own quantity")
    ax.set_title(f"{name}: temperature by thermal model")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(folder / "temperature.png", dpi=110)
    plt.close(fig)
    made.append("temperature.png")
    if ok and "mu1" in ok[0].result:
        fig, ax = plt.subplots(figsize=(7.5, 4))
        for c in ok:
            ax.plot(c.result["t_s"], c.result["mu1"], styles.get(c.label, "-"), lw=1, label=c.label)
        ax.set_xlabel("t (s)")
        ax.set_ylabel("friction coefficient mu1 (lower)")
        ax.set_title(f"{name}: friction by thermal model")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(folder / "friction.png", dpi=110)
        plt.close(fig)
        made.append("friction.png")
    if ok and "u_m" in ok[0].result:
        fig, ax = plt.subplots(figsize=(6.5, 4.5))
        for c in ok:
            ax.plot(1e3 * c.result["u_m"], 1e-3 * c.result["F_N"], styles.get(c.label, "-"), lw=0.8,
                    label=c.label)
        ax.set_xlabel("relative displacement u (mm)")
        ax.set_ylabel("horizontal force F (kN)")
        ax.set_title(f"{name}: hysteresis by thermal model")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(folder / "hysteresis.png", dpi=110)
        plt.close(fig)
        made.append("hysteresis.png")
    return made


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
    at that moment, friction work, peak displacement (issue 13)."""
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


# ======================================================================================
# fpd converge
# ======================================================================================
OUTPUTS = ("peak_u_m", "friction_work_J", "peak_T_C", "end_T_C")


def _duration(scene):
    return scene["solver"].get("duration") or scn.loading_length(scene["loading"])


def closed_form(scene):
    """The closed-form value of each output for scenes that have one
    (thermal-only ``heat`` loading), else None.  Returns {output: value}."""
    if scene["loading"]["kind"] != "heat" or scene["loading"]["plate"] not in ("lower", "both"):
        return None
    try:
        from fpd.thermal import exact
    except ImportError:
        return None
    t = scene.thermal("lower")
    ld = scene["loading"]
    dur = _duration(scene)
    q = ld["flux_W_m2"]
    kappa = t["k"] / (t["rho"] * t["c"])
    H, T0 = t["plate_thickness"], t["T0_C"]
    a = 0.5 * scene["device"]["pad_diameter"]
    # half-space within ~1e-6 of the rise: the image of the back face enters
    # as ierfc(2 deep) and the plate's rim as ierfc((R - a) / sqrt(kappa t))
    deep = H / (2 * math.sqrt(kappa * dur))
    if t["T0_C"] != t["T_air_C"]:
        return None
    if t["model"] == "fe1d" and t["source"] == "follow-pad":
        if deep > 1.75:
            rise, what = float(exact.halfspace_flux_surface(dur, q, t["k"], kappa)), "half-space, constant flux"
        elif t["back"] == "adiabatic":
            rise, what = float(exact.slab_flux(0.0, dur, q, t["k"], kappa, H)[0]), "slab, adiabatic back"
        else:
            return None
    elif (t["model"] in ("axisym", "fe3d") and deep > 1.75
          and (t["plate_radius"] * (0.886 if t["model"] == "fe3d" else 1.0) - a) > 3.5 * math.sqrt(kappa * dur)):
        rise, what = float(exact.disk_mean(dur, q, a, t["k"], kappa)), "disk source on a half-space"
    elif t["model"] == "lumped":
        from fpd.thermal.params import PlateParams
        pp = PlateParams(**t, a_contact_m=a)
        area = t["exchange_area_m2"] or math.pi * t["plate_radius"] ** 2
        P = q * pp.contact_area
        val = float(exact.lumped_newton(dur, P, t["h_conv"] * area, t["c"] * pp.mass, T0, t["T_air_C"]))
        rise, what = val - T0, "lumped Newton cooling"
    else:
        return None
    # constant flux: the surface temperature rises monotonically, so peak = end
    return {"peak_T_C": T0 + rise, "end_T_C": T0 + rise, "_what": what, "_model": t["model"]}


def richardson(values, ratio=2.0):
    """Order p and extrapolated value of a sequence refined by ``ratio``
    (coarse to fine). p is the least-squares slope of log|v_k - v_k+1|
    against the level (with three levels exactly the classical
    log((v1 - v2) / (v2 - v3)) / log(ratio)); the limit is extrapolated from
    the two finest, v_n + (v_n - v_n-1) / (ratio^p - 1). Without a
    convergent sequence (p <= 0.05, or a zero difference) the finest value
    is returned as the reference, with p as measured."""
    v = np.asarray(values, float)
    d = np.diff(v)
    if len(v) < 3 or np.any(d == 0):
        return float("nan"), float(v[-1])
    k = np.arange(len(d))
    p = float(-np.polyfit(k, np.log(np.abs(d)), 1)[0] / math.log(ratio))
    if not math.isfinite(p) or p <= 0.05:
        return p, float(v[-1])
    return p, float(v[-1] + d[-1] / (ratio ** p - 1.0))


def fit_order(h, err):
    """Least-squares slope of log(error) against log(h) over the levels whose
    error is above round-off."""
    h, err = np.asarray(h, float), np.abs(np.asarray(err, float))
    ok = np.isfinite(err) & (err > 0) & np.isfinite(h) & (h > 0)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(h[ok]), np.log(err[ok]), 1)[0])


@dataclass
class Sweep:
    name: str            # "dt", "mesh", "mesh-r", "mesh-z"
    param: str           # what is refined
    levels: list         # list of (label, overrides, h) coarse to fine
    cases: list = field(default_factory=list)
    exact: bool = False  # measured against the closed form (else Richardson)


def converge_plan(scene, fast=False) -> tuple[list[Sweep], list[str]]:
    """Sweeps for a scene: dt (4 levels, ratio 2), and for FE models the mesh
    (3 levels, ratio 2; axisym: r and z separately)."""
    t = scene.thermal("lower")
    dt0 = scene["solver"]["dt"]
    dur = _duration(scene)
    base = []
    if fast:
        if scene["loading"]["kind"] != "heat" and (dur is None or dur > 6.0):
            base.append("solver.duration=6.0")
            dur = 6.0
    n_dt, coarse = 4, 4.0
    dts = [dt0 * coarse / 2 ** k for k in range(n_dt)]
    if dur is not None:
        dts = [d for d in dts if d <= dur / 4] or dts
    model = t["model"]
    # against a closed form the held parameter must not leave an error floor
    # above the swept one: the dt sweep then runs on a mesh 8 times finer and
    # the mesh sweep at a quarter of the finest dt (Richardson cancels it)
    # (fe1d only: refining an axisym mesh 8 times is too dear, so its dt
    # sweep is measured against its Richardson limit, see exact_for)
    has_exact = closed_form(scene) is not None
    dt_mesh = []
    if has_exact and model == "fe1d":
        dt_mesh = thermal_set(n_elements=8 * t["n_elements"], grading=t["grading"] ** 0.125)
    if fast and model == "axisym":
        dt_mesh = thermal_set(nr=0, per_radius=10, nz=max(4, t["nz"] // 4))
    if fast and model == "fe3d":
        dt_mesh = thermal_set(per_radius=10, nz=max(4, t["nz"] // 4))
    sweeps = [Sweep("dt", "solver.dt", [(f"dt={d:.6g}", [f"solver.dt={d!r}"] + dt_mesh, d) for d in dts],
                    exact=has_exact and model not in ("axisym", "fe3d"))]
    fine_dt = [f"solver.dt={dts[-1] / (4 if has_exact and model == 'fe1d' else 1)!r}"]
    if model == "fe1d":
        n0, g0 = t["n_elements"], t["grading"]
        if fast:
            n0 = max(8, n0 // 4)
        levels = []
        for k in range(3):
            n, g = n0 * 2 ** k // 2, g0 ** (1.0 / 2 ** (k - 1))
            from fpd.meshes.line import graded_nodes
            h1 = float(graded_nodes(t["plate_thickness"], n, g)[1])
            levels.append((f"n_elements={n}, grading={g:.5g}", fine_dt + thermal_set(n_elements=n, grading=g), h1))
        sweeps.append(Sweep("mesh", "thermal.n_elements", levels, exact=has_exact))
    elif model == "axisym":
        # r: the automatic footprint mesh (nr = 0) at 10, 20, 40 elements per
        # footprint radius (fewer than 10 is refused at load)
        a = 0.5 * scene["device"]["pad_diameter"]
        nz0 = max(4, t["nz"] // 4) if fast else t["nz"]
        per0 = 20
        r_lv, z_lv, b_lv = [], [], []
        for k in range(3):
            per = per0 * 2 ** k // 2
            nz = max(2, nz0 * 2 ** k // 2)
            g = t["grading"] ** (1.0 / 2 ** (k - 1))      # z is graded: keep the family nested
            r_lv.append((f"per_radius={per}", fine_dt + thermal_set(nr=0, per_radius=per, nz=nz0), a / per))
            z_lv.append((f"nz={nz}, grading={g:.5g}", fine_dt + thermal_set(nr=0, per_radius=per0, nz=nz, grading=g),
                         t["plate_thickness"] / nz))
            b_lv.append((f"per_radius={per}, nz={nz}", fine_dt + thermal_set(nr=0, per_radius=per, nz=nz, grading=g),
                         a / per))
        # one direction at a time keeps the other's error: Richardson removes
        # it; both together are measured against the closed form if any
        sweeps += [Sweep("mesh-r", "thermal.per_radius", r_lv), Sweep("mesh-z", "thermal.nz", z_lv)]
        if has_exact:
            sweeps.append(Sweep("mesh", "thermal.per_radius+nz", b_lv, exact=True))
    elif model == "fe3d":
        sweeps += fe3d_sweeps(scene, t, fine_dt, fast, has_exact)
    return sweeps, base


def fe3d_sweeps(scene, t, fine_dt, fast, has_exact) -> list:
    """fe3d (issue 13): the face mesh (per_radius 10, 20, 40 elements per
    footprint radius, nz held), the depth mesh (nz halved and doubled, the
    grading kept nested) and the thermal step (step_multiple 40, 20, 10, 5
    mechanical steps); each against its Richardson limit (a heat scene's
    closed form is reported as closed_form_error_finest)."""
    a = 0.5 * scene["device"]["pad_diameter"]
    nz0 = max(4, t["nz"] // 4) if fast else t["nz"]
    per0 = 10 if fast else t["per_radius"]
    xy, zz = [], []
    for k in range(3):
        per = 10 * 2 ** k
        nz = max(2, nz0 * 2 ** k // 2)
        g = t["grading"] ** (1.0 / 2 ** (k - 1))
        xy.append((f"per_radius={per}", fine_dt + thermal_set(per_radius=per, nz=nz0), a / per))
        zz.append((f"nz={nz}, grading={g:.5g}", fine_dt + thermal_set(per_radius=per0, nz=nz, grading=g),
                   t["plate_thickness"] / nz))
    steps = [(f"step_multiple={m}", thermal_set(per_radius=per0, nz=nz0, step_multiple=m), float(m))
             for m in (40, 20, 10, 5)]
    # the face mesh against its Richardson limit: the held depth mesh leaves an
    # error floor against a closed form (closed_form_error_finest reports it)
    return [Sweep("mesh-xy", "thermal.per_radius", xy), Sweep("mesh-z", "thermal.nz", zz),
            Sweep("thermal-step", "thermal.step_multiple", steps)]


def cmd_converge(args) -> int:
    base_scene = scn.load(args.scene)
    name = base_scene.name
    out = out_dir(args, f"converge-{name}")
    sweeps, base = converge_plan(base_scene, args.fast)
    if not model_available(base_scene.thermal("lower")["model"]):
        raise SceneError(f"{base_scene.path}: thermal.model = \"{base_scene.thermal('lower')['model']}\": "
                         "not available in this checkout")
    for sw in sweeps:
        for label, ov, h in sw.levels:
            c = run_case(args.scene, base + ov, label)
            sw.cases.append(c)
            _say(args, f"converge {sw.name}: {label}: {c.m['status']}, {c.runtime_s:.2f} s")
    exact = closed_form(sw.cases[-1].scene) if sweeps else None
    rows, orders = converge_tables(sweeps, exact)
    folder = ResultsFolder(out)
    try:
        write_rows(folder.path("converge.csv"), rows,
                   ["sweep", "level", "dt", "mesh", "mesh_size_m", "output", "value", "reference", "error",
                    "runtime_s"])
        write_rows(folder.path("orders.csv"), orders,
                   ["sweep", "output", "reference_kind", "observed_order", "richardson_order",
                    "finest_error", "coarsest_error", "closed_form_error_finest"])
        plots = converge_plots(folder.subdir("plots"), rows, name)
        folder.path("converge.md").write_text(converge_report(name, sweeps, rows, orders, exact, args.fast, plots))
        folder.path("summary.json").write_text(json.dumps(
            {"study": "converge", "scene": name, "fast": bool(args.fast), "orders": orders,
             "closed_form": exact.get("_what") if exact else None}, indent=2, default=_json) + "\n")
    except BaseException:
        folder.discard()
        raise
    folder.commit()
    if not args.quiet:
        for o in orders:
            print(f"{o['sweep']:7s} {o['output']:16s} order {fmt(o['observed_order'], '.2f'):>6s}  "
                  f"finest error {fmt(o['finest_error'], '.3g')}")
        print(f"results in {out}/")
    failed = [c for sw in sweeps for c in sw.cases if not c.ok]
    return EXIT_FAILED if failed else EXIT_OK


def converge_tables(sweeps, exact):
    rows, orders = [], []
    for sw in sweeps:
        for out in OUTPUTS:
            vals = [c.m.get(out, float("nan")) for c in sw.cases]
            if not all(math.isfinite(v) for v in vals):
                continue
            if sw.exact and exact is not None and out in exact:
                ref, kind, p_r = exact[out], "closed form: " + exact["_what"], float("nan")
                if len(vals) >= 3:
                    p_r = richardson(vals)[0]
            elif len(vals) >= 3:
                p_r, ref = richardson(vals)
                kind = "Richardson" if math.isfinite(p_r) and p_r > 0.05 else "finest level (no asymptotic range)"
            else:
                continue
            errs = [abs(v - ref) for v in vals]
            hs = [h for _, _, h in sw.levels]
            for (label, _, h), c, v, e in zip(sw.levels, sw.cases, vals, errs):
                rows.append({"sweep": sw.name, "level": label, "dt": c.sim.dt,
                             "mesh": _mesh_label(c.scene), "mesh_size_m": h if sw.name != "dt" else float("nan"),
                             "output": out, "value": v, "reference": ref, "error": e, "runtime_s": c.runtime_s})
            # the finest level's error against a Richardson value is implied by
            # the other two; fit the order on the levels above it
            fit = fit_order(hs[:-1], errs[:-1]) if kind == "Richardson" else fit_order(hs, errs)
            scale = max(abs(ref), 1e-300)
            if out in ("peak_T_C", "end_T_C"):
                T0 = sw.cases[-1].scene.thermal("lower")["T0_C"]
                scale = max(abs(ref - T0), 1e-300)
            cf = abs(vals[-1] - exact[out]) if exact is not None and out in exact else float("nan")
            orders.append({"sweep": sw.name, "output": out, "reference_kind": kind, "observed_order": fit,
                           "closed_form_error_finest": cf,
                           "richardson_order": p_r, "finest_error": errs[-1], "coarsest_error": errs[0],
                           "finest_error_rel": errs[-1] / scale, "reference": ref})
    return rows, orders


def _mesh_label(scene) -> str:
    t = scene.thermal("lower")
    if t["model"] == "fe1d":
        return f"n_elements={t['n_elements']} grading={t['grading']:.5g}"
    if t["model"] == "axisym":
        return (f"nr={t['nr']} nz={t['nz']}" if t["nr"] else f"per_radius={t['per_radius']} nz={t['nz']}")
    if t["model"] == "fe3d":
        return f"per_radius={t['per_radius']} nz={t['nz']} step_multiple={t['step_multiple']}"
    return t["model"]


UNITS = {"peak_u_m": "m", "friction_work_J": "J", "peak_T_C": "K", "end_T_C": "K"}


def converge_plots(folder: Path, rows, name) -> list[str]:
    plt = _plt()
    outputs = [o for o in OUTPUTS if any(r["output"] == o for r in rows)]
    made = []
    for out in outputs:
        fig, ax = plt.subplots(figsize=(6, 4.2))
        for sw in dict.fromkeys(r["sweep"] for r in rows):
            sel = [r for r in rows if r["output"] == out and r["sweep"] == sw and r["error"] > 0]
            if not sel:
                continue
            ax.loglog([r["runtime_s"] for r in sel], [r["error"] for r in sel], "o-", label=f"refine {sw}")
            for r in sel:
                ax.annotate(r["level"].split(",")[0], (r["runtime_s"], r["error"]), fontsize=6,
                            xytext=(3, 3), textcoords="offset points")
        ax.set_xlabel("run time (s)")
        ax.set_ylabel(f"error of {out} ({UNITS[out]})")
        ax.set_title(f"{name}: work-precision, {out}")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fn = f"work_precision_{out}.png"
        fig.savefig(folder / fn, dpi=110)
        plt.close(fig)
        made.append(fn)
    return made


def converge_report(name, sweeps, rows, orders, exact, fast, plots) -> str:
    L = [f"# Convergence: `{name}`\n"]
    if fast:
        L.append("Fast version (shortened duration, fewer and coarser levels).\n")
    L.append("Each sweep refines one thing by a factor 2 and holds the rest:\n")
    for sw in sweeps:
        c = sw.cases[-1] if sw.cases else None
        held = (f"mesh {_mesh_label(c.scene)}" if sw.name == "dt" else f"dt = {c.sim.dt:g} s") if c else ""
        ref = (f"the closed form ({exact['_what']})" if sw.exact and exact else
               "its Richardson limit")
        L.append(f"- `{sw.name}` ({sw.param}, {len(sw.levels)} levels), held: {held}; errors against {ref}.")
    L.append("\nRichardson: p is the slope of log|v_k - v_k+1| over the levels (with three levels the "
             "classical log((v1 - v2)/(v2 - v3))/log 2) and the limit is v_n + (v_n - v_n-1)/(2^p - 1). "
             "The observed order is the least-squares slope of log(error) against log(step), for a "
             "Richardson reference over the levels above the finest (whose error it implies). Against a "
             "closed form a sweep measures its own error only while the held parameter's error is smaller: "
             "that is why an fe1d dt sweep runs on a mesh 8 times finer, and why axisym's one-direction mesh "
             "sweeps use Richardson (the other direction's error stays in every level) while the joint "
             "sweep uses the closed form. `closed_form_error_finest` in orders.csv gives the finest level's "
             "distance to the closed form in every sweep.\n")
    hdr = ["sweep", "output", "reference", "observed order", "Richardson p", "coarsest error", "finest error",
           "finest error (rel.)", "finest vs closed form"]
    L.append(md_table(hdr, [[o["sweep"], o["output"], o["reference_kind"], fmt(o["observed_order"], ".2f"),
                             fmt(o["richardson_order"], ".2f"), fmt(o["coarsest_error"], ".3g"),
                             fmt(o["finest_error"], ".3g"), fmt(o["finest_error_rel"], ".2e"),
                             fmt(o["closed_form_error_finest"], ".3g")] for o in orders]))
    L.append("## Levels\n")
    hdr = ["sweep", "level", "dt (s)", "mesh", "run time (s)"] + [o for o in OUTPUTS]
    body = []
    for sw in sweeps:
        for (label, _, _), c in zip(sw.levels, sw.cases):
            body.append([sw.name, label, fmt(c.sim.dt, ".4g"), _mesh_label(c.scene), fmt(c.runtime_s, ".2f")]
                        + [fmt(c.m.get(o, float("nan")), ".6g") for o in OUTPUTS])
    L.append(md_table(hdr, body))
    L.append("Peak displacement is not monotone in dt (a stick-slip event can move by a step), so its order "
             "is the least reliable; friction work and temperatures are the convergence measures.\n")
    if plots:
        L.append("## Work-precision (error against run time)\n")
        L += [f"![{p}](plots/{p})" for p in plots]
    return "\n".join(L) + "\n"


# ======================================================================================
# fpd stability (coupling/stability.py)
# ======================================================================================
def cmd_stability(args) -> int:
    from .stability import cmd_stability as run
    return run(args)
