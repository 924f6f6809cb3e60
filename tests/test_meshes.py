"""Meshes: grading, named boundaries, reading user meshes, the VTK series."""
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from fpd.meshes.line import graded_nodes, line_mesh
from fpd.meshes.rz import radial_nodes, read_rz_mesh, rz_mesh
from fpd.meshes.vtk import VTKSeries


def test_line_grading():
    z = graded_nodes(0.05, 40, 1.1)
    h = np.diff(z)
    assert z[0] == 0.0 and z[-1] == 0.05 and len(z) == 41
    assert np.allclose(h[1:] / h[:-1], 1.1)
    assert np.allclose(np.diff(graded_nodes(1.0, 4, 1.0)), 0.25)
    m = line_mesh(0.05, 40, 1.1)
    assert np.allclose(m.p[0], z)
    with pytest.raises(ValueError):
        graded_nodes(0.05, 0, 1.1)


def test_radial_band_refinement():
    r = radial_nodes(0.4, 60, band_r=0.2)
    h = np.diff(r)
    assert r[0] == 0 and r[-1] == 0.4 and len(r) == 61
    assert np.allclose(h[:45], 0.2 / 45)           # uniform over the band
    assert np.all(np.diff(h[45:]) > 0)              # growing beyond it


@pytest.mark.parametrize("triangles", [False, True])
def test_rz_mesh_boundaries(triangles):
    m = rz_mesh(0.4, 0.05, 12, 6, 1.1, triangles=triangles)
    r, z = m.p
    assert np.isclose(z.max(), 0.0) and np.isclose(z.min(), -0.05)
    checks = {"top": z == z.max(), "bottom": z == z.min(), "outer": r == r.max(), "axis": r == 0}
    for name, on in checks.items():
        nodes = np.unique(m.facets[:, m.boundaries[name]])
        assert np.array_equal(np.sort(nodes), np.flatnonzero(on)), name
    assert len(m.boundaries["top"]) == 12 and len(m.boundaries["outer"]) == 6
    dz = np.diff(np.unique(z))
    assert dz[-1] < dz[0]                           # finest at the sliding face


def _section(tmp_path, kind):
    """A 4 x 2 r-z section with named boundary line cells, as meshio data."""
    m = rz_mesh(0.2, 0.02, 4, 2, 1.0, triangles=(kind == "triangle"))
    pts = np.column_stack((m.p.T, np.zeros(m.p.shape[1])))
    names = ["top", "bottom", "outer", "axis"]
    lines = np.concatenate([m.facets[:, m.boundaries[n]].T for n in names])
    tags = np.concatenate([[i] * len(m.boundaries[n]) for i, n in enumerate(names)])
    return m, pts, [(kind, m.t.T), ("line", lines)], names, tags


@pytest.mark.parametrize("kind", ["quad", "triangle"])
def test_read_gmsh_physical_names(tmp_path, kind):
    m, pts, cells, names, tags = _section(tmp_path, kind)
    mesh = meshio.Mesh(pts, cells,
                       cell_data={"gmsh:physical": [np.full(len(cells[0][1]), 99), tags + 1],
                                  "gmsh:geometrical": [np.full(len(cells[0][1]), 1), tags + 1]},
                       field_data={n: np.array([i + 1, 1]) for i, n in enumerate(names)})
    path = tmp_path / "plate.msh"
    meshio.write(path, mesh, file_format="gmsh22")
    got = read_rz_mesh(path)
    for n in names:
        assert np.array_equal(np.sort(np.unique(got.facets[:, got.boundaries[n]])),
                              np.sort(np.unique(m.facets[:, m.boundaries[n]]))), n


def test_read_vtu_cell_sets(tmp_path):
    m, pts, cells, names, tags = _section(tmp_path, "quad")
    sets = {n: [np.array([], dtype=int), np.flatnonzero(tags == i)] for i, n in enumerate(names)}
    path = tmp_path / "plate.vtu"
    meshio.write(path, meshio.Mesh(pts, cells, cell_sets=sets))
    got = read_rz_mesh(path)
    assert {k: len(v) for k, v in got.boundaries.items()} == {"top": 4, "bottom": 4, "outer": 2, "axis": 2}


