"""Pipe centrelines for planning: straight, vertical, and an elbow (L-shape) with a bend radius.

Frame: the pipe starts at the origin along +z (the robot's rear foot frame at the start). An elbow
turns towards +x in the x-z plane: an entry leg of length `entry` along z, a circular arc of
centreline radius `bend_radius` through `bend_angle` (90 deg for the paper's L-shape), then an exit
leg. The entry leg is extended to -infinity and the exit leg to +infinity, so points behind the
start or past the end are still measured against the pipe (the robot enters from and leaves into
pipe).

For a point x, `locate` returns the distance to the centreline and the arc-length coordinate s of
the nearest centreline point. A body tube of radius r is inside the pipe of diameter D iff every
point of its centreline has distance <= D/2 - r.

"vertical" is geometrically a straight pipe; it differs in the axial gravity the planner applies to
the statics (the robot climbs against g).

`Pipe` is the one description of a pipe's geometry: the analytic planner measures against its
centreline, and the FE foot and crawl studies (`studies.foot.model`, `studies.crawl`) build their
rigid wall (`fem.rigid_surfaces.CylinderWall`, a straight pipe on the z axis) and its VTU from its
`radius`. The FE elbow wall (`fem.pipe_surfaces.ElbowPipe`) uses this frame by default.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.limits import MAX_LENGTH_MM, length_mm

KINDS = ("straight", "vertical", "elbow")


@dataclass(frozen=True)
class Pipe:
    kind: str = "straight"
    diameter: float = 70.0  # mm, inner diameter
    bend_radius: float = 40.0  # mm, centreline radius of the elbow
    entry: float = 150.0  # mm, entry leg (the whole length for straight/vertical)
    exit: float = 150.0  # mm, exit leg (elbow)
    bend_angle: float = np.pi / 2  # rad

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ModelInputError("pipe", f"must be one of {', '.join(KINDS)}, got {self.kind!r}")
        length_mm(self.diameter, "diameter")
        length_mm(self.entry, "length")
        if self.kind == "elbow":
            length_mm(self.bend_radius, "bend-radius")
            if not 0.0 <= self.exit <= MAX_LENGTH_MM:
                raise ModelInputError(
                    "exit-length", f"must be in [0, {MAX_LENGTH_MM:g}] mm, got {self.exit!r}"
                )
            if not 0 < self.bend_angle <= np.pi:
                raise ModelInputError("bend-angle", "must be in (0, 180] deg")

    # -- geometry ----------------------------------------------------------------------------------
    @property
    def radius(self) -> float:
        """Inner radius, mm: where the wall is."""
        return self.diameter / 2.0

    @property
    def bend_start(self) -> float:
        return self.entry

    @property
    def bend_end(self) -> float:
        return self.entry + (self.bend_radius * self.bend_angle if self.kind == "elbow" else 0.0)

    @property
    def length(self) -> float:
        return self.entry if self.kind != "elbow" else self.bend_end + self.exit

    def goal(self) -> float:
        """Arc length the rear foot must pass: the pipe end (straight) or the end of the bend."""
        return self.length if self.kind != "elbow" else self.bend_end

    def point(self, s: ArrayLike) -> np.ndarray:
        """Centreline point(s) at arc length s (extended beyond both ends)."""
        s = np.asarray(s, dtype=float)
        out = np.zeros(s.shape + (3,))
        if self.kind != "elbow":
            out[..., 2] = s
            return out
        R, a_end, L1 = self.bend_radius, self.bend_angle, self.entry
        a = np.clip((s - L1) / R, 0.0, a_end)
        out[..., 0] = R * (1 - np.cos(a))
        out[..., 2] = L1 + R * np.sin(a)
        before = s < L1
        out[before, 0] = 0.0
        out[before, 2] = s[before]
        after = s > self.bend_end
        t = s[after] - self.bend_end
        out[after, 0] = R * (1 - np.cos(a_end)) + t * np.sin(a_end)
        out[after, 2] = L1 + R * np.sin(a_end) + t * np.cos(a_end)
        return out

    def tangent(self, s: ArrayLike) -> np.ndarray:
        """Unit tangent(s) of the centreline at arc length s."""
        s = np.asarray(s, dtype=float)
        out = np.zeros(s.shape + (3,))
        if self.kind != "elbow":
            out[..., 2] = 1.0
            return out
        a = np.clip((s - self.entry) / self.bend_radius, 0.0, self.bend_angle)
        out[..., 0] = np.sin(a)
        out[..., 2] = np.cos(a)
        return out

    def locate(self, points: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """(distance to the centreline, arc length of the nearest centreline point) for (..., 3)."""
        x = np.asarray(points, dtype=float)
        px, py, pz = x[..., 0], x[..., 1], x[..., 2]
        if self.kind != "elbow":
            return np.hypot(px, py), pz.copy()
        L1, R, a_end = self.entry, self.bend_radius, self.bend_angle
        # entry leg, (-inf, L1] along z
        t1 = np.minimum(pz, L1)
        d1 = np.sqrt(px**2 + py**2 + (pz - t1) ** 2)
        s1 = t1
        # arc: centre (R, 0, L1); point(a) = C + R(-cos a, 0, sin a)
        qx, qz = px - R, pz - L1
        a = np.clip(np.arctan2(qz, -qx), 0.0, a_end)
        d2 = np.sqrt((qx + R * np.cos(a)) ** 2 + py**2 + (qz - R * np.sin(a)) ** 2)
        s2 = L1 + R * a
        # exit leg, [0, inf) from the bend end along (sin a_end, 0, cos a_end)
        ex, ez = R * (1 - np.cos(a_end)), L1 + R * np.sin(a_end)
        ux, uz = np.sin(a_end), np.cos(a_end)
        t3 = np.maximum((px - ex) * ux + (pz - ez) * uz, 0.0)
        d3 = np.sqrt((px - ex - t3 * ux) ** 2 + py**2 + (pz - ez - t3 * uz) ** 2)
        s3 = self.bend_end + t3
        d = np.stack([d1, d2, d3])
        s = np.stack([s1, s2, s3])
        k = np.argmin(d, axis=0)
        return np.take_along_axis(d, k[None], 0)[0], np.take_along_axis(s, k[None], 0)[0]

    def plane_distance(self, x: ArrayLike, z: ArrayLike) -> np.ndarray:
        """Distance of the points (x, 0, z) to the centreline: `locate`'s distance in the x-z plane.

        The bend-plane fit check of `analytic.cycle`: equal to `locate`'s distance up to rounding
        (~1e-14 mm), in about half its time (no arc length, no y terms).
        """
        px, pz = np.asarray(x, dtype=float), np.asarray(z, dtype=float)
        if self.kind != "elbow":
            return np.abs(px)
        L1, R, a_end = self.entry, self.bend_radius, self.bend_angle
        d = np.hypot(px, np.maximum(pz - L1, 0.0))
        qx, qz = px - R, pz - L1
        a = np.clip(np.arctan2(qz, -qx), 0.0, a_end)
        d = np.minimum(d, np.hypot(qx + R * np.cos(a), qz - R * np.sin(a)))
        ex, ez = R * (1 - np.cos(a_end)), L1 + R * np.sin(a_end)
        ux, uz = np.sin(a_end), np.cos(a_end)
        t = np.maximum((px - ex) * ux + (pz - ez) * uz, 0.0)
        return np.minimum(d, np.hypot(px - ex - t * ux, pz - ez - t * uz))
