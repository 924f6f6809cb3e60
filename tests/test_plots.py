"""The plots a run writes: summary.json names every PNG in plots/, cycles.csv's
per-cycle temperatures against the run's own timeseries, the drawn lines'
envelope is every row's, curves that coincide say so, and no label is cut off
at the figure's edge."""
from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

import fpd
from fpd.outputs import plots

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    import matplotlib.pyplot as plt
    plt.close("all")


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    out = tmp_path_factory.mktemp("plots") / "lab"
    fpd.run("lab-sine", out=out, solver={"duration": 5.0})
    return out


def _csv(path):
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return {h: np.array([float(r[j]) for r in rows[1:]]) for j, h in enumerate(rows[0]) if h != "phase"}


def test_summary_lists_every_png(lab, tmp_path):
    for folder in (lab, ):
        s = json.loads((folder / "summary.json").read_text())
        written = sorted(p.name for p in (folder / "plots").glob("*.png"))
        assert sorted(s["plots"]) == written
        assert "lower_plate_hottest.png" in written and "cycles.png" in written
    # fpd run (the command) too, on a TFP (four hottest-field pictures)
    from fpd.frontends import cli
    out = tmp_path / "tfp"
    assert cli.main(["run", "tfp-lab", "--out", str(out), "--quiet", "--set", "solver.duration=1.0"]) == 0
    s = json.loads((out / "summary.json").read_text())
    written = sorted(p.name for p in (out / "plots").glob("*.png"))
    assert sorted(s["plots"]) == written
    assert sum(n.endswith("_hottest.png") for n in written) == 4


def test_cycles_csv_temperature_per_cycle(lab):
    """T<i>_peak_C / T<i>_mean_C of each cycle: the max and the mean of that
    column over the cycle's rows of timeseries.csv (computed here); the
    surfaces heat from one cycle to the next (the programme's steady sliding)."""
    ts = _csv(lab / "timeseries.csv")
    cyc = _csv(lab / "cycles.csv")
    assert len(cyc["cycle"]) == 2
    T = 1.0 / 0.4
    t = ts["t_s"]
    for k in range(2):
        k_of_row = np.floor(t / T * (1 + 1e-12)).astype(int)
        sel = k_of_row == k
        for i in (1, 2):
            col = ts[f"T{i}_C"][sel]
            assert cyc[f"T{i}_peak_C"][k] == pytest.approx(col.max(), rel=1e-9)
            assert cyc[f"T{i}_mean_C"][k] == pytest.approx(col.mean(), rel=1e-9)
    assert cyc["T1_peak_C"][1] > cyc["T1_peak_C"][0] + 5.0
    assert cyc["T1_mean_C"][0] < cyc["T1_peak_C"][0]
    s = json.loads((lab / "summary.json").read_text())
    assert s["test_machine"]["cycles"][1]["T2_peak_C"] == pytest.approx(cyc["T2_peak_C"][1], rel=1e-12)


