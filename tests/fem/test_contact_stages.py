"""The augmented-Lagrangian loop of `fem.contact_stages` when a Uzawa re-solve diverges."""

from types import SimpleNamespace

import numpy as np
import pytest

from softcrawl.fem import contact_stages as cs
from softcrawl.fem.newton import Diverged, NewtonRecord


class _Term:
    """A contact term whose penetration is 1 / (1 + number of solves) and whose Uzawa update
    moves the multiplier towards 1."""

    def __init__(self):
        self.multiplier = np.zeros(1)
        self.committed = None

    def augment(self, x, relax=1.0):
        self.multiplier = self.multiplier + relax * (1.0 - self.multiplier)
        return float(x[1])


class _Solver:
    """Converges while the multiplier's relaxed step is small enough, diverges otherwise."""

    def __init__(self, term, limit):
        self.term, self.limit, self.calls = term, limit, []

    def load_step(self, x, P, f):
        self.calls.append(float(self.term.multiplier[0]))
        if self.term.multiplier[0] > self.limit:
            raise Diverged("residual stalls")
        n = len(self.calls)
        return np.array([float(self.term.multiplier[0]), 1.0 / (1 + n)]), NewtonRecord((1.0, 1e-9), True)


def _model(term):
    model = SimpleNamespace(contacts=[term])
    model.commit = lambda x: setattr(term, "committed", x.copy())
    return model


def test_a_diverged_uzawa_resolve_keeps_the_last_converged_solve_and_its_multipliers():
    term = _Term()
    solver = _Solver(term, limit=0.25)  # lambda above 0.25 diverges
    x, its, res, pen = cs._solve_augmented(solver, _model(term), np.zeros(2), 0.0, 1.0, 1e-6, 4)
    # first solve at lambda = 0; the updates w = 1, 1/2 diverge, 1/4 converges (lambda = 1/4);
    # from there w = 1/4, 1/8, 1/16 diverge (MAX_RELAXATIONS + 1 failures): the loop stops
    assert cs.MAX_RELAXATIONS == 2
    assert solver.calls == [0.0, 1.0, 0.5, 0.25, 0.4375, 0.34375, 0.296875]
    assert len(its) == 2  # two converged solves
    assert x[0] == 0.25 and term.multiplier[0] == 0.25  # in equilibrium with its own multipliers
    assert np.array_equal(term.committed, x)  # the history is committed once, from that state
    assert pen == x[1] > 1e-6  # the penetration above tol is returned, not hidden


def test_converging_resolves_take_full_updates():
    term = _Term()
    solver = _Solver(term, limit=2.0)
    x, its, _, pen = cs._solve_augmented(solver, _model(term), np.zeros(2), 0.0, 1.0, 0.4, 4)
    assert solver.calls == [0.0, 1.0]  # one full update, then the penetration 1/3 < 0.4
    assert term.multiplier[0] == 1.0 and pen < 0.4 and len(its) == 2


class _GrindingSolver:
    """A Newton solver that converges only in sub-steps of at most `h_ok` of the stage, each solve
    taking `seconds`: the stage shrinks its sub-steps and grinds on."""

    def __init__(self, model, options, h_ok=1e-3, seconds=0.02):
        self.h_ok, self.seconds, self.iterations, self.assembly_s = h_ok, seconds, 0, 0.0
        self.linear = SimpleNamespace(seconds=0.0, factorizations=0)
        self.last = 0.0

    def load_step(self, x, P, f):
        import time

        time.sleep(self.seconds)
        if f - self.last > self.h_ok + 1e-15:
            raise Diverged("residual stalls")
        self.last = f
        return np.array([f]), NewtonRecord((1.0,) * 8 + (1e-9,), True)  # 8 iterations: no regrowth


def _grinding_model():
    model = SimpleNamespace(contacts=[], chambers=[])
    model.initial_state = lambda: np.zeros(1)
    model.commit = lambda x: None
    return model


