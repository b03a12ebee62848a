"""The Hertz case of `softcrawl verify` (`fem.contact_verification`) without its 10-30 s solve:
the closed forms (plane-strain modulus, Hertz half width and peak pressure) against known numbers
and Johnson's other forms of them, the graded spacing and the quarter-ring mesh against their
definitions, the model's contact surface and boundary conditions, the comparison at a prescribed
rigid shift of the ring (whose contact force is an integral by hand), and the staged run that the
case asks for (a scripted `run_stages`). The solve itself is `tests/fem/test_contact.py`'s."""

import numpy as np
import pytest
import skfem
from scipy.integrate import quad

from softcrawl.fem import contact_verification as cv
from softcrawl.fem.contact_stages import Stage, StagedResult
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.rigid_surfaces import Plane


def test_plane_strain_modulus():
    # mu = 1, K = 3: nu = 7 / 20, E = 2 mu (1 + nu) = 2.7, E* = E / (1 - nu^2) = 2 mu / (1 - nu) = 40 / 13
    assert cv.MATERIAL.poisson_ratio == pytest.approx(0.35, rel=1e-15)
    assert cv.plane_strain_modulus(cv.MATERIAL) == pytest.approx(40 / 13, rel=1e-14)
    # K = 2/3 mu: nu = 0, E* = E = 2 mu
    assert cv.plane_strain_modulus(NeoHookean(mu=1.5, bulk=1.0)) == pytest.approx(3.0, rel=1e-14)


def test_hertz_line_contact_known_numbers():
    # F' = 1, R = pi, E* = 4: a^2 = 4 F' R / (pi E*) = 1, p0 = 2 F' / (pi a) = 2 / pi
    a, p0 = cv.hertz_line_contact(1.0, np.pi, 4.0)
    assert a == pytest.approx(1.0, rel=1e-15)
    assert p0 == pytest.approx(2.0 / np.pi, rel=1e-15)
    assert isinstance(a, float) and isinstance(p0, float)


@pytest.mark.parametrize(
    "force, radius, e_star", [(0.0724, 10.0, 40 / 13), (3.0, 2.5, 200.0), (250.0, 40.0, 2.2e5)]
)
def test_hertz_pressure_carries_the_force_and_has_johnsons_peak(force, radius, e_star):
    """The elliptic pressure p0 sqrt(1 - x^2 / a^2) over |x| <= a integrates to F' (quadrature),
    and p0 = sqrt(F' E* / (pi R)) = a E* / (2 R) (Johnson, Contact Mechanics, 1985, eq. 4.45)."""
    a, p0 = cv.hertz_line_contact(force, radius, e_star)
    carried, _ = quad(lambda x: p0 * np.sqrt(1.0 - (x / a) ** 2), -a, a, epsabs=0.0, epsrel=1e-12)
    assert carried == pytest.approx(force, rel=1e-9)
    assert p0 == pytest.approx(np.sqrt(force * e_star / (np.pi * radius)), rel=1e-12)
    assert p0 == pytest.approx(a * e_star / (2.0 * radius), rel=1e-12)


@pytest.mark.parametrize(
    "args, points",
    [
        # uniform 1 up to 3 (inclusive), then cells of 1.3, 1.69, 2.197 and the last clipped at 10
        ((1.0, 3.0, 10.0), [0, 1, 2, 3, 4.3, 5.99, 8.187, 10]),
        # growth 2: cells 2, 4, then 8 clipped to 1 at 10, a sliver under h / 2 = 4: merged
        ((1.0, 3.0, 10.0, 2.0), [0, 1, 2, 3, 5, 10]),
        # ... at 13 the last cell is exactly h / 2: kept
        ((1.0, 3.0, 13.0, 2.0), [0, 1, 2, 3, 5, 9, 13]),
        # a sliver of the only cell is the cell
        ((1.0, 0.0, 0.5), [0, 0.5]),
        # a sliver after one uniform cell is merged into it
        ((1.0, 1.0, 1.2), [0, 1.2]),
        # the uniform part ends at `total` when fine_length exceeds it (0 .. total)
        ((0.7, 8.4, 8.0), [0, 0.7, 1.4, 2.1, 2.8, 3.5, 4.2, 4.9, 5.6, 6.3, 7.0, 8.0]),
        # total inside the uniform part, on a cell: uniform only
        ((1.0, 3.0, 3.0), [0, 1, 2, 3]),
    ],
)
def test_graded_spacing_by_hand(args, points):
    got = cv._graded(*args)
    assert got.shape == (len(points),)
    assert np.allclose(got, points, rtol=0.0, atol=1e-12)


def _polar(X):
    return np.hypot(X[0], X[1]), np.arctan2(X[1], X[0])


