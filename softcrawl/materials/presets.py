"""Material presets of the robot's parts, each with its source, and `NAME@mu=VALUE` overrides."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from softcrawl.checks import brief
from softcrawl.fem.laws import NeoHookean
from softcrawl.materials.fitting import DEFAULT_MAX_STRAIN, FULL_RANGE_STRAIN, fit_tensile
from softcrawl.materials.material import (
    LinearElastic,
    Material,
    MaterialError,
    shear_modulus_nearly_incompressible,
    shore_a_to_youngs,
)
from softcrawl.materials.tensile import DATA_ATTRIBUTION, DATA_LICENSE, TENSILE_FILES, load_tensile

_G_PER_CM3 = 1.0e-9  # t/mm^3 per g/cm^3

#: Densities [t/mm^3]. Smooth-On technical bulletins give specific gravity 1.07 (Ecoflex 00-30,
#: 00-50) and 1.08 (Dragon Skin 30). The datasheet numbers quoted in the preset sources are from
#: the bulletins as the author knows them, not re-checked against the current editions.
_SILICONE_DENSITY = {
    "ecoflex-00-50": 1.07 * _G_PER_CM3,
    "ecoflex-00-30": 1.07 * _G_PER_CM3,
    "dragon-skin-30": 1.08 * _G_PER_CM3,
}


def _ecoflex_00_50() -> Material:
    return Material(
        name="ecoflex-00-50",
        law=NeoHookean.nearly_incompressible(0.030),
        density=_SILICONE_DENSITY["ecoflex-00-50"],
        source="docs/decisions/001-materials.md default mu = 0.030 MPa (literature 0.022-0.047 MPa; "
        "Smooth-On TDS (not re-checked) 100 % modulus 12 psi = 0.083 MPa -> NH secant mu = 0.047 MPa); "
        "SG 1.07 (Smooth-On TDS)",
    )


def _ecoflex_00_30() -> Material:
    return Material(
        name="ecoflex-00-30",
        law=NeoHookean.nearly_incompressible(0.018),
        density=_SILICONE_DENSITY["ecoflex-00-30"],
        source="literature mu ~ 0.0125-0.023 MPa, mid value 0.018 MPa (SRMD tensile fit 0-100 % "
        "gives 0.016 MPa; Smooth-On TDS (not re-checked) 100 % modulus 10 psi = 0.069 MPa -> NH secant "
        "0.039 MPa, an upper bound); SG 1.07 (Smooth-On TDS)",
    )


def _dragon_skin_30() -> Material:
    return Material(
        name="dragon-skin-30",
        law=NeoHookean.nearly_incompressible(0.20),
        density=_SILICONE_DENSITY["dragon-skin-30"],
        source="literature mu ~ 0.1-0.2 MPa, upper value 0.20 MPa since the SRMD tensile fit "
        "0-100 % gives 0.22 MPa (0-50 %: 0.19 MPa; Smooth-On TDS (not re-checked) 100 % modulus 86 psi = "
        "0.59 MPa -> NH secant 0.34 MPa); SG 1.08 (Smooth-On TDS)",
    )


def _printed_rubber(shore_a: float) -> Material:
    """The feet's 3D-printed rubber of hardness `shore_a` (paper Fig. 21 tests 50A-70A)."""
    youngs = shore_a_to_youngs(shore_a)
    return Material(
        name=f"rubber-{shore_a:g}a",
        law=NeoHookean.nearly_incompressible(shear_modulus_nearly_incompressible(youngs)),
        density=1.15 * _G_PER_CM3,
        source=f"3D-printed rubber foot, Shore {shore_a:g}A: E = {youngs:.3f} MPa by Gent's relation "
        "(docs/decisions/001-materials.md), mu from E with K = 1000 mu; density 1.15 g/cm^3 assumed "
        "(typical of rubber-like PolyJet photopolymers, not measured)",
    )


def _abs() -> Material:
    return Material(
        name="abs",
        law=LinearElastic(youngs=2000.0, poisson=0.35),
        density=1.04 * _G_PER_CM3,
        source="docs/decisions/001-materials.md (rings, seal heads): E = 2000 MPa, nu = 0.35; density "
        "1.04 g/cm^3 (typical ABS)",
    )


def _kevlar() -> Material:
    return Material(
        name="kevlar",
        law=LinearElastic(youngs=31067.0, poisson=0.36),
        density=1.44 * _G_PER_CM3,
        source="docs/decisions/001-materials.md fiber thread E = 31067 MPa (for a truss; diameter 0.3 mm "
        "is a geometry parameter); nu = 0.36 nominal (Kevlar 49), unused by truss elements; "
        "density 1.44 g/cm^3 (Kevlar 49)",
    )


@functools.cache
def _fitted(data_name: str) -> Material:
    """Neo-Hookean fit at the default strain range, computed at first use and cached."""
    data = load_tensile(data_name)
    fit = fit_tensile(data, "neo-hookean", DEFAULT_MAX_STRAIN)
    source = (
        f"Neo-Hookean least-squares fit to SRMD uniaxial tensile data ({TENSILE_FILES[data_name]}), "
        f"engineering strain {fit.strain_range[0]:.3f}-{fit.strain_range[1]:.3f}, "
        f"{fit.n_points} points, RMS error {fit.rms_error:.2g} MPa "
        f"({100 * fit.relative_rms_error:.1f} %); crosshead strain tends to under-estimate "
        f"stiffness. {DATA_ATTRIBUTION} {DATA_LICENSE}"
    )
    return fit.to_material(name=f"{data_name}-fit", density=_SILICONE_DENSITY[data_name], source=source)


