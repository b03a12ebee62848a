"""The queue of a sweep: which grid points are done, pending or missing, and keeping it whole.

Every grid point is an optuna trial enqueued with fixed parameters (`Study.enqueue_trial`,
WAITING, with the point also in ``user_attrs["point"]``: optuna 5 shows a live trial's user
attributes, not its system attributes); workers pop WAITING trials with `Study.ask` inside
`Study.optimize`. What each trial of a point means:

    COMPLETE                                   a result
    FAIL with user_attrs["failure"]            a result (the evaluation failed; its reason)
    FAIL, failure, number < retry marker       superseded (``--retry-failed``)
    FAIL with user_attrs["handed_back"]        its worker was interrupted or hit a full disk
    FAIL, no attribute                         its worker died (killed, out of memory, ...)
    PRUNED                                     gave way to another trial of the point
    WAITING, RUNNING                           pending

`refresh` (run under the study lock) brings the queue up to date: it fails the RUNNING trials of
dead workers (optuna's `fail_stale_trials` for a silent heartbeat; at once for a worker on this
machine whose process is gone, and, for SQLite, every RUNNING trial when the first worker joins:
`studies.sweeps.storage.WorkerPresence`), then enqueues each point that has neither a result nor a pending
trial. A point whose worker died `MAX_DEATHS` times becomes a failed result instead of looping
(a design that kills its worker by exhausting memory would otherwise be retried forever).
"""

from __future__ import annotations

import datetime
import os
import socket
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from softcrawl.studies.sweeps.spec import SweepSpec, point_key

#: A point whose worker died this often is a failed result.
MAX_DEATHS = 3
#: Study user attribute: FAIL results of trials numbered below it are superseded.
RETRY_MARKER = "retry_failed_before"


def host_id() -> str:
    """This machine and PID namespace: a RUNNING trial with this host id and a dead PID is dead."""
    parts = [socket.gethostname()]
    for path in ("/proc/sys/kernel/random/boot_id", "/proc/self/ns/pid"):
        try:
            parts.append(Path(path).read_text().strip() if "boot" in path else str(os.stat(path).st_ino))
        except OSError:
            pass
    return ":".join(parts)


