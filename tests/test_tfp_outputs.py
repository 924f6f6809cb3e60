"""The TFP's outputs for people: ``fpd render`` on a TFP results folder (its
five bodies, mu1..mu4 and T1..T4 of the surfaces S1..S4), the hottest field of
each FE part (plots/<part>_plate_hottest.png), and the flat bearing's folder
refused by ``fpd render`` in one line."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
PARTS = ("lower", "slider_lower", "slider_upper", "upper")     # heated by S1, S2, S3, S4


from tests.test_vtk import _csv, _fpd     # the same CLI runner and CSV reader


def _picture_ok(path):
    from PIL import Image

    with Image.open(path) as im:
        a = np.asarray(im.convert("RGB"), dtype=float)
    return a.shape[0] > 100 and a.shape[1] > 100 and a.var() > 0.0


@pytest.fixture(scope="module")
def tfp_run(tmp_path_factory):
    """tfp-lab (fe1d on all four parts), one cycle, a VTK frame every 250 steps:
    9 frames (t = 0, 1.25, ..., 10 s)."""
    out = tmp_path_factory.mktemp("tfpout") / "lab"
    r = _fpd("run", "tfp-lab", "--set", "loading.cycles=1", "--set", "solver.dt=5e-3",
             "--set", "output.vtk_every=250", "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    return out


# -- fpd render ------------------------------------------------------------------------
def test_render_draws_the_tfp_bodies_with_per_surface_labels(tfp_run):
    """The series is read as a TFP (six bodies), each frame's title carries
    mu1..mu4 and T1..T4 equal to timeseries.csv at that time, the slider
    plates (whose fields are drawn) are grey under their fields, the column
    strips are as wide as the footprint that heats each part."""
    from matplotlib import colormaps
    from matplotlib.colors import Normalize
    from PIL import Image

    from fpd.outputs import render as rd

    r = _fpd("render", tfp_run, "--quiet")
    assert r.returncode == 0, r.stderr
    pngs = sorted((tfp_run / "render" / "frames").glob("frame_*.png"))
    assert len(pngs) == 9 and all(_picture_ok(p) for p in pngs[::4])
    with Image.open(tfp_run / "render" / "device.gif") as gif:
        assert gif.n_frames == 9

    frames = rd.read_device_series(tfp_run / "vtk" / "device.pvd")
    lay = rd.layout_of(frames)
    assert lay is rd.TFP_LAYOUT
    assert lay.names[1] == "lower slider plate" and lay.names[3] == "upper slider plate"
    ts = _csv(tfp_run / "timeseries.csv")
    for f in frames:
        j = int(np.argmin(np.abs(ts["t_s"] - f["time"])))
        assert abs(ts["t_s"][j] - f["time"]) < 1e-9
        lines = rd.frame_title(f, "tfp-lab", lay).split("\n")
        assert len(lines) == 3
        assert lines[1] == ",  ".join(f"mu{i} = {ts[f'mu{i}'][j]:.4f}" for i in range(1, 5))
        assert lines[2] == ",  ".join(f"T{i} = {ts[f'T{i}_C'][j]:.2f} {rd.DEG}" for i in range(1, 5))
    # the parts heat differently: T2 (slider plate, the pad's small footprint) is not T1
    assert ts["T2_C"][-1] != pytest.approx(ts["T1_C"][-1], abs=0.5)
    # every part has its field series: the plates grey under them, so are the pad and the superstructure
    with_field = {b: (tfp_run / "vtk" / f"{side}_plate.pvd").is_file() for b, side in lay.sides.items()}
    assert all(with_field.values())
    colours = rd.body_colours(frames[-1], lay, with_field, colormaps["plasma"], Normalize(20.0, 60.0))
    assert colours == list(lay.greys)
    assert rd._footprint_widths(tfp_run) == {"lower": 0.30, "upper": 0.30, "slider_lower": 0.10,
                                            "slider_upper": 0.10}


def test_render_paints_lumped_tfp_parts_by_their_own_temperature():
    """Without fields (lumped parts) each heated body is painted with its own
    surface's temperature: S2's on the lower slider plate, S4's on the upper plate."""
    from matplotlib import colormaps
    from matplotlib.colors import Normalize

    from fpd.outputs import render as rd

    f = {"time": 1.0, "body": np.arange(6), "T_C": np.array([30.0, 40.0, np.nan, 41.0, 31.0, np.nan]),
         "mu": np.array([0.1, 0.02, np.nan, 0.021, 0.11, np.nan]), "polygons": [np.zeros((3, 2))] * 6}
    lay = rd.layout_of([f])
    cmap, norm = colormaps["plasma"], Normalize(20.0, 50.0)
    colours = rd.body_colours(f, lay, {}, cmap, norm)
    assert colours[1] == cmap(norm(40.0)) and colours[3] == cmap(norm(41.0)) and colours[4] == cmap(norm(31.0))
    assert colours[2] == lay.greys[2] and colours[5] == lay.greys[5]
    assert rd.frame_title(f, "x", lay).split("\n")[1:] == [
        "mu1 = 0.1000,  mu2 = 0.0200,  mu3 = 0.0210,  mu4 = 0.1100",
        f"T1 = 30.00 {rd.DEG},  T2 = 40.00 {rd.DEG},  T3 = 41.00 {rd.DEG},  T4 = 31.00 {rd.DEG}"]
    # a DFP's four bodies keep their own reading: mu1, T1 of the lower plate, mu2, T2 of the upper
    g = {"time": 0.0, "body": np.arange(4), "T_C": np.array([25.0, np.nan, 26.0, np.nan]),
         "mu": np.array([0.05, np.nan, 0.06, np.nan]), "polygons": [np.zeros((3, 2))] * 4}
    assert rd.layout_of([g]) is rd.DFP_LAYOUT
    assert rd.frame_title(g, "x", rd.DFP_LAYOUT).split("\n")[1] == \
        f"mu1 = 0.0500,  T1 = 25.00 {rd.DEG},  mu2 = 0.0600,  T2 = 26.00 {rd.DEG}"


