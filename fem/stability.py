r"""Stability of an equilibrium: the inertia of the tangent and its lowest eigenmodes.

An equilibrium x of a conservative model (a hyperelastic body, frictionless penalty contact:
the tangent K = dR/dx on the free dofs is symmetric) is stable when the second variation of
the energy is positive, i.e. the displacement stiffness has no negative eigenvalue.

Mixed u-p models. For "p2p1" the tangent is the saddle-point matrix

    K = [[A, B^T], [B, -C]],    C = (1 / kappa) M_p  (positive definite),

and the physical stiffness is its Schur complement on the displacements,
S = A + B^T C^{-1} B (the pressure eliminated). Haynsworth's inertia additivity gives
In(K) = In(-C) + In(S), so the number of unstable modes is

    n_unstable = neg(K) - neg(K_pp),

the tangent's negative pivots minus those of the pressure block (all n_p of them when C is
positive definite). For "p2" (no pressure dofs) it is neg(K). Sylvester's law of inertia makes
the count that of the pivots D of any LDL^T factorisation P K P^T = L D L^T (D with 1x1 and 2x2
blocks): `inertia` takes it from MKL PARDISO's symmetric indefinite factorisation (iparm 22/23;
iparm 14 counts perturbed pivots, whose signs are not certified: they are reported) or, for a
small dense matrix, from `scipy.linalg.ldl` (the eigenvalues of the block diagonal D).

Lowest modes. Shift-invert Lanczos (`scipy.sparse.linalg.eigsh`, ARPACK mode 3) on S without
forming it: (S - sigma I)^{-1} v is the displacement part of the solution of

    [[A - sigma I, B^T], [B, -C]] [w; q] = [v; 0],

one factorisation of the shifted saddle-point matrix (PARDISO's LDL^T, SuperLU without it)
serves every Lanczos step. The
eigenvalues nearest sigma come out; with sigma at or below zero and k above the negative count,
the negative ones are all found, which cross-checks the pivot count.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.linsolve import pardiso_available

#: Largest matrix whose inertia is taken from a dense LDL^T when PARDISO is missing.
DENSE_LIMIT = 4000
#: |lambda| below this share of the largest |diagonal| counts as a zero pivot (dense path).
ZERO_TOL = 1e-12
#: `stability` asks Lanczos for more modes (doubling) until it has found every negative one, up to this.
MAX_MODES = 128
#: A tangent is symmetric when |K - K^T| / |K| (max norms) is below this.
SYMMETRY_TOL = 1e-9


@dataclass(frozen=True)
class Inertia:
    """Counts of positive, negative and zero pivots of a symmetric matrix, and how many pivots
    the factorisation perturbed (their signs are not certified; 0 for the dense path)."""

    positive: int
    negative: int
    zero: int = 0
    perturbed: int = 0


def _dense_inertia(A) -> Inertia:
    M = A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float)
    _, D, _ = sla.ldl(M, lower=True)
    lam = np.linalg.eigvalsh(D)  # D is block diagonal (1x1, 2x2): its eigenvalues are cheap
    tol = ZERO_TOL * max(
        float(np.abs(np.diag(M)).max(initial=0.0)), float(np.abs(lam).max(initial=0.0)), 1e-300
    )
    return Inertia(int(np.sum(lam > tol)), int(np.sum(lam < -tol)), int(np.sum(np.abs(lam) <= tol)))


class SymmetricFactor:
    """LDL^T of a symmetric (indefinite) sparse matrix by MKL PARDISO (mtype -2): `inertia` and
    `solve`; `close()` frees PARDISO's memory. Pivot perturbation 1e-13 (as few perturbed pivots
    as possible), scaling and weighted matching (advised for saddle-point systems)."""

    def __init__(self, A) -> None:
        import pypardiso  # third-party, loaded only when a large matrix is factorised

        T = sp.triu(sp.coo_matrix(A)).tocoo()
        n = A.shape[0]
        # PARDISO needs every diagonal entry stored, a zero one too: coo -> csr keeps explicit zeros
        rows = np.concatenate([T.row, np.arange(n)])
        cols = np.concatenate([T.col, np.arange(n)])
        vals = np.concatenate([T.data, np.zeros(n)])
        self.U = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
        self.U.sort_indices()
        ps = self.ps = pypardiso.PyPardisoSolver(mtype=-2)
        ps.set_iparm(1, 1)  # user-set iparm
        ps.set_iparm(2, 2)  # METIS ordering
        ps.set_iparm(10, 13)  # pivot perturbation 1e-13
        ps.set_iparm(11, 1)  # scaling and weighted matching
        ps.set_iparm(13, 1)
        ps.set_phase(12)  # analysis and numeric factorisation
        ps._call_pardiso(self.U, np.zeros(n))
        pos, neg = int(ps.iparm[21]), int(ps.iparm[22])
        self.inertia = Inertia(pos, neg, n - pos - neg, int(ps.iparm[13]))

    def solve(self, b: np.ndarray) -> np.ndarray:
        self.ps.set_phase(33)
        return self.ps._call_pardiso(self.U, np.asfortranarray(b, dtype=float))

    def close(self) -> None:
        self.ps.free_memory(everything=True)


def _pardiso_inertia(A) -> Inertia:
    f = SymmetricFactor(A)
    f.close()
    return f.inertia


def inertia(A, method: str | None = None) -> Inertia:
    """Inertia of the symmetric matrix A (dense or sparse): "pardiso" (MKL's LDL^T), "dense"
    (`scipy.linalg.ldl`), or None: PARDISO when it imports, else dense up to `DENSE_LIMIT`."""
    n = A.shape[0]
    if A.shape != (n, n):
        raise SolverInputError("A", f"needs a square matrix, got shape {A.shape}")
    if method is None:
        method = "pardiso" if pardiso_available() and sp.issparse(A) else "dense"
    if method == "dense":
        if n > DENSE_LIMIT:
            raise SolverInputError("A", f"{n} rows is too many for a dense LDL^T (at most {DENSE_LIMIT})")
        return _dense_inertia(A)
    if method == "pardiso":
        return _pardiso_inertia(A)
    raise SolverInputError("method", f"{method!r} is not one of pardiso, dense")


def asymmetry(K) -> float:
    """max |K - K^T| / max |K|."""
    big = abs(K).max()
    return float(abs(K - K.T).max() / big) if big > 0 else 0.0


@dataclass(frozen=True)
class Stability:
    """The unstable-mode count of a state and its lowest modes (module docstring)."""

    n_unstable: int
    tangent: Inertia
    pressure_block: Inertia | None
    eigenvalues: np.ndarray  # (k,) lowest eigenvalues of S found (N/mm), ascending
    modes: np.ndarray  # (n_free_u, k) their displacement vectors on the free displacement dofs
    asymmetry: float


def split_tangent(K, free_dofs: np.ndarray, n_u: int):
    """(index of the free displacement dofs, index of the free pressure dofs) into K's rows."""
    is_u = np.asarray(free_dofs) < n_u
    return np.flatnonzero(is_u), np.flatnonzero(~is_u)


def unstable_count(K, iu, ip, method: str | None = None) -> tuple[int, Inertia, Inertia | None]:
    """neg(K) - neg(K_pp) for the symmetric tangent K with displacement rows iu, pressure rows ip."""
    whole = inertia(K, method)
    if ip.size == 0:
        return whole.negative, whole, None
    block = inertia(sp.csr_matrix(K)[ip][:, ip], method)
    return whole.negative - block.negative, whole, block


def lowest_modes(K, iu, ip, k: int, sigma: float = 0.0, tol: float = 1e-8):
    """The k eigenpairs of the Schur complement S nearest `sigma` (ascending eigenvalues)."""
    K = sp.csr_matrix(K)
    nu = iu.size
    order = np.concatenate([iu, ip])
    Kp = K[order][:, order].tocsc()
    shift = sp.diags(np.concatenate([np.full(nu, sigma), np.zeros(ip.size)]))
    shifted = (Kp - shift).tocsr()
    if pardiso_available():
        lu = SymmetricFactor(shifted)
    else:
        lu = spla.splu(shifted.tocsc(), permc_spec="MMD_AT_PLUS_A", options=dict(SymmetricMode=True))
    A = Kp[:nu, :nu]
    if ip.size:
        B = Kp[nu:, :nu]
        C = (-Kp[nu:, nu:]).tocsc()
        clu = spla.splu(C)

        def s_matvec(v):
            return A @ v + B.T @ clu.solve(B @ v)
    else:

        def s_matvec(v):
            return A @ v

    def op_inv(v):
        rhs = np.zeros(Kp.shape[0])
        rhs[:nu] = v
        return lu.solve(rhs)[:nu]

    S = spla.LinearOperator((nu, nu), matvec=s_matvec, dtype=float)
    OPinv = spla.LinearOperator((nu, nu), matvec=op_inv, dtype=float)
    k = min(k, nu - 2)
    try:
        lam, vec = spla.eigsh(S, k=k, sigma=sigma, which="LM", OPinv=OPinv, tol=tol)
    finally:
        if isinstance(lu, SymmetricFactor):
            lu.close()
    order_lam = np.argsort(lam)
    return lam[order_lam], vec[:, order_lam]


def stability(
    K, free_dofs, n_u: int, k: int | None = None, sigma: float = 0.0, method: str | None = None
) -> Stability:
    """Unstable-mode count and the lowest modes of a state whose tangent on the free dofs is K
    (`fem.model.SolidModel.residual_and_tangent`); k modes (default: the unstable count + 4),
    more if some negative ones lie farther from sigma than positive ones (then the lowest is
    among those found once all negative ones are).
    K must be symmetric to `SYMMETRY_TOL` (a conservative model); it is symmetrised."""
    K = sp.csr_matrix(K)
    skew = asymmetry(K)
    if skew > SYMMETRY_TOL:
        raise SolverInputError("K", f"the tangent is not symmetric ({skew:.2e}): no energy, no inertia test")
    K = ((K + K.T) * 0.5).tocsr()
    iu, ip = split_tangent(K, free_dofs, n_u)
    n, whole, block = unstable_count(K, iu, ip, method)
    k = (n + 4) if k is None else k
    lam, vec = lowest_modes(K, iu, ip, k, sigma)
    while np.sum(lam < 0) < n and k < MAX_MODES and k < iu.size - 2:  # some farther than a positive one
        k = min(2 * k, MAX_MODES)
        lam, vec = lowest_modes(K, iu, ip, k, sigma)
    return Stability(n, whole, block, lam, vec, skew)
