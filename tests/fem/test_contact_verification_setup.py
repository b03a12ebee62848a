"""How each contact case of `softcrawl verify` (`fem.contact_verification`) is set up and what it
reports from its solved state: the block (extent and cells), its contact, loads and boundary
conditions, the stages it asks `run_stages` for (a recording stub), and each reported detail and
error against the contact report at the state the solve returned (a spy around the real
`run_stages`). The cases' pass/fail at their defaults is `tests/fem/test_contact.py`'s; the Hertz
case is `tests/fem/test_contact_hertz_parts.py`'s."""

from types import SimpleNamespace

import numpy as np
import pytest

from softcrawl.fem import contact_verification as cv
from softcrawl.fem.contact_stages import Stage, StagedResult
from softcrawl.fem.newton import NewtonOptions
from softcrawl.fem.rigid_surfaces import CylinderWall, Plane

REAL_RUN_STAGES = cv.run_stages


def _record(monkeypatch, solve, converged=False, residuals=((1.0,),)):
    """run_stages replaced: with `solve` the real one, else a scripted result at the undeformed
    state, one "drag" step per sequence of `residuals`, step k with k + 1 Uzawa solves of
    k + 1 Newton iterations each."""
    calls = []

    def run_stages(model, stages, **kw):
        if solve:
            res = REAL_RUN_STAGES(model, stages, **kw)
        else:
            x = model.initial_state()
            steps = [
                SimpleNamespace(stage="drag", iterations=[k + 1] * (k + 1), residuals=list(r), x=x)
                for k, r in enumerate(residuals)
            ]
            res = StagedResult(tuple(steps), converged, "scripted", 0.0, 0, 0.0, 0.0, x)
        calls.append((model, stages, kw, res))
        return res

    monkeypatch.setattr(cv, "run_stages", run_stages)
    return calls


def _fixed(model):
    """(3, n_nodes) bool: the displacement components fixed by the Dirichlet conditions, and
    (3, n_nodes) their values at load factor 1."""
    x = np.random.default_rng(0).normal(size=model.n_dofs)
    y = model.apply_dirichlet(x.copy(), 1.0)
    n_u = model.space.n_u
    return (y[:n_u] != x[:n_u]).reshape(-1, 3).T, model.displacement(y)


def _on(model, tag):
    out = np.zeros(model.displacement(model.initial_state()).shape[1], dtype=bool)
    out[model.boundary_nodes(tag)] = True
    return out


def _block(model, size, tets):
    X = model.mesh.p
    assert np.allclose(X.min(axis=1), 0.0) and np.allclose(X.max(axis=1), size)
    assert model.mesh.t.shape[1] == tets  # 6 tetrahedra per grid cell


def _dead_total(model):
    return model.dead_load[: model.space.n_u].reshape(-1, 3).sum(axis=0)


STAGES = {
    "contact-press": ([Stage("press", factor=1.0, steps=2)], {"penetration_tol": 1e-12, "max_augment": 8}),
    "contact-area": ([Stage("press", factor=1.0, steps=2)], {"penetration_tol": 1e-12, "max_augment": 8}),
    "contact-drag": (
        [Stage("press", pressure=0.2, steps=2), Stage("drag", factor=1.0, friction={0: 0.3}, steps=4)],
        {"penetration_tol": 1e-8},
    ),
    "contact-stick": ([Stage("load", factor=1.0, steps=2)], {"penetration_tol": 1e-8}),
    "contact-newton": (
        [Stage("press", pressure=0.2, steps=2), Stage("drag", factor=1.0, friction={0: 0.3}, steps=8)],
        {"penetration_tol": 1e-8, "options": NewtonOptions(tol=1e-11)},
    ),
}


@pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")
@pytest.mark.parametrize("case", list(STAGES))
def test_each_case_asks_for_its_stages_and_fails_when_they_fail(monkeypatch, case):
    calls = _record(monkeypatch, solve=False)
    r = cv.CASES[case]()
    [(model, stages, kw, _)] = calls
    assert (stages, kw) == STAGES[case]
    assert model.contacts[0].spec.penalty == 100.0  # eps_N of every documented case
    if case == "contact-drag":  # dragged by 0.5 mm, 8 x the stick limit shear strain mu p / mu_solid
        assert np.allclose(_fixed(model)[1][0, _on(model, "z1")], 0.5)
    if case == "contact-newton":  # a wall of radius 20 mm
        assert model.contacts[0].spec.surface.radius == 20.0
    assert (r.name, r.error, r.passed) == (case, np.inf, False)
    tolerance = {"contact-area": 1e-8, "contact-newton": 1.0}.get(case, 5e-3)
    assert r.tolerance == tolerance
    if case in ("contact-press", "contact-area", "contact-newton"):  # drag and stick keep their details
        assert r.details == {"message": "scripted"}


@pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")
@pytest.mark.parametrize(
    "last, error",
    [
        ([1e-1, 1e-2, 1e-4, 1e-8], 1.8 / 2.0),  # quadratic: passes
        ([1e-1, 1e-2, 1e-3, 1e-4], 1.8),  # linear: fails, 1.8 / 1
        ([1e-1, 1e-2, 1e-2, 1e-4], np.inf),  # order 0 (a stall)
        ([1e-3, 1e-4, 1e-3, 1e-6], np.inf),  # a negative order
    ],
)
def test_the_newton_error_is_the_tolerance_over_the_last_order(monkeypatch, last, error):
    _record(monkeypatch, solve=False, converged=True, residuals=([1e-1, 1e-3, 1e-9], last))
    r = cv.newton_test()
    assert r.details["orders"] == [pytest.approx(3.0), cv.convergence_order(last)]
    assert r.details["order_last_increment"] == cv.convergence_order(last)
    assert r.details["residuals_last"] == last
    assert (r.error, r.tolerance) == (pytest.approx(error, rel=1e-12), 1.0)


def test_the_press_case_is_a_quarter_block_under_a_dead_load_on_a_plane(monkeypatch):
    calls = _record(monkeypatch, solve=False)
    cv.press_test(pressure=0.4, penalty=70.0, smoothing=0.01)
    [(model, *_)] = calls
    _block(model, (1.0, 1.0, 1.0), 6 * 3 * 3 * 2)
    spec = model.contacts[0].spec
    assert (spec.tags, spec.surface, spec.penalty, spec.smoothing, spec.mu) == (
        ("z0",),
        Plane(),
        70.0,
        0.01,
        0.0,
    )
    assert np.allclose(_dead_total(model), (0.0, 0.0, -0.4))  # p times the 1 x 1 top
    assert np.abs(model.dead_load[2 : model.space.n_u : 3][~_on(model, "z1")]).max() < 1e-15  # on the top
    fixed, u = _fixed(model)
    assert np.array_equal(fixed[0], _on(model, "x0")) and np.array_equal(fixed[1], _on(model, "y0"))
    assert not fixed[2].any() and np.all(u[fixed] == 0.0)


def test_the_area_case_stretches_the_quarter_block_laterally(monkeypatch):
    calls = _record(monkeypatch, solve=False)
    r = cv.area_test(pressure=0.2, stretch=1.1, penalty=70.0)
    [(model, *_)] = calls
    _block(model, (1.5, 1.0, 1.0), 6 * 3 * 2 * 2)
    spec = model.contacts[0].spec
    assert (spec.tags, spec.surface, spec.penalty, spec.mu) == (("z0",), Plane(), 70.0, 0.0)
    assert np.allclose(_dead_total(model), (0.0, 0.0, -0.2 * 1.5))  # p A0
    fixed, u = _fixed(model)
    assert np.array_equal(fixed[0], _on(model, "x0") | _on(model, "x1"))
    assert np.array_equal(fixed[1], _on(model, "y0") | _on(model, "y1"))
    assert not fixed[2].any()
    assert np.allclose(u[0, _on(model, "x1")], 0.1 * 1.5) and np.allclose(u[1, _on(model, "y1")], 0.1 * 1.0)
    assert np.all(u[0, _on(model, "x0")] == 0.0) and np.all(u[1, _on(model, "y0")] == 0.0)
    assert r.tolerance == 1e-8


