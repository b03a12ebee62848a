"""Least-squares fits of the incompressible hyperelastic laws to a uniaxial tensile test.

`fit_uniaxial` fits any registered law (`fem.laws.LAWS`): it selects the points
(`select_fit_points`), weighs the residuals, and leaves the least squares to the law
(`IsochoricI1Law.fit_uniaxial`: linear for Neo-Hookean and Yeoh, a search over Jm for Gent, a
generic nonlinear least squares for a law that brings only a start and bounds). The fitted
constants make the law (`from_fit`, nearly incompressible); its uniaxial stress gives the errors.

Residuals are absolute (MPa, `weighting="absolute"`, the default for the 0-100 % fits) or
relative to the measured stress (`weighting="relative"`): over the full pull-to-failure curve the
stress spans three decades (0.005-1 MPa), so an absolute fit is decided by the last points and
ignores the actuator's range (stretch < 3), while a relative fit weighs every decade alike. The
full-range presets (`materials.presets`) use the relative residuals and state both errors.
See `select_fit_points` for the data handling and `DEFAULT_MAX_STRAIN` for the
default strain range.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import IsochoricI1Law, law_class
from softcrawl.materials.material import DEFAULT_K_OVER_MU, Material, MaterialError, finite_number
from softcrawl.materials.tensile import TensileData

WEIGHTINGS = ("absolute", "relative")
#: Full range of the shipped pull-to-failure tests (engineering strain; Ecoflex 00-50 ends at 16.4).
FULL_RANGE_STRAIN = 100.0


#: Default upper engineering strain of the fits (stretch 2). The ePSA's silicone works at
#: principal stretches up to about 1.5-2, so this is the range the FE model must get right. The
#: Neo-Hookean model cannot follow the strain stiffening of the pull-to-failure curve (to ~1600 %
#: strain): a least-squares fit over the whole curve is dominated by the large-strain points and
#: gives for Ecoflex 00-50 a mu about 4x the small-strain value (0.087 vs 0.022 MPa), which would
#: make the actuator far too stiff in its working range.
DEFAULT_MAX_STRAIN = 1.0


@dataclass(frozen=True, kw_only=True)
class FitResult:
    """A least-squares fit of an incompressible hyperelastic law to uniaxial tension.

    `law` is the fitted law (nearly incompressible, K = DEFAULT_K_OVER_MU mu);
    `param_names`/`values` are its constants in MPa (``mu`` or ``C10, C20, C30``, ...);
    `strain_range` is the (min, max) engineering strain of the points used, `max_strain` the
    requested upper bound; errors are on the nominal stress: `rms_error` [MPa],
    `relative_rms_error` = rms_error / RMS(measured stress), `r_squared` = 1 - SS_res / SS_tot.
    """

    law: IsochoricI1Law
    param_names: tuple[str, ...]
    values: tuple[float, ...]
    max_strain: float
    strain_range: tuple[float, float]
    n_points: int
    rms_error: float
    relative_rms_error: float
    r_squared: float
    notes: tuple[str, ...] = ()
    weighting: str = "absolute"
    #: RMS of (model - measured) / measured over the points: the error a relative fit minimises.
    rms_pointwise_relative_error: float = float("nan")

    @property
    def model(self) -> str:
        """The law's registry name."""
        return self.law.NAME

    @property
    def params(self) -> dict[str, float]:
        return dict(zip(self.param_names, self.values))

    @property
    def initial_shear_modulus(self) -> float:
        """mu of the law (2 C10 for Yeoh) [MPa]."""
        return self.law.mu

    def predict(self, stretch: ArrayLike) -> np.ndarray:
        """Model nominal stress [MPa] at `stretch`."""
        return self.law.uniaxial_nominal_stress(stretch)

    def to_material(
        self, *, name: str, density: float, source: str, k_over_mu: float = DEFAULT_K_OVER_MU
    ) -> Material:
        law = type(self.law).from_fit(self.values, k_over_mu)
        return Material(name=name, law=law, density=density, source=source)

    def to_dict(self) -> dict:
        return {
            "model": self.model,
            "params_mpa": self.params,
            "initial_shear_modulus_mpa": self.initial_shear_modulus,
            "max_strain": self.max_strain,
            "strain_range": list(self.strain_range),
            "n_points": self.n_points,
            "rms_error_mpa": self.rms_error,
            "relative_rms_error": self.relative_rms_error,
            "r_squared": self.r_squared,
            "weighting": self.weighting,
            "rms_pointwise_relative_error": self.rms_pointwise_relative_error,
            "notes": list(self.notes),
        }


def select_fit_points(
    stretch: ArrayLike, nominal_stress: ArrayLike, max_strain: float = DEFAULT_MAX_STRAIN
) -> tuple[np.ndarray, np.ndarray]:
    """The (stretch, stress) points a fit uses, as two arrays.

    * Toe region: crosshead strain includes the take-up of slack and the load cell zero offset,
      so the first readings can be zero or negative (Ecoflex 00-50 starts at -0.0009 MPa). All
      points up to and including the last non-positive stress are dropped. The strain origin is
      not shifted: that would be one more fitted parameter, and the offset is a few % strain.
    * Range: only points with engineering strain lam - 1 <= max_strain are kept.
    * Noise is left to the least squares (no smoothing): the residual RMS is reported instead.
    """
    lam, stress = _validated_curve(stretch, nominal_stress)
    limit = finite_number(max_strain, "max_strain")
    if limit <= 0.0:
        raise MaterialError("max_strain", f"must be > 0, got {limit:g}")
    non_positive = np.flatnonzero(stress <= 0.0)
    start = int(non_positive[-1]) + 1 if non_positive.size else 0
    keep = np.arange(lam.size) >= start
    keep &= lam - 1.0 <= limit
    return lam[keep], stress[keep]


