"""The threads policy of `fem.parallel` (docs/decisions/069-crawl-speed.md): greedy workers take
what a lone process takes, shared ones split the cores; the user's settings win."""

from __future__ import annotations

import pytest

from softcrawl.fem import parallel


@pytest.mark.parametrize(("cores", "workers", "share"), [(2, 1, "2"), (2, 2, "1"), (2, 3, "1"), (8, 2, "4")])
def test_shared_workers_share_the_cores(monkeypatch, cores, workers, share):
    monkeypatch.setattr(parallel, "cores", lambda: cores)
    for name in parallel.THREAD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    assert parallel.worker_env(workers, "shared") == dict.fromkeys(parallel.THREAD_VARIABLES, share)


def test_greedy_workers_take_what_a_lone_process_takes(monkeypatch):
    for name in parallel.THREAD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    assert parallel.worker_env(2, "greedy") == {}  # the lone process's defaults: nothing set
    with pytest.raises(ValueError, match="policy"):
        parallel.worker_env(2, "all")


def test_the_users_setting_is_kept(monkeypatch):
    monkeypatch.setattr(parallel, "cores", lambda: 2)
    monkeypatch.setenv("MKL_NUM_THREADS", "2")
    monkeypatch.delenv("SOFTCRAWL_THREADS", raising=False)
    monkeypatch.delenv("OMP_NUM_THREADS", raising=False)
    assert parallel.worker_env(2, "shared") == {"SOFTCRAWL_THREADS": "1", "OMP_NUM_THREADS": "1"}
