r"""Rigid-motion projection of a predicted state on the stiff parts of a multi-material body.

Why. The predictors of `fem.path` extrapolate every node along a line (Euler) or a parabola
(Hermite). A part that turns as a rigid body by an angle a over a step is then stretched by its
chord error, a strain ~ a^2 / 2 (a 3 deg turn: 1.4e-3). In a stiff part (ABS, E = 2000 MPa, tied
to silicone with mu = 0.06 MPa) that spurious strain carries stresses far above the physical
ones, and Newton spends its first iterations taking it out again: on the whole robot the
residual of the predicted state sat in the ABS rings and seal heads and their interfaces
(~95 % of its square), and a 10 kPa load target took 4-10 iterations and cut-backs
(docs/decisions/050-rigid-abs.md, `bench/robot_trace.py`).

What. Stiff elements: shear modulus >= `ratio` x the smallest in the body. Their connected
components (elements sharing a node) are the stiff parts. For each part, with a_n = X_n + u_n the
node positions of the last converged state and b_n = X_n + u~_n those of the prediction, the rigid
motion (R, t) minimising sum_n |R (a_n - a_c) + t - b_n|^2 (Kabsch: R from the SVD of the
cross-covariance, det R = +1, t = b_c, the centroid of the prediction) replaces the prediction:

    u~_n <- R (a_n - a_c) + b_c - X_n        for every node n of the part.

The part keeps its last converged (elastic) shape and moves as the predictor says it moves on
average; a part with a prescribed displacement is left alone (the Dirichlet values are set after
the prediction); nodes on its interface move with it (the soft side takes the mismatch, at a stress
scaled by its own small modulus). Mixed pressures and the soft parts keep their prediction. A
prediction that is already a rigid motion of the last state is returned unchanged (round-off),
so the projection never moves the converged solution: it changes only Newton's starting point.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components


def kabsch(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The rotation R (det +1) minimising sum |R (a_n - a_c) - (b_n - b_c)|^2, a and b (n, 3)."""
    U, _, Vt = np.linalg.svd((b - b.mean(axis=0)).T @ (a - a.mean(axis=0)))
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    return U @ D @ Vt


class StiffParts:
    """The node sets of the stiff parts of a `fem.model.SolidModel` (module docstring)."""

    def __init__(self, nodes: np.ndarray, parts: list[np.ndarray], n_u: int) -> None:
        self.reference = nodes.T  # (n_nodes, 3)
        self.parts = parts
        self.n_u = n_u

    @classmethod
    def of(cls, model, ratio: float) -> StiffParts:
        """The parts of `model` whose shear modulus is at least `ratio` x the smallest one."""
        mu = np.asarray(model.mu, dtype=float)  # (E, 1)
        mu_elem = mu.reshape(mu.shape[0], -1).max(axis=1)
        stiff = np.flatnonzero(mu_elem >= ratio * mu_elem.min())
        elem_nodes = model.space.elem_nodes[stiff]  # (m, 10)
        if stiff.size in (0, mu_elem.size):  # one material: nothing is stiff against the rest
            return cls(model.nodes, [], model.n_u)
        # elements joined through shared nodes: the components of the element-node incidence
        m, k = elem_nodes.shape
        inc = sp.csr_matrix((np.ones(m * k), (np.repeat(np.arange(m), k), elem_nodes.ravel())),
                            shape=(m, model.space.n_nodes))  # fmt: skip
        n_parts, label = connected_components(inc @ inc.T, directed=False)
        held = np.zeros(model.space.n_nodes, dtype=bool)  # nodes with a prescribed component
        held[np.asarray(model.fixed_dofs)[np.asarray(model.fixed_dofs) < model.n_u] // 3] = True
        parts = [np.unique(elem_nodes[label == i]) for i in range(n_parts)]
        return cls(model.nodes, [p for p in parts if not held[p].any()], model.n_u)

    def project(self, x_last: np.ndarray, x_pred: np.ndarray) -> np.ndarray:
        """The prediction x_pred with every stiff part moved rigidly from x_last (module
        docstring); a new array."""
        out = x_pred.copy()
        u_last = x_last[: self.n_u].reshape(-1, 3)
        u_new = out[: self.n_u].reshape(-1, 3)  # a view: writes go to `out`
        for nodes in self.parts:
            X = self.reference[nodes]
            a, b = X + u_last[nodes], X + u_new[nodes]
            R = kabsch(a, b)
            u_new[nodes] = (a - a.mean(axis=0)) @ R.T + b.mean(axis=0) - X
        return out
