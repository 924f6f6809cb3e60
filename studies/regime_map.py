"""``fpd map [--quick] --out DIR``: the regime map, a packaged sweep.

Where does each modelling choice change the answer? The default device (DFP,
R1 = R2 = 2.2 m, pad 0.25 m wide, 100 t, kumar2015 mu_ref = 0.06) is run over
pad aspect h/D (the pad's height over its diameter, its steel mass following)
and intensity, in two families: cosine velocity pulses (1 s, amplitude V) and
FEMA P695 far-field components scaled to a target PGA (two components in
--quick, the 44 otherwise; the median over components is mapped). Each cell
runs these variants (dt = 1 ms and 0.5 ms):

    A  two-phase + fe1d, dt          B  two-phase + fe1d, dt/2
    C  seated + fe1d, dt             E  seated + fe1d, dt/2
    D  two-phase + lumped, dt        F  two-phase + lumped, dt/2
    G  two-phase + fe1d, dt, mu_ref = 0.6   H  the same at dt/2

and maps, with the 1 %, 5 % and 20 % contours:

- rocking: the share of the peak pad tilt |beta| that survives dt -> 0
  (Richardson: beta* = 2 beta(dt/2) - beta(dt); a tilt that is a splitting
  artefact is proportional to dt and gives 0, a real rocking episode gives 1),
  at mu_ref = 0.06 (A, B) and at a high-friction 0.6 (G, H), where the pad
  can stay stuck long enough to rock (docs/two_phase.md section 6);
- two-phase against seated: |u_A - u_C| / u_C in peak displacement and the
  same in friction work;
- lumped against fe1d: (dT_A - dT_D) / dT_A in the peak surface temperature
  rise, and |u_D - u_A| / u_A in peak displacement (through mu(T)).

Each difference is also computed at dt/2 (B, E, F); their distance is the
cell's error bar, and a cell whose bar straddles a contour is marked.
"""
from __future__ import annotations

import copy
import json
import math
import os
import statistics
import time
from pathlib import Path

import numpy as np

from fpd.schema import scene as scn
from fpd.schema.scene import SceneError
from .sweep import EXIT_MEMBERS, STORE, Member, Sweep, finalize, run_sweep

LEVELS = (0.01, 0.05, 0.20)
DT = 1e-3
STEEL = 7850.0
VARIANTS = {   # name: (mechanics, thermal, dt factor, mu_ref)
    "A": ("two-phase", "fe1d", 1.0, 0.06), "B": ("two-phase", "fe1d", 0.5, 0.06),
    "C": ("seated", "fe1d", 1.0, 0.06), "E": ("seated", "fe1d", 0.5, 0.06),
    "D": ("two-phase", "lumped", 1.0, 0.06), "F": ("two-phase", "lumped", 0.5, 0.06),
    "G": ("two-phase", "fe1d", 1.0, 0.6), "H": ("two-phase", "fe1d", 0.5, 0.6),
}
GRIDS = {
    "quick": {"h_over_D": [0.2, 0.4, 0.8, 1.6, 3.2], "pulse_V": [0.2, 0.5, 1.0, 2.0],
              "pga_g": [0.1, 0.3, 0.6, 1.0], "components": [(1, "a"), (12, "b")],
              "pulse_s": 4.0, "record_s": 10.0},
    "full": {"h_over_D": [0.2, 0.3, 0.4, 0.6, 0.8, 1.2, 1.6, 2.4, 3.2],
             "pulse_V": [0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0],
             "pga_g": [0.05, 0.1, 0.2, 0.3, 0.45, 0.6, 0.8, 1.0], "components": None,
             "pulse_s": 8.0, "record_s": None},
}


