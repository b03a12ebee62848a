"""Run or resume a sweep with one or several worker processes, and report how it ended.

`run_sweep` queues the grid (under the study lock), runs ``workers`` workers (in this process
for one, spawned processes for several, and for one under a memory limit: the watchdog's hard
stop ends its process, which must not be the command's; workers on other machines may join
through a shared ``--storage``), and returns the table of `studies.sweeps.tables.collect`. It
raises

* `SweepStopped` when the run stopped early: a signal (the workers hand their points back at
  once; exit code 128 + signal), a fault of the machine such as a full disk, a database that
  failed mid-run, or workers that died; every case is one line, and the same command resumes;
* the `StudyError` of the evaluator when no point could be evaluated because of bad input.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from softcrawl.studies.sweeps import memory, queue
from softcrawl.studies.sweeps.faults import SweepStopped, WorkerReport
from softcrawl.studies.sweeps.pool import run_pool
from softcrawl.studies.sweeps.spec import StudyError, SweepSpec, TableLayout
from softcrawl.studies.sweeps.storage import StorageFault, storage_faults
from softcrawl.studies.sweeps.tables import collect, input_failure
from softcrawl.studies.sweeps.worker import open_sweep, run_worker


def run_sweep(
    spec: SweepSpec,
    *,
    layout: TableLayout | None = None,
    workers: int = 1,
    progress: bool = True,
    retry: bool = False,
    poll_s: float = 1.0,
) -> list[dict[str, Any]]:
    """Run (or resume) a sweep and return its table. ``retry``: evaluate the points whose
    evaluation failed again (after a fix of the evaluator, for example)."""
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise StudyError("workers", f"must be a positive integer, got {workers!r}")
    try:
        Path(spec.out_dir).mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise StudyError("out", f"cannot create {spec.out_dir}: {exc.strerror or exc}") from exc
    study, lock = open_sweep(spec)
    try:
        with storage_faults(spec.storage_url), lock:
            if retry:
                queue.mark_retry(study)
            queue.refresh(study, spec)
    except StorageFault as exc:
        raise SweepStopped(WorkerReport(stop=str(exc))) from exc
    bar = _Progress(study, spec, workers) if progress else None
    try:
        if workers == 1 and memory.limit_gb() is None:
            report = run_worker(spec, poll_s=poll_s, on_step=bar.update if bar else None)
        else:
            report = _run_pool(spec, workers, poll_s, bar)
    finally:
        if bar is not None:
            bar.close()
    if report.signum or report.stop:
        raise SweepStopped(report)
    error = input_failure(study, spec)
    if error is not None:
        raise error
    return collect(study, spec, layout or TableLayout())


def _worker_main(spec_dict: dict[str, Any], index: int, poll_s: float) -> WorkerReport:
    return run_worker(SweepSpec(**spec_dict), poll_s=poll_s)


def _run_pool(spec: SweepSpec, workers: int, poll_s: float, bar: _Progress | None) -> WorkerReport:
    total, died = run_pool(_worker_main, spec.to_dict(), workers, poll_s, bar.update if bar else None)
    if died and not total.signum:  # fail the trials of dead workers now (a memory stop: its reason)
        study, lock = open_sweep(spec)
        try:
            with storage_faults(spec.storage_url), lock:
                queue.refresh(study, spec)
        except StorageFault:
            pass  # the next run does it
    if died and not total.signum and not total.stop and _unfinished(spec):
        why = " (137: the memory watchdog's stop or the kernel's out-of-memory kill)" if 137 in died else ""
        total.stop = f"{len(died)} of {workers} workers died (exit codes {died}){why}"
    return total


def _unfinished(spec: SweepSpec) -> bool:
    study, _ = open_sweep(spec)
    return any(s not in ("completed", "failed") for s, _ in queue.statuses(study, spec).values())


class _Progress:
    """A tqdm bar over the grid points that have a result (failed ones counted as postfix)."""

    def __init__(self, study: Any, spec: SweepSpec, workers: int):
        from tqdm.auto import tqdm

        self.study, self.spec = study, spec
        desc = spec.name + (f" ({workers} workers)" if workers > 1 else "")
        self.bar = tqdm(total=len(spec.points()), desc=desc, unit="pt", dynamic_ncols=True)
        self.update()

    def update(self) -> None:
        try:
            states = [s for s, _ in queue.statuses(self.study, self.spec).values()]
        except Exception:  # noqa: BLE001 - a progress bar never stops a sweep
            return
        self.bar.n = sum(s in ("completed", "failed") for s in states)
        self.bar.set_postfix(failed=states.count("failed"), refresh=False)
        self.bar.refresh()

    def close(self) -> None:
        self.bar.close()
