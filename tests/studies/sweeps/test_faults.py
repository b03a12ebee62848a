"""Faults of a sweep run through the command line: kill -9, SIGTERM, Ctrl-C, a full disk, bad
input. Each ends with one line (or none, for kill -9) and is followed by a resume that leaves every
grid point COMPLETE exactly once. The resume runs in this process with a grace period of 600 s and
must finish within `RESUME_LIMIT_S`: it does not wait for a heartbeat to go stale."""

from __future__ import annotations

import dataclasses
import errno
import os
import re
import signal
import time
from collections import Counter
from pathlib import Path

import pytest

pytest.importorskip("optuna")

from softcrawl.studies.epsa.evaluator import EPSA_TABLE
from softcrawl.studies.sweeps.sweep import run_sweep
from tests.studies.sweeps.cli_runs import (
    completed_once,
    run,
    spec_of,
    start,
    study_argv,
    trials,
    wait_for_running,
)

#: A resume must not wait for the grace period (600 s): it finishes well within this (s).
RESUME_LIMIT_S = 90
#: Longest a command of these tests may take (s): a guard against hangs on a loaded machine.
COMMAND_LIMIT_S = 300


def _wait_for(predicate, timeout=COMMAND_LIMIT_S):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.05)
    raise AssertionError(f"condition not met within {timeout} s")


def _resume(out, monkeypatch, env=None):
    """The same sweep, resumed in this process with a grace period of 600 s."""
    for key, value in (env or {}).items():
        monkeypatch.setenv(key, value)
    spec = dataclasses.replace(spec_of(out), grace_period=600)
    t0 = time.monotonic()
    rows = run_sweep(spec, layout=EPSA_TABLE, progress=False, poll_s=0.2)
    assert time.monotonic() - t0 < RESUME_LIMIT_S
    assert {r["trial_status"] for r in rows} == {"completed"}


def _states(spec):
    return Counter(t.state.name for t in trials(spec))


def test_sigterm_hands_the_running_point_back_in_one_line(tmp_path, monkeypatch):
    spec = spec_of(tmp_path)
    proc = start(study_argv(tmp_path), env={"SOFTCRAWL_FAKE_SLEEP": "5"})
    wait_for_running(spec)
    proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=COMMAND_LIMIT_S)
    assert proc.returncode == 128 + signal.SIGTERM
    assert err.splitlines() == [
        "softcrawl study chamber-radius: interrupted: 1 point handed back; run the same command to resume"
    ]
    assert "RUNNING" not in _states(spec)
    assert [t.user_attrs["handed_back"] for t in trials(spec) if "handed_back" in t.user_attrs] == [
        "signal SIGTERM"
    ]
    _resume(tmp_path, monkeypatch)
    assert completed_once(spec)


def test_ctrl_c_stops_two_workers_without_tracebacks(tmp_path, monkeypatch):
    spec = spec_of(tmp_path)
    proc = start(study_argv(tmp_path, "--workers", "2"), env={"SOFTCRAWL_FAKE_SLEEP": "5"})
    _wait_for(lambda: (tmp_path / "chamber-radius").exists() and _states(spec)["RUNNING"] == 2)
    os.killpg(proc.pid, signal.SIGINT)  # what a terminal sends on Ctrl-C: the whole group
    out, err = proc.communicate(timeout=COMMAND_LIMIT_S)
    assert proc.returncode == 128 + signal.SIGINT
    lines = err.splitlines()  # 2 points, or 1 if a signal landed where it cannot interrupt
    assert len(lines) == 1 and re.fullmatch(
        r"softcrawl study chamber-radius: interrupted: [12] points? handed back; "
        r"run the same command to resume",
        lines[0],
    ), err
    assert "RUNNING" not in _states(spec)
    _resume(tmp_path, monkeypatch)
    assert completed_once(spec)


