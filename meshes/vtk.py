"""A time series of fields on a mesh: VTU frames (meshio) and a .pvd index.

The .pvd is rewritten (to a temporary file, then renamed) after every frame,
so an interrupted run leaves a valid series of the frames written so far.
meshio's XDMF TimeSeriesWriter is not used: it writes its heavy data into
the working directory and keeps it in memory.

Two spellings of the same writer: ``VTKSeries(pvd_path)`` (the thermal
models' tests) and ``PVDWriter(folder, name)`` (the run's ``vtk/`` folder,
coupling/vtk_output.py), which also writes an empty but valid index at once
and has ``close()``. meshio is imported on the first frame only.
"""
from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np


class VTKSeries:
    """``add(time, points, cells, point_data, cell_data)`` writes
    ``<stem>_<k>.vtu`` next to ``<stem>.pvd`` and lists it there with its time.

    cells: meshio-style blocks [(cell type, connectivity), ...]; point_data:
    {name: array per point}; cell_data: {name: [one array per cell block]}.
    """

    def __init__(self, pvd_path):
        self.pvd = Path(pvd_path)
        if self.pvd.suffix != ".pvd":
            raise ValueError(f"{self.pvd}: a VTK series index must end in .pvd")
        self.pvd.parent.mkdir(parents=True, exist_ok=True)
        self.frames: list[tuple[float, str]] = []

    def add(self, time: float, points, cells, point_data: dict | None = None,
            cell_data: dict | None = None) -> Path:
        import meshio

        points = np.asarray(points, dtype=float)
        if points.ndim != 2 or points.shape[1] not in (2, 3):
            raise ValueError(f"points must be (n, 2) or (n, 3), got {points.shape}")
        if points.shape[1] == 2:
            points = np.column_stack((points, np.zeros(len(points))))
        data = {k: np.asarray(v) for k, v in (point_data or {}).items()}
        cdata = {k: [np.asarray(a) for a in v] for k, v in (cell_data or {}).items()}
        name = f"{self.pvd.stem}_{len(self.frames):06d}.vtu"
        path = self.pvd.parent / name
        meshio.write(path, meshio.Mesh(points, [(k, np.asarray(c)) for k, c in cells],
                                       point_data=data, cell_data=cdata), file_format="vtu")
        self.frames.append((float(time), name))
        self._flush()
        return path

    def __len__(self) -> int:
        return len(self.frames)

    def _flush(self) -> None:
        lines = ['<?xml version="1.0"?>',
                 '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
                 "  <Collection>"]
        lines += [f'    <DataSet timestep="{t!r}" group="" part="0" file={quoteattr(f)}/>'
                  for t, f in self.frames]
        lines += ["  </Collection>", "</VTKFile>", ""]
        tmp = self.pvd.with_suffix(".pvd.tmp")
        tmp.write_text("\n".join(lines))
        os.replace(tmp, self.pvd)


class PVDWriter(VTKSeries):
    """``folder/name.pvd`` and its frames ``folder/name_000000.vtu``, ...;
    the index exists (empty) from construction; ``close()`` at the end
    (also a context manager)."""

    def __init__(self, folder, name: str):
        super().__init__(Path(folder) / f"{name}.pvd")
        self.name = name
        self.closed = False
        self._flush()

    def add(self, time, points, cells, point_data=None, cell_data=None) -> Path:
        if self.closed:
            raise RuntimeError(f"{self.pvd}: series already closed")
        return super().add(time, points, cells, point_data, cell_data)

    def close(self) -> None:
        if not self.closed:
            self._flush()
            self.closed = True

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
