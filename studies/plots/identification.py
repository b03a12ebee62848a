"""FE identification of k_p(P) and f_p(P) beside the prototype's eqs. 19-24 (Section VII-A)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from studies.plots.style import pyplot, save


def plot_identification(rows: Sequence[Mapping[str, Any]], path: str | Path, *, title: str = "") -> Path:
    """k_p(P) and f_p(P) identified from the FE (points and the fitted piecewise lines) beside the
    prototype ePSAs' eqs. 19-24 (`studies.catalogue.fe_identification.comparison_rows`; paper units
    N/m and N)."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    P = [float(r["pressure_kpa"]) for r in rows]
    for ax, key, unit in ((axes[0], "k_p", "N/m"), (axes[1], "f_p", "N")):
        suffix = "_n_per_m" if key == "k_p" else "_n"
        for i in (1, 2, 3):
            ax.plot(
                P,
                [float(r[f"{key}_epsa{i}{suffix}"]) for r in rows],
                color=f"C{i}",
                lw=1,
                ls="--",
                label=f"prototype ePSA {i} (eqs. 19-24)",
            )
        ax.plot(P, [float(r[f"{key}_fe{suffix}"]) for r in rows], "ko", label="FE, per pressure")
        ax.plot(P, [float(r[f"{key}_fe_fit{suffix}"]) for r in rows], "k-", lw=1.5, label="FE, piecewise fit")
        ax.set_xlabel("pressure P (kPa)")
        ax.set_ylabel(f"{key} ({unit})")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    if title:
        fig.suptitle(title, fontsize=10)
    return save(fig, path)
