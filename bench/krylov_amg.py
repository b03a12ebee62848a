"""The iterative alternative to PARDISO for the P2-P1 Newton systems: block-preconditioned GMRES.

The tangent of the mixed formulation is the saddle-point matrix

    K = [[A, B^T], [B, -C]],   A = K_uu (free displacement dofs),  B = K_pu,  C = M_p / K_bulk

with M_p the P1 pressure mass matrix. The block-diagonal preconditioner

    P^{-1} = diag(AMG(A), -S^{-1}),   S = int (1/mu + 1/K_bulk) N_c N_d dV  (lumped)

approximates the displacement block by one smoothed-aggregation AMG V-cycle (pyamg, with the
rigid-body modes as near-null space) and the Schur complement B A^{-1} B^T + C by the pressure
mass matrix scaled with 1/mu (the incompressible-elasticity estimate, element by element so
that the stiff seal head gets its own modulus). GMRES (right preconditioning, `fem.krylov`)
solves to a relative residual of 1e-8.

pyamg is not a dependency of the project: it is used here only, to measure the alternative
(`pip install pyamg`). See bench/linear_solvers.py for the comparison with PARDISO.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def pressure_schur(model) -> np.ndarray:
    """Lumped int (1/mu + 1/K) N_c dV on the pressure dofs (all of them)."""
    space = model.space
    w = (1.0 / model.mu + 1.0 / model.bulk) * space.dx  # (E, Q)
    lumped = np.einsum("ceq,eq->ce", space.Np, w)
    return np.bincount(space.p_dofs.reshape(-1) - model.n_u, lumped.reshape(-1), minlength=model.n_p)


def rigid_modes(coords: np.ndarray) -> np.ndarray:
    """(3 n, 6) translations and rotations of the nodes `coords` (n, 3), dof 3 i + c."""
    n = coords.shape[0]
    B = np.zeros((3 * n, 6))
    for c in range(3):
        B[c::3, c] = 1.0
    x, y, z = (coords - coords.mean(axis=0)).T
    B[0::3, 3], B[1::3, 3] = -y, x
    B[1::3, 4], B[2::3, 4] = -z, y
    B[0::3, 5], B[2::3, 5] = z, -x
    return B


class BlockPreconditioner:
    """diag(AMG(A), S^{-1}) on the free dofs of `model` for its tangent K (module docstring)."""

    def __init__(self, model, K: sp.csr_matrix) -> None:
        import pyamg

        free = model.free_dofs
        is_u = free < model.n_u
        self.u, self.p = np.flatnonzero(is_u), np.flatnonzero(~is_u)
        A = K[self.u][:, self.u].tocsr()
        # near-null space on the free u dofs: rigid modes of all nodes, restricted
        modes = rigid_modes(model.nodes.T)[free[is_u]]
        self.amg = pyamg.smoothed_aggregation_solver(A, B=modes, max_coarse=2000)
        s = pressure_schur(model)[free[~is_u] - model.n_u]
        # vertices of no element (the swept ePSA mesh has a few) have empty rows: left at 0
        self.s_inv = np.divide(1.0, s, out=np.zeros_like(s), where=s > 0)
        self.complexity = self.amg.operator_complexity()

    def __call__(self, r: np.ndarray) -> np.ndarray:
        out = np.empty_like(r)
        out[self.u] = self.amg.solve(r[self.u], maxiter=1, cycle="V", tol=1e-30)
        out[self.p] = -self.s_inv * r[self.p]  # the Schur complement is negative definite
        return out
