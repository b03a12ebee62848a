"""The elbow's wall (fem.pipe_surfaces.ElbowPipe) and the straight pipe of any axis
(fem.rigid_surfaces.CylinderWall): the curvature operator against finite differences of the normal,
the torus's two principal curvatures, the closest point against a dense sampling of the wall and
the analytic planner's centreline, a point sliding across the junctions, bad input, the contact
law's tangent on the elbow, and the contact-elbow verification case."""

import numpy as np
import pytest

from softcrawl.analytic.pipe import Pipe
from softcrawl.fem import pipe_verification as pv
from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.contact_verification import convergence_order
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.model import Dirichlet
from softcrawl.fem.pipe_surfaces import ElbowPipe
from softcrawl.fem.rigid_surfaces import CylinderWall
from tests.fem.tiles import assert_tangent_matches_differences, press_tile

R_PIPE, R_BEND, ENTRY = 10.0, 25.0, 20.0
ELBOW = ElbowPipe(R_PIPE, R_BEND, entry=ENTRY)
# the same elbow in an oblique frame: axis (1, 2, 2) / 3, turning towards (2, -1, 0) / sqrt(5)
OBLIQUE = ElbowPipe(R_PIPE, R_BEND, entry=ENTRY, start=(1.0, -2.0, 3.0), axis=(1, 2, 2), turn=(2, -1, 0))


def torus_point(pipe, phi, theta, d):
    """Points at bend angle phi, angle theta around the pipe (0: the outer side of the bend) and
    distance d from the centreline."""
    c, _ = pipe.centreline(np.atleast_1d(phi))
    u = (c - pipe.torus_centre) / pipe.bend_radius
    th = np.atleast_1d(theta)[:, None]
    return c + d * (np.cos(th) * u + np.sin(th) * pipe.torus_axis)


def leg_point(pipe, s, theta, d, exit_leg=False):
    """Points at arc length s along a leg (from its junction: s < 0 on the entry leg, > 0 on the
    exit leg), with the cross-section frame of the adjacent torus end."""
    phi = pipe.bend_angle if exit_leg else 0.0
    c, w = pipe.centreline([phi])
    u = (c - pipe.torus_centre) / pipe.bend_radius
    th = np.atleast_1d(theta)[:, None]
    return c + np.atleast_1d(s)[:, None] * w + d * (np.cos(th) * u + np.sin(th) * pipe.torus_axis)


def fd_curvature(surface, x, h=1e-6):
    """-dn/dx by central differences, (n, 3, 3)."""
    out = np.empty((x.shape[0], 3, 3))
    for j in range(3):
        step = np.zeros(3)
        step[j] = h
        out[:, :, j] = -(surface.project(x + step)[1] - surface.project(x - step)[1]) / (2 * h)
    return out


def fd_gap_gradient(surface, x, h=1e-6):
    return np.stack(
        [(surface.project(x + h * e)[0] - surface.project(x - h * e)[0]) / (2 * h) for e in np.eye(3)], axis=1
    )


@pytest.mark.parametrize("pipe", [ELBOW, OBLIQUE], ids=["default-frame", "oblique-frame"])
@pytest.mark.parametrize(
    "theta",
    [0.0, np.pi, np.pi / 2, -np.pi / 2, 2.2],
    ids=["outer", "inner", "crown", "crown-below", "oblique"],
)
def test_the_torus_curvature_is_the_derivative_of_its_normal(pipe, theta):
    """C = -dn/dx on the torus (the outer and inner sides of the bend, the crowns) at points from
    the wall to near the centreline, and dg/dx = n, against central differences."""
    phi = np.linspace(0.1, pipe.bend_angle - 0.1, 7)
    x = np.vstack([torus_point(pipe, phi, theta, d) for d in (9.99, 7.0, 2.0)])
    g, n, C = pipe.project(x)
    assert np.all(pipe.locate(x)[0] == 1)
    assert np.abs(C - fd_curvature(pipe, x)).max() < 1e-7 * np.abs(C).max()
    assert np.abs(fd_gap_gradient(pipe, x) - n).max() < 1e-8
    assert np.allclose(C, np.swapaxes(C, 1, 2), atol=1e-15)


