"""Where ``simulate`` puts the history it records (issue 7, memory).

The loop fills a buffer of the rows ``start()`` asks for (in the loop's
column order) and hands it over whenever it is full and once at the end.
Two sinks:

- ``MemoryHistory`` (the default, for in-process users: studies, tests):
  every row kept in one array in the canonical column order, so
  ``Result.data`` / ``res["u_m"]`` work as they always did.
- ``StreamHistory`` (``fpd run``): each block is appended to
  ``timeseries.csv`` as it arrives (the bytes ``write_csv`` writes), and only
  what the summary and the plots need stays in memory: running reductions
  (``Stats``: max, min, first and last row; exact whatever the chunking) and
  a bounded, decimated copy for the plots (``PlotSampler``: per bin, its
  first and last rows and the rows where each plotted column peaks, so peaks
  stay visible). Thermal-only scenes with a closed-form check also spill the
  raw rows to a binary file, from which the check reads back its samples.
  Memory: O(capacity) + O(plot rows), whatever the number of steps.

Taking a block is two-phase: ``prepare(block)`` does the slow part (the
CSV text) and changes nothing, ``commit(prepared)`` appends it; ``simulate``
commits and empties its buffer with SIGINT/SIGTERM held (``signals_held``),
so a Ctrl-C never leaves half a block in the CSV nor a block taken twice.
"""
from __future__ import annotations

import contextlib
import os
import signal
import threading
from pathlib import Path

import numpy as np

from fpd.mechanics.phases import PHASES

CHUNK_ROWS = 1 << 14        # rows per block streamed (37 columns: 4.8 MB)
PLOT_FULL_ROWS = 50_000     # up to this many rows the plots get every row
PLOT_BINS = 2000            # beyond: this many bins (a few per pixel of a 770-px plot)
PLOT_COLUMNS = ("u_m", "F_N", "xg_m", "W1_J", "W2_J", "E_input_J", "E_reseat_J", "T1_C", "T2_C",
                "mu1", "mu2")


@contextlib.contextmanager
def signals_held():
    """SIGINT and SIGTERM wait (pending, not lost) until the block is done."""
    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        yield
        return
    sigs = {signal.SIGINT, signal.SIGTERM}
    old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


class Stats:
    """Running reductions over the recorded rows (canonical columns).

    max and min per column combine exactly across blocks, so the summary of
    a streamed run is the one of the same run held in memory."""

    def __init__(self, columns):
        self.columns = list(columns)
        self.rows = 0
        self.max = self.min = self.first = self.last = None

    def add(self, block: np.ndarray) -> None:
        if not len(block):
            return
        mx, mn = block.max(axis=0), block.min(axis=0)
        if self.rows == 0:
            self.max, self.min, self.first = mx, mn, block[0].copy()
        else:
            self.max, self.min = np.maximum(self.max, mx), np.minimum(self.min, mn)
        self.last = block[-1].copy()
        self.rows += len(block)

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


