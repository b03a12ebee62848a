r"""The tensor algebra of isotropic hyperelasticity in I1, and the Neo-Hookean kernel.

The laws themselves (energy, Psi', Psi'', uniaxial stress, fit) are in `fem.laws`
(docs/decisions/002-laws.md); this module has what their stress and tangent are made of
(`fem.laws.base.IsochoricI1Law`): for a law
W(F) = Psi(I1bar) + K/2 (J - 1)^2, I1bar = J^{-2/3} I1,  I1 = F:F,  J = det F,  H = F^{-T}, with
c = 2 Psi' J^{-2/3}, D = F - I1/3 H and d = 4 Psi'' J^{-4/3}:

    P_iso = c D
    A_iso = c [ dd - 2/3 (F (x) H + H (x) F) + 2/9 I1 H (x) H + I1/3 H (.) H ] + d D (x) D

(the bracket is the Neo-Hookean tangent per unit c; the last term is d c / dF (x) D, zero for
Neo-Hookean, whose Psi = mu/2 (I1bar - 3) has Psi' = mu/2, Psi'' = 0). `fem.solid` uses the
Neo-Hookean kernel below (`iso_stress`, `mixed_tangent`) directly for the laws linear in I1.

Decoupled (isochoric/volumetric) Neo-Hookean solid with shear modulus mu and bulk modulus K:

    W(F) = mu/2 (J^{-2/3} I1 - 3) + K/2 (J - 1)^2,     I1 = F:F,  J = det F,  H = F^{-T}.

Small K/mu is a compressible solid; K/mu >= 1000 is the nearly incompressible silicone. The split
lets the mixed u-p formulation (`fem.model`) replace the volumetric part by an independent
pressure p: W_mixed = W_iso + p (J - 1) - p^2 / (2K).

Isochoric part (derivatives with dJ/dF = J H, dH_iJ/dF_kL = -H_iL H_kJ):

    P_iso = mu J^{-2/3} (F - I1/3 H)
    A_iso[iJkL] = mu J^{-2/3} [ d_ik d_JL - 2/3 (F_iJ H_kL + H_iJ F_kL)
                                + 2/9 I1 H_iJ H_kL + I1/3 H_iL H_kJ ]

Pressure part for a given p (mixed) and its F-derivative:

    P_p = p J H,       A_p[iJkL] = p J (H_iJ H_kL - H_iL H_kJ)

Displacement-only volumetric part, p = K (J - 1):

    A_vol = K J^2 H_iJ H_kL + K (J - 1) J (H_iJ H_kL - H_iL H_kJ)

Arrays: F has shape (3, 3, ...) (trailing axes are elements and quadrature points); tangents have
shape (3, 3, 3, 3, ...). Units: MPa.
"""

from __future__ import annotations

import numpy as np


def det3(F: np.ndarray) -> np.ndarray:
    return (
        F[0, 0] * (F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1])
        - F[0, 1] * (F[1, 0] * F[2, 2] - F[1, 2] * F[2, 0])
        + F[0, 2] * (F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0])
    )


def cofactor3(F: np.ndarray) -> np.ndarray:
    """cof F = J F^{-T}, exact for any F (no division)."""
    C = np.empty_like(F)
    for i in range(3):
        i1, i2 = (i + 1) % 3, (i + 2) % 3
        for j in range(3):
            j1, j2 = (j + 1) % 3, (j + 2) % 3
            C[i, j] = F[i1, j1] * F[i2, j2] - F[i1, j2] * F[i2, j1]
    return C


def inv_transpose3(F: np.ndarray) -> np.ndarray:
    return cofactor3(F) / det3(F)


def iso_stress(F, mu, J, H):
    I1 = np.einsum("ij...,ij...->...", F, F)
    return mu * J ** (-2 / 3) * (F - I1 / 3 * H)


def outer(A, B):
    """out[i,J,k,L] = A[i,J] B[k,L] (trailing axes broadcast)."""
    return A[:, :, None, None] * B[None, None, :, :]


def _cross(A, B):
    """out[i,J,k,L] = A[i,L] B[k,J]."""
    return A[:, None, None, :] * B.swapaxes(0, 1)[None, :, :, None]


def iso_tangent(F, mu, J, H):
    I1 = np.einsum("ij...,ij...->...", F, F)
    c = mu * J ** (-2 / 3)
    eye = np.eye(3)
    dd = (eye[:, None, :, None] * eye[None, :, None, :]).reshape((3, 3, 3, 3) + (1,) * (F.ndim - 2))
    A = outer(F, H)
    A += outer(H, F)
    A *= -2.0 / 3.0
    A += (2.0 / 9.0 * I1) * outer(H, H)
    A += (I1 / 3.0) * _cross(H, H)
    A += dd
    A *= c
    return A


def general_iso_tangent(F, c, d, J, H):
    """c [Neo-Hookean bracket] + d D (x) D with D = F - I1/3 H (module docstring)."""
    I1 = np.einsum("ij...,ij...->...", F, F)
    A = iso_tangent(F, 1.0, J, H) * (c * J ** (2 / 3))
    D = F - I1 / 3 * H
    return A + d * outer(D, D)


def mixed_tangent(F, mu, p, J, H):
    """A_iso + A_p in one pass: four weighted outer products,
    c dd - 2c/3 (F (x) H + H (x) F) + (2c I1/9 + p J) H (x) H + (c I1/3 - p J) H (.) H, c = mu J^-2/3."""
    I1 = np.einsum("ij...,ij...->...", F, F)
    c = mu * J ** (-2 / 3)
    pJ = p * J
    A = outer(F, H)
    A += outer(H, F)
    A *= -2.0 / 3.0 * c
    A += (2.0 / 9.0 * c * I1 + pJ) * outer(H, H)
    A += (c * I1 / 3.0 - pJ) * _cross(H, H)
    eye = np.eye(3)
    A += c * (eye[:, None, :, None] * eye[None, :, None, :]).reshape((3, 3, 3, 3) + (1,) * (F.ndim - 2))
    return A


def pressure_stress(p, J, H):
    return p * J * H


def pressure_tangent(p, J, H):
    return (p * J) * (outer(H, H) - _cross(H, H))


def cauchy_stress(P: np.ndarray, F: np.ndarray) -> np.ndarray:
    """sigma = J^{-1} P F^T."""
    return np.einsum("iJ...,kJ...->ik...", P, F) / det3(F)


def von_mises(sigma: np.ndarray) -> np.ndarray:
    s = sigma - np.einsum("kk...->...", sigma) / 3 * np.eye(3).reshape((3, 3) + (1,) * (sigma.ndim - 2))
    return np.sqrt(1.5 * np.einsum("ij...,ij...->...", s, s))


def principal_stretches(F: np.ndarray) -> np.ndarray:
    """Principal stretches sqrt(eig(F^T F)), ascending, shape (..., 3)."""
    C = np.einsum("kI...,kJ...->...IJ", F, F)
    return np.sqrt(np.clip(np.linalg.eigvalsh(C), 0.0, None))
