r"""A linear axial link between the mean displacements of two boundary sets, or of one set and the
ground: a spring with a preload whose stiffness, preload and rest extension can change along a
load path (`set_load`), e.g. a pressure-driven actuator reduced to its axial force law.

For the nodes A and B of two boundary tags and one displacement component c, the link's
extension is the difference of the mean displacements (the mean over A is 0 for the ground)

    Delta = (1/n_B) sum_{i in B} u_ic - (1/n_A) sum_{j in A} u_jc,

and the force it exerts, positive when it pushes B along +c and A along -c, is

    T = F0 - k (Delta - Delta0)        (F0 preload in N, k >= 0 in N/mm, Delta0 rest extension).

It derives from the energy Pi = k/2 (Delta - Delta0)^2 - F0 Delta, so with g = dDelta/du
(1/n_B on the dofs of B, -1/n_A on those of A)

    r = dPi/du = -T g,          K = d2Pi/du2 = k g g^T      (symmetric, one dense item).

The force is spread equally over the nodes of each set: use it with a rigid-plate constraint
(`fem.equal_displacement.EqualDisplacement`) on the same sets when the sets must move as one.
An internal link (two sets) adds no net force to the body; a ground link puts the force T
(along +c) on it: a support whose force `tension` reports.

A model of one wedge of a cyclic-symmetric body (`fem.periodic_tie`) carries the `share`
1 / copies of the link: its residual and tangent are share r and share K, while `set_load`,
`extension` and `tension` speak of the whole link. A wedge's tag has its cut nodes on both cuts;
`nodes` (a function of the discretisation and the tag) may pick one node of each orbit instead, so
that the mean is the whole body's (`studies.crawl_fe.wedge.face_nodes`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from softcrawl.fem.errors import SolverInputError


def _finite(value, parameter: str, minimum: float | None = None) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = float("nan")
    if not np.isfinite(v) or (minimum is not None and v < minimum):
        bound = "" if minimum is None else f" >= {minimum:g}"
        raise SolverInputError(parameter, f"must be a finite number{bound}, got {value!r}")
    return v


@dataclass(frozen=True)
class AxialLink:
    """Spec of the link: `tag_b` pushed along +component, `tag_a` (None: the ground) along -."""

    tag_b: str
    tag_a: str | None = None
    component: int = 2
    stiffness: float = 0.0  # k, N/mm
    preload: float = 0.0  # F0, N
    rest: float = 0.0  # Delta0, mm
    name: str = "link"
    share: float = 1.0  # the fraction of the link the model carries (module docstring)
    nodes: Callable | None = None  # (space, tag) -> the nodes a mean runs over; None: all of the tag's

    def __post_init__(self):
        if self.component not in (0, 1, 2):
            raise SolverInputError("axial_link.component", "must be 0, 1 or 2")
        if not (np.isfinite(self.share) and 0 < self.share <= 1):
            raise SolverInputError("axial_link.share", f"must be in (0, 1], got {self.share!r}")
        _finite(self.stiffness, "axial_link.stiffness", 0.0)
        _finite(self.preload, "axial_link.preload")
        _finite(self.rest, "axial_link.rest")
        if self.tag_a is not None and self.tag_a == self.tag_b:
            raise SolverInputError("axial_link.tag_a", "the two ends must be different boundaries")

    def build(self, space) -> AxialLinkTerm:
        return AxialLinkTerm(space, self)


class AxialLinkTerm:
    """The link on a discretisation: a term of `fem.model.SolidModel` (`extra_terms`)."""

    symmetric = True

    def __init__(self, space, spec: AxialLink) -> None:
        self.spec, self.name = spec, spec.name
        pick = spec.nodes or (lambda space, tag: space.boundary_nodes(tag))
        nodes_b = pick(space, spec.tag_b)
        parts = [3 * nodes_b + spec.component]
        weights = [np.full(nodes_b.size, 1.0 / nodes_b.size)]
        if spec.tag_a is not None:
            nodes_a = pick(space, spec.tag_a)
            if np.intersect1d(nodes_a, nodes_b).size:
                raise SolverInputError("axial_link.tag_a", "the two ends share nodes")
            parts.append(3 * nodes_a + spec.component)
            weights.append(np.full(nodes_a.size, -1.0 / nodes_a.size))
        self.dofs = np.concatenate(parts)[:, None]  # (n, 1): one item
        self.g = np.concatenate(weights)  # dDelta/du on self.dofs
        self.stiffness, self.preload, self.rest = spec.stiffness, spec.preload, spec.rest

    def set_load(self, stiffness: float, preload: float, rest: float | None = None) -> None:
        """Change k, F0 (and Delta0) for the next solves (the path calls this between states)."""
        self.stiffness = _finite(stiffness, "axial_link.stiffness", 0.0)
        self.preload = _finite(preload, "axial_link.preload")
        if rest is not None:
            self.rest = _finite(rest, "axial_link.rest")

    def extension(self, x: np.ndarray) -> float:
        """Delta (mm) at state x."""
        return float(self.g @ x[self.dofs[:, 0]])

    def tension(self, x: np.ndarray) -> float:
        """T = F0 - k (Delta - Delta0) (N): the force on B along +c (on A along -c). For a ground
        link, the ground's support force on the body along +c is T."""
        return self.preload - self.stiffness * (self.extension(x) - self.rest)

    def arrays(self, x, pressures=None, with_tangent=True):
        share = self.spec.share
        r = (-share * self.tension(x) * self.g)[:, None]
        K = (share * self.stiffness * np.outer(self.g, self.g))[None] if with_tangent else None
        return r, K