@pytest.mark.parametrize("pipe", [ELBOW, OBLIQUE], ids=["default-frame", "oblique-frame"])
def test_the_legs_curvature_is_the_derivative_of_their_normal(pipe):
    rng = np.random.default_rng(3)
    th, d = rng.uniform(-np.pi, np.pi, 12), rng.uniform(0.5, 9.9, 12)
    x = np.vstack(
        [leg_point(pipe, -rng.uniform(0.1, 40.0), t, r) for t, r in zip(th[:6], d[:6])]
        + [leg_point(pipe, rng.uniform(0.1, 40.0), t, r, exit_leg=True) for t, r in zip(th[6:], d[6:])]
    )
    g, n, C = pipe.project(x)
    assert list(pipe.locate(x)[0]) == [0] * 6 + [2] * 6
    assert np.abs(C - fd_curvature(pipe, x)).max() < 1e-7 * np.abs(C).max()
    assert np.abs(fd_gap_gradient(pipe, x) - n).max() < 1e-8
    assert np.allclose(g, R_PIPE - d, rtol=0, atol=1e-12)


def test_the_straight_pipe_with_an_oblique_axis():
    """CylinderWall about the line through (1, 2, 3) along (1, 2, -0.5): C against differences of
    n, dg/dx = n, and the gap r - distance to the axis line."""
    axis = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    wall = CylinderWall(5.0, centre=(1.0, 2.0, 3.0), axis=tuple(axis))
    rng = np.random.default_rng(4)
    q = rng.normal(size=(20, 3)) * 3.0
    x = np.array([1.0, 2.0, 3.0]) + q
    g, n, C = wall.project(x)
    dist = np.linalg.norm(q - np.outer(q @ axis, axis), axis=1)
    assert np.allclose(g, 5.0 - dist, rtol=0, atol=1e-12)
    assert np.abs(C - fd_curvature(wall, x)).max() < 1e-7 * np.abs(C).max()
    assert np.abs(fd_gap_gradient(wall, x) - n).max() < 1e-8


@pytest.mark.parametrize("theta", [0.0, 0.7, np.pi / 2, 2.0, np.pi])
def test_on_the_wall_the_torus_has_its_two_principal_curvatures(theta):
    """At the wall (d = r): C n = 0, C w = cos(theta) / (R + r cos(theta)) w along the pipe, and
    1 / r around it."""
    phi = np.array([0.3, 0.8, 1.2])
    x = torus_point(ELBOW, phi, theta, R_PIPE)
    g, n, C = ELBOW.project(x)
    _, w = ELBOW.centreline(phi)
    b = np.cross(n, w)
    along = np.cos(theta) / (R_BEND + R_PIPE * np.cos(theta))
    assert np.allclose(g, 0.0, atol=1e-12)
    assert np.allclose(np.einsum("nij,nj->ni", C, n), 0.0, atol=1e-14)
    assert np.allclose(np.einsum("nij,nj->ni", C, w), along * w, atol=1e-14)
    assert np.allclose(np.einsum("nij,nj->ni", C, b), b / R_PIPE, atol=1e-14)


def _wall_samples(pipe, n_phi, n_theta, n_s, length=40.0):
    """Points of the wall: the entry leg back to -length, the torus, the exit leg to +length."""
    th = np.linspace(-np.pi, np.pi, n_theta, endpoint=False)
    phi = np.linspace(0.0, pipe.bend_angle, n_phi)
    s = np.linspace(0.0, length, n_s)
    torus = np.vstack([torus_point(pipe, phi, t, pipe.radius) for t in th])
    entry = np.vstack([leg_point(pipe, -s, t, pipe.radius) for t in th])
    out = np.vstack([leg_point(pipe, s, t, pipe.radius, exit_leg=True) for t in th])
    return np.vstack([torus, entry, out])


def test_the_closest_point_against_a_dense_sampling_and_the_planners_centreline():
    """For points inside the pipe (on the legs, the torus and near both junctions): no sampled wall
    point is closer than the gap, the nearest sample is within the sampling's reach of it, the
    claimed wall point x - g n lies on the wall, and g is r minus the distance to the analytic
    planner's centreline (`softcrawl.analytic.pipe.Pipe`, independent code) at its arc length."""
    rng = np.random.default_rng(5)
    pts = np.vstack(
        [
            *[
                torus_point(ELBOW, [p], t, d)
                for p, t, d in zip(
                    rng.uniform(0, np.pi / 2, 8), rng.uniform(-3, 3, 8), rng.uniform(0.5, 9.5, 8)
                )
            ],
            *[leg_point(ELBOW, [s], t, 8.0) for s, t in zip((-0.05, -5.0, 0.0), (0.3, 3.0, 1.0))],
            *[leg_point(ELBOW, [s], t, 9.0, exit_leg=True) for s, t in zip((0.05, 5.0), (2.5, -1.0))],
        ]
    )
    g, n, _ = ELBOW.project(pts)
    samples = _wall_samples(ELBOW, 500, 500, 250)  # spacing <= 0.28 mm
    for x, gap in zip(pts, g):
        dmin = np.sqrt(((samples - x) ** 2).sum(axis=1)).min()
        assert gap - 1e-9 <= dmin <= gap + 0.005, (x, gap, dmin)
    wall = pts - g[:, None] * n
    assert np.allclose(ELBOW.project(wall)[0], 0.0, atol=1e-12)
    planner = Pipe("elbow", 2 * R_PIPE, R_BEND, entry=ENTRY, exit=100.0)
    dist, s = planner.locate(pts)
    assert np.allclose(g, R_PIPE - dist, rtol=0, atol=1e-12)
    assert np.allclose(ELBOW.locate(pts)[1], s, rtol=0, atol=1e-9)


