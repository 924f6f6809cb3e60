"""The Python API: ``fpd.run``, ``fpd.load_scene``, ``fpd.compare``, ``fpd.converge``.

What the command line does, for a script or a notebook::

    import fpd
    r = fpd.run("default", solver={"duration": 5.0})
    r.summary["peak_u_m"]            # the fields of summary.json
    r.history["u_m"]                 # a column of timeseries.csv, as a numpy array
    r.plot("hysteresis")             # a figure of plots/, as a matplotlib Figure

A scene (``SceneLike``) is given as a packaged name (``"default"``,
``"stability/tall-pad"``), a path to a TOML file, a dict with the TOML file's
structure, or a Scene from ``load_scene``. Overrides are keyword arguments, as nested dicts
(``solver={"dt": 5e-4}``) or dotted keys (``**{"friction.mu_ref": 0.08}``); they
replace keys of the scene before it is validated, as ``--set`` does. Every key,
column and summary field is described in docs/reference.md.

Bad input raises ``fpd.SceneError`` (a ValueError) with the one-line message
the command line prints; a numerical failure does not raise: the Result's
``status`` is ``"failed"`` and its history holds the steps computed until then.
"""
from __future__ import annotations

import copy
import csv
import json
import os
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Union

if TYPE_CHECKING:         # the annotations' types, never imported at run time (import fpd stays cheap)
    import matplotlib.figure
    import numpy
    import pandas
    import xarray

from fpd.schema import scene as scn
from fpd.schema.scene import Scene, SceneError

# what a scene argument may be: a packaged name or a path, a dict shaped like the TOML file, a Scene
SceneLike = Union[str, os.PathLike, Mapping, Scene, None]

__all__ = ["run", "load_scene", "compare", "converge", "Result", "History", "StudyResult", "SceneError"]


# -- scenes ---------------------------------------------------------------------------
def _merge(into: dict, over: Mapping, where: str = "") -> None:
    """Deep-merge ``over`` into ``into``; dotted keys open nested tables."""
    for key, value in over.items():
        if not isinstance(key, str) or not key:
            raise SceneError(f"override {where}{key!r}: keys are non-empty strings")
        parts = key.split(".")
        node = into
        for p in parts[:-1]:
            nxt = node.setdefault(p, {})
            if not isinstance(nxt, dict):
                raise SceneError(f"override {where}{key}: '{p}' is not a table")
            node = nxt
        last = parts[-1]
        if isinstance(value, Mapping):
            nxt = node.setdefault(last, {})
            if not isinstance(nxt, dict):
                raise SceneError(f"override {where}{key}: '{last}' is not a table")
            _merge(nxt, value, f"{where}{key}.")
        else:
            node[last] = copy.deepcopy(value)


def _raw_and_path(scene) -> tuple[dict, str]:
    """The unvalidated TOML tree of a scene argument, and the path messages name."""
    if isinstance(scene, Scene):
        # overrides apply to what the scene was made from (a per-plate table
        # of the resolved form would hide an override of the base table)
        raw = getattr(scene, "_fpd_raw", None)
        return copy.deepcopy(raw) if raw is not None else _resolved_raw(scene), scene.path
    if isinstance(scene, Mapping):
        raw = copy.deepcopy(dict(scene))
        raw.setdefault("name", "scene")         # a dict without a name: results/scene, not '<dict>'
        return raw, "<dict>"
    if scene is None or isinstance(scene, (str, os.PathLike)):
        path = scn.resolve_path(None if scene is None else os.fspath(scene))
        raw = scn.read_toml(path)
        raw.setdefault("name", path.stem)
        return raw, str(path)
    raise SceneError(f"scene = {scene!r}: give a packaged scene name, a path to a TOML file, a dict or a Scene")


