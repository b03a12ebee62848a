"""Study runner on optuna: resumable, multi-worker parameter sweeps and optimisations.

A **sweep** is an optuna study over a parameter grid. Every grid point is enqueued once as a
fixed-parameter trial (``study.enqueue_trial``); workers claim WAITING trials one at a time through
the storage (``set_trial_state_values(RUNNING)`` only succeeds for the worker that moves the trial
out of WAITING), evaluate them and ``tell`` the result. The study also carries a ``GridSampler``
over the same grid, so optuna's own tools (dashboard, ``trials_dataframe``) see the search space,
but the sampler never picks a point: optuna documents that ``GridSampler`` may evaluate a grid
point more than once when several processes share a study, and the enqueue/claim scheme does not.

Guarantees and how they are obtained:

* **Exactly once across workers.** PostgreSQL/MySQL: the claim runs ``SELECT ... FOR UPDATE``.
  SQLite ignores ``FOR UPDATE`` and the Python driver starts transactions lazily, so two processes
  could both read WAITING and both claim; for ``sqlite:///`` URLs the enqueue + claim step runs
  under an exclusive ``fcntl`` lock on ``<db>.lock`` (SQLite files are for one machine anyway).
  The database is put in WAL mode and opened with a 60 s busy timeout. As a last guard, a worker
  that claims a point which another trial already completed, or claimed earlier, gives its trial
  up (FAIL with ``user_attrs["duplicate_of"]``; such trials are ignored by :func:`collect`).
* **Resumable.** A killed worker leaves its trial RUNNING. Every running trial records a heartbeat
  (``heartbeat_interval`` s); a trial silent for ``grace_period`` s is failed by
  ``optuna.storages.fail_stale_trials``. A FAIL trial without ``user_attrs["failure"]`` is a lost
  evaluation (not a result), so its point counts as missing and is enqueued again. COMPLETE trials
  and failed *evaluations* are never recomputed: restarting a sweep computes only what is missing.
* **Failures never stop a sweep.** Any exception of the evaluator, and any evaluation that reports
  ``ok = False`` (a diverged design), becomes a FAIL trial whose reason is kept in
  ``user_attrs["failure"]`` (and the traceback in ``user_attrs["traceback"]``).
* **Metrics.** Everything the evaluator returns in ``Evaluation.attrs`` (JSON-able) is stored as
  trial user attributes; :func:`collect` exports them, one CSV row per grid point and pressure.

Evaluators are referenced as ``"module:function"`` strings, so spawned worker processes can import
them. Signature: ``evaluator(params: dict, fixed: dict, settings: dict) -> Evaluation``.
:func:`evaluate_epsa` is the ePSA evaluator: it builds an ``EPSADesign`` and calls
``studies.parts.epsa_response.simulate_epsa`` (or the ``settings["simulate"]`` reference, which tests use to
inject fast fakes).
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib
import itertools
import json
import math
import os
import sqlite3
import threading
import time
import traceback
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

#: Seconds between two heartbeats of a running trial.
DEFAULT_HEARTBEAT_S = 10
#: A RUNNING trial whose last heartbeat is older than this (s) belongs to a dead worker.
DEFAULT_GRACE_S = 60
#: Default evaluator (ePSA knowledge still in the engine: to be removed, see docs/DESIGN.md).
EPSA_EVALUATOR = "studies.catalogue.epsa_evaluator:evaluate_epsa"
#: Columns of an ActuatorCurve row, in CSV order.
CURVE_COLUMNS = (
    "pressure_kpa",
    "length_mm",
    "outer_radius_mm",
    "chamber_volume_mm3",
    "max_principal_stretch",
    "max_fiber_tension_n",
    "status",
    "tip_lateral_mm",
)
#: SQLite busy timeout (s): how long a writer waits for another process's lock.
SQLITE_TIMEOUT_S = 60


class StudyError(ValueError):
    """Invalid study input (user error); ``parameter`` names the offending option."""

    def __init__(self, parameter: str, message: str):
        self.parameter = parameter
        super().__init__(f"{parameter}: {message}")


class SweepInterrupted(RuntimeError):
    """Some worker processes did not finish; the study is consistent and can be resumed."""


@dataclass(frozen=True)
class Evaluation:
    """What an evaluator returns. ``ok = False`` makes the trial FAIL with ``message`` as reason."""

    ok: bool
    values: tuple[float, ...] = ()
    attrs: Mapping[str, Any] = field(default_factory=dict)
    message: str = ""


@dataclass(frozen=True)
class SweepSpec:
    """One sweep: a grid (param -> values) on top of fixed params, evaluated by ``evaluator``.

    ``storage`` is an RDB URL; ``None`` means ``sqlite:///<out_dir>/study.db``. ``settings`` are
    passed to the evaluator unchanged (material, quick, pressures_kpa, simulate, ...).
    ``directions`` are the optuna directions of the values the evaluator returns.
    """

    name: str
    grid: Mapping[str, Sequence[Any]]
    out_dir: str
    fixed: Mapping[str, Any] = field(default_factory=dict)
    evaluator: str = EPSA_EVALUATOR
    settings: Mapping[str, Any] = field(default_factory=dict)
    storage: str | None = None
    directions: tuple[str, ...] = ("maximize",)
    heartbeat_interval: int = DEFAULT_HEARTBEAT_S
    grace_period: int = DEFAULT_GRACE_S

    def __post_init__(self):
        if not self.grid:
            raise StudyError("grid", "is empty")
        grid = {}
        for key, values in self.grid.items():
            values = tuple(values)
            if not values:
                raise StudyError(f"grid.{key}", "has no values")
            if len(set(values)) != len(values):
                raise StudyError(f"grid.{key}", f"repeats a value: {values}")
            grid[str(key)] = values
        object.__setattr__(self, "grid", grid)
        object.__setattr__(self, "fixed", dict(self.fixed))
        object.__setattr__(self, "settings", dict(self.settings))
        object.__setattr__(self, "out_dir", str(self.out_dir))
        object.__setattr__(self, "directions", tuple(self.directions))
        if self.heartbeat_interval < 1 or self.grace_period <= self.heartbeat_interval:
            raise StudyError(
                "grace_period", "needs heartbeat_interval >= 1 and grace_period > heartbeat_interval"
            )

    @property
    def storage_url(self) -> str:
        if self.storage:
            return self.storage
        return f"sqlite:///{Path(self.out_dir).resolve() / 'study.db'}"

    def points(self) -> list[dict[str, Any]]:
        """Every grid point, in grid order (the last parameter varies fastest)."""
        keys = list(self.grid)
        return [dict(zip(keys, combo)) for combo in itertools.product(*self.grid.values())]

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self) | {"grid": {k: list(v) for k, v in self.grid.items()}}


def point_key(params: Mapping[str, Any]) -> str:
    """Canonical identity of a grid point (floats and equal ints compare equal)."""

    def norm(v):
        return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else v

    return json.dumps({k: norm(v) for k, v in sorted(params.items())}, sort_keys=True)


def load_callable(ref: str) -> Callable:
    """Import ``"module:function"``."""
    if not isinstance(ref, str) or ":" not in ref:
        raise StudyError("evaluator", f"expected 'module:function', got {ref!r}")
    module, _, name = ref.partition(":")
    obj = importlib.import_module(module)
    for part in name.split("."):
        obj = getattr(obj, part)
    return obj


# -- storage ------------------------------------------------------------------------------------


def _sqlite_path(url: str) -> Path | None:
    if not url.startswith("sqlite:///"):
        return None
    path = url[len("sqlite:///") :]
    return None if path in ("", ":memory:") else Path(path)


def _quiet_optuna() -> None:
    """Heartbeats are 'experimental' in optuna since 2.9; keep the terminal for progress bars.
    Optuna logs a failed trial as a WARNING with a traceback; a failed design is a result here (its
    reason is in the tables and the summary), so only optuna's errors reach the terminal."""
    import warnings

    import optuna

    warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)
    optuna.logging.set_verbosity(optuna.logging.ERROR)