@pytest.mark.parametrize("exit_leg", [False, True], ids=["bend-start", "bend-end"])
@pytest.mark.parametrize("theta", [0.0, np.pi / 2, np.pi, 2.5])
def test_a_point_sliding_across_a_junction_sees_a_c1_wall(exit_leg, theta):
    """Along the pipe at a fixed place in its cross-section (d = 9 mm), through the plane where a
    leg meets the torus: the gap and the normal are continuous, the curvature jumps by the torus's
    curvature along the pipe, cos(theta) / (R + d cos(theta)) w w."""
    d, eps = 9.0, 1e-9
    sign = 1.0 if exit_leg else -1.0
    leg = leg_point(ELBOW, [sign * eps], theta, d, exit_leg=exit_leg)
    phi = ELBOW.bend_angle - eps / R_BEND if exit_leg else eps / R_BEND
    bend = torus_point(ELBOW, [phi], theta, d)
    (g1, n1, C1), (g2, n2, C2) = ELBOW.project(leg), ELBOW.project(bend)
    assert ELBOW.locate(leg)[0][0] == (2 if exit_leg else 0) and ELBOW.locate(bend)[0][0] == 1
    assert abs(g1[0] - g2[0]) < 1e-12 and np.abs(n1 - n2).max() < 1e-9
    _, w = ELBOW.centreline([ELBOW.bend_angle if exit_leg else 0.0])
    jump = np.cos(theta) / (R_BEND + d * np.cos(theta)) * np.outer(w[0], w[0])
    assert np.abs((C2 - C1)[0] - jump).max() < 1e-8
    # a point crossing on a straight line oblique to the junction plane: g(t) is C1, its slope
    # n . v the same on both sides (one-sided differences over 2e-4 mm: 2e-5 apart at most measured,
    # O(1e-4 C); a kink of the gap would part them by O(0.1-1))
    v = np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])
    x0 = leg[0]
    t = np.array([-2e-4, -1e-4, 0.0, 1e-4, 2e-4])
    gt = ELBOW.project(x0 + t[:, None] * v)[0]
    left, right = (gt[2] - gt[0]) / 2e-4, (gt[4] - gt[2]) / 2e-4
    assert abs(left - right) < 6e-5


@pytest.mark.parametrize(
    "kwargs, parameter",
    [
        ({"radius": 10.0, "bend_radius": 10.0}, "contact.surface.bend_radius"),
        ({"radius": 10.0, "bend_radius": 8.0}, "contact.surface.bend_radius"),
        ({"radius": -1.0, "bend_radius": 8.0}, "contact.surface.radius"),
        ({"radius": 10.0, "bend_radius": float("nan")}, "contact.surface.bend_radius"),
        ({"radius": 10.0, "bend_radius": 20.0, "entry": -1.0}, "contact.surface.entry"),
        ({"radius": 10.0, "bend_radius": 20.0, "bend_angle": 4.0}, "contact.surface.bend_angle"),
        ({"radius": 10.0, "bend_radius": 20.0, "bend_angle": 0.0}, "contact.surface.bend_angle"),
        ({"radius": 10.0, "bend_radius": 20.0, "turn": (1.0, 0.0, 1.0)}, "contact.surface.turn"),
        ({"radius": 10.0, "bend_radius": 20.0, "axis": (0.0, 0.0, 0.0)}, "contact.surface.axis"),
        ({"radius": 10.0, "bend_radius": 20.0, "start": (0.0, np.inf, 0.0)}, "contact.surface.start"),
    ],
)
def test_bad_elbows_name_the_parameter(kwargs, parameter):
    with pytest.raises(SolverInputError) as info:
        ElbowPipe(**kwargs)
    assert info.value.parameter == parameter