@functools.cache
def _fitted_full_range(data_name: str, model: str) -> Material:
    """A fit of the law `model` (Yeoh or Gent) over the whole pull-to-failure curve with relative residuals
    (`materials.fitting` says why), computed at first use and cached."""
    data = load_tensile(data_name)
    fit = fit_tensile(data, model, FULL_RANGE_STRAIN, weighting="relative")
    working = fit_tensile(data, "neo-hookean", DEFAULT_MAX_STRAIN)
    lam = data.stretch[(data.stretch > 1.0) & (data.stretch <= 1.0 + DEFAULT_MAX_STRAIN)]
    measured = data.nominal_stress[(data.stretch > 1.0) & (data.stretch <= 1.0 + DEFAULT_MAX_STRAIN)]
    keep = measured > 0.0
    low = float(np.sqrt(np.mean(((fit.predict(lam[keep]) - measured[keep]) / measured[keep]) ** 2)))
    constants = ", ".join(f"{k} = {v:.4g}" for k, v in fit.params.items())
    source = (
        f"{model.capitalize()} least-squares fit (relative residuals) to SRMD uniaxial tensile data "
        f"({TENSILE_FILES[data_name]}) over its full range, engineering strain "
        f"{fit.strain_range[0]:.3f}-{fit.strain_range[1]:.2f}, {fit.n_points} points: {constants} "
        f"(MPa); RMS relative error {100 * fit.rms_pointwise_relative_error:.1f} % over the range, "
        f"{100 * low:.1f} % over strain 0-{DEFAULT_MAX_STRAIN:g} (where the Neo-Hookean fit "
        f"mu = {working.values[0]:.4g} MPa has {100 * working.relative_rms_error:.1f} % of RMS "
        f"stress). {DATA_ATTRIBUTION} {DATA_LICENSE}"
    )
    return fit.to_material(name=f"{data_name}-{model}", density=_SILICONE_DENSITY[data_name], source=source)


PRESETS: dict[str, Callable[[], Material]] = {
    "ecoflex-00-50": _ecoflex_00_50,
    "ecoflex-00-50-fit": functools.partial(_fitted, "ecoflex-00-50"),
    "ecoflex-00-50-yeoh": functools.partial(_fitted_full_range, "ecoflex-00-50", "yeoh"),
    "ecoflex-00-50-gent": functools.partial(_fitted_full_range, "ecoflex-00-50", "gent"),
    "ecoflex-00-30": _ecoflex_00_30,
    "ecoflex-00-30-fit": functools.partial(_fitted, "ecoflex-00-30"),
    "dragon-skin-30": _dragon_skin_30,
    "dragon-skin-30-fit": functools.partial(_fitted, "dragon-skin-30"),
    "rubber-70a": functools.partial(_printed_rubber, 70.0),
    "rubber-60a": functools.partial(_printed_rubber, 60.0),
    "rubber-50a": functools.partial(_printed_rubber, 50.0),
    "abs": _abs,
    "kevlar": _kevlar,
}


def material_names() -> tuple[str, ...]:
    """Names of the presets, in registry order."""
    return tuple(PRESETS)


#: Range of the shear modulus of a `NAME@mu=VALUE` override (MPa). The override re-scales a
#: preset for calibration; soft robots are made of elastomers, from the softest silicone gels
#: (~1 kPa) to hard rubbers (Shore 90A: mu ~ 10 MPa; 100 MPa leaves a margin). Outside it the
#: value is a unit mistake: at mu = 1e6 MPa a 20 kPa load is below the solver's tolerance and the
#: ePSA run reports meaningless states.
OVERRIDE_MU_RANGE = (1.0e-3, 100.0)


def get_material(name: str) -> Material:
    """The preset called `name` (fit presets are computed at first use, then cached).

    `NAME@mu=VALUE` is the preset with its shear modulus replaced by VALUE MPa (K/mu kept, see
    `Material.with_mu`), VALUE within `OVERRIDE_MU_RANGE`: how a calibrated modulus (`softcrawl
    calibrate`) is used in studies.
    """
    if not isinstance(name, str):
        raise MaterialError("material", f"must be a preset name, got {brief(name)}")
    base, at, override = name.partition("@")
    if base not in PRESETS:
        raise MaterialError(
            "material",
            f"unknown material {brief(name)}; valid: {', '.join(PRESETS)} (optionally NAME@mu=VALUE)",
        )
    if not at:
        return PRESETS[base]()
    key, _, value = override.partition("=")
    try:
        mu = float(value)
    except ValueError:
        mu = math.nan
    low, high = OVERRIDE_MU_RANGE
    if key.strip() != "mu" or not math.isfinite(mu) or not low <= mu <= high:
        raise MaterialError(
            "material", f"{brief(name)}: write NAME@mu=VALUE with VALUE in [{low:g}, {high:g}] MPa"
        )
    return replace(PRESETS[base]().with_mu(mu), name=f"{base}@mu={value}")