class PlotSampler:
    """A bounded copy of the history for the plots.

    Up to ``full_rows`` rows: every row (the plots are the ones of the full
    history). Beyond: the rows fall into ``bins`` bins of ``b`` consecutive
    rows; per bin the first and last rows and, for each plotted column, the
    rows of its maximum and minimum are kept (whole rows, so u and F stay
    paired in the hysteresis loop). At most (2 + 2 x plotted columns) x bins
    rows, whatever the length of the run. Blocks must hold whole bins (their
    length a multiple of ``bin_rows``), but for the last one."""

    def __init__(self, columns, n_rows_max: int, full_rows: int = PLOT_FULL_ROWS, bins: int = PLOT_BINS):
        self.columns = list(columns)
        self.bin_rows = 1 if n_rows_max <= full_rows else -(-n_rows_max // bins)
        self.cols = [self.columns.index(c) for c in PLOT_COLUMNS if c in self.columns]
        self.parts = []

    def add(self, block: np.ndarray) -> None:
        b, m = self.bin_rows, len(block)
        if b == 1 or m == 0:
            self.parts.append(block.copy())
            return
        nb = -(-m // b)
        starts = np.arange(nb) * b
        keep = [starts, np.minimum(starts + b - 1, m - 1)]
        whole = (m // b) * b
        if self.cols and whole:
            v = block[:whole, self.cols].reshape(m // b, b, len(self.cols))
            base = starts[:m // b, None]
            keep += [(base + v.argmax(axis=1)).ravel(), (base + v.argmin(axis=1)).ravel()]
        if self.cols and whole < m:
            v = block[whole:, self.cols]
            keep += [whole + v.argmax(axis=0), whole + v.argmin(axis=0)]
        self.parts.append(block[np.unique(np.concatenate(keep))])

    def data(self) -> np.ndarray:
        if not self.parts:
            return np.empty((0, len(self.columns)))
        if len(self.parts) > 1:
            self.parts = [np.concatenate(self.parts)]
        return self.parts[0]


class CsvWriter:
    """timeseries.csv on an open text file: the header at once, then blocks
    of rows (canonical columns, ``phase`` as its code) as they come.

    Each ``SUB`` rows are formatted by one %-operation (the bytes np.savetxt
    wrote, ~10% faster, and without an object copy of the whole history)."""

    SUB = 4096

    def __init__(self, fh, columns):
        self.fh = fh
        cols = list(columns)
        self.j = cols.index("phase") if "phase" in cols else -1
        self.rowfmt = ",".join("%s" if c == "phase" else "%.10g" for c in cols) + "\n"
        self.names = np.array(PHASES, dtype=object)
        fh.write(",".join(cols) + "\n")

    def format(self, data: np.ndarray) -> list[str]:
        """The text of these rows, in pieces of SUB rows (changes nothing)."""
        parts = []
        for s in range(0, data.shape[0], self.SUB):
            block = data[s:s + self.SUB]
            rows = block.tolist()
            if self.j >= 0:
                for row, name in zip(rows, self.names[np.nan_to_num(block[:, self.j]).astype(int)].tolist()):
                    row[self.j] = name
            parts.append((self.rowfmt * len(rows)) % tuple(x for row in rows for x in row))
        return parts

    def write(self, data: np.ndarray) -> None:
        for text in self.format(data):
            self.fh.write(text)


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


class StreamHistory:
    """Blocks appended to ``csv_path`` as they come; summary reductions and a
    decimated plot copy kept (module docstring). ``spill_path``: also the raw
    float64 rows (canonical order), for ``rows_at()`` (closed-form samples)."""

    streamed = True

    def __init__(self, csv_path, spill_path=None, chunk_rows: int | None = None, plots: bool = True,
                 plot_full_rows: int = PLOT_FULL_ROWS, plot_bins: int = PLOT_BINS):
        self.csv_path = Path(csv_path)
        self.spill_path = Path(spill_path) if spill_path is not None else None
        self.chunk_rows = chunk_rows
        self.keep_plot = plots
        self._plot_args = (plot_full_rows, plot_bins)
        self.rows = 0
        self._fh = self._spill = None

    def start(self, loop_columns, columns, n_rows_max: int) -> int:
        self.columns = list(columns)
        self.idx = [list(loop_columns).index(c) for c in columns]
        self.stats = Stats(columns)
        self.plot = PlotSampler(columns, n_rows_max, *self._plot_args)
        self._fh = open(self.csv_path, "w", newline="")
        self._csv = CsvWriter(self._fh, columns)
        if self.spill_path is not None:
            self._spill = open(self.spill_path, "wb")
        self.rows = 0
        b = self.plot.bin_rows            # blocks before the last hold whole plot bins
        return max(1, min(n_rows_max, max(b, (self.chunk_rows or CHUNK_ROWS) // b * b)))

    def prepare(self, block: np.ndarray):
        rows = block[:, self.idx]
        return rows, self._csv.format(rows)

    def commit(self, prepared) -> None:
        rows, texts = prepared
        if not len(rows):
            return
        for text in texts:
            self._fh.write(text)
        if self._spill is not None:
            self._spill.write(rows.tobytes())
        self.stats.add(rows)
        if self.keep_plot:
            self.plot.add(rows)
        self.rows += len(rows)

    def finish(self) -> None:
        for f in (self._fh, self._spill):
            if f is not None:
                f.close()

    def plot_data(self) -> np.ndarray:
        """The bounded copy of the rows for the plots (PlotSampler)."""
        if not self.keep_plot:
            raise RuntimeError("this history kept no rows for plots (StreamHistory(plots=False))")
        return self.plot.data()

    def rows_at(self, index) -> np.ndarray:
        """Rows (canonical order) at these indices, read back from the spill."""
        if self.spill_path is None:
            raise RuntimeError("this history kept no raw rows (StreamHistory(spill_path=...))")
        mm = np.memmap(self.spill_path, dtype=np.float64, mode="r", shape=(self.rows, len(self.columns)))
        try:
            return np.array(mm[np.asarray(index)])
        finally:
            del mm

    def discard_spill(self) -> None:
        if self.spill_path is not None:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(self.spill_path)
