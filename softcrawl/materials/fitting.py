"""Least-squares fits of incompressible hyperelastic laws to a uniaxial tensile test.

Both Neo-Hookean and Yeoh nominal stresses are linear in their constants (`materials.material`),
so `fit_neo_hookean` and `fit_yeoh` are linear least squares on the nominal stress. Gent is
linear in mu for a fixed Jm, so `fit_gent` is a one-dimensional search over Jm (> the largest
I1 - 3 of the data) around a linear least squares.

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

from softcrawl.materials.material import (
    DEFAULT_K_OVER_MU,
    Material,
    MaterialError,
    finite_number,
    gent_uniaxial,
    neo_hookean_uniaxial,
    yeoh_design_matrix,
    yeoh_is_stable,
    yeoh_uniaxial,
)
from softcrawl.materials.tensile import TensileData

FIT_MODELS = ("neo-hookean", "yeoh", "gent")
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
    """A least-squares fit of an incompressible hyperelastic model to uniaxial tension.

    `param_names`/`values` are the constants in MPa (``mu`` or ``C10, C20, C30``);
    `strain_range` is the (min, max) engineering strain of the points used, `max_strain` the
    requested upper bound; errors are on the nominal stress: `rms_error` [MPa],
    `relative_rms_error` = rms_error / RMS(measured stress), `r_squared` = 1 - SS_res / SS_tot.
    """

    model: str
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
    def params(self) -> dict[str, float]:
        return dict(zip(self.param_names, self.values))

    @property
    def initial_shear_modulus(self) -> float:
        """mu for Neo-Hookean and Gent, 2 C10 for Yeoh [MPa]."""
        return 2.0 * self.values[0] if self.model == "yeoh" else self.values[0]

    def predict(self, stretch: ArrayLike) -> np.ndarray:
        """Model nominal stress [MPa] at `stretch`."""
        if self.model == "neo-hookean":
            return neo_hookean_uniaxial(stretch, self.values[0])
        if self.model == "gent":
            return gent_uniaxial(stretch, *self.values)
        return yeoh_uniaxial(stretch, self.values)

    def to_material(
        self, *, name: str, density: float, source: str, k_over_mu: float = DEFAULT_K_OVER_MU
    ) -> Material:
        mu = self.initial_shear_modulus
        if self.model == "neo-hookean":
            return Material(
                name=name, model="neo-hookean", mu=mu, bulk=k_over_mu * mu, density=density, source=source
            )
        if self.model == "gent":
            return Material(
                name=name,
                model="gent",
                mu=mu,
                gent_jm=self.values[1],
                bulk=k_over_mu * mu,
                density=density,
                source=source,
            )
        return Material(
            name=name,
            model="yeoh",
            yeoh_c=tuple(self.values),
            bulk=k_over_mu * mu,
            density=density,
            source=source,
        )

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


def fit_neo_hookean(
    stretch: ArrayLike,
    nominal_stress: ArrayLike,
    max_strain: float = DEFAULT_MAX_STRAIN,
    weighting: str = "absolute",
) -> FitResult:
    """Fit mu of P = mu (lam - lam^-2) by linear least squares: mu = sum(g P) / sum(g^2).

    `stretch` = 1 + engineering strain, `nominal_stress` in MPa; points are chosen by
    `select_fit_points` (default strain range 0-`DEFAULT_MAX_STRAIN` = 0-100 %, stretch <= 2, the
    ePSA's operating range; see that constant for why not the whole curve).
    """
    lam, stress = _points_for_fit(stretch, nominal_stress, max_strain, n_params=1)
    g = lam - lam**-2
    w = _weights(stress, weighting)
    mu = float((w * g) @ (w * stress) / ((w * g) @ (w * g)))
    if mu <= 0.0:
        raise MaterialError("nominal_stress", f"fitted mu = {mu:g} MPa is not positive")
    return _fit_result("neo-hookean", ("mu",), (mu,), lam, stress, mu * g, max_strain, (), weighting)


def fit_yeoh(
    stretch: ArrayLike,
    nominal_stress: ArrayLike,
    max_strain: float = DEFAULT_MAX_STRAIN,
    stable: bool = True,
    weighting: str = "absolute",
) -> FitResult:
    """Fit (C10, C20, C30) of the incompressible uniaxial Yeoh law by linear least squares.

    P = 2 (lam - lam^-2)(C10 + 2 C20 (I1 - 3) + 3 C30 (I1 - 3)^2), I1 = lam^2 + 2/lam.

    Stability (`stable=True`, default): the unconstrained fit is kept if dW/dI1 > 0 for every
    I1 >= 3 (see `yeoh_is_stable`). Otherwise it is refitted with bounds C10 > 0, C30 >= 0 and C20
    free. A negative C20 is accepted (it captures the softening of the initial slope typical of
    silicones) as long as C20^2 < 3 C10 C30; if not, the fit is repeated with C20 >= 0 as well,
    which is always stable (a conservative choice, not the best stable fit). Each such step is
    recorded in `FitResult.notes`. With `stable=False` the unconstrained fit is returned as is,
    which may not be usable as a `Material` (on the shipped Ecoflex data C30 comes out < 0).
    """
    lam, stress = _points_for_fit(stretch, nominal_stress, max_strain, n_params=3)
    w = _weights(stress, weighting)[:, None]
    full_design = yeoh_design_matrix(lam)
    design, stress_w = full_design * w, stress * w[:, 0]
    coefficients = np.linalg.lstsq(design, stress_w, rcond=None)[0]
    notes: list[str] = []
    if stable and not yeoh_is_stable(coefficients):
        notes.append(
            f"unconstrained fit (C10, C20, C30) = ({', '.join(f'{c:.4g}' for c in coefficients)})"
            " is unstable at large strain; refitted with C10 > 0, C30 >= 0"
        )
        coefficients = _bounded_lstsq(design, stress_w, c20_min=-np.inf)
        if not yeoh_is_stable(coefficients):
            notes.append(f"C20 = {coefficients[1]:.4g} < 0 with C20^2 >= 3 C10 C30; refitted with C20 >= 0")
            coefficients = _bounded_lstsq(design, stress_w, c20_min=0.0)
    values = tuple(float(c) for c in coefficients)
    if values[0] <= 0.0:
        raise MaterialError("nominal_stress", f"fitted C10 = {values[0]:g} MPa is not positive")
    return _fit_result(
        "yeoh",
        ("C10", "C20", "C30"),
        values,
        lam,
        stress,
        full_design @ coefficients,
        max_strain,
        tuple(notes),
        weighting,
    )


def fit_gent(
    stretch: ArrayLike,
    nominal_stress: ArrayLike,
    max_strain: float = DEFAULT_MAX_STRAIN,
    weighting: str = "absolute",
) -> FitResult:
    """Fit (mu, Jm) of P = mu (lam - lam^-2) / (1 - x/Jm), x = lam^2 + 2/lam - 3.

    For each Jm the best mu is a linear least squares; Jm is searched (bounded scalar search on
    log Jm) between 1.0001 x_max (the data's largest x: Gent is undefined past Jm) and 1e6 (where
    Gent is Neo-Hookean to within x_max/1e6)."""
    from scipy.optimize import minimize_scalar

    lam, stress = _points_for_fit(stretch, nominal_stress, max_strain, n_params=2)
    w = _weights(stress, weighting)
    x = lam**2 + 2.0 / lam - 3.0
    g = lam - lam**-2

    def best_mu(jm: float) -> tuple[float, float]:
        a = w * g / (1.0 - x / jm)
        mu = float(a @ (w * stress) / (a @ a))
        return mu, float(np.sum((mu * a - w * stress) ** 2))

    lo, hi = np.log(1.0001 * x.max()), np.log(1e6)
    found = minimize_scalar(lambda t: best_mu(np.exp(t))[1], bounds=(lo, hi), method="bounded")
    jm = float(np.exp(found.x))
    mu = best_mu(jm)[0]
    if mu <= 0.0:
        raise MaterialError("nominal_stress", f"fitted mu = {mu:g} MPa is not positive")
    predicted = mu * g / (1.0 - x / jm)
    return _fit_result("gent", ("mu", "Jm"), (mu, jm), lam, stress, predicted, max_strain, (), weighting)


def fit_tensile(
    data: TensileData,
    model: str = "neo-hookean",
    max_strain: float = DEFAULT_MAX_STRAIN,
    weighting: str = "absolute",
) -> FitResult:
    """Fit `model` ('neo-hookean', 'yeoh' or 'gent') to a loaded tensile test."""
    if model == "neo-hookean":
        return fit_neo_hookean(data.stretch, data.nominal_stress, max_strain, weighting)
    if model == "yeoh":
        return fit_yeoh(data.stretch, data.nominal_stress, max_strain, weighting=weighting)
    if model == "gent":
        return fit_gent(data.stretch, data.nominal_stress, max_strain, weighting)
    raise MaterialError("model", f"unknown fit model {model!r}; valid: {', '.join(FIT_MODELS)}")


def _weights(stress: np.ndarray, weighting: str) -> np.ndarray:
    """1 (absolute residuals) or 1/stress (relative residuals; the stresses are > 0 here)."""
    if weighting == "absolute":
        return np.ones_like(stress)
    if weighting == "relative":
        return 1.0 / stress
    raise MaterialError("weighting", f"unknown weighting {weighting!r}; valid: {', '.join(WEIGHTINGS)}")


def _bounded_lstsq(design: np.ndarray, stress: np.ndarray, c20_min: float) -> np.ndarray:
    from scipy.optimize import lsq_linear

    # C10 > 0 strictly: a tiny positive floor far below any elastomer's modulus.
    lower = [1e-12, c20_min, 0.0]
    upper = [np.inf, np.inf, np.inf]
    return lsq_linear(design, stress, bounds=(lower, upper), method="bvls").x


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
    model: str,
    names: tuple[str, ...],
    values: Sequence[float],
    lam: np.ndarray,
    stress: np.ndarray,
    predicted: np.ndarray,
    max_strain: float,
    notes: tuple[str, ...],
    weighting: str,
) -> FitResult:
    residual = stress - predicted
    rms = float(np.sqrt(np.mean(residual**2)))
    rms_rel = float(np.sqrt(np.mean((residual / stress) ** 2)))
    ss_tot = float(np.sum((stress - stress.mean()) ** 2))
    return FitResult(
        model=model,
        param_names=names,
        values=values,
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