def _members(grid: dict, base: dict, base_path: str) -> list[Member]:
    D = base["device"]["pad_diameter"]
    out = []
    loads = [("pulse", V, {"kind": "pulse", "shape": "cosine", "velocity_mps": V, "period_s": 1.0, "t0_s": 0.5,
                           "duration_s": grid["pulse_s"]}, None) for V in grid["pulse_V"]]
    if grid["pga_g"]:
        from fpd.loading import p695
        comps = grid["components"] or p695.members("p695-far-field")
        for pga in grid["pga_g"]:
            for rid, comp in comps:
                loads.append(("p695", pga, {"kind": "record", "record_set": "p695-far-field", "record_id": rid,
                                            "component": comp, "target_pga_g": pga}, f"{rid}{comp}"))
    for hD in grid["h_over_D"]:
        h = hD * D
        for family, level, loading, comp in loads:
            for v, (mech, therm, f, mu) in VARIANTS.items():
                raw = copy.deepcopy(base)
                raw["device"]["pad_height"] = h
                raw["device"]["pad_mass"] = STEEL * math.pi * (D / 2) ** 2 * h
                raw["loading"] = dict(loading)
                raw["mechanics"] = {"model": mech}
                raw.setdefault("thermal", {})["model"] = therm
                raw["friction"]["mu_ref"] = mu
                raw.setdefault("solver", {})["dt"] = DT * f
                if family == "p695" and grid["record_s"]:
                    raw["solver"]["duration"] = grid["record_s"]
                raw["output"] = {"plots": False, "vtk_every": 0}
                axes = {"map.family": family, "map.h_over_D": hD, "map.intensity": level,
                        "map.component": comp, "map.variant": v}
                out.append(Member("", axes, raw, base_path))
    return out


def cmd_map(args) -> int:
    if args.workers is not None and args.workers < 1:
        raise SceneError(f"--workers {args.workers}: must be >= 1")
    kind = "quick" if args.quick else "full"
    grid = GRIDS[kind]
    out = Path(args.out) if args.out else Path("results") / f"map-{kind}"
    from fpd.outputs.claim import hold
    hold(args, out, check=False)    # one writer of DIR at a time (outputs/claim.py)
    if out.exists() and not out.is_dir():
        raise SceneError(f"{out}: exists and is not a folder (--out)")
    if out.is_dir() and any(out.iterdir()) and not (out / "sweep").is_dir() and not args.force:
        raise SceneError(f"{out}: folder exists and is not a map's; use --force to replace it")
    from fpd.loading import p695
    if not p695.available():
        sys_msg = "fpd map: the FEMA P695 records are not installed (pip install 'fpd-sim[records]'); " \
                  "mapping the pulses only"
        print(sys_msg)
        grid = dict(grid, pga_g=[])
    base_path = scn.SCENES_DIR / "default.toml"
    base = scn.read_toml(base_path)
    sw = Sweep(f"<fpd map --{kind}>" if args.quick else "<fpd map>", f"map-{kind}",
               "the regime map: pad aspect x intensity, eight model variants per cell",
               base_path, "product", {}, {}, "summary")
    t0 = time.perf_counter()
    sw.members = finalize(sw, _members(grid, base, str(base_path)))
    sw.axes = {"map.family": ["pulse", "p695"], "map.h_over_D": grid["h_over_D"],
               "map.intensity": grid["pulse_V"] + grid["pga_g"], "map.variant": list(VARIANTS)}
    code = run_sweep(sw, out / "sweep", getattr(args, "workers", None), getattr(args, "scheduler", None),
                     args.force, args.quiet)
    if code not in (0, EXIT_MEMBERS):     # failed members are cells of the map too
        return code
    store = out / "sweep" / STORE
    res = {}
    for m in sw.members:
        try:
            res[m.id] = json.loads((store / f"{m.hash}.json").read_text())
        except (OSError, ValueError):
            res[m.id] = {"status": "missing", "summary": {}}
    cells = reduce(sw.members, res, grid)
    wall = time.perf_counter() - t0
    from fpd.coupling.recording import signals_held
    figs = figures(cells, grid, out)
    with signals_held():
        _atomic_text(out / "map.md", report(cells, grid, kind, wall, figs, sw, res))
        _atomic_text(out / "map.json", json.dumps(_jsonable(cells), indent=1) + "\n")
    if not args.quiet:
        print(f"map: {len(sw.members)} runs, {wall:.0f} s; report {out / 'map.md'}")
    return 0