def test_render_refuses_a_flat_bearing_folder_in_one_line(tmp_path):
    out = tmp_path / "fb"
    r = _fpd("run", "flat-lab", "--set", "loading.cycles=0.25", "--set", "output.plots=false",
             "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    r = _fpd("render", out)
    assert r.returncode == 2, r.stderr
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    assert "flat bearing" in r.stderr and "fb" in r.stderr
    assert not (out / "render").exists()


# -- the hottest field of each part -------------------------------------------------------
def test_tfp_run_draws_each_parts_hottest_field(tfp_run):
    for part in PARTS:
        assert _picture_ok(tfp_run / "plots" / f"{part}_plate_hottest.png"), part


def test_hottest_fields_python_and_compiled_loops(monkeypatch):
    """simulate() offers the TFP's four fields every hot_every = N // 2000
    steps (here 2): each part's hottest node is its column's peak surface
    temperature over those steps (fe1d: heat enters at the face, so the
    hottest node of all times is a face node), at that step's time; the
    compiled loop (chunks cut at those steps) keeps the same fields as the
    Python loop, bit for bit."""
    from fpd import kernels
    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.outputs.hottest import TFP_SIDES, HottestFields
    from fpd.coupling.run import simulate

    sets = ["solver.duration=5", "output.csv_every=1"]
    kept = []
    for jit in (True, False):
        if not jit:
            monkeypatch.setenv("FPD_NO_JIT", "1")
        elif not kernels.available():
            continue
        sim = build(scn.load("tfp-elcentro", sets))
        assert sim.n_steps == 5000
        hot = HottestFields.of(sim)
        assert hot.parts == TFP_SIDES
        r = simulate(sim, hottest=hot)
        assert r.status == "ok", r.message
        t = r["t_s"]
        looked = np.arange(len(t)) % 2 == 0
        looked[0] = False                        # step 0 is not looked at (as simulate())
        for i, part in enumerate(PARTS, start=1):
            Tcol = r[f"T{i}_C"]
            j = np.flatnonzero(looked)[np.argmax(Tcol[looked])]
            tmax, when = hot[part][0], hot[part][1]
            assert tmax == pytest.approx(Tcol[j], rel=1e-12), part
            assert when == pytest.approx(t[j], abs=1e-12), part
            assert tmax > 25.0                   # every part heated (El Centro x 2)
        kept.append({p: (hot[p][0], hot[p][1], hot[p][4]) for p in PARTS})
    if len(kept) == 2:
        for p in PARTS:
            assert kept[0][p][:2] == kept[1][p][:2] and np.array_equal(kept[0][p][2], kept[1][p][2]), p


def test_api_run_writes_the_tfp_series(tmp_path):
    """fpd.run(..., out=) on a TFP writes the TFP's series as ``fpd run`` does
    (it drew the DFP's and failed on the TFP stepper)."""
    import pyvista

    import fpd

    out = tmp_path / "api"
    r = fpd.run("tfp-lab", out=out, **{"loading.cycles": 0.5, "solver.dt": 5e-3, "output.vtk_every": 500,
                                      "output.plots": False})
    assert r.ok
    for part in PARTS:
        assert (out / "vtk" / f"{part}_plate.pvd").is_file(), part
    dev = pyvista.PVDReader(str(out / "vtk" / "device.pvd"))
    assert len(dev.time_values) == 3
    g = dev.read()
    g = g[0] if isinstance(g, pyvista.MultiBlock) else g
    assert sorted(np.asarray(g.cell_data["body"]).tolist()) == [0, 1, 2, 3, 4, 5]


def test_render_clips_each_field_to_its_body(tmp_path):
    """A part's field wider than its body (a section wrapped onto a sliding
    surface fans out; an axisym section is centred on the footprint) is drawn
    only over that body: a hot field 10 x 10 times the lower slider plate's
    square colours as many pixels as the square painted in the same
    temperature. (Before, the field spilled over the whole drawing.)"""
    import pyvista
    from PIL import Image

    from fpd.outputs import render as rd

    sq = np.array([[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]])
    at = [(-1.5, -1.5), (0.0, 0.0), (1.5, -1.5), (-1.5, 1.5), (1.5, 1.5), (0.0, 1.5)]   # body 1 in the middle

    def frame(T1):
        return {"time": 0.0, "body": np.arange(6), "polygons": [sq + np.array(c) for c in at],
                "T_C": np.array([np.nan, T1, np.nan, np.nan, 0.0, np.nan]), "mu": np.full(6, np.nan)}

    pts = np.array([[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]])
    g = pyvista.UnstructuredGrid(np.array([4, 0, 1, 2, 3]), np.array([9], dtype=np.uint8), pts)
    g.point_data["T_C"] = np.full(4, 100.0)

    def hot_pixels(frames, fields, sub):
        png = rd.draw_frames(frames, tmp_path / sub, "x", fields)[0]
        with Image.open(png) as im:
            a = np.asarray(im.convert("RGB"), dtype=float)
        a = a[:, : int(0.8 * a.shape[1])]                     # leave out the colour bar
        top = np.array([240.0, 249.0, 33.0])                   # plasma(1): T = 100, the scale's top
        return int((np.abs(a - top).max(axis=2) < 40).sum())

    clipped = hot_pixels([frame(np.nan)], {"slider_lower": [g], "width": 0.02}, "field")
    painted = hot_pixels([frame(100.0)], {}, "painted")
    assert painted > 200
    assert abs(clipped - painted) <= 0.05 * painted, (clipped, painted)