def test_the_bend_radius_error_says_why():
    with pytest.raises(SolverInputError, match="must exceed the pipe radius 10 mm"):
        ElbowPipe(10.0, 10.0)
    assert ElbowPipe(10.0, 25.0).with_radius(12.0) == ElbowPipe(12.0, 25.0)
    with pytest.raises(SolverInputError, match="bend_radius"):
        ElbowPipe(10.0, 25.0).with_radius(30.0)


def test_the_contact_laws_tangent_on_the_elbow_matches_finite_differences():
    """-df/dx of the law with friction (normal, both curvatures of the torus, stick, slip and the
    slip-normal coupling) at points near the wall of the torus and the legs."""
    rng = np.random.default_rng(6)
    th = rng.uniform(-np.pi, np.pi, 60)
    x = np.vstack(
        [torus_point(OBLIQUE, [p], t, R_PIPE) for p, t in zip(rng.uniform(0.05, 1.5, 40), th[:40])]
        + [leg_point(OBLIQUE, [-s], t, R_PIPE) for s, t in zip(rng.uniform(0.5, 9, 10), th[40:50])]
        + [
            leg_point(OBLIQUE, [s], t, R_PIPE, exit_leg=True)
            for s, t in zip(rng.uniform(0.5, 9, 10), th[50:])
        ]
    )
    x = x + rng.normal(size=x.shape) * 0.1
    stick = x + rng.normal(size=x.shape) * 0.02
    lam = rng.uniform(0, 0.1, x.shape[0])
    assert_tangent_matches_differences(x, (OBLIQUE, lam, stick, 10.0, 7.0, 0.4))


def test_a_contact_spec_takes_the_elbow():
    spec = ContactSpec(("z0",), ELBOW, penalty=1.0)
    assert spec.surface is ELBOW


def test_the_elbow_case_balances_the_load_with_no_moment_about_the_torus_axis():
    """`softcrawl verify --case contact-elbow`: the contact resultant is -F and its moment about the
    torus axis zero (fem.pipe_verification), Newton converges quadratically in the press, every base
    point is in contact, and the normals' spread over the curved base makes sum p_N dA exceed F
    (by 0.058 % measured)."""
    r = pv.elbow_test()
    assert (r.name, r.tolerance) == ("contact-elbow", 1e-8)
    assert r.passed, r.details
    d = r.details
    assert r.error == max(d["errors"].values())
    assert d["order_last_increment"] >= 1.8
    assert d["contact_fraction"] == 1.0
    assert 1.0 < d["normal_force_sum_over_load"] < 1.002
    assert d["load_N"] == pytest.approx(0.2 * 2.0, rel=1e-14)


@pytest.mark.parametrize("alpha", [np.pi / 2, 0.4, 2.4, np.pi])
def test_every_point_has_a_foot_for_any_bend_angle(alpha):
    """Random points anywhere, inside the pipe or far outside it: the gap is r minus the distance to
    the planner's centreline (the nearest point over the three pieces), and inside the reach R the
    arc lengths agree."""
    pipe = ElbowPipe(R_PIPE, R_BEND, entry=ENTRY, bend_angle=alpha)
    planner = Pipe("elbow", 2 * R_PIPE, R_BEND, entry=ENTRY, exit=1000.0, bend_angle=alpha)
    x = np.random.default_rng(7).uniform(-80.0, 100.0, size=(4000, 3))
    g = pipe.project(x)[0]
    dist, s = planner.locate(x)
    assert np.allclose(g, R_PIPE - dist, rtol=0, atol=1e-9)
    near = dist < 0.99 * R_BEND
    assert near.sum() > 200 and np.allclose(pipe.locate(x[near])[1], s[near], rtol=0, atol=1e-9)


def _press_across_the_junction(hold: bool):
    """The contact-elbow tile centred on the bend's start (half on the entry leg, half on the torus),
    pressed by 0.4 N along the wall's outward normal there; `hold`: its top's axial displacement held."""
    load = 0.4 * ELBOW.frame([ENTRY])[2][0]
    bcs = [Dirichlet("z1", (2,), (0.0,))] if hold else []  # the default frame's axis is z
    res, st, resultant, term = press_tile(pv.elbow_tile(ELBOW, ENTRY), ELBOW, load, bcs)
    before, (after, s_after, *_) = ELBOW.locate(term.X)[0], ELBOW.locate(term.positions(res.x))
    return res, st, resultant, load, before, after, s_after


