"""Results folders: written atomically, complete even after a failure.

Everything goes into a temporary folder beside DIR that is renamed into place
at the end; with --force the old DIR is kept until the new one is complete.
"""
from __future__ import annotations

import json
import math
import os
import shutil
from pathlib import Path

import numpy as np

from .history import CsvWriter, StreamHistory
from .scene import Scene, SceneError, to_toml

from fpd import __version__ as VERSION


def check_out_dir(out: Path, force: bool) -> None:
    if out.exists() and not out.is_dir():
        raise SceneError(f"{out}: exists and is not a folder (--out)")
    if out.exists() and any(out.iterdir()) and not force:
        raise SceneError(f"{out}: results folder exists and is not empty; use --force to replace it")


class ResultsFolder:
    """A temporary folder beside ``out``; ``commit()`` moves it into place."""

    def __init__(self, out: Path):
        self.out = Path(out)
        self.out.parent.mkdir(parents=True, exist_ok=True)
        self.tmp = self.out.parent / f".{self.out.name}.partial-{os.getpid()}"
        if self.tmp.exists():
            shutil.rmtree(self.tmp)
        self.tmp.mkdir()

    def path(self, *parts) -> Path:
        """A file path inside the folder (its parent created)."""
        p = self.tmp.joinpath(*parts)
        p.parent.mkdir(parents=True, exist_ok=True)
        return p

    def subdir(self, name: str) -> Path:
        p = self.tmp / name
        p.mkdir(parents=True, exist_ok=True)
        return p

    def commit(self) -> Path:
        old = None
        if self.out.exists():
            old = self.out.parent / f".{self.out.name}.old-{os.getpid()}"
            os.replace(self.out, old)
        try:
            os.replace(self.tmp, self.out)
        except BaseException:
            if old is not None:          # put the old results back
                os.replace(old, self.out)
            raise
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
        return self.out

    def discard(self) -> None:
        shutil.rmtree(self.tmp, ignore_errors=True)


def write_csv(path: Path, result, chunk: int = 4096) -> None:
    """timeseries.csv of an in-memory result: one row per recorded step, units
    in the column names (a streamed result has written it as it ran), in
    blocks of ``chunk`` rows: a 10^6-step run stays well under 1 GiB."""
    data = result.data
    with open(path, "w", newline="") as fh:
        w = CsvWriter(fh, result.columns)
        for s in range(0, data.shape[0], chunk):
            w.write(data[s:s + chunk])


def _f(x):
    x = float(x)
    return x if math.isfinite(x) else None


def summary(scene: Scene, result, sim) -> dict:
    d = scene.data
    s = {"status": result.status, "message": result.message, "scene": scene.name,
         "models": {"mechanics": d["mechanics"]["model"] if sim.mechanics else "none",
                    "thermal_lower": d["thermal"]["lower"]["model"],
                    "thermal_upper": d["thermal"]["upper"]["model"],
                    "friction_lower": d["friction"]["lower"]["law"],
                    "friction_upper": d["friction"]["upper"]["law"],
                    "coupling": d["coupling"]["scheme"]},
         "steps": int(getattr(result, "steps", result.n_rows - 1)),
         "dt_s": sim.dt, "runtime_s": result.runtime_s, "version": VERSION}
    if result.n_rows == 0:
        return s
    st = result.stats          # max, min, last row: the same in memory or streamed
    if "u_m" in result:
        s["peak_u_m"] = _f(st.peak_abs("u_m"))
        s["residual_u_m"] = _f(st.final("u_m"))
        s["peak_F_N"] = _f(st.peak_abs("F_N"))
        s["friction_work_J"] = {"lower": _f(st.final("W1_J")), "upper": _f(st.final("W2_J"))}
        e_in = st.final("E_input_J")
        out = st.final("E_kin_J") + st.final("E_pot_J") + st.final("W1_J") + st.final("W2_J")
        if "E_reseat_J" in result:
            out += st.final("E_reseat_J")
            s["reseat_loss_J"] = _f(st.final("E_reseat_J"))
        s["input_work_J"] = _f(e_in)
        s["energy_residual_rel"] = _f(abs(e_in - out) / abs(e_in)) if e_in else 0.0
    if "T1_C" in result:
        s["peak_T1_C"] = _f(st.peak("T1_C"))
        s["peak_T2_C"] = _f(st.peak("T2_C"))
        s["heat"] = heat_ledger(result, sim)
        s["heat_residual_rel"] = s["heat"]["residual_rel"]
    if d["loading"]["kind"] == "heat" and d["loading"]["reference"] != "none" and result.n_rows > 1:
        s["reference"] = closed_form_check(result, sim)
    if "mu1" in result:
        s["min_mu1"] = _f(st.low("mu1"))
        s["min_mu2"] = _f(st.low("mu2"))
    if d["coupling"]["scheme"] == "iterated":
        s["coupling_iterations"] = {"total": int(result.iterations), "max_per_step": int(result.max_iterations)}
    s.update(result.info)
    return s


