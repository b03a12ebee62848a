"""Tagging by geometric predicates, without pytetwild: a Delaunay tet mesh of a (convex) cylinder."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tagging import RevolvedSegment, boundary_facets, point_triangle_distance, tet_volumes
from softcrawl.geometry.tetwild import tag_boundary

R, H = 2.0, 5.0
SEGMENTS = [
    RevolvedSegment("bottom", (0.0, 0.0), (R, 0.0)),
    RevolvedSegment("side", (R, 0.0), (R, H), curved=True),
    RevolvedSegment("top", (R, H), (0.0, H)),
]


@pytest.fixture(scope="module")
def cylinder():
    """Extruded disk triangulation, each prism split into 3 tets (diagonals by global index: conforming)."""
    from scipy.spatial import Delaunay

    xy = [np.zeros((1, 2))]
    for k, r in enumerate(np.linspace(R / 4, R, 4), start=1):
        th = 2 * np.pi * (np.arange(16 * k) + 0.5 * k) / (16 * k)
        xy.append(np.column_stack([r * np.cos(th), r * np.sin(th)]))
    xy = np.vstack(xy)
    tri = np.sort(Delaunay(xy).simplices, axis=1)
    zs = np.linspace(0, H, 9)
    n = len(xy)
    pts = np.vstack([np.column_stack([xy, np.full(n, z)]) for z in zs])
    tets = []
    for layer in range(len(zs) - 1):
        b, t = layer * n, (layer + 1) * n
        i, j, k = tri[:, 0], tri[:, 1], tri[:, 2]
        tets += [
            np.column_stack([i + b, j + b, k + b, k + t]),
            np.column_stack([i + b, j + b, j + t, k + t]),
            np.column_stack([i + b, i + t, j + t, k + t]),
        ]
    tets = np.vstack(tets).astype(np.int64)
    vol = tet_volumes(pts, tets)
    tets[vol < 0] = tets[vol < 0][:, [0, 2, 1, 3]]
    # perturb the nodes a little, as pytetwild's envelope would
    rng = np.random.default_rng(0)
    return pts + rng.uniform(-0.003, 0.003, pts.shape), tets


def test_boundary_facets_outward(cylinder):
    pts, tets = cylinder
    tris, owner = boundary_facets(tets)
    vol = np.einsum("ij,ij->i", pts[tris[:, 0]], np.cross(pts[tris[:, 1]], pts[tris[:, 2]])).sum() / 6
    assert vol == pytest.approx(tet_volumes(pts, tets).sum(), rel=1e-9)
    assert len(owner) == len(tris)


def test_tag_and_snap(cylinder):
    pts, tets = cylinder
    new, facets, n_untagged = tag_boundary(pts, tets, SEGMENTS, tol=0.05)
    assert n_untagged == 0
    mesh = TaggedMesh(new, tets, np.ones(len(tets), int), {1: "cyl"}, facets)
    assert mesh.area("bottom") == pytest.approx(math.pi * R**2, rel=0.01)
    assert mesh.area("top") == pytest.approx(math.pi * R**2, rel=0.01)
    assert mesh.area("side") == pytest.approx(2 * math.pi * R * H, rel=0.01)
    side = np.unique(facets["side"])
    assert np.allclose(np.hypot(new[side, 0], new[side, 1]), R, atol=1e-12)
    assert np.allclose(new[np.unique(facets["top"]), 2], H, atol=1e-12)
    assert (mesh.tet_volumes() > 0).all()
    m2 = mesh.to_skfem(1)
    assert {k: len(v) for k, v in m2.boundaries.items()} == {k: len(v) for k, v in facets.items()}


@settings(max_examples=60, deadline=None)
@given(x=st.floats(-10, 10), y=st.floats(-10, 10), z=st.floats(-10, 10))
def test_segment_projection_idempotent_and_nearest(x, y, z):
    p = np.array([[x, y, z]])
    for seg in SEGMENTS:
        q, d = seg.closest(p)
        q2, d2 = seg.closest(q)
        assert d2[0] == pytest.approx(0.0, abs=1e-9)
        assert np.allclose(q2, q, atol=1e-9)
        assert d[0] == pytest.approx(np.linalg.norm(q - p), abs=1e-9)


def test_point_triangle_distance():
    a, b, c = (np.array([[0.0, 0, 0]]), np.array([[1.0, 0, 0]]), np.array([[0.0, 1, 0]]))
    for x, expected in [
        ([0.2, 0.2, 0.5], 0.5),
        ([2, 0, 0], 1.0),
        ([-1, -1, 0], math.sqrt(2)),
        ([0.5, 0.5, 1], 1.0),
    ]:
        assert point_triangle_distance(np.array([x], float), a, b, c)[0] == pytest.approx(expected)
