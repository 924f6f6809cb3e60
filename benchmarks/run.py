"""Speed and accuracy read together: `python benchmarks/run.py [--quick]`.

For each case: steps, time-stepping loop time, per-step time, the whole
`fpd run` process (imports, CSV, summary; plots and VTK off), that
process's own loop time, its peak memory, and the thermal error against a
closed form where the case has one.
Also the cost-linearity check: loop time at N and 2N steps, and the peak
memory of `fpd run` at 10^5 and 10^6 steps (the history is streamed to disk,
so it should not grow with the steps).
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

CASES = [
    # name, scene, overrides
    ("El Centro, seated, lumped", "default", ["mechanics.model=seated", "thermal.model=lumped"]),
    ("El Centro, seated, no heat", "default", ["mechanics.model=seated", "thermal.model=none"]),
    ("El Centro, two-phase, lumped", "default", ["mechanics.model=two-phase", "thermal.model=lumped"]),
    ("El Centro, two-phase, fe1d", "default", ["mechanics.model=two-phase", "thermal.model=fe1d"]),
    ("El Centro, two-phase, axisym ~10k nodes", "default",
     ["mechanics.model=two-phase", "thermal.model=axisym", "thermal.nr=200", "thermal.nz=50"]),
]


def loop_time(scene_name, overrides, repeat=1):
    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate

    best = None
    for _ in range(repeat):
        sim = build(scn.load(scene_name, overrides))
        r = simulate(sim)
        if r.status != "ok":
            raise RuntimeError(r.message)
        best = r.runtime_s if best is None else min(best, r.runtime_s)
    return sim.n_steps, best


# the child reports its own high-water mark: VmHWM belongs to the process's
# address space (getrusage's ru_maxrss would carry over the forking parent's)
_CHILD = ("import atexit, sys\n"
          "def _hwm():\n"
          "    kib = [l.split()[1] for l in open('/proc/self/status') if l.startswith('VmHWM')][0]\n"
          "    sys.stderr.write(f'\\nMAXRSS_KIB {kib}\\n')\n"
          "atexit.register(_hwm)\n"
          "sys.argv = ['fpd'] + sys.argv[1:]\n"
          "from fpd.frontends.cli import entry\n"
          "entry()\n")


def process_time(scene_name, overrides, plots=False):
    """Wall time and peak RSS of the whole `fpd run` process (its own
    VmHWM at exit: RUSAGE_CHILDREN would report the largest child so far)."""
    with tempfile.TemporaryDirectory() as tmp:
        args = [sys.executable, "-c", _CHILD, "run", scene_name, "--out", f"{tmp}/out", "--quiet",
                "--set", f"output.plots={'true' if plots else 'false'}", "--set", "output.vtk_every=0"]
        for o in overrides:
            args += ["--set", o]
        env = dict(os.environ, PYTHONPATH=str(ROOT))
        t0 = time.perf_counter()
        r = subprocess.run(args, env=env, capture_output=True, text=True, cwd=ROOT)
        wall = time.perf_counter() - t0
        if r.returncode != 0:
            raise RuntimeError(r.stderr.strip())
        peak = [int(x.split()[1]) for x in r.stderr.splitlines() if x.startswith("MAXRSS_KIB")][-1]
        summary = json.loads(Path(tmp, "out", "summary.json").read_text())
    return wall, peak / 1024.0, summary


def thermal_error():
    """fe1d default mesh and scheme against the half-space solution, 1 MW/m2 for 10 s."""
    try:
        from fpd.thermal import exact
        from fpd.thermal.fe1d import FE1DPlate
        from fpd.thermal.params import PlateParams
    except ImportError:
        return None
    p = PlateParams(model="fe1d", plate_thickness=0.2, back="adiabatic", h_conv=0.0)
    dt, q = 1e-3, 1e6
    plate = FE1DPlate(p, dt)
    P = q * p.contact_area
    for _ in range(10000):
        T = plate.step(P, 0.0)
    Te = p.T0_C + exact.halfspace_surface(q, 10.0, p.k, p.rho, p.c)
    return abs(T - Te)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="skip the axisym case and the 10^6-step checks")
    ap.add_argument("--repeat", type=int, default=1, help="best of N loop timings per case")
    args = ap.parse_args()
    import numpy
    try:
        from fpd import kernels
        jit = "compiled kernels (numba)" if kernels.available() else "pure kernels (numpy/LAPACK)"
    except ImportError:
        jit = "?"
    print(f"machine: {os.cpu_count()} cores, Python {sys.version.split()[0]}, numpy {numpy.__version__}, "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, fe1d path: {jit}")
    err = None
    try:
        err = thermal_error()
    except Exception as exc:  # the closed form API may differ while it is being built
        print(f"(thermal error not measured: {exc})")
    print(f"{'case':42s} {'steps':>8s} {'loop s':>8s} {'us/step':>8s} {'process s':>9s} {'its loop s':>10s} "
          f"{'peak MiB':>8s} {'thermal err K':>13s}")
    for name, scene_name, over in CASES:
        if args.quick and "axisym" in name:
            continue
        try:
            n, loop = loop_time(scene_name, over, args.repeat)
            wall, mem, summary = process_time(scene_name, over)
        except Exception as exc:
            print(f"{name:42s} not available: {str(exc)[:60]}")
            continue
        e = f"{err:.3g}" if err is not None and "fe1d" in name else "-"
        print(f"{name:42s} {n:8d} {loop:8.3f} {1e6 * loop / n:8.2f} {wall:9.2f} {summary['runtime_s']:10.3f} "
              f"{mem:8.0f} {e:>13s}")
    print("(loop s: best in this process, where numba is loaded; its loop s: the fpd process's own loop,\n"
          " which for a short lumped or mechanics-only scene is the Python one: coupling/fast_loop.py)")
    # memory against steps: the default scene (two-phase, fe1d) with a finer dt
    print("\nfpd run default, memory against steps (whole process, VmHWM):")
    for dt in ("4e-4", "4e-5")[:1 if args.quick else 2]:
        for plots in (False, True):
            try:
                wall, mem, s = process_time("default", [f"solver.dt={dt}"], plots=plots)
            except Exception as exc:
                print(f"  dt = {dt}: not available: {str(exc)[:60]}")
                continue
            print(f"  {s['steps']:8d} steps, plots {'on ' if plots else 'off'}: loop {s['runtime_s']:7.2f} s, "
                  f"process {wall:7.2f} s, peak {mem:6.0f} MiB")
    # cost linear in steps: the same scene over 2x and 4x the steps (record repeats at rest)
    print("\ncost against steps (two-phase if available, else seated; fe1d if available, else lumped):")
    base = ["solver.dt=1e-3"]
    for mech in ("two-phase", "seated"):
        for th in ("fe1d", "lumped"):
            try:
                loop_time("default", [f"mechanics.model={mech}", f"thermal.model={th}", "solver.duration=2"])
            except Exception:
                continue
            prev = None
            durations = (40, 80, 160) if args.quick else (40, 80, 160, 320, 640, 1000)
            for d in durations:
                n, t = loop_time("default", base + [f"mechanics.model={mech}", f"thermal.model={th}",
                                                    f"solver.duration={d}"], repeat=3)
                # the time ratio scaled to a doubling of the steps (1000 s is 1.5625x 640 s)
                ratio = f"{2.0 * (t / prev[1]) / (n / prev[0]):5.2f}x per 2x steps" if prev else ""
                print(f"  {mech:9s} {th:6s} {n:8d} steps {t:8.3f} s {1e6 * t / n:6.2f} us/step {ratio}")
                prev = (n, t)
            return


if __name__ == "__main__":
    main()
