"""Plots of the study tables (matplotlib, Agg backend): ePSA curves (paper Figs. 8-9) and the
Pareto front of the actuator optimisation. Inputs are the rows of ``studies.runner.collect`` /
``collect_search`` or the same rows read back from CSV (strings), so plots can be redrawn from the
CSV files alone. Pressures in kPa, lengths in mm.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping, Sequence

from studies.rules import design_curves


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_curves(rows: Sequence[Mapping[str, Any]], param: str, path: str | Path, *,
                title: str = "", label: str | None = None, unit: str = "") -> Path:
    """Length and outer radius against pressure, one line per value of ``param``.

    The undeformed state (0 kPa) starts every line; lines follow the solution path, so states past
    a limit point (volume control, falling pressure) bend back. A limit (burst) pressure is marked
    with a star at the limit state and its value; a diverged evaluation ends in a cross and is dashed; a missing or failed point
    without curve data is listed in the legend as such."""
    plt = _pyplot()
    curves = design_curves(rows, param)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    label = label or param
    for i, (value, c) in enumerate(sorted(curves.items())):
        color = f"C{i % 10}"
        name = f"{label} = {value:g}{unit}"
        if not c.path:
            axes[0].plot([], [], color=color, label=f"{name}: {c.trial_status}"
                         + (f" ({_short(c.reason)})" if c.reason else ""))
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
            ax.plot(p, y, style, marker="o", ms=3, color=color,
                    label=name + suffix if ax is axes[0] else None)
            if c.limit_pressure is not None:
                k = max(range(len(p)), key=lambda j: p[j])  # the state at the limit pressure
                ax.plot([p[k]], [y[k]], marker="*", ms=14, color=color, mec="k")
                ax.annotate(f"{c.limit_pressure:.3g} kPa", (p[k], y[k]),
                            textcoords="offset points", xytext=(4, 4), fontsize=7, color=color)
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
    return _save(fig, path)


def _short(text: str, n: int = 40) -> str:
    text = str(text)
    return text if len(text) <= n else text[: n - 3] + "..."


def _num(v) -> float | None:
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def _flag(v) -> bool:
    return v is True or str(v).lower() == "true"


def plot_pareto(rows: Sequence[Mapping[str, Any]], path: str | Path, *, title: str = "",
                reference: Mapping[str, float] | None = None) -> Path:
    """Extension against the radius change |dR| at the target pressure, coloured by fiber length;
    the Pareto front is outlined and the ``reference`` design (Table 1) is starred if present."""
    plt = _pyplot()
    done = [r for r in rows if r.get("trial_status") == "completed"
            and _num(r.get("extension_mm")) is not None]
    fig, ax = plt.subplots(figsize=(6.5, 4.8))
    if done:
        x = [_num(r["radius_change_mm"]) if _num(r.get("radius_change_mm")) is not None
             else abs(_num(r["radial_expansion_mm"])) for r in done]
        y = [_num(r["extension_mm"]) for r in done]
        c = [_num(r.get("fiber_length_mm")) or 0.0 for r in done]
        sc = ax.scatter(x, y, c=c, cmap="viridis", s=22, zorder=2)
        fig.colorbar(sc, ax=ax, label="fiber length, both helices (mm)")
        front2 = [(a, b) for a, b in zip(x, y)  # non-dominated in this plane only
                  if not any(a2 <= a and b2 >= b and (a2, b2) != (a, b) for a2, b2 in zip(x, y))]
        if len(front2) > 1:
            ax.step(*zip(*sorted(front2)), where="post", color="0.4", lw=1, zorder=1,
                    label="front of extension vs radius change")
        front = sorted((a, b) for a, b, r in zip(x, y, done) if _flag(r.get("pareto")))
        if front:
            ax.scatter(*zip(*front), facecolors="none", edgecolors="r", s=70, zorder=3,
                       label="Pareto-optimal (3 objectives)")
        if reference:
            for r, a, b in zip(done, x, y):
                if all(_num(r.get(k)) is not None and abs(_num(r[k]) - float(v)) < 1e-9
                       for k, v in reference.items()):
                    ax.scatter([a], [b], marker="*", s=260, c="red", edgecolors="k", zorder=4,
                               label="Table 1 (r = {chamber_radius:g} mm, N = {fiber_turns:g})"
                               .format(**reference))
                    break
    n_failed = sum(1 for r in rows if r.get("trial_status") == "failed")
    ax.set_xlabel("radius change |dR| at the target pressure (mm)")
    ax.set_ylabel("extension at the target pressure (mm)")
    ax.set_title((title + "\n" if title else "") + f"{len(done)} designs, {n_failed} failed "
                 "(not shown)", fontsize=9)
    ax.grid(alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    return _save(fig, path)


def plot_identification(rows: Sequence[Mapping[str, Any]], path: str | Path, *, title: str = "") -> Path:
    """k_p(P) and f_p(P) identified from the FE (points and the fitted piecewise lines) beside the
    prototype ePSAs' eqs. 19-24 (`studies.identify.comparison_rows`; paper units N/m and N)."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    P = [float(r["pressure_kpa"]) for r in rows]
    for ax, key, unit in ((axes[0], "k_p", "N/m"), (axes[1], "f_p", "N")):
        suffix = "_n_per_m" if key == "k_p" else "_n"
        for i in (1, 2, 3):
            ax.plot(P, [float(r[f"{key}_epsa{i}{suffix}"]) for r in rows], color=f"C{i}", lw=1,
                    ls="--", label=f"prototype ePSA {i} (eqs. 19-24)")
        ax.plot(P, [float(r[f"{key}_fe{suffix}"]) for r in rows], "ko", label="FE, per pressure")
        ax.plot(P, [float(r[f"{key}_fe_fit{suffix}"]) for r in rows], "k-", lw=1.5,
                label="FE, piecewise fit")
        ax.set_xlabel("pressure P (kPa)")
        ax.set_ylabel(f"{key} ({unit})")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    if title:
        fig.suptitle(title, fontsize=10)
    return _save(fig, path)


def _save(fig, path) -> Path:
    """Lay out, write (creating the folder) and close a figure; returns the path."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
