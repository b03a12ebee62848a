"""Figures of the robot-level model: the ring and foot-radius studies, the workspace comparison
and a 3D render of a deformed robot (pyvista off screen; matplotlib when VTK cannot render)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from softcrawl.geometry.swept import boundary_faces
from softcrawl.studies.plots.style import number, pyplot, save


def _series(rows, key, value):
    pts = [(number(r.get(key)), number(r.get(value))) for r in rows]
    pts = sorted((a, b) for a, b in pts if a is not None and b is not None and math.isfinite(b))
    return [a for a, _ in pts], [b for _, b in pts]


def plot_robot_study(name: str, summary, curves, folder) -> Path:
    """rings: theta, extension, splay and arc-fit RMS against n; foot-radius: theta against d,
    with the asymmetric-load bending curves of every design."""
    plt = pyplot()
    key = "n_rings" if name == "rings" else "d"
    panels = [("theta_asym_deg", "theta at P = (100, 40, 60) kPa (deg)"),
              ("extension_equal_mm", "extension at P = 100 kPa, equal (mm)"),
              ("splay_max_mm", "max splay (mm)"), ("arc_rms_max_mm", "max arc-fit RMS (mm)")]  # fmt: skip
    if name != "rings":
        panels = [panels[0], ("d_eff_asym_mm", "effective d of eq. 7 (mm)"), panels[2], panels[3]]
    fig, axes = plt.subplots(1, 5, figsize=(20, 4))
    for ax, (col, label) in zip(axes, panels):
        x, y = _series(summary, key, col)
        ax.plot(x, y, "o-")
        ax.set_xlabel(key)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    ax = axes[-1]
    for value in sorted({r.get(key) for r in curves if r.get(key) is not None}, key=float):
        rows = [r for r in curves if r.get(key) == value and r.get("case") == "asymmetric"]
        rows = [r for r in rows if number(r.get("P2_kpa")) == 40.0 and number(r.get("P3_kpa")) == 60.0]
        x, y = _series(rows, "P1_kpa", "theta_deg")
        ax.plot(x, y, "o-", label=f"{key} = {value}")
    ax.set_xlabel("P1 (kPa), P2 = 40, P3 = 60 kPa")
    ax.set_ylabel("theta (deg)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    material = next((r.get("material") for r in curves if r.get("material")), "")
    fig.suptitle(f"robot study {name} ({material})")
    return save(fig, Path(folder) / f"{name}.png", rect=(0, 0, 1, 0.95))


def plot_workspace(fe, cc_fe, cc_eq3, path, title: str) -> Path:
    """Three tip clouds (n, 3) side by side: FE, CC fed with FE single-actuator lengths, CC fed
    with eq. 3's lengths, on common axes and one colour bar (the tip height)."""
    plt = pyplot()
    fig = plt.figure(figsize=(15, 5))
    clouds = [(fe, "FE robot"), (cc_fe, "CC, FE single-ePSA lengths"), (cc_eq3, "CC, eq. 3 lengths")]
    allp = np.vstack([c for c, _ in clouds])
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    axes = []
    for k, (cloud, label) in enumerate(clouds, start=1):
        ax = fig.add_subplot(1, 3, k, projection="3d")
        axes.append(ax)
        points = ax.scatter(
            cloud[:, 0], cloud[:, 1], cloud[:, 2], c=cloud[:, 2], s=8, cmap="viridis", vmin=lo[2], vmax=hi[2]
        )
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_zlim(lo[2], hi[2])
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
        ax.set_zlabel("z (mm)")
        ax.set_title(label)
    # one colour scale for the three clouds, so that FE and CC compare by eye
    fig.colorbar(points, ax=axes, shrink=0.7, pad=0.07, label="tip height z (mm), one scale for all three")
    fig.suptitle(title)
    return save(fig, path, tight=False)


def render_robot(robot, x, path, title: str = "") -> Path:
    """Deformed boundary of the robot coloured by part (off-screen pyvista, or matplotlib)."""
    mesh = robot.mesh
    u = robot.model.displacement(x)[:, : mesh.n_nodes].T
    pts = mesh.points + u
    faces = boundary_faces(mesh.tets)
    part = np.zeros(len(mesh.tets), int)
    names = sorted(set(mesh.region_names.values()))
    for rid, name in mesh.region_names.items():
        part[mesh.region == rid] = names.index(name)
    face_part = _face_owner(mesh.tets, faces, part)
    path = Path(path)
    try:
        import pyvista as pv

        pv.OFF_SCREEN = True
        surf = pv.PolyData(pts, np.hstack([np.full((len(faces), 1), 3), faces]).ravel())
        surf.cell_data["part"] = face_part
        pl = pv.Plotter(off_screen=True, window_size=[900, 900])
        pl.add_mesh(surf, scalars="part", cmap="tab20", show_edges=True, edge_color="#444444", line_width=0.2,
                    show_scalar_bar=False)  # fmt: skip
        pl.add_text(title, font_size=9)
        pl.view_isometric()
        path.parent.mkdir(parents=True, exist_ok=True)
        pl.screenshot(str(path))
        pl.close()
    except Exception:  # noqa: BLE001 - no OpenGL context here: draw with matplotlib instead
        plt = pyplot()
        fig = plt.figure(figsize=(7, 7))
        ax = fig.add_subplot(projection="3d")
        ax.plot_trisurf(pts[:, 0], pts[:, 1], pts[:, 2], triangles=faces, cmap="viridis", linewidth=0.1)
        ax.set_title(title)
        ax.set_box_aspect(np.ptp(pts, axis=0))
        save(fig, path, tight=False)
    return path


def _face_owner(tets, faces, part):
    """The part of the tetrahedron each boundary face belongs to."""
    local = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])
    all_faces = np.sort(tets[:, local].reshape(-1, 3), axis=1)
    owner = np.repeat(part, 4)
    keys = all_faces @ np.array([1, 1 << 20, 1 << 40], dtype=np.int64)
    want = np.sort(faces, axis=1) @ np.array([1, 1 << 20, 1 << 40], dtype=np.int64)
    order = np.argsort(keys)
    pos = np.searchsorted(keys, want, sorter=order)
    return owner[order[pos]]
