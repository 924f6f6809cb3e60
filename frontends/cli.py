"""``fpd``: the command line (docs/reference.md).

Exit status: 0 success; 2 bad input (one line on stderr, no results folder);
1 numerical failure (history kept); 130 interrupted (history kept); fpd sweep:
3 some members failed or errored, 4 members not run (the cluster lost).
"""
from __future__ import annotations

import os

# threaded BLAS made small solves up to 100x slower on 2 cores: before numpy loads
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import contextlib  # noqa: E402
import errno  # noqa: E402
import signal  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

from fpd.status import EXIT_FAILED, EXIT_INPUT, EXIT_INTERRUPTED, EXIT_MEMBERS, EXIT_OK, EXIT_UNFINISHED  # noqa: F401


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        sys.stderr.write(f"fpd: error: {message} (see fpd --help)\n")
        raise SystemExit(EXIT_INPUT)


_FMT = argparse.RawDescriptionHelpFormatter     # the examples keep their layout


def _wrap(text: str) -> str:
    """A description wrapped as argparse would (the raw formatter leaves it as given)."""
    import textwrap
    return textwrap.fill(text, 88)


_MAIN_EPILOG = """\
examples:
  fpd run                                 run the packaged default scene into results/default/
  fpd run lab-sine --set solver.dt=5e-4   a packaged scene with one key changed
  fpd check my-scene.toml                 validate a scene file and print it resolved
  fpd scenes                              list the packaged scenes
  fpd run --help                          the options of one command

Scene keys, output columns, summary.json fields, exit status: docs/reference.md
(or `fpd reference`). Exit status: 0 ok, 1 numerical failure, 2 bad input, 130 interrupted
(fpd sweep: 3 members not ok, 4 members not run).
"""

_SCENE_HELP = "a scene file (TOML) or a packaged scene name (see `fpd scenes`)"
_SET_HELP = ("override one dotted scene key, typed as TOML (e.g. --set solver.dt=5e-4, "
             "--set thermal.model=lumped); repeat for more keys")


def _common(q, out_default: str) -> None:
    """--out, --force, --quiet: the options every command that writes a folder has."""
    q.add_argument("--out", metavar="DIR", help=f"results folder (default: {out_default})")
    q.add_argument("--force", action="store_true", help="replace DIR if it exists and is not empty")
    q.add_argument("--quiet", action="store_true", help="print nothing but errors (no progress, no report)")


