r"""The hyperelastic body: nearly incompressible, mixed u-p or displacement only, any law W_iso(I1bar).

Energy. With W_iso(F) = Psi(I1bar), I1bar = J^{-2/3} I1 (any law of `fem.laws`: Neo-Hookean
Psi = mu/2 (I1bar - 3), Yeoh, Gent) the mixed ("p2p1") energy is

    Pi(u, p) = int_Omega [ W_iso(F) + p (J - 1) - p^2 / (2K) ] dV

and the displacement-only formulation ("p2") uses the full W(F) = W_iso + K/2 (J - 1)^2.
Residuals (test functions du, dp):

    R_u = int (P_iso + p J F^{-T}) : grad du dV,       R_p = int (J - 1 - p/K) dp dV

Psi', Psi'' and K are element-wise (a mapping subdomain -> law gives a multi-material body). The
stress is P_iso = c (F - I1/3 H) with c = 2 Psi' J^{-2/3}; the tangent is the Neo-Hookean one with
this c plus d D (x) D, d = 4 Psi'' J^{-4/3}, D = F - I1/3 H (`fem.neohooke`). A body of
Neo-Hookean laws only has Psi' = mu/2 constant and d = 0: its stress and tangent take the
original Neo-Hookean path (no Psi'' term, no extra product), so it is not slowed down. Otherwise
the D (x) D term is one more batched product per chunk, sum_q d dx (D g_a)_i (D g_b)_k.

Assembly is vectorised over all elements and quadrature points (batched matrix products), never a
per-basis-function loop: docs/decisions/012-assembly.md says why this matters. The pointwise
algebra (F, J, F^-T, P) runs on contiguous component arrays of the whole mesh; the element
matrices are built per chunk of elements (temporaries stay in cache) on the assembly threads
(`fem.parallel`) and written straight into the sparsity pattern's value array, only the upper
half of each symmetric element matrix (`fem.pattern.Mirrored`). On the 3,840-tet benchmark tube
(19,431 DOFs, 2 cores) an assembly went from ~230 ms to ~75 ms (one thread) against ~350 ms for a
PARDISO solve (bench/assembly_bench.py).

Why P2-P1 (measured: plane-strain tube A = 1, B = 20 mm, K/mu = 1000, geometric radial grading,
`fem.verification.tube_test`, pressure ramp to 0.5 mu and then 2 mu):

    formulation  cells (radial x around)  DOFs   Newton iterations   inner-radius error
    p2p1         6 x 4                    1123   56                  5.5e-4 (0.5 mu), 2.8e-3 (2 mu)
    p2p1         12 x 8                   4059   50                  2.3e-5 (0.5 mu), 1.4e-3 (2 mu)
    p2p1         24 x 16                  15403  37                  4.9e-7 (0.5 mu), 1.6e-3 (2 mu)
    p2           6 x 4                    1053   317, stalls at 61 kPa ~ 2 mu
                                                 (and fails at 0.5 mu alone, 182 it.)
    p2           12 x 8                   3825   324, stalls at 62 kPa

The P2-P1 error at 0.5 mu converges at observed orders 4.6 and 5.6 (nodal superconvergence); at
2 mu it levels off at ~1.5e-3, which is the K/mu = 1000 compressibility against the incompressible
analytic solution: at K/mu = 1e5 the same meshes give 4.3e-3 and 1.7e-4 (order 4.7).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from softcrawl.fem.discretisation import Discretisation
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws.base import IsochoricI1Law
from softcrawl.fem.neohooke import cofactor3, det3
from softcrawl.fem.parallel import for_chunks
from softcrawl.fem.pattern import Mirrored

#: Elements per chunk of the volume assembly (`fem.parallel.for_chunks`): small enough for the
#: temporaries of a chunk (~10 kB per element) to stay in a core's cache.
_CHUNK = 128


class InvertedElement(ArithmeticError):
    """A trial state with det F <= 0 somewhere: the caller cuts the step back."""


def _uu_entries():
    """The 465 stored entries (r, c) of the symmetric 30 x 30 K_uu, r = 10 i + a, c = 10 k + b:
    first the upper triangles of the three diagonal blocks i = k (the entries that get c g.g),
    then the blocks i < k."""
    r, c = np.triu_indices(30)
    first = r // 10 == c // 10
    return np.concatenate([r[first], r[~first]]), np.concatenate([c[first], c[~first]])


_UU_ROWS, _UU_COLS = _uu_entries()


def _uu_gather() -> np.ndarray:
    """Indices into [K_fh (900) | M (900)] of the terms K_fh[i a, k b] and M[k a, i b] of the
    stored K_uu entries [i a, k b] (see `Solid._tangent_chunk`)."""
    (i, a), (k, b) = np.divmod(_UU_ROWS, 10), np.divmod(_UU_COLS, 10)
    return np.concatenate([30 * _UU_ROWS + _UU_COLS, 900 + (10 * k + a) * 30 + 10 * i + b])


_UU_GATHER = _uu_gather()


def _view(a: np.ndarray, shape) -> np.ndarray:
    """A reshaped view of `a` (an error, never a silent copy: results are written into it)."""
    v = a.view()
    v.shape = shape
    return v


class Stress(NamedTuple):
    """The pointwise state of the body (tensors (3, 3, E, Q), scalars (E, Q))."""

    F: np.ndarray  # (3, 3, E, Q)
    J: np.ndarray  # (E, Q)
    H: np.ndarray  # F^-T, (3, 3, E, Q)
    p: np.ndarray  # pressure, (E, Q)
    c: np.ndarray  # 2 Psi' J^-2/3 (mu J^-2/3 for Neo-Hookean), (E, Q)
    I1: np.ndarray  # F:F, (E, Q)
    P: np.ndarray  # first Piola stress, (3, 3, E, Q)
    d: np.ndarray | None = None  # 4 Psi'' J^-4/3 (E, Q); None for a Neo-Hookean body


class Solid:
    """The body of `space` with `materials` (one law, e.g. `NeoHookean`, `fem.laws.Yeoh`, or a
    mapping subdomain -> law)."""

    def __init__(self, space: Discretisation, materials) -> None:
        self.space = space
        self.mixed = space.mixed
        self.mu, self.bulk, self._nonlinear = _material_arrays(space.mesh, materials, space.dx.shape[0])
        # g_a . g_b (a <= b, `np.triu_indices(10)`) at each quadrature point: (E, Q, 55)
        ta, tb = np.triu_indices(10)
        self._gg = np.ascontiguousarray(np.einsum("aJeq,aJeq->eqa", space.dN[ta], space.dN[tb]))
        u = space.u_dofs
        # Symmetric element matrices: the upper triangle of K_uu and, for the mixed formulation,
        # K_up (standing for K_pu = K_up^T too) and the upper triangle of K_pp.
        self.groups = [Mirrored(u[_UU_ROWS], u[_UU_COLS])]
        if self.mixed:
            self._Np_qc = np.ascontiguousarray(space.Np.transpose(1, 2, 0))  # (E, Q, 4)
            # K_pp = -int Np_c Np_d / K dV depends on the mesh and the material only.
            Kpp = -np.einsum("ceq,deq,eq->ecd", space.Np, space.Np, space.dx / self.bulk)
            self._Kpp_upper = Kpp[(slice(None),) + np.triu_indices(4)]  # (E, 10)
            self.groups += [Mirrored.block(u, space.p_dofs), Mirrored.upper(space.p_dofs)]
        self._elem_dofs = np.ascontiguousarray(space.element_dofs.T)  # (E, n_local)

    def internal_force(self, stress: Stress) -> np.ndarray:
        """The body's internal force on all dofs (the residual R_u, R_p of the module docstring)."""
        values = self.element_residual(stress)
        return np.bincount(
            self._elem_dofs.reshape(-1), weights=values.reshape(-1), minlength=self.space.n_dofs
        )

    def pressure_field(self, x: np.ndarray) -> np.ndarray:
        """Mixed pressure at the quadrature points (E, Q); for "p2", K (J - 1)."""
        if self.mixed:
            return np.einsum("ce,ceq->eq", x[self.space.p_dofs], self.space.Np)
        F = self.space.deformation_gradient(x)
        return self.bulk * (det3(F) - 1.0)

    def stress(self, x: np.ndarray) -> Stress:
        """F, J, H = F^-T, the pressure p, c = 2 Psi' J^-2/3 (mu J^-2/3 for Neo-Hookean), I1 = F:F,
        the first Piola stress P = c (F - I1/3 H) + p J H at all quadrature points (p = K (J - 1)
        for "p2") and, for a non-Neo-Hookean law, d = 4 Psi'' J^-4/3.

        Tensors are (3, 3, E, Q) and scalars (E, Q), contiguous: every component is one
        contiguous array, so the pointwise algebra runs at memory speed."""
        F = self.space.deformation_gradient(x)
        J = det3(F)
        if np.any(J <= 0.0) or not np.all(np.isfinite(J)):
            raise InvertedElement("det F <= 0")
        H = cofactor3(F)
        H /= J
        p = self.pressure_field(x) if self.mixed else self.bulk * (J - 1.0)
        I1 = np.einsum("ijeq,ijeq->eq", F, F)
        if not self._nonlinear:
            c = self.mu * J ** (-2.0 / 3.0)
            P = c * (F - (I1 / 3.0) * H) + (p * J) * H
            return Stress(F, J, H, p, c, I1, P)
        c, d = self._law_coefficients(J, I1)
        P = c * (F - (I1 / 3.0) * H) + (p * J) * H
        return Stress(F, J, H, p, c, I1, P, d)

    def _law_coefficients(self, J, I1):
        """c = 2 Psi' J^-2/3 and d = 4 Psi'' J^-4/3 (E, Q) for a body with a non-Neo-Hookean law."""
        j23 = J ** (-2.0 / 3.0)
        psi1 = np.broadcast_to(0.5 * self.mu, J.shape).copy()  # Neo-Hookean elements
        psi2 = np.zeros_like(J)
        x = j23 * I1 - 3.0
        for elements, law in self._nonlinear:
            try:
                law.check_state(x[elements])
            except ValueError as exc:
                raise InvertedElement(str(exc)) from None
            psi1[elements], psi2[elements] = law.psi_derivatives(x[elements])
        return 2.0 * psi1 * j23, 4.0 * psi2 * j23 * j23

    def element_residual(self, stress: Stress) -> np.ndarray:
        """Element residuals (E, n_local) in the local order of `element_dofs`:
        R_u[i a] = int P_iJ g_aJ dV and R_p[c] = int (J - 1 - p/K) Np_c dV."""
        E, Q = self.space.dx.shape
        Pw = np.ascontiguousarray((stress.P * self.space.dx).transpose(2, 0, 3, 1)).reshape(E, 3, 3 * Q)
        Ru = np.matmul(Pw, self.space.g_aqJ.transpose(0, 2, 1)).reshape(
            E, 30
        )  # [e, i, (q, J)] @ [e, (q, J), a]
        if not self.mixed:
            return Ru
        w = (stress.J - 1.0 - stress.p / self.bulk) * self.space.dx
        return np.hstack([Ru, np.matmul(w[:, None, :], self._Np_qc)[:, 0]])

    def element_tangent(self, stress: Stress, blocks) -> None:
        """Element matrices into blocks[0..2] (K_uu, K_up, K_pp; K_uu only for "p2"),
        over chunks of elements on the assembly threads (`fem.parallel`); see `_tangent_chunk`."""
        J, p, c, I1, dx = stress.J, stress.p, stress.c, stress.I1, self.space.dx
        w1 = (2.0 / 9.0) * c * I1 + p * J
        if not self.mixed:
            w1 += self.bulk * J * J
        w2 = c * I1 / 3.0 - p * J
        # (E, Q, 3, 3) arrays for the batched products of the chunks: H and the combination
        # A = -2c/3 F + w1/2 H, with V = A g (dx included in A)
        H = np.ascontiguousarray(stress.H.transpose(2, 3, 0, 1))
        A = stress.F * ((-2.0 / 3.0) * c * dx) + stress.H * (0.5 * w1 * dx)
        A = np.ascontiguousarray(A.transpose(2, 3, 0, 1))
        weights = np.stack([w2 * dx, c * dx, J * dx])
        D = None
        if stress.d is not None:  # D = F - I1/3 H and its weight d dx, for the d D (x) D term
            D = np.ascontiguousarray((stress.F - (I1 / 3.0) * stress.H).transpose(2, 3, 0, 1))
            weights = np.concatenate([weights, (stress.d * dx)[None]])
        for_chunks(
            lambda s: self._tangent_chunk(s, A[s], H[s], weights[:, s], blocks, None if D is None else D[s]),
            self.space.dx.shape[0],
            _CHUNK,
        )

    def _tangent_chunk(self, s, A, H, weights, blocks, D=None):
        r"""Element matrices of the elements `s` (a slice) into blocks[k][s]; A and H are
        (n, Q, 3, 3) (A as below, dx included) and weights (3, n, Q) = (w2 dx, c dx, J dx), plus
        d dx as a fourth row when `D` = F - I1/3 H (n, Q, 3, 3) is given (non-Neo-Hookean laws:
        the term d (D g_a)_i (D g_b)_k is added to K_fh).

        Local dofs: u component i of node a is 10 i + a, then the pressure dofs c. With
        g_a = grad N_a, f_ai = F_iJ g_aJ, h_ai = H_iJ g_aJ and c = 2 Psi' J^-2/3, the Neo-Hookean +
        pressure tangent (`fem.neohooke.mixed_tangent`) contracted with g_a and g_b is, per
        quadrature point (weight dx),

            K_uu[i a, k b] = c (g_a . g_b) d_ik - 2c/3 (f_ai h_bk + h_ai f_bk)
                             + w1 h_ai h_bk + w2 h_ak h_bi,
            w1 = 2c I1/9 + p J (+ K J^2 for "p2"),   w2 = c I1/3 - p J,
            K_up[i a, c] = J h_ai Np_c,   K_pu = K_up^T,   K_pp = -Np_c Np_d / K (constant).

        The quadrature sums are inside batched matrix products, one per element: with
        V = -2c/3 f + w1/2 h = A g (A = -2c/3 F + w1/2 H, formed pointwise for all elements), the
        f/h terms are K_fh = [V; h]^T [h; V] (inner dimension 2Q); the
        swapped term is M[k a, i b] = sum w2 h_ka h_ib read with i and k exchanged. K_uu is
        symmetric, so only half of it is stored (`fem.pattern.Mirrored`; the 465 entries of
        `_uu_entries`): one gather picks their K_fh and M terms. The upper triangle of
        G = sum c (g_a . g_b) (precomputed g_a . g_b) is added to the three diagonal blocks,
        which come first.
        """
        gt = self.space.g_qJa[s]  # gt[e, q, J, a] = dN_a/dX_J
        n, Q = H.shape[:2]
        w_sw, w_g, w_p = weights[:3, :, :, None]
        Vh = np.empty((n, 3 * Q, 3, 10))  # rows [V; h; V]
        np.matmul(A, gt, out=Vh[:, :Q])  # V[e, q, i, a] = (A g_a)_i dx
        np.matmul(H, gt, out=Vh[:, Q : 2 * Q])  # h[e, q, i, a]
        Vh[:, 2 * Q :] = Vh[:, :Q]
        Vh = Vh.reshape(n, 3 * Q, 30)
        h = Vh[:, Q : 2 * Q]  # (n, Q, 30)
        terms = np.empty((n, 1800))  # [K_fh | M]
        np.matmul(Vh[:, : 2 * Q].transpose(0, 2, 1), Vh[:, Q:], out=_view(terms[:, :900], (n, 30, 30)))
        np.matmul((h * w_sw).transpose(0, 2, 1), h, out=_view(terms[:, 900:], (n, 30, 30)))
        if D is not None:  # + sum_q d dx (D g_a)_i (D g_b)_k, symmetric, into the K_fh part
            Dg = np.matmul(D, gt).reshape(n, Q, 30)
            _view(terms[:, :900], (n, 30, 30))[...] += np.matmul(
                (Dg * weights[3][:, :, None]).transpose(0, 2, 1), Dg
            )
        picked = np.take(terms, _UU_GATHER, axis=1)  # (n, 465 + 465)
        Kuu = blocks[0][s]
        np.add(picked[:, :465], picked[:, 465:], out=Kuu)
        G = np.matmul(w_g.transpose(0, 2, 1), self._gg[s])  # (n, 1, 55): c (g_a . g_b), a <= b
        _view(Kuu[:, :165], (n, 3, 55))[...] += G  # the diagonal blocks' upper triangles
        if self.mixed:
            np.matmul(h.transpose(0, 2, 1), self._Np_qc[s] * w_p, out=_view(blocks[1][s], (n, 30, 4)))
            blocks[2][s] = self._Kpp_upper[s]


