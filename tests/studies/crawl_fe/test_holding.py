"""The holds of the rigid-body modes carry no force once friction acts.

The quick one body in a vertical straight pipe, heading up (gravity -z), both skirts in Coulomb
contact: inserted frictionless with the six holds stiff, then friction on and the holds softened
(`studies.crawl_fe.pipe`), then its weight ramped on. The wall's axial friction must then carry
the weight and the holds ~nothing: their largest force below 1e-3 of the wall's axial friction.
With the holds left stiff (1e3 N/mm against the skirts' ~10 N/mm) they would take nearly all of
it, so the test fails if the release does not happen.

The pipe is 77 mm (0.5 mm on each 39 mm skirt tip) to keep the insertion to a few Newton
iterations; the 70 mm pipe's insertion is the record's measurement (docs/decisions/076-one-body.md).
"""

import numpy as np
import pytest

from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl_fe.mass import part_masses
from softcrawl.studies.crawl_fe.model import build_body
from softcrawl.studies.crawl_fe.pipe import into_pipe
from softcrawl.studies.robot_fe.model import G_MM_S2


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_friction_holds_the_weight_and_the_holds_carry_nothing():
    bm = build_body(CrawlSetup(pipe_diameter=77.0), "quick", gravity=(0.0, 0.0, -1.0))
    run = into_pipe(bm, insert_steps=2, load_steps=1)
    assert run.converged, run.message
    inserted, loaded = run.states[0], run.states[-1]
    assert min(inserted.normal.values()) > 0.1  # both skirts touch the wall
    weight = sum(p.mass_g for p in part_masses(bm.model.mesh, bm.materials)) * 1e-6 * G_MM_S2
    carried = loaded.wall_friction[2]
    assert carried == pytest.approx(weight, rel=0.01)  # the wall holds the weight (+z friction)
    assert max(abs(v) for v in loaded.holds.values()) < 1e-3 * abs(carried)
    assert np.hypot(*loaded.wall_friction[:2]) < 1e-3 * abs(carried)  # no lateral net friction
