"""simulate()'s compiled path: when to use it, and the driver.

The staggered step with one thermal step per step, lumped / fe1d / no
plates and friction laws of tribology.friction runs in the coupled engine
(coupling/engine_kernel.run_chunk) compiled by fpd.kernels.compiled with the
device bound (``bind={"dev": mech.engine_device}``), over ranges of steps;
this module calls it in chunks that end at simulate()'s events (progress
bar, VTK frames, hottest-field tracker, every 2048 steps so that Ctrl-C is
seen within ~10 ms). The device declares what the engine needs
(``engine_device``, ``engine_state()``, ``engine_pull(S)``, ``engine_push(S, n)``:
mechanics/two_phase.py, bidirectional.py, tfp.py); the plates' rows P travel
as float64 copies written back after each chunk (fe1d arrays are shared), so
the Python loop can take over at any step (an injected failure, a step the
engine hands back because Python would raise there).

Used only with numba installed and FPD_NO_JIT unset. A scene with an fe1d
plate uses it always (numba is loaded for the column kernel anyway); a
lumped or mechanics-only scene only when numba is already loaded in the
process (a study, a process that ran an fe1d scene) or when the device's
Python step is slow enough that loading numba pays for itself over the run
(``engine_worth_loading(n_steps)``; the TFP past ~5000 steps): loading numba
and the kernels costs ~0.7 s, while the planar DFP's Python loop costs
~10 us per step.
"""
from __future__ import annotations

import sys

import numpy as np

from fpd import kernels

from . import compile_aside, engine_kernel

CHUNK = 2048                 # steps per call at most (progress bar, Ctrl-C latency)
enabled = True               # False: always the Python loop (tests compare the two)


def _numba_loaded() -> bool:
    return "numba" in sys.modules


def _plate_kind(plate):
    """'none', 'lumped', 'fe1d' or None (not compiled: the Python loop runs it)."""
    from fpd.thermal.lumped import LumpedPlate

    if plate is None:
        return "none"
    if "step" in vars(plate):
        return None                  # patched (tests)
    if type(plate) is LumpedPlate:
        return "lumped"
    if type(plate).__name__ == "FE1DPlate" and type(plate).__module__ == "fpd.thermal.fe1d":
        return "fe1d"
    return None


def plate_kinds(sim, worth_loading: bool = False):
    """The plates' kinds when a compiled loop (this one, the bidirectional's,
    the TFP's) can step them and read the laws, and may (numba available,
    loaded, needed for an fe1d plate, or ``worth_loading``: a loop whose
    Python steps cost more than loading numba), else None."""
    kinds = [_plate_kind(p) for p in sim.plates]
    if None in kinds:
        return None
    if "fe1d" not in kinds and not _numba_loaded() and not worth_loading:
        return None
    if not kernels.available():
        return None
    if any(getattr(law, "P", None) is None for law in sim.laws):
        return None
    return kinds


def law_rows(laws):
    """The friction laws as the loop kernels read them (friction_kernel.law_mu's rows)."""
    return tuple(np.array(law.P) for law in laws)


def plate_arrays(plates, kinds, lj):
    """Per plate the arrays the loop kernels step, (Mb, Ab, FAC, V, I, P), and
    whether P is a float64 copy of the plate's row (written back by
    unpack_plates), with the kind codes of the engine ``lj``. fe1d arrays
    are the plate's own; stand-ins of their types for the others (one
    compiled signature for every mix; (2, 2) in Fortran order: a (2, 1) array
    would also be C-contiguous, typed 'C' by numba)."""
    dummy_f, dummy_i = np.zeros(1), np.zeros(8, dtype=np.int32)
    dummy_F, dummy_T = np.zeros((2, 2), order="F"), tuple(np.zeros(1) for _ in range(6))
    out = []
    for plate, kind in zip(plates, kinds):
        if kind == "fe1d":
            it = plate.integ
            P = it.P if isinstance(it.P, np.ndarray) else np.array(it.P)
            out.append(((it.Mb, it.Ab, it.FAC, it.V, it.I, P), P is not it.P))
        else:
            P = np.array(plate.P) if kind == "lumped" else dummy_f
            out.append(((dummy_F, dummy_F, dummy_T, dummy_T, dummy_i, P), kind == "lumped"))
    codes = [{"none": lj.KIND_NONE, "lumped": lj.KIND_LUMPED, "fe1d": lj.KIND_FE1D}[k] for k in kinds]
    return out, codes


