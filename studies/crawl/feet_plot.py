"""Figure of `study feet`: the FE crawl speed against the foot angle, one line per hardness, beside
Fig. 21's 10 mm/s, with both statements' verdicts in the title (`studies.crawl.feet_statements`)."""

from __future__ import annotations

import textwrap

from softcrawl.paper import FIG21_ANGLE_DEG, FIG21_MIN_SPEED_MM_S, FIG21_PIPE_MM
from softcrawl.studies.crawl.feet_statements import verdicts
from softcrawl.studies.plots.style import pyplot, save


def plot_feet(rows, path, friction: str = ""):
    """Speed (mm/s) against angle (deg) through the completed points of each hardness; failed and
    missing points are not drawn (feet.csv and summary.md give their reasons). `friction`: the mu
    line, printed under the verdicts."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    for shore in sorted({float(r["shore_a"]) for r in rows}, reverse=True):
        done = sorted(
            (r for r in rows if float(r["shore_a"]) == shore and r["status"] == "completed"),
            key=lambda r: float(r["angle_deg"]),
        )
        if done:
            angles = [float(r["angle_deg"]) for r in done]
            ax.plot(angles, [float(r["speed_mm_s"]) for r in done], "o-", label=f"FE, {shore:g}A")
    ax.axhline(
        FIG21_MIN_SPEED_MM_S, color="k", ls="--", lw=1, label=f"Fig. 21: > {FIG21_MIN_SPEED_MM_S:g} mm/s"
    )
    ax.axvspan(*FIG21_ANGLE_DEG, color="0.92", zorder=0, label="Fig. 21's angles")
    ax.set(
        xlabel="foot angle (deg, included angle of the skirt)",
        ylabel="steady crawl speed (mm/s)",
        xlim=(FIG21_ANGLE_DEG[0] - 10, FIG21_ANGLE_DEG[1] + 10),
    )
    ax.set_ylim(bottom=min(0.0, ax.get_ylim()[0]), top=max(ax.get_ylim()[1], 1.2 * FIG21_MIN_SPEED_MM_S))
    title = [f"FE crawl, {FIG21_PIPE_MM:g} mm pipe, inflate 100 kPa, 2 s cycles"]
    title += [v.text() for v in verdicts(rows)] + ([friction] if friction else [])
    ax.set_title("\n".join(textwrap.fill(line, 120) for line in title), fontsize=6.5)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return save(fig, path)
