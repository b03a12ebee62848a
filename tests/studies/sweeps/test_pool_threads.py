"""Sweep workers start with the threads policy of `fem.parallel.worker_env` (decision 069); the
parent's environment is left as it was."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from softcrawl.fem import parallel
from softcrawl.fem.parallel import THREAD_VARIABLES, worker_env
from softcrawl.studies.sweeps.faults import WorkerReport
from softcrawl.studies.sweeps.pool import run_pool


def report_threads(spec_dict: dict, index: int, poll_s: float) -> WorkerReport:
    env = {name: os.environ.get(name) for name in THREAD_VARIABLES}
    Path(spec_dict["folder"], f"worker-{index}.json").write_text(json.dumps(env))
    return WorkerReport(completed=1)


@pytest.mark.parametrize("policy", ["greedy", "shared"])
def test_two_workers_start_with_the_policys_threads(tmp_path, monkeypatch, policy):
    for name in THREAD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setattr(parallel, "WORKER_POLICY", policy)
    monkeypatch.setenv("OMP_NUM_THREADS", "3")  # the user's: kept
    before = dict(os.environ)
    total, dead = run_pool(report_threads, {"folder": str(tmp_path)}, 2, 0.1)
    assert (total.completed, dead) == (2, [])
    expected = dict.fromkeys(THREAD_VARIABLES) | {"OMP_NUM_THREADS": "3"} | worker_env(2, policy)
    for index in range(2):
        assert json.loads((tmp_path / f"worker-{index}.json").read_text()) == expected
    assert dict(os.environ) == before
