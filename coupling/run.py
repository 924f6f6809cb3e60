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

from fpd.mechanics.phases import PHASES, MechanicsFailure

from .build import Simulation
from .fast_loop import compiled_loop
from .history import MemoryHistory, signals_held

# canonical column order (docs/reference.md); extra diagnostic columns follow
CANONICAL = ("t_s", "xg_m", "u_m", "v_mps", "F_N", "z_m", "theta_rad", "beta_rad", "s1_m", "s2_m",
             "N1_N", "N2_N", "mu1", "mu2", "T1_C", "T2_C", "W1_J", "W2_J", "phase", "E_input_J",
             "E_kin_J", "E_pot_J", "E_reseat_J", "E_stored_J", "E_air_J")


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

    @property
    def stats(self):
        """Max, min, first and last row per column (history.Stats)."""
        if self.streamed:
            return self.history.stats
        if self._stats is None:
            from .history import Stats
            self._stats = Stats(self.columns)
            self._stats.add(self.data)
        return self._stats

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
    mech_cols = list(sim.mechanics.columns) if sim.mechanics else ["t_s"]
    heat = any(p is not None for p in sim.plates)
    cols = list(mech_cols)
    if sim.mechanics:
        cols += ["mu1", "mu2"]
    if heat:
        cols += ["T1_C", "T2_C", "E_stored_J", "E_air_J"]
    order = [c for c in CANONICAL if c in cols] + [c for c in cols if c not in CANONICAL]
    return cols, order


