"""Where a study lives: optuna's RDB storage, the study lock, and storage errors as one line.

Storage: `optuna.storages.RDBStorage(url, heartbeat_interval=..., grace_period=...)`. SQLite
files are put in WAL mode and opened with a 60 s busy timeout and ``synchronous = NORMAL`` (in WAL
mode a crash keeps the database consistent; a power cut may lose the last commits, which a resumed
sweep recomputes).

The study lock (`studies.sweeps.locks`) serialises the steps that optuna does not make atomic
across processes.
"""

from __future__ import annotations

import contextlib
import json
import re
import sqlite3
import warnings
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any

from softcrawl.studies.sweeps.faults import machine_fault
from softcrawl.studies.sweeps.locks import AdvisoryLock, FileLock, NoLock, WorkerPresence
from softcrawl.studies.sweeps.spec import SearchSpec, StudyError, SweepSpec, jsonable

#: SQLite busy timeout (s): how long a writer waits for another process's database lock.
SQLITE_TIMEOUT_S = 60
#: Spec fields that may differ between runs of one study (per-machine paths, worker tuning).
LOCAL_FIELDS = ("out_dir", "storage", "heartbeat_interval", "grace_period")
LOCAL_SETTINGS = ("vtu_dir", "out_dir")
#: What a study created by this engine records (study user attribute ``softcrawl_schema``): 2 =
#: named objectives (`set_metric_names`), the objective of the study's declaration, metrics as
#: flat user attributes, no machine paths in the stored spec (decision 063). A study
#: without it was made before and is refused, not migrated: optuna cannot rename, re-direct or
#: re-score finished trials.
SCHEMA = 2


def sqlite_path(url: str) -> Path | None:
    """The database file of an ``sqlite:///`` URL (None for other URLs and in-memory SQLite)."""
    if not url.startswith("sqlite:///"):
        return None
    path = url[len("sqlite:///") :]
    return None if path in ("", ":memory:") else Path(path)


def quiet_optuna() -> None:
    """Heartbeats are 'experimental' in optuna; a failed trial is a result here (its reason is in
    the tables), so optuna's per-trial warnings stay off the terminal."""
    import optuna

    warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)
    optuna.logging.set_verbosity(optuna.logging.ERROR)


def safe_url(url: str) -> str:
    """The URL with its password masked (it goes into error messages)."""
    try:
        from sqlalchemy.engine import make_url

        return make_url(url).render_as_string(hide_password=True)
    except Exception:  # noqa: BLE001 - an unparsable URL: mask what looks like user:password@
        return re.sub(r"(://[^:/@]*):[^@]*@", r"\1:***@", url)


def one_line(exc: BaseException) -> str:
    """An exception as one line: the driver's own message when SQLAlchemy wraps one."""
    orig = getattr(exc, "orig", None) or exc.__cause__ or exc
    text = " ".join(str(orig).split()) or type(orig).__name__
    return text if len(text) < 300 else text[:297] + "..."


def storage_error(url: str, exc: BaseException) -> StudyError:
    """What went wrong opening ``url``, as an input error naming --storage."""
    import sqlalchemy.exc as sa_exc

    where = safe_url(url)
    if isinstance(exc, ModuleNotFoundError | ImportError):
        name = getattr(exc, "name", None) or getattr(exc.__cause__, "name", None) or "its driver"
        hint = ' (pip install -e ".[postgres]")' if url.startswith("postgres") else ""
        return StudyError("storage", f"{where} needs the Python package {name!r}{hint}")
    if isinstance(exc, sa_exc.NoSuchModuleError):
        return StudyError("storage", f"unknown database dialect in {where}: {one_line(exc)}")
    if isinstance(exc, sa_exc.ArgumentError):
        return StudyError("storage", f"not a database URL: {where}: {one_line(exc)}")
    return StudyError("storage", f"cannot use {where}: {one_line(exc)}")


# -- storage and study ---------------------------------------------------------------------------


def worker_presence(url: str) -> WorkerPresence | None:
    db = sqlite_path(url)
    return WorkerPresence(Path(f"{db}.workers")) if db is not None else None


class _SqliteConnect:
    """Connection factory for SQLite files: busy timeout and ``synchronous = NORMAL``."""

    def __init__(self, path: str):
        self.path = path

    def __call__(self) -> sqlite3.Connection:
        con = sqlite3.connect(self.path, timeout=SQLITE_TIMEOUT_S, check_same_thread=False)
        con.execute("PRAGMA synchronous=NORMAL")
        return con


def _make_storage(url: str, spec: SweepSpec | SearchSpec, schema_lock: NoLock) -> Any:
    import optuna

    engine_kwargs = None
    db = sqlite_path(url)
    with schema_lock:  # the tables of an empty database are created by one process at a time
        if db is not None:
            con = sqlite3.connect(db, timeout=SQLITE_TIMEOUT_S)
            try:
                con.execute("PRAGMA journal_mode=WAL")
            finally:
                con.close()
            engine_kwargs = {"creator": _SqliteConnect(str(db))}
        return optuna.storages.RDBStorage(
            url,
            engine_kwargs=engine_kwargs,
            heartbeat_interval=spec.heartbeat_interval,
            grace_period=spec.grace_period,
        )


