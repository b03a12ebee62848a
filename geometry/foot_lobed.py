r"""The lobed reading of paper Fig. 3: the foot's section swept around each of the three sub circles.

Fig. 3 shows a "scanning section" and a "scanning direction", and "d is the distance from the foot
center to the sub circle center". `geometry.foot` reads this as one section revolved about the robot
axis (the conical foot). The lobed reading sweeps the same section about each sub circle's centre
c_i = d (cos psi_i, sin psi_i) (psi_i the actuator angles): three lobes, each a revolved foot whose hub
is the actuator seat. With the conical foot's section (hub rim r_h - d about its own centre, the same
skirt, tip reach r_t - d), a lobe reaches d + (r_t - d) = r_t from the robot axis, so both readings
have the prototype's 78 mm maximum and 46 mm envelope. This module is a reading under test
(docs/decisions/066-body-geometry.md), not a production foot: no study uses it.

Tip outline. In the direction phi, Delta the angle to the nearest lobe (|Delta| <= 60 deg), the
union of the three tip circles (radius a = r_t - d about c_i) reaches
    rho(Delta) = d cos(Delta) + sqrt(a^2 - d^2 sin^2(Delta)),
r_t at a lobe and d/2 + sqrt(a^2 - 3 d^2 / 4) between two (28.86 mm for Table 1). A pipe of radius
R is touched where rho > R: |Delta| < Delta_c with cos(Delta_c) = (R^2 + d^2 - a^2) / (2 R d), a
share 3 * 2 Delta_c / (2 pi) of the circumference (`contact_share`).

The axis. The point on the robot axis lies d from every lobe's centre; with a > d and a hub of
radius r_h - d < d, it is under every lobe's skirt, whose front face crosses it at
z = -(d - (r_h - d)) / tan(angle / 2) (`axis_crossing`): the lobed foot closes the central channel
unless cut.

Mesh (`mesh_foot_lobed`). pytetwild on the three lobes' revolved surfaces (fTetWild keeps the
union: winding number > 1/2), tags of `geometry.foot` found against each lobe's segments about its
own centre, cached like every pytetwild part (`geometry.tetwild.mesh_part`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from softcrawl.geometry.design_base import ACTUATOR_ANGLES_DEG
from softcrawl.geometry.foot import foot_segments, foot_surface
from softcrawl.geometry.foot_design import FootDesign
from softcrawl.geometry.surfaces import merge
from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tetwild import CacheDir, mesh_part

#: Sectors of each lobe's input surface for pytetwild (the lobes are ~25 mm in radius).
LOBE_N_THETA = 64


def lobe_design(foot: FootDesign) -> FootDesign:
    """One lobe: the section of `foot` about a sub circle's centre (hub r_h - d, tip r_t - d, no bore)."""
    return foot.replace(
        hub_radius=foot.hub_radius - foot.d, tip_radius=foot.tip_radius - foot.d, bore_radius=0.0
    )


def lobe_centres(foot: FootDesign) -> list[tuple[float, float]]:
    return [
        (foot.d * math.cos(math.radians(a)), foot.d * math.sin(math.radians(a))) for a in ACTUATOR_ANGLES_DEG
    ]


def outline_radius(foot: FootDesign, delta: np.ndarray | float) -> np.ndarray:
    """rho(Delta) of the module docstring: the lobed tip outline's distance from the robot axis."""
    d, a = foot.d, foot.tip_radius - foot.d
    delta = np.asarray(delta, float)
    return d * np.cos(delta) + np.sqrt(a * a - (d * np.sin(delta)) ** 2)


def contact_share(foot: FootDesign, pipe_diameter: float) -> float:
    """Share of a pipe's circumference that the undeformed lobed tip outline reaches (0..1)."""
    d, a, R = foot.d, foot.tip_radius - foot.d, pipe_diameter / 2
    c = (R * R + d * d - a * a) / (2 * R * d)
    if c <= math.cos(math.pi / 3):
        return 1.0
    if c >= 1.0:
        return 0.0
    return 3 * 2 * math.acos(c) / (2 * math.pi)


def axis_crossing(foot: FootDesign) -> float | None:
    """z of the lobes' front face on the robot axis (None if the lobes do not reach the axis)."""
    r_h, r_t = foot.hub_radius - foot.d, foot.tip_radius - foot.d
    if not r_h < foot.d < r_t:
        return None
    return -(foot.d - r_h) / math.tan(math.radians(foot.angle / 2))


def mesh_foot_lobed(
    foot: FootDesign | None = None, edge_length: float = 4.0, cache_dir: CacheDir = None
) -> TaggedMesh:
    """pytetwild mesh of the lobed foot (module docstring), hub tops at z = 0, the foot's tags."""
    foot = foot or FootDesign()
    lobe, centres = lobe_design(foot), lobe_centres(foot)

    def surface():
        return merge(
            *(foot_surface(lobe, LOBE_N_THETA).translate((cx, cy, 0.0), inplace=False) for cx, cy in centres)
        )

    segments = [dataclasses.replace(s, centre=c) for c in centres for s in foot_segments(lobe)]
    sagitta = (lobe.tip_radius) * (1 - math.cos(math.pi / LOBE_N_THETA))
    return mesh_part(
        "foot_lobed",
        surface,
        segments,
        foot.short_hash(),
        "foot",
        edge_length,
        cache_dir,
        LOBE_N_THETA,
        sagitta,
    )
