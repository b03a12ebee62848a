"""`fem.chamber` at prescribed states, no solve: the cavity volume, its load vector q = dV/du and
the tangent dq/du (issue 32: the chamber's reported volume and load guarded line by line).

* Volume: the enclosed volume is a surface integral of x . n da; under a homogeneous deformation
  x = F X it is det F times the reference volume exactly, also for the discretised surface (the
  P2 geometry maps affinely). A diagonal F keeps the octant's symmetry planes (through the
  origin) in place, so their flux stays zero and needs no weight. The reference volume of the P2
  octant of a sphere of radius a is pi a^3 / 6 to the surface's interpolation error.
* Cut-plane weights: a plane-strain quarter tube, w = (1, 1, 0), has the volume pi a^2 h / 4 of
  its cavity; with w = (1, 1, 1) the cap z = h adds its flux h * (area) / 3 and the volume is
  wrong: the weights are what removes it.
* q against central differences of the volume; dq/du against central differences of q.
"""

import math

import numpy as np
import pytest

from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import ChamberSpec, SolidModel
from softcrawl.fem.reference_models import MU
from softcrawl.fem.structured import curved, sphere_octant, tube_sector

A = 5.0


@pytest.fixture(scope="module")
def octant():
    mesh = sphere_octant(A, 7.5, n_radial=1, n_surface=3)
    return SolidModel(mesh, NeoHookean.nearly_incompressible(MU, 1000.0), chambers=ChamberSpec(("inner",)))


def homogeneous(model, F) -> np.ndarray:
    x = model.initial_state()
    X = model.space.nodes
    x[: model.n_u] = ((np.asarray(F) - np.eye(3)) @ X).T.ravel()
    return x


def wavy(model, seed=0) -> np.ndarray:
    """A smooth, non-affine displacement of a few percent that keeps the symmetry planes
    (u_i = X_i g_i(X): no normal motion on X_i = 0)."""
    x = model.initial_state()
    X = model.space.nodes
    k = np.random.default_rng(seed).uniform(0.1, 0.3, 3)
    g = np.stack([np.sin(k[0] * X[1] + 1), np.cos(k[1] * X[2]), np.sin(k[2] * X[0] + 2)])
    x[: model.n_u] = (0.05 * X * g).T.ravel()
    return x


def in_plane(model, d: np.ndarray) -> np.ndarray:
    """d without its normal component on the symmetry planes (a closed-chamber variation)."""
    u = d[: model.n_u].reshape(-1, 3)
    u[np.abs(model.space.nodes.T) < 1e-9] = 0.0
    return d


def test_volume_of_the_reference_octant_and_under_a_homogeneous_stretch(octant):
    V0 = octant.chamber_volume(octant.initial_state())
    assert V0 == pytest.approx(math.pi * A**3 / 6, rel=2e-3)
    for F in (np.diag([1.2, 0.9, 1.1]), np.diag([1.0, 1.0, 1.5])):
        assert octant.chamber_volume(homogeneous(octant, F)) == pytest.approx(
            np.linalg.det(F) * V0, rel=1e-12
        )


def test_cut_plane_weights_drop_the_flux_of_the_cap():
    h = 2.0
    mesh = curved(tube_sector(A, 3 * A, height=h, n_radial=2, n_angle=6, quadratic=False), "cylinder")
    law = NeoHookean.nearly_incompressible(MU, 1000.0)
    cut = SolidModel(mesh, law, chambers=ChamberSpec(("inner",), (1.0, 1.0, 0.0)))
    x0 = cut.initial_state()
    exact = math.pi * A**2 * h / 4
    assert cut.chamber_volume(x0) == pytest.approx(exact, rel=2e-3)
    # a stretch along the cut axis only: the cavity grows with it (the weights keep x, y fluxes)
    assert cut.chamber_volume(homogeneous(cut, np.diag([1.0, 1.0, 1.3]))) == pytest.approx(
        1.3 * cut.chamber_volume(x0), rel=1e-12
    )
    full = SolidModel(mesh, law, chambers=ChamberSpec(("inner",), (1.0, 1.0, 1.0)))
    # sum(w) = 3 instead of 2 and no z flux on the open cylinder: 2/3 of the volume
    assert full.chamber_volume(x0) == pytest.approx(2 / 3 * cut.chamber_volume(x0), rel=1e-12)


def test_load_vector_is_the_derivative_of_the_volume(octant):
    x = wavy(octant)
    q = octant.pressure_load(x)
    rng = np.random.default_rng(1)
    for _ in range(3):
        d = np.zeros_like(x)
        d[: octant.n_u] = rng.standard_normal(octant.n_u)
        d = in_plane(octant, d)
        eps = 1e-6
        fd = (octant.chamber_volume(x + eps * d) - octant.chamber_volume(x - eps * d)) / (2 * eps)
        assert q @ d == pytest.approx(fd, rel=1e-6)
    # only the chamber's element dofs carry load, and P q is the pressure force
    assert octant.pressure_force(x, 0.25) == pytest.approx(0.25 * q, rel=1e-15, abs=0)


def test_facet_tangent_matches_central_differences_of_the_facet_load(octant):
    x = wavy(octant, seed=2)
    chamber = octant.chambers[0]
    q, dq = chamber.load(x, True)
    q_only, none = chamber.load(x, False)
    assert none is None and np.array_equal(q, q_only)
    rng = np.random.default_rng(3)
    eps = 1e-6
    for f in rng.choice(q.shape[1], 4, replace=False):
        for b in rng.choice(30, 6, replace=False):
            e = np.zeros_like(x)
            e[chamber.u_dofs[b, f]] = eps
            fd = (chamber.load(x + e, False)[0][:, f] - chamber.load(x - e, False)[0][:, f]) / (2 * eps)
            assert dq[f, :, b] == pytest.approx(fd, rel=1e-5, abs=1e-9 * np.abs(dq[f]).max())


def test_an_unknown_chamber_tag_is_an_error_naming_the_chamber():
    from softcrawl.fem.errors import SolverInputError

    mesh = sphere_octant(A, 7.5, n_radial=1, n_surface=2)
    with pytest.raises(SolverInputError) as err:
        SolidModel(mesh, NeoHookean.nearly_incompressible(MU, 1000.0), chambers=ChamberSpec(("cavity",)))
    assert err.value.parameter == "chamber" and "unknown boundary tag 'cavity'" in err.value.detail
