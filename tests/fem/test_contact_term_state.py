"""`fem.contact.ContactTerm` at prescribed states, no solve (issue 32): its residual and tangent, the
history (commit, Uzawa update, friction change) and the report's friction and slip.

A unit cube's face z = 0 is pushed DEPTH into the plane z = 0 (uniform p_N = eps_N DEPTH) and slid
by SLIDE along x from its stick points. With Coulomb friction mu and eps_T large enough for full
slip the traction is mu p_N against the slide: the friction force is -mu N e_x, every point
slips. The residual summed per component is minus the force on the body (the six P2 shape
functions of a facet sum to one), and the tangent is its derivative.
"""

import numpy as np
import pytest

from softcrawl.fem import contact_verification as cv
from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.model import SolidModel
from softcrawl.fem.rigid_surfaces import Plane
from softcrawl.fem.structured import box

PENALTY, DEPTH, MU, SLIDE = 10.0, 0.05, 0.3, 0.2


def block(**spec):
    model = SolidModel(
        box((1.0, 1.0, 1.0), (2, 2, 1)),
        cv.MATERIAL,
        contacts=[ContactSpec(("z0",), Plane(), penalty=PENALTY, **spec)],
    )
    return model, model.contacts[0]


def moved(model, dx=0.0, dz=-DEPTH, stretch=0.0):
    x = model.initial_state()
    X = model.space.nodes
    u = np.zeros((3, X.shape[1]))
    u[0] = dx + stretch * X[0]
    u[2] = dz
    x[: model.n_u] = u.T.reshape(-1)
    return x


def test_residual_is_minus_the_force_and_the_tangent_its_derivative():
    model, term = block(mu=MU)
    x = moved(model, dx=0.01)  # sticking: |t*| = eps_T 0.01 < mu p_N
    r, K = term.arrays(x)
    rep = term.report(x)
    total = r.reshape(6, 3, -1).sum(axis=(0, 2))
    assert total == pytest.approx(-(rep.normal_force_vector + rep.friction_force), rel=1e-12)
    assert rep.normal_force == pytest.approx(PENALTY * DEPTH, rel=1e-12) and total[2] < 0
    assert K is not None and term.state(x).stiffness is None  # arrays: tangent by default, state: not
    rng = np.random.default_rng(0)
    d = np.zeros_like(x)
    d[: model.n_u] = rng.standard_normal(model.n_u) * 1e-7
    r2, _ = term.arrays(x + d, with_tangent=False)
    dr = np.einsum("fab,bf->af", K, d[term.dofs])
    assert r2 - r == pytest.approx(dr, rel=1e-5, abs=1e-14)


def test_full_slip_friction_and_the_commit_that_returns_to_the_cone():
    model, term = block(mu=MU)
    x = moved(model, dx=SLIDE)
    rep = term.report(x)
    assert rep.friction_force == pytest.approx([-MU * PENALTY * DEPTH, 0.0, 0.0], rel=1e-9)
    assert rep.slip_fraction == 1.0 and rep.facet_slip == pytest.approx(np.ones_like(rep.facet_slip))
    assert rep.name == "contact"
    pos = term.positions(x)
    term.commit(x)
    # slipping points: stored on the cone, |x - x_s| = mu p_N / eps_T behind the slide
    assert term.stick[:, 0] == pytest.approx(pos[:, 0] - MU * PENALTY * DEPTH / term.spec.eps_t, rel=1e-12)
    assert term.stick[:, 2] == pytest.approx(pos[:, 2], abs=1e-15)
    # the report at the committed state uses the stick points it was solved with
    assert term.report(x).friction_force == pytest.approx(rep.friction_force, rel=1e-12)
    # at a new state, the committed stick points: back 0.01 from the cone, now sticking
    back = term.report(moved(model, dx=SLIDE - 0.01))
    assert back.slip_fraction == 0.0 and np.abs(back.facet_slip).max() == 0.0
    assert back.friction_force[0] == pytest.approx(-(MU * PENALTY * DEPTH - term.spec.eps_t * 0.01), rel=1e-9)