def pack_plates(plates, arrays) -> None:
    """The plates' rows into their float64 copies (before a chunk)."""
    for plate, (arr, copy) in zip(plates, arrays):
        if copy:
            arr[5][:] = plate.integ.P if hasattr(plate, "integ") else plate.P


def unpack_plates(plates, arrays) -> None:
    """The float64 copies back into the plates' rows (the Python loop's state)."""
    for plate, (arr, copy) in zip(plates, arrays):
        if copy:
            target = plate.integ.P if hasattr(plate, "integ") else plate.P
            target[:] = arr[5].tolist()


def eligible(sim):
    """The plate kinds when the compiled engine can run this simulation's
    steps (and may: numba available, loaded, needed or worth loading), else None."""
    mech = sim.mechanics
    if not enabled or mech is None or sim.substeps != 1 or sim.scene["coupling"]["scheme"] != "staggered":
        return None
    if getattr(mech, "engine_device", None) is None:
        return None
    if any(k in vars(mech) for k in ("step", "values", "save", "restore")):
        return None                  # patched (tests): the Python loop calls the patch
    worth = getattr(mech, "engine_worth_loading", None)
    return plate_kinds(sim, worth_loading=bool(worth and worth(sim.n_steps)))


def engine(mech):
    """The coupled engine compiled with this stepper's device bound (ImportError without numba)."""
    return kernels.compiled("fpd.coupling.engine_kernel", bind={"dev": mech.engine_device})


def loop_columns(sim) -> list:
    """The loop's row: the stepper's columns, mu_i and, with plates, T_i, E_stored_J, E_air_J."""
    n = len(sim.plates)
    cols = list(sim.mechanics.columns) + [f"mu{i + 1}" for i in range(n)]
    if any(p is not None for p in sim.plates):
        cols += [f"T{i + 1}_C" for i in range(n)] + ["E_stored_J", "E_air_J"]
    if getattr(sim, "wear", None) is not None:
        cols += [f"path{i + 1}_m" for i in range(n)] + [f"wear{i + 1}_m" for i in range(n)]
    return cols


# the loop's wear columns (loop_columns: the first N of each, N the interfaces)
WEAR_COLUMNS = tuple(f"path{i}_m" for i in range(1, 5)) + tuple(f"wear{i}_m" for i in range(1, 5))


def wear_state(sim):
    """(rows, state) of the loop's wear (friction_kernel.wear_step): per
    interface the wear coefficient's row, and the paths then the depths
    (float64, shared by the compiled and the Python loop); None without wear."""
    if getattr(sim, "wear", None) is None:
        return None
    if getattr(sim, "wear_PW", None) is None:
        sim.wear_PW = np.zeros(2 * len(sim.plates))
    return tuple(np.array(w.P) for w in sim.wear), sim.wear_PW


def warm(sim) -> None:
    """Load (or compile) the engine now, if this simulation will use it: at
    build time, before the run's folder exists and its Ctrl-C handling starts."""
    kinds = eligible(sim)
    if kinds is None:
        return
    try:
        CompiledLoop(sim, engine(sim.mechanics), kinds, 1, 1, loop_columns(sim), None)
    except ImportError:
        return


def compiled_loop(sim, every: int, n_rows: int, cols, inject_failure_at=None, track=None):
    """A CompiledLoop for this simulation, or None: the Python loop runs it.
    ``track``: (SX, SN, LI, SL), every step's extremes and ledger (run.StepTracker)."""
    kinds = eligible(sim)
    if kinds is None:
        return None
    if inject_failure_at is not None and inject_failure_at <= 1:
        return None
    if list(cols) != loop_columns(sim):
        return None
    try:
        eng = engine(sim.mechanics)
        return CompiledLoop(sim, eng, kinds, every, n_rows, cols, inject_failure_at, track)
    except ImportError:
        return None


