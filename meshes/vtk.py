"""A time series of fields on a mesh: VTU frames (meshio) and a .pvd index.

The .pvd is rewritten (to a temporary file, then renamed) after every frame,
so an interrupted run leaves a valid series of the frames written so far.
meshio's XDMF TimeSeriesWriter is not used: it writes its heavy data into
the working directory and keeps it in memory.
"""
from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np


class VTKSeries:
    """``add(time, points, cells, point_data)`` writes ``<stem>_<k>.vtu`` next
    to ``<stem>.pvd`` and lists it there with its time."""

    def __init__(self, pvd_path):
        self.pvd = Path(pvd_path)
        if self.pvd.suffix != ".pvd":
            raise ValueError(f"{self.pvd}: a VTK series index must end in .pvd")
        self.pvd.parent.mkdir(parents=True, exist_ok=True)
        self.frames: list[tuple[float, str]] = []

    def add(self, time: float, points, cells, point_data: dict | None = None) -> Path:
        import meshio

        points = np.asarray(points, dtype=float)
        if points.ndim != 2 or points.shape[1] not in (2, 3):
            raise ValueError(f"points must be (n, 2) or (n, 3), got {points.shape}")
        if points.shape[1] == 2:
            points = np.column_stack((points, np.zeros(len(points))))
        data = {k: np.asarray(v) for k, v in (point_data or {}).items()}
        name = f"{self.pvd.stem}_{len(self.frames):06d}.vtu"
        path = self.pvd.parent / name
        meshio.write(path, meshio.Mesh(points, [(k, np.asarray(c)) for k, c in cells],
                                       point_data=data), file_format="vtu")
        self.frames.append((float(time), name))
        self._flush()
        return path

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
