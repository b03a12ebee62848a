"""Connecting ring (ABS): a plate of thickness t with three actuator holes and a central bore.

Plate region in the (x, y) plane: the disk rho <= R_out minus the holes |x - c_i| < r_h, with
c_i = d (cos psi_i, sin psi_i), psi = 90, 210, 330 deg, minus the bore rho < r_b (if r_b > 0);
extruded over z in [-t/2, t/2] (the robot places ring k at z_k). Volume
t pi (R_out^2 - 3 r_h^2 - r_b^2).

The planar region is triangulated by a Delaunay triangulation of points on the circles (spacing
below a third of the narrowest ligament, so the circle edges are recovered; checked), keeping the
triangles outside the holes; the two faces and the side walls are assembled with shared vertices,
so the surface is watertight by construction.
Tags: ``top``, ``bottom``, ``outer``, ``bore``, ``hole1..3`` (hole i holds actuator i).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from softcrawl.geometry.design import ACTUATOR_ANGLES_DEG, MIN_LIGAMENT, RingDesign
from softcrawl.geometry.surfaces import triangle_polydata
from softcrawl.geometry.tagging import RevolvedSegment

if TYPE_CHECKING:
    import pyvista as pv


def hole_centres(d: float) -> list[tuple[float, float]]:
    return [(d * math.cos(math.radians(a)), d * math.sin(math.radians(a))) for a in ACTUATOR_ANGLES_DEG]


def _circles(design: RingDesign) -> list[tuple[tuple[float, float], float]]:
    circles = [((0.0, 0.0), design.outer_radius)]
    circles += [(c, design.hole_radius) for c in hole_centres(design.d)]
    if design.bore_radius > 0:
        circles.append(((0.0, 0.0), design.bore_radius))
    return circles


def ring_volume(design: RingDesign) -> float:
    return (
        design.thickness
        * math.pi
        * (design.outer_radius**2 - 3 * design.hole_radius**2 - design.bore_radius**2)
    )


def _plate_triangulation(design: RingDesign, spacing: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    from scipy.spatial import Delaunay

    pts, loops = [], []
    count = 0
    for (cx, cy), r in _circles(design):
        n = max(24, int(math.ceil(2 * math.pi * r / spacing)))
        th = 2 * math.pi * np.arange(n) / n
        pts.append(np.column_stack([cx + r * np.cos(th), cy + r * np.sin(th)]))
        loops.append(count + np.arange(n))
        count += n
    xy = np.vstack(pts)
    tri = Delaunay(xy).simplices
    c = xy[tri].mean(axis=1)
    keep = np.hypot(c[:, 0], c[:, 1]) < design.outer_radius
    for (cx, cy), r in _circles(design)[1:]:
        keep &= np.hypot(c[:, 0] - cx, c[:, 1] - cy) > r
    tri = tri[keep]
    a, b, cc = xy[tri[:, 0]], xy[tri[:, 1]], xy[tri[:, 2]]
    cw = ((b[:, 0] - a[:, 0]) * (cc[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (cc[:, 0] - a[:, 0])) < 0
    tri[cw] = tri[cw][:, [0, 2, 1]]
    # boundary edges (used once), directed with the plate on their left
    e = np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    key = np.sort(e, axis=1)
    _, inv, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    bnd = e[cnt[inv.ravel()] == 1]
    if len(bnd) != count:
        raise RuntimeError("ring triangulation did not recover the circle edges; reduce the spacing")
    return xy, tri, bnd


def ring_surface(design: RingDesign, spacing: float | None = None) -> pv.PolyData:
    """Closed, outward-oriented ring surface, z in [-t/2, t/2]."""
    if spacing is None:
        gaps = [
            design.d * math.sqrt(3) - 2 * design.hole_radius,
            design.outer_radius - design.d - design.hole_radius,
        ]
        if design.bore_radius > 0:
            gaps.append(design.d - design.hole_radius - design.bore_radius)
        spacing = max(min(gaps) / 3.0, MIN_LIGAMENT / 4)
        spacing = min(spacing, 2 * math.pi * design.hole_radius / 48)
    xy, tri, bnd = _plate_triangulation(design, spacing)
    n = len(xy)
    h = design.thickness / 2
    points = np.vstack([np.column_stack([xy, np.full(n, -h)]), np.column_stack([xy, np.full(n, h)])])
    faces = [tri[:, ::-1], tri + n]
    i, j = bnd[:, 0], bnd[:, 1]
    faces += [np.column_stack([i, j, j + n]), np.column_stack([i, j + n, i + n])]
    return triangle_polydata(points, np.vstack(faces))


def ring_segments(design: RingDesign, z0: float = 0.0) -> list[RevolvedSegment]:
    h = design.thickness / 2
    R = design.outer_radius
    segs = [
        RevolvedSegment("bottom", (0.0, z0 - h), (R, z0 - h)),
        RevolvedSegment("outer", (R, z0 - h), (R, z0 + h), curved=True),
        RevolvedSegment("top", (R, z0 + h), (0.0, z0 + h)),
    ]
    for k, c in enumerate(hole_centres(design.d), start=1):
        segs.append(
            RevolvedSegment(
                f"hole{k}", (design.hole_radius, z0 + h), (design.hole_radius, z0 - h), c, curved=True
            )
        )
    if design.bore_radius > 0:
        segs.append(
            RevolvedSegment("bore", (design.bore_radius, z0 + h), (design.bore_radius, z0 - h), curved=True)
        )
    return segs