def _resolved_raw(scene: Scene) -> dict:
    """A resolved scene as an input tree that validates to the same scene."""
    data = copy.deepcopy(scene.data)
    ld = data["loading"]
    if "file" in ld and "path" in ld:
        ld["file"] = ld["path"]            # the file named relative to the scene's folder, made absolute
    ld.pop("path", None)
    return data


def load_scene(scene: SceneLike = None, **overrides: Any) -> Scene:
    """Read, override and validate a scene; raise ``SceneError`` on bad input.

    ``scene``: a packaged name (``"default"``, ``"lab-sine"``, ``"stability/tall-pad"``;
    ``None`` is the default scene), a path to a TOML file, a dict shaped like
    the TOML file, or a Scene. ``overrides``: nested dicts or dotted keys,
    e.g. ``load_scene("default", solver={"dt": 5e-4}, **{"friction.mu_ref": 0.08})``.

    The returned Scene is fully resolved (every default filled in):
    ``s["solver"]["dt"]``, ``s.thermal("lower")``, ``s.friction("upper")``;
    ``fpd.schema.scene.to_toml(s)`` gives it back as TOML.
    """
    raw, path = _raw_and_path(scene)
    try:
        sup = overrides.get("superstructure")
        scn.replace_load(raw, [k.split(".", 1)[1] for k in overrides if k.startswith("superstructure.")]
                         + (list(sup) if isinstance(sup, Mapping) else []))
        _merge(raw, overrides)
    except SceneError as exc:
        raise SceneError(f"{path}: {exc}") from None
    sc = scn.validate(copy.deepcopy(raw), path)
    sc._fpd_raw = raw
    return sc


