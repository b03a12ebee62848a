"""One actuator's run (`softcrawl epsa`): length and outer radius against pressure, the deformed
silhouette at every computed pressure, and with a sideways probe (--side-load) the path of the tip.

The silhouette panel has an equal aspect ratio and limits around the part (its widest deformed
state plus a margin), so that a 9 mm radius part is not drawn in a +-100 mm box; its legend sits
below the axes. The tip path is the sideways displacement of the top face's centroid against the
height of the top, one point per computed state, labelled with its pressure.
"""

from __future__ import annotations

import numpy as np

from softcrawl.studies.plots.labels import material_label
from softcrawl.studies.plots.style import pyplot, save
from softcrawl.units import mpa_to_kpa


def _silhouettes(ax, model, path_result) -> None:
    """Outer outline in the x-z plane at the reference state and every computed state, the axis
    z drawn horizontally (the part lies on its side) with equal scales."""
    outer = model.boundary_nodes("outer")
    X = model.nodes[:, outer]
    plane = np.abs(X[1]) <= 1e-6 * np.abs(X).max()
    states = [("reference (0 kPa)", 0.0, np.zeros_like(X))]
    for s in path_result.steps:
        p = mpa_to_kpa(s.pressure)
        label = f"P = {p:.3g} kPa" if p > 0 else "0 kPa, side load on"
        states.append((label, p, model.displacement(s.x)[:, outer]))
    cmap = pyplot().get_cmap("viridis")
    p_max = max(p for _, p, _ in states) or 1.0
    extent = []
    for k, (label, p, u) in enumerate(states):
        x = X + u
        colour = "0.55" if k == 0 else cmap(0.1 + 0.85 * p / p_max)
        for side in (1, -1):
            sel = plane & (np.sign(X[0]) == side)
            order = np.argsort(X[2][sel])
            ax.plot(
                x[2][sel][order],
                x[0][sel][order],
                "-",
                color=colour,
                lw=1.2,
                label=label if side == 1 else None,
            )
        extent.append(x[:, plane])
    pts = np.hstack(extent)
    ax.plot([], [])  # the x range follows from the equal aspect and the z range
    ax.set_xlim(min(0.0, pts[2].min()) - 2, pts[2].max() * 1.02)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("z, along the actuator (mm)")
    ax.set_ylabel("x (mm)")
    ax.set_title("outer silhouette in the x-z plane (equal scales; base at z = 0)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)


def _tip_path(ax, model, path_result) -> None:
    """Sideways displacement of the top face's centroid against its height, per computed state."""
    top = model.boundary_nodes("end_top")
    Z0 = model.nodes[2, top].mean()
    states = [(0.0, np.zeros(3))] + [
        (mpa_to_kpa(s.pressure), model.displacement(s.x)[:, top].mean(axis=1)) for s in path_result.steps
    ]
    lateral = [float(np.hypot(u[0], u[1])) for _, u in states]
    height = [Z0 + u[2] for _, u in states]
    ax.plot(lateral, height, "o-", color="C3")
    for (p, _), x, z in zip(states, lateral, height):
        ax.annotate(f"{p:.3g} kPa", (x, z), textcoords="offset points", xytext=(5, -3), fontsize=7)
    ax.set_xlabel("sideways tip displacement (mm)")
    ax.set_ylabel("height of the top z (mm)")
    ax.set_title("tip path under the side load", fontsize=10)
    ax.grid(alpha=0.3)


#: Smallest span of a value axis (mm): a radius that changes by micrometres (a wound chamber) is
#: drawn flat on a half-millimetre axis, not stretched until the solver's noise looks like a trend.
MIN_SPAN_MM = {"length_mm": 2.0, "outer_radius_mm": 0.5}


def _minimum_span(ax, values, span: float) -> None:
    """Widen the y axis about the data's middle to at least `span`."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if values.size and values.max() - values.min() < span:
        mid = 0.5 * (values.max() + values.min())
        ax.set_ylim(mid - span / 2, mid + span / 2)


def plot_epsa(path, curve, model=None, path_result=None, side_load_n: float | None = None):
    """Length and radius against P (volume-controlled branch dashed), the silhouettes, and with a
    side load the tip path (module docstring)."""
    plt = pyplot()
    shape = model is not None and path_result is not None and bool(path_result.steps)
    tip = shape and side_load_n is not None
    n = 3 if tip else 2
    fig = plt.figure(figsize=(5.2 * n, 8.2 if shape else 4.8))
    grid = fig.add_gridspec(2 if shape else 1, n, height_ratios=[1.4, 1] if shape else [1])
    axes = [fig.add_subplot(grid[0, k]) for k in range(n)]
    p = curve.column("pressure_kpa")
    ok = np.array([r.status != "failed" for r in curve.rows])
    vol = np.array([r.status == "volume-control" for r in curve.rows])
    for ax, col, label in (
        (axes[0], "length_mm", "length L (mm)"),
        (axes[1], "outer_radius_mm", "outer radius R at mid-length (mm)"),
    ):
        y = curve.column(col)
        ax.plot(p[ok & ~vol], y[ok & ~vol], "o-", label="computed states (pressure control)")
        if vol.any():
            k = np.argmax(vol[ok]) - 1
            ax.plot(p[ok][k:], y[ok][k:], "s--", label="volume control (past the limit point)")
        if curve.limit_pressure_kpa is not None:
            ax.axvline(
                curve.limit_pressure_kpa,
                color="r",
                ls=":",
                label=f"limit point {curve.limit_pressure_kpa:.1f} kPa",
            )
        ax.set_xlabel("chamber pressure P (kPa)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        _minimum_span(ax, y[ok], MIN_SPAN_MM[col])
    axes[0].legend(fontsize=8, loc="upper left")
    turns = curve.design.get("fiber_turns")
    winding = f", {curve.fibers} winding model" if curve.fibers and turns else ""
    design = f"r0 = {curve.design.get('chamber_radius')} mm, N = {turns}{winding}"
    probe = f", side load {side_load_n:g} N" if side_load_n else ""
    fig.suptitle(f"ePSA {design}; {material_label(curve.material)}{probe}", fontsize=11)
    axes[0].set_title("length", fontsize=10)
    axes[1].set_title("outer radius", fontsize=10)
    if tip:
        _tip_path(axes[2], model, path_result)
    if shape:
        _silhouettes(fig.add_subplot(grid[1, :]), model, path_result)
    return save(fig, path, outside=True)
