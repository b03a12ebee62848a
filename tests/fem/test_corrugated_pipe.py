"""The bellows-like wall (fem.corrugated_pipe.CorrugatedPipe): the cylinder at zero amplitude, C
against finite differences of the normal, the two principal curvatures at crests and troughs,
the foot against a dense sampling of the profile, bad input, the contact law's tangent, and a
free tile pressed into a crest."""

from dataclasses import replace

import numpy as np
import pytest
import skfem

from softcrawl.fem.contact_verification import convergence_order
from softcrawl.fem.corrugated_pipe import CorrugatedPipe
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.fem.structured import box
from tests.fem.tiles import assert_tangent_matches_differences, press_tile

CENTRE = np.array([1.0, 2.0, 3.0])
AXIS = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
SIDE = np.cross(AXIS, [0.0, 0.0, 1.0]) / np.linalg.norm(np.cross(AXIS, [0.0, 0.0, 1.0]))
# a 75 mm bellows (the paper's Fig. 26 diameter) with 2 mm deep, 10 mm long corrugations
BELLOWS = CorrugatedPipe(37.5, 2.0, 10.0, centre=tuple(CENTRE), axis=tuple(AXIS))


def at(z, theta, rho):
    """Points at axial coordinate z, angle theta and distance rho from the axis (oblique frame)."""
    other = np.cross(AXIS, SIDE)
    z, theta, rho = (np.atleast_1d(v)[:, None] for v in (z, theta, rho))
    return CENTRE + z * AXIS + rho * (np.cos(theta) * SIDE + np.sin(theta) * other)


def fd(surface, x, h=1e-6):
    """(-dn/dx, dg/dx) by central differences."""
    C = np.empty((x.shape[0], 3, 3))
    grad = np.empty((x.shape[0], 3))
    for j in range(3):
        step = np.zeros(3)
        step[j] = h
        (gp, n_p, _), (gm, n_m, _) = surface.project(x + step), surface.project(x - step)
        C[:, :, j] = -(n_p - n_m) / (2 * h)
        grad[:, j] = (gp - gm) / (2 * h)
    return C, grad


def test_zero_amplitude_is_the_cylinder():
    rng = np.random.default_rng(1)
    x = at(rng.uniform(-20, 20, 50), rng.uniform(0, 2 * np.pi, 50), rng.uniform(0.5, 40, 50))
    g, n, C = CorrugatedPipe(37.5, 0.0, 10.0, tuple(CENTRE), tuple(AXIS)).project(x)
    g2, n2, C2 = CylinderWall(37.5, tuple(CENTRE), tuple(AXIS)).project(x)
    assert np.allclose(g, g2, rtol=0, atol=1e-12) and np.allclose(n, n2, rtol=0, atol=1e-14)
    assert np.allclose(C, C2, rtol=0, atol=1e-15)


@pytest.mark.parametrize("where", ["crest", "trough", "flank", "random"])
def test_the_curvature_is_the_derivative_of_the_normal(where):
    """C = -dn/dx and dg/dx = n against central differences, from 0.5 mm past the wall to 1.2 mm
    inside it (max_gap 1.27 mm)."""
    rng = np.random.default_rng(2)
    z = {"crest": 0.0, "trough": 5.0, "flank": 2.5, "random": rng.uniform(-20, 20, 40)}[where]
    z = np.broadcast_to(z, 40)
    rho = BELLOWS.profile(z)[0] - rng.uniform(-0.5, 1.2, 40)
    x = at(z, rng.uniform(0, 2 * np.pi, 40), rho)
    g, n, C = BELLOWS.project(x)
    C_fd, grad = fd(BELLOWS, x)
    assert np.abs(C - C_fd).max() < 1e-7 * np.abs(C).max()
    assert np.abs(grad - n).max() < 1e-7
    assert np.allclose(C, np.swapaxes(C, 1, 2), atol=1e-15)


@pytest.mark.parametrize(
    "z, sign", [(0.0, 1.0), (5.0, -1.0), (-10.0, 1.0)], ids=["crest", "trough", "crest-2"]
)
def test_the_principal_curvatures_at_crests_and_troughs(z, sign):
    """At a crest of f (the wall farthest out: a pocket, concave from inside) kappa = h k^2 along
    the axis; at a trough kappa = -h k^2 (a ridge); around the axis 1 / f; n = -e_r."""
    k = 2 * np.pi / 10.0
    f = 37.5 + sign * 2.0
    x = at([z], [0.7], [f])
    g, n, C = BELLOWS.project(x)
    t = np.cross(AXIS, -n[0])
    assert abs(g[0]) < 1e-12
    assert np.allclose(C[0] @ AXIS, sign * 2.0 * k * k * AXIS, atol=1e-12)
    assert np.allclose(C[0] @ t, t / f, atol=1e-14)
    assert np.allclose(C[0] @ n[0], 0.0, atol=1e-14)


