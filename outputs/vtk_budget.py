"""What a run's VTK series costs, known before any of it is written, and the
grid an fe3d plate's frames are written on.

The run's series (outputs/vtk_output.py) builds its first frame in memory as
*entries*: ``[(series name, parts)]``, parts ``[(part name or None, points,
cells, point_data, cell_data)]``. ``check_budget`` estimates one frame's
bytes with meshes/vtk.frame_size (the temperatures at their uncompressed
size, since a hot frame compresses worse than the cold first one; the
geometry at the first frame's compressed size plus 10 %), multiplies by the
number of frames the run writes (1 + steps // output.vtk_every) and refuses,
in one line with the estimate and the ways to lower it, a series over
``output.vtk_max_GB`` (GB = 1e9 bytes), before the first file exists. Every
frame of a series has the same arrays of the same lengths (only the points
move and the fields change), so the estimate of one frame is the estimate of
each.

``output.vtk_fe3d`` chooses an fe3d plate's output grid (``FieldView``):

- ``"slice"`` (default): the section y = 0 through the plate, every node in
  x and in depth (quads in the device's x-z plane, the plane ``fpd render``
  draws), ~1/70 of the plate's nodes;
- ``"coarse"``: the whole plate, every second node across the face (x, y),
  every node through the depth (the heated layer kept), ~1/4 of the nodes;
- ``"full"``: every node.

fe3d frames are float32 (``SINGLE``: 7 significant digits, 0.1 um in
position, 1e-4 K at 1000 C, far below the mesh's 0.14 mm and what a colour
map shows); the other series keep float64 (they are small).
"""
from __future__ import annotations

import numpy as np

from fpd.meshes.vtk import frame_size

GRIDS = ("slice", "coarse", "full")
SINGLE_MODELS = ("fe3d",)        # plate models whose field series are written in float32


class FieldView:
    """``view.field(plate)`` -> (points, cells, T) of a plate's field on the
    output grid of ``mode`` (see the module's text), or None; every model
    but fe3d, and fe3d's "full", give ``plate.field()``. fe3d's field is the
    tensor grid of its x, y, z nodes (node (i, j, k) at (i ny + j) nz + k);
    a slice or a coarse grid asks the plate for the temperatures of its y
    rows only (``temperature(rows=...)``) and is built once."""

    def __init__(self, plate, model: str, mode: str = "full"):
        reduce = model == "fe3d" and all(hasattr(plate, a) for a in "xyz") and hasattr(plate, "temperature")
        self.mode = mode if reduce else "full"
        self.single = model in SINGLE_MODELS
        self._mesh = None
        if self.mode == "full":
            return
        x, y, z = (np.asarray(v, dtype=float) for v in (plate.x, plate.y, plate.z))
        nx, ny, nz = len(x), len(y), len(z)
        if self.mode == "slice":
            self._rows, self._cols = [int(np.argmin(np.abs(y)))], slice(None)
            X, Z = np.meshgrid(x, z, indexing="ij")
            pts = np.column_stack((X.ravel(), np.full(X.size, y[self._rows[0]]), Z.ravel()))
            n = np.arange(nx * nz).reshape(nx, nz)
            quads = np.stack([n[:-1, :-1].ravel(), n[1:, :-1].ravel(), n[1:, 1:].ravel(), n[:-1, 1:].ravel()], axis=1)
            self._mesh = (pts, [("quad", quads)])
        else:                                            # coarse
            from fpd.meshes.box import hex_mesh

            ix = np.unique(np.r_[np.arange(0, nx, 2), nx - 1])
            iy = np.unique(np.r_[np.arange(0, ny, 2), ny - 1])
            self._rows, self._cols = iy, ix
            pts, hexes = hex_mesh(x[ix], y[iy], z)
            self._mesh = (pts, [("hexahedron", hexes)])

    def field(self, plate):
        if self._mesh is None:
            return plate.field()
        T = plate.temperature(rows=self._rows)[self._cols]
        return self._mesh[0], self._mesh[1], T.ravel()


def depth_of(local_points, n_placed: int) -> np.ndarray:
    """Per placed point, its depth below the sliding face (m): |z| of the
    plate-local points, repeated when the placement mirrored a section."""
    p = np.asarray(local_points, dtype=float)
    d = np.abs(p[:, 2]) if p.shape[1] == 3 else np.zeros(len(p))
    reps = n_placed // max(len(d), 1)
    return np.tile(d, reps) if reps > 1 else d


def put(writers: dict, t: float, entries) -> None:
    """Write one frame's entries (a single part: ``add``, several: ``add_parts``)."""
    for name, parts in entries:
        w = writers[name]
        if len(parts) == 1 and parts[0][0] is None:
            w.add(t, *parts[0][1:])
        else:
            w.add_parts(t, parts)


def frame_bytes(entries, single: dict) -> dict:
    """Bytes per frame of each series (meshes/vtk.frame_size of its files)."""
    return {name: sum(frame_size(p[1], p[2], p[3], p[4], single.get(name, False)) for p in parts)
            for name, parts in entries}


def _size(b: float) -> str:
    return f"{b / 1e9:.1f} GB" if b >= 1e8 else f"{b / 1e6:.1f} MB" if b >= 1e5 else f"{b / 1e3:.0f} kB"


def check_budget(sim, entries, single: dict, fe3d: bool) -> float:
    """The series' estimated size (bytes); a SceneError (one
    line: the estimate, the limit, how to lower it) if over output.vtk_max_GB.
    ``fe3d``: the run has fe3d fields not already on a slice."""
    from fpd.schema.scene import SceneError

    out = sim.scene["output"]
    every = int(out["vtk_every"])
    frames = sim.n_steps // every + 1
    per = frame_bytes(entries, single)
    per_frame = sum(per.values())
    total = frames * per_frame
    limit = float(out["vtk_max_GB"]) * 1e9
    if total <= limit:
        return total
    fits = int(limit // per_frame)                     # frames within the limit
    biggest = sorted(per.items(), key=lambda kv: -kv[1])[:3]
    what = ", ".join(f"{k} {_size(v)}" for k, v in biggest)
    ways = []
    if fits >= 2:
        ways.append(f"raise output.vtk_every to {sim.n_steps // fits + 1} or more")
    if fe3d:
        ways.append('write the fe3d fields on a slice (output.vtk_fe3d = "slice")')
    ways.append(f"or raise output.vtk_max_GB (at least {total / 1e9:.3g})")
    raise SceneError(f"{sim.scene.path}: output.vtk_every = {every}: the VTK series would take about "
                     f"{_size(total)} ({frames} frames of {_size(per_frame)}: {what}), over "
                     f"output.vtk_max_GB = {out['vtk_max_GB']:g}; {', '.join(ways)}; nothing written")
