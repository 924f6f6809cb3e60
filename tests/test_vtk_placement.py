"""Plate fields in device coordinates (outputs/placement.py): they overlay
device.pvd (the hot column under the pad, on the concave surfaces), and
every cell array of the series is finite (issue 18)."""
from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


def _fpd(*args, cwd=ROOT):
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "fpd", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("place") / "dfp"
    r = _fpd("run", "--set", "solver.duration=6.0", "--set", "output.vtk_every=500", "--set", "output.plots=false",
             "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    return out


def _polys(g):
    off, conn = g.cell_offsets, g.cell_connectivity
    return [g.points[conn[off[c]:off[c + 1]]][:, [0, 2]] for c in range(g.n_cells)]


def test_plate_columns_sit_under_the_pad_on_the_sliding_surfaces(run):
    import pyvista

    R1 = R2 = 2.2
    h, a = 0.10, 0.125
    dev = pyvista.PVDReader(str(run / "vtk" / "device.pvd"))
    low = pyvista.PVDReader(str(run / "vtk" / "lower_plate.pvd"))
    up = pyvista.PVDReader(str(run / "vtk" / "upper_plate.pvd"))
    assert dev.time_values == low.time_values == up.time_values
    moved = 0
    for t in dev.time_values:
        for r in (dev, low, up):
            r.set_active_time_value(t)
        plates, bodies = dev.read()
        lower_poly, upper_poly = _polys(plates)
        pad = _polys(bodies)[0]
        gl, gu = low.read()[0], up.read()[0]
        # the lower plate's arc is centred at C1 = (xg, R1): its polygon's mean x is xg
        xg = lower_poly[:, 0].mean()
        top_l = gl.points[np.argmax(gl.points[:, 2])][[0, 2]]       # the column's sliding-face node
        assert math.hypot(top_l[0] - xg, top_l[1] - R1) == pytest.approx(R1, abs=1e-9)
        # ... under the pad's bottom arc (the fe1d column follows the footprint)
        bottom = pad[:32]
        assert bottom[:, 0].min() - 1e-9 <= top_l[0] <= bottom[:, 0].max() + 1e-9
        assert abs(top_l[0] - bottom[:, 0].mean()) < 0.1 * a
        # the rest of the column goes down into the steel, along the radius
        d = np.hypot(gl.points[:, 0] - xg, gl.points[:, 2] - R1) - R1
        assert d.min() >= -1e-9 and d.max() == pytest.approx(0.05, rel=1e-6)
        # the upper plate: its column's face node on the upper arc, above the pad's top arc
        apex_x = upper_poly[:, 0].mean()
        face_u = gu.points[np.argmin(gu.points[:, 2])][[0, 2]]
        top = pad[32:]
        # the upper plate polygon's first arc is its sliding surface, about C2 = (apex_x, C2z)
        x0, z0 = upper_poly[0]
        C2z = z0 - math.sqrt(R2 ** 2 - (x0 - apex_x) ** 2)
        assert top[:, 0].min() - 1e-9 <= face_u[0] <= top[:, 0].max() + 1e-9
        assert math.hypot(face_u[0] - apex_x, face_u[1] - C2z) == pytest.approx(R2, abs=1e-9)
        du = np.hypot(gu.points[:, 0] - apex_x, gu.points[:, 2] - C2z) - R2
        assert du.min() >= -1e-9 and du.max() == pytest.approx(0.05, rel=1e-6)
        moved += abs(top_l[0]) > 0.01
        for g in (plates, bodies, gl, gu):
            for name in list(g.cell_data) + list(g.point_data):
                assert np.isfinite(np.asarray(g[name], dtype=float)).all(), name
    assert moved >= 3          # the pad moved: the placement was tested off-centre too


def test_place_field_conventions():
    """Depth below or above z = 0 (fe1d/axisym vs fe3d) lands at the same place;
    an axisym section is mirrored; a 3-D point on the face wraps onto the sphere."""
    from types import SimpleNamespace

    from fpd.outputs.placement import place_field
    from fpd.mechanics.geometry import DeviceGeometry

    geom = DeviceGeometry("DFP", 2.0, 3.0, 0.1, 0.2, 10.0, 1e4)
    vals = {"xg_m": 0.3, "u_m": 0.1, "z_m": 0.002, "s1_m": 0.05, "s2_m": 0.07}
    p = SimpleNamespace(model="fe1d", source="follow-pad", radius_m=0.0)
    col_down = (np.array([[0, 0, 0.0], [0, 0, -0.01]]), [("line", np.array([[0, 1]]))], np.array([30.0, 20.0]))
    col_up = (np.array([[0, 0, 0.0], [0, 0, 0.01]]), col_down[1], col_down[2])
    a = place_field("lower", col_down, geom, p, vals)[0]
    b = place_field("lower", col_up, geom, SimpleNamespace(model="fe3d", source="follow-pad", radius_m=0.0), vals)[0]
    np.testing.assert_allclose(a, b)
    ang = 0.05 / 2.0
    np.testing.assert_allclose(a[0], [0.3 + 2.0 * math.sin(ang), 0.0, 2.0 - 2.0 * math.cos(ang)], atol=1e-12)
    np.testing.assert_allclose(a[1], [0.3 + 2.01 * math.sin(ang), 0.0, 2.0 - 2.01 * math.cos(ang)], atol=1e-12)
    up = place_field("upper", col_down, geom, p, vals)[0]
    apex = (0.3 + 0.1, 0.1 + 0.002)
    ang2 = -0.07 / 3.0
    np.testing.assert_allclose(up[0], [apex[0] + 3.0 * math.sin(ang2), 0.0, apex[1] - 3.0 + 3.0 * math.cos(ang2)],
                               atol=1e-12)
    assert up[1, 2] > up[0, 2]                               # the steel is above the upper face
    sec = (np.array([[0, 0, 0.0], [0.1, 0, 0.0], [0.1, 0, -0.01], [0, 0, -0.01]]), [("quad", np.array([[0, 1, 2, 3]]))],
           np.arange(4.0))
    w, cells, T = place_field("lower", sec, geom, SimpleNamespace(model="axisym", source="follow-pad", radius_m=0.0),
                              vals)
    assert len(w) == 8 and sum(len(c) for _, c in cells) == 2 and len(T) == 8
    np.testing.assert_allclose(w[5, 0] - 0.3, -(w[1, 0] - 0.3), atol=1e-12)    # mirrored about the plate centre
    cube = (np.array([[0.05, 0.02, 0.0], [0.05, 0.02, 0.01]]), [("line", np.array([[0, 1]]))], np.zeros(2))
    c3 = place_field("lower", cube, geom, SimpleNamespace(model="fe3d", source="follow-pad", radius_m=0.0), vals)[0]
    assert math.dist(c3[0], (0.3, 0.0, 2.0)) == pytest.approx(2.0, abs=1e-12)
    assert math.dist(c3[1], (0.3, 0.0, 2.0)) == pytest.approx(2.01, abs=1e-12)
    assert c3[0, 1] > 0                                      # y kept off the device's plane


def test_render_refuses_to_overwrite_without_force(run):
    r = _fpd("render", run, "--quiet")
    assert r.returncode == 0, r.stderr
    first = sorted(p.name for p in (run / "render" / "frames").iterdir())
    assert len(first) == 13 and (run / "render" / "device.gif").is_file()
    r = _fpd("render", run)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "--force" in r.stderr
    r = _fpd("render", run, "--force", "--quiet")
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in (run / "render" / "frames").iterdir()) == first
    assert not list(run.glob(".render*"))


