"""The prediction figure (`softcrawl study predict-crawl`): the FE crawl with the identified feet
over Table 2 and Fig. 21's statements.

Left: speed in the direction of travel against pipe diameter, forward and backward, FE (filled:
converged, 2 cycles) beside Table 2 (squares) and the issue's +-30 % band around it. Right: Fig.
21's statement, "more than 10 mm/s over 50A-70A and 30-120 deg" (the 10 mm/s line) and "a speed
that rises with the angle at 70A", against the feet study's speeds (`fig21_rows`: one line per
hardness), or a note where that study has not run under the results folder.
"""

from __future__ import annotations

import csv
from pathlib import Path

from softcrawl.paper import FIG21_MIN_SPEED_MM_S, TABLE2_MM_S
from softcrawl.studies.plots.style import pyplot, save

COLOURS = {"forward": "C0", "backward": "C3"}


def fig21_rows(results: Path) -> list[dict]:
    """The feet study's completed points under `results` (material, angle_deg, speed_mm_s), or []
    where it has not run: every DIR/feet/*/feet.csv (`studies.crawl.feet_study`)."""
    rows = []
    for table in sorted((Path(results) / "feet").glob("*/feet.csv")):
        with open(table, newline="") as fh:
            rows += [r for r in csv.DictReader(fh) if r.get("status") == "completed"]
    return rows


def plot_prediction(rows, results: Path, path: Path, tolerance: float = 0.30) -> Path:
    """`rows`: `studies.crawl.prediction.Prediction`s; `results`: where the feet study's table is."""
    plt = pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for k, direction in enumerate(("forward", "backward")):
        mine = sorted((r for r in rows if r.direction == direction), key=lambda r: r.pipe_diameter)
        colour = COLOURS[direction]
        d = sorted(TABLE2_MM_S)
        paper = [TABLE2_MM_S[x][k] for x in d]
        left.plot(d, paper, "s--", color=colour, mfc="none", label=f"Table 2, {direction}")
        left.fill_between(d, [(1 - tolerance) * v for v in paper], [(1 + tolerance) * v for v in paper],
                          color=colour, alpha=0.08, lw=0)  # fmt: skip
        if mine:
            left.plot([r.pipe_diameter for r in mine], [r.speed_mm_s for r in mine], "-", color=colour)
            for r in mine:
                face = colour if r.converged else "none"
                left.plot(r.pipe_diameter, r.speed_mm_s, "o", color=colour, mfc=face)
            left.plot([], [], "o-", color=colour, label=f"FE, identified feet, {direction}")
    left.axhline(0.0, color="0.6", lw=0.8)
    mu = sorted({(r.mu_smooth, r.mu_grooved) for r in rows})
    mus = ", ".join(f"mu {s:g} / {g:g}" for s, g in mu)
    left.set(xlabel="pipe diameter (mm)", ylabel="speed in the direction of travel (mm/s)",
             title=f"Table 2 held out ({mus}; band: +-{100 * tolerance:g} %)")  # fmt: skip
    left.legend(fontsize=8)
    _fig21(right, fig21_rows(results))
    return save(fig, path)


def _fig21(ax, rows: list[dict]) -> None:
    label = f"Fig. 21: > {FIG21_MIN_SPEED_MM_S:g} mm/s"
    ax.axhline(FIG21_MIN_SPEED_MM_S, color="k", ls="--", lw=1, label=label)
    ax.set(xlabel="foot angle (deg)", ylabel="forward speed, 70 mm pipe (mm/s)", xlim=(20, 130))
    if not rows:
        ax.set_ylim(0.0, 3 * FIG21_MIN_SPEED_MM_S)
        ax.text(0.5, 0.5, "feet study not run under this results folder\n(softcrawl study feet)",
                ha="center", va="center", transform=ax.transAxes)  # fmt: skip
        ax.set_title("Fig. 21's statements")
        ax.legend(fontsize=8)
        return
    for material in sorted({r["material"] for r in rows}):
        mine = (r for r in rows if r["material"] == material)
        pts = sorted((float(r["angle_deg"]), float(r["speed_mm_s"])) for r in mine)
        ax.plot(*zip(*pts), "o-", label=material)
    ax.set_ylim(bottom=min(0.0, ax.get_ylim()[0]))
    ax.set_title("Fig. 21's statements against the FE feet")
    ax.legend(fontsize=8)
