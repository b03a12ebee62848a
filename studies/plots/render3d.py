"""Off-screen 3D renders with pyvista: cut-away views of parts and of solved states.

Off screen without X. On Linux without a display VTK's default window is the X one, which prints
"bad X server connection" and may fail; `pyvista_offscreen()` selects VTK's EGL window
(`VTK_DEFAULT_OPENGL_WINDOW`, read by VTK >= 9.4 when a window is made) before pyvista makes one.
Where EGL is missing too, the callers fall back to a matplotlib drawing.

What a render shows:

- a cut-away: the half y < 0 is removed (the plane y = 0 holds the axis of an ePSA, so the cut
  shows the chamber and the wall); the cut face is drawn in the colour of its region;
- each boundary tag (or, for an assembly, each part) in its own colour from one categorical
  palette, and the legend built from the same colours (one actor per tag, so they cannot differ);
- the fibers as lines (deformed with the body in a solved state);
- a solved state coloured by a named field (von Mises stress by default) with a labelled scalar bar;
- a ruler along the part's length (a scale bar in mm) and the axes triad;
- a camera that fits the bounds of everything drawn, legend and bar outside the part's box.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from softcrawl.fem.vtu import write_state
from softcrawl.studies.plots.style import pyplot, save

#: Categorical colours (matplotlib's tab10), assigned in sorted tag order.
PALETTE = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
)
FIBER_COLOUR = "#b8860b"  # dark goldenrod: visible on light and dark faces
WINDOW = (1200, 900)


def facet_group(mesh, tag: str) -> str:
    """Legend group of a tag: the tag itself for a single part, the part name for an assembly."""
    if len(mesh.region_names) == 1:
        return tag
    if tag.startswith("interface:"):
        return tag.split(":", 1)[1].split("/")[0]
    return tag.split(":", 1)[0]


def facet_groups(mesh) -> dict[str, np.ndarray]:
    """Boundary triangles per legend group (`facet_group`): the tags of a part, the parts of an assembly."""
    out: dict[str, list[np.ndarray]] = {}
    for tag in sorted(mesh.facets):
        out.setdefault(facet_group(mesh, tag), []).append(mesh.facets[tag])
    return {name: np.vstack(tris) for name, tris in out.items()}


def pyvista_offscreen():
    """pyvista set up for off-screen rendering without X (module docstring)."""
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv

    pv.OFF_SCREEN = True
    return pv


def colours(names) -> dict[str, str]:
    """One distinct colour per name, in sorted order (tab10, or tab20 beyond ten names)."""
    names = sorted(names)
    if len(names) <= len(PALETTE):
        return dict(zip(names, PALETTE))
    import matplotlib
    from matplotlib.colors import to_hex

    cmap = matplotlib.colormaps["tab20"]
    return {name: to_hex(cmap(i % 20)) for i, name in enumerate(names)}


def _cut(pv, dataset, keep_y_positive: bool = True):
    """The half y >= 0 of a dataset (pyvista keeps the side the normal points away from)."""
    return dataset.clip(normal=(0, -1, 0) if keep_y_positive else (0, 1, 0), origin=(0, 0, 0), crinkle=False)


def _half_line(pv, points: np.ndarray, reference: np.ndarray):
    """The segments of a polyline whose reference ends both lie in y >= 0 (no VTK clip of lines)."""
    keep = reference[:, 1] >= 0
    segments = np.nonzero(keep[:-1] & keep[1:])[0]
    if segments.size == 0:
        return None
    cells = np.column_stack([np.full(segments.size, 2), segments, segments + 1]).ravel()
    return pv.PolyData(points, lines=cells)


#: The camera of a part's render (direction from the focal point, view up): from the front-right,
#: above, the z axis up. A solved state uses `LYING`: the actuator lies along the image (z to the
#: right, -x up), seen in a three-quarter view from the cut side (-y), above and from its top end,
#: so that the cut face shows the chamber and the wall and the render is wide enough to read.
STANDING = ((2.0, -1.6, 1.0), (0.0, 0.0, 1.0))
LYING = ((-0.4, -1.0, 0.25), (-1.0, 0.0, 0.0))
#: The window of a lying render (pixels): wide, like the actuator.
WIDE_WINDOW = (2200, 800)


def _finish(pl, bounds, view=STANDING) -> np.ndarray:
    """Ruler along z, axes triad, a camera (`view`) that fits `bounds`; the screenshot (rows,
    cols, 3) cropped to what was drawn."""
    x0, x1, y0, y1, z0, z1 = bounds
    pad = 0.08 * max(x1 - x0, z1 - z0)
    pl.add_ruler(
        pointa=(x1 + pad, 0.0, z0),
        pointb=(x1 + pad, 0.0, z1),
        title="z (mm)",
        label_format="%.0f",
        font_size_factor=0.7,
        label_size_factor=0.7,
    )
    if view == STANDING:
        pl.add_axes(line_width=3)  # a lying render is cropped to the part: the ruler names z
    pl.camera_position = [view[0], (0.0, 0.0, 0.0), view[1]]
    pl.reset_camera(bounds=(x0 - pad, x1 + 2 * pad, y0 - pad, y1 + pad, z0 - pad, z1 + pad))
    image = np.asarray(pl.screenshot(return_img=True))[..., :3]
    pl.close()
    drawn = np.nonzero((image < 250).any(axis=2))
    if drawn[0].size:
        r0, r1 = max(drawn[0].min() - 10, 0), drawn[0].max() + 10
        c0, c1 = max(drawn[1].min() - 10, 0), drawn[1].max() + 10
        image = image[r0:r1, c0:c1]
    return image


def _compose(path: Path, image, title: str, entries=(), colourbar=None, height: float = 6.5) -> Path:
    """The render with a matplotlib title, legend swatches in the render's own colours, and a
    colour bar (label, cmap, (low, high)) beside it; `height` in inches (a wide render is made
    lower, so that its labels stay legible when the page scales it to its width)."""
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
    from matplotlib.patches import Patch

    plt = pyplot()
    h, w = image.shape[:2]
    fig = plt.figure(figsize=(4.0 + height * w / h, height))
    ax = fig.add_axes((0.0, 0.0, height * w / h / (4.0 + height * w / h), 0.88))
    ax.imshow(image)
    ax.set_axis_off()
    if title:
        fig.suptitle(title, fontsize=11)
    if entries:
        handles = [Patch(facecolor=c, edgecolor="k", label=name) for name, c in entries]
        fig.legend(handles=handles, loc="upper right", fontsize=9, frameon=False, bbox_to_anchor=(0.99, 0.9))
    if colourbar is not None:
        label, cmap, (low, high) = colourbar
        left = 1.0 - 2.6 / (4.0 + height * w / h)
        cax = fig.add_axes((left, 0.12, 0.25 / (4.0 + height * w / h), 0.55))
        fig.colorbar(ScalarMappable(Normalize(low, high), cmap), cax=cax, label=label)
    return save(fig, path, tight=False)


def render_tagged(mesh, path, title: str = "") -> Path:
    """Cut-away of a `geometry.tagged_mesh.TaggedMesh`: tags (parts) in their colours, the cut
    face by region, the fibers, a ruler and a legend in the same colours."""
    pv = pyvista_offscreen()
    path = Path(path)
    groups = facet_groups(mesh)
    palette = colours(groups)
    grid = pv.UnstructuredGrid({pv.CellType.TETRA: mesh.tets}, mesh.points)
    grid.cell_data["region"] = mesh.region
    pl = pv.Plotter(off_screen=True, window_size=list(WINDOW))
    pl.set_background("white")
    cut_away = len(mesh.region_names) == 1  # a part; an assembly is shown whole
    keep = (lambda d: _cut(pv, d)) if cut_away else (lambda d: d)
    if cut_away:
        cut = _cut(pv, grid).extract_surface(algorithm="dataset_surface")
        pl.add_mesh(cut, color="#d9d9d9", show_edges=True, edge_color="#9a9a9a", line_width=0.2, ambient=0.4)
    for name, tris in groups.items():
        faces = np.hstack([np.full((len(tris), 1), 3), tris]).ravel()
        surf = keep(pv.PolyData(mesh.points, faces))
        if surf.n_cells:
            pl.add_mesh(surf, color=palette[name], show_edges=False, ambient=0.3)
    for fiber in mesh.fibers:
        fiber = np.asarray(fiber, dtype=float)
        line = _half_line(pv, fiber, fiber) if cut_away else pv.lines_from_points(fiber)
        if line is not None:
            pl.add_mesh(line, color=FIBER_COLOUR, line_width=3)
    entries = [[name, palette[name]] for name in sorted(groups)]
    if mesh.fibers:
        entries.append(["Kevlar fibers", FIBER_COLOUR])
    if cut_away:
        entries.append(["cut face (plane y = 0)", "#d9d9d9"])
    return _compose(path, _finish(pl, grid.bounds), title, entries)


def render_state(
    model,
    x,
    path,
    *,
    pressure_mpa: float,
    factor: float = 0.0,
    title: str = "",
    field: str = "von_mises_MPa",
    field_label: str = "von Mises stress (MPa)",
    clim=None,
    helices=(),
) -> Path:
    """Cut-away of a solved state of a `fem.model.SolidModel` on its deformed shape, coloured by
    the cell field `field` of `fem.vtu.write_state`, with the deformed fiber curves `helices`
    (reference polylines (n, 3)) and the undeformed outline for comparison."""
    pv = pyvista_offscreen()
    path = Path(path)
    with tempfile.TemporaryDirectory() as tmp:
        grid = pv.read(
            write_state(Path(tmp) / "state.vtu", model, x, pressure_mpa=pressure_mpa, factor=factor)
        )
    linear = grid.linear_copy()
    deformed = linear.warp_by_vector("displacement_mm")
    pl = pv.Plotter(off_screen=True, window_size=list(WIDE_WINDOW))
    pl.set_background("white")
    # the elements whose reference centroid lies in y >= 0 (VTK's clip of this grid crashes
    # with VTK 9.7, and a whole-element cut shows the elements as they are)
    kept = np.nonzero(np.asarray(linear.cell_centers().points)[:, 1] >= 0)[0]
    half = deformed.extract_cells(kept)
    pl.add_mesh(
        half,
        scalars=field,
        cmap="viridis",
        clim=clim,
        show_edges=False,
        show_scalar_bar=False,
    )
    outline = (
        linear.extract_cells(kept).extract_surface(algorithm="dataset_surface").extract_feature_edges(45)
    )
    pl.add_mesh(outline, color="#888888", line_width=1)
    for helix in helices:
        moved = pv.PolyData(np.asarray(helix, dtype=float)).sample(linear)
        kept = _half_line(
            pv, np.asarray(moved.points) + np.asarray(moved["displacement_mm"]), np.asarray(helix)
        )
        if kept is not None:
            pl.add_mesh(kept, color=FIBER_COLOUR, line_width=3)
    bounds = np.array(deformed.bounds).reshape(3, 2)
    bounds = np.column_stack(
        [np.minimum(bounds[:, 0], linear.bounds[::2]), np.maximum(bounds[:, 1], linear.bounds[1::2])]
    )
    low, high = clim if clim is not None else (float(half[field].min()), float(half[field].max()))
    entries = [("undeformed outline (0 kPa)", "#888888")] + (
        [("Kevlar fibers", FIBER_COLOUR)] if helices else []
    )
    image = _finish(pl, tuple(bounds.ravel()), LYING)
    return _compose(path, image, title, entries, (field_label, "viridis", (low, high)), height=4.0)