def test_pvd_index_is_extended_not_rewritten(tmp_path, monkeypatch):
    """Linear cost: after the index is created, a frame writes only its own
    DataSet lines (and the closing tags), never the whole index again."""
    import xml.etree.ElementTree as ET

    from fpd.meshes import vtk

    replaced, written = [], []
    real_replace = os.replace
    monkeypatch.setattr(vtk.os, "replace", lambda a, b: (replaced.append(b), real_replace(a, b)))
    w = vtk.PVDWriter(tmp_path, "s")
    real_append = w._append

    def spy(entries):
        before = w._body_end
        real_append(entries)
        written.append(w._body_end - before)
    w._append = spy
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    for k in range(300):
        w.add_parts(0.1 * k, [("a", pts, [("triangle", [[0, 1, 2]])], {"T_C": np.arange(3.0)}, None),
                              ("b", pts, [("triangle", [[0, 1, 2]])], None, {"body": [np.array([1])]})])
    assert len(replaced) == 1                              # the empty index, once
    assert max(written) <= 200                             # bytes per frame: two lines, whatever the frame count
    root = ET.parse(tmp_path / "s.pvd").getroot()         # valid without close()
    ds = list(root.iter("DataSet"))
    assert len(ds) == 600 and ds[-1].get("file") == "s_b_000299.vtu" and ds[-1].get("part") == "1"
    w.close()


