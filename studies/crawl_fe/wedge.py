r"""The FE body as one wedge of 2 pi / 3: the robot's three-fold symmetry, tied exactly (issue 34).

Why (docs/decisions/096-body-wedge.md). The body's mesh (`geometry.body_mesh`, its section
three-fold symmetric) is the same, tet for tet, under the rotation R by 120 deg about the axis z.
In a straight pipe, horizontal or vertical, with equal chamber pressures, the loads and supports
are too, and the state keeps the symmetry, u(R X) = R u(X), until a bifurcation breaks it (the
whole body's lateral drift stays below 3e-9 mm in every committed straight and vertical run). One
wedge then carries the body with a third of the unknowns. A bellows is the same at every azimuth
too, but there the whole body leaves the symmetric path at its snaps over the ridges (2.2 mm from
it by s = 0.93 of the first extension with inertia): the wedge, which cannot leave it, is not
offered there.

The wedge (`wedge_mesh`). The orbit {T, R T, R^2 T} of each tet (matched by centroid, a KD-tree;
refused when a tet has no image: the mesh is not three-fold) gives its member whose centroid's
polar angle, counted from the wedge's start psi_1 - 60 deg, is least: exactly one tet per orbit,
ePSA 1 (psi_1 = 90 deg, `ACTUATOR_ANGLES_DEG`) whole in the wedge's middle, the rings, hubs and
skirts cut. The faces the wedge shares with the next wedge's tets (R T) are tagged `cut_end`,
those shared with the previous one's (R^2 T) `cut_start` (outward, as every tag); each other tag
keeps the wedge's facets (ePSA 2 and 3's tags are gone). `cut_end` = R `cut_start` node for node,
and `fem.periodic_tie.CyclicTie` ties u_b = R u_a and the mixed pressure p_b = p_a exactly (the
tied dofs condensed out, docs/decisions/083-exact-wedge.md).

Holds (`HOLDS`). The tie leaves two of the six rigid modes: a translation t is tied only when
R t = t (along z), a turn about an axis a only when R a = a (the twist about z). The axial
translation and the twist are held by ground links on the rear hub face `rear_bottom`: hold_z on
its mean u_z, and twist on its mean u_x (the wedge sits about +y, so a turn theta gives
u_x = -theta y, of mean -theta ybar != 0, and an axial translation gives none). Two independent
springs on the two modes: isostatic, as the whole body's six (`studies.crawl_fe.model`). Each
carries the share 1 / 3 of its link (`fem.axial_link`), so its force is the whole link's.

The whole body's readings (`whole_force`, `BodyModel.volumes`, `cycle.FootProbe`). A force the
wall puts on the wedge, f, is one of three, R^k f: the whole body's is sum_k R^k f = (0, 0, 3 f_z)
(the lateral parts cancel), and a normal force's magnitude is 3 times the wedge's. The three
chambers have one volume. The feet's hub faces are one node of each of their orbits
(`face_nodes`), turned into all three wedges: the foot positions are the whole body's, and the
drift, bend and heading are 0 by construction (the symmetry is assumed, not measured).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from scipy.spatial import cKDTree

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.periodic_tie import CyclicTie, cut_pairs, rotation_z
from softcrawl.geometry.design_base import ACTUATOR_ANGLES_DEG
from softcrawl.geometry.tagged_mesh import facet_keys
from softcrawl.geometry.tagging import TET_FACES

#: The FE body's wedge count: its three ePSAs.
COPIES = 3
#: (name, tag_b, tag_a or None for the ground, component) of the wedge's two holds (module docstring).
HOLDS = (("hold_z", "rear_bottom", None, 2), ("twist", "rear_bottom", None, 0))
#: The wedge's cut tags: `cut_end` = R `cut_start`.
CUTS = ("cut_start", "cut_end")


def wedge_mesh(tagged, copies: int = COPIES):
    """One wedge of 2 pi / `copies` of the whole body's tagged mesh (module docstring)."""
    if copies != COPIES:
        raise SolverInputError(
            "wedge", f"the FE body has {COPIES} ePSAs: a wedge of 360/{COPIES} deg, not {copies}"
        )
    points, tets = tagged.points, tagged.tets
    centroid = points[tets].mean(axis=1)
    scale = float(np.ptp(points, axis=0).max())
    tree = cKDTree(centroid)
    start = math.radians(ACTUATOR_ANGLES_DEG[0]) - math.pi / copies
    angle = lambda c: np.mod(np.arctan2(c[:, 1], c[:, 0]) - start, 2 * math.pi)  # noqa: E731
    images = np.empty((copies, len(tets)), dtype=np.int64)  # images[k, i]: the tet R^k T_i
    for k in range(copies):
        dist, images[k] = tree.query(centroid @ rotation_z(2 * math.pi * k / copies).T)
        if np.any(dist > 1e-8 * scale):
            raise SolverInputError(
                "wedge",
                f"{int(np.sum(dist > 1e-8 * scale))} tets have no image turned by {360 * k // copies} deg: "
                f"the body's mesh is not {copies}-fold symmetric",
            )
    # each orbit's member of least angle from the wedge's start; sector[i]: T_i = R^sector T_member
    theta = angle(centroid)[images]  # (copies, n)
    first = np.argmin(theta, axis=0)
    member = images[first, np.arange(len(tets))]
    kept = np.unique(member)
    if kept.size * copies != len(tets):
        raise SolverInputError("wedge", f"the mesh's {len(tets)} tets do not fall into orbits of {copies}")
    sector = np.empty(len(tets), dtype=np.int64)
    for k in range(copies):
        sector[images[k, kept]] = k
    faces = tets[kept][:, TET_FACES].reshape(-1, 3)  # outward, the tets positively oriented
    keys = facet_keys(faces)
    # the tet across each face (-1 on the boundary): an interior face's two copies sort together
    every = facet_keys(tets[:, TET_FACES].reshape(-1, 3))
    order = np.argsort(every, kind="stable")
    same = every[order[1:]] == every[order[:-1]]
    across = np.full(every.size, -1)
    across[order[:-1][same]], across[order[1:][same]] = order[1:][same] // 4, order[:-1][same] // 4
    across = across[(4 * kept[:, None] + np.arange(4)).ravel()]
    facets = {}
    for cut, k in zip(CUTS, (copies - 1, 1)):  # shared with R^2 T (the wedge before), with R T
        facets[cut] = faces[(across >= 0) & (sector[np.maximum(across, 0)] == k)]
    for tag, tris in tagged.facets.items():
        inside = tris[np.isin(facet_keys(tris), keys)]
        if len(inside):
            facets[tag] = inside
    used, inverse = np.unique(tets[kept], return_inverse=True)
    renumber = {tag: np.searchsorted(used, tris) for tag, tris in facets.items()}
    region = tagged.region[kept]
    names = {rid: name for rid, name in tagged.region_names.items() if np.any(region == rid)}
    return replace(
        tagged,
        points=points[used],
        tets=inverse.reshape(-1, 4),
        region=region,
        region_names=names,
        facets=renumber,
        meta=tagged.meta | {"wedge": copies, "whole_nodes": used},
    )


