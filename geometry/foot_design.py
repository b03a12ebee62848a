"""The grooved flexible foot's design (paper Fig. 3): a hub disk with a conical skirt.

Frozen, keyword-only, validated on construction like every design of `geometry.design` (which
re-exports it). Units mm, angles in degrees. The section and its reading of Fig. 3 are in
`geometry.foot`; the body geometry the hub radius comes from in `softcrawl.body`.

The angle. ``angle`` is the included angle of the skirt's cone: its smooth front face leaves the
hub's top rim (rho = hub_radius, z = 0) at angle / 2 from the axis and runs to the tip at
``tip_radius``, which stays at 39 mm (the prototype's 78 mm maximum diameter) for every angle, so
every foot of Fig. 21 touches the 70 mm pipe it was tested in. The skirt's back face, t below the
front face, meets the hub side at z = -t / sin(angle / 2); the hub must reach that deep. Its
thickness is therefore, unless given, ``root_thickness`` = max(4 mm, t / sin(angle / 2)): 4 mm
(the committed results' hub) from 97.2 to 180 deg, 4.24 mm at 90, 6 mm at 60, 7.84 mm at 45 and
11.59 mm at 30 deg. Front and back face lengths (slant):
    L_front = (r_tip - r_hub) / sin(angle / 2),   L_back = L_front - t cos(angle / 2) / sin(angle / 2).
docs/decisions/066-body-geometry.md gives the reasons and the alternatives.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from softcrawl.body import BODY
from softcrawl.geometry.design_base import MIN_LIGAMENT, DesignBase, check_number, spec
from softcrawl.geometry.errors import DesignError

__all__ = ["HUB_THICKNESS", "MIN_SKIRT_ANGLE", "FootDesign"]

#: Smallest included angle of the foot's conical skirt (deg). Below it the "cone" is a tube along
#: the axis, not a foot, and the skirt geometry divides by sin(angle / 2) (a 5e-324 deg skirt
#: was a ZeroDivisionError). The paper's foot has 120 deg.
MIN_SKIRT_ANGLE = 10.0
#: Least axial thickness of the foot's hub (mm): the value of every committed foot result (a
#: 120 deg skirt's root needs 3.46 mm). A narrower skirt needs t / sin(angle / 2) (record 066).
HUB_THICKNESS = 4.0


@dataclass(frozen=True, kw_only=True)
class FootDesign(DesignBase):
    """Grooved flexible foot (paper Fig. 3): a hub disk with a conical skirt, see ``geometry.foot``."""

    kind: ClassVar[str] = "foot"
    d: float = spec(BODY.d, "distance foot centre -> actuator centres (the sub circle)")
    hub_radius: float = spec(BODY.part_radius, "hub disk radius: the body's part radius d + R0 + rim")
    hub_thickness: float | None = spec(
        None, f"axial hub thickness; unset: max({HUB_THICKNESS:g}, skirt_thickness / sin(angle / 2))"
    )
    bore_radius: float = spec(4.0, "central bore for the endoscope (<= d - R0)")
    tip_radius: float = spec(39.0, "skirt tip radius: 78 mm prototype maximum diameter")
    angle: float = spec(120.0, "included angle of the conical skirt, 180 = flat disk", "deg")
    skirt_thickness: float = spec(3.0, "skirt wall thickness")
    groove_height: float = spec(1.0, "h, groove depth on the back face")
    groove_width: float = spec(1.0, "width of a groove along the skirt")
    n_grooves: int = spec(5, "number of grooves on the back face", "")

    def __post_init__(self) -> None:
        check_number(self, "angle", minimum=MIN_SKIRT_ANGLE, maximum=180.0, unit="deg")
        check_number(self, "skirt_thickness")
        if self.hub_thickness is None:
            object.__setattr__(self, "hub_thickness", self.root_thickness)
        for name in (
            "d",
            "hub_radius",
            "hub_thickness",
            "tip_radius",
            "skirt_thickness",
            "groove_height",
            "groove_width",
        ):
            check_number(self, name)
        check_number(self, "bore_radius", minimum=0.0)
        check_number(self, "n_grooves", integer=True, minimum=0)
        p = ""
        if self.bore_radius + MIN_LIGAMENT > self.hub_radius:
            raise DesignError(p + "bore_radius", "leaves no hub material (must be < hub_radius)")
        if self.tip_radius <= self.hub_radius + self.skirt_thickness:
            raise DesignError(p + "tip_radius", f"{self.tip_radius} must exceed hub_radius + skirt_thickness")
        if self.hub_thickness < self.skirt_thickness / self.sin_half_angle - 1e-9:
            raise DesignError(
                p + "hub_thickness",
                f"{self.hub_thickness} must be >= skirt_thickness / "
                f"sin(angle / 2) = {self.skirt_thickness / self.sin_half_angle:.3f} so the "
                f"skirt root lies on the hub",
            )
        if self.groove_height > self.skirt_thickness - MIN_LIGAMENT:
            raise DesignError(
                p + "groove_height",
                f"{self.groove_height} must leave {MIN_LIGAMENT} mm of the {self.skirt_thickness} mm skirt",
            )
        land = self.back_face_length / (self.n_grooves + 1) - self.groove_width
        if self.n_grooves and land < MIN_LIGAMENT:
            raise DesignError(
                p + "n_grooves",
                f"{self.n_grooves} grooves of width {self.groove_width} mm "
                f"do not fit on the {self.back_face_length:.2f} mm back face",
            )

    @property
    def sin_half_angle(self) -> float:
        return math.sin(math.radians(self.angle / 2))

    @property
    def root_thickness(self) -> float:
        """The default hub thickness: max(HUB_THICKNESS, t / sin(angle / 2)), the least hub whose side
        holds the whole root of the skirt (its back face leaves the hub side at z = -t / sin)."""
        return max(HUB_THICKNESS, self.skirt_thickness / self.sin_half_angle)

    def replace(self, **changes) -> FootDesign:
        """A copy with some fields changed; a hub thickness that was the derived one (`root_thickness`)
        is derived again for the new angle and skirt unless `changes` sets it."""
        if "hub_thickness" not in changes and self.hub_thickness == self.root_thickness:
            changes["hub_thickness"] = None
        return super().replace(**changes)

    @property
    def front_face_length(self) -> float:
        """Slant length of the smooth front face, hub rim to tip."""
        return (self.tip_radius - self.hub_radius) / self.sin_half_angle

    @property
    def back_face_length(self) -> float:
        """Slant length of the back face (before grooves), from where it leaves the hub to the tip."""
        a = math.radians(self.angle / 2)
        return self.front_face_length - self.skirt_thickness * math.cos(a) / math.sin(a)
