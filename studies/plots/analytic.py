"""Figures of the paper's analytic models (package `robot`): the workspace cloud and a gait plan."""

from __future__ import annotations

import numpy as np

from softcrawl.analytic import kinematics as kin
from softcrawl.studies.plots.style import pyplot, save


def plot_workspace(ws, path) -> None:
    """3D tip cloud and its x-y, x-z, y-z projections (cf. the paper's Fig. 11(d)), one colour bar
    for all four (the bending angle). Constrained layout keeps the labels apart."""
    plt = pyplot()
    fig = plt.figure(figsize=(12, 10), layout="constrained")
    c = np.degrees(ws.theta)
    ax = fig.add_subplot(2, 2, 1, projection="3d")
    sc = ax.scatter(ws.tip_mm[:, 0], ws.tip_mm[:, 1], ws.tip_mm[:, 2], c=c, s=3, cmap="viridis")
    (
        ax.set_xlabel("x (mm)", labelpad=8),
        ax.set_ylabel("y (mm)", labelpad=8),
        ax.set_zlabel("z (mm)", labelpad=8),
    )
    ax.set_box_aspect(None, zoom=0.78)  # room for the z label inside the panel
    ax.set_title("tip positions, each ePSA pressure 0-100 kPa")
    for k, (i, j, name) in enumerate([(0, 1, "x-y"), (0, 2, "x-z"), (1, 2, "y-z")], start=2):
        a = fig.add_subplot(2, 2, k)
        a.scatter(ws.tip_mm[:, i], ws.tip_mm[:, j], c=c, s=3, cmap="viridis")
        a.set_xlabel("xyz"[i] + " (mm)"), a.set_ylabel("xyz"[j] + " (mm)")
        a.set_aspect("equal", adjustable="datalim"), a.set_title(name + " projection"), a.grid(alpha=0.3)
    fig.colorbar(sc, ax=fig.axes, shrink=0.6, label="bending angle theta (deg)")
    fig.suptitle("Workspace of the robot's front foot (constant-curvature model, paper Fig. 11(d))")
    save(fig, path, tight=False)


def _arc_world(pos, rot, theta, phi, length, n=40):
    f = np.linspace(0.0, 1.0, n)
    local = kin.arc_point(theta * f, phi, length * f)
    return np.asarray(pos) + local @ np.asarray(rot).T


def plot_plan(plan, path) -> None:
    """Bend-plane (x-z) view of the pipe, the inflated body of every cycle, the feet, and the gait."""
    plt = pyplot()
    pipe = plan.pipe
    fig, (ax, ag) = plt.subplots(1, 2, figsize=(13, 6), gridspec_kw=dict(width_ratios=[1.2, 1]))
    s_max = max([c.progress for c in plan.cycles] + [0.0]) + 200.0
    s = np.linspace(-20.0, min(s_max, pipe.length + 150.0), 600)
    cl = pipe.point(s)
    tg = pipe.tangent(s)
    nrm = np.stack([tg[:, 2], np.zeros_like(s), -tg[:, 0]], -1)  # in-plane normal
    r = pipe.diameter / 2.0
    for sign in (1, -1):
        w = cl + sign * r * nrm
        ax.plot(w[:, 0], w[:, 2], "k-", lw=1.5)
        b = cl + sign * (r - plan.body_radius) * nrm
        ax.plot(b[:, 0], b[:, 2], "k:", lw=0.8)
    ax.plot(cl[:, 0], cl[:, 2], color="0.6", lw=0.8, ls="--")
    cmap = plt.get_cmap("viridis")
    n = max(len(plan.cycles), 1)
    rot = np.asarray(plan.start_rotation)
    for c in plan.cycles:
        col = cmap((c.index - 1) / max(n - 1, 1))
        pts = _arc_world(c.rear_before, rot, c.theta, c.phi, c.length_inflated)
        ax.plot(pts[:, 0], pts[:, 2], color=col, lw=2, alpha=0.8)
        ax.plot(*np.array(c.rear_before)[[0, 2]], "s", color=col, ms=5)
        ax.plot(*np.array(c.front)[[0, 2]], "o", color=col, ms=5)
        step = c.length_inflated - c.length_deflated
        rot = rot @ kin.arc_rotation(c.kappa * step, c.phi)
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    ticks = np.unique(np.linspace(1, max(n, 2), min(max(n, 2), 8)).round().astype(int))
    fig.colorbar(
        ScalarMappable(Normalize(1, max(n, 2)), cmap),
        ax=ax,
        shrink=0.7,
        ticks=ticks,
        label="cycle (colour of the body)",
    )
    ax.set_aspect("equal"), ax.set_xlabel("x (mm)"), ax.set_ylabel("z (mm)")
    status = "passes" if plan.success else "FAILS"
    ax.set_title(
        f"{pipe.kind} D = {pipe.diameter:g} mm"
        + (f", R = {pipe.bend_radius:g} mm" if pipe.kind == "elbow" else "")
        + f": {status} in {len(plan.cycles)} cycles\n(squares: rear foot, circles: front "
        "foot; dotted: body-centreline limit)",
        fontsize=9,
    )
    gait = plan.gait()
    if gait:
        P = np.array([g[1:] for g in gait])
        x = np.arange(len(gait) + 1)
        for i, ls in zip(range(3), ("-", "--", ":")):
            ag.step(x, np.append(P[:, i], P[-1, i]), where="post", ls=ls, lw=2 - 0.4 * i, label=f"P{i + 1}")
        ag.set_xlabel("phase (inflate, deflate, ...)"), ag.set_ylabel("ePSA pressure (kPa)")
        ag.set_ylim(-5, 105), ag.legend(), ag.grid(alpha=0.3), ag.set_title("gait sequence")
    save(fig, path)
