"""Structured meshes for verification and benchmarks: box, thick-tube sector, thick-sphere octant.

Vertices come from a tensor grid in parameter space mapped onto the exact geometry; the
quadratic (`MeshTet2`) version places every edge midpoint on the curved geometry:
- tube: radius = mean of the end radii, angle of the chord midpoint, z of the chord midpoint;
- sphere: radius = mean of the end radii, direction of the chord midpoint.
So inner and outer surfaces are represented to O(h^3) instead of the O(h^2) of straight facets.
Boundaries are tagged by geometric predicates on the facet midpoints (tolerance 1e-8 relative).

The sphere octant is three hexahedral patches (a "cubed" octant: each patch spans one pole and
the octant centre (1,1,1)/sqrt 3), so no element degenerates at a pole.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import skfem


def box(size=(1.0, 1.0, 1.0), cells=(2, 2, 2)) -> skfem.MeshTet:
    m = skfem.MeshTet.init_tensor(*[np.linspace(0, s, n + 1) for s, n in zip(size, cells)])
    tol = 1e-8 * max(size)
    return m.with_boundaries(
        {
            "x0": lambda x: np.abs(x[0]) < tol,
            "x1": lambda x: np.abs(x[0] - size[0]) < tol,
            "y0": lambda x: np.abs(x[1]) < tol,
            "y1": lambda x: np.abs(x[1] - size[1]) < tol,
            "z0": lambda x: np.abs(x[2]) < tol,
            "z1": lambda x: np.abs(x[2] - size[2]) < tol,
        }
    )


def tube_sector(
    inner=3.0,
    outer=9.0,
    height=1.0,
    n_radial=4,
    n_angle=6,
    n_height=1,
    angle=np.pi / 2,
    quadratic=True,
    geometric=False,
):
    """A sector 0 <= theta <= angle of a thick tube, 0 <= z <= height.

    `geometric=True` grades the radial spacing geometrically, r = A (B/A)^s, so that cells are
    about as long radially as around (log-polar squares): right for thick tubes with B/A >> 1.

    Boundaries: inner, outer, bottom (z = 0), top (z = height), sym_y (theta = 0, the plane
    y = 0) and sym_x (theta = pi/2, the plane x = 0, when angle = pi/2).
    """
    grid = skfem.MeshTet.init_tensor(
        np.linspace(0, 1, n_radial + 1), np.linspace(0, 1, n_angle + 1), np.linspace(0, 1, n_height + 1)
    )
    s, t, w = grid.p
    r = inner * (outer / inner) ** s if geometric else inner + s * (outer - inner)
    th = t * angle
    p = np.vstack([r * np.cos(th), r * np.sin(th), w * height])
    mesh = skfem.MeshTet(p, grid.t)
    rtol = 1e-8 * outer

    def radius(x):
        return np.hypot(x[0], x[1])

    tags = {
        "inner": lambda x: np.abs(radius(x) - inner) < 1e-6 * inner,
        "outer": lambda x: np.abs(radius(x) - outer) < 1e-6 * outer,
        "bottom": lambda x: np.abs(x[2]) < rtol,
        "top": lambda x: np.abs(x[2] - height) < rtol,
        "sym_y": lambda x: np.abs(x[1]) < rtol,
    }
    if np.isclose(angle, np.pi / 2):
        tags["sym_x"] = lambda x: np.abs(x[0]) < rtol
    mesh = tag_boundaries(mesh, tags)
    return curved(mesh, "cylinder") if quadratic else mesh


def sphere_octant(inner=5.0, outer=7.5, n_radial=4, n_surface=4, quadratic=True):
    """Octant x, y, z >= 0 of a thick sphere. Boundaries: inner, outer, sym_x, sym_y, sym_z."""
    e = np.eye(3)
    centre = np.ones(3) / np.sqrt(3)
    grid = skfem.MeshTet.init_tensor(
        np.linspace(0, 1, n_surface + 1), np.linspace(0, 1, n_surface + 1), np.linspace(0, 1, n_radial + 1)
    )
    points, tets, offset = [], [], 0
    for k in range(3):
        j, l = (k + 1) % 3, (k + 2) % 3
        corners = [e[k], (e[k] + e[j]) / np.sqrt(2), centre, (e[k] + e[l]) / np.sqrt(2)]
        a, b, s = grid.p
        d = (
            np.outer(corners[0], (1 - a) * (1 - b))
            + np.outer(corners[1], a * (1 - b))
            + np.outer(corners[2], a * b)
            + np.outer(corners[3], (1 - a) * b)
        )
        d /= np.linalg.norm(d, axis=0)
        points.append(d * (inner + s * (outer - inner)))
        tets.append(grid.t + offset)
        offset += grid.p.shape[1]
    p = np.hstack(points)
    t = np.hstack(tets)
    key = np.round(p / (outer * 1e-9)).astype(np.int64)
    _, first, inverse = np.unique(key, axis=1, return_index=True, return_inverse=True)
    mesh = skfem.MeshTet(p[:, first], inverse.reshape(-1)[t])
    rtol = 1e-8 * outer
    mesh = tag_boundaries(
        mesh,
        {
            "inner": lambda x: np.abs(np.linalg.norm(x, axis=0) - inner) < 1e-6 * inner,
            "outer": lambda x: np.abs(np.linalg.norm(x, axis=0) - outer) < 1e-6 * outer,
            "sym_x": lambda x: np.abs(x[0]) < rtol,
            "sym_y": lambda x: np.abs(x[1]) < rtol,
            "sym_z": lambda x: np.abs(x[2]) < rtol,
        },
    )
    return curved(mesh, "sphere") if quadratic else mesh


def tag_boundaries(mesh, predicates):
    """The mesh with boundaries {name: facets whose three vertices satisfy the predicate}."""
    facets = mesh.boundary_facets()
    out = {}
    for name, pred in predicates.items():
        ok = np.all([pred(mesh.p[:, mesh.facets[i, facets]]) for i in range(3)], axis=0)
        out[name] = facets[ok]
    return replace(mesh, _boundaries=out)


def curved(mesh: skfem.MeshTet, kind: str) -> skfem.MeshTet2:
    m2 = skfem.MeshTet2.from_mesh(mesh)
    m2 = replace(m2, _boundaries=mesh.boundaries)
    doflocs = m2.doflocs.copy()
    edges = mesh.edges  # (2, n_edges)
    a, b = mesh.p[:, edges[0]], mesh.p[:, edges[1]]
    mid = 0.5 * (a + b)
    if kind == "cylinder":
        ra, rb = np.hypot(a[0], a[1]), np.hypot(b[0], b[1])
        rm = np.hypot(mid[0], mid[1])
        scale = np.where(rm > 0, 0.5 * (ra + rb) / np.where(rm > 0, rm, 1), 1.0)
        mid[:2] *= scale
    elif kind == "sphere":
        ra, rb, rm = np.linalg.norm(a, axis=0), np.linalg.norm(b, axis=0), np.linalg.norm(mid, axis=0)
        mid *= 0.5 * (ra + rb) / rm
    n_v = mesh.p.shape[1]
    doflocs[:, n_v : n_v + edges.shape[1]] = mid
    return replace(m2, doflocs=doflocs)


def joined(*meshes: skfem.MeshTet) -> skfem.MeshTet:
    """Several straight meshes as one mesh of disjoint bodies (no node is shared); tag it after."""
    points, cells, offset = [], [], 0
    for m in meshes:
        points.append(m.p)
        cells.append(m.t + offset)
        offset += m.p.shape[1]
    return skfem.MeshTet(np.hstack(points), np.hstack(cells))


def mirrored(mesh: skfem.MeshTet, axis: int) -> skfem.MeshTet:
    """The straight mesh reflected in the plane x_axis = 0 (cells reordered to stay positive)."""
    p = mesh.p.copy()
    p[axis] *= -1.0
    return skfem.MeshTet(p, mesh.t[[0, 2, 1, 3]])
