"""Results folders: written atomically, complete even after a failure.

Everything goes into a temporary folder beside DIR that is renamed into place
at the end; with --force the old DIR is kept until the new one is complete.
"""
from __future__ import annotations

import errno
import json
import math
import os
import shutil
from pathlib import Path

import numpy as np

from fpd.mechanics.phases import PHASES, TFP_PHASES  # noqa: F401

from .history import CsvWriter, StreamHistory, WriteError  # noqa: F401 (callers import these from here too)
from fpd.schema.scene import Scene, SceneError, to_toml

from fpd import __version__ as VERSION


def check_out_dir(out: Path, force: bool) -> None:
    if out.exists() and not out.is_dir():
        raise SceneError(f"{out}: exists and is not a folder (--out)")
    if out.exists() and any(out.iterdir()) and not force:
        raise SceneError(f"{out}: results folder exists and is not empty; use --force to replace it")


def guard_frames(on_frame, dt: float):
    """``on_frame`` whose write errors say at which step they happened."""
    def frame(n, sim):
        try:
            on_frame(n, sim)
        except WriteError:
            raise
        except OSError as exc:
            raise WriteError(exc, t_s=n * dt) from None
    return frame


def describe_os_error(exc: OSError) -> str:
    """``PATH: cause (ENOSPC)`` for one line."""
    code = errno.errorcode.get(exc.errno, "") if exc.errno else ""
    cause = exc.strerror or str(exc)
    if exc.errno == errno.ENOENT and "removed" not in cause:
        cause += " (the folder being written was removed?)"
    where = f"cannot write {exc.filename}" if exc.filename else "cannot write the results"
    return f"{where}: {cause}" + (f" ({code})" if code else "")


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
        self._mkdir(p.parent)
        return p

    def subdir(self, name: str) -> Path:
        p = self.tmp / name
        self._mkdir(p)
        return p

    def _mkdir(self, p: Path) -> None:
        """Create p below the temporary folder, never the folder itself: if
        it was removed underneath the run, writing fails (ENOENT) instead of
        quietly starting an incomplete folder again."""
        if not self.tmp.is_dir():
            raise FileNotFoundError(errno.ENOENT, "the folder being written was removed", str(self.tmp))
        rel = p.relative_to(self.tmp)
        q = self.tmp
        for part in rel.parts:
            q = q / part
            q.mkdir(exist_ok=True)

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


class ParquetWriter:
    """timeseries.parquet (``output.history = "parquet"``): the same rows and
    columns as timeseries.csv, as float64 columns (``phase`` as a dictionary
    of its names), one row group per block, written with pyarrow (an
    optional dependency: ``pip install fpd-sim[parquet]``). pandas
    (``read_parquet``), polars, DuckDB and pyarrow read it directly; xarray
    through pandas (``xr.Dataset.from_dataframe``). The values are the
    floats of the run, unrounded (the CSV keeps 10 significant digits).

    Same two-phase use as CsvWriter: ``format(rows)`` builds the block's
    table and changes nothing, ``write(prepared)`` appends it."""

    def __init__(self, path, columns):
        import pyarrow as pa
        import pyarrow.parquet as pq

        self.pa = pa
        self.cols = list(columns)
        self.j = self.cols.index("phase") if "phase" in self.cols else -1
        self.names = pa.array(TFP_PHASES, type=pa.string())
        fields = [pa.field(c, pa.dictionary(pa.int8(), pa.string()) if c == "phase" else pa.float64())
                  for c in self.cols]
        self.schema = pa.schema(fields)
        # no compression: float64 histories hardly compress, and the point is speed; no
        # dictionary encoding of the float columns either (it tries every value: ~5x the write time)
        self.w = pq.ParquetWriter(str(path), self.schema, compression="none", write_statistics=False,
                                  use_dictionary=[c for c in self.cols if c == "phase"] or False)

    def format(self, data: np.ndarray):
        pa = self.pa
        arrays = []
        for i, c in enumerate(self.cols):
            col = np.ascontiguousarray(data[:, i])
            if i == self.j:
                arrays.append(pa.DictionaryArray.from_arrays(pa.array(np.nan_to_num(col).astype(np.int8)),
                                                             self.names))
            else:
                arrays.append(pa.array(col, type=pa.float64()))
        return [pa.Table.from_arrays(arrays, schema=self.schema)]

    def write(self, data: np.ndarray) -> None:
        for table in self.format(data):
            self.w.write_table(table)

    def close(self) -> None:
        self.w.close()


