"""A hyperelastic fit against the tensile test it was fitted to (`softcrawl material fit`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from softcrawl.studies.plots.style import pyplot, save


def plot_fit(data, fit, path) -> Path:
    """The tensile data, the fitted law over the fitted range and beyond, and the whole test."""
    plt = pyplot()
    strain, stress = data.strain, data.nominal_stress
    fig, (near, full) = plt.subplots(1, 2, figsize=(11, 4.2))
    zoom = min(2.0 * fit.max_strain, float(strain.max()))
    for axis, upper in ((near, zoom), (full, float(strain.max()))):
        shown = strain <= upper
        axis.plot(strain[shown], stress[shown], ".", ms=3, color="0.4", label="data")
        curve = np.linspace(0.0, upper, 300)
        axis.plot(
            curve, fit.predict(1.0 + curve), "-", color="C3", label=f"{fit.model} fit ({params_text(fit)})"
        )
        axis.axvspan(fit.strain_range[0], fit.strain_range[1], color="C0", alpha=0.12, label="fitted range")
        axis.set_xlabel("engineering strain [-]")
        axis.set_ylabel("nominal stress [MPa]")
        axis.set_ylim(min(0.0, float(stress[shown].min())), 1.15 * float(stress[shown].max()))
        axis.grid(alpha=0.3)
    near.set_title(f"{data.name}: fitted range and beyond")
    full.set_title("whole pull-to-failure test")
    near.legend(fontsize=8, loc="upper left")
    fig.text(
        0.01,
        0.01,
        f"RMS error {fit.rms_error:.2g} MPa ({100 * fit.relative_rms_error:.1f} %),"
        f" strain {fit.strain_range[0]:.2f}-{fit.strain_range[1]:.2f}. "
        + (
            "Data: Soft Robotics Materials Database (Marechal et al. 2021), ODbL/DbCL."
            if data.attribution
            else "Data: user-supplied file."
        ),
        fontsize=7,
    )
    return save(fig, path, rect=(0, 0.04, 1, 1))


def params_text(fit) -> str:
    return ", ".join(f"{k}={v:.3g}" for k, v in fit.params.items()) + " MPa"
