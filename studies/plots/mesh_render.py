"""Off-screen PNG of a tagged mesh: boundary facets coloured by tag (by part for assemblies), fibers.

pyvista renders a cut-away off screen (`studies.plots.render3d`); if VTK cannot render on the
machine, a matplotlib (Agg) drawing of the boundary triangles is written instead, with the same
colours. Returns the renderer used.
"""

from __future__ import annotations

from pathlib import Path

from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.studies.plots.render3d import colours, render_tagged
from softcrawl.studies.plots.render3d import facet_group as _group
from softcrawl.studies.plots.style import pyplot, save


def render_png(mesh: TaggedMesh, path: str | Path, title: str = "") -> str:
    """Cut-away render (`studies.plots.render3d.render_tagged`); matplotlib where VTK cannot render."""
    path = Path(path)
    try:
        render_tagged(mesh, path, title=title)
        return "pyvista"
    except Exception:  # noqa: BLE001 - any VTK rendering failure: fall back to matplotlib
        return _render_matplotlib(mesh, path)


def _render_matplotlib(mesh: TaggedMesh, path: Path) -> str:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    plt = pyplot()
    fig = plt.figure(figsize=(8, 6))
    ax = fig.add_subplot(projection="3d")
    colors = colours({_group(mesh, t) for t in mesh.facets})
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