def _atomic_text(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    tmp.write_text(text)
    os.replace(tmp, path)


def _jsonable(x):
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


# -- from runs to cells ---------------------------------------------------------------------
def _get(r, key):
    if r is None or r.get("status") != "ok":
        return math.nan
    v = r["summary"]
    for k in key.split("."):
        v = v.get(k) if isinstance(v, dict) else None
    return float(v) if isinstance(v, (int, float)) and v is not None else math.nan


def _rel(a, b):
    return abs(a - b) / abs(b) if b else math.nan


def _metrics(runs: dict, T0: float) -> dict:
    """The mapped quantities of one load case, from its variants' results."""
    g = lambda v, k: _get(runs.get(v), k)  # noqa: E731
    m = {}
    for name, (a, b) in {"tilt_share_mu006": ("A", "B"), "tilt_share_mu06": ("G", "H")}.items():
        ta, tb = g(a, "peak_beta_rad"), g(b, "peak_beta_rad")
        m[name] = min(max(2 * tb - ta, 0.0) / tb, 1.0) if tb > 0 else (0.0 if tb == 0 else math.nan)
        m[name + "_beta_mrad"] = 1e3 * tb
    for name, (p, q), key in (("u_2p_vs_seated", ("A", "C"), "peak_u_m"),
                              ("W_2p_vs_seated", ("A", "C"), "friction_work_total_J"),
                              ("u_lumped_vs_fe1d", ("D", "A"), "peak_u_m")):
        m[name] = _rel(g(p, key), g(q, key))
        fine = {"A": "B", "C": "E", "D": "F"}
        m[name + "_fine"] = _rel(g(fine[p], key), g(fine[q], key))
    dA, dD = g("A", "peak_T1_C") - T0, g("D", "peak_T1_C") - T0
    dB, dF = g("B", "peak_T1_C") - T0, g("F", "peak_T1_C") - T0
    m["T_lumped_vs_fe1d"] = (dA - dD) / dA if dA > 0 else math.nan
    m["T_lumped_vs_fe1d_fine"] = (dB - dF) / dB if dB > 0 else math.nan
    m["dT_fe1d_K"], m["dT_lumped_K"] = dA, dD
    m["peak_u_mm"] = 1e3 * g("A", "peak_u_m")
    m["capacity_ratio"] = g("A", "capacity_ratio")          # 1: the slide reached a rim
    m["stuck"] = 1.0 if m["peak_u_mm"] < 1e-3 else 0.0       # the bearing never slid: nothing to compare
    m["failed"] = sorted(v for v, r in runs.items() if r.get("status") != "ok")
    m["overturned"] = 1.0 if any("overturned" in str(r.get("message", "")) for r in runs.values()) else 0.0
    return m


def reduce(members, res, grid) -> dict:
    """cells[family][(h_over_D, intensity)] = metrics (P695: median over components)."""
    T0 = 20.0
    groups = {}
    for m in members:
        a = m.axes
        key = (a["map.family"], a["map.h_over_D"], a["map.intensity"], a["map.component"])
        groups.setdefault(key, {})[a["map.variant"]] = res[m.id]
        T0 = m.scene["thermal"]["lower"]["T0_C"]
    per_case = {k: _metrics(v, T0) for k, v in groups.items()}
    cells = {"pulse": {}, "p695": {}}
    for (fam, hD, lev, comp), mt in per_case.items():
        cells[fam].setdefault((hD, lev), []).append(mt)
    out = {}
    for fam, d in cells.items():
        out[fam] = {}
        for key, lst in d.items():
            agg = {}
            for k in lst[0]:
                if k == "failed":
                    agg[k] = sorted({f for x in lst for f in x[k]})
                    continue
                vals = [x[k] for x in lst if not math.isnan(x[k])]
                agg[k] = statistics.median(vals) if vals else math.nan
                if len(lst) > 1 and len(vals) > 1:
                    agg[k + "_spread"] = (min(vals), max(vals))
            agg["n"] = len(lst)
            out[fam][key] = agg
    return out


# -- figures and report ---------------------------------------------------------------------
PANELS = {
    "rocking": (("tilt_share_mu006", "tilt surviving dt -> 0, mu_ref = 0.06"),
                ("tilt_share_mu06", "tilt surviving dt -> 0, mu_ref = 0.6")),
    "two-phase-vs-seated": (("u_2p_vs_seated", "two-phase vs seated: peak displacement"),
                            ("W_2p_vs_seated", "two-phase vs seated: friction work")),
    "lumped-vs-fe1d": (("T_lumped_vs_fe1d", "lumped vs fe1d: peak surface temperature rise"),
                       ("u_lumped_vs_fe1d", "lumped vs fe1d: peak displacement (mu(T))")),
}


def _grid_values(cells, fam, key, grid):
    ys = grid["h_over_D"]
    xs = grid["pulse_V"] if fam == "pulse" else grid["pga_g"]
    Z = np.full((len(ys), len(xs)), np.nan)
    E = np.full_like(Z, np.nan)
    S = np.zeros_like(Z, dtype=bool)
    O = np.zeros_like(Z, dtype=bool)
    for i, y in enumerate(ys):
        for j, x in enumerate(xs):
            c = cells[fam].get((y, x))
            if c is None:
                continue
            S[i, j] = c.get("stuck", 0.0) >= 0.5 and "share" not in key
            O[i, j] = c.get("overturned", 0.0) > 0
            Z[i, j] = abs(c.get(key, np.nan))
            fine = c.get(key + "_fine")
            if fine is not None and not math.isnan(fine):
                E[i, j] = abs(abs(fine) - Z[i, j])
    _grid_values.stuck, _grid_values.overturned = S, O
    return xs, ys, Z, E


def _pct(z):
    return f"{100 * z:.0f}%" if 100 * z >= 10 else f"{100 * z:.2g}%"


def _pulse_pga(V, Tp=1.0):
    """Peak ground acceleration (g) of the 1 s cosine velocity pulse V/2 (1 - cos 2 pi t/Tp)."""
    return math.pi * V / Tp / 9.81


def rocking_threshold_g(h_over_D, D=0.25):
    """The closed form: a pad at rest rocks on its corner when the ground
    acceleration exceeds g X0/Z0 (~ (2a/h') g, docs/two_phase.md), in g."""
    from fpd.coupling.build import geometry_of
    from fpd.mechanics.two_phase import rocking_threshold
    h = h_over_D * D
    sc = scn.load("default", [f"device.pad_height={h!r}", f"device.pad_mass={STEEL * math.pi * (D / 2) ** 2 * h!r}"])
    g = geometry_of(sc)
    return rocking_threshold(g) / g.g


def _threshold_line(ax, fam, xs, ys, grid):
    """Where the closed form puts the rocking onset, on the categorical intensity axis."""
    pga = [_pulse_pga(x) for x in xs] if fam == "pulse" else list(xs)
    px, py = [], []
    for i, y in enumerate(ys):
        thr = rocking_threshold_g(y)
        if pga[0] <= thr <= pga[-1]:
            px.append(float(np.interp(math.log(thr), np.log(pga), np.arange(len(xs)))))
            py.append(i)
        elif thr < pga[0]:
            px.append(-0.5)
            py.append(i)
    if px:
        ax.plot(px, py, "w--", lw=1.2, marker="|", ms=10, label="rocking onset from rest, g X0/Z0")
        ax.legend(loc="lower left", fontsize=7, framealpha=0.6)


def _straddles(z, e):
    return [lv for lv in LEVELS if not (math.isnan(z) or math.isnan(e)) and (z - e) < lv < (z + e)]


def figures(cells, grid, out: Path) -> list[str]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    fams = [f for f in ("pulse", "p695") if cells.get(f)]
    names = []
    for fig_name, panels in PANELS.items():
        fig, axs = plt.subplots(len(panels), len(fams), figsize=(5.2 * len(fams), 4.0 * len(panels)),
                                squeeze=False, constrained_layout=True)
        for r, (key, title) in enumerate(panels):
            for c, fam in enumerate(fams):
                ax = axs[r][c]
                xs, ys, Z, E = _grid_values(cells, fam, key, grid)
                Zc = np.clip(Z, 1e-4, 1.0)
                xi, yi = np.arange(len(xs)), np.arange(len(ys))
                mesh = ax.pcolormesh(xi, yi, np.ma.masked_invalid(Zc), norm=LogNorm(1e-4, 1.0), cmap="viridis",
                                     shading="nearest")
                if np.isfinite(Zc).sum() >= 4 and len(xs) > 1 and len(ys) > 1:
                    cs = ax.contour(xi, yi, np.ma.masked_invalid(Zc), levels=list(LEVELS),
                                    colors=["white", "orange", "red"], linewidths=1.6)
                    ax.clabel(cs, fmt={lv: f"{100 * lv:g} %" for lv in LEVELS}, fontsize=8)
                for i in range(len(ys)):
                    for j in range(len(xs)):
                        z, e = Z[i, j], E[i, j]
                        if math.isnan(z):
                            stuck = _grid_values.stuck[i, j]
                            label = "no slip" if stuck else "overturned" if _grid_values.overturned[i, j] else "failed"
                            ax.text(j, i, label, ha="center", va="center",
                                    fontsize=7, color="gray" if stuck else "red")
                            continue
                        txt = _pct(z)
                        if _straddles(z, e):
                            txt += "\n±" + f"{100 * e:.1g}"
                        ax.text(j, i, txt, ha="center", va="center", fontsize=7,
                                color="black" if Zc[i, j] > 0.03 else "white")
                if key.startswith("tilt_share"):
                    _threshold_line(ax, fam, xs, ys, grid)
                ax.set_xticks(xi, [f"{x:g}" for x in xs] if fam != "pulse" else
                              [f"{x:g}\n({_pulse_pga(x):.2g} g)" for x in xs])
                ax.set_yticks(yi, [f"{y:g}" for y in ys])
                ax.set_xlabel("1 s cosine pulse: velocity amplitude V (m/s) (peak ground acceleration)"
                              if fam == "pulse"
                              else "target PGA (g), P695 far-field, median of components")
                ax.set_ylabel("pad aspect h/D")
                ax.set_title(title, fontsize=9)
                fig.colorbar(mesh, ax=ax, label="relative difference" if "share" not in key else "share")
        fig.suptitle(f"regime map: {fig_name.replace('-', ' ')} (contours 1 %, 5 %, 20 %; ± = dt error bar "
                     "where it straddles a contour)", fontsize=10)
        name = f"map-{fig_name}.png"
        tmp = out / f".{name}.tmp-{os.getpid()}.png"
        fig.savefig(tmp, dpi=90)
        plt.close(fig)
        os.replace(tmp, out / name)
        names.append(name)
    return names


def _where(cells, fam, key, grid, level):
    xs, ys, Z, E = _grid_values(cells, fam, key, grid)
    hits = [(ys[i], xs[j]) for i in range(len(ys)) for j in range(len(xs)) if Z[i, j] >= level]
    return hits, Z, E


def report(cells, grid, kind, wall, figs, sw, res) -> str:
    n_bad = sum(1 for r in res.values() if r.get("status") != "ok")
    L = [f"# Regime map ({kind})", "",
         f"Default device (DFP R1 = R2 = 2.2 m, pad diameter D = 0.25 m, 100 t, kumar2015 mu_ref = 0.06), "
         f"pad aspect h/D in {grid['h_over_D']} (steel pad mass following h); "
         f"{len(sw.members)} runs ({n_bad} not ok: "
         f"{', '.join(sorted({str(r.get('message', ''))[:90] for r in res.values() if r.get('status') != 'ok'})) or 'none'}); "
         f"their own wall time summed {sum(r.get('wall_s', 0.0) for r in res.values()):.0f} s; this invocation "
         f"{wall:.0f} s.",
         f"Intensity: 1 s cosine velocity pulses V = {grid['pulse_V']} m/s ({grid['pulse_s']:g} s runs)"
         + (f"; FEMA P695 far-field components "
            f"{'all 44' if not grid['components'] else ', '.join(f'{r}{c}' for r, c in grid['components'])} "
            f"scaled (one factor for the set) to a median PGA of {grid['pga_g']} g"
            + (f", first {grid['record_s']:g} s of each" if grid['record_s'] else "") + " (cell = median of the "
            "components)" if grid["pga_g"] else "") + ".",
         f"Resolution: dt = {DT * 1e3:g} ms with every difference recomputed at dt/2 = {DT * 5e2:g} ms "
         "(the error bar of a cell is the distance between the two; cells whose bar straddles a contour "
         "carry it in the figures); fe1d plates at the default mesh.", ""]
    for f in figs:
        L.append(f"![{f}]({f})")
    L.append("")
    for fig_name, panels in PANELS.items():
        L += [f"## {fig_name.replace('-', ' ')}", ""]
        if fig_name == "rocking":
            L += ["Closed form (docs/two_phase.md): a pad at rest rocks on its corner above g X0/Z0 = "
                  + ", ".join(f"{rocking_threshold_g(y):.3g} g (h/D = {y:g})" for y in grid["h_over_D"])
                  + "; the dashed line in the figure. A sliding pad never starts rocking, so at mu_ref = 0.06 "
                  "(the bearing slides from ~0.06 (R1 + R2)/L g) the pad cannot reach it.", ""]
        for key, title in panels:
            for fam in cells:
                if not cells[fam]:
                    continue
                hits20, Z, E = _where(cells, fam, key, grid, 0.20)
                hits5, _, _ = _where(cells, fam, key, grid, 0.05)
                hits1, _, _ = _where(cells, fam, key, grid, 0.01)
                fin = Z[np.isfinite(Z)]
                err = E[np.isfinite(E)]
                if not fin.size:
                    L.append(f"- {title}, {fam}: no finished cells")
                    continue
                near = sum(1 for i in range(Z.shape[0]) for j in range(Z.shape[1]) if _straddles(Z[i, j], E[i, j]))
                L.append(f"- **{title}**, {fam}: {100 * fin.min():.3g} % to {100 * fin.max():.3g} % "
                         f"(median {100 * float(np.median(fin)):.3g} %); >= 1 %: {len(hits1)}, >= 5 %: "
                         f"{len(hits5)}, >= 20 %: {len(hits20)} of {fin.size} cells"
                         + (f" (>= 20 % at h/D, intensity = {', '.join(f'({a:g}, {b:g})' for a, b in hits20[:8])}"
                            f"{' ...' if len(hits20) > 8 else ''})" if hits20 else "")
                         + (f"; dt error bar max {100 * err.max():.2g} % (median {100 * float(np.median(err)):.2g} %)"
                            if err.size else "") + (f"; {near} cells straddle a contour" if near else ""))
        L.append("")
    L += ["## Numbers behind the map", "",
          "| family | h/D | intensity | peak u (mm) | dT fe1d (K) | dT lumped (K) | beta(dt/2) mrad mu .06 | "
          "beta(dt/2) mrad mu .6 | tilt share .06 | tilt share .6 | u 2p/seated | W 2p/seated | T lumped/fe1d | "
          "u lumped/fe1d | capacity ratio | not ok |", "|" + "---|" * 16]
    for fam, d in cells.items():
        for (hD, lev), c in sorted(d.items()):
            def p(k):
                v = c.get(k, math.nan)
                return "-" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{100 * v:.3g} %"

            def n(k, fmt=".3g"):
                v = c.get(k, math.nan)
                return "-" if isinstance(v, float) and math.isnan(v) else format(v, fmt)
            L.append(f"| {fam} | {hD:g} | {lev:g} | {n('peak_u_mm')} | {n('dT_fe1d_K')} | {n('dT_lumped_K')} | "
                     f"{n('tilt_share_mu006_beta_mrad')} | {n('tilt_share_mu06_beta_mrad')} | {p('tilt_share_mu006')} | "
                     f"{p('tilt_share_mu06')} | {p('u_2p_vs_seated')} | {p('W_2p_vs_seated')} | "
                     f"{p('T_lumped_vs_fe1d')} | {p('u_lumped_vs_fe1d')} | {n('capacity_ratio')} | "
                     f"{','.join(c['failed']) or ''} |")
    L += ["", "Variants: A two-phase+fe1d dt, B the same at dt/2, C seated+fe1d dt, E at dt/2, D two-phase+lumped "
          "dt, F at dt/2, G two-phase+fe1d mu_ref = 0.6 dt, H at dt/2. Every run is a row of sweep/sweep.csv "
          "(map.* columns say which cell and variant).", ""]
    return "\n".join(L)
