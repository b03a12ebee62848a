r"""Structured (swept) tetrahedral mesh of the ePSA: deterministic, fast, and lean for P2 elements.

Why a second mesher. pytetwild (`geometry.tetwild.mesh_epsa`) meshes any closed surface, but it is
isotropic and follows the surface triangulation: 48 segments around a 3 mm chamber give ~0.4 mm
edges and ~74k P2 unknowns for the Table 1 actuator, where quadratic elements on the exact
cylinders need far fewer. The actuator is a solid of revolution, so a swept mesh is exact in
topology and cheap: a polar cross-section triangulated and extruded in z.

Cross-section. A disc of radius R0 in `n_around` sectors: a fan of triangles around the axis up
to the chamber radius r0 (plus intermediate rings when r0 is large compared with the wall
cells), then `n_radial` rings across the wall r0..R0. Layers in the end caps (0 <= z <= c and
L - c <= z <= L) use the whole disc; layers along the chamber only the wall annulus, so the
cavity stays empty.

Prisms to tetrahedra. Each triangular prism (a, b, c | a', b', c') with a < b < c (global node
numbers; the top layer keeps the order) is split into [a, b, c, a'], [b, c, a', b'], [c, a', b', c'].
Every quadrilateral face is then cut along the diagonal from its larger bottom node to its
smaller top node, whichever prism it belongs to, so neighbouring prisms conform.

Tags (exact predicates, the mesh being structured): `outer` (rho = R0), `end_bottom` (z = 0),
`end_top` (z = L), `chamber_wall` (rho = r0, c < z < L - c), `chamber_ends` (z = c or L - c,
rho < r0). The same `meta['curved_surfaces']` as the pytetwild meshes, so `to_skfem(order=2)`
puts the midside nodes on the exact cylinders.
"""

from __future__ import annotations

import numpy as np

from softcrawl.geometry.design import DesignError, EPSADesign
from softcrawl.geometry.epsa_shape import epsa_segments, fiber_helices
from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tagging import curved_surface_meta, orient_positive


