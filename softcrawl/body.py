"""The robot's body across its axis: the one geometry the FE foot, the FE robot and the planner share.

The paper gives two numbers (Section VI-B): "The maximum diameter of the robotic prototype is 78 mm
and the minimum diameter is 46 mm", chosen "to create a prototype that is easily testable ... using
off-the-shelf transparent pipes with diameters ranging from 55 mm to 75 mm". With Table 1's
actuators (radius R0 = 9 mm) on the circle of radius d = 14 mm,

    envelope radius   E = d + R0                       (23 mm: 2 E = 46 mm, the minimum diameter)

is the envelope of the actuator bundle, to the millimetre. The paper's text makes 46 mm the body's
diameter that passes the smallest pipe (the maximum, 78 mm, is the feet's reach into the largest),
so nothing rigid on the prototype's body lies outside the bundle's envelope: its rings and foot hubs
lie within 2 E. A ring that is a plate with closed holes of radius R0 at d cannot: its material
outside a hole is P - (d + R0) thick, zero at P = E (and a disk tangent to the three actuators is
not meshable either). The paper shows no ring drawing (Fig. 13 is a photograph), so the prototype's
rings may have open seats; the model's rigid parts get one rim instead:

    part radius       P = E + rim                      (24 mm with rim = 1 mm: 48 mm)

the outer radius of every rigid part that carries the bundle: the foot's hub (`FootDesign.hub_radius`),
the connecting rings (`RingDesign.outer_radius`) and, therefore, the single outline of rings and
hubs in the swept robot mesh. The rim is a modelling necessity, not a datum: 1 mm is twice the
design rules' smallest ligament (`geometry.design_base.MIN_LIGAMENT`, 0.5 mm) and the hub rim the
committed foot and crawl results were computed with. The planner (`softcrawl.analytic`) models the
prototype itself, with its identified actuator laws, so its body tube has the prototype's
envelope radius E (`clearance_radius`). docs/decisions/066-body-geometry.md gives the reasons and
what moved. Core layer: imports only `softcrawl.paper` and `softcrawl.checks`.
"""

from __future__ import annotations

from dataclasses import dataclass

from softcrawl.checks import number
from softcrawl.paper import D_MM, EPSA_RADIUS_MM

#: Rigid material outside the actuator bundle's envelope, mm (module docstring).
PART_RIM_MM = 1.0


@dataclass(frozen=True, kw_only=True)
class Body:
    """The body's cross-section: actuators of radius `epsa_radius` on the circle `d`, rigid parts
    (foot hubs, rings) `rim` beyond their envelope. Lengths in mm."""

    d: float = D_MM
    epsa_radius: float = EPSA_RADIUS_MM
    rim: float = PART_RIM_MM

    def __post_init__(self) -> None:
        for name in ("d", "epsa_radius", "rim"):
            object.__setattr__(
                self, name, number(getattr(self, name), name, minimum=0.0, min_open=True, unit="mm")
            )

    @property
    def envelope_radius(self) -> float:
        """E = d + R0: the actuator bundle's envelope (23 mm; the paper's 46 mm minimum diameter)."""
        return self.d + self.epsa_radius

    @property
    def envelope_diameter(self) -> float:
        return 2.0 * self.envelope_radius

    @property
    def part_radius(self) -> float:
        """P = E + rim: the outer radius of the foot hubs and the rings (24 mm)."""
        return self.envelope_radius + self.rim

    @property
    def clearance_radius(self) -> float:
        """The planner's body tube: the prototype's envelope E (module docstring)."""
        return self.envelope_radius


#: Table 1's body (d = 14 mm, R0 = 9 mm, rim 1 mm).
BODY = Body()
