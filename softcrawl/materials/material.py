"""Isotropic materials of the robot's parts: a name, a constitutive law, a density, a source.

Units are the project's: mm, N, MPa (= N/mm^2), s, tonne. Density is in t/mm^3
(1.07 g/cm^3 = 1.07e-9 t/mm^3). Stretch is dimensionless.

Constitutive laws
-----------------
A `Material` holds a law object. The hyperelastic laws are the solver's own, one module each in
`fem.laws` (registry `fem.laws.LAWS`: Neo-Hookean, Yeoh, Gent; each states its energy, uniaxial
stress, validity and fit), e.g. ``Material(name=..., law=Yeoh.nearly_incompressible(c10, c20,
c30), density=...)``. `LinearElastic` (ABS rings, Kevlar fiber trusses, here) is given by Young's
modulus E and Poisson's ratio nu; mu and K follow from

    mu = E / (2 (1 + nu)),   K = E / (3 (1 - 2 nu)).

For every law the small-strain constants are related by

    lambda = K - 2 mu / 3,   E = 9 K mu / (3 K + mu),   nu = (3 K - 2 mu) / (2 (3 K + mu)).

Nearly incompressible solids default to K = 1000 mu (docs/decisions/001-materials.md: K/mu >= 1000),
i.e. nu = 0.4995: the volume change under the actuator's stresses stays below about 0.1 %, which is
incompressible for every purpose of this project, while the real bulk modulus of silicone
(K ~ 1 GPa, K/mu ~ 10^4-10^5) would make the stiffness matrix badly conditioned and aggravate
volumetric locking of displacement elements for no gain in accuracy.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.checks import brief
from softcrawl.errors import InputError
from softcrawl.fem.laws import DEFAULT_K_OVER_MU, IsochoricI1Law, NeoHookean, with_mu

#: Largest density accepted (t/mm^3): 100 g/cm^3, four times the densest element (osmium,
#: 22.6 g/cm^3); a larger value is almost surely given in g/cm^3 or kg/m^3.
MAX_DENSITY = 1.0e-7
#: Largest modulus accepted (MPa), for mu, K, E and the Yeoh constants: 1e6 MPa = 1 TPa, the Young's
#: modulus of diamond, the stiffest bulk solid. Larger values are unit mistakes (Pa for MPa).
MAX_MODULUS = 1.0e6
#: The law constants of a material's record (`Material.to_dict`, `softcrawl material show`), in
#: their order; None where the law has no such constant (a new law's constants follow them).
RECORD_CONSTANTS = ("yeoh_c", "gent_jm", "youngs", "poisson")


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
class LinearElastic:
    """Small-strain isotropic elasticity by Young's modulus `youngs` (MPa) and Poisson's ratio
    `poisson` (ABS rings, Kevlar fiber trusses); `mu` and `bulk` follow (module docstring)."""

    NAME: ClassVar[str] = "linear-elastic"
    MODULI: ClassVar[tuple[str, ...]] = ("youngs",)
    youngs: float
    poisson: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "youngs", modulus(self.youngs, "youngs"))
        poisson = finite_number(self.poisson, "poisson")
        if not -1.0 < poisson < 0.5:
            raise MaterialError("poisson", f"must be in (-1, 0.5), got {poisson:g}")
        object.__setattr__(self, "poisson", poisson)

    @property
    def mu(self) -> float:
        return shear_modulus_from_youngs(self.youngs, self.poisson)

    @property
    def bulk(self) -> float:
        return bulk_modulus_from_youngs(self.youngs, self.poisson)

    @property
    def label(self) -> str:
        return f"linear elastic E = {self.youngs:.4g} MPa, nu = {self.poisson:.3g}"

    def record(self) -> dict:
        return {"youngs": self.youngs, "poisson": self.poisson}

    def solver_law(self) -> NeoHookean:
        """The FE solver's law: a Neo-Hookean solid with the small-strain mu and K, which agrees
        with linear elasticity at the strains of a stiff part (~1e-4 at 100 kPa)."""
        return NeoHookean(mu=self.mu, bulk=self.bulk)


@dataclass(frozen=True, kw_only=True)
class Material:
    """An isotropic material, validated on construction: `law` is a hyperelastic law of
    `fem.laws` (e.g. ``NeoHookean.nearly_incompressible(0.03)``, K = 1000 mu) or a
    `LinearElastic`; `mu` and `bulk` are the law's. Moduli in MPa, density in t/mm^3.
    """

    name: str
    law: IsochoricI1Law | LinearElastic
    density: float
    source: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise MaterialError("name", "must be a non-empty string")
        if not isinstance(self.law, (IsochoricI1Law, LinearElastic)):
            raise MaterialError("law", f"must be a law of fem.laws or a LinearElastic, got {brief(self.law)}")
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
        for name in self.law.MODULI:  # a larger value is a unit mistake (Pa for MPa)
            limit = DEFAULT_K_OVER_MU * MAX_MODULUS if name == "bulk" else MAX_MODULUS
            if abs(getattr(self.law, name)) > limit:
                raise MaterialError(name, f"must be within +-{limit:g} MPa, got {getattr(self.law, name):g}")
        if self.law.mu > MAX_MODULUS:
            raise MaterialError("mu", f"shear modulus {self.law.mu:g} MPa exceeds {MAX_MODULUS:g} MPa")
        object.__setattr__(self, "density", density)

    # -- the law's constants ---------------------------------------------------------------

    @property
    def model(self) -> str:
        """The law's registry name ('neo-hookean', 'yeoh', 'gent', 'linear-elastic')."""
        return self.law.NAME

    @property
    def mu(self) -> float:
        """Initial shear modulus [MPa]."""
        return self.law.mu

    @property
    def bulk(self) -> float:
        """Bulk modulus K [MPa]."""
        return self.law.bulk

    @property
    def is_hyperelastic(self) -> bool:
        return isinstance(self.law, IsochoricI1Law)

    @property
    def law_label(self) -> str:
        """The constitutive law and its constants in one line (every study and row names it)."""
        return self.law.label

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

    def with_mu(self, mu: float) -> Material:
        """A copy with shear modulus `mu` [MPa] and every modulus of the law scaled along
        (`fem.laws.with_mu`): K/mu and the curve's shape are kept (Yeoh: all three constants
        scaled; Gent: Jm kept; linear elastic: E scaled, nu kept). The source text records the
        change. Used for calibration studies.
        """
        new_mu = modulus(mu, "mu")
        note = f"{self.source}; mu rescaled {self.mu:.6g} -> {new_mu:.6g} MPa (K/mu kept)"
        return dataclasses.replace(self, law=with_mu(self.law, new_mu), source=note)

    def uniaxial_nominal_stress(self, stretch: ArrayLike) -> np.ndarray:
        """Nominal stress [MPa] in incompressible uniaxial tension (hyperelastic laws only)."""
        if not self.is_hyperelastic:
            raise MaterialError("model", "uniaxial_nominal_stress is for hyperelastic laws")
        return self.law.uniaxial_nominal_stress(stretch)

    def to_dict(self) -> dict:
        """Name, law and constants (`RECORD_CONSTANTS`), source and derived constants, JSON-ready
        (units: MPa, t/mm^3)."""
        record = {"name": self.name, "model": self.model, "density": self.density}
        record.update(mu=self.mu, bulk=self.bulk, **dict.fromkeys(RECORD_CONSTANTS))
        record.update(self.law.record())
        record.update(
            source=self.source,
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
