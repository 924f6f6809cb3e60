"""The staggered thermo-mechanical loop (model.md section 5).

Per step: mu_i(T_i^n) -> mechanics step -> friction work of each interface
and footprint position -> thermal step of each plate -> T_i^{n+1}.
``iterated`` repeats the step (every model restored exactly from its
snapshot) with mu evaluated at the new temperatures until they change by less
than tol_K.
"""
from __future__ import annotations

import math
import sys
import time

import numpy as np

from fpd.tribology.friction_kernel import wear_step
from fpd.mechanics.phases import PHASES, MechanicsFailure

from .build import Simulation
from .engine_kernel import hotter
from .fast_loop import _plate_kind, compiled_loop, loop_columns, wear_state
from .recording import MemoryHistory, signals_held

# canonical column order (docs/reference.md), every device; extra diagnostic columns follow
CANONICAL = ("t_s", "xg_m", "u_m", "v_mps", "F_N", "z_m", "theta_rad", "beta_rad",
             "s1_m", "s2_m", "s3_m", "s4_m", "N1_N", "N2_N", "N3_N", "N4_N", "mu1", "mu2", "mu3", "mu4",
             "T1_C", "T2_C", "T3_C", "T4_C", "W1_J", "W2_J", "W3_J", "W4_J", "phase", "E_input_J",
             "E_kin_J", "E_pot_J", "E_rim_J", "E_reseat_J", "E_stored_J", "E_air_J")


LOOKS = 2000        # looks at the fields per run: often enough to catch the peak, cheap


