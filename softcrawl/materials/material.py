"""Isotropic materials of the robot's parts, validated on construction.

Units are the project's: mm, N, MPa (= N/mm^2), s, tonne. Density is in t/mm^3
(1.07 g/cm^3 = 1.07e-9 t/mm^3). Stretch is dimensionless.

Constitutive models
-------------------
``neo-hookean`` (compressible, for the FE solver)::

    W = mu/2 (I1_bar - 3) + K/2 (J - 1)^2,   I1_bar = J^(-2/3) tr(C)

``yeoh``::

    W = C10 (I1_bar - 3) + C20 (I1_bar - 3)^2 + C30 (I1_bar - 3)^3 + K/2 (J - 1)^2

with initial shear modulus mu = 2 C10. ``gent`` (initial shear modulus mu, locking parameter Jm)::

    W = -mu Jm / 2 ln(1 - (I1_bar - 3) / Jm) + K/2 (J - 1)^2

``linear-elastic`` (ABS rings, Kevlar fiber trusses) is given
by Young's modulus E and Poisson's ratio nu; mu and K follow from

    mu = E / (2 (1 + nu)),   K = E / (3 (1 - 2 nu)).

For every model the small-strain constants are related by

    lambda = K - 2 mu / 3,   E = 9 K mu / (3 K + mu),   nu = (3 K - 2 mu) / (2 (3 K + mu)).

Nearly incompressible solids default to K = 1000 mu (docs/decisions/001-materials.md: K/mu >= 1000),
i.e. nu = 0.4995: the volume change under the actuator's stresses stays below about 0.1 %, which is
incompressible for every purpose of this project, while the real bulk modulus of silicone
(K ~ 1 GPa, K/mu ~ 10^4-10^5) would make the stiffness matrix badly conditioned and aggravate
volumetric locking of displacement elements for no gain in accuracy.

Uniaxial tension of an incompressible solid: with stretch lam = 1 + engineering strain and
I1 = lam^2 + 2/lam, the nominal (engineering) stress P = force / undeformed area is

    Neo-Hookean:  P = mu (lam - lam^-2)
    Yeoh:         P = 2 (lam - lam^-2) (C10 + 2 C20 (I1 - 3) + 3 C30 (I1 - 3)^2)
    Gent:         P = mu (lam - lam^-2) / (1 - (I1 - 3) / Jm)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.checks import brief
from softcrawl.errors import InputError

MODELS = ("neo-hookean", "yeoh", "gent", "linear-elastic")
HYPERELASTIC_MODELS = ("neo-hookean", "yeoh", "gent")

#: Default bulk-to-shear modulus ratio of the nearly incompressible solids (nu = 0.4995).
DEFAULT_K_OVER_MU = 1000.0

#: Largest density accepted (t/mm^3): 100 g/cm^3, four times the densest element (osmium,
#: 22.6 g/cm^3); a larger value is almost surely given in g/cm^3 or kg/m^3.
MAX_DENSITY = 1.0e-7
#: Largest modulus accepted (MPa), for mu, K, E and the Yeoh constants: 1e6 MPa = 1 TPa, the Young's
#: modulus of diamond, the stiffest bulk solid. Larger values are unit mistakes (Pa for MPa).
MAX_MODULUS = 1.0e6


class MaterialError(InputError):
    """Bad material input; `parameter` names the offending field or argument."""


# --------------------------------------------------------------------------------------------
# Small-strain relations
# --------------------------------------------------------------------------------------------


def shear_modulus_from_youngs(youngs: float, poisson: float) -> float:
    """mu = E / (2 (1 + nu)) [MPa]."""
    return youngs / (2.0 * (1.0 + poisson))


def bulk_modulus_from_youngs(youngs: float, poisson: float) -> float:
    """K = E / (3 (1 - 2 nu)) [MPa]."""
    return youngs / (3.0 * (1.0 - 2.0 * poisson))


def shear_modulus_nearly_incompressible(youngs: float, k_over_mu: float = DEFAULT_K_OVER_MU) -> float:
    """mu such that E = 9 K mu / (3 K + mu) with K = k_over_mu * mu: mu = E (3k + 1) / (9k)."""
    return youngs * (3.0 * k_over_mu + 1.0) / (9.0 * k_over_mu)


def shore_a_to_youngs(shore_a: float) -> float:
    """Young's modulus [MPa] from Shore A hardness by Gent's relation (Gent 1958):

        E = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S))   [MPa]

    An empirical fit for rubbers, most trustworthy between about 40A and 90A; it diverges at
    S = 100. Shore 70A gives E = 5.52 MPa.
    """
    s = finite_number(shore_a, "shore_a")
    if not 0.0 <= s < 100.0:
        raise MaterialError("shore_a", f"Shore A hardness must be in [0, 100), got {s:g}")
    return 0.0981 * (56.0 + 7.62336 * s) / (0.137505 * (254.0 - 2.54 * s))


# --------------------------------------------------------------------------------------------
# Material
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class Material:
    """An isotropic material, validated on construction.

    Give ``mu`` (and optionally ``bulk``, default ``DEFAULT_K_OVER_MU * mu``) for
    ``neo-hookean``; ``yeoh_c = (C10, C20, C30)`` for ``yeoh`` (``mu`` is then 2 C10);
    ``mu`` and ``gent_jm`` for ``gent``;
    ``youngs`` and ``poisson`` for ``linear-elastic`` (``mu`` and ``bulk`` are derived). After
    construction ``mu`` and ``bulk`` are always set. Moduli in MPa, density in t/mm^3.
    """

    name: str
    model: str
    density: float
    mu: float | None = None
    bulk: float | None = None
    yeoh_c: tuple[float, float, float] | None = None
    gent_jm: float | None = None
    youngs: float | None = None
    poisson: float | None = None
    source: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise MaterialError("name", "must be a non-empty string")
        if self.model not in MODELS:
            raise MaterialError("model", f"unknown model {self.model!r}; valid: {', '.join(MODELS)}")
        density = finite_number(self.density, "density")
        if density <= 0.0:
            raise MaterialError("density", f"must be > 0 t/mm^3, got {density:g}")
        if density > MAX_DENSITY:
            raise MaterialError(
                "density",
                f"{density:g} t/mm^3 is implausible; density is in t/mm^3 (1.07 g/cm^3 = 1.07e-9 t/mm^3)",
            )
        if not isinstance(self.source, str):
            raise MaterialError("source", "must be a string")
        if self.model == "linear-elastic":
            mu, bulk = self._linear_elastic_moduli()
        else:
            mu, bulk = self._hyperelastic_moduli()
        object.__setattr__(self, "density", density)
        object.__setattr__(self, "mu", mu)
        object.__setattr__(self, "bulk", bulk)

    def _linear_elastic_moduli(self) -> tuple[float, float]:
        if self.yeoh_c is not None:
            raise MaterialError("yeoh_c", "only for model 'yeoh'")
        if self.gent_jm is not None:
            raise MaterialError("gent_jm", "only for model 'gent'")
        if self.youngs is None:
            raise MaterialError("youngs", "required for model 'linear-elastic'")
        if self.poisson is None:
            raise MaterialError("poisson", "required for model 'linear-elastic'")
        youngs = modulus(self.youngs, "youngs")
        poisson = finite_number(self.poisson, "poisson")
        if not -1.0 < poisson < 0.5:
            raise MaterialError("poisson", f"must be in (-1, 0.5), got {poisson:g}")
        object.__setattr__(self, "youngs", youngs)
        object.__setattr__(self, "poisson", poisson)
        mu = shear_modulus_from_youngs(youngs, poisson)
        bulk = bulk_modulus_from_youngs(youngs, poisson)
        _check_consistent(self.mu, mu, "mu")
        _check_consistent(self.bulk, bulk, "bulk")
        return mu, bulk

    def _hyperelastic_moduli(self) -> tuple[float, float]:
        for field_name in ("youngs", "poisson"):
            if getattr(self, field_name) is not None:
                raise MaterialError(
                    field_name,
                    f"only for model 'linear-elastic'; give mu (and bulk) for model {self.model!r}",
                )
        if self.model == "yeoh":
            coefficients = _yeoh_coefficients(self.yeoh_c)
            object.__setattr__(self, "yeoh_c", coefficients)
            mu = 2.0 * coefficients[0]
            _check_consistent(self.mu, mu, "mu")
        else:
            if self.yeoh_c is not None:
                raise MaterialError("yeoh_c", "only for model 'yeoh'")
            if self.model == "gent":
                jm = finite_number(self.gent_jm, "gent_jm") if self.gent_jm is not None else None
                if jm is None or jm <= 0.0:
                    raise MaterialError("gent_jm", f"model 'gent' needs a locking parameter Jm > 0, got {jm}")
                object.__setattr__(self, "gent_jm", jm)
            elif self.gent_jm is not None:
                raise MaterialError("gent_jm", "only for model 'gent'")
            if self.mu is None:
                raise MaterialError("mu", f"required for model {self.model!r}")
            mu = modulus(self.mu, "mu")
        if mu > MAX_MODULUS:  # 2 C10 of a Yeoh law
            raise MaterialError("yeoh_c", f"2 C10 = {mu:g} MPa exceeds {MAX_MODULUS:g} MPa")
        bulk = DEFAULT_K_OVER_MU * mu if self.bulk is None else finite_number(self.bulk, "bulk")
        if bulk <= 0.0:
            raise MaterialError("bulk", f"must be > 0 MPa, got {bulk:g}")
        if bulk > DEFAULT_K_OVER_MU * MAX_MODULUS:
            raise MaterialError("bulk", f"must be <= {DEFAULT_K_OVER_MU * MAX_MODULUS:g} MPa, got {bulk:g}")
        if bulk < 2.0 * mu / 3.0:
            raise MaterialError(
                "bulk",
                f"K/mu = {bulk / mu:g} < 2/3 gives a negative Poisson "
                f"ratio; nearly incompressible solids use K/mu >= 1000",
            )
        return mu, bulk

    # -- derived constants (small strain) ------------------------------------------------------

    @property
    def lame_lambda(self) -> float:
        """First Lame parameter lambda = K - 2 mu / 3 [MPa]."""
        return self.bulk - 2.0 * self.mu / 3.0

    @property
    def youngs_modulus(self) -> float:
        """Small-strain Young's modulus E = 9 K mu / (3 K + mu) [MPa]."""
        return 9.0 * self.bulk * self.mu / (3.0 * self.bulk + self.mu)

    @property
    def poisson_ratio(self) -> float:
        """Small-strain Poisson ratio nu = (3 K - 2 mu) / (2 (3 K + mu))."""
        return (3.0 * self.bulk - 2.0 * self.mu) / (2.0 * (3.0 * self.bulk + self.mu))

    @property
    def k_over_mu(self) -> float:
        """Bulk-to-shear modulus ratio K / mu."""
        return self.bulk / self.mu

    @property
    def is_hyperelastic(self) -> bool:
        return self.model in HYPERELASTIC_MODELS

    @property
    def law_label(self) -> str:
        """The constitutive law and its constants in one line (every study and row names it)."""
        if self.model == "yeoh":
            c = ", ".join(f"{v:.4g}" for v in self.yeoh_c)
            return f"Yeoh (C10, C20, C30) = ({c}) MPa"
        if self.model == "gent":
            return f"Gent mu = {self.mu:.4g} MPa, Jm = {self.gent_jm:.4g}"
        if self.model == "neo-hookean":
            return f"Neo-Hookean mu = {self.mu:.4g} MPa"
        return f"linear elastic E = {self.youngs:.4g} MPa, nu = {self.poisson:.3g}"

    def with_mu(self, mu: float) -> Material:
        """A copy with shear modulus `mu` [MPa] and everything else scaled along.

        K/mu is kept (so the compressibility, nu, is unchanged); for Yeoh all three constants are
        scaled by mu_new / mu_old (same curve shape); for linear-elastic E is scaled and nu kept.
        The source text records the change. Used for calibration studies.
        """
        new_mu = modulus(mu, "mu")
        scale = new_mu / self.mu
        note = f"{self.source}; mu rescaled {self.mu:.6g} -> {new_mu:.6g} MPa (K/mu kept)"
        if self.model == "linear-elastic":
            return dataclasses.replace(self, youngs=self.youngs * scale, mu=None, bulk=None, source=note)
        if self.model == "yeoh":
            return dataclasses.replace(
                self,
                yeoh_c=tuple(c * scale for c in self.yeoh_c),
                mu=None,
                bulk=self.bulk * scale,
                source=note,
            )
        return dataclasses.replace(self, mu=new_mu, bulk=self.bulk * scale, source=note)

    def uniaxial_nominal_stress(self, stretch: ArrayLike) -> np.ndarray:
        """Nominal stress [MPa] in incompressible uniaxial tension (hyperelastic models only)."""
        if self.model == "neo-hookean":
            return neo_hookean_uniaxial(stretch, self.mu)
        if self.model == "yeoh":
            return yeoh_uniaxial(stretch, self.yeoh_c)
        if self.model == "gent":
            return gent_uniaxial(stretch, self.mu, self.gent_jm)
        raise MaterialError("model", "uniaxial_nominal_stress is for hyperelastic models")

    def to_dict(self) -> dict:
        """Fields plus derived constants, JSON-ready (units: MPa, t/mm^3)."""
        record = dataclasses.asdict(self)
        if record["yeoh_c"] is not None:
            record["yeoh_c"] = list(record["yeoh_c"])
        record.update(
            youngs_modulus=self.youngs_modulus,
            poisson_ratio=self.poisson_ratio,
            lame_lambda=self.lame_lambda,
            k_over_mu=self.k_over_mu,
        )
        return record