def test_thin_keeps_every_rows_envelope():
    """thin(): per bin the extremes of each column, so a line drawn through
    the kept rows has the same min and max per bin (hence per pixel column)."""
    rng = np.random.default_rng(3)
    n = 100_003
    y = np.cumsum(rng.normal(size=n))
    z = np.sin(np.arange(n) / 50.0) + 0.1 * rng.normal(size=n)
    keep = plots.thin(n, y, z, bins=1000)
    assert len(keep) < n / 10
    assert keep[0] == 0 and keep[-1] == n - 1
    b = -(-n // 1000)
    for col in (y, z):
        for lo in range(0, n - b, b):
            inside = keep[(keep >= lo) & (keep < lo + b)]
            assert col[inside].max() == col[lo:lo + b].max() and col[inside].min() == col[lo:lo + b].min()
    assert plots.thin(1000, y[:1000]) == slice(None)


def test_tfp_coinciding_curves_are_named():
    """A symmetric TFP: S1 equals S4 and S2 equals S3 within 1 % of their range; the
    temperature and friction legends say so (the dashed curve over the solid)."""
    r = fpd.run("tfp-elcentro", solver={"duration": 8.0})
    h = r.history
    for a, b in ((1, 4), (2, 3)):
        x, y = h[f"T{a}_C"], h[f"T{b}_C"]
        assert np.max(np.abs(x - y)) <= 0.01 * np.ptp(x)
    for name in ("temperature", "friction"):
        texts = [t.get_text() for t in r.plot(name).axes[0].get_legend().get_texts()]
        assert any("S4" in t and "= S1" in t for t in texts), texts
        assert any("S3" in t and "= S2" in t for t in texts), texts
        assert not any("S1" in t.split()[0] and "=" in t for t in texts)


def _drawn_ticklabels(ax):
    """The tick labels drawn (ticks inside the view limits)."""
    out = []
    for axis in (ax.xaxis, ax.yaxis):
        lo, hi = sorted(axis.get_view_interval())
        span = hi - lo
        for tick in axis.get_major_ticks():
            if lo - 1e-9 * span <= tick.get_loc() <= hi + 1e-9 * span:
                out += [lab for lab in (tick.label1, tick.label2) if lab.get_visible()]
    return out


@pytest.mark.parametrize("scene,over", [
    ("default", {"solver": {"duration": 4.0}}),
    ("impvall-bidirectional", {"solver": {"duration": 4.0}}),
    ("lab-sine", {"solver": {"duration": 5.0}}),
    ("tfp-elcentro", {"solver": {"duration": 4.0}}),
])
def test_no_text_cut_at_the_figure_edge(scene, over):
    """Every title, label, tick label and legend of every figure lies inside
    its figure (fixed margins: nothing is clipped)."""
    r = fpd.run(scene, **over)
    for name, fig in r.plot().items():
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        W, H = fig.bbox.width, fig.bbox.height
        texts = list(fig.texts)
        for ax in fig.axes:
            texts += [ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label]
            texts += _drawn_ticklabels(ax)
            if ax.get_legend():
                texts.append(ax.get_legend())
            for child in ax.get_children():      # secondary axes (cycles' Q_d)
                if hasattr(child, "yaxis") and child is not ax:
                    texts += [child.yaxis.label] + _drawn_ticklabels(child)
        for t in texts:
            if not t.get_visible() or (hasattr(t, "get_text") and not t.get_text()):
                continue
            bb = t.get_window_extent(renderer)
            assert bb.x0 >= -1 and bb.y0 >= -1 and bb.x1 <= W + 1 and bb.y1 <= H + 1, \
                (scene, name, getattr(t, "get_text", lambda: "legend")(), bb, (W, H))


def test_compare_loops_are_small_multiples(tmp_path):
    """fpd compare's hysteresis.png: one panel per thermal model on shared axes
    (five loops on one axes hid each other), the first model faint behind the others."""
    from types import SimpleNamespace

    from matplotlib.figure import Figure

    from fpd.studies import compare
    t = np.linspace(0.0, 10.0, 3001)
    cases = [SimpleNamespace(label=f"model {k}", result={"u_m": 0.05 * np.sin(t), "F_N": 5e4 * np.sign(np.cos(t))
                                                       + 1e5 * k * 0.05 * np.sin(t)}) for k in range(5)]
    saved = {}
    real = Figure.savefig
    Figure.savefig = lambda self, path, **kw: (saved.setdefault("fig", self), real(self, path, **kw))[1]
    try:
        assert compare._loops(tmp_path, cases, "x") == "hysteresis.png"
    finally:
        Figure.savefig = real
    fig = saved["fig"]
    shown = [a for a in fig.axes if a.get_visible()]
    assert [a.get_title() for a in shown] == [f"model {k}" for k in range(5)]
    assert all(a.get_shared_y_axes().joined(a, shown[0]) for a in shown)
    assert [len(a.lines) for a in shown] == [1, 2, 2, 2, 2]
    assert (tmp_path / "hysteresis.png").stat().st_size > 10_000


def _text_figure():
    """A figure with what the run's figures draw: lines, a legend, a title,
    rotated and mathematical text (its fraction bar is a box), a suptitle."""
    from fpd.outputs import drawing
    fig, (ax,) = drawing.new_figure()
    t = np.linspace(0.0, 10.0, 500)
    ax.plot(t, np.sin(t), label="sin t")
    ax.plot(t, np.cos(t), "--", label=r"$\frac{\mu_1}{2}$ cos t")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(f"temperature ({drawing.DEG})")
    ax.set_title("a title: 0123456789 AVWT fi")
    ax.text(0.5, 0.5, "tilted", rotation=33, transform=ax.transAxes)
    ax.legend()
    fig.suptitle("two\nlines", fontsize=9)
    return fig


def test_png_writer_keeps_the_pixels(tmp_path):
    """drawing.save writes the PNG itself (rows unfiltered, zlib): the image
    read back is matplotlib's own PNG of the figure pixel for pixel, with its
    resolution and mode."""
    import io

    from PIL import Image

    from fpd.outputs import drawing
    fig = _text_figure()
    drawing.save(fig, tmp_path / "ours.png")
    ref = io.BytesIO()
    fig.savefig(ref, format="png", dpi=drawing.DPI)
    a, b = Image.open(tmp_path / "ours.png"), Image.open(ref)
    assert a.mode == b.mode == "RGBA" and a.size == b.size and a.info["dpi"] == b.info["dpi"]
    assert "Matplotlib" in a.info["Software"]
    assert np.array_equal(np.asarray(a), np.asarray(b))


def test_lean_glyph_loop_draws_the_same_pixels():
    """The command line's glyph loop (drawing._draw_glyphs: the transform's
    matrix and the font size once per string) draws every pixel of
    matplotlib's own loop: straight, rotated and mathematical text."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg, RendererAgg

    from fpd.outputs import drawing
    loop = RendererAgg.__dict__.get("_draw_text_glyphs_and_boxes")
    if loop is None or getattr(loop, "_fpd", False):
        pytest.skip("this matplotlib has no glyph loop of that form (the command line keeps its own)")

    def pixels():
        fig = _text_figure()
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        return np.asarray(canvas.buffer_rgba()).copy()

    ref = pixels()
    RendererAgg._draw_text_glyphs_and_boxes = drawing._draw_glyphs(loop)
    try:
        lean = pixels()
    finally:
        RendererAgg._draw_text_glyphs_and_boxes = loop
    assert ref.shape == lean.shape and (ref[..., :3] < 128).sum() > 2000      # text drawn
    assert np.array_equal(ref, lean)


def test_lean_marker_copy_is_matplotlibs():
    """The command line's copy of a MarkerStyle (drawing._copy_markers: the
    marker rebuilt from its name, fill style and user styles instead of a
    deep copy, as every tick after an axis's first takes its lines'
    properties) gives matplotlib's marker: the same paths, transforms,
    fill, cap and join styles, for the tick markers and filled, unfilled
    and half-filled ones; and the same pixels for a figure of many ticks."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.markers import MarkerStyle

    from fpd.outputs import drawing
    setm = MarkerStyle.__dict__.get("_set_marker")
    if setm is None or getattr(setm, "_fpd", False):
        pytest.skip("this matplotlib has no marker setter of that form (the command line keeps its own)")

    def state(m):
        alt = m.get_alt_path()
        return (m.get_path().vertices.tolist(), m.get_path().codes if m.get_path().codes is None
                else m.get_path().codes.tolist(), m.get_transform().get_matrix().tolist(),
                None if alt is None else alt.vertices.tolist(),
                None if alt is None else m.get_alt_transform().get_matrix().tolist(),
                m.is_filled(), m.get_fillstyle(), m.get_capstyle(), m.get_joinstyle(), m.get_marker())

    def pixels():
        fig = Figure(figsize=(4, 3), dpi=80)
        ax = fig.add_subplot()
        ax.plot(np.arange(30), np.arange(30) ** 1.5, "o-", markevery=3)
        ax.set_xticks(np.arange(0, 30, 1))
        ax.minorticks_on()
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        return np.asarray(canvas.buffer_rgba()).copy()

    cases = [(m, fs) for m in (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, "|", "_", "o", "s", "^", "x", "+", "D")
             for fs in ("full", "left", "none")]
    ref = [state(MarkerStyle(MarkerStyle(m, fs, capstyle="round"))) for m, fs in cases]
    ref_px = pixels()
    MarkerStyle._set_marker = drawing._copy_markers(setm)
    try:
        lean = [state(MarkerStyle(MarkerStyle(m, fs, capstyle="round"))) for m, fs in cases]
        lean_px = pixels()
    finally:
        MarkerStyle._set_marker = setm
    assert lean == ref
    assert np.array_equal(ref_px, lean_px)


