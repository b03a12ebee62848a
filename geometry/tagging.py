"""Boundary facets of a tetrahedral mesh and their tags, found by geometric predicates.

pytetwild (fTetWild) keeps no surface tags and moves boundary vertices within its envelope, so the
tags are recovered after meshing. Each part describes its boundary as a list of
:class:`RevolvedSegment` (tag, a straight segment p0 -> p1 in the (rho, z) half plane, revolved about
an axis parallel to z through ``centre``). A segment with constant z is a plane annulus, one with
constant rho a cylinder, any other a cone. The segment is listed with the solid on its left, so the
outward normal in the (rho, z) plane is the right normal (t_z, -t_rho) of the direction t.

A boundary facet gets the tag of the segment that is nearest to all three of its vertices (the
largest vertex distance), provided that distance is within ``tol`` and the facet normal points
within 60 degrees of the segment's outward normal. :func:`snap_to_surfaces` then moves the tagged
vertices onto the exact surfaces (closest point on the segment, same polar angle about the axis),
reverting any move that would invert a tetrahedron.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Local faces of a positively oriented tet (a, b, c, d), each listed with an outward normal.
TET_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])


@dataclass(frozen=True)
class RevolvedSegment:
    """A tagged surface patch: segment p0 -> p1 in (rho, z), revolved about the axis at ``centre``."""

    tag: str
    p0: tuple[float, float]
    p1: tuple[float, float]
    centre: tuple[float, float] = (0.0, 0.0)
    curved: bool = False  # True when rho varies over the surface (cylinder, cone): P2 nodes are snapped

    def _rz(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        dx = x[:, 0] - self.centre[0]
        dy = x[:, 1] - self.centre[1]
        rho = np.hypot(dx, dy)
        return dx, dy, rho, x[:, 2]

    def closest(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Closest points on the surface to x (n, 3) and their distances."""
        dx, dy, rho, z = self._rz(x)
        p0 = np.asarray(self.p0, float)
        p1 = np.asarray(self.p1, float)
        t = p1 - p0
        s = np.clip(((rho - p0[0]) * t[0] + (z - p0[1]) * t[1]) / (t @ t), 0.0, 1.0)
        rq = p0[0] + s * t[0]
        zq = p0[1] + s * t[1]
        safe = np.where(rho > 1e-12, rho, 1.0)
        cx = np.where(rho > 1e-12, dx / safe, 1.0)
        cy = np.where(rho > 1e-12, dy / safe, 0.0)
        q = np.column_stack([self.centre[0] + rq * cx, self.centre[1] + rq * cy, zq])
        return q, np.hypot(rho - rq, z - zq)

    def normal(self, x: np.ndarray) -> np.ndarray:
        """Outward unit normal of the exact surface at (the polar angle of) x."""
        dx, dy, rho, _ = self._rz(x)
        t = np.asarray(self.p1, float) - np.asarray(self.p0, float)
        t = t / np.linalg.norm(t)
        n_rho, n_z = t[1], -t[0]
        safe = np.where(rho > 1e-12, rho, 1.0)
        return np.column_stack([n_rho * dx / safe, n_rho * dy / safe, np.full(len(x), n_z)])

    def area(self) -> float:
        """Exact area of the revolved segment (full revolution): pi (rho0 + rho1) |p1 - p0|."""
        return float(
            np.pi * (self.p0[0] + self.p1[0]) * np.hypot(self.p1[0] - self.p0[0], self.p1[1] - self.p0[1])
        )


def curved_surface_meta(segments: list[RevolvedSegment]) -> dict[str, list]:
    """``TaggedMesh.meta['curved_surfaces']``: per tag, [p0, p1, centre] of its curved segments."""
    out: dict[str, list] = {}
    for s in segments:
        if s.curved:
            out.setdefault(s.tag, []).append([list(s.p0), list(s.p1), list(s.centre)])
    return out