def test_the_hertz_mesh_is_a_quarter_ring_graded_towards_the_contact_point():
    radius, hole, thickness, fine = 10.0, 2.0, 0.5, 0.08
    mesh = cv._hertz_mesh(radius, hole, thickness, fine)
    vertices = mesh.p[:, np.unique(mesh.t)]  # mesh.p also holds the P2 midside nodes
    assert vertices.shape[1] == 25 * 30 * 2
    r, th = _polar(vertices)
    assert (r.min(), r.max()) == (pytest.approx(hole, rel=1e-14), pytest.approx(radius, rel=1e-14))
    assert (th.min(), th.max()) == (pytest.approx(-np.pi / 2, rel=1e-14), pytest.approx(0.0, abs=1e-14))
    assert set(np.round(vertices[2], 14)) == {0.0, thickness}
    # radial cells: 12 of `fine` under the outer surface, then growing by 1.3
    radii = np.unique(np.round(r, 9))
    dr = np.diff(radii)[::-1]
    assert np.allclose(dr[:12], fine, rtol=1e-9) and dr[12] == pytest.approx(1.3 * fine, rel=1e-9)
    assert len(radii) == 25
    # angular cells: 15 of arc `fine` on the outer surface from the contact point, then growing
    angles = np.unique(np.round(th, 12))
    darc = radius * np.diff(angles)
    assert np.allclose(darc[:15], fine, rtol=1e-9) and darc[15] == pytest.approx(1.3 * fine, rel=1e-9)
    assert len(angles) == 30
    # P2 with the midside nodes of curved edges on their circles: the volume of the quarter ring
    basis = skfem.Basis(mesh, skfem.ElementTetP2())
    volume = skfem.Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(basis)
    assert volume == pytest.approx(np.pi / 4 * (radius**2 - hole**2) * thickness, rel=1e-4)
    on = {name: basis.get_dofs(facets).all() for name, facets in mesh.boundaries.items()}
    loc = basis.doflocs
    assert np.allclose(np.hypot(*loc[:2, on["outer"]]), radius, rtol=1e-13)
    assert np.allclose(np.hypot(*loc[:2, on["inner"]]), hole, rtol=1e-13)
    assert np.allclose(loc[0, on["sym"]], 0.0, atol=1e-13)
    assert np.allclose(loc[2, on["z0"]], 0.0, atol=1e-14)
    assert np.allclose(loc[2, on["z1"]], thickness, atol=1e-14)
    # every facet of each surface, two triangles per grid face
    count = {name: len(f) for name, f in mesh.boundaries.items()}
    assert count == {"outer": 2 * 29, "inner": 2 * 29, "sym": 2 * 24, "z0": 2 * 29 * 24, "z1": 2 * 29 * 24}


def test_the_hertz_mesh_and_its_surfaces_scale_with_the_ring():
    """The ring scaled by 1e-4 (R = 1 um) is the same mesh scaled, with the same facets on each
    surface: the tagging tolerances scale with R (an absolute one of 1e-8 or 1e-6 mm would take
    the first cells, 8 nm thick here, into the symmetry plane and the outer surface)."""
    big = cv._hertz_mesh(10.0, 2.0, 0.5, 0.08)
    small = cv._hertz_mesh(1e-3, 2e-4, 5e-5, 8e-6)
    assert np.allclose(small.p * 1e4, big.p, rtol=0.0, atol=1e-13)
    assert set(small.boundaries) == set(big.boundaries)
    for name, facets in big.boundaries.items():
        assert np.array_equal(np.sort(small.boundaries[name]), np.sort(facets)), name


def _ring(radius=10.0, hole=2.0, approach=0.06, fine=0.5, penalty=100.0, smoothing=0.0):
    return cv.hertz_model(radius, hole, approach, fine, penalty, smoothing)


def test_the_hertz_model_touches_the_plane_at_the_contact_point_and_moves_the_hole():
    model = _ring(radius=8.0, hole=3.0, approach=0.05, penalty=50.0, smoothing=0.002)
    assert model.space.formulation == "p2"
    spec = model.contacts[0].spec
    assert spec.tags == ("outer",) and spec.surface == Plane((0.0, -8.0, 0.0), (0.0, 1.0, 0.0))
    assert (spec.penalty, spec.smoothing, spec.mu) == (50.0, 0.002, 0.0)
    term = model.contacts[0]
    x0 = model.initial_state()
    pos = term.positions(x0)
    gap = pos[:, 1] + 8.0
    # the ring rests on the plane: no point inside, the nearest one at its angle's sagitta
    assert gap.min() >= 0.0 and gap.min() < 0.5**2 / (2 * 8.0)
    assert abs(pos[np.argmin(gap), 0]) < 0.5
    rng = np.random.default_rng(3)
    x = rng.normal(size=model.n_dofs)
    y = model.apply_dirichlet(x.copy(), 0.5)
    u = model.displacement(y)
    inner = model.boundary_nodes("inner")
    assert np.allclose(u[0, inner], 0.0) and np.allclose(u[1, inner], -0.025)
    assert np.allclose(u[0, model.boundary_nodes("sym")], 0.0)
    assert np.allclose(u[2, model.boundary_nodes("z0")], 0.0) and np.allclose(
        u[2, model.boundary_nodes("z1")], 0.0
    )
    fixed = y != x
    n_fixed = 2 * len(inner) + len(
        np.setdiff1d(model.boundary_nodes("sym"), inner)
    )  # x and y of the hole, x of the plane x = 0 ...
    n_fixed += len(model.boundary_nodes("z0")) + len(model.boundary_nodes("z1"))  # ... and z of both faces
    assert fixed.sum() == n_fixed


