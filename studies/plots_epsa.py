"""Plots of one actuator's response: length and outer radius against pressure, deformed shape."""
from __future__ import annotations

import numpy as np


def plot_epsa(path, curve, model=None, path_result=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3 if model is not None else 2, figsize=(13, 4.2))
    p = curve.column("pressure_kpa")
    ok = np.array([r.status != "failed" for r in curve.rows])
    vol = np.array([r.status == "volume-control" for r in curve.rows])
    for ax, col, label in ((axes[0], "length_mm", "length L (mm)"), (axes[1], "outer_radius_mm", "outer radius R at L/2 (mm)")):
        y = curve.column(col)
        ax.plot(p[ok & ~vol], y[ok & ~vol], "o-", label="pressure control")
        if vol.any():
            ax.plot(p[ok][np.argmax(vol[ok]) - 1:], y[ok][np.argmax(vol[ok]) - 1:], "s--",
                    label="volume control (past limit)")
        if curve.limit_pressure_kpa is not None:
            ax.axvline(curve.limit_pressure_kpa, color="r", ls=":", label=f"limit {curve.limit_pressure_kpa:.1f} kPa")
        ax.set_xlabel("pressure P (kPa)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[0].set_title(f"{curve.material}, mu = {curve.mu_mpa:.4g} MPa")
    axes[1].set_title(f"r0 = {curve.design.get('chamber_radius')} mm, N = {curve.design.get('fiber_turns')}")
    if model is not None and path_result is not None and path_result.steps:
        ax = axes[2]
        outer = model.boundary_nodes("outer")
        X = model.nodes[:, outer]
        front = X[1] > -1e-9 * np.abs(X).max()
        ax.plot(X[0][front], X[2][front], ".", ms=2, color="0.6", label="reference")
        x = X + model.displacement(path_result.steps[-1].x)[:, outer]
        ax.plot(x[0][front], x[2][front], ".", ms=2, color="C3",
                label=f"P = {path_result.steps[-1].pressure * 1e3:.1f} kPa")
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("z (mm)")
        ax.set_title("outer surface, side view (y >= 0)")
        ax.legend(fontsize=8, markerscale=4)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
