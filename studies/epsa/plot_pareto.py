"""The Pareto front of the actuator optimisation (`softcrawl study optimise-actuator`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from softcrawl.studies.plots.style import number, pyplot, save


def _flag(v) -> bool:
    return v is True or str(v).lower() == "true"


def plot_pareto(
    rows: Sequence[Mapping[str, Any]],
    path: str | Path,
    *,
    title: str = "",
    reference: Mapping[str, float] | None = None,
) -> Path:
    """Extension against the radius change |dR| at the target pressure, coloured by fiber length;
    the Pareto front is outlined and the ``reference`` design (Table 1) is starred if present."""
    plt = pyplot()
    done = [
        r for r in rows if r.get("trial_status") == "completed" and number(r.get("extension_mm")) is not None
    ]
    fig, ax = plt.subplots(figsize=(6.5, 4.8))
    if done:
        x = [
            number(r["radius_change_mm"])
            if number(r.get("radius_change_mm")) is not None
            else abs(number(r["radial_expansion_mm"]))
            for r in done
        ]
        y = [number(r["extension_mm"]) for r in done]
        c = [number(r.get("fiber_length_mm")) or 0.0 for r in done]
        sc = ax.scatter(x, y, c=c, cmap="viridis", s=22, zorder=2)
        fig.colorbar(sc, ax=ax, label="fiber length, both helices (mm)")
        front2 = [
            (a, b)
            for a, b in zip(x, y)  # non-dominated in this plane only
            if not any(a2 <= a and b2 >= b and (a2, b2) != (a, b) for a2, b2 in zip(x, y))
        ]
        if len(front2) > 1:
            ax.step(
                *zip(*sorted(front2)),
                where="post",
                color="0.4",
                lw=1,
                zorder=1,
                label="front of extension vs radius change",
            )
        front = sorted((a, b) for a, b, r in zip(x, y, done) if _flag(r.get("pareto")))
        if front:
            ax.scatter(
                *zip(*front),
                facecolors="none",
                edgecolors="r",
                s=70,
                zorder=3,
                label="Pareto-optimal (3 objectives)",
            )
        if reference:
            for r, a, b in zip(done, x, y):
                if all(
                    number(r.get(k)) is not None and abs(number(r[k]) - float(v)) < 1e-9
                    for k, v in reference.items()
                ):
                    ax.scatter(
                        [a],
                        [b],
                        marker="*",
                        s=260,
                        c="red",
                        edgecolors="k",
                        zorder=4,
                        label="Table 1 (r = {chamber_radius:g} mm, N = {fiber_turns:g})".format(**reference),
                    )
                    break
    n_failed = sum(1 for r in rows if r.get("trial_status") == "failed")
    ax.set_xlabel("radius change |dR| at the target pressure (mm)")
    ax.set_ylabel("extension at the target pressure (mm)")
    import textwrap

    wrapped = "\n".join(textwrap.wrap(title, 70)) + "\n" if title else ""
    ax.set_title(wrapped + f"{len(done)} designs, {n_failed} failed (not shown)", fontsize=9)
    ax.grid(alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    return save(fig, path)
