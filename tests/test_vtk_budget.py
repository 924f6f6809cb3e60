"""The VTK series within a size budget (outputs/vtk_budget.py, meshes/vtk.py):
compressed frames that ParaView's readers (pyvista) and meshio open with the
values the run computed, a size estimated before writing that bounds the
actual size, the refusal beyond output.vtk_max_GB, fe3d frames on a slice
or a coarse grid, and fpd render on every series a run writes with the
heated layer drawn where it can be seen."""
from __future__ import annotations

import os

import numpy as np
import pytest

from tests.test_vtk import _assert_picture, _csv, _fpd

SHORT = ["solver.duration=2.0", "output.plots=false"]
EVERY = 250
# frame_size counts the temperatures uncompressed and the geometry at frame 0's
# compressed size + 10 %: measured 1.0-1.4 x the actual size on these runs
RATIO = 1.6


def _vtk_bytes(folder):
    return sum(p.stat().st_size for p in folder.iterdir())


def _run_series(tmp_path, model, over=()):
    """A short default-scene run with a VTK series, the plate fields
    recorded at every frame as the model gives them (float64)."""
    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate
    from fpd.outputs.vtk_output import VTKSeries

    sc = scn.load(None, SHORT + [f'thermal.model="{model}"', f"output.vtk_every={EVERY}", *over])
    sim = build(sc)
    seen = []

    def record():
        seen.append([(np.array(p.field()[0], dtype=float), np.array(p.field()[2], dtype=float).copy())
                     for p in sim.plates])
    vtk = VTKSeries(tmp_path / "vtk", sim)
    record()

    def on_frame(n, s):
        vtk.frame(n, s)
        record()
    res = simulate(sim, on_frame=on_frame, frame_every=EVERY)
    vtk.close()
    assert res.status == "ok"
    return sim, vtk, seen, tmp_path / "vtk"


@pytest.mark.parametrize("model,grid", [("fe1d", "slice"), ("fe3d", "slice"), ("fe3d", "coarse")])
def test_estimate_bounds_the_series_written(tmp_path, model, grid):
    sim, vtk, _, folder = _run_series(tmp_path, model, [f'output.vtk_fe3d="{grid}"'])
    actual = _vtk_bytes(folder)
    frames = sim.n_steps // EVERY + 1
    assert len(list(folder.glob("lower_plate_*.vtu"))) == frames == 9
    assert actual <= vtk.estimate_bytes <= RATIO * actual, (actual, vtk.estimate_bytes)


def test_files_open_in_pyvista_and_meshio_with_the_models_values(tmp_path):
    """Every .vtu of an fe3d run (the default slice) opens in meshio and in
    pyvista; the plate frames hold the model's temperatures on the section
    y = 0 (float32: 1e-6 relative) at the depth and place of the field,
    the device frames timeseries.csv's T and mu (float64, as before)."""
    import meshio
    import pyvista

    from fpd.outputs.placement import place_field

    sim, _, seen, folder = _run_series(tmp_path, "fe3d")
    plate = sim.plates[0]
    nx, ny, nz = len(plate.x), len(plate.y), len(plate.z)
    j = int(np.argmin(np.abs(plate.y)))
    files = sorted(folder.glob("*.vtu"))
    assert len(files) == 9 * 4                     # device plates, bodies; lower, upper plate
    for f in files:
        m = meshio.read(f)
        g = pyvista.read(f)
        assert len(m.points) == g.n_points > 0
        np.testing.assert_array_equal(np.asarray(m.points, dtype=float), np.asarray(g.points, dtype=float))
        for name in g.point_data:
            np.testing.assert_array_equal(m.point_data[name], g.point_data[name])
        for name in g.cell_data:
            np.testing.assert_array_equal(np.concatenate(m.cell_data[name]), g.cell_data[name])
    reader = pyvista.PVDReader(str(folder / "lower_plate.pvd"))
    times = reader.time_values
    assert len(times) == len(seen) == 9
    for k in (0, 4, 8):
        reader.set_active_time_value(times[k])
        g = reader.read()[0]
        pts, T = seen[k][0]
        row = T.reshape(nx, ny, nz)[:, j, :].ravel()       # the model's own field on y = y_j
        assert g.point_data["T_C"].dtype == np.float32
        np.testing.assert_allclose(g.point_data["T_C"], row, rtol=1e-6)
        local = pts.reshape(nx, ny, nz, 3)[:, j, :, :].reshape(-1, 3)
        np.testing.assert_allclose(g.point_data["depth_m"], local[:, 2], rtol=1e-6, atol=1e-9)
    assert float(g.point_data["T_C"].max()) > 21.0       # heated: the comparison is not of a uniform field
    # the same file in meshio, and the placement of the frame's points
    m = meshio.read(folder / "lower_plate_000008.vtu")
    np.testing.assert_allclose(m.point_data["T_C"], seen[8][0][1].reshape(nx, ny, nz)[:, j, :].ravel(), rtol=1e-6)
    assert m.cells[0].type == "quad" and len(m.cells[0].data) == (nx - 1) * (nz - 1)
    vals = {"xg_m": 0.0}
    w = place_field("lower", (seen[0][0][0].reshape(nx, ny, nz, 3)[:, j].reshape(-1, 3), [], seen[0][0][1]),
                    sim.geometry, sim.plate_params[0], vals)[0]
    g0 = pyvista.read(folder / "lower_plate_000000.vtu")
    np.testing.assert_allclose(g0.points, w, atol=1e-6)    # float32 positions: 0.1 um at 2 m


