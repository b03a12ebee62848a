"""`softcrawl robot --resume` after kill -9 (issue 30): the quick robot mesh (42,034 DOFs) along a
sequential path of six pressure targets, killed once the third converged sub-step is on disk
(OUT/checkpoints/state-000003.npz), resumed, ends with the states.csv and VTU series of an
uninterrupted run. Two uninterrupted runs are compared first (their spread is printed, pytest -s);
every number within RTOL of its column's largest magnitude (the Newton tolerance's order)."""

from __future__ import annotations

import csv
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from tests.studies.sweeps.cli_runs import ROOT

pytestmark = [pytest.mark.slow, pytest.mark.timeout(3600)]

ARGS = ["robot", "--first", "0,20,30", "--pressures", "0,40,60", "--steps", "3", "--mesh", "quick"]
RTOL = 1e-6


def _start(out: Path, *extra: str) -> subprocess.Popen:
    env = os.environ | {"PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    return subprocess.Popen(
        [sys.executable, "-m", "softcrawl", *ARGS, "--out", str(out), *extra],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )


def _compare(out: Path, ref: Path) -> float:
    """The largest difference of a states.csv number, relative to its column's largest magnitude."""
    with open(out / "states.csv") as fa, open(ref / "states.csv") as fb:
        a, b = list(csv.DictReader(fa)), list(csv.DictReader(fb))
    assert len(a) == len(b) == 6
    worst = 0.0
    for key in a[0]:
        if key == "material":
            assert {r[key] for r in a} == {r[key] for r in b}
            continue
        x, y = np.array([float(r[key]) for r in a]), np.array([float(r[key]) for r in b])
        scale = max(float(np.nanmax(np.abs(y))), 1e-12)
        assert np.array_equal(np.isnan(x), np.isnan(y)), key
        diff = float(np.nanmax(np.abs(x - y)))
        assert diff <= RTOL * scale, f"{key}: {diff:.3g} against {scale:.3g}"
        worst = max(worst, diff / scale)
    assert sorted(p.name for p in (out / "vtu").glob("robot_*.vtu")) == [
        f"robot_{k:03d}.vtu" for k in range(6)
    ]
    assert not (out / "checkpoints").exists()
    return worst


def test_kill_9_mid_path_then_resume_gives_the_uninterrupted_states(tmp_path):
    refs = [tmp_path / "run1", tmp_path / "run2"]
    for proc in [_start(r) for r in refs]:
        assert proc.wait(timeout=1800) == 0, proc.stderr.read()
    print(f"\nrobot: spread of two uninterrupted runs {_compare(refs[1], refs[0]):.3g}")
    out = tmp_path / "killed"
    proc = _start(out)
    state = out / "checkpoints" / "state-000003.npz"
    deadline = time.monotonic() + 1800
    while not state.exists():
        assert proc.poll() is None, proc.stderr.read()
        assert time.monotonic() < deadline
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)
    assert proc.wait() == -signal.SIGKILL
    assert not (out / "states.csv").exists()  # killed before its outputs
    resumed = subprocess.run(
        [sys.executable, "-m", "softcrawl", *ARGS, "--out", str(out), "--resume"],
        env=os.environ | {"PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"},
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert resumed.returncode == 0, resumed.stderr
    assert resumed.stdout.splitlines()[0].startswith("robot: resuming from ")
    print(f"robot: kill -9 after state 3, resumed: {_compare(out, refs[0]):.3g}")
