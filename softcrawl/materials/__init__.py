"""Materials of the robot's parts: validated constants, tensile data, hyperelastic fits, presets.

Modules (one job each):
    material  `Material` (Neo-Hookean, Yeoh, linear elastic), small-strain relations, Shore A
    tensile   the shipped tensile tests (Soft Robotics Materials Database) and their CSV reader
    fitting   least-squares fits of hyperelastic laws to a tensile test
    presets   named presets with their sources; `NAME@mu=VALUE` overrides
    fem_law   a `Material` as the constitutive law the FE solver takes

`materials` sits beside `geometry` and `robot`: it may use the generic solver (`fem_law`), and
nothing in `geometry`, `fem`, `robot` or `materials` imports `studies`.
"""

from softcrawl.materials.fitting import (
    DEFAULT_MAX_STRAIN,
    FIT_MODELS,
    FitResult,
    fit_neo_hookean,
    fit_tensile,
    fit_yeoh,
    select_fit_points,
)
from softcrawl.materials.material import (
    DEFAULT_K_OVER_MU,
    MODELS,
    Material,
    MaterialError,
    neo_hookean_uniaxial,
    shore_a_to_youngs,
    yeoh_is_stable,
    yeoh_uniaxial,
)
from softcrawl.materials.presets import PRESETS, get_material, material_names
from softcrawl.materials.tensile import (
    DATA_ATTRIBUTION,
    DATA_LICENSE,
    TENSILE_FILES,
    TensileData,
    load_tensile,
)

__all__ = [
    "DATA_ATTRIBUTION",
    "DATA_LICENSE",
    "DEFAULT_K_OVER_MU",
    "DEFAULT_MAX_STRAIN",
    "FIT_MODELS",
    "FitResult",
    "MODELS",
    "Material",
    "MaterialError",
    "PRESETS",
    "TENSILE_FILES",
    "TensileData",
    "fit_neo_hookean",
    "fit_tensile",
    "fit_yeoh",
    "get_material",
    "load_tensile",
    "material_names",
    "neo_hookean_uniaxial",
    "select_fit_points",
    "shore_a_to_youngs",
    "yeoh_is_stable",
    "yeoh_uniaxial",
]
