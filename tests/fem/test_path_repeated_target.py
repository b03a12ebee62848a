"""A path whose first target repeats the start (a zero-length segment, as the workspace study's
paths from the unloaded state have) goes on to the next target; it used to stop with a
TypeError in the step memory (no direction stored for the zero-length segment)."""

from softcrawl.fem.path import load_path
from tests.fem.test_stiff_parts import _bar


def test_a_repeated_target_then_a_segment():
    model = _bar(dirichlet_top=False)
    res = load_path(model, [(0.0, 0.0), (0.0, 0.0), (0.0, 0.5)])
    assert res.converged, res.message
    assert [s.factor for s in res.steps] == [0.0, 0.0, 0.5]
