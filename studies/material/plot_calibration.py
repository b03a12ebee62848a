"""The calibrated FE actuator against the prototype statics (`softcrawl calibrate`)."""

from __future__ import annotations

from pathlib import Path

from softcrawl.studies.plots.style import pyplot, save


def plot_calibration(cal, path) -> Path:
    """FE length at the calibrated mu and the prototype statics model (eqs. 19-24) against P."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.plot(
        cal.pressures_kpa, cal.prototype_length_mm, "ko-", label="prototype statics (eqs. 19-24, mean, g = 0)"
    )
    ax.plot(cal.pressures_kpa, cal.fe_length_mm, "s--", color="C3", label=f"FE, mu = {cal.mu_mpa:.4f} MPa")
    ax.set_xlabel("pressure P (kPa)")
    ax.set_ylabel("ePSA length (mm)")
    ax.set_title(f"calibrated mu: RMS error {cal.rms_error_mm:.2f} mm ({cal.mesh} mesh)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, path)
