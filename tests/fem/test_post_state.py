"""`fem.post` at prescribed states, no solve (issue 32: the reported length, radius and pressure
guarded line by line).

A quarter tube (inner A, outer B, height H, n_height layers) is given prescribed displacements:
a rigid shift, a homogeneous stretch, and a radial expansion growing with z, rho -> rho (1 + a z / H).
Then, exactly:
* actuator length (mean z of the top face minus that of the bottom face) = stretch x H, for any
  shift (the default tags are the ePSA's `end_bottom` and `end_top`);
* outer radius at z_ref = B (1 + a z_ref / H), for a quarter arc shifted off the axis (the circle
  fit finds its centre) and for a layer of 3 nodes (the least a circle fit needs); a layer of 2
  nodes is measured from the axis;
* the Kasa circle centre of points on a circle is its centre;
* the element pressure is -tr(sigma) / 3 of the element's Cauchy stress.
"""

from dataclasses import replace

import numpy as np
import pytest

from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import SolidModel
from softcrawl.fem.post import actuator_length, circle_centre, element_fields, outer_radius_at
from softcrawl.fem.structured import tube_sector

A, B, H = 3.0, 9.0, 4.0


def tube(n_angle=3, n_height=4):
    mesh = tube_sector(A, B, height=H, n_radial=1, n_angle=n_angle, n_height=n_height)
    bnd = dict(mesh.boundaries)
    mesh = replace(mesh, _boundaries={**bnd, "end_bottom": bnd["bottom"], "end_top": bnd["top"]})
    return SolidModel(mesh, NeoHookean.nearly_incompressible(0.03, 30.0))


def state(model, u_of_X) -> np.ndarray:
    x = model.initial_state()
    x[: model.n_u] = u_of_X(model.nodes).T.ravel()
    return x


def shift(t):
    return lambda X: np.broadcast_to(np.asarray(t, float)[:, None], X.shape)


def flare(a, t=(0.0, 0.0, 0.0)):
    """rho -> rho (1 + a Z / H), then a shift t."""
    return lambda X: np.vstack([X[:2] * (a * X[2] / H), np.zeros_like(X[2])]) + np.asarray(t, float)[:, None]


@pytest.fixture(scope="module")
def model():
    return tube()


def test_actuator_length_with_the_default_end_tags(model):
    assert actuator_length(model, model.initial_state()) == pytest.approx(H)
    assert actuator_length(model, state(model, shift((1.0, -2.0, 7.0)))) == pytest.approx(H)
    stretch = state(model, lambda X: np.vstack([0 * X[:2], 0.3 * X[2] + 7.0]))
    assert actuator_length(model, stretch) == pytest.approx(1.3 * H)
    assert actuator_length(model, stretch, bottom="bottom", top="top") == pytest.approx(1.3 * H)


@pytest.mark.parametrize("t", [(0.0, 0.0, 0.0), (3.0, -2.0, 0.5)])
def test_outer_radius_of_each_layer_of_a_flared_shifted_arc(model, t):
    x = state(model, flare(0.2, t))
    for z_ref in (0.0, 1.0, 2.5, H):  # layers at 0, 0.5, ..., 4 (P2): every z_ref hits one
        assert outer_radius_at(model, x, z_ref) == pytest.approx(B * (1 + 0.2 * z_ref / H), rel=1e-12)
    # between layers: the nearest one (z_ref 2.6 -> the layer at 2.5)
    assert outer_radius_at(model, x, 2.6) == pytest.approx(B * (1 + 0.2 * 2.5 / H), rel=1e-12)


def test_outer_radius_of_a_three_node_layer_is_fitted_and_of_a_two_node_layer_is_from_the_axis():
    m = tube(n_angle=1, n_height=1)  # a vertex layer: 2 corners + 1 midside; mid-height: 2 midsides
    assert m.boundary_nodes("outer")[np.abs(m.nodes[2, m.boundary_nodes("outer")]) < 1e-12].size == 3
    x = state(m, shift((3.0, -2.0, 0.0)))
    assert outer_radius_at(m, x, 0.0) == pytest.approx(B, rel=1e-12)
    mid = outer_radius_at(m, m.initial_state(), H / 2)
    assert mid == pytest.approx(B, rel=1e-12)


def test_circle_centre_of_an_arc():
    th = np.linspace(0.2, 1.1, 7)
    xy = np.vstack([3.0 + 5.0 * np.cos(th), -2.0 + 5.0 * np.sin(th)])
    assert circle_centre(xy) == pytest.approx([3.0, -2.0], abs=1e-10)


def test_element_pressure_is_minus_the_mean_normal_stress(model):
    x = state(model, lambda X: 0.1 * np.vstack([X[0], 0.5 * X[1], -0.3 * X[2]]))
    x[model.n_u :] = 0.02  # the mixed (P1) pressure field: the hydrostatic stress
    f = element_fields(model, x)
    assert f.pressure == pytest.approx(-np.einsum("kke->e", f.cauchy) / 3, rel=1e-12, abs=0)
    assert np.abs(f.pressure).min() > 1e-3
    assert f.jacobian == pytest.approx(1.1 * 1.05 * 0.97, rel=1e-12)


def stub(points):
    """A model stub: `outer_radius_at` reads only the tagged nodes, their positions and x's displacement."""
    from types import SimpleNamespace

    nodes = np.asarray(points, float).T
    return SimpleNamespace(
        nodes=nodes,
        boundary_nodes=lambda tag: np.arange(nodes.shape[1]),
        displacement=lambda x: np.zeros_like(nodes),
    )


def test_outer_radius_layer_tolerance_and_a_two_node_layer():
    """The layer is the nodes within 1e-9 max(1, |z_ref|) of the nearest (that bound included); a
    layer of two nodes is measured from the axis (no circle through two points)."""
    two = stub([(B, 0.0, 0.0), (0.0, 2 * B, 0.0), (5 * B, 0.0, 3.0)])
    assert outer_radius_at(two, None, 0.0) == pytest.approx(1.5 * B, rel=1e-12)
    # at z_ref = 0: a node 1e-9 off is in the layer, one 1.5e-9 off is not
    near = stub([(B, 0.0, 0.0), (0.0, 3 * B, 1e-9), (0.0, 7 * B, 1.5e-9)])
    assert outer_radius_at(near, None, 0.0) == pytest.approx(2 * B, rel=1e-12)
    # at z_ref = 100: the tolerance grows to 1e-7
    far = stub([(B, 0.0, 100.0), (0.0, 3 * B, 100.0 + 5e-8), (0.0, 9 * B, 100.0 + 2e-7)])
    assert outer_radius_at(far, None, 100.0) == pytest.approx(2 * B, rel=1e-12)
