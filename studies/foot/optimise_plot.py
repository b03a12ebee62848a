"""The Pareto front of `softcrawl study optimise-feet`: the anchoring margin against the foot's mass.

One point per completed trial (x: mass in g, y: the worst-case margin of
`studies.foot.anchoring`), coloured by hardness; the non-dominated set (largest margin for its
mass) joined by a step line and outlined; the paper's foot (the enqueued first trial) starred; the
margin 0 line (above it every pipe's two Fig. 4 inequalities hold); failed trials counted in the
title. Drawn from the rows of trials.csv, so `softcrawl replot` redraws it from the table alone.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from softcrawl.studies.plots.style import number, pyplot, save

#: One colour per hardness, in the order of the study's choices (softer -> lighter).
COLOURS = {"rubber-50a": "#9ecae1", "rubber-60a": "#4292c6", "rubber-70a": "#08306b"}


def _flag(v: Any) -> bool:
    return v is True or str(v).lower() == "true"


def front(points: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    """The non-dominated (mass, margin) pairs: no other point is as light and at least as good,
    with one of the two strictly better; sorted by mass."""
    return sorted(
        (m, g)
        for m, g in points
        if not any((m2 <= m and g2 >= g) and (m2, g2) != (m, g) for m2, g2 in points)
    )


def plot_front(rows: Sequence[Mapping[str, Any]], path: str | Path, *, title: str = "") -> Path:
    """pareto.png of the trials (module docstring)."""
    plt = pyplot()
    done = [
        r
        for r in rows
        if r.get("trial_status") == "completed"
        and number(r.get("margin")) is not None
        and number(r.get("mass_g")) is not None
    ]
    fig, ax = plt.subplots(figsize=(6.5, 4.8))
    for hardness, colour in COLOURS.items():
        pts = [(number(r["mass_g"]), number(r["margin"])) for r in done if r.get("hardness") == hardness]
        if pts:
            label = f"Shore {hardness.split('-')[1].upper()}"
            ax.scatter(*zip(*pts), s=24, color=colour, zorder=2, label=label)
    points = [(number(r["mass_g"]), number(r["margin"])) for r in done]
    best = front(points)
    if len(best) > 1:
        ax.step(*zip(*best), where="post", color="0.4", lw=1, zorder=1)
    if best:
        ax.scatter(*zip(*best), facecolors="none", edgecolors="r", s=80, zorder=3, label="Pareto front")
    paper = [r for r in done if _flag(r.get("initial"))]
    if paper:
        ax.scatter(
            [number(paper[0]["mass_g"])],
            [number(paper[0]["margin"])],
            marker="*",
            s=260,
            c="red",
            edgecolors="k",
            zorder=4,
            label="the paper's foot (120 deg, 70A, 3 mm)",
        )
    ax.axhline(0.0, color="k", lw=0.8, ls="--", zorder=0)
    ax.set_xlabel("foot mass (g)")
    ax.set_ylabel("worst-case anchoring margin over the pipes")
    failed = sum(r.get("trial_status") != "completed" for r in rows)
    ax.set_title(
        (title + "\n" if title else "")
        + f"{len(done)} completed, {failed} failed trials; above 0: Fig. 4 holds in every pipe",
        fontsize=9,
    )
    if done:
        ax.legend(fontsize=8, loc="best")
    return save(fig, path)
