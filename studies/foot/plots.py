"""Figures of the foot studies: the groove segment (Fig. 10(a)) and the whole foot (Fig. 10(b))."""

from __future__ import annotations

import numpy as np

from softcrawl.studies.plots.style import pyplot, save


def plot_groove(points, path, settings):
    """Friction / (mu N) against drag per (h, mu); von Mises p99 and deformation against h."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    by_mu: dict = {}
    for p in points:
        curve, s = p.get("curve") or {}, p.get("summary") or {}
        h, mu = p["params"]["groove_height"], p["params"]["mu"]
        if curve.get("drag_mm"):
            n = np.asarray(curve["normal_n"])
            axes[0].plot(
                curve["drag_mm"], np.asarray(curve["friction_n"]) / (mu * n), label=f"h = {h:g}, mu = {mu:g}"
            )
        if s and p["status"] == "completed":
            by_mu.setdefault(mu, []).append(
                (h, s["von_mises_mpa_p99"], s["von_mises_mpa_max"], s["deformation_max_mm"])
            )
    axes[0].set(xlabel="drag (mm)", ylabel="friction / (mu N)", title="friction-displacement")
    axes[0].axhline(1.0, color="0.6", lw=0.8, ls="--")
    axes[0].legend(fontsize=7)
    for mu, rows in sorted(by_mu.items()):
        rows = np.array(sorted(rows))
        axes[1].plot(rows[:, 0], rows[:, 1], "o-", label=f"p99, mu = {mu:g}")
        axes[1].plot(rows[:, 0], rows[:, 2], "x:", label=f"raw max, mu = {mu:g}")
        axes[2].plot(rows[:, 0], rows[:, 3], "o-", label=f"mu = {mu:g}")
    axes[1].set(xlabel="groove height h (mm)", ylabel="von Mises (MPa)", title="stress after 5 mm drag")
    axes[2].set(
        xlabel="groove height h (mm)", ylabel="max displacement rel. backing (mm)", title="deformation"
    )
    for ax in axes[1:]:
        ax.legend(fontsize=7)
    load = f"{settings.get('pressure_kpa', 100):g} kPa"
    fig.suptitle(f"groove segment, {settings.get('material')}, {load} (paper Fig. 10(a))")
    return save(fig, path, rect=(0, 0, 1, 0.94))


def plot_foot(points, path, settings):
    """Resistance against drag (forward, backward) per pipe diameter; F_bwd / F_fwd against D."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    ratios = []
    for p in points:
        D = p["params"]["pipe_diameter"]
        for direction, c in (p.get("curves") or {}).items():
            ls = {"forward": "-", "backward": "--"}.get(direction, ":")  # ":": the flipped foot
            (line,) = axes[0].plot(c["drag_mm"], c["resistance_n"], ls, label=f"D = {D:g} mm, {direction}")
            if c.get("limit_point_mm") is not None:  # the drag stopped past this peak (a snap)
                axes[0].plot(c["limit_point_mm"], c["limit_point_n"], "x", color=line.get_color(), ms=8)
        s = p.get("summary") or {}
        if s.get("ratio_bwd_fwd") is not None and np.isfinite(s.get("ratio_bwd_fwd", np.nan)):
            ratios.append((D, s["ratio_bwd_fwd"], p["status"] == "completed"))
    axes[0].set(
        xlabel="hub displacement (mm)", ylabel="resistance (N)", title="drag resistance (x: limit point)"
    )
    axes[0].legend(fontsize=7)
    done = np.array(sorted((d, r) for d, r, ok in ratios if ok)).reshape(-1, 2)
    partial = np.array(sorted((d, r) for d, r, ok in ratios if not ok)).reshape(-1, 2)
    axes[1].plot(done[:, 0], done[:, 1], "o-", label="both drags complete")
    if partial.size:  # a drag that stopped early: its peak so far, a lower bound of the ratio
        axes[1].plot(partial[:, 0], partial[:, 1], "^", mfc="none", label="drag stopped early (lower bound)")
    axes[1].legend(fontsize=7)
    axes[1].axhline(1.0, color="0.6", lw=0.8, ls="--")
    axes[1].set(xlabel="pipe diameter (mm)", ylabel="F_bwd / F_fwd", title="anchoring (Fig. 4 needs > 1)")
    fig.suptitle(
        f"grooved foot, {settings.get('material')}, angle {settings.get('angle', 120):g} deg, "
        f"mu smooth {settings.get('mu_smooth')}, grooved {settings.get('mu_grooved')} (paper Fig. 10(b))"
    )
    return save(fig, path, rect=(0, 0, 1, 0.94))
