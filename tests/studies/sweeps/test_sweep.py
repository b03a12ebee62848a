"""Sweeps: resumable, exactly-once, failure-tolerant (fake evaluators, no FE)."""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
import time
from collections import Counter

import pytest

optuna = pytest.importorskip("optuna")
from optuna.trial import TrialState  # noqa: E402

from softcrawl.studies.epsa.evaluator import EPSA_EVALUATOR, EPSA_TABLE  # noqa: E402
from softcrawl.studies.sweeps.spec import SweepSpec, point_key  # noqa: E402
from softcrawl.studies.sweeps.sweep import run_sweep  # noqa: E402
from softcrawl.studies.sweeps.tables import collect  # noqa: E402
from softcrawl.studies.sweeps.worker import open_sweep, run_worker  # noqa: E402

FAKE = "tests.studies.fakes:fake_simulate"


def _spec(tmp_path, radii=(2.0, 3.0, 4.0, 5.0, 6.0), turns=(0,), simulate=FAKE, **kw):
    return SweepSpec(
        name="t",
        grid={"chamber_radius": radii, "fiber_turns": turns},
        out_dir=str(tmp_path),
        evaluator=EPSA_EVALUATOR,
        settings={"material": "fake", "simulate": simulate},
        **kw,
    )


class runner:  # the engine's functions under the names the tests use
    @staticmethod
    def run_sweep(spec, **kw):
        return run_sweep(spec, layout=EPSA_TABLE, **kw)

    @staticmethod
    def open_study(spec):
        return open_sweep(spec)[0]

    @staticmethod
    def collect(study, spec):
        return collect(study, spec, EPSA_TABLE)

    run_worker = staticmethod(run_worker)


def _complete_counts(spec):
    study = runner.open_study(spec)
    counts = Counter(point_key(t.params) for t in study.get_trials(states=(TrialState.COMPLETE,)))
    return study, counts


def test_sweep_completes_every_point_once(tmp_path, monkeypatch):
    monkeypatch.setenv("SOFTCRAWL_FAKE_LOG", str(tmp_path / "log"))
    spec = _spec(tmp_path)
    rows = runner.run_sweep(spec, progress=False)
    study, counts = _complete_counts(spec)
    assert sorted(counts.values()) == [1] * 5
    assert {r["trial_status"] for r in rows} == {"completed"}
    assert len(rows) == 5 * 6  # one row per (design, pressure), 0 kPa reference included
    trial = study.get_trials(states=(TrialState.COMPLETE,))[0]
    assert len(trial.user_attrs["rows"]) == 6 and "metrics" not in trial.user_attrs  # flat (063)
    # extension is measured from the 0 kPa reference row (here 103 mm, seal head included)
    assert trial.user_attrs["extension_mm"] == pytest.approx(
        trial.user_attrs["rows"][-1]["length_mm"] - trial.user_attrs["rows"][0]["length_mm"]
    )
    # running again computes nothing
    runner.run_sweep(spec, progress=False)
    assert len((tmp_path / "log").read_text().splitlines()) == 5


