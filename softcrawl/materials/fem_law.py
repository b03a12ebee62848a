"""A `Material` as the constitutive law of the FE solver (`fem.neohooke.NeoHookean`, `fem.laws`).

The solver takes a law object with its constants in MPa: Neo-Hookean, Yeoh (three terms) or Gent,
each with its bulk modulus. A linear-elastic material (ABS) becomes a Neo-Hookean solid with its
small-strain mu and K, which agrees with linear elasticity at the strains of a stiff part (~1e-4
at 100 kPa).
"""

from __future__ import annotations

from softcrawl.fem.laws import Gent, IsochoricI1Law, NeoHookean, Yeoh
from softcrawl.materials.material import Material, MaterialError


def solid_law(material: Material, *, hyperelastic_only: bool = False) -> IsochoricI1Law:
    """The solver law of `material`. With `hyperelastic_only`, a linear-elastic material is an
    error naming `material` (a silicone body must not silently become ABS)."""
    if material.model == "yeoh":
        c10, c20, c30 = material.yeoh_c
        return Yeoh(c10=c10, c20=c20, c30=c30, bulk=material.bulk)
    if material.model == "gent":
        return Gent(mu=material.mu, jm=material.gent_jm, bulk=material.bulk)
    if hyperelastic_only and material.model != "neo-hookean":
        raise MaterialError(
            "material",
            f"{material.name} is {material.model}; a soft body needs a hyperelastic material "
            "(Neo-Hookean, Yeoh or Gent, e.g. ecoflex-00-50, ecoflex-00-50-yeoh)",
        )
    return NeoHookean(mu=material.mu, bulk=material.bulk)
