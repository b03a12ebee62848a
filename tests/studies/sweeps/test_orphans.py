"""Workers die with their parent: kill -9 of the main process alone (not of its process group, as a
job scheduler or the out-of-memory killer does) leaves no worker running as an orphan; their points
are handed back and the next run computes each exactly once (`studies.sweeps.pool.die_with_parent`)."""

from __future__ import annotations

import ctypes
import os
import signal
import time
from pathlib import Path

import pytest

pytest.importorskip("optuna")

from softcrawl.studies.sweeps.pool import PR_SET_PDEATHSIG, die_with_parent
from tests.studies.sweeps.cli_runs import completed_once, spec_of, start, study_argv, trials
from tests.studies.sweeps.test_faults import COMMAND_LIMIT_S, _resume, _states, _wait_for

#: The workers are gone this long (s) after their parent was killed (the issue's acceptance).
ORPHAN_LIMIT_S = 5


def _group(pgid: int) -> list[tuple[int, str]]:
    """(pid, command line) of every live process of process group `pgid` (zombies excluded)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
            cmdline = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        fields = stat.rpartition(")")[2].split()
        if fields[0] != "Z" and int(fields[2]) == pgid:
            found.append((int(entry.name), cmdline))
    return found


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")
def test_kill_9_of_the_parent_alone_leaves_no_orphan(tmp_path, monkeypatch):
    log = tmp_path / "log"
    spec = spec_of(tmp_path)
    proc = start(study_argv(tmp_path, "--workers", "2"),
                 env={"SOFTCRAWL_FAKE_SLEEP": "5", "SOFTCRAWL_FAKE_LOG": str(log)})  # fmt: skip
    _wait_for(lambda: (tmp_path / "chamber-radius").exists() and _states(spec)["RUNNING"] == 2)
    workers = [pid for pid, _ in _group(proc.pid) if pid != proc.pid]
    assert len(workers) >= 2, _group(proc.pid)
    os.kill(proc.pid, signal.SIGKILL)  # the parent only
    killed = time.monotonic()
    proc.wait(timeout=COMMAND_LIMIT_S)  # not communicate(): orphans would hold its pipes open
    time.sleep(max(0.0, killed + ORPHAN_LIMIT_S - time.monotonic()))
    assert _group(proc.pid) == []
    proc.communicate(timeout=COMMAND_LIMIT_S)
    handed = [t.user_attrs.get("handed_back") for t in trials(spec) if "handed_back" in t.user_attrs]
    assert handed == ["signal SIGTERM"] * 2  # as after Ctrl-C: the points went back at once
    assert "RUNNING" not in _states(spec)
    done_before = _states(spec)["COMPLETE"]
    n_before = len(log.read_text().splitlines())
    _resume(tmp_path, monkeypatch, env={"SOFTCRAWL_FAKE_LOG": str(log)})
    assert completed_once(spec)
    resumed = log.read_text().splitlines()[n_before:]
    assert len(resumed) == 5 - done_before and len(set(resumed)) == len(resumed)


def test_a_worker_whose_parent_is_already_gone_gets_sigterm(monkeypatch):
    sent = []
    monkeypatch.setattr(os, "kill", lambda pid, sig: sent.append((pid, sig)))
    assert die_with_parent(os.getppid() + 10**6) in ("prctl", "watchdog")  # not our parent
    assert sent[0] == (os.getpid(), signal.SIGTERM)
    if Path("/proc/self/stat").exists():  # undo the request in this (the test's) process
        ctypes.CDLL(None).prctl(PR_SET_PDEATHSIG, 0, 0, 0, 0)
