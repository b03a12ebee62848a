"""Design parameters of the ePSA, the flexible foot, the connecting ring and the robot.

Frozen, keyword-only dataclasses, validated on construction. Units: mm, degrees for angles.
Defaults are the paper's Table 1 (ePSA length 100 mm, radius 9 mm, chamber radius 3 mm, 20 winding
turns, groove height 1 mm, foot radius d = 14 mm, 3 connecting rings) plus dimensions the paper
gives or implies (Sections II, V, VI):

* Kevlar fiber diameter 0.3 mm (docs/decisions/001-materials.md).
* End caps: the silicone body closes each end of the air chamber with ``end_cap_thickness`` = 5 mm.
  The paper gives no value; 5 mm is close to the 6 mm side wall (R0 - r0), so the ends are not the
  weak spot of the chamber, and leaves 90 % of the body length (90 mm) pressurised.
* Seal head: a separate ABS disk of the ePSA radius, ``seal_head_thickness`` = 3 mm (not given).
* Prototype diameters (Section VI.B): maximum 78 mm = foot tip diameter (``FootDesign.tip_radius`` =
  39 mm), minimum 46 mm = 2 (d + R0), the envelope of the actuator bundle. Feet of 78 mm touch the
  wall of every pipe of the 55-75 mm range the prototype was built for. The foot hub and the rings
  share one outer radius, the body's part radius d + R0 + rim = 24 mm (`softcrawl.body`,
  docs/decisions/066-body-geometry.md); a robot of another d or R0 sizes its parts from its own
  `Body`.
* Foot angle 120 deg: the included angle of the foot's conical skirt, whose front face leaves the
  hub's top rim and whose tip stays at ``tip_radius`` for every angle (see ``geometry.foot``). The
  hub is by default as thick as the skirt's root needs, max(4 mm, t / sin(angle / 2)), so that
  every angle of Fig. 21 (30-120 deg) builds; 4 mm for 97.2-180 deg (record 066).

Every invalid value raises :class:`DesignError`, an ``InputError`` whose ``parameter`` attribute is
the field name (dotted for nested designs, e.g. ``foot.hub_radius``).

Analytic helpers (``EPSADesign``): chamber length l_c = L - 2 c; silicone body volume
V = pi (R0^2 L - r0^2 l_c); length of one fiber helix of N turns on radius R0 over length L,
s = N sqrt((2 pi R0)^2 + (L / N)^2) = sqrt((2 pi R0 N)^2 + L^2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

from softcrawl.body import BODY, Body
from softcrawl.checks import brief
from softcrawl.geometry.design_base import (
    ACTUATOR_ANGLES_DEG,
    MAX_DIMENSION,
    MAX_FEATURE_COUNT,
    MIN_FEATURE,
    MIN_LIGAMENT,
    DesignBase,
    check_number,
    derived_part,
    spec,
)
from softcrawl.geometry.design_files import read_design_file
from softcrawl.geometry.errors import DesignError
from softcrawl.geometry.foot_design import HUB_THICKNESS, MIN_SKIRT_ANGLE, FootDesign

__all__ = [
    "ACTUATOR_ANGLES_DEG",
    "MAX_DIMENSION",
    "MAX_FEATURE_COUNT",
    "MIN_FEATURE",
    "MIN_LIGAMENT",
    "MIN_SKIRT_ANGLE",
    "HUB_THICKNESS",
    "DesignError",
    "EPSADesign",
    "FootDesign",
    "RingDesign",
    "RobotDesign",
    "load_design",
]


@dataclass(frozen=True, kw_only=True)
class EPSADesign(DesignBase):
    """Extensible pneumatic soft actuator: silicone cylinder with a closed axial air chamber."""

    kind: ClassVar[str] = "epsa"
    length: float = spec(100.0, "L0, body length")
    outer_radius: float = spec(9.0, "R0, outer radius")
    chamber_radius: float = spec(3.0, "r0, air chamber radius")
    fiber_turns: int = spec(20, "N, turns of each of the two helices", "")
    fiber_diameter: float = spec(0.3, "Kevlar thread diameter")
    end_cap_thickness: float = spec(5.0, "silicone closing each chamber end")
    seal_head_thickness: float = spec(3.0, "ABS seal head disk")

    def __post_init__(self) -> None:
        for name in (
            "length",
            "outer_radius",
            "chamber_radius",
            "fiber_diameter",
            "end_cap_thickness",
            "seal_head_thickness",
        ):
            check_number(self, name)
        check_number(self, "fiber_turns", integer=True, minimum=0)
        p = ""
        if self.chamber_radius >= self.outer_radius:
            raise DesignError(
                p + "chamber_radius",
                f"{self.chamber_radius} must be smaller than outer_radius {self.outer_radius}",
            )
        if self.outer_radius - self.chamber_radius < MIN_LIGAMENT:
            raise DesignError(
                p + "chamber_radius",
                f"wall thickness {self.outer_radius - self.chamber_radius} is below {MIN_LIGAMENT} mm",
            )
        if self.fiber_diameter >= self.outer_radius - self.chamber_radius:
            raise DesignError(p + "fiber_diameter", "must be smaller than the wall thickness")
        if self.fiber_turns > self.length / self.fiber_diameter:
            raise DesignError(
                p + "fiber_turns",
                f"{self.fiber_turns} turns over {self.length} mm put the turns of one helix closer "
                f"than the {self.fiber_diameter} mm thread is thick (at most L / fiber_diameter = "
                f"{math.floor(self.length / self.fiber_diameter)})",
            )
        if 2 * self.end_cap_thickness >= self.length:
            raise DesignError(
                p + "end_cap_thickness",
                f"two end caps of {self.end_cap_thickness} mm "
                f"leave no chamber in a body of length {self.length} mm",
            )

    @property
    def wall_thickness(self) -> float:
        return self.outer_radius - self.chamber_radius

    @property
    def chamber_length(self) -> float:
        """l_c = L - 2 c."""
        return self.length - 2 * self.end_cap_thickness

    @property
    def chamber_volume(self) -> float:
        return math.pi * self.chamber_radius**2 * self.chamber_length

    @property
    def body_volume(self) -> float:
        """Silicone volume pi (R0^2 L - r0^2 l_c)."""
        return math.pi * self.outer_radius**2 * self.length - self.chamber_volume

    @property
    def chamber_wall_area(self) -> float:
        return 2 * math.pi * self.chamber_radius * self.chamber_length

    @property
    def helix_length(self) -> float:
        """Length of one helix: N sqrt((2 pi R0)^2 + (L/N)^2) (= L for N = 0)."""
        return math.hypot(2 * math.pi * self.outer_radius * self.fiber_turns, self.length)

    @property
    def fiber_angle_deg(self) -> float:
        """Winding angle of the fibers measured from the axis."""
        return math.degrees(math.atan2(2 * math.pi * self.outer_radius * self.fiber_turns, self.length))


@dataclass(frozen=True, kw_only=True)
class RingDesign(DesignBase):
    """Connecting ring (ABS): a plate with three actuator holes at radius d and a central bore."""

    kind: ClassVar[str] = "ring"
    d: float = spec(BODY.d, "radius of the actuator hole centres")
    hole_radius: float = spec(BODY.epsa_radius, "actuator holes (= ePSA radius, tied to it)")
    outer_radius: float = spec(BODY.part_radius, "ring outer radius: the body's part radius d + R0 + rim")
    bore_radius: float = spec(3.5, "central bore (endoscope passage; 0 = none)")
    thickness: float = spec(5.0, "axial thickness")

    def __post_init__(self) -> None:
        for name in ("d", "hole_radius", "outer_radius", "thickness"):
            check_number(self, name)
        check_number(self, "bore_radius", minimum=0.0)
        p = ""
        gap = self.d * math.sqrt(3) - 2 * self.hole_radius
        if gap < MIN_LIGAMENT:
            raise DesignError(
                p + "hole_radius",
                f"holes of radius {self.hole_radius} at d = {self.d} "
                f"overlap or leave less than {MIN_LIGAMENT} mm between them",
            )
        if self.d + self.hole_radius + MIN_LIGAMENT > self.outer_radius:
            raise DesignError(
                p + "outer_radius",
                f"{self.outer_radius} must be >= d + hole_radius + "
                f"{MIN_LIGAMENT} = {self.d + self.hole_radius + MIN_LIGAMENT}",
            )
        if self.bore_radius > 0 and self.bore_radius + MIN_LIGAMENT > self.d - self.hole_radius:
            raise DesignError(
                p + "bore_radius",
                f"{self.bore_radius} must be <= d - hole_radius - "
                f"{MIN_LIGAMENT} = {self.d - self.hole_radius - MIN_LIGAMENT}",
            )


@dataclass(frozen=True, kw_only=True)
class RobotDesign(DesignBase):
    """Three ePSAs at radius d, psi = 90, 210, 330 deg, n_rings rings, a foot at each end.

    Layout (z along the robot axis): rear foot hub z in [-hub_thickness, 0]; ePSAs z in [0, L];
    seal heads z in [L, L + t_s]; front foot hub z in [L + t_s, L + t_s + hub_thickness]; ring k
    (k = 1..n) centred at z = k L / (n + 1). ``foot`` and ``ring`` default to parts sized from d
    and the ePSA radius; given explicitly, they must agree with d and R0.
    """

    kind: ClassVar[str] = "robot"
    epsa: EPSADesign = field(default_factory=EPSADesign)
    d: float = spec(BODY.d, "distance robot axis -> actuator centres")
    n_rings: int = spec(3, "number of connecting rings", "")
    foot: FootDesign | None = None
    ring: RingDesign | None = None
    pipe_diameter_min: float = spec(55.0, "smallest pipe the robot is sized for")
    pipe_diameter_max: float = spec(75.0, "largest pipe the robot is sized for")

    def __post_init__(self) -> None:
        check_number(self, "d")
        check_number(self, "n_rings", integer=True, minimum=0)
        check_number(self, "pipe_diameter_min")
        check_number(self, "pipe_diameter_max")
        if not isinstance(self.epsa, EPSADesign):
            raise DesignError("epsa", "must be an EPSADesign")
        R0 = self.epsa.outer_radius
        if self.d * math.sqrt(3) <= 2 * R0:
            raise DesignError(
                "d",
                f"actuators of radius {R0} overlap at d = {self.d} "
                f"(need d > 2 R0 / sqrt(3) = {2 * R0 / math.sqrt(3):.3f})",
            )
        # (d > 2 R0 / sqrt(3) > R0: the centre channel d - R0 for the endoscope is never empty)
        if self.foot is None:
            object.__setattr__(self, "foot", derived_part("foot", FootDesign, self._foot_sizes()))
        if self.ring is None:
            object.__setattr__(self, "ring", derived_part("ring", RingDesign, self._ring_sizes()))
        if not isinstance(self.foot, FootDesign):
            raise DesignError("foot", "must be a FootDesign")
        if not isinstance(self.ring, RingDesign):
            raise DesignError("ring", "must be a RingDesign")
        if self.foot.d != self.d:
            raise DesignError("foot.d", f"{self.foot.d} differs from the robot's d = {self.d}")
        if self.ring.d != self.d:
            raise DesignError("ring.d", f"{self.ring.d} differs from the robot's d = {self.d}")
        if self.ring.hole_radius != R0:
            raise DesignError("ring.hole_radius", f"{self.ring.hole_radius} must equal the ePSA radius {R0}")
        if self.foot.hub_radius < self.d + R0:
            raise DesignError(
                "foot.hub_radius",
                f"{self.foot.hub_radius} must be >= d + R0 = {self.d + R0} to carry the actuators",
            )
        if self.foot.bore_radius > self.d - R0:
            raise DesignError(
                "foot.bore_radius",
                f"{self.foot.bore_radius} cuts into the actuators (must be <= d - R0 = {self.d - R0})",
            )
        if self.n_rings and self.epsa.length / (self.n_rings + 1) <= self.ring.thickness + MIN_LIGAMENT:
            raise DesignError(
                "n_rings",
                f"{self.n_rings} rings of thickness {self.ring.thickness} mm "
                f"do not fit along the {self.epsa.length} mm actuators",
            )
        if self.pipe_diameter_min > self.pipe_diameter_max:
            raise DesignError("pipe_diameter_min", "must not exceed pipe_diameter_max")
        if 2 * self.ring.outer_radius >= self.pipe_diameter_min:
            raise DesignError(
                "ring.outer_radius",
                f"rings of diameter {2 * self.ring.outer_radius} mm do "
                f"not fit in a {self.pipe_diameter_min} mm pipe",
            )
        if 2 * self.foot.tip_radius <= self.pipe_diameter_max:
            raise DesignError(
                "foot.tip_radius",
                f"feet of diameter {2 * self.foot.tip_radius} mm do not "
                f"touch the wall of a {self.pipe_diameter_max} mm pipe",
            )

    _nested: ClassVar[dict[str, type]] = {"epsa": EPSADesign, "foot": FootDesign, "ring": RingDesign}

    @property
    def body(self) -> Body:
        """The body's cross-section (`softcrawl.body`): this robot's d and R0, the default rim."""
        return Body(d=self.d, epsa_radius=self.epsa.outer_radius)

    def _foot_sizes(self) -> dict[str, float]:
        """The default foot: d, a hub of the body's part radius, a bore of up to 4 mm."""
        R0 = self.epsa.outer_radius
        return dict(d=self.d, hub_radius=self.body.part_radius, bore_radius=min(4.0, self.d - R0))

    def _ring_sizes(self) -> dict[str, float]:
        """The default ring: holes of the ePSA radius, the body's part radius, a bore of up to 3.5 mm."""
        R0 = self.epsa.outer_radius
        return dict(
            d=self.d,
            hole_radius=R0,
            outer_radius=self.body.part_radius,
            bore_radius=max(0.0, min(3.5, self.d - R0 - 1.5)),
        )

    @property
    def channel_radius(self) -> float:
        """Radius of the free centre channel between the actuators (endoscope room): d - R0."""
        return self.d - self.epsa.outer_radius

    @property
    def actuator_centres(self) -> list[tuple[float, float]]:
        return [
            (self.d * math.cos(math.radians(a)), self.d * math.sin(math.radians(a)))
            for a in ACTUATOR_ANGLES_DEG
        ]

    @property
    def ring_centres_z(self) -> list[float]:
        return [k * self.epsa.length / (self.n_rings + 1) for k in range(1, self.n_rings + 1)]

    @property
    def max_diameter(self) -> float:
        return 2 * self.foot.tip_radius

    @property
    def bundle_diameter(self) -> float:
        """Envelope of the actuator bundle, 2 (d + R0) (46 mm for Table 1: the prototype minimum)."""
        return self.body.envelope_diameter


DESIGN_TYPES: dict[str, type] = {
    "epsa": EPSADesign,
    "foot": FootDesign,
    "ring": RingDesign,
    "robot": RobotDesign,
}


def load_design(
    path: str | Path, parameter: str = "path"
) -> EPSADesign | FootDesign | RingDesign | RobotDesign:
    """Any design file, its class by its ``kind``; errors name `parameter` (unreadable) or the field."""
    data = read_design_file(path, parameter)
    kind, known = data.get("kind"), sorted(DESIGN_TYPES)
    if not isinstance(kind, str) or kind not in DESIGN_TYPES:
        why = "the key 'kind' is missing" if "kind" not in data else f"unknown design kind {brief(kind)}"
        raise DesignError("kind", f"{why} (one of {known})")
    return DESIGN_TYPES[kind].from_dict(data)