def test_read_clockwise_cells_are_reoriented(tmp_path):
    from fpd.thermal.axisym import AxisymPlate
    from fpd.thermal.params import PlateParams

    m, pts, cells, names, tags = _section(tmp_path, "quad")
    cells = [("quad", cells[0][1][:, ::-1]), cells[1]]
    sets = {n: [np.array([], dtype=int), np.flatnonzero(tags == i)] for i, n in enumerate(names)}
    path = tmp_path / "cw.vtu"
    meshio.write(path, meshio.Mesh(pts, cells, cell_sets=sets))
    base = dict(model="axisym", plate_radius=0.2, plate_thickness=0.02, nr=4, nz=2, grading=1.0,
                a_contact_m=0.07)
    a = AxisymPlate(PlateParams(**base), 0.1)
    b = AxisymPlate(PlateParams(mesh_file=str(path), **base), 0.1)
    assert b.stored_heat() == 0.0 and np.all(b.M.diagonal() > 0)
    for i in range(3):
        assert abs(a.step(1e4, 0.02 * i) - b.step(1e4, 0.02 * i)) < 1e-9


def test_read_mesh_missing_boundary_is_a_clear_error(tmp_path):
    m, pts, cells, names, tags = _section(tmp_path, "quad")
    sets = {"top": [np.array([], dtype=int), np.flatnonzero(tags == 0)]}
    path = tmp_path / "plate.vtu"
    meshio.write(path, meshio.Mesh(pts, cells, cell_sets=sets))
    with pytest.raises(ValueError, match=r"plate\.vtu: missing .*bottom, outer"):
        read_rz_mesh(path)
    with pytest.raises(ValueError, match="cannot read"):
        read_rz_mesh(tmp_path / "nothing.msh")


def test_axisym_on_a_user_mesh_matches_generated(tmp_path):
    from fpd.thermal.axisym import AxisymPlate
    from fpd.thermal.params import PlateParams

    m, pts, cells, names, tags = _section(tmp_path, "quad")
    sets = {n: [np.array([], dtype=int), np.flatnonzero(tags == i)] for i, n in enumerate(names)}
    path = tmp_path / "plate.vtu"
    meshio.write(path, meshio.Mesh(pts, cells, cell_sets=sets))
    base = dict(model="axisym", plate_radius=0.2, plate_thickness=0.02, nr=4, nz=2, grading=1.0,
                a_contact_m=0.07)
    a = AxisymPlate(PlateParams(**base), 0.1)
    b = AxisymPlate(PlateParams(mesh_file=str(path), **base), 0.1)
    for i in range(5):
        assert abs(a.step(1e4, 0.03 * i) - b.step(1e4, 0.03 * i)) < 1e-9


def test_vtk_series_readable_by_pyvista(tmp_path):
    import pyvista as pv
    from fpd.thermal.axisym import AxisymPlate
    from fpd.thermal.fe1d import FE1DPlate
    from fpd.thermal.params import PlateParams

    for model, name in ((FE1DPlate(PlateParams(n_elements=8), 0.1), "col"),
                        (AxisymPlate(PlateParams(nr=6, nz=3), 0.1), "plate")):
        series = VTKSeries(tmp_path / f"{name}.pvd")
        times = []
        for k in range(3):
            model.step(1e4, 0.0)
            pts, cells, T = model.field()
            series.add(0.1 * (k + 1), pts, cells, {"T_C": T})
            times.append(0.1 * (k + 1))
            # valid after every frame: an interrupted run leaves a readable series
            root = ET.parse(tmp_path / f"{name}.pvd").getroot()
            assert len(root.find("Collection")) == k + 1
        ds = root.find("Collection")
        assert [float(d.get("timestep")) for d in ds] == times
        reader = pv.get_reader(str(tmp_path / f"{name}.pvd"))
        assert np.allclose(reader.time_values, times)
        reader.set_active_time_value(times[-1])
        grid = reader.read()[0]
        assert np.allclose(np.asarray(grid.point_data["T_C"]), T)
        one = pv.read(tmp_path / ds[0].get("file"))
        assert one.n_points == len(pts)