class CompiledLoop:
    """Runs steps 1.. of simulate()'s loop compiled; see run()."""

    def __init__(self, sim, eng, kinds, every, n_rows, cols, inject_failure_at, track=None):
        self.sim, self.lj = sim, eng
        self.kinds, self.cols = kinds, list(cols)
        mech = sim.mechanics
        ni = len(sim.plates)
        N = sim.n_steps
        # the Python loop takes over at an injected failure
        self.n_stop = N if inject_failure_at is None else min(N, inject_failure_at - 1)
        self.C, self.S, self.L, self.X = mech.engine_state()
        self.S0 = np.zeros(len(self.S))
        self.LW = law_rows(sim.laws)
        self.areas = np.array(sim.areas, dtype=float)
        self.eta = np.array([p.heat_share for p in sim.plate_params], dtype=float)
        self.T, self.mu = np.zeros(ni), np.zeros(ni)
        self.hot = np.full(ni, -np.inf)     # each face's highest temperature at the looks so far
        self.mun, self.dW = np.zeros(ni), np.zeros(ni)
        self.ctl = np.zeros(eng.N_CTL, dtype=np.int64)
        self.ctl[eng.C_NROWS], self.ctl[eng.C_EVERY], self.ctl[eng.C_N] = n_rows, every, N
        self.ctl[eng.C_HEAT] = any(k != "none" for k in kinds)
        self.ctl[eng.C_NVAL] = len(mech.columns)
        self.ctl[eng.C_2D] = 1 if getattr(mech, "two_d", False) else 0
        wear = wear_state(sim)
        if wear is None:             # stand-ins of the same types
            self.WL, self.PW = self.LW, np.zeros(0)
        else:
            self.WL, self.PW = wear
            self.ctl[eng.C_WEAR] = 1
        self.row = np.zeros(len(cols))
        # per plate: (Mb, Ab, FAC, V, I, P) and whether P is a copy; then six tuples over the plates
        self.plates, codes = plate_arrays(sim.plates, kinds, eng)
        self.kind_codes = np.array(codes, dtype=np.int64)
        self.plate_args = tuple(tuple(arr[j] for arr, _ in self.plates) for j in range(6))
        if track is None:            # every row kept: the history sees every step (stand-ins of the same types)
            track = (np.zeros(1), np.zeros(1), np.zeros(0, dtype=np.int64), np.zeros(2))
        else:
            self.ctl[eng.C_TRACK] = 1
        self.track = track
        # load the engine now (build() did: warm()), not in the timed loop; a first compile
        # shares its work with a second process (coupling/compile_aside.py)
        compile_aside.share(sim, self.C, self.S, self.L, self.X, sim.dt, self.mun, self.dW, self.row,
                            self.plates, kinds)
        self._call(np.zeros((1, len(cols))))

    def _args(self, buf):
        return (self.C, self.S, self.S0, self.L, self.X, self.sim.dt, self.LW, self.areas, self.eta,
                self.kind_codes, *self.plate_args, self.T, self.hot, self.mu, self.mun, self.dW, buf, self.row,
                self.ctl, *self.track, self.WL, self.PW)

    def _call(self, buf):
        """run_chunk from ctl[C_NDONE] to ctl[C_NEND] (0 to 0: just the dispatch)."""
        return self.lj.run_chunk(*self._args(buf))

    # -- the models' state <-> the engine's arrays ----------------------------------------
    def _pack(self):
        self.sim.mechanics.engine_pull(self.S)
        pack_plates(self.sim.plates, self.plates)

    def _unpack(self, n=None):
        self.sim.mechanics.engine_push(self.S, int(self.ctl[self.lj.C_NDONE]) if n is None else n)
        unpack_plates(self.sim.plates, self.plates)

    # -- the run -----------------------------------------------------------------------
    def run(self, buf, k, last_row, T, mu, bar=None, hottest=None, hot_every=1,
            on_frame=None, frame_every=0, start=0, pending=False):
        """Steps start+1..n_stop (or until a step the Python loop must take),
        their rows into buf (loop column order) from row k, with simulate()'s
        temperatures T and friction coefficients mu (lists, one per
        interface) and counters as they are after step start.
        Returns an Outcome; never raises for Ctrl-C or a failed row (the
        Outcome carries them, simulate() raises them once its own counters
        are set). Outcome.full: buf filled up at step Outcome.steps; the
        caller empties it and calls again with start=that step and
        pending=True (that step's frame, hottest and progress events are run
        then, after the flush, in simulate()'s order)."""
        lj = self.lj
        ctl = self.ctl
        ctl[lj.C_NDONE], ctl[lj.C_K], ctl[lj.C_LAST] = start, k, last_row
        ctl[lj.C_NROWS] = len(buf)
        self.T[:], self.mu[:] = T, mu
        self._pack()
        run_chunk = self.lj.run_chunk
        ctl[lj.C_HOT] = hot_every if hottest is not None else 0
        args = self._args(buf)
        events = (bar, hottest, on_frame, frame_every)
        out = Outcome()
        n = start
        events_of = 0                # the step whose events are running (Ctrl-C there: that step)
        try:
            if pending:              # the chunk stopped before its look at step n, if any
                events_of = n
                look = hottest is not None and n % hot_every == 0 and engine_kernel.hotter(self.T, self.hot)
                self._events(n, *events, look)
                events_of = 0
            while n < self.n_stop:
                n_end = min(self.n_stop, (n // CHUNK + 1) * CHUNK)
                if on_frame is not None and frame_every:
                    n_end = min(n_end, (n // frame_every + 1) * frame_every)
                ctl[lj.C_NEND] = n_end
                status = run_chunk(*args)
                n = int(ctl[lj.C_NDONE])
                if status == lj.REPLAY:
                    break
                if status == lj.ROW_FAILED:
                    n += 1
                    vals = self.row.tolist()
                    bad = [c for c, x in zip(self.cols, vals) if not np.isfinite(x)]
                    out.failure = (n, "non-finite " + ", ".join(bad))
                    break
                if status == lj.FULL:
                    out.full = True
                    break
                events_of = n
                self._events(n, *events, status == lj.LOOK)
                events_of = 0
        except KeyboardInterrupt:
            out.interrupted = True
        finally:
            self._unpack()
        out.steps = int(ctl[lj.C_NDONE])
        out.k, out.last_row = int(ctl[lj.C_K]), int(ctl[lj.C_LAST])
        out.T, out.mu = self.T.tolist(), self.mu.tolist()
        # the step in progress (simulate()'s n) when it stopped early
        out.n = out.steps
        if out.failure:
            out.n = out.failure[0]
        elif out.interrupted and not events_of:
            out.n = min(out.steps + 1, self.sim.n_steps)
        return out

    def _events(self, n, bar, hottest, on_frame, frame_every, look):
        """simulate()'s events at the end of step n, in its order (``look``:
        at the plate fields, for ``hottest``)."""
        if on_frame is not None and frame_every and n % frame_every == 0 and int(self.ctl[self.lj.C_LAST]) == n:
            self._unpack(n)
            self.sim.frame_values = self._frame_values(self.row)
            on_frame(n, self.sim)
        if look:
            self._unpack(n)
            hottest.update(self.sim.plates, n * self.sim.dt)
        if bar is not None and n % 2048 == 0:
            bar.update(n)

    def _frame_values(self, r):
        vals = dict(zip(self.cols, r.tolist()))
        for c in ("phase", "diagonal", "phases"):
            if c in vals:
                vals[c] = int(vals[c])
        return vals


class Outcome:
    """How the compiled part ended: steps done, rows kept, the loop's floats."""

    steps = n = k = last_row = 0
    T = mu = ()
    interrupted = False
    full = False             # the row buffer filled up (see CompiledLoop.run)
    failure = None           # (step, what) of a non-finite row