def make_storage(spec: SweepSpec):
    """The RDB storage of a spec, with heartbeats; SQLite files get WAL mode and a busy timeout."""
    import optuna

    _quiet_optuna()
    url = spec.storage_url
    engine_kwargs = None
    db = _sqlite_path(url)
    if db is not None:
        db.parent.mkdir(parents=True, exist_ok=True)
        with _file_lock(db):
            con = sqlite3.connect(db, timeout=SQLITE_TIMEOUT_S)
            try:
                con.execute("PRAGMA journal_mode=WAL")
            finally:
                con.close()
        engine_kwargs = {"creator": _sqlite_creator(str(db))}
    with _file_lock(db):  # table creation by two processes at once races on SQLite
        return optuna.storages.RDBStorage(
            url,
            engine_kwargs=engine_kwargs,
            heartbeat_interval=spec.heartbeat_interval,
            grace_period=spec.grace_period,
        )


class _sqlite_creator:
    """Connection factory: busy timeout, and ``synchronous = NORMAL``, which in WAL mode keeps
    the database consistent on a crash (a power cut may lose the last commits, which a resumed
    sweep recomputes) and makes each commit several times cheaper than the default FULL."""

    def __init__(self, path: str):
        self.path = path

    def __call__(self):
        con = sqlite3.connect(self.path, timeout=SQLITE_TIMEOUT_S, check_same_thread=False)
        con.execute("PRAGMA synchronous=NORMAL")
        return con


