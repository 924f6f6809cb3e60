"""Where the coupled loop puts the rows it records: the contract every
history sink follows (``start``, ``prepare``, ``commit``, ``finish``), the
in-memory sink (``MemoryHistory``, the default), the running reductions the
summary is made of (``Stats``) and ``signals_held`` (a block is committed with
SIGINT/SIGTERM held, so no row is lost or taken twice). The sinks that write
files (``StreamHistory``, the CSV text) are outputs/history.py's.
"""
from __future__ import annotations

import contextlib
import signal
import threading

import numpy as np

CHUNK_ROWS = 1 << 11        # rows per block handed over: the engine writes its rows into a block that
                            # stays in the L2 cache (60 columns: 1 MB; 16384 rows cost the TFP 10 % more)


@contextlib.contextmanager
def signals_held():
    """SIGINT and SIGTERM wait (pending, not lost) until the block is done.

    Their handlers are swapped for one that only notes the signal, and the
    signal is raised again once the block is done. (Blocking them with
    pthread_sigmask holds them only in this thread: a signal the system
    hands to another thread of the process, one numba, dask or a library
    started, would still interrupt the block, since Python runs its
    handlers in the main thread.)"""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending = []
    sigs = (signal.SIGINT, signal.SIGTERM)
    old = {}
    try:
        for s in sigs:
            old[s] = signal.signal(s, lambda sig, frame: pending.append(sig))
        yield
    finally:
        for s, handler in old.items():
            signal.signal(s, handler)
        for sig in dict.fromkeys(pending):
            signal.raise_signal(sig)


class Stats:
    """Running reductions over the recorded rows (canonical columns).

    max and min per column combine exactly across blocks, so the summary of
    a streamed run is the one of the same run held in memory."""

    def __init__(self, columns):
        self.columns = list(columns)
        self.rows = 0
        self.max = self.min = self.first = self.last = None
        # the energy ledger over the whole history (largest |residual|, largest |input|)
        # (input first, then every term it goes into: kinetic, potential, the friction
        # work of each interface, the re-seating and rim losses where the device has them)
        terms = ("E_input_J", "E_kin_J", "E_pot_J", "W1_J", "W2_J")
        extra = [c for c in ("W3_J", "W4_J", "E_reseat_J", "E_rim_J", "E_land_J") if c in self.columns]
        self._ledger_cols = ([self.columns.index(c) for c in (*terms, *extra)]
                             if all(c in self.columns for c in terms) else None)
        self.ledger_worst = self.input_worst = 0.0
        # when the assembly first left the bearing, and when it rose highest (a vertical record)
        self._lift = ([self.columns.index(c) for c in ("t_s", "n_lift", "lift_m")]
                      if all(c in self.columns for c in ("t_s", "n_lift", "lift_m")) else None)
        self.first_lift_t = self.peak_lift_t = None
        self._peak_lift = -np.inf

    def add(self, block: np.ndarray) -> None:
        if not len(block):
            return
        if self._lift is not None:
            jt, jn, jl = self._lift
            if self.first_lift_t is None:
                up = np.flatnonzero(block[:, jn] > 0.0)
                if up.size:
                    self.first_lift_t = float(block[up[0], jt])
            k = int(np.argmax(block[:, jl]))
            if block[k, jl] > self._peak_lift and block[k, jl] > 0.0:
                self._peak_lift = float(block[k, jl])
                self.peak_lift_t = float(block[k, jt])
        mx, mn = block.max(axis=0), block.min(axis=0)
        if self.rows == 0:
            self.max, self.min, self.first = mx, mn, block[0].copy()
        else:
            self.max, self.min = np.maximum(self.max, mx), np.minimum(self.min, mn)
        self.last = block[-1].copy()
        self.rows += len(block)
        if self._ledger_cols is not None:
            j = self._ledger_cols
            res = block[:, j[0]] - block[:, j[1:]].sum(axis=1)
            self.ledger_worst = max(self.ledger_worst, float(np.max(np.abs(res))))
            self.input_worst = max(self.input_worst, float(np.max(np.abs(block[:, j[0]]))))

    def merge_steps(self, names, mx, mn, ledger_worst: float, input_worst: float) -> None:
        """Fold in the extremes of every step (coupling/run.StepTracker), where
        the history kept fewer rows than steps."""
        if self.rows == 0:
            return
        for name, a, b in zip(names, mx, mn):
            if name in self.columns and a >= b:
                j = self.columns.index(name)
                self.max[j] = max(self.max[j], a)
                self.min[j] = min(self.min[j], b)
        self.ledger_worst = max(self.ledger_worst, float(ledger_worst))
        self.input_worst = max(self.input_worst, float(input_worst))

    def _get(self, arr, name) -> float:
        return float(arr[self.columns.index(name)])

    def peak(self, name) -> float:
        return self._get(self.max, name)

    def low(self, name) -> float:
        return self._get(self.min, name)

    def peak_abs(self, name) -> float:
        """max |x| (= max(max x, -min x), exactly)."""
        j = self.columns.index(name)
        return float(np.maximum(self.max[j], -self.min[j]))

    def final(self, name) -> float:
        return self._get(self.last, name)


class MemoryHistory:
    """Every row in memory, canonical order (the default sink)."""

    streamed = False

    def __init__(self, chunk_rows: int | None = None):
        self.chunk_rows = chunk_rows
        self.rows = 0

    def start(self, loop_columns, columns, n_rows_max: int) -> int:
        """Get ready for at most n_rows_max rows; return the buffer size (rows)."""
        self.columns = list(columns)
        self.idx = [list(loop_columns).index(c) for c in columns]
        self.data = np.empty((n_rows_max, len(columns)))    # pages touched only as rows arrive
        self.rows = 0
        return max(1, min(n_rows_max, self.chunk_rows or CHUNK_ROWS))

    def prepare(self, block: np.ndarray):
        """The slow part of taking a block, changing nothing (may be interrupted)."""
        return block

    def commit(self, block) -> None:
        """Take the prepared block (quick; called with signals held)."""
        m = min(len(block), len(self.data) - self.rows)     # never beyond the rows announced
        np.take(block[:m], self.idx, axis=1, out=self.data[self.rows:self.rows + m])
        self.rows += m

    def finish(self) -> None:
        self.data = self.data[:self.rows]