def simulate(sim: Simulation, progress: bool = False, every: int = 1, inject_failure_at: int | None = None,
             on_frame=None, frame_every: int = 0, hottest=None, history=None, on_loop_end=None) -> Result:
    """Run the scene's loop; never raises for numerical failure or Ctrl-C:
    the Result carries ``status`` and the history computed so far.

    ``history``: where the rows go (coupling/history.py): by default all kept
    in memory; a ``StreamHistory`` writes them to disk block by block.
    ``on_loop_end()`` is called when the stepping is over, before the last
    block is handed to the history (the command line starts holding Ctrl-C
    there, so the last block of the CSV is always written)."""
    if getattr(sim.mechanics, "n_interfaces", 2) == 4:     # the TFP: its own staggered loop
        from .tfp_loop import simulate_tfp
        return simulate_tfp(sim, progress=progress, every=every, inject_failure_at=inject_failure_at,
                            history=history, on_loop_end=on_loop_end, on_frame=on_frame, frame_every=frame_every,
                            hottest=hottest)
    mech = sim.mechanics
    p1, p2 = sim.plates
    law1, law2 = (getattr(law, "evaluate", law) for law in sim.laws)   # mechanics.friction: the bound kernel
    dt, N = sim.dt, sim.n_steps
    sub = sim.substeps
    cpl = sim.scene["coupling"]
    iterated = cpl["scheme"] == "iterated"
    tol, max_iter = cpl["tol_K"], cpl["max_iter"]
    eta1, eta2 = sim.plate_params[0].heat_share, sim.plate_params[1].heat_share
    Tair1, Tair2 = sim.plate_params[0].T0_C, sim.plate_params[1].T0_C
    area = sim.geometry.contact_area
    cols, order = _columns(sim)
    n_rows = N // every + 1 + (1 if N % every else 0)
    # rows are recorded into buf (loop column order) and handed to the history
    # whenever it is full (flush): memory O(buffer), not O(steps), when streamed
    hist = history if history is not None else MemoryHistory()
    cap = hist.start(cols, order, n_rows)
    buf = np.full((cap, len(cols)), np.nan)
    store_s = 0.0
    heat = p1 is not None or p2 is not None
    T1 = p1.surface_temperature() if p1 else Tair1
    T2 = p2.surface_temperature() if p2 else Tair2
    mu1 = mu2 = 0.0

    # bound methods (the loop runs 10^4..10^6 times; issue 7)
    zero = (lambda: 0.0)
    stored1, stored2 = (p1.stored_heat if p1 else zero), (p2.stored_heat if p2 else zero)
    lost1, lost2 = (p1.heat_lost if p1 else zero), (p2.heat_lost if p2 else zero)
    values = mech.values if mech else None

    def row(n):
        if not mech:
            r = (n * dt,)
            return r + (T1, T2, stored1() + stored2(), lost1() + lost2()) if heat else r
        if heat:
            return values() + (mu1, mu2, T1, T2, stored1() + stored2(), lost1() + lost2())
        return values() + (mu1, mu2)

    if mech:
        mu1 = law1(T1, mech.N1 / area, 0.0)
        mu2 = law2(T2, mech.N2 / area, 0.0)

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
    from .hottest import look_every
    hot_every = look_every(N)              # the plates' fields, ~2000 times a run
    c1_old = c2_old = 0.0
    fast = mech is not None and not iterated and sub == 1
    # bidirectional steppers (model.md 8): the plates get the 2D footprint centres
    two_d = mech is not None and hasattr(mech, "centre1")
    mech_step = mech.step if mech else None
    p1_step, p2_step = (p1.step if p1 else None), (p2.step if p2 else None)
    # the common case compiled (coupling/fast_loop.py); the loop below takes over where it stops
    jit = compiled_loop(sim, every, n_rows, cols, inject_failure_at) if fast else None
    if fast and jit is None and two_d:      # the bidirectional stepper's own compiled loop
        from .bidirectional_loop import compiled_loop_2d
        jit = compiled_loop_2d(sim, every, n_rows, cols, inject_failure_at)
    # the bar's clock starts after the kernels are loaded (or compiled): its ETA is the stepping's
    bar = _Progress(N, dt, progress)
    t_start = time.perf_counter()
    n = last_row = n0 = 0
    try:
        full = False
        while jit is not None:
            out = jit.run(buf, k, last_row, T1, T2, mu1, mu2, bar, hottest, hot_every, on_frame, frame_every,
                          start=n0, pending=full)
            n, k, last_row = out.n, out.k, out.last_row
            T1, T2, mu1, mu2 = out.T1, out.T2, out.mu1, out.mu2
            total_iter, worst_iter = out.steps, (1 if out.steps else 0)
            if out.interrupted:
                raise KeyboardInterrupt
            if out.failure:
                raise NumericalFailure(out.failure[0], out.failure[0] * dt, out.failure[1])
            n0, full = out.steps, out.full
            if not full:
                break
            flush()                     # the buffer is full: as the loop below does
        for n in range(n0 + 1, N + 1):
            if fast:                    # staggered, one thermal step per step: the loop below, unrolled
                mu1 = law1(T1, mech.N1 / area, mech.slip_v1)
                mu2 = law2(T2, mech.N2 / area, mech.slip_v2)
                dW1, dW2 = mech_step(mu1, mu2)
                if heat:
                    c1, c2 = (mech.centre1, mech.centre2) if two_d else (mech.s1, -mech.s2)
                    P1, P2 = eta1 * dW1 / dt, eta2 * dW2 / dt
                    if p1:
                        T1 = p1_step(P1, c1)
                    if p2:
                        T2 = p2_step(P2, c2)
                total_iter += 1
                worst_iter = 1
                if inject_failure_at is not None and n == inject_failure_at:
                    mech.restore(tuple(float("nan") if isinstance(x, float) else x for x in mech.save()))
            elif mech is None:                                   # thermal-only scene
                P1, P2 = sim.heat_power
                for _ in range(sub):
                    if p1:
                        T1 = p1.step(P1, 0.0)
                    if p2:
                        T2 = p2.step(P2, 0.0)
            else:
                snaps = (mech.save(), p1.save() if p1 else None, p2.save() if p2 else None) if iterated else None
                Tg1, Tg2 = T1, T2
                it = 0
                while True:
                    it += 1
                    mu1 = law1(Tg1, mech.N1 / area, mech.slip_v1)
                    mu2 = law2(Tg2, mech.N2 / area, mech.slip_v2)
                    dW1, dW2 = mech.step(mu1, mu2)
                    if heat:
                        c1, c2 = (mech.centre1, mech.centre2) if two_d else (mech.s1, -mech.s2)
                        P1, P2 = eta1 * dW1 / dt, eta2 * dW2 / dt
                        if sub == 1:
                            T1n = p1.step(P1, c1) if p1 else T1
                            T2n = p2.step(P2, c2) if p2 else T2
                        else:
                            for j in range(1, sub + 1):
                                w = j / sub
                                T1n = p1.step(P1, c1_old + w * (c1 - c1_old)) if p1 else T1
                                T2n = p2.step(P2, c2_old + w * (c2 - c2_old)) if p2 else T2
                    else:
                        T1n, T2n = T1, T2
                    if not iterated or (abs(T1n - Tg1) <= tol and abs(T2n - Tg2) <= tol):
                        break
                    if it >= max_iter:
                        raise NumericalFailure(n, n * dt, f"iterated coupling did not converge in {max_iter} "
                                                          f"iterations (|dT| = {max(abs(T1n - Tg1), abs(T2n - Tg2)):.3g} K > tol_K = {tol:g})")
                    mech.restore(snaps[0])
                    if p1:
                        p1.restore(snaps[1])
                    if p2:
                        p2.restore(snaps[2])
                    Tg1, Tg2 = T1n, T2n
                total_iter += it
                worst_iter = max(worst_iter, it)
                T1, T2 = T1n, T2n
                if heat:
                    c1_old, c2_old = mech.s1, -mech.s2
                if inject_failure_at is not None and n == inject_failure_at:
                    # poison the state (tests of the failure path): every float of the snapshot
                    mech.restore(tuple(float("nan") if isinstance(x, float) else x for x in mech.save()))
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
            if hottest is not None and n % hot_every == 0:
                hottest.update(sim.plates, n * dt)
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
                 (p1, p2), dict(sim.info), history=hist)
    # a failed or interrupted step n is not counted, unless its row was already kept
    res.steps = n if status == "ok" or last_row == n else n - 1
    return res


def phase_names(codes: np.ndarray) -> list[str]:
    return [PHASES[int(c)] for c in codes]
