"""`fem.contact_stages` with a scripted Newton solver, no FE solve (the fakes of
test_contact_stages_driver.py): cursors and resumed stages, the augmented-Lagrangian loop's stops,
the result without steps, and each bad input one error naming its parameter with its detail."""

import numpy as np
import pytest

from softcrawl.fem import contact_stages as cs
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.newton import NewtonRecord
from tests.fem.test_contact_stages_driver import _model, _run, _Solver, _Term


def _cursor(**fields) -> cs.Cursor:
    """A cursor half way through stage 0 (no secant, no counts), with `fields` replaced."""
    default = dict(stage=0, t=0.5, h=0.5, x=np.zeros(3), prev_t=None, prev_x=None, f0=0.0, f=0.5)
    default |= dict(P0=np.array([0.0]), P=np.array([0.0]), newton_iterations=0, assembly_s=0.0, solve_s=0.0)
    return cs.Cursor(**(default | fields))


def test_cursors_say_where_the_run_stands(monkeypatch):
    cursors = []
    stages = [cs.Stage("a", pressure=0.2, factor=1.0, steps=2), cs.Stage("b", factor=3.0, steps=2)]
    res, solver = _run(monkeypatch, _model(), stages, on_cursor=cursors.append)
    assert [(c.stage, c.t, c.h) for c in cursors] == [
        (0, 0.5, 0.5),
        (0, 1.0, 0.5),
        (1, 0.5, 0.5),
        (1, 1.0, 0.5),
    ]
    c = cursors[2]
    assert (
        np.array_equal(c.x, res.steps[2].x) and c.prev_t == 0.0 and np.array_equal(c.prev_x, res.steps[1].x)
    )
    assert c.P0.tolist() == [0.2] and c.f0 == 1.0 and c.P.tolist() == [0.2] and c.f == 2.0
    assert (c.newton_iterations, c.assembly_s, c.solve_s, c.factorizations) == (6, 0.75, 1.5, 3)
    assert res.factorizations == 4  # the solver's count reaches the result too
    assert cursors[0].prev_t == 0.0 and np.array_equal(cursors[0].prev_x, np.zeros(3))


def test_a_resumed_stage_continues_from_the_cursor_without_setting_friction(monkeypatch):
    term = _Term()
    stages = [
        cs.Stage("a", factor=1.0),
        cs.Stage("b", factor=3.0, friction={0: 0.4}, steps=4),
        cs.Stage("c", friction={0: 0.2}),
    ]
    start = _cursor(
        stage=1,
        h=0.25,
        x=np.array([2.0, 0.0, 20.0]),
        prev_t=0.25,
        prev_x=np.array([1.5, 0.0, 15.0]),
        f0=1.0,
        f=2.0,
    )
    res, solver = _run(monkeypatch, _model(term=term), stages, start=start, x0=np.full(3, 9.0))
    assert res.converged
    assert [c.f for c in solver.calls] == [2.5, 3.0, 3.0]  # stage a skipped; b from t = 0.5 with h = 0.25
    assert np.allclose(solver.calls[0].x, [2.5, 0.0, 25.0])  # the cursor's secant, not x0
    assert [e[1] for e in term.log if e[0] == "friction"] == [0.2]  # only stage c sets its friction


def test_a_resumed_run_that_fails_at_once_names_the_cursor(monkeypatch):
    start = _cursor()
    res, solver = _run(
        monkeypatch,
        _model(),
        [cs.Stage("a", factor=1.0)],
        start=start,
        diverge=lambda f, n: True,
        max_cutbacks=0,
    )
    assert solver.calls[0].f == 1.0 and solver.calls[0].x.tolist() == [0.0, 0.0, 0.0]
    assert res.message == "stage 'a' diverged (scripted); last converged: stage 'a' at s = 0.5"


@pytest.mark.parametrize("index", [-1, 2])
def test_a_cursor_outside_the_stages_is_refused(monkeypatch, index):
    monkeypatch.setattr(cs, "NewtonSolver", _Solver)
    start = _cursor(stage=index, t=0.0, h=1.0, P0=np.zeros(1), P=np.zeros(1), f=0.0)
    with pytest.raises(SolverInputError, match=f"stage {index} of a run of 2 stages"):
        cs.run_stages(_model(), [cs.Stage("a"), cs.Stage("b")], start=start)


@pytest.mark.parametrize(
    "kw, name",
    [
        ({"penetration_tol": 0.0}, "penetration_tol"),
        ({"min_step_fraction": 0.0}, "min_step_fraction"),
        ({"min_step_fraction": 1.0}, "min_step_fraction"),
        ({"min_step_fraction": float("nan")}, "min_step_fraction"),
    ],
)
def test_bad_run_inputs_name_the_parameter(kw, name):
    with pytest.raises(SolverInputError, match=name) as err:
        cs.run_stages(_model(), [cs.Stage("a")], **kw)
    assert err.value.parameter == name if hasattr(err.value, "parameter") else True


def test_a_stage_needs_a_sub_step():
    with pytest.raises(SolverInputError, match="stage.steps") as err:
        cs.Stage("press", steps=0)
    assert "press: needs at least one sub-step" in str(err.value)
    assert (
        cs.Stage("press").steps == 1
        and cs.Stage("press").pressure is None
        and cs.Stage("press").factor is None
    )


def test_a_result_without_steps_reports_its_end_state():
    res = cs.StagedResult((), True, "", 0.0, 0, 0.0, 0.0, np.ones(2))
    assert np.array_equal(res.x, np.ones(2))


