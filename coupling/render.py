"""``fpd render DIR``: PNG frames and an animated GIF from a run's VTK series.

Reads ``DIR/vtk/device.pvd`` with pyvista (VTK's XML readers only: no
OpenGL) and draws every frame with matplotlib's Agg backend: the polygons of
the device in the x-z plane coloured by temperature (one colour scale for the
whole animation, with its colour bar; pad and superstructure, which carry no
temperature, in grey), the time and the friction coefficients in the title.
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
GREYS = ("#9a9a9a", "#c8c8c8", "#9a9a9a", "#d9d9d9")   # bodies without a temperature


def frame_indices(n: int, cap: int = MAX_FRAMES) -> np.ndarray:
    """At most ``cap`` indices of 0..n-1, evenly spread, first and last kept."""
    if n <= cap:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, cap)).astype(int))


def read_device_series(pvd: Path, cap: int = MAX_FRAMES) -> list[dict]:
    """The sampled frames of device.pvd: dicts with time, polygons (list of
    (k, 2) x-z arrays), body, T_C, mu (per polygon)."""
    import pyvista

    from .scene import SceneError

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
        grid = data[0] if isinstance(data, pyvista.MultiBlock) else data
        pts = np.asarray(grid.points)[:, [0, 2]]
        off = np.asarray(grid.cell_offsets if hasattr(grid, "cell_offsets") else grid.offset)
        conn = np.asarray(grid.cell_connectivity)
        polys = [pts[conn[off[k]:off[k + 1]]] for k in range(grid.n_cells)]
        cd = grid.cell_data
        n = grid.n_cells
        frames.append({
            "time": float(times[i]),
            "polygons": polys,
            "body": np.asarray(cd["body"]) if "body" in cd else np.arange(n),
            "T_C": np.asarray(cd["T_C"], dtype=float) if "T_C" in cd else np.full(n, np.nan),
            "mu": np.asarray(cd["mu"], dtype=float) if "mu" in cd else np.full(n, np.nan),
        })
    return frames


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


def draw_frames(frames, out_dir: Path, title: str) -> list[Path]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import Normalize
    from PIL import Image

    (x0, x1), (z0, z1) = _limits(frames)
    norm = Normalize(*_t_range(frames))
    cmap = matplotlib.colormaps["plasma"]
    out_dir.mkdir(parents=True, exist_ok=True)
    for old in out_dir.glob("frame_*.png"):
        old.unlink()
    # one figure for all frames: only the polygons, their colours and the title change
    fig, ax = plt.subplots(figsize=(8.0, 5.0), dpi=100, layout="constrained")
    coll = PolyCollection(frames[0]["polygons"], edgecolors="k", linewidths=0.8)
    ax.add_collection(coll)
    sm = matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap)
    fig.colorbar(sm, ax=ax, label="plate surface temperature (degC)", shrink=0.85)
    ax.set_xlim(x0, x1)
    ax.set_ylim(z0, z1)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    ax.text(0.01, 0.02, "plates coloured by their surface temperature; pad and superstructure in grey",
            transform=ax.transAxes, fontsize=8, color="0.3")
    head = ax.set_title("t\nmu", fontsize=11)     # two lines: room kept by the layout
    fig.canvas.draw()
    fig.set_layout_engine("none")      # freeze the layout: same frame geometry throughout
    # the axes, ticks and colour bar are drawn once (the slow part); per frame
    # only the polygons and the title are drawn over that background (blitting)
    coll.set_animated(True)
    head.set_animated(True)
    fig.canvas.draw()
    canvas = fig.canvas
    background = canvas.copy_from_bbox(fig.bbox)
    paths = []
    for k, f in enumerate(frames):
        colours = [cmap(norm(T)) if np.isfinite(T) else GREYS[int(body) % len(GREYS)]
                   for body, T in zip(f["body"], f["T_C"])]
        coll.set_verts(f["polygons"])
        coll.set_facecolor(colours)
        words = []
        for i, name in ((0, "1"), (2, "2")):
            sel = np.flatnonzero(f["body"] == i)
            if sel.size:
                mu, T = f["mu"][sel[0]], f["T_C"][sel[0]]
                if np.isfinite(mu):
                    words.append(f"mu{name} = {mu:.4f}")
                if np.isfinite(T):
                    words.append(f"T{name} = {T:.2f} C")
        head.set_text(f"{title}   t = {f['time']:.3f} s\n" + ",  ".join(words))
        canvas.restore_region(background)
        ax.draw_artist(coll)
        ax.draw_artist(head)
        p = out_dir / f"frame_{k:04d}.png"
        Image.fromarray(np.asarray(canvas.buffer_rgba())[..., :3]).save(p, compress_level=3)
        paths.append(p)
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


def render(run_dir, cap: int = MAX_FRAMES) -> tuple[list[Path], Path]:
    """Render DIR's device series; returns (PNG paths, GIF path)."""
    from .scene import SceneError

    d = Path(run_dir)
    if not d.is_dir():
        raise SceneError(f"{d}: no such results folder")
    pvd = d / "vtk" / "device.pvd"
    if not pvd.is_file():
        raise SceneError(f"{d}: no VTK series (vtk/device.pvd missing); run the scene with "
                         "--set output.vtk_every=N, N > 0")
    title = d.name
    try:
        title = json.loads((d / "summary.json").read_text())["scene"]
    except (OSError, ValueError, KeyError):
        pass
    frames = read_device_series(pvd, cap)
    # written beside, moved into place complete (a full disk or a kill leaves
    # the old render/ or none, never half a set of frames)
    from .output import ResultsFolder
    out = d / "render"
    folder = ResultsFolder(out)
    try:
        pngs = draw_frames(frames, folder.subdir("frames"), title)
        write_gif(pngs, folder.path("device.gif"))
        folder.commit()
    except BaseException:
        folder.discard()
        raise
    return [out / "frames" / p.name for p in pngs], out / "device.gif"


def cmd_render(args) -> int:
    from .claim import hold
    hold(args, args.dir, check=False)   # one writer of DIR at a time (coupling/claim.py)
    import shutil
    for stale in Path(args.dir).glob(".render.partial-*"):   # of a render that was killed: ours to tidy now
        shutil.rmtree(stale, ignore_errors=True)
    pngs, gif = render(args.dir)
    if not getattr(args, "quiet", False):
        print(f"{len(pngs)} frames in {pngs[0].parent}/, animation {gif}")
    sys.stdout.flush()
    return 0
