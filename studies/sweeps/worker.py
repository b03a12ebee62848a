"""One sweep worker: pop a queued grid point, evaluate it, store the result; until none is left.

Each step holds the study lock while it refreshes the queue (`studies.sweeps.queue.refresh`) and
pops the next trial with optuna's own ``Study.optimize(n_trials=1)`` (fail stale trials, ``ask``,
heartbeat thread, ``tell``); the objective's first act is to release the lock, so evaluations run
in parallel and only the queue bookkeeping is serialised. The objective

* records its worker (``worker_pid``, ``worker_host``), so that a later run on the same machine
  fails the trial at once if this process dies, instead of waiting for the heartbeat grace period
  (for SQLite, `studies.sweeps.storage.WorkerPresence` covers even a worker that could record
  nothing because the disk was full);
* gives way (PRUNED, ``duplicate_of``) if the point already has a result or an earlier running
  trial: a guard that should never fire where the study lock exists;
* evaluates; any exception of the evaluator, and an evaluation with ``ok = False``, is a failed
  result with its reason (``user_attrs["failure"]``; ``input_error`` names the parameter of an
  `InputError`); a fault of the machine or a signal hands the point back instead;
* watches its resident memory (`studies.sweeps.memory`): the peak is stored (``peak_rss_gb``),
  and a point above ``--max-memory`` is a failed result "out of memory at N.N GB (limit M GB)".

Bounded waits: with nothing to pop while other workers' trials run, a worker polls (to take over
a point whose worker dies) for at most ``idle_timeout`` s (default: twice the grace period plus a
minute) without any change in the study, and a run never evaluates more than
`MAX_EVALUATIONS_PER_POINT` times the number of points, so that a bug that keeps handing points
back ends with a message instead of a loop.
"""

from __future__ import annotations

import math
import os
import threading
import time
import traceback
from collections.abc import Callable
from typing import Any

from softcrawl.errors import InputError
from softcrawl.studies.sweeps import memory, queue
from softcrawl.studies.sweeps.faults import (
    Interrupted,
    MachineFault,
    SignalGuard,
    WorkerReport,
    machine_fault,
)
from softcrawl.studies.sweeps.spec import Evaluation, SweepSpec, jsonable, load_callable, point_key
from softcrawl.studies.sweeps.storage import StorageFault, connect, storage_faults, worker_presence

#: A run evaluates at most this many times the number of grid points.
MAX_EVALUATIONS_PER_POINT = 2 * queue.MAX_DEATHS


class EvaluationFailed(Exception):
    """Raised in the objective so that ``optimize(catch=...)`` records a failed result."""


class HandBack(Exception):
    """Raised in the objective after marking the trial ``handed_back``: optuna fails the trial
    and re-raises this, and the worker stops."""

    def __init__(self, reason: str, signum: int = 0):
        super().__init__(reason)
        self.reason, self.signum = reason, signum


def sweep_sampler() -> Any:
    """Every trial of a sweep comes from the queue; the sampler only serves the (guarded-against)
    case of an ask on an empty queue, so the cheapest one."""
    import optuna

    return optuna.samplers.RandomSampler(seed=0)


def open_sweep(spec: SweepSpec) -> tuple[Any, Any]:
    """(study, lock) of a sweep, created if absent."""
    return connect(spec, sampler=sweep_sampler())


def evaluate(evaluator: Any, params: dict, spec: Any, guard: SignalGuard) -> Evaluation:
    """Call the evaluator; its exceptions become failed evaluations, faults of the machine and
    signals are raised as `MachineFault` and `Interrupted`."""
    try:
        with guard.evaluating():
            return evaluator(params, dict(spec.fixed), dict(spec.settings))
    except Exception as exc:  # any failure is a failed trial, never a crash
        line = machine_fault(exc)
        if line is not None:
            raise MachineFault(line) from exc
        attrs = {"traceback": traceback.format_exc(limit=8)}
        if isinstance(exc, InputError):
            attrs["input_error"] = {"parameter": exc.parameter, "detail": getattr(exc, "detail", str(exc))}
        return Evaluation(ok=False, message=f"{type(exc).__name__}: {exc}", attrs=attrs)