def _material_arrays(mesh, materials, n_elem):
    """(mu, K) arrays (E, 1) and the non-Neo-Hookean laws as [(element indices, law)]."""
    if isinstance(materials, IsochoricI1Law):
        nonlinear = [] if materials.LINEAR_IN_I1 else [(np.arange(n_elem), materials)]
        return np.full((n_elem, 1), materials.mu), np.full((n_elem, 1), materials.bulk), nonlinear
    if not isinstance(materials, Mapping):
        raise SolverInputError(
            "materials", "give a law (NeoHookean, Yeoh, Gent) or a mapping subdomain -> law"
        )
    subdomains = mesh.subdomains or {}
    mu = np.full((n_elem, 1), np.nan)
    bulk = np.full((n_elem, 1), np.nan)
    nonlinear = []
    for name, mat in materials.items():
        if name not in subdomains:
            raise SolverInputError("materials", f"unknown subdomain {name!r}; known: {sorted(subdomains)}")
        if not isinstance(mat, IsochoricI1Law):
            raise SolverInputError("materials", f"subdomain {name!r}: {mat!r} is not a solver law")
        mu[subdomains[name]] = mat.mu
        bulk[subdomains[name]] = mat.bulk
        if not mat.LINEAR_IN_I1:
            nonlinear.append((np.asarray(subdomains[name]), mat))
    if np.isnan(mu).any():
        raise SolverInputError("materials", "some elements have no material")
    return mu, bulk, nonlinear
