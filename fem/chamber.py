r"""Follower pressure in a closed chamber: the cavity volume, its load vector and its tangent.

A chamber pressure P acts on the deformed chamber surface Gamma (the boundary tags of the
chamber). With Nanson's formula n da = cof(F) N dA, and N the outward normal of the solid (it
points into the cavity), the cavity's volume and its derivative are

    V_cav = -1/sum(w) int_Gamma sum_i w_i x_i (cof F N)_i dA,
    q = dV_cav/du = -int_Gamma (cof F N) . du dA

so the pressure load is P q(u), and its consistent tangent is P dq/du with
d(cof F)_iJ / dF_kL = J (H_iJ H_kL - H_iL H_kJ), H = F^{-T}. The weights w drop the flux through
cut planes (symmetry planes through the origin contribute nothing; a plane-strain cap z = H does
unless w_z = 0). dq/du is not symmetric facet by facet; with it Newton converges quadratically.
For a closed (or symmetrically cut) chamber the load is conservative (P dV/du), and the assembled
tangent is symmetric to round-off.

A model may have several chambers, each with its own pressure (the robot's three ePSAs).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcrawl.fem.discretisation import Discretisation, element_first
from softcrawl.fem.neohooke import cofactor3, det3


@dataclass(frozen=True)
class ChamberSpec:
    """A chamber: the boundary `tags` of its surface and the cut-plane `volume_weights`."""

    tags: tuple[str, ...]
    volume_weights: tuple[float, float, float] = (1.0, 1.0, 1.0)
    name: str = "chamber"


class Chamber:
    """Facet quadrature of one chamber surface on `space`."""

    def __init__(self, space: Discretisation, spec: ChamberSpec) -> None:
        self.space = space
        self.spec = spec
        self.tags = tuple(spec.tags)
        facets = np.concatenate([space.boundary(t, "chamber") for t in self.tags])
        fb = space.facet_basis(facets, intorder=4)
        self.N = np.stack([np.asarray(phi[0]) for phi in fb.basis])  # (10, F, Qf)
        self.dN = np.stack([phi[0].grad for phi in fb.basis])  # (10, 3, F, Qf)
        self.normal = fb.normals  # (3, F, Qf) solid outward
        self.dx = fb.dx
        self.node_dofs = fb.element_dofs  # (10, F)
        self.weights = np.asarray(spec.volume_weights, dtype=float)
        self._g_aqJ = element_first(self.dN)
        self._g_qaJ = np.ascontiguousarray(self.dN.transpose(2, 3, 0, 1))  # (F, Qf, 10, 3)
        self._nodes = np.ascontiguousarray(self.node_dofs.T)
        self._Ndx = np.ascontiguousarray((self.N * self.dx).transpose(1, 0, 2))  # (F, 10, Qf)
        self.u_dofs = (3 * self.node_dofs[:, None, :] + np.arange(3)[None, :, None]).reshape(30, -1)

    def _kinematics(self, x):
        F = self.space.deformation_gradient(x, self._g_aqJ, self._nodes)
        cofN = -np.einsum("iJfq,Jfq->ifq", cofactor3(F), self.normal)  # cavity-outward n da/dA
        return F, cofN

    def volume(self, x: np.ndarray) -> float:
        """Enclosed cavity volume of the deformed chamber (mm^3)."""
        _, cofN = self._kinematics(x)
        ue = x[: self.space.n_u].reshape(-1, 3)[self.node_dofs]  # (10, F, 3)
        X = np.einsum("iaf,afq->ifq", self.space.nodes[:, self.node_dofs], self.N)
        xq = X + np.einsum("afi,afq->ifq", ue, self.N)
        w = self.weights
        return float(np.einsum("i,ifq,ifq,fq->", w, xq, cofN, self.dx) / w.sum())

    def load(self, x: np.ndarray, with_tangent: bool):
        """Facet vectors q (30, F) and, if asked, the facet tangents dq/du (F, 30, 30), local dof
        3 a + i (`u_dofs`)."""
        F, cofN = self._kinematics(x)
        q = np.einsum("afq,ifq,fq->aif", self.N, cofN, self.dx).reshape(30, -1)
        if not with_tangent:
            return q, None
        J = det3(F)
        H = cofactor3(F) / J
        # d(cof F N)_i / dF_kL = -J (H_iJ H_kL - H_iL H_kJ) N_J = D[i, L, k]   (the minus: cavity
        # normal); dq[a i, b k] = int N_a D[i, L, k] dN_b/dX_L dA: per point (10 x 3) @ D[i]
        # gives E[i, b, k], then one (10 x Qf) @ (Qf x 90) product per facet.
        HN = np.einsum("iJfq,Jfq->ifq", H, self.normal)
        D = -J * (HN[:, None, None] * H.transpose(1, 0, 2, 3)[None] - H[:, :, None] * HN[None, None])
        D = np.ascontiguousarray(D.transpose(3, 4, 0, 1, 2))  # (F, Qf, 3, 3, 3)
        E = np.matmul(self._g_qaJ[:, :, None], D)  # (F, Qf, 3, 10, 3)
        n_f, n_q = E.shape[:2]
        dq = np.matmul(self._Ndx, E.reshape(n_f, n_q, 90)).reshape(n_f, 30, 30)
        return q, dq
