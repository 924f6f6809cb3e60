"""What every figure of a run is drawn with (matplotlib, imported only when a
figure is made): Agg figures without pyplot, with fixed margins in inches
(no layout pass that draws the figure twice), lines drawn through at most a
few points per pixel column (``thin``: per bin of consecutive rows the first,
last, smallest and largest value of every drawn column, so the drawn
envelope is the one of every row), one spelling of the units."""
from __future__ import annotations

DPI = 110
DEG = "\N{DEGREE SIGN}C"     # the one spelling of the unit in every figure
BINS = 1500                  # bins of rows per drawn line: ~2.5 per pixel column of a 7-inch figure
PYPLOT = False               # Result.plot(): figures made by pyplot (shown by plt.show())
LEAN = False                 # the command line's own process: import matplotlib lean (lean_import)
_imported = False


def lean_import() -> None:
    """Import matplotlib's Figure for a process that only writes figures
    (``fpd run``; set ``LEAN``), at about 0.1 s less process time, nothing
    drawn differently:

    - the garbage collector's full passes stop scanning the objects that
      exist already (``gc.freeze``: the numba and scipy modules loaded, the
      run's history, then matplotlib's modules): importing matplotlib and
      drawing create enough objects to trigger several such passes;
    - matplotlib's import writes a property table into the docstring of
      every artist class's ``set`` (``matplotlib.artist.kwdoc``), read only
      by ``help()``: the process skips writing it.

    Library use (``fpd.run``, ``Result.plot``) imports matplotlib as usual."""
    global _imported
    if _imported or not LEAN:
        return
    _imported = True
    import gc
    import sys
    if "matplotlib.figure" in sys.modules:
        return
    gc.freeze()
    import matplotlib.artist
    kwdoc = matplotlib.artist.kwdoc
    matplotlib.artist.kwdoc = lambda artist: ""
    try:
        import matplotlib.figure  # noqa: F401
        from matplotlib.backends import backend_agg  # noqa: F401
    finally:
        matplotlib.artist.kwdoc = kwdoc
    gc.freeze()                     # and matplotlib's own modules: the figures' passes skip them too


def _same(a, b, rel: float = 0.003) -> bool:
    """Would two curves hide each other (within rel of their range)?"""
    import numpy as np
    span = max(float(np.ptp(a)), float(np.ptp(b)), 1e-12 * max(1.0, float(np.max(np.abs(a)))))
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) <= rel * span


def thin(n: int, *columns, bins: int = BINS):
    """Row indices that draw ``columns`` (arrays of n rows) as every row
    would at a few points per pixel: all rows when n <= 4 bins, else per bin
    of consecutive rows its first and last row and the rows of each column's
    smallest and largest value (whole rows: an x-y pair stays paired)."""
    import numpy as np
    if n <= 4 * bins:
        return slice(None)
    b = -(-n // bins)
    nb = n // b
    whole = nb * b
    starts = np.arange(nb) * b
    keep = [starts, starts + b - 1, np.arange(whole, n)]
    for c in columns:
        v = np.asarray(c)[:whole].reshape(nb, b)
        keep += [starts + v.argmax(axis=1), starts + v.argmin(axis=1)]
    return np.unique(np.concatenate(keep))


XY_BINS = 25_000             # x-y curves (loops, orbits): a time bin must not cut a fast swing short


def thin_xy(n: int, x, y):
    """Row indices that draw the x-y curve (x, y) as every row would: per
    time bin its extremes (``thin``) with bins fine enough (XY_BINS) that a
    fast swing of the curve keeps its shape."""
    return thin(n, x, y, bins=XY_BINS)


def new_figure(nrows: int = 1, ncols: int = 1, figsize=(7.0, 3.2), left=0.8, right=0.15, bottom=0.5,
               top=0.35, hgap=0.35, wgap=0.7, sharex=False, sharey=False):
    """A Figure and its axes (a flat list) with fixed margins in inches."""
    if PYPLOT:
        import matplotlib.pyplot as plt
        fig = plt.figure(figsize=figsize)
    else:
        lean_import()
        from matplotlib.figure import Figure
        fig = Figure(figsize=figsize)
    W, H = figsize
    aw = (W - left - right - (ncols - 1) * wgap) / ncols
    ah = (H - bottom - top - (nrows - 1) * hgap) / nrows
    fig.subplots_adjust(left=left / W, right=1 - right / W, bottom=bottom / H, top=1 - top / H,
                        hspace=hgap / ah, wspace=wgap / aw)
    ax = fig.subplots(nrows, ncols, squeeze=False, sharex=sharex, sharey=sharey)
    return fig, [a for row in ax for a in row]


def save(fig, path) -> None:
    fig.savefig(path, dpi=DPI)
    if PYPLOT:
        import matplotlib.pyplot as plt
        plt.close(fig)
