r"""One displacement component shared by every node of a boundary, by penalty: a rigid plate's
translation that is free but common (the face stays plane and keeps its orientation).

For the nodes i of boundary `tag` and the component c, with u_i = u_ic and the mean
ubar = (1/n) sum_i u_i, the penalty energy and its derivatives are

    E = k/2 sum_i (u_i - ubar)^2,    dE/du_i = k (u_i - ubar),    d2E/du_i du_j = k (delta_ij - 1/n)

(the terms of d ubar / du_i cancel because sum_i (u_i - ubar) = 0). The constraint error is the
node's share of the force through the plate divided by k. One item: a dense n x n block on the
face's dofs (a face of a few hundred nodes).

Used by the groove-segment model: its top face is glued to the rigid rest of the foot, which
moves in z but does not tilt, so that a follower pressure on that face has the total normal force
p A exactly and the strip cannot rotate under the friction moment.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcrawl.fem.errors import SolverInputError


@dataclass(frozen=True)
class EqualDisplacement:
    tag: str
    component: int
    stiffness: float  # k, N/mm per node

    def __post_init__(self):
        if self.component not in (0, 1, 2):
            raise SolverInputError("equal_displacement.component", "must be 0, 1 or 2")
        if not (np.isfinite(self.stiffness) and self.stiffness > 0):
            raise SolverInputError(
                "equal_displacement.stiffness", f"must be positive, got {self.stiffness!r}"
            )

    def build(self, space) -> _EqualTerm:
        return _EqualTerm(space, self)


class _EqualTerm:
    def __init__(self, space, spec: EqualDisplacement) -> None:
        nodes = space.boundary_nodes(spec.tag)
        self.n_u = space.n_u
        self.dofs = (3 * nodes + spec.component)[:, None]  # (n, 1): one item
        n = nodes.size
        self.K = spec.stiffness * (np.eye(n) - 1.0 / n)[None]

    def arrays(self, x, pressures=None, with_tangent=True):
        u = x[self.dofs[:, 0]]
        r = (self.K[0] @ u)[:, None]
        return r, (self.K if with_tangent else None)
