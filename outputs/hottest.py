"""Each plate's temperature field at its hottest moment, for ``plots/``.

``simulate`` offers the plates' fields every few steps (and the VTK series
at its frames); the hottest one per plate is kept and drawn with matplotlib
(no OpenGL needed).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

# (side, what the picture calls it, the timeseries column of its model's temperature,
# the body whose footprint heats it), in the order of sim.plates; the picture is
# plots/<side>_plate_hottest.png
DFP_SIDES = (("lower", "lower plate", "T1_C", "pad"), ("upper", "upper plate", "T2_C", "pad"))
# the TFP's four heated parts (S1 .. S4), named as vtk/<side>_plate.pvd names them: the
# outer plates carry the slider plates' footprints, the slider plates the pad's
TFP_SIDES = (("lower", "lower plate", "T1_C", "lower slider plate"),
             ("slider_lower", "lower slider plate", "T2_C", "pad"),
             ("slider_upper", "upper slider plate", "T3_C", "pad"),
             ("upper", "upper plate", "T4_C", "upper slider plate"))


def parts_of(sim) -> tuple:
    """The parts of a simulation's plates (DFP_SIDES or TFP_SIDES)."""
    return TFP_SIDES if len(getattr(sim, "plates", ())) == 4 else DFP_SIDES


class HottestFields:
    """side -> (Tmax, time, points, cells, T) of the hottest field seen.

    ``parts``: DFP_SIDES (two plates, the default) or TFP_SIDES (the TFP's
    four heated parts); ``HottestFields.of(sim)`` picks them."""

    def __init__(self, parts=DFP_SIDES):
        self.parts = tuple(parts)
        self.best = {}
        self.surface = {}        # side -> the model's T1_C / T2_C at the kept time
        self.params = {}         # side -> PlateParams (what that column is)

    @classmethod
    def of(cls, sim) -> "HottestFields":
        return cls(parts_of(sim))

    def __getitem__(self, side):
        self.resolve()
        return self.best[side]

    def __contains__(self, side) -> bool:
        return side in self.best

    def consider(self, side: str, t: float, points, cells, T, surface=None, params=None) -> None:
        """surface: the plate model's own temperature at that time (its
        T1_C / T2_C column: footprint mean, material point...); params: the
        plate's PlateParams (what that column is, the footprint radius)."""
        T = np.asarray(T, dtype=float)
        tmax = float(np.nanmax(T)) if T.size else float("nan")
        if params is not None:
            self.params[side] = params
        best = self.best.get(side)
        if best is None or tmax > best[0]:
            self.best[side] = (tmax, t, np.asarray(points, dtype=float).copy(),
                               [(k, np.asarray(cc).copy()) for k, cc in cells], T.copy())
            self.surface[side] = None if surface is None else float(surface)

    def update(self, plates, t: float) -> None:
        """Offer the current field of every plate that has one. A plate with
        peak_temperature() and field_state() (fe3d, whose field is dear to
        build) is compared first and only its state kept; its field is built
        when asked for (resolve)."""
        for (side, *_), plate in zip(self.parts, plates):
            if plate is not None and hasattr(plate, "field_state"):
                tmax = plate.peak_temperature()
                best = self.best.get(side)
                if best is None or tmax > best[0]:
                    self.best[side] = (tmax, t, plate, plate.field_state())
                continue
            if plate is not None and hasattr(plate, "temperature") and side in self.best:
                # the field is built only when it beats the kept one (a look is then a max)
                T = plate.temperature()
                if not (np.size(T) and float(np.nanmax(T)) > self.best[side][0]):
                    continue
            fld = plate.field() if plate is not None else None
            if fld is not None:
                self.consider(side, t, *fld, surface=plate.surface_temperature(),
                              params=getattr(plate, "params", None))

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
        for side, label, column, under in self.parts:
            # a plate that never heated (an SFP's housing: its articulation
            # carries no friction) gets no picture of its uniform field
            if side in self.best and np.nanmax(self.best[side][4]) > np.nanmin(self.best[side][4]):
                out.append(plot_plate_field(Path(plots_dir) / f"{side}_plate_hottest.png",
                                            label, *self.best[side],
                                            surface=self.surface.get(side), params=self.params.get(side),
                                            column=column, under=under))
        return out


def quantity_of(model: str, source: str = "follow-pad", radius_m: float = 0.0, under: str = "pad") -> str:
    """What a plate model's temperature column (T1_C / T2_C) is, in words
    (``under``: the body whose footprint heats the plate; a TFP's outer
    plates are heated under the slider plates)."""
    if model == "lumped":
        return "plate mean (lumped)"
    if model == "fe1d":
        if source == "fixed-point":
            return f"material point at r = {radius_m:g} m, surface (fe1d)"
        return f"surface under the {under}, 1-D column (fe1d)"
    if model == "axisym":
        return "footprint mean, surface (axisym)"
    return f"surface under the {under} ({model})"


