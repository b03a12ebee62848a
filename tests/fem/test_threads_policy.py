"""The threads policy of `fem.parallel` (docs/decisions/069-crawl-speed.md): N workers share the
cores for the assembly pool and MKL; the user's settings win; a spawned sweep worker sees them."""

from __future__ import annotations

import pytest

from softcrawl.fem import parallel


@pytest.mark.parametrize(("cores", "workers", "share"), [(2, 1, "2"), (2, 2, "1"), (2, 3, "1"), (8, 2, "4")])
def test_workers_share_the_cores(monkeypatch, cores, workers, share):
    monkeypatch.setattr(parallel, "cores", lambda: cores)
    for name in parallel.THREAD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    assert parallel.worker_env(workers) == dict.fromkeys(parallel.THREAD_VARIABLES, share)


def test_the_users_setting_is_kept(monkeypatch):
    monkeypatch.setattr(parallel, "cores", lambda: 2)
    monkeypatch.setenv("MKL_NUM_THREADS", "2")
    monkeypatch.delenv("SOFTCRAWL_THREADS", raising=False)
    monkeypatch.delenv("OMP_NUM_THREADS", raising=False)
    env = parallel.worker_env(2)
    assert env == {"SOFTCRAWL_THREADS": "1", "MKL_NUM_THREADS": "2", "OMP_NUM_THREADS": "1"}
