"""A time series of VTK unstructured-grid frames with its ParaView index.

``PVDWriter(folder, name)`` writes ``folder/name_0000.vtu``, ... (binary,
through meshio) and ``folder/name.pvd``, the XML collection that lists every
frame with its time. The index is rewritten (to a temporary file, then
renamed over the old one) after every frame, so a run interrupted at any
moment leaves a valid series holding every frame written so far; ParaView and
``pyvista.PVDReader`` open it directly.

meshio is imported on the first frame, never at module import, so that runs
without VTK output do not load it. (meshio's XDMF TimeSeriesWriter is not
used: it writes its HDF5 data beside the cwd and holds every frame in memory.)
"""
from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr


class PVDWriter:
    """Frames of one series: ``add(time, points, cells, ...)`` per frame,
    ``close()`` at the end (also usable as a context manager).

    points: (n, 3) array (2-D points are padded with z = 0); cells: a
    meshio-style list of (cell type, connectivity) blocks, e.g.
    ``[("line", conn)]`` or ``[("polygon", conn4), ("polygon", conn12)]``;
    point_data: {name: (n,) or (n, k) array}; cell_data: {name: [one array per
    cell block]} (meshio's layout).
    """

    def __init__(self, folder, name: str):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.name = name
        self.pvd = self.folder / f"{name}.pvd"
        self.frames: list[tuple[float, str]] = []
        self.closed = False
        self._write_index()          # an empty but valid collection from the start

    def __len__(self) -> int:
        return len(self.frames)

    def add(self, time: float, points, cells, point_data=None, cell_data=None) -> Path:
        """Write one frame at ``time`` (s) and update the index. Returns the .vtu path."""
        if self.closed:
            raise RuntimeError(f"{self.pvd}: series already closed")
        import meshio
        import numpy as np

        pts = np.asarray(points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] not in (2, 3):
            raise ValueError(f"points must be (n, 2) or (n, 3), got {pts.shape}")
        if pts.shape[1] == 2:
            pts = np.column_stack((pts, np.zeros(len(pts))))
        blocks = [(str(kind), np.asarray(conn, dtype=np.int64)) for kind, conn in cells]
        fname = f"{self.name}_{len(self.frames):04d}.vtu"
        path = self.folder / fname
        mesh = meshio.Mesh(pts, blocks,
                           point_data={k: np.asarray(v) for k, v in (point_data or {}).items()},
                           cell_data={k: [np.asarray(a) for a in v] for k, v in (cell_data or {}).items()})
        tmp = path.with_name(path.name + ".tmp")
        meshio.write(tmp, mesh, file_format="vtu", binary=True)
        os.replace(tmp, path)
        self.frames.append((float(time), fname))
        self._write_index()
        return path

    def close(self) -> None:
        if not self.closed:
            self._write_index()
            self.closed = True

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _write_index(self) -> None:
        lines = ['<?xml version="1.0"?>',
                 '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
                 "  <Collection>"]
        for t, fname in self.frames:
            lines.append(f'    <DataSet timestep="{t!r}" group="" part="0" file={quoteattr(fname)}/>')
        lines += ["  </Collection>", "</VTKFile>", ""]
        tmp = self.pvd.with_name(self.pvd.name + ".tmp")
        with open(tmp, "w") as fh:
            fh.write("\n".join(lines))
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, self.pvd)
