"""`run_stages` resumed from a `Cursor` (fem.contact_stages, "Resuming"): a block pressed on a plane
with friction, pulled past mu N and released, stopped after any converged sub-step and continued
in a fresh model with the contact history put back, ends in the state of the uninterrupted run,
bit for bit; the stage it resumes in does not set its friction again (that resets the stick points)."""

import numpy as np
import pytest

from softcrawl.fem.contact_stages import Stage, run_stages
from tests.fem.test_axial_link import _pulled_block

MU, N, K = 0.3, 0.04, 1e-4


def _stages(pull):
    slide, hold = 1.02 * MU * N, 0.5 * MU * N
    return [
        Stage("press", factor=1.0, steps=2),
        # friction set where the pull begins: a resumed pull must not reset the stick points
        Stage("pull", friction={0: MU}, drive=lambda s: pull.set_load(K, s * slide), steps=4),
        Stage("release", drive=lambda s: pull.set_load(K, slide + s * (hold - slide)), steps=2),
    ]


def _history(model, pull):
    c = model.contacts[0]
    return c.multiplier.copy(), c.stick.copy(), c.mu, c.surface, (pull.stiffness, pull.preload, pull.rest)


def _put_back(model, pull, saved):
    c = model.contacts[0]
    c.multiplier, c.stick, c.mu, c.surface = saved[0].copy(), saved[1].copy(), saved[2], saved[3]
    pull.set_load(*saved[4])


def test_a_run_resumed_after_any_sub_step_ends_where_the_uninterrupted_run_ends():
    model, pull = _pulled_block(N, K)
    cursors = []
    full = run_stages(
        model,
        _stages(pull),
        penetration_tol=1e-8,
        on_cursor=lambda c: cursors.append((c, _history(model, pull))),
    )
    assert full.converged, full.message
    stages = [c.stage for c, _ in cursors]
    assert stages == sorted(stages) and set(stages) == {0, 1, 2}  # the pull is cut back: more than 4
    assert full.newton_iterations == cursors[-1][0].newton_iterations
    for k, (cursor, saved) in enumerate(cursors):
        fresh, fresh_pull = _pulled_block(N, K)
        _put_back(fresh, fresh_pull, saved)
        res = run_stages(fresh, _stages(fresh_pull), penetration_tol=1e-8, start=cursor)
        assert res.converged, res.message
        assert len(res.steps) == len(cursors) - 1 - k  # only the sub-steps after the cursor
        assert np.array_equal(res.x, full.x), f"resumed after sub-step {k}"
        assert np.array_equal(fresh.contacts[0].stick, model.contacts[0].stick)


def test_setting_friction_again_on_the_resumed_stage_would_change_the_result():
    """The check above has teeth: resumed mid-pull (the block still sticking) with the friction set
    again, i.e. the stick points reset to the current positions, the next state moves by 1e-5 mm
    (0.2 % of its largest displacement; 1.0e-5 mm seen) instead of 0."""
    model, pull = _pulled_block(N, K)
    cursors, steps = [], []
    run_stages(
        model,
        _stages(pull),
        penetration_tol=1e-8,
        on_step=steps.append,
        on_cursor=lambda c: cursors.append((c, _history(model, pull))),
    )
    k, (cursor, saved) = next((k, cs) for k, cs in enumerate(cursors) if cs[0].stage == 1 and cs[0].t == 0.5)
    fresh, fresh_pull = _pulled_block(N, K)
    _put_back(fresh, fresh_pull, saved)
    fresh.contacts[0].set_friction(MU, cursor.x)
    res = run_stages(fresh, _stages(fresh_pull), penetration_tol=1e-8, start=cursor)
    assert np.abs(res.steps[0].x - steps[k + 1].x).max() > 1e-6


def test_a_cursor_at_the_end_of_the_last_stage_returns_its_state_without_a_step():
    model, pull = _pulled_block(N, K)
    cursors = []
    full = run_stages(model, _stages(pull), penetration_tol=1e-8, on_cursor=lambda c: cursors.append(c))
    res = run_stages(model, _stages(pull), penetration_tol=1e-8, start=cursors[-1])
    assert res.converged and res.steps == () and np.array_equal(res.x, full.x)


def test_a_cursor_past_the_stages_is_refused():
    from dataclasses import replace

    from softcrawl.fem.errors import SolverInputError

    model, pull = _pulled_block(N, K)
    cursors = []
    run_stages(model, _stages(pull)[:1], penetration_tol=1e-8, on_cursor=cursors.append)
    with pytest.raises(SolverInputError, match="start"):
        run_stages(model, _stages(pull), start=replace(cursors[-1], stage=5))