def finite_number(value: object, parameter: str) -> float:
    """`value` as a finite float (numbers and numeric strings), or a `MaterialError`; the moduli
    are bounded by `MAX_MODULUS` in magnitude (a larger number is a unit mistake)."""
    if isinstance(value, bool):
        raise MaterialError(parameter, f"must be a number, got {value!r}")
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        raise MaterialError(parameter, f"must be a finite number, got {brief(value)}") from None
    if not math.isfinite(number):
        raise MaterialError(parameter, f"must be finite, got {number!r}")
    return number


def modulus(value: object, parameter: str) -> float:
    """A modulus in (0, MAX_MODULUS] MPa."""
    number = finite_number(value, parameter)
    if not 0.0 < number <= MAX_MODULUS:
        raise MaterialError(parameter, f"must be in (0, {MAX_MODULUS:g}] MPa, got {number:g}")
    return number


def _check_consistent(given: object, derived: float, parameter: str) -> None:
    """A redundant field may be given only if it equals the derived value."""
    if given is None:
        return
    value = finite_number(given, parameter)
    if not math.isclose(value, derived, rel_tol=1e-9):
        raise MaterialError(
            parameter,
            f"{value:g} contradicts the value {derived:g} derived from the other constants; leave it out",
        )


def _yeoh_coefficients(yeoh_c: Sequence[float] | None) -> tuple[float, float, float]:
    """Validate (C10, C20, C30): C10 > 0 and dW/dI1 > 0 for every I1 >= 3.

    dW/dI1 = C10 + 2 C20 x + 3 C30 x^2 with x = I1 - 3 >= 0 stays positive for all x iff
    C30 >= 0 and (C20 >= 0 or C20^2 < 3 C10 C30). Otherwise the model loses stability (the
    uniaxial stress turns down) at some finite stretch, which a path-following solver would find.
    """
    if yeoh_c is None:
        raise MaterialError("yeoh_c", "required for model 'yeoh': (C10, C20, C30) in MPa")
    try:
        values = tuple(yeoh_c)
    except TypeError:
        raise MaterialError("yeoh_c", f"must be a sequence (C10, C20, C30), got {yeoh_c!r}") from None
    if len(values) != 3:
        raise MaterialError("yeoh_c", f"needs 3 constants (C10, C20, C30), got {len(values)}")
    c10, c20, c30 = (finite_number(v, "yeoh_c") for v in values)
    if max(abs(c10), abs(c20), abs(c30)) > MAX_MODULUS:
        raise MaterialError("yeoh_c", f"constants must be within +-{MAX_MODULUS:g} MPa")
    if c10 <= 0.0:
        raise MaterialError("yeoh_c", f"initial shear modulus 2 C10 must be > 0, got C10 = {c10:g}")
    if not yeoh_is_stable((c10, c20, c30)):
        raise MaterialError(
            "yeoh_c",
            f"(C10, C20, C30) = ({c10:g}, {c20:g}, {c30:g}) is unstable: "
            "dW/dI1 turns negative at large strain (need C30 >= 0 and "
            "C20 >= 0 or C20^2 < 3 C10 C30)",
        )
    return (c10, c20, c30)


