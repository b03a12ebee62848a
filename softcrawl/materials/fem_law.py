"""A `Material` as the constitutive law of the FE solver (`fem.laws`).

A hyperelastic material's law is the solver's law itself (Neo-Hookean, Yeoh, Gent, any law of
`fem.laws.LAWS`, with its bulk modulus). A linear-elastic material (ABS) becomes a Neo-Hookean
solid with its small-strain mu and K (`LinearElastic.solver_law`), which agrees with linear
elasticity at the strains of a stiff part (~1e-4 at 100 kPa).
"""

from __future__ import annotations

from softcrawl.fem.laws import LAWS, IsochoricI1Law
from softcrawl.materials.material import Material, MaterialError


def solid_law(material: Material, *, hyperelastic_only: bool = False) -> IsochoricI1Law:
    """The solver law of `material`. With `hyperelastic_only`, a linear-elastic material is an
    error naming `material` (a silicone body must not silently become ABS)."""
    if isinstance(material.law, IsochoricI1Law):
        return material.law
    if hyperelastic_only:
        raise MaterialError(
            "material",
            f"{material.name} is {material.model}; a soft body needs a hyperelastic material "
            f"({', '.join(LAWS)}, e.g. ecoflex-00-50, ecoflex-00-50-yeoh)",
        )
    return material.law.solver_law()