def test_failed_and_invalid_designs_do_not_stop_the_sweep(tmp_path, monkeypatch):
    monkeypatch.setenv("SOFTCRAWL_FAKE_DIVERGE", "1")
    spec = _spec(tmp_path, simulate="tests.studies.fakes:raising_simulate")
    rows = runner.run_sweep(spec, progress=False)
    by_r = {}
    for r in rows:
        by_r.setdefault(r["chamber_radius"], []).append(r)
    assert {r["trial_status"] for r in by_r[4.0]} == {"failed"}
    assert "DesignError" in by_r[4.0][0]["reason"] and "chamber_radius" in by_r[4.0][0]["reason"]
    assert {r["trial_status"] for r in by_r[5.0]} == {"failed"}
    assert "Newton diverged at 60 kPa" in by_r[5.0][0]["reason"]
    assert len(by_r[5.0]) == 3  # the partial curve (0, 20, 40 kPa) is kept
    assert {r["trial_status"] for r in by_r[6.0]} == {"completed"}  # a limit point is a result
    assert by_r[6.0][0]["limit_pressure_kpa"] == 80.0
    for radius in (2.0, 3.0):
        assert {r["trial_status"] for r in by_r[radius]} == {"completed"}
    study = runner.open_study(spec)
    failed = study.get_trials(states=(TrialState.FAIL,))
    assert len(failed) == 2 and all("failure" in t.user_attrs for t in failed)
    # an invalid design that the grid itself produces (chamber radius >= outer radius)
    spec2 = SweepSpec(
        name="bad",
        grid={"chamber_radius": (3.0, 9.5)},
        out_dir=str(tmp_path / "b"),
        evaluator=EPSA_EVALUATOR,
        settings={"simulate": FAKE},
    )
    rows2 = runner.run_sweep(spec2, progress=False)
    assert [r["trial_status"] for r in rows2 if r["chamber_radius"] == 9.5] == ["failed"]
    assert (
        "must be smaller than outer_radius" in [r for r in rows2 if r["chamber_radius"] == 9.5][0]["reason"]
    )
    # failed evaluations are results: a restart does not recompute them
    runner.run_sweep(spec, progress=False)
    assert len(runner.open_study(spec).get_trials(states=(TrialState.FAIL,))) == 2
    # ... unless asked to retry them (here the evaluator is "fixed" for r = 5)
    monkeypatch.delenv("SOFTCRAWL_FAKE_DIVERGE")
    rows = runner.run_sweep(spec, progress=False, retry=True)
    status = {r["chamber_radius"]: r["trial_status"] for r in rows}
    assert status == {2.0: "completed", 3.0: "completed", 4.0: "failed", 5.0: "completed", 6.0: "completed"}
    assert len(runner.open_study(spec).get_trials()) == 7  # 5 + the two retried points


def _worker(spec_dict):
    run_worker(SweepSpec(**spec_dict))


def test_killed_worker_resumes_without_loss_or_duplicates(tmp_path, monkeypatch):
    log = tmp_path / "log"
    monkeypatch.setenv("SOFTCRAWL_FAKE_LOG", str(log))
    monkeypatch.setenv("SOFTCRAWL_FAKE_SLEEP", "0.6")
    spec = _spec(tmp_path, radii=(2.0, 3.0, 4.0), turns=(0, 20), heartbeat_interval=1, grace_period=2)
    study = runner.open_study(spec)
    proc = mp.get_context("spawn").Process(target=_worker, args=(spec.to_dict(),))
    proc.start()
    deadline = time.time() + 60
    while time.time() < deadline:  # kill while a trial is RUNNING, after >= 2 are COMPLETE
        trials = study.get_trials(deepcopy=False)
        done = sum(t.state == TrialState.COMPLETE for t in trials)
        running = [t for t in trials if t.state == TrialState.RUNNING]
        if done >= 2 and running:
            break
        time.sleep(0.05)
    os.kill(proc.pid, signal.SIGKILL)
    proc.join()
    trials = study.get_trials()
    assert any(t.state == TrialState.RUNNING for t in trials), "kill did not hit a running trial"
    done_before = {point_key(t.params) for t in trials if t.state == TrialState.COMPLETE}
    assert 2 <= len(done_before) < 6
    n_logged = len(log.read_text().splitlines())
    monkeypatch.setenv("SOFTCRAWL_FAKE_SLEEP", "0")
    rows = runner.run_sweep(spec, progress=False)
    _, counts = _complete_counts(spec)
    assert len(counts) == 6 and set(counts.values()) == {1}
    assert {r["trial_status"] for r in rows} == {"completed"} and len(rows) == 36
    # the resumed run computed exactly the points that were not complete at the kill
    lines = log.read_text().splitlines()
    assert len(lines) - n_logged == 6 - len(done_before)
    after = Counter(tuple(line.split(",")[:2]) for line in lines[n_logged:])
    assert max(after.values()) == 1


