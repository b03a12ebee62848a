r"""The unknowns of a solid on quadratic tetrahedra and the deformation gradient at its points.

Unknowns. Displacements u on the P2 nodes (dof 3 * node + i, node numbering of scikit-fem's
scalar `ElementTetP2` basis) and, for the mixed formulation "p2p1", a P1 pressure p on the
vertices after them (Taylor-Hood P2-P1, inf-sup stable, so it does not lock as K/mu -> inf).
The displacement-only formulation "p2" has no pressure dofs.

Pressure groups. The pressure p = K (J - 1) jumps where the material does (silicone next to ABS:
K differs by a factor ~70 and J - 1 by more), so one continuous field across a material
interface forces a wrong, smeared pressure into the elements next to it. `pressure_groups`
(one integer per element) gives each group its own continuous P1 field: a vertex shared by
elements of g groups carries g pressure dofs, one per group. Displacements stay continuous
everywhere (the tie). With one group (the default) this is the usual Taylor-Hood space.

Kinematics. F_iJ = d_iJ + sum_a u_ai dN_a/dX_J at the quadrature points. The shape-function
gradients are kept in element-first layouts, so that F of a whole mesh is one small
(3 x 10) @ (10 x 3Q) product per element: g_aqJ[e, a, 3 q + J] and g_qJa[e, q, J, a].

Local element dofs are component-major: local 10 i + a is component i of node a, then the four
pressure dofs. Arrays of F are (3, 3, E, Q), contiguous per component.
"""

from __future__ import annotations

import numpy as np
import skfem

from softcrawl.fem import p2_mapping
from softcrawl.fem.errors import SolverInputError

FORMULATIONS = ("p2p1", "p2")


