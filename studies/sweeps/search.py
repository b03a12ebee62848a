"""Optimisations: optuna's NSGA-II or TPE proposes the points, with a sweep's storage and faults.

The study lock, the heartbeat, the hand-back on a signal or a full disk and the failed-result
rules are those of a sweep (`studies.sweeps.worker`). What differs: the sampler proposes each
point (``optimize`` creates the trial), the ``initial`` points are enqueued once, by the process
that creates the study, and the budget ``n_trials`` counts results (completed and failed trials;
a handed-back or dead worker's trial is not one), so a restarted search tops up what is missing.
With several workers the total may exceed the budget by the trials in flight at the end.

Seeds: each worker, and each resumption, seeds its sampler with ``seed + 1000 * worker + number
of trials so far``: with one seed, parallel workers would propose the same random points.
A point the sampler proposes again (NSGA-II crossover repeats points) is not recomputed: the
earlier result is copied (``copied_from``).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from typing import Any

from softcrawl.studies.sweeps import memory, queue
from softcrawl.studies.sweeps.faults import SignalGuard, SweepStopped, WorkerReport
from softcrawl.studies.sweeps.pool import run_pool
from softcrawl.studies.sweeps.spec import Evaluation, SearchSpec, StudyError, load_callable, point_key
from softcrawl.studies.sweeps.storage import StorageFault, connect, storage_faults
from softcrawl.studies.sweeps.tables import blank, flat_attrs
from softcrawl.studies.sweeps.worker import EvaluationFailed, HandBack, run_guarded, store


def make_sampler(spec: SearchSpec, seed: int | None) -> Any:
    import optuna

    if spec.sampler == "tpe":
        return optuna.samplers.TPESampler(seed=seed, multivariate=True)
    population = max(4, min(20, spec.n_trials // 4))
    return optuna.samplers.NSGAIISampler(seed=seed, population_size=population)


def open_search(spec: SearchSpec, worker: int = 0) -> tuple[Any, Any]:
    """(study, lock) of a search, created (with its initial points queued) if absent."""

    def enqueue_initial(study: Any) -> None:
        for params in spec.initial:
            study.enqueue_trial(dict(params), user_attrs={"initial": True})

    study, lock = connect(spec, on_create=enqueue_initial, ignore=("n_trials",))
    if spec.seed is not None:
        seed = spec.seed + 1000 * worker + len(study.get_trials(deepcopy=False))
    else:
        seed = None
    study.sampler = make_sampler(spec, seed)
    return study, lock


def results(study: Any) -> list[Any]:
    """The finished trials that are results (completed, or failed with a reason)."""
    return [t for t in study.get_trials(deepcopy=False) if queue.classify(t) in ("completed", "failed")]


def suggest(trial: Any, key: str, dimension: tuple[Any, ...]) -> Any:
    """The trial's value of one dimension of the space (`SearchSpec.space`)."""
    if dimension[0] == "categorical":
        return trial.suggest_categorical(key, list(dimension[1]))
    kind, low, high = dimension
    return (
        trial.suggest_int(key, int(low), int(high))
        if kind == "int"
        else trial.suggest_float(key, float(low), float(high))
    )


def _twin(study: Any, params: Mapping[str, Any], number: int) -> Any:
    key = point_key(params)
    for t in results(study):
        if t.number != number and point_key(t.params) == key:
            return t
    return None


class SearchWorker:
    """Trials until the study holds ``n_trials`` results; one instance per process."""

    def __init__(self, spec: SearchSpec, guard: SignalGuard, worker: int):
        self.spec, self.guard = spec, guard
        self.study, self.lock = open_search(spec, worker)
        self.evaluator = load_callable(spec.evaluator)
        self.report = WorkerReport()

    def objective(self, trial: Any) -> list[float]:
        self.lock.release()
        params = {key: suggest(trial, key, dimension) for key, dimension in self.spec.space.items()}
        twin = _twin(self.study, params, trial.number)
        if twin is None:
            return run_guarded(trial, self.evaluator, params, self.spec, self.guard)
        copied = {k: v for k, v in twin.user_attrs.items() if k not in ("initial", "failure", "worker_pid")}
        result = Evaluation(
            ok=twin.state.name == "COMPLETE",
            values=tuple(twin.values or ()),
            attrs=copied | {"copied_from": twin.number},
            message=twin.user_attrs.get("failure", ""),
        )
        return store(trial, result, len(self.spec.directions))

    def record(self, study: Any, trial: Any) -> None:
        kind = queue.classify(trial)
        if kind in ("completed", "failed"):
            setattr(self.report, kind, getattr(self.report, kind) + 1)

    def run(self, on_step: Callable[[], None] | None = None) -> WorkerReport:
        while not self.guard.signum:
            self.lock.acquire()
            try:
                if len(results(self.study)) >= self.spec.n_trials:
                    break
                self.study.optimize(
                    self.objective, n_trials=1, catch=(EvaluationFailed,), callbacks=[self.record]
                )
            except HandBack as exc:
                self.report.handed_back += 1
                self.report.signum = exc.signum
                self.report.stop = "" if exc.signum else exc.reason
                break
            finally:
                self.lock.release_if_held()
            if on_step is not None:
                on_step()
        self.report.signum = self.report.signum or self.guard.signum
        return self.report