def test_the_wall_time_budget_stops_a_grinding_stage_with_a_recorded_failure(monkeypatch):
    import time

    monkeypatch.setattr(cs, "NewtonSolver", _GrindingSolver)
    stage = cs.Stage("drag", factor=1.0, steps=1)
    t0 = time.perf_counter()
    res = cs.run_stages(_grinding_model(), [stage], max_cutbacks=50, max_wall_s=0.5)
    wall = time.perf_counter() - t0
    assert not res.converged
    assert "max_wall_s = 0.5 s" in res.message and "'drag'" in res.message
    assert 0.5 <= wall < 0.75  # stops within one solve attempt (0.02 s) of the budget
    assert res.steps and res.steps[-1].factor < 1.0  # the converged sub-steps are kept
    unlimited = cs.run_stages(_grinding_model(), [cs.Stage("drag", factor=0.01, steps=1)], max_cutbacks=50)
    assert unlimited.converged  # without a budget the same stage finishes (10 sub-steps of 1e-3)


@pytest.mark.parametrize("budget", [0.0, -1.0, float("nan")])
def test_a_non_positive_budget_names_the_parameter(budget):
    from softcrawl.fem.errors import SolverInputError

    with pytest.raises(SolverInputError, match="max_wall_s"):
        cs.run_stages(_grinding_model(), [cs.Stage("drag", factor=1.0)], max_wall_s=budget)


def test_the_minimum_sub_step_stops_a_grinding_stage(monkeypatch):
    monkeypatch.setattr(cs, "NewtonSolver", lambda m, o: _GrindingSolver(m, o, h_ok=1e-3, seconds=0.0))
    res = cs.run_stages(
        _grinding_model(), [cs.Stage("drag", factor=1.0, steps=2)], max_cutbacks=50, min_step_fraction=1e-2
    )
    # sub-steps of 1e-3 converge but the stage's step is 1/2: 1e-3 < 1e-2 / 2, so it stops at the start
    assert not res.converged and "min_step_fraction = 0.01" in res.message and not res.steps
    res = cs.run_stages(
        _grinding_model(), [cs.Stage("drag", factor=0.01, steps=2)], max_cutbacks=50, min_step_fraction=0.1
    )
    assert res.converged  # it converges in sub-steps of 1/16 (factor 6.25e-4), above 0.1 / 2 of the stage


class _CreepingSolver(_GrindingSolver):
    """Converges freely up to half the stage, then only in increments of at most 1e-18, below the
    floating-point resolution of the stage parameter there (1.1e-16 at 0.5)."""

    def load_step(self, x, P, f):
        if f > 0.5 and f - self.last > 1e-18:
            raise Diverged("residual stalls")
        self.last = f
        return np.array([f]), NewtonRecord((1.0,) * 8 + (1e-9,), True)


def test_sub_steps_below_the_parameters_resolution_stop_with_a_recorded_failure(monkeypatch):
    """A stage whose sub-steps shrink until t + h == t cannot advance: it stops with a message,
    not a ZeroDivisionError in the next predictor (which is what it raised before, found by the
    one-body insertion of record 076)."""
    monkeypatch.setattr(cs, "NewtonSolver", lambda m, o: _CreepingSolver(m, o, seconds=0.0))
    res = cs.run_stages(_grinding_model(), [cs.Stage("insert", factor=1.0, steps=2)], max_cutbacks=80)
    assert not res.converged
    assert "floating-point resolution" in res.message and "'insert'" in res.message
    assert [s.factor for s in res.steps] == [0.5]  # the converged half is kept


class _RecordingSolver:
    """Converges at once and records the load factor of every solve."""

    def __init__(self, model, options):
        self.factors, self.iterations, self.assembly_s = [], 0, 0.0
        self.linear = SimpleNamespace(seconds=0.0, factorizations=0)
        _RecordingSolver.last = self

    def load_step(self, x, P, f):
        self.factors.append(float(f))
        return x, NewtonRecord((1.0, 1e-9), True)


@pytest.mark.parametrize("factor0", [0.0, 1.0])
def test_stages_that_keep_the_factor_keep_the_start_factor(monkeypatch, factor0):
    """A body already under its weight (factor0 = 1) keeps it through stages that move only the
    pressures (factor None); from the default start the factor stays 0, and a stage that sets one
    moves it linearly from factor0."""
    monkeypatch.setattr(cs, "NewtonSolver", _RecordingSolver)
    stages = [cs.Stage("inflate", pressure=0.01, steps=2), cs.Stage("weight", factor=0.5, steps=2)]
    res = cs.run_stages(_grinding_model(), stages, factor0=factor0)
    assert res.converged
    half = factor0 + 0.5 * (0.5 - factor0)
    assert _RecordingSolver.last.factors == pytest.approx([factor0, factor0, half, 0.5])
    assert [s.factor for s in res.steps] == pytest.approx([factor0, factor0, half, 0.5])