class Discretisation:
    """P2 displacements (and P1 pressures for "p2p1") on `mesh` with `intorder` quadrature."""

    def __init__(self, mesh, formulation: str = "p2p1", intorder: int = 2, pressure_groups=None) -> None:
        if formulation not in FORMULATIONS:
            raise SolverInputError("formulation", f"{formulation!r} is not one of {FORMULATIONS}")
        self.mesh = mesh
        self.formulation = formulation
        self.mixed = formulation == "p2p1"
        self.basis = skfem.Basis(mesh, skfem.ElementTetP2(), intorder=intorder)
        self.n_nodes = self.basis.N
        self.n_u = 3 * self.n_nodes
        self.nodes = self.basis.doflocs  # (3, n_nodes) reference positions
        self.dN = np.stack([phi[0].grad for phi in self.basis.basis])  # (10, 3, E, Q)
        self.dx = self.basis.dx  # (E, Q)
        self.node_dofs = self.basis.element_dofs  # (10, E)
        n_elem, n_qp = self.dx.shape
        self.g_aqJ = np.ascontiguousarray(self.dN.transpose(2, 0, 3, 1)).reshape(n_elem, 10, 3 * n_qp)
        self.g_qJa = np.ascontiguousarray(self.dN.transpose(2, 3, 1, 0))
        self.elem_nodes = np.ascontiguousarray(self.node_dofs.T)  # (E, 10)
        self.u_dofs = (3 * self.node_dofs[None, :, :] + np.arange(3)[:, None, None]).reshape(30, -1)
        if self.mixed:
            self.pbasis = skfem.Basis(mesh, skfem.ElementTetP1(), quadrature=self.basis.quadrature)
            self.Np = np.stack([np.asarray(phi[0]) for phi in self.pbasis.basis])  # (4, E, Q)
            self.p_dofs, self.pressure_vertex, self.pressure_group = _pressure_dofs(
                self.pbasis.element_dofs, pressure_groups
            )
            self.p_dofs = self.p_dofs + self.n_u  # (4, E)
            self.n_p = len(self.pressure_vertex)
        else:
            self.n_p = 0
        self.n_dofs = self.n_u + self.n_p
        self.element_dofs = np.vstack([self.u_dofs, self.p_dofs]) if self.mixed else self.u_dofs

    @property
    def volume(self) -> float:
        """Reference volume of the body (mm^3)."""
        return float(self.dx.sum())

    @property
    def size(self) -> float:
        """Largest extent of the reference body (mm)."""
        return float(np.ptp(self.nodes, axis=1).max())

    def boundary(self, tag: str, parameter: str = "tag") -> np.ndarray:
        """The facets of boundary `tag`; an unknown or empty tag is an error naming `parameter`."""
        boundaries = self.mesh.boundaries or {}
        if tag not in boundaries:
            raise SolverInputError(parameter, f"unknown boundary tag {tag!r}; known: {sorted(boundaries)}")
        if len(boundaries[tag]) == 0:
            raise SolverInputError(parameter, f"boundary tag {tag!r} has no facets")
        return boundaries[tag]

    def boundary_nodes(self, tag: str) -> np.ndarray:
        """Scalar P2 nodes (vertices and edge midpoints) of boundary `tag`."""
        return self.basis.get_dofs(self.boundary(tag)).flatten()

    def facet_basis(self, facets: np.ndarray, intorder: int = 4, parameter: str = "tag") -> skfem.FacetBasis:
        """The P2 basis on the given boundary facets (the facet's element, traced), its quadrature
        points placed in their curved elements by `fem.p2_mapping`. Where they cannot be (an element
        folded by its curvature), this is an error naming `parameter` (refine the mesh).
        """
        try:
            return p2_mapping.facet_basis(self.mesh, facets, intorder=intorder)
        except p2_mapping.InversionError as exc:
            raise SolverInputError(
                parameter,
                f"the facet quadrature points could not be placed in their curved P2 elements ({exc}); "
                "the elements are too coarse for the surface's curvature: refine the mesh",
            ) from exc

    def displacement(self, x: np.ndarray) -> np.ndarray:
        """Nodal displacements, shape (3, n_nodes)."""
        return x[: self.n_u].reshape(-1, 3).T

    def deformation_gradient(self, x: np.ndarray, g_aqJ=None, elem_nodes=None) -> np.ndarray:
        """F_iJ = d_iJ + sum_a u_ai dN_a/dX_J, contiguous (3, 3, n, Q), from one (3 x 10) @ (10 x 3Q)
        product per element; g_aqJ is (n, 10, 3Q) and elem_nodes (n, 10) (default: the volume
        points of every element; a facet basis passes its own)."""
        g_aqJ = self.g_aqJ if g_aqJ is None else g_aqJ
        elem_nodes = self.elem_nodes if elem_nodes is None else elem_nodes
        n, _, m = g_aqJ.shape
        u = x[: self.n_u].reshape(-1, 3)[elem_nodes]  # (n, 10, 3)
        grad_u = np.matmul(u.transpose(0, 2, 1), g_aqJ).reshape(n, 3, m // 3, 3)  # [e, i, q, J]
        F = np.ascontiguousarray(grad_u.transpose(1, 3, 0, 2))
        F[0, 0] += 1.0
        F[1, 1] += 1.0
        F[2, 2] += 1.0
        return F


def _pressure_dofs(vertex_dofs: np.ndarray, groups) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pressure dof numbers (4, E), and the vertex and group of each pressure dof: one dof per
    (vertex, group) pair that occurs (see the module docstring); groups None means one group."""
    if groups is None:
        n = vertex_dofs.max() + 1
        return vertex_dofs.copy(), np.arange(n), np.zeros(n, dtype=np.int64)
    groups = np.asarray(groups)
    if groups.shape != (vertex_dofs.shape[1],) or not np.issubdtype(groups.dtype, np.integer):
        raise SolverInputError("pressure_groups", f"give one integer per element ({vertex_dofs.shape[1]})")
    n_groups = int(groups.max()) + 1
    key = vertex_dofs.astype(np.int64) * n_groups + groups[None, :]
    unique, inverse = np.unique(key, return_inverse=True)
    return inverse.reshape(vertex_dofs.shape), unique // n_groups, unique % n_groups


def element_first(dN: np.ndarray) -> np.ndarray:
    """Gradients dN (10, 3, n, Q) in the layout of `Discretisation.deformation_gradient`."""
    return np.ascontiguousarray(dN.transpose(2, 0, 3, 1)).reshape(dN.shape[2], 10, -1)
