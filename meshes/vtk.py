"""A time series of fields on a mesh: VTU frames and a .pvd index.

Cost linear in the number of frames (issue 18): each frame is one ``.vtu``
written by ``write_vtu`` (VTK XML, each array inline as uncompressed
base64 binary, the form meshio writes and every VTK reader takes; no meshio
object, no compression: ~0.1 ms a small frame where meshio took ~0.7 ms), and the ``.pvd`` index is extended
in place: the new ``<DataSet>`` line is written over the closing tags, which
are written again after it (a few hundred bytes per frame, whatever the
number of frames, where rewriting the whole index cost O(frames) each time
and dominated long series). The index on disk is valid after every frame,
so an interrupted run leaves a readable series of the frames written so far.

A series may have several parts per time (``add_parts``): one file per part,
listed with ``part="k"`` and a ``name`` (ParaView and pyvista read them as
one multiblock per time), so each body carries only the fields it has.

Two spellings of the same writer: ``VTKSeries(pvd_path)`` (the thermal
models' tests) and ``PVDWriter(folder, name)`` (the run's ``vtk/`` folder,
outputs/vtk_output.py), which also writes an empty but valid index at once
and has ``close()``.
"""
from __future__ import annotations

import os
from binascii import b2a_base64
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

# VTK cell type ids of the meshio-style names used here
VTK_TYPES = {"vertex": 1, "line": 3, "triangle": 5, "polygon": 7, "quad": 9, "tetra": 10,
             "hexahedron": 12, "wedge": 13, "pyramid": 14}
_DTYPES = {np.dtype("float64"): "Float64", np.dtype("float32"): "Float32", np.dtype("int64"): "Int64",
           np.dtype("int32"): "Int32", np.dtype("uint8"): "UInt8"}
_HEAD = '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n  <Collection>\n'
_TAIL = b"  </Collection>\n</VTKFile>\n"


def _array(a) -> np.ndarray:
    a = np.asarray(a)
    if a.dtype == bool:
        a = a.astype(np.uint8)
    elif a.dtype.kind == "f" and a.dtype != np.float32:
        a = a.astype(np.float64)
    elif a.dtype.kind in "iu" and a.dtype not in _DTYPES:
        a = a.astype(np.int64)
    return np.ascontiguousarray(a.astype(a.dtype.newbyteorder("<")))


_CELLS: dict = {}      # the Cells XML of a topology already written (a series repeats its topology)


def _data_array(name, arr) -> str:
    """One <DataArray> element, its bytes inline: base64 of (UInt64 size, data)."""
    arr = _array(arr)
    comps = "" if arr.ndim == 1 else f' NumberOfComponents="{arr.shape[1]}"'
    label = f' Name={quoteattr(name)}' if name is not None else ""
    raw = arr.tobytes()
    data = b2a_base64(np.uint64(len(raw)).tobytes() + raw, newline=False).decode()
    return (f'        <DataArray type="{_DTYPES[arr.dtype.newbyteorder("=")]}"{label}{comps}'
            f' format="binary">{data}</DataArray>\n')


def _cells_xml(cells) -> tuple[int, str]:
    """(number of cells, the connectivity, offsets and types arrays as XML)."""
    conn, offs, types = [], [], []
    end = 0
    for kind, c in cells:
        c = np.asarray(c, dtype=np.int64)
        if c.ndim == 1:
            c = c[None, :]
        m, k = c.shape
        conn.append(c.ravel())
        offs.append(end + k * np.arange(1, m + 1, dtype=np.int64))
        end += m * k
        types.append(np.full(m, VTK_TYPES[kind], dtype=np.uint8))
    n = sum(len(t) for t in types)
    return n, (_data_array("connectivity", np.concatenate(conn) if conn else np.zeros(0, np.int64))
               + _data_array("offsets", np.concatenate(offs) if offs else np.zeros(0, np.int64))
               + _data_array("types", np.concatenate(types) if types else np.zeros(0, np.uint8)))


