"""Viscous stabilisation (`fem.stabilisation`, docs/decisions/094-backward-snap.md): the lumped
volumes against the body's volume, a free block's gradient flow under a dead load against its
closed form (where the static problem has no solution), a path that ends where the static
one does once c reaches 0, and bad input."""

import numpy as np
import pytest

from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.stabilisation import Stabilisation
from softcrawl.fem.structured import box

LAW = NeoHookean(mu=1.0, bulk=10.0)


def _block(size=(2.0, 1.0, 1.0), **kw):
    return SolidModel(box(size, (2, 2, 2)), LAW, formulation="p2", extra_terms=[Stabilisation()], **kw)


def _term(model) -> Stabilisation:
    return next(t for t in model.terms if isinstance(t, Stabilisation))


def test_the_lumped_volumes_sum_to_the_body_volume():
    term = _term(_block())
    assert term.volume.sum() == pytest.approx(2.0, rel=1e-12)
    assert np.all(term.volume > 0)


@pytest.mark.parametrize("steps", [1, 4])
def test_a_free_block_under_a_dead_load_flows_with_its_volume_weighted_mean(steps):
    """No constraint, a force F on x1, c on over a stage of duration T: the internal forces sum to
    zero, so each sub-step balances sum_i c V_i du_i / dt = F, and the volume-weighted mean
    displacement is exactly F T / (c V) along x and 0 across, in any number of sub-steps (the
    static problem has no solution: F unbalanced)."""
    F, c, T = 0.3, 2.0, 0.5
    model = _block(dead_loads={"x1": (F, 0.0, 0.0)})
    term = _term(model)
    term.set_coefficient(c)
    res = run_stages(model, [Stage("push", factor=1.0, steps=steps, duration=T)], factor0=1.0)
    assert res.converged, res.message
    assert len(res.steps) == steps
    mean = (term.volume * res.x[term.dofs]).sum(axis=1) / term.volume.sum()
    assert mean[0] == pytest.approx(F * T / (c * 2.0), rel=1e-9)
    assert np.abs(mean[1:]).max() < 1e-9 * mean[0]
    assert term.force == pytest.approx([-F, 0.0, 0.0], abs=1e-9 * F)  # the last sub-step's resultant
    static = SolidModel(
        box((2.0, 1.0, 1.0), (2, 2, 2)), LAW, formulation="p2", dead_loads={"x1": (F, 0.0, 0.0)}
    )
    assert not run_stages(static, [Stage("push", factor=1.0, steps=steps)], factor0=1.0).converged


def test_without_a_time_step_the_term_adds_nothing():
    """A pseudo-time stage without a duration: the path is the static one, bit for bit."""
    stretch = [Dirichlet.fixed("x0"), Dirichlet.prescribed("x1", 0, 0.4)]
    static = SolidModel(box((2.0, 1.0, 1.0), (2, 2, 2)), LAW, formulation="p2", dirichlet=stretch)
    reference = run_stages(static, [Stage("pull", factor=1.0, steps=2)])
    model = _block(dirichlet=stretch)
    _term(model).set_coefficient(1.0)
    res = run_stages(model, [Stage("pull", factor=1.0, steps=2)])
    assert np.array_equal(res.x, reference.x)


def test_a_stabilised_path_ends_at_the_static_state_once_c_is_zero():
    """A block held on x0 and stretched 20 % on x1: on with c = 1 it lags (an artificial force),
    then a stage takes c to 0: the end state is the unstabilised solution to the solver's
    tolerance, as it must be for a hyperelastic body (path-independent)."""
    stretch = [Dirichlet.fixed("x0"), Dirichlet.prescribed("x1", 0, 0.4)]
    static = SolidModel(box((2.0, 1.0, 1.0), (2, 2, 2)), LAW, formulation="p2", dirichlet=stretch)
    reference = run_stages(static, [Stage("pull", factor=1.0, steps=4)])
    model = _block(dirichlet=stretch)
    term = _term(model)
    term.rest(model.initial_state())

    def on(s):
        term.set_coefficient(1.0)

    def off(s):
        term.set_coefficient(1.0 - s)

    stages = [
        Stage("pull", factor=1.0, steps=2, drive=on, duration=1.0),
        Stage("settle", steps=4, drive=off, duration=1.0),
    ]
    res = run_stages(model, stages)
    assert res.converged, res.message
    lagging = next(s for s in res.steps if s.stage == "pull")
    assert np.abs(lagging.x - reference.x).max() > 1e-4  # the stabilised path is another path
    assert np.abs(res.x - reference.x).max() < 1e-8
    assert term.coefficient == 0.0 and np.all(term.force == 0.0)


@pytest.mark.parametrize("c", [-1.0, float("nan"), float("inf")])
def test_a_bad_coefficient_names_its_parameter(c):
    term = _term(_block())
    with pytest.raises(SolverInputError, match="stabilisation.coefficient"):
        term.set_coefficient(c)


def test_at_c_zero_the_model_is_the_one_without_the_term_bit_for_bit():
    """A term switched off (c = 0, with or without a time step) changes neither the residual nor
    the tangent's values or pattern, so runs where it is off (the flipped feet inside the wall,
    record 094) are the runs from before, to the last bit."""
    stretch = [Dirichlet.fixed("x0"), Dirichlet.prescribed("x1", 0, 0.4)]
    plain = SolidModel(box((2.0, 1.0, 1.0), (2, 2, 2)), LAW, formulation="p2", dirichlet=stretch)
    model = _block(dirichlet=stretch)
    x = plain.initial_state() + 1e-2 * np.sin(np.arange(plain.n_dofs))
    R0, K0 = plain.residual_and_tangent(x, np.zeros(1), 1.0)
    for dt in (None, 0.25):
        _term(model).set_time_step(dt)
        R, K = model.residual_and_tangent(x, np.zeros(1), 1.0)
        assert np.array_equal(R, R0)
        assert np.array_equal(K.indptr, K0.indptr) and np.array_equal(K.indices, K0.indices)
        assert np.array_equal(K.data, K0.data)
