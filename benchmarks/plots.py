"""What the plots cost a run: `python3 benchmarks/plots.py [SCENE ...] [--repeat R]`.

For each scene (default: ``default``, ``impvall-bidirectional``, ``lab-sine``,
``tfp-elcentro``):

- the process time (user + system) of ``fpd run SCENE`` with
  ``output.plots = true`` and with ``output.plots = false``, best of R runs,
  and their difference: what the plots cost the command (importing
  matplotlib, the hottest-field looks during the loop, drawing, writing the
  PNGs);
- in one process, the time of the plotting alone (``make_plots``, the
  per-cycle plot and the hottest-field pictures) after the run, per figure.

``--cli``: instead, the process time of the plotting part of ``fpd run
SCENE`` in the command's own process (its lean matplotlib import included:
importing matplotlib, every figure and hottest-field picture, writing the
PNGs), best of R runs; with ``--against ROOT`` the same for the source tree
at ROOT, the runs of both trees interleaved (A, B, A, B, ...) so that a
machine shared with other work loads both alike.

The numba cache must be warm (run ``python3 -m fpd run SCENE`` once before,
in each tree measured).
"""
from __future__ import annotations

import argparse
import importlib
import os
import resource
import subprocess
import sys
import tempfile
import time

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
SCENES = ("default", "impvall-bidirectional", "lab-sine", "tfp-elcentro")


def process_time(scene: str, plots: bool, out: str) -> float:
    env = dict(os.environ, PYTHONPATH=ROOT, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MPLBACKEND="Agg")
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sys.executable, "-m", "fpd", "run", scene, "--set", f"output.plots={str(plots).lower()}",
                    "--out", out, "--force", "--quiet"], env=env, check=True, cwd=ROOT)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def in_process(scene: str, out: str) -> list[tuple[str, float]]:
    """Per-figure process time of the plots of one run, in this process."""
    sys.path.insert(0, ROOT)
    import fpd
    from fpd.outputs import output

    times = []
    calls = {}
    real_write_all = output.write_all

    def write_all(folder, sc, result, sim, plots=True, hottest=None):
        s = real_write_all(folder, sc, result, sim, plots=False)
        t0 = time.process_time()
        importlib.import_module("matplotlib.figure")     # what the first figure pays, once
        times.append(("import matplotlib", time.process_time() - t0))
        from fpd.outputs import figures as pl
        s["plots"] = pl.make_plots(folder.subdir("plots"), result.plot_view(), sc, timings=times)
        if s.get("test_machine", {}).get("cycles"):
            from fpd.outputs.cycles import plot_cycles
            t1 = time.process_time()
            plot_cycles(folder.path("plots", "cycles.png"), s["test_machine"]["cycles"], sc.name)
            times.append(("cycles.png", time.process_time() - t1))
        if hottest is not None:
            t1 = time.process_time()
            hottest.pictures(folder.subdir("plots"))
            times.append(("*_hottest.png", time.process_time() - t1))
        calls["make_plots"] = time.process_time() - t0
        return s

    output.write_all = write_all
    try:
        fpd.run(scene, out=out, force=True)
    finally:
        output.write_all = real_write_all
    return times


# run in a child process: fpd run's own command line (its lean matplotlib import), the process
# time spent inside the plotting calls of write_all summed and printed as the last line
_CLI = r"""
import sys, time
from fpd.outputs import cycles, figures, hottest
spent = [0.0]
def timed(f):
    def g(*a, **k):
        t0 = time.process_time()
        try:
            return f(*a, **k)
        finally:
            spent[0] += time.process_time() - t0
    return g
figures.make_plots = timed(figures.make_plots)
cycles.plot_cycles = timed(cycles.plot_cycles)
hottest.HottestFields.pictures = timed(hottest.HottestFields.pictures)
sys.argv = ["fpd", "run", %r, "--out", %r, "--force", "--quiet"]
from fpd.frontends.cli import main
code = main()
print("plotting-process-s", spent[0])
sys.exit(code)
"""


def cli_plotting(root: str, scene: str, out: str) -> float:
    """Process time of the plotting part of ``fpd run SCENE`` (tree at root)."""
    env = dict(os.environ, PYTHONPATH=root, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MPLBACKEND="Agg")
    r = subprocess.run([sys.executable, "-c", _CLI % (scene, out)], env=env, check=True, cwd=root,
                       capture_output=True, text=True)
    return float(r.stdout.strip().splitlines()[-1].split()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenes", nargs="*", default=list(SCENES))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-split", action="store_true", help="skip the in-process per-figure times")
    ap.add_argument("--cli", action="store_true",
                    help="only the plotting part of fpd run in its own process (best of R)")
    ap.add_argument("--against", metavar="ROOT", help="with --cli: also the source tree at ROOT, interleaved")
    a = ap.parse_args(argv)
    if a.cli:
        trees = [("this tree", ROOT)] + ([("against", os.path.abspath(a.against))] if a.against else [])
        with tempfile.TemporaryDirectory(prefix="fpd-plots-") as tmp:
            print(f"plotting part of fpd run, process s, best of {a.repeat} (all runs)")
            for sc in a.scenes:
                runs = {name: [] for name, _ in trees}
                for _ in range(a.repeat):
                    for name, root in trees:
                        runs[name].append(cli_plotting(root, sc, os.path.join(tmp, "cli")))
                for name, _ in trees:
                    print(f"{sc:24s} {name:10s} {min(runs[name]):6.3f}   ("
                          + " ".join(f"{t:.3f}" for t in runs[name]) + ")", flush=True)
        return 0
    with tempfile.TemporaryDirectory(prefix="fpd-plots-") as tmp:
        print(f"{'scene':24s} {'with plots':>11s} {'without':>9s} {'plots cost':>11s}  (process s, best of {a.repeat})")
        for sc in a.scenes:
            on = min(process_time(sc, True, os.path.join(tmp, "on")) for _ in range(a.repeat))
            off = min(process_time(sc, False, os.path.join(tmp, "off")) for _ in range(a.repeat))
            print(f"{sc:24s} {on:11.2f} {off:9.2f} {on - off:11.2f}", flush=True)
        if not a.no_split:
            for sc in a.scenes:
                code = ("import sys, json; sys.path.insert(0, %r); sys.argv = ['x']; "
                        "import importlib.util as u; s = u.spec_from_file_location('b', %r); m = u.module_from_spec(s); "
                        "s.loader.exec_module(m); print(json.dumps(m.in_process(%r, %r)))"
                        % (ROOT, os.path.abspath(__file__), sc, os.path.join(tmp, "split")))
                env = dict(os.environ, PYTHONPATH=ROOT, OPENBLAS_NUM_THREADS="1", MPLBACKEND="Agg")
                import json
                out = subprocess.run([sys.executable, "-c", code], env=env, check=True, capture_output=True,
                                     text=True, cwd=ROOT).stdout.strip().splitlines()[-1]
                times = json.loads(out)
                total = sum(t for _, t in times)
                print(f"{sc}: plotting alone {total:.2f} s: " + ", ".join(f"{n} {t:.3f}" for n, t in times))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
