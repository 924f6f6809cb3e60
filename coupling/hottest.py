"""Each plate's temperature field at its hottest moment, for ``plots/``.

``simulate`` offers the plates' fields every few steps (and the VTK series
at its frames); the hottest one per plate is kept and drawn with matplotlib
(no OpenGL needed).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np


class HottestFields:
    """side -> (Tmax, time, points, cells, T) of the hottest field seen."""

    def __init__(self):
        self.best = {}

    def __getitem__(self, side):
        self.resolve()
        return self.best[side]

    def __contains__(self, side) -> bool:
        return side in self.best

    def consider(self, side: str, t: float, points, cells, T) -> None:
        T = np.asarray(T, dtype=float)
        tmax = float(np.nanmax(T)) if T.size else float("nan")
        best = self.best.get(side)
        if best is None or tmax > best[0]:
            self.best[side] = (tmax, t, np.asarray(points, dtype=float).copy(),
                               [(k, np.asarray(cc).copy()) for k, cc in cells], T.copy())

    def update(self, plates, t: float) -> None:
        """Offer the current field of every plate that has one. A plate with
        peak_temperature() and field_state() (fe3d, whose field is dear to
        build) is compared first and only its state kept; its field is built
        when asked for (resolve)."""
        for side, plate in zip(("lower", "upper"), plates):
            if plate is not None and hasattr(plate, "field_state"):
                tmax = plate.peak_temperature()
                best = self.best.get(side)
                if best is None or tmax > best[0]:
                    self.best[side] = (tmax, t, plate, plate.field_state())
                continue
            fld = plate.field() if plate is not None else None
            if fld is not None:
                self.consider(side, t, *fld)

    def resolve(self) -> None:
        """Build the fields kept as states (update)."""
        for side, best in list(self.best.items()):
            if len(best) == 4:
                tmax, t, plate, state = best
                pts, cells, T = plate.field(state)
                self.best[side] = (tmax, t, pts, cells, np.asarray(T, dtype=float))

    def pictures(self, plots_dir) -> list[Path]:
        self.resolve()
        out = []
        for side in ("lower", "upper"):
            if side in self.best:
                out.append(plot_plate_field(Path(plots_dir) / f"{side}_plate_hottest.png",
                                            f"{side} plate", *self.best[side]))
        return out


def _plane_axes(points: np.ndarray) -> tuple[int, int]:
    """The two coordinates along which the points spread most (x, y, z order kept)."""
    ext = np.ptp(points, axis=0) if len(points) else np.zeros(3)
    i, j = sorted(np.argsort(ext)[-2:])
    return int(i), int(j)


def plot_plate_field(path: Path, label: str, tmax: float, t: float, points, cells, T) -> Path:
    """A plate's temperature field: a line mesh as T along the line, a 2-D
    mesh (triangles, quads) as a coloured r-z section."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    names = "xyz"
    points = np.asarray(points, dtype=float)
    if points.shape[1] == 2:
        points = np.column_stack((points, np.zeros(len(points))))
    kinds = {k for k, _ in cells}
    if "hexahedron" in kinds and len(T) == len(points):
        # a 3D plate (fe3d, depth z >= 0): draw its sliding face z = 0, where the heat enters
        conn = np.vstack([np.asarray(cc)[:, :4] for k, cc in cells if k == "hexahedron"])
        conn = conn[np.all(np.abs(points[conn, 2]) <= 1e-12, axis=1)]
        cells = [("quad", conn)]
        kinds = {"quad"}
        label = f"{label} face"
    fig, ax = plt.subplots(figsize=(6.4, 4.2), constrained_layout=True)
    point_T = len(T) == len(points)
    if kinds <= {"line"} or not point_T:
        ext = np.ptp(points, axis=0)
        k = int(np.argmax(ext))
        if point_T:
            order = np.argsort(points[:, k])
            ax.plot(points[order, k], T[order], "-", color="tab:red")
        else:
            mids = np.array([points[np.asarray(cc)].mean(axis=1)[:, k] for _, cc in cells]).ravel()
            order = np.argsort(mids)
            ax.plot(mids[order], T[order], "-", color="tab:red")
        ax.set_xlabel(f"{names[k]} (m), plate coordinates")
        ax.set_ylabel("T (degC)")
        ax.grid(True, alpha=0.3)
    else:
        i, j = _plane_axes(points)
        tris = []
        for kind, conn in cells:
            conn = np.asarray(conn)
            if kind == "triangle":
                tris.append(conn)
            elif kind == "quad":
                tris += [conn[:, [0, 1, 2]], conn[:, [0, 2, 3]]]
        tri = Triangulation(points[:, i], points[:, j], np.vstack(tris))
        pc = ax.tripcolor(tri, T, shading="gouraud", cmap="inferno")
        fig.colorbar(pc, ax=ax, label="T (degC)")
        ext = np.ptp(points[:, [i, j]], axis=0)
        stretched = ext.min() > 0 and ext.max() / ext.min() > 3.0
        ax.set_aspect("auto" if stretched else "equal")     # a thin plate: stretch its thickness
        short = " (stretched)" if stretched else ""
        ax.set_xlabel(f"{names[i]} (m)" + (short if ext[0] < ext[1] else ""))
        ax.set_ylabel(f"{names[j]} (m)" + (short if ext[1] < ext[0] else ""))
    ax.set_title(f"{label} at its hottest: t = {t:.3f} s, max T = {tmax:.2f} degC")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
