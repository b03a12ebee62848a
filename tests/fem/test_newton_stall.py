"""A residual that stalls below `NewtonOptions.stall_tol` is accepted as converged (fem.newton,
"Stalled residuals"), and only then.

The stall is made with a tolerance below round-off (1e-17): the residual of the pressurised tube
settles at its floor (~1e-15 relative) and stops shrinking. That is the same situation as a
contact whose points flip on a kink, without the contact."""

import numpy as np
import pytest

from softcrawl.fem import reference_models as RM
from softcrawl.fem.newton import Diverged, NewtonOptions, NewtonSolver

UNREACHABLE = 1e-17


def _solve(**options):
    model = RM.tube_model(3.0, 9.0, n_radial=3, n_angle=4)
    solver = NewtonSolver(model, NewtonOptions(max_iter=20, stall_iter=5, reuse_factor=False, **options))
    return model, solver.load_step(model.initial_state(), 0.3 * RM.MU, 0.0)


def test_a_stall_above_the_tolerance_is_a_divergence_without_stall_tol():
    with pytest.raises(Diverged, match="residual stalls"):
        _solve(tol=UNREACHABLE)


def test_a_stall_below_stall_tol_is_accepted_and_shows_its_floor():
    model, (x, record) = _solve(tol=UNREACHABLE, stall_tol=1e-10)
    assert record.converged
    assert UNREACHABLE < record.residuals[-1] <= 1e-10
    assert record.iterations >= 4  # three iterations without halving
    _, (reference, _) = _solve(tol=1e-10)
    u = slice(0, model.n_u)
    assert np.linalg.norm(x[u] - reference[u]) <= 1e-9 * np.linalg.norm(reference[u])


def test_a_stall_above_stall_tol_is_still_a_divergence():
    with pytest.raises(Diverged, match="residual stalls"):
        _solve(tol=UNREACHABLE, stall_tol=1e-30)
