"""A `Material` as the constitutive law of the FE solver (`fem.neohooke.NeoHookean`).

The solver takes a law object with the shear and bulk moduli in MPa; a linear-elastic material
(ABS) becomes a Neo-Hookean solid with its small-strain mu and K, which agrees with linear
elasticity at the strains of a stiff part (~1e-4 at 100 kPa).
"""

from __future__ import annotations

from fem.neohooke import NeoHookean
from materials.material import Material, MaterialError


def solid_law(material: Material, *, hyperelastic_only: bool = False) -> NeoHookean:
    """The solver law of `material`. With `hyperelastic_only`, a linear-elastic material is an
    error naming `material` (a silicone body must not silently become ABS)."""
    if material.model == "yeoh":
        raise MaterialError(
            "material",
            f"{material.name} is a Yeoh material; the solver has no Yeoh law yet (use a Neo-Hookean preset)",
        )
    if hyperelastic_only and material.model != "neo-hookean":
        raise MaterialError(
            "material",
            f"{material.name} is {material.model}; a soft body needs a "
            "Neo-Hookean material (e.g. ecoflex-00-50, ecoflex-00-50-fit)",
        )
    return NeoHookean(mu=material.mu, bulk=material.bulk)
