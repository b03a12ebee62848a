"""FE identification of k_p(P) and f_p(P) beside the prototype's eqs. 19-24 (Section VII-A).

The paper's laws are two straight lines in P, split at a breakpoint (60 kPa). The FE's fitted laws
are drawn the same way, one segment per piece over its own pressure range, so that the jump
between the pieces shows as a jump, not as a sloping line between two samples. Where a fitted
line dips below zero while the per-pressure values (dots) stay positive, the figure says so: a
negative k_p there is an artefact of forcing two straight lines through a curved k_p(P), not a
negative stiffness of the actuator.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from softcrawl.studies.plots.style import pyplot, save

QUANTITIES = (
    ("k_p", "_n_per_m", "k_p_n_per_m", "stiffness k_p (N/m)"),
    ("f_p", "_n", "f_p_n", "thrust f_p (N)"),
)


def _pieces(laws, key, p_lo, p_hi):
    """(P range, values) of each piece of a fitted law {slope, intercept, p_max_kpa}."""
    out, start = [], p_lo
    for law in laws.get(key, []):
        end = p_hi if law.get("p_max_kpa") is None else min(float(law["p_max_kpa"]), p_hi)
        P = np.linspace(start, end, 50)
        out.append((P, law["slope"] * P + law["intercept"]))
        start = end
    return out


def plot_identification(
    rows: Sequence[Mapping[str, Any]], path: str | Path, *, title: str = "", laws: Mapping | None = None
) -> Path:
    """k_p(P) and f_p(P) identified from the FE (points and the fitted piecewise lines) beside the
    prototype ePSAs' eqs. 19-24 (`studies.epsa.identification.comparison_rows`; paper units
    N/m and N). `laws` (identification.json) draws the fit piece by piece."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    P = np.array([float(r["pressure_kpa"]) for r in rows])
    for ax, (key, suffix, law_key, ylabel) in zip(axes, QUANTITIES):
        for i in (1, 2, 3):
            values = [float(r[f"{key}_epsa{i}{suffix}"]) for r in rows]
            ax.plot(P, values, color=f"C{i}", lw=1, ls="--", label=f"prototype ePSA {i} (eqs. 19-24)")
        points = np.array([float(r[f"{key}_fe{suffix}"]) for r in rows])
        ax.plot(P, points, "ko", label="FE, identified at each pressure")
        if laws:
            fitted = _pieces(laws, law_key, P.min(), P.max())
            for k, (pp, vv) in enumerate(fitted):
                ax.plot(pp, vv, "k-", lw=1.5, label="FE, two-line fit (paper's form)" if k == 0 else None)
        else:
            pp = P
            vv = np.array([float(r[f"{key}_fe_fit{suffix}"]) for r in rows])
            fitted = [(pp, vv)]
            ax.plot(pp, vv, "k-", lw=1.5, label="FE, two-line fit (paper's form)")
        low = min(v.min() for _, v in fitted)
        if low < 0 <= points.min():
            ax.axhline(0.0, color="0.4", lw=0.8)
            ax.annotate(
                f"the fitted line dips to {low:.3g} here: an artefact of two straight\n"
                "lines through a curved law; the identified values stay > 0",
                xy=(pp[np.argmin(vv)] if not laws else fitted[0][0][-1], low),
                xytext=(0.3, 0.8),
                textcoords="axes fraction",
                fontsize=8,
                arrowprops=dict(arrowstyle="->", color="0.3"),
            )
        ax.set_xlabel("chamber pressure P (kPa)")
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=5, frameon=False)
    axes[0].set_title("stiffness against a weight (eq. 3)", fontsize=10)
    axes[1].set_title("pressure thrust (eq. 3)", fontsize=10)
    if title:
        fig.suptitle(title, fontsize=11)
    return save(fig, path, rect=(0, 0.06, 1, 1))