HISTORY_FILES = {"csv": "timeseries.csv", "parquet": "timeseries.parquet"}


def history_format(scene: Scene) -> str:
    """output.history: "csv" (the default) or "parquet"; parquet needs pyarrow."""
    fmt = scene["output"].get("history", "csv")
    if fmt == "parquet":
        try:
            import pyarrow  # noqa: F401
            import pyarrow.parquet  # noqa: F401
        except ImportError:
            raise SceneError(f'{scene.path}: output.history = "parquet" needs pyarrow '
                             '(pip install pyarrow, or the fpd-sim[parquet] extra); or use "csv"') from None
    return fmt


def write_parquet(path: Path, result, chunk: int = 1 << 16) -> None:
    """timeseries.parquet of an in-memory result."""
    w = ParquetWriter(path, result.columns)
    try:
        for s in range(0, result.data.shape[0], chunk):
            w.write(result.data[s:s + chunk])
    finally:
        w.close()


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


def rim_summary(d: dict, st) -> dict:
    """The DFP / SFP / flat bearing's rims (docs/model.md 9, 7): per surface its capacity, the
    peak slide (arc from its centre), their ratio and the impacts counted on
    it; the rim's loss and the impacts' impulse (N s: an impact is an
    impulse, never a force); the largest ratio, for sweep tables."""
    dev = d["device"]
    sides = (("lower", "s1_m", "d1", "n_rim1"),) + ((("upper", "s2_m", "d2", "n_rim2"),)
                                                      if dev["kind"] in ("DFP", "flat") else ())
    cap = {}
    for side, col, key, n in sides:
        peak = st.peak_abs(col)
        cap[side] = {"capacity_m": _f(dev[key]), "peak_slide_m": _f(peak), "ratio": _f(peak / dev[key]),
                     "impacts": int(round(st.final(n)))}
    return {"rim_loss_J": _f(st.final("E_rim_J")), "rim_impulse_Ns": _f(st.peak_abs("J_rim_Ns")),
            "capacity": cap, "capacity_ratio": _f(max(c["ratio"] for c in cap.values())),
            "rim_impacts": {side: c["impacts"] for side, c in cap.items()}}


def lift_summary(st) -> dict:
    """Lift-off under a vertical record (docs/model.md 10): how many times the
    moving assembly left the lower plate and when first (a recorded row's
    time), the time it spent in flight, the highest it rose above its seated
    position and when, and the landings' loss (None where it never left)."""
    return {"count": int(round(st.final("n_lift"))), "flight_time_s": _f(st.final("t_flight_s")),
            "first_lift_t_s": st.first_lift_t, "peak_lift_m": _f(st.peak("lift_m")),
            "peak_lift_t_s": st.peak_lift_t, "landing_loss_J": _f(st.final("E_land_J"))}


def summary(scene: Scene, result, sim) -> dict:
    d = scene.data
    if d["device"]["kind"] == "TFP":
        return tfp_summary(scene, result, sim)
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
        if "E_rim_J" in result:
            out += st.final("E_rim_J")
            s.update(rim_summary(d, st))
        if "E_land_J" in result:
            out += st.final("E_land_J")
            s["lift_off"] = lift_summary(st)
        s["input_work_J"] = _f(e_in)
        # the largest residual over the recorded history, relative to the largest input
        # (a ledger that closes only at the end would hide what went wrong on the way)
        s["energy_residual_rel"] = _f(st.ledger_worst / st.input_worst) if st.input_worst else 0.0
        s["energy_residual_final_rel"] = _f(abs(e_in - out) / abs(e_in)) if e_in else 0.0
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
    meter = _cycle_meter(scene, result)
    if meter is not None and meter.cycles():       # a run shorter than one cycle has nothing to report
        from .cycles import summary_block
        s["test_machine"] = summary_block(meter, scene)
    if d["coupling"]["scheme"] == "iterated":
        s["coupling_iterations"] = {"total": int(result.iterations), "max_per_step": int(result.max_iterations)}
    if "path1_m" in result:
        s["wear"] = wear_summary(st, ("lower", "upper"))
    s.update(result.info)
    return s