def test_a_tile_pressed_across_a_junction():
    """Held along the pipe, the tile stays across the junction (48 base points on the leg, 48 on
    the torus, none crosses), every point in contact, and Newton converges quadratically: the
    junction costs nothing while no point crosses it. The torus half pushes the tile back towards
    the leg (u . a = sin(phi) > 0 there): 4.45e-3 N along -a measured, 1.1 % of the load, which the
    hold carries; across the pipe the contact balances the load exactly."""
    res, st, resultant, load, before, after, _ = _press_across_the_junction(hold=True)
    assert res.converged and st.active.all()
    assert list(np.bincount(before, minlength=3)) == [48, 48, 0] and np.array_equal(before, after)
    assert convergence_order(res.steps[-1].residuals) >= 1.8
    assert np.allclose(resultant[:2], -load[:2], rtol=0, atol=1e-12)
    assert -5e-3 < resultant[2] < -4e-3


def test_a_free_tile_slides_off_the_bend_into_the_leg():
    """Free, the frictionless tile is pushed off the torus (the load has a component down the
    bend's wall there) onto the straight leg, where sliding along the axis is neutral: every torus
    point reaches the leg, the pressure stays continuous (the first solve needs 10 Newton
    iterations where points cross, against 4 held), and the contact balances the whole load.

    The push ends when the last torus point reaches the junction, so that point stops ON it
    (measured: s - entry = 3.6e-15 mm, which `locate` may give to either piece): the test asks
    that every point's arc length be at most the entry's, to 1e-9 mm, not that its piece index
    be the leg's (which failed on round-off: 95 of 96). A tile that stayed across the junction
    has points up to 1 mm past it."""
    res, st, resultant, load, before, after, s_after = _press_across_the_junction(hold=False)
    assert res.converged and st.active.all()
    assert list(np.bincount(before, minlength=3)) == [48, 48, 0]
    assert np.all(s_after <= ENTRY + 1e-9) and np.count_nonzero(after == 2) == 0
    assert np.allclose(resultant, -load, rtol=0, atol=1e-12)


def test_the_frame_follows_the_planners_centreline():
    """`ElbowPipe.frame(s)`: the point and tangent of the planner's centreline at arc length s on
    both legs (extended) and the bend, and u the unit vector from the torus axis (constant on the legs)."""
    s = np.linspace(-30.0, ENTRY + R_BEND * np.pi / 2 + 30.0, 41)
    planner = Pipe("elbow", 2 * R_PIPE, R_BEND, entry=ENTRY, exit=100.0)
    c, w, u = ELBOW.frame(s)
    assert np.allclose(c, planner.point(s), rtol=0, atol=1e-12)
    assert np.allclose(w, planner.tangent(s), rtol=0, atol=1e-12)
    assert np.allclose(np.einsum("ni,ni->n", u, w), 0.0, atol=1e-15)
    assert np.allclose(u[s <= ENTRY], [-1.0, 0.0, 0.0]) and np.allclose(
        u[s >= ENTRY + R_BEND * np.pi / 2], [0.0, 0.0, 1.0]
    )


def test_every_pipe_gives_a_points_position_along_its_centreline():
    """`arc_length`: along the axis from the centre for the straight and bellows pipes, the
    nearest centreline point's arc length for the elbow (its legs and its torus)."""
    from softcrawl.fem.corrugated_pipe import CorrugatedPipe

    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    x = np.array([[1.0, 2.0, 3.0], [-4.0, 0.5, 7.0]])
    for pipe in (
        CylinderWall(35.0, centre=(1.0, 1.0, 0.0), axis=axis),
        CorrugatedPipe(35.0, 2.0, 10.0, (1.0, 1.0, 0.0), axis),
    ):
        assert np.allclose(pipe.arc_length(x), (x - [1.0, 1.0, 0.0]) @ axis, rtol=0, atol=1e-12)
    points = np.array(
        [[0.0, 0.0, ENTRY - 5.0], [3.0, 0.0, ENTRY + 10.0], [R_BEND + 40.0, 0.0, ENTRY + R_BEND]]
    )
    arc = ELBOW.arc_length(points)
    assert arc[0] == pytest.approx(ENTRY - 5.0, abs=1e-12)
    assert np.array_equal(arc, ELBOW.locate(points)[1])
    assert ENTRY < arc[1] < ENTRY + R_BEND * np.pi / 2 < arc[2]