def _shifted(model, d):
    x = model.initial_state()
    x[1 : model.space.n_u : 3] = -d
    return x


def test_the_hertz_comparison_at_a_rigid_shift_into_the_plane():
    """Every point of the ring moved by (0, -d): the penalty pressure eps_N (d - R + sqrt(R^2 - x^2))
    on the chord |x| <= c = sqrt(R^2 - (R - d)^2); F' its integral over the whole chord."""
    radius, d, eps = 10.0, 0.1, 100.0
    model = _ring(fine=0.25)
    x = _shifted(model, d)
    r = cv.hertz_result(model, x, radius, 0.05)
    assert (r.name, r.tolerance) == ("contact-hertz", 0.05)
    D = r.details
    c = np.sqrt(radius**2 - (radius - d) ** 2)
    force, _ = quad(lambda s: eps * (d - radius + np.sqrt(radius**2 - s**2)), -c, c)
    assert D["force_per_length"] == pytest.approx(force, rel=3e-3)  # 1.0e-3 observed
    a, p0 = cv.hertz_line_contact(D["force_per_length"], radius, 40 / 13)
    assert (D["half_width_hertz"], D["p0_hertz"]) == (
        pytest.approx(a, rel=1e-14),
        pytest.approx(p0, rel=1e-14),
    )
    assert D["a_over_R"] == pytest.approx(a / radius, rel=1e-14)
    assert D["p0_fe"] == pytest.approx(eps * d, rel=1e-3)  # 2.6e-4 observed: the point nearest x = 0
    assert D["half_width_fe"] == pytest.approx(c, rel=0.06)  # 1.9e-2 observed: the last pressed point
    assert D["half_width_fe"] < c
    assert D["dofs"] == model.n_dofs
    assert r.error == pytest.approx(abs(D["p0_fe"] / D["p0_hertz"] - 1.0), rel=1e-14)
    assert not r.passed  # a rigid shift is no Hertz state: p0_fe = eps d is 6.3 x p0


def _scripted(monkeypatch, converged, state=None):
    calls = []

    def run_stages(model, stages, **kw):
        calls.append((model, stages, kw))
        x = state(model) if state else model.initial_state()
        return StagedResult(
            (), converged, "" if converged else "stage 'press' diverged (scripted)", 0.0, 0, 0.0, 0.0, x
        )

    monkeypatch.setattr(cv, "run_stages", run_stages)
    return calls


def test_the_hertz_case_runs_one_stage_to_the_full_approach_and_reports_a_failure(monkeypatch):
    calls = _scripted(monkeypatch, False)
    r = cv.hertz_test()
    assert (r.name, r.error, r.tolerance, r.passed) == ("contact-hertz", np.inf, 0.05, False)
    assert r.details == {"message": "stage 'press' diverged (scripted)"}
    [(model, stages, kw)] = calls
    assert stages == [Stage("press", factor=1.0, steps=2)] and kw == {"penetration_tol": 1e-6}
    # the documented case: R = 10, hole 2, approach 0.06, cells of 0.08 at the contact, eps_N = 100
    spec = model.contacts[0].spec
    assert (spec.penalty, spec.smoothing, spec.surface.point) == (100.0, 0.0, (0.0, -10.0, 0.0))
    r_nodes, th = _polar(model.mesh.p[:, np.unique(model.mesh.t)])
    assert (r_nodes.min(), r_nodes.max()) == (pytest.approx(2.0), pytest.approx(10.0))
    assert np.sort(np.unique(np.round(th, 12)))[1] == pytest.approx(-np.pi / 2 + 0.008, rel=1e-9)
    u = model.displacement(model.apply_dirichlet(model.initial_state(), 1.0))
    assert np.allclose(u[1, model.boundary_nodes("inner")], -0.06)
    assert model.n_dofs == 26019


def test_the_hertz_case_compares_the_state_its_solve_returns(monkeypatch):
    calls = _scripted(monkeypatch, True, lambda m: _shifted(m, 0.08))
    r = cv.hertz_test(
        radius=10.0, hole=3.0, approach=0.08, fine=0.5, penalty=60.0, tolerance=0.5, smoothing=0.0
    )
    [(model, _, _)] = calls
    assert model.contacts[0].spec.penalty == 60.0
    assert np.allclose(
        model.displacement(model.apply_dirichlet(model.initial_state(), 1.0))[
            1, model.boundary_nodes("inner")
        ],
        -0.08,
    )
    same = cv.hertz_result(model, _shifted(model, 0.08), 10.0, 0.5)
    assert (r.name, r.error, r.tolerance) == (same.name, same.error, same.tolerance)
    assert r.details == same.details
    assert r.details["p0_fe"] == pytest.approx(60.0 * 0.08, rel=1e-2)
