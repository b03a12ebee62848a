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
def test_the_inserted_foot_on_48_sectors_has_unstable_waves_at_the_mesh_scale(foot):
    """The frictionless insertion into the 60 mm pipe on the default mesh (48 sectors x 3 cells):
    unstable modes (9 measured, docs/decisions/068-squeezed-skirt.md), which Lanczos finds as the
    pivots count them; the lowest is the two-sectors-per-wave mode (24 lobes), alone, and the
    next come in degenerate cos / sin pairs (25, 26, ... lobes), so the count is odd; it sits at
    the back-tip corner; the skirt does not touch itself."""
    design, law = foot
    model = sm.build_model(sm.foot_mesh(design, 48, 3), law, design)
    res = sm.insert(model, design, Pipe(diameter=60.0), 8)
    assert res.converged
    st = sm.state_stability(model, res.x)
    assert st.n_unstable >= 1 and st.n_unstable % 2 == 1
    assert np.sum(st.eigenvalues < 0) == st.n_unstable  # Lanczos finds the pivots' count
    if st.n_unstable >= 3:
        assert st.eigenvalues[1] == pytest.approx(st.eigenvalues[2], rel=1e-6)
    lowest = sm.mode_field(model, st.modes[:, 0])
    assert int(np.argmax(sm.lobe_spectrum(model.nodes, lowest))) == 24
    corner = int(np.argmax(np.linalg.norm(lowest, axis=0)))
    assert np.hypot(*model.nodes[:2, corner]) == pytest.approx(design.tip_radius - 1.5, abs=0.01)  # B1
    assert sm.self_gap(model, res.x).gap > 1.0
    # by harmonic (docs/decisions/074-cyclic-stability.md): the same pivots, and the modes of L
    # lobes in harmonic 48 - L, the lowest in n = 24
    by_n, cs = sm.cyclic_state_stability(model, res.x, 48)
    assert (by_n.tangent.negative, by_n.pressure_block.negative) == (
        st.tangent.negative,
        st.pressure_block.negative,
    )
    unstable = [h.n for h in cs.harmonics if h.n_unstable]
    assert min(cs.harmonics, key=lambda h: h.eigenvalues[0]).n == 24
    assert unstable == list(range(24 - (st.n_unstable - 1) // 2, 25))