@contextlib.contextmanager
def _file_lock(db: Path | None) -> Iterator[None]:
    """Exclusive inter-process lock beside an SQLite file (no-op for other databases)."""
    if db is None:
        yield
        return
    import fcntl

    with open(f"{db}.lock", "a+") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def open_study(spec: SweepSpec):
    """Create or load the optuna study of a sweep."""
    import optuna

    storage = make_storage(spec)
    sampler = optuna.samplers.GridSampler({k: list(v) for k, v in spec.grid.items()})
    with _file_lock(_sqlite_path(spec.storage_url)):
        study = optuna.create_study(
            study_name=spec.name,
            storage=storage,
            sampler=sampler,
            directions=list(spec.directions),
            load_if_exists=True,
        )
    stored = study.user_attrs.get("spec")
    if stored is None:
        study.set_user_attr("spec", spec.to_dict())
    else:
        _check_same_study(stored, spec.to_dict())
    return study


#: Spec fields that may differ between runs of one study (per-machine paths, worker tuning).
_LOCAL_FIELDS = ("out_dir", "storage", "heartbeat_interval", "grace_period")
_LOCAL_SETTINGS = ("vtu_dir",)


def _check_same_study(stored: Mapping[str, Any], new: Mapping[str, Any]) -> None:
    """Refuse to resume a study with different grid, evaluator or settings: its points would
    mix two different computations."""

    def core(d):
        d = json.loads(json.dumps(_jsonable(dict(d))))
        for key in _LOCAL_FIELDS:
            d.pop(key, None)
        d["settings"] = {k: v for k, v in d.get("settings", {}).items() if k not in _LOCAL_SETTINGS}
        return d

    a, b = core(stored), core(new)
    if a != b:
        diff = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))
        raise StudyError(
            "storage",
            f"study {new.get('name')!r} exists with different "
            f"{', '.join(diff)}; use another --out/--storage or the "
            "same options",
        )


# -- trial bookkeeping --------------------------------------------------------------------------


def _trial_point(trial) -> str | None:
    fixed = trial.system_attrs.get("fixed_params")
    if fixed is not None:
        return point_key(fixed)
    return point_key(trial.params) if trial.params else None


def is_lost(trial, retry_before: int = 0) -> bool:
    """A FAIL trial that is not a result: its worker died, it gave way to a duplicate, or it
    failed before a retry of the failed points (``retry_before``, see :func:`retry_failed`)."""
    from optuna.trial import TrialState

    return trial.state == TrialState.FAIL and (
        "failure" not in trial.user_attrs or "duplicate_of" in trial.user_attrs or trial.number < retry_before
    )


def retry_failed(study) -> None:
    """Make the failed evaluations of a sweep count as missing, so that they run again (after a
    fix of the evaluator, for example). Trials keep their history; collect shows the new ones."""
    study.set_user_attr("retry_failed_before", len(study.get_trials(deepcopy=False)))


def _retry_before(study) -> int:
    return int(study.user_attrs.get("retry_failed_before", 0))


def trials_by_point(study, trials=None) -> dict[str, list]:
    out: dict[str, list] = {}
    for trial in study.get_trials(deepcopy=False) if trials is None else trials:
        key = _trial_point(trial)
        if key is not None:
            out.setdefault(key, []).append(trial)
    return out


def _point_pending_or_done(trials, retry_before: int = 0) -> bool:
    from optuna.trial import TrialState

    for t in trials:
        if t.state in (TrialState.COMPLETE, TrialState.RUNNING, TrialState.WAITING):
            return True
        if t.state == TrialState.FAIL and not is_lost(t, retry_before):
            return True
    return False


def enqueue_missing(study, spec: SweepSpec, trials=None) -> int:
    """Enqueue every grid point that has no trial that is waiting, running, complete or failed as
    a result. Idempotent; call it under :func:`_file_lock` for SQLite. Returns how many.
    ``trials``: a current snapshot of the study's trials (fetched if None)."""
    by_point = trials_by_point(study, trials)
    retry = _retry_before(study)
    n = 0
    for params in spec.points():
        if not _point_pending_or_done(by_point.get(point_key(params), []), retry):
            study.enqueue_trial(params, skip_if_exists=False)
            n += 1
    return n