def _augmented(term, solver_calls, penetrations, tol, max_augment):
    class Solver:
        def load_step(self, x, P, f):
            solver_calls.append(term.multiplier.copy())
            return x + 1.0, NewtonRecord((1.0, 1e-10), True)

    pens = iter(penetrations)
    term.augment = lambda x, relax=1.0: (setattr(term, "multiplier", term.multiplier + relax), next(pens))[1]
    model = _model(term=term)
    out = cs._solve_augmented(Solver(), model, np.zeros(3), np.zeros(1), 1.0, tol, max_augment)
    return out, model


def test_the_uzawa_loop_stops_at_the_tolerance_inclusive():
    term, calls = _Term(), []
    (x, its, res, pen), model = _augmented(term, calls, [2.0, 1.0], tol=1.0, max_augment=4)
    assert len(calls) == 2 and its == (1, 1) and pen == 1.0 and res == (1.0, 1e-10)
    assert term.multiplier.tolist() == [1.0, 1.0]  # the last update (no solve after it) is undone
    assert len(model.commits) == 1 and np.array_equal(model.commits[0], x)


def test_the_uzawa_loop_stops_after_max_augment_updates():
    term, calls = _Term(), []
    (x, its, _, pen), _ = _augmented(term, calls, [5.0] * 9, tol=1.0, max_augment=2)
    assert its == (1, 1, 1) and pen == 5.0 and x.tolist() == [3.0, 3.0, 3.0]
    assert term.multiplier.tolist() == [2.0, 2.0]
    term, calls = _Term(), []
    (_, its, _, _), _ = _augmented(term, calls, [5.0] * 9, tol=1.0, max_augment=0)
    assert its == (1,) and term.multiplier.tolist() == [0.0, 0.0]


def test_a_model_without_contacts_has_no_penetration():
    calls = []

    class Solver:
        def load_step(self, x, P, f):
            calls.append(f)
            return x, NewtonRecord((1.0, 1e-10), True)

    x, its, _, pen = cs._solve_augmented(Solver(), _model(), np.zeros(3), np.zeros(1), 1.0, 1e-3, 4)
    assert pen == 0.0 and its == (1,) and calls == [1.0]


@pytest.mark.parametrize(
    "kw, name, detail",
    [
        ({"penetration_tol": 0.0}, "penetration_tol", "must be positive (mm)"),
        ({"penetration_tol": -1e-3}, "penetration_tol", "must be positive (mm)"),
        ({"max_wall_s": 0.0}, "max_wall_s", "must be a positive time in s or None, got 0.0"),
        ({"min_step_fraction": 0.0}, "min_step_fraction", "must be in (0, 1) or None, got 0.0"),
        ({"min_step_fraction": 1.0}, "min_step_fraction", "must be in (0, 1) or None, got 1.0"),
    ],
)
def test_each_bad_input_is_one_error_with_its_parameter_and_detail(monkeypatch, kw, name, detail):
    monkeypatch.setattr(cs, "NewtonSolver", _Solver)
    with pytest.raises(SolverInputError) as err:
        cs.run_stages(_model(), [cs.Stage("a")], **kw)
    assert err.value.parameter == name and err.value.detail == detail


def test_a_cursor_past_the_stages_is_one_error_with_its_detail(monkeypatch):
    monkeypatch.setattr(cs, "NewtonSolver", _Solver)
    start = _cursor(stage=1, t=0.0, h=1.0, P0=np.zeros(1), P=np.zeros(1), f=0.0)
    with pytest.raises(SolverInputError) as err:
        cs.run_stages(_model(), [cs.Stage("a")], start=start)
    assert err.value.parameter == "start" and err.value.detail == "stage 1 of a run of 1 stages"


def test_a_stage_without_sub_steps_is_one_error_with_its_detail():
    for steps in (0, -2, 0.5):
        with pytest.raises(SolverInputError) as err:
            cs.Stage("press", steps=steps)
        assert (
            err.value.parameter == "stage.steps" and err.value.detail == "press: needs at least one sub-step"
        )
    assert cs.Stage("one", steps=1).steps == 1 and cs.Stage("two", steps=1.5).steps == 1.5


def test_a_cursor_at_the_end_of_a_stage_resumes_at_the_next_with_its_loads(monkeypatch):
    term = _Term()
    start = _cursor(
        t=1.0,
        x=np.array([1.0, 0.3, 10.0]),
        prev_t=0.5,
        prev_x=np.array([0.5, 0.3, 5.0]),
        P0=[0],
        f0=0,
        P=[0.3],
        f=1,
    )
    stages = [cs.Stage("a", factor=1.0), cs.Stage("b", factor=3.0, friction={0: 0.4}, steps=2)]
    res, solver = _run(monkeypatch, _model(term=term), stages, start=start)
    assert [(c.P.tolist(), c.f) for c in solver.calls] == [([0.3], 2.0), ([0.3], 3.0)]
    assert solver.calls[0].x.tolist() == [1.0, 0.3, 10.0]  # a new stage: no secant from the last one
    assert [e[1] for e in term.log if e[0] == "friction"] == [0.4]
    assert res.steps[0].pressure.dtype == float and res.converged


def test_a_resumed_stage_starts_with_no_cut_backs_counted(monkeypatch):
    start = _cursor()
    res, solver = _run(
        monkeypatch,
        _model(),
        [cs.Stage("a", factor=1.0)],
        start=start,
        diverge=lambda f, n: n == 1,
        max_cutbacks=1,
    )
    assert res.converged and [c.f for c in solver.calls] == [1.0, 0.75, 1.0]


def test_a_cursor_within_1e_12_of_the_stage_end_is_at_the_end(monkeypatch):
    start = _cursor(t=1.0 - 1e-12, f=1.0)
    res, solver = _run(
        monkeypatch, _model(), [cs.Stage("a", factor=1.0), cs.Stage("b", factor=2.0)], start=start
    )
    assert [c.f for c in solver.calls] == [2.0] and res.converged
