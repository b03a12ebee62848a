"""Helpers of the sweep fault tests: `softcrawl study` in a subprocess, and what its study holds."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

from softcrawl.studies.epsa.grid_studies import study_folder, study_settings, sweep_spec
from softcrawl.studies.sweeps.spec import point_key
from softcrawl.studies.sweeps.worker import open_sweep

ROOT = Path(__file__).resolve().parents[3]
FAKE = "tests.studies.fakes:fake_simulate"


def study_argv(out, *extra: str, name: str = "chamber-radius") -> list[str]:
    return ["study", name, "--quick", "--simulator", FAKE, "--out", str(out), "--no-progress", *extra]


def start(argv: list[str], env: dict[str, str] | None = None, **kwargs) -> subprocess.Popen:
    """``softcrawl ARGV`` in a new process (its own session, so that a test can signal the
    whole process group as a terminal's Ctrl-C does)."""
    full_env = os.environ | {"PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"} | (env or {})
    return subprocess.Popen(
        [sys.executable, "-m", "softcrawl", *argv],
        cwd=ROOT,
        env=full_env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        **kwargs,
    )


def run(argv: list[str], env: dict | None = None, timeout: float = 300) -> subprocess.CompletedProcess:
    proc = start(argv, env)
    out, err = proc.communicate(timeout=timeout)
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, err)


def spec_of(out, name: str = "chamber-radius", storage: str | None = None):
    """The SweepSpec that `softcrawl study NAME --quick --simulator FAKE --out OUT` runs."""
    settings = study_settings(name, "ecoflex-00-50", True, simulator=FAKE)
    folder = study_folder(out, name, "ecoflex-00-50", True)
    return sweep_spec(name, folder, settings | {"vtu_dir": str(folder / "vtu")}, storage)


def trials(spec) -> list:
    return open_sweep(spec)[0].get_trials(deepcopy=False)


def wait_for_running(spec, timeout: float = 300) -> None:
    """Until some trial of the study is RUNNING (bounded: fails the test after ``timeout`` s)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        db = Path(spec.out_dir) / "study.db"
        if spec.storage or db.exists():
            try:
                if any(t.state.name == "RUNNING" for t in trials(spec)):
                    return
            except Exception:  # noqa: BLE001 - the study is still being created
                pass
        time.sleep(0.05)
    raise AssertionError(f"no trial started running within {timeout} s")


def completed_once(spec) -> bool:
    """Every grid point has exactly one COMPLETE trial, and no trial is RUNNING or WAITING."""
    all_trials = trials(spec)
    done = Counter(point_key(t.params) for t in all_trials if t.state.name == "COMPLETE")
    pending = [t for t in all_trials if t.state.name in ("RUNNING", "WAITING")]
    every = sorted(done) == sorted(point_key(p) for p in spec.points())
    return not pending and every and set(done.values()) == {1}


def comparable(rows: list[dict]) -> list[dict]:
    """CSV rows without what differs between two runs of the same study (trial numbers, worker
    process, wall time, peak memory, the study's own folder)."""
    drop = {"trial", "worker_pid", "wall_s", "vtu", "study", "peak_rss_gb"}
    return [{k: v for k, v in r.items() if k not in drop} for r in rows]
