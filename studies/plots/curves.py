"""Study curves (paper Figs. 8-9): ePSA length and outer radius against pressure per design.

Inputs are the rows of a sweep table (`studies.sweeps.tables.collect`) or the same rows read back
from CSV (strings), so a figure can be redrawn from the CSV alone. Pressures in kPa, lengths in mm.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from studies.plots.style import pyplot, save, short
from studies.review.rules import design_curves


def plot_curves(
    rows: Sequence[Mapping[str, Any]],
    param: str,
    path: str | Path,
    *,
    title: str = "",
    label: str | None = None,
    unit: str = "",
) -> Path:
    """Length and outer radius against pressure, one line per value of ``param``.

    The undeformed state (0 kPa) starts every line; lines follow the solution path, so states past
    a limit point (volume control, falling pressure) bend back. A limit (burst) pressure is marked
    with a star at the limit state and its value; a diverged evaluation ends in a cross and is
    dashed; a missing or failed point
    without curve data is listed in the legend as such."""
    plt = pyplot()
    curves = design_curves(rows, param)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    label = label or param
    for i, (value, c) in enumerate(sorted(curves.items())):
        color = f"C{i % 10}"
        name = f"{label} = {value:g}{unit}"
        if not c.path:
            axes[0].plot(
                [],
                [],
                color=color,
                label=f"{name}: {c.trial_status}" + (f" ({short(c.reason)})" if c.reason else ""),
            )
            continue
        p = [0.0] + [q for q, *_ in c.path]
        style = "--" if c.trial_status == "failed" else "-"
        suffix = ""
        if c.limit_pressure is not None:
            suffix = f", limit {c.limit_pressure:.3g} kPa"
        elif c.trial_status == "failed":
            suffix = ", diverged"
        lengths, radii = [x for _, x, _, _ in c.path], [y for _, _, y, _ in c.path]
        for ax, ys, y0 in ((axes[0], lengths, c.length0), (axes[1], radii, c.radius0)):
            y = [y0] + ys
            ax.plot(
                p, y, style, marker="o", ms=3, color=color, label=name + suffix if ax is axes[0] else None
            )
            if c.limit_pressure is not None:
                k = max(range(len(p)), key=lambda j: p[j])  # the state at the limit pressure
                ax.plot([p[k]], [y[k]], marker="*", ms=14, color=color, mec="k")
                ax.annotate(
                    f"{c.limit_pressure:.3g} kPa",
                    (p[k], y[k]),
                    textcoords="offset points",
                    xytext=(4, 4),
                    fontsize=7,
                    color=color,
                )
            elif c.trial_status == "failed":
                ax.plot([p[-1]], [y[-1]], marker="x", ms=10, mew=2, color=color)
    axes[0].set_ylabel("ePSA length (mm)")
    axes[1].set_ylabel("ePSA outer radius (mm)")
    for ax in axes:
        ax.set_xlabel("pressure (kPa)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=10)
    return save(fig, path)