def store(trial: Any, result: Evaluation, n_values: int) -> list[float]:
    """Store the evaluation's attributes; its values, or `EvaluationFailed` with the reason. An
    evaluation's ``constraints`` (floats, <= 0 feasible) become optuna trial constraints
    (`Trial.set_constraint`), which the TPE and NSGA-II samplers use to prefer feasible trials
    and ``best_trial`` / ``best_trials`` use to leave infeasible ones out. The dict attribute
    ``metrics`` is stored flat, one user attribute per metric, so that optuna-dashboard can sort
    and plot them (decision 063)."""
    for key, value in result.attrs.items():
        if key == "metrics" and isinstance(value, dict):
            for name, metric in value.items():
                trial.set_user_attr(str(name), jsonable(metric))
        else:
            trial.set_user_attr(key, jsonable(value))
    names = list(result.attrs.get("constraint_names") or ())
    for i, value in enumerate(result.attrs.get("constraints") or ()):
        trial.set_constraint(names[i] if i < len(names) else f"c{i}", float(value))
    values = [float(v) for v in result.values]
    if result.ok and len(values) == n_values and all(map(math.isfinite, values)):
        return values
    reason = result.message or ("evaluator returned no finite values" if result.ok else "failed")
    trial.set_user_attr("failure", reason)
    raise EvaluationFailed(reason)


def run_guarded(trial: Any, evaluator: Any, params: dict, spec: Any, guard: SignalGuard) -> list[float]:
    """`evaluate` + `store`, handing the point back on a signal or a fault of the machine."""
    trial.set_user_attr("worker_pid", os.getpid())
    trial.set_user_attr("worker_host", queue.host_id())
    watch = memory.MemoryWatch(memory.limit_gb(), on_hard_stop=lambda why: _fail_now(trial, why))
    try:
        try:
            with watch:
                result = evaluate(evaluator, params, spec, guard)
        finally:
            if watch.peak_gb is not None:
                trial.set_user_attr("peak_rss_gb", round(watch.peak_gb, 3))
    except memory.OutOfMemory as exc:
        attrs = {"out_of_memory_gb": round(exc.peak_gb, 3), "memory_limit_gb": exc.limit_gb}
        if exc.last_state:
            attrs["last_state"] = exc.last_state
        result = Evaluation(ok=False, message=exc.reason, attrs=attrs)
    except Interrupted as exc:
        trial.set_user_attr("handed_back", f"signal {exc}")
        raise HandBack(f"signal {exc}", exc.signum) from None
    except MachineFault as exc:
        trial.set_user_attr("handed_back", exc.line)
        raise HandBack(exc.line) from None
    return store(trial, result, len(spec.directions))


def _fail_now(trial: Any, reason: str) -> None:
    """The memory watchdog's last act before it ends the process: the failure, on the trial; the
    trial itself is failed by whoever finds its worker dead (the reason is kept)."""
    trial.set_user_attr("failure", reason)