def test_device_frames_keep_float64_and_open_in_meshio(tmp_path):
    import meshio

    out = tmp_path / "r"
    r = _fpd("run", "sfp-harmonic", "--set", "output.vtk_every=500", "--set", "loading.cycles=0.5",
             "--set", "output.plots=false", "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    ts = _csv(out / "timeseries.csv")
    steps = np.rint(ts["t_s"] / 1e-3).astype(int)
    rows = np.flatnonzero(steps % 500 == 0)
    files = sorted((out / "vtk").glob("device_plates_*.vtu"))
    assert len(files) == len(rows) >= 2
    for f, i in zip(files, rows):
        m = meshio.read(f)
        T = np.concatenate(m.cell_data["T_C"])
        assert T.dtype == np.float64
        np.testing.assert_allclose(T, [ts["T1_C"][i], ts["T2_C"][i]], rtol=1e-9)       # the CSV's 10 digits
        np.testing.assert_allclose(np.concatenate(m.cell_data["mu"]), [ts["mu1"][i], ts["mu2"][i]], rtol=1e-9)
    head = files[0].read_bytes()[:400]
    assert b'compressor="vtkZLibDataCompressor"' in head and b'format="appended"' in head


def test_slice_and_coarse_grids_are_the_models_field(tmp_path):
    """FieldView: the slice is the full field's row y = 0 and the coarse grid
    its every second node across the face (each from the model's
    temperature(rows=...), computed without the full field)."""
    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate
    from fpd.outputs.vtk_budget import FieldView

    sim = build(scn.load(None, ["solver.duration=3.0", 'thermal.model="fe3d"']))
    simulate(sim)
    p = sim.plates[0]
    pts, cells, T = p.field()
    nx, ny, nz = len(p.x), len(p.y), len(p.z)
    T3, P3 = T.reshape(nx, ny, nz), pts.reshape(nx, ny, nz, 3)
    assert np.ptp(T) > 1.0
    j = int(np.argmin(np.abs(p.y)))
    sp, sc, sT = FieldView(p, "fe3d", "slice").field(p)
    np.testing.assert_allclose(sT, T3[:, j, :].ravel(), rtol=1e-12)
    np.testing.assert_array_equal(sp, P3[:, j].reshape(-1, 3))
    assert sc[0][0] == "quad" and sc[0][1].max() == nx * nz - 1
    cp, cc, cT = FieldView(p, "fe3d", "coarse").field(p)
    ix = np.unique(np.r_[np.arange(0, nx, 2), nx - 1])
    iy = np.unique(np.r_[np.arange(0, ny, 2), ny - 1])
    np.testing.assert_allclose(cT, T3[ix][:, iy].ravel(), rtol=1e-12)
    np.testing.assert_array_equal(cp, P3[ix][:, iy].reshape(-1, 3))
    assert cc[0][0] == "hexahedron" and len(cc[0][1]) == (len(ix) - 1) * (len(iy) - 1) * (nz - 1)
    full = FieldView(p, "fe3d", "full").field(p)
    np.testing.assert_array_equal(full[2], T)


def test_refused_beyond_the_budget_in_one_line_before_writing(tmp_path):
    """The fe3d default scene with a frame every step: ~9 GB estimated,
    refused in one line (the estimate, the limit, how to lower it), exit 2,
    no results folder."""
    out = tmp_path / "x"
    r = _fpd("run", "default", "--set", 'thermal.model="fe3d"', "--set", "output.vtk_every=1", "--out", out)
    assert r.returncode == 2, r.stderr
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    line = r.stderr
    assert "output.vtk_every = 1" in line and "output.vtk_max_GB = 2" in line and "GB" in line
    assert "raise output.vtk_every to" in line and "nothing written" in line
    est = float(line.split("would take about ")[1].split(" GB")[0])
    assert 4.0 < est < 30.0
    assert not out.exists() and not list(tmp_path.iterdir())
    # the full 3-D field: the way out named is the slice
    r = _fpd("run", "default", "--set", 'thermal.model="fe3d"', "--set", "output.vtk_every=1", "--set",
             'output.vtk_fe3d="full"', "--set", "output.vtk_max_GB=5", "--out", out)
    assert r.returncode == 2 and 'output.vtk_fe3d = "slice"' in r.stderr and not out.exists()


def test_budget_rejects_a_bad_limit():
    r = _fpd("run", "--set", "output.vtk_max_GB=0", "--set", "output.vtk_every=10")
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "vtk_max_GB" in r.stderr
    r = _fpd("run", "--set", 'output.vtk_fe3d="half"')
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "vtk_fe3d" in r.stderr


# -- fpd render -----------------------------------------------------------------------
def test_render_finds_the_bidirectional_series(tmp_path):
    """A bidirectional run writes device3d.pvd; fpd render draws it (it
    looked for device.pvd only and said "run with vtk_every"): one polygon
    per body, the plates' T and mu those of timeseries.csv, the pad as wide
    as its diameter."""
    from fpd.outputs import render as rd

    out = tmp_path / "bi"
    r = _fpd("run", "impvall-bidirectional", "--set", "solver.duration=1.0", "--set", "solver.dt=2e-3",
             "--set", "thermal.model=lumped", "--set", "output.vtk_every=100", "--set", "output.plots=false",
             "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    assert not (out / "vtk" / "device.pvd").exists() and rd.device_series(out) == out / "vtk" / "device3d.pvd"
    r = _fpd("render", out, "--quiet")
    assert r.returncode == 0, r.stderr
    pngs = sorted((out / "render" / "frames").glob("frame_*.png"))
    assert len(pngs) == 6
    _assert_picture(pngs[-1])
    frames = rd.read_device_series(out / "vtk" / "device3d.pvd")
    ts = _csv(out / "timeseries.csv")
    for f in frames:
        assert sorted(f["body"].tolist()) == [0, 1, 2, 3]
        i = int(np.argmin(np.abs(ts["t_s"] - f["time"])))
        lower = int(np.flatnonzero(f["body"] == 0)[0])
        assert f["T_C"][lower] == pytest.approx(ts["T1_C"][i], rel=1e-9)
        assert f["mu"][lower] == pytest.approx(ts["mu1"][i], rel=1e-9)
        pad = f["polygons"][int(np.flatnonzero(f["body"] == 1)[0])]
        assert np.ptp(pad[:, 0]) == pytest.approx(0.25, rel=0.05)       # impvall: pad_diameter 0.25 m


def test_layer_view_reaches_the_heated_depth():
    """A field heated over 0.2 mm (T - 20 = 10 exp(-d / 0.2 mm)): the section
    shows 1.5 x the depth where the rise falls to 5 % (0.2 ln 20 = 0.60 mm),
    0.90 mm, within a node spacing; the lower plate's depth runs down (< 0)."""
    import pyvista

    from fpd.outputs.render import layer_view

    d = np.linspace(0.0, 0.05, 5001)                  # 10 um nodes
    pts = np.column_stack((np.zeros_like(d), np.zeros_like(d), -d))
    g = pyvista.UnstructuredGrid(np.column_stack((np.full(len(d) - 1, 2), np.arange(len(d) - 1),
                                                  np.arange(1, len(d)))).ravel(),
                                 np.full(len(d) - 1, 3, dtype=np.uint8), pts)
    g.point_data["T_C"] = 20.0 + 10.0 * np.exp(-d / 2e-4)
    g.point_data["depth_m"] = d
    lv = layer_view([g, g], "lower", 0.25)
    assert lv["depth_mm"] == pytest.approx(1.5 * 0.2 * np.log(20.0), abs=0.015)
    polys, vals = lv["pieces"][0]
    assert all(q[:, 1].max() <= 1e-12 for q in polys)              # down into the lower plate
    assert min(q[:, 1].min() for q in polys) >= -lv["depth_mm"] - 0.011
    assert lv["xlim"][0] < -0.12 and lv["xlim"][1] > 0.12          # the column drawn as wide as the footprint
    up = layer_view([g], "upper", 0.25)
    assert all(q[:, 1].min() >= -1e-12 for q in up["pieces"][0][0])
    del g.point_data["depth_m"]
    assert layer_view([g], "lower", 0.25) is None                 # a series without depths: no section


def test_render_draws_the_heated_layer_sections(tmp_path):
    """An fe1d run's frames: the device and, above and below it, the upper and
    lower plates' heated layers, where the hottest colour of the frame shows
    (the device alone, at its scale, shows the plates nearly uniform)."""
    from PIL import Image

    out = tmp_path / "fe"
    r = _fpd("run", "--set", 'thermal.model="fe1d"', "--set", "solver.duration=3.0", "--set",
             "output.vtk_every=1000", "--set", "output.plots=false", "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    r = _fpd("render", out, "--quiet")
    assert r.returncode == 0, r.stderr
    png = out / "render" / "frames" / "frame_0003.png"
    with Image.open(png) as im:
        a = np.asarray(im.convert("RGB"), dtype=float)
    assert a.shape[0] >= 700                                       # 5 in + two sections of 1.3 in, 100 dpi
    a = a[:, : int(0.85 * a.shape[1])]                             # the colour bar left out
    top = np.array([240.0, 249.0, 33.0])                           # plasma(1): the hottest temperature drawn
    hot = np.abs(a - top).max(axis=2) < 60
    rows = np.flatnonzero(hot.any(axis=1))
    h = a.shape[0]
    # hot pixels in the upper section (top fifth of the figure) and in the lower one (bottom third)
    assert (rows < 0.2 * h).any() and (rows > 0.66 * h).any(), rows
    assert hot.sum() > 300