def boundary_facets(tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Outward-oriented boundary triangles (k, 3) of positively oriented tets, and their tet index."""
    faces = tets[:, TET_FACES].reshape(-1, 3)
    owner = np.repeat(np.arange(len(tets)), 4)
    key = np.sort(faces, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    once = counts[inverse.ravel()] == 1
    return faces[once], owner[once]


def facet_normals(points: np.ndarray, tris: np.ndarray) -> np.ndarray:
    a, b, c = points[tris[:, 0]], points[tris[:, 1]], points[tris[:, 2]]
    n = np.cross(b - a, c - a)
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def classify_facets(
    points: np.ndarray,
    tris: np.ndarray,
    segments: list[RevolvedSegment],
    tol: float,
    min_alignment: float = 0.5,
) -> np.ndarray:
    """Index into ``segments`` for each triangle, -1 where no segment matches."""
    normals = facet_normals(points, tris)
    centroids = points[tris].mean(axis=1)
    best = np.full(len(tris), -1)
    best_dist = np.full(len(tris), np.inf)
    for i, seg in enumerate(segments):
        dist = np.max([seg.closest(points[tris[:, k]])[1] for k in range(3)], axis=0)
        align = np.einsum("ij,ij->i", normals, seg.normal(centroids))
        ok = (dist <= tol) & (align >= min_alignment) & (dist < best_dist)
        best[ok] = i
        best_dist[ok] = dist[ok]
    return best


def tet_volumes(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    a = points[tets[:, 0]]
    return (
        np.einsum(
            "ij,ij->i", np.cross(points[tets[:, 1]] - a, points[tets[:, 2]] - a), points[tets[:, 3]] - a
        )
        / 6.0
    )


def orient_positive(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Swap two vertices of every tetrahedron of negative volume, in place; return the volumes
    (all non-negative after the swap)."""
    vol = tet_volumes(points, tets)
    tets[vol < 0] = tets[vol < 0][:, [0, 2, 1, 3]]
    return np.abs(vol)


def snap_to_surfaces(
    points: np.ndarray,
    tets: np.ndarray,
    facets: dict[str, np.ndarray],
    segments: dict[str, list[RevolvedSegment]],
    max_move: float,
) -> tuple[np.ndarray, int]:
    """Project the vertices of tagged facets onto their exact surfaces.

    ``segments`` maps a tag to the surfaces it may lie on (a vertex goes to the nearest). Vertices on
    several tags (edges of the part) are projected in turn, which lands them on the intersection
    curve for the orthogonal plane/cylinder pairs of these parts. Moves larger than ``max_move`` are
    skipped; moves that would make a tet's volume drop below 10 % of its old value are reverted.
    Returns the new points and the number of vertices moved.
    """
    new = points.copy()
    for tag, tris in facets.items():
        if tag not in segments or len(tris) == 0:
            continue
        verts = np.unique(tris)
        x = new[verts]
        q_best = x.copy()
        d_best = np.full(len(verts), np.inf)
        for seg in segments[tag]:
            q, d = seg.closest(x)
            take = d < d_best
            q_best[take] = q[take]
            d_best[take] = d[take]
        move = d_best <= max_move
        new[verts[move]] = q_best[move]
    vol0 = tet_volumes(points, tets)
    for _ in range(10):
        bad = tet_volumes(new, tets) < 0.1 * vol0
        if not bad.any():
            break
        revert = np.unique(tets[bad])
        new[revert] = points[revert]
    moved = int(np.count_nonzero(np.any(new != points, axis=1)))
    return new, moved


def _point_segment(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", x - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return np.linalg.norm(x - (a + t[:, None] * ab), axis=1)


def point_triangle_distance(x: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Distance of points x (n, 3) to triangles (a, b, c) (n, 3 each), pairwise.

    If the projection on the triangle's plane falls inside (barycentric coordinates >= 0) the distance
    is the plane distance, otherwise the distance to the nearest edge.
    """
    n = np.cross(b - a, c - a)
    nn = np.einsum("ij,ij->i", n, n)
    dist_plane = np.einsum("ij,ij->i", x - a, n) / np.sqrt(nn)
    p = x - (dist_plane / np.sqrt(nn))[:, None] * n
    w_a = np.einsum("ij,ij->i", np.cross(c - b, p - b), n) / nn
    w_b = np.einsum("ij,ij->i", np.cross(a - c, p - c), n) / nn
    w_c = 1.0 - w_a - w_b
    inside = (w_a >= 0) & (w_b >= 0) & (w_c >= 0)
    edge = np.minimum(np.minimum(_point_segment(x, a, b), _point_segment(x, b, c)), _point_segment(x, c, a))
    return np.where(inside, np.abs(dist_plane), edge)


def distance_to_surface(x: np.ndarray, points: np.ndarray, tris: np.ndarray, k: int = 12) -> np.ndarray:
    """Distance of points x to a triangle set (exact among the k triangles with the nearest centroids)."""
    from scipy.spatial import cKDTree

    cent = points[tris].mean(axis=1)
    _, idx = cKDTree(cent).query(x, k=min(k, len(tris)))
    idx = np.atleast_2d(idx.T).T if idx.ndim == 1 else idx
    best = np.full(len(x), np.inf)
    for j in range(idx.shape[1]):
        t = tris[idx[:, j]]
        best = np.minimum(best, point_triangle_distance(x, points[t[:, 0]], points[t[:, 1]], points[t[:, 2]]))
    return best


def closest_on_triangles(
    x: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Closest points of triangles (a, b, c) to x, pairwise: (distance (n,), barycentric (n, 3))."""
    n = np.cross(b - a, c - a)
    nn = np.einsum("ij,ij->i", n, n)
    dist_plane = np.einsum("ij,ij->i", x - a, n) / np.sqrt(nn)
    p = x - (dist_plane / np.sqrt(nn))[:, None] * n
    wa = np.einsum("ij,ij->i", np.cross(c - b, p - b), n) / nn
    wb = np.einsum("ij,ij->i", np.cross(a - c, p - c), n) / nn
    bary = np.column_stack([wa, wb, 1.0 - wa - wb])
    dist = np.abs(dist_plane)
    inside = (bary >= 0).all(axis=1)
    if (~inside).any():
        best = np.full(len(x), np.inf)
        best_bary = np.zeros((len(x), 3))
        for i, j in ((0, 1), (1, 2), (2, 0)):
            pi, pj = (a, b, c)[i], (a, b, c)[j]
            e = pj - pi
            t = np.clip(np.einsum("ij,ij->i", x - pi, e) / np.einsum("ij,ij->i", e, e), 0.0, 1.0)
            d = np.linalg.norm(x - (pi + t[:, None] * e), axis=1)
            take = d < best
            best[take] = d[take]
            w = np.zeros((len(x), 3))
            w[:, i], w[:, j] = 1.0 - t, t
            best_bary[take] = w[take]
        dist = np.where(inside, dist, best)
        bary = np.where(inside[:, None], bary, best_bary)
    return dist, bary


def embed_points(
    x: np.ndarray, points: np.ndarray, tris: np.ndarray, k: int = 12
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Host triangle, barycentric coordinates and distance of each point x on a triangle set.

    Among the k triangles with the nearest centroids, the one with the closest point is taken;
    returns (triangle index (n,), barycentric (n, 3), distance (n,)).
    """
    from scipy.spatial import cKDTree

    cent = points[tris].mean(axis=1)
    _, idx = cKDTree(cent).query(x, k=min(k, len(tris)))
    idx = idx.reshape(len(x), -1)
    best = np.full(len(x), np.inf)
    host = np.zeros(len(x), dtype=np.int64)
    bary = np.zeros((len(x), 3))
    for j in range(idx.shape[1]):
        t = tris[idx[:, j]]
        d, w = closest_on_triangles(x, points[t[:, 0]], points[t[:, 1]], points[t[:, 2]])
        take = d < best
        best[take], host[take], bary[take] = d[take], idx[take, j], w[take]
    return host, bary, best
