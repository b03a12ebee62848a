"""Study curves (paper Figs. 8-9): ePSA length and outer radius against pressure per design.

Inputs are the rows of a sweep table (`studies.sweeps.tables.collect`) or the same rows read back
from CSV (strings), so a figure can be redrawn from the CSV alone. Pressures in kPa, lengths in mm.

What is drawn, and how (the figure's second legend says the same):

- every computed equilibrium is a marker; the undeformed state (0 kPa) starts every design;
- consecutive pressure-controlled states are joined by a thin solid line (the path between them
  was computed in sub-steps, but only the requested pressures are recorded);
- from the last pressure-controlled state to the first state found by volume control the path
  was not recorded: that stretch is dotted, so a straight line does not pose as a linear response;
- the volume-controlled branch past a limit point (the pressure falls while the chamber grows)
  is dashed, with square markers;
- a limit point is a star at its own pressure (the peak of a parabola through the volume-control
  samples, `fem.path`), at the length or radius of the nearest computed state;
- a diverged design ends in a cross.

When some designs hold their radius and others balloon (the fiber-turns study), a third panel
shows the radius change R - R0 of the designs that hold it on their own axis.

The Table 1 rule's threshold (`target_kpa`, the 100 kPa the design must withstand) is a vertical
line on every panel, and the paper's chosen value (`chosen`) is drawn with a thick line and named
"Table 1" in the legend.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from softcrawl.studies.epsa.rules import design_curves
from softcrawl.studies.plots.style import pyplot, save, short

#: A design "holds its radius" when its largest |R - R0| is below this fraction of the largest
#: change of all designs; such designs get their own radius panel when the others are 5x larger.
SMALL_CHANGE = 0.2


def _branches(c):
    """(pressure-controlled states incl. the reference, volume-controlled states) as arrays of
    (p, length, radius)."""
    controlled = [(0.0, c.length0, c.radius0)] + [(p, x, y) for p, x, y, st in c.path if st == "converged"]
    volume = [(p, x, y) for p, x, y, st in c.path if st == "volume-control"]
    return np.array(controlled, dtype=float), np.array(volume, dtype=float).reshape(-1, 3)


def _limit_state(c, controlled, volume):
    """(p, length, radius) of the star: the limit pressure, the shape of the nearest state."""
    states = np.vstack([controlled, volume])
    k = int(np.argmin(np.abs(states[:, 0] - c.limit_pressure)))
    return c.limit_pressure, states[k, 1], states[k, 2]


def _draw_design(axes, c, color, name, zoom_axis, lw=1.2):
    controlled, volume = _branches(c)
    failed = c.trial_status == "failed"
    panels = [(axes[0], 1, 0.0), (axes[1], 2, 0.0)] + ([(zoom_axis, 2, c.radius0)] if zoom_axis else [])
    for ax, col, offset in panels:
        label = name if ax is axes[0] else None
        ax.plot(controlled[:, 0], controlled[:, col] - offset, "-", lw=lw, marker="o", ms=3.5, color=color)
        ax.plot([], [], "-", lw=lw, marker="o", ms=3.5, color=color, label=label)
        if len(volume):
            gap = np.vstack([controlled[-1], volume[0]])
            ax.plot(gap[:, 0], gap[:, col] - offset, ":", lw=1.2, color=color)
            ax.plot(volume[:, 0], volume[:, col] - offset, "--", lw=1.2, marker="s", ms=3.5, color=color)
        if c.limit_pressure is not None:
            p, *shape = _limit_state(c, controlled, volume)
            y = shape[col - 1] - offset
            ax.plot([p], [y], marker="*", ms=15, color=color, mec="k", zorder=5)
            ax.annotate(
                f"{p:.3g} kPa",
                (p, y),
                textcoords="offset points",
                xytext=(6, -10),
                fontsize=8,
                color=color,
            )
        elif failed:
            last = volume[-1] if len(volume) else controlled[-1]
            ax.plot([last[0]], [last[col] - offset], marker="x", ms=10, mew=2, color=color)


def _style_legend(ax) -> None:
    """What the line styles and markers mean (module docstring)."""
    handles = [
        ax.plot([], [], "-", marker="o", ms=3.5, color="0.3", label="computed states (pressure control)")[0],
        ax.plot([], [], ":", color="0.3", label="not recorded: up to the first volume-control state")[0],
        ax.plot(
            [], [], "--", marker="s", ms=3.5, color="0.3", label="volume control past the limit (P falls)"
        )[0],
        ax.plot([], [], "*", ms=12, color="w", mec="k", label="limit (burst) point")[0],
        ax.plot([], [], "x", ms=8, mew=2, color="0.3", label="diverged")[0],
    ]
    ax.legend(
        handles=handles, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False
    )


def _small_designs(curves) -> list[float]:
    """Values of the designs whose radius change is too small to read next to the others'."""
    change = {
        v: max([abs(y - c.radius0) for _, _, y, _ in c.path], default=0.0)
        for v, c in curves.items()
        if c.path
    }
    if not change:
        return []
    big = max(change.values())
    small = [v for v, d in change.items() if d < SMALL_CHANGE * big]
    if not small or big < 5 * max(change[v] for v in small) or big == 0:
        return []
    return sorted(small)


def plot_curves(
    rows: Sequence[Mapping[str, Any]],
    param: str,
    path: str | Path,
    *,
    title: str = "",
    label: str | None = None,
    unit: str = "",
    chosen: float | None = None,
    target_kpa: float | None = None,
) -> Path:
    """Length and outer radius against pressure, one colour per value of ``param`` (module
    docstring); `label` and `unit` name the parameter in the legend ("r0", " mm")."""
    plt = pyplot()
    curves = design_curves(rows, param)
    small = _small_designs(curves)
    fig, axes = plt.subplots(1, 3 if small else 2, figsize=(16 if small else 12, 4.8))
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
        if c.limit_pressure is not None:
            name += f", limit {c.limit_pressure:.3g} kPa"
        elif c.trial_status == "failed":
            name += ", diverged"
        thick = chosen is not None and value == chosen
        if thick:
            name += " (Table 1)"
        _draw_design(axes, c, color, name, axes[2] if value in small else None, lw=3.2 if thick else 1.2)
    axes[0].set_ylabel("ePSA length L (mm)")
    axes[1].set_ylabel("outer radius R at mid-length (mm)")
    axes[0].set_title("length")
    axes[1].set_title("outer radius")
    if small:
        shown = ", ".join(f"{v:g}" for v in small)
        axes[2].set_ylabel("radius change R - R0 (mm)")
        axes[2].set_title(f"radius change of {label} = {shown}{unit} (own scale)", fontsize=10)
        axes[2].axhline(0.0, color="0.5", lw=0.8)
    for ax in axes:
        ax.set_xlabel("chamber pressure P (kPa)")
        ax.grid(alpha=0.3)
        if target_kpa is not None:
            ax.axvline(target_kpa, color="crimson", lw=1.2, ls="-.", zorder=0)
    if target_kpa is not None:
        axes[0].plot([], [], color="crimson", lw=1.2, ls="-.", label=f"rule: withstand {target_kpa:g} kPa")
    ncol = 3 if len(curves) > 4 else 2
    axes[0].legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=ncol, frameon=False)
    _style_legend(axes[1])
    if title:
        fig.suptitle(title, fontsize=11)
    return save(fig, path, outside=True)