def _parser() -> argparse.ArgumentParser:
    from fpd import __version__

    p = _Parser(prog="fpd", formatter_class=_FMT, epilog=_MAIN_EPILOG,
                description=_wrap("Thermo-mechanical simulator of multiple friction pendulum isolators: a double or "
                            "single friction pendulum sliding, tilting and heating up under an earthquake "
                            "record or a bearing-test machine, with friction falling as the plates heat."))
    p.add_argument("--version", action="version", version=f"fpd {__version__}",
                   help="print the version and exit")
    sub = p.add_subparsers(dest="cmd", parser_class=_Parser, metavar="COMMAND", title="commands")

    r = sub.add_parser(
        "run", formatter_class=_FMT, help="run a scene (default: the packaged default scene)",
        description=_wrap("Run a scene and write DIR: timeseries.csv (one row per step, units in the column names), "
                    "summary.json, scene.toml (the resolved scene), plots/ and, with output.vtk_every > 0, vtk/. "
                    "Bad input stops before anything is written (exit 2)."),
        epilog="""examples:
  fpd run                                       the default scene into results/default/
  fpd run lab-sine --out lab --force            a packaged scene into ./lab, replacing it
  fpd run stability/tall-pad --quiet            a scene of the stability catalogue
  fpd run my.toml --set solver.duration=5 --set output.vtk_every=100
  fpd run results/default/scene.toml --out again   repeat a run exactly
""")
    r.add_argument("scene", nargs="?", metavar="SCENE", help=_SCENE_HELP + "; default: default")
    _common(r, "results/<scene name>/")
    r.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help=_SET_HELP)

    c = sub.add_parser(
        "check", formatter_class=_FMT, help="validate a scene and print it resolved",
        description=_wrap("Validate a scene (and read its record) without running it; print it as TOML with every "
                    "default filled in. Exit 2 with one line naming the key when it is not valid."),
        epilog="""examples:
  fpd check default                             every key of the default scene
  fpd check sfp-harmonic --set friction.mu=0.08   does the override validate?
""")
    c.add_argument("scene", metavar="SCENE", help=_SCENE_HELP)
    c.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help=_SET_HELP)

    sub.add_parser("scenes", formatter_class=_FMT, help="list the packaged scenes",
                   description=_wrap("List the packaged scenes with their one-line descriptions; any of them "
                               "runs by name (`fpd run NAME`)."),
                   epilog="examples:\n  fpd scenes\n  fpd scenes | grep stability\n")

    studies = {
        "compare": ("the scene under lumped / fe1d / axisym plates",
                    "Run the scene with the paper's lumped plate, fe1d (follow-pad and fixed-point) and axisym "
                    "plates side by side; write compare.csv, compare.md (when lumped would be right), plots/.",
                    "results/compare-<scene name>/",
                    "  fpd compare default\n  fpd compare lab-sine --fast --out cmp\n"
                    "  fpd compare lab-sine --liners\n"),
        "converge": ("dt and mesh refinement, error against run time",
                     "Refine dt and each mesh direction separately; measure the error against the closed form "
                     "where the scene has one, Richardson's limit otherwise; write converge.csv, orders.csv "
                     "(observed orders), converge.md and work-precision plots.",
                     "results/converge-<scene name>/",
                     "  fpd converge heat-disk\n  fpd converge default --fast\n"),
    }
    for name, (helptext, desc, out_default, ex) in studies.items():
        q = sub.add_parser(name, formatter_class=_FMT, help=helptext, description=_wrap(desc),
                           epilog="examples:\n" + ex)
        q.add_argument("scene", metavar="SCENE", help=_SCENE_HELP)
        _common(q, out_default)
        q.add_argument("--fast", action="store_true", help="a short version (what the tests run)")
        if name == "compare":
            q.add_argument("--liners", action="store_true",
                           help="instead of the plate models: the scene once per liner preset (docs/liners.md), "
                                "its [friction] replaced by the preset; write liners.csv, liners.md "
                                "(default DIR results/compare-liners-<scene name>/)")

    s = sub.add_parser(
        "stability", formatter_class=_FMT, help="the stiff and extreme catalogue",
        description=_wrap("Run the stability catalogue (the packaged stability/* scenes) at a coarse and a fine dt; "
                    "check finiteness, ledgers, temperature bounds and that both dt tell the same story; "
                    "write stability.csv, stability.md and plots/."),
        epilog="examples:\n  fpd stability --fast\n  fpd stability --out stab --force\n")
    _common(s, "results/stability/")
    s.add_argument("--fast", action="store_true", help="a short version (what the tests run)")

    d = sub.add_parser(
        "render", formatter_class=_FMT, help="PNG frames and a GIF from a run's VTK series",
        description=_wrap("Render a results folder's vtk/ series (written with output.vtk_every > 0) into "
                    "DIR/render/frames/ (at most 200 PNG frames) and DIR/render/device.gif."),
        epilog="examples:\n  fpd run default --set output.vtk_every=100 --out r\n  fpd render r\n")
    d.add_argument("dir", metavar="DIR", help="a results folder of `fpd run` with a vtk/ folder")
    d.add_argument("--force", action="store_true", help="replace an existing DIR/render")
    d.add_argument("--quiet", action="store_true", help="print nothing but errors (no progress, no report)")

    sub.add_parser(
        "reference", formatter_class=_FMT, help="print the reference (docs/reference.md)",
        description=_wrap("Print the reference generated from the code: every command and option, exit status, "
                    "scene key (type, unit, default, allowed values, meaning), output column and summary.json "
                    "field. docs/reference.md is this output."),
        epilog="examples:\n  fpd reference > docs/reference.md\n  fpd reference | grep flux\n")

    # studies/sweep.py: many runs on Dask, one table (docs/sweeps.md)
    w = sub.add_parser(
        "sweep", formatter_class=_FMT, help="run a scene over axes of values on Dask workers; one table",
        description=_wrap("Run a base scene over axes of values (any dotted scene key with a list of values, "
                    "record sets, scale factors; their product or zip) on dask.distributed workers and write "
                    "one tidy table: sweep.csv (and sweep.parquet with pyarrow), one row per member with its "
                    "axis values, status, message and every scalar of its summary.json, and sweep.md. "
                    "Finished members are stored as they finish: a rerun skips them (docs/sweeps.md)."),
        epilog="""examples:
  fpd sweep my-sweep.toml --out sw              one worker per core on a local cluster
  fpd sweep my-sweep.toml --out sw --workers 1  one local worker
  fpd sweep my-sweep.toml --out sw --scheduler tcp://head:8786   an existing Dask cluster

exit status: 0 every member ok; 3 some members failed or errored (the table is complete,
a rerun retries them); 4 members not run (the cluster lost: run again to finish);
2 bad input; 130 interrupted.
""")
    w.add_argument("sweep", metavar="SWEEP.toml", help="the sweep file (TOML: scene, mode, [axes], [set], [run])")
    w.add_argument("--out", metavar="DIR", help="results folder (default: results/<sweep name>/)")
    w.add_argument("--workers", type=int, help="local worker processes (default: one per core)")
    w.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, e.g. tcp://host:8786")
    w.add_argument("--force", action="store_true", help="start afresh (default: resume a sweep in --out)")
    w.add_argument("--keep-failed", action="store_true",
                   help="on a rerun, keep stored failed and error members (default: retry every member not ok)")
    w.add_argument("--max-members", type=int, metavar="N",
                   help="refuse a sweep of more than N members (default: 100000)")
    w.add_argument("--quiet", action="store_true", help="print nothing but errors (no progress, no report)")

    m = sub.add_parser(
        "map", formatter_class=_FMT,
        help="the regime map: where each model choice changes the answer (a packaged sweep)",
        description=_wrap("The regime map: the default device over pad aspect h/D and intensity (pulses and "
                    "FEMA P695 records scaled), each cell run with two-phase / seated, fe1d / lumped plates "
                    "and two friction levels at dt and dt/2; heat maps with the 1, 5 and 20 % contours and "
                    "map.md stating where each model choice changes the answer (docs/sweeps.md)."),
        epilog="examples:\n  fpd map --quick --out map\n  fpd map --out map --workers 2\n")
    m.add_argument("--quick", action="store_true", help="a coarse map (a few minutes on 2 cores)")
    m.add_argument("--out", metavar="DIR", help="results folder (default: results/map/)")
    m.add_argument("--workers", type=int, help="local worker processes (default: one per core)")
    m.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, e.g. tcp://host:8786")
    m.add_argument("--force", action="store_true", help="start afresh (default: resume the map's sweep in --out)")
    m.add_argument("--quiet", action="store_true", help="print nothing but errors (no progress, no report)")
    return p


