"""``fpd converge``: dt, mesh and thermal-step sweeps of a scene, observed
orders against a closed form or Richardson extrapolation. The shared runner
is studies/study_runner.py.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fpd.schema import scene as scn
from fpd.outputs.output import ResultsFolder
from fpd.schema.scene import SceneError
from .study_runner import (EXIT_FAILED, EXIT_OK, _json, _plt, _say, fmt, md_table, model_available, out_dir,
                           run_case, thermal_set, write_rows)


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
    """fe3d: the face mesh (per_radius 10, 20, 40 elements per
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
