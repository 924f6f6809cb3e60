"""VTK output (vtk/*.pvd), fpd render and import hygiene (issue 5)."""
from __future__ import annotations

import csv
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
EVERY = 100


def _fpd(*args, cwd=ROOT):
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "fpd", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=120)


def _csv(path):
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) if k != "phase" else 0.0 for r in rows]) for k in rows[0]}


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("vtk") / "sfp"
    r = _fpd("run", "sfp-harmonic", "--set", f"output.vtk_every={EVERY}", "--set", "loading.cycles=1",
             "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    return out


def _pvd_frames(pvd):
    root = ET.parse(pvd).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


# -- the device series --------------------------------------------------------------
def test_device_series_matches_timeseries(run_dir):
    import pyvista

    ts = _csv(run_dir / "timeseries.csv")
    steps = np.rint(ts["t_s"] / 1e-3).astype(int)
    rows = np.flatnonzero(steps % EVERY == 0)
    assert len(rows) == 21                       # 2 s at 1 ms: frames at steps 0, 100, ..., 2000
    reader = pyvista.PVDReader(str(run_dir / "vtk" / "device.pvd"))
    assert np.allclose(reader.time_values, ts["t_s"][rows], rtol=0, atol=1e-12)
    assert not (run_dir / "vtk" / "lower_plate.pvd").exists()     # lumped plates: no field series
    R1 = 2.0
    for k, i in enumerate(rows):
        reader.set_active_time_value(reader.time_values[k])
        plates, bodies = reader.read()          # two parts: no NaN cells
        assert plates.n_cells == 2 and bodies.n_cells == 2
        cd = plates.cell_data
        assert list(cd["body"]) == [0, 2] and list(bodies.cell_data["body"]) == [1, 3]
        np.testing.assert_allclose(cd["T_C"], [ts["T1_C"][i], ts["T2_C"][i]], rtol=1e-9)
        np.testing.assert_allclose(cd["mu"], [ts["mu1"][i], ts["mu2"][i]], rtol=1e-9)
        assert "T_C" not in bodies.cell_data and "mu" not in bodies.cell_data
        for g in (plates, bodies):
            assert np.all(g.points[:, 1] == 0.0)      # x-z plane
            for name in g.cell_data:
                assert np.isfinite(g.cell_data[name]).all()

        def polys(g):
            off, conn = g.cell_offsets, g.cell_connectivity
            return [g.points[conn[off[c]:off[c + 1]]][:, [0, 2]] for c in range(g.n_cells)]
        (p0, p2), (p1, p3) = polys(plates), polys(bodies)
        poly = [p0, p1, p2, p3]
        xg, u = ts["xg_m"][i], ts["u_m"][i]
        # the lower plate moves with the ground: its arc is centred under C1 = (xg, R1)
        assert poly[0][:, 0].mean() == pytest.approx(xg, abs=1e-9)
        # the superstructure block is centred on the upper apex, xg + u
        assert poly[3][:, 0].mean() == pytest.approx(xg + u, abs=1e-9)
        # the pad's bottom arc lies on the lower concave surface (seated)
        bottom = poly[1][:32]
        np.testing.assert_allclose(np.hypot(bottom[:, 0] - xg, bottom[:, 1] - R1), R1, atol=1e-9)


def test_seated_dfp_polygons_touch_both_surfaces():
    from fpd.outputs.device_drawings import device_polygons, pad_pose
    from fpd.mechanics.geometry import DeviceGeometry
    from fpd.thermal.params import PlateParams

    g = DeviceGeometry("DFP", 2.2, 3.0, 0.10, 0.25, 30.0, 1e5)
    pp = (PlateParams(), PlateParams())
    theta, xg = 0.04, 0.3
    O, ang = pad_pose(g, None, theta, xg)
    s = g.seated(theta, xg)
    u, z = g.L * math.sin(theta), g.L * (1 - math.cos(theta))
    lower, pad, upper, block = device_polygons(g, pp, xg, u, z, O, ang)
    bottom, top = pad[:32], pad[32:]
    np.testing.assert_allclose(np.hypot(*(bottom - s["C1"]).T), g.R1, atol=1e-12)
    np.testing.assert_allclose(np.hypot(*(top - s["C2"]).T), g.R2, atol=1e-12)
    np.testing.assert_allclose(np.hypot(*(upper[:32] - s["C2"]).T), g.R2, atol=1e-12)   # plate surface
    np.testing.assert_allclose(np.hypot(*(lower[:32] - s["C1"]).T), g.R1, atol=1e-12)
    assert block[:, 1].min() == pytest.approx(s["apex"][1] + pp[1].plate_thickness)


def test_tilting_pad_rotates_about_its_pivot_corner():
    from fpd.outputs.device_drawings import pad_pose
    from fpd.mechanics.geometry import DeviceGeometry

    g = DeviceGeometry("DFP", 2.2, 2.2, 0.10, 0.25, 30.0, 1e5)

    class Rocking:              # a two-phase stepper in the tilt phase, rocking on corner A
        mode, beta, diagonal, theta = 2, 0.05, 0, 0.02

    O0, a0 = pad_pose(g, None, 0.02, 0.0)
    O, a = pad_pose(g, Rocking(), 0.02, 0.0)
    assert a == pytest.approx(a0 + 0.05)
    A = g.pad_corners_body()["A"]
    np.testing.assert_allclose(g.to_world(O, a, *A), g.to_world(O0, a0, *A), atol=1e-12)
    assert not np.allclose(O, O0)


# -- the plate series (a stand-in plate with a field) -------------------------------
class LinePlate:
    """A stand-in FE plate: a 1-D column whose surface heats with the power in."""

    def __init__(self, n=6, kind="line"):
        self.kind = kind
        self.T = np.full(n, 20.0)
        self.E = 0.0

    def step(self, power_W, centre_m):
        self.E += power_W * 1e-3
        self.T = 20.0 + self.E * 1e-3 * np.linspace(1.0, 0.0, len(self.T))
        return self.surface_temperature()

    def surface_temperature(self):
        return float(self.T[0])

    def stored_heat(self):
        return self.E

    def heat_lost(self):
        return 0.0

    def save(self):
        return (self.T.copy(), self.E)

    def restore(self, snap):
        self.T, self.E = snap[0].copy(), snap[1]

    def field(self):
        n = len(self.T)
        if self.kind == "line":
            pts = np.zeros((n, 3))
            pts[:, 2] = -np.linspace(0.0, 0.05, n)
            return pts, [("line", np.column_stack((np.arange(n - 1), np.arange(1, n))))], self.T.copy()
        # a quad strip two nodes wide: r-z section
        m = n // 2
        r, zz = np.meshgrid([0.0, 0.4], -np.linspace(0.0, 0.05, m))
        pts = np.column_stack((r.ravel(), np.zeros(2 * m), zz.ravel()))
        quads = np.array([[2 * j, 2 * j + 1, 2 * j + 3, 2 * j + 2] for j in range(m - 1)])
        return pts, [("quad", quads)], np.repeat(self.T[:m], 2)


def test_plate_field_series_and_hottest_picture(tmp_path):
    import pyvista

    from fpd.schema import scene as scn
    from fpd.coupling.build import build
    from fpd.coupling.run import simulate
    from fpd.outputs.vtk_output import VTKSeries

    sc = scn.load("sfp-harmonic", ["loading.cycles=1", f"output.vtk_every={EVERY}"])
    sim = build(sc)
    lower, upper = LinePlate(), LinePlate(kind="quad")
    sim.plates = (lower, upper)
    fields = []
    vtk = VTKSeries(tmp_path / "vtk", sim)
    fields.append(lower.field()[2])

    def on_frame(n, s):
        vtk.frame(n, s)
        fields.append(lower.field()[2])

    res = simulate(sim, on_frame=on_frame, frame_every=EVERY)
    vtk.close()
    assert res.status == "ok"
    reader = pyvista.PVDReader(str(tmp_path / "vtk" / "lower_plate.pvd"))
    assert len(reader.time_values) == len(fields) == 21
    np.testing.assert_allclose(reader.time_values, np.arange(21) * EVERY * sim.dt, atol=1e-12)
    for k in (0, 10, 20):
        reader.set_active_time_value(reader.time_values[k])
        g = reader.read()[0]
        np.testing.assert_allclose(g.point_data["T_C"], fields[k], rtol=1e-12)
        assert g.n_cells == 5
    up = pyvista.PVDReader(str(tmp_path / "vtk" / "upper_plate.pvd"))
    assert len(up.time_values) == 21
    # the device frame's T1 is the plate's surface temperature of the same step
    dev = pyvista.PVDReader(str(tmp_path / "vtk" / "device.pvd"))
    dev.set_active_time_value(dev.time_values[-1])
    assert dev.read()[0].cell_data["T_C"][0] == pytest.approx(fields[-1][0], rel=1e-12)
    pics = vtk.hottest_pictures(tmp_path / "plots")
    # an SFP's upper housing carries no friction and never heats: no picture of it (issue 18)
    assert [p.name for p in pics] == ["lower_plate_hottest.png"]
    assert np.ptp(vtk.hottest["upper"][4]) == 0.0
    hot = vtk.hottest["lower"]
    assert hot[0] == pytest.approx(max(f.max() for f in fields))
    for p in pics:
        _assert_picture(p)


def test_fe_plate_run_writes_plate_series_and_hottest_pictures(tmp_path):
    """The real path through fpd run with an FE plate model (fe1d)."""
    import pyvista

    out = tmp_path / "fe"
    r = _fpd("run", "--set", 'thermal.model="fe1d"', "--set", "solver.duration=3.0",
             "--set", f"output.vtk_every={EVERY}", "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    ts = _csv(out / "timeseries.csv")
    dev = pyvista.PVDReader(str(out / "vtk" / "device.pvd"))
    assert len(dev.time_values) == 31
    for side, col in (("lower", "T1_C"), ("upper", "T2_C")):
        pl = pyvista.PVDReader(str(out / "vtk" / f"{side}_plate.pvd"))
        assert pl.time_values == dev.time_values
        pl.set_active_time_value(pl.time_values[-1])
        T = pl.read()[0].point_data["T_C"]
        assert T.max() > 20.0 and np.isfinite(T).all()
        _assert_picture(out / "plots" / f"{side}_plate_hottest.png")
    dev.set_active_time_value(dev.time_values[-1])
    np.testing.assert_allclose(dev.read()[0].cell_data["T_C"], [ts["T1_C"][-1], ts["T2_C"][-1]],
                               rtol=1e-9)


def test_pvd_is_valid_after_every_frame(tmp_path):
    from fpd.meshes.vtk import PVDWriter

    w = PVDWriter(tmp_path, "s")
    assert _pvd_frames(tmp_path / "s.pvd") == []
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    for k in range(3):
        w.add(0.5 * k, pts, [("triangle", [[0, 1, 2]])], point_data={"T_C": np.arange(3.0) + k})
        # no close(): an interrupted run leaves exactly the frames written so far
        assert _pvd_frames(tmp_path / "s.pvd") == [(0.5 * j, f"s_{j:06d}.vtu") for j in range(k + 1)]
    assert not list(tmp_path.glob("*.tmp"))


# -- fpd render ------------------------------------------------------------------------
def _assert_picture(path):
    from PIL import Image

    with Image.open(path) as im:
        a = np.asarray(im.convert("RGB"), dtype=float)
    assert a.shape[0] > 100 and a.shape[1] > 100
    assert a.var() > 0.0


def test_render_frames_and_gif(run_dir):
    from PIL import Image

    r = _fpd("render", run_dir)
    assert r.returncode == 0, r.stderr
    pngs = sorted((run_dir / "render" / "frames").glob("frame_*.png"))
    assert [p.name for p in pngs] == [f"frame_{k:04d}.png" for k in range(21)]
    for p in pngs[::10]:
        _assert_picture(p)
    with Image.open(run_dir / "render" / "device.gif") as gif:
        assert gif.n_frames == len(pngs)
        gif.seek(0)
        assert np.asarray(gif.convert("RGB"), dtype=float).var() > 0.0


def test_render_caps_frames():
    from fpd.outputs.render import frame_indices

    idx = frame_indices(1001, 200)
    assert len(idx) == 200 and idx[0] == 0 and idx[-1] == 1000 and np.all(np.diff(idx) > 0)
    assert list(frame_indices(7, 200)) == list(range(7))


def test_render_bad_dirs(tmp_path):
    r = _fpd("render", tmp_path / "nope")
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "nope" in r.stderr
    (tmp_path / "run").mkdir()
    r = _fpd("render", tmp_path / "run")
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "vtk_every" in r.stderr
    assert not (tmp_path / "run" / "render").exists()


# -- import hygiene ---------------------------------------------------------------------
_IMPORT_PROBE = """
import sys
from fpd.frontends import cli
from fpd.schema import scene as scn
from fpd.coupling.build import build
from fpd.coupling.run import simulate
over = ["solver.duration=0.5", "output.plots=false", "thermal.model={model}"]
sc = scn.load(None, over)
assert sc["output"]["vtk_every"] == 0
res = simulate(build(sc))
assert res.status == "ok", res.message
args = ["run", "--out", {out!r}, "--quiet"]
for o in over:
    args += ["--set", o]
assert cli.main(args) == 0
bad = [m for m in {forbidden!r} if m in sys.modules]
assert not bad, bad
"""


@pytest.mark.parametrize("model,forbidden", [
    ("lumped", ("meshio", "pyvista", "skfem", "vtk", "vtkmodules")),   # no FE, no VTK: none of them
    ("none", ("meshio", "pyvista", "skfem", "vtk", "vtkmodules")),
    ("fe1d", ("meshio", "pyvista", "vtk", "vtkmodules")),              # FE plates but no VTK output
])
def test_run_imports_only_what_the_scene_uses(tmp_path, model, forbidden):
    code = _IMPORT_PROBE.format(model=model, out=str(tmp_path / "out"), forbidden=forbidden)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
