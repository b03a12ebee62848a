"""The axial link (`fem.axial_link`) against closed forms: two free blocks pushed apart by a
preloaded spring, each held by a ground spring, on a frictionless plane; one block pulled by a
preloaded ground link on a plane with Coulomb friction: it sticks below mu N and slides above."""

import numpy as np
import pytest
import skfem

from softcrawl.fem.axial_link import AxialLink
from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.equal_displacement import EqualDisplacement
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.rigid_surfaces import Plane
from softcrawl.fem.structured import box

RUBBER = NeoHookean(mu=1.0, bulk=2.0 / 3.0)  # nu = 0: no Poisson slip under the normal load


def _two_blocks():
    """Blocks A = [0, 1] x [0, 1] x [0, 1] and B = A + (2, 0, 0) in one mesh."""
    m = box((1.0, 1.0, 1.0), (2, 2, 2))
    p = np.hstack([m.p, m.p + np.array([[2.0], [0.0], [0.0]])])
    t = np.hstack([m.t, m.t + m.p.shape[1]])
    tol = 1e-9
    return skfem.MeshTet(p, t).with_boundaries(
        {
            "a_x1": lambda x: np.abs(x[0] - 1.0) < tol,
            "b_x0": lambda x: np.abs(x[0] - 2.0) < tol,
            "y0": lambda x: np.abs(x[1]) < tol,
            "z0": lambda x: np.abs(x[2]) < tol,
            "z1": lambda x: np.abs(x[2] - 1.0) < tol,
        }
    )


def test_link_tangent_matches_finite_differences():
    mesh = _two_blocks()
    model = SolidModel(mesh, RUBBER, extra_terms=[AxialLink("b_x0", "a_x1", 0, 0.7, 0.3, 0.1)])
    term = model.terms[-1]
    rng = np.random.default_rng(3)
    x = rng.normal(size=model.n_dofs) * 1e-2
    r, K = term.arrays(x)
    dx = rng.normal(size=model.n_dofs) * 1e-6
    r2, _ = term.arrays(x + dx)
    assert np.allclose(r2[:, 0] - r[:, 0], K[0] @ dx[term.dofs[:, 0]], atol=1e-12)
    # an internal link puts no net force on the body
    assert abs(r.sum()) < 1e-12


def test_two_free_blocks_pushed_apart_match_the_closed_form():
    """Every axial force on a block acts on one rigid face: the blocks translate without strain,
    u_B = -u_A = F0 / (2 k + k_g) exactly, and the ground forces cancel."""
    F0, k, kg, N = 0.5, 0.2, 0.05, 0.4
    links = [
        AxialLink("b_x0", "a_x1", 0, k, 0.0, name="actuator"),
        AxialLink("a_x1", None, 0, kg, name="ground_a"),
        AxialLink("b_x0", None, 0, kg, name="ground_b"),
    ]
    plates = [EqualDisplacement(tag, 0, 100.0) for tag in ("a_x1", "b_x0")]
    model = SolidModel(
        _two_blocks(),
        RUBBER,
        dirichlet=[Dirichlet.symmetry("y0", 1)],
        dead_loads={"z1": (0.0, 0.0, -2 * N)},
        contacts=[ContactSpec(("z0",), Plane(), penalty=100.0)],
        extra_terms=links + plates,
    )
    actuator, ground_a, ground_b = model.terms[-5:-2]

    def drive(s):
        actuator.set_load(k, s * F0)

    stages = [Stage("press", factor=1.0, steps=2), Stage("push", drive=drive, steps=2)]
    res = run_stages(model, stages, penetration_tol=1e-8)
    assert res.converged, res.message
    d = F0 / (2 * k + kg)
    u_b = ground_b.extension(res.x)
    u_a = ground_a.extension(res.x)
    assert u_b == pytest.approx(d, rel=1e-6)
    assert u_a == pytest.approx(-d, rel=1e-6)
    assert actuator.tension(res.x) == pytest.approx(F0 - k * 2 * d, rel=1e-6)
    assert abs(ground_a.tension(res.x) + ground_b.tension(res.x)) < 1e-8 * F0


def _pulled_block(N, k, mu=0.0, preload=0.0):
    """Block 2 x 1 x 0.5 (half: y >= 0) pressed by the dead load N on the plane z = 0 (penalty
    100, friction mu), its end face x1 held plane and pulled along x by a ground link of
    stiffness k and preload `preload`; returns (model, the link)."""
    model = SolidModel(
        box((2.0, 1.0, 0.5), (4, 2, 2)),
        RUBBER,
        dirichlet=[Dirichlet.symmetry("y0", 1)],
        dead_loads={"z1": (0.0, 0.0, -N)},
        contacts=[ContactSpec(("z0",), Plane(), penalty=100.0, mu=mu)],
        extra_terms=[AxialLink("x1", None, 0, k, preload, name="pull"), EqualDisplacement("x1", 0, 10.0)],
    )
    return model, model.terms[-2]  # the link's term (the spec above is its input)


