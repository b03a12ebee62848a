"""The solver against closed-form solutions (docs/decisions/010-verification.md), on coarse meshes."""

import numpy as np
import pytest

from softcrawl.fem import reference_models as RM
from softcrawl.fem import verification as V
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.path import NewtonOptions, load_path
from softcrawl.fem.structured import box


def test_patch_test_reproduces_homogeneous_stretch():
    r = V.patch_test()
    assert r.details["field_error"] <= 1e-8, r.details
    assert r.details["stress_error"] <= 2e-4, r.details  # observed 5.7e-5: K/mu = 1e4 vs incompressible


def test_dead_load_gives_the_homogeneous_uniaxial_stretch():
    r = V.dead_load_test()
    assert r.passed, r.details
    assert r.details["incompressible_error"] <= 2.5e-4, r.details  # observed 7.6e-5: K/mu = 1e4
    # the load really is dead: doubling it follows the material law, not a linear spring
    r2 = V.dead_load_test(stretch=2.5)
    assert r2.passed and abs(r2.details["stretch"] - 2.5) / 1.5 < 6e-4, r2.details  # observed 2.0e-4


@pytest.mark.parametrize(
    "loads, word",
    [
        ({"nowhere": (0, 0, 1)}, "unknown boundary"),
        ({"z1": (0, 1)}, "finite total force"),
        ({"z1": (0, 0, float("nan"))}, "finite total force"),
    ],
)
def test_bad_dead_load_names_the_parameter(loads, word):
    with pytest.raises(SolverInputError) as e:
        SolidModel(box((1, 1, 1), (1, 1, 1)), NeoHookean(mu=0.03, bulk=30.0), dead_loads=loads)
    assert e.value.parameter == "dead_loads" and word in str(e.value)


def test_plane_strain_tube_at_half_and_twice_mu():
    r = V.tube_test()
    assert r.passed, r.details
    # observed (inner, outer): 2.3e-5, 6.6e-7 at 0.5 mu; 1.4e-3, 8.7e-5 at 2 mu (the K/mu = 1000
    # compressibility against the incompressible solution grows with the pressure)
    limits = {"P=0.5mu": (1e-4, 1e-5), "P=2.0mu": (4e-3, 3e-4)}
    for key, (inner, outer) in limits.items():
        assert r.details[key]["inner_err"] < inner, r.details[key]
        assert r.details[key]["outer_err"] < outer, r.details[key]


def test_sphere_volume_control_follows_analytic_curve_past_its_maximum():
    r = V.sphere_volume_test()
    assert r.details["passed_maximum"]
    assert r.passed and r.tolerance <= 3e-3, r.details  # observed 1.0e-3


def test_sphere_pressure_control_reports_the_limit_point():
    r = V.sphere_limit_test()
    assert r.passed and r.tolerance <= 2e-3, r.details  # observed 6.8e-4
    assert any("limit point at P ~" in e for e in r.details["events"])
    # the states after the maximum are flagged as past the limit, the ones before are not
    assert r.details["past_limit_states"] >= 1 and r.details["past_limit_flags_consistent"]


def test_newton_converges_quadratically_under_follower_pressure():
    r = V.newton_test()
    res = np.array(r.details["residuals"])
    assert res[-1] < 1e-10
    # last two ratios r_{k+1} / r_k^2 bounded: quadratic, not linear, convergence
    assert r.passed, r.details
    assert r.details["orders"][-1] > 1.6


def test_diverging_solve_returns_a_failure_naming_the_last_converged_load():
    mesh = box((1.0, 1.0, 1.0), (1, 1, 1))
    bcs = [Dirichlet.fixed("z0"), Dirichlet.prescribed("z1", 2, -3.0)]  # crush through itself
    model = SolidModel(mesh, NeoHookean.nearly_incompressible(0.03, 10.0), dirichlet=bcs)
    res = load_path(model, [(0.0, 1.0)], control="displacement")
    assert not res.converged
    assert "last converged load" in res.message and "load factor" in res.message


def test_unknown_boundary_tag_is_a_named_error():
    with pytest.raises(SolverInputError) as err:
        SolidModel(box(), NeoHookean(mu=0.03, bulk=30.0), dirichlet=[Dirichlet.fixed("nope")])
    assert err.value.parameter == "dirichlet"


def test_reaction_balances_the_pressure_load():
    """x-equilibrium of a quarter tube: the support force on the plane x = 0 cancels the net
    pressure force P * int_0^h y_edge(z) dz, y_edge(z) the deformed inner edge on that plane
    (one quadratic element layer: Simpson's rule over its three nodes is exact)."""
    model = RM.tube_model(3.0, 9.0, n_radial=3, n_angle=4)
    P = 0.005
    res = load_path(model, [(P, 0.0)])
    x = res.steps[-1].x
    edge = np.intersect1d(model.boundary_nodes("inner"), model.boundary_nodes("sym_x"))
    pos = model.nodes[:, edge] + model.displacement(x)[:, edge]
    y0, ymid, y1 = pos[1, np.argsort(pos[2])]
    resultant = P * (y0 + 4 * ymid + y1) / 6
    support = model.reaction(x, "sym_x", pressure=P)
    assert support[0] == pytest.approx(-resultant, rel=1e-7)


def test_volume_control_lands_on_targets_before_and_flags_states_past_the_limit():
    # a stalling pressure control (3 Newton iterations from the last state, no cut-back) hands over to volume
    # control on the monotone tube: the targets are landed on and are not "past the limit"
    model = RM.tube_model(3.0, 9.0, n_radial=4, n_angle=6)
    targets = [(0.3 * V.MU, 0.0), (0.6 * V.MU, 0.0)]
    res = load_path(model, targets, options=NewtonOptions(max_iter=3, max_cutbacks=0, predictor="none"))
    assert res.converged and res.limit_pressure is None, res.message
    assert [s.control for s in res.steps] == ["volume", "volume"]
    assert not any(s.past_limit for s in res.steps)
    np.testing.assert_allclose([s.pressure for s in res.steps], [t[0] for t in targets], rtol=1e-5)
