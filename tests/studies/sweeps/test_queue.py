"""The queue of a sweep: deaths, duplicates, bounded waits, and bugs that must fail fast."""

from __future__ import annotations

import subprocess
import time
import warnings

import optuna
import pytest

from softcrawl.studies.epsa.evaluator import EPSA_EVALUATOR, EPSA_TABLE
from softcrawl.studies.sweeps import queue, worker
from softcrawl.studies.sweeps.spec import SweepSpec, point_key
from softcrawl.studies.sweeps.storage import worker_presence
from softcrawl.studies.sweeps.sweep import run_sweep
from softcrawl.studies.sweeps.worker import open_sweep, run_worker

FAKE = "tests.studies.fakes:fake_simulate"


def _spec(tmp_path, radii=(2.0, 3.0, 4.0), simulate=FAKE, **kw):
    return SweepSpec(
        name="q",
        grid={"chamber_radius": radii},
        out_dir=str(tmp_path),
        evaluator=EPSA_EVALUATOR,
        settings={"material": "fake", "simulate": simulate},
        **kw,
    )


def _died(study, params):
    """A trial whose worker died (FAIL, no reason, not handed back), as fail_stale_trials leaves it."""
    dist = {k: optuna.distributions.CategoricalDistribution([2.0, 3.0, 4.0]) for k in params}
    study.add_trial(
        optuna.trial.create_trial(
            state=optuna.trial.TrialState.FAIL,
            params=params,
            distributions=dist,
            user_attrs={"point": params},
        )
    )


def test_a_point_whose_worker_keeps_dying_becomes_a_failed_result(tmp_path):
    spec = _spec(tmp_path)
    study, _ = open_sweep(spec)
    for _ in range(queue.MAX_DEATHS - 1):
        _died(study, {"chamber_radius": 4.0})
    assert queue.refresh(study, spec).waiting == 3  # two deaths: queued again
    study2, _ = open_sweep(_spec(tmp_path / "b"))
    for _ in range(queue.MAX_DEATHS):
        _died(study2, {"chamber_radius": 4.0})
    rows = run_sweep(_spec(tmp_path / "b"), layout=EPSA_TABLE, progress=False)
    by_r = {r["chamber_radius"]: r for r in rows}
    assert by_r[4.0]["trial_status"] == "failed" and "died 3 times" in by_r[4.0]["reason"]
    assert by_r[2.0]["trial_status"] == by_r[3.0]["trial_status"] == "completed"


def test_a_point_queued_twice_is_computed_once(tmp_path, monkeypatch):
    """Where no study lock exists (not SQLite, not PostgreSQL) a point may be queued twice; the
    second trial gives way when it is popped."""
    log = tmp_path / "log"
    monkeypatch.setenv("SOFTCRAWL_FAKE_LOG", str(log))
    spec = _spec(tmp_path, radii=(2.0,))
    study, _ = open_sweep(spec)
    for _ in range(2):
        study.enqueue_trial({"chamber_radius": 2.0}, user_attrs={"point": {"chamber_radius": 2.0}})
    report = run_worker(spec)
    assert (report.completed, report.gave_way) == (1, 1)
    assert len(log.read_text().splitlines()) == 1
    pruned = study.get_trials(states=(optuna.trial.TrialState.PRUNED,))
    assert [t.user_attrs["duplicate_of"] for t in pruned] == [0]


def test_an_idle_worker_stops_waiting_for_a_live_worker_elsewhere(tmp_path):
    spec = _spec(tmp_path, radii=(2.0,))
    study, _ = open_sweep(spec)
    other = worker_presence(spec.storage_url)
    assert other.join()  # another live worker of the study: this test process
    queue.refresh(study, spec)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # optuna: heartbeats are meant for optimize()
        trial = study.ask()  # a point running on another machine, whose worker is alive
    trial.set_user_attr("worker_host", "another-machine")
    trial.set_user_attr("worker_pid", 1)
    t0 = time.monotonic()
    report = run_worker(spec, poll_s=0.05, idle_timeout=1.0)
    assert time.monotonic() - t0 < 20 and report.completed == 0 and not report.stop
    assert study.get_trials()[0].state == optuna.trial.TrialState.RUNNING  # left to its worker
    other.leave()
    assert run_worker(spec, poll_s=0.05, idle_timeout=1.0).completed == 1  # its worker died: taken over


def test_dropping_the_failure_reason_fails_fast_instead_of_looping(tmp_path, monkeypatch):
    """Issue #19 planted this bug (the reason of a failed evaluation not stored) and the
    failed-design test hung; now the point comes back MAX_DEATHS times and ends as a failed
    result with another reason, so that test fails quickly."""

    def store_without_reason(trial, result, n_values):
        for key, value in result.attrs.items():
            trial.set_user_attr(key, value)
        if result.ok:
            return [float(v) for v in result.values]
        raise worker.EvaluationFailed(result.message)

    monkeypatch.setattr(worker, "store", store_without_reason)
    spec = _spec(tmp_path, simulate="tests.studies.fakes:raising_simulate")
    t0 = time.monotonic()
    rows = run_sweep(spec, layout=EPSA_TABLE, progress=False)
    assert time.monotonic() - t0 < 30
    four = [r for r in rows if r["chamber_radius"] == 4.0][0]
    assert four["trial_status"] == "failed" and "DesignError" not in four["reason"]


def test_a_resumed_sweep_equals_a_clean_run(tmp_path):
    clean = run_sweep(_spec(tmp_path / "clean"), layout=EPSA_TABLE, progress=False)
    spec = _spec(tmp_path / "resumed")
    run_worker(spec, max_trials=1)
    study, _ = open_sweep(spec)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # optuna: heartbeats are meant for optimize()
        trial = study.ask()  # a trial left RUNNING by a worker of this machine, killed (kill -9)
    gone = subprocess.Popen(["true"])
    gone.wait()
    trial.set_user_attr("worker_host", queue.host_id())
    trial.set_user_attr("worker_pid", gone.pid)
    t0 = time.monotonic()
    resumed = run_sweep(spec, layout=EPSA_TABLE, progress=False)
    assert time.monotonic() - t0 < 30  # no wait for the grace period (60 s)
    drop = ("trial", "worker_pid", "wall_s", "peak_rss_gb")  # process figures
    assert [{k: v for k, v in r.items() if k not in drop} for r in resumed] == [
        {k: v for k, v in r.items() if k not in drop} for r in clean
    ]
    assert {point_key(t.params) for t in study.get_trials() if t.state.name == "COMPLETE"} == {
        point_key({"chamber_radius": r}) for r in (2.0, 3.0, 4.0)
    }


@pytest.mark.parametrize("workers", [0, -1, True, 1.5])
def test_workers_must_be_a_positive_integer(tmp_path, workers):
    with pytest.raises(ValueError) as err:
        run_sweep(_spec(tmp_path), workers=workers)
    assert err.value.parameter == "workers"
