r"""Rigid analytic surfaces for contact: a plane and the inside of a circular cylinder.

A surface gives, at spatial points x (n, 3), the signed gap g (positive: separated, negative:
penetrating), the unit normal n pointing from the wall into the admissible side (the side where
the body lives) and the curvature operator C with dn/dx = -C (n, 3, 3), or None where the
normal is constant.

- `Plane(point, normal)`: g = (x - x0) . n, n constant, C = 0.
- `CylinderWall(radius, centre, axis)`: the body lives inside a cylinder of radius R about the
  line through `centre` along the unit `axis` a. With r_vec = (I - a a)(x - c), r = |r_vec| and
  e = r_vec / r: g = R - r, n = -e, and de/dx = (I - a a - e e) / r, so C = t t / r with t the
  circumferential direction (I - a a - e e = t t). A point on the axis has no defined normal;
  it is never in contact for R > 0 (its gap is R).

Both are frozen dataclasses; `with_radius` gives a shrunk or grown copy of the cylinder, which is
how the staged insertion of `fem.contact_stages` moves the wall. The cylinder is the straight pipe
of any axis (a vertical pipe is the same wall); the elbow, two legs and a torus section behind the
same `project`, is `fem.pipe_surfaces.ElbowPipe`; a bellows-like pipe `fem.corrugated_pipe.CorrugatedPipe`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from softcrawl.fem.errors import SolverInputError


def unit3(v, parameter: str) -> np.ndarray:
    """A finite, non-zero 3-vector, normalised; `SolverInputError` naming `parameter` otherwise."""
    v = np.asarray(v, dtype=float).reshape(-1)
    if v.shape != (3,) or not np.all(np.isfinite(v)) or np.linalg.norm(v) == 0:
        raise SolverInputError(parameter, f"must be a finite, non-zero 3-vector, got {v!r}")
    return v / np.linalg.norm(v)


def point3(v, parameter: str) -> np.ndarray:
    """A finite 3-vector; `SolverInputError` naming `parameter` otherwise."""
    v = np.asarray(v, dtype=float).reshape(-1)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise SolverInputError(parameter, f"must be a finite 3-vector, got {v!r}")
    return v


def positive(value, parameter: str) -> float:
    """A finite number > 0, as float; `SolverInputError` naming `parameter` otherwise."""
    try:
        ok = np.isfinite(float(value)) and float(value) > 0
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise SolverInputError(parameter, f"must be a positive number, got {value!r}")
    return float(value)


@dataclass(frozen=True)
class Plane:
    """The half space (x - point) . normal >= 0 is admissible; `normal` points into it."""

    point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    normal: tuple[float, float, float] = (0.0, 0.0, 1.0)
    _n: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "point", tuple(point3(self.point, "contact.surface.point")))
        n = unit3(self.normal, "contact.surface.normal")
        object.__setattr__(self, "normal", tuple(n))
        object.__setattr__(self, "_n", n)

    def project(self, x: np.ndarray):
        """(gap (n,), normal (n, 3), curvature None) at points x (n, 3)."""
        g = (x - np.asarray(self.point)) @ self._n
        return g, np.broadcast_to(self._n, x.shape), None


@dataclass(frozen=True)
class CylinderWall:
    """The inside of a cylinder of `radius` about the line through `centre` along `axis`."""

    radius: float
    centre: tuple[float, float, float] = (0.0, 0.0, 0.0)
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    _a: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "radius", positive(self.radius, "contact.surface.radius"))
        object.__setattr__(self, "centre", tuple(point3(self.centre, "contact.surface.centre")))
        a = unit3(self.axis, "contact.surface.axis")
        object.__setattr__(self, "axis", tuple(a))
        object.__setattr__(self, "_a", a)

    def with_radius(self, radius: float) -> CylinderWall:
        return replace(self, radius=radius)

    def arc_length(self, x: np.ndarray) -> np.ndarray:
        """Position (n,) of points x (n, 3) along the centreline: (x - centre) . axis."""
        return (np.asarray(x, dtype=float).reshape(-1, 3) - np.asarray(self.centre)) @ self._a

    def project(self, x: np.ndarray):
        """(gap (n,), normal (n, 3), curvature C (n, 3, 3) with dn/dx = -C) at points x (n, 3)."""
        a = self._a
        d = x - np.asarray(self.centre)
        r_vec = d - np.outer(d @ a, a)
        r = np.linalg.norm(r_vec, axis=1)
        safe = np.maximum(r, 1e-12 * self.radius)
        e = r_vec / safe[:, None]
        t = np.cross(a, e)  # circumferential direction
        C = t[:, :, None] * t[:, None, :] / safe[:, None, None]
        return self.radius - r, -e, C
