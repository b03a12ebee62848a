"""`studies.skirt.model`: the lobe count of a known wave, the carried axisymmetric state, the
seeded geometry, and (slow) the unstable count of the inserted foot on a coarse mesh."""

import numpy as np
import pytest

from softcrawl.analytic.pipe import Pipe
from softcrawl.geometry.design import FootDesign
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.skirt import model as sm


@pytest.mark.parametrize("n", [0, 3, 12, 26])
def test_the_lobe_count_of_a_circumferential_wave(n):
    theta = np.repeat(2 * np.pi * np.arange(96) / 96, 3)
    rho = np.tile([30.0, 32.0, 35.0], 96)
    z = np.tile([-5.0, -6.0, -8.0], 96)
    nodes = np.stack([rho * np.cos(theta), rho * np.sin(theta), z])
    wave = np.cos(n * theta + 0.3)
    u = np.stack([wave * np.cos(theta), wave * np.sin(theta), 0.2 * wave])  # radial and axial
    assert int(np.argmax(sm.lobe_spectrum(nodes, u))) == n


@pytest.fixture(scope="module")
def foot():
    design = FootDesign()
    law = solid_law(get_material("rubber-70a"), hyperelastic_only=True)
    return design, law


def test_an_axisymmetric_state_is_carried_exactly_to_more_sectors(foot):
    """A rigid-free axisymmetric field u_r = a rho z, u_z = b rho^2 on 24 sectors, carried to
    48: the vertices and the section's midsides take it exactly, the others the edge mean."""
    design, law = foot
    src = sm.build_model(sm.foot_mesh(design, 24, 3), law, design)
    dst = sm.build_model(sm.foot_mesh(design, 48, 3), law, design)

    def field(model):
        X = model.nodes
        rho = np.hypot(X[0], X[1])
        ur, uz = 1e-3 * rho * X[2], 2e-4 * rho**2
        x = model.initial_state()
        x[: model.n_u] = np.stack([ur * X[0] / rho, ur * X[1] / rho, uz]).T.reshape(-1)
        if model.n_p:
            x[model.n_u :] = 0.01 * rho[model.space.pressure_vertex]
        return x

    got = sm.map_axisymmetric(src, field(src), dst)
    want = dst.apply_dirichlet(field(dst), 0.0)
    n_v = dst.mesh.nvertices
    assert np.abs(got - want)[: 3 * n_v].max() < 1e-9
    assert np.abs(got - want)[dst.n_u :].max() < 1e-9
    assert np.abs(got - want)[: dst.n_u].max() < 0.05 * np.abs(want).max()  # edge means


def test_the_seeded_mesh_moves_its_nodes_by_the_amplitude(foot):
    design, _ = foot
    mesh = sm.foot_mesh(design, 24, 3)
    shape = np.zeros_like(np.asarray(mesh.doflocs))
    shape[2, 10] = 4.0
    shape[0, 20] = -2.0
    moved = sm.seeded_mesh(mesh, shape, 0.05)
    d = np.asarray(moved.doflocs) - np.asarray(mesh.doflocs)
    assert d[2, 10] == pytest.approx(0.05) and d[0, 20] == pytest.approx(-0.025)
    assert np.count_nonzero(d) == 2


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_the_inserted_foot_on_24_sectors_is_unstable_with_short_waves(foot):
    """The frictionless insertion into the 60 mm pipe on 24 sectors x 3 cells: the state has
    unstable modes (the count of docs/decisions/068-squeezed-skirt.md), the lowest one a wave of
    about one per two sectors, and the skirt does not touch itself."""
    design, law = foot
    model = sm.build_model(sm.foot_mesh(design, 24, 3), law, design)
    res = sm.insert(model, design, Pipe(diameter=60.0), 8)
    assert res.converged
    st = sm.state_stability(model, res.x)
    assert st.n_unstable > 0
    assert np.sum(st.eigenvalues < 0) == st.n_unstable  # Lanczos finds the pivots' count
    lobes = int(np.argmax(sm.lobe_spectrum(model.nodes, sm.mode_field(model, st.modes[:, 0]))))
    assert lobes >= 8
    assert sm.self_gap(model, res.x).gap > 0.1
