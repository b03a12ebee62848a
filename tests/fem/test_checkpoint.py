"""`fem.checkpoint`: atomic states, pruning to the newest three, and one line that names the option
or the version when a run would resume a folder that is not its own."""

from __future__ import annotations

import errno

import numpy as np
import pytest

from softcrawl.fem import checkpoint
from softcrawl.fem.checkpoint import CheckpointError, Checkpoints

OPTIONS = {"pipe_diameter": 70.0, "cycles": 1, "gait": "inflate", "pressures": (0.0, 100.0)}


def _save(cp, i):
    return cp.save(
        i, {"x": np.arange(5.0) * i, "stick": np.ones((3, 2)) * i}, {"stage": f"s{i}", "t": 0.25 * i}
    )


def test_the_latest_state_reads_back_exactly_and_only_the_newest_three_are_kept(tmp_path):
    cp = Checkpoints(tmp_path / "ck", OPTIONS, version="1.0")
    assert cp.load_latest() is None  # a fresh run
    for i in range(1, 6):
        _save(cp, i)
    assert [p.name for p in cp.states()] == ["state-000003.npz", "state-000004.npz", "state-000005.npz"]
    meta, arrays = Checkpoints(tmp_path / "ck", dict(OPTIONS), version="1.0").load_latest()
    assert meta == {"stage": "s5", "t": 1.25}
    assert np.array_equal(arrays["x"], np.arange(5.0) * 5) and arrays["stick"].shape == (3, 2)


def test_a_write_cut_short_leaves_the_previous_state_whole(tmp_path, monkeypatch):
    cp = Checkpoints(tmp_path, OPTIONS, version="1.0")
    _save(cp, 1)

    def full_disk(handle, **arrays):
        handle.write(b"PK\x03\x04 half a zip")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(checkpoint.np, "savez", full_disk)
    with pytest.raises(OSError):
        _save(cp, 2)
    assert [p.name for p in tmp_path.iterdir() if p.suffix == ".npz"] == ["state-000001.npz"]
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary left
    monkeypatch.undo()
    assert cp.load_latest()[0]["stage"] == "s1"


@pytest.mark.parametrize(
    "options, version, named",
    [
        (OPTIONS | {"pipe_diameter": 65.0}, "1.0", "pipe_diameter = 70.0, this run has 65.0"),
        (OPTIONS | {"cycles": 2}, "1.0", "cycles = 1, this run has 2"),
        (
            {k: v for k, v in OPTIONS.items() if k != "gait"},
            "1.0",
            "gait = 'inflate', this run has '(not set)'",
        ),
        (OPTIONS, "1.1", "written by softcrawl 1.0, this is 1.1"),
    ],
)
def test_a_changed_option_or_version_refuses_to_resume_in_one_line(tmp_path, options, version, named):
    _save(Checkpoints(tmp_path, OPTIONS, version="1.0"), 1)
    with pytest.raises(CheckpointError) as info:
        Checkpoints(tmp_path, options, version=version).load_latest()
    assert info.value.parameter == "resume"
    assert named in str(info.value) and "\n" not in str(info.value), str(info.value)


def test_the_hash_depends_on_content_not_on_order_or_tuple_types():
    a = checkpoint.content_hash({"a": 1, "b": (1.0, 2.0)}, "1.0")
    assert a == checkpoint.content_hash({"b": [1.0, 2.0], "a": 1}, "1.0")
    assert a != checkpoint.content_hash({"a": 1, "b": (1.0, 2.0)}, "1.1")