def pid_alive(pid: int) -> bool:
    """Whether process ``pid`` of this machine runs (a zombie does not)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return True


def trial_point(trial: Any) -> str | None:
    """The point of a trial: ``user_attrs["point"]`` (set when it was enqueued), else its params."""
    point = trial.user_attrs.get("point")
    if point is not None:
        return point_key(point)
    return point_key(trial.params) if trial.params else None


def retry_marker(study: Any) -> int:
    return int(study.user_attrs.get(RETRY_MARKER, 0))


def classify(trial: Any, retry_before: int = 0) -> str:
    """completed | failed | pending | superseded | handed_back | died | gave_way (see above)."""
    from optuna.trial import TrialState

    state, attrs = trial.state, trial.user_attrs
    if state == TrialState.COMPLETE:
        return "completed"
    if state in (TrialState.WAITING, TrialState.RUNNING):
        return "pending"
    if state == TrialState.PRUNED:
        return "gave_way"
    if "failure" in attrs:
        return "failed" if trial.number >= retry_before else "superseded"
    if "handed_back" in attrs:
        return "handed_back"
    return "died" if trial.number >= retry_before else "superseded"


def by_point(trials: Iterable[Any]) -> dict[str, list[Any]]:
    out: dict[str, list[Any]] = {}
    for trial in trials:
        key = trial_point(trial)
        if key is not None:
            out.setdefault(key, []).append(trial)
    return out


def point_status(trials: list[Any], retry_before: int) -> tuple[str, Any]:
    """(status, trial) of one point: completed | failed | running | waiting | missing. A
    completed trial wins over anything else, then the earliest failed result."""
    from optuna.trial import TrialState

    rank = {"completed": 0, "failed": 1, "pending": 2}
    useful = [t for t in trials if classify(t, retry_before) in rank]
    if not useful:
        return "missing", None
    best = min(
        useful, key=lambda t: (rank[classify(t, retry_before)], t.state != TrialState.RUNNING, t.number)
    )
    kind = classify(best, retry_before)
    if kind == "pending":
        kind = "running" if best.state == TrialState.RUNNING else "waiting"
    return kind, best


def statuses(study: Any, spec: SweepSpec, trials: list[Any] | None = None) -> dict[str, tuple[str, Any]]:
    """point key -> (status, trial) for every grid point."""
    trials = study.get_trials(deepcopy=False) if trials is None else trials
    groups, retry = by_point(trials), retry_marker(study)
    return {point_key(p): point_status(groups.get(point_key(p), []), retry) for p in spec.points()}


@dataclass(frozen=True)
class QueueState:
    """After `refresh`: trials waiting to be popped, running elsewhere, and finished."""

    waiting: int
    running: int
    finished: int


def _dead_here(trial: Any, here: str, grace_s: float, now: datetime.datetime) -> bool:
    """A RUNNING trial whose worker is gone: on this machine with its process ended, or never
    started (no worker recorded, popped long ago: killed between the pop and the objective)."""
    host, pid = trial.user_attrs.get("worker_host"), trial.user_attrs.get("worker_pid")
    if host is None:
        start = trial.datetime_start
        return start is not None and (now - start).total_seconds() > 2 * grace_s
    return host == here and isinstance(pid, int) and (pid == os.getpid() or not pid_alive(pid))


def fail_dead(study: Any, trials: list[Any], grace_s: float, everyone: bool = False) -> bool:
    """Fail the RUNNING trials of dead workers that optuna's heartbeat cannot see (yet), or every
    RUNNING trial (``everyone``: no other worker is alive); returns whether any was failed."""
    import optuna
    from optuna.trial import TrialState

    here, now, changed = host_id(), datetime.datetime.now(), False
    for trial in trials:
        if trial.state == TrialState.RUNNING and (everyone or _dead_here(trial, here, grace_s, now)):
            try:
                study.tell(trial.number, state=TrialState.FAIL)
                changed = True
            except (ValueError, RuntimeError, optuna.exceptions.UpdateFinishedTrialError):
                pass  # it finished in the meantime
    return changed


def refresh(study: Any, spec: SweepSpec) -> QueueState:
    """Bring the queue up to date (under the study lock): fail dead workers' trials, enqueue
    every point without a result or a pending trial, count what waits and what runs."""
    import optuna
    from optuna.trial import TrialState

    optuna.storages.fail_stale_trials(study)
    trials = study.get_trials(deepcopy=False)
    if fail_dead(study, trials, spec.grace_period):
        trials = study.get_trials(deepcopy=False)
    groups, retry = by_point(trials), retry_marker(study)
    enqueued = 0
    for params in spec.points():
        point = groups.get(point_key(params), [])
        if point_status(point, retry)[0] != "missing":
            continue
        deaths = sum(classify(t, retry) == "died" for t in point)
        if deaths >= MAX_DEATHS:
            _record_deaths(study, spec, params, deaths)
        else:
            study.enqueue_trial(params, user_attrs={"point": params, "earlier_trials": len(point)})
            enqueued += 1
    waiting = sum(t.state == TrialState.WAITING for t in trials) + enqueued
    running = sum(t.state == TrialState.RUNNING for t in trials)
    return QueueState(waiting, running, sum(t.state.is_finished() for t in trials))


def _record_deaths(study: Any, spec: SweepSpec, params: Mapping[str, Any], deaths: int) -> None:
    import optuna
    from optuna.distributions import CategoricalDistribution

    reason = f"its worker died {deaths} times while evaluating it (killed, or out of memory?)"
    study.add_trial(
        optuna.trial.create_trial(
            state=optuna.trial.TrialState.FAIL,
            params=dict(params),
            distributions={k: CategoricalDistribution(list(spec.grid[k])) for k in params},
            user_attrs={"failure": reason},
        )
    )


def mark_retry(study: Any) -> None:
    """Make the failed results so far count as missing, so that they are evaluated again."""
    study.set_user_attr(RETRY_MARKER, len(study.get_trials(deepcopy=False)))


def duplicate_of(study: Any, trial_number: int, key: str, retry_before: int) -> int | None:
    """Another trial of the same point that is a result, or that runs and was popped earlier."""
    from optuna.trial import TrialState

    for t in study.get_trials(deepcopy=False):
        if t.number == trial_number or trial_point(t) != key:
            continue
        kind = classify(t, retry_before)
        if kind in ("completed", "failed") or (t.state == TrialState.RUNNING and t.number < trial_number):
            return t.number
    return None