def yeoh_is_stable(yeoh_c: Sequence[float]) -> bool:
    """True if dW/dI1 = C10 + 2 C20 x + 3 C30 x^2 > 0 for all x = I1 - 3 >= 0."""
    c10, c20, c30 = yeoh_c
    return c10 > 0.0 and c30 >= 0.0 and (c20 >= 0.0 or c20 * c20 < 3.0 * c10 * c30)


# --------------------------------------------------------------------------------------------
# Uniaxial response of the incompressible models
# --------------------------------------------------------------------------------------------


def neo_hookean_uniaxial(stretch: ArrayLike, mu: float) -> np.ndarray:
    """Nominal stress P = mu (lam - lam^-2) [MPa], incompressible uniaxial tension."""
    lam = np.asarray(stretch, dtype=float)
    return mu * (lam - lam**-2)


def yeoh_uniaxial(stretch: ArrayLike, yeoh_c: Sequence[float]) -> np.ndarray:
    """Nominal stress P = 2 (lam - lam^-2)(C10 + 2 C20 x + 3 C30 x^2), x = lam^2 + 2/lam - 3."""
    lam = np.asarray(stretch, dtype=float)
    return yeoh_design_matrix(lam) @ np.asarray(yeoh_c, dtype=float)


def gent_uniaxial(stretch: ArrayLike, mu: float, jm: float) -> np.ndarray:
    """Nominal stress P = mu (lam - lam^-2) / (1 - x/Jm), x = lam^2 + 2/lam - 3 (x < Jm)."""
    lam = np.asarray(stretch, dtype=float)
    return mu * (lam - lam**-2) / (1.0 - (lam**2 + 2.0 / lam - 3.0) / jm)


def yeoh_design_matrix(lam: np.ndarray) -> np.ndarray:
    x = lam**2 + 2.0 / lam - 3.0
    g = 2.0 * (lam - lam**-2)
    return np.column_stack([g, 2.0 * g * x, 3.0 * g * x**2])