def wear_summary(st, surfaces) -> dict:
    """Per surface the sliding path (m) and the Archard wear depth (m) at the end."""
    return {name: {"path_m": _f(st.final(f"path{i}_m")), "depth_m": _f(st.final(f"wear{i}_m"))}
            for i, name in enumerate(surfaces, 1)}


def tfp_summary(scene: Scene, result, sim) -> dict:
    """summary.json of a TFP run: per surface S1..S4."""
    d = scene.data
    s = {"status": result.status, "message": result.message, "scene": scene.name,
         "models": {"device": "TFP", "mechanics": d["mechanics"]["model"],
                    **{f"thermal_{part}": d["thermal"][part]["model"] for part in d["thermal"]},
                    **{f"friction_{k}": d["friction"][k]["law"] for k in d["friction"]},
                    "coupling": d["coupling"]["scheme"]},
         "steps": int(getattr(result, "steps", result.n_rows - 1)),
         "dt_s": sim.dt, "runtime_s": result.runtime_s, "version": VERSION}
    if result.n_rows == 0:
        return s
    st = result.stats
    s["peak_u_m"] = _f(st.peak_abs("u_m"))
    s["residual_u_m"] = _f(st.final("u_m"))
    s["peak_F_N"] = _f(st.peak_abs("F_N"))
    s["friction_work_J"] = {f"S{i}": _f(st.final(f"W{i}_J")) for i in range(1, 5)}
    e_in = st.final("E_input_J")
    out = st.final("E_kin_J") + st.final("E_pot_J") + st.final("E_rim_J") + sum(
        st.final(f"W{i}_J") for i in range(1, 5))
    s["rim_loss_J"] = _f(st.final("E_rim_J"))
    if "J_rim_Ns" in result:
        s["rim_impulse_Ns"] = _f(st.peak_abs("J_rim_Ns"))
        s["rim_impacts"] = {f"S{i}": int(st.final(f"n_rim{i}")) for i in range(1, 5)}
    if "E_reseat_J" in result:
        out += st.final("E_reseat_J")
        s["reseat_loss_J"] = _f(st.final("E_reseat_J"))
    if "E_land_J" in result:
        out += st.final("E_land_J")
        s["lift_off"] = lift_summary(st)
    s["input_work_J"] = _f(e_in)
    s["energy_residual_rel"] = _f(abs(e_in - out) / abs(e_in)) if e_in else 0.0
    s["peak_slide_m"] = {f"S{i}": _f(st.peak_abs(f"s{i}_m")) for i in range(1, 5)}
    # per surface its capacity (device.d1..d4), peak slide, their ratio and impacts, as the DFP's
    dev = d["device"]
    cap = {}
    for i in range(1, 5):
        peak = st.peak_abs(f"s{i}_m")
        cap[f"S{i}"] = {"capacity_m": _f(dev[f"d{i}"]), "peak_slide_m": _f(peak), "ratio": _f(peak / dev[f"d{i}"]),
                        "impacts": int(round(st.final(f"n_rim{i}"))) if f"n_rim{i}" in result else 0}
    s["capacity"] = cap
    s["capacity_ratio"] = _f(max(c["ratio"] for c in cap.values()))
    if "T1_C" in result:
        for i in range(1, 5):
            s[f"peak_T{i}_C"] = _f(st.peak(f"T{i}_C"))
        s["heat"] = heat_ledger(result, sim)
        s["heat_residual_rel"] = s["heat"]["residual_rel"]
    for i in range(1, 5):
        s[f"min_mu{i}"] = _f(st.low(f"mu{i}"))
    meter = _cycle_meter(scene, result)
    if meter is not None and meter.cycles():       # the test machine: EDC, N_mean per cycle (cycles.csv)
        from .cycles import summary_block
        s["test_machine"] = summary_block(meter, scene)
    if d["coupling"]["scheme"] == "iterated":
        s["coupling_iterations"] = {"total": int(result.iterations), "max_per_step": int(result.max_iterations)}
    if "path1_m" in result:
        s["wear"] = wear_summary(st, ("S1", "S2", "S3", "S4"))
    s.update(result.info)
    return s