class SweepWorker:
    """The loop of `run_worker`; one instance per process."""

    def __init__(
        self,
        spec: SweepSpec,
        guard: SignalGuard,
        poll_s: float,
        idle_timeout: float | None,
        on_step: Callable[[], None] | None = None,
    ):
        self.spec, self.guard, self.poll_s, self.on_step = spec, guard, poll_s, on_step
        self.idle_timeout = 2 * spec.grace_period + 60 if idle_timeout is None else idle_timeout
        self.study, self.lock = open_sweep(spec)
        self.evaluator = load_callable(spec.evaluator)
        self.report = WorkerReport()
        self.retry = queue.retry_marker(self.study)
        self.presence = worker_presence(spec.storage_url)
        if self.presence is not None:
            with self.lock:
                if self.presence.join():  # the only worker: every RUNNING trial is dead
                    queue.fail_dead(self.study, self.study.get_trials(deepcopy=False), 0, everyone=True)

    def objective(self, trial: Any) -> list[float]:
        """Release the study lock (held since the pop), then evaluate the popped point."""
        from optuna import TrialPruned

        self.lock.release()
        fixed = trial.user_attrs.get("point")
        if fixed is None:  # asked an empty queue: not a grid point
            trial.set_user_attr("duplicate_of", -1)
            raise TrialPruned()
        params = {k: trial.suggest_categorical(k, list(v)) for k, v in self.spec.grid.items()}
        twin = queue.duplicate_of(self.study, trial.number, point_key(fixed), self.retry)
        if twin is not None:
            trial.set_user_attr("duplicate_of", twin)
            raise TrialPruned()
        return run_guarded(trial, self.evaluator, params, self.spec, self.guard)

    def record(self, study: Any, trial: Any) -> None:
        """optimize callback: tally the outcome of the trial just run."""
        kind = queue.classify(trial, self.retry)
        if kind == "completed":
            self.report.completed += 1
        elif kind == "failed":
            self.report.failed += 1
        else:
            self.report.gave_way += 1

    def step(self) -> queue.QueueState:
        """Refresh the queue and, if a trial waits, pop and evaluate it."""
        self.lock.acquire()
        try:
            state = queue.refresh(self.study, self.spec)
            if state.waiting:
                self.study.optimize(
                    self.objective, n_trials=1, catch=(EvaluationFailed,), callbacks=[self.record]
                )
        finally:
            self.lock.release_if_held()
        return state

    def run(self, max_trials: int | None) -> WorkerReport:
        budget = MAX_EVALUATIONS_PER_POINT * len(self.spec.points())
        evaluations, idle_since, last_seen = 0, 0.0, None
        while not self.guard.signum and (max_trials is None or evaluations < max_trials):
            try:
                state = self.step()
            except HandBack as exc:
                self._hand_back(exc)
                break
            if self.on_step is not None:
                self.on_step()
            if state.waiting:
                evaluations, last_seen = evaluations + 1, None
                if evaluations > budget:
                    self.report.stop = (
                        f"{evaluations} evaluations for {len(self.spec.points())} points: points keep "
                        "coming back without a result (a bug?)"
                    )
                    break
                continue
            if not state.running:
                break
            if state != last_seen:
                idle_since, last_seen = time.monotonic(), state
            elif time.monotonic() - idle_since > self.idle_timeout:
                break  # the running points stay with their (live) workers
            time.sleep(self.poll_s)
        self.report.signum = self.report.signum or self.guard.signum
        return self.report

    def _hand_back(self, exc: HandBack) -> None:
        """The trial was failed as handed back; queue its point again at once (best effort: the
        next run does it anyway)."""
        self.report.handed_back += 1
        self.report.signum = self.report.signum or exc.signum
        if not exc.signum:
            self.report.stop = exc.reason
        try:
            with self.lock:
                queue.refresh(self.study, self.spec)
        except Exception:  # noqa: BLE001 - e.g. the database is on the full disk too
            pass


def run_worker(
    spec: SweepSpec,
    *,
    max_trials: int | None = None,
    poll_s: float = 1.0,
    idle_timeout: float | None = None,
    on_step: Callable[[], None] | None = None,
) -> WorkerReport:
    """Evaluate queued points of ``spec`` until none is left (or ``max_trials`` evaluations).

    Returns what this worker did; ``report.stop`` / ``report.signum`` say why it stopped early.
    A database that fails mid-run is reported the same way (``stop``), never as a traceback."""
    with SignalGuard() as guard, _quiet_heartbeat_thread():
        worker = None
        try:
            with storage_faults(spec.storage_url):
                worker = SweepWorker(spec, guard, poll_s, idle_timeout, on_step)
                return worker.run(max_trials)
        except StorageFault as exc:
            report = worker.report if worker is not None else WorkerReport()
            report.stop = machine_fault(exc) or str(exc)
            report.signum = report.signum or guard.signum
            return report
        finally:
            if worker is not None and worker.presence is not None:
                worker.presence.leave()


class _quiet_heartbeat_thread:
    """optuna's heartbeat thread dies with a traceback on stderr when the database fails (a full
    disk, a lost server); the worker reports that failure itself, in one line."""

    def __enter__(self) -> None:
        self._previous = threading.excepthook

        def hook(args: threading.ExceptHookArgs) -> None:
            if "_record_heartbeat" not in (args.thread.name if args.thread else ""):
                self._previous(args)

        threading.excepthook = hook

    def __exit__(self, *exc: object) -> None:
        threading.excepthook = self._previous
