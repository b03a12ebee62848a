"""`run_stages` (fem.contact_stages) driven with a scripted Newton solver and a stub contact term, no
FE solve: the loads interpolated linearly between the stages' ends, the surfaces, friction and
drive set at the documented moments, the secant predictor, the cut-back and regrowth of sub-steps,
the contact history restored after a diverged sub-step, the wall-time and sub-step guards, the
recorded steps and result (cursors, resuming and bad inputs: test_contact_stages_cursor.py)."""

from types import SimpleNamespace

import numpy as np
import pytest

from softcrawl.fem import contact_stages as cs
from softcrawl.fem.newton import Diverged, NewtonOptions, NewtonRecord


class _Term:
    """A contact term's history (multipliers, stick points, surface, mu) and a log of its calls."""

    def __init__(self, penetration=0.0):
        self.multiplier, self.stick = np.zeros(2), np.zeros(2)
        self.surface, self.mu, self.penetration, self.log = "s0", 0.0, penetration, []

    def set_surface(self, surface):
        self.surface = surface
        self.log.append(("surface", surface))

    def set_time_step(self, dt):  # viscous slip's sub-step time (not logged: every sub-step sets it)
        self.time_step = dt

    def set_friction(self, mu, x):
        self.mu, self.stick = mu, np.array(x[:2], dtype=float)
        self.log.append(("friction", mu, np.array(x)))

    def augment(self, x, relax=1.0):
        self.multiplier = self.multiplier + relax
        self.log.append(("augment", relax))
        return self.penetration


class _Solver:
    """A Newton solver whose converged state is x(f, P) = (f, P[0], 10 f) whatever the guess; it takes
    `iterations` iterations, diverges where `diverge(f, attempt)` says so (first corrupting the contact
    history in place, which the stage must restore) and records every call."""

    def __init__(self, model, options, iterations=2, diverge=None):
        self.model, self.options, self.n, self.diverge = model, options, iterations, diverge
        self.iterations, self.assembly_s, self.linear = 0, 0.0, SimpleNamespace(seconds=0.0, factorizations=0)
        self.calls = []

    def load_step(self, x, P, f):
        term = self.model.contacts[0] if self.model.contacts else None
        self.calls.append(SimpleNamespace(x=np.array(x), P=np.array(P), f=f, surface=term and term.surface))
        if self.diverge is not None and self.diverge(f, len(self.calls)):
            if term is not None:
                term.multiplier += 5.0
                term.stick += 7.0
            raise Diverged("scripted")
        self.iterations += self.n
        self.assembly_s += 0.25
        self.linear.seconds += 0.5
        self.linear.factorizations += 1  # one per load step here
        residuals = (1.0,) + (1e-3,) * (self.n - 1) + (1e-10,)
        return np.array([f, P[0], 10.0 * f]), NewtonRecord(residuals, True)


def _model(chambers=1, term=None):
    model = SimpleNamespace(contacts=[] if term is None else [term], chambers=[None] * chambers)
    model.initial_state = lambda: np.zeros(3)
    model.commits = []
    model.commit = lambda x: model.commits.append(np.array(x))
    return model


def _run(monkeypatch, model, stages, iterations=2, diverge=None, **kw):
    made = []

    def factory(m, o):
        made.append(_Solver(m, o, iterations, diverge))
        return made[-1]

    monkeypatch.setattr(cs, "NewtonSolver", factory)
    res = cs.run_stages(model, stages, **kw)
    return res, made[0]


def test_loads_move_linearly_from_each_stage_start_to_its_end(monkeypatch):
    stages = [
        cs.Stage("a", pressure=0.2, factor=1.0, steps=2),
        cs.Stage("b", pressure=(0.4, 0.1)),  # factor None keeps 1
        cs.Stage("c", factor=0.5, steps=2),  # pressure None keeps (0.4, 0.1)
    ]
    res, solver = _run(monkeypatch, _model(chambers=2), stages)
    assert res.converged and res.message == "all stages reached"
    got = [(c.P.tolist(), c.f) for c in solver.calls]
    assert got == [
        ([0.1, 0.1], 0.5),
        ([0.2, 0.2], 1.0),
        ([0.4, 0.1], 1.0),
        ([0.4, 0.1], 0.75),
        ([0.4, 0.1], 0.5),
    ]
    assert [(st.stage, st.s) for st in res.steps] == [
        ("a", 0.5),
        ("a", 1.0),
        ("b", 1.0),
        ("c", 0.5),
        ("c", 1.0),
    ]
    last = res.steps[-1]
    assert last.pressure.tolist() == [0.4, 0.1] and last.factor == 0.5
    assert np.array_equal(last.x, [0.5, 0.4, 5.0]) and np.array_equal(res.x, last.x)
    assert last.iterations == (2,) and last.residuals == (1.0, 1e-3, 1e-10) and last.penetration == 0.0
    # the result carries the solver's effort and the last state
    assert (res.newton_iterations, res.assembly_s, res.solve_s) == (10, 1.25, 2.5)
    assert np.array_equal(res.end_x, last.x) and 0.0 <= res.wall_s < 5.0


