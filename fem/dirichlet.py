r"""Dirichlet conditions, linear ties, and the condensation of both.

A `Dirichlet` condition fixes components of u on a tagged boundary to `factor * value` (mm); the
load factor f of the path scales every prescribed value. A tie (`fem.periodic_tie`) makes a dof
s a fixed linear combination of others, x_s = sum_j c_sj x_mj (a wedge's cut follows the other
cut, turned). `Constraints` collects the constrained dofs of a model (a dof fixed twice keeps its
first value), the tied ones, the free dofs, and the map from a global dof to its free number (-1
for a constrained or tied dof) that the sparsity pattern uses (`fem.pattern`). Reactions are the
residual on the constrained dofs.

Condensation. With q the free dofs, every state is x = T q + x_D: T has a 1 in the row of each
free dof and the coefficients c_sj in the row of a tied dof s; x_D holds the prescribed values.
The equations on q are the reduced residual T^T R and tangent T^T K T (the pattern assembles the
latter): a tie is exact, unlike a penalty, and adds no unknown. A tie whose dof and masters are
all prescribed is left to the prescribed values, and kept only to fold its reaction row (the
norms below); one that mixes free and prescribed dofs, or ties a dof to a tied dof, is refused.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcrawl.fem.discretisation import Discretisation
from softcrawl.fem.errors import SolverInputError


@dataclass(frozen=True)
class Dirichlet:
    """Displacement components `components` on boundary `tag` equal `factor * values` (mm)."""

    tag: str
    components: tuple[int, ...] = (0, 1, 2)
    values: tuple[float, ...] = (0.0, 0.0, 0.0)

    @classmethod
    def fixed(cls, tag: str) -> Dirichlet:
        return cls(tag, (0, 1, 2), (0.0, 0.0, 0.0))

    @classmethod
    def symmetry(cls, tag: str, axis: int) -> Dirichlet:
        """Symmetry plane normal to coordinate `axis`: zero normal displacement."""
        return cls(tag, (axis,), (0.0,))

    @classmethod
    def prescribed(cls, tag: str, component: int, value: float) -> Dirichlet:
        return cls(tag, (component,), (float(value),))


class Constraints:
    """The constrained dofs of `conditions` on `space`, their values at factor 1, the free dofs."""

    def __init__(self, space: Discretisation, conditions=(), ties=()) -> None:
        self.conditions = tuple(conditions)
        fixed, values = [], []
        for bc in self.conditions:
            if len(bc.components) != len(bc.values):
                raise SolverInputError("dirichlet", f"{bc.tag}: components and values differ in length")
            if any(c not in (0, 1, 2) for c in bc.components):
                raise SolverInputError("dirichlet", f"{bc.tag}: components must be 0, 1 or 2")
            nodes = space.basis.get_dofs(space.boundary(bc.tag, "dirichlet")).flatten()
            for c, v in zip(bc.components, bc.values):
                fixed.append(3 * nodes + c)
                values.append(np.full(nodes.size, float(v)))
        if fixed:
            self.fixed_dofs, first = np.unique(np.concatenate(fixed), return_index=True)
            self.fixed_values = np.concatenate(values)[first]
        else:
            self.fixed_dofs = np.zeros(0, dtype=np.int64)
            self.fixed_values = np.zeros(0)
        self.n_dofs = space.n_dofs
        self._tie(space, ties)
        self._number_free()

    def _tie(self, space, ties) -> None:
        """The tied dofs (n_s,), their masters (n_s, k) and coefficients (n_s, k) (module
        docstring); a master's coefficient 0 pads a row."""
        rows = [spec.links(space) for spec in ties]
        k = max((m.shape[1] for _, m, _ in rows), default=1)
        pad = lambda a, v: np.pad(a, ((0, 0), (0, k - a.shape[1])), constant_values=v)  # noqa: E731
        slaves = np.concatenate([s for s, _, _ in rows] + [np.zeros(0, np.int64)]).astype(np.int64)
        masters = np.vstack([pad(m, 0) for _, m, _ in rows] + [np.zeros((0, k), np.int64)]).astype(np.int64)
        coefs = np.vstack([pad(c, 0.0) for _, _, c in rows] + [np.zeros((0, k))])
        fixed = np.zeros(self.n_dofs, dtype=bool)
        fixed[self.fixed_dofs] = True
        held = np.where(coefs != 0, fixed[masters], fixed[slaves][:, None])  # pads follow the dof
        all_held = held.all(axis=1) & fixed[slaves]
        if np.any(~all_held & (held.any(axis=1) | fixed[slaves])):
            raise SolverInputError("tie", "a tied dof and its masters must be all free or all prescribed")
        # an all-prescribed tie condenses nothing, but its reaction row still folds (`fold`)
        self._held = slaves[all_held], masters[all_held], coefs[all_held]
        slaves, masters, coefs = slaves[~all_held], masters[~all_held], coefs[~all_held]
        if np.unique(slaves).size != slaves.size or np.isin(masters[coefs != 0], slaves).any():
            raise SolverInputError("tie", "a dof is tied twice, or to a tied dof")
        self.slave_dofs, self.slave_masters, self.slave_coefs = slaves, masters, coefs

    def _number_free(self) -> None:
        taken = np.union1d(self.fixed_dofs, self.slave_dofs)
        self.free_dofs = np.setdiff1d(np.arange(self.n_dofs), taken)
        self.free_index = np.full(self.n_dofs, -1, dtype=np.int64)
        self.free_index[self.free_dofs] = np.arange(self.free_dofs.size)
        # the masters' free numbers, -1 at the pads (`fem.pattern.Pattern` links)
        self.slave_free = np.where(self.slave_coefs != 0, self.free_index[self.slave_masters], -1)

    @property
    def links(self):
        """(tied dofs, their masters' free numbers (-1: none), coefficients) for `fem.pattern`."""
        return self.slave_dofs, self.slave_free, self.slave_coefs

    def fold(self, v: np.ndarray) -> np.ndarray:
        """v on all dofs with each tied dof's row added to its masters' (times the coefficients)
        and set to 0: a wedge's forces as the whole body's on its own nodes, each counted once
        (the norms of `fem.newton` compare them). The all-prescribed ties fold too: a held cut
        node's reaction is then the whole body's, not split between the two cuts. v itself when
        nothing is tied."""
        held = self._held[0].size
        if not self.slave_dofs.size and not held:
            return v
        out = v.copy()
        for slaves, masters, coefs in ((self.slave_dofs, self.slave_masters, self.slave_coefs), self._held):
            keep = coefs != 0
            w = coefs * v[slaves][:, None]
            np.add.at(out, masters[keep], w[keep])
            out[slaves] = 0.0
        return out

    def reduce(self, R: np.ndarray) -> np.ndarray:
        """T^T R: the residual on the free dofs (a tied dof's row goes to its masters')."""
        return self.fold(R)[self.free_dofs]

    def _follow(self, x: np.ndarray) -> np.ndarray:
        """x with its tied dofs set from their masters (in place)."""
        if self.slave_dofs.size:
            x[self.slave_dofs] = (self.slave_coefs * x[self.slave_masters]).sum(axis=1)
        return x

    def step(self, x: np.ndarray, dq: np.ndarray, alpha: float = 1.0) -> np.ndarray:
        """x + alpha T dq: the free dofs moved by alpha dq, the tied ones following (a copy)."""
        x = x.copy()
        x[self.free_dofs] += alpha * dq
        return self._follow(x)

    def pin(self, dofs: np.ndarray) -> None:
        """Fix `dofs` at 0: dofs that no element touches (a mesh vertex of no tetrahedron), which
        nothing determines. Left free they are empty rows of the tangent, which PARDISO's pivot
        perturbation papers over at the price of iterative refinement in every solve."""
        dofs = np.setdiff1d(dofs, np.union1d(self.fixed_dofs, self.slave_dofs))
        if dofs.size == 0:
            return
        fixed = np.concatenate([self.fixed_dofs, dofs])
        order = np.argsort(fixed)
        self.fixed_dofs = fixed[order]
        self.fixed_values = np.concatenate([self.fixed_values, np.zeros(dofs.size)])[order]
        self._number_free()

    def apply(self, x: np.ndarray, factor: float) -> np.ndarray:
        """A copy of x with the constrained dofs at `factor` times their values and the tied dofs
        following their masters."""
        x = x.copy()
        x[self.fixed_dofs] = factor * self.fixed_values
        return self._follow(x)