def _fail_stale(study, grace_period: float, trials) -> bool:
    """Fail RUNNING trials of dead workers (heartbeat older than the grace period, or never
    recorded and started longer ago than the grace period). ``trials``: a snapshot taken after
    ``fail_stale_trials``. Returns whether it failed any trial (the snapshot is then stale)."""
    import datetime

    from optuna.trial import TrialState

    storage = study._storage
    now = datetime.datetime.now()
    changed = False
    for t in trials:
        if (
            t.state != TrialState.RUNNING
            or t.datetime_start is None
            or (now - t.datetime_start).total_seconds() < grace_period
        ):
            continue
        with contextlib.suppress(Exception):
            if not _has_heartbeat(storage, t._trial_id):
                changed |= storage.set_trial_state_values(t._trial_id, state=TrialState.FAIL)
    return changed


def _has_heartbeat(storage, trial_id: int) -> bool:
    from optuna.storages._rdb import models
    from optuna.storages._rdb.storage import _create_scoped_session

    with _create_scoped_session(storage.scoped_session) as session:
        return models.TrialHeartbeatModel.where_trial_id(trial_id, session) is not None


def _claim(study, trials) -> int | None:
    """Move one WAITING trial to RUNNING; the storage lets only one worker succeed per trial."""
    from optuna.trial import TrialState

    storage = study._storage
    for t in trials:
        if t.state != TrialState.WAITING:
            continue
        with contextlib.suppress(Exception):  # UpdateFinishedTrialError: another worker won
            if storage.set_trial_state_values(t._trial_id, state=TrialState.RUNNING):
                return t._trial_id
    return None


def _duplicate_of(study, trial_id: int, trials=None) -> int | None:
    """Number of another trial that completed this point, or claimed it earlier. ``trials``: a
    snapshot taken under the claim lock (exact for SQLite); None fetches a fresh one."""
    from optuna.trial import TrialState

    me = study._storage.get_trial(trial_id)
    key = _trial_point(me)
    retry = _retry_before(study)
    for t in trials_by_point(study, trials).get(key, []):
        if t._trial_id == trial_id:
            continue
        if t.state == TrialState.COMPLETE or (t.state == TrialState.FAIL and not is_lost(t, retry)):
            return t.number
        if t.state == TrialState.RUNNING and (t.datetime_start, t.number) < (me.datetime_start, me.number):
            return t.number
    return None


class _Heartbeat:
    """Background thread recording a trial's heartbeat every ``interval`` seconds."""

    def __init__(self, storage, trial_id: int, interval: float):
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(storage, trial_id, interval), daemon=True)

    def _run(self, storage, trial_id, interval):
        while not self._stop.wait(interval):
            with contextlib.suppress(Exception):  # a busy database: try again next beat
                storage.record_heartbeat(trial_id)

    def __enter__(self):
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()


