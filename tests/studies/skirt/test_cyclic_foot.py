"""fem.cyclic on the revolved foot (24 sectors, 2 cells through the skirt): at a cyclic state with
unstable modes (no displacement, a uniform compressive mixed pressure of 0.03 mu, whose geometric
stiffness buckles the skirt) the count by harmonic equals `fem.stability`'s count on the whole
tangent, pivot for pivot, and the harmonics that hold the unstable modes are the lobe counts
`lobe_spectrum` finds in the whole tangent's modes."""

import numpy as np
import pytest

from softcrawl.geometry.design import FootDesign
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.skirt import model as sm
from softcrawl.studies.skirt import runs

SECTORS = 24
P_OVER_MU = -0.03


@pytest.fixture(scope="module")
def foot_state():
    design = FootDesign()
    law = solid_law(get_material("rubber-70a"), hyperelastic_only=True)
    model = sm.build_model(sm.foot_mesh(design, SECTORS, 2), law, design)
    x = model.initial_state()
    x[model.n_u :] = P_OVER_MU * float(np.max(model.mu))
    whole = sm.state_stability(model, x)
    by_harmonic = sm.cyclic_state_stability(model, x, SECTORS)
    return model, whole, by_harmonic, x, design


def test_the_count_by_harmonic_is_the_whole_tangents(foot_state):
    _, whole, (st, cs), _, _ = foot_state
    assert whole.n_unstable > 4  # the state is a real test: several unstable modes
    assert (st.tangent.positive, st.tangent.negative) == (whole.tangent.positive, whole.tangent.negative)
    assert st.pressure_block.negative == whole.pressure_block.negative
    assert st.n_unstable == whole.n_unstable
    assert cs.circulant_error < 1e-12
    k = whole.n_unstable
    np.testing.assert_allclose(st.eigenvalues[:k], whole.eigenvalues[:k], rtol=1e-6)


def test_the_unstable_harmonics_are_the_lobe_counts_of_the_whole_tangents_modes(foot_state):
    model, whole, (_, cs), _, _ = foot_state

    def harmonic(lobes):
        r = lobes % SECTORS
        return min(r, SECTORS - r)

    lobes = [
        int(np.argmax(sm.lobe_spectrum(model.nodes, sm.mode_field(model, whole.modes[:, i]))))
        for i in range(whole.n_unstable)
    ]
    expected = sorted(h.n for h in cs.harmonics for _ in range(h.multiplicity * h.n_unstable))
    assert sorted(harmonic(n) for n in lobes) == expected


def test_the_study_describes_a_state_by_harmonic(foot_state):
    model, whole, _, x, design = foot_state
    row = runs.describe_state(model, x, design, cyclic_sectors=SECTORS)
    assert row["counter"] == "by harmonic"
    assert row["n_unstable"] == whole.n_unstable
    per_n = {int(n): k for n, k in row["unstable_by_harmonic"].items()}
    assert sum(k * (1 if n in (0, SECTORS // 2) else 2) for n, k in per_n.items()) == whole.n_unstable
    assert len(row["lowest_by_harmonic"]) == SECTORS // 2 + 1
    assert row["lowest_eigenvalues"][0] == pytest.approx(min(row["lowest_by_harmonic"]))


class _Contact:
    multiplier = None
    surface = None

    def set_surface(self, surface):
        self.surface = surface


class _Model:
    contacts = (_Contact(), _Contact())


def test_a_kept_state_is_read_back_with_its_contact_multipliers_and_wall(tmp_path):
    kept = runs.Settled(True, "ok", 6, np.arange(5.0), 12.5, 100.0)
    source = _Model()
    source.contacts[0].multiplier, source.contacts[1].multiplier = np.ones(3), np.full(4, 2.0)
    runs.keep_state(tmp_path / "S96-C6.npz", kept, source)
    model = type("M", (), {"contacts": (_Contact(), _Contact())})()
    pipe = type("P", (), {"radius": 30.0})()
    got = runs.carried_state(96, 6, model, None, None, pipe, {}, tmp_path)  # nothing to compute with
    assert got.reused and got.converged and got.newton_iterations == 6 and got.wall_s == 12.5
    np.testing.assert_array_equal(got.x, kept.x)
    np.testing.assert_array_equal(model.contacts[1].multiplier, np.full(4, 2.0))
    assert model.contacts[0].surface.radius == 30.0