def test_the_foot_against_a_dense_sampling_of_the_profile():
    """The wall is a surface of revolution, so the nearest wall point lies in the point's meridian
    plane: the distance to a profile sampled every 2e-4 mm equals |g| within the sampling's reach
    (observed 3e-7 mm), for points near the wall, 3-30 mm from it and near the axis (the foot
    searched over many pitches: with 2 samples per pitch instead of 32 the search ends in the
    wrong basin, 0.1 mm off), inside and past the wall; g's sign says which side."""
    rng = np.random.default_rng(3)
    z = rng.uniform(-20, 20, 100)
    f = BELLOWS.profile(z)[0]
    rho = np.concatenate(
        [f[:30] - rng.uniform(-0.5, 3.0, 30), f[30:90] - rng.uniform(3.0, 30.0, 60), rng.uniform(0, 5, 10)]
    )
    g = BELLOWS.project(at(z, rng.uniform(0, 2 * np.pi, 100), rho))[0]
    zz = np.linspace(-70, 70, 700_001)
    ff = BELLOWS.profile(zz)[0]
    dmin = np.array([np.sqrt((zz - a) ** 2 + (ff - b) ** 2).min() for a, b in zip(z, rho)])
    assert np.abs(dmin - np.abs(g)).max() < 1e-6
    assert np.array_equal(g > 0, rho < BELLOWS.profile(z)[0])


@pytest.mark.parametrize(
    "kwargs, parameter",
    [
        ({"radius": 10.0, "amplitude": 10.0, "pitch": 5.0}, "contact.surface.amplitude"),
        ({"radius": 10.0, "amplitude": -1.0, "pitch": 5.0}, "contact.surface.amplitude"),
        ({"radius": 10.0, "amplitude": "deep", "pitch": 5.0}, "contact.surface.amplitude"),
        ({"radius": 10.0, "amplitude": 1.0, "pitch": 0.0}, "contact.surface.pitch"),
        ({"radius": 0.0, "amplitude": 1.0, "pitch": 5.0}, "contact.surface.radius"),
        ({"radius": 10.0, "amplitude": 1.0, "pitch": 5.0, "axis": (0, 0, 0)}, "contact.surface.axis"),
    ],
)
def test_bad_bellows_name_the_parameter(kwargs, parameter):
    with pytest.raises(SolverInputError) as info:
        CorrugatedPipe(**kwargs)
    assert info.value.parameter == parameter


def test_the_contact_laws_tangent_on_the_bellows_matches_finite_differences():
    rng = np.random.default_rng(4)
    z = rng.uniform(-20, 20, 60)
    x = at(z, rng.uniform(0, 2 * np.pi, 60), BELLOWS.profile(z)[0] + rng.normal(size=60) * 0.1)
    stick = x + rng.normal(size=x.shape) * 0.02
    assert_tangent_matches_differences(x, (BELLOWS, rng.uniform(0, 0.1, 60), stick, 10.0, 7.0, 0.4))


def test_a_free_tile_pressed_into_a_crest():
    """A 2 x 1 x 1 mm tile (the elbow case's) on the wall at a crest of the default-frame bellows,
    2 um into it, pressed by 0.4 N outwards and held by nothing else, frictionless: the crest is a
    pocket (concave both ways: radii 1.27 mm along the axis, 39.5 mm around it), so the tile stays;
    the contact balances the load and Newton converges quadratically (order 3.0 measured in the
    last increment)."""
    pipe = CorrugatedPipe(37.5, 2.0, 10.0)
    straight = box((2.0, 1.0, 1.0), (4, 2, 2))
    m2 = replace(skfem.MeshTet2.from_mesh(straight), _boundaries=straight.boundaries)
    xi, eta, zeta = m2.doflocs - np.array([1.0, 0.5, 0.0])[:, None]
    rho = pipe.profile(xi)[0] + 0.002 - zeta
    th = eta / 37.5
    mesh = replace(m2, doflocs=np.vstack([rho * np.cos(th), rho * np.sin(th), xi]))
    res, st, resultant, _ = press_tile(mesh, pipe, (0.4, 0.0, 0.0))
    assert res.converged, res.message
    assert st.active.mean() > 0.85  # 91.7 % measured: a few base points lift off the tight crest
    assert np.allclose(resultant, [-0.4, 0.0, 0.0], rtol=0, atol=1e-12)
    assert convergence_order(res.steps[-1].residuals) >= 1.8
