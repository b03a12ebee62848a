r"""A GIF of the crawl: the deformed feet inside the pipe, one frame per converged state.

Input: the VTU series that `studies.crawl.files` writes for `softcrawl crawl`
(vtu/crawl.pvd listing crawl_NNNN.vtu, NNNN the state's index in states.csv, each with the point
field displacement_mm; the rigid wall in vtu/pipe.vtu) and, when present, states.csv beside vtu/
for the frame titles (time, pressures, the two hub plates' axial displacements).

Each frame draws the current configuration x = X + u of both feet, cut at the plane y = 0 (the
half y >= 0 is kept, so the skirts' section against the wall shows), coloured by the axial
displacement u_z with one colour range over all frames (so a colour means the same displacement
in every frame), in front of the far half of the pipe (translucent). The camera is fixed for the
whole series (parallel projection, looking along +y, the pipe axis horizontal, forward to the
right) so that the feet's motion along the axis is seen as motion in the picture, not hidden by
a camera that follows them.

Frames are equally spaced in the GIF while the states are not equally spaced in time (the solver
refines hard segments): the title states each frame's time. Off screen through pyvista (EGL
without a display, `studies.plots.render3d.pyvista_offscreen`); the GIF is written with Pillow
(already a dependency of pyvista and matplotlib): pyvista's own GIF writer needs imageio, which is
not installed with pyvista >= 0.45, and a new dependency for one optional output is not worth it.
MP4 would need ffmpeg: not offered.
"""

from __future__ import annotations

import csv
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from softcrawl.studies.plots.render3d import pyvista_offscreen

FRAME_MS = 250  # per state; the last frame is held LAST_HOLD times as long
LAST_HOLD = 8
WINDOW = (960, 420)
PIPE_SHARE, TITLE_SHARE, BAR_SHARE = 0.7, 0.1, 0.2  # of the picture's height
FIELD = "displacement_mm"


def series_files(vtu_folder: Path) -> tuple[list[tuple[float, Path]], Path | None]:
    """(time, VTU path) of every state in crawl.pvd, in file order, and the pipe's VTU (or None)."""
    pvd = Path(vtu_folder) / "crawl.pvd"
    root = ET.parse(pvd).getroot()
    states, pipe = [], None
    for entry in root.iter("DataSet"):
        path = pvd.parent / entry.get("file", "")
        if entry.get("part") == "1":
            pipe = path if path.exists() else None
        else:
            states.append((float(entry.get("timestep", "0")), path))
    return states, pipe


def _titles(states_csv: Path | None) -> dict[str, str]:
    """Frame title per VTU file name, from states.csv (empty when there is none)."""
    if states_csv is None or not Path(states_csv).exists():
        return {}
    out = {}
    with open(states_csv, newline="") as fh:
        for row in csv.DictReader(fh):
            P = [float(row[f"p{i}_kpa"]) for i in (1, 2, 3)]
            when = (
                f"{row['stage']} (setup)"
                if int(row["cycle"]) == 0
                else f"cycle {row['cycle']}, {row['phase']}, t = {float(row['time_s']):.3f} s"
            )
            out[f"crawl_{int(row['index']):04d}.vtu"] = (
                f"{when}; P = {'/'.join(f'{p:.0f}' for p in P)} kPa; hub plates: rear "
                f"{float(row['rear_u_mm']):+.2f} mm, front {float(row['front_u_mm']):+.2f} mm"
            )
    return out


def _deformed_half(pv, path: Path):
    """The state's mesh in its current configuration, half y >= 0, with u_z as point data."""
    grid = pv.read(path)
    u = np.asarray(grid.point_data[FIELD])
    grid.points = np.asarray(grid.points) + u
    grid.point_data["u_z (mm)"] = u[:, 2]
    return grid.clip(normal=(0, -1, 0), origin=(0, 0, 0), crinkle=False)


def _axial_range(grids) -> tuple[float, float]:
    """One colour range of u_z over every frame's drawn half."""
    uz = [np.asarray(g.point_data["u_z (mm)"]) for g in grids]
    lo, hi = min(float(u.min()) for u in uz), max(float(u.max()) for u in uz)
    if hi - lo < 1e-9:  # a series without axial motion: a range the scalar bar can draw
        lo, hi = lo - 0.5, hi + 0.5
    return lo, hi


def _camera(pl, bounds) -> None:
    """Fixed side view of `bounds` (x0, x1, y0, y1, z0, z1): along +y onto the cut face, up = -x, so
    that +z (forward) points to the right of the picture. The pipe fills the middle PIPE_SHARE of
    the height, the title above it and the scalar bar below it (the picture's bottom BAR_SHARE)."""
    x0, x1, _, _, z0, z1 = bounds
    aspect = WINDOW[0] / WINDOW[1]
    height = max((x1 - x0) / PIPE_SHARE, 1.04 * (z1 - z0) / aspect)
    # picture-up is -x: moving the focal point to +x moves the pipe up, clear of the bar
    centre = (0.5 * (x0 + x1) + 0.5 * (BAR_SHARE - TITLE_SHARE) * height, 0.0, 0.5 * (z0 + z1))
    distance = 4.0 * max(x1 - x0, z1 - z0)
    pl.camera_position = [(centre[0], -distance, centre[2]), centre, (-1.0, 0.0, 0.0)]
    pl.camera.parallel_projection = True
    pl.camera.parallel_scale = 0.5 * height


def write_crawl_gif(vtu_folder, path, states_csv=None, frame_ms: int = FRAME_MS) -> Path:
    """The GIF of the series in `vtu_folder` (module docstring) at `path`; returns `path`."""
    from PIL import Image

    pv = pyvista_offscreen()
    states, pipe_path = series_files(Path(vtu_folder))
    if not states:
        raise ValueError(f"{vtu_folder}/crawl.pvd lists no state")
    titles = _titles(states_csv)
    halves = [_deformed_half(pv, vtu) for _, vtu in states]  # each VTU read once
    clim = _axial_range(halves)
    pl = pv.Plotter(off_screen=True, window_size=WINDOW)
    pl.set_background("white")
    bounds = np.array(halves[0].bounds, dtype=float)
    if pipe_path is not None:
        pipe = pv.read(pipe_path).clip(normal=(0, -1, 0), origin=(0, 0, 0), crinkle=False)
        pl.add_mesh(pipe, color="#9aa5b1", opacity=0.25, show_edges=False, name="pipe")
        bounds = np.array(pipe.bounds, dtype=float)
    _camera(pl, bounds)
    frames = []
    for k, ((time_s, vtu), half) in enumerate(zip(states, halves)):
        pl.add_mesh(
            half,
            scalars="u_z (mm)",
            cmap="coolwarm",
            clim=clim,
            name="feet",
            scalar_bar_args={
                "title": "axial displacement u_z (mm)",
                "color": "black",
                "vertical": False,
                "position_x": 0.3,
                "position_y": 0.02,
                "width": 0.4,
                "height": 0.1,
            },
        )
        title = titles.get(vtu.name, f"state {k}, t = {time_s:.3f} s")
        pl.add_text(title, position="upper_left", font_size=9, color="black", name="title")
        frames.append(Image.fromarray(np.asarray(pl.screenshot(return_img=True))))
    pl.close()
    path = Path(path)
    durations = [frame_ms] * (len(frames) - 1) + [frame_ms * LAST_HOLD]
    frames[0].save(path, save_all=True, append_images=frames[1:], duration=durations, loop=0)
    return path
