"""Grooved flexible foot (paper Fig. 3), as a solid of revolution about the robot axis.

Reading of the text (the figure itself is not available). Fig. 3 shows (a) a design block diagram,
(b) a "scanning section" and (c) a "scanning direction": the foot is a section swept around the axis.
"d is the distance from the foot center to the sub circle center": the three sub circles are the
actuator seats at radius d on the foot. "The front surface of the foot is smooth and the back surface
is engraved with grooves", "the angle is used to describe the contact area", "h is the groove height".
The prototype's maximum diameter is 78 mm (the feet), for pipes of 55-75 mm, and the rear foot "is
flipped by the extension force", which brings the groove surface into contact with the wall.

We read this as: a hub disk that carries the three actuators, with a central bore for the endoscope,
and a conical skirt of thickness t around it, leaning backwards (towards -z, away from the direction
of travel) like a brush, so that it slides forward easily. ``angle`` is the included angle of the
skirt's cone (120 deg: the skirt leaves the hub at 60 deg from the axis); 180 deg is a flat disk. The
skirt's tip, at ``tip_radius`` = 39 mm (78 mm diameter), touches the wall of every pipe of the range.
The front face (the one facing +z and outwards, the one that touches the wall when the skirt bends
back in a pipe) is smooth; the back face (facing -z, towards the axis) carries ``n_grooves``
rectangular circumferential grooves of depth h = ``groove_height`` and width ``groove_width``,
equally spaced. Flipping the skirt forward turns the grooved face to the wall.

Section in the (rho, z) half plane, local frame with the hub's top face at z = 0, alpha = angle / 2,
u = (sin alpha, -cos alpha) the skirt direction, n = (cos alpha, sin alpha) the front-face normal:
  hub     rho in [r_bore, r_hub], z in [-t_hub, 0]
  front   F(s) = (r_hub, 0) + s u,  0 <= s <= (r_tip - r_hub) / sin alpha
  back    B(s) = F(s) - t n, starting where it meets the hub side (s = t / tan alpha, z = -t / sin alpha)
  rim     the segment F_end -> B_end (perpendicular to the skirt)
  grooves notches of depth h into the back face (towards n).
Tags: ``hub_top`` (z = 0), ``hub_bottom`` (z = -t_hub), ``hub_side``, ``bore``, ``front`` (smooth),
``back`` (grooved, groove walls included), ``rim``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.surfaces import revolve_profile, subdivide_profile
from softcrawl.geometry.tagging import RevolvedSegment

if TYPE_CHECKING:
    import pyvista as pv

FOOT_N_THETA = 96


def skirt_directions(design: FootDesign) -> tuple[np.ndarray, np.ndarray]:
    """(u, n) in the (rho, z) plane: the skirt's direction and its front face's outward normal."""
    a = math.radians(design.angle / 2)
    return np.array([math.sin(a), -math.cos(a)]), np.array([math.cos(a), math.sin(a)])


def foot_profile(design: FootDesign) -> tuple[np.ndarray, list[str]]:
    """Closed CCW (rho, z) polygon of the foot section and the tag of each edge (edge i: v_i -> v_i+1)."""
    a = math.radians(design.angle / 2)
    u, n = skirt_directions(design)
    t, h, w = design.skirt_thickness, design.groove_height, design.groove_width
    r_hub, t_hub, r_b = design.hub_radius, design.hub_thickness, design.bore_radius
    F0 = np.array([r_hub, 0.0])
    F1 = F0 + design.front_face_length * u
    B0 = np.array([r_hub, -t / math.sin(a)])
    B1 = F1 - t * n
    Lb = design.back_face_length
    pts: list[np.ndarray] = [np.array([r_b, -t_hub]), np.array([r_hub, -t_hub])]
    tags: list[str] = ["hub_bottom"]
    if abs(B0[1] + t_hub) > 1e-9:
        pts.append(B0)
        tags.append("hub_side")
    pitch = Lb / (design.n_grooves + 1)
    for i in range(design.n_grooves):
        sc = (i + 1) * pitch
        p, q = B0 + (sc - w / 2) * u, B0 + (sc + w / 2) * u
        pts += [p, p + h * n, q + h * n, q]
        tags += ["back"] * 4
    pts += [B1, F1, F0, np.array([r_b, 0.0])]
    tags += ["back", "rim", "front", "hub_top"]
    tags.append("bore")  # closing edge back to the first vertex (on the axis when r_bore = 0)
    return np.array(pts), tags


def foot_segments(design: FootDesign, z0: float = 0.0) -> list[RevolvedSegment]:
    prof, tags = foot_profile(design)
    segs = []
    for i, tag in enumerate(tags):
        p0, p1 = prof[i], prof[(i + 1) % len(prof)]
        if p0[0] <= 1e-12 and p1[0] <= 1e-12:
            continue  # an edge on the axis is not a surface
        curved = abs(p0[1] - p1[1]) > 1e-12
        segs.append(
            RevolvedSegment(
                tag, (float(p0[0]), float(p0[1] + z0)), (float(p1[0]), float(p1[1] + z0)), curved=curved
            )
        )
    return segs


def foot_surface(design: FootDesign, n_theta: int = FOOT_N_THETA) -> pv.PolyData:
    prof, _ = foot_profile(design)
    return revolve_profile(subdivide_profile(prof, 2 * math.pi * design.tip_radius / n_theta * 2), n_theta)


def foot_volume(design: FootDesign) -> float:
    """Exact volume of the revolved section, 2 pi * integral of rho over the section (Pappus)."""
    prof, _ = foot_profile(design)
    r, z = prof[:, 0], prof[:, 1]
    r1, z1 = np.roll(r, -1), np.roll(z, -1)
    # Green: integral of rho dA = closed integral of rho^2 / 2 dz = sum (z1 - z0)(r0^2 + r0 r1 + r1^2) / 6
    return float(2 * math.pi * np.sum((z1 - z) * (r * r + r * r1 + r1 * r1)) / 6.0)