def closed_form_check(result, sim) -> dict:
    """Thermal-only scenes: the surface temperature of the heated plate
    against the closed form the scene names (model.md section 7)."""
    from fpd.thermal import exact

    ld = sim.scene["loading"]
    side = 0 if ld["plate"] in ("lower", "both") else 1
    p = sim.plate_params[side]
    q, kappa = ld["flux_W_m2"], p.diffusivity
    m = result.n_rows - 1              # rows after the initial one
    pick = np.unique(np.linspace(0, m - 1, min(m, 50)).astype(int))
    rows = result.rows_at(1 + pick)    # in memory, or read back from a streamed run's spill
    t = rows[:, result.columns.index("t_s")]
    T = rows[:, result.columns.index(f"T{side + 1}_C")]
    kind = ld["reference"]
    if kind == "halfspace":
        rise = exact.halfspace_flux_surface(t, q, p.k, kappa)
        what = "surface temperature, semi-infinite solid, constant flux"
    elif kind == "slab":
        rise = np.array([exact.slab_flux(0.0, ti, q, p.k, kappa, p.plate_thickness)[0] for ti in t])
        what = "heated-face temperature, slab with an adiabatic back face"
    else:
        rise = np.asarray(exact.disk_mean(t, q, p.a_contact_m, p.k, kappa))
        what = "footprint-mean temperature, disk source on a half-space"
    err = T - (p.T0_C + rise)
    return {"closed_form": kind, "quantity": what, "T_end_C": float(T[-1]),
            "T_exact_end_C": float(p.T0_C + rise[-1]), "error_end_K": float(err[-1]),
            "max_abs_error_K": float(np.max(np.abs(err))), "samples": int(len(t))}


def heat_ledger(result, sim) -> dict:
    """Per plate: heat delivered = stored + lost; friction work x share = delivered."""
    out = {"plates": {}}
    worst = 0.0
    for i, (side, plate) in enumerate(zip(("lower", "upper"), result.plates)):
        if plate is None:
            continue
        q_in, st, lo = plate.heat_in(), plate.stored_heat(), plate.heat_lost()
        res = abs(q_in - st - lo) / q_in if q_in else abs(st - lo)
        entry = {"heat_in_J": q_in, "stored_J": st, "lost_J": lo, "residual_rel": res}
        fixed_point = sim.plate_params[i].model == "fe1d" and sim.plate_params[i].source == "fixed-point"
        if fixed_point:
            # the column at r0 receives the flux only while the footprint covers it
            entry["work_vs_heat"] = "not compared: fixed-point column heated only while covered"
        elif sim.mechanics is not None and result.status == "ok":
            W = result.stats.final(f"W{i + 1}_J") * sim.plate_params[i].heat_share
            entry["friction_heat_J"] = W
            entry["work_vs_heat_rel"] = abs(W - q_in) / W if W else abs(q_in)
            res = max(res, entry["work_vs_heat_rel"])
        worst = max(worst, res)
        out["plates"][side] = entry
    out["residual_rel"] = worst
    return out


def needs_rows(scene: Scene) -> bool:
    """Does the summary read rows back (the closed-form check of a heat scene)?"""
    ld = scene["loading"]
    return ld["kind"] == "heat" and ld["reference"] != "none"


def stream_history(folder: ResultsFolder, scene: Scene, **kw):
    """The history ``fpd run`` gives ``simulate``: timeseries.csv written into
    the folder as the run goes (plus a raw spill, removed by write_all, when
    the summary reads rows back)."""
    spill = folder.path(".history.f64") if needs_rows(scene) else None
    kw.setdefault("plots", bool(scene["output"]["plots"]))
    return StreamHistory(folder.path("timeseries.csv"), spill_path=spill, **kw)


def write_all(folder: ResultsFolder, scene: Scene, result, sim, plots: bool = True) -> dict:
    """Everything but what the run streamed: timeseries.csv (unless streamed
    already), scene.toml, summary.json, plots/."""
    if not result.streamed:
        write_csv(folder.path("timeseries.csv"), result)
    folder.path("scene.toml").write_text(to_toml(scene))
    s = summary(scene, result, sim)
    if result.streamed:
        result.history.discard_spill()
    if plots and result.n_rows > 1:
        from .plots import make_plots
        s["plots"] = make_plots(folder.subdir("plots"), result.plot_view(), scene)
    folder.path("summary.json").write_text(json.dumps(s, indent=2) + "\n")
    return s