def test_the_press_case_reports_the_uzawa_solves_of_its_last_sub_step(monkeypatch):
    _record(monkeypatch, solve=False, converged=True, residuals=((1.0,), (1.0,), (1.0,)))
    assert cv.press_test().details["uzawa_solves"] == [3, 3, 3]


@pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")
def test_the_drag_case_drags_the_pressed_top_of_a_half_block(monkeypatch):
    calls = _record(monkeypatch, solve=False)
    cv.drag_test(drag=0.7, penalty=70.0, smoothing=0.01, slip_band=0.1)
    [(model, *_)] = calls
    _block(model, (2.0, 1.0, 1.0), 6 * 4 * 2 * 2)
    spec = model.contacts[0].spec
    # friction only from the drag stage on: none while pressing
    assert (spec.surface, spec.penalty, spec.smoothing, spec.slip_band, spec.mu) == (
        Plane(),
        70.0,
        0.01,
        0.1,
        0.0,
    )
    assert model.chambers[0].tags == ("z1",) and not model.dead_load.any()
    fixed, u = _fixed(model)
    top = _on(model, "z1")
    assert np.array_equal(fixed[0], top) and np.array_equal(fixed[1], top | _on(model, "y0"))
    assert not fixed[2].any()
    assert np.allclose(u[0, top], 0.7) and np.all(u[1, fixed[1]] == 0.0)


@pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")
def test_the_stick_case_loads_a_poisson_free_block_in_shear_and_compression(monkeypatch):
    calls = _record(monkeypatch, solve=False)
    cv.stick_test(mu=0.4, pressure=0.03, penalty=70.0, ratio=0.6, smoothing=0.01, slip_band=0.1)
    [(model, *_)] = calls
    _block(model, (2.0, 1.0, 0.5), 6 * 4 * 2 * 2)
    spec = model.contacts[0].spec
    assert (spec.surface, spec.penalty, spec.mu, spec.smoothing, spec.slip_band) == (
        Plane(),
        70.0,
        0.4,
        0.01,
        0.1,
    )
    assert np.allclose(model.solid.mu, 1.0) and np.allclose(model.solid.bulk, 2.0 / 3.0)  # nu = 0
    normal = 0.03 * 2.0  # p over the 2 x 1 top
    assert np.allclose(_dead_total(model), (0.6 * 0.4 * normal, 0.0, -normal))
    fixed, _ = _fixed(model)
    assert np.array_equal(fixed[1], _on(model, "y0")) and not fixed[0].any() and not fixed[2].any()


def test_the_newton_case_drags_a_block_inside_a_cylinder(monkeypatch):
    calls = _record(monkeypatch, solve=False)
    cv.newton_test(radius=15.0, penalty=70.0, smoothing=0.001, slip_band=0.1)
    [(model, *_)] = calls
    _block(model, (2.0, 1.0, 1.0), 6 * 4 * 2 * 2)
    spec = model.contacts[0].spec
    wall = CylinderWall(15.0, (0.0, 0.5, float(np.sqrt(15.002**2 - 0.25))), (1.0, 0.0, 0.0))
    assert (spec.surface, spec.penalty, spec.smoothing, spec.slip_band) == (wall, 70.0, 0.001, 0.1)
    assert (spec.mu, spec.max_initial_penetration) == (0.0, 0.003)
    # the base's long edges 2 um into the wall, its centre line 4 um clear (about R - sqrt(R^2 - 1/4))
    base = model.mesh.p[:, model.mesh.p[2] == 0.0]
    gap = spec.surface.project(base.T)[0]
    assert np.allclose(gap[np.abs(base[1] - 0.5) == 0.5], -0.002, rtol=1e-9)
    assert gap.max() == pytest.approx(15.0 - np.sqrt(15.002**2 - 0.25), rel=1e-12)
    assert gap.max() == pytest.approx(0.25 / 30 - 0.002, rel=1e-2)
    fixed, u = _fixed(model)
    top = _on(model, "z1")
    assert np.array_equal(fixed[0], top) and np.array_equal(fixed[1], top) and not fixed[2].any()
    assert np.allclose(u[0, top], 0.4) and np.allclose(u[1, top], 0.3)
    assert model.chambers[0].tags == ("z1",)


