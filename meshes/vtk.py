"""A time series of fields on a mesh: VTU frames and a .pvd index.

Each frame is one ``.vtu`` written by ``write_vtu``: VTK XML, every array
zlib-compressed in a raw appended block (the layout ParaView writes by
default, read by ParaView, pyvista and meshio); the cell arrays of a
topology the series has written before are compressed once and their bytes
reused, so a frame costs its points and fields. ``single`` series store
floats as float32 (7 significant digits: a large plate field, where the
size matters). ``frame_size`` estimates the bytes of a series' frame from
one frame (not below any frame's), from which a run bounds its series
before writing any of it.

The ``.pvd`` index is extended in place: the new ``<DataSet>`` line is
written over the closing tags, which are written again after it (a few
hundred bytes per frame, whatever the number of frames). The index on disk
is valid after every frame, so an interrupted run leaves a readable series
of the frames written so far.

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
import zlib
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
BLOCK = 1 << 20         # uncompressed bytes per zlib block (VTK's compressed-array layout)
LEVEL = 1               # zlib level: 6 shrinks a frame's arrays ~10 % more at 2-6x the time
INDEX_ENTRY = 256       # bytes of the .pvd index per file listed, at most (frame_size)


def _array(a, single: bool = False) -> np.ndarray:
    """Little-endian, a VTK type; floats as float32 when ``single``."""
    a = np.asarray(a)
    if a.dtype == bool:
        a = a.astype(np.uint8)
    elif a.dtype.kind == "f":
        a = a.astype(np.float32 if single else (a.dtype if a.dtype == np.float32 else np.float64))
    elif a.dtype.kind in "iu" and a.dtype not in _DTYPES:
        a = a.astype(np.int64)
    return np.ascontiguousarray(a.astype(a.dtype.newbyteorder("<")))


def _compressed(raw: bytes) -> bytes:
    """VTK's compressed-array layout (header_type UInt64): [blocks, block
    size, size of the last block, compressed size of each block], then the
    zlib streams."""
    n = len(raw)
    if n == 0:
        return np.array([0, BLOCK, 0], dtype="<u8").tobytes()
    chunks = [zlib.compress(raw[i:i + BLOCK], LEVEL) for i in range(0, n, BLOCK)]
    last = n - BLOCK * (len(chunks) - 1)
    head = np.array([len(chunks), BLOCK, last] + [len(c) for c in chunks], dtype="<u8")
    return head.tobytes() + b"".join(chunks)


def _bound(raw_len: int) -> int:
    """The most bytes ``_compressed`` takes for ``raw_len`` bytes (zlib's
    worst case: stored blocks, 5 bytes per 16 kB and its 6-byte frame)."""
    blocks = max(1, -(-raw_len // BLOCK))
    return 8 * (3 + blocks) + raw_len + 5 * (raw_len // 16383 + blocks) + 6 * blocks


def _element(name, arr: np.ndarray, offset: int) -> str:
    comps = "" if arr.ndim == 1 else f' NumberOfComponents="{arr.shape[1]}"'
    label = f' Name={quoteattr(name)}' if name is not None else ""
    return (f'        <DataArray type="{_DTYPES[arr.dtype.newbyteorder("=")]}"{label}{comps}'
            f' format="appended" offset="{offset}"/>\n')


_CELLS: dict = {}      # compressed cell arrays of a topology already written (a series repeats its topology)


def _cells_arrays(cells) -> tuple[int, list]:
    """(number of cells, [(name, array, compressed bytes)] of connectivity,
    offsets and types), Int32 where the indices fit (half the bytes)."""
    conn, offs, types = [], [], []
    end = 0
    for kind, c in cells:
        c = np.asarray(c)
        if c.ndim == 1:
            c = c[None, :]
        m, k = c.shape
        conn.append(c.ravel())
        offs.append(end + k * np.arange(1, m + 1, dtype=np.int64))
        end += m * k
        types.append(np.full(m, VTK_TYPES[kind], dtype=np.uint8))
    conn = np.concatenate(conn) if conn else np.zeros(0, np.int64)
    offs = np.concatenate(offs) if offs else np.zeros(0, np.int64)
    types = np.concatenate(types) if types else np.zeros(0, np.uint8)
    wide = max(end, int(conn.max()) if conn.size else 0) >= 2 ** 31
    it = np.int64 if wide else np.int32
    out = []
    for name, a in (("connectivity", conn.astype(it)), ("offsets", offs.astype(it)), ("types", types)):
        a = _array(a)
        out.append((name, a, _compressed(a.tobytes())))
    return len(types), out


def _cells_cached(cells):
    """_cells_arrays, computed once per topology: a small one is known by its
    bytes, a large one (a 3-D plate mesh) by the identity of its arrays (the
    field's mesh is built once and handed out again every frame)."""
    size = sum(np.size(c) for _, c in cells)
    if size <= 1 << 16:
        key = ("b",) + tuple((kind, np.shape(c), np.asarray(c).tobytes()) for kind, c in cells)
        keep = None
    else:
        key = ("id",) + tuple((kind, id(c)) for kind, c in cells)
        keep = [c for _, c in cells]
    hit = _CELLS.get(key)
    if hit is not None and (keep is None or all(a is b for a, b in zip(hit[2], keep))):
        return hit[0], hit[1]
    n, arrays = _cells_arrays(cells)
    if len(_CELLS) > 64:
        _CELLS.clear()
    _CELLS[key] = (n, arrays, keep)
    return n, arrays


def _layout(points, cells, point_data, cell_data, single):
    """The file's sections: (n points, n cells, [(section, name, array,
    compressed bytes or None)]) in the order written."""
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise ValueError(f"points must be (n, 2) or (n, 3), got {points.shape}")
    if points.shape[1] == 2:
        points = np.column_stack((points, np.zeros(len(points))))
    n_cells, cell_arrays = _cells_cached(cells)
    items = [("PointData", name, _array(a, single), None) for name, a in (point_data or {}).items()]
    items += [("CellData", name, _array(np.concatenate([np.atleast_1d(np.asarray(p)) for p in parts]), single), None)
              for name, parts in (cell_data or {}).items()]
    items.append(("Points", None, _array(points, single), None))
    items += [("Cells", name, a, z) for name, a, z in cell_arrays]
    return len(points), n_cells, items


def _xml(n_points, n_cells, items, sizes) -> bytes:
    body, off = [], 0
    for section in ("PointData", "CellData", "Points", "Cells"):
        body.append(f"      <{section}>\n")
        for (sec, name, arr, _), size in zip(items, sizes):
            if sec == section:
                body.append(_element(name, arr, off))
            off += size if sec == section else 0
        body.append(f"      </{section}>\n")
    # offsets follow the order of ``items``, which is the order of the sections
    return ('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
            'byte_order="LittleEndian" header_type="UInt64" compressor="vtkZLibDataCompressor">\n'
            '  <UnstructuredGrid>\n'
            f'    <Piece NumberOfPoints="{n_points}" NumberOfCells="{n_cells}">\n'
            + "".join(body) + '    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding="raw">\n   _').encode()


_END = b"\n  </AppendedData>\n</VTKFile>\n"


def write_vtu(path, points, cells, point_data=None, cell_data=None, single: bool = False):
    """One VTK XML UnstructuredGrid file, every array zlib-compressed in one
    raw appended block (the form ParaView writes by default; pyvista and
    meshio read it); returns ``path`` as given. cells: [(meshio cell type
    name, connectivity (m, k)), ...]; point_data {name: (n,) or (n, c)};
    cell_data {name: [one array per cell block]}; ``single``: floats
    (points and data) as float32. A topology already written (the same
    cells again, a series' next frame) is not compressed again."""
    n_points, n_cells, items = _layout(points, cells, point_data, cell_data, single)
    blobs = [z if z is not None else _compressed(arr.tobytes()) for _, _, arr, z in items]
    with open(path, "wb") as fh:
        fh.write(_xml(n_points, n_cells, items, [len(b) for b in blobs]))
        for b in blobs:
            fh.write(b)
        fh.write(_END)
    return path


CHANGING = ("T_C", "mu")      # arrays whose values change from frame to frame (frame_size)
MARGIN = 1.10                 # on the compressed size of the arrays that move or stay (frame_size)


def frame_size(points, cells, point_data=None, cell_data=None, single: bool = False,
               changing=CHANGING) -> int:
    """Bytes that a series' frame like this one takes, its index line
    included, estimated from this one frame so as not to fall below any
    frame of the series: the arrays named in ``changing`` (temperatures,
    friction: their values change, a cold first frame compresses far better
    than a hot one) at zlib's worst case, about their uncompressed size; the
    others (the points, which a frame moves rigidly, depths, the cell arrays,
    the same in every frame) at this frame's compressed size plus 10 %; the
    XML with every offset at its longest."""
    n_points, n_cells, items = _layout(points, cells, point_data, cell_data, single)
    sizes = []
    for _, name, arr, z in items:
        if z is not None:
            sizes.append(len(z))
        elif name in changing:
            sizes.append(_bound(arr.nbytes))
        else:
            sizes.append(int(MARGIN * len(_compressed(arr.tobytes()))) + 64)
    return len(_xml(n_points, n_cells, items, sizes)) + 24 * len(items) + sum(sizes) + len(_END) + INDEX_ENTRY


class VTKSeries:
    """``add(time, points, cells, point_data, cell_data)`` writes
    ``<stem>_<k>.vtu`` next to ``<stem>.pvd`` and lists it there with its time.

    cells: meshio-style blocks [(cell type, connectivity), ...]; point_data:
    {name: array per point}; cell_data: {name: [one array per cell block]}.
    """

    def __init__(self, pvd_path, single: bool = False):
        self.pvd = Path(pvd_path)
        self.single = single          # floats written as float32 (write_vtu)
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
        path = Path(write_vtu(os.path.join(self._dir, name), points, cells, point_data, cell_data, self.single))
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
            paths.append(write_vtu(os.path.join(self._dir, f), points, cells, pdata, cdata, self.single))
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

    def __init__(self, folder, name: str, single: bool = False):
        super().__init__(Path(folder) / f"{name}.pvd", single)
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
