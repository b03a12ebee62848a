"""The holds of the rigid-body modes carry no force once friction acts.

The quick one body in a vertical straight pipe, heading up (gravity -z), both skirts in Coulomb
contact: inserted frictionless with the six holds stiff, then friction on and the holds softened
(`studies.crawl_fe.pipe`), then its weight ramped on. The wall's axial friction must then carry
the weight and the holds ~nothing: their largest force below 1e-3 of the wall's axial friction.
With the holds left stiff (1e3 N/mm against the skirts' ~10 N/mm) they would take nearly all of
it, so the test fails if the release does not happen.

Kept small so that it runs on a shared machine: the pipe is 77 mm (0.5 mm on each 39 mm skirt
tip, one insertion step), and the body is the quick one shortened to 30 mm actuators without rings,
its skirts with 2 cells through the thickness and 5 mm along (70,398 displacement unknowns against
the quick body's 132,273): the same mesher, model and phases, whose holding does not depend on the
length. The 70 mm pipe's insertion of the quick body is in docs/decisions/076-one-body.md.
"""

import numpy as np
import pytest

from softcrawl.geometry.body_mesh import BodyMeshSettings
from softcrawl.geometry.design import EPSADesign, RobotDesign
from softcrawl.geometry.robot_mesh import RobotMeshSettings
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl_fe.mass import part_masses
from softcrawl.studies.crawl_fe.model import build_body
from softcrawl.studies.crawl_fe.pipe import into_pipe
from softcrawl.studies.robot_fe.model import G_MM_S2

SMALL = BodyMeshSettings(
    robot=RobotMeshSettings(n_around=12, n_radial=1, axial_size=10.0, web_size=6.0),
    sectors=36,
    thickness_layers=2,
    cell_size=5.0,
)


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_friction_holds_the_weight_and_the_holds_carry_nothing():
    setup = CrawlSetup(pipe_diameter=77.0)
    bm = build_body(
        setup, SMALL, gravity=(0.0, 0.0, -1.0), design=RobotDesign(n_rings=0, epsa=EPSADesign(length=30.0))
    )
    run = into_pipe(bm, insert_steps=1, load_steps=1)
    assert run.converged, run.message
    inserted, loaded = run.states[0], run.states[-1]
    assert min(inserted.normal.values()) > 0.1  # both skirts touch the wall
    weight = sum(p.mass_g for p in part_masses(bm.model.mesh, bm.materials)) * 1e-6 * G_MM_S2
    carried = loaded.wall_friction[2]
    assert carried == pytest.approx(weight, rel=0.01)  # the wall holds the weight (+z friction)
    assert max(abs(v) for v in loaded.holds.values()) < 1e-3 * abs(carried)
    assert np.hypot(*loaded.wall_friction[:2]) < 1e-3 * abs(carried)  # no lateral net friction