def _title_figure():
    """Titles matplotlib leaves at y = 1 and titles it lifts: over x ticks on
    top, over a y axis offset text, two lines over a small title pad."""
    from fpd.outputs import drawing
    fig, ax = drawing.new_figure(2, 2, figsize=(8.0, 6.0), hgap=0.9)
    t = np.linspace(0.0, 1.0, 50)
    for a in ax:
        a.plot(t, t ** 2)
    ax[0].set_title("plain")
    ax[1].plot(t, 1e7 + t)                              # the y axis gets an offset text
    ax[1].set_title("an offset text on the y axis: a long title over it")
    ax[2].xaxis.tick_top()
    ax[2].set_title("ticks on top")
    ax[3].set_title("two\nlines", pad=-12)
    return fig


def test_lean_title_placement_is_matplotlibs():
    """The command line's title placement (drawing._place_titles: no y axis
    layout pass where it cannot move a title) puts every title where
    matplotlib does, the lifted ones included: the same pixels."""
    from matplotlib.axes._base import _AxesBase
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from fpd.outputs import drawing
    place = _AxesBase.__dict__["_update_title_position"]
    if getattr(place, "_fpd", False):
        pytest.skip("this process places titles lean already")

    def drawn():
        fig = _title_figure()
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        return np.asarray(canvas.buffer_rgba()).copy(), [a.title.get_position()[1] for a in fig.axes]

    ref, ys = drawn()
    _AxesBase._update_title_position = drawing._place_titles(place)
    try:
        lean, lean_ys = drawn()
    finally:
        _AxesBase._update_title_position = place
    assert ys[0] == 1.0 and min(ys[1:]) > 1.0           # matplotlib lifted the last three
    assert lean_ys == ys
    assert np.array_equal(ref, lean)