@pytest.mark.parametrize("ratio", [0.5, 2.0])
def test_block_held_by_friction_sticks_below_mu_n_and_slides_above(ratio):
    """Block 2 x 1 x 0.5 pressed by N on a plane with mu, pulled along x by a ground link with
    preload F0 = ratio mu N and stiffness k on its end face: for F0 < mu N it sticks (the
    friction balances F0, the face moves only elastically); for F0 > mu N it slides until the
    spring takes the rest, u = (F0 - mu N) / k, with the friction at mu N."""
    mu, N, k = 0.3, 0.04, 0.01
    F0 = ratio * mu * N
    model, pull = _pulled_block(N, k)
    stages = [
        Stage("press", factor=1.0, steps=2),
        Stage("friction", friction={0: mu}),
        Stage("pull", drive=lambda s: pull.set_load(k, s * F0), steps=4),
    ]
    res = run_stages(model, stages, penetration_tol=1e-8)
    assert res.converged, res.message
    rep = model.contacts[0].report(res.x)
    u = pull.extension(res.x)
    assert rep.normal_force == pytest.approx(N, rel=1e-6)
    # the Newton tolerance: 2e-8 N seen
    assert rep.friction_force[0] + pull.tension(res.x) == pytest.approx(0.0, abs=1e-7 * N)
    if ratio < 1:
        assert abs(u) < 0.01 * F0 / k  # elastic only (0.0055 F0 / k seen); a slide is of order F0 / k
        assert rep.slip_fraction < 0.5
    else:
        assert u == pytest.approx((F0 - mu * N) / k, rel=1e-3)
        assert rep.friction_force[0] == pytest.approx(-mu * N, rel=1e-3)
        assert rep.slip_fraction > 0.99


def test_bad_links_name_the_parameter():
    with pytest.raises(SolverInputError, match="axial_link.stiffness"):
        AxialLink("a", None, 2, -1.0)
    with pytest.raises(SolverInputError, match="axial_link.component"):
        AxialLink("a", None, 3)
    with pytest.raises(SolverInputError, match="axial_link.tag_a"):
        AxialLink("a", "a")


def test_reported_contact_forces_balance_when_the_uzawa_loop_stops_early():
    """With one solve per step (max_augment = 0) the state keeps the multipliers it was solved
    with: the reported normal force is the applied N (before the fix the report used the
    multipliers of an update that no solve had balanced: 2 N after one pure-penalty step) and
    the friction balances the link."""
    mu, N, k = 0.3, 0.04, 0.01
    model, pull = _pulled_block(N, k, mu=mu, preload=0.5 * mu * N)
    res = run_stages(model, [Stage("load", factor=1.0)], penetration_tol=1e-12, max_augment=0)
    assert res.converged, res.message
    rep = model.contacts[0].report(res.x)
    assert rep.normal_force == pytest.approx(N, rel=1e-6)
    assert rep.friction_force[0] + pull.tension(res.x) == pytest.approx(0.0, abs=1e-7 * N)


def test_a_sliding_block_unloads_back_to_stick():
    """Pulled past mu N (full slip), then the pull drops below mu N: the block sticks where it
    slid to and the friction follows the pull (the unloading starts with every point on the
    Coulomb limit: `fem.contact_law.SLIP_MARGIN`; this block unloads with or without it)."""
    mu, N, k = 0.3, 0.04, 1e-4
    model, pull = _pulled_block(N, k)
    F_slide, F_hold = 1.02 * mu * N, 0.5 * mu * N
    stages = [
        Stage("press", factor=1.0, steps=2),
        Stage("friction", friction={0: mu}),
        Stage("pull", drive=lambda s: pull.set_load(k, s * F_slide), steps=2),
        Stage("release", drive=lambda s: pull.set_load(k, F_slide + s * (F_hold - F_slide)), steps=2),
    ]
    slid = {}
    res = run_stages(
        model,
        stages,
        penetration_tol=1e-8,
        on_step=lambda st: slid.update({st.stage: pull.extension(st.x)}),
    )
    assert res.converged, res.message
    u_slide = (F_slide - mu * N) / k  # 2.4 mm
    assert slid["pull"] == pytest.approx(u_slide, rel=1e-3)
    assert slid["release"] == pytest.approx(u_slide, abs=0.01 * u_slide)  # it stays where it slid to
    rep = model.contacts[0].report(res.x)
    assert rep.friction_force[0] == pytest.approx(-pull.tension(res.x), abs=1e-7 * N)


def test_a_share_scales_the_terms_not_the_link():
    """A wedge model carries `share` of the link: residual and tangent scaled, while tension and
    extension speak of the whole link."""
    mesh = _two_blocks()
    full = SolidModel(mesh, RUBBER, extra_terms=[AxialLink("b_x0", "a_x1", 0, 0.7, 0.3, 0.1)]).terms[-1]
    part = SolidModel(
        mesh, RUBBER, extra_terms=[AxialLink("b_x0", "a_x1", 0, 0.7, 0.3, 0.1, share=0.25)]
    ).terms[-1]
    x = np.random.default_rng(4).normal(size=full.dofs.max() + 1) * 1e-2
    (r1, K1), (r4, K4) = full.arrays(x), part.arrays(x)
    assert np.allclose(r4, 0.25 * r1, rtol=1e-14) and np.allclose(K4, 0.25 * K1, rtol=1e-14)
    assert part.tension(x) == full.tension(x) and part.extension(x) == full.extension(x)
    for bad in (0.0, 1.5, float("nan")):
        with pytest.raises(SolverInputError, match="share"):
            AxialLink("b_x0", "a_x1", share=bad)