def cross_section(
    r0: float, R0: float, n_around: int, n_radial: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Polar cross-section: nodes (n, 2), triangles (t, 3), and a mask of the wall triangles."""
    wall = (R0 - r0) / n_radial
    n_inner = max(1, int(round(r0 / wall)))
    theta = 2 * np.pi * np.arange(n_around) / n_around
    radii = [r0 * k / n_inner for k in range(1, n_inner)] + list(np.linspace(r0, R0, n_radial + 1))
    nodes = [np.zeros((1, 2))] + [np.column_stack([r * np.cos(theta), r * np.sin(theta)]) for r in radii]
    ring = lambda k: 1 + k * n_around + (np.arange(n_around) % n_around)  # noqa: E731
    nxt = lambda k: 1 + k * n_around + ((np.arange(n_around) + 1) % n_around)  # noqa: E731
    tris = [np.column_stack([np.zeros(n_around, int), ring(0), nxt(0)])]
    is_wall = [np.zeros(n_around, bool)]
    for k in range(len(radii) - 1):
        a, b, c, d = ring(k), nxt(k), ring(k + 1), nxt(k + 1)
        tris += [np.column_stack([a, c, d]), np.column_stack([a, d, b])]
        inside_wall = k >= n_inner - 1
        is_wall += [np.full(n_around, inside_wall)] * 2
    return np.vstack(nodes), np.vstack(tris), np.concatenate(is_wall)


def levels(a: float, b: float, size: float) -> np.ndarray:
    n = max(1, int(np.ceil((b - a) / size - 1e-9)))
    return np.linspace(a, b, n + 1)


def mesh_epsa_swept(
    design: EPSADesign | None = None,
    *,
    n_around: int = 16,
    n_radial: int = 2,
    axial_size: float = 5.0,
    fiber_points_per_turn: int = 32,
    seal_head: bool = False,
) -> TaggedMesh:
    """Swept tetrahedral mesh of the ePSA body (region `epsa`) with its five tags and fibers.

    `seal_head=True` adds the ABS seal head, L <= z <= L + t_s, as region `seal_head` sharing
    the nodes of the body's top face (a perfect tie). Then `end_top` lists those interface
    facets (inside the mesh) and the seal head's free faces are tagged `seal_top` and `seal_side`.
    """
    design = design or EPSADesign()
    if n_around < 6:
        raise DesignError("n_around", f"needs at least 6 sectors around, got {n_around}")
    if n_radial < 1:
        raise DesignError("n_radial", f"needs at least 1 cell across the wall, got {n_radial}")
    if not axial_size > 0:
        raise DesignError("axial_size", f"must be positive, got {axial_size}")
    R0, r0, L, c = design.outer_radius, design.chamber_radius, design.length, design.end_cap_thickness
    xy, tris, is_wall = cross_section(r0, R0, n_around, n_radial)
    t_s = design.seal_head_thickness if seal_head else 0.0
    z = np.unique(
        np.concatenate(
            [levels(0, c, axial_size), levels(c, L - c, axial_size), levels(L - c, L, axial_size)]
            + ([levels(L, L + t_s, axial_size)] if seal_head else [])
        )
    )
    n2 = len(xy)
    points = np.column_stack([np.tile(xy, (len(z), 1)), np.repeat(z, n2)])
    tris = np.sort(tris, axis=1)
    tets, region = [], []
    for k in range(len(z) - 1):
        zmid = 0.5 * (z[k] + z[k + 1])
        in_cap = zmid < c or zmid > L - c
        layer = tris if in_cap else tris[is_wall]
        a, b, cc = (layer[:, i] + k * n2 for i in range(3))
        a1, b1, c1 = a + n2, b + n2, cc + n2
        tets += [np.column_stack(t) for t in ((a, b, cc, a1), (b, cc, a1, b1), (cc, a1, b1, c1))]
        region += [np.full(3 * len(layer), 2 if zmid > L else 1)]
    tets = np.vstack(tets).astype(np.int64)
    region = np.concatenate(region)
    orient_positive(points, tets)
    facets = _tag_facets(points, tets, design, t_s)
    names = {1: "epsa", 2: "seal_head"} if seal_head else {1: "epsa"}
    mesh = TaggedMesh(
        points,
        tets,
        region,
        names,
        facets,
        tuple(fiber_helices(design, fiber_points_per_turn)),
        design.short_hash(),
        float(axial_size),
        {
            "kind": "epsa",
            "mesher": "swept",
            "n_around": n_around,
            "n_radial": n_radial,
            "axial_size": axial_size,
            "fiber_points_per_turn": fiber_points_per_turn,
            "curved_surfaces": curved_surface_meta(epsa_segments(design)),
        },
    )
    return mesh


def boundary_faces(tets: np.ndarray) -> np.ndarray:
    """Boundary triangles, outward-oriented (faces that belong to exactly one tet)."""
    local = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])  # outward for positive tets
    faces = tets[:, local].reshape(-1, 3)
    key = np.sort(faces, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return faces[counts[inverse.reshape(-1)] == 1]


def _tag_facets(
    points: np.ndarray, tets: np.ndarray, design: EPSADesign, seal_thickness: float = 0.0
) -> dict[str, np.ndarray]:
    R0, r0, L, c = design.outer_radius, design.chamber_radius, design.length, design.end_cap_thickness
    faces = boundary_faces(tets)
    top = L + seal_thickness
    p = points[faces]  # (f, 3 vertices, 3)
    rho = np.hypot(p[..., 0], p[..., 1])
    zz = p[..., 2]
    tol = 1e-9 * max(R0, L)
    on = lambda cond: np.all(cond, axis=1)  # noqa: E731
    tags = {
        "end_bottom": on(np.abs(zz) < tol),
        "end_top": on(np.abs(zz - top) < tol),
        "outer": on(np.abs(rho - R0) < 1e-9 * R0) & on(zz < L + tol),
        "chamber_wall": on(np.abs(rho - r0) < 1e-9 * R0)
        & on(zz > c - tol)
        & on(zz < L - c + tol)
        & ~on(np.abs(zz - c) < tol)
        & ~on(np.abs(zz - (L - c)) < tol),
        "chamber_ends": (on(np.abs(zz - c) < tol) | on(np.abs(zz - (L - c)) < tol)) & on(rho < r0 + tol),
    }
    if seal_thickness > 0:
        tags["seal_top"] = tags.pop("end_top")
        tags["seal_side"] = on(np.abs(rho - R0) < 1e-9 * R0) & on(zz > L - tol)
    assigned = np.sum(list(tags.values()), axis=0)
    if not np.all(assigned == 1):
        raise RuntimeError(f"swept mesh tagging: {np.sum(assigned != 1)} facets with {set(assigned)} tags")
    out = {k: faces[v].astype(np.int64) for k, v in tags.items()}
    if seal_thickness > 0:  # the body's top face, now the interface with the seal head
        all_faces = tets[:, [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]]].reshape(-1, 3)
        on_top = np.all(np.abs(points[all_faces][..., 2] - L) < tol, axis=1)
        key = np.sort(all_faces[on_top], axis=1)
        _, first = np.unique(key, axis=0, return_index=True)
        out["end_top"] = all_faces[on_top][first].astype(np.int64)
    return out
