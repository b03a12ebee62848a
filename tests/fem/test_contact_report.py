"""Identities of `ContactTerm.report` at prescribed states, no solve (issue 32): the area of a 1 x 1
face pressed flat into a plane is 1 mm^2 in the reference, the same after a rigid shift and 1.44x
after a 1.2 x 1.2 in-plane stretch (Nanson: da = J F^-T N dA); the normal force is the pressure
integral; the mean pressure is force / area."""

from dataclasses import replace

import numpy as np
import pytest

from softcrawl.fem import contact_verification as cv
from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.model import SolidModel
from softcrawl.fem.rigid_surfaces import Plane
from softcrawl.fem.structured import box

PENALTY, DEPTH = 10.0, 0.05


def pressed(stretch: float = 1.0, shift=(0.0, 0.0)):
    """A unit cube whose bottom face z = 0 sits DEPTH into the plane z = 0 (uniform p_N = PENALTY *
    DEPTH), stretched in x and y by `stretch` and shifted in-plane by `shift`: its report."""
    model = SolidModel(
        box((1.0, 1.0, 1.0), (2, 2, 1)),
        cv.MATERIAL,
        contacts=[ContactSpec(("z0",), Plane(), penalty=PENALTY)],
    )
    term = model.contacts[0]
    X = term.space.nodes
    x = model.initial_state()
    u = np.zeros((3, X.shape[1]))
    u[0] = (stretch - 1.0) * X[0] + shift[0]
    u[1] = (stretch - 1.0) * X[1] + shift[1]
    u[2] = -DEPTH
    x[: model.n_u] = u.T.reshape(-1)
    return term.report(x)


def test_reference_area_force_and_mean_pressure_at_a_uniform_penetration():
    r = pressed()
    assert r.area_reference == pytest.approx(1.0, rel=1e-12)
    assert r.contact_fraction == pytest.approx(1.0, rel=1e-12)
    assert r.normal_force == pytest.approx(PENALTY * DEPTH * 1.0, rel=1e-12)
    assert r.max_pressure == pytest.approx(PENALTY * DEPTH, rel=1e-12)
    assert r.max_penetration == pytest.approx(DEPTH, rel=1e-12)
    np.testing.assert_allclose(r.normal_force_vector, [0.0, 0.0, PENALTY * DEPTH], atol=1e-12)
    np.testing.assert_allclose(r.facet_pressure, PENALTY * DEPTH, rtol=1e-12)
    np.testing.assert_allclose(r.facet_active, 1.0, rtol=1e-12)
    assert r.slip_fraction == 0.0 and r.mean_pressure == pytest.approx(r.normal_force / r.area_current)


def test_mean_pressure_is_force_over_current_area():
    r = pressed()
    assert r.mean_pressure == r.normal_force / r.area_current
    assert replace(r, area_current=0.0).mean_pressure == 0.0


def test_current_area_is_the_reference_area_under_a_rigid_shift():
    r = pressed(shift=(0.3, -0.2))
    assert r.area_current == pytest.approx(r.area_reference, rel=1e-9)
    assert r.mean_pressure == pytest.approx(PENALTY * DEPTH, rel=1e-9)


def test_current_area_follows_nanson_under_a_stretch():
    r = pressed(stretch=1.2)
    assert r.area_reference == pytest.approx(1.0, rel=1e-12)  # the reference area does not move
    assert r.area_current == pytest.approx(1.44 * r.area_reference, rel=1e-9)
    assert r.mean_pressure == pytest.approx(PENALTY * DEPTH / 1.44, rel=1e-9)


def test_reference_area_and_force_do_not_move_with_a_stretch():
    """The force is the integral over the reference face (p_N per reference area)."""
    r = pressed(stretch=1.2)
    assert r.area_reference == pytest.approx(1.0, rel=1e-12)
    assert r.normal_force == pytest.approx(PENALTY * DEPTH, rel=1e-12)


def test_half_the_face_in_contact_is_half_the_area():
    """A plane tilted about y touches only where x < 0.5: half the reference area, the force of
    the pressed half only."""
    model = SolidModel(
        box((1.0, 1.0, 1.0), (4, 2, 1)),
        cv.MATERIAL,
        contacts=[ContactSpec(("z0",), Plane(), penalty=PENALTY)],
    )
    term = model.contacts[0]
    x = model.initial_state()
    X = term.space.nodes
    u = np.zeros((3, X.shape[1]))
    u[2] = np.where(X[0] <= 0.5 + 1e-9, -DEPTH, 0.01)
    x[: model.n_u] = u.T.reshape(-1)
    r = term.report(x)
    assert r.contact_fraction == pytest.approx(0.5, abs=0.13)
    assert r.area_reference == pytest.approx(r.contact_fraction, rel=1e-12)
    assert 0 < r.normal_force < PENALTY * DEPTH