def _cycle_meter(scene: Scene, result):
    """The per-cycle meter of a test-machine run: the streamed history's (fed
    every block; ``stream_history`` gives it one, a bare StreamHistory has
    none and its summary no ``test_machine``), or one fed the rows held in
    memory; None for other scenes."""
    from .cycles import CycleMeter, meter_for
    if result.streamed:
        return next((m for m in getattr(result.history, "meters", ()) if isinstance(m, CycleMeter)), None)
    meter = meter_for(scene, result.columns)
    if meter is not None:
        meter.add(result.data)
    return meter


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
    for i, (side, plate) in enumerate(zip(list(sim.scene.data["thermal"]), result.plates)):
        if plate is None:
            continue
        q_in, st, lo = plate.heat_in(), plate.stored_heat(), plate.heat_lost()
        res = abs(q_in - st - lo) / q_in if q_in else abs(st - lo)
        entry = {"heat_in_J": q_in, "stored_J": st, "lost_J": lo, "residual_rel": res}
        if hasattr(plate, "point_peak"):            # fe3d: its fixed material point (radius_m, 0) on the face
            entry["point_radius_m"] = plate.point_xy[0]
            entry["point_T_end_C"] = plate.point_temperature()
            entry["point_T_peak_C"], entry["point_t_peak_s"] = plate.point_peak
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
    from .cycles import meter_for
    kw.setdefault("meters", (lambda columns: meter_for(scene, columns),))
    fmt = history_format(scene)
    if fmt != "csv":
        kw.setdefault("writer", ParquetWriter)
    return StreamHistory(folder.path(HISTORY_FILES[fmt]), spill_path=spill, **kw)


def write_all(folder: ResultsFolder, scene: Scene, result, sim, plots: bool = True, hottest=None) -> dict:
    """Everything but what the run streamed: timeseries.csv (unless streamed
    already), scene.toml, summary.json, plots/ (with each plate's hottest
    field when ``hottest``, a HottestFields, is given); summary.json's
    ``plots`` names every PNG written in plots/."""
    if not result.streamed:
        fmt = history_format(scene)
        (write_parquet if fmt == "parquet" else write_csv)(folder.path(HISTORY_FILES[fmt]), result)
    folder.path("scene.toml").write_text(to_toml(scene))
    s = summary(scene, result, sim)
    if result.streamed:
        result.history.discard_spill()
    if "test_machine" in s:
        from .cycles import plot_cycles, write_cycles_csv
        write_cycles_csv(folder.path("cycles.csv"), s["test_machine"]["cycles"])
    if plots and result.n_rows > 1:
        from .figures import make_plots
        s["plots"] = make_plots(folder.subdir("plots"), result.plot_view(), scene)
        if s.get("test_machine", {}).get("cycles"):
            plot_cycles(folder.path("plots", "cycles.png"), s["test_machine"]["cycles"], scene.name)
            s["plots"].append("cycles.png")
    if plots and hottest is not None:
        s.setdefault("plots", [])
        s["plots"] += [Path(p).name for p in hottest.pictures(folder.subdir("plots"))]
    folder.path("summary.json").write_text(json.dumps(s, indent=2) + "\n")
    return s


# -- a write that fails -------------------------------------------------------------------
def _last_row_t(csv_path: Path) -> tuple[int, float | None]:
    """(size of the whole-line prefix, t_s of its last row or None: header only)."""
    with open(csv_path, "rb") as fh:
        header = fh.readline()
        size = fh.seek(0, os.SEEK_END)
        back = min(size, 1 << 16)
        fh.seek(size - back)
        tail = fh.read(back)
    keep = size - back + tail.rfind(b"\n") + 1
    if keep <= len(header):
        return len(header), None
    lines = tail[:keep - (size - back)].splitlines()
    j = header.decode().strip().split(",").index("t_s")
    return keep, float(lines[-1].decode().split(",")[j])


