"""`fem.contact_law` point by point at prescribed positions (issue 32): the kink of the normal law,
the exact and rounded cones at their joints, the law's defaults (no smoothing, no band), the slip
flag's thresholds, a point at g = 0 with no pressure, and the friction of points out of contact.

Points lie DEPTH into the plane z = 0 (p_N = EPS_N DEPTH) with their stick points offset along x by
`s`: the trial traction is EPS_T s, so r = EPS_T s / (MU p_N) sets where each point is on the cone.
"""

import numpy as np
import pytest

from softcrawl.fem.contact_law import SLIP_MARGIN, committed_stick, cone, evaluate, normal_pressure
from softcrawl.fem.rigid_surfaces import Plane

EPS_N, EPS_T, MU, DEPTH = 10.0, 5.0, 0.4, 0.05
P = EPS_N * DEPTH  # 0.5 MPa
RADIUS = MU * P  # 0.2 MPa


def law(r, depth=DEPTH, mu=MU, with_tangent=False, **kw):
    """The law at points DEPTH deep whose trial traction is r (MU p_N), one point per r."""
    r = np.atleast_1d(np.asarray(r, float))
    x = np.zeros((r.size, 3))
    x[:, 2] = -depth
    stick = x.copy()
    stick[:, 0] -= r * RADIUS / EPS_T  # t* = -EPS_T (x - x_s) = -r RADIUS e_x
    return evaluate(x, Plane(), np.zeros(r.size), stick, EPS_N, EPS_T, mu, with_tangent, **kw)


def test_the_normal_kink_is_active_with_zero_pressure():
    p, dp, active = normal_pressure(np.array([-1.0, 0.0, 2.0]), 0.0)
    assert p.tolist() == [0.0, 0.0, 2.0] and dp.tolist() == [0.0, 1.0, 1.0]
    assert active.tolist() == [False, True, True]


def test_the_exact_cone_at_one_and_the_defaults_are_the_exact_laws():
    phi, dphi = cone(np.array([0.5, 1.0, 2.0]), 0.0)
    assert phi.tolist() == [0.5, 1.0, 1.0] and dphi.tolist() == [1.0, 1.0, 0.0]
    at_zero = evaluate(np.zeros((1, 3)), Plane(), np.zeros(1), np.zeros((1, 3)), EPS_N, EPS_T, 0.0, False)
    assert at_zero.pressure[0] == 0.0 and at_zero.active[0]  # no smoothing by default
    beyond = law(1.05)  # no band by default: the friction is mu p_N
    assert np.linalg.norm(beyond.friction[0]) == pytest.approx(RADIUS, rel=1e-12)


def test_the_stick_limit_carries_its_margin_and_no_more():
    st = law([1.0 + 0.5 * SLIP_MARGIN, 1.5])
    # within the margin: stuck, the trial traction itself; beyond: on the cone
    assert np.linalg.norm(st.friction[0]) == pytest.approx(RADIUS * (1 + 0.5 * SLIP_MARGIN), rel=1e-14)
    assert np.linalg.norm(st.friction[0]) > RADIUS
    assert np.linalg.norm(st.friction[1]) == pytest.approx(RADIUS, rel=1e-14)
    assert st.friction[:, 0] == pytest.approx(-np.linalg.norm(st.friction, axis=1))  # against the offset


def test_the_slip_flag_is_full_slip_beyond_the_band_and_the_margin():
    st = law([0.5, 1.0 + 0.5 * SLIP_MARGIN, 1.0 + 2 * SLIP_MARGIN, 1.5])
    assert st.slip.tolist() == [False, False, True, True] and st.slip.dtype == bool
    band = law([0.85, 1.05, 1.1 * (1 + 0.5 * SLIP_MARGIN), 1.15], slip_band=0.2)
    assert band.slip.tolist() == [False, False, False, True]
    # on the band, below the Coulomb limit by phi(r) = r - (r - 1 + w/2)^2 / (2 w)
    assert np.linalg.norm(band.friction[1]) == pytest.approx(RADIUS * (1.05 - 0.15**2 / 0.4), rel=1e-12)


def test_without_friction_or_contact_there_is_no_friction():
    st = law([0.5, 2.0], mu=0.0, with_tangent=False)
    assert np.array_equal(st.trial, np.zeros((2, 3))) and np.array_equal(st.friction, np.zeros((2, 3)))
    assert st.slip.tolist() == [False, False] and st.stiffness is None
    many = law(np.linspace(0.1, 2.0, 5), mu=0.0)
    assert many.slip.shape == (5,)
    out = law([0.5, 2.0], depth=-0.1)  # 0.1 above the plane, stick points offset: no contact
    assert np.array_equal(out.friction, np.zeros((2, 3))) and not out.active.any()


def test_a_point_at_zero_gap_has_only_the_normal_and_the_slip_normal_stiffness():
    """g = 0: active with p_N = 0, so the Coulomb radius is 0 and the point is on the cone with
    r = inf (phi = 1, phi' = 0): K = eps_N n n + mu eps_N m n^T (m the trial direction)."""
    x = np.zeros((1, 3))
    stick = np.array([[-0.5 / EPS_T, 0.0, 0.0]])  # |t*| = 0.5, r would be 0.5 at a unit radius
    st = evaluate(x, Plane(), np.zeros(1), stick, EPS_N, EPS_T, MU, True)
    n, m = np.array([0.0, 0.0, 1.0]), np.array([-1.0, 0.0, 0.0])
    assert st.pressure[0] == 0.0 and st.active[0]
    assert st.stiffness[0] == pytest.approx(EPS_N * np.outer(n, n) + MU * EPS_N * np.outer(m, n), abs=1e-12)


def test_the_slip_flag_is_boolean_without_friction_too():
    assert law([0.5, 2.0], mu=0.0).slip.dtype == bool


def test_commit_returns_a_small_slide_to_the_cone():
    """A slide whose trial traction is under 1 MPa: the stored point is mu p_N / eps_T behind x,
    along the unit slip direction (not the traction itself)."""
    st = law([3.0])  # |t*| = 0.6 MPa, radius 0.2 MPa
    x = np.array([[0.0, 0.0, -DEPTH]])
    stick = x - np.array([[3.0 * RADIUS / EPS_T, 0.0, 0.0]])
    new = committed_stick(st, x, stick, EPS_T, MU)
    assert new[0] == pytest.approx([-RADIUS / EPS_T, 0.0, -DEPTH], rel=1e-12)
