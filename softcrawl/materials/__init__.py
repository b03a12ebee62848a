"""Materials of the robot's parts: validated constants, tensile data, hyperelastic fits, presets.

Modules (one job each):
    material  `Material` (a name, a law, a density, a source), `LinearElastic`, small-strain
              relations, Shore A; the hyperelastic laws are the solver's (`fem.laws`)
    tensile   the shipped tensile tests (Soft Robotics Materials Database) and their CSV reader
    fitting   least-squares fits of any registered law (`fem.laws.LAWS`) to a tensile test
    presets   named presets with their sources; `NAME@mu=VALUE` overrides
    fem_law   a `Material` as the constitutive law the FE solver takes

`materials` sits beside `geometry` and `robot`: it may use the generic solver (`fem_law`), and
nothing in `geometry`, `fem`, `robot` or `materials` imports `studies`.
"""

from softcrawl.materials.fitting import (
    DEFAULT_MAX_STRAIN,
    FitResult,
    fit_tensile,
    fit_uniaxial,
    select_fit_points,
)
from softcrawl.materials.material import (
    DEFAULT_K_OVER_MU,
    LinearElastic,
    Material,
    MaterialError,
    shore_a_to_youngs,
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
    "FitResult",
    "LinearElastic",
    "Material",
    "MaterialError",
    "PRESETS",
    "TENSILE_FILES",
    "TensileData",
    "fit_tensile",
    "fit_uniaxial",
    "get_material",
    "load_tensile",
    "material_names",
    "select_fit_points",
    "shore_a_to_youngs",
]