def _drop_rows(csv_path: Path, keep: int, nbytes: int) -> int:
    """Cut at least ``nbytes`` of whole rows off the end (never the header); new size."""
    with open(csv_path, "r+b") as fh:
        header = len(fh.readline())
        start = max(header, keep - nbytes - (1 << 16))
        fh.seek(start)
        chunk = fh.read(max(0, keep - nbytes - start))
        cut = start + chunk.rfind(b"\n") + 1 if b"\n" in chunk else header
        fh.truncate(max(cut, header))
        return max(cut, header)


def after_write_error(folder: ResultsFolder, scene: Scene, sim, exc: OSError, history=None,
                      result=None) -> str:
    """What ``fpd run`` leaves when writing its results fails (disk full,
    quota, permission, the folder removed underneath), and the one line that
    says so. The state of DIR afterwards (docs/studies.md, "Running on
    shared machines"):

    - DIR existed (``--force``): it is left as it was, the earlier complete
      results; the new partial ones are deleted (their space given back).
    - else, when at least one row and a summary fit: DIR holds the history as
      far as it was written: ``timeseries.csv`` cut at its last complete row
      (rows dropped from its end until ``scene.toml`` and ``summary.json``
      fit), ``scene.toml`` and ``summary.json`` with ``status = "failed"``,
      the message and ``write_error``; no ``vtk/``, no ``plots/`` (possibly
      cut short, and their space is needed).
    - else nothing: the temporary folder is removed, DIR is not created.

    So DIR never holds a truncated file or a summary that claims more than
    the folder holds."""
    dt = sim.dt
    if result is not None:
        computed = int(result.steps)
    elif getattr(exc, "t_s", None) is not None:
        computed = int(round(exc.t_s / dt))
    elif history is not None and getattr(history, "rows", 0):
        computed = int(round(history.stats.final("t_s") / dt))
    else:
        computed = 0
    if exc.filename and str(exc.filename).startswith(str(folder.tmp)):
        # name the file as the user knows it: DIR/..., not the temporary folder beside it
        exc.filename = str(folder.out) + str(exc.filename)[len(str(folder.tmp)):]
    what = describe_os_error(exc)
    line = f"{what}; {computed} steps computed (t = {computed * dt:.6g} s)"
    if history is not None and hasattr(history, "abandon"):
        history.abandon()
    out = folder.out
    if out.exists():
        folder.discard()
        return line + f"; nothing kept, {out} still holds the earlier results"
    csv_path = folder.tmp / "timeseries.csv"
    try:
        for p in list(folder.tmp.iterdir()):        # all but the history: rewritten or dropped
            if p.name != "timeseries.csv":
                if p.is_dir() and not p.is_symlink():
                    shutil.rmtree(p)
                else:
                    p.unlink()
        keep, t_last = _last_row_t(csv_path)
        os.truncate(csv_path, keep)
        free = 1 << 15
        while True:
            if t_last is None:
                raise OSError(exc.errno, "no complete row of the history could be kept")
            kept = int(round(t_last / dt))
            s = {"status": "failed",
                 "message": f"writing the results failed at step {computed} (t = {computed * dt:.6g} s): {what}; "
                            f"timeseries.csv holds the rows up to step {kept} (t = {t_last:.6g} s)",
                 "scene": scene.name, "steps": kept, "steps_computed": computed, "dt_s": dt,
                 "write_error": {"path": exc.filename, "errno": errno.errorcode.get(exc.errno or 0),
                                 "cause": exc.strerror},
                 "kept": ["timeseries.csv", "scene.toml", "summary.json"], "version": VERSION}
            if result is not None:
                s["run_status"], s["run_message"] = result.status, result.message
            try:
                folder.path("scene.toml").write_text(to_toml(scene))
                folder.path("summary.json").write_text(json.dumps(s, indent=2) + "\n")
                break
            except OSError as again:
                if again.errno not in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG):
                    raise
                keep = _drop_rows(csv_path, keep, free)      # make room for the summary
                keep, t_last = _last_row_t(csv_path)
                free *= 2
        folder.commit()
    except (OSError, ValueError, IndexError):        # ValueError, IndexError: a last row not as written
        folder.discard()
        left = f", partial files left in {folder.tmp}" if folder.tmp.exists() else ""
        return line + f"; nothing kept ({out} not created{left})"
    return line + (f"; the history up to step {kept} (t = {t_last:.6g} s) kept in {out} "
                   "(summary.json status \"failed\")")