def write_vtu(path, points, cells, point_data=None, cell_data=None):
    """One VTK XML UnstructuredGrid file, each array inline as base64 of
    (UInt64 byte count, little-endian data); returns ``path`` as given. cells: [(meshio cell type name, connectivity (m, k)), ...];
    point_data {name: (n,) or (n, c)}; cell_data {name: [one array per cell block]}."""
    points = np.asarray(points, dtype=float)
    if points.shape[1] == 2:
        points = np.column_stack((points, np.zeros(len(points))))
    key = tuple((kind, np.shape(c), np.asarray(c).tobytes()) for kind, c in cells)
    cached = _CELLS.get(key)
    if cached is None:
        cached = _cells_xml(cells)
        if len(_CELLS) > 64:
            _CELLS.clear()
        _CELLS[key] = cached
    n_cells, cells_xml = cached
    xml = []

    def entry(name, arr):
        xml.append(_data_array(name, arr))

    xml.append('      <PointData>\n')
    for name, a in (point_data or {}).items():
        entry(name, a)
    xml.append('      </PointData>\n      <CellData>\n')
    for name, parts in (cell_data or {}).items():
        entry(name, np.concatenate([np.atleast_1d(np.asarray(p)) for p in parts]))
    xml.append('      </CellData>\n      <Points>\n')
    entry(None, points)
    xml.append('      </Points>\n      <Cells>\n')
    xml.append(cells_xml)
    xml.append('      </Cells>\n')
    text = ('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
            'byte_order="LittleEndian" header_type="UInt64">\n  <UnstructuredGrid>\n'
            f'    <Piece NumberOfPoints="{len(points)}" NumberOfCells="{n_cells}">\n'
            + "".join(xml) + '    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n')
    with open(path, "wb") as fh:
        fh.write(text.encode())
    return path


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
        self._dir = str(self.pvd.parent)
        self._fh = None
        self._body_end = None          # byte offset of the closing tags in the index

    def add(self, time: float, points, cells, point_data: dict | None = None,
            cell_data: dict | None = None) -> Path:
        points = np.asarray(points, dtype=float)
        if points.ndim != 2 or points.shape[1] not in (2, 3):
            raise ValueError(f"points must be (n, 2) or (n, 3), got {points.shape}")
        name = f"{self.pvd.stem}_{len(self.frames):06d}.vtu"
        path = Path(write_vtu(os.path.join(self._dir, name), points, cells, point_data, cell_data))
        self.frames.append((float(time), name))
        self._append([(float(time), 0, None, name)])
        return path

    def add_parts(self, time: float, parts) -> list[Path]:
        """One time with several parts: parts = [(name, points, cells,
        point_data, cell_data), ...], each written to
        ``<stem>_<name>_<k>.vtu`` and listed with part="i" name="name"."""
        k = len(self.frames)
        entries, paths = [], []
        for i, (pname, points, cells, pdata, cdata) in enumerate(parts):
            f = f"{self.pvd.stem}_{pname}_{k:06d}.vtu"
            paths.append(write_vtu(os.path.join(self._dir, f), points, cells, pdata, cdata))
            entries.append((float(time), i, pname, f))
        self.frames.append((float(time), entries[0][3] if entries else ""))
        self._append(entries)
        return paths

    def __len__(self) -> int:
        return len(self.frames)

    def _append(self, entries) -> None:
        """Write these DataSet lines over the closing tags, then the tags again."""
        text = "".join(f'    <DataSet timestep="{t!r}" group="" part="{p}"'
                       + (f" name={quoteattr(n)}" if n else "") + f" file={quoteattr(f)}/>\n"
                       for t, p, n, f in entries).encode()
        if self._body_end is None:
            self._start()
        fh = self._fh
        fh.seek(self._body_end)
        fh.write(text + _TAIL)      # longer than the tags it overwrites: nothing to truncate
        fh.flush()                  # in the OS's hands: a crash of the process leaves a valid index
        self._body_end += len(text)

    def _start(self) -> None:
        """A fresh index with no frames (written to a temporary file, renamed),
        kept open for the frames to come."""
        tmp = self.pvd.with_suffix(".pvd.tmp")
        head = _HEAD.encode()
        tmp.write_bytes(head + _TAIL)
        os.replace(tmp, self.pvd)
        self._body_end = len(head)
        self._fh = open(self.pvd, "r+b")

    def _close_index(self) -> None:
        fh = getattr(self, "_fh", None)
        if fh is not None:
            fh.close()
            self._fh = None

    def __del__(self):
        self._close_index()


class PVDWriter(VTKSeries):
    """``folder/name.pvd`` and its frames ``folder/name_000000.vtu``, ...;
    the index exists (empty) from construction; ``close()`` at the end
    (also a context manager)."""

    def __init__(self, folder, name: str):
        super().__init__(Path(folder) / f"{name}.pvd")
        self.name = name
        self.closed = False
        self._start()

    def add(self, time, points, cells, point_data=None, cell_data=None) -> Path:
        if self.closed:
            raise RuntimeError(f"{self.pvd}: series already closed")
        return super().add(time, points, cells, point_data, cell_data)

    def add_parts(self, time, parts) -> list[Path]:
        if self.closed:
            raise RuntimeError(f"{self.pvd}: series already closed")
        return super().add_parts(time, parts)

    def close(self) -> None:
        self.closed = True
        self._close_index()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
