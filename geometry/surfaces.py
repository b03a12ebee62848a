"""Watertight triangulated surfaces built from simple primitives (numpy in, pyvista out).

Every solid of this package is described by closed, outward-oriented triangle surfaces:

* :func:`revolve_profile` turns a closed polygon in the (r, z) half plane, listed counter-clockwise
  (solid on the left), into a closed surface of revolution about the z axis. A profile vertex on the
  axis (r = 0) becomes a single pole vertex, so a profile that runs along the axis gives a solid
  without a hole. The surface is exact at the ``n_theta`` meridians: every vertex lies on the exact
  surface of revolution; facets are chords (sagitta r (1 - cos(pi / n_theta))).
* :func:`prism_with_holes` extrudes a planar region (outer circle minus circular holes) along z.
* :func:`flipped` reverses the orientation of a surface (an inner cavity boundary).

The returned :class:`pyvista.PolyData` are triangles only, with consistent outward normals.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import pyvista as pv


def triangle_polydata(points: np.ndarray, tris: np.ndarray) -> pv.PolyData:
    """A pyvista surface of the triangles `tris` (t, 3) on `points` (n, 3)."""
    import pyvista as pv

    faces = np.hstack([np.full((len(tris), 1), 3, dtype=np.int64), tris.astype(np.int64)])
    return pv.PolyData(np.asarray(points, dtype=float), faces.ravel())


def subdivide_profile(profile: np.ndarray, max_edge: float) -> np.ndarray:
    """Insert points on each edge of a closed polygon so no edge is longer than ``max_edge``."""
    profile = np.asarray(profile, dtype=float)
    out = []
    for a, b in zip(profile, np.roll(profile, -1, axis=0)):
        n = max(1, int(np.ceil(np.linalg.norm(b - a) / max_edge)))
        t = np.arange(n)[:, None] / n
        out.append(a + t * (b - a))
    return np.vstack(out)


def revolve_arrays(profile: np.ndarray, n_theta: int) -> tuple[np.ndarray, np.ndarray]:
    """Points and triangles of the surface of revolution of a closed CCW (r, z) polygon.

    Vertices with r == 0 become poles (one vertex each). Edges lying on the axis are skipped.
    """
    profile = np.asarray(profile, dtype=float)
    m = len(profile)
    theta = 2 * np.pi * np.arange(n_theta) / n_theta
    on_axis = profile[:, 0] <= 1e-12
    index = np.empty((m, n_theta), dtype=np.int64)
    points = []
    count = 0
    for k, (r, z) in enumerate(profile):
        if on_axis[k]:
            points.append([[0.0, 0.0, z]])
            index[k, :] = count
            count += 1
        else:
            points.append(np.column_stack([r * np.cos(theta), r * np.sin(theta), np.full(n_theta, z)]))
            index[k, :] = count + np.arange(n_theta)
            count += n_theta
    tris = []
    j0 = np.arange(n_theta)
    j1 = np.roll(j0, -1)
    for k in range(m):
        k1 = (k + 1) % m
        if on_axis[k] and on_axis[k1]:
            continue
        a, b = index[k, j0], index[k, j1]
        c, d = index[k1, j0], index[k1, j1]
        # Walking the profile CCW (solid on the left) with theta increasing: the outward normal is
        # (theta direction) x (profile direction) -> triangles (a, b, d), (a, d, c).
        if on_axis[k]:
            tris.append(np.column_stack([a, d, c]))
        elif on_axis[k1]:
            tris.append(np.column_stack([a, b, c]))
        else:
            tris.append(np.column_stack([a, b, d]))
            tris.append(np.column_stack([a, d, c]))
    return np.vstack(points), np.vstack(tris)


def revolve_profile(profile: np.ndarray, n_theta: int) -> pv.PolyData:
    """Closed surface of revolution (pyvista.PolyData) of a closed CCW (r, z) polygon."""
    return triangle_polydata(*revolve_arrays(profile, n_theta))


def flipped(surface: pv.PolyData) -> pv.PolyData:
    """The same surface with reversed orientation (triangle winding)."""
    tris = surface.faces.reshape(-1, 4)[:, 1:]
    return triangle_polydata(np.asarray(surface.points), tris[:, ::-1])


def merge(*surfaces: pv.PolyData) -> pv.PolyData:
    """Concatenate surfaces (no vertex welding): a multi-shell closed surface."""
    pts, tris, off = [], [], 0
    for s in surfaces:
        pts.append(np.asarray(s.points))
        tris.append(s.faces.reshape(-1, 4)[:, 1:] + off)
        off += s.n_points
    return triangle_polydata(np.vstack(pts), np.vstack(tris))


def signed_volume(surface: pv.PolyData) -> float:
    """Enclosed volume of a closed oriented triangle surface (divergence theorem)."""
    p = np.asarray(surface.points)
    t = surface.faces.reshape(-1, 4)[:, 1:]
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
