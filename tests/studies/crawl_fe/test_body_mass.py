"""The one body's mass from its parts' densities, against a hand computation of the parts' volumes.

Hand volumes (exact solids of Table 1's design): ePSA pi R0^2 L - pi r0^2 (L - 2 c); seal head
pi R0^2 t_s; ring (pi P^2 - 3 pi R0^2 - pi b^2) t_r; foot the revolved section's Pappus volume
(`geometry.foot.foot_volume`, hub with its 4 mm bore). The FE volumes are the curved P2 elements'
(`studies.crawl_fe.mass`). They differ by what the mesh simplifies, each bounded here:
  - the seal heads' and the rings' and hubs' outlines are chordal polygons (12 sides on a seal head
    at the quick mesh: at most 1 - 12 sin(30 deg) / (2 pi) = 4.5 % of its volume; the 36-side
    outline 0.5 %);
  - the mesh's hubs have the rings' 3.5 mm bore (`robot_mesh.stiff_outline`), +0.3 % of the feet.
Quick mesh, observed: ePSAs -0.016 %, seal heads -3.4 %, rings -0.86 %, feet +0.37 %, total -0.07 %.
"""

import math

import pytest

from softcrawl.geometry.body_mesh import mesh_body
from softcrawl.geometry.design import RobotDesign
from softcrawl.geometry.foot import foot_volume
from softcrawl.materials import get_material
from softcrawl.paper import ROBOT_MASS_G
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl_fe.mass import mass_summary
from softcrawl.studies.crawl_fe.model import part_materials

DESIGN = RobotDesign()


def _hand_volumes(design):
    e, f, r = design.epsa, design.foot, design.ring
    return {
        "epsa": 3
        * math.pi
        * (e.outer_radius**2 * e.length - e.chamber_radius**2 * (e.length - 2 * e.end_cap_thickness)),
        "seal_head": 3 * math.pi * e.outer_radius**2 * e.seal_head_thickness,
        "ring": design.n_rings
        * math.pi
        * (r.outer_radius**2 - 3 * e.outer_radius**2 - r.bore_radius**2)
        * r.thickness,
        "foot": 2 * foot_volume(f),
    }


def test_mass_from_the_parts_densities():
    materials = part_materials(CrawlSetup())
    summary = mass_summary(DESIGN, mesh_body(DESIGN, "quick").to_skfem(2), materials)
    hand = _hand_volumes(DESIGN)
    density = {
        "epsa": get_material(materials["epsa"]).density,
        "seal_head": get_material("abs").density,
        "ring": get_material("abs").density,
        "foot": get_material("rubber-70a").density,
    }
    bounds = {"epsa": 1e-3, "seal_head": 0.045, "ring": 0.015, "foot": 0.01}
    for part, volume in hand.items():
        fe = summary["parts"][part]["volume_mm3"]
        assert fe == pytest.approx(volume, rel=bounds[part]), part
    hand_total = sum(density[p] * v for p, v in hand.items()) * 1e6
    assert summary["total_g"] == pytest.approx(hand_total, rel=5e-3)
    assert summary["difference_g"] == pytest.approx(summary["total_g"] - ROBOT_MASS_G)
    assert 0 < summary["winding_g"] < 0.02 * summary["total_g"]