def test_a_model_without_chambers_has_one_zero_pressure(monkeypatch):
    res, solver = _run(monkeypatch, _model(chambers=0), [cs.Stage("a", factor=2.0)])
    assert solver.calls[0].P.tolist() == [0.0] and solver.calls[0].f == 2.0
    assert res.steps[0].pressure.tolist() == [0.0]


def test_the_options_and_the_start_state_reach_the_solver(monkeypatch):
    opt = NewtonOptions(max_iter=7)
    _, solver = _run(
        monkeypatch, _model(), [cs.Stage("a", factor=1.0)], options=opt, x0=np.array([1.0, 2, 3])
    )
    assert solver.options is opt and solver.calls[0].x.tolist() == [1.0, 2.0, 3.0]
    _, solver = _run(monkeypatch, _model(), [cs.Stage("a", factor=1.0)])
    assert solver.options == NewtonOptions() and solver.calls[0].x.tolist() == [0.0, 0.0, 0.0]


def test_each_sub_step_starts_from_the_secant_prediction_within_its_stage(monkeypatch):
    stages = [cs.Stage("a", factor=1.0, steps=4), cs.Stage("b", factor=2.0, steps=2)]
    _, solver = _run(monkeypatch, _model(), stages)
    guesses = [c.x.tolist() for c in solver.calls]
    # stage a: x(f) = (f, 0, 10 f) is linear, so from the second sub-step on the secant is exact
    assert guesses[0] == [0.0, 0.0, 0.0]
    # after the first sub-step the previous state is the start (t = 0): x + (x - x0) h / t
    assert np.allclose(guesses[1], [0.5, 0.0, 5.0]) and np.allclose(guesses[3], [1.0, 0.0, 10.0])
    # stage b starts from the last state, not from a secant through stage a's states
    assert guesses[4] == [1.0, 0.0, 10.0]
    assert np.allclose(guesses[5], [2.0, 0.0, 20.0])


def test_the_secant_uses_the_sub_step_ratio(monkeypatch):
    """After a cut-back the step h differs from the last one: the prediction is scaled by h / dt."""
    diverge = lambda f, n: n == 2  # noqa: E731 (the second attempt, at f = 1.0, diverges)
    _, solver = _run(monkeypatch, _model(), [cs.Stage("a", factor=2.0, steps=2)], diverge=diverge)
    f = [c.f for c in solver.calls]
    assert f == [1.0, 2.0, 1.5, 2.0]
    # third call: prev = (0, x0), x at t = 0.5, h = 0.25: x + (x - x0) * 0.25 / 0.5
    assert np.allclose(solver.calls[2].x, [1.5, 0.0, 15.0])
    assert np.allclose(solver.calls[3].x, [2.0, 0.0, 20.0])


@pytest.mark.parametrize("iterations, calls", [(6, 3), (7, 4)])
def test_easy_sub_steps_grow_back_to_the_stage_step_and_no_further(monkeypatch, iterations, calls):
    diverge = lambda f, n: n == 1  # noqa: E731 (the first attempt, h = 1/2, is cut to 1/4)
    _, solver = _run(
        monkeypatch, _model(), [cs.Stage("a", factor=1.0, steps=2)], iterations=iterations, diverge=diverge
    )
    f = [c.f for c in solver.calls]
    if iterations <= 6:  # doubled back to 1/2 after the easy sub-step, never to 1
        assert f == [0.5, 0.25, 0.75, 1.0][: calls + 1]
        assert len(f) == 4
    else:  # a hard sub-step keeps h
        assert f == [0.5, 0.25, 0.5, 0.75, 1.0]


def test_surfaces_drive_and_friction_are_set_where_the_docstring_says(monkeypatch):
    term = _Term()
    seen = []
    stages = [
        cs.Stage("shrink", factor=1.0, steps=2, surfaces={0: lambda s: f"wall {s}"}, drive=seen.append),
        cs.Stage("stick", friction={0: 0.3}, steps=2),
    ]
    res, solver = _run(monkeypatch, _model(term=term), stages)
    assert res.converged
    # the surface at s is in place when the solve at s runs; the drive is called with s first
    assert [c.surface for c in solver.calls] == ["wall 0.5", "wall 1.0", "wall 1.0", "wall 1.0"]
    assert seen == [0.5, 1.0]
    frictions = [e for e in term.log if e[0] == "friction"]
    assert len(frictions) == 1 and frictions[0][1] == 0.3  # once, at the stage's start
    assert np.array_equal(frictions[0][2], [1.0, 0.0, 10.0])  # with the state the stage starts from
    assert len(res.steps) == 4 and len(_model_commits(solver)) == 4


def _model_commits(solver):
    return solver.model.commits


