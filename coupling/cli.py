"""``fpd``: the command line (interface.md).

Exit status: 0 success; 2 bad input (one line on stderr, no results folder);
1 numerical failure (history kept); 130 interrupted (history kept).
"""
from __future__ import annotations

import os

# threaded BLAS made small solves up to 100x slower on 2 cores: before numpy loads
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import signal  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

EXIT_OK, EXIT_FAILED, EXIT_INPUT, EXIT_INTERRUPTED = 0, 1, 2, 130


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        sys.stderr.write(f"fpd: error: {message} (see fpd --help)\n")
        raise SystemExit(EXIT_INPUT)


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="fpd", description="Thermo-mechanical simulator of multiple friction pendulum isolators")
    sub = p.add_subparsers(dest="cmd", parser_class=_Parser)
    r = sub.add_parser("run", help="run a scene (default: the packaged default scene)")
    r.add_argument("scene", nargs="?")
    r.add_argument("--out")
    r.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    r.add_argument("--force", action="store_true")
    r.add_argument("--quiet", action="store_true")
    c = sub.add_parser("check", help="validate a scene and print it resolved")
    c.add_argument("scene")
    c.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    sub.add_parser("scenes", help="list the packaged scenes")
    for name, helptext in (("compare", "the scene under lumped / fe1d / axisym plates"),
                           ("converge", "dt and mesh refinement, error against run time")):
        q = sub.add_parser(name, help=helptext)
        q.add_argument("scene")
        q.add_argument("--out")
        q.add_argument("--force", action="store_true")
        q.add_argument("--quiet", action="store_true")
        q.add_argument("--fast", action="store_true", help="a short version (what the tests run)")
    s = sub.add_parser("stability", help="the stiff and extreme catalogue")
    s.add_argument("--out")
    s.add_argument("--force", action="store_true")
    s.add_argument("--quiet", action="store_true")
    s.add_argument("--fast", action="store_true")
    d = sub.add_parser("render", help="PNG frames and a GIF from a run's VTK series")
    d.add_argument("dir")
    d.add_argument("--force", action="store_true", help="replace an existing DIR/render")
    d.add_argument("--quiet", action="store_true")
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
    from . import scene as scn
    from .build import build
    from .output import ResultsFolder, check_out_dir, stream_history, write_all
    from .run import simulate

    scene = scn.load(args.scene, args.set)
    out = Path(args.out) if args.out else Path("results") / scene.name
    check_out_dir(out, args.force)
    sim = build(scene)
    inject = os.environ.get("FPD_INJECT_NAN_AT_STEP")
    try:
        folder = ResultsFolder(out)
    except OSError as exc:       # --out under a file, or where we may not write: a bad option
        raise scn.SceneError(f"{out}: cannot create the results folder there (--out): {exc.strerror}") from None
    held = _HoldSignals()
    try:
        progress = not args.quiet and sys.stderr.isatty()
        vtk = None
        if scene["output"]["vtk_every"] > 0:
            from .vtk_output import VTKSeries
            vtk = VTKSeries(folder.subdir("vtk"), sim)
        hottest = None
        if scene["output"]["plots"] and any(p is not None and p.field() is not None for p in sim.plates):
            from .hottest import HottestFields
            hottest = vtk.hottest if vtk else HottestFields()
        # timeseries.csv is written as the run goes (memory bounded whatever the
        # steps); signals are held from the end of the stepping until the folder is complete
        result = simulate(sim, progress=progress, every=scene["output"]["csv_every"],
                          inject_failure_at=int(inject) if inject else None,
                          on_frame=vtk.frame if vtk else None,
                          frame_every=scene["output"]["vtk_every"], hottest=hottest,
                          history=stream_history(folder, scene), on_loop_end=held.start)
        held.start()
        if vtk:
            vtk.close()
        solver = scene["solver"]
        solver.setdefault("duration", sim.n_steps * sim.dt)
        s = write_all(folder, scene, result, sim, plots=scene["output"]["plots"])
        if hottest is not None:
            hottest.pictures(folder.subdir("plots"))
        folder.commit()
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
        parts.append(f"friction work {(s['friction_work_J']['lower'] + s['friction_work_J']['upper']) / 1e3:.2f} kJ")
        parts.append(f"energy residual {s['energy_residual_rel']:.1e}")
    if "peak_T1_C" in s:
        parts.append(f"peak T {s['peak_T1_C']:.1f} / {s['peak_T2_C']:.1f} \N{DEGREE SIGN}C")
    print("; ".join(parts))
    if s.get("test_machine", {}).get("cycles"):        # coupling/cycles.py
        print("per cycle: " + "; ".join(f"{c['cycle']}: EDC {c['EDC_J'] / 1e3:.1f} kJ, K_eff {c['K_eff_N_m'] / 1e3:.0f} kN/m, "
                                        f"mu_eff {c['mu_eff']:.4f}" for c in s["test_machine"]["cycles"]))
    print(f"results in {out}/")


def cmd_check(args) -> int:
    from . import scene as scn
    scene = scn.load(args.scene, args.set)
    if scene["loading"]["kind"] == "record":
        from .build import build
        build(scene)  # reads and checks the record too
    sys.stdout.write(scn.to_toml(scene))
    return EXIT_OK


def cmd_scenes(args) -> int:
    from . import scene as scn
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
    from fpd.mechanics.ground_motion import RecordError

    from .scene import SceneError
    try:
        handler = {"run": cmd_run, "check": cmd_check, "scenes": cmd_scenes}.get(args.cmd)
        if handler is None:
            # coupling/studies.py: cmd_compare, cmd_converge, cmd_stability;
            # coupling/render.py: cmd_render (imported only when asked for)
            import importlib
            module = importlib.import_module(".render" if args.cmd == "render" else ".studies", __package__)
            handler = getattr(module, f"cmd_{args.cmd}")
        return handler(args)
    except (SceneError, RecordError) as exc:
        return _input_error(str(exc))
    except KeyboardInterrupt:
        sys.stderr.write("fpd: interrupted\n")
        return EXIT_INTERRUPTED


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
