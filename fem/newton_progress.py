r"""When a Newton iteration is given up, or accepted at a floor: tests on its residual history.

h_0, h_1, ..., h_k are the relative residuals (`fem.newton`'s merits) of the iterations so far;
`best(a, b)` is the lowest of h_a .. h_b.

Stalled residuals. After `stall_iter` iterations the best of the last three must be below half
the best before them, best(k-2, k) <= 0.5 best(0, k-3); a residual that stops shrinking is a
divergence, unless `stall_tol` is set and h_k <= stall_tol and the residual has not halved in
three iterations: then the state is accepted as converged (its `NewtonRecord` keeps the
residuals, so the floor shows). This is for non-smooth problems: a penalty contact whose points
sit on the kink of the normal law (gap = 0) or on the Coulomb cone flip between the two branches
from one iteration to the next, and the residual settles at a floor set by the few flipping
points rather than by the physics (docs/decisions/056-newton-stall.md). `tol` stays the target;
`stall_tol` only bounds what a stall may leave.

No new lowest residual (`progress_iter`; None, the default: off). After `progress_iter`
iterations, three in a row without a new lowest residual, best(k-2, k) > best(0, k-3), are a
divergence. The stall test asks for halving and so must wait long (12 iterations on the feet) not
to give up a slow but steady descent; this one gives up only an iteration that has climbed back
from its best and stays above it, which the non-monotone line search allows (a full step is taken
when it is below the largest of the last three residuals). Abaqus/Standard's increment control
gives an increment up in the same situation, sooner: after I_0 = 4 iterations, a residual that
grows in two consecutive iterations (Abaqus Analysis User's Guide, "Convergence criteria for
nonlinear problems"). Measured on the FE-body crawl, where the sub-steps at the feet's slip onset
fail this way: docs/decisions/090-newton-progress.md.
"""

from __future__ import annotations

from collections.abc import Sequence


def stalled(history: Sequence[float], k: int) -> bool:
    """After k iterations, the best of the last three merits is not below half the best before
    them (the residual has stopped shrinking)."""
    return len(history) > k and min(history[-3:]) > 0.5 * min(history[:-3])


def accepts_stall(history: Sequence[float], stall_tol: float | None, p_ok: bool) -> bool:
    """The current state is below `stall_tol` and has stopped shrinking for three iterations
    (not `stall_iter`: below stall_tol a converging Newton iteration gains orders of magnitude
    per step, so three without halving is a floor, and each further one costs a solve)."""
    return stall_tol is not None and p_ok and history[-1] <= stall_tol and stalled(history, 3)


def divergence(history: Sequence[float], stall_iter: int, progress_iter: int | None) -> str | None:
    """Why the iteration is given up (module docstring), or None while it may go on."""
    if stalled(history, stall_iter):
        return f"residual stalls at {history[-1]:.2e} after {len(history) - 1} iterations"
    late = progress_iter is not None and len(history) > max(progress_iter, 3)
    if late and min(history[-3:]) > min(history[:-3]):
        return (
            f"no new lowest residual in three iterations (at {history[-1]:.2e} after {len(history) - 1}; "
            f"lowest {min(history):.2e})"
        )
    return None