def _jsonable(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return value


def evaluate_trial(study, trial_id: int, spec: SweepSpec, evaluator: Callable, trials=None) -> str:
    """Evaluate a claimed trial and tell the study. Returns "completed" | "failed" | "duplicate".
    ``trials``: the snapshot the claim was made from, if it was taken under the SQLite lock."""
    import optuna
    from optuna.trial import TrialState

    trial = optuna.trial.Trial(study, trial_id)
    dup = _duplicate_of(study, trial_id, trials)
    if dup is not None:
        trial.set_user_attr("duplicate_of", dup)
        study.tell(trial, state=TrialState.FAIL)
        return "duplicate"
    params = {k: trial.suggest_categorical(k, list(v)) for k, v in spec.grid.items()}
    trial.set_user_attr("worker_pid", os.getpid())
    with _Heartbeat(study._storage, trial_id, spec.heartbeat_interval):
        try:
            result = evaluator(params, dict(spec.fixed), dict(spec.settings))
        except Exception as exc:  # noqa: BLE001 - any failure is a failed trial, never a crash
            result = Evaluation(
                ok=False,
                message=f"{type(exc).__name__}: {exc}",
                attrs={"traceback": traceback.format_exc(limit=8)},
            )

    for key, value in result.attrs.items():
        trial.set_user_attr(key, _jsonable(value))
    values = [float(v) for v in result.values]
    if result.ok and len(values) == len(spec.directions) and all(map(math.isfinite, values)):
        study.tell(trial, values)
        return "completed"
    reason = result.message or ("evaluator returned no finite values" if result.ok else "failed")
    trial.set_user_attr("failure", reason)
    study.tell(trial, state=TrialState.FAIL)
    return "failed"


# -- workers ------------------------------------------------------------------------------------


def run_worker(
    spec: SweepSpec, *, progress: bool = False, max_trials: int | None = None, poll_s: float = 1.0
) -> dict[str, int]:
    """Claim and evaluate grid points until none is waiting or running. Returns counts.

    ``max_trials`` stops after that many evaluations (for tests). While other workers still run
    trials, the worker waits (``poll_s``) so that it can take over points of workers that die.
    """
    with _sigterm_as_exit():
        return _run_worker(spec, progress=progress, max_trials=max_trials, poll_s=poll_s)


@contextlib.contextmanager
def _sigterm_as_exit() -> Iterator[None]:
    """SIGTERM raises SystemExit (so a running trial is handed back) while a worker runs."""
    import signal

    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        raise SystemExit(128 + signum)

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _run_worker(spec: SweepSpec, *, progress: bool, max_trials: int | None, poll_s: float) -> dict[str, int]:
    import optuna
    from optuna.trial import TrialState

    study = open_study(spec)
    evaluator = load_callable(spec.evaluator)
    lock_path = _sqlite_path(spec.storage_url)
    counts = {"completed": 0, "failed": 0, "duplicate": 0}
    bar = _progress_bar(study, spec, f"{spec.name} [pid {os.getpid()}]") if progress else None
    try:
        while max_trials is None or counts["completed"] + counts["failed"] < max_trials:
            with _file_lock(lock_path):
                optuna.storages.fail_stale_trials(study)
                trials = study.get_trials(deepcopy=False)
                if _fail_stale(study, spec.grace_period, trials):
                    trials = study.get_trials(deepcopy=False)
                if enqueue_missing(study, spec, trials):
                    trials = study.get_trials(deepcopy=False)
                trial_id = _claim(study, trials)
                if trial_id is not None:
                    study._storage.record_heartbeat(trial_id)
            if trial_id is None:
                if any(t.state == TrialState.RUNNING for t in trials):
                    time.sleep(poll_s)
                    if bar is not None:
                        _update_bar(bar, study, spec)
                    continue
                break
            try:
                counts[
                    evaluate_trial(
                        study, trial_id, spec, evaluator, trials if lock_path is not None else None
                    )
                ] += 1
            except BaseException:  # Ctrl-C, SIGTERM: give the point back at once (lost trial)
                with contextlib.suppress(Exception):
                    study._storage.set_trial_state_values(trial_id, state=TrialState.FAIL)
                raise
            if bar is not None:
                _update_bar(bar, study, spec)
    finally:
        if bar is not None:
            bar.close()
    return counts


def _worker_main(spec_dict: dict[str, Any]) -> None:
    run_worker(SweepSpec(**spec_dict))


def run_sweep(spec: SweepSpec, *, workers: int = 1, progress: bool = True, retry: bool = False) -> list[dict]:
    """Run (or resume) a sweep with ``workers`` processes and return :func:`collect` rows.
    ``retry``: evaluate the points whose evaluation failed again (see :func:`retry_failed`)."""
    if not isinstance(workers, int) or workers < 1:
        raise StudyError("workers", f"must be a positive integer, got {workers!r}")
    Path(spec.out_dir).mkdir(parents=True, exist_ok=True)
    study = open_study(spec)
    with _file_lock(_sqlite_path(spec.storage_url)):
        if retry:
            retry_failed(study)
        enqueue_missing(study, spec)
    if workers == 1:
        run_worker(spec, progress=progress)
    else:
        import multiprocessing as mp

        ctx = mp.get_context("spawn")
        procs = [
            ctx.Process(target=_worker_main, args=(spec.to_dict(),), daemon=False) for _ in range(workers)
        ]
        for p in procs:
            p.start()
        bar = _progress_bar(study, spec, f"{spec.name} ({workers} workers)") if progress else None
        try:
            with _sigterm_as_exit():
                while any(p.is_alive() for p in procs):
                    time.sleep(1.0)
                    if bar is not None:
                        _update_bar(bar, study, spec)
        except BaseException:  # Ctrl-C / SIGTERM of the parent: stop the workers cleanly
            for p in procs:
                if p.is_alive():
                    p.terminate()  # SIGTERM: the worker hands its running point back
            raise
        finally:
            for p in procs:
                p.join()
            if bar is not None:
                _update_bar(bar, study, spec)
                bar.close()
        bad = [p.exitcode for p in procs if p.exitcode != 0]
        if bad:
            raise SweepInterrupted(
                f"{len(bad)} of {workers} workers exited with codes {bad}; "
                "run the same command again to resume"
            )
    return collect(study, spec)


def _progress_bar(study, spec, desc):
    from tqdm.auto import tqdm

    bar = tqdm(total=len(spec.points()), desc=desc, unit="pt", dynamic_ncols=True)
    _update_bar(bar, study, spec)
    return bar


def _update_bar(bar, study, spec) -> None:
    status = point_status(study, spec)
    done = sum(1 for s, _ in status.values() if s in ("completed", "failed"))
    bar.n = done
    failed = sum(1 for s, _ in status.values() if s == "failed")
    bar.set_postfix(failed=failed, refresh=False)
    bar.refresh()


# -- results ------------------------------------------------------------------------------------


def point_status(study, spec: SweepSpec) -> dict[str, tuple[str, Any]]:
    """For each grid point: (status, trial) with status completed | failed | running | waiting |
    missing. A completed trial wins over anything else; lost/duplicate trials are ignored."""
    from optuna.trial import TrialState

    by_point = trials_by_point(study)
    retry = _retry_before(study)
    out = {}
    rank = {TrialState.COMPLETE: 0, TrialState.FAIL: 1, TrialState.RUNNING: 2, TrialState.WAITING: 3}
    names = {
        TrialState.COMPLETE: "completed",
        TrialState.FAIL: "failed",
        TrialState.RUNNING: "running",
        TrialState.WAITING: "waiting",
    }
    for params in spec.points():
        key = point_key(params)
        trials = [t for t in by_point.get(key, []) if t.state in rank and not is_lost(t, retry)]
        if not trials:
            out[key] = ("missing", None)
            continue
        best = min(trials, key=lambda t: (rank[t.state], t.number))
        out[key] = (names[best.state], best)
    return out


def collect(study, spec: SweepSpec) -> list[dict[str, Any]]:
    """Table of a sweep: one row per (grid point, curve row), every grid point present.

    Columns: study, material, the grid and fixed parameters, trial, trial_status, reason,
    converged, limit_pressure_kpa, the ActuatorCurve row columns (status -> row_status) and any
    scalar metric the evaluator stored. A point without curve rows gets one row with empty
    curve columns, so failed and missing points are never dropped."""
    status = point_status(study, spec)
    rows = []
    for params in spec.points():
        state, trial = status[point_key(params)]
        attrs = flat_attrs(trial)
        base = {"study": spec.name, "material": spec.settings.get("material", "")}
        base |= {k: v for k, v in spec.fixed.items()} | dict(params)
        for key in DESIGN_COLUMNS:  # the undeformed reference of the curve
            if key not in base and isinstance(attrs.get("design"), dict):
                base[key] = attrs["design"].get(key, "")
        base |= {
            "trial": trial.number if trial is not None else "",
            "trial_status": state,
            "reason": attrs.get("failure", "") if state == "failed" else "",
            "converged": attrs.get("converged", ""),
            "limit_pressure_kpa": _blank(attrs.get("limit_pressure_kpa")),
        }
        scalars = {k: v for k, v in attrs.items() if k in SCALAR_METRICS}
        curve_rows = attrs.get("rows") or [None]
        for row in curve_rows:
            out = dict(base)
            for col in CURVE_COLUMNS:
                value = row.get(col, "") if row else ""
                out["row_status" if col == "status" else col] = _blank(value)
            out |= {k: _blank(v) for k, v in scalars.items()}
            rows.append(out)
    return rows


#: Design fields copied from ``user_attrs["design"]`` to every CSV row.
DESIGN_COLUMNS = ("length", "outer_radius")
#: Scalar user attributes copied to every CSV row of a point.
SCALAR_METRICS = ("wall_s", "n_dofs", "message", "worker_pid", "vtu")


def flat_attrs(trial) -> dict[str, Any]:
    """A trial's user attributes with the ``metrics`` dict merged in (one level)."""
    attrs = dict(trial.user_attrs) if trial is not None else {}
    metrics = attrs.get("metrics")
    return {**metrics, **attrs} if isinstance(metrics, dict) else attrs


def _blank(value):
    return "" if value is None else value


def write_csv(rows: Sequence[Mapping[str, Any]], path: str | Path) -> Path:
    """Write dict rows to CSV (union of the keys, first-seen order)."""
    import csv

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    columns: list[str] = []
    for row in rows:
        columns += [k for k in row if k not in columns]
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
    return path


def read_csv(path: str | Path) -> list[dict[str, str]]:
    import csv

    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


# -- optimisation -------------------------------------------------------------------------------

#: Samplers of :func:`run_search`.
SAMPLERS = ("nsga2", "tpe")


@dataclass(frozen=True)
class SearchSpec:
    """An optimisation: the same storage, evaluator and failure handling as a sweep, but optuna's
    TPE or NSGA-II sampler proposes the points. ``space``: param -> ("float"|"int", low, high).
    ``initial`` points (e.g. the paper's Table 1 design) are enqueued once and evaluated first.
    ``n_trials`` is the study's total budget (finished trials, failed ones included), so a
    restarted search only tops up what is missing."""

    name: str
    space: Mapping[str, tuple[str, float, float]]
    out_dir: str
    n_trials: int
    directions: tuple[str, ...]
    sampler: str = "nsga2"
    seed: int | None = 0
    fixed: Mapping[str, Any] = field(default_factory=dict)
    evaluator: str = EPSA_EVALUATOR
    settings: Mapping[str, Any] = field(default_factory=dict)
    storage: str | None = None
    initial: tuple[Mapping[str, Any], ...] = ()
    heartbeat_interval: int = DEFAULT_HEARTBEAT_S
    grace_period: int = DEFAULT_GRACE_S
    #: Constrained optimisation: the evaluator puts "constraints" (floats, <= 0 feasible) in its
    #: attrs; each becomes an optuna trial constraint (`Trial.set_constraint`, which TPE and
    #: NSGA-II use to prefer feasible trials).
    constrained: bool = False

    def __post_init__(self):
        if self.sampler not in SAMPLERS:
            raise StudyError("sampler", f"unknown sampler {self.sampler!r}; valid: {', '.join(SAMPLERS)}")
        if not isinstance(self.n_trials, int) or self.n_trials < 1:
            raise StudyError("trials", f"must be a positive integer, got {self.n_trials!r}")
        for key, (kind, low, high) in self.space.items():
            if kind not in ("float", "int") or not low < high:
                raise StudyError(f"space.{key}", f"bad range {(kind, low, high)!r}")
        object.__setattr__(self, "space", {k: tuple(v) for k, v in self.space.items()})
        object.__setattr__(self, "fixed", dict(self.fixed))
        object.__setattr__(self, "settings", dict(self.settings))
        object.__setattr__(self, "initial", tuple(dict(p) for p in self.initial))
        object.__setattr__(self, "directions", tuple(self.directions))
        object.__setattr__(self, "out_dir", str(self.out_dir))

    storage_url = SweepSpec.storage_url

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


class _EvaluationFailed(Exception):
    """Raised inside an optuna objective so that ``optimize(catch=...)`` records a FAIL trial."""


def _make_sampler(spec: SearchSpec, seed: int | None):
    import optuna

    if spec.sampler == "tpe":
        return optuna.samplers.TPESampler(seed=seed, multivariate=True)
    population = max(4, min(20, spec.n_trials // 4))
    return optuna.samplers.NSGAIISampler(seed=seed, population_size=population)


def open_search(spec: SearchSpec, worker: int = 0):
    """Create or load the study. Each worker (and each resumption) seeds its sampler
    differently: with one seed, parallel workers would propose the same random points."""
    import optuna

    storage = make_storage(spec)
    seed = None
    with _file_lock(_sqlite_path(spec.storage_url)):
        if spec.seed is not None:
            with contextlib.suppress(KeyError):
                done = optuna.load_study(study_name=spec.name, storage=storage)
                seed = spec.seed + 1000 * worker + len(done.get_trials(deepcopy=False))
            seed = spec.seed + 1000 * worker if seed is None else seed
        study = optuna.create_study(
            study_name=spec.name,
            storage=storage,
            sampler=_make_sampler(spec, seed),
            directions=list(spec.directions),
            load_if_exists=True,
        )
        stored = study.user_attrs.get("spec")
        if stored is not None:
            _check_same_study({**stored, "n_trials": 0}, {**spec.to_dict(), "n_trials": 0})
        else:
            study.set_user_attr("spec", spec.to_dict())
            for params in spec.initial:
                study.enqueue_trial(dict(params), user_attrs={"initial": True})
    return study


def _finished_results(study) -> int:
    from optuna.trial import TrialState

    return sum(
        1
        for t in study.get_trials(deepcopy=False, states=(TrialState.COMPLETE, TrialState.FAIL))
        if not is_lost(t)
    )


def search_worker(spec: SearchSpec, *, progress: bool = False, worker: int = 0) -> None:
    """Run trials until the study holds ``spec.n_trials`` finished (non-lost) trials. With
    several workers the total may exceed the budget by the trials in flight at the end."""
    study = open_search(spec, worker)
    evaluator = load_callable(spec.evaluator)

    def objective(trial):
        params = {}
        for key, (kind, low, high) in spec.space.items():
            params[key] = (
                trial.suggest_int(key, int(low), int(high))
                if kind == "int"
                else trial.suggest_float(key, float(low), float(high))
            )
        trial.set_user_attr("worker_pid", os.getpid())
        twin = _twin(study, params, trial.number)
        if twin is not None:  # NSGA-II crossover repeats points: reuse, do not recompute
            result = Evaluation(
                ok=twin.state.name == "COMPLETE",
                values=tuple(twin.values or ()),
                attrs={
                    k: v for k, v in twin.user_attrs.items() if k not in ("initial", "failure", "worker_pid")
                }
                | {"copied_from": twin.number},
                message=twin.user_attrs.get("failure", ""),
            )
        else:
            try:
                result = evaluator(params, dict(spec.fixed), dict(spec.settings))
            except Exception as exc:  # noqa: BLE001
                result = Evaluation(
                    ok=False,
                    message=f"{type(exc).__name__}: {exc}",
                    attrs={"traceback": traceback.format_exc(limit=8)},
                )
        for key, value in result.attrs.items():
            trial.set_user_attr(key, _jsonable(value))
        if spec.constrained:
            for i, value in enumerate(result.attrs.get("constraints", ())):
                trial.set_constraint(f"c{i}", float(value))
        values = [float(v) for v in result.values]
        if result.ok and len(values) == len(spec.directions) and all(map(math.isfinite, values)):
            return values
        trial.set_user_attr("failure", result.message or "failed")
        raise _EvaluationFailed(result.message)

    def stop_when_done(study, _trial):
        if _finished_results(study) >= spec.n_trials:
            study.stop()

    remaining = spec.n_trials - _finished_results(study)
    if remaining > 0:
        study.optimize(
            objective,
            n_trials=remaining,
            catch=(_EvaluationFailed, Exception),
            callbacks=[stop_when_done],
            show_progress_bar=progress,
        )


def _twin(study, params: Mapping[str, Any], number: int):
    """A finished, non-lost earlier trial with the same parameters, if any."""
    from optuna.trial import TrialState

    key = point_key(params)
    for t in study.get_trials(deepcopy=False, states=(TrialState.COMPLETE, TrialState.FAIL)):
        if t.number != number and not is_lost(t) and point_key(t.params) == key:
            return t
    return None


def _search_main(spec_dict: dict[str, Any], worker: int) -> None:
    with _sigterm_as_exit():
        search_worker(SearchSpec(**spec_dict), worker=worker)


def run_search(spec: SearchSpec, *, workers: int = 1, progress: bool = True) -> list[dict]:
    """Run (or resume) an optimisation with ``workers`` processes; returns :func:`collect_search`."""
    if not isinstance(workers, int) or workers < 1:
        raise StudyError("workers", f"must be a positive integer, got {workers!r}")
    Path(spec.out_dir).mkdir(parents=True, exist_ok=True)
    study = open_search(spec)
    if workers == 1:
        search_worker(spec, progress=progress)
    else:
        import multiprocessing as mp

        ctx = mp.get_context("spawn")
        procs = [ctx.Process(target=_search_main, args=(spec.to_dict(), i)) for i in range(workers)]
        for p in procs:
            p.start()
        for p in procs:
            p.join()
    return collect_search(study, spec)


def collect_search(study, spec: SearchSpec) -> list[dict[str, Any]]:
    """One row per (non-lost) trial: params, status, reason, objectives, metrics, pareto flag."""
    from optuna.trial import TrialState

    pareto = (
        {t.number for t in study.best_trials}
        if any(t.state == TrialState.COMPLETE for t in study.get_trials(deepcopy=False))
        else set()
    )
    names = spec.settings.get("objective_names") or [f"value_{i}" for i in range(len(spec.directions))]
    rows = []
    for t in study.get_trials(deepcopy=False):
        if is_lost(t) or t.state not in (TrialState.COMPLETE, TrialState.FAIL):
            continue
        attrs = flat_attrs(t)
        row = {"trial": t.number} | dict(t.params)
        row |= {
            "trial_status": "completed" if t.state == TrialState.COMPLETE else "failed",
            "reason": attrs.get("failure", ""),
            "initial": bool(attrs.get("initial", False)),
        }
        for i, name in enumerate(names):
            row[name] = t.values[i] if t.values else ""
        for key in (
            "extension_mm",
            "radial_expansion_mm",
            "top_pressure_kpa",
            "limit_pressure_kpa",
            "fiber_length_mm",
            "mass_g",
            "wall_s",
            "copied_from",
        ):
            row[key] = _blank(attrs.get(key))
        if spec.constrained:
            row["constraints"] = json.dumps(attrs.get("constraints", []))
        row["pareto"] = t.number in pareto
        rows.append(row)
    return rows