def test_a_diverged_sub_step_restores_the_contact_history_and_halves(monkeypatch):
    term = _Term()
    term.multiplier, term.stick = np.array([1.0, 2.0]), np.array([3.0, 4.0])
    stages = [cs.Stage("shrink", factor=1.0, surfaces={0: lambda s: f"wall {s}"})]
    res, solver = _run(monkeypatch, _model(term=term), stages, diverge=lambda f, n: True, max_cutbacks=2)
    assert res.converged is False and not res.steps
    assert [c.f for c in solver.calls] == [1.0, 0.5, 0.25]  # max_cutbacks = 2 halvings, then it stops
    assert res.message == "stage 'shrink' diverged (scripted); last converged: the start"
    # the solver corrupted the history in place before each failure: restored each time
    assert term.multiplier.tolist() == [1.0, 2.0] and term.stick.tolist() == [3.0, 4.0]
    assert term.surface == "s0"
    assert np.array_equal(res.x, np.zeros(3))  # no step: the last state is the start


def test_cut_backs_count_in_a_row_only(monkeypatch):
    """The first and third attempts diverge: with max_cutbacks = 1 the stage finishes (the count
    restarts after each converged sub-step)."""
    res, solver = _run(
        monkeypatch,
        _model(),
        [cs.Stage("a", factor=1.0, steps=2)],
        diverge=lambda f, n: n in (1, 3),
        max_cutbacks=1,
    )
    assert res.converged, res.message
    assert [c.f for c in solver.calls] == [0.5, 0.25, 0.75, 0.5, 1.0]


def test_the_failure_message_names_the_last_converged_sub_step(monkeypatch):
    res, _ = _run(
        monkeypatch,
        _model(),
        [cs.Stage("a", factor=1.0, steps=2), cs.Stage("b", factor=2.0)],
        diverge=lambda f, n: f > 1.0,
        max_cutbacks=0,
    )
    assert res.message == "stage 'b' diverged (scripted); last converged: stage 'a' at s = 1"
    assert len(res.steps) == 2 and res.steps[-1].stage == "a"


def test_min_step_fraction_boundary(monkeypatch):
    """A halved sub-step of exactly min_step_fraction / steps is still tried; below it the stage stops."""
    res, solver = _run(
        monkeypatch,
        _model(),
        [cs.Stage("a", factor=1.0, steps=2)],
        diverge=lambda f, n: n <= 2,
        min_step_fraction=0.5,
        max_cutbacks=9,
    )
    # h = 1/2 diverges, 1/4 = 0.5 / 2 is tried (it diverges too), 1/8 < 1/4 stops
    assert [c.f for c in solver.calls] == [0.5, 0.25]
    assert res.converged is False
    assert res.message == (
        "stage 'a' diverged (scripted) with sub-steps below min_step_fraction = 0.5 of its step; "
        "last converged: the start"
    )


def test_the_defaults_six_cut_backs_four_updates_and_1e_3_mm(monkeypatch):
    # six halvings after the first attempt, then the stage gives up
    res, solver = _run(monkeypatch, _model(), [cs.Stage("a", factor=1.0)], diverge=lambda f, n: True)
    assert len(solver.calls) == 7 and not res.converged
    # four Uzawa updates (five solves) while the penetration stays above the default 1e-3 mm
    term = _Term(penetration=1.0000001e-3)
    res, solver = _run(monkeypatch, _model(term=term), [cs.Stage("a", factor=1.0)])
    assert res.steps[0].iterations == (2,) * 5 and res.steps[0].penetration == 1.0000001e-3
    term = _Term(penetration=1e-3)  # at the tolerance: no update
    res, solver = _run(monkeypatch, _model(term=term), [cs.Stage("a", factor=1.0)])
    assert res.steps[0].iterations == (2,)


def test_on_step_receives_every_converged_sub_step(monkeypatch):
    seen = []
    res, _ = _run(monkeypatch, _model(), [cs.Stage("a", factor=1.0, steps=3)], on_step=seen.append)
    assert seen == list(res.steps) and len(seen) == 3


def test_sub_steps_grow_back_by_doubling_after_two_cut_backs(monkeypatch):
    _, solver = _run(monkeypatch, _model(), [cs.Stage("a", factor=1.0)], diverge=lambda f, n: n in (1, 2))
    assert [c.f for c in solver.calls] == [1.0, 0.5, 0.25, 0.75, 1.0]  # 1/4, then 1/2, then the rest


def test_the_wall_time_budget_is_a_recorded_failure(monkeypatch):
    clock = iter([0.0, 10.0, 10.0, 10.0])
    monkeypatch.setattr(cs.time, "perf_counter", lambda: next(clock))
    res, solver = _run(monkeypatch, _model(), [cs.Stage("a", factor=1.0, steps=2)], max_wall_s=5.0)
    assert res.converged is False and not solver.calls
    assert res.message == (
        "stage 'a' stopped at the wall-time budget max_wall_s = 5 s (trying s = 0.5 in sub-steps of 0.5); "
        "last converged: the start"
    )
    assert res.wall_s == 10.0


def test_the_budget_is_exceeded_only_past_it(monkeypatch):
    clock = iter([0.0] + [5.0] * 20)
    monkeypatch.setattr(cs.time, "perf_counter", lambda: next(clock))
    res, solver = _run(monkeypatch, _model(), [cs.Stage("a", factor=1.0, steps=2)], max_wall_s=5.0)
    assert res.converged and len(solver.calls) == 2  # 5 s spent of a 5 s budget: not stopped
