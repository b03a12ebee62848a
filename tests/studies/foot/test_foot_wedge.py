"""A wedge of the lone foot (`studies.foot.wedge` in `studies.foot.model`): what is refused before
any solve, and (slow) the quick foot at 70 mm on a quarter wedge against the whole foot."""

import pytest

from softcrawl.analytic.pipe import Pipe
from softcrawl.geometry.design import DesignError, FootDesign
from softcrawl.geometry.foot_revolved import mesh_foot_revolved
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.foot.model import run_foot
from softcrawl.studies.foot.simulate import simulate_foot

LAW = solid_law(get_material("rubber-70a"), hyperelastic_only=True)


def test_a_wedge_count_must_match_the_mesh():
    whole = mesh_foot_revolved(FootDesign(), n_theta=24).to_skfem(2)
    wedge = mesh_foot_revolved(FootDesign(), n_theta=24, copies=4).to_skfem(2)
    kw = {"mu_smooth": 0.3, "mu_grooved": 0.3}
    with pytest.raises(DesignError, match="copies"):
        run_foot(whole, LAW, FootDesign(), Pipe(diameter=70.0), copies=4, **kw)
    with pytest.raises(DesignError, match="copies"):
        run_foot(wedge, LAW, FootDesign(), Pipe(diameter=70.0), **kw)


@pytest.mark.parametrize(
    "kwargs", [{"wedge": 0}, {"wedge": 13}, {"wedge": 4, "flipped": True}, {"wedge": 4, "mesher": "tetwild"}]
)
def test_bad_wedges_are_refused_before_any_work(kwargs):
    with pytest.raises(DesignError, match="wedge"):
        simulate_foot(FootDesign(), 75.0, quick=True, **kwargs)


@pytest.mark.slow
def test_the_quarter_wedge_drags_as_the_whole_foot():
    """Quick foot, 70 mm, mu 0.3: insertion, forward and backward drags. Record 083 measured
    52.30031549 / 12.90883179 / 19.69594733 N on the quarter, the whole foot's to 6e-10 (record
    082's penalty tie: 52.300307 / 12.908830 / 19.695945 N, 1.6e-7 off)."""
    runs = [
        simulate_foot(FootDesign(), 70.0, quick=True, mu_smooth=0.3, mu_grooved=0.3, wedge=w) for w in (1, 4)
    ]
    whole, quarter = runs
    assert whole.converged and quarter.converged
    assert quarter.n_dofs < 0.3 * whole.n_dofs
    assert quarter.normal_force == pytest.approx(whole.normal_force, rel=1e-8)
    assert quarter.forward.peak == pytest.approx(whole.forward.peak, rel=1e-8)
    assert quarter.backward.peak == pytest.approx(whole.backward.peak, rel=1e-8)
    assert quarter.backward.flipped_at == whole.backward.flipped_at
