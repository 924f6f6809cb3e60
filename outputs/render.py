"""``fpd render DIR``: PNG frames and an animated GIF from a run's VTK series.

Reads ``DIR/vtk/device.pvd`` with pyvista (VTK's XML readers only: no
OpenGL) and draws every frame with matplotlib's Agg backend: the polygons of
the device in the x-z plane coloured by temperature (one colour scale for the
whole animation, with its colour bar; pad and superstructure, which carry no
temperature, in grey), the time and the friction coefficients in the title.
The device is read from the series itself: four bodies (a DFP, an SFP: lower
plate, pad, upper plate, superstructure; mu1, mu2, T1, T2) or six (a TFP,
outputs/device_drawings.py: lower plate, lower slider plate, pad, upper slider plate,
upper plate, superstructure; mu1..mu4, T1..T4 of the surfaces S1..S4, as the
TFP's timeseries columns name them). A flat-bearing run writes no VTK: its
folder is refused in one line.
Matplotlib rather than VTK's renderer, so that rendering needs no display,
no EGL/OSMesa library and no system package on a fresh machine.

Writes ``DIR/render/frames/frame_0000.png``, ... (at most ``MAX_FRAMES``,
evenly sampled over the series) and ``DIR/render/device.gif`` (pillow).
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

MAX_FRAMES = 200
GIF_FRAME_MS = 80
BODY_NAMES = ("lower plate", "pad", "upper plate", "superstructure")
DEG = "\N{DEGREE SIGN}C"
GREYS = ("#9a9a9a", "#c8c8c8", "#9a9a9a", "#d9d9d9")   # bodies without a temperature


class Layout:
    """Which body of device.pvd is what: ``names`` per body index, ``greys``
    (the colour of a body without a temperature, or under its field),
    ``sides``: body -> the plate series (vtk/<side>_plate.pvd) drawn over it,
    ``surfaces``: (body, i) -> that body's mu / T_C are mu{i} / T{i}."""

    def __init__(self, kind, names, greys, sides, surfaces, bodies_note):
        self.kind, self.names, self.greys = kind, names, greys
        self.sides, self.surfaces, self.bodies_note = sides, surfaces, bodies_note


DFP_LAYOUT = Layout("DFP", BODY_NAMES, GREYS, {0: "lower", 2: "upper"}, ((0, "1"), (2, "2")),
                    "pad and superstructure")
# outputs/device_drawings.TFPDrawing's BODIES order; T_C, mu of body 0, 1, 3, 4 are S1..S4's
TFP_LAYOUT = Layout("TFP", ("lower plate", "lower slider plate", "pad", "upper slider plate", "upper plate",
                            "superstructure"),
                    ("#9a9a9a", "#b3b3b3", "#c8c8c8", "#b3b3b3", "#9a9a9a", "#d9d9d9"),
                    {0: "lower", 1: "slider_lower", 3: "slider_upper", 4: "upper"},
                    ((0, "1"), (1, "2"), (3, "3"), (4, "4")), "pad and superstructure")


def layout_of(frames) -> Layout:
    """The device's layout from its bodies: six (0..5) a TFP, else a DFP / SFP."""
    top = max(int(np.max(f["body"])) for f in frames if len(f["body"]))
    return TFP_LAYOUT if top == len(TFP_LAYOUT.names) - 1 else DFP_LAYOUT


def frame_title(f: dict, title: str, layout: Layout) -> str:
    """The frame's title: the run, the time, each surface's mu and T (a TFP:
    mu1..mu4 on one line, T1..T4 on the next; a DFP both on one line)."""
    mus, Ts = [], []            # per surface: its words (none where the value is not finite)
    for body, name in layout.surfaces:
        sel = np.flatnonzero(f["body"] == body)
        mu, T = (f["mu"][sel[0]], f["T_C"][sel[0]]) if sel.size else (np.nan, np.nan)
        mus.append([f"mu{name} = {mu:.4f}"] if np.isfinite(mu) else [])
        Ts.append([f"T{name} = {T:.2f} {DEG}"] if np.isfinite(T) else [])
    head = f"{title}   t = {f['time']:.3f} s\n"
    if layout.kind == "TFP":
        lines = [",  ".join(sum(mus, [])), ",  ".join(sum(Ts, []))]
        return head + "\n".join(x for x in lines if x)
    return head + ",  ".join(sum((m + T for m, T in zip(mus, Ts)), []))     # mu1, T1, mu2, T2


