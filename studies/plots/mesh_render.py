"""Off-screen PNG of a tagged mesh: boundary facets coloured by tag (by part for assemblies), fibers.

pyvista renders off screen (``pyvista.OFF_SCREEN``); if VTK cannot render on the machine, a
matplotlib (Agg) drawing of the boundary triangles is written instead. Returns the renderer used.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geometry.tagged_mesh import TaggedMesh
from studies.plots.style import pyplot, save


def _group(mesh: TaggedMesh, tag: str) -> str:
    """Legend group of a tag: the tag itself for a single part, the part name for an assembly."""
    if len(mesh.region_names) == 1:
        return tag
    if tag.startswith("interface:"):
        return tag.split(":", 1)[1].split("/")[0]
    return tag.split(":", 1)[0]


def _surface(mesh: TaggedMesh):
    import pyvista as pv

    tags = sorted({_group(mesh, t) for t in mesh.facets})
    order = sorted(mesh.facets)
    tris = np.vstack([mesh.facets[t] for t in order])
    ids = np.concatenate([np.full(len(mesh.facets[t]), tags.index(_group(mesh, t))) for t in order])
    faces = np.hstack([np.full((len(tris), 1), 3), tris]).ravel()
    surf = pv.PolyData(mesh.points, faces)
    surf.cell_data["tag"] = ids
    return surf, tags


def render_png(mesh: TaggedMesh, path: str | Path, window_size=(900, 700)) -> str:
    path = Path(path)
    try:
        import pyvista as pv

        pv.OFF_SCREEN = True
        surf, tags = _surface(mesh)
        pl = pv.Plotter(off_screen=True, window_size=list(window_size))
        pl.add_mesh(
            surf,
            scalars="tag",
            cmap="tab20",
            show_edges=True,
            edge_color="#555555",
            line_width=0.3,
            opacity=0.85,
            show_scalar_bar=False,
        )
        for f in mesh.fibers:
            pl.add_mesh(pv.lines_from_points(f), color="gold", line_width=2)
        if len(tags) <= 16:
            pl.add_legend(
                [[t, pv.plotting.colors.Color(c).hex_rgb] for t, c in zip(tags, _tab20(len(tags)))],
                bcolor="white",
                size=(0.25, 0.3),
            )
        pl.view_isometric()
        pl.screenshot(str(path))
        pl.close()
        return "pyvista"
    except Exception:  # noqa: BLE001 - any VTK rendering failure: fall back to matplotlib
        return _render_matplotlib(mesh, path)


def _tab20(n: int):
    import matplotlib

    cmap = matplotlib.colormaps["tab20"]
    return [cmap(i / max(n - 1, 1))[:3] for i in range(n)]


def _render_matplotlib(mesh: TaggedMesh, path: Path) -> str:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    plt = pyplot()
    fig = plt.figure(figsize=(8, 6))
    ax = fig.add_subplot(projection="3d")
    groups = sorted({_group(mesh, t) for t in mesh.facets})
    colors = dict(zip(groups, _tab20(len(groups))))
    for tag in sorted(mesh.facets):
        ax.add_collection3d(
            Poly3DCollection(
                mesh.points[mesh.facets[tag]],
                facecolor=colors[_group(mesh, tag)],
                edgecolor="k",
                linewidth=0.05,
                alpha=0.6,
            )
        )
    for f in mesh.fibers:
        ax.plot(f[:, 0], f[:, 1], f[:, 2], color="goldenrod", lw=0.8)
    lo, hi = mesh.points.min(axis=0), mesh.points.max(axis=0)
    c, r = (lo + hi) / 2, (hi - lo).max() / 2
    ax.set(
        xlim=(c[0] - r, c[0] + r),
        ylim=(c[1] - r, c[1] + r),
        zlim=(c[2] - r, c[2] + r),
        xlabel="x (mm)",
        ylabel="y (mm)",
        zlabel="z (mm)",
    )
    save(fig, path, tight=False)
    return "matplotlib"