def test_the_press_details_are_the_report_at_the_solved_state(monkeypatch):
    calls = _record(monkeypatch, solve=True)
    r = cv.press_test(penalty=50.0)
    [(model, _, _, res)] = calls
    rep = model.contacts[0].report(res.x)
    d = r.details
    assert d["penetration_over_penalty"] == rep.max_penetration / (0.3 / 50.0)
    assert d["pressure_error"] == float(np.abs(model.contacts[0].state(res.x).pressure / 0.3 - 1).max())
    assert d["uzawa_solves"] == res.steps[-1].iterations and len(res.steps) == 2
    assert r.error == max(d["pressure_error"], d["penetration_over_penalty"])


def test_the_drag_details_are_the_report_at_the_solved_state(monkeypatch):
    calls = _record(monkeypatch, solve=True)
    r = cv.drag_test()
    [(model, _, _, res)] = calls
    rep = model.contacts[0].report(res.x)
    d = r.details
    assert set(d) == {"normal_force", "friction_x", "slip_fraction"}
    assert d["normal_force"] == rep.normal_force == pytest.approx(0.2 * 2.0, rel=1e-10)  # p on the 2 x 1 top
    assert d["friction_x"] == rep.friction_force[0] == pytest.approx(-0.3 * d["normal_force"], rel=1e-4)
    assert d["slip_fraction"] == rep.slip_fraction == 1.0
    assert r.error == abs(d["friction_x"] + 0.3 * d["normal_force"]) / (0.3 * d["normal_force"]) > 0
    assert (r.name, r.tolerance) == ("contact-drag", 5e-3)


def test_the_drag_error_counts_the_sticking_share():
    """Dragged by 0.04 mm (a shear strain under mu p / mu_solid = 0.06) most of the base sticks:
    the error is the sticking share, larger than the force mismatch."""
    r = cv.drag_test(drag=0.04)
    d = r.details
    assert 0 < d["slip_fraction"] < 0.5
    assert abs(d["friction_x"] + 0.3 * d["normal_force"]) / (0.3 * d["normal_force"]) < r.error
    assert r.error == pytest.approx(1.0 - r.details["slip_fraction"], rel=1e-12, abs=0.0)


def test_the_stick_error_adds_the_slipping_share():
    """At 0.95 mu N part of the base slips: the error is the force mismatch plus that share."""
    r = cv.stick_test(ratio=0.95)
    d = r.details
    assert d["shear"] == pytest.approx(0.95 * 0.3 * 0.04, rel=1e-14)
    assert d["slip_fraction"] > 0
    expected = abs(d["friction_x"] + d["shear"]) / d["shear"] + d["slip_fraction"]
    assert r.error == pytest.approx(expected, rel=1e-12, abs=0.0)


def test_the_newton_details_are_the_last_increment_at_the_solved_state(monkeypatch):
    calls = _record(monkeypatch, solve=True)
    r = cv.newton_test()
    [(model, _, _, res)] = calls
    rep = model.contacts[0].report(res.x)
    d = r.details
    drag = [s for s in res.steps if s.stage == "drag"]
    assert d["orders"] == [cv.convergence_order(s.residuals) for s in drag] and len(drag) == 8
    assert d["order_last_increment"] == d["orders"][-1]
    assert d["residuals_last"] == list(drag[-1].residuals)
    assert d["slip_fraction"] == rep.slip_fraction == 1.0
    assert d["friction_over_mu_n"] == float(np.linalg.norm(rep.friction_force) / (0.3 * rep.normal_force))
    assert d["friction_over_mu_n"] == pytest.approx(1.0, abs=2e-3)
    assert (r.name, r.tolerance, r.error) == ("contact-newton", 1.0, 1.8 / d["order_last_increment"])
