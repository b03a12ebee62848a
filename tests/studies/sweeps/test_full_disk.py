"""A real full disk: a 4 MiB tmpfs, mounted in a private mount namespace (``unshare``: as root,
or as a user where user namespaces are allowed), holds the study database and the outputs. The
sweep stops with one line, leaves no partial file, and resumes once space is freed with every
point complete exactly once and no wait for the heartbeat grace period. Skipped where no mount
namespace can be made (the injected full disk of test_faults.py runs everywhere)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import pytest

from tests.studies.sweeps.cli_runs import ROOT

UNSHARE = ["unshare", "--mount"] if os.geteuid() == 0 else ["unshare", "--user", "--map-root-user", "--mount"]


def _can_mount(tmp_path) -> str | None:
    if shutil.which("unshare") is None or sys.platform != "linux":
        return "no unshare(1) on this system"
    probe = subprocess.run(
        [*UNSHARE, "sh", "-c", f"mount -t tmpfs -o size=1m tmpfs {tmp_path}"], capture_output=True, text=True
    )
    return None if probe.returncode == 0 else f"cannot mount a tmpfs here: {probe.stderr.strip()}"


@pytest.mark.parametrize(
    "keep, full",
    [(400_000, "database"), (700_000, "output")],
    ids=["the-database-fills-the-disk", "an-output-fills-the-disk"],
)
def test_real_full_disk_then_resume(tmp_path, keep, full):
    """``keep`` bytes are left free: with 0.4 MB the database's write-ahead log meets the full
    disk first (the point cannot be handed back: nothing can be written; the resume fails it at
    once, as no worker holds the study), with 0.7 MB and the study database on another disk an
    output file does (the point is handed back)."""
    disk = tmp_path / "disk"
    disk.mkdir()
    reason = _can_mount(disk)
    if reason:
        pytest.skip(reason)
    driver = f"{sys.executable} -m tests.studies.sweeps.full_disk_driver {disk} {keep} {full}"
    script = f"mount -t tmpfs -o size=4m tmpfs {disk} && exec {driver}"
    env = os.environ | {"PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    done = subprocess.run(
        [*UNSHARE, "sh", "-c", script], cwd=ROOT, env=env, capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads(done.stdout.splitlines()[-1])
    lines = report["first_stderr"].splitlines()
    assert report["first_code"] == 1 and len(lines) == 1, report
    assert "disk full" in lines[0] and lines[0].endswith("run the same command to resume"), lines
    assert ("SQLite" in lines[0]) == (full == "database") and report["partial_files"] == [], report
    if full == "output":
        assert "1 point handed back" in lines[0] and report["left_running"] == [], report
    assert report["resume_s"] < 90 and report["resumed_statuses"] == ["completed"], report
    assert report["completed_once"] and report["shapes"] == [f"r{r}-n0.bin" for r in (2, 3, 4, 5, 6)]