def _hex_field(n=5, m=4):
    """A small fe3d-like field: hexahedra, x, y in the face, z the depth (>= 0)."""
    x = np.linspace(-0.2, 0.2, n)
    z = np.linspace(0.0, 0.04, m)
    X, Y, Z = np.meshgrid(x, x, z, indexing="ij")
    pts = np.column_stack((X.ravel(), Y.ravel(), Z.ravel()))
    idx = np.arange(len(pts)).reshape(n, n, m)
    hexes = []
    for i in range(n - 1):
        for j in range(n - 1):
            for k in range(m - 1):
                hexes.append([idx[i, j, k], idx[i + 1, j, k], idx[i + 1, j + 1, k], idx[i, j + 1, k],
                              idx[i, j, k + 1], idx[i + 1, j, k + 1], idx[i + 1, j + 1, k + 1], idx[i, j + 1, k + 1]])
    T = 20.0 + 30.0 * np.exp(-(pts[:, 0] ** 2 + pts[:, 1] ** 2) / 0.01 - pts[:, 2] / 0.005)
    return pts, [("hexahedron", np.array(hexes))], T


def test_three_d_field_series_and_picture(tmp_path):
    """fe3d's convention (hexahedra, depth z >= 0): placed, written, read back, drawn."""
    import pyvista
    from types import SimpleNamespace

    from fpd.outputs.hottest import plot_plate_field
    from fpd.outputs.placement import place_field
    from fpd.mechanics.geometry import DeviceGeometry
    from fpd.meshes.vtk import PVDWriter

    fld = _hex_field()
    geom = DeviceGeometry("DFP", 2.2, 2.2, 0.1, 0.25, 30.0, 1e5)
    params = SimpleNamespace(model="fe3d", source="follow-pad", radius_m=0.0, a_contact_m=0.125)
    pw, cw, Tw = place_field("upper", fld, geom, params, {"xg_m": 0.1, "u_m": 0.05, "z_m": 0.0, "s2_m": 0.0})
    with PVDWriter(tmp_path, "upper_plate") as w:
        w.add(0.0, pw, cw, point_data={"T_C": Tw})
    g = pyvista.PVDReader(str(tmp_path / "upper_plate.pvd")).read()[0]
    assert g.n_cells == 4 * 4 * 3 and np.allclose(g.point_data["T_C"], fld[2])
    face = fld[0][:, 2] == 0.0
    assert np.all(g.points[face, 2] < g.points[~face, 2].max())       # the steel is above the face
    p = plot_plate_field(tmp_path / "hot.png", "upper plate", float(fld[2].max()), 1.0, *fld,
                         surface=30.0, params=params, column="T2_C")
    from PIL import Image
    with Image.open(p) as im:
        assert np.asarray(im.convert("RGB"), dtype=float).var() > 0