def search_worker(
    spec: SearchSpec, *, worker: int = 0, on_step: Callable[[], None] | None = None
) -> WorkerReport:
    """Run trials until the study holds ``spec.n_trials`` results; returns what this worker did."""
    with SignalGuard() as guard:
        try:
            with storage_faults(spec.storage_url):
                return SearchWorker(spec, guard, worker).run(on_step)
        except StorageFault as exc:
            return WorkerReport(stop=str(exc), signum=guard.signum)


def _search_main(spec_dict: dict[str, Any], index: int, poll_s: float) -> WorkerReport:
    return search_worker(SearchSpec(**spec_dict), worker=index)


def run_search(spec: SearchSpec, *, workers: int = 1, progress: bool = True) -> list[dict[str, Any]]:
    """Run (or resume) an optimisation with ``workers`` processes; returns `collect_search`."""
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise StudyError("workers", f"must be a positive integer, got {workers!r}")
    study, _ = open_search(spec)
    bar = _SearchProgress(study, spec) if progress else None
    try:
        if workers == 1 and memory.limit_gb() is None:  # a memory stop must not end this process
            report = search_worker(spec, on_step=bar.update if bar else None)
        else:
            report, died = run_pool(_search_main, spec.to_dict(), workers, 1.0, bar.update if bar else None)
            if len(died) == workers and not report.signum and not report.stop:  # none finished the budget
                report.stop = f"{len(died)} of {workers} workers died (exit codes {died})"
    finally:
        if bar is not None:
            bar.close()
    if report.signum or report.stop:
        raise SweepStopped(report)
    done = results(study)
    if done and all("input_error" in t.user_attrs for t in done):
        first = done[0].user_attrs["input_error"]
        raise StudyError(first["parameter"], f"{first['detail']} (no point of the study could be evaluated)")
    return collect_search(study, spec)


def collect_search(study: Any, spec: SearchSpec) -> list[dict[str, Any]]:
    """One row per result: params, status, reason, objectives, metrics, copied_from, pareto."""
    done = results(study)
    pareto = {t.number for t in study.best_trials} if any(t.state.name == "COMPLETE" for t in done) else set()
    rows = []
    for t in done:
        attrs = flat_attrs(t)
        row = {"trial": t.number} | dict(t.params)
        row |= {
            "trial_status": "completed" if t.state.name == "COMPLETE" else "failed",
            "reason": attrs.get("failure", ""),
            "initial": bool(attrs.get("initial", False)),
        }
        for i, name in enumerate(spec.objective_names):
            row[name] = t.values[i] if t.values else ""
        for key in (*spec.metric_columns, "copied_from"):
            row[key] = blank(attrs.get(key))
        if "constraints" in attrs:  # a constrained search (`worker.store`): feasible when all <= 0
            row["constraints"] = json.dumps(attrs["constraints"])
        row["pareto"] = t.number in pareto
        row["peak_rss_gb"] = blank(attrs.get("peak_rss_gb"))  # `studies.sweeps.memory`
        rows.append(row)
    return rows


class _SearchProgress:
    """A tqdm bar over the budget of results."""

    def __init__(self, study: Any, spec: SearchSpec):
        from tqdm.auto import tqdm

        self.study = study
        self.bar = tqdm(total=spec.n_trials, desc=spec.name, unit="trial", dynamic_ncols=True)
        self.update()

    def update(self) -> None:
        try:
            self.bar.n = len(results(self.study))
            self.bar.refresh()
        except Exception:  # noqa: BLE001 - a progress bar never stops a search
            pass

    def close(self) -> None:
        self.bar.close()