def _input_error(msg: str) -> int:
    sys.stderr.write(f"fpd: error: {msg}\n")
    return EXIT_INPUT


def _sigterm(signum, frame):
    raise KeyboardInterrupt


class _HoldSignals:
    """Between start() and stop(), Ctrl-C and SIGTERM are held, not raised: a
    second interrupt while the computed history is written cannot lose it."""

    got = None
    old = {}

    def start(self):
        if not self.old:
            self.old = {sig: signal.signal(sig, self._hold) for sig in (signal.SIGINT, signal.SIGTERM)}

    def _hold(self, signum, frame):
        self.got = signum

    def stop(self):
        for sig, handler in self.old.items():
            signal.signal(sig, handler)
        self.old = {}


def cmd_run(args) -> int:
    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.outputs.claim import hold
    from fpd.outputs.output import ResultsFolder, after_write_error, guard_frames, stream_history, write_all
    from fpd.coupling.run import simulate

    scene = scn.load(args.scene, args.set)
    out = Path(args.out) if args.out else Path("results") / scene.name
    hold(args, out)             # DIR ours until the command returns; exit 2 if another process has it
    sim = build(scene)
    inject = os.environ.get("FPD_INJECT_NAN_AT_STEP")
    try:
        folder = ResultsFolder(out)
    except OSError as exc:       # --out under a file, or where we may not write: a bad option
        if exc.errno in (errno.ENOSPC, errno.EDQUOT):
            raise                   # not the option's fault: main() says so, exit 1
        raise scn.SceneError(f"{out}: cannot create the results folder there (--out): {exc.strerror}") from None
    held = _HoldSignals()
    history = result = None
    try:
        progress = not args.quiet and sys.stderr.isatty()
        vtk = None
        if scene["output"]["vtk_every"] > 0:
            from fpd.outputs.vtk_output import VTKSeries        # the device's drawing: its stepper names it
            vtk = VTKSeries(folder.subdir("vtk"), sim)
        hottest = None
        if scene["output"]["plots"] and any(p is not None and p.field() is not None for p in sim.plates):
            from fpd.outputs.hottest import HottestFields
            hottest = vtk.hottest if vtk else HottestFields.of(sim)   # two plates or the TFP's four parts
        # timeseries.csv is written as the run goes (memory bounded whatever the
        # steps); signals are held from the end of the stepping until the folder is complete
        history = stream_history(folder, scene)
        result = simulate(sim, progress=progress, every=scene["output"]["csv_every"],
                          inject_failure_at=int(inject) if inject else None,
                          on_frame=guard_frames(vtk.frame, sim.dt) if vtk else None,
                          frame_every=scene["output"]["vtk_every"], hottest=hottest,
                          history=history, on_loop_end=held.start)
        held.start()
        if vtk:
            vtk.close()
        solver = scene["solver"]
        solver.setdefault("duration", sim.n_steps * sim.dt)
        s = write_all(folder, scene, result, sim, plots=scene["output"]["plots"], hottest=hottest)
        folder.commit()
    except OSError as exc:      # disk full, quota, permission, folder removed: one line (output.after_write_error)
        held.start()
        sys.stderr.write(f"fpd: {after_write_error(folder, scene, sim, exc, history, result)}\n")
        return EXIT_FAILED
    except BaseException:
        folder.discard()
        raise
    finally:
        held.stop()
    if held.got is not None and result.status == "ok":
        sys.stderr.write(f"fpd: interrupted while writing; the complete results are in {out}\n")
        return EXIT_INTERRUPTED
    if not args.quiet:
        _report(s, out)
    if result.status == "failed":
        sys.stderr.write(f"fpd: {result.message}; history up to then kept in {out}\n")
        return EXIT_FAILED
    if result.status == "interrupted":
        sys.stderr.write(f"fpd: {result.message}; history up to then kept in {out}\n")
        return EXIT_INTERRUPTED
    return EXIT_OK


