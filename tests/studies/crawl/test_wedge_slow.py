"""The quick crawl on a quarter wedge of the feet against the whole feet (`studies.foot.wedge`,
docs/decisions/082-crawl-wedge.md, 083-exact-wedge.md): one inflate cycle at 70 mm, mu 0.5, state by state.

Slow (about 100 s idle): `python -m pytest -m slow tests/studies/crawl/test_wedge_slow.py`.
"""

import pytest

from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.crawl.mesh import QUICK_SECTORS, crawl_mesh
from softcrawl.studies.crawl.model import CrawlSetup, build, run_crawl
from softcrawl.studies.crawl.schedule import preset

pytestmark = pytest.mark.slow


def _crawl(copies):
    setup = CrawlSetup(insert_steps=4, steps=4, cycles=1, sectors=QUICK_SECTORS, copies=copies)
    design, mesh = crawl_mesh(setup.mirrored, foot=setup.foot, **setup.mesh_options())
    cm = build(mesh, solid_law(get_material(setup.material), hyperelastic_only=True), design, setup)
    res = run_crawl(cm, preset("inflate", 100.0, 2.0))
    assert res.converged, res.message
    return res


def test_the_quarter_wedge_crawls_as_the_whole_feet():
    whole, wedge = _crawl(1), _crawl(4)
    assert wedge.n_dofs < 0.3 * whole.n_dofs
    # exact tie: 4.8e-7 mm on the 5.352 mm stride (record 083; 082's penalty tie left 5.4e-6)
    assert wedge.strides[0] == pytest.approx(whole.strides[0], abs=2e-6)
    assert len(wedge.states) == len(whole.states)
    for a, b in zip(wedge.states, whole.states):
        for key in ("rear_normal_n", "front_normal_n", "actuator_force_n"):
            assert a[key] == pytest.approx(b[key], rel=1e-6, abs=1e-5), (a["stage"], key)  # 8.5e-7 N
        for key in ("rear_u_mm", "front_u_mm", "rear_tip_lead_mm"):
            assert a[key] == pytest.approx(b[key], abs=5e-6), (a["stage"], key)  # 1.1e-6 mm
