r"""Cyclic symmetry by penalty: the nodes of one cut face of a wedge follow the other cut's, turned.

A body of revolution that is loaded and supported the same way in every one of `copies` wedges
(feet in a straight pipe under equal actuator forces) deforms the same way in each, turned by
2 pi / copies about the z axis. A wedge model carries it when each node b of its cut face
``tag_b`` (theta = 2 pi / copies) moves as its partner a on ``tag_a`` (theta = 0), turned:

    u_b = R u_a,        R the rotation by the wedge angle about z.

This is rotational periodicity, not mirror symmetry: it holds on a mesh that is only the same in
every sector (the revolved foot's tets are split the same way in every sector, not mirror
symmetrically, so symmetry planes on it would model another mesh). The constraint is imposed by a
penalty k per node pair, with the gap g = u_b - R u_a = B [u_a; u_b], B = [-R, I]:

    E = k/2 sum_pairs |g|^2,     r = k B^T g,     K = k B^T B     (symmetric, a 6 x 6 item per pair).

Its error is the force carried across the cut at a node divided by k (`max_gap` reports it).

The mixed formulation's P1 pressure is continuous across the cut of the whole body, so the
wedge's pressure at a cut vertex b must equal its partner's at a (a scalar: no turn). The
energy Pi(u, p) is concave in p (the -p^2 / (2K) of `fem.solid`), so its penalty enters with
that sign, k_p in mm^3/MPa per vertex pair (`PeriodicPressureTie`):

    Pi += -k_p/2 sum_pairs (p_b - p_a)^2,    r = -k_p (p_b - p_a) [-1, 1],    K = -k_p [[1, -1], [-1, 1]].

Pairs are found by position (the cut faces of `geometry.foot_revolved` with `copies`: every node
of one cut turned by the angle lies on a node of the other, to round-off).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from softcrawl.fem.errors import SolverInputError


def rotation_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class PeriodicTie:
    tag_a: str  # the cut at theta = 0
    tag_b: str  # the cut at theta = angle
    angle: float  # rad, the wedge's angle about z
    stiffness: float  # k, N/mm per node pair
    name: str = "periodic"

    def __post_init__(self):
        _check(self)

    def build(self, space) -> PeriodicTieTerm:
        return PeriodicTieTerm(space, self)


def _check(spec) -> None:
    """The angle and the penalty of a tie (`PeriodicTie`, `PeriodicPressureTie`)."""
    if not (np.isfinite(spec.angle) and 0 < abs(spec.angle) < 2 * math.pi):
        raise SolverInputError(
            "periodic_tie.angle", f"must be a wedge angle in (0, 2 pi), got {spec.angle!r}"
        )
    if not (np.isfinite(spec.stiffness) and spec.stiffness > 0):
        raise SolverInputError("periodic_tie.stiffness", f"must be positive, got {spec.stiffness!r}")


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


@dataclass(frozen=True)
class PeriodicPressureTie:
    """The P1 pressure of the cut vertices of `tag_b` equal to their partners' on `tag_a`."""

    tag_a: str
    tag_b: str
    angle: float
    stiffness: float  # k_p, mm^3/MPa per vertex pair
    name: str = "periodic_pressure"

    def __post_init__(self):
        _check(self)

    def build(self, space) -> PeriodicPressureTerm:
        return PeriodicPressureTerm(space, self)


class PeriodicPressureTerm:
    symmetric = True

    def __init__(self, space, spec: PeriodicPressureTie) -> None:
        if not space.mixed:
            raise SolverInputError("periodic_tie", "a pressure tie needs the mixed (p2p1) formulation")
        self.spec, self.name = spec, spec.name
        a, b = cut_pairs(space, spec.tag_a, spec.tag_b, spec.angle)
        vertex = np.isin(a, space.pressure_vertex)  # the P1 pressure lives on the vertices
        a, b = a[vertex], b[vertex]
        order = np.argsort(space.pressure_vertex)
        sorted_v = space.pressure_vertex[order]
        if np.unique(sorted_v).size != sorted_v.size:
            raise SolverInputError("periodic_tie", "a vertex with a pressure per material: not supported")
        dof = lambda v: space.n_u + order[np.searchsorted(sorted_v, v)]  # noqa: E731
        self.dofs = np.vstack([dof(a), dof(b)])  # (2, pairs)
        self.K = -spec.stiffness * np.array([[1.0, -1.0], [-1.0, 1.0]])

    def max_gap(self, x: np.ndarray) -> float:
        """The largest |p_b - p_a| (MPa)."""
        return float(np.abs(x[self.dofs[1]] - x[self.dofs[0]]).max())

    def arrays(self, x, pressures=None, with_tangent=True):
        d = x[self.dofs[1]] - x[self.dofs[0]]
        r = -self.spec.stiffness * np.vstack([-d, d])
        K = np.tile(self.K, (d.size, 1, 1)) if with_tangent else None
        return r, K


class PeriodicTieTerm:
    symmetric = True

    def __init__(self, space, spec: PeriodicTie) -> None:
        self.spec, self.name = spec, spec.name
        self.a, self.b = cut_pairs(space, spec.tag_a, spec.tag_b, spec.angle)
        R = rotation_z(spec.angle)
        self.R = R
        self.dofs = np.concatenate(
            [3 * self.a[None] + np.arange(3)[:, None], 3 * self.b[None] + np.arange(3)[:, None]]
        )
        self.B = np.hstack([-R, np.eye(3)])  # g = B [u_a; u_b]
        self.K = spec.stiffness * (self.B.T @ self.B)

    def gaps(self, x: np.ndarray) -> np.ndarray:
        """g = u_b - R u_a per pair, (pairs, 3) in mm."""
        return (self.B @ x[self.dofs]).T

    def max_gap(self, x: np.ndarray) -> float:
        """The largest |u_b - R u_a| (mm): the constraint's error."""
        return float(np.linalg.norm(self.gaps(x), axis=1).max())

    def arrays(self, x, pressures=None, with_tangent=True):
        r = self.spec.stiffness * (self.B.T @ self.gaps(x).T)  # (6, pairs)
        K = np.tile(self.K, (self.a.size, 1, 1)) if with_tangent else None
        return r, K
