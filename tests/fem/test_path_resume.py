"""`load_path` resumed from a `fem.path_cursor.PathCursor` written to and read back from a
`fem.checkpoint` folder: a column under a growing dead load, stopped after any converged sub-step,
ends where the uninterrupted path ends, with the same steps."""

import numpy as np
import pytest

from softcrawl.fem import path_cursor
from softcrawl.fem.checkpoint import Checkpoints
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.path import NewtonOptions, load_path
from tests.fem.test_stiff_parts import _bar

TARGETS = [(0.0, 0.4), (0.0, 1.0), (0.0, 1.5)]
OPTIONS = NewtonOptions(rigid_ratio=100.0)


def test_a_path_resumed_after_any_sub_step_ends_where_the_uninterrupted_path_ends(tmp_path):
    cursors = []
    full = load_path(_bar(dirichlet_top=False), TARGETS, options=OPTIONS, on_cursor=cursors.append)
    assert full.converged and len(cursors) >= 3
    assert any(0 < c.t < 1 for c in cursors) and any(c.t == 0 for c in cursors)  # mid-segment and between
    scale = np.abs(full.steps[-1].x).max()
    for k, cursor in enumerate(cursors):
        store = Checkpoints(tmp_path / f"c{k}", {"targets": TARGETS})
        store.save(1, *path_cursor.to_arrays(cursor))
        back = path_cursor.from_arrays(*store.load_latest())
        res = load_path(_bar(dirichlet_top=False), TARGETS, options=OPTIONS, start=back)
        assert res.converged, res.message
        assert [s.factor for s in res.steps] == [s.factor for s in full.steps]
        for a, b in zip(res.steps, full.steps):
            # the same states, within round-off (the resumed predictor factorises afresh)
            assert np.abs(a.x - b.x).max() <= 1e-10 * scale, f"resumed after sub-step {k}"
        assert res.stats.iterations >= full.stats.iterations - 1


def test_a_cursor_past_the_targets_is_refused():
    cursors = []
    load_path(_bar(dirichlet_top=False), TARGETS[:2], options=OPTIONS, on_cursor=cursors.append)
    with pytest.raises(SolverInputError, match="start"):
        load_path(_bar(dirichlet_top=False), TARGETS[:1], options=OPTIONS, start=cursors[-1])