def test_two_workers_share_one_storage(tmp_path, monkeypatch):
    log = tmp_path / "log"
    monkeypatch.setenv("SOFTCRAWL_FAKE_LOG", str(log))
    monkeypatch.setenv("SOFTCRAWL_FAKE_SLEEP", "0.2")
    spec = _spec(tmp_path, radii=(2.0, 2.5, 3.0, 3.5, 4.0, 4.5), turns=(0, 20))
    rows = runner.run_sweep(spec, workers=2, progress=False)
    _, counts = _complete_counts(spec)
    assert len(counts) == 12 and set(counts.values()) == {1}
    lines = log.read_text().splitlines()
    assert len(lines) == 12  # no point computed twice
    assert len({line.split(",")[2] for line in lines}) == 2  # both workers did work
    assert {r["trial_status"] for r in rows} == {"completed"}


def test_collect_lists_missing_points(tmp_path):
    spec = _spec(tmp_path)
    study = runner.open_study(spec)
    rows = runner.collect(study, spec)
    assert [r["trial_status"] for r in rows] == ["missing"] * 5
    runner.run_worker(spec, max_trials=2)
    rows = runner.collect(study, spec)
    assert Counter(r["trial_status"] for r in rows) == {"completed": 12, "waiting": 3}


def test_spec_validation(tmp_path):
    with pytest.raises(ValueError) as err:
        SweepSpec(name="x", grid={"chamber_radius": ()}, out_dir=str(tmp_path), evaluator=EPSA_EVALUATOR)
    assert err.value.parameter == "grid.chamber_radius"
    with pytest.raises(ValueError):
        runner.run_sweep(_spec(tmp_path), workers=0)


def test_resume_refuses_different_settings(tmp_path):
    spec = _spec(tmp_path)
    runner.open_study(spec)
    other = SweepSpec(**{**spec.to_dict(), "settings": {**spec.settings, "quick": True}})
    with pytest.raises(ValueError) as err:
        runner.open_study(other)
    assert err.value.parameter == "storage" and "settings" in str(err.value)
    runner.open_study(SweepSpec(**{**spec.to_dict(), "heartbeat_interval": 2}))  # local: fine


def test_terminated_worker_hands_its_point_back_at_once(tmp_path, monkeypatch):
    monkeypatch.setenv("SOFTCRAWL_FAKE_SLEEP", "1.0")
    spec = _spec(tmp_path, radii=(2.0, 3.0, 4.0), grace_period=600)  # staleness would take 10 min
    study = runner.open_study(spec)
    proc = mp.get_context("spawn").Process(target=_worker, args=(spec.to_dict(),))
    proc.start()
    deadline = time.time() + 60
    while time.time() < deadline and not study.get_trials(states=(TrialState.RUNNING,)):
        time.sleep(0.05)
    os.kill(proc.pid, signal.SIGTERM)
    proc.join()
    assert not study.get_trials(states=(TrialState.RUNNING,))
    monkeypatch.setenv("SOFTCRAWL_FAKE_SLEEP", "0")
    t0 = time.time()
    rows = runner.run_sweep(spec, progress=False)
    assert time.time() - t0 < 30 and {r["trial_status"] for r in rows} == {"completed"}
    _, counts = _complete_counts(spec)
    assert len(counts) == 3 and set(counts.values()) == {1}


def test_limit_point_below_the_first_pressure_is_a_result(tmp_path):
    spec = _spec(tmp_path, radii=(3.0, 6.0), simulate="tests.studies.fakes:early_limit_simulate")
    rows = runner.run_sweep(spec, progress=False)
    six = [r for r in rows if r["chamber_radius"] == 6.0]
    assert {r["trial_status"] for r in six} == {"completed"}
    assert [r["row_status"] for r in six] == ["reference"] + ["volume-control"] * 3
    assert six[0]["limit_pressure_kpa"] == 15.0