# -- the history as named arrays ---------------------------------------------------------
class History(Mapping):
    """A run's history: column name -> numpy array (one entry per recorded step).

    The columns are those of timeseries.csv, in its order (``columns``), with
    units in their names (``t_s``, ``u_m``, ``F_N``, ``T1_C``...); ``phase``
    holds the phase names (``stick``, ``slip``, ``tilt``) as the CSV does, and
    ``phase_code`` its integer codes. ``data`` is the whole table as one 2-D
    float array (``phase`` as its code). ``to_pandas()`` and ``to_xarray()``
    convert it when those packages are installed."""

    def __init__(self, columns, data):
        self.columns = list(columns)
        self.data = data

    def __getitem__(self, name: str) -> "numpy.ndarray":
        """The column ``name`` as a numpy array (``phase``: its names; ``phase_code``: its codes)."""
        import numpy as np

        if name == "phase_code" and "phase" in self.columns:
            return self.data[:, self.columns.index("phase")].astype(int)
        if name not in self.columns:
            raise KeyError(f"{name}: not a column of this run; columns: {', '.join(self.columns)}")
        col = self.data[:, self.columns.index(name)]
        if name == "phase":     # the DFP's codes, and the TFP's after them (mechanics/phases.py)
            from fpd.mechanics.phases import TFP_PHASES
            return np.array(TFP_PHASES, dtype=object)[col.astype(int)].astype(str)
        return col

    def __iter__(self):
        return iter(self.columns)

    def __len__(self):
        return len(self.columns)

    @property
    def n_rows(self) -> int:
        """The number of recorded rows."""
        return int(self.data.shape[0])

    def __repr__(self):
        return f"History({self.n_rows} rows: {', '.join(self.columns)})"

    def to_pandas(self) -> "pandas.DataFrame":
        """A pandas DataFrame, one column per history column (``phase`` categorical)."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("History.to_pandas() needs pandas: pip install pandas "
                              "(or use the history as a mapping of numpy arrays)") from None
        df = pd.DataFrame({c: self[c] for c in self.columns})
        if "phase" in df:
            from fpd.mechanics.phases import PHASES, TFP_PHASES
            codes = self["phase_code"]
            names = PHASES if (codes.size == 0 or codes.max() < len(PHASES)) else TFP_PHASES
            df["phase"] = pd.Categorical(df["phase"], categories=list(names))
        return df

    def to_xarray(self) -> "xarray.Dataset":
        """An xarray Dataset over the dimension ``t_s``; each variable has its unit
        and meaning (docs/reference.md) in ``attrs``."""
        try:
            import xarray as xr
        except ImportError:
            raise ImportError("History.to_xarray() needs xarray: pip install xarray "
                              "(or use the history as a mapping of numpy arrays)") from None
        from .reference import COLUMNS
        t = self["t_s"]
        variables = {}
        for c in self.columns:
            if c == "t_s":
                continue
            unit, meaning = COLUMNS.get(c, ("", ""))
            variables[c] = ("t_s", self[c], {"units": unit, "description": meaning})
        unit, meaning = COLUMNS["t_s"]
        return xr.Dataset(variables, coords={"t_s": ("t_s", t, {"units": unit, "description": meaning})})


class Result:
    """What ``fpd.run`` returns.

    - ``summary``: dict, the fields of summary.json (``status``, ``peak_u_m``,
      ``friction_work_J``, ``peak_T1_C``, ...; docs/reference.md)
    - ``history``: a ``History`` (column -> numpy array; ``.to_pandas()``, ``.to_xarray()``)
    - ``scene``: the resolved Scene that ran
    - ``out``: the results folder (a Path) when ``out=`` was given, else None
    - ``status``, ``ok``: ``"ok"`` / ``"failed"`` / ``"interrupted"`` and whether it is ``"ok"``
    - ``plot()``, ``plot("hysteresis")``: the run's figures as matplotlib Figures
    """

    def __init__(self, summary, history, scene, out):
        self.summary, self.history, self.scene, self.out = summary, history, scene, out

    @property
    def status(self) -> str:
        """``"ok"``, ``"failed"`` or ``"interrupted"`` (summary.json's ``status``)."""
        return self.summary["status"]

    @property
    def ok(self) -> bool:
        """Did the run end with status ``"ok"``?"""
        return self.status == "ok"

    def figure_names(self) -> list[str]:
        """The names ``plot`` takes for this run (those of the PNGs ``fpd run`` writes in plots/,
        without the hottest-field pictures)."""
        from fpd.outputs import figures
        names = list(figures.figures(self.history, self.scene)) if self.history.n_rows > 1 else []
        if self.summary.get("test_machine", {}).get("cycles"):
            names.append("cycles")
        return names

    def plot(self, name: str | None = None) -> "dict[str, matplotlib.figure.Figure] | matplotlib.figure.Figure":
        """The run's figures, as ``fpd run`` draws them into plots/, as matplotlib Figures.

        ``plot()``: a dict name -> Figure of every figure of this run (``hysteresis``,
        ``response``, ``temperature``, ``friction``; ``orbit``, ``force_orbit``,
        ``heat_path`` for a bidirectional run; ``cycles`` on the test machine).
        ``plot("hysteresis")``: that one Figure. The figures are made by pyplot:
        a notebook shows them; a script calls ``plt.show()`` or
        ``fig.savefig("loop.png")`` (and ``plt.close(fig)`` when done with it). Raises ``ValueError`` for a name this run has not.
        """
        from fpd.outputs import drawing, figures
        names = self.figure_names()
        if name is not None and name not in names:
            raise ValueError(f"plot({name!r}): this run's figures are {', '.join(names) or 'none (fewer than 2 rows)'}")
        builders = figures.figures(self.history, self.scene) if self.history.n_rows > 1 else {}
        if "cycles" in names:
            from fpd.outputs.cycles import cycles_figure
            builders["cycles"] = lambda: cycles_figure(self.summary["test_machine"]["cycles"], self.scene.name)
        old, drawing.PYPLOT = drawing.PYPLOT, True
        try:
            if name is not None:
                return builders[name]()
            return {n: build() for n, build in builders.items()}
        finally:
            drawing.PYPLOT = old

    def __repr__(self):
        return (f"Result(scene={self.scene.name!r}, status={self.status!r}, "
                f"steps={self.summary.get('steps')}, out={str(self.out) if self.out else None!r})")


def _check_args(fn: str, out, **flags) -> None:
    """The API's own arguments, before anything runs: ``out`` a path (or
    None), the flags booleans; else SceneError (one line naming the argument)."""
    if out is not None and not isinstance(out, (str, os.PathLike)):
        raise SceneError(f"fpd.{fn}(out={out!r}): out must be a folder path (a str or a Path) or None, "
                         f"not {type(out).__name__}")
    if isinstance(out, str) and not out.strip():
        raise SceneError(f"fpd.{fn}(out={out!r}): out must be a folder path, not an empty string")
    for name, value in flags.items():
        if not (isinstance(value, bool) or type(value).__name__ == "bool_"):     # numpy's too
            raise SceneError(f"fpd.{fn}({name}={value!r}): {name} must be True or False, not {type(value).__name__}")


def run(scene: SceneLike = None, out: str | os.PathLike | None = None, *, force: bool = False,
        progress: bool = False, **overrides: Any) -> Result:
    """Run a scene and return a ``Result`` (summary, history, scene, out).

    ``scene``: a packaged name, a path, a dict or a Scene (see ``load_scene``);
    ``overrides``: nested dicts or dotted keys, e.g.
    ``fpd.run("default", solver={"duration": 5.0}, thermal={"model": "lumped"})``.
    ``out``: a folder to write what ``fpd run --out`` writes (timeseries.csv,
    summary.json, scene.toml, plots/, vtk/), refused when it exists and is not
    empty unless ``force``; without it nothing is written. ``progress``: a
    progress bar on stderr.

    Raises ``SceneError`` on bad input. A numerical failure does not raise:
    ``result.status == "failed"``, ``result.summary["message"]`` says where.
    """
    from fpd.coupling.build import build
    from fpd.outputs.output import ResultsFolder, check_out_dir, summary, write_all
    from fpd.coupling.run import simulate

    _check_args("run", out, force=force, progress=progress)
    sc = load_scene(scene, **overrides)
    if progress:
        from fpd import jitcache
        jitcache.enable()           # the one-line notice before a first compile goes with the bar
    if out is not None:
        out = Path(out)
        check_out_dir(out, force)
    sim = build(sc)
    if out is None:
        result = simulate(sim, progress=progress, every=sc["output"]["csv_every"])
        sc["solver"].setdefault("duration", sim.n_steps * sim.dt)
        s = summary(sc, result, sim)
        return Result(s, History(result.columns, result.data), sc, None)
    try:
        folder = ResultsFolder(out)
    except OSError as exc:
        raise SceneError(f"{out}: cannot create the results folder there (out): {exc.strerror}") from None
    try:
        vtk = hottest = None
        if sc["output"]["vtk_every"] > 0:
            from fpd.outputs.vtk_output import VTKSeries        # the device's drawing: its stepper names it
            vtk = VTKSeries(folder.subdir("vtk"), sim)
        if sc["output"]["plots"] and any(p is not None and p.field() is not None for p in sim.plates):
            from fpd.outputs.hottest import HottestFields
            hottest = vtk.hottest if vtk else HottestFields.of(sim)   # two plates or the TFP's four parts
        result = simulate(sim, progress=progress, every=sc["output"]["csv_every"],
                          on_frame=vtk.frame if vtk else None, frame_every=sc["output"]["vtk_every"],
                          hottest=hottest)
        if vtk:
            vtk.close()
        sc["solver"].setdefault("duration", sim.n_steps * sim.dt)
        s = write_all(folder, sc, result, sim, plots=sc["output"]["plots"], hottest=hottest)
        folder.commit()
    except BaseException:
        folder.discard()
        raise
    return Result(s, History(result.columns, result.data), sc, out)


# -- the studies ---------------------------------------------------------------------------
class StudyResult:
    """What ``fpd.compare`` / ``fpd.converge`` return.

    - ``rows``: list of dicts, the study's main table (compare.csv / orders.csv)
    - ``table``: the name of that table; ``tables``: every CSV table of the study by name
    - ``summary``: its summary.json; ``report``: its markdown report
    - ``out``: the folder, when ``out=`` was given (else the files were written to
      a temporary folder, read back and removed)
    - ``to_pandas()``: ``rows`` as a DataFrame (pandas needed)
    """

    def __init__(self, table, tables, summary, report, out):
        self.table, self.tables, self.summary, self.report, self.out = table, tables, summary, report, out

    @property
    def rows(self) -> list[dict]:
        """The main table's rows (compare.csv / orders.csv), one dict per row."""
        return self.tables[self.table]

    def to_pandas(self, table: str | None = None) -> "pandas.DataFrame":
        """A table (``table``, default the main one) as a pandas DataFrame."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("StudyResult.to_pandas() needs pandas: pip install pandas") from None
        return pd.DataFrame(self.tables[table or self.table])

    def __repr__(self):
        return f"StudyResult({self.table}: {len(self.rows)} rows, out={str(self.out) if self.out else None!r})"


def _cell(v: str):
    try:
        return float(v) if v != "" else float("nan")
    except ValueError:
        return v


def _study(kind: str, table: str, scene, out, force, fast, quiet, overrides) -> StudyResult:
    import argparse

    from fpd.studies.compare import cmd_compare
    from fpd.studies.converge import cmd_converge
    _check_args(kind, out, force=force, fast=fast, quiet=quiet)

    with tempfile.TemporaryDirectory(prefix=f"fpd-{kind}-") as tmp:
        if overrides or isinstance(scene, (Mapping, Scene)):
            # the studies load their scene by name or path: hand them the overridden one as a file
            sc = load_scene(scene, **overrides)
            arg = Path(tmp) / f"{sc.name}.toml"
            arg.write_text(scn.to_toml(Scene(sc.path, _resolved_raw(sc))))
            arg = str(arg)
        else:
            arg = None if scene is None else os.fspath(scene)
            if arg is None:
                arg = "default"
        where = Path(out) if out is not None else Path(tmp) / "study"
        args = argparse.Namespace(scene=arg, out=str(where), force=force, quiet=quiet, fast=fast)
        cmd = cmd_compare if kind == "compare" else cmd_converge
        cmd(args)
        tables = {}
        for f in sorted(where.glob("*.csv")):
            with open(f, newline="") as fh:
                tables[f.stem] = [{k: _cell(v) for k, v in row.items()} for row in csv.DictReader(fh)]
        summary = json.loads((where / "summary.json").read_text())
        report = (where / f"{kind}.md").read_text()
    return StudyResult(table, tables, summary, report, where if out is not None else None)


def compare(scene: SceneLike = None, out: str | os.PathLike | None = None, *, fast: bool = False,
            force: bool = False, quiet: bool = True, **overrides: Any) -> StudyResult:
    """``fpd compare``: the scene under lumped, fe1d (follow-pad, fixed-point) and
    axisym plates. ``rows`` = compare.csv (one row per model and plate: peak and
    end temperature, min mu, friction work, errors against the reference model).
    ``fast``: a short version (8 s, coarser meshes). Other arguments as ``run``."""
    return _study("compare", "compare", scene, out, force, fast, quiet, overrides)


def converge(scene: SceneLike = None, out: str | os.PathLike | None = None, *, fast: bool = False,
             force: bool = False, quiet: bool = True, **overrides: Any) -> StudyResult:
    """``fpd converge``: dt and mesh refinement of the scene, error against run
    time. ``rows`` = orders.csv (observed order and finest error per sweep and
    output); ``tables["converge"]`` every level. Other arguments as ``compare``."""
    return _study("converge", "orders", scene, out, force, fast, quiet, overrides)
