"""The FEMA P695 far-field sweep (44 components, default scene) on a cluster
started by hand: a `dask scheduler` and N `dask worker --nthreads 1`
processes, each in its own temporary folder (127.0.0.1 only), the sweep run
from another folder with --scheduler and a relative --out. Prints the wall
time of the whole command (best of --repeat, fresh DIR each time), the
rerun with nothing new, and where the time went (sweep.md's phases).

    python benchmarks/sweep_external.py [--workers 2] [--repeat 2]
"""
from __future__ import annotations

import argparse
import os
import re
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SWEEP = """name = "p695-far-field-default"
scene = "default"
[axes]
"loading.record_set" = ["p695-far-field"]
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=2)
    a = ap.parse_args()
    base = Path(tempfile.mkdtemp(prefix="fpd-external-"))
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    addr = f"tcp://127.0.0.1:{port}"
    procs = []

    def spawn(folder, args):
        d = base / folder
        d.mkdir(exist_ok=True)
        with open(d / "log.txt", "ab") as log:
            procs.append(subprocess.Popen([sys.executable, "-m", "dask", *args], cwd=d, env=env, stdout=log,
                                          stderr=log, start_new_session=True))
    try:
        spawn("scheduler", ["scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"])
        for i in range(a.workers):
            spawn(f"worker{i + 1}", ["worker", addr, "--host", "127.0.0.1", "--nthreads", "1", "--no-dashboard",
                                     "--memory-limit", "0"])
        from dask.distributed import Client
        with Client(addr, timeout="30s", set_as_default=False) as c:
            c.wait_for_workers(a.workers, timeout=120)
        client = base / "client"
        client.mkdir()
        (client / "p695.toml").write_text(SWEEP)

        def sweep(out, *extra):
            t0 = time.perf_counter()
            r = subprocess.run([sys.executable, "-m", "fpd", "sweep", "p695.toml", "--out", out, "--scheduler", addr,
                                "--quiet", *extra], cwd=client, env=env, capture_output=True, text=True)
            if r.returncode:
                sys.exit(f"fpd sweep failed ({r.returncode}): {r.stderr}")
            return time.perf_counter() - t0
        sweep("warm")                      # numba's cache and the record set, once per worker (not timed)
        load = os.getloadavg()[0]
        times = [sweep(f"run{i}") for i in range(a.repeat)]
        md = (client / f"run{a.repeat - 1}" / "sweep.md").read_text()
        rerun = sweep(f"run{a.repeat - 1}")
        phases = re.search(r"\(cluster start.*?\)", md)
        print(f"P695 far-field, 44 members, default scene, on a scheduler and {a.workers} workers started by "
              f"hand; load average {load:.1f} on {os.cpu_count()} cores")
        print(f"sweep: {min(times):.1f} s best of {a.repeat} ({', '.join(f'{t:.1f}' for t in times)}); "
              f"rerun with nothing new: {rerun:.2f} s")
        print(f"phases of the last run: {phases.group(0) if phases else '?'}")
    finally:
        for p in procs:
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait(timeout=10)


if __name__ == "__main__":
    main()