def test_lean_process_draws_the_same_figures(tmp_path):
    """A process that imports matplotlib lean (fpd run's own: no set()
    signatures, no 3-D axes, the glyph loop, text measured and laid out
    once per string: the text figure drawn twice, the second from what the
    first left) writes the same pixels as one importing it as usual."""
    import subprocess
    import sys

    from PIL import Image
    code = ("import sys; from fpd.outputs import drawing; drawing.LEAN = sys.argv[1] == 'lean'; "
            "sys.path.insert(0, sys.argv[3]); from test_plots import _text_figure, _title_figure; "
            "drawing.save(_text_figure(), sys.argv[2]); drawing.save(_title_figure(), sys.argv[2] + '.t.png'); "
            "drawing.save(_text_figure(), sys.argv[2] + '.2.png'); "
            "import matplotlib.projections as p; print('3d' in p.get_projection_names())")
    here = str(Path(__file__).resolve().parent)
    out = {}
    for mode in ("lean", "usual"):
        r = subprocess.run([sys.executable, "-c", code, mode, str(tmp_path / f"{mode}.png"), here],
                           capture_output=True, text=True, cwd=ROOT, check=True)
        out[mode] = r.stdout.split()[-1]
    assert out == {"lean": "False", "usual": "True"}     # the lean import left the 3-D axes out
    for suffix in ("", ".t.png", ".2.png"):
        a, b = (np.asarray(Image.open(tmp_path / f"{m}.png{suffix}")) for m in ("lean", "usual"))
        assert np.array_equal(a, b)
