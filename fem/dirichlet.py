"""Dirichlet conditions and the condensation of the constrained dofs.

A `Dirichlet` condition fixes components of u on a tagged boundary to `factor * value` (mm); the
load factor f of the path scales every prescribed value. `Constraints` collects the constrained
dofs of a model (a dof fixed twice keeps its first value), the free dofs, and the map from a
global dof to its free number (-1 for a constrained dof) that the sparsity pattern uses to drop
constrained rows and columns (`fem.pattern`). Reactions are the residual on the constrained dofs.
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

    def __init__(self, space: Discretisation, conditions=()) -> None:
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
        self._number_free()

    def _number_free(self) -> None:
        self.free_dofs = np.setdiff1d(np.arange(self.n_dofs), self.fixed_dofs)
        self.free_index = np.full(self.n_dofs, -1, dtype=np.int64)
        self.free_index[self.free_dofs] = np.arange(self.free_dofs.size)

    def pin(self, dofs: np.ndarray) -> None:
        """Fix `dofs` at 0: dofs that no element touches (a mesh vertex of no tetrahedron), which
        nothing determines. Left free they are empty rows of the tangent, which PARDISO's pivot
        perturbation papers over at the price of iterative refinement in every solve."""
        dofs = np.setdiff1d(dofs, self.fixed_dofs)
        if dofs.size == 0:
            return
        fixed = np.concatenate([self.fixed_dofs, dofs])
        order = np.argsort(fixed)
        self.fixed_dofs = fixed[order]
        self.fixed_values = np.concatenate([self.fixed_values, np.zeros(dofs.size)])[order]
        self._number_free()

    def apply(self, x: np.ndarray, factor: float) -> np.ndarray:
        """A copy of x with the constrained dofs at `factor` times their values."""
        x = x.copy()
        x[self.fixed_dofs] = factor * self.fixed_values
        return x
