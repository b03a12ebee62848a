"""One actuator's run (`softcrawl epsa`): length and outer radius against pressure, deformed shape."""

from __future__ import annotations

import numpy as np

from studies.plots.style import pyplot, save


def plot_epsa(path, curve, model=None, path_result=None):
    """Length and radius against P (volume-controlled branch dashed), and the outer silhouette."""
    plt = pyplot()
    shape = model is not None and path_result is not None and bool(path_result.steps)
    fig, axes = plt.subplots(
        1,
        3 if shape else 2,
        figsize=(13, 4.6),
        gridspec_kw={"width_ratios": [1, 1, 0.6] if shape else [1, 1]},
    )
    p = curve.column("pressure_kpa")
    ok = np.array([r.status != "failed" for r in curve.rows])
    vol = np.array([r.status == "volume-control" for r in curve.rows])
    for ax, col, label in (
        (axes[0], "length_mm", "length L (mm)"),
        (axes[1], "outer_radius_mm", "outer radius R at L/2 (mm)"),
    ):
        y = curve.column(col)
        ax.plot(p[ok & ~vol], y[ok & ~vol], "o-", label="pressure control")
        if vol.any():
            ax.plot(
                p[ok][np.argmax(vol[ok]) - 1 :],
                y[ok][np.argmax(vol[ok]) - 1 :],
                "s--",
                label="volume control (past limit)",
            )
        if curve.limit_pressure_kpa is not None:
            ax.axvline(
                curve.limit_pressure_kpa, color="r", ls=":", label=f"limit {curve.limit_pressure_kpa:.1f} kPa"
            )
        ax.set_xlabel("pressure P (kPa)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[0].set_title(f"{curve.material}, mu = {curve.mu_mpa:.4g} MPa")
    winding = f" ({curve.fibers})" if curve.fibers and curve.design.get("fiber_turns") else ""
    axes[1].set_title(
        f"r0 = {curve.design.get('chamber_radius')} mm, N = {curve.design.get('fiber_turns')}{winding}"
    )
    if shape:
        ax = axes[2]
        outer = model.boundary_nodes("outer")
        X = model.nodes[:, outer]
        plane = np.abs(X[1]) <= 1e-6 * np.abs(X).max()  # silhouette in the x-z plane
        last = path_result.steps[-1]
        x = X + model.displacement(last.x)[:, outer]
        for pos, colour, label in ((X, "0.6", "reference"), (x, "C3", f"P = {last.pressure * 1e3:.1f} kPa")):
            for side in (1, -1):
                sel = plane & (np.sign(X[0]) == side)
                order = np.argsort(X[2][sel])
                ax.plot(
                    pos[0][sel][order],
                    pos[2][sel][order],
                    "-",
                    color=colour,
                    label=label if side == 1 else None,
                )
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("z (mm)")
        ax.set_title("outer silhouette (x-z plane)")
        ax.legend(fontsize=8, loc="lower center")
    return save(fig, path)