def body_colours(f: dict, layout: Layout, with_field: dict, cmap, norm) -> list:
    """Per polygon of frame f: its grey (no temperature, or a plate whose
    field is drawn over it) or its temperature's colour (a lumped plate: T is
    the plate mean)."""
    out = []
    for body, T in zip(f["body"], f["T_C"]):
        b = int(body)
        if not np.isfinite(T) or with_field.get(b, False):
            out.append(layout.greys[b % len(layout.greys)])
        else:
            out.append(cmap(norm(T)))
    return out


def frame_indices(n: int, cap: int = MAX_FRAMES) -> np.ndarray:
    """At most ``cap`` indices of 0..n-1, evenly spread, first and last kept."""
    if n <= cap:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, cap)).astype(int))


def hull(xz: np.ndarray) -> np.ndarray:
    """Convex hull (counter-clockwise, monotone chain) of (k, 2) points."""
    p = np.unique(np.round(np.asarray(xz, dtype=float), 12), axis=0)
    if len(p) < 3:
        return p

    def half(pts):
        h = []
        for q in pts:
            while len(h) >= 2 and ((h[-1][0] - h[-2][0]) * (q[1] - h[-2][1])
                                   - (h[-1][1] - h[-2][1]) * (q[0] - h[-2][0])) <= 0:
                h.pop()
            h.append(q)
        return h
    lower, upper = half(p), half(p[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _add_solid_bodies(grid, polys, body, T, mu) -> None:
    """A 3-D device frame (device3d.pvd: caps, cylinder, box, cell data per
    cell) as one polygon per body: the outline of its x-z projection (the
    side view), with the body's T_C and mu."""
    pts = np.asarray(grid.points)
    off = np.asarray(grid.cell_offsets)
    conn = np.asarray(grid.cell_connectivity)
    cd = grid.cell_data
    b = np.asarray(cd["body"]) if "body" in cd else np.zeros(grid.n_cells, dtype=int)
    for k in np.unique(b):
        cells = np.flatnonzero(b == k)
        ids = np.unique(np.concatenate([conn[off[c]:off[c + 1]] for c in cells]))
        polys.append(hull(pts[ids][:, [0, 2]]))
        body.append(int(k))
        T.append(float(np.asarray(cd["T_C"])[cells[0]]) if "T_C" in cd else np.nan)
        mu.append(float(np.asarray(cd["mu"])[cells[0]]) if "mu" in cd else np.nan)


def read_device_series(pvd: Path, cap: int = MAX_FRAMES) -> list[dict]:
    """The sampled frames of device.pvd (or a bidirectional run's
    device3d.pvd, each body drawn as its side view's outline): dicts with
    time, polygons (list of (k, 2) x-z arrays), body, T_C, mu (per polygon)."""
    import pyvista

    solid = Path(pvd).stem == "device3d"

    from fpd.schema.scene import SceneError

    try:
        reader = pyvista.PVDReader(str(pvd))
        times = list(reader.time_values)
    except Exception as exc:          # unreadable index
        raise SceneError(f"{pvd}: not a readable VTK series ({exc})") from None
    if not times:
        raise SceneError(f"{pvd}: the series holds no frames")
    frames = []
    for i in frame_indices(len(times), cap):
        reader.set_active_time_value(times[i])
        data = reader.read()
        # the device is two parts per time (plates with T_C and mu; pad and
        # superstructure with body only): draw them together, in body order
        grids = list(data) if isinstance(data, pyvista.MultiBlock) else [data]
        polys, body, T, mu = [], [], [], []
        for grid in grids:
            if grid is None or grid.n_cells == 0:
                continue
            if solid:
                _add_solid_bodies(grid, polys, body, T, mu)
                continue
            pts = np.asarray(grid.points)[:, [0, 2]]
            off = np.asarray(grid.cell_offsets if hasattr(grid, "cell_offsets") else grid.offset)
            conn = np.asarray(grid.cell_connectivity)
            n = grid.n_cells
            cd = grid.cell_data
            polys += [pts[conn[off[k]:off[k + 1]]] for k in range(n)]
            body += list(np.asarray(cd["body"]) if "body" in cd else np.arange(len(body), len(body) + n))
            T += list(np.asarray(cd["T_C"], dtype=float) if "T_C" in cd else np.full(n, np.nan))
            mu += list(np.asarray(cd["mu"], dtype=float) if "mu" in cd else np.full(n, np.nan))
        order = np.argsort(body, kind="stable")
        if solid:       # the side view of the 3-D device: the pad in front of the plates' dishes
            order = np.concatenate((order[np.asarray(body)[order] != 1], order[np.asarray(body)[order] == 1]))
        frames.append({
            "solid": solid,
            "time": float(times[i]),
            "polygons": [polys[k] for k in order],
            "body": np.asarray(body)[order],
            "T_C": np.asarray(T)[order],
            "mu": np.asarray(mu)[order],
        })
    return frames


def read_field_series(pvd: Path, times) -> list:
    """A placed plate-field series (vtk/<side>_plate.pvd) at the given times:
    per time a list of (polygon (k, 2) x-z array, T) pieces to draw, or
    None where the series has no frame: a column (line cells) becomes a
    strip as wide as the footprint (``width``), a section its cells, a 3-D
    field the faces of its cells in the plane y = 0 (nearest nodes)."""
    import pyvista

    reader = pyvista.PVDReader(str(pvd))
    have = list(reader.time_values)
    out = []
    for t in times:
        if not have:
            out.append(None)
            continue
        j = int(np.argmin(np.abs(np.asarray(have) - t)))
        if abs(have[j] - t) > 1e-9 * max(1.0, abs(t)):
            out.append(None)
            continue
        reader.set_active_time_value(have[j])
        data = reader.read()
        g = data[0] if isinstance(data, pyvista.MultiBlock) else data
        out.append(g)
    return out


def field_pieces(g, width: float, coords=None):
    """Polygons (x-z, or the (n, 2) ``coords`` given per point) and their
    temperatures of one placed field grid."""
    pts = np.asarray(g.points)
    xz = pts[:, [0, 2]] if coords is None else np.asarray(coords, dtype=float)
    T = np.asarray(g.point_data["T_C"], dtype=float) if "T_C" in g.point_data else None
    Tc = np.asarray(g.cell_data["T_C"], dtype=float) if "T_C" in g.cell_data else None
    off = np.asarray(g.cell_offsets)
    conn = np.asarray(g.cell_connectivity)
    types = np.asarray(g.celltypes)
    if len(types) and types[0] in (5, 9) and np.all(types == types[0]):
        # one kind of section cell (an fe3d slice, an axisym section): all at once, (m, k, 2)
        ids = conn.reshape(len(types), -1)
        return xz[ids], (Tc if Tc is not None else T[ids].mean(axis=1))
    polys, vals = [], []
    ytol = 1e-9 + 1e-6 * float(np.ptp(pts[:, 1])) if len(pts) else 0.0
    on_plane = np.abs(pts[:, 1] - pts[np.argmin(np.abs(pts[:, 1])), 1]) <= ytol if len(pts) else None
    for c in range(g.n_cells):
        ids = conn[off[c]:off[c + 1]]
        v = Tc[c] if Tc is not None else float(T[ids].mean())
        if types[c] == 3:                     # a line segment of a column: a strip of the footprint's width
            p, q = xz[ids[0]], xz[ids[1]]
            d = q - p
            n = np.hypot(*d)
            if n == 0:
                continue
            tvec = np.array([-d[1], d[0]]) / n * 0.5 * width
            polys.append(np.array([p - tvec, p + tvec, q + tvec, q - tvec]))
        elif types[c] in (5, 7, 9):           # triangles, polygons, quads of a section
            polys.append(xz[ids])
        else:                                 # 3-D cells: the nodes on the plane y = 0
            sel = ids[on_plane[ids]]
            if len(sel) >= 3:
                q = xz[sel]
                ctr = q.mean(axis=0)
                order = np.argsort(np.arctan2(q[:, 1] - ctr[1], q[:, 0] - ctr[0]))
                polys.append(q[order])
            else:
                continue
        vals.append(v)
    return polys, np.asarray(vals)


LAYER_ROW = 0.3          # height of a heated-layer section, relative to the device's axes
LAYER_INCHES = 1.3       # the figure grows by this per section
LAYER_FRACTION = 0.05    # the section reaches 1.5 x as deep as any point heated by this part of the peak rise
SIDE_NAMES = {"lower": "lower plate", "upper": "upper plate", "slider_lower": "lower slider plate",
              "slider_upper": "upper slider plate"}
UPWARD = ("upper", "slider_upper")      # plates whose steel lies above their sliding face


def layer_view(grids, side: str, width: float):
    """The heated layer of one placed plate series (its ``depth_m``), for a
    section at its own scale: {"pieces": per frame (polygons in (x m, depth
    mm: negative down into a lower plate, positive up into an upper one), T),
    "depth_mm": the depth shown, "xlim"}; None when the series carries no
    depth (a series from elsewhere). The depth shown reaches 1.5 x as deep as
    any point heated by LAYER_FRACTION of the series' peak rise (at least
    0.05 mm, at most the plate)."""
    have = [g for g in grids if g is not None]
    if not have or any("depth_m" not in g.point_data for g in have):
        return None
    sign = 1.0 if side in UPWARD else -1.0

    def point_T(g):
        if "T_C" in g.point_data:
            return np.asarray(g.point_data["T_C"], dtype=float)
        return None
    Ts = [point_T(g) for g in have]
    allT = np.concatenate([t for t in Ts if t is not None] or [np.zeros(1)])
    T0, rise = float(allT.min()), float(np.ptp(allT))
    dmax = max(float(np.max(g.point_data["depth_m"])) for g in have)
    hot = 0.0
    if rise > 1e-9:
        for g, t in zip(have, Ts):
            if t is not None:
                d = np.asarray(g.point_data["depth_m"], dtype=float)[t - T0 >= LAYER_FRACTION * rise]
                hot = max(hot, float(d.max()) if d.size else 0.0)
        D = 1.5 * hot
    else:
        D = 2e-3
    D = min(max(D, 5e-5), dmax) if dmax > 0 else 1e-3
    pieces, xs = [], []
    for g in grids:
        if g is None:
            pieces.append(([], np.zeros(0)))
            continue
        d = np.asarray(g.point_data["depth_m"], dtype=float)
        x = np.asarray(g.points)[:, 0]
        polys, vals = field_pieces(g, width, coords=np.column_stack((x, sign * 1e3 * d)))
        if isinstance(polys, np.ndarray):          # (m, k, 2): the cells within the depth shown
            keep = np.abs(polys[:, :, 1]).min(axis=1) <= 1e3 * D
            pieces.append((polys[keep], vals[keep]))
            xs.append(polys[keep][:, :, 0].ravel())
            continue
        keep = [i for i, q in enumerate(polys) if np.abs(q[:, 1]).min() <= 1e3 * D]
        pieces.append(([polys[i] for i in keep], vals[keep] if len(vals) else vals))
        xs += [q[:, 0] for q in (polys[i] for i in keep)]
    xall = np.concatenate(xs) if xs else np.zeros(0)
    xall = xall if xall.size else np.zeros(1)
    x0, x1 = float(xall.min()), float(xall.max())
    pad = 0.03 * max(x1 - x0, 1e-3)
    return {"pieces": pieces, "depth_mm": 1e3 * D, "xlim": (x0 - pad, x1 + pad), "sign": sign}


def _layer_axes(ax, side: str, lv: dict) -> None:
    """A heated-layer section's axes: x as the device's, depth in mm from the sliding face."""
    from matplotlib.ticker import FuncFormatter

    D = lv["depth_mm"]
    ax.set_xlim(*lv["xlim"])
    ax.set_ylim((0.0, D) if lv["sign"] > 0 else (-D, 0.0))
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{abs(v):g}"))
    ax.set_ylabel("depth (mm)", fontsize=8)
    ax.set_xlabel("x (m)", fontsize=8, labelpad=1)
    ax.tick_params(labelsize=7)
    ax.set_facecolor("0.85")
    ax.set_title(SIDE_NAMES[side], fontsize=8, loc="left")


def _limits(frames):
    allpts = np.vstack([np.vstack(f["polygons"]) for f in frames])
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    pad = 0.05 * (hi - lo).max()
    return (lo[0] - pad, hi[0] + pad), (lo[1] - pad, hi[1] + pad)


def _t_range(frames):
    T = np.concatenate([f["T_C"] for f in frames])
    T = T[np.isfinite(T)]
    if T.size == 0:
        return 0.0, 1.0
    lo, hi = float(T.min()), float(T.max())
    if hi - lo < 1e-6:
        lo, hi = lo - 0.5, hi + 0.5
    return lo, hi


def draw_frames(frames, out_dir: Path, title: str, fields=None, progress=None) -> list[Path]:
    """fields: {side: [grid or None per frame]} of the placed plate fields and
    the footprint width: a plate with a field is drawn grey with its field
    over it (the hot track and the thin heated layer where the model has
    them); a plate without (lumped: T is the plate mean) is painted in its
    temperature. progress(k, n) is called per frame."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import Normalize
    from matplotlib.patches import Polygon
    from PIL import Image

    fields = dict(fields or {})
    width = fields.pop("width", 0.02)       # a float, or per side (a TFP: slider or pad footprint)
    (x0, x1), (z0, z1) = _limits(frames)
    lo, hi = _t_range(frames)
    pieces = {}
    for side, grids in fields.items():
        w = width.get(side, 0.02) if isinstance(width, dict) else width
        pieces[side] = [field_pieces(g, w) if g is not None else ([], np.zeros(0)) for g in grids]
        for _, v in pieces[side]:
            if v.size:
                lo, hi = min(lo, float(v.min())), max(hi, float(v.max()))
    cmap = matplotlib.colormaps["plasma"]
    out_dir.mkdir(parents=True, exist_ok=True)
    # one figure for all frames: only the polygons, their colours and the title change
    layout = layout_of(frames)
    # the heated layer (a fraction of a mm under the sliding face, invisible at the
    # device's scale) of each plate series that carries its depth: a zoomed section
    # of its own, above the device for a plate whose steel is above its face, below otherwise
    layers = {}
    for side in pieces:
        w = width.get(side, 0.02) if isinstance(width, dict) else width
        lv = layer_view(fields[side], side, w)
        if lv is not None:
            layers[side] = lv
            for _, v in lv["pieces"]:
                if v.size:
                    lo, hi = min(lo, float(v.min())), max(hi, float(v.max()))
    norm = Normalize(lo, hi)
    above = [sd for sd in ("upper", "slider_upper") if sd in layers]
    below = [sd for sd in ("slider_lower", "lower") if sd in layers]
    # a TFP's longer note (which body is which surface) in a row of its own below
    # the axes, so that the layout keeps it clear of the x label (a free fig.text
    # is not part of the layout; the layout's rect misplaces the title with a colour bar)
    rows = above + ["device"] + below + (["note"] if layout.kind == "TFP" or layers else [])
    heights = [{"device": 1.0, "note": 0.1}.get(r, LAYER_ROW) for r in rows]
    fig_h = (5.4 if layout.kind == "TFP" else 5.0) + LAYER_INCHES * len(layers)
    fig, axes = plt.subplots(len(rows), 1, figsize=(8.0, fig_h), dpi=100, layout="constrained",
                             height_ratios=heights, squeeze=False)
    axes = dict(zip(rows, axes[:, 0]))
    ax = axes["device"]
    nax = axes.get("note")
    if nax is not None:
        nax.axis("off")
    body_of = {side: b for b, side in layout.sides.items()}
    coll = PolyCollection(frames[0]["polygons"], edgecolors="none", linewidths=0.0)
    ax.add_collection(coll)
    # one collection per plate field, clipped to its own body (a section or a 3-D field
    # wrapped onto a sliding surface fans out beyond the body drawn; an axisym section
    # is centred on the footprint); no antialiasing: the strips of a column abut, and
    # antialiased seams between them would let the grey plate show through as stripes
    fcolls = {}
    for side in pieces:
        fcolls[side] = PolyCollection([], edgecolors="none", linewidths=0.0, cmap=cmap, norm=norm,
                                      antialiaseds=False)
        ax.add_collection(fcolls[side])
    # the bodies' outlines last, over the fields
    edges = PolyCollection(frames[0]["polygons"], facecolors="none", edgecolors="k", linewidths=0.8)
    ax.add_collection(edges)
    lcolls = {}
    for side, lv in layers.items():
        la = axes[side]
        lcolls[side] = PolyCollection([], edgecolors="none", linewidths=0.0, cmap=cmap, norm=norm,
                                      antialiaseds=False)
        la.add_collection(lcolls[side])
        _layer_axes(la, side, lv)
    sm = matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap)
    fig.colorbar(sm, ax=[axes[r] for r in rows if r != "note"], label=f"temperature ({DEG})",
                 shrink=0.85 if not layers else 0.95)
    ax.set_xlim(x0, x1)
    ax.set_ylim(z0, z1)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    with_field = {b: side in pieces for b, side in layout.sides.items()}
    if any(with_field.values()):
        note = ("plate temperature fields where the models have them (a 1-D column: a strip\n"
                f"of the footprint's width); the rest of the plates, {layout.bodies_note} in grey")
    else:
        note = f"plates coloured by their model's temperature (lumped: the plate mean)\n{layout.bodies_note} in grey"
    if layout.kind == "TFP":
        note += ("\nbottom to top: lower plate (S1: mu1, T1), lower slider plate (S2: mu2, T2), pad,\n"
                 "upper slider plate (S3: mu3, T3), upper plate (S4: mu4, T4), superstructure")
    if frames[0].get("solid"):
        note += "\nthe 3-D device (device3d.pvd) seen from the side: each body's outline, the pad in front"
    if layers:
        note += ("\nthe sections above and below: each plate's heated layer, its depth under the sliding "
                 "face stretched, x as in the device")
    if nax is not None:
        nax.text(0.0, 1.0, note, transform=nax.transAxes, fontsize=7, color="0.3", va="top", ha="left")
    else:
        fig.text(0.01, 0.01, note, fontsize=7, color="0.3", va="bottom")
    # room kept by the layout for the title's lines (two; a TFP's three)
    head = ax.set_title("t\nmu" + ("\nT" if layout.kind == "TFP" else ""), fontsize=11)
    fig.canvas.draw()
    fig.set_layout_engine("none")      # freeze the layout: same frame geometry throughout
    for side, lv in layers.items():     # how much the depth is stretched, now that the axes have their size
        la = axes[side]
        bb = la.get_window_extent()
        (x0l, x1l), (y0l, y1l) = la.get_xlim(), la.get_ylim()
        stretch = (bb.height / ((y1l - y0l) * 1e-3)) / (bb.width / (x1l - x0l))
        la.set_title(f"{SIDE_NAMES[side]}: the top {lv['depth_mm']:.2g} mm under its sliding face "
                     f"(depth stretched {stretch:,.0f} x)", fontsize=8, loc="left")
    # the axes, ticks and colour bar are drawn once (the slow part); per frame
    # only the polygons and the title are drawn over that background (blitting)
    for a in (coll, edges, *fcolls.values(), *lcolls.values()):
        a.set_animated(True)
    head.set_animated(True)
    fig.canvas.draw()
    canvas = fig.canvas
    background = canvas.copy_from_bbox(fig.bbox)
    paths = []
    for k, f in enumerate(frames):
        coll.set_verts(f["polygons"])
        coll.set_facecolor(body_colours(f, layout, with_field, cmap, norm))
        edges.set_verts(f["polygons"])
        for side, fc in fcolls.items():
            p, v = pieces[side][k]
            fc.set_verts(p)
            fc.set_array(v)
            sel = np.flatnonzero(f["body"] == body_of.get(side, -1))
            fc.set_clip_path(Polygon(f["polygons"][sel[0]], closed=True, transform=ax.transData)
                             if sel.size else ax.patch)
        for side, lc in lcolls.items():
            p, v = layers[side]["pieces"][k]
            lc.set_verts(p)
            lc.set_array(v)
        head.set_text(frame_title(f, title, layout))
        canvas.restore_region(background)
        ax.draw_artist(coll)
        for fc in fcolls.values():
            ax.draw_artist(fc)
        ax.draw_artist(edges)
        ax.draw_artist(head)
        for side, lc in lcolls.items():
            axes[side].draw_artist(lc)
        p = out_dir / f"frame_{k:04d}.png"
        Image.fromarray(np.asarray(canvas.buffer_rgba())[..., :3]).save(p, compress_level=3)
        paths.append(p)
        if progress is not None:
            progress(k + 1, len(frames))
    plt.close(fig)
    return paths


def write_gif(pngs: list[Path], path: Path, frame_ms: int = GIF_FRAME_MS) -> Path:
    from PIL import Image

    images = []
    for p in pngs:
        with Image.open(p) as im:
            images.append(im.convert("RGB").quantize(colors=255, method=Image.Quantize.FASTOCTREE))
    images[0].save(path, save_all=True, append_images=images[1:], duration=frame_ms, loop=0,
                   optimize=False, disposal=1)
    return path


# the device series a run writes (a planar run's and a TFP's, a bidirectional run's) and the
# plate field series drawn over them (the slider plates: a TFP's)
DEVICE_SERIES = ("device.pvd", "device3d.pvd")
FIELD_SIDES = ("lower", "slider_lower", "slider_upper", "upper")


def device_series(d: Path) -> Path | None:
    """DIR/vtk's device series: the first of DEVICE_SERIES there, or None."""
    for name in DEVICE_SERIES:
        if (Path(d) / "vtk" / name).is_file():
            return Path(d) / "vtk" / name
    return None


def render(run_dir, cap: int = MAX_FRAMES, force: bool = False, progress=None) -> tuple[list[Path], Path]:
    """Render DIR's device series (and its placed plate fields) into
    DIR/render/; returns (PNG paths, GIF path). An existing DIR/render is
    refused unless ``force`` (then replaced once the new one is complete)."""
    from fpd.schema.scene import SceneError

    d = Path(run_dir)
    if not d.is_dir():
        raise SceneError(f"{d}: no such results folder")
    pvd = device_series(d)
    if _device_kind(d) == "flat" and pvd is None:
        raise SceneError(f"{d}: a flat-bearing run (device.kind = \"flat\"); fpd render cannot draw it: "
                         "the flat bearing writes no VTK series yet")
    if pvd is None:
        raise SceneError(f"{d}: no VTK series (vtk/{' or vtk/'.join(DEVICE_SERIES)} missing); run the scene with "
                         "--set output.vtk_every=N, N > 0")
    out = d / "render"
    if out.exists() and not force:
        raise SceneError(f"{out}: exists; use --force to replace it")
    title = d.name
    try:
        title = json.loads((d / "summary.json").read_text())["scene"]
    except (OSError, ValueError, KeyError):
        pass
    frames = read_device_series(pvd, cap)
    fields = {}
    times = [f["time"] for f in frames]
    for side in FIELD_SIDES:
        f = d / "vtk" / f"{side}_plate.pvd"
        if f.is_file():
            fields[side] = read_field_series(f, times)
    if fields:
        fields["width"] = _footprint_widths(d)
    # written beside, moved into place complete (a full disk or a kill leaves
    # the old render/ or none, never half a set of frames)
    from .output import ResultsFolder
    folder = ResultsFolder(out)
    try:
        pngs = draw_frames(frames, folder.subdir("frames"), title, fields, progress)
        write_gif(pngs, folder.path("device.gif"))
        folder.commit()
    except BaseException:
        folder.discard()
        raise
    return [out / "frames" / p.name for p in pngs], out / "device.gif"


def _scene(d: Path) -> dict:
    """DIR/scene.toml, or {} if unreadable (a hand-made folder)."""
    try:
        import tomllib
        return tomllib.loads((d / "scene.toml").read_text())
    except Exception:
        return {}


def _device_kind(d: Path) -> str:
    dev = _scene(d).get("device", {})
    return dev.get("kind", "") if isinstance(dev, dict) else ""


def _footprint_widths(d: Path) -> dict:
    """Per plate series, the diameter of the footprint that heats it (the
    width a column field is drawn with) from DIR/scene.toml: the pad's, but
    a TFP's outer plates carry the slider plates (slider_diameter); 2 cm if
    unreadable (a hand-made folder: any readable width will do)."""
    dev = _scene(d).get("device", {})
    try:
        pad = float(dev["pad_diameter"])
    except (KeyError, TypeError, ValueError):
        pad = 0.02
    try:
        outer = float(dev["slider_diameter"]) if dev.get("kind") == "TFP" else pad
    except (KeyError, TypeError, ValueError):
        outer = pad
    return {"lower": outer, "upper": outer, "slider_lower": pad, "slider_upper": pad}


def cmd_render(args) -> int:
    from .claim import hold
    hold(args, args.dir, check=False)   # one writer of DIR at a time (outputs/claim.py)
    import shutil
    for stale in Path(args.dir).glob(".render.partial-*"):   # of a render that was killed: ours to tidy now
        shutil.rmtree(stale, ignore_errors=True)
    quiet = getattr(args, "quiet", False)
    show = not quiet and sys.stderr.isatty()

    def progress(k, n):
        if show and (k == n or k % 5 == 0):
            sys.stderr.write(f"\rrendering frame {k}/{n}")
            sys.stderr.flush()
    pngs, gif = render(args.dir, force=getattr(args, "force", False), progress=progress)
    if show:
        sys.stderr.write("\n")
    if not quiet:
        print(f"{len(pngs)} frames in {pngs[0].parent}/, animation {gif}")
    sys.stdout.flush()
    return 0
