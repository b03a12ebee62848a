r"""Facet quadrature on curved quadratic tetrahedra: the element map inverted from the straight tet.

A scikit-fem `FacetBasis` evaluates the element's basis at the facet's quadrature points: it maps
the reference facet's points to space, x = G(X), and finds their reference coordinates in the
element by inverting the isoparametric map x = F(Y) = sum_a x_a N_a(Y) with Newton,

    Y <- Y + DF(Y)^-1 (x - F(Y)),

started at Y = (1/2, 1/2, 1/2) and clipped to [0, 1]^3. That start lies outside the reference tet
(its coordinates sum to 3/2). On a curved element whose bow is large against its thickness (a
skirt of a revolved foot near the axis, 24-32 sectors: docs/decisions/066-body-geometry.md), the
map folds out there and Newton does not converge, so the facet basis cannot be built.

`CurvedP2Mapping` starts Newton instead at the inverse of the straight tet through the element's
four vertices x_0..x_3,

    Y_0 = A^-1 (x - x_0),   A = [x_1 - x_0, x_2 - x_0, x_3 - x_0],

which is exact when the element is straight and, on a curved one, off by the bow of its edges,
and iterates without clipping to the same tolerance (1e-12 on the step). The converged point is
checked: it must lie in the closed reference tet (to 1e-8) and map back onto x (to 1e-9 of the
element's size), or the inversion is reported as failed. Where scikit-fem's Newton converges, the two agree
to round-off (tests/fem/test_p2_mapping.py).
"""

from __future__ import annotations

import numpy as np
import skfem
from skfem.mapping import MappingIsoparametric

#: Newton's step tolerance and iteration cap, as scikit-fem's `invF`.
NEWTON_TOL = 1e-12
NEWTON_MAX_ITERS = 50
#: How far outside the reference tet (in reference coordinates) a converged point may lie.
REFERENCE_TOL = 1e-8


class InversionError(Exception):
    """The element map could not be inverted at some point (Newton did not converge, or converged
    outside the element)."""


class CurvedP2Mapping(MappingIsoparametric):
    """The isoparametric P2 tet map of scikit-fem with `invF` started from the straight tet."""

    def __init__(self, mesh: skfem.MeshTet2) -> None:
        super().__init__(mesh, skfem.ElementTetP2(), skfem.ElementTriP2())

    def invF(self, x, tind=None, newton_max_iters=NEWTON_MAX_ITERS, newton_tol=NEWTON_TOL):
        """Reference coordinates (3, n_elements, n_points) of the points x (3, n_elements, n_points)."""
        t = self.mesh.t if tind is None else self.mesh.t[:, tind]
        p = self.mesh.p
        x0 = p[:, t[0]]  # (3, n)
        edges = np.stack([p[:, t[i]] - x0 for i in (1, 2, 3)], axis=2).transpose(1, 0, 2)  # (n, xyz, ref)
        X = np.einsum("nij,jnq->inq", np.linalg.inv(edges), x - x0[:, :, None])
        for _ in range(newton_max_iters):
            dX = np.einsum("ijnq,jnq->inq", self.invDF(X, tind), x - self.F(X, tind))
            X = X + dX
            if (np.linalg.norm(dX, 1, (0, 2)) < newton_tol).all():
                break
        else:
            raise InversionError(f"Newton did not converge to {newton_tol:g} in {newton_max_iters} steps")
        outside = np.maximum(-X.min(axis=0), X.sum(axis=0) - 1.0).max()
        if outside > REFERENCE_TOL:
            raise InversionError(f"a point converged {outside:.3g} outside its reference tetrahedron")
        size = np.linalg.norm(edges, axis=1).max()
        miss = np.abs(self.F(X, tind) - x).max()
        if miss > 1e-9 * max(size, 1.0):
            raise InversionError(f"the inverted points map back {miss:.3g} mm from their positions")
        return X


def facet_basis(mesh: skfem.Mesh, facets: np.ndarray, intorder: int = 4) -> skfem.FacetBasis:
    """The P2 basis on `facets` of `mesh`; on a quadratic mesh (`MeshTet2`) its quadrature points
    placed by `CurvedP2Mapping`, on a straight one by its affine map. Raises `InversionError` where
    they cannot be placed."""
    mapping = CurvedP2Mapping(mesh) if isinstance(mesh, skfem.MeshTet2) else None
    return skfem.FacetBasis(mesh, skfem.ElementTetP2(), mapping=mapping, facets=facets, intorder=intorder)
