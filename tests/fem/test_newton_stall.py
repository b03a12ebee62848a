"""A residual that stalls below `NewtonOptions.stall_tol` is accepted as converged, and only then;
one that makes no new lowest residual in three iterations after `progress_iter` is given up
(`fem.newton_progress`: "Stalled residuals", "No new lowest residual").

The stall is made with a tolerance below round-off (1e-17): the residual of the pressurised tube
settles at its floor (~1e-15 relative) and stops shrinking. That is the same situation as a
contact whose points flip on a kink, without the contact."""

import re

import numpy as np
import pytest

from softcrawl.fem import reference_models as RM
from softcrawl.fem.newton import Diverged, NewtonOptions, NewtonSolver
from softcrawl.fem.newton_progress import divergence

UNREACHABLE = 1e-17


def _solve(**options):
    model = RM.tube_model(3.0, 9.0, n_radial=3, n_angle=4)
    settings = {"max_iter": 20, "stall_iter": 5, "reuse_factor": False} | options
    solver = NewtonSolver(model, NewtonOptions(**settings))
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


def test_progress_iter_gives_up_a_floor_sooner_than_the_stall_test_and_names_why():
    with pytest.raises(Diverged, match="residual stalls") as slow:
        _solve(tol=UNREACHABLE, stall_iter=19)
    with pytest.raises(Diverged, match="no new lowest residual in three iterations") as fast:
        _solve(tol=UNREACHABLE, stall_iter=19, progress_iter=3)
    after = [int(re.search(r"after (\d+)", str(e.value)).group(1)) for e in (slow, fast)]
    assert after[1] < after[0]


def test_progress_iter_leaves_a_converging_solve_and_an_accepted_floor_alone():
    _, (x, record) = _solve(tol=1e-10)
    _, (y, same) = _solve(tol=1e-10, progress_iter=3)
    assert same.residuals == record.residuals and np.array_equal(x, y)
    _, (_, floor) = _solve(tol=UNREACHABLE, stall_tol=1e-10, progress_iter=3)
    assert floor.converged


#: Histories measured on the FE-body crawl's first cycle (docs/decisions/090-newton-progress.md):
#: an attempt at the retraction's slip onset that the stall test gave up after 12 iterations, and
#: the slowest attempt that converged (13 iterations), whose residual bumps once on its way down.
GIVEN_UP = (0.9985, 0.0899, 0.3591, 0.3897, 0.2099, 0.3092, 0.2797, 0.2408, 0.2457, 0.2316, 0.1427)
SLOW = (0.1443, 0.1345, 0.1291, 0.1249, 0.1207, 0.1160, 0.1224, 0.1172, 0.1050, 0.0965, 0.0586, 1.2e-3)


def test_the_rule_on_measured_histories():
    def first(history, progress_iter):
        for k in range(1, len(history) + 1):
            if divergence(history[:k], 12, progress_iter) is not None:
                return k - 1
        return None

    assert first(GIVEN_UP, 4) == 4  # three iterations above the first one's 0.0899
    assert first(GIVEN_UP, None) is None  # the stall test alone waits for its 12th iteration
    assert first(SLOW, 4) is None
    assert first(SLOW[:8] + (0.1180,) + SLOW[9:], 4) == 8  # one more bump and it is given up