def fit_uniaxial(
    stretch: ArrayLike,
    nominal_stress: ArrayLike,
    model: str = "neo-hookean",
    max_strain: float = DEFAULT_MAX_STRAIN,
    weighting: str = "absolute",
) -> FitResult:
    """Fit the registered law `model` to uniaxial tension (module docstring).

    `stretch` = 1 + engineering strain, `nominal_stress` in MPa; points are chosen by
    `select_fit_points` (default strain range 0-`DEFAULT_MAX_STRAIN` = 0-100 %, stretch <= 2, the
    ePSA's operating range; see that constant for why not the whole curve).
    """
    try:
        cls = law_class(model, "model")
    except SolverInputError as exc:
        raise MaterialError(exc.parameter, exc.detail) from None
    lam, stress = _points_for_fit(stretch, nominal_stress, max_strain, n_params=len(cls.FIT_PARAMS))
    values, notes = cls.fit_uniaxial(lam, stress, _weights(stress, weighting))
    if values[0] <= 0.0:
        name = cls.FIT_PARAMS[0]
        raise MaterialError("nominal_stress", f"fitted {name} = {values[0]:g} MPa is not positive")
    try:
        law = cls.from_fit(values)
    except SolverInputError as exc:
        raise MaterialError("nominal_stress", f"the fitted {cls.NAME} law is invalid: {exc}") from None
    return _fit_result(law, values, lam, stress, max_strain, tuple(notes), weighting)


def fit_tensile(
    data: TensileData,
    model: str = "neo-hookean",
    max_strain: float = DEFAULT_MAX_STRAIN,
    weighting: str = "absolute",
) -> FitResult:
    """Fit the registered law `model` (`fem.laws.LAWS`) to a loaded tensile test."""
    return fit_uniaxial(data.stretch, data.nominal_stress, model, max_strain, weighting)


def _weights(stress: np.ndarray, weighting: str) -> np.ndarray:
    """1 (absolute residuals) or 1/stress (relative residuals; the stresses are > 0 here)."""
    if weighting == "absolute":
        return np.ones_like(stress)
    if weighting == "relative":
        return 1.0 / stress
    raise MaterialError("weighting", f"unknown weighting {weighting!r}; valid: {', '.join(WEIGHTINGS)}")


def _validated_curve(stretch: ArrayLike, nominal_stress: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    lam = np.asarray(stretch, dtype=float)
    stress = np.asarray(nominal_stress, dtype=float)
    if lam.ndim != 1:
        raise MaterialError("stretch", f"must be a 1-D array, got shape {lam.shape}")
    if stress.shape != lam.shape:
        raise MaterialError("nominal_stress", f"shape {stress.shape} differs from stretch shape {lam.shape}")
    if not np.all(np.isfinite(lam)) or np.any(lam <= 0.0):
        raise MaterialError("stretch", "must be finite and > 0 (stretch = 1 + engineering strain)")
    if not np.all(np.isfinite(stress)):
        raise MaterialError("nominal_stress", "must be finite")
    return lam, stress


def _points_for_fit(
    stretch: ArrayLike, nominal_stress: ArrayLike, max_strain: float, n_params: int
) -> tuple[np.ndarray, np.ndarray]:
    lam, stress = select_fit_points(stretch, nominal_stress, max_strain)
    if lam.size < n_params + 2:
        raise MaterialError(
            "max_strain",
            f"only {lam.size} usable points up to strain {max_strain:g}; need at least {n_params + 2}",
        )
    return lam, stress


def _fit_result(
    law: IsochoricI1Law,
    values: Sequence[float],
    lam: np.ndarray,
    stress: np.ndarray,
    max_strain: float,
    notes: tuple[str, ...],
    weighting: str,
) -> FitResult:
    residual = stress - law.uniaxial_nominal_stress(lam)
    rms = float(np.sqrt(np.mean(residual**2)))
    rms_rel = float(np.sqrt(np.mean((residual / stress) ** 2)))
    ss_tot = float(np.sum((stress - stress.mean()) ** 2))
    return FitResult(
        law=law,
        param_names=law.FIT_PARAMS,
        values=tuple(values),
        max_strain=float(max_strain),
        strain_range=(round(float(lam.min() - 1.0), 9), round(float(lam.max() - 1.0), 9)),
        n_points=int(lam.size),
        rms_error=rms,
        relative_rms_error=rms / float(np.sqrt(np.mean(stress**2))),
        r_squared=1.0 - float(np.sum(residual**2)) / ss_tot if ss_tot > 0.0 else float("nan"),
        notes=notes,
        weighting=weighting,
        rms_pointwise_relative_error=rms_rel,
    )