def _report(s: dict, out: Path) -> None:
    parts = [f"{s['scene']}: {s['status']}, {s['steps']} steps in {s['runtime_s']:.2f} s"]
    if "peak_u_m" in s and s["peak_u_m"] is not None:
        parts.append(f"peak u {1e3 * s['peak_u_m']:.1f} mm, residual {1e3 * s['residual_u_m']:.1f} mm")
        parts.append(f"friction work {sum(s['friction_work_J'].values()) / 1e3:.2f} kJ")
        parts.append(f"energy residual {s['energy_residual_rel']:.1e}")
    if "peak_T1_C" in s:
        parts.append(f"peak T {s['peak_T1_C']:.1f} / {s['peak_T2_C']:.1f} \N{DEGREE SIGN}C")
    print("; ".join(parts))
    if s.get("test_machine", {}).get("cycles"):        # outputs/cycles.py
        print("per cycle: " + "; ".join(f"{c['cycle']}: EDC {c['EDC_J'] / 1e3:.1f} kJ, K_eff {c['K_eff_N_m'] / 1e3:.0f} kN/m, "
                                        f"mu_eff {c['mu_eff']:.4f}" for c in s["test_machine"]["cycles"]))
    print(f"results in {out}/")


def cmd_check(args) -> int:
    from fpd.schema import scene as scn
    scene = scn.load(args.scene, args.set)
    if scene["loading"]["kind"] == "record":
        from fpd.coupling.build import build
        build(scene)  # reads and checks the record too
    sys.stdout.write(scn.to_toml(scene))
    return EXIT_OK


