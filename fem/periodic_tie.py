r"""Cyclic symmetry, exact: the nodes of one cut face of a wedge follow the other cut's, turned.

A body of revolution that is loaded and supported the same way in every one of `copies` wedges
(feet in a straight pipe under equal actuator forces) deforms the same way in each, turned by
2 pi / copies about the z axis. A wedge model carries it when each node b of its cut face
``tag_b`` (theta = 2 pi / copies) moves as its partner a on ``tag_a`` (theta = 0), turned:

    u_b = R u_a,        R the rotation by the wedge angle about z,

so each displacement dof of b is a combination of a's: u_bi = sum_j R_ij u_aj (`links`; the
coefficients that round to 0, as cos 90 deg, are dropped, so a quarter wedge ties each dof of b
to one of a, signed). `fem.dirichlet.Constraints` condenses the tied dofs out: the equations are
T^T R and T^T K T on the free dofs, so the tie holds to round-off and adds no unknown and no
penalty to the conditioning (record 083; a penalty tie, record 082, left the force across the
cut over k as its error, and a stalled Newton floor on a crushed foot).

This is rotational periodicity, not mirror symmetry: it holds on a mesh that is only the same in
every sector (the revolved foot's tets are split the same way in every sector, not mirror
symmetrically, so symmetry planes on it would model another mesh).

The mixed formulation's P1 pressure is continuous across the cut of the whole body, so the
wedge's pressure at a cut vertex b equals its partner's at a (a scalar: no turn), `pressure`.

Pairs are found by position (the cut faces of `geometry.foot_revolved` with `copies`: every node
of one cut turned by the angle lies on a node of the other, to round-off).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from softcrawl.fem.errors import SolverInputError

#: Coefficients of the turn below this are dropped (cos 90 deg = 6e-17).
ZERO = 1e-12


def rotation_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class CyclicTie:
    """The cut `tag_b` (theta = `angle`) follows the cut `tag_a` (theta = 0) turned by `angle`;
    with `pressure`, the mixed formulation's cut vertices' pressures too."""

    tag_a: str
    tag_b: str
    angle: float  # rad, the wedge's angle about z
    pressure: bool = True

    def __post_init__(self):
        if not (np.isfinite(self.angle) and 0 < abs(self.angle) < 2 * math.pi):
            raise SolverInputError(
                "periodic_tie.angle", f"must be a wedge angle in (0, 2 pi), got {self.angle!r}"
            )

    def links(self, space):
        """(tied dofs (n,), master dofs (n, 3), coefficients (n, 3)): `fem.dirichlet`."""
        a, b = cut_pairs(space, self.tag_a, self.tag_b, self.angle)
        R = rotation_z(self.angle)
        R[np.abs(R) < ZERO] = 0.0
        slaves = (3 * b[:, None] + np.arange(3)).ravel()  # (pairs * 3,) pair by pair
        masters = np.repeat(3 * a[:, None] + np.arange(3), 3, axis=0)  # row (b, i): a's 3 dofs
        coefs = np.tile(R, (a.size, 1))
        if self.pressure and space.mixed:
            pa, pb = _pressure_pairs(space, a, b)
            slaves = np.concatenate([slaves, pb])
            masters = np.vstack([masters, np.column_stack([pa, pa, pa])])
            coefs = np.vstack([coefs, np.tile([1.0, 0.0, 0.0], (pa.size, 1))])
        return slaves, masters, coefs


def _pressure_pairs(space, a, b):
    """The P1 pressure dofs of the cut pairs (a, b) that are vertices, field by field: a vertex
    where materials with their own pressure fields meet has one pressure dof per field, and each
    is tied to its partner's dof of the same field. A field that a wedge has at only one of the
    two (a material interface meeting the cut: its elements on one side only) is one dof of the
    whole body already, and stays free."""
    vertex = np.isin(a, space.pressure_vertex)  # the P1 pressure lives on the vertices
    a, b = a[vertex], b[vertex]
    groups = np.asarray(space.pressure_group, dtype=np.int64)
    n_groups = int(groups.max()) + 1 if groups.size else 1
    key = np.asarray(space.pressure_vertex, dtype=np.int64) * n_groups + groups
    order = np.argsort(key)
    sorted_key = key[order]

    def dof(v, g):  # the pressure dof of (vertex v, group g), -1 where v has no such field
        k = v.astype(np.int64) * n_groups + g
        at = np.minimum(np.searchsorted(sorted_key, k), key.size - 1)
        return np.where(sorted_key[at] == k, space.n_u + order[at], -1)

    pa, pb = [], []
    for g in range(n_groups):
        da, db = dof(a, g), dof(b, g)
        both = (da >= 0) & (db >= 0)
        pa.append(da[both])
        pb.append(db[both])
    return np.concatenate(pa), np.concatenate(pb)


def cut_pairs(space, tag_a: str, tag_b: str, angle: float) -> tuple[np.ndarray, np.ndarray]:
    """(nodes a on `tag_a`, their partners b on `tag_b`): b = a turned by `angle` about z."""
    a, b = space.boundary_nodes(tag_a), space.boundary_nodes(tag_b)
    if a.size != b.size or a.size == 0:
        raise SolverInputError(
            "periodic_tie.tags", f"the cuts have {a.size} and {b.size} nodes: they must pair up"
        )
    turned = (rotation_z(angle) @ space.nodes[:, a]).T
    dist, idx = cKDTree(space.nodes[:, b].T).query(turned)
    scale = max(float(np.ptp(space.nodes, axis=1).max()), 1.0)
    if np.any(dist > 1e-8 * scale) or np.unique(idx).size != a.size:
        raise SolverInputError(
            "periodic_tie.tags",
            f"{int(np.sum(dist > 1e-8 * scale))} nodes of {tag_a!r} turned by the angle lie on no "
            f"node of {tag_b!r}",
        )
    return a, b[idx]
