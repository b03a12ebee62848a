r"""The inside of a pipe elbow as a rigid contact surface: two straight legs joined by a torus section.

The straight pipe is `fem.rigid_surfaces.CylinderWall(radius, centre, axis)`: any point on the
axis and any unit direction (a vertical pipe is the same object; gravity is a load, not a wall).
This module adds the elbow behind the same interface, `project(x) -> (g, n, C)` with the gap g
(positive inside the pipe, negative: penetrating the wall), the unit normal n from the wall into
the pipe and the curvature operator C = -dn/dx, so that it plugs into `fem.contact_law` as it is.

Geometry (`ElbowPipe`). The centreline starts at `start` along the unit `axis` a; after the
entry leg of length L1 it bends towards the unit `turn` direction t (t . a = 0) on a circle of
centreline radius R through the angle alpha (90 deg by default), then runs straight on. With
e2 = a x t (the torus axis, normal to the bend plane) and the torus centre C0 = start + L1 a + R t,
the centreline point at bend angle phi is C0 + R u(phi), u(phi) = -cos(phi) t + sin(phi) a, with
tangent w(phi) = sin(phi) t + cos(phi) a. The entry leg runs to -infinity, the exit leg (from
phi = alpha along w(alpha)) to +infinity, as in `softcrawl.analytic.pipe.Pipe`, whose frame the
defaults reproduce (start 0, axis z, turn x). The pipe's inner radius r must be below R (at r = R
the inner wall of the bend folds onto the torus axis); the wall is the set at distance r from
the centreline.

Closest point. The centreline is C1 with curvature 1/R and no two parts closer than 2R, so its
reach is R: every point x at distance d < R from the centreline has one nearest centreline point
c(x), the nearest wall point is c + r (x - c) / d, and

    g = r - d,      e = (x - c) / d,      n = -e,       dg/dx = n.

c(x) is the foot of the perpendicular on the piece whose parameter range contains it: on the
entry leg s = (x - start) . a <= L1; on the torus the bend angle phi = atan2(q . a, -q . t) of
q = x - C0 in [0, alpha]; on the exit leg s >= 0 past the bend's end. Of the pieces with a valid
foot the nearest wins (a point in the plane of a junction has the same foot on both). Every point
has one: with q = rho u(phi) + y e2, (x - start) . a - L1 = rho sin(phi) and the exit leg's
s = rho sin(phi - alpha), so the three ranges [-pi, 0], [0, alpha] and [alpha, alpha + pi] of
phi cover the circle (a point on the torus axis, rho = 0, has phi = 0).

Curvature. On a leg with direction a_k, C = (I - a_k a_k - e e) / d (`CylinderWall`). On the
torus, with rho = (x - C0) . u the distance from the torus axis and w the centreline tangent,
dc/dx = (R / rho) w w, so de/dx = (I - e e)(I - (R / rho) w w) / d and, since w . e = 0,

    C = de/dx = b b / d + (cos(theta) / rho) w w,     b = e x w,   cos(theta) = e . u,

symmetric, with the torus's two principal curvatures on the wall (d = r, rho = R + r cos theta):
1 / r around the pipe (the meridian, direction b) and cos(theta) / (R + r cos theta) along it
(direction w): positive on the outer side of the bend (theta = 0), zero at the crown
(theta = +-90 deg), negative on the inner side (theta = 180 deg, a saddle).

Junctions. At phi = 0 and phi = alpha the torus meets a leg with a common foot c, normal and
gap: g and n are continuous (C1), but C jumps by (cos(theta) / rho) w w, the torus's curvature
along the pipe, which a straight leg does not have (w is the leg's axis there). A contact point
that slides across a junction sees a continuous force and a tangent whose curvature part p_N C
changes by p_N cos(theta) / rho in the pipe's direction: a frictionless point gets no kick, and
Newton's local quadratic convergence holds only for increments in which no point crosses a
junction (the crossing is a kink of the residual's derivative, like a change of contact status
under the exact normal law). docs/decisions/073-pipe-surfaces.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.rigid_surfaces import point3, positive, unit3

#: The pieces of an elbow, as `ElbowPipe.locate` numbers them.
PIECES = ("entry", "bend", "exit")


@dataclass(frozen=True)
class ElbowPipe:
    """The inside of a pipe of inner `radius` r around an elbow centreline (module docstring)."""

    radius: float
    bend_radius: float
    entry: float = 0.0
    bend_angle: float = np.pi / 2
    start: tuple[float, float, float] = (0.0, 0.0, 0.0)
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    turn: tuple[float, float, float] = (1.0, 0.0, 0.0)
    _frame: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        r = positive(self.radius, "contact.surface.radius")
        R = positive(self.bend_radius, "contact.surface.bend_radius")
        if not R > r:
            raise SolverInputError(
                "contact.surface.bend_radius",
                f"must exceed the pipe radius {r:g} mm (got {R:g} mm): the bend's inner wall would "
                "fold onto the torus axis",
            )
        if not (np.isfinite(self.entry) and self.entry >= 0):
            raise SolverInputError("contact.surface.entry", f"must be a length >= 0 mm, got {self.entry!r}")
        if not (np.isfinite(self.bend_angle) and 0 < self.bend_angle <= np.pi):
            raise SolverInputError(
                "contact.surface.bend_angle", f"must be in (0, pi] rad, got {self.bend_angle!r}"
            )
        a = unit3(self.axis, "contact.surface.axis")
        t = unit3(self.turn, "contact.surface.turn")
        if abs(a @ t) > 1e-9:
            raise SolverInputError(
                "contact.surface.turn", f"must be perpendicular to the axis, got axis . turn = {a @ t:.3g}"
            )
        start = point3(self.start, "contact.surface.start")
        for name, value in (("radius", r), ("bend_radius", R), ("entry", float(self.entry))):
            object.__setattr__(self, name, value)
        object.__setattr__(self, "bend_angle", float(self.bend_angle))
        object.__setattr__(self, "start", tuple(start))
        object.__setattr__(self, "axis", tuple(a))
        object.__setattr__(self, "turn", tuple(t))
        centre = start + self.entry * a + R * t
        object.__setattr__(self, "_frame", (start, a, t, np.cross(a, t), centre))

    # ------------------------------------------------------------ geometry
    @property
    def diameter(self) -> float:
        return 2.0 * self.radius

    @property
    def torus_centre(self) -> np.ndarray:
        return self._frame[4].copy()

    @property
    def torus_axis(self) -> np.ndarray:
        """e2 = axis x turn, the normal of the bend plane."""
        return self._frame[3].copy()

    def centreline(self, phi) -> tuple[np.ndarray, np.ndarray]:
        """(point C0 + R u(phi), tangent w(phi)) on the bend at angles phi (k,) -> (k, 3) each."""
        _, a, t, _, c0 = self._frame
        phi = np.asarray(phi, dtype=float)[:, None]
        u = -np.cos(phi) * t + np.sin(phi) * a
        return c0 + self.bend_radius * u, np.sin(phi) * t + np.cos(phi) * a

    def frame(self, s) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(point, tangent w, outward bend direction u) of the centreline at arc lengths s (k,), each
        (k, 3); s = 0 at `start`, the legs extended; on the legs u is the torus's at their end."""
        s = np.asarray(s, dtype=float).reshape(-1)
        phi = np.clip((s - self.entry) / self.bend_radius, 0.0, self.bend_angle)
        c, w = self.centreline(phi)
        u = (c - self._frame[4]) / self.bend_radius
        past = np.where(
            s < self.entry, s - self.entry, np.maximum(s - self.entry - self.bend_radius * phi, 0.0)
        )
        return c + past[:, None] * w, w, u

    @property
    def exit_start(self) -> np.ndarray:
        return self.centreline([self.bend_angle])[0][0]

    @property
    def exit_axis(self) -> np.ndarray:
        return self.centreline([self.bend_angle])[1][0]

    def with_radius(self, radius: float) -> ElbowPipe:
        """The same centreline with another wall radius (the staged insertion moves the wall)."""
        return replace(self, radius=radius)

    # ------------------------------------------------------------ closest point
    def arc_length(self, x: np.ndarray) -> np.ndarray:
        """Arc length (n,) of the nearest centreline point of points x (n, 3), 0 at `start`."""
        return self.locate(x)[1]

    def locate(self, x: np.ndarray):
        """(piece (n,) int into `PIECES`, arc length s (n,) of the nearest centreline point, its
        position c (n, 3), its tangent (n, 3)) for points x (n, 3); s = 0 at `start`."""
        start, a, t, e2, c0 = self._frame
        L1, R, alpha = self.entry, self.bend_radius, self.bend_angle
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        s1 = (x - start) @ a
        q = x - c0
        phi = np.arctan2(q @ a, -(q @ t))
        s3 = (x - self.exit_start) @ self.exit_axis
        valid = np.stack([s1 <= L1, (phi >= 0.0) & (phi <= alpha), s3 >= 0.0])
        phi_c = np.clip(phi, 0.0, alpha)
        bend, w = self.centreline(phi_c)
        feet = np.stack(
            [
                start + np.minimum(s1, L1)[:, None] * a,
                bend,
                self.exit_start + np.maximum(s3, 0.0)[:, None] * self.exit_axis,
            ]
        )
        dist = np.linalg.norm(x[None] - feet, axis=2)
        piece = np.argmin(np.where(valid, dist, np.inf), axis=0)  # every point has a foot
        rows = np.arange(x.shape[0])
        arc = np.stack([s1, L1 + R * phi_c, L1 + R * alpha + s3])[piece, rows]
        tangent = np.stack([np.broadcast_to(a, w.shape), w, np.broadcast_to(self.exit_axis, w.shape)])
        return piece, arc, feet[piece, rows], tangent[piece, rows]

    def project(self, x: np.ndarray):
        """(gap (n,), normal (n, 3), curvature C (n, 3, 3) with dn/dx = -C) at points x (n, 3)."""
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        piece, _, c, w = self.locate(x)
        dvec = x - c
        d = np.linalg.norm(dvec, axis=1)
        safe = np.maximum(d, 1e-12 * self.radius)
        e = dvec / safe[:, None]
        eye = np.eye(3)[None]
        ee = e[:, :, None] * e[:, None, :]
        ww = w[:, :, None] * w[:, None, :]
        # straight legs and the torus: (I - e e - w w) / d around the pipe; the torus adds its
        # curvature along the pipe, cos(theta) / rho = (e . u) / ((x - C0) . u)
        C = (eye - ee - ww) / safe[:, None, None]
        on_bend = piece == 1
        if on_bend.any():
            u = (c[on_bend] - self._frame[4]) / self.bend_radius
            rho = np.maximum(np.einsum("ni,ni->n", x[on_bend] - self._frame[4], u), 1e-12 * self.radius)
            cos_theta = np.einsum("ni,ni->n", e[on_bend], u)
            C[on_bend] += (cos_theta / rho)[:, None, None] * ww[on_bend]
        return self.radius - d, -e, C
