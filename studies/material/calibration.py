"""Calibration: the shear modulus that makes the FE Table 1 ePSA match the prototype statics.

Target: the mean length of the three prototype ePSAs from the identified statics model
(eqs. 3 and 19-24, `analytic.prototype`), without gravity (g = 0) because the FE model has none.
Objective: the RMS length difference over the pressures (kPa)

    e(mu) = sqrt( mean_P ( L_FE(P; mu) - L_proto(P) )^2 ),

minimised over log(mu) by scipy's bounded scalar search; every evaluation is a full FE ramp
(`studies.epsa.response.simulate_epsa` with the material's mu replaced, K/mu kept). A ramp that does not
reach the last pressure (a limit point or a divergence) scores the penalty `FAILED_PENALTY_MM`.
The body is Neo-Hookean, so this is one honest estimate of an *effective* modulus: it also absorbs
what the FE model leaves out (the silicone coat over the fibers, the prototype's fabrication).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from softcrawl.analytic.prototype import prototype_epsa
from softcrawl.geometry.design import EPSADesign
from softcrawl.materials import get_material
from softcrawl.studies.epsa.model import DEFAULT_FIBERS
from softcrawl.studies.epsa.response import same_pressure, simulate_epsa

FAILED_PENALTY_MM = 1e3


@dataclass(frozen=True)
class Calibration:
    mu_mpa: float
    rms_error_mm: float
    pressures_kpa: tuple[float, ...]
    prototype_length_mm: tuple[float, ...]
    fe_length_mm: tuple[float, ...]
    base_material: str
    evaluations: tuple[tuple[float, float], ...] = field(default_factory=tuple)  # (mu, rms)
    mesh: str = "quick"
    fibers: str = ""  # the winding model of the FE runs (studies.epsa.model.FIBER_MODELS)


def prototype_lengths(pressures_kpa) -> np.ndarray:
    return np.mean([[prototype_epsa(i).length(p, g=0.0) for p in pressures_kpa] for i in (1, 2, 3)], axis=0)


def calibrate_mu(
    design: EPSADesign | None = None,
    *,
    base_material="ecoflex-00-50",
    pressures_kpa=(20.0, 40.0, 60.0, 80.0, 100.0),
    bounds=(0.02, 0.4),
    mesh="quick",
    xatol=0.02,
    progress=None,
) -> Calibration:
    from scipy.optimize import minimize_scalar

    design = design or EPSADesign()
    base = get_material(base_material)
    target = prototype_lengths(pressures_kpa)
    cache: dict[float, tuple[float, np.ndarray]] = {}

    def rms(log_mu: float) -> float:
        mu = float(math.exp(log_mu))
        curve = simulate_epsa(design, material=base.with_mu(mu), pressures_kpa=pressures_kpa, mesh=mesh)
        good = [r for r in curve.rows if r.status == "converged"]
        lengths = np.array(
            [
                next((r.length_mm for r in good if same_pressure(r.pressure_kpa, p)), np.nan)
                for p in pressures_kpa
            ]
        )
        err = (
            FAILED_PENALTY_MM
            if np.isnan(lengths).any() or curve.limit_pressure_kpa is not None
            else float(np.sqrt(np.mean((lengths - target) ** 2)))
        )
        cache[mu] = (err, lengths)
        if progress is not None:
            progress(f"mu = {mu:.4f} MPa: RMS length error {err:.3g} mm ({curve.wall_s:.0f} s)")
        return err

    minimize_scalar(
        rms, bounds=(math.log(bounds[0]), math.log(bounds[1])), method="bounded", options={"xatol": xatol}
    )
    mu_best = min(cache, key=lambda m: cache[m][0])
    err, lengths = cache[mu_best]
    return Calibration(
        mu_best,
        err,
        tuple(pressures_kpa),
        tuple(target.tolist()),
        tuple(lengths.tolist()),
        base.name,
        tuple(sorted((m, e) for m, (e, _) in cache.items())),
        mesh if isinstance(mesh, str) else "custom",
        DEFAULT_FIBERS,
    )
