"""The study lock, and which worker processes of an SQLite study are alive.

The study lock serialises the few steps that optuna does not make atomic across processes
(docs/decisions/022-study-lock.md has the measurements behind each):

* creating the tables of an empty database (two processes race on ``CREATE TABLE`` in SQLite,
  on ``CREATE TYPE studydirection`` in PostgreSQL);
* bringing the queue up to date (enqueue each missing grid point once: optuna's
  `enqueue_trial` has no "only if absent" that holds across processes);
* popping a queued trial: "is a trial waiting?" and `study.ask()` as one step, so that no worker
  asks an empty queue (optuna would then create a fresh, unqueued trial). On SQLite the pop
  itself also needs it: SQLite ignores ``SELECT ... FOR UPDATE`` and the Python driver opens its
  transactions lazily, so two processes can both move one WAITING trial to RUNNING.

SQLite: an exclusive `fcntl.flock` on ``<db>.lock`` (the kernel drops it when its process dies).
PostgreSQL: a transaction-scoped advisory lock (``pg_advisory_xact_lock``) on a connection of its
own; the server drops it when the connection ends, and a holder that vanishes without closing is
cut off by ``idle_in_transaction_session_timeout``. Other databases: no lock (optuna's own row
locks keep pops exactly-once on MySQL; the queue may then hold a point twice, and the duplicate
gives way when it is popped). Every wait for the lock is bounded (`LOCK_TIMEOUT_S`).
"""

from __future__ import annotations

import hashlib
import time
from pathlib import Path
from typing import Any

from softcrawl.studies.sweeps.spec import StudyError

#: Longest wait for the study lock (s); the lock is held for milliseconds at a time.
LOCK_TIMEOUT_S = 120
#: A PostgreSQL lock holder idle for this long inside its lock transaction is cut off (s).
PG_IDLE_TIMEOUT_S = 60


class NoLock:
    """Databases without a lock of ours (see the module docstring). Re-entrant, like the others:
    ``_depth`` counts the acquisitions not yet released."""

    _depth = 0

    def acquire(self) -> None:
        self._depth += 1

    def release(self) -> None:
        self._depth -= 1

    def release_if_held(self) -> None:
        """Release every acquisition (after a step whose objective may have released already)."""
        while self._depth > 0:
            self.release()

    def __enter__(self) -> NoLock:
        self.acquire()
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()


class FileLock(NoLock):
    """Exclusive, re-entrant inter-process lock on a file beside an SQLite database."""

    def __init__(self, path: Path, timeout_s: float = LOCK_TIMEOUT_S):
        self.path, self.timeout_s = Path(path), timeout_s
        self._handle = None
        self._depth = 0

    def acquire(self) -> None:
        import fcntl

        if self._depth == 0:
            handle = open(self.path, "a+")  # held open while locked
            deadline = time.monotonic() + self.timeout_s
            while True:
                try:
                    fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
                    break
                except BlockingIOError:
                    if time.monotonic() > deadline:
                        handle.close()
                        raise StudyError(
                            "storage", f"the study lock {self.path} was busy for over {self.timeout_s:g} s"
                        ) from None
                    time.sleep(0.01)
            self._handle = handle
        self._depth += 1

    def release(self) -> None:
        import fcntl

        self._depth -= 1
        if self._depth == 0 and self._handle is not None:
            fcntl.flock(self._handle, fcntl.LOCK_UN)
            self._handle.close()
            self._handle = None


class AdvisoryLock(NoLock):
    """PostgreSQL transaction-scoped advisory lock on a connection of its own (re-entrant)."""

    def __init__(self, engine: Any, name: str, timeout_s: float = LOCK_TIMEOUT_S):
        digest = hashlib.sha256(f"softcrawl:{name}".encode()).digest()
        self.key = int.from_bytes(digest[:8], "big", signed=True)
        self.engine, self.timeout_s = engine, timeout_s
        self._conn = self._txn = None
        self._depth = 0

    def acquire(self) -> None:
        from sqlalchemy import text

        if self._depth == 0:
            if self._conn is None or self._conn.closed:
                self._conn = self.engine.connect()
                self._conn.execute(text(f"SET idle_in_transaction_session_timeout = '{PG_IDLE_TIMEOUT_S}s'"))
                self._conn.commit()
            self._txn = self._conn.begin()
            self._conn.execute(text(f"SET LOCAL lock_timeout = '{int(self.timeout_s * 1000)}ms'"))
            try:
                self._conn.execute(text("SELECT pg_advisory_xact_lock(:key)"), {"key": self.key})
            except Exception as exc:
                self._txn.rollback()
                self._conn.close()
                if "lock timeout" in str(exc):
                    raise StudyError(
                        "storage", f"the study lock was busy for over {self.timeout_s:g} s"
                    ) from exc
                raise
        self._depth += 1

    def release(self) -> None:
        self._depth -= 1
        if self._depth == 0 and self._txn is not None:
            self._txn.commit()
            self._txn = None


class WorkerPresence:
    """SQLite only (one machine): every worker process of a study holds a shared `flock` on
    ``<db>.workers`` while it runs; the kernel drops it when the process dies, however it dies.
    A worker that joins (under the study lock) and finds no other holder knows that every RUNNING
    trial of the study belongs to a dead process, including a trial whose worker could record
    nothing about itself because the disk was full."""

    def __init__(self, path: Path):
        self.path = Path(path)
        self._handle = None

    def join(self) -> bool:
        """Take the shared lock; returns whether no other worker held it."""
        import fcntl

        handle = open(self.path, "a+")  # held open while this worker runs
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            alone = True
        except BlockingIOError:
            alone = False
        fcntl.flock(handle, fcntl.LOCK_SH)  # joins are serialised by the study lock
        self._handle = handle
        return alone

    def leave(self) -> None:
        if self._handle is not None:
            self._handle.close()
            self._handle = None