def test_kill_9_then_resume_without_a_grace_period_wait(tmp_path, monkeypatch):
    log = tmp_path / "log"
    spec = spec_of(tmp_path)
    proc = start(study_argv(tmp_path), env={"SOFTCRAWL_FAKE_SLEEP": "1", "SOFTCRAWL_FAKE_LOG": str(log)})
    _wait_for(lambda: (tmp_path / "chamber-radius").exists() and _states(spec)["COMPLETE"] >= 2)
    wait_for_running(spec)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=COMMAND_LIMIT_S)
    states = _states(spec)
    assert states["RUNNING"] == 1 and 2 <= states["COMPLETE"] < 5
    n_before = len(log.read_text().splitlines())
    _resume(tmp_path, monkeypatch, env={"SOFTCRAWL_FAKE_LOG": str(log)})  # the dead worker: this machine
    assert completed_once(spec)
    resumed = log.read_text().splitlines()[n_before:]
    assert len(resumed) == 5 - states["COMPLETE"] and len(set(resumed)) == len(resumed)


def test_full_disk_hands_points_back_and_leaves_no_partial_file(tmp_path, monkeypatch):
    """The full disk is injected: the fake evaluator's output write fails with ENOSPC half-way
    while a marker file exists (tests/studies/fakes.py); removing it frees the space.
    `test_real_full_disk` does the same on a real, tiny filesystem."""
    spec, shapes, full = spec_of(tmp_path), tmp_path / "shapes", tmp_path / "disk-is-full"
    env = {"SOFTCRAWL_FAKE_OUTPUT": str(shapes), "SOFTCRAWL_FAKE_FULL_DISK": str(full)}
    proc = start(study_argv(tmp_path), env=env | {"SOFTCRAWL_FAKE_SLEEP": "0.5"})
    _wait_for(lambda: (tmp_path / "chamber-radius").exists() and _states(spec)["COMPLETE"] >= 2)
    full.touch()
    out, err = proc.communicate(timeout=COMMAND_LIMIT_S)
    assert proc.returncode == 1
    lines = err.splitlines()
    assert len(lines) == 1 and "disk full: No space left on device" in lines[0], err
    assert lines[0].endswith("1 point handed back; run the same command to resume")
    assert "RUNNING" not in _states(spec)
    assert not [p for p in shapes.iterdir() if p.name.startswith(".partial-")]
    assert not Path(spec.out_dir, "curves.csv").exists()
    full.unlink()  # space freed
    _resume(tmp_path, monkeypatch, env=env)
    assert completed_once(spec)
    assert sorted(p.name for p in shapes.iterdir()) == [f"r{r:g}-n0.bin" for r in (2, 3, 4, 5, 6)]


def test_a_study_whose_every_point_fails_on_input_exits_2(tmp_path):
    done = run(["study", "fiber-turns", "--quick", "--simulator", "tests.studies.fakes:invalid_simulate",
                "--out", str(tmp_path), "--no-progress"])  # fmt: skip
    assert done.returncode == 2
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("softcrawl study: error: chamber_radius: made-up invalid")
    assert "no point of the study could be evaluated" in lines[0] and "Traceback" not in done.stderr


def test_a_full_disk_while_writing_the_tables_is_one_line_and_loses_nothing(tmp_path, monkeypatch, capsys):
    from softcrawl.studies.cli import main
    from softcrawl.studies.epsa import grid_studies  # writes the tables of the grid studies

    log = tmp_path / "log"
    monkeypatch.setenv("SOFTCRAWL_FAKE_LOG", str(log))
    real = grid_studies.write_csv

    def full(rows, path):
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.setattr(grid_studies, "write_csv", full)
    assert main(study_argv(tmp_path)) == 1
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "disk full: No space left on device" in err[0], err
    assert err[0].endswith("run the same command to write the tables")
    monkeypatch.setattr(grid_studies, "write_csv", real)
    assert main(study_argv(tmp_path)) == 0
    assert len(log.read_text().splitlines()) == 5  # nothing computed twice
    assert Path(spec_of(tmp_path).out_dir, "curves.csv").exists()
