"""A crawl from the cached insertion is the crawl with the insertion computed (issue 31).

`softcrawl crawl --quick --cycles 1 --mu-smooth 0.5 --mu-grooved 0.5 --insertion-cache` on one
thread twice with one empty cache: the first run computes the insertion and writes it, the second
reads it. On one thread a quick crawl is bit-identical run to run (stride 5.352028127835839 mm,
computed without the cache on 2026-11-28 with the symmetric-part solves of
docs/decisions/080-symmetric-part.md; the LU path's reference of docs/decisions/061-long-runs.md
was 5.352028349711552 mm, 2.2e-7 mm away, with the same 79 Newton iterations): both runs must
give that stride exactly, and the second's states.csv and cycles.csv must be the first's byte for byte (the
insertion's rows included, with their Newton counts). That the key ignores the friction, and
changes with every input of the insertion, is tested without a solve (test_insertion_cache.py).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.studies.sweeps.cli_runs import ROOT

pytestmark = [pytest.mark.slow, pytest.mark.timeout(7200)]

DETERMINISTIC = {"SOFTCRAWL_THREADS": "1", "MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
#: The friction is given: since docs/decisions/075-predict-crawl.md the default is the committed
#: identification's, and the reference below is the crawl at mu 0.5 of decisions 061 and 069.
ARGS = ["crawl", "--quick", "--cycles", "1", "--mu-smooth", "0.5", "--mu-grooved", "0.5"]
STRIDE_MM = 5.352028127835839  # the one-thread reference (module docstring)


def _crawl(out: Path, cache: Path, *extra: str) -> dict:
    env = os.environ | {"PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg", "SOFTCRAWL_CACHE": str(cache)}
    done = subprocess.run(
        [sys.executable, "-m", "softcrawl", *ARGS, "--out", str(out), *extra],
        env=env | DETERMINISTIC,
        capture_output=True,
        text=True,
        timeout=3600,
    )
    assert done.returncode == 0, done.stderr
    return json.loads((out / "summary.json").read_text())


def test_a_crawl_from_the_cached_insertion_is_the_computed_one(tmp_path):
    cache = tmp_path / "cache"
    cold = _crawl(tmp_path / "cold", cache, "--insertion-cache")
    warm = _crawl(tmp_path / "warm", cache, "--insertion-cache")
    assert (cold["insertion_cached"], warm["insertion_cached"]) == (False, True)
    assert len(list((cache / "insertions").glob("insertion-*"))) == 2  # the folder and its lock
    for name in ("states.csv", "cycles.csv"):
        assert (tmp_path / "warm" / name).read_bytes() == (tmp_path / "cold" / name).read_bytes(), name
    assert warm["strides_mm"] == cold["strides_mm"] == [STRIDE_MM]
    assert warm["newton_iterations"] == cold["newton_iterations"]  # the insertion's counted