def look_every(n_steps: int) -> int:
    """Steps between two looks at the plate fields (a hottest-field tracker's updates)."""
    return max(1, n_steps // LOOKS)


class NumericalFailure(RuntimeError):
    def __init__(self, step: int, t: float, what: str):
        super().__init__(f"numerical failure at step {step} (t = {t:.6g} s): {what}")
        self.step, self.t, self.what = step, t, what


class Interrupted(RuntimeError):
    pass


# what stops a loop and is reported in its Result (status, message), history kept
LOOP_STOPS = (NumericalFailure, MechanicsFailure, ArithmeticError, ValueError, KeyboardInterrupt)


def stop_status(exc: BaseException, n: int, dt: float) -> tuple[str, str]:
    """(status, message) of a loop stopped at step n by one of LOOP_STOPS."""
    if isinstance(exc, KeyboardInterrupt):
        return "interrupted", f"interrupted at step {n} (t = {n * dt:.6g} s)"
    if isinstance(exc, NumericalFailure):
        return "failed", str(exc)
    if isinstance(exc, MechanicsFailure):           # e.g. the pad overturned
        return "failed", str(NumericalFailure(n, n * dt, str(exc)))
    # overflow, division by zero, math domain...
    return "failed", str(NumericalFailure(n, n * dt, f"{type(exc).__name__}: {exc}"))


def check_row(r, cols, n: int, dt: float) -> None:
    """A history row must be finite: NumericalFailure naming the columns that are not."""
    if not math.isfinite(sum(r)):
        bad = [c for c, x in zip(cols, r) if not math.isfinite(x)]
        raise NumericalFailure(n, n * dt, "non-finite " + ", ".join(bad))


class Result:
    """A run's history (numpy columns) and its bookkeeping.

    In memory (the default): ``data`` holds every recorded row, ``res["u_m"]``
    a column. Streamed (``simulate(..., history=StreamHistory(...))``, what
    ``fpd run`` does): the rows are in the CSV the history wrote; ``stats``
    (reductions for the summary), ``plot_view()`` (a bounded copy for the
    plots) and ``rows_at()`` (rows read back, when the history spilled them)
    stand in for ``data``, which is None."""

    def __init__(self, columns, data, status="ok", message="", runtime_s=0.0, iterations=0,
                 max_iterations=0, plates=(None, None), info=None, history=None):
        self.columns = list(columns)
        self.data = data
        self.status = status
        self.message = message
        self.runtime_s = runtime_s
        self.iterations = iterations
        self.max_iterations = max_iterations
        self.plates = plates
        self.info = info or {}
        self.history = history
        self._stats = None

    @property
    def streamed(self) -> bool:
        return self.data is None and self.history is not None

    def __getitem__(self, name) -> np.ndarray:
        if self.streamed:
            raise KeyError(f"{name}: this run's history was streamed to {self.history.csv_path}, not kept "
                           "in memory (read that file, or run simulate() without a stream history)")
        return self.data[:, self.columns.index(name)]

    def __contains__(self, name) -> bool:
        return name in self.columns

    @property
    def n_rows(self) -> int:
        return self.history.rows if self.streamed else self.data.shape[0]

    step_extremes = None      # a StepTracker when the history kept fewer rows than steps

    @property
    def stats(self):
        """Max, min, first and last row per column (recording.Stats): of every
        step, whatever rows the history kept (the step extremes merged in)."""
        if self.streamed:
            st = self.history.stats
        else:
            if self._stats is None:
                from .recording import Stats
                self._stats = Stats(self.columns)
                self._stats.add(self.data)
            st = self._stats
        tr = self.step_extremes
        if tr is not None and not getattr(st, "_steps_merged", False):
            st.merge_steps(tr.names, tr.SX, tr.SN, tr.SL[0], tr.SL[1])
            st._steps_merged = True
        return st

    def plot_view(self) -> "Result":
        """What the plots draw: this result, or the streamed history's bounded copy."""
        if not self.streamed:
            return self
        return Result(self.columns, self.history.plot_data(), self.status, self.message, self.runtime_s)

    def rows_at(self, index) -> np.ndarray:
        """Whole rows (canonical order) at these row indices."""
        return self.history.rows_at(index) if self.streamed else self.data[np.asarray(index)]


class _Progress:
    def __init__(self, total_steps: int, dt: float, enabled: bool):
        self.total, self.dt, self.enabled = total_steps, dt, enabled
        self.t0 = self.last = time.perf_counter()

    def update(self, n: int):
        now = time.perf_counter()
        if not self.enabled or now - self.last < 0.25:
            return
        self.last = now
        frac = n / self.total
        eta = (now - self.t0) * (1 - frac) / max(frac, 1e-9)
        bar = "#" * int(30 * frac)
        sys.stderr.write(f"\r[{bar:<30}] {100 * frac:5.1f}%  t = {n * self.dt:.3f} s  eta {eta:.0f} s ")
        sys.stderr.flush()

    def close(self):
        if self.enabled:
            sys.stderr.write("\r" + " " * 70 + "\r")
            sys.stderr.flush()


def _columns(sim: Simulation):
    """(loop columns, canonical order) of this simulation's rows."""
    n = len(sim.plates)
    heat = any(p is not None for p in sim.plates)
    if sim.mechanics:
        cols = loop_columns(sim)
    else:                                   # a thermal-only scene
        cols = ["t_s"] + ([f"T{i + 1}_C" for i in range(n)] + ["E_stored_J", "E_air_J"] if heat else [])
    order = [c for c in CANONICAL if c in cols] + [c for c in cols if c not in CANONICAL]
    return cols, order


LEDGER = ("E_input_J", "E_kin_J", "E_pot_J", "W1_J", "W2_J", "W3_J", "W4_J", "E_reseat_J", "E_rim_J",
          "E_land_J")


class StepTracker:
    """Every step's extremes of the loop's row (the stepper's values, mu_i,
    T_i) and the energy ledger's worst residual and input, when the history
    keeps fewer rows than steps (output.csv_every > 1): the summary's peaks
    and ledger then read every step, as with every row kept. The arrays are
    the compiled engine's too (engine_kernel.track_row, the same arithmetic)."""

    def __init__(self, cols: list, n: int):
        self.names = cols[:n]
        self.SX, self.SN = np.full(n, -np.inf), np.full(n, np.inf)
        self.SL = np.zeros(2)
        li = [cols.index(c) for c in LEDGER if c in cols[:n]]
        base = all(c in cols[:n] for c in LEDGER[:5])
        self.LI = np.array(li if base else [], dtype=np.int64)

    @property
    def arrays(self):
        return self.SX, self.SN, self.LI, self.SL

    def add(self, row) -> None:
        SX, SN = self.SX, self.SN
        for j in range(len(SX)):
            x = row[j]
            if x > SX[j]:
                SX[j] = x
            if x < SN[j]:
                SN[j] = x
        LI = self.LI
        if len(LI):
            s = 0.0
            for k in LI[1:]:
                s += row[k]
            r = abs(row[LI[0]] - s)
            if r > self.SL[0]:
                self.SL[0] = r
            e = abs(row[LI[0]])
            if e > self.SL[1]:
                self.SL[1] = e


def _poisoned(snap):
    """A snapshot with every float NaN (tests of the failure path)."""
    if isinstance(snap, float):
        return float("nan")
    if isinstance(snap, np.ndarray):
        return np.full_like(snap, np.nan) if snap.dtype.kind == "f" else snap
    if isinstance(snap, tuple):
        return tuple(_poisoned(x) for x in snap)
    return snap


def simulate(sim: Simulation, progress: bool = False, every: int = 1, inject_failure_at: int | None = None,
             on_frame=None, frame_every: int = 0, hottest=None, history=None, on_loop_end=None) -> Result:
    """Run the scene's loop, for any device (N interfaces); never raises for
    numerical failure or Ctrl-C: the Result carries ``status`` and the history
    computed so far.

    ``history``: where the rows go (coupling/recording.py): by default all
    kept in memory; a ``StreamHistory`` (outputs/history.py) writes them to
    disk block by block. ``on_frame(n, sim)`` every ``frame_every`` steps,
    after the row, with ``sim.frame_values`` the row as a dict (the VTK
    series); ``hottest``: offered the plates every look_every(N) steps.
    ``on_loop_end()`` is called when the stepping is over, before the last
    block is handed to the history (the command line starts holding Ctrl-C
    there, so the last block of the CSV is always written)."""
    mech = sim.mechanics
    plates, laws = list(sim.plates), [getattr(law, "evaluate", law) for law in sim.laws]
    ni = len(plates)
    dt, N = sim.dt, sim.n_steps
    sub = sim.substeps
    cpl = sim.scene["coupling"]
    iterated = cpl["scheme"] == "iterated"
    tol, max_iter = cpl["tol_K"], cpl["max_iter"]
    eta = [pp.heat_share for pp in sim.plate_params]
    areas = sim.areas
    cols, order = _columns(sim)
    n_rows = N // every + 1 + (1 if N % every else 0)
    # rows are recorded into buf (loop column order) and handed to the history
    # whenever it is full (flush): memory O(buffer), not O(steps), when streamed
    hist = history if history is not None else MemoryHistory()
    cap = hist.start(cols, order, n_rows)
    buf = np.full((cap, len(cols)), np.nan)
    store_s = 0.0
    heat = any(p is not None for p in plates)
    live = [(i, p) for i, p in enumerate(plates) if p is not None]
    T = [p.surface_temperature() if p is not None else pp.T0_C for p, pp in zip(plates, sim.plate_params)]
    mu = [0.0] * ni
    values = mech.values if mech else None
    # Archard wear (friction_kernel.wear_step): the state the compiled loop shares
    wear = wear_state(sim) if mech else None
    if wear is not None:
        WL, PW = wear
        PW[:] = 0.0

    def row(n):
        r = values() + tuple(mu) if mech else (n * dt,)
        if heat:
            r += tuple(T) + (sum(p.stored_heat() for _, p in live), sum(p.heat_lost() for _, p in live))
        if wear is not None:
            r += tuple(PW.tolist())
        return r

    if mech:
        Nn = mech.N
        mu = [law(T[i], Nn[i] / areas[i], 0.0) for i, law in enumerate(laws)]

    def flush():
        """Hand buf[:k] to the history; the slow part (formatting) may be
        interrupted and is then redone, the commit and emptying are atomic."""
        nonlocal k, store_s
        t0 = time.perf_counter()
        ready = hist.prepare(buf[:k])
        with signals_held():
            hist.commit(ready)
            k = 0
        store_s += time.perf_counter() - t0

    buf[0] = row(0)
    k = 1
    if k == cap:
        flush()
    status, message = "ok", ""
    total_iter, worst_iter = 0, 0
    hot_every = look_every(N)              # the plates' fields, ~2000 times a run
    # ... when a face is hotter than at the earlier looks, with lumped and fe1d plates
    # (engine_kernel.hotter: no hotter field otherwise); every time with the others
    hot = [-math.inf] * ni if all(_plate_kind(p) in ("none", "lumped", "fe1d") for p in plates) else None
    old = mech.footprints() if mech else None
    # every step's extremes and ledger when not every step's row is kept
    tracker = StepTracker(cols, len(mech.columns) + ni * (2 if heat else 1)) if (mech and every > 1) else None
    # the compiled engine (coupling/fast_loop.py); the loop below takes over where it stops
    fast = mech is not None and not iterated and sub == 1
    jit = (compiled_loop(sim, every, n_rows, cols, inject_failure_at, tracker.arrays if tracker else None)
           if fast else None)
    # the bar's clock starts after the kernels are loaded (or compiled): its ETA is the stepping's
    bar = _Progress(N, dt, progress)
    t_start = time.perf_counter()
    n = last_row = n0 = 0
    try:
        full = False
        while jit is not None:
            out = jit.run(buf, k, last_row, T, mu, bar, hottest, hot_every, on_frame, frame_every,
                          start=n0, pending=full)
            n, k, last_row = out.n, out.k, out.last_row
            T, mu = out.T, out.mu
            total_iter, worst_iter = out.steps, (1 if out.steps else 0)
            if out.interrupted:
                raise KeyboardInterrupt
            if out.failure:
                raise NumericalFailure(out.failure[0], out.failure[0] * dt, out.failure[1])
            n0, full = out.steps, out.full
            if not full:
                break
            flush()                     # the buffer is full: as the loop below does
        if jit is not None and mech is not None:
            old = mech.footprints()
        if jit is not None and hot is not None:
            hot = jit.hot.tolist()      # the faces' highest temperatures at the engine's looks
        for n in range(n0 + 1, N + 1):
            if mech is None:                                    # thermal-only scene
                for _ in range(sub):
                    for i, p in live:
                        T[i] = p.step(sim.heat_power[i], 0.0)
            else:
                snaps = (mech.save(), [p.save() if p is not None else None for p in plates]) if iterated else None
                Tg = T
                it = 0
                while True:
                    it += 1
                    Nn, vn = mech.N, mech.slip_v
                    mu = [law(Tg[i], Nn[i] / areas[i], vn[i]) for i, law in enumerate(laws)]
                    dW = mech.step(*mu)
                    Tn = list(T)
                    if heat:
                        new = mech.footprints()
                        for i, p in live:
                            P = eta[i] * dW[i] / dt
                            if sub == 1:
                                Tn[i] = p.step(P, new[i])
                            else:
                                c0, c1 = old[i], new[i]
                                for j in range(1, sub + 1):
                                    w = j / sub
                                    Tn[i] = p.step(P, c0 + w * (c1 - c0))
                    if not iterated or all(abs(a - b) <= tol for a, b in zip(Tn, Tg)):
                        break
                    if it >= max_iter:
                        raise NumericalFailure(n, n * dt, f"iterated coupling did not converge in {max_iter} "
                                               f"iterations (|dT| = {max(abs(a - b) for a, b in zip(Tn, Tg)):.3g} K "
                                               f"> tol_K = {tol:g})")
                    mech.restore(snaps[0])
                    for p, s in zip(plates, snaps[1]):
                        if p is not None:
                            p.restore(s)
                    Tg = Tn
                total_iter += it
                worst_iter = max(worst_iter, it)
                if wear is not None:
                    Nw = mech.N
                    for i in range(ni):
                        wear_step(WL[i], Tg[i], dW[i], mu[i], Nw[i], areas[i], PW, i, ni)
                T = Tn
                if heat and sub > 1:
                    old = new
                if inject_failure_at is not None and n == inject_failure_at:
                    # poison the state (tests of the failure path): every float of the snapshot
                    mech.restore(_poisoned(mech.save()))
                if tracker is not None:
                    tracker.add(values() + tuple(mu) + (tuple(T) if heat else ()))
            if n % every == 0 or n == N or n == inject_failure_at:
                r = row(n)
                check_row(r, cols, n, dt)
                buf[k] = r
                k += 1
                last_row = n
                if k == cap:
                    flush()
                if on_frame is not None and frame_every and n % frame_every == 0:
                    sim.frame_values = dict(zip(cols, r))   # the CSV row, for the VTK frame
                    on_frame(n, sim)
            if hottest is not None and n % hot_every == 0 and (hot is None or hotter(T, hot)):
                hottest.update(plates, n * dt)
            if n % 2048 == 0:
                bar.update(n)
    except LOOP_STOPS as exc:
        status, message = stop_status(exc, n, dt)
    runtime = time.perf_counter() - t_start - store_s      # stepping only, not storing
    if on_loop_end is not None:
        on_loop_end()
    bar.close()
    flush()
    with signals_held():
        hist.finish()
    res = Result(order, None if hist.streamed else hist.data, status, message, runtime, total_iter, worst_iter,
                 tuple(plates), dict(sim.info), history=hist)
    # a failed or interrupted step n is not counted, unless its row was already kept
    res.steps = n if status == "ok" or last_row == n else n - 1
    res.step_extremes = tracker
    return res


def phase_names(codes: np.ndarray) -> list[str]:
    return [PHASES[int(c)] for c in codes]
