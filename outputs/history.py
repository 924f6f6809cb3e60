"""Where ``simulate`` puts the history it records (memory bounded whatever the length of the run).

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
import errno
import os
from pathlib import Path

import numpy as np

from fpd.coupling.recording import CHUNK_ROWS, Stats
from fpd.mechanics.phases import TFP_PHASES

PLOT_FULL_ROWS = 50_000     # up to this many rows the plots get every row
PLOT_BINS = 2000            # beyond: this many bins (a few per pixel of a 770-px plot)
PLOT_COLUMNS = ("u_m", "F_N", "xg_m", "W1_J", "W2_J", "E_input_J", "E_reseat_J", "T1_C", "T2_C",
                "mu1", "mu2", "ux_m", "uy_m", "Fx_N", "Fy_N")


class WriteError(OSError):
    """Writing the results failed (disk full, quota, permission, the folder
    removed underneath): the system's error, its file, and the time of the
    last step computed when it happened (``t_s``, None if unknown)."""

    def __init__(self, cause: OSError, path=None, t_s=None):
        super().__init__(cause.errno, cause.strerror or str(cause), path or cause.filename)
        self.t_s = t_s


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
        self.names = np.array(TFP_PHASES, dtype=object)     # the planar phases, then the TFP's
        fh.write(",".join(cols) + "\n")

    def format(self, data: np.ndarray) -> list[str]:
        """The text of these rows, in pieces of SUB rows (changes nothing)."""
        parts = []
        ncol = data.shape[1] if data.ndim == 2 else 0
        for s in range(0, data.shape[0], self.SUB):
            block = data[s:s + self.SUB]
            # one flat list of the block's values (a third cheaper than a
            # generator over row lists); the phase codes replaced by their names
            flat = np.ascontiguousarray(block).ravel().tolist()
            if self.j >= 0:
                flat[self.j::ncol] = self.names[np.nan_to_num(block[:, self.j]).astype(int)].tolist()
            parts.append((self.rowfmt * len(block)) % tuple(flat))
        return parts

    def write(self, data: np.ndarray) -> None:
        for text in self.format(data):
            self.fh.write(text)


class _Sink:
    """A file written unbuffered: ``size`` is what the system has taken, so
    a failed write (disk full) leaves a known prefix that ``cut`` restores.
    Text is written as UTF-8 (the CSV is ASCII)."""

    def __init__(self, path):
        self.path = Path(path)
        try:
            self.f = open(self.path, "wb", buffering=0)
        except OSError as exc:
            raise WriteError(exc, path=exc.filename or str(self.path), t_s=0.0) from None
        self.size = 0

    def write(self, data) -> None:
        view = memoryview(data.encode() if isinstance(data, str) else data)
        while len(view):
            try:
                n = self.f.write(view)
            except OSError as exc:
                if exc.filename is None:
                    exc.filename = str(self.path)
                raise
            self.size += n
            view = view[n:]

    def alive(self) -> None:
        """The file is still in the folder (not removed underneath the run)."""
        if os.fstat(self.f.fileno()).st_nlink == 0:
            raise FileNotFoundError(errno.ENOENT, "removed while the run was writing it", str(self.path))

    def cut(self, size: int) -> None:
        with contextlib.suppress(OSError):
            os.ftruncate(self.f.fileno(), size)
            self.size = size

    def close(self) -> None:
        self.f.close()


class StreamHistory:
    """Blocks appended to ``csv_path`` as they come; summary reductions and a
    decimated plot copy kept (module docstring). ``spill_path``: also the raw
    float64 rows (canonical order), for ``rows_at()`` (closed-form samples)."""

    streamed = True

    def __init__(self, csv_path, spill_path=None, chunk_rows: int | None = None, plots: bool = True,
                 plot_full_rows: int = PLOT_FULL_ROWS, plot_bins: int = PLOT_BINS, meters=(), writer=None):
        self.csv_path = Path(csv_path)
        # writer: a class (path, columns) -> format(rows) / write / close, e.g.
        # output.ParquetWriter; None: the CSV text on an open file (CsvWriter)
        self._writer_cls = writer
        # meters: callables columns -> an object with add(rows) (or None), fed
        # every block (e.g. outputs/cycles.CycleMeter: per-cycle loop areas)
        self._meter_makers = tuple(meters)
        self.meters = []
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
        self.meters = [m for m in (make(self.columns) for make in self._meter_makers) if m is not None]
        if self._writer_cls is None:
            self._fh = _Sink(self.csv_path)
            self._csv = CsvWriter(self._fh, columns)
        else:
            try:
                self._csv = self._writer_cls(self.csv_path, columns)
            except OSError as exc:
                    raise WriteError(exc, path=exc.filename or str(self.csv_path), t_s=0.0) from None
            self._fh = None
        if self.spill_path is not None:
            self._spill = _Sink(self.spill_path)
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
        fh_good = self._fh.size if self._fh is not None else 0
        spill_good = self._spill.size if self._spill is not None else 0
        try:
            if self._fh is None:
                for table in texts:          # a binary writer (output.ParquetWriter): whole blocks
                    self._csv.w.write_table(table)
            else:
                self._fh.alive()
                for text in texts:
                    self._fh.write(text)
            if self._spill is not None:
                self._spill.write(rows.tobytes())
        except OSError as exc:
            # the CSV cut back to its last complete line (the rows of this block
            # that fit are kept and counted); the spill, read only by a complete
            # run's summary, back to the rows before the block; a binary writer
            # keeps none of the block
            m = 0
            if self._fh is not None:
                done = self._fh.size - fh_good
                data = "".join(texts).encode()[:done]
                keep = data.rfind(b"\n") + 1
                m = data.count(b"\n", 0, keep)
                self._fh.cut(fh_good + keep)
            if self._spill is not None:
                self._spill.cut(spill_good)
            if m:
                self._take(rows[:m])
            t_s = float(rows[-1, self.columns.index("t_s")]) if "t_s" in self.columns else None
            raise WriteError(exc, path=exc.filename or str(self.csv_path), t_s=t_s) from None
        self._take(rows)

    def _take(self, rows) -> None:
        """Count rows that reached the file: statistics, meters, plot copy."""
        self.stats.add(rows)
        for m in self.meters:
            m.add(rows)
        if self.keep_plot:
            self.plot.add(rows)
        self.rows += len(rows)

    def finish(self) -> None:
        if self._fh is not None:
            self._fh.alive()
        for f in (self._fh, self._spill):
            if f is not None:
                f.close()
        if self._fh is None and self._writer_cls is not None:
            self._csv.close()

    def abandon(self) -> None:
        """After a write failure: close the files, keeping what is in them."""
        for f in (self._fh, self._spill):
            if f is not None:
                with contextlib.suppress(OSError):
                    f.close()
        if self._fh is None and self._writer_cls is not None:
            with contextlib.suppress(OSError):
                self._csv.close()

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