def wedge_p2(wedge, whole):
    """The wedge's P2 skfem mesh with each midside node where the whole mesh's P2 mesh has it. A
    tet of the wedge may have an edge on a curved surface whose facet is the next wedge's (the tet
    touches the surface along that edge only): the whole mesh snaps that midside node onto the
    surface (`TaggedMesh.to_skfem`), the wedge's facets alone would not, and the cuts would not
    pair (module docstring)."""
    from skfem import MeshTet2

    w2, m2 = wedge.to_skfem(order=2), whole.to_skfem(order=2)
    used = np.asarray(wedge.meta["whole_nodes"])
    n = np.int64(len(whole.points))
    key = lambda e: np.minimum(e[0], e[1]).astype(np.int64) * n + np.maximum(e[0], e[1])  # noqa: E731
    whole_keys = key(m2.edges)
    order = np.argsort(whole_keys)
    found = order[np.searchsorted(whole_keys, key(used[w2.edges]), sorter=order)]
    doflocs = np.array(w2.doflocs)
    doflocs[:, w2.nvertices :] = np.asarray(m2.doflocs)[:, m2.nvertices + found]
    return MeshTet2(doflocs, w2.t, _boundaries=w2._boundaries, _subdomains=w2._subdomains)


def ties(copies: int) -> list:
    """The wedge's cyclic tie of its displacements and mixed pressure; none for the whole body."""
    return [] if copies == 1 else [CyclicTie(*CUTS, 2 * math.pi / copies)]


def face_nodes(space, tag: str, copies: int) -> np.ndarray:
    """One node of each orbit of the whole body's boundary `tag`, as nodes of the wedge: its
    nodes off `cut_end`, and for those on `cut_end` their partners on `cut_start`. (A node on
    `cut_start` whose facets of `tag` are all the previous wedge's is not among the wedge's nodes
    of `tag`, but its image on `cut_end` is.) All of `tag`'s nodes for the whole body."""
    nodes = space.boundary_nodes(tag)
    if copies == 1:
        return nodes
    a, b = cut_pairs(space, *CUTS, 2 * math.pi / copies)
    on_end = np.isin(nodes, b)
    partner = dict(zip(b.tolist(), a.tolist()))
    moved = np.array([partner[n] for n in nodes[on_end].tolist()], dtype=np.int64)
    return np.unique(np.concatenate([nodes[~on_end], moved]))


def whole_force(force, copies: int) -> np.ndarray:
    """The whole body's force from one wedge's, sum_k R^k f (module docstring)."""
    f = np.asarray(force, dtype=float)
    if copies == 1:
        return f
    return np.sum([rotation_z(2 * math.pi * k / copies) @ f for k in range(copies)], axis=0)


def whole_points(points: np.ndarray, copies: int) -> np.ndarray:
    """(n, 3) points of one wedge turned into all `copies` wedges, (copies n, 3)."""
    if copies == 1:
        return points
    return np.vstack([points @ rotation_z(2 * math.pi * k / copies).T for k in range(copies)])