def test_without_friction_the_commit_puts_the_stick_points_at_the_positions():
    model, term = block()
    x = moved(model, dx=SLIDE)
    term.commit(x)
    assert np.array_equal(term.stick, term.positions(x))
    assert term.report(x).slip_fraction == 0.0 and np.all(term.report(x).friction_force == 0.0)


def test_uzawa_update_penetration_and_reset():
    model, term = block()
    x = moved(model)
    assert term.augment(x, relax=0.5) == pytest.approx(DEPTH, rel=1e-12)
    assert term.multiplier == pytest.approx(np.full_like(term.multiplier, 0.5 * PENALTY * DEPTH))
    term.augment(x, relax=0.5)  # lambda <- lambda + 0.5 (p_N - lambda), p_N = lambda + eps_N DEPTH
    assert term.multiplier == pytest.approx(np.full_like(term.multiplier, PENALTY * DEPTH))
    term.reset_multipliers()
    assert np.array_equal(term.multiplier, np.zeros_like(term.multiplier))
    assert term.augment(moved(model, dz=0.3)) == 0.0  # nothing in contact
    assert term.augment(moved(model, dz=-DEPTH / 4)) == pytest.approx(DEPTH / 4, rel=1e-12)


def test_set_friction_restarts_the_stick_points_and_set_surface_moves_the_wall():
    model, term = block()
    x = moved(model, dx=SLIDE)
    term.commit(x)
    term.set_friction(MU, x)
    assert term.mu == MU and np.array_equal(term.stick, term.positions(x))
    assert term.report(x).friction_force == pytest.approx([0.0, 0.0, 0.0], abs=1e-15)
    term.set_surface(Plane(point=(0.0, 0.0, -DEPTH)))
    assert term.report(x).normal_force == pytest.approx(0.0, abs=1e-15)
    assert term.report(moved(model, dz=-2 * DEPTH)).normal_force == pytest.approx(PENALTY * DEPTH, rel=1e-12)


def test_the_spec_smoothing_and_slip_band_reach_the_law():
    model, term = block(smoothing=0.02)
    at_zero = term.report(moved(model, dz=0.0))  # g = 0: p_N = eps_N delta / 8
    assert at_zero.max_pressure == pytest.approx(PENALTY * 0.02 / 8, rel=1e-12)
    model, term = block(mu=MU, slip_band=0.2)
    limit = MU * PENALTY * DEPTH
    x = moved(model, dx=limit / term.spec.eps_t)  # r = 1: on the band, phi = 1 - 0.1^2 / 0.4
    assert term.report(x).friction_force[0] == pytest.approx(-limit * (1 - 0.01 / 0.4), rel=1e-9)


@pytest.mark.parametrize(
    "field, value, parameter, detail",
    [
        ("tags", (), "contact.tags", "give at least one boundary tag"),
        (
            "surface",
            "plane",
            "contact.surface",
            "must be a Plane, a CylinderWall, an ElbowPipe or a CorrugatedPipe",
        ),
        ("penalty", 0.0, "contact.penalty", "must be a positive number, got 0.0"),
        ("penalty", float("nan"), "contact.penalty", "must be a positive number, got nan"),
        ("penalty", "stiff", "contact.penalty", "must be a positive number, got 'stiff'"),
        ("tangential_penalty", -1.0, "contact.tangential_penalty", "must be a positive number, got -1.0"),
        ("mu", -0.1, "contact.mu", "the friction coefficient must be >= 0, got -0.1"),
        ("mu", float("inf"), "contact.mu", "the friction coefficient must be >= 0, got inf"),
        ("mu", None, "contact.mu", "the friction coefficient must be >= 0, got None"),
        ("max_initial_penetration", -0.1, "contact.max_initial_penetration", "must be a number >= 0"),
        ("max_initial_penetration", float("inf"), "contact.max_initial_penetration", "must be a number >= 0"),
        ("smoothing", -0.1, "contact.smoothing", "must be a gap band >= 0 (mm)"),
        ("smoothing", float("nan"), "contact.smoothing", "must be a gap band >= 0 (mm)"),
        ("slip_band", 1.0, "contact.slip_band", "must be a share of the Coulomb radius in [0, 1), got 1.0"),
        ("slip_band", -0.1, "contact.slip_band", "must be a share of the Coulomb radius in [0, 1), got -0.1"),
        (
            "slip_band",
            float("nan"),
            "contact.slip_band",
            "must be a share of the Coulomb radius in [0, 1), got nan",
        ),
    ],
)
def test_a_bad_contact_spec_is_one_error_naming_its_field(field, value, parameter, detail):
    kwargs = {"tags": ("z0",), "surface": Plane(), "penalty": PENALTY} | {field: value}
    with pytest.raises(SolverInputError) as err:
        ContactSpec(**kwargs)
    assert (err.value.parameter, err.value.detail) == (parameter, detail)


