"""The crawl's checks that can fail (issue 17), on the whole two-feet model: 10-25 minutes each on
a loaded 2-core machine, so all slow. One cycle, insertion in 4 steps, 4 sub-steps per segment, 70 mm pipe,
the inflate schedule at 100 kPa, mu = 0.5 on both faces (FOOT_FRICTION).

- symmetric feet (rear foot as on the robot, front foot mirrored: the pair is symmetric under
  z -> -z about the centre, same mu on both faces) do not advance: |stride| below 1 % of the
  actuator's motion in the cycle (the noise of a solver tolerance and a non-symmetric
  pytetwild mesh is far below that);
- the paper's feet advance forward, mirrored feet (--backward) advance backward;
- at every converged state after insertion the wall's axial friction forces and the ground
  springs' forces sum to zero within 1e-6 of the largest friction force (Newton tolerance), and
  the ground springs carry less than 1e-3 of it;
- the stride changes by less than 5 % between 4 and 8 sub-steps per schedule segment.
"""

import functools

import numpy as np
import pytest

pytestmark = pytest.mark.slow


@functools.cache
def _crawl(feet: str, steps: int = 4, cycles: int = 1):
    from studies.catalogue.contact_studies import _material
    from studies.parts.crawl_mesh import crawl_mesh
    from studies.parts.crawl_model import CrawlSetup, build, run_crawl
    from studies.parts.crawl_schedule import preset

    setup = CrawlSetup(pipe_diameter=70.0, feet=feet, insert_steps=4, steps=steps, cycles=cycles)
    design, mesh = crawl_mesh(setup.mirrored)
    cm = build(mesh, _material({"material": "rubber-70a"}), design, setup)
    return run_crawl(cm, preset("inflate"))


def _check_balance(res):
    assert res.converged, res.message
    assert res.momentum_max_n < 1e-6 * res.friction_max_n
    assert res.ground_max_n < 1e-3 * res.friction_max_n


def test_symmetric_feet_do_not_advance():
    res = _crawl("symmetric")
    _check_balance(res)
    deltas = [s["delta_mm"] for s in res.states if s["cycle"] > 0]
    swing = max(deltas) - min(deltas)
    assert swing > 0.5  # the actuators moved the feet apart (1.16 mm seen)
    assert abs(res.strides[0]) < 0.01 * swing


def test_paper_feet_advance_forward_and_mirrored_feet_backward():
    fwd, bwd = _crawl("paper"), _crawl("backward")
    _check_balance(fwd)
    _check_balance(bwd)
    assert fwd.strides[0] > 0.5
    assert bwd.strides[0] < -0.5


def test_stride_converges_in_the_step_size():
    coarse, fine = _crawl("paper", 4), _crawl("paper", 8)
    _check_balance(fine)
    assert abs(fine.strides[0] - coarse.strides[0]) < 0.05 * abs(fine.strides[0])
    assert np.isfinite(fine.strides[0])