def _make_locks(url: str, name: str) -> tuple[NoLock, NoLock]:
    """(schema lock, study lock) for ``url``."""
    db = sqlite_path(url)
    if db is not None:
        db.parent.mkdir(parents=True, exist_ok=True)
        lock = FileLock(Path(f"{db}.lock"))
        return lock, lock
    if url.split(":", 1)[0].split("+", 1)[0] in ("postgresql", "postgres"):
        import sqlalchemy

        engine = sqlalchemy.create_engine(url, poolclass=sqlalchemy.pool.NullPool)
        return AdvisoryLock(engine, "optuna-schema"), AdvisoryLock(engine, f"study:{name}")
    return NoLock(), NoLock()


def connect(
    spec: SweepSpec | SearchSpec,
    *,
    sampler: Any = None,
    on_create: Callable[[Any], None] | None = None,
    ignore: tuple[str, ...] = (),
) -> tuple[Any, NoLock]:
    """Open (or create) the optuna study of ``spec``; returns (study, study lock).

    The spec is stored with the study; resuming with a different grid, evaluator or settings is
    refused (fields in `LOCAL_FIELDS` and ``ignore`` may differ). ``on_create(study)`` runs once,
    in the process that creates the study, under the lock. Any failure to reach or create the
    database is a `StudyError` naming ``storage``."""
    import optuna
    from sqlalchemy.engine import make_url

    quiet_optuna()
    url = spec.storage_url
    try:
        make_url(url)
    except Exception as exc:  # a URL that does not parse (bad port, no scheme, ...)
        raise StudyError("storage", f"not a database URL: {safe_url(url)}: {one_line(exc)}") from exc
    try:
        schema_lock, lock = _make_locks(url, spec.name)
        storage = _make_storage(url, spec, schema_lock)
        with lock:
            study = optuna.create_study(
                study_name=spec.name,
                storage=storage,
                sampler=sampler,
                directions=list(spec.directions),
                load_if_exists=True,
            )
            stored = study.user_attrs.get("spec")
            if stored is None:
                study.set_metric_names(list(spec.metric_names))
                study.set_user_attr("spec", stored_spec(spec))
                study.set_user_attr("softcrawl_schema", SCHEMA)
                if on_create is not None:
                    on_create(study)
            schema = study.user_attrs.get("softcrawl_schema")
    except StudyError:
        raise
    except Exception as exc:  # every way a database can be unreachable is one line
        raise storage_error(url, exc) from exc
    if schema != SCHEMA:
        raise StudyError(
            "storage",
            f"study {spec.name!r} in {safe_url(url)} was made by an older softcrawl (unnamed objective, "
            "packed metrics; decision 063): it cannot be resumed; use another --out/--storage",
        )
    if stored is not None:
        check_same_study(stored, spec.to_dict(), ignore)
    return study, lock


def stored_spec(spec: SweepSpec | SearchSpec) -> dict[str, Any]:
    """The spec as the database keeps it: without the fields and settings that name this
    machine's folders (`LOCAL_FIELDS`, `LOCAL_SETTINGS`), so no absolute path is stored."""
    d = jsonable(spec.to_dict())
    for key in ("out_dir", "storage"):
        d.pop(key, None)
    d["settings"] = {k: v for k, v in d.get("settings", {}).items() if k not in LOCAL_SETTINGS}
    return d


def check_same_study(stored: Mapping[str, Any], new: Mapping[str, Any], ignore: tuple[str, ...] = ()) -> None:
    """Refuse to resume a study with different grid, evaluator or settings: its points would mix
    two different computations."""

    def core(d: Mapping[str, Any]) -> dict[str, Any]:
        d = json.loads(json.dumps(jsonable(dict(d))))
        for key in (*LOCAL_FIELDS, *ignore):
            d.pop(key, None)
        d["settings"] = {k: v for k, v in d.get("settings", {}).items() if k not in LOCAL_SETTINGS}
        return d

    a, b = core(stored), core(new)
    if a != b:
        diff = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))
        raise StudyError(
            "storage",
            f"study {new.get('name')!r} exists with different {', '.join(diff)}; "
            "use another --out/--storage or the same options",
        )


def database_error(exc: BaseException) -> BaseException | None:
    """The database error behind ``exc`` (itself, or one it was raised from or during), if any.
    optuna sometimes hides a failed commit behind an exception of its own (an AssertionError
    raised while it handles the failed ``tell``), so the whole chain is searched."""
    import optuna
    import sqlalchemy.exc as sa_exc

    kinds = (optuna.exceptions.StorageInternalError, sa_exc.SQLAlchemyError, sqlite3.Error)
    seen = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        if isinstance(exc, kinds):
            return exc
        exc = exc.__cause__ or exc.__context__
    return None


@contextlib.contextmanager
def storage_faults(url: str) -> Iterator[None]:
    """Turn a database that fails mid-run (connection lost, disk full) into a `StorageFault`."""
    try:
        yield
    except StudyError:
        raise
    except Exception as exc:
        cause = database_error(exc)
        if cause is None:
            raise
        fault = machine_fault(exc)  # a full disk or an unwritable file is said as such
        raise StorageFault(fault or f"storage {safe_url(url)}: {one_line(cause)}") from exc


class StorageFault(RuntimeError):
    """The database failed during a run (not the user's input): one line, the run stops."""
