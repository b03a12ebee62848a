r"""Right-preconditioned GMRES: a Newton step on the current tangent with an older factorisation.

A Newton iteration needs the step dx with K dx = -R to the accuracy of the forcing term eta,
||W (K dx + R)|| <= eta ||W R|| (W: diagonal row weights that put forces and volume constraints
on one scale). When the factorisation of an earlier tangent K0 is at hand, GMRES on K with the
right preconditioner K0^{-1} gets there in a few iterations as long as K0^{-1} K is close to the
identity: each iteration costs one product with K and one solve with the old factors (forward and
back substitution), an order of magnitude less than a new factorisation (docs/decisions/016-solver-pass1.md
has the measurements).

GMRES (Saad & Schultz 1986) builds an orthonormal basis v_1..v_m of the Krylov space of
A = W K M^{-1} from v_1 = W b / ||W b|| (Arnoldi, classical Gram-Schmidt with one
re-orthogonalisation pass, CGS2) and picks y minimising ||beta e_1 - H y|| over the (m + 1) x m
Hessenberg matrix H; the residual norm of that least-squares problem is the true (weighted)
residual in exact arithmetic, so the loop stops as soon as it is below rtol ||W b||. The solution
is x = M^{-1} V y. No restart: the callers cap the iterations far below any memory concern.

The vector operations are `np.einsum` (numpy's own loops), not BLAS: numpy's OpenBLAS runs a
dot product of 22k entries on its threads, and on a machine busy with other jobs each call waited
1-25 ms for them (12 GMRES iterations without the preconditioner: 0.32 s with BLAS dot products,
0.03 s on one BLAS thread; docs/decisions/017-solver-pass2.md).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class KrylovResult:
    x: np.ndarray
    iterations: int
    relative_residual: float  # ||W (b - K x)|| / ||W b||
    converged: bool
    residuals: tuple[float, ...] = ()  # relative residual after each iteration


def dot(a: np.ndarray, b: np.ndarray) -> float:
    """a . b of two vectors by numpy's own loop, not a BLAS call (module docstring)."""
    return float(np.einsum("i,i->", a, b))


def norm(a: np.ndarray) -> float:
    """||a||_2 of a vector without BLAS (module docstring)."""
    return float(np.sqrt(np.einsum("i,i->", a, a)))


def projected_iterations(k: int, rel: float, rtol: float) -> float:
    """Iterations to reach rtol at the geometric mean rate of the first k, which reached rel."""
    if rel >= 1.0:
        return np.inf
    return k * np.log(rtol) / np.log(rel)


def gmres(
    matvec: Callable[[np.ndarray], np.ndarray],
    precondition: Callable[[np.ndarray], np.ndarray],
    b: np.ndarray,
    *,
    rtol: float,
    max_iter: int,
    weights: np.ndarray | None = None,
    abandon: bool = False,
) -> KrylovResult:
    """Solve K x = b with x = M^{-1} y (right preconditioning), stopping at
    ||W (b - K x)|| <= rtol ||W b|| or after `max_iter` iterations. `matvec` is v -> K v,
    `precondition` v -> M^{-1} v, `weights` the diagonal of W (ones when None). With `abandon`,
    the loop also stops (not converged) from the third iteration on when the average rate so far,
    continued, would need more than `max_iter` iterations (`projected_iterations`): a caller that
    falls back to a factorisation then wastes fewer iterations."""
    w = np.ones_like(b) if weights is None else weights
    r0 = w * b
    beta = norm(r0)
    if beta == 0.0:
        return KrylovResult(np.zeros_like(b), 0, 0.0, True)
    V = np.empty((max_iter + 1, b.size))
    Z = np.empty((max_iter, b.size))  # preconditioned basis vectors M^{-1} v_j
    H = np.zeros((max_iter + 1, max_iter))
    V[0] = r0 / beta
    rel, k, y, history = 1.0, 0, np.zeros(0), []
    for k in range(1, max_iter + 1):
        j = k - 1
        Z[j] = precondition(V[j] / w)
        u = w * matvec(Z[j])
        for _ in range(2):  # classical Gram-Schmidt, twice (CGS2): V orthonormal to round-off
            c = np.einsum("ij,j->i", V[:k], u)
            H[:k, j] += c
            u -= np.einsum("i,ij->j", c, V[:k])
        H[k, j] = norm(u)
        if H[k, j] > 0:
            V[k] = u / H[k, j]
        e1 = np.zeros(k + 1)
        e1[0] = beta
        y, *_ = np.linalg.lstsq(H[: k + 1, :k], e1, rcond=None)
        rel = float(np.linalg.norm(e1 - H[: k + 1, :k] @ y)) / beta
        history.append(rel)
        if rel <= rtol or H[k, j] == 0:
            break
        if abandon and k >= 3 and projected_iterations(k, rel, rtol) > max_iter:
            break
    x = np.einsum("i,ij->j", y, Z[: y.size])
    return KrylovResult(x, k, rel, rel <= rtol, tuple(history))