def test_a_good_contact_spec_is_normalised():
    spec = ContactSpec(
        "z0", Plane(), penalty=3, mu=1, slip_band=0.0, smoothing=0.0, max_initial_penetration=0.0
    )
    assert spec.tags == ("z0",) and spec.penalty == 3.0 and type(spec.penalty) is float
    assert spec.mu == 1.0 and type(spec.mu) is float and spec.eps_t == 3.0
    spec = ContactSpec(("z0", "x0"), Plane(), penalty=3.0, tangential_penalty=2, slip_band=0.99)
    assert spec.eps_t == 2.0 and type(spec.tangential_penalty) is float


def test_the_terms_facets_and_its_setup_errors_name_the_parameter():
    model, term = block()
    assert np.array_equal(term.facets, np.unique(model.mesh.boundaries["z0"]))
    mesh = box((1.0, 1.0, 1.0), (1, 1, 1))
    with pytest.raises(SolverInputError) as err:
        SolidModel(mesh, cv.MATERIAL, contacts=[ContactSpec(("nowhere",), Plane(), penalty=1.0)])
    assert err.value.parameter == "contact.tags"
    spec = ContactSpec(("z0",), Plane(point=(0.0, 0.0, 0.5)), penalty=1.0, name="foot")
    with pytest.raises(SolverInputError) as err:
        SolidModel(mesh, cv.MATERIAL, contacts=[spec])
    assert err.value.parameter == "contact.max_initial_penetration"
    assert err.value.detail == (
        "foot: the reference state penetrates the surface by 0.5 mm (> 0 mm); "
        "start with the surface clear of the body"
    )
    # within the accepted penetration: built
    ok = ContactSpec(("z0",), Plane(point=(0.0, 0.0, 0.5)), penalty=1.0, max_initial_penetration=0.5)
    assert SolidModel(mesh, cv.MATERIAL, contacts=[ok]).contacts[0].spec.max_initial_penetration == 0.5


def test_the_report_at_a_committed_state_uses_the_stick_points_it_was_solved_with():
    """With a rounded cone the commit stores slipping points at r = 1, where phi = 1 - w/8: the
    report at the committed x keeps the traction the residual balanced (mu p_N), later states
    start from the stored points."""
    model, term = block(mu=MU, slip_band=0.2)
    x = moved(model, dx=SLIDE)
    before = term.report(x).friction_force
    term.commit(x)
    assert term.report(x).friction_force == pytest.approx(before, rel=1e-12)
    assert before[0] == pytest.approx(-MU * PENALTY * DEPTH, rel=1e-12)
    other = moved(model, dx=SLIDE + 1e-3)
    assert term.report(other).friction_force[0] > before[0]  # from the stored points: below the limit


def test_fractions_of_a_small_face_and_of_no_contact():
    model = SolidModel(
        box((0.5, 0.5, 1.0), (1, 1, 1)),
        cv.MATERIAL,
        contacts=[ContactSpec(("z0",), Plane(), penalty=PENALTY, mu=MU)],
    )
    term = model.contacts[0]
    rep = term.report(moved(model, dx=SLIDE))
    assert rep.area_reference == pytest.approx(0.25) and rep.contact_fraction == pytest.approx(1.0)
    assert rep.slip_fraction == 1.0  # a contact area under 1 mm^2 still divides
    none = term.report(moved(model, dz=0.3))
    assert (none.slip_fraction, none.contact_fraction, none.normal_force) == (0.0, 0.0, 0.0)
    term.reset_multipliers()
    assert term.multiplier.shape == term.positions(moved(model)).shape[:1]
