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

from mechanics.seated import PHASES

from .scene import Scene, SceneError, to_toml

VERSION = "0.1.0"


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
    """timeseries.csv: one row per recorded step, units in the column names.

    Written in blocks of `chunk` rows, each formatted by one %-operation
    (the bytes np.savetxt wrote, ~10% faster, and without the object copy of
    the whole history: a 10^6-step run stays well under 1 GiB)."""
    cols = result.columns
    data = result.data
    j = cols.index("phase") if "phase" in cols else -1
    rowfmt = ",".join("%s" if c == "phase" else "%.10g" for c in cols) + "\n"
    names = np.array(PHASES, dtype=object)
    with open(path, "w", newline="") as fh:
        fh.write(",".join(cols) + "\n")
        for s in range(0, data.shape[0], chunk):
            block = data[s:s + chunk]
            rows = block.tolist()
            if j >= 0:
                for row, name in zip(rows, names[np.nan_to_num(block[:, j]).astype(int)].tolist()):
                    row[j] = name
            fh.write((rowfmt * len(rows)) % tuple(x for row in rows for x in row))


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
    if "u_m" in result:
        u = result["u_m"]
        s["peak_u_m"] = _f(np.max(np.abs(u)))
        s["residual_u_m"] = _f(u[-1])
        s["peak_F_N"] = _f(np.max(np.abs(result["F_N"])))
        s["friction_work_J"] = {"lower": _f(result["W1_J"][-1]), "upper": _f(result["W2_J"][-1])}
        e_in = result["E_input_J"][-1]
        out = result["E_kin_J"][-1] + result["E_pot_J"][-1] + result["W1_J"][-1] + result["W2_J"][-1]
        if "E_reseat_J" in result:
            out += result["E_reseat_J"][-1]
            s["reseat_loss_J"] = _f(result["E_reseat_J"][-1])
        s["input_work_J"] = _f(e_in)
        s["energy_residual_rel"] = _f(abs(e_in - out) / abs(e_in)) if e_in else 0.0
    if "T1_C" in result:
        s["peak_T1_C"] = _f(np.max(result["T1_C"]))
        s["peak_T2_C"] = _f(np.max(result["T2_C"]))
        s["heat"] = heat_ledger(result, sim)
        s["heat_residual_rel"] = s["heat"]["residual_rel"]
    if d["loading"]["kind"] == "heat" and d["loading"]["reference"] != "none" and result.n_rows > 1:
        s["reference"] = closed_form_check(result, sim)
    if "mu1" in result:
        s["min_mu1"] = _f(np.min(result["mu1"]))
        s["min_mu2"] = _f(np.min(result["mu2"]))
    if d["coupling"]["scheme"] == "iterated":
        s["coupling_iterations"] = {"total": int(result.iterations), "max_per_step": int(result.max_iterations)}
    s.update(result.info)
    return s


def closed_form_check(result, sim) -> dict:
    """Thermal-only scenes: the surface temperature of the heated plate
    against the closed form the scene names (model.md section 7)."""
    from thermal import exact

    ld = sim.scene["loading"]
    side = 0 if ld["plate"] in ("lower", "both") else 1
    p = sim.plate_params[side]
    q, kappa = ld["flux_W_m2"], p.diffusivity
    t = result["t_s"][1:]
    T = result[f"T{side + 1}_C"][1:]
    pick = np.unique(np.linspace(0, len(t) - 1, min(len(t), 50)).astype(int))
    t, T = t[pick], T[pick]
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
            W = result[f"W{i + 1}_J"][-1] * sim.plate_params[i].heat_share
            entry["friction_heat_J"] = W
            entry["work_vs_heat_rel"] = abs(W - q_in) / W if W else abs(q_in)
            res = max(res, entry["work_vs_heat_rel"])
        worst = max(worst, res)
        out["plates"][side] = entry
    out["residual_rel"] = worst
    return out


def write_all(folder: ResultsFolder, scene: Scene, result, sim, plots: bool = True) -> dict:
    write_csv(folder.path("timeseries.csv"), result)
    folder.path("scene.toml").write_text(to_toml(scene))
    s = summary(scene, result, sim)
    if plots and result.n_rows > 1:
        from .plots import make_plots
        s["plots"] = make_plots(folder.subdir("plots"), result, scene)
    folder.path("summary.json").write_text(json.dumps(s, indent=2) + "\n")
    return s