def cmd_scenes(args) -> int:
    from fpd.schema import scene as scn
    for name in scn.packaged_scenes():
        try:
            raw = scn.read_toml(scn.SCENES_DIR / f"{name}.toml")
            desc = raw.get("description", "")
        except scn.SceneError:
            desc = "(unreadable)"
        print(f"{name:24s} {desc}")
    return EXIT_OK


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    if args.cmd is None:
        _parser().print_help()
        return EXIT_INPUT
    signal.signal(signal.SIGTERM, _sigterm)
    if argv is None:
        # the command's own process (not a caller's): the garbage collector
        # runs less often (compiling the kernels and drawing allocate many
        # small objects: about 8 % of a first run's compile), kernels and
        # figures load lean (fpd/kernels.py, outputs/drawing.py)
        import gc
        gc.set_threshold(20_000, 50, 100)
        from fpd import kernels
        from fpd.outputs import drawing
        kernels.LEAN = drawing.LEAN = True
    if not getattr(args, "quiet", False):
        from fpd import jitcache
        jitcache.enable()           # one line on stderr before the first compile of the kernels
    from fpd.loading.ground_motion import RecordError

    from fpd.schema.scene import SceneError
    args.claims = contextlib.ExitStack()     # results folders claimed (outputs/claim.py), released on return
    try:
        handler = {"run": cmd_run, "check": cmd_check, "scenes": cmd_scenes}.get(args.cmd)
        if handler is None:
            # the studies (studies/<name>.py: cmd_compare, cmd_converge, cmd_stability,
            # cmd_sweep; regime_map.py: cmd_map), outputs/render.py: cmd_render,
            # frontends/reference.py: cmd_reference (imported only when asked for)
            import importlib
            module = importlib.import_module({"render": "fpd.outputs.render", "reference": "fpd.frontends.reference",
                                              "map": "fpd.studies.regime_map"}.get(args.cmd, f"fpd.studies.{args.cmd}"))
            handler = getattr(module, f"cmd_{args.cmd}")
        with args.claims:
            return handler(args)
    except (SceneError, RecordError) as exc:
        return _input_error(str(exc))
    except KeyboardInterrupt:
        sys.stderr.write("fpd: interrupted\n")
        return EXIT_INTERRUPTED
    except OSError as exc:      # a study's results could not be written: none were (ResultsFolder)
        claimed = getattr(args, "claimed", None)
        if exc.errno is None or isinstance(exc, BrokenPipeError) or not claimed:
            raise
        from fpd.outputs.output import describe_os_error
        sys.stderr.write(f"fpd: {describe_os_error(exc)}; {args.cmd} wrote nothing, {claimed[0]} unchanged\n")
        return EXIT_FAILED


def entry() -> None:
    """The console script: run, then ignore further Ctrl-C/SIGTERM while the
    interpreter exits (the results are already complete and in place; a late
    signal must not turn a finished run's exit status into a crash)."""
    try:
        code = main()
        sys.stdout.flush()
    except BrokenPipeError:             # `fpd scenes | head`: the reader left, not an error of ours
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        code = EXIT_OK
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    sys.exit(code)


if __name__ == "__main__":
    entry()