DEG = "\N{DEGREE SIGN}C"


def _hot_extent(x: np.ndarray, T: np.ndarray, lo: float, hi: float, frac: float = 0.02,
                grow: float = 1.5, least: float = 0.0) -> tuple[float, float]:
    """The range of x where T rises above frac of its rise, grown by ``grow``
    (at least ``least`` wide), clipped to [lo, hi]: the zoom on the hot part."""
    rise = T - np.nanmin(T)
    top = np.nanmax(rise)
    if not np.isfinite(top) or top <= 0:
        return lo, hi
    hot = x[rise >= frac * top]
    a, b = float(hot.min()), float(hot.max())
    w = max((b - a) * grow, least)
    c = 0.5 * (a + b) if b - a > 0 else a
    a, b = max(lo, c - 0.5 * w), min(hi, c + 0.5 * w)
    return a, b


def plot_plate_field(path: Path, label: str, tmax: float, t: float, points, cells, T,
                     surface=None, params=None, column="T_C", under="pad") -> Path:
    """A plate's temperature field at its hottest, drawn as a field and
    zoomed on the hot part (the heated track and the thin heated layer):

    - a column (fe1d: a line through the thickness): T against the depth
      into the steel, the depth axis cut where the rise fades;
    - a 2-D section (axisym: r and z): the r-depth section coloured by T,
      zoomed on the heated track and the heated layer, the footprint's
      half-width marked;
    - a 3-D field (fe3d: x, y in the face, depth): the sliding face coloured
      by T (nodes on the face) and the section through the heated track's
      centre line.

    The title gives the hottest node and, when known, what the run's
    T1_C / T2_C column holds at that time (the model's surface quantity:
    footprint mean, material point, ...) and why the two differ."""
    from matplotlib.tri import Triangulation

    from .drawing import new_figure, save

    points = np.asarray(points, dtype=float)
    if points.shape[1] == 2:
        points = np.column_stack((points, np.zeros(len(points))))
    T = np.asarray(T, dtype=float)
    point_T = len(T) == len(points)
    depth = np.abs(points[:, 2])                  # the sliding face is z = 0 (either sign convention)
    ext = np.ptp(points, axis=0) if len(points) else np.zeros(3)
    a = getattr(params, "a_contact_m", None)
    model = getattr(params, "model", "")
    what = quantity_of(model, getattr(params, "source", "follow-pad"), getattr(params, "radius_m", 0.0), under) \
        if params is not None else None
    three_d = point_T and ext[0] > 0 and ext[1] > 0 and ext[2] > 0
    section = point_T and not three_d and ext[2] > 0 and (ext[0] > 0 or ext[1] > 0)
    # fixed margins (inches): room for the three-line title above, the colour bar at the right
    if three_d:
        fig, axes = new_figure(1, 2, figsize=(10, 4.4), left=0.7, right=0.1, top=0.75, bottom=0.5, wgap=0.75)
    else:
        fig, (ax,) = new_figure(figsize=(7, 4.6), left=0.8, right=0.15 if not section else 0.1, top=0.8,
                                bottom=0.55)
    if not point_T or not (three_d or section):
        # a column: T against the depth (cell values at the cell mid-depths)
        if point_T:
            d, y = depth, T
        else:
            d = np.concatenate([depth[np.asarray(cc)].mean(axis=1) for _, cc in cells])
            y = T
        o = np.argsort(d)
        d, y = d[o], y[o]
        lo, hi = _hot_extent(d, y, 0.0, float(d.max()), grow=1.0, least=0.0)
        dmax = min(float(d.max()), max(3.0 * hi, 2e-3))
        ax.plot(1e3 * d, y, "-", color="tab:red", lw=1.6)
        ax.set_xlim(0.0, 1e3 * dmax)
        ax.set_xlabel("depth into the steel from the sliding face (mm)"
                      + (f"; plate {1e3 * float(d.max()):.0f} mm thick" if dmax < d.max() else ""))
        ax.set_ylabel(f"T ({DEG})")
        ax.grid(True, alpha=0.3)
    elif section:
        i = 0 if ext[0] > 0 else 1
        r = points[:, i]
        tris = []
        for kind, conn in cells:
            conn = np.asarray(conn)
            if kind == "triangle":
                tris.append(conn)
            elif kind == "quad":
                tris += [conn[:, [0, 1, 2]], conn[:, [0, 2, 3]]]
        tri = Triangulation(1e3 * r, 1e3 * depth, np.vstack(tris) if tris else None)
        pc = ax.tripcolor(tri, T, shading="gouraud", cmap="inferno")
        fig.colorbar(pc, ax=ax, label=f"T ({DEG})")
        face = depth <= 1e-9 * max(ext[2], 1e-12)
        r0, r1 = _hot_extent(r[face], T[face], float(r.min()), float(r.max()), grow=1.3,
                             least=2.5 * (a or 0.0))
        d0, d1 = _hot_extent(depth, T, 0.0, float(depth.max()), grow=1.0)
        ax.set_xlim(1e3 * r0, 1e3 * r1)
        ax.set_ylim(1e3 * min(float(depth.max()), max(2.0 * d1, 2e-3)), 0.0)    # depth down
        if a:      # the footprint's width, drawn on the face around the hottest surface point
            rc = float(r[face][np.argmax(T[face])])
            ax.plot([1e3 * max(rc - a, r0), 1e3 * min(rc + a, r1)], [0.0, 0.0], color="tab:cyan", lw=4,
                    solid_capstyle="butt", clip_on=False, label=f"{under} footprint width (2 a = {2e3 * a:.0f} mm)")
            ax.legend(loc="lower right", fontsize=8)
        ax.set_xlabel(("r" if model == "axisym" else "xy"[i]) + " (mm), from the plate centre (zoomed)")
        ax.set_ylabel("depth below the sliding face (mm, zoomed)")
    else:
        face = depth <= 1e-9 * max(ext[2], 1e-12) + 1e-12
        ax = axes[0]
        pc = ax.tripcolor(Triangulation(1e3 * points[face, 0], 1e3 * points[face, 1]), T[face],
                          shading="gouraud", cmap="inferno")
        fig.colorbar(pc, ax=ax, label=f"T ({DEG})")
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
        ax.set_title("sliding face", fontsize=9)
        # the section through the heated track's centre line: the face nodes'
        # y weighted by their rise over half the peak (the hottest node can sit
        # at the footprint's rim, where a section would graze the track)
        rise = np.where(face, T - np.nanmin(T), 0.0)
        w = np.where(rise >= 0.5 * np.nanmax(rise), rise, 0.0)
        yc = float(np.sum(w * points[:, 1]) / np.sum(w)) if np.sum(w) > 0 else float(points[int(np.nanargmax(T)), 1])
        ys = np.unique(points[:, 1])
        yk = ys[np.argmin(np.abs(ys - yc))]
        sel = np.abs(points[:, 1] - yk) <= 1e-9 * max(ext[1], 1e-12) + 1e-12
        ax = axes[1]
        pc = ax.tripcolor(Triangulation(1e3 * points[sel, 0], 1e3 * depth[sel]), T[sel], shading="gouraud",
                          cmap="inferno")
        d0, d1 = _hot_extent(depth[sel], T[sel], 0.0, float(depth.max()), grow=1.0)
        x0, x1 = _hot_extent(points[sel & face, 0], T[sel & face], float(points[:, 0].min()),
                             float(points[:, 0].max()), grow=1.3, least=2.5 * (a or 0.0))
        ax.set_xlim(1e3 * x0, 1e3 * x1)
        ax.set_ylim(1e3 * min(float(depth.max()), max(2.0 * d1, 2e-3)), 0.0)
        ax.set_xlabel("x (mm, zoomed)")
        ax.set_ylabel("depth (mm, zoomed)")
        ax.set_title(f"section y = {1e3 * yk:.0f} mm through the heated track", fontsize=9)
    head = f"{label} at its hottest, t = {t:.3f} s: hottest node {tmax:.2f} {DEG}"
    if surface is not None and what is not None:
        head += f"\n{column} at that time: {surface:.2f} {DEG}, the {what}"
        if surface < tmax - 0.005:
            head += ("\n(a mean over the footprint is below the footprint's hottest point)" if "mean" in what
                     else "\n(the model's point is not the hottest node)")
    fig.suptitle(head, fontsize=9.5, y=1 - 0.08 / fig.get_figheight(), va="top")
    # the title's lines above the axes (fixed margins, no layout pass)
    H = fig.get_figheight()
    lines = head.count("\n") + 1
    top = (0.2 + 0.17 * lines + (0.25 if three_d else 0.0)) / H
    fig.subplots_adjust(top=1 - top)
    path.parent.mkdir(parents=True, exist_ok=True)
    save(fig, path)
    return path
