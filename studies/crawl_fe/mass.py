r"""The one body's mass from its parts' densities (issue 34: "the robot's mass comes from its parts'
densities, listed, and is compared with the prototype's 70.2 g").

    m_part = rho_part * V_part,     V_part = sum over the part's elements of int dV

on the curved P2 elements the solver integrates (`fem.discretisation`: the quadrature weights
`dx`), so the mass is that of the FE body a gravity load acts on. Densities are the materials'
(`softcrawl.materials` presets): the silicone's, ABS 1.04 g/cm^3 (rings, seal heads), the feet's
rubber (1.15 g/cm^3, assumed). The Kevlar winding is smeared as fiber sheets with no volume: its
mass is not in the body (`winding_mass_g` gives it for the record). The prototype's tubing, seals,
glue and the endoscope channel's fittings are unknown, so the difference to 70.2 g is reported,
not fitted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import skfem

from softcrawl.geometry.epsa_shape import fiber_helices
from softcrawl.materials import get_material
from softcrawl.paper import ROBOT_MASS_G
from softcrawl.studies.crawl_fe.model import part_kind

TONNE_TO_G = 1.0e6


@dataclass(frozen=True)
class PartMass:
    """One part kind of the body: its material, density (t/mm^3), volume (mm^3) and mass (g)."""

    part: str
    material: str
    density: float
    volume: float

    @property
    def mass_g(self) -> float:
        return self.density * self.volume * TONNE_TO_G


def part_masses(mesh, materials: dict[str, str], copies: int = 1) -> list[PartMass]:
    """The mass of each part kind of the body on `mesh` (the P2 skfem mesh of
    `geometry.body_mesh`, with its regions as subdomains; `materials`: part kind -> material name,
    `studies.crawl_fe.model.part_materials`), from the volumes of its curved P2 elements at the
    solver's quadrature (`intorder` 2). `copies`: the mesh is one wedge of 2 pi / copies of the
    body (`studies.crawl_fe.wedge`), each of its volumes a 1 / copies of the whole body's."""
    dx = skfem.Basis(mesh, skfem.ElementTetP2(), intorder=2).dx
    volumes: dict[str, float] = {}
    for name, elements in mesh.subdomains.items():
        kind = part_kind(name)
        volumes[kind] = volumes.get(kind, 0.0) + copies * float(dx[np.asarray(elements)].sum())
    out = []
    for kind, volume in volumes.items():
        material = get_material(materials[kind])
        out.append(PartMass(kind, material.name, material.density, volume))
    return out


def winding_mass_g(design) -> float:
    """The Kevlar winding of the three actuators (not in the FE body's volume), g."""
    e = design.epsa
    length = sum(float(np.linalg.norm(np.diff(h, axis=0), axis=1).sum()) for h in fiber_helices(e))
    return 3 * length * math.pi * e.fiber_diameter**2 / 4 * get_material("kevlar").density * TONNE_TO_G


def mass_summary(design, mesh, materials: dict[str, str], copies: int = 1) -> dict:
    """Per part and in total (g), the winding, and the difference to the prototype's ROBOT_MASS_G;
    `part_masses`'s arguments, and the `RobotDesign` (for the winding)."""
    parts = part_masses(mesh, materials, copies)
    total = sum(p.mass_g for p in parts)
    return {
        "parts": {
            p.part: {
                "material": p.material,
                "density_t_mm3": p.density,
                "volume_mm3": p.volume,
                "mass_g": p.mass_g,
            }
            for p in parts
        },
        "total_g": total,
        "winding_g": winding_mass_g(design),
        "prototype_g": ROBOT_MASS_G,
        "difference_g": total - ROBOT_MASS_G,
    }
